/* lens-layout's job (layout_run.h). */
#include "sparselens/layout_run.h"
#include "sparselens/outfile.h"

#include <math.h>
#include <stdio.h>

static void surface_row(table_out *t, long i, double z, double radius, double conic, double sd, double sag,
                        const char *material, int stop)
{
    table_out_int(t, i);
    table_out_fmt(t, z, 1, "%.9g");
    table_out_fmt(t, radius, 0, "%.9g");
    table_out_fmt(t, conic, 0, "%.6g");
    table_out_fmt(t, sd, 0, "%.6g");
    table_out_fmt(t, sag, 1e-3, "%.6g");
    table_out_key_int(t, material, stop);
}

static void print_surfaces(table_out *t, const lens_t *lens)
{
    const char *cols[] = {"surface", "z_mm", "radius_mm", "conic", "semi_diameter_mm", "sag_rim_mm", "material", "stop"};
    table_out_table(t, "surfaces", NULL, cols, 8);
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *s = &lens->surf[i];
        surface_row(t, (long)i + 1, lens->vertex_z[i], s->radius, s->conic, s->semi_diameter,
                    lens_sag(s, s->semi_diameter * s->semi_diameter),
                    s->medium.kind == GLASS_AIR ? "air" : s->material[0] ? s->material : "glass", s->is_stop);
    }
    surface_row(t, (long)lens->nsurf + 1, lens_total_track(lens), INFINITY, 0, NAN, 0, "sensor", 0);
}

int layout_run(layout_request *rq, table_out *out, lens_err *err)
{
    design_set *ds = &rq->set;
    if (design_set_focus(ds, err) != 0)
        return -1;
    /* the drawing is of the lens; a system alone, or beside it, adds its image-space rays */
    imaging lens_im = ds->im[0];
    lens_im.sys = NULL;
    const imaging *sys_im = ds->im[0].sys ? &ds->im[0] : ds->nmodels > 1 ? &ds->im[1] : NULL;
    /* a field a model cannot image at the primary wavelength: the lens's rays are drawn
     * as far as they go, the system's not at all */
    unsigned char sys_skip[IMAGING_MAX_FIELDS] = {0};
    for (int f = 0; f < ds->nfields; f++)
        for (int m = 0; m < ds->nmodels; m++) {
            int sys = ds->im[m].sys != NULL;
            int st = design_set_imaged(ds, m, f, 0, sys ? "its rays are not drawn" : "its rays are drawn as far as they go", err);
            if (st < 0)
                return -1;
            if (sys && st > 0)
                sys_skip[f] = 1;
        }
    layout_drawing d;
    if (layout_build(&lens_im, sys_im, sys_skip, ds->field, ds->nfields, ds->lambda[ds->primary], rq->rays,
                     rq->full_stop, &d, err) != 0)
        return -1;
    d.title = rq->title;
    print_surfaces(out, lens_im.lens);
    if (!out->json) {
        fprintf(out->f, "# rays at %.7g um: %d of %d reach the sensor\n", ds->lambda[ds->primary], d.passed, d.rays);
    } else {
        table_out_keys(out, "rays", NULL);
        table_out_key_int(out, "launched", d.rays);
        table_out_key_int(out, "reach_sensor", d.passed);
    }
    if (sys_im) {
        /* the rays' times: the lens's and the system's for the same rays */
        design_set both = *ds;
        both.nmodels = 2, both.names[0] = "lens", both.names[1] = "poly";
        both.seconds[0] = d.seconds[0], both.seconds[1] = d.seconds[1];
        design_set_print_footer(out, &both, "the rays");
        char text[128];
        snprintf(text, sizeof text, "sensor points differ by at most %.4g um (dotted: the system's rays)",
                 1e3 * d.system_diff);
        const char *k[1] = {"sensor_points_um"};
        double v[1] = {1e3 * d.system_diff};
        design_set_print_difference(out, &both, text, 1, k, v);
    } else if (!out->json && ds->sensor_shift != 0) {
        fprintf(out->f, "# sensor plane moved %.9g mm along the axis\n", ds->sensor_shift);
    } else if (out->json) {
        table_out_keys(out, "sensor", NULL);
        table_out_key_num(out, "shift_mm", ds->sensor_shift);
    }
    int rc = 0;
    if (rq->png && layout_write_png(&d, rq->png, rq->width, err) != 0)
        rc = -1;
    if (rc == 0 && rq->svg && layout_write_svg(&d, rq->svg, err) != 0) {
        outfile_remove(rq->png); /* the run failed: none of its pictures stays */
        rc = -1;
    }
    layout_free(&d);
    return rc;
}
