/* Field curve and focal shift pictures (field_curves.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sparselens/field_curves.h"
#include "sparselens/plot.h"

static const double white[3] = {1, 1, 1}, black[3] = {0, 0, 0};

/* Collects one quantity over the rows of a model and wavelength, against field. */
enum { Q_TAN, Q_SAG, Q_DIST, Q_LAT };

static double quantity(const field_row *r, int q)
{
    switch (q) {
    case Q_TAN: return r->focus.z_tan;
    case Q_SAG: return r->focus.z_sag;
    case Q_DIST: return r->distortion_pct;
    default: return r->lateral_um;
    }
}

static void panel_range(const field_figure *fig, int q0, int q1, double *lo, double *hi)
{
    size_t n = (size_t)fig->nmodels * fig->nfields * fig->nl;
    double *v = malloc(sizeof(double) * 2 * (n ? n : 1));
    if (!v) {
        *lo = -1, *hi = 1;
        return;
    }
    for (size_t i = 0; i < n; i++)
        v[2 * i] = quantity(&fig->rows[i], q0), v[2 * i + 1] = quantity(&fig->rows[i], q1);
    plot_range(v, (int)(2 * n), 0, lo, hi);
    if (*lo > 0)
        *lo = 0;
    if (*hi < 0)
        *hi = 0;
    free(v);
}

static void draw(const field_figure *fig, const plot_panel *p, int q, double thick)
{
    double *x = malloc(sizeof(double) * fig->nfields), *y = malloc(sizeof(double) * fig->nfields);
    for (int m = 0; x && y && m < fig->nmodels; m++)
        for (int l = 0; l < fig->nl; l++) {
            double rgb[3];
            plot_lambda_rgb(fig->lambda[l], rgb);
            for (int f = 0; f < fig->nfields; f++) {
                x[f] = quantity(&fig->rows[((size_t)m * fig->nfields + f) * fig->nl + l], q);
                y[f] = fig->field[f];
            }
            if (m == 0)
                plot_line(p, x, y, fig->nfields, rgb, thick);
            else
                plot_dots(p, x, y, fig->nfields, rgb, thick > 1 ? 2.5 : 1.5);
        }
    free(x);
    free(y);
}

int field_write_png(const field_figure *fig, const char *path, lens_err *err)
{
    const int PW = 300, PH = 360, left = 60, gap = 70, top = 84;
    img_canvas *c = img_new(left + 3 * (PW + gap), top + PH + 50, white);
    if (!c) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    plot_title(c, 10, 22, img_width(c) - 20, fig->title, 14, black);
    double lx = plot_legend_lambdas(c, 10, 44, fig->lambda, fig->nl);
    char s[128];
    snprintf(s, sizeof s, "focus: T thick, S thin%s%s%s", fig->nmodels > 1 ? "; dots " : "",
             fig->nmodels > 1 ? fig->model_names[1] : "", fig->nmodels > 1 ? "" : "");
    img_text(c, lx + 10, 44, s, 11, black);
    double ftop = 0;
    for (int f = 0; f < fig->nfields; f++)
        ftop = fmax(ftop, fig->field[f]);
    const char *unit = fig->finite ? "field, mm" : "field, °";
    const char *titles[3] = {"field curves, mm", "distortion, %", "lateral colour, µm"};
    for (int k = 0; k < 3; k++) {
        plot_panel p = {c, left + k * (PW + gap), top, PW, PH, 0, 1, 0, ftop > 0 ? ftop : 1};
        int q0 = k == 0 ? Q_TAN : k == 1 ? Q_DIST : Q_LAT, q1 = k == 0 ? Q_SAG : q0;
        panel_range(fig, q0, q1, &p.xmin, &p.xmax);
        plot_axes(&p, titles[k], NULL, unit);
        draw(fig, &p, q0, 2.5);
        if (k == 0)
            draw(fig, &p, Q_SAG, 1);
    }
    int rc = img_write_png(c, path, err);
    img_free(c);
    return rc;
}

int field_shift_write_png(const field_shift_figure *fig, const char *path, lens_err *err)
{
    const int PW = 520, PH = 320, left = 70, top = 64;
    img_canvas *c = img_new(left + PW + 30, top + PH + 50, white);
    double *um = malloc(sizeof(double) * (size_t)fig->nmodels * fig->n);
    if (!c || !um) {
        img_free(c);
        free(um);
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    plot_title(c, 10, 22, img_width(c) - 20, fig->title, 14, black);
    for (int i = 0; i < fig->nmodels * fig->n; i++)
        um[i] = 1e3 * fig->shift[i];
    plot_panel p = {c, left, top, PW, PH, fig->lambda[0], fig->lambda[fig->n - 1], 0, 0};
    plot_range(um, fig->nmodels * fig->n, 0, &p.ymin, &p.ymax);
    plot_axes(&p, "chromatic focal shift, µm", "wavelength, µm", "µm");
    const double blue[3] = {0, 0.35, 0.75}, red[3] = {0.8, 0.1, 0.1};
    plot_line(&p, fig->lambda, um, fig->n, blue, 2);
    if (fig->nmodels > 1)
        plot_dots(&p, fig->lambda, um + fig->n, fig->n, red, 2.5);
    double lx = plot_legend(c, left, 44, blue, 0, fig->model_names[0]);
    if (fig->nmodels > 1)
        plot_legend(c, lx, 44, red, 1, fig->model_names[1]);
    int rc = img_write_png(c, path, err);
    img_free(c);
    free(um);
    return rc;
}
