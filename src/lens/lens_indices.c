/* The refractive indices of a lens at one wavelength (lens.h): what every trace and
 * every first-order computation starts from. */
#include "sparselens/lens.h"

int lens_indices(const lens_t *lens, double lambda_um, double *n, lens_err *err)
{
    for (size_t i = 0; i < lens->nsurf; i++) {
        if (lens->surf[i].medium.kind == GLASS_AIR) { /* half the surfaces of most lenses */
            n[i] = 1.0;
            continue;
        }
        if (glass_index(&lens->surf[i].medium, lambda_um, &n[i], err)) {
            const char *file = lens->path[0] ? lens->path : NULL;
            lens_err e2;
            lens_errf(&e2, file, lens->surf[i].line, "surface %zu: %s", i + 1, err->msg);
            *err = e2;
            return -1;
        }
    }
    return 0;
}
