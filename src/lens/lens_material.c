/* Material look-up for the prescription readers, and exact number formatting. */
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lens/lens_material.h"

void material_ctx_init(material_ctx *m, const lens_load_options *opt, const char *lens_path)
{
    memset(m, 0, sizeof *m);
    m->opt = opt;
    m->lens_path = lens_path;
}

void material_ctx_free(material_ctx *m)
{
    glass_catalog_free(m->cat);
    glass_catalog_free(m->own);
    m->cat = m->own = NULL;
}

int material_add_own(material_ctx *m, const glass_t *g, lens_err *err)
{
    if (!m->own && !(m->own = glass_catalog_new())) {
        lens_errf(err, m->lens_path, 0, "out of memory");
        return -1;
    }
    return glass_catalog_add(m->own, g, err);
}

/* Adds path unless a file with the same real path was added already (the lens may sit in
 * the directory of the default catalog). */
static int add_catalog(material_ctx *m, const char *path, char seen[][PATH_MAX], int *nseen,
                       lens_err *err)
{
    char real[PATH_MAX];
    if (!realpath(path, real))
        snprintf(real, sizeof real, "%s", path);
    for (int i = 0; i < *nseen; i++)
        if (strcmp(seen[i], real) == 0)
            return 0;
    if (*nseen < 8)
        strcpy(seen[(*nseen)++], real);
    return glass_catalog_load(&m->cat, path, err);
}

static int load_catalogs(material_ctx *m, lens_err *err)
{
    char seen[8][PATH_MAX];
    int nseen = 0;
    m->loaded = 1;
    if (m->opt && m->opt->catalogs)
        for (const char *const *c = m->opt->catalogs; *c; c++)
            if (add_catalog(m, *c, seen, &nseen, err) != 0)
                return -1;
    if (m->lens_path && strcmp(m->lens_path, "-") != 0) {
        char beside[PATH_MAX];
        const char *slash = strrchr(m->lens_path, '/');
        int dirlen = slash ? (int)(slash - m->lens_path) + 1 : 0;
        snprintf(beside, sizeof beside, "%.*sglass.catalog", dirlen, m->lens_path);
        if (access(beside, R_OK) == 0 && add_catalog(m, beside, seen, &nseen, err) != 0)
            return -1;
    }
    m->shipped_from = glass_catalog_size(m->cat);
    const char *def = glass_default_catalog_path();
    if (def && add_catalog(m, def, seen, &nseen, err) != 0)
        return -1;
    return 0;
}

int material_lookup(material_ctx *m, const char *name, const glass_t **g, const char **searched,
                    lens_err *err)
{
    if (m->own && (*g = glass_catalog_find(m->own, name)) != NULL)
        return 0;
    if (!m->loaded && load_catalogs(m, err) != 0)
        return -1;
    *g = glass_catalog_find(m->cat, name);
    if (*g)
        return 0;
    const char *s = glass_catalog_sources(m->cat);
    *searched = *s ? s : "none found";
    return 1;
}

void lens_fmt_double(double v, char buf[32])
{
    if (isinf(v)) {
        strcpy(buf, v > 0 ? "inf" : "-inf");
        return;
    }
    /* At least as many digits as the integer part has, so that 10 prints as "10", not
     * "1e+01" (%g switches to an exponent when it exceeds the precision). */
    int min_prec = 1;
    double a = fabs(v);
    if (a >= 1 && a < 1e15)
        min_prec = (int)floor(log10(a)) + 1;
    for (int prec = min_prec; prec <= 17; prec++) {
        snprintf(buf, 32, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            return;
    }
}

void lens_add_note(lens_t *lens, const char *fmt, ...)
{
    char line[sizeof lens->notes];
    va_list ap;
    va_start(ap, fmt);
    int w = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (w <= 0)
        return; /* an empty note is no note: joined by '\n' it could not be written back
                   (a trailing empty one vanished, so written text was no fixed point) */
    char *notes = lens->notes;
    size_t cap = sizeof lens->notes, n = strlen(notes), sep = n ? 1 : 0;
    size_t len = (size_t)w < sizeof line ? (size_t)w : sizeof line - 1;
    int full = n + sep + len >= cap;
    if (full && n + sep + 3 >= cap) { /* no room for more: mark the end, once */
        if (n >= 3 && strcmp(notes + n - 3, "...") != 0)
            memcpy(notes + n - 3, "...", 4);
        return;
    }
    /* Full: what fits, then "...", so that the cut is seen. */
    if (full)
        len = cap - 1 - n - sep - 3;
    if (sep)
        notes[n++] = '\n';
    memcpy(notes + n, line, len);
    n += len;
    if (full) {
        memcpy(notes + n, "...", 3);
        n += 3;
    }
    notes[n] = '\0';
}
