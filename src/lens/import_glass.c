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

/* Upper case, hyphens, underscores and blanks removed: N-BK7, n-bk7, NBK7 and N_BK7 are
 * one glass. */
static void normalise(const char *in, char *out, size_t cap)
{
    size_t o = 0;
    for (; *in && o + 1 < cap; in++)
        if (*in != '-' && *in != '_' && *in != ' ')
            out[o++] = (char)toupper((unsigned char)*in);
    out[o] = '\0';
}

static int has_vendor(const glass_catalog *cat, const char *vendor)
{
    size_t n = glass_catalog_size(cat);
    for (size_t i = 0; i < n; i++)
        if (strcasecmp(glass_catalog_vendor(cat, i), vendor) == 0)
            return 1;
    return 0;
}

typedef struct {
    const glass_t *g;
    size_t index;
    char others[120]; /* other vendors of a glass of that name, "HOYA, CDGM" */
} glass_match;

/* How well catalog glass i answers `want`: the name as written before one matched
 * without punctuation, a glass before an old name standing for another, then catalog
 * order (the user's catalogs first, then the shipped vendor order). Lower is better. */
static int rank(const glass_catalog *cat, size_t i, const char *name)
{
    return (strcasecmp(glass_catalog_at(cat, i)->name, name) == 0 ? 0 : 2) +
           (glass_catalog_alias_of(cat, i) ? 1 : 0);
}

/* The best glass of `vendor` (NULL: any) whose name matches `name` loosely. -1: two
 * different names of one vendor match equally (better an error than a wrong glass). */
static int find_loose(const material_ctx *mc, const char *name, const char *vendor,
                      glass_match *m)
{
    const glass_catalog *cat = mc->cat;
    char want[64], have[64];
    normalise(name, want, sizeof want);
    memset(m, 0, sizeof *m);
    int best = 99;
    size_t n = glass_catalog_size(cat);
    for (size_t i = 0; i < n; i++) {
        const glass_t *c = glass_catalog_at(cat, i);
        /* The user's catalogs come first whatever the suffix; it chooses among the
         * shipped catalog's vendors. */
        if (vendor && i >= mc->shipped_from && strcasecmp(glass_catalog_vendor(cat, i), vendor) != 0)
            continue;
        normalise(c->name, have, sizeof have);
        if (strcmp(want, have) != 0)
            continue;
        int r = rank(cat, i, name);
        if (r < best) {
            best = r;
            m->g = c;
            m->index = i;
        } else if (r == best && !import_eq(m->g->name, c->name) &&
                   strcmp(glass_catalog_vendor(cat, i), glass_catalog_vendor(cat, m->index)) ==
                       0) {
            return -1;
        }
    }
    if (!m->g)
        return 0;
    /* Other vendors' glasses of the name, for the note that says which one was taken. */
    const char *mine = glass_catalog_vendor(cat, m->index);
    for (size_t i = 0; i < n && !vendor; i++) {
        const char *v = glass_catalog_vendor(cat, i);
        if (glass_catalog_alias_of(cat, i) || strcmp(v, mine) == 0 || strstr(m->others, v))
            continue;
        normalise(glass_catalog_at(cat, i)->name, have, sizeof have);
        if (strcmp(want, have) == 0)
            append(m->others, sizeof m->others, v);
    }
    return 1;
}

/* NAME_VENDOR or NAME.VENDOR (Zemax and CODE V qualify names so) selects that vendor's
 * glass; a suffix that is no vendor's is dropped as a last resort. */
static int resolve(const material_ctx *mc, const char *name, glass_match *m)
{
    const glass_catalog *cat = mc->cat;
    char base[64];
    snprintf(base, sizeof base, "%s", name);
    char *cut = strrchr(base, '_'), *dot = strrchr(base, '.');
    if (!cut || (dot && dot > cut))
        cut = dot;
    if (cut && cut != base && cut[1] && has_vendor(cat, cut + 1)) {
        *cut = '\0';
        return find_loose(mc, base, cut + 1, m);
    }
    int rc = find_loose(mc, name, NULL, m);
    if (rc == 0 && cut && cut != base) {
        *cut = '\0';
        rc = find_loose(mc, base, NULL, m);
    }
    return rc;
}

/* What a design file names and what it gets, for the note. */
static void note_choice(import_glass_ctx *g, const char *name, const glass_match *m)
{
    const glass_catalog *cat = g->m.cat;
    const char *vendor = glass_catalog_vendor(cat, m->index);
    const char *target = glass_catalog_alias_of(cat, m->index);
    char what[400] = "";
    if (target)
        snprintf(what, sizeof what, "%s read as %s %s (an old name; its successor's data)",
                 name, vendor, target);
    else if (m->others[0])
        snprintf(what, sizeof what, "%s is %s's %s (also sold by %s; add _VENDOR to choose)",
                 name, vendor, m->g->name, m->others);
    if (what[0] && !strstr(g->choices, what))
        append(g->choices, sizeof g->choices, what);
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

/* The n_d/V_d a Zemax GLAS line carries beside a catalog glass are not read by Zemax,
 * and other writers fill them with round placeholders (1.5 and 40, 0 and 0): values
 * with at most two decimals and a whole V_d are taken for such, never for data. */
static int placeholder(double nd, double vd)
{
    return !(nd > 1.0) || !(vd > 0) || (fabs(nd * 100 - round(nd * 100)) < 1e-9 &&
                                        fabs(vd - round(vd)) < 1e-9);
}

int import_glass_lookup(import_glass_ctx *g, const char *name, double nd, double vd,
                        const char *file, long line, lens_surface *s, lens_err *err)
{
    const glass_t *hit = NULL;
    const char *searched = "none found";
    int rc = material_lookup(&g->m, name, &hit, &searched, err);
    if (rc < 0)
        return -1;
    glass_match m;
    memset(&m, 0, sizeof m);
    if (hit)
        m.index = glass_catalog_index(g->m.cat, hit);
    else if (g->m.cat && (rc = resolve(&g->m, name, &m)) < 0) {
        lens_errf(err, file, line, "glass %s matches two different glasses of one catalog; "
                                   "write the name exactly", name);
        return -1;
    }
    if (m.g)
        hit = m.g;
    if (hit) {
        const char *problem = glass_catalog_problem(g->m.cat, m.index);
        if (problem) {
            lens_errf(err, file, line, "glass %s cannot be used: %s", hit->name, problem);
            return -1;
        }
        note_choice(g, name, &m);
        s->medium = *hit;
        snprintf(s->material, sizeof s->material, "%s", hit->name);
        return 0;
    }
    int given = isfinite(nd) || isfinite(vd);
    int have_ndvd = given && !placeholder(nd, vd);
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
    else if (given)
        lens_errf(err, file, line,
                  "glass %s not found in %s (the file's n_d %g, V_d %g beside a catalog "
                  "glass are placeholders, not its data: add its maker's catalog with "
                  "--glass-catalog)%s",
                  name, searched, nd, vd, hint);
    else
        lens_errf(err, file, line, "glass %s not found in %s%s", name, searched, hint);
    return -1;
}

void import_glass_note(const import_glass_ctx *g, lens_t *lens)
{
    if (g->choices[0])
        lens_add_note(lens, "glass names: %s", g->choices);
    const glass_catalog *cat = g->m.cat;
    size_t n = glass_catalog_size(cat), bad = 0;
    char first[120] = "";
    for (size_t i = 0; i < n; i++)
        if (glass_catalog_problem(cat, i) && !glass_catalog_alias_of(cat, i) && bad++ == 0)
            snprintf(first, sizeof first, "%s %s", glass_catalog_vendor(cat, i),
                     glass_catalog_at(cat, i)->name);
    if (bad)
        lens_add_note(lens, "glass catalogs: %zu glass%s unusable (formula contradicts its own "
                            "n_d, first %s); the rest are used",
                      bad, bad == 1 ? "" : "es", first);
    if (g->fallbacks[0])
        lens_add_note(lens, "glass not in catalogs, n_d/V_d model used: %s", g->fallbacks);
}

