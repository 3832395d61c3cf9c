/* Tangential and sagittal foci by close real rays (field_curves.h). */
#include "sparselens/field_curves.h"

#include <math.h>
#include <string.h>

#include "sparselens/ray_bundle.h"

int field_focus_trace(const imaging *im, double field, double lambda, double delta,
                      field_focus *ff, lens_err *err)
{
    memset(ff, 0, sizeof *ff);
    ff->field = field, ff->lambda = lambda;
    ff->z_tan = ff->z_sag = NAN;
    if (bundle_chief(im, field, lambda, ff->chief, err) != 0)
        return -1;
    const double pupil[8] = {0, delta, 0, -delta, delta, 0, -delta, 0};
    ray_bundle b;
    if (bundle_aim(im, field, lambda, pupil, 4, &b, err) != 0)
        return -1;
    double s[16];
    int ok[4];
    ff->seconds = bundle_image(im, &b, ff->chief, s, ok);
    bundle_free(&b);
    /* A sensor ray is the line (x - dz u, y - dz v) at dz along +z from the plane. */
    if (ok[0] && ok[1] && s[3] != s[7])
        ff->z_tan = (s[1] - s[5]) / (s[3] - s[7]);
    if (ok[2] && ok[3] && s[10] != 0 && s[14] != 0)
        ff->z_sag = 0.5 * (s[8] / s[10] + s[12] / s[14]);
    return 0;
}
