/* lens-fit's samples checked in the user's terms before the fit (fit_input.h). */
#include "app/fit_input.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int fit_input_check_init(fit_input_check *c, int nin, const char *const *in_names,
                         lens_err *err)
{
    memset(c, 0, sizeof *c);
    c->nin = nin;
    c->in_names = in_names;
    c->in = malloc((size_t)(nin > 0 ? nin : 1) * sizeof *c->in);
    if (!c->in) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    static const char *const frame_names[4] = {"x", "y", "u", "v"};
    int *frame_in[4] = {&c->ix, &c->iy, &c->iu, &c->iv};
    for (int k = 0; k < 4; k++) {
        *frame_in[k] = -1;
        for (int i = 0; i < nin; i++)
            if (strcmp(in_names[i], frame_names[k]) == 0)
                *frame_in[k] = i;
    }
    return 0;
}

void fit_input_check_free(fit_input_check *c)
{
    free(c->in);
    c->in = NULL;
}

static void widen(fit_spread *s, double v, int first)
{
    if (first || v < s->lo)
        s->lo = v;
    if (first || v > s->hi)
        s->hi = v;
}

/* r = |(x, y)|, u' and v' as the meridional frame computes them (poly_frame.c). */
void fit_input_check_row(fit_input_check *c, const double *in, long line)
{
    int first = c->usable++ == 0;
    if (first)
        c->first_line = line;
    c->last_line = line;
    for (int i = 0; i < c->nin; i++)
        widen(&c->in[i], in[i], first);
    if (c->ix < 0 || c->iy < 0 || c->iu < 0 || c->iv < 0)
        return;
    double x = in[c->ix], y = in[c->iy], u = in[c->iu], v = in[c->iv];
    double r = sqrt(x * x + y * y), co = r > 0 ? x * (1 / r) : 1, si = r > 0 ? y * (1 / r) : 0;
    widen(&c->frame[0], r, first);
    widen(&c->frame[1], co * u + si * v, first);
    widen(&c->frame[2], co * v - si * u, first);
}

/* Squares and sums of squares of 1e100 stay far from overflow (outputs of 1e150 already
 * left the fit with one term and no held-out error); 1/lambda^2 of 1e-100 likewise. */
const char *fit_input_bad_value(const char *name, double v, int output)
{
    if (output)
        return isnan(v) || fabs(v) <= FIT_MAX_MAGNITUDE ? NULL
               : isinf(v) ? "outputs must be finite or nan (a blocked ray)"
                          : "out of range (values must lie within +-1e100)";
    if (!isfinite(v))
        return "inputs must be finite";
    if (fabs(v) > FIT_MAX_MAGNITUDE)
        return "out of range (values must lie within +-1e100)";
    if (strcmp(name, "lambda") == 0 && !(v > 0))
        return "a wavelength must be > 0 um";
    if (strcmp(name, "lambda") == 0 && v < 1 / FIT_MAX_MAGNITUDE)
        return "out of range (a wavelength must lie within 1e-100 to 1e100 um)";
    return NULL;
}

/* The fitter's test of a column it cannot scale (fit.c): no spread beyond round-off. */
static int no_spread(const fit_spread *s)
{
    double mag = fmax(fabs(s->lo), fabs(s->hi));
    return !(s->hi - s->lo > 1e-12 * mag) || s->hi == s->lo;
}

/* " on all N usable samples (lines A to B)", or " on the one usable sample". */
static void usable_rows(const fit_input_check *c, char *buf, size_t len)
{
    if (c->usable == 1)
        snprintf(buf, len, " on the one usable sample");
    else
        snprintf(buf, len, " on all %zu usable samples (lines %ld to %ld)", c->usable,
                 c->first_line, c->last_line);
}

int fit_input_check_columns(const fit_input_check *c, const char *path, size_t count,
                            lens_err *err)
{
    char rows[96];
    usable_rows(c, rows, sizeof rows);
    if (c->usable == 0) {
        lens_errf(err, path, 0, "none of the %zu samples is usable: every ray is blocked "
                  "(out_eta 0, or an output nan)", count);
        return -1;
    }
    for (int i = 0; i < c->nin; i++) {
        const fit_spread *s = &c->in[i];
        if (!no_spread(s))
            continue;
        const char *name = c->in_names[i], *unit = strcmp(name, "lambda") == 0 ? " um" : "";
        if (s->hi == s->lo)
            lens_errf(err, path, c->first_line, "input %s is %.10g%s%s: leave it out of "
                      "--inputs", name, s->lo, unit, rows);
        else
            lens_errf(err, path, c->first_line, "input %s varies only from %.17g to %.17g%s%s "
                      "(by less than 1e-12 of its size): leave it out of --inputs",
                      name, s->lo, s->hi, unit, rows);
        return -1;
    }
    return 0;
}

/* The meridional frame fits in r = |(x, y)|, u' = (x u + y v) / r and v' = (x v - y u) / r
 * (poly_frame.c): each must vary over the usable rows. */
int fit_input_check_frame(const fit_input_check *c, const char *path, lens_err *err)
{
    static const char *const what[3] = {
        "the sensor radius r = sqrt(x^2 + y^2)",
        "the radial direction u' = (x u + y v) / r",
        "the skew direction v' = (x v - y u) / r"};
    static const char *const unit[3] = {" mm", "", ""};
    char rows[96];
    usable_rows(c, rows, sizeof rows);
    for (int k = 0; k < 3 && c->ix >= 0 && c->iy >= 0 && c->iu >= 0 && c->iv >= 0; k++) {
        const fit_spread *s = &c->frame[k];
        if (!no_spread(s))
            continue;
        lens_errf(err, path, c->first_line, "%s of the meridional frame is %.10g%s%s%s: fit "
                  "rays that vary in it, or give --frame none", what[k], s->lo, unit[k], rows,
                  k == 2 && s->lo == 0 ? " (every one a meridional ray, its direction along "
                                         "its sensor point)" : "");
        return -1;
    }
    return 0;
}

