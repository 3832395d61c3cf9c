/* The plain-text scene format of man 5 lens-scene: one statement per line, '#' starts a
 * comment, words separated by blanks. Every error names FILE:LINE. */
#include "sparselens/scene.h"
#include "sparselens/numparse.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "render/render_math.h"
#include "sparselens/data_path.h"
#include "sparselens/input_file.h"

#define MAX_TOKENS 40

void scene_init(scene_t *s)
{
    memset(s, 0, sizeof *s);
    s->sensor_w = s->sensor_h = NAN;
    s->width = 64;
    s->height = 64;
    s->focus = NAN;
    s->fstop = NAN;
    s->mode = SCENE_GREY;
    s->spp = 16;
    s->seed = 1;
    s->transmittance = EFFECT_AUTO;
    s->vignetting = EFFECT_AUTO;
    s->dispersion = EFFECT_AUTO;
}

void scene_free(scene_t *s)
{
    for (size_t i = 0; i < s->nobj; i++) free(s->obj[i].tex.pix);
    free(s->obj);
    s->obj = NULL;
    s->nobj = 0;
}

const char *scene_mode_name(scene_mode m)
{
    return m == SCENE_RGB ? "rgb" : m == SCENE_SPECTRAL ? "spectral" : "grey";
}

/* Parsing state for one line. */
typedef struct {
    const char *path;
    long line;
    char *tok[MAX_TOKENS];
    int n;
    lens_err *err;
} line_ctx;

/* A position or size in mm, within what the renderer can intersect: |v| up to
 * SCENE_MAX_MM and, for a size, at least SCENE_MIN_MM (a texture of 5e-324 mm tiles
 * to infinity; an emitter at 1e160 mm is lost in round-off). */
static int num(line_ctx *c, int i, double *v);
static int length(line_ctx *c, int i, double *v, int is_size, const char *what)
{
    if (num(c, i, v)) return -1;
    if (is_size ? !(*v >= SCENE_MIN_MM && *v <= SCENE_MAX_MM) : !(fabs(*v) <= SCENE_MAX_MM)) {
        if (is_size)
            lens_errf(c->err, c->path, c->line, "%s %s mm is outside %g to %g mm", what,
                      c->tok[i], SCENE_MIN_MM, SCENE_MAX_MM);
        else
            lens_errf(c->err, c->path, c->line, "%s %s mm is outside -%g to %g mm", what,
                      c->tok[i], SCENE_MAX_MM, SCENE_MAX_MM);
        return -1;
    }
    return 0;
}

static int num(line_ctx *c, int i, double *v)
{
    if (i >= c->n) {
        lens_errf(c->err, c->path, c->line, "'%s' needs more numbers", c->tok[0]);
        return -1;
    }
    if (parse_double(c->tok[i], v)) {
        lens_errf(c->err, c->path, c->line, "'%s' is not a finite number", c->tok[i]);
        return -1;
    }
    return 0;
}

static int is_number(const char *t)
{
    double v;
    return parse_double(t, &v) == 0;
}

/* Reads 1 or 3 numbers starting at *i (a grey value is copied to all channels). */
static int read_colour(line_ctx *c, int *i, const char *what, double rgb[3], int allow_neg)
{
    int k = 0;
    double v[3];
    while (*i < c->n && k < 3 && is_number(c->tok[*i])) {
        parse_double(c->tok[*i], &v[k++]);
        (*i)++;
    }
    if (k != 1 && k != 3) {
        /* a token that stopped the numbers and is no keyword: name it, not the count */
        const char *t = *i < c->n ? c->tok[*i] : "";
        if ((k == 0 || k == 2) && (strspn(t, "0123456789+-.") > 0 || !strncasecmp(t, "nan", 3) ||
                                   !strncasecmp(t, "inf", 3)))
            lens_errf(c->err, c->path, c->line, "'%s': '%s' is not a finite number", what, t);
        else
            lens_errf(c->err, c->path, c->line, "'%s' takes one value or three (r g b), got %d",
                      what, k);
        return -1;
    }
    for (int j = 0; j < 3; j++) {
        rgb[j] = v[k == 1 ? 0 : j];
        if (!allow_neg && rgb[j] < 0) {
            lens_errf(c->err, c->path, c->line, "'%s' must not be negative", what);
            return -1;
        }
        /* The image is stored as 32-bit floats: a value near their limit (3.4e38)
         * sums to inf over a pixel's samples. */
        if (fabs(rgb[j]) > SCENE_MAX_VALUE) {
            lens_errf(c->err, c->path, c->line, "'%s' %g is above %g", what, rgb[j],
                      SCENE_MAX_VALUE);
            return -1;
        }
    }
    return 0;
}

/* Binary PPM (P6, 8 bit) or PGM (P5): simple enough to read here without a library. */
static int load_pnm(const char *file, scene_texture *t, line_ctx *c)
{
    lens_err why;
    FILE *f = input_open(file, &why);
    if (!f) {
        lens_errf(c->err, c->path, c->line, "image texture %s", why.msg);
        return -1;
    }
    char magic[3] = {0};
    int w = 0, h = 0, maxv = 0;
    if (fscanf(f, "%2s", magic) != 1 || (strcmp(magic, "P6") && strcmp(magic, "P5"))) {
        fclose(f);
        lens_errf(c->err, c->path, c->line, "%s: image textures are binary PPM (P6) or PGM (P5)",
                  file);
        return -1;
    }
    int got = 0;
    while (got < 3) {
        int ch = fgetc(f);
        if (ch == EOF) break;
        if (ch == '#') {
            while (ch != '\n' && ch != EOF) ch = fgetc(f);
            continue;
        }
        if (isspace(ch)) continue;
        ungetc(ch, f);
        int *dst = got == 0 ? &w : got == 1 ? &h : &maxv;
        if (fscanf(f, "%d", dst) != 1) break;
        got++;
    }
    int comps = magic[1] == '6' ? 3 : 1;
    if (got < 3 || w <= 0 || h <= 0 || w > 16384 || h > 16384 || maxv <= 0 || maxv > 255) {
        fclose(f);
        lens_errf(c->err, c->path, c->line, "%s: bad or unsupported PNM header (8-bit only)", file);
        return -1;
    }
    fgetc(f); /* the single blank after maxval */
    size_t npx = (size_t)w * (size_t)h;
    unsigned char *raw = malloc(npx * (size_t)comps);
    t->pix = malloc(npx * 3 * sizeof *t->pix);
    if (!raw || !t->pix || fread(raw, (size_t)comps, npx, f) != npx) {
        free(raw);
        free(t->pix);
        t->pix = NULL;
        fclose(f);
        lens_errf(c->err, c->path, c->line, "%s: image data truncated", file);
        return -1;
    }
    fclose(f);
    for (size_t i = 0; i < npx; i++)
        for (int k = 0; k < 3; k++) t->pix[3 * i + k] = raw[comps * i + (comps == 3 ? k : 0)] / (float)maxv;
    free(raw);
    t->w = w;
    t->h = h;
    return 0;
}

/* rel against the scene's directory, into out; a path out cannot hold whole (longer
 * than any the system opens) is refused, never cut. */
static int resolve(const line_ctx *c, const char *rel, char *out, size_t outlen)
{
    const char *slash = strrchr(c->path, '/');
    int n = rel[0] == '/' || !slash
                ? snprintf(out, outlen, "%s", rel)
                : snprintf(out, outlen, "%.*s/%s", (int)(slash - c->path), c->path, rel);
    if (n < 0 || (size_t)n >= outlen) {
        lens_errf(c->err, c->path, c->line, "the path '%.40s...' is %d characters long, "
                  "more than the %zu a path may have", rel, n, outlen - 1);
        return -1;
    }
    return 0;
}

/* Modifiers after an object's geometry: albedo, checker, image, emit. */
static int read_modifiers(line_ctx *c, int i, scene_object *o)
{
    o->tex.kind = TEX_CONSTANT;
    o->tex.a[0] = o->tex.a[1] = o->tex.a[2] = 0.5;
    while (i < c->n) {
        const char *m = c->tok[i++];
        if (!strcmp(m, "albedo")) {
            o->tex.kind = TEX_CONSTANT;
            if (read_colour(c, &i, m, o->tex.a, 0)) return -1;
        } else if (!strcmp(m, "checker")) {
            o->tex.kind = TEX_CHECKER;
            double a, b;
            if (num(c, i, &a) || num(c, i + 1, &b) || num(c, i + 2, &o->tex.size)) return -1;
            if (a < 0 || b < 0 || o->tex.size <= 0) {
                lens_errf(c->err, c->path, c->line,
                          "checker needs albedos >= 0 and a square size > 0");
                return -1;
            }
            if (length(c, i + 2, &o->tex.size, 1, "checker square")) return -1;
            i += 3;
            for (int k = 0; k < 3; k++) o->tex.a[k] = a, o->tex.b[k] = b;
        } else if (!strcmp(m, "image")) {
            if (i + 1 >= c->n) {
                lens_errf(c->err, c->path, c->line, "image needs FILE and WIDTH_MM");
                return -1;
            }
            char file[PATH_MAX];
            if (resolve(c, c->tok[i], file, sizeof file)) return -1;
            if (length(c, i + 1, &o->tex.size, 1, "image width")) return -1;
            i += 2;
            o->tex.kind = TEX_IMAGE;
            free(o->tex.pix);
            o->tex.pix = NULL;
            if (load_pnm(file, &o->tex, c)) return -1;
        } else if (!strcmp(m, "emit")) {
            if (read_colour(c, &i, m, o->emit, 0)) return -1;
        } else {
            lens_errf(c->err, c->path, c->line,
                      "unknown modifier '%s' (albedo, checker, image, emit)", m);
            return -1;
        }
    }
    if (o->kind == OBJ_PLANE && scene_is_emitter(o) && o->tex.kind == TEX_IMAGE) {
        lens_errf(c->err, c->path, c->line, "an emitter has no texture");
        return -1;
    }
    return 0;
}

static int unit_normal(line_ctx *c, double n[3])
{
    /* Scaled by the largest component first: the squares of (0, 0, -1e200) overflow,
     * and those of (0, 0, 1e-200) vanish. */
    double m = fmax(fabs(n[0]), fmax(fabs(n[1]), fabs(n[2])));
    if (!(m > 0)) {
        lens_errf(c->err, c->path, c->line, "the normal must not be zero");
        return -1;
    }
    for (int k = 0; k < 3; k++) n[k] /= m;
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) n[k] /= l;
    return 0;
}

static int add_object(scene_t *s, line_ctx *c, object_kind kind)
{
    scene_object o;
    memset(&o, 0, sizeof o);
    o.kind = kind;
    o.line = c->line;
    int i = 1;
    if (s->nobj >= SCENE_MAX_OBJECTS) {
        lens_errf(c->err, c->path, c->line, "more than %d objects (each ray is tested against "
                  "every object: lens-scene(5), LIMITS)", SCENE_MAX_OBJECTS);
        return -1;
    }
    for (int k = 0; k < 3; k++, i++)
        if (length(c, i, &o.p[k], 0, "position")) return -1;
    if (kind == OBJ_PLANE || kind == OBJ_DISK) {
        for (int k = 0; k < 3; k++, i++)
            if (num(c, i, &o.n[k])) return -1;
        if (unit_normal(c, o.n)) return -1;
    }
    if (kind == OBJ_SPHERE || kind == OBJ_DISK) {
        if (num(c, i, &o.radius)) return -1;
        if (!(o.radius > 0)) {
            lens_errf(c->err, c->path, c->line, "radius must be > 0");
            return -1;
        }
        if (length(c, i++, &o.radius, 1, "radius")) return -1;
    }
    if (read_modifiers(c, i, &o)) {
        free(o.tex.pix);
        return -1;
    }
    o.r2 = o.radius * o.radius;
    o.emitter = o.emit[0] > 0 || o.emit[1] > 0 || o.emit[2] > 0;
    o.lum = 0.2126 * o.emit[0] + 0.7152 * o.emit[1] + 0.0722 * o.emit[2];
    if (kind != OBJ_SPHERE) rm_frame(o.n, o.e1, o.e2);
    scene_object *grown = realloc(s->obj, (s->nobj + 1) * sizeof *grown);
    if (!grown) {
        free(o.tex.pix);
        lens_errf(c->err, c->path, c->line, "out of memory");
        return -1;
    }
    s->obj = grown;
    s->obj[s->nobj++] = o;
    return 0;
}

static int effect(line_ctx *c, effect_setting *e)
{
    if (c->n != 2) goto bad;
    if (!strcmp(c->tok[1], "on")) *e = EFFECT_ON;
    else if (!strcmp(c->tok[1], "off")) *e = EFFECT_OFF;
    else if (!strcmp(c->tok[1], "auto")) *e = EFFECT_AUTO;
    else goto bad;
    return 0;
bad:
    lens_errf(c->err, c->path, c->line, "'%s' takes on, off or auto", c->tok[0]);
    return -1;
}

static int positive_pair(line_ctx *c, double *a, double *b)
{
    if (c->n != 3 || num(c, 1, a) || num(c, 2, b)) {
        if (c->n != 3) lens_errf(c->err, c->path, c->line, "'%s' takes two numbers", c->tok[0]);
        return -1;
    }
    if (!(*a > 0 && *b > 0)) {
        lens_errf(c->err, c->path, c->line, "'%s' values must be > 0", c->tok[0]);
        return -1;
    }
    return 0;
}

static int statement(scene_t *s, line_ctx *c, int *have_camera)
{
    const char *k = c->tok[0];
    double a, b;
    if (!strcmp(k, "camera")) {
        if (*have_camera) {
            lens_errf(c->err, c->path, c->line, "a second 'camera' statement (a scene has one)");
            return -1;
        }
        if (c->n != 2) {
            lens_errf(c->err, c->path, c->line, "camera takes one file (a lens or a .poly)");
            return -1;
        }
        if (resolve(c, c->tok[1], s->camera, sizeof s->camera)) return -1;
        /* a bare name with no such file beside the scene is a lens name (lens_load
         * looks in ./, $SPARSELENS_LENS_PATH and the shipped lenses) */
        if (!strchr(c->tok[1], '/') && access(s->camera, R_OK) != 0)
            snprintf(s->camera, sizeof s->camera, "%s", c->tok[1]);
        size_t l = strlen(s->camera);
        s->camera_is_poly = l > 5 && !strcmp(s->camera + l - 5, ".poly");
        *have_camera = 1;
    } else if (!strcmp(k, "sensor")) {
        if (positive_pair(c, &s->sensor_w, &s->sensor_h)) return -1;
    } else if (!strcmp(k, "resolution")) {
        if (positive_pair(c, &a, &b)) return -1;
        if (a != floor(a) || b != floor(b) || a > 16384 || b > 16384) {
            lens_errf(c->err, c->path, c->line, "resolution takes whole numbers up to 16384");
            return -1;
        }
        s->width = (int)a;
        s->height = (int)b;
    } else if (!strcmp(k, "focus")) {
        s->focus_line = c->line;
        if (c->n == 2 && !strcmp(c->tok[1], "inf")) {
            s->focus = INFINITY;
            return 0;
        }
        if (c->n != 2 || num(c, 1, &s->focus) || !(s->focus > 0)) {
            if (c->n != 2 || s->focus <= 0)
                lens_errf(c->err, c->path, c->line, "focus takes a distance > 0 mm, or inf");
            return -1;
        }
    } else if (!strcmp(k, "fstop")) {
        s->fstop_line = c->line;
        if (c->n != 2 || num(c, 1, &s->fstop) || !(s->fstop > 0)) {
            if (c->n != 2 || s->fstop <= 0)
                lens_errf(c->err, c->path, c->line, "fstop takes a number > 0");
            return -1;
        }
    } else if (!strcmp(k, "mode")) {
        if (c->n == 2 && !strcmp(c->tok[1], "grey")) s->mode = SCENE_GREY;
        else if (c->n == 2 && !strcmp(c->tok[1], "rgb")) s->mode = SCENE_RGB;
        else if (c->n == 2 && !strcmp(c->tok[1], "spectral")) s->mode = SCENE_SPECTRAL;
        else {
            lens_errf(c->err, c->path, c->line, "mode takes grey, rgb or spectral");
            return -1;
        }
    } else if (!strcmp(k, "spp") || !strcmp(k, "seed")) {
        long v;
        /* spp: the bound of --spp. */
        if (c->n != 2 || parse_long(c->tok[1], &v) || v < (k[1] == 'p' ? 1 : 0) ||
            (k[1] == 'p' && v > SCENE_MAX_SPP)) {
            lens_errf(c->err, c->path, c->line, "'%s' takes a whole number %s", k,
                      k[1] == 'p' ? ">= 1 (at most 1073741824, as --spp)" : ">= 0");
            return -1;
        }
        if (k[1] == 'p') s->spp = v;
        else s->seed = (unsigned long)v;
    } else if (!strcmp(k, "transmittance")) {
        return effect(c, &s->transmittance);
    } else if (!strcmp(k, "vignetting")) {
        return effect(c, &s->vignetting);
    } else if (!strcmp(k, "dispersion")) {
        return effect(c, &s->dispersion);
    } else if (!strcmp(k, "blades")) {
        double n, rot = 0;
        if (c->n < 2 || c->n > 3 || num(c, 1, &n) || (c->n == 3 && num(c, 2, &rot)) ||
            n != floor(n) || n < 3 || n > 16) {
            lens_errf(c->err, c->path, c->line, "blades takes a count from 3 to 16 and an optional "
                      "rotation in degrees");
            return -1;
        }
        s->blades = (int)n;
        s->blade_rotation = rot;
    } else if (!strcmp(k, "filter")) {
        double r = 1;
        int tent = c->n >= 2 && !strcmp(c->tok[1], "tent");
        if (!((c->n == 2 && (tent || !strcmp(c->tok[1], "box"))) ||
              (c->n == 3 && tent && !num(c, 2, &r) && r >= 0.5 && r <= 4))) {
            lens_errf(c->err, c->path, c->line, "filter takes box, or tent [RADIUS] (pixels, 0.5 to 4)");
            return -1;
        }
        s->filter_tent = tent;
        s->filter_radius = r;
    } else if (!strcmp(k, "plane")) {
        return add_object(s, c, OBJ_PLANE);
    } else if (!strcmp(k, "disk")) {
        return add_object(s, c, OBJ_DISK);
    } else if (!strcmp(k, "sphere")) {
        return add_object(s, c, OBJ_SPHERE);
    } else {
        lens_errf(c->err, c->path, c->line, "unknown statement '%s'", k);
        return -1;
    }
    return 0;
}

int scene_parse(const char *text, const char *path, scene_t *s, lens_err *err)
{
    scene_init(s);
    if (strlen(path) >= sizeof s->path) {
        lens_errf(err, NULL, 0, "a scene path of %zu characters, more than the %zu a path "
                  "may have", strlen(path), sizeof s->path - 1);
        return -1;
    }
    snprintf(s->path, sizeof s->path, "%s", path);
    int have_camera = 0;
    line_ctx c = {.path = path, .line = 0, .err = err};
    const char *p = text;
    char buf[4096];
    while (*p) {
        const char *e = strchr(p, '\n');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        c.line++;
        if (len >= sizeof buf) {
            lens_errf(err, path, c.line, "line longer than %zu bytes", sizeof buf - 1);
            goto fail;
        }
        memcpy(buf, p, len);
        buf[len] = 0;
        p += len + (e ? 1 : 0);
        char *hash = strchr(buf, '#');
        if (hash) *hash = 0;
        c.n = 0;
        for (char *t = strtok(buf, " \t\r"); t; t = strtok(NULL, " \t\r")) {
            if (c.n == MAX_TOKENS) {
                lens_errf(err, path, c.line, "too many words on a line");
                goto fail;
            }
            c.tok[c.n++] = t;
        }
        if (c.n == 0) continue;
        if (statement(s, &c, &have_camera)) goto fail;
    }
    if (!have_camera) {
        lens_errf(err, path, 0, "no 'camera' statement");
        goto fail;
    }
    if (s->nobj == 0) {
        lens_errf(err, path, 0, "the scene has no objects");
        goto fail;
    }
    return 0;
fail:
    scene_free(s);
    return -1;
}

int scene_load(const char *path, scene_t *s, lens_err *err)
{
    /* A bare name that is not a file here is a scene name: ./, $SPARSELENS_SCENE_PATH,
     * then the shipped scenes (data_path.h); the camera is then found beside it. */
    static const char *const exts[] = {".scene", NULL};
    char found[PATH_MAX + 64];
    if (strcmp(path, "-") && data_find("scenes", "SPARSELENS_SCENE_PATH", path, exts, found,
                                       sizeof found) == 0)
        path = found;
    FILE *f = strcmp(path, "-") ? input_open(path, err) : stdin;
    if (!f)
        return -1;
    size_t cap = 4096, len = 0;
    char *text = malloc(cap);
    size_t got;
    while (text && (got = fread(text + len, 1, cap - len - 1, f)) > 0) {
        len += got;
        if (cap - len < 2) {
            char *g = len < (1u << 26) ? realloc(text, cap * 2) : NULL;
            if (!g) {
                free(text);
                text = NULL;
                break;
            }
            text = g;
            cap *= 2;
        }
    }
    int read_error = ferror(f), code = errno;
    if (f != stdin) fclose(f);
    if (!text) {
        lens_errf(err, path, 0, "out of memory or file too large");
        return -1;
    }
    if (read_error) {
        free(text);
        lens_errf(err, path, 0, "read error: %s", strerror(code));
        return -1;
    }
    text[len] = 0;
    const char *nul = memchr(text, 0, len);
    if (nul) {
        long line = 1;
        for (const char *q = text; q < nul; q++)
            line += *q == '\n';
        free(text);
        lens_errf(err, path, line, "NUL byte (not a text file?)");
        return -1;
    }
    /* A UTF-8 byte-order mark (some editors write one) is not part of the text. */
    size_t bom = len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    int rc = scene_parse(text + bom, path, s, err);
    free(text);
    return rc;
}
