/* Line plots for the designer analyses (plot.h). */
#include "sparselens/plot.h"

#include "sparselens/escape.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const double black[3] = {0, 0, 0}, grid[3] = {0.9, 0.9, 0.9}, axis[3] = {0.55, 0.55, 0.55};

void plot_lambda_rgb(double lambda, double rgb[3])
{
    if (!(lambda >= 0.38 && lambda <= 0.78)) {
        rgb[0] = rgb[1] = rgb[2] = 0.35;
        return;
    }
    double t = (0.70 - fmin(fmax(lambda, 0.40), 0.70)) / 0.30; /* 0 red .. 1 violet */
    double h = t * 270.0 / 60.0, v = 0.78;
    int i = (int)floor(h);
    double f = h - i, q = v * (1 - f), p = v * f;
    double c[6][3] = {{v, p, 0}, {q, v, 0}, {0, v, p}, {0, q, v}, {p, 0, v}, {v, 0, q}};
    memcpy(rgb, c[i < 0 ? 0 : i > 5 ? 5 : i], sizeof c[0]);
}

double plot_nice(double x)
{
    double e = pow(10, floor(log10(x))), m = x / e;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * e;
}

void plot_range(const double *v, int n, int symmetric, double *lo, double *hi)
{
    double a = INFINITY, b = -INFINITY;
    for (int i = 0; i < n; i++)
        if (isfinite(v[i]))
            a = fmin(a, v[i]), b = fmax(b, v[i]);
    if (!(a <= b))
        a = -1, b = 1;
    if (symmetric)
        b = fmax(fabs(a), fabs(b)), a = -b;
    double span = b - a, mag = fmax(fabs(a), fabs(b));
    if (!(span > 1e-9 * mag) || span == 0) {
        double pad = mag > 0 ? 0.1 * mag : 1e-6;
        a -= pad, b += pad;
        span = b - a;
    }
    *lo = a - 0.05 * span;
    *hi = b + 0.05 * span;
}

double plot_px(const plot_panel *p, double x)
{
    return p->x0 + (x - p->xmin) / (p->xmax - p->xmin) * p->w;
}

double plot_py(const plot_panel *p, double y)
{
    return p->y0 + p->h - (y - p->ymin) / (p->ymax - p->ymin) * p->h;
}

static void tick_label(double v, double step, char *s, size_t n)
{
    if (fabs(v) < 1e-9 * step)
        v = 0;
    snprintf(s, n, "%.4g", v);
}

void plot_title(img_canvas *c, double x, double y, double width, const char *raw, double height,
                const double rgb[3])
{
    char text[1024]; /* as drawn (escape.h), so that a cut falls between its characters */
    text_utf8(text, sizeof text, raw);
    double w = img_text_width(text, height);
    if (w <= width) {
        img_text(c, x, y, text, height, rgb);
        return;
    }
    double h = height * width / w;
    if (h >= 0.6 * height) {
        img_text(c, x, y, text, h, rgb);
        return;
    }
    /* too long even small: cut at a character that leaves room for the ellipsis */
    char buf[1024];
    size_t n = strlen(text) < sizeof buf - 4 ? strlen(text) : sizeof buf - 4;
    h = 0.6 * height;
    for (; n > 0; n--) {
        if ((text[n] & 0xC0) == 0x80) /* not inside a UTF-8 character */
            continue;
        snprintf(buf, sizeof buf, "%.*s…", (int)n, text);
        if (img_text_width(buf, h) <= width)
            break;
    }
    img_text(c, x, y, buf, h, rgb);
}

void plot_axes(const plot_panel *p, const char *title, const char *xlabel, const char *ylabel)
{
    char s[64];
    double xs = plot_nice((p->xmax - p->xmin) / 5), ys = plot_nice((p->ymax - p->ymin) / 5);
    for (double x = ceil(p->xmin / xs) * xs; x <= p->xmax + 1e-9 * xs; x += xs) {
        double X = plot_px(p, x);
        img_line(p->c, X, p->y0, X, p->y0 + p->h, grid, 1);
        tick_label(x, xs, s, sizeof s);
        img_text(p->c, X - img_text_width(s, 10) / 2, p->y0 + p->h + 14, s, 10, black);
    }
    for (double y = ceil(p->ymin / ys) * ys; y <= p->ymax + 1e-9 * ys; y += ys) {
        double Y = plot_py(p, y);
        img_line(p->c, p->x0, Y, p->x0 + p->w, Y, grid, 1);
        tick_label(y, ys, s, sizeof s);
        img_text(p->c, p->x0 - 6 - img_text_width(s, 10), Y + 4, s, 10, black);
    }
    if (p->xmin < 0 && p->xmax > 0)
        img_line(p->c, plot_px(p, 0), p->y0, plot_px(p, 0), p->y0 + p->h, axis, 1);
    if (p->ymin < 0 && p->ymax > 0)
        img_line(p->c, p->x0, plot_py(p, 0), p->x0 + p->w, plot_py(p, 0), axis, 1);
    img_rect(p->c, p->x0, p->y0, p->x0 + p->w, p->y0 + p->h, black, 1);
    if (title) /* beside the y label, if any */
        plot_title(p->c, p->x0, p->y0 - 8, p->w - (ylabel ? img_text_width(ylabel, 10) + 12 : 0),
                   title, 12, black);
    if (xlabel)
        img_text(p->c, p->x0 + p->w - img_text_width(xlabel, 10), p->y0 + p->h + 30, xlabel, 10, black);
    if (ylabel) /* above the frame at its right end: inside it overprinted the curves */
        img_text(p->c, p->x0 + p->w - img_text_width(ylabel, 10), p->y0 - 8, ylabel, 10, axis);
}

/* Liang-Barsky clipping of a segment to the panel's rectangle. */
static int clip(const plot_panel *p, double *x0, double *y0, double *x1, double *y1)
{
    double t0 = 0, t1 = 1, dx = *x1 - *x0, dy = *y1 - *y0;
    double q[4] = {*x0 - p->x0, p->x0 + p->w - *x0, *y0 - p->y0, p->y0 + p->h - *y0};
    double d[4] = {-dx, dx, -dy, dy};
    for (int k = 0; k < 4; k++) {
        if (d[k] == 0) {
            if (q[k] < 0)
                return 0;
            continue;
        }
        double t = q[k] / d[k];
        if (d[k] < 0)
            t0 = fmax(t0, t);
        else
            t1 = fmin(t1, t);
    }
    if (t0 > t1)
        return 0;
    double ax = *x0, ay = *y0;
    *x0 = ax + t0 * dx, *y0 = ay + t0 * dy;
    *x1 = ax + t1 * dx, *y1 = ay + t1 * dy;
    return 1;
}

void plot_line(const plot_panel *p, const double *x, const double *y, int n, const double rgb[3],
               double thickness)
{
    for (int i = 0; i + 1 < n; i++) {
        if (!isfinite(x[i]) || !isfinite(y[i]) || !isfinite(x[i + 1]) || !isfinite(y[i + 1]))
            continue;
        double a = plot_px(p, x[i]), b = plot_py(p, y[i]), c = plot_px(p, x[i + 1]), d = plot_py(p, y[i + 1]);
        if (clip(p, &a, &b, &c, &d))
            img_line(p->c, a, b, c, d, rgb, thickness);
    }
}

void plot_dots(const plot_panel *p, const double *x, const double *y, int n, const double rgb[3],
               double radius)
{
    for (int i = 0; i < n; i++) {
        if (!isfinite(x[i]) || !isfinite(y[i]))
            continue;
        double a = plot_px(p, x[i]), b = plot_py(p, y[i]);
        if (a >= p->x0 && a <= p->x0 + p->w && b >= p->y0 && b <= p->y0 + p->h)
            img_dot(p->c, a, b, radius, rgb, 1);
    }
}

double plot_legend(img_canvas *c, double x, double y, const double rgb[3], int dots, const char *text)
{
    if (dots)
        for (int k = 0; k < 3; k++)
            img_dot(c, x + 3 + 7 * k, y - 4, 2, rgb, 1);
    else
        img_line(c, x, y - 4, x + 18, y - 4, rgb, 2);
    img_text(c, x + 24, y, text, 11, black);
    return x + 34 + img_text_width(text, 11);
}

double plot_legend_lambdas(img_canvas *c, double x, double y, const double *lambda, int nl)
{
    for (int l = 0; l < nl; l++) {
        double rgb[3];
        char s[64];
        plot_lambda_rgb(lambda[l], rgb);
        snprintf(s, sizeof s, "%.4g µm", lambda[l]);
        x = plot_legend(c, x, y, rgb, 0, s);
    }
    return x;
}
