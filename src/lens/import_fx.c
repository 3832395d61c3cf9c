/* Reader of the .fx prescriptions of the EGSR 2016 lens set (lenses/reference/fx):
 *
 *   radius thickness material [n_d V_d] housing-radius [more columns]   [// or # comment]
 *
 * Traps this reader handles, each seen in the shipped files:
 *  - material: air, iris/IRIS (the stop), or a glass name (often "abbe") followed by n_d
 *    and V_d. A name found in the glass catalogs is taken from there (lensbaby.fx writes
 *    N-SSK8 with the placeholder 1.5 50); otherwise the (n_d, V_d) model is used.
 *  - a cx_ prefix marks a cylindrical surface: refused, the lens is not rotationally
 *    symmetric;
 *  - |radius| >= FX_FLAT_RADIUS (10000, 100000, 1e6, 1e7 in the files) means flat;
 *  - a thickness a/b/c lists zoom positions: the first is taken, and a note says so;
 *  - "#!scale s" scales every length (radii, thicknesses, housings, EFL, asphere terms);
 *  - "#!aspheric=k,A4,A6,A8,A10" after a surface makes it an even asphere;
 *  - "#EFL f ..." gives the nominal focal length (the first value for zooms);
 *  - whole-line '#' comments (some files keep other prescriptions commented out),
 *    trailing "// ..." and "# ..." comments, CRLF line ends, and extra columns after
 *    the housing radius (wideangle*.fx keep paraxial ray heights there): ignored. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/line_reader.h"
#include "sparselens/import_table.h"
#include "lens/lens_material.h"
#include "sparselens/numparse.h"

#define FX_FLAT_RADIUS 10000.0
#define FX_MAX_TOKENS 32
/* A catalog glass whose n_d differs more than this from the file's is worth a note. */
#define FX_ND_NOTE 5e-4

/* "#!aspheric=k,A4,A6,A8,A10" -> conic and a4..a10 */
static int parse_aspheric(const char *spec, lens_surface *s, const char *path, long line,
                          lens_err *err)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", spec);
    char *save = NULL;
    int n = 0;
    for (char *t = strtok_r(buf, ", \t\r\n", &save); t; t = strtok_r(NULL, ", \t\r\n", &save)) {
        double v;
        if (n >= 5 || parse_double(t, &v) != 0) {
            lens_errf(err, path, line, "#!aspheric= expects k,A4,A6,A8,A10 as numbers, not '%.*s'",
                      (int)strcspn(spec, "\r\n"), spec);
            return -1;
        }
        if (n == 0)
            s->conic = v;
        else
            s->asphere[n - 1] = v;
        n++;
    }
    if (n == 0) {
        lens_errf(err, path, line, "#!aspheric= without coefficients");
        return -1;
    }
    return 0;
}

typedef struct {
    material_ctx mat;
    int zoom_noted, extra_noted;
    char missing[256]; /* glass names not in any catalog, for one note */
} fx_state;

static int fx_surface(char *text, lens_t *lens, fx_state *st, const char *path, long line,
                      lens_err *err)
{
    /* Comments: "//" first, then '#', keeping a "#!aspheric=" spec. */
    char *c = strstr(text, "//");
    if (c)
        *c = '\0';
    char *asph = strstr(text, "#!aspheric=");
    char asph_spec[256] = "";
    if (asph) {
        snprintf(asph_spec, sizeof asph_spec, "%s", asph + strlen("#!aspheric="));
        *asph = '\0';
    }
    char *hash = strchr(text, '#');
    if (hash)
        *hash = '\0';
    char *tok[FX_MAX_TOKENS];
    int nt = 0;
    char *save = NULL;
    for (char *t = strtok_r(text, " \t\r\n", &save); t && nt < FX_MAX_TOKENS;
         t = strtok_r(NULL, " \t\r\n", &save))
        tok[nt++] = t;
    if (nt == 0)
        return 0;
    if (nt < 4) {
        lens_errf(err, path, line,
                  "expected: radius thickness material [n_d V_d] housing-radius (%d fields)", nt);
        return -1;
    }
    lens_surface *s = lens_add_surface_at(lens, path, line, err);
    if (!s)
        return -1;
    size_t idx = lens->nsurf;
    if (parse_double(tok[0], &s->radius) != 0 || s->radius == 0) {
        lens_errf(err, path, line, "radius '%s' is not a non-zero number", tok[0]);
        return -1;
    }
    if (fabs(s->radius) >= FX_FLAT_RADIUS)
        s->radius = INFINITY;
    char *slash = strchr(tok[1], '/');
    if (slash) {
        *slash = '\0';
        if (!st->zoom_noted)
            lens_add_note(lens, "zoom lens: the first position of each variable thickness is taken "
                                "(line %ld: %s/%s)", line, tok[1], slash + 1);
        st->zoom_noted = 1;
    }
    if (parse_double(tok[1], &s->thickness) != 0) {
        lens_errf(err, path, line, "thickness '%s' is not a number", tok[1]);
        return -1;
    }
    const char *m = tok[2];
    if (strncasecmp(m, "cx_", 3) == 0) {
        lens_errf(err, path, line,
                  "cylindrical surface '%s': the lens is not rotationally symmetric and cannot "
                  "be imported",
                  m);
        return -1;
    }
    int housing;
    if (strcasecmp(m, "air") == 0 || strcasecmp(m, "iris") == 0) {
        s->medium = glass_air();
        s->is_stop = strcasecmp(m, "iris") == 0;
        strcpy(s->material, s->is_stop ? "stop" : "air");
        housing = 3;
    } else {
        double nd, vd;
        if (nt < 6 || parse_double(tok[3], &nd) != 0 || parse_double(tok[4], &vd) != 0) {
            lens_errf(err, path, line, "glass '%s' needs n_d, V_d and the housing radius after it",
                      m);
            return -1;
        }
        char what[64];
        snprintf(what, sizeof what, "glass '%.40s'", m);
        if (glass_check_ndvd(nd, vd, what, path, line, err) != 0)
            return -1;
        const glass_t *g = NULL;
        const char *searched;
        int rc = strcasecmp(m, "abbe") == 0 ? 1 : material_lookup(&st->mat, m, &g, &searched, err);
        if (rc < 0)
            return -1;
        if (rc == 0) {
            s->medium = *g;
            if (fabs(g->nd - nd) > FX_ND_NOTE)
                lens_add_note(lens, "surface %zu: glass %s from the catalog (nd %.5f); the file "
                                    "gives %g/%g",
                              idx, g->name, g->nd, nd, vd);
        } else {
            s->medium = glass_from_ndvd(nd, vd);
            if (rc == 1 && strcasecmp(m, "abbe") != 0 && !strstr(st->missing, m)) {
                size_t n = strlen(st->missing);
                snprintf(st->missing + n, sizeof st->missing - n, " %s", m);
            }
        }
        snprintf(s->material, sizeof s->material, "%s", m);
        housing = 5;
    }
    if (parse_double(tok[housing], &s->semi_diameter) != 0 || !(s->semi_diameter > 0)) {
        lens_errf(err, path, line, "housing radius '%s' is not a positive number", tok[housing]);
        return -1;
    }
    if (nt > housing + 1 && !st->extra_noted) {
        lens_add_note(lens, "columns after the housing radius are ignored (first on line %ld)",
                      line);
        st->extra_noted = 1;
    }
    if (asph_spec[0] && parse_aspheric(asph_spec, s, path, line, err) != 0)
        return -1;
    return 0;
}

static void scale_lens(lens_t *lens, double k)
{
    for (size_t i = 0; i < lens->nsurf; i++) {
        lens_surface *s = &lens->surf[i];
        s->radius *= k;
        s->thickness *= k;
        s->semi_diameter *= k;
        /* z(h) -> k z(h / k): a_n h^n becomes a_n k^(1-n) h^n; the conic is unchanged. */
        for (int j = 0; j < LENS_ASPHERE_TERMS; j++)
            s->asphere[j] *= pow(k, -(3 + 2 * j));
    }
    if (isfinite(lens->focal))
        lens->focal *= k;
}

int lens_read_fx(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                 lens_err *err)
{
    lens_init(lens);
    snprintf(lens->path, sizeof lens->path, "%s", path);
    fx_state st;
    memset(&st, 0, sizeof st);
    material_ctx_init(&st.mat, opt, path);
    line_reader lr;
    line_reader_init(&lr, f, path, LINE_MAX_BYTES);
    long line = 0;
    double scale = 1;
    int rc = -1, rd;
    while ((rd = line_next(&lr, err)) == LINE_OK) {
        line = lr.line;
        char *p = lr.buf;
        while (isspace((unsigned char)*p))
            p++;
        if (*p == '#') {
            double v;
            char *end;
            if (strncmp(p, "#!scale", 7) == 0) {
                v = strtod(p + 7, &end);
                if (end == p + 7 || !(v > 0) || !isfinite(v)) {
                    lens_errf(err, path, line, "#!scale needs a positive number");
                    goto out;
                }
                scale *= v;
                lens_add_note(lens, "scaled by %g as the file asks (#!scale)", v);
            } else if (strncasecmp(p, "#EFL", 4) == 0 && !isfinite(lens->focal)) {
                v = strtod(p + 4, &end);
                if (end != p + 4 && v > 0 && isfinite(v))
                    lens->focal = v;
            }
            continue;
        }
        if (fx_surface(p, lens, &st, path, line, err) != 0)
            goto out;
    }
    if (rd != LINE_END)
        goto out;
    if (lens->nsurf == 0) {
        lens_errf(err, path, line > 0 ? line : 1, "no surfaces");
        goto out;
    }
    int nstop = 0;
    for (size_t i = 0; i < lens->nsurf; i++)
        nstop += lens->surf[i].is_stop;
    if (nstop == 0) {
        lens_errf(err, path, line, "no aperture stop (no 'iris' line)");
        goto out;
    }
    if (st.missing[0])
        lens_add_note(lens, "glasses not in the glass catalogs, modelled from their n_d/V_d:%s",
                      st.missing);
    if (scale != 1)
        scale_lens(lens, scale);
    rc = lens_finish(lens, err);
out:
    line_reader_free(&lr);
    material_ctx_free(&st.mat);
    if (rc != 0)
        lens_free(lens);
    return rc;
}
