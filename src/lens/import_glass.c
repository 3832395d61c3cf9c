/* Glass look-up for the design-file importers (import_common.h): the user's catalogs,
 * glass.catalog beside the lens and the shipped one, with the loose name matching design
 * programs need (NBK7 for N-BK7, SK16_SCHOTT), and the n_d/V_d model fallback. */
#include "lens/import_common.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

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

