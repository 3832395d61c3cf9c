/* Refractive index of the media a lens is made of.
 * Long file: the model glass and the catalog reader with its vendor, alias and
 * unusable-entry rules share one lookup, which splitting would expose in a header.
 *
 * The (n_d, V_d) model glass. Patents give most glasses as n_d and V_d only; two numbers
 * fix an index and a slope, not the curvature of n(lambda) that sets the secondary
 * spectrum. The model supplies the missing facts from Schott's "normal lines" (the
 * straight lines through K7 and F2 on which normal glasses lie; Schott, Optical Glass,
 * eq. 3.10): the relative partial dispersions
 *   P_g,F = (n_g - n_F) / (n_F - n_C) = 0.6438 - 0.001682 V_d
 *   P_C,t = (n_C - n_t) / (n_F - n_C) = 0.5450 + 0.004743 V_d
 * and fits n(l) = A + B / (l^2 - C) + D l^2 (an ultraviolet pole and an infrared slope)
 * so that n(d) = n_d, n(F) - n(C) = (n_d - 1) / V_d exactly, and both partial
 * dispersions hold. For fixed C the conditions are linear in A, B, D; C is found by
 * bisection on the P_C,t condition.
 * Against the shipped Schott catalog the model is within 5e-5 over 0.4-0.7 um and
 * 3.5e-4 over 0.36-1.0 um for normal glasses (N-BK7, N-SK16, N-BAF10, F2, F5); glasses
 * off the normal lines (dense flints such as N-SF6: 1.6e-3 and 5.5e-3) are only as good
 * as the assumption. Assumptions: a normal glass; 0.36 .. 1.0 um only, outside that range
 * an error, not an extrapolation. Should an (n_d, V_d) pair lie so far outside the
 * glass map that no pole C in [-0.2, 0.1] um^2 fits (none does for n_d 1.35-2.2 and
 * V_d 15-100), the model falls back to Cauchy's n = A + B / l^2 with the same two exact
 * conditions. */
#include "base/index_hash.h"
#include "base/line_reader.h"
#include "sparselens/glass.h"
#include "sparselens/input_file.h"

#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "sparselens/agf.h"
#include "sparselens/data_path.h"
#include "sparselens/glass_formula.h"
#include "sparselens/numparse.h"

#define NDVD_LAMBDA_MIN 0.36
#define NDVD_LAMBDA_MAX 1.0

glass_t glass_air(void)
{
    glass_t g;
    memset(&g, 0, sizeof g);
    g.kind = GLASS_AIR;
    g.nd = 1.0;
    g.lambda_min = 0.0;
    g.lambda_max = INFINITY;
    return g;
}

glass_t glass_constant(double nd)
{
    glass_t g = glass_air();
    g.kind = GLASS_CONSTANT;
    g.nd = nd;
    return g;
}

int glass_check_ndvd(double nd, double vd, const char *what, const char *file, long line,
                     lens_err *err)
{
    if (!isfinite(nd) || nd < 1) {
        lens_errf(err, file, line, "%s: n_d %g %s", what, nd,
                  isfinite(nd) ? "is below 1 (indices are relative to air)" : "is not a number");
        return -1;
    }
    if (nd > GLASS_ND_MAX) {
        lens_errf(err, file, line, "%s: n_d %g is above %g, which no optical glass reaches", what,
                  nd, GLASS_ND_MAX);
        return -1;
    }
    if (!isnan(vd) && !(vd > 0 && isfinite(vd))) {
        lens_errf(err, file, line, "%s: Abbe number V_d %g must be positive and finite", what,
                  vd);
        return -1;
    }
    return 0;
}

#define G_LINE 0.4358343 /* mercury g line, um */
#define T_LINE 1.0139722 /* mercury t line, um */
#define PGF_A 0.6438
#define PGF_B (-0.001682)
#define PCT_A 0.5450
#define PCT_B 0.004743
#define NDVD_POLE_LO (-0.2)
#define NDVD_POLE_HI 0.1

static double ndvd_eval(const double *c, double l)
{
    double l2 = l * l;
    return c[0] + c[1] / (l2 - c[2]) + c[3] * l2;
}

/* A, B, D for the pole C: n(d) = nd, n(F) - n(C) = dfc, n(g) - n(F) = pgf dfc. */
static void ndvd_fit(double nd, double dfc, double pgf, double pole, double *c)
{
    double fd = 1 / (GLASS_D_LINE * GLASS_D_LINE - pole);
    double ff = 1 / (GLASS_F_LINE * GLASS_F_LINE - pole);
    double fc = 1 / (GLASS_C_LINE * GLASS_C_LINE - pole);
    double fg = 1 / (G_LINE * G_LINE - pole);
    double a11 = ff - fc, a12 = GLASS_F_LINE * GLASS_F_LINE - GLASS_C_LINE * GLASS_C_LINE;
    double a21 = fg - ff, a22 = G_LINE * G_LINE - GLASS_F_LINE * GLASS_F_LINE;
    double det = a11 * a22 - a12 * a21;
    c[1] = (dfc * a22 - a12 * pgf * dfc) / det;
    c[3] = (a11 * pgf * dfc - a21 * dfc) / det;
    c[2] = pole;
    c[0] = nd - c[1] * fd - c[3] * GLASS_D_LINE * GLASS_D_LINE;
}

/* Residual of the P_C,t condition for the pole C. */
static double ndvd_residual(double nd, double dfc, double pgf, double pct, double pole)
{
    double c[4];
    ndvd_fit(nd, dfc, pgf, pole, c);
    return (ndvd_eval(c, GLASS_C_LINE) - ndvd_eval(c, T_LINE)) / dfc - pct;
}

glass_t glass_from_ndvd(double nd, double vd)
{
    glass_t g = glass_air();
    g.kind = GLASS_NDVD;
    g.nd = nd;
    g.vd = vd;
    g.lambda_min = NDVD_LAMBDA_MIN;
    g.lambda_max = NDVD_LAMBDA_MAX;
    double dfc = (nd - 1.0) / vd;
    double pgf = PGF_A + PGF_B * vd, pct = PCT_A + PCT_B * vd;
    double lo = NDVD_POLE_LO, hi = NDVD_POLE_HI;
    double rlo = ndvd_residual(nd, dfc, pgf, pct, lo), rhi = ndvd_residual(nd, dfc, pgf, pct, hi);
    if (isfinite(rlo) && isfinite(rhi) && (rlo < 0) != (rhi < 0)) {
        for (int i = 0; i < 80; i++) { /* 80 halvings: below one ulp of the bracket */
            double mid = 0.5 * (lo + hi);
            double r = ndvd_residual(nd, dfc, pgf, pct, mid);
            if ((r < 0) == (rlo < 0)) {
                lo = mid;
                rlo = r;
            } else {
                hi = mid;
            }
        }
        ndvd_fit(nd, dfc, pgf, 0.5 * (lo + hi), g.coef);
        return g;
    }
    /* Cauchy fallback: pole at 0, no infrared term. */
    double b = dfc / (1.0 / (GLASS_F_LINE * GLASS_F_LINE) - 1.0 / (GLASS_C_LINE * GLASS_C_LINE));
    g.coef[0] = nd - b / (GLASS_D_LINE * GLASS_D_LINE);
    g.coef[1] = b;
    g.coef[2] = 0;
    g.coef[3] = 0;
    return g;
}

double glass_index_unchecked(const glass_t *g, double l)
{
    switch (g->kind) {
    case GLASS_AIR:
        return 1.0;
    case GLASS_CONSTANT:
        return g->nd;
    case GLASS_NDVD:
        return ndvd_eval(g->coef, l);
    case GLASS_FORMULA:
        return glass_formula_eval(g->formula, g->coef, l);
    }
    return NAN;
}

int glass_index(const glass_t *g, double l, double *n, lens_err *err)
{
    if (!(l >= g->lambda_min && l <= g->lambda_max)) {
        if (g->name[0])
            lens_errf(err, NULL, 0, "wavelength %g um is outside the range %g..%g um of "
                      "glass %s", l, g->lambda_min, g->lambda_max, g->name);
        else /* a glass given by numbers is named by them */
            lens_errf(err, NULL, 0, "wavelength %g um is outside the range %g..%g um of the "
                      "model glass nd %.6g vd %.6g", l, g->lambda_min, g->lambda_max, g->nd,
                      g->vd);
        return -1;
    }
    double v = glass_index_unchecked(g, l);
    if (!isfinite(v) || v < 1.0) {
        lens_errf(err, NULL, 0, "glass %s has no real index at %g um", g->name, l);
        return -1;
    }
    *n = v;
    return 0;
}

/* ---- catalogs ------------------------------------------------------------------ */

/* What a catalog knows of each glass besides its data: whose it is, whether it is an old
 * name read as another glass, and why it cannot be used (a formula that contradicts the
 * entry's own n_d). */
typedef struct {
    char vendor[GLASS_VENDOR_MAX];
    int alias_of; /* index of the glass an old name stands for, or -1 */
    char problem[224];
} glass_entry;

struct glass_catalog {
    glass_t *g;
    glass_entry *e;
    size_t n, cap;
    char *sources; /* "a.catalog, b.agf" */
    char vendor[GLASS_VENDOR_MAX]; /* vendor of the glasses being added */
    const char *loading;           /* file being read, for problems */
};

glass_catalog *glass_catalog_new(void)
{
    return calloc(1, sizeof(glass_catalog));
}

void glass_catalog_free(glass_catalog *cat)
{
    if (!cat)
        return;
    free(cat->g);
    free(cat->e);
    free(cat->sources);
    free(cat);
}

void glass_catalog_set_vendor(glass_catalog *cat, const char *vendor)
{
    size_t o = 0;
    for (; vendor[o] && o + 1 < sizeof cat->vendor; o++)
        cat->vendor[o] = (char)toupper((unsigned char)vendor[o]);
    cat->vendor[o] = '\0';
}

/* A catalog's nominal n_d must agree with its own formula; a coefficient typed in the
 * wrong column, or a wrong formula number, shows up here rather than as a subtly wrong
 * lens. 1e-3 leaves room for makers' rounding, which is near 1e-5. */
#define CATALOG_ND_TOLERANCE 1e-3

static void check_consistent(const glass_catalog *cat, const glass_t *g, char *problem,
                             size_t cap)
{
    problem[0] = '\0';
    if (g->kind != GLASS_FORMULA || !(g->nd > 1) || !(GLASS_D_LINE >= g->lambda_min) ||
        !(GLASS_D_LINE <= g->lambda_max))
        return;
    double n = glass_formula_eval(g->formula, g->coef, GLASS_D_LINE);
    if (!(fabs(n - g->nd) <= CATALOG_ND_TOLERANCE))
        snprintf(problem, cap,
                 "in %s, formula %d (%s) gives n_d %.6f where the entry says %.6f "
                 "(coefficients in the wrong order, or a wrong formula number?)",
                 cat->loading ? cat->loading : "its catalog", g->formula,
                 glass_formula_name(g->formula), n, g->nd);
}

int glass_catalog_add(glass_catalog *cat, const glass_t *g, lens_err *err)
{
    if (!g->name[0]) {
        lens_errf(err, NULL, 0, "a catalog glass needs a name");
        return -1;
    }
    if (cat->n == cat->cap) {
        size_t cap = cat->cap ? 2 * cat->cap : 64;
        glass_t *ng = realloc(cat->g, cap * sizeof *ng);
        if (ng)
            cat->g = ng;
        glass_entry *ne = ng ? realloc(cat->e, cap * sizeof *ne) : NULL;
        if (!ne) {
            lens_errf(err, NULL, 0, "out of memory");
            return -1;
        }
        cat->e = ne;
        cat->cap = cap;
    }
    glass_entry *e = &cat->e[cat->n];
    memcpy(e->vendor, cat->vendor, sizeof e->vendor);
    e->alias_of = -1;
    check_consistent(cat, g, e->problem, sizeof e->problem);
    cat->g[cat->n++] = *g;
    return 0;
}

int glass_catalog_add_source(glass_catalog *cat, const char *path)
{
    size_t old = cat->sources ? strlen(cat->sources) : 0;
    char *s = realloc(cat->sources, old + strlen(path) + 3);
    if (!s)
        return -1;
    if (old)
        strcpy(s + old, ", ");
    strcpy(s + old + (old ? 2 : 0), path);
    cat->sources = s;
    return 0;
}

const glass_t *glass_catalog_find(const glass_catalog *cat, const char *name)
{
    if (!cat)
        return NULL;
    /* The first in catalog order: the user's catalogs, then the shipped vendor order
     * (whose old names stand for that vendor's successors). */
    for (size_t i = 0; i < cat->n; i++)
        if (strcasecmp(cat->g[i].name, name) == 0)
            return &cat->g[i];
    return NULL;
}

size_t glass_catalog_size(const glass_catalog *cat)
{
    return cat ? cat->n : 0;
}

const glass_t *glass_catalog_at(const glass_catalog *cat, size_t i)
{
    return cat && i < cat->n ? &cat->g[i] : NULL;
}

size_t glass_catalog_index(const glass_catalog *cat, const glass_t *g)
{
    return cat && g >= cat->g && g < cat->g + cat->n ? (size_t)(g - cat->g) : (size_t)-1;
}

const char *glass_catalog_vendor(const glass_catalog *cat, size_t i)
{
    return cat && i < cat->n ? cat->e[i].vendor : "";
}

const char *glass_catalog_alias_of(const glass_catalog *cat, size_t i)
{
    return cat && i < cat->n && cat->e[i].alias_of >= 0 ? cat->g[cat->e[i].alias_of].name : NULL;
}

const char *glass_catalog_problem(const glass_catalog *cat, size_t i)
{
    return cat && i < cat->n && cat->e[i].problem[0] ? cat->e[i].problem : NULL;
}

const char *glass_catalog_sources(const glass_catalog *cat)
{
    return cat && cat->sources ? cat->sources : "";
}

/* Keywords of the .catalog format, indexed by AGF formula number. */
static const char *const formula_keyword[] = {
    [GLASS_F_SCHOTT] = "schott",         [GLASS_F_SELLMEIER1] = "sellmeier1",
    [GLASS_F_HERZBERGER] = "herzberger", [GLASS_F_SELLMEIER2] = "sellmeier2",
    [GLASS_F_CONRADY] = "conrady",       [GLASS_F_SELLMEIER3] = "sellmeier3",
    [GLASS_F_HANDBOOK1] = "handbook1",   [GLASS_F_HANDBOOK2] = "handbook2",
    [GLASS_F_SELLMEIER4] = "sellmeier4", [GLASS_F_EXTENDED1] = "extended1",
    [GLASS_F_SELLMEIER5] = "sellmeier5", [GLASS_F_EXTENDED2] = "extended2",
    [GLASS_F_EXTENDED3] = "extended3",
};

static int formula_from_token(const char *t)
{
    for (int f = GLASS_F_SCHOTT; f <= GLASS_F_EXTENDED3; f++)
        if (strcasecmp(t, formula_keyword[f]) == 0)
            return f;
    long v;
    if (parse_long(t, &v) == 0 && v >= GLASS_F_SCHOTT && v <= GLASS_F_EXTENDED3)
        return (int)v;
    return 0;
}

int glass_parse_catalog_line(char *line, const char *path, long lineno, glass_t *g,
                             lens_err *err)
{
    char *tok[GLASS_MAX_COEF + 8];
    int nt = 0;
    char *save = NULL;
    for (char *t = strtok_r(line, " \t\r\n", &save); t; t = strtok_r(NULL, " \t\r\n", &save)) {
        if (nt == (int)(sizeof tok / sizeof *tok)) {
            lens_errf(err, path, lineno, "too many fields");
            return -1;
        }
        tok[nt++] = t;
    }
    if (nt < 2) {
        lens_errf(err, path, lineno, "expected: name formula coefficients... lambda_min "
                                     "lambda_max nd vd");
        return -1;
    }
    memset(g, 0, sizeof *g);
    g->kind = GLASS_FORMULA;
    if (strlen(tok[0]) >= sizeof g->name) {
        lens_errf(err, path, lineno, "glass name '%s' is too long", tok[0]);
        return -1;
    }
    strcpy(g->name, tok[0]);
    g->formula = formula_from_token(tok[1]);
    if (!g->formula) {
        lens_errf(err, path, lineno, "unknown dispersion formula '%s' (sellmeier1, schott, "
                                     "... or an AGF formula number 1-13)", tok[1]);
        return -1;
    }
    int nc = glass_formula_ncoef(g->formula);
    if (nt != 2 + nc + 4) {
        lens_errf(err, path, lineno,
                  "glass %s: formula %s takes %d coefficients, then lambda_min lambda_max "
                  "nd vd (%d fields expected, %d found)",
                  g->name, glass_formula_name(g->formula), nc, 2 + nc + 4, nt);
        return -1;
    }
    double v[GLASS_MAX_COEF + 4];
    for (int i = 0; i < nc + 4; i++)
        if (parse_double(tok[2 + i], &v[i]) != 0) {
            lens_errf(err, path, lineno, "glass %s: '%s' is not a finite number", g->name,
                      tok[2 + i]);
            return -1;
        }
    memcpy(g->coef, v, (size_t)nc * sizeof *v);
    g->lambda_min = v[nc];
    g->lambda_max = v[nc + 1];
    g->nd = v[nc + 2];
    g->vd = v[nc + 3];
    if (!(g->lambda_min > 0 && g->lambda_max > g->lambda_min)) {
        lens_errf(err, path, lineno, "glass %s: wavelength range %g..%g um is empty", g->name,
                  g->lambda_min, g->lambda_max);
        return -1;
    }
    /* The bounds of lens(5) for n_d (glass_check_ndvd); V_d 0 marks a glass without
     * a catalog Abbe number. */
    char what[sizeof g->name + 8];
    snprintf(what, sizeof what, "glass %s", g->name);
    if (glass_check_ndvd(g->nd, NAN, what, path, lineno, err) != 0)
        return -1;
    if (!(g->vd >= 0)) {
        lens_errf(err, path, lineno, "glass %s: vd %g must be >= 0", g->name, g->vd);
        return -1;
    }
    /* A formula that contradicts n_d is the catalog's problem for that glass alone:
     * glass_catalog_add records it. */
    return 0;
}

static int ends_with_ci(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

struct same_name_ctx {
    const glass_catalog *cat;
    const char *name;
};

/* The same name of the same vendor (two vendors may both sell an F2). */
static int same_name(const void *ctx, int index)
{
    const struct same_name_ctx *c = ctx;
    return strcasecmp(c->cat->g[index].name, c->name) == 0 &&
           strcmp(c->cat->e[index].vendor, c->cat->vendor) == 0;
}

/* "vendor NAME": the glasses that follow are NAME's. */
static int is_directive(char *line, const char *word, char **rest)
{
    size_t n = strlen(word);
    if (strncasecmp(line, word, n) != 0 || (line[n] && !isspace((unsigned char)line[n])))
        return 0;
    *rest = line + n;
    return 1;
}

static int add_named(glass_catalog *cat, index_hash *names, const glass_t *g, const char *path,
                     long line, lens_err *err)
{
    uint64_t h = index_hash_text_nocase(g->name);
    struct same_name_ctx ctx = {cat, g->name};
    if (index_hash_find(names, h, same_name, &ctx) >= 0) {
        lens_errf(err, path, line, "glass %s is listed twice in this file", g->name);
        return -1;
    }
    if (glass_catalog_add(cat, g, err) != 0)
        return -1;
    if (index_hash_add(names, h, (int)(cat->n - 1)) != 0) {
        lens_errf(err, path, line, "out of memory");
        return -1;
    }
    return 0;
}

/* "alias OLD NEW": OLD is read as the vendor's NEW, listed before it in this file. */
static int add_alias(glass_catalog *cat, index_hash *names, char *rest, const char *path,
                     long line, lens_err *err)
{
    char *save = NULL, *old = strtok_r(rest, " \t\r\n", &save);
    char *target = old ? strtok_r(NULL, " \t\r\n", &save) : NULL;
    if (!target || strtok_r(NULL, " \t\r\n", &save)) {
        lens_errf(err, path, line, "expected: alias OLD-NAME GLASS");
        return -1;
    }
    struct same_name_ctx ctx = {cat, target};
    int to = index_hash_find(names, index_hash_text_nocase(target), same_name, &ctx);
    if (to < 0) {
        lens_errf(err, path, line, "alias %s: no glass %s of %s above it", old, target,
                  cat->vendor[0] ? cat->vendor : "this file");
        return -1;
    }
    glass_t g = cat->g[to];
    if (strlen(old) >= sizeof g.name) {
        lens_errf(err, path, line, "glass name '%s' is too long", old);
        return -1;
    }
    strcpy(g.name, old);
    if (add_named(cat, names, &g, path, line, err) != 0)
        return -1;
    cat->e[cat->n - 1].alias_of = to;
    return 0;
}

/* One pass, with a hash of the names read so far: a catalog of n glasses is read in
 * time linear in n (a scan per glass took minutes at 200 000). */
static int load_text_catalog(glass_catalog *cat, FILE *f, const char *path, lens_err *err)
{
    line_reader lr;
    line_reader_init(&lr, f, path, LINE_MAX_BYTES);
    index_hash names = {0};
    int rc = -1, st;
    while ((st = line_next(&lr, err)) == LINE_OK) {
        char *hash = strchr(lr.buf, '#');
        if (hash)
            *hash = '\0';
        char *p = lr.buf, *rest;
        while (isspace((unsigned char)*p))
            p++;
        if (!*p)
            continue;
        if (is_directive(p, "vendor", &rest)) {
            char *save = NULL, *v = strtok_r(rest, " \t\r\n", &save);
            if (!v || strtok_r(NULL, " \t\r\n", &save) || strlen(v) >= GLASS_VENDOR_MAX) {
                lens_errf(err, path, lr.line, "expected: vendor NAME (one word, at most %d "
                                              "characters)", GLASS_VENDOR_MAX - 1);
                goto out;
            }
            glass_catalog_set_vendor(cat, v);
            continue;
        }
        if (is_directive(p, "alias", &rest)) {
            if (add_alias(cat, &names, rest, path, lr.line, err) != 0)
                goto out;
            continue;
        }
        glass_t g;
        if (glass_parse_catalog_line(p, path, lr.line, &g, err) != 0 ||
            add_named(cat, &names, &g, path, lr.line, err) != 0)
            goto out;
    }
    rc = st == LINE_END ? 0 : -1;
out:
    index_hash_free(&names);
    line_reader_free(&lr);
    return rc;
}

/* A file's glasses are its maker's until a vendor line says otherwise: SCHOTT for
 * schott_2017.agf, NIKON for NIKON.AGF (the _VENDOR suffix of names selects them). */
static void vendor_from_path(glass_catalog *cat, const char *path)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    char v[GLASS_VENDOR_MAX];
    size_t o = 0;
    for (; base[o] && base[o] != '_' && base[o] != '.' && base[o] != '-' && o + 1 < sizeof v; o++)
        v[o] = base[o];
    v[o] = '\0';
    glass_catalog_set_vendor(cat, v);
}

/* agf.c hands each glass to a callback; this is it. */
static int agf_add(void *cat, const glass_t *g, lens_err *err)
{
    return glass_catalog_add(cat, g, err);
}

int glass_catalog_load(glass_catalog **catp, const char *path, lens_err *err)
{
    lens_err why;
    FILE *f = input_open(path, &why);
    if (!f) {
        lens_errf(err, NULL, 0, "glass catalog %s", why.msg);
        return -1;
    }
    int created = 0;
    if (!*catp) {
        *catp = glass_catalog_new();
        created = 1;
        if (!*catp) {
            fclose(f);
            lens_errf(err, path, 0, "out of memory");
            return -1;
        }
    }
    size_t before = (*catp)->n;
    vendor_from_path(*catp, path);
    (*catp)->loading = path;
    /* AGF catalogs (Zemax's format) are read by agf.c, one glass_catalog_add each. */
    int rc = ends_with_ci(path, ".agf") ? agf_read(path, agf_add, *catp, err)
                                        : load_text_catalog(*catp, f, path, err);
    fclose(f);
    (*catp)->loading = NULL;
    if (rc == 0 && glass_catalog_add_source(*catp, path) != 0) {
        lens_errf(err, path, 0, "out of memory");
        rc = -1;
    }
    if (rc != 0) {
        /* Leave the catalog as it was before this file. */
        (*catp)->n = before;
        if (created) {
            glass_catalog_free(*catp);
            *catp = NULL;
        }
    }
    return rc;
}

static int readable(const char *p)
{
    return access(p, R_OK) == 0;
}

const char *glass_default_catalog_path(void)
{
    /* One buffer per thread: the answer depends only on the environment and the
     * executable's location, so recomputing it per call is harmless. */
    static _Thread_local char buf[PATH_MAX + 64];
    const char *env = getenv("SPARSELENS_GLASS_CATALOG");
    if (env && *env)
        return readable(env) ? env : NULL;
    return data_shipped_file("lenses", "glass.catalog", buf, sizeof buf) == 0 ? buf : NULL;
}

void glass_format_catalog_line(const glass_t *g, char *buf, size_t n)
{
    int nc = glass_formula_ncoef(g->formula);
    size_t o = (size_t)snprintf(buf, n, "%s %s", g->name, formula_keyword[g->formula]);
    double v[GLASS_MAX_COEF + 4];
    memcpy(v, g->coef, (size_t)nc * sizeof *v);
    v[nc] = g->lambda_min, v[nc + 1] = g->lambda_max, v[nc + 2] = g->nd, v[nc + 3] = g->vd;
    for (int i = 0; i < nc + 4 && o < n; i++)
        o += (size_t)snprintf(buf + o, n - o, " %.17g", v[i]);
}
