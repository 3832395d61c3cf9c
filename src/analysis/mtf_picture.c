/* MTF pictures (mtf.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sparselens/mtf.h"
#include "sparselens/plot.h"

int mtf_write_png(const mtf_figure *fig, const char *path, lens_err *err)
{
    const int PW = 330, PH = 240, left = 60, gap = 50, top = 84;
    int cols = fig->nfields < 3 ? fig->nfields : 3, rowsn = (fig->nfields + cols - 1) / cols;
    const double white[3] = {1, 1, 1}, black[3] = {0, 0, 0}, grey[3] = {0.55, 0.55, 0.55},
                 limit[3] = {0.75, 0.75, 0.75}, blue[3] = {0.0, 0.3, 0.75}, red[3] = {0.8, 0.15, 0.1};
    img_canvas *c = img_new(left + cols * (PW + gap), top + rowsn * (PH + 60), white);
    double *x = malloc(sizeof(double) * (fig->nrows + 200)), *y = malloc(sizeof(double) * (fig->nrows + 200));
    if (!c || !x || !y) {
        img_free(c), free(x), free(y);
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    plot_title(c, 10, 22, img_width(c) - 20, fig->title, 14, black);
    double lx = plot_legend(c, 10, 44, blue, 0, "diffraction T (thick) S (thin)");
    lx = plot_legend(c, lx, 44, grey, 0, "geometric");
    if (fig->nu_c > 0 && !(fig->through_focus > 0))
        lx = plot_legend(c, lx, 44, limit, 0, "diffraction limit");
    if (fig->nmodels > 1) {
        char s[64];
        snprintf(s, sizeof s, "dots: %s", fig->model_names[1]);
        plot_legend(c, lx, 44, red, 1, s);
    }
    int want = fig->nl > 1 ? fig->nl : 0; /* the all-wavelength rows, or the only wavelength */
    double xmin = INFINITY, xmax = -INFINITY;
    for (size_t i = 0; i < fig->nrows; i++)
        xmin = fmin(xmin, fig->rows[i].x), xmax = fmax(xmax, fig->rows[i].x);
    if (!(xmax > xmin))
        xmax = xmin + 1;
    for (int f = 0; f < fig->nfields; f++) {
        plot_panel p = {c, left + (f % cols) * (PW + gap), top + (f / cols) * (PH + 60), PW, PH, xmin, xmax, 0, 1.02};
        char t[128];
        snprintf(t, sizeof t, "field %g%s", fig->field[f], fig->finite ? " mm" : "°");
        plot_axes(&p, t, fig->through_focus > 0 ? "focus shift, mm" : "cycles/mm", "MTF");
        if (fig->nu_c > 0 && !(fig->through_focus > 0)) {
            int k = 0;
            for (; k < 200; k++)
                x[k] = xmin + (xmax - xmin) * k / 199.0, y[k] = mtf_diffraction_limit(x[k] / fig->nu_c);
            plot_line(&p, x, y, k, limit, 1.5);
        }
        for (int m = 0; m < fig->nmodels; m++)
            for (int q = 0; q < 4; q++) { /* diff T, diff S, geo T, geo S */
                int k = 0;
                for (size_t i = 0; i < fig->nrows; i++) {
                    const mtf_row *r = &fig->rows[i];
                    if (r->model != m || r->field != f || r->lambda != want)
                        continue;
                    x[k] = r->x, y[k] = q < 2 ? r->diff[q] : r->geo[q - 2], k++;
                }
                const double *rgb = q < 2 ? blue : grey;
                if (m == 0)
                    plot_line(&p, x, y, k, rgb, q % 2 ? 1 : 2.5);
                else
                    plot_dots(&p, x, y, k, q < 2 ? red : grey, q % 2 ? 1.5 : 2.5);
            }
    }
    int rc = img_write_png(c, path, err);
    img_free(c);
    free(x), free(y);
    return rc;
}
