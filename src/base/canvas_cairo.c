/* The picture canvas of image.h through cairo (the only file that includes it): real
 * fonts (DejaVu Sans through fontconfig, so "µm" and "°" print), antialiased shapes,
 * and PNG, SVG or PDF output by the file name. A canvas records its drawing (a cairo
 * recording surface), so a picture written as SVG or PDF stays vector; raster pictures
 * (lens-render's preview: a rectangle per pixel) draw straight into an image surface. */
#include "sparselens/image.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "sparselens/escape.h"
#include "sparselens/outfile.h"

#define FONT "DejaVu Sans"

struct img_canvas {
    int w, h;
    cairo_surface_t *s;
    cairo_t *cr;
    long ops; /* drawing operations so far: a raster canvas is switched to at many */
    char *texts; /* with SPARSELENS_TEXT_BOXES set: a line per text drawn (text_box) */
    size_t ntexts, captexts;
};

/* The font on a context: unhinted metrics, so that a text measured by img_text_width is as
 * wide when drawn (hinted advances round per glyph: a long title came out 3 % wider
 * than measured and ran off the picture). */
static void set_font(cairo_t *cr)
{
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_font_options_t *o = cairo_font_options_create();
    cairo_font_options_set_hint_metrics(o, CAIRO_HINT_METRICS_OFF);
    cairo_set_font_options(cr, o);
    cairo_font_options_destroy(o);
}

/* Past this many operations a recorded canvas is turned into pixels: a preview that
 * draws each pixel would fill memory with recorded rectangles. */
#define MAX_RECORDED_OPS 200000

img_canvas *img_new(int width, int height, const double bg[3])
{
    if (width <= 0 || height <= 0)
        return NULL;
    img_canvas *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->w = width, c->h = height;
    cairo_rectangle_t extent = {0, 0, width, height};
    c->s = cairo_recording_surface_create(CAIRO_CONTENT_COLOR, &extent);
    c->cr = cairo_create(c->s);
    if (cairo_status(c->cr) != CAIRO_STATUS_SUCCESS) {
        img_free(c);
        return NULL;
    }
    cairo_set_source_rgb(c->cr, bg[0], bg[1], bg[2]);
    cairo_paint(c->cr);
    set_font(c->cr);
    return c;
}

void img_free(img_canvas *c)
{
    if (!c)
        return;
    if (c->cr)
        cairo_destroy(c->cr);
    if (c->s)
        cairo_surface_destroy(c->s);
    free(c->texts);
    free(c);
}

int img_width(const img_canvas *c) { return c->w; }
int img_height(const img_canvas *c) { return c->h; }

/* Replays the recording into an image surface and draws on that from now on. */
static void to_raster(img_canvas *c)
{
    cairo_surface_t *img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, c->w, c->h);
    cairo_t *cr = cairo_create(img);
    cairo_set_source_surface(cr, c->s, 0, 0);
    cairo_paint(cr);
    set_font(cr);
    cairo_destroy(c->cr);
    cairo_surface_destroy(c->s);
    c->s = img, c->cr = cr;
}

static int ok(img_canvas *c, int n, const double *v)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]) || fabs(v[i]) > 1e7)
            return 0;
    if (++c->ops == MAX_RECORDED_OPS && cairo_surface_get_type(c->s) == CAIRO_SURFACE_TYPE_RECORDING)
        to_raster(c);
    return 1;
}

static void source(img_canvas *c, const double rgb[3], double alpha)
{
    cairo_set_source_rgba(c->cr, rgb[0], rgb[1], rgb[2], alpha);
}

void img_line(img_canvas *c, double x0, double y0, double x1, double y1, const double rgb[3],
              double thickness)
{
    if (!ok(c, 5, (double[]){x0, y0, x1, y1, thickness}))
        return;
    source(c, rgb, 1);
    cairo_set_line_width(c->cr, thickness > 0 ? thickness : 1);
    cairo_move_to(c->cr, x0, y0);
    cairo_line_to(c->cr, x1, y1);
    cairo_stroke(c->cr);
}

void img_dashed_line(img_canvas *c, double x0, double y0, double x1, double y1,
                     const double rgb[3], double thickness, double dash)
{
    if (!ok(c, 6, (double[]){x0, y0, x1, y1, thickness, dash}))
        return;
    cairo_set_dash(c->cr, (double[]){dash, dash}, 2, 0);
    img_line(c, x0, y0, x1, y1, rgb, thickness);
    cairo_set_dash(c->cr, NULL, 0, 0);
}

void img_circle(img_canvas *c, double cx, double cy, double r, const double rgb[3],
                double thickness)
{
    if (!ok(c, 4, (double[]){cx, cy, r, thickness}) || r <= 0)
        return;
    source(c, rgb, 1);
    cairo_new_path(c->cr);
    cairo_arc(c->cr, cx, cy, r, 0, 2 * M_PI);
    if (thickness > 0) {
        cairo_set_line_width(c->cr, thickness);
        cairo_stroke(c->cr);
    } else {
        cairo_fill(c->cr);
    }
}

void img_rect(img_canvas *c, double x0, double y0, double x1, double y1, const double rgb[3],
              double thickness)
{
    if (!ok(c, 5, (double[]){x0, y0, x1, y1, thickness}))
        return;
    source(c, rgb, 1);
    cairo_rectangle(c->cr, fmin(x0, x1), fmin(y0, y1), fabs(x1 - x0), fabs(y1 - y0));
    if (thickness > 0) {
        cairo_set_line_width(c->cr, thickness);
        cairo_stroke(c->cr);
    } else {
        cairo_fill(c->cr);
    }
}

void img_dot(img_canvas *c, double x, double y, double radius, const double rgb[3], double alpha)
{
    if (!ok(c, 3, (double[]){x, y, radius}) || radius <= 0)
        return;
    source(c, rgb, alpha);
    cairo_new_path(c->cr);
    cairo_arc(c->cr, x, y, radius, 0, 2 * M_PI);
    cairo_fill(c->cr);
}

void img_polygon(img_canvas *c, const double *xy, int n, const double rgb[3], double alpha)
{
    if (n < 3 || !ok(c, 2 * n, xy))
        return;
    source(c, rgb, alpha);
    cairo_new_path(c->cr);
    for (int i = 0; i < n; i++)
        cairo_line_to(c->cr, xy[2 * i], xy[2 * i + 1]);
    cairo_close_path(c->cr);
    cairo_fill(c->cr);
}

/* The font size whose capital H is `height` pixels tall. */
static double font_size(cairo_t *cr, double height)
{
    cairo_set_font_size(cr, 100);
    cairo_text_extents_t e;
    cairo_text_extents(cr, "H", &e);
    double size = e.height > 0 ? 100 * height / e.height : height * 1.37;
    cairo_set_font_size(cr, size);
    return size;
}

/* Where each text lands, for checks that labels stay inside the picture and clear of
 * each other (tests/cli/pictures.sh): with the environment variable
 * SPARSELENS_TEXT_BOXES=FILE, writing a picture appends "# picture PATH W H" to FILE
 * and a line "x0 y0 x1 y1 TEXT" per text drawn (its ink box in pixels). */
static void text_box(img_canvas *c, double x, double y, const char *text)
{
    if (!getenv("SPARSELENS_TEXT_BOXES"))
        return;
    cairo_text_extents_t e;
    cairo_text_extents(c->cr, text, &e);
    char line[1024];
    int n = snprintf(line, sizeof line, "%.1f %.1f %.1f %.1f %s\n", x + e.x_bearing,
                     y + e.y_bearing, x + e.x_bearing + e.width, y + e.y_bearing + e.height, text);
    if (n <= 0 || (size_t)n >= sizeof line)
        return;
    if (c->ntexts + (size_t)n + 1 > c->captexts) {
        size_t cap = 2 * c->captexts + sizeof line;
        char *t = realloc(c->texts, cap);
        if (!t)
            return;
        c->texts = t, c->captexts = cap;
    }
    memcpy(c->texts + c->ntexts, line, (size_t)n + 1);
    c->ntexts += (size_t)n;
}

static void text_boxes_write(const img_canvas *c, const char *path)
{
    const char *log = getenv("SPARSELENS_TEXT_BOXES");
    FILE *f = log && *log ? fopen(log, "a") : NULL;
    if (!f)
        return;
    fprintf(f, "# picture %s %d %d\n%s", path, c->w, c->h, c->texts ? c->texts : "");
    fclose(f);
}

void img_text(img_canvas *c, double x, double y, const char *text, double height,
              const double rgb[3])
{
    if (!text || !*text || !ok(c, 3, (double[]){x, y, height}))
        return;
    /* cairo takes only well-formed UTF-8: any other string puts the context in error,
     * and it draws nothing more (a blank picture) */
    char shown[4096];
    text_utf8(shown, sizeof shown, text);
    source(c, rgb, 1);
    font_size(c->cr, height);
    text_box(c, x, y, shown);
    cairo_move_to(c->cr, x, y);
    cairo_show_text(c->cr, shown);
    cairo_new_path(c->cr);
}

double img_text_width(const char *text, double height)
{
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1);
    cairo_t *cr = cairo_create(s);
    set_font(cr);
    font_size(cr, height);
    cairo_text_extents_t e;
    char shown[4096];
    text_utf8(shown, sizeof shown, text);
    cairo_text_extents(cr, shown, &e);
    cairo_destroy(cr);
    cairo_surface_destroy(s);
    return e.x_advance;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

static cairo_status_t write_file(void *closure, const unsigned char *data, unsigned int len)
{
    return fwrite(data, 1, len, closure) == len ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

/* The picture onto a surface of the file's kind, written through f. */
static cairo_status_t render(const img_canvas *c, const char *path, FILE *f)
{
    cairo_surface_t *out;
    int vector = ends_with(path, ".svg") || ends_with(path, ".pdf");
    if (ends_with(path, ".svg"))
        out = cairo_svg_surface_create_for_stream(write_file, f, c->w, c->h);
    else if (ends_with(path, ".pdf"))
        out = cairo_pdf_surface_create_for_stream(write_file, f, c->w, c->h);
    else
        out = cairo_image_surface_create(CAIRO_FORMAT_RGB24, c->w, c->h);
    cairo_t *cr = cairo_create(out);
    cairo_set_source_surface(cr, c->s, 0, 0);
    cairo_paint(cr);
    cairo_destroy(cr);
    cairo_status_t st;
    if (vector) {
        cairo_surface_finish(out);
        st = cairo_surface_status(out);
    } else {
        st = cairo_surface_write_to_png_stream(out, write_file, f);
    }
    cairo_surface_destroy(out);
    return st;
}

int img_write_png(const img_canvas *c, const char *path, lens_err *err)
{
    /* the kind follows the name: PNG data in a file called .jpg is a file no viewer
     * opens as what its name says */
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    if (dot && (!slash || dot > slash) && !ends_with(path, ".png") && !ends_with(path, ".svg") &&
        !ends_with(path, ".pdf")) {
        lens_errf(err, path, 0, "a picture is written as PNG, SVG or PDF, by the name's ending "
                                "(.png, .svg, .pdf), and '%s' is none of them", dot);
        return -1;
    }
    char tmp[4096];
    if (cairo_status(c->cr) != CAIRO_STATUS_SUCCESS) { /* a drawing failed: not a picture */
        lens_errf(err, path, 0, "cannot draw the picture: %s",
                  cairo_status_to_string(cairo_status(c->cr)));
        return -1;
    }
    if (outfile_tmp_path(path, tmp, sizeof tmp) != 0) {
        lens_errf(err, path, 0, "cannot make a temporary file name");
        return -1;
    }
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        lens_errf(err, path, 0, "cannot write: %s", strerror(errno));
        return -1;
    }
    cairo_status_t st = render(c, path, f);
    int bad = st != CAIRO_STATUS_SUCCESS || fflush(f) != 0;
    if (fclose(f) != 0 || bad) {
        outfile_discard_path(tmp);
        lens_errf(err, path, 0, "cannot write the picture: %s",
                  st != CAIRO_STATUS_SUCCESS ? cairo_status_to_string(st) : "write error");
        return -1;
    }
    text_boxes_write(c, path);
    return outfile_commit_path(tmp, path, err);
}

int img_png_info(const char *path, int *width, int *height, long *nonblank, lens_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        lens_errf(err, path, 0, "cannot open: %s", strerror(errno));
        return -1;
    }
    fclose(f);
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        lens_errf(err, path, 0, "cannot read as a PNG image");
        return -1;
    }
    cairo_surface_flush(s);
    int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    int stride = cairo_image_surface_get_stride(s);
    const unsigned char *d = cairo_image_surface_get_data(s);
    uint32_t corner;
    memcpy(&corner, d, 4);
    long n = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint32_t p;
            memcpy(&p, d + (size_t)y * (size_t)stride + 4 * (size_t)x, 4);
            n += (p & 0xffffff) != (corner & 0xffffff);
        }
    cairo_surface_destroy(s);
    *width = w, *height = h, *nonblank = n;
    return 0;
}
