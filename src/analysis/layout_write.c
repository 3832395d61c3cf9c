/* The layout drawing as SVG text and as a PNG (layout.h). Both draw the same lines in
 * the same order: elements, stop, sensor, axis, lens rays, system rays. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sparselens/escape.h"
#include "sparselens/image.h"
#include "sparselens/layout.h"
#include "sparselens/outfile.h"
#include "sparselens/plot.h"

static const double glass_fill[3] = {0.80, 0.90, 0.97}, glass_edge[3] = {0.2, 0.35, 0.5},
                    dark[3] = {0.1, 0.1, 0.1}, axis_rgb[3] = {0.6, 0.6, 0.6};

static void hex(const double rgb[3], char s[8])
{
    snprintf(s, 8, "#%02x%02x%02x", (int)lround(255 * rgb[0]), (int)lround(255 * rgb[1]),
             (int)lround(255 * rgb[2]));
}

/* A field's label for legends: "10°" or "100 mm" (the PNG's and the SVG's text is UTF-8). */
static void field_label(const layout_drawing *d, int f, char *s, size_t n)
{
    snprintf(s, n, "%g%s", d->field[f], d->finite ? " mm" : "°");
}

int layout_write_svg(const layout_drawing *d, const char *path, lens_err *err)
{
    outfile *of = outfile_open(path, err);
    if (!of)
        return -1;
    FILE *f = outfile_stream(of);
    double span = fmax(d->zmax - d->zmin, d->ymax - d->ymin), pad = 0.04 * span, w = span / 900;
    double x0 = d->zmin - pad, y0 = -d->ymax - 2 * pad - 0.06 * span;
    double W = d->zmax - d->zmin + 2 * pad, H = d->ymax - d->ymin + 3 * pad + 0.06 * span;
    /* y is up in the lens frame, down in SVG: every point is written as (z, -y) */
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"%.6f %.6f %.6f %.6f\" "
               "width=\"%.0fmm\" height=\"%.0fmm\">\n",
            x0, y0, W, H, W, H);
    fputs("<title>", f);
    text_xml(f, d->title ? d->title : "layout");
    fputs("</title>\n<desc>Meridional section, lens frame in mm: x = z (towards the sensor), "
          "y = -y (the picture's y grows down)</desc>\n", f);
    fprintf(f, "<rect x=\"%.6f\" y=\"%.6f\" width=\"%.6f\" height=\"%.6f\" fill=\"white\"/>\n", x0, y0, W, H);
    char c[8];
    for (int i = 0; i < d->nlines; i++) {
        const layout_line *l = &d->line[i];
        double rgb[3];
        const char *fill = "none", *dash = "";
        char stroke[8], fillc[8];
        double sw = w;
        switch (l->kind) {
        case LAYOUT_ELEMENT: hex(glass_edge, stroke), hex(glass_fill, fillc), fill = fillc; sw = 1.5 * w; break;
        case LAYOUT_STOP: hex(dark, stroke), sw = 3 * w; break;
        case LAYOUT_SENSOR: hex(dark, stroke), sw = 2.5 * w; break;
        case LAYOUT_AXIS: hex(axis_rgb, stroke), dash = " stroke-dasharray=\"4 2\""; break;
        case LAYOUT_RAY: layout_field_rgb(l->field, rgb), hex(rgb, stroke); break;
        default: hex(dark, stroke), dash = " stroke-dasharray=\"1 1\""; break;
        }
        fprintf(f, "<%s fill=\"%s\" stroke=\"%s\" stroke-width=\"%.6f\"%s points=\"",
                l->kind == LAYOUT_ELEMENT ? "polygon" : "polyline", fill, stroke, sw, dash);
        for (int k = 0; k < l->n; k++)
            if (isfinite(l->zy[2 * k]) && isfinite(l->zy[2 * k + 1]))
                fprintf(f, "%s%.6f,%.6f", k ? " " : "", l->zy[2 * k], -l->zy[2 * k + 1]);
        fprintf(f, "\"/>\n");
    }
    double fs = 0.03 * span, tx = d->zmin, ty = y0 + 1.2 * fs;
    fprintf(f, "<text x=\"%.6f\" y=\"%.6f\" font-family=\"sans-serif\" font-size=\"%.6f\">", tx, ty, fs);
    text_xml(f, d->title ? d->title : "");
    fputs("</text>\n", f);
    for (int k = 0; k < d->nfields; k++) {
        double rgb[3];
        char s[64];
        layout_field_rgb(k, rgb);
        hex(rgb, c);
        field_label(d, k, s, sizeof s);
        fprintf(f, "<text x=\"%.6f\" y=\"%.6f\" font-family=\"sans-serif\" font-size=\"%.6f\" fill=\"%s\">",
                tx + k * 8 * fs, ty + 1.4 * fs, 0.8 * fs, c);
        text_xml(f, s);
        fputs("</text>\n", f);
    }
    fprintf(f, "</svg>\n");
    return outfile_commit(of, err);
}

int layout_write_png(const layout_drawing *d, const char *path, int width, lens_err *err)
{
    const double white[3] = {1, 1, 1};
    double margin = 30, head = 56, spanz = d->zmax - d->zmin, spany = d->ymax - d->ymin;
    double s = (width - 2 * margin) / (spanz > 0 ? spanz : 1);
    int height = (int)ceil(spany * s + head + 2 * margin + 20);
    if (height > 4 * width) /* a lens taller than wide stays on the page */
        s *= 4.0 * width / height, height = 4 * width;
    img_canvas *c = img_new(width, height, white);
    double *xy = NULL;
    int cap = 0;
    if (!c) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    double ox = margin - d->zmin * s, oy = head + margin + d->ymax * s; /* pixel of z = 0, y = 0 */
    for (int i = 0; i < d->nlines; i++) {
        const layout_line *l = &d->line[i];
        if (l->n > cap) {
            free(xy);
            cap = l->n;
            xy = malloc(sizeof(double) * 2 * (size_t)cap);
            if (!xy)
                break;
        }
        for (int k = 0; k < l->n; k++)
            xy[2 * k] = ox + l->zy[2 * k] * s, xy[2 * k + 1] = oy - l->zy[2 * k + 1] * s;
        double rgb[3], t = 1;
        switch (l->kind) {
        case LAYOUT_ELEMENT: img_polygon(c, xy, l->n, glass_fill, 1); rgb[0] = glass_edge[0], rgb[1] = glass_edge[1], rgb[2] = glass_edge[2], t = 1.5; break;
        case LAYOUT_STOP: rgb[0] = rgb[1] = rgb[2] = dark[0], t = 3; break;
        case LAYOUT_SENSOR: rgb[0] = rgb[1] = rgb[2] = dark[0], t = 2.5; break;
        case LAYOUT_AXIS: rgb[0] = axis_rgb[0], rgb[1] = axis_rgb[1], rgb[2] = axis_rgb[2]; break;
        case LAYOUT_RAY: layout_field_rgb(l->field, rgb); break;
        default: rgb[0] = rgb[1] = rgb[2] = 0, t = 1; break;
        }
        int closed = l->kind == LAYOUT_ELEMENT;
        for (int k = 0; k + 1 < l->n + closed; k++) {
            int a = k, b = (k + 1) % l->n;
            if (l->kind == LAYOUT_AXIS || l->kind == LAYOUT_SYSTEM)
                img_dashed_line(c, xy[2 * a], xy[2 * a + 1], xy[2 * b], xy[2 * b + 1], rgb, t,
                                l->kind == LAYOUT_AXIS ? 8 : 3);
            else
                img_line(c, xy[2 * a], xy[2 * a + 1], xy[2 * b], xy[2 * b + 1], rgb, t);
        }
    }
    free(xy);
    plot_title(c, margin, 24, width - 2 * margin, d->title ? d->title : "", 14, dark);
    double lx = margin;
    for (int k = 0; k < d->nfields; k++) {
        double rgb[3];
        char s2[64];
        layout_field_rgb(k, rgb);
        field_label(d, k, s2, sizeof s2);
        img_line(c, lx, 42, lx + 18, 42, rgb, 2);
        img_text(c, lx + 24, 46, s2, 11, dark);
        lx += 40 + img_text_width(s2, 11);
    }
    /* a scale bar of a round length */
    double bar = pow(10, floor(log10(spanz / 4)));
    if (spanz / bar > 8)
        bar *= 5;
    else if (spanz / bar > 4)
        bar *= 2;
    double by = height - 14, bx = width - margin - bar * s;
    img_line(c, bx, by, bx + bar * s, by, dark, 2);
    char s3[32];
    snprintf(s3, sizeof s3, "%g mm", bar);
    img_text(c, bx, by - 6, s3, 10, dark);
    int rc = img_write_png(c, path, err);
    img_free(c);
    return rc;
}
