/* lens-info's job (see info_run.h). */
#include "sparselens/info_run.h"

#include <math.h>
#include <stdarg.h>
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

static void warn(info_report *rep, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void warn(info_report *rep, const char *fmt, ...)
{
    if (rep->nwarnings == (int)(sizeof rep->warnings / sizeof rep->warnings[0]))
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(rep->warnings[rep->nwarnings++], sizeof rep->warnings[0], fmt, ap);
    va_end(ap);
}

/* A header value a computed one should match: nominal focal lengths and f-numbers are
 * rounded (a "50 mm f/2" lens computes 50.4 mm, f/2.03), so 5 % apart is a question
 * about the data (fisheye-ii: f/1.75 against f/2.8), not rounding. */
static void check_header(info_report *rep, const char *what, double computed, double header,
                         const char *unit, const char *hint)
{
    if (isfinite(header) && isfinite(computed) && fabs(computed - header) > 0.05 * header)
        warn(rep, "the computed %s (%.4g%s) differs from the header's (%.4g%s) by %.0f %%: %s",
             what, computed, unit, header, unit, 100 * fabs(computed - header) / header, hint);
}

/* Where the sensor is focused, in words, when that is not plainly infinity. */
static void check_focus(info_report *rep, const paraxial_data *p)
{
    double shift = p->sensor_distance - p->bfl; /* + : behind the infinity focus */
    if (!isfinite(p->focus_distance) || p->afocal)
        return;
    /* Negative with the sensor nearer than the infinity focus: the conjugate is past
     * infinity. Negative with it beyond: the conjugate object is real-side of the
     * front focal point but still behind the first surface (fisheye.lens, whose front
     * focal point lies deep inside the lens). Either way no real object is sharp. */
    if (p->focus_distance < 0)
        warn(rep, "focus_distance %.6g mm is negative: the sensor is %.3g mm %s the infinity "
                  "focus, so no real object is sharp (a virtual one %.6g mm behind the first "
                  "surface is); for objects at infinity that is a defocus of %.3g mm",
             p->focus_distance, fabs(shift), shift < 0 ? "nearer the lens than" : "beyond",
             -p->focus_distance, fabs(shift));
    else if (p->focus_distance < 1000 * fabs(p->efl))
        warn(rep, "focus_distance %.6g mm: the sensor is focused on a near object, %.3g mm "
                  "behind the infinity focus; an object at infinity (lens-spot's and "
                  "lens-distort's default) is seen defocused (--focus best or lens-info --focus "
                  "inf --format lens refocus it)",
             p->focus_distance, shift);
}

int info_run(const info_cli *o, const lens_t *lens, info_report *rep, lens_err *err)
{
    memset(rep, 0, sizeof *rep);
    rep->lambda = o->lambda;
    if (paraxial_compute(lens, o->lambda, &rep->p, err) != 0)
        return -1;
    const paraxial_data *p = &rep->p;
    if (p->afocal)
        warn(rep, "the lens has no power (afocal): efl, bfl, ffl and fnumber are infinite");
    check_header(rep, "focal length", p->efl, lens->focal, " mm",
                 "check the prescription or the header");
    check_header(rep, "f-number", p->fnumber, lens->fnumber, "",
                 "the stop's semi-diameter sets it (lens-trace, lens-spot and lens-distort "
                 "--fnumber N stop it down)");
    check_focus(rep, p);
    rep->have_sensor = !isnan(lens->sensor_w);
    rep->sensor_w = lens->sensor_w;
    rep->sensor_h = lens->sensor_h;
    rep->sensor_radius = rep->field_of_view_deg = rep->image_circle_radius = NAN;
    if (!rep->have_sensor) {
        warn(rep, "no sensor size in the lens header; give --sensor WxH for field_of_view_deg");
        return 0;
    }
    rep->sensor_radius = 0.5 * hypot(lens->sensor_w, lens->sensor_h);
    if (lens_field_of_view(lens, o->lambda, rep->sensor_radius, &rep->field_of_view_deg,
                           &rep->image_circle_radius, err) != 0)
        return -1;
    if (rep->image_circle_radius < rep->sensor_radius)
        warn(rep, "the sensor diagonal (%.4g mm) reaches past the image circle (radius %.4g mm); "
                  "field_of_view_deg is the image circle's",
             2 * rep->sensor_radius, rep->image_circle_radius);
    return 0;
}

static void key(table_out *t, const char *name, double v, double scale, const char *unit)
{
    table_out_str(t, name);
    table_out_num(t, v, scale);
    table_out_unit(t, unit);
    table_out_row_end(t);
}

/* The keys and their units: a text line each "key value unit", in JSON the values at the
 * top and the units in "units" (lens-info(1) lists them). */
static const struct {
    const char *name, *unit;
} info_keys[] = {{"wavelength", "um"}, {"efl", "mm"}, {"bfl", "mm"}, {"ffl", "mm"},
                 {"fnumber", "1"}, {"entrance_pupil_z", "mm"}, {"entrance_pupil_diameter", "mm"},
                 {"exit_pupil_z", "mm"}, {"exit_pupil_from_last_surface", "mm"}, {"exit_pupil_diameter", "mm"}, {"stop_surface", "-"},
                 {"total_track", "mm"}, {"sensor", "mm"}, {"field_of_view_deg", "deg"},
                 {"image_circle_radius", "mm"}, {"sensor_distance", "mm"},
                 {"focus_distance", "mm"}, {"focal_header", "mm"}, {"fnumber_header", "1"}};

void info_report_print(FILE *f, const lens_t *lens, const info_report *rep, const output_cli *out)
{
    const paraxial_data *p = &rep->p;
    table_out t;
    output_cli_begin(out, &t, f, 10);
    table_out_keys(&t, NULL, NULL);
    /* lengths that cancel to round-off are zero on the scale of the whole lens */
    double L = isfinite(p->total_track) ? fabs(p->total_track) : 1;
    table_out_key_str(&t, "name", lens->name[0] ? lens->name : "-");
    key(&t, "wavelength", rep->lambda, 0, "um");
    key(&t, "efl", p->efl, L, "mm");
    key(&t, "bfl", p->bfl, L, "mm");
    key(&t, "ffl", p->ffl, L, "mm");
    key(&t, "fnumber", p->fnumber, 0, "1");
    key(&t, "entrance_pupil_z", p->entrance_pupil_z, L, "mm");
    key(&t, "entrance_pupil_diameter", p->entrance_pupil_diameter, L, "mm");
    /* z from the first surface, as every z of the project (the paraxial calculation
     * measures the exit pupil from the last surface, as CODE V and Zemax print it) */
    key(&t, "exit_pupil_z", p->exit_pupil_z + lens->vertex_z[lens->nsurf - 1], L, "mm");
    key(&t, "exit_pupil_from_last_surface", p->exit_pupil_z, L, "mm");
    key(&t, "exit_pupil_diameter", p->exit_pupil_diameter, L, "mm");
    table_out_str(&t, "stop_surface");
    table_out_int(&t, p->stop_surface);
    table_out_unit(&t, "-");
    table_out_row_end(&t);
    key(&t, "total_track", p->total_track, 0, "mm");
    if (rep->have_sensor) {
        char size[64];
        snprintf(size, sizeof size, "%gx%g", rep->sensor_w, rep->sensor_h);
        table_out_str(&t, "sensor");
        table_out_str(&t, size);
        table_out_unit(&t, "mm");
        table_out_row_end(&t);
        key(&t, "field_of_view_deg", rep->field_of_view_deg, 0, "deg");
        key(&t, "image_circle_radius", rep->image_circle_radius, L, "mm");
    } else {
        key(&t, "field_of_view_deg", NAN, 0, "deg");
    }
    key(&t, "sensor_distance", p->sensor_distance, L, "mm");
    key(&t, "focus_distance", p->focus_distance, 0, "mm");
    if (isfinite(lens->focal))
        key(&t, "focal_header", lens->focal, 0, "mm");
    if (isfinite(lens->fnumber))
        key(&t, "fnumber_header", lens->fnumber, 0, "1");
    if (out->json) {
        table_out_keys(&t, "units", NULL);
        for (size_t k = 0; k < sizeof info_keys / sizeof info_keys[0]; k++) {
            table_out_key_str(&t, info_keys[k].name, info_keys[k].unit);
        }
    }
    const char *w[8];
    for (int k = 0; k < rep->nwarnings; k++)
        w[k] = rep->warnings[k];
    table_out_end(&t, w, rep->nwarnings);
}
