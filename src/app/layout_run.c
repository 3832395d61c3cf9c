/* lens-layout's job (layout_run.h). */
#include "sparselens/layout_run.h"

#include <math.h>

static void print_surfaces(FILE *out, const lens_t *lens)
{
    fprintf(out, "# columns: surface z_mm radius_mm conic semi_diameter_mm sag_rim_mm material stop\n");
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *s = &lens->surf[i];
        fprintf(out, "%zu %.9g %.9g %.6g %.6g %.6g %s %d\n", i + 1, lens->vertex_z[i], s->radius, s->conic,
                s->semi_diameter, lens_sag(s, s->semi_diameter * s->semi_diameter),
                s->medium.kind == GLASS_AIR ? "air" : s->material[0] ? s->material : "glass", s->is_stop);
    }
    fprintf(out, "%zu %.9g inf 0 nan 0 sensor 0\n", lens->nsurf + 1, lens_total_track(lens));
}

int layout_run(layout_request *rq, FILE *out, lens_err *err)
{
    design_set *ds = &rq->set;
    if (design_set_focus(ds, err) != 0)
        return -1;
    /* the drawing is of the lens; a system alone, or beside it, adds its image-space rays */
    imaging lens_im = ds->im[0];
    lens_im.sys = NULL;
    const imaging *sys_im = ds->im[0].sys ? &ds->im[0] : ds->nmodels > 1 ? &ds->im[1] : NULL;
    layout_drawing d;
    if (layout_build(&lens_im, sys_im, ds->field, ds->nfields, ds->lambda[ds->primary], rq->rays, &d, err) != 0)
        return -1;
    d.title = rq->title;
    print_surfaces(out, lens_im.lens);
    fprintf(out, "# rays at %.7g um: %d of %d reach the sensor\n", ds->lambda[ds->primary], d.passed, d.rays);
    if (ds->sensor_shift != 0)
        fprintf(out, "# sensor plane moved %.9g mm along the axis\n", ds->sensor_shift);
    if (sys_im) {
        fprintf(out, "# time imaging the rays: lens %.4g s, poly %.4g s (%.3g x the lens's)\n", d.seconds[0],
                d.seconds[1], d.seconds[0] > 0 ? d.seconds[1] / d.seconds[0] : NAN);
        fprintf(out, "# poly - lens: sensor points differ by at most %.4g um (dotted: the system's rays)\n",
                1e3 * d.system_diff);
    }
    int rc = 0;
    if (rq->png && layout_write_png(&d, rq->png, rq->width, err) != 0)
        rc = -1;
    if (rc == 0 && rq->svg && layout_write_svg(&d, rq->svg, err) != 0)
        rc = -1;
    layout_free(&d);
    return rc;
}
