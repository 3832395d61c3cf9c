/* libFuzzer target: the prescription readers (native, .fx, pbrt .dat) and the glass
 * catalog reader on arbitrary bytes. A reader must return an error or a lens that
 * lens_finish accepted, and never crash, leak or read out of bounds. The first byte
 * picks the reader. Built and run by tools/fuzz.sh (make fuzz). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sparselens/lens.h"
#include "sparselens/import_table.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    int which = data[0] % 4;
    data++;
    size--;
    FILE *f = fmemopen((void *)data, size ? size : 1, "r");
    if (!f)
        return 0;
    if (!size) {
        fclose(f);
        f = fopen("/dev/null", "r");
    }
    lens_t lens;
    lens_err err;
    int rc = 0;
    /* Glass names resolve in no catalog: keeps each run independent of the disk. */
    static const char *const none[] = {NULL};
    lens_load_options opt = {.catalogs = (const char *const *)none};
    setenv("SPARSELENS_GLASS_CATALOG", "/nonexistent", 1);
    switch (which) {
    case 0:
        rc = lens_read_native(f, "fuzz.lens", &opt, &lens, &err);
        break;
    case 1:
        rc = lens_read_fx(f, "fuzz.fx", &opt, &lens, &err);
        break;
    case 2:
        rc = lens_read_pbrt(f, "fuzz.dat", &opt, &lens, &err);
        break;
    default: {
        char path[] = "/tmp/fuzz_glass_XXXXXX";
        int fd = mkstemp(path);
        if (fd >= 0) {
            if (write(fd, data, size) == (ssize_t)size) {
                glass_catalog *cat = NULL;
                if (glass_catalog_load(&cat, path, &err) == 0)
                    glass_catalog_free(cat);
            }
            close(fd);
            unlink(path);
        }
        fclose(f);
        return 0;
    }
    }
    fclose(f);
    if (rc == 0) {
        /* What was read must write and read back. */
        char *text = NULL;
        size_t len = 0;
        FILE *m = open_memstream(&text, &len);
        lens_write(m, &lens);
        fclose(m);
        FILE *r = fmemopen(text, len ? len : 1, "r");
        lens_t again;
        if (lens_read_native(r, "rt.lens", &opt, &again, &err) == 0) {
            if (again.nsurf != lens.nsurf)
                abort();
            lens_free(&again);
        } else if (!strstr(err.msg, "unknown material")) {
            abort(); /* only catalog glasses may fail to resolve again */
        }
        fclose(r);
        free(text);
        lens_free(&lens);
    }
    return 0;
}
