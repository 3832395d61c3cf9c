/* lens-info's job (see info_run.h). */
#include "sparselens/info_run.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sparselens/field_of_view.h"

/* Notes about where the sensor was are no longer true after refocusing: they are replaced
 * by one that says how it was moved. */
static void note_refocus(lens_t *lens, double focus, double lambda)
{
    char kept[sizeof lens->notes] = "";
    for (char *save, *line = strtok_r(lens->notes, "\n", &save); line;
         line = strtok_r(NULL, "\n", &save))
        if (!strstr(line, "focus"))
            snprintf(kept + strlen(kept), sizeof kept - strlen(kept), "%s\n", line);
    snprintf(kept + strlen(kept), sizeof kept - strlen(kept),
             "sensor refocused by lens-info --focus %g (paraxial, at %g um)", focus, lambda);
    snprintf(lens->notes, sizeof lens->notes, "%s", kept);
}

int info_prepare(const info_cli *o, lens_t *lens, lens_err *err)
{
    if (!isnan(o->sensor.w)) {
        lens->sensor_w = o->sensor.w;
        lens->sensor_h = o->sensor.h;
    }
    if (isnan(o->focus))
        return o->as_lens;
    double t;
    if (paraxial_focus_thickness(lens, o->lambda, o->focus, &t, err) != 0)
        return -1;
    lens->surf[lens->nsurf - 1].thickness = t;
    note_refocus(lens, o->focus, o->lambda);
    if (lens_finish(lens, err) != 0)
        return -1;
    return 1;
}

int info_run(const info_cli *o, const lens_t *lens, info_report *rep, lens_err *err)
{
    memset(rep, 0, sizeof *rep);
    rep->lambda = o->lambda;
    if (paraxial_compute(lens, o->lambda, &rep->p, err) != 0)
        return -1;
    rep->have_sensor = !isnan(lens->sensor_w);
    rep->sensor_w = lens->sensor_w;
    rep->sensor_h = lens->sensor_h;
    rep->sensor_radius = rep->field_of_view_deg = rep->image_circle_radius = NAN;
    if (!rep->have_sensor)
        return 0;
    rep->sensor_radius = 0.5 * hypot(lens->sensor_w, lens->sensor_h);
    return lens_field_of_view(lens, o->lambda, rep->sensor_radius, &rep->field_of_view_deg,
                              &rep->image_circle_radius, err);
}

static void print_key(FILE *f, const char *key, double v)
{
    if (isinf(v))
        fprintf(f, "%s %s\n", key, v > 0 ? "inf" : "-inf");
    else
        fprintf(f, "%s %.10g\n", key, v == 0 ? 0.0 : v); /* no "-0" */
}

void info_report_print(FILE *f, const lens_t *lens, const info_report *rep)
{
    const paraxial_data *p = &rep->p;
    fprintf(f, "name %s\n", lens->name[0] ? lens->name : "-");
    print_key(f, "wavelength", rep->lambda);
    print_key(f, "efl", p->efl);
    print_key(f, "bfl", p->bfl);
    print_key(f, "ffl", p->ffl);
    print_key(f, "fnumber", p->fnumber);
    print_key(f, "entrance_pupil_z", p->entrance_pupil_z);
    print_key(f, "entrance_pupil_diameter", p->entrance_pupil_diameter);
    print_key(f, "exit_pupil_z", p->exit_pupil_z);
    print_key(f, "exit_pupil_diameter", p->exit_pupil_diameter);
    fprintf(f, "stop_surface %d\n", p->stop_surface);
    print_key(f, "total_track", p->total_track);
    if (rep->have_sensor) {
        fprintf(f, "sensor %gx%g\n", rep->sensor_w, rep->sensor_h);
        print_key(f, "field_of_view_deg", rep->field_of_view_deg);
        print_key(f, "image_circle_radius", rep->image_circle_radius);
    } else {
        print_key(f, "field_of_view_deg", NAN);
    }
    print_key(f, "sensor_distance", p->sensor_distance);
    print_key(f, "focus_distance", p->focus_distance);
}
