/* The project's own prescription format (man 5 lens): reader and writer.
 *
 *   # key: value                   header (name, source, focal, fnumber, sensor, note)
 *   radius thickness material semi-diameter [k=.. a4=.. a6=.. a8=.. a10=.. a12=..] [stop]
 *
 * Everything else after '#' is a comment. The writer prints every number in its
 * shortest form that reads back to the same double, so write -> read is exact. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/line_reader.h"
#include "sparselens/lens.h"
#include "lens/lens_material.h"
#include "sparselens/numparse.h"

#define MAX_TOKENS 16

static const char *const asphere_keys[LENS_ASPHERE_TERMS] = {"a4", "a6", "a8", "a10", "a12"};

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1]))
        s[--n] = '\0';
    return s;
}

static int parse_radius(const char *t, double *r)
{
    if (strcasecmp(t, "inf") == 0 || strcasecmp(t, "+inf") == 0 || strcasecmp(t, "-inf") == 0) {
        *r = t[0] == '-' ? -INFINITY : INFINITY;
        return 0;
    }
    return parse_double(t, r);
}

/* "# key: value" with key a single word; 1 if the line is one, 0 if a plain comment. */
static int header_key(char *body, char **key, char **value)
{
    char *p = body;
    while (isalpha((unsigned char)*p) || *p == '_')
        p++;
    char *end = p;
    while (*p == ' ' || *p == '\t')
        p++;
    if (end == body || *p != ':')
        return 0;
    *end = '\0';
    *key = body;
    *value = trim(p + 1);
    return 1;
}

static int set_string(char *dst, size_t size, const char *v, const char *path, long line,
                      const char *key, lens_err *err)
{
    if (strlen(v) >= size) {
        lens_errf(err, path, line, "header %s: value longer than %zu characters", key, size - 1);
        return -1;
    }
    strcpy(dst, v);
    return 0;
}

static int positive(const char *t, double *v)
{
    return parse_double(t, v) == 0 && *v > 0 ? 0 : -1;
}

static int parse_header(lens_t *lens, char *key, char *value, unsigned *seen, const char *path,
                        long line, material_ctx *mat, lens_err *err)
{
    static const char *const keys[] = {"name", "source", "focal", "fnumber", "sensor", "note"};
    int k = -1;
    for (int i = 0; i < 6; i++)
        if (strcmp(key, keys[i]) == 0)
            k = i;
    if (strcmp(key, "glass") == 0) { /* a glass of the file's own, catalog-line form */
        glass_t g;
        if (glass_parse_catalog_line(value, path, line, &g, err) != 0)
            return -1;
        g.embedded = 1;
        return material_add_own(mat, &g, err);
    }
    if (k < 0) {
        lens_errf(err, path, line,
                  "unknown header key '%s' (known: name, source, focal, fnumber, sensor, note, "
                  "glass; write other comments without 'word:' right after '#')",
                  key);
        return -1;
    }
    if (k != 5 && (*seen & (1u << k))) {
        lens_errf(err, path, line, "header %s given twice", key);
        return -1;
    }
    *seen |= 1u << k;
    switch (k) {
    case 0:
        return set_string(lens->name, sizeof lens->name, value, path, line, key, err);
    case 1:
        return set_string(lens->source, sizeof lens->source, value, path, line, key, err);
    case 2:
    case 3:
        if (positive(value, k == 2 ? &lens->focal : &lens->fnumber) != 0) {
            lens_errf(err, path, line, "header %s: '%s' is not a positive number", key, value);
            return -1;
        }
        return 0;
    case 4: {
        char buf[128];
        size_t n = 0;
        for (const char *p = value; *p && n + 1 < sizeof buf; p++)
            if (!isspace((unsigned char)*p))
                buf[n++] = *p;
        buf[n] = '\0';
        char *x = strpbrk(buf, "xX");
        if (x)
            *x = '\0';
        if (!x || positive(buf, &lens->sensor_w) != 0 || positive(x + 1, &lens->sensor_h) != 0) {
            lens_errf(err, path, line, "header sensor: '%s' is not WIDTHxHEIGHT in mm (e.g. 36x24)",
                      value);
            return -1;
        }
        return 0;
    }
    default:
        if (strlen(lens->notes) + strlen(value) + 2 > sizeof lens->notes) {
            lens_errf(err, path, line, "notes longer than %zu characters", sizeof lens->notes - 1);
            return -1;
        }
        lens_add_note(lens, "%s", value);
        return 0;
    }
}

/* Material token -> medium. Returns 0, or -1 with err set. */
static int parse_material(const char *t, lens_surface *s, material_ctx *mat, const char *path,
                          long line, lens_err *err)
{
    if (strlen(t) >= sizeof s->material) {
        lens_errf(err, path, line, "material '%.40s...' is too long", t);
        return -1;
    }
    strcpy(s->material, t);
    if (strcasecmp(t, "air") == 0) {
        s->medium = glass_air();
        return 0;
    }
    if (strcasecmp(t, "stop") == 0) {
        s->medium = glass_air();
        s->is_stop = 1;
        return 0;
    }
    const char *slash = strchr(t, '/');
    if (slash || isdigit((unsigned char)t[0]) || t[0] == '.' || t[0] == '-' || t[0] == '+') {
        char nd_s[48];
        snprintf(nd_s, sizeof nd_s, "%.*s", slash ? (int)(slash - t) : (int)strlen(t), t);
        double nd, vd = 0;
        if (parse_double(nd_s, &nd) != 0 || (slash && parse_double(slash + 1, &vd) != 0)) {
            lens_errf(err, path, line, "material '%s': expected nd/Vd or nd as finite numbers", t);
            return -1;
        }
        char what[64];
        snprintf(what, sizeof what, "material '%s'", t);
        if (glass_check_ndvd(nd, slash ? vd : NAN, what, path, line, err) != 0)
            return -1;
        s->medium = slash ? glass_from_ndvd(nd, vd) : glass_constant(nd);
        return 0;
    }
    const glass_t *g;
    const char *searched;
    int rc = material_lookup(mat, t, &g, &searched, err);
    if (rc < 0)
        return -1;
    if (rc > 0) {
        lens_errf(err, path, line,
                  "unknown material '%s': not air, stop, nd/Vd or nd, and not a glass in the "
                  "catalogs searched (%s)", t,
                  searched);
        return -1;
    }
    s->medium = *g;
    return 0;
}

static int parse_surface(char **tok, int nt, lens_t *lens, material_ctx *mat, const char *path,
                         long line, lens_err *err)
{
    if (nt < 4) {
        lens_errf(err, path, line,
                  "expected: radius thickness material semi-diameter [k=.. a4=.. ... a12=..] "
                  "[stop] (%d field%s found)",
                  nt, nt == 1 ? "" : "s");
        return -1;
    }
    lens_surface *s = lens_add_surface_at(lens, path, line, err);
    if (!s)
        return -1;
    if (parse_radius(tok[0], &s->radius) != 0) {
        lens_errf(err, path, line, "radius '%s' is not a number (inf for a flat surface)", tok[0]);
        return -1;
    }
    if (s->radius == 0) {
        lens_errf(err, path, line, "radius 0: write inf for a flat surface");
        return -1;
    }
    if (parse_double(tok[1], &s->thickness) != 0) {
        lens_errf(err, path, line, "thickness '%s' is not a finite number", tok[1]);
        return -1;
    }
    if (parse_double(tok[3], &s->semi_diameter) != 0 || !(s->semi_diameter > 0)) {
        lens_errf(err, path, line, "semi-diameter '%s' is not a positive finite number", tok[3]);
        return -1;
    }
    if (parse_material(tok[2], s, mat, path, line, err) != 0)
        return -1;
    unsigned seen = 0;
    for (int i = 4; i < nt; i++) {
        if (strcasecmp(tok[i], "stop") == 0) {
            if (s->is_stop) {
                lens_errf(err, path, line, "'stop' given twice on one surface");
                return -1;
            }
            s->is_stop = 1;
            continue;
        }
        char *eq = strchr(tok[i], '=');
        if (!eq) {
            lens_errf(err, path, line, "unexpected field '%s' (k=.., a4=.. ... a12=.., or stop)",
                      tok[i]);
            return -1;
        }
        *eq = '\0';
        int k = -2;
        if (strcasecmp(tok[i], "k") == 0)
            k = -1;
        for (int j = 0; j < LENS_ASPHERE_TERMS; j++)
            if (strcasecmp(tok[i], asphere_keys[j]) == 0)
                k = j;
        if (k == -2) {
            lens_errf(err, path, line, "unknown surface coefficient '%s' (k, a4, a6, a8, a10, a12)",
                      tok[i]);
            return -1;
        }
        if (seen & (1u << (k + 1))) {
            lens_errf(err, path, line, "coefficient %s given twice", tok[i]);
            return -1;
        }
        seen |= 1u << (k + 1);
        double v;
        if (parse_double(eq + 1, &v) != 0) {
            lens_errf(err, path, line, "%s='%s' is not a finite number", tok[i], eq + 1);
            return -1;
        }
        if (k < 0)
            s->conic = v;
        else
            s->asphere[k] = v;
    }
    return 0;
}

int lens_read_native(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                     lens_err *err)
{
    lens_init(lens);
    snprintf(lens->path, sizeof lens->path, "%s", path);
    material_ctx mat;
    material_ctx_init(&mat, opt, path);
    line_reader lr;
    line_reader_init(&lr, f, path, LINE_MAX_BYTES);
    long line = 0;
    unsigned seen = 0;
    int rc = -1, st;
    while ((st = line_next(&lr, err)) == LINE_OK) {
        line = lr.line;
        char *p = trim(lr.buf);
        if (!*p)
            continue;
        if (*p == '#') {
            char *key, *value;
            if (header_key(trim(p + 1), &key, &value) &&
                parse_header(lens, key, value, &seen, path, line, &mat, err) != 0)
                goto out;
            continue;
        }
        char *hash = strchr(p, '#');
        if (hash)
            *hash = '\0';
        char *tok[MAX_TOKENS];
        int nt = 0;
        char *save = NULL;
        for (char *t = strtok_r(p, " \t", &save); t; t = strtok_r(NULL, " \t", &save)) {
            if (nt == MAX_TOKENS) {
                lens_errf(err, path, line, "too many fields");
                goto out;
            }
            tok[nt++] = t;
        }
        if (parse_surface(tok, nt, lens, &mat, path, line, err) != 0)
            goto out;
    }
    if (st != LINE_END)
        goto out;
    if (lens->nsurf == 0) {
        lens_errf(err, path, line > 0 ? line : 1, "no surfaces (%s)",
                  line ? "only comments and blank lines" : "empty file");
        goto out;
    }
    int nstop = 0;
    for (size_t i = 0; i < lens->nsurf; i++)
        nstop += lens->surf[i].is_stop;
    if (nstop == 0) {
        lens_errf(err, path, line,
                  "no aperture stop (give one surface the material 'stop', or a trailing 'stop')");
        goto out;
    }
    rc = lens_finish(lens, err);
out:
    line_reader_free(&lr);
    material_ctx_free(&mat);
    if (rc != 0)
        lens_free(lens);
    return rc;
}

static void material_text(const lens_surface *s, char *out, size_t size)
{
    char a[32], b[32];
    switch (s->medium.kind) {
    case GLASS_AIR:
        snprintf(out, size, "%s", s->is_stop ? "stop" : "air");
        return;
    case GLASS_CONSTANT:
        lens_fmt_double(s->medium.nd, a);
        snprintf(out, size, "%s", a);
        return;
    case GLASS_NDVD:
        lens_fmt_double(s->medium.nd, a);
        lens_fmt_double(s->medium.vd, b);
        snprintf(out, size, "%s/%s", a, b);
        return;
    case GLASS_FORMULA:
        snprintf(out, size, "%s", s->medium.name[0] ? s->medium.name : s->material);
        return;
    }
}

int lens_write(FILE *f, const lens_t *lens)
{
    char a[32], b[32];
    if (lens->name[0])
        fprintf(f, "# name: %s\n", lens->name);
    if (lens->source[0])
        fprintf(f, "# source: %s\n", lens->source);
    if (isfinite(lens->focal)) {
        lens_fmt_double(lens->focal, a);
        fprintf(f, "# focal: %s\n", a);
    }
    if (isfinite(lens->fnumber)) {
        lens_fmt_double(lens->fnumber, a);
        fprintf(f, "# fnumber: %s\n", a);
    }
    if (isfinite(lens->sensor_w) && isfinite(lens->sensor_h)) {
        lens_fmt_double(lens->sensor_w, a);
        lens_fmt_double(lens->sensor_h, b);
        fprintf(f, "# sensor: %sx%s\n", a, b);
    }
    for (const char *p = lens->notes; *p;) {
        const char *nl = strchr(p, '\n');
        int n = nl ? (int)(nl - p) : (int)strlen(p);
        fprintf(f, "# note: %.*s\n", n, p);
        p += n + (nl ? 1 : 0);
    }
    /* glasses of no catalog travel with the lens, each once */
    for (size_t i = 0; i < lens->nsurf; i++) {
        const glass_t *g = &lens->surf[i].medium;
        int first = g->kind == GLASS_FORMULA && g->embedded && g->name[0];
        for (size_t j = 0; first && j < i; j++)
            first = !(lens->surf[j].medium.embedded && !strcmp(lens->surf[j].medium.name, g->name));
        if (first) {
            char line[GLASS_MAX_COEF * 26 + 128];
            glass_format_catalog_line(g, line, sizeof line);
            fprintf(f, "# glass: %s\n", line);
        }
    }
    fprintf(f, "# radius      thickness     material      semi-diameter\n");
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *s = &lens->surf[i];
        char r[32], t[32], sd[32], m[64];
        lens_fmt_double(s->radius, r);
        lens_fmt_double(s->thickness, t);
        lens_fmt_double(s->semi_diameter, sd);
        material_text(s, m, sizeof m);
        fprintf(f, "%-13s %-13s %-13s %s", r, t, m, sd);
        if (s->conic != 0) {
            lens_fmt_double(s->conic, a);
            fprintf(f, " k=%s", a);
        }
        for (int k = 0; k < LENS_ASPHERE_TERMS; k++)
            if (s->asphere[k] != 0) {
                lens_fmt_double(s->asphere[k], a);
                fprintf(f, " %s=%s", asphere_keys[k], a);
            }
        if (s->is_stop && s->medium.kind != GLASS_AIR)
            fprintf(f, " stop");
        fputc('\n', f);
    }
    return ferror(f) ? -1 : 0;
}
