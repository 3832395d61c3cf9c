/* The frame the design-file readers (.zmx, .seq) share (import_common.h): the start
 * and end of a parse, numbers as keyword arguments, the fields and wavelengths notes,
 * radii from curvatures and the system aperture applied to the finished lens. */
#include "lens/import_common.h"

#include "sparselens/numparse.h"
#include "sparselens/paraxial.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

char *import_begin(const char *data, size_t len, const char *path, const char *program,
                   lens_t *lens, import_system *sys, lens_err *err)
{
    lens_init(lens);
    memset(sys, 0, sizeof *sys);
    sys->path = path;
    sys->lens = lens;
    sys->unit = 1;
    sys->epd = sys->fno = NAN;
    snprintf(lens->path, sizeof lens->path, "%s", path);
    const char *base = strrchr(path, '/');
    snprintf(lens->source, sizeof lens->source, "%s file %s", program, base ? base + 1 : path);
    size_t text_len;
    char *text = import_decode(data, len, &text_len);
    if (!text)
        lens_errf(err, path, 0, "out of memory");
    else if (import_check_lines(text, text_len, path, err) != 0) {
        free(text);
        text = NULL;
    }
    return text;
}

int import_parse(const char *data, size_t len, const char *path, const lens_load_options *opt,
                 lens_t *lens, const import_format *fmt, lens_err *err)
{
    import_system *state = calloc(1, fmt->state_size); /* the state begins with it */
    if (!state) {
        lens_init(lens);
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    char *text = import_begin(data, len, path, fmt->program, lens, state, err);
    int rc = text ? 0 : -1;
    if (rc == 0) {
        state->inf_words = fmt->inf_words;
        rc = fmt->read(state, text, err);
    }
    if (rc == 0)
        rc = fmt->build(state, opt, err);
    fmt->free(state);
    free(state);
    free(text);
    if (rc != 0)
        lens_free(lens);
    return rc;
}

int import_number(const import_system *sys, char **tok, int n, int i, long line, double *v,
                  lens_err *err)
{
    if (n > i && sys->inf_words && (import_eq(tok[i], "INFINITY") || import_eq(tok[i], "INF"))) {
        *v = INFINITY;
        return 0;
    }
    if (n > i && parse_double(tok[i], v) == 0)
        return 0;
    lens_errf(err, sys->path, line, "%s: expected a number, found '%s'", tok[0],
              n > i ? tok[i] : "end of line");
    return -1;
}

/* Appends the printf-formatted text to buf (of cap bytes, o used) while it fits. */
static void list_add(char *buf, size_t cap, size_t *o, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void list_add(char *buf, size_t cap, size_t *o, const char *fmt, ...)
{
    if (*o >= cap)
        return;
    va_list ap;
    va_start(ap, fmt);
    int w = vsnprintf(buf + *o, cap - *o, fmt, ap);
    va_end(ap);
    if (w > 0)
        *o += (size_t)w;
}

void import_fields_note(lens_t *lens, const char *kind, const double *x, int nx,
                        const double *y, int n)
{
    if (n <= 0)
        return;
    char buf[sizeof lens->notes];
    size_t o = 0;
    list_add(buf, sizeof buf, &o, "fields %s:", kind);
    for (int i = 0; i < n; i++) {
        double xi = x && i < nx ? x[i] : 0;
        if (xi != 0)
            list_add(buf, sizeof buf, &o, " (%g,%g)", xi, y[i]);
        else
            list_add(buf, sizeof buf, &o, " %g", y[i]);
    }
    lens_add_note(lens, "%s", buf);
}

void import_waves_note(lens_t *lens, const double *wave, int n, double per_um, int primary)
{
    if (n <= 0)
        return;
    char buf[sizeof lens->notes];
    size_t o = 0;
    list_add(buf, sizeof buf, &o, "wavelengths (um):");
    for (int i = 0; i < n; i++)
        list_add(buf, sizeof buf, &o, " %.7g%s", wave[i] / per_um,
                 i + 1 == primary ? " (primary)" : "");
    lens_add_note(lens, "%s", buf);
}

int import_set_aperture(lens_t *lens, double fnumber, double epd_mm, const char *what,
                        int hard, lens_err *err)
{
    paraxial_data p;
    lens_err e;
    e.msg[0] = '\0';
    if (paraxial_compute(lens, GLASS_D_LINE, &p, &e) != 0 || !(p.fnumber > 0) ||
        !isfinite(p.fnumber) || !isfinite(p.efl)) {
        lens_add_note(lens, "aperture %s not applied: %s", what,
                      e.msg[0] ? e.msg : "the lens has no finite paraxial f-number");
        return 0;
    }
    double target = fnumber > 0 ? fnumber : fabs(p.efl) / epd_mm;
    lens_surface *s = &lens->surf[lens->stop];
    double old = s->semi_diameter, sd = old * p.fnumber / target;
    if (!isfinite(sd) || isnan(lens_sag(s, sd * sd))) {
        lens_errf(err, lens->path, s->line,
                  "%s needs a stop semi-diameter of %g mm, more than surface %d can have", what,
                  sd, lens->stop + 1);
        return -1;
    }
    lens->fnumber = target;
    if (hard && sd > old * (1 + 1e-6)) {
        /* A hard aperture on the stop clips the beam the system aperture asks for. */
        lens_add_note(lens, "%s asks for a stop semi-diameter of %.6g mm; the stop's clear "
                            "aperture %g mm is kept (f/%.4g, not f/%.4g)",
                      what, sd, old, p.fnumber, target);
        return 0;
    }
    s->semi_diameter = sd;
    if (fabs(sd - old) > 1e-6 * old)
        lens_add_note(lens, "stop semi-diameter %.6g mm from %s (the file's is %g)", sd, what,
                      old);
    return 0;
}

double import_radius(double c, double unit)
{
    if (c == 0 || !isfinite(c))
        return INFINITY;
    double r = 1.0 / c;
    char buf[40];
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, r);
        double v = strtod(buf, NULL);
        if (1.0 / v == c) {
            r = v;
            break;
        }
    }
    return r * unit;
}

int import_finish(lens_t *lens, const import_skips *skips, double fnumber, const char *fno_name,
                  double epd_mm, const char *epd_name, int hard, lens_err *err)
{
    import_skips_note(skips, lens);
    import_clean_text(lens);
    import_seat_stop(lens);
    if (lens_finish(lens, err) != 0)
        return -1;
    const char *what = NULL;
    int rc = 0;
    double old = lens->surf[lens->stop].semi_diameter;
    if (isfinite(fnumber) && fnumber > 0)
        rc = import_set_aperture(lens, fnumber, 0, what = fno_name, hard, err);
    else if (isfinite(epd_mm) && epd_mm > 0)
        rc = import_set_aperture(lens, 0, epd_mm, what = epd_name, hard, err);
    double sd = lens->surf[lens->stop].semi_diameter;
    if (rc != 0 || sd == old)
        return rc;
    /* The system aperture resized the stop after the checks: a widened stop can now cross
     * its neighbour, which the native reader would refuse in the written lens. */
    import_seat_stop(lens);
    if (lens_finish(lens, err) != 0) {
        size_t n = strlen(err->msg);
        snprintf(err->msg + n, sizeof err->msg - n, " (stop semi-diameter %g mm from %s)", sd, what);
        return -1;
    }
    return 0;
}
