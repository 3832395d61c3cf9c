/* Spot diagram pictures: PNG panels through image.h, density images through exr_io.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/exr_io.h"
#include "sparselens/image.h"
#include "sparselens/plot.h"
#include "sparselens/spot.h"

typedef struct {
    double cx, cy; /* panel centre on the sensor, mm (the pooled centroid) */
} panel;

/* Common half-width (mm) of every panel and the panel centres. */
static double layout(const spot_figure *fig, panel *pn)
{
    double half = 0;
    for (int m = 0; m < fig->nmodels; m++)
        for (int f = 0; f < fig->nfields; f++) {
            const spot *s = fig->spots + (size_t)(m * fig->nfields + f) * fig->nl;
            double cx = 0, cy = 0;
            size_t k = 0;
            for (int l = 0; l < fig->nl; l++)
                for (size_t i = 0; i < s[l].passed; i++, k++)
                    cx += s[l].ray[4 * i], cy += s[l].ray[4 * i + 1];
            panel *p = &pn[m * fig->nfields + f];
            p->cx = k ? cx / (double)k : s[0].chief[0];
            p->cy = k ? cy / (double)k : s[0].chief[1];
            for (int l = 0; l < fig->nl; l++) {
                for (size_t i = 0; i < s[l].passed; i++)
                    half = fmax(half, fmax(fabs(s[l].ray[4 * i] - p->cx), fabs(s[l].ray[4 * i + 1] - p->cy)));
                if (isfinite(s[l].airy))
                    half = fmax(half, s[l].airy);
            }
        }
    return half > 0 ? 1.15 * half : 1e-3;
}

int spot_write_png(const spot_figure *fig, const char *path, lens_err *err)
{
    const int P = 300, gap = 16, head = 78, foot = 66;
    int W = fig->nfields * (P + gap) + gap;
    int H = head + fig->nmodels * (P + foot) + 8;
    const double white[3] = {1, 1, 1}, black[3] = {0, 0, 0}, grey[3] = {0.6, 0.6, 0.6},
                 light[3] = {0.88, 0.88, 0.88};
    /* the title: the lens and what it shows on one line, the setup (f-number, object,
     * focus) on the next; the picture is wide enough for each at 80 % of its height (a
     * one-field picture too), and each shrinks to fit rather than being cut off */
    char line1[512];
    const char *setup = strstr(fig->title, "  f/");
    snprintf(line1, sizeof line1, "%.*s", setup ? (int)(setup - fig->title) : (int)strlen(fig->title),
             fig->title);
    double wmin = fmax(420, 2 * gap + fmax(img_text_width(line1, 0.8 * 14),
                                           setup ? img_text_width(setup + 2, 0.8 * 11) : 0));
    panel *pn = calloc((size_t)(fig->nmodels * fig->nfields), sizeof *pn);
    img_canvas *c = img_new(W < wmin ? (int)ceil(wmin) : W, H, white);
    if (!pn || !c) {
        free(pn);
        img_free(c);
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    W = img_width(c);
    double half = layout(fig, pn), px = P / (2 * half); /* pixels per mm */
    plot_title(c, gap, 22, W - 2 * gap, line1, 14, black);
    if (setup)
        plot_title(c, gap, 42, W - 2 * gap, setup + 2, 11, black);
    /* legend: wavelengths in their colours */
    double lx = gap;
    for (int l = 0; l < fig->nl; l++) {
        double rgb[3];
        char s[32];
        plot_lambda_rgb(fig->spots[l].lambda, rgb);
        snprintf(s, sizeof s, "%.4g µm", fig->spots[l].lambda);
        img_dot(c, lx + 5, 61, 4, rgb, 1);
        img_text(c, lx + 14, 66, s, 11, rgb);
        lx += 24 + img_text_width(s, 11);
    }
    double bar = plot_nice(half * 1000 * 0.8) / 1000; /* mm */
    for (int m = 0; m < fig->nmodels; m++)
        for (int f = 0; f < fig->nfields; f++) {
            const spot *s = fig->spots + (size_t)(m * fig->nfields + f) * fig->nl;
            const panel *p = &pn[m * fig->nfields + f];
            double x0 = gap + f * (P + gap), y0 = head + m * (P + foot);
            double ox = x0 + P / 2.0, oy = y0 + P / 2.0;
            img_rect(c, x0, y0, x0 + P, y0 + P, light, 1);
            img_line(c, ox, y0, ox, y0 + P, light, 1);
            img_line(c, x0, oy, x0 + P, oy, light, 1);
            /* Airy disc of the first wavelength, about the centroid */
            if (isfinite(s[0].airy))
                img_circle(c, ox, oy, s[0].airy * px, grey, 1);
            size_t total = 0;
            for (int l = 0; l < fig->nl; l++)
                total += s[l].passed;
            double alpha = total > 3000 ? 0.5 : 0.85, dr = total > 3000 ? 1.2 : 1.8;
            for (int l = 0; l < fig->nl; l++) {
                double rgb[3];
                plot_lambda_rgb(s[l].lambda, rgb);
                /* sensor y up in the picture */
                for (size_t i = 0; i < s[l].passed; i++)
                    img_dot(c, ox + (s[l].ray[4 * i] - p->cx) * px,
                            oy - (s[l].ray[4 * i + 1] - p->cy) * px, dr, rgb, alpha);
            }
            /* chief ray of the first wavelength */
            double chx = ox + (s[0].chief[0] - p->cx) * px, chy = oy - (s[0].chief[1] - p->cy) * px;
            img_line(c, chx - 5, chy, chx + 5, chy, black, 1);
            img_line(c, chx, chy - 5, chx, chy + 5, black, 1);
            /* scale bar, bottom left */
            double by = y0 + P - 12, bl = bar * px;
            img_line(c, x0 + 10, by, x0 + 10 + bl, by, black, 2);
            img_line(c, x0 + 10, by - 4, x0 + 10, by + 4, black, 1);
            img_line(c, x0 + 10 + bl, by - 4, x0 + 10 + bl, by + 4, black, 1);
            char t[160];
            snprintf(t, sizeof t, "%g µm", bar * 1000);
            img_text(c, x0 + 10, by - 8, t, 10, black);
            /* labels under the panel */
            double rms = 0;
            size_t np = 0;
            for (int l = 0; l < fig->nl; l++)
                if (s[l].passed)
                    rms += s[l].rms_centroid * s[l].rms_centroid * (double)s[l].passed, np += s[l].passed;
            rms = np ? sqrt(rms / (double)np) : NAN; /* about each wavelength's centroid */
            snprintf(t, sizeof t, "%s%sfield %g%s", fig->nmodels > 1 ? fig->model_names[m] : "",
                     fig->nmodels > 1 ? "  " : "", s[0].field, fig->finite ? " mm" : "°");
            img_text(c, x0 + 2, y0 + P + 18, t, 12, black);
            snprintf(t, sizeof t, "RMS %.3g µm  y %.4g mm", rms * 1000, s[0].chief[1]);
            img_text(c, x0 + 2, y0 + P + 36, t, 11, black);
            snprintf(t, sizeof t, "Airy r %.3g µm (circle)", s[0].airy * 1000);
            img_text(c, x0 + 2, y0 + P + 53, t, 10, grey);
            /* a wavelength the model cannot image at this field says so in the panel */
            for (int l = 0, k = 0; l < fig->nl; l++)
                if (s[l].not_imaged) {
                    double rgb[3];
                    plot_lambda_rgb(s[l].lambda, rgb);
                    snprintf(t, sizeof t, "%.4g µm: not imaged", s[l].lambda);
                    img_text(c, x0 + 8, y0 + 18 + 16 * k++, t, 10, rgb);
                }
        }
    int rc = img_write_png(c, path, err);
    img_free(c);
    free(pn);
    return rc;
}

int spot_write_exr(const spot_figure *fig, const char *path, double *um_per_pixel,
                   int *panel_px, lens_err *err)
{
    const int P = 256;
    int W = fig->nfields * P, H = fig->nmodels * P, nc = fig->nl + 1;
    panel *pn = calloc((size_t)(fig->nmodels * fig->nfields), sizeof *pn);
    float **planes = calloc((size_t)nc, sizeof *planes);
    char (*names)[32] = calloc((size_t)nc, sizeof *names);
    const char **np = calloc((size_t)nc, sizeof *np);
    int rc = -1;
    if (!pn || !planes || !names || !np)
        goto oom;
    for (int k = 0; k < nc; k++)
        if (!(planes[k] = calloc((size_t)W * (size_t)H, sizeof(float))))
            goto oom;
    double half = layout(fig, pn), pix = 2 * half / P; /* mm per pixel */
    double area_um2 = pix * pix * 1e6;
    for (int l = 0; l < fig->nl; l++) {
        snprintf(names[l], sizeof names[l], "lambda_%.0fnm", fig->spots[l].lambda * 1000);
        for (int k = 0; k < l; k++)
            if (strcmp(names[k], names[l]) == 0)
                snprintf(names[l], sizeof names[l], "lambda_%.0fnm_%d", fig->spots[l].lambda * 1000, l);
        np[l] = names[l];
    }
    np[fig->nl] = "density";
    for (int m = 0; m < fig->nmodels; m++)
        for (int f = 0; f < fig->nfields; f++) {
            const spot *s = fig->spots + (size_t)(m * fig->nfields + f) * fig->nl;
            const panel *p = &pn[m * fig->nfields + f];
            for (int l = 0; l < fig->nl; l++) {
                if (!s[l].rays)
                    continue;
                float w = (float)(1.0 / ((double)s[l].rays * area_um2));
                for (size_t i = 0; i < s[l].passed; i++) {
                    int x = (int)floor((s[l].ray[4 * i] - p->cx) / pix + P / 2.0);
                    int y = (int)floor(P / 2.0 - (s[l].ray[4 * i + 1] - p->cy) / pix);
                    if (x < 0 || x >= P || y < 0 || y >= P)
                        continue;
                    size_t at = (size_t)(m * P + y) * (size_t)W + (size_t)(f * P + x);
                    planes[l][at] += w;
                    planes[fig->nl][at] += w / (float)fig->nl;
                }
            }
        }
    *um_per_pixel = pix * 1000;
    *panel_px = P;
    rc = exr_write_float(path, W, H, nc, np, (const float *const *)planes, err);
    goto out;
oom:
    lens_errf(err, path, 0, "out of memory");
out:
    if (planes)
        for (int k = 0; k < nc; k++)
            free(planes[k]);
    free(planes);
    free(names);
    free(np);
    free(pn);
    return rc;
}
