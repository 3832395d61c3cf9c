/* Grid map picture of lens-distort (see distort.h). */
#include <math.h>
#include <stdio.h>

#include <string.h>

#include "sparselens/distort.h"
#include "sparselens/image.h"
#include "sparselens/plot.h"

/* How each model's grid is drawn, so that a system drawn over its lens leaves the lens
 * visible: the lens wide and solid, the system thin, dashed and in another colour. */
typedef struct {
    double rgb[3], width, dash, dot;
} grid_style;

static const grid_style styles[2] = {{{0.05, 0.3, 0.8}, 3.2, 0, 2.6}, {{0.85, 0.15, 0.1}, 1.3, 5, 1.6}};

static void grid_segment(img_canvas *c, const grid_style *g, double x0, double y0, double x1, double y1)
{
    if (g->dash > 0)
        img_dashed_line(c, x0, y0, x1, y1, g->rgb, g->width, g->dash);
    else
        img_line(c, x0, y0, x1, y1, g->rgb, g->width);
}

int distort_write_png(const char *path, const char *title, int nmodels, const char *const *names,
                      const double *const *pts, int nx, int ny, double half_w, double half_h,
                      double factor, lens_err *err)
{
    const int S = 760, margin = 60, head = 86;
    double px = (S - 2.0 * margin) / (2 * fmax(half_w, half_h)); /* pixels per mm */
    int W = (int)(2 * half_w * px) + 2 * margin, H = (int)(2 * half_h * px) + 2 * margin + head;
    if (W < 480)
        W = 480;
    const double white[3] = {1, 1, 1}, black[3] = {0, 0, 0}, grey[3] = {0.72, 0.72, 0.72};
    img_canvas *c = img_new(W, H, white);
    if (!c) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    double ox = W / 2.0, oy = head + margin + half_h * px;
    /* the title on two lines (what, then the setup: f-number, object, focus), each
     * shrunk to the width rather than cut off */
    char line1[512];
    const char *setup = strstr(title, "  f/");
    snprintf(line1, sizeof line1, "%.*s", setup ? (int)(setup - title) : (int)strlen(title), title);
    plot_title(c, 14, 24, W - 28, line1, 14, black);
    if (setup)
        plot_title(c, 14, 44, W - 28, setup + 2, 11, black);
    char t[200];
    /* legend: each model in the style its grid is drawn in, then the ideal grid */
    double lx = 14, ly = 70;
    for (int m = 0; m < nmodels; m++) {
        grid_segment(c, &styles[m], lx, ly - 4, lx + 30, ly - 4);
        img_dot(c, lx + 15, ly - 4, styles[m].dot, styles[m].rgb, 1);
        img_text(c, lx + 38, ly, names[m], 12, styles[m].rgb);
        lx += 60 + img_text_width(names[m], 12);
    }
    img_line(c, lx, ly - 4, lx + 30, ly - 4, grey, 1);
    snprintf(t, sizeof t, "ideal grid;  displacement exaggerated ×%g", factor);
    img_text(c, lx + 38, ly, t, 12, black);
    img_rect(c, ox - half_w * px, oy - half_h * px, ox + half_w * px, oy + half_h * px, grey, 1);
    /* sensor y up in the picture */
#define PX(p) (ox + (p)[0] * px)
#define PY(p) (oy - (p)[1] * px)
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            const double *p = pts[0] + 4 * (j * nx + i);
            if (i + 1 < nx)
                img_line(c, PX(p), PY(p), PX(p + 4), PY(p + 4), grey, 1);
            if (j + 1 < ny)
                img_line(c, PX(p), PY(p), PX(p + 4 * nx), PY(p + 4 * nx), grey, 1);
        }
    for (int m = 0; m < nmodels; m++) {
        /* ideal + factor (real - ideal) */
        double q[2][2];
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                const double *p = pts[m] + 4 * (j * nx + i);
                if (!isfinite(p[2]))
                    continue;
                q[0][0] = p[0] + factor * (p[2] - p[0]);
                q[0][1] = p[1] + factor * (p[3] - p[1]);
                img_dot(c, PX(q[0]), PY(q[0]), styles[m].dot, styles[m].rgb, 1);
                const double *nb[2] = {i + 1 < nx ? p + 4 : NULL, j + 1 < ny ? p + 4 * nx : NULL};
                for (int k = 0; k < 2; k++) {
                    if (!nb[k] || !isfinite(nb[k][2]))
                        continue;
                    q[1][0] = nb[k][0] + factor * (nb[k][2] - nb[k][0]);
                    q[1][1] = nb[k][1] + factor * (nb[k][3] - nb[k][1]);
                    grid_segment(c, &styles[m], PX(q[0]), PY(q[0]), PX(q[1]), PY(q[1]));
                }
            }
    }
#undef PX
#undef PY
    /* a scale bar: 1, 2 or 5 x 10^k mm near a quarter of the width */
    double want = half_w / 2, e = pow(10, floor(log10(want))), mm = want / e;
    mm = (mm < 1.5 ? 1 : mm < 3.5 ? 2 : mm < 7.5 ? 5 : 10) * e;
    double by = H - 18;
    img_line(c, 14, by, 14 + mm * px, by, black, 2);
    snprintf(t, sizeof t, "%g mm on the sensor", mm);
    img_text(c, 22 + mm * px, by + 5, t, 11, black);
    int rc = img_write_png(c, path, err);
    img_free(c);
    return rc;
}
