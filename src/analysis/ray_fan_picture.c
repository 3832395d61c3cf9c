/* Ray fan pictures (ray_fan.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sparselens/plot.h"
#include "sparselens/ray_fan.h"

int ray_fan_write_png(const ray_fan_figure *fig, const char *path, lens_err *err)
{
    const int PW = 340, PH = 190, left = 70, gap = 60, top = 84, rowgap = 56;
    int W = left + 2 * (PW + gap), H = top + fig->nfields * (PH + rowgap) + 10;
    const double white[3] = {1, 1, 1}, black[3] = {0, 0, 0};
    img_canvas *c = img_new(W, H, white);
    if (!c) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    /* one scale for every panel, in um */
    double lo = 0, hi = 0;
    size_t nfans = (size_t)fig->nmodels * fig->nfields * fig->nl;
    for (size_t k = 0; k < nfans; k++) {
        const ray_fan *fn = &fig->fans[k];
        for (int i = 0; i < fn->npts; i++) {
            double a = fn->ey[i], b = fn->ex[fn->npts + i];
            if (isfinite(a))
                hi = fmax(hi, fabs(a));
            if (isfinite(b))
                hi = fmax(hi, fabs(b));
        }
    }
    hi = hi > 0 ? hi * 1e3 : 1;
    double dummy[2] = {-hi, hi};
    plot_range(dummy, 2, 1, &lo, &hi);
    plot_title(c, left - 50, 22, W - left + 40, fig->title, 14, black);
    double lx = plot_legend_lambdas(c, left - 50, 44, fig->lambda, fig->nl);
    if (fig->nmodels > 1) {
        char s[64];
        snprintf(s, sizeof s, "lines %s, dots %s", fig->model_names[0], fig->model_names[1]);
        img_text(c, lx + 10, 44, s, 11, black);
    }
    double *x = NULL, *y = NULL;
    for (int f = 0; f < fig->nfields; f++)
        for (int side = 0; side < 2; side++) {
            plot_panel p = {c, left + side * (PW + gap), top + f * (PH + rowgap), PW, PH, -1, 1, lo, hi};
            char t[128];
            snprintf(t, sizeof t, "%s  field %g%s", side ? "sagittal ex" : "tangential ey",
                     fig->field[f], fig->finite ? " mm" : "°");
            plot_axes(&p, t, side ? "px" : "py", "µm");
            for (int m = 0; m < fig->nmodels; m++)
                for (int l = 0; l < fig->nl; l++) {
                    const ray_fan *fn = &fig->fans[((size_t)m * fig->nfields + f) * fig->nl + l];
                    double rgb[3];
                    plot_lambda_rgb(fig->lambda[l], rgb);
                    free(x), free(y);
                    x = malloc(sizeof(double) * fn->npts), y = malloc(sizeof(double) * fn->npts);
                    if (!x || !y)
                        continue;
                    for (int i = 0; i < fn->npts; i++) {
                        x[i] = fn->pupil[i];
                        y[i] = 1e3 * (side ? fn->ex[fn->npts + i] : fn->ey[i]);
                    }
                    if (m == 0)
                        plot_line(&p, x, y, fn->npts, rgb, 2);
                    else
                        plot_dots(&p, x, y, fn->npts, rgb, 2);
                }
        }
    free(x), free(y);
    int rc = img_write_png(c, path, err);
    img_free(c);
    return rc;
}
