/* Shared machinery of the prescription and catalog importers (see import_common.h). */
#include "base/line_reader.h"
#include "lens/import_common.h"

#include "sparselens/paraxial.h"
#include "sparselens/numparse.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define IMPORT_MAX_FILE (64L << 20)

/* One code point as UTF-8; unpaired surrogates become '?', so a damaged file stays text. */
static size_t put_utf8(unsigned long c, char *o)
{
    if (c < 0x80) {
        o[0] = (char)c;
        return 1;
    }
    if (c < 0x800) {
        o[0] = (char)(0xC0 | (c >> 6));
        o[1] = (char)(0x80 | (c & 0x3F));
        return 2;
    }
    if (c >= 0xD800 && c < 0xE000) {
        o[0] = '?';
        return 1;
    }
    if (c < 0x10000) {
        o[0] = (char)(0xE0 | (c >> 12));
        o[1] = (char)(0x80 | ((c >> 6) & 0x3F));
        o[2] = (char)(0x80 | (c & 0x3F));
        return 3;
    }
    o[0] = (char)(0xF0 | (c >> 18));
    o[1] = (char)(0x80 | ((c >> 12) & 0x3F));
    o[2] = (char)(0x80 | ((c >> 6) & 0x3F));
    o[3] = (char)(0x80 | (c & 0x3F));
    return 4;
}

static char *decode_utf16(const unsigned char *d, size_t len, int big_endian)
{
    size_t nunits = len / 2;
    /* Each code unit becomes at most 3 bytes (a surrogate pair, 2 units, 4 bytes). */
    char *out = malloc(nunits * 3 + 1);
    if (!out)
        return NULL;
    size_t o = 0;
    for (size_t i = 0; i < nunits; i++) {
        unsigned long u = big_endian ? (unsigned long)d[2 * i] << 8 | d[2 * i + 1]
                                     : (unsigned long)d[2 * i + 1] << 8 | d[2 * i];
        if (u >= 0xD800 && u < 0xDC00 && i + 1 < nunits) {
            unsigned long v = big_endian ? (unsigned long)d[2 * i + 2] << 8 | d[2 * i + 3]
                                         : (unsigned long)d[2 * i + 3] << 8 | d[2 * i + 2];
            if (v >= 0xDC00 && v < 0xE000) {
                u = 0x10000 + ((u - 0xD800) << 10) + (v - 0xDC00);
                i++;
            }
        }
        if (u == 0)
            u = ' '; /* a NUL inside a text file would end it early */
        o += put_utf8(u, out + o);
    }
    out[o] = '\0';
    return out;
}

char *import_decode(const char *data, size_t len)
{
    const unsigned char *d = (const unsigned char *)data;
    if (len >= 2 && d[0] == 0xFF && d[1] == 0xFE)
        return decode_utf16(d + 2, len - 2, 0);
    if (len >= 2 && d[0] == 0xFE && d[1] == 0xFF)
        return decode_utf16(d + 2, len - 2, 1);
    /* UTF-16 LE without a BOM: ASCII text with every second byte zero. */
    if (len >= 4 && d[0] != 0 && d[1] == 0 && d[2] != 0 && d[3] == 0)
        return decode_utf16(d, len, 0);
    size_t skip = (len >= 3 && d[0] == 0xEF && d[1] == 0xBB && d[2] == 0xBF) ? 3 : 0;
    char *out = malloc(len - skip + 1);
    if (!out)
        return NULL;
    for (size_t i = skip; i < len; i++)
        out[i - skip] = d[i] ? (char)d[i] : ' ';
    out[len - skip] = '\0';
    return out;
}

int import_read_stream(FILE *f, const char *path, char **data, size_t *len, lens_err *err)
{
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        if (n == cap) {
            if ((long)cap >= IMPORT_MAX_FILE) {
                free(buf);
                lens_errf(err, path, 0, "larger than %ld MB: not a prescription or catalog",
                          IMPORT_MAX_FILE >> 20);
                return -1;
            }
            char *nb = realloc(buf, cap * 2);
            if (!nb) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0)
            break;
    }
    if (!buf) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    if (ferror(f)) {
        free(buf);
        lens_errf(err, path, 0, "read error");
        return -1;
    }
    *data = buf;
    *len = n;
    return 0;
}

int import_read_file(const char *path, char **data, size_t *len, lens_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        lens_errf(err, path, 0, "cannot open: %s", strerror(errno));
        return -1;
    }
    int rc = import_read_stream(f, path, data, len, err);
    fclose(f);
    return rc;
}

char *import_begin(const char *data, size_t len, const char *path, const char *program,
                   lens_t *lens, import_system *sys, lens_err *err)
{
    lens_init(lens);
    memset(sys, 0, sizeof *sys);
    sys->path = path;
    sys->lens = lens;
    sys->unit = 1;
    sys->epd = sys->fno = NAN;
    snprintf(lens->path, sizeof lens->path, "%s", path);
    const char *base = strrchr(path, '/');
    snprintf(lens->source, sizeof lens->source, "%s file %s", program, base ? base + 1 : path);
    char *text = import_decode(data, len);
    if (!text)
        lens_errf(err, path, 0, "out of memory");
    else if (import_check_lines(text, path, err) != 0) {
        free(text);
        text = NULL;
    }
    return text;
}

int import_check_lines(const char *text, const char *path, lens_err *err)
{
    long line = 1;
    for (const char *p = text;; line++) {
        size_t n = strcspn(p, "\r\n");
        if (n > LINE_MAX_BYTES) {
            lens_errf(err, path, line, "line longer than %d bytes", LINE_MAX_BYTES);
            return -1;
        }
        p += n;
        if (!*p)
            return 0;
        p += (p[0] == '\r' && p[1] == '\n') ? 2 : 1;
    }
}

int import_read_parse(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                      lens_err *err, import_parser parse)
{
    char *data;
    size_t len;
    lens_init(lens);
    if (import_read_stream(f, path, &data, &len, err) != 0)
        return -1;
    int rc = parse(data, len, path, opt, lens, err);
    free(data);
    return rc;
}

int import_grow(void **array, size_t *cap, size_t n, size_t size)
{
    if (n < *cap)
        return 0;
    size_t nc = *cap ? 2 * *cap : 16;
    void *a = realloc(*array, nc * size);
    if (!a)
        return -1;
    *array = a;
    *cap = nc;
    return 0;
}

int import_any_nonzero(char **tok, int n, int from)
{
    for (int i = from; i < n; i++) {
        double v;
        if (parse_double(tok[i], &v) == 0 && v != 0)
            return 1;
    }
    return 0;
}

char *import_next_line(import_lines *it)
{
    if (!it->p || !*it->p)
        return NULL;
    char *start = it->p, *e = start;
    while (*e && *e != '\n' && *e != '\r')
        e++;
    if (*e == '\r' && e[1] == '\n')
        *e++ = '\0';
    if (*e) {
        *e = '\0';
        it->p = e + 1;
    } else {
        it->p = e;
    }
    it->line++;
    return start;
}

int import_tokens(char *line, char **tok, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        while (*p && isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        char *start;
        if (*p == '"' || *p == '\'') {
            char q = *p++;
            start = p;
            while (*p && *p != q)
                p++;
        } else {
            start = p;
            while (*p && !isspace((unsigned char)*p))
                p++;
        }
        if (*p)
            *p++ = '\0';
        if (n < max)
            tok[n++] = start;
    }
    return n;
}

int import_eq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (toupper((unsigned char)*a) != toupper((unsigned char)*b))
            return 0;
    return *a == *b;
}

const char *import_rest_after(const char *line, const char *keyword)
{
    const char *p = line + strspn(line, " \t");
    size_t k = strlen(keyword);
    if (strncasecmp(p, keyword, k) != 0 || (p[k] && p[k] != ' ' && p[k] != '\t'))
        return NULL;
    p += k;
    return p + strspn(p, " \t");
}

void import_set_name(lens_t *lens, const char *name)
{
    size_t n = strlen(name), room = sizeof lens->name - 1;
    if (n <= room) {
        memcpy(lens->name, name, n + 1);
        return;
    }
    snprintf(lens->name, sizeof lens->name, "%.*s...", (int)(room - 3), name);
    lens_add_note(lens, "name shortened from %zu characters", n);
}

void import_skip_word(import_skips *sk, const char *what, const char *word)
{
    char label[IMPORT_SKIP_LABEL];
    snprintf(label, sizeof label, "%s %.40s%s", what, word, strlen(word) > 40 ? "..." : "");
    import_skip(sk, label);
}

void import_skip(import_skips *sk, const char *label)
{
    for (int i = 0; i < sk->n; i++)
        if (strcmp(sk->label[i], label) == 0) {
            sk->count[i]++;
            return;
        }
    if (sk->n < IMPORT_MAX_SKIPS - 1) {
        snprintf(sk->label[sk->n], sizeof sk->label[0], "%s", label);
        sk->count[sk->n++] = 1;
        return;
    }
    /* Out of slots: the last one gathers the rest, so nothing goes unmentioned. */
    if (sk->n == IMPORT_MAX_SKIPS - 1) {
        snprintf(sk->label[sk->n], sizeof sk->label[0], "other features");
        sk->count[sk->n++] = 0;
    }
    sk->count[IMPORT_MAX_SKIPS - 1]++;
}

void import_skips_note(const import_skips *sk, lens_t *lens)
{
    if (sk->n == 0)
        return;
    char buf[sizeof lens->notes];
    size_t o = (size_t)snprintf(buf, sizeof buf, "skipped:");
    for (int i = 0; i < sk->n && o < sizeof buf; i++) {
        int w = sk->count[i] > 1
                    ? snprintf(buf + o, sizeof buf - o, "%s %s (%d)", i ? "," : "", sk->label[i],
                               sk->count[i])
                    : snprintf(buf + o, sizeof buf - o, "%s %s", i ? "," : "", sk->label[i]);
        if (w < 0)
            break;
        o += (size_t)w;
    }
    lens_add_note(lens, "%s", buf);
}

void import_glass_init(import_glass_ctx *g, const lens_load_options *opt, const char *lens_path)
{
    memset(g, 0, sizeof *g);
    g->opt = opt;
    material_ctx_init(&g->m, opt, lens_path);
}

void import_glass_free(import_glass_ctx *g)
{
    material_ctx_free(&g->m);
}

static void append(char *dst, size_t cap, const char *s)
{
    size_t o = strlen(dst);
    if (o + 1 < cap)
        snprintf(dst + o, cap - o, "%s%s", o ? ", " : "", s);
}

/* Upper case, hyphens and blanks removed: N-BK7, n-bk7 and NBK7 are one glass. */
static void normalise(const char *in, char *out, size_t cap)
{
    size_t o = 0;
    for (; *in && o + 1 < cap; in++)
        if (*in != '-' && *in != ' ')
            out[o++] = (char)toupper((unsigned char)*in);
    out[o] = '\0';
}

static const glass_t *find_loose(const glass_catalog *cat, const char *name)
{
    const glass_t *g = glass_catalog_find(cat, name);
    if (g)
        return g;
    char want[64], have[64];
    normalise(name, want, sizeof want);
    const glass_t *hit = NULL;
    size_t n = glass_catalog_size(cat);
    for (size_t i = 0; i < n; i++) {
        const glass_t *c = glass_catalog_at(cat, i);
        normalise(c->name, have, sizeof have);
        if (strcmp(want, have) == 0) {
            /* The same name again (a later catalog) loses to the first; two different
             * names that match loosely are ambiguous: better an error than a wrong glass. */
            if (hit && !import_eq(hit->name, c->name))
                return NULL;
            if (!hit)
                hit = c;
        }
    }
    return hit;
}

int import_glass_model(lens_surface *s, double nd, double vd, const char *file, long line,
                       lens_err *err)
{
    if (!isfinite(vd) || vd == 0)
        vd = NAN; /* not given, or 0: a bare index */
    char what[64];
    snprintf(what, sizeof what, "model glass %g/%g", nd, isnan(vd) ? 0 : vd);
    if (glass_check_ndvd(nd, vd, what, file, line, err) != 0)
        return -1;
    if (!isnan(vd)) {
        s->medium = glass_from_ndvd(nd, vd);
        snprintf(s->material, sizeof s->material, "%.10g/%.10g", nd, vd);
    } else {
        s->medium = glass_constant(nd);
        snprintf(s->material, sizeof s->material, "%.10g", nd);
    }
    return 0;
}

int import_glass_lookup(import_glass_ctx *g, const char *name, double nd, double vd,
                        const char *file, long line, lens_surface *s, lens_err *err)
{
    const glass_t *hit = NULL;
    const char *searched = "none found";
    int rc = material_lookup(&g->m, name, &hit, &searched, err);
    if (rc < 0)
        return -1;
    if (!hit && g->m.cat)
        hit = find_loose(g->m.cat, name);
    if (!hit && g->m.cat) {
        /* CODE V and some Zemax files qualify the name with its maker: SK16_SCHOTT. */
        char base[64];
        snprintf(base, sizeof base, "%s", name);
        char *cut = strrchr(base, '_');
        if (!cut)
            cut = strrchr(base, '.');
        if (cut && cut != base) {
            *cut = '\0';
            hit = find_loose(g->m.cat, base);
        }
    }
    if (hit) {
        s->medium = *hit;
        snprintf(s->material, sizeof s->material, "%s", hit->name);
        return 0;
    }
    int have_ndvd = isfinite(nd) && nd > 1.0 && isfinite(vd) && vd > 0;
    if (have_ndvd && g->opt && g->opt->ndvd_fallback) {
        if (import_glass_model(s, nd, vd, file, line, err) != 0)
            return -1;
        char what[96];
        snprintf(what, sizeof what, "%s as %s", name, s->material);
        append(g->fallbacks, sizeof g->fallbacks, what);
        return 0;
    }
    char hint[200] = "";
    if (g->maker_catalogs[0])
        snprintf(hint, sizeof hint, "; the file names the catalogs %s: add their AGF files "
                                    "with --glass-catalog",
                 g->maker_catalogs);
    if (have_ndvd)
        lens_errf(err, file, line,
                  "glass %s not found in %s (the file gives n_d %g, V_d %g: "
                  "--glass-fallback ndvd would use them)%s",
                  name, searched, nd, vd, hint);
    else
        lens_errf(err, file, line, "glass %s not found in %s%s", name, searched, hint);
    return -1;
}

void import_glass_note(const import_glass_ctx *g, lens_t *lens)
{
    if (g->fallbacks[0])
        lens_add_note(lens, "glass not in catalogs, n_d/V_d model used: %s", g->fallbacks);
}

int import_set_aperture(lens_t *lens, double fnumber, double epd_mm, const char *what,
                        int hard, lens_err *err)
{
    paraxial_data p;
    lens_err e;
    e.msg[0] = '\0';
    if (paraxial_compute(lens, GLASS_D_LINE, &p, &e) != 0 || !(p.fnumber > 0) ||
        !isfinite(p.fnumber) || !isfinite(p.efl)) {
        lens_add_note(lens, "aperture %s not applied: %s", what,
                      e.msg[0] ? e.msg : "the lens has no finite paraxial f-number");
        return 0;
    }
    double target = fnumber > 0 ? fnumber : fabs(p.efl) / epd_mm;
    lens_surface *s = &lens->surf[lens->stop];
    double old = s->semi_diameter, sd = old * p.fnumber / target;
    if (!isfinite(sd) || isnan(lens_sag(s, sd * sd))) {
        lens_errf(err, lens->path, s->line,
                  "%s needs a stop semi-diameter of %g mm, more than surface %d can have", what,
                  sd, lens->stop + 1);
        return -1;
    }
    lens->fnumber = target;
    if (hard && sd > old * (1 + 1e-6)) {
        /* A hard aperture on the stop clips the beam the system aperture asks for. */
        lens_add_note(lens, "%s asks for a stop semi-diameter of %.6g mm; the stop's clear "
                            "aperture %g mm is kept (f/%.4g, not f/%.4g)",
                      what, sd, old, p.fnumber, target);
        return 0;
    }
    s->semi_diameter = sd;
    if (fabs(sd - old) > 1e-6 * old)
        lens_add_note(lens, "stop semi-diameter %.6g mm from %s (the file's is %g)", sd, what,
                      old);
    return 0;
}

double import_radius(double c, double unit)
{
    if (c == 0 || !isfinite(c))
        return INFINITY;
    double r = 1.0 / c;
    char buf[40];
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, r);
        double v = strtod(buf, NULL);
        if (1.0 / v == c) {
            r = v;
            break;
        }
    }
    return r * unit;
}

/* Control characters become '?', and blanks at both ends go: what the native format's
 * header lines can carry and read back unchanged. */
static void clean_line(char *s, size_t cap)
{
    for (char *p = s; *p; p++)
        if ((unsigned char)*p < 0x20 || (unsigned char)*p == 0x7F)
            *p = '?';
    char *b = s;
    while (*b == ' ')
        b++;
    size_t n = strlen(b);
    while (n && b[n - 1] == ' ')
        n--;
    memmove(s, b, n);
    s[n] = '\0';
    if (!n && cap > 1) {
        s[0] = '?';
        s[1] = '\0';
    }
}

void import_clean_text(lens_t *lens)
{
    if (lens->name[0])
        clean_line(lens->name, sizeof lens->name);
    clean_line(lens->source, sizeof lens->source);
    char out[sizeof lens->notes], line[sizeof lens->notes];
    size_t o = 0;
    for (const char *p = lens->notes; *p;) {
        size_t n = strcspn(p, "\n");
        memcpy(line, p, n);
        line[n] = '\0';
        clean_line(line, sizeof line);
        int w = snprintf(out + o, sizeof out - o, "%s%s", o ? "\n" : "", line);
        if (w < 0 || (size_t)w >= sizeof out - o)
            break;
        o += (size_t)w;
        p += n;
        if (*p == '\n')
            p++;
    }
    out[o] = '\0';
    memcpy(lens->notes, out, o + 1);
}

int import_finish(lens_t *lens, const import_skips *skips, double fnumber, const char *fno_name,
                  double epd_mm, const char *epd_name, int hard, lens_err *err)
{
    import_skips_note(skips, lens);
    import_clean_text(lens);
    if (lens_finish(lens, err) != 0)
        return -1;
    if (isfinite(fnumber) && fnumber > 0)
        return import_set_aperture(lens, fnumber, 0, fno_name, hard, err);
    if (isfinite(epd_mm) && epd_mm > 0)
        return import_set_aperture(lens, 0, epd_mm, epd_name, hard, err);
    return 0;
}
