/* lens-info --seidel (info_run.h): the third-order view of a lens, the paraxial ray
 * table and the Seidel sums, as tables a designer reads beside CODE V's or ray-optics'. */
#include <math.h>
#include <stdio.h>

#include "sparselens/info_run.h"
#include "sparselens/seidel.h"

int info_seidel_print(FILE *f, const lens_t *lens, const info_cli *o, const info_report *rep, lens_err *err)
{
    double field = o->seidel_field;
    if (isnan(field))
        field = rep->field_of_view_deg / 2;
    if (!isfinite(field)) {
        lens_errf(err, lens->path, 0, "--seidel: no field of view (no sensor size): give --field DEG "
                                      "or --sensor WxH");
        return -1;
    }
    seidel_data s;
    if (seidel_compute(lens, o->lambda, field, &s, err) != 0)
        return -1;
    table_out t;
    output_cli_begin(&o->out, &t, f, 8);
    /* lengths on the scale of the lens, sums on the scale of their largest term */
    double L = isfinite(rep->p.total_track) ? fabs(rep->p.total_track) : 1, big = 0;
    for (size_t i = 0; i < s.nsurf; i++)
        for (int k = 0; k < 5; k++)
            big = fmax(big, fabs(s.surf[i].S[k]));
    table_out_keys(&t, "paraxial", NULL);
    table_out_key_num(&t, "wavelength_um", s.lambda);
    table_out_key_num(&t, "field_deg", s.field);
    table_out_key_num(&t, "marginal_height_mm", s.y0);
    table_out_key_num(&t, "chief_slope", s.ubar0);
    table_out_key_num(&t, "lagrange_invariant_mm", s.H);
    static const char *const ray_cols[] = {"surface", "y_mm", "u", "ybar_mm", "ubar", "n"};
    table_out_table(&t, "rays",
                    "marginal ray (y, u) and chief ray (ybar, ubar): height at each surface and slope "
                    "after it, index after it",
                    ray_cols, 6);
    for (size_t i = 0; i < s.nsurf; i++) {
        const seidel_surface *q = &s.surf[i];
        table_out_int(&t, (long long)i + 1);
        table_out_num(&t, q->y, L);
        table_out_num(&t, q->u, 1);
        table_out_num(&t, q->ybar, L);
        table_out_num(&t, q->ubar, 1);
        table_out_num(&t, q->n, 0);
        table_out_row_end(&t);
    }
    static const char *const sum_cols[] = {"surface", "S_I", "S_II", "S_III", "S_IV", "S_V"};
    table_out_table(&t, "seidel",
                    "Seidel sums in mm (Welford's convention: S_I > 0 is undercorrected spherical "
                    "aberration); the last row is the lens's",
                    sum_cols, 6);
    for (size_t i = 0; i <= s.nsurf; i++) {
        const double *S = i < s.nsurf ? s.surf[i].S : s.sum;
        if (i < s.nsurf)
            table_out_int(&t, (long long)i + 1);
        else
            table_out_str(&t, "sum");
        for (int k = 0; k < 5; k++)
            table_out_num(&t, S[k], big);
        table_out_row_end(&t);
    }
    table_out_keys(&t, "wavefront", "wavefront coefficients of the sums, mm at the pupil's rim and the field");
    table_out_key_num(&t, "W040", s.sum[0] / 8);
    table_out_key_num(&t, "W131", s.sum[1] / 2);
    table_out_key_num(&t, "W222", s.sum[2] / 2);
    table_out_key_num(&t, "W220", (s.sum[2] + s.sum[3]) / 4);
    table_out_key_num(&t, "W311", s.sum[4] / 2);
    char note[160];
    const char *warnings[1] = {note};
    int nw = 0;
    if (s.s5_undefined) {
        snprintf(note, sizeof note, "S_V set to 0 on %d surface(s) the marginal ray meets normally", s.s5_undefined);
        nw = 1;
    }
    table_out_end(&t, warnings, nw);
    seidel_free(&s);
    return 0;
}
