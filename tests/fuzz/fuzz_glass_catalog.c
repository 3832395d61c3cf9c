/* libFuzzer target: the project's .catalog glass catalog reader (glass_catalog_load).
 * Every glass it accepts must give a finite index inside its own wavelength range, or
 * an error, never a silent NaN.
 * needs: src/lens/glass.c */
#include <math.h>

#include "fuzz_common.h"
#include "sparselens/glass.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_path(data, size);
    glass_catalog *cat = NULL;
    lens_err err;
    if (glass_catalog_load(&cat, path, &err) == 0) {
        for (size_t i = 0; i < glass_catalog_size(cat); i++) {
            const glass_t *g = glass_catalog_at(cat, i);
            FUZZ_CHECK(glass_catalog_find(cat, g->name) != NULL);
            const double l[] = {g->lambda_min, 0.5 * (g->lambda_min + g->lambda_max),
                                g->lambda_max, GLASS_D_LINE};
            for (int k = 0; k < 4; k++) {
                double n;
                if (glass_index(g, l[k], &n, &err) == 0)
                    FUZZ_CHECK(isfinite(n) && n > 0);
            }
        }
    } else {
        FUZZ_CHECK(err.msg[0] != 0 && strchr(err.msg, '\n') == NULL);
    }
    glass_catalog_free(cat);
    return 0;
}
