/* Zemax AGF glass catalog reader. A glass is an NM record followed by the records that
 * describe it until the next NM: CD carries the dispersion coefficients in the order of
 * the formula's definition (Zemax's numbering, kept in glass.h), LD the wavelength range
 * in micrometres over which the maker fitted them. */
#include "sparselens/agf.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "sparselens/glass_formula.h"
#include "lens/import_common.h"
#include "sparselens/numparse.h"

#define AGF_MAX_TOK 32

int agf_is_agf_path(const char *path)
{
    size_t n = strlen(path);
    return n > 4 && strcasecmp(path + n - 4, ".agf") == 0;
}

typedef struct {
    glass_t g;
    long line;
    int open, have_cd;
} pending;

static int flush(pending *p, const char *path, agf_add_fn add, void *ctx, lens_err *err)
{
    if (!p->open)
        return 0;
    p->open = 0;
    if (!p->have_cd) {
        lens_errf(err, path, p->line, "glass %s has no CD (dispersion coefficients) line",
                  p->g.name);
        return -1;
    }
    /* A formula that contradicts the NM line's n_d is a problem of that glass alone,
     * recorded by glass_catalog_add: the rest of the catalog stays usable. */
    return add(ctx, &p->g, err);
}

int agf_parse(const char *data, size_t len, const char *path, agf_add_fn add, void *ctx,
              lens_err *err)
{
    size_t text_len;
    char *text = import_decode(data, len, &text_len);
    if (!text) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    if (import_check_lines(text, text_len, path, err) != 0) {
        free(text);
        return -1;
    }
    import_lines it = {text, 0};
    char *line, *tok[AGF_MAX_TOK];
    pending p;
    memset(&p, 0, sizeof p);
    int rc = 0, nglass = 0;
    while (rc == 0 && (line = import_next_line(&it))) {
        int n = import_tokens(line, tok, AGF_MAX_TOK);
        if (n == 0)
            continue;
        if (n > AGF_MAX_TOK) {
            lens_errf(err, path, it.line, "more than %d words on a line", AGF_MAX_TOK);
            rc = -1;
            break;
        }
        if (import_eq(tok[0], "NM")) {
            if ((rc = flush(&p, path, add, ctx, err)) != 0)
                break;
            double f, nd, vd;
            if (n < 6 || parse_double(tok[2], &f) != 0 || parse_double(tok[4], &nd) != 0 ||
                parse_double(tok[5], &vd) != 0) {
                lens_errf(err, path, it.line,
                          "NM line: expected name, formula, MIL code, n_d, V_d");
                rc = -1;
                break;
            }
            if (!(f >= 1 && f <= 13) || f != floor(f) || glass_formula_ncoef((int)f) <= 0) {
                lens_errf(err, path, it.line, "glass %s: unknown dispersion formula %s",
                          tok[1], tok[2]);
                rc = -1;
                break;
            }
            if (strlen(tok[1]) >= sizeof p.g.name) {
                lens_errf(err, path, it.line, "glass name %.20s... is too long", tok[1]);
                rc = -1;
                break;
            }
            memset(&p, 0, sizeof p);
            p.open = 1;
            p.line = it.line;
            p.g.kind = GLASS_FORMULA;
            p.g.formula = (int)f;
            snprintf(p.g.name, sizeof p.g.name, "%s", tok[1]);
            p.g.nd = nd;
            p.g.vd = vd;
            /* No LD line: the range is unknown, so no wavelength is refused. */
            p.g.lambda_min = 0.0;
            p.g.lambda_max = INFINITY;
            nglass++;
        } else if (import_eq(tok[0], "CD")) {
            if (!p.open) {
                lens_errf(err, path, it.line, "CD line before any NM (glass name) line");
                rc = -1;
                break;
            }
            int nc = glass_formula_ncoef(p.g.formula);
            for (int i = 1; i < n; i++) {
                double v;
                if (parse_double(tok[i], &v) != 0) {
                    lens_errf(err, path, it.line, "glass %s: CD value '%s' is not a number",
                              p.g.name, tok[i]);
                    rc = -1;
                    break;
                }
                if (i - 1 < nc && i - 1 < GLASS_MAX_COEF)
                    p.g.coef[i - 1] = v;
                else if (v != 0) {
                    lens_errf(err, path, it.line,
                              "glass %s: formula %d (%s) takes %d coefficients, CD has more",
                              p.g.name, p.g.formula, glass_formula_name(p.g.formula), nc);
                    rc = -1;
                    break;
                }
            }
            p.have_cd = 1;
        } else if (import_eq(tok[0], "LD")) {
            double lo, hi;
            if (!p.open || n < 3 || parse_double(tok[1], &lo) != 0 ||
                parse_double(tok[2], &hi) != 0 || !(lo > 0) || !(hi > lo)) {
                lens_errf(err, path, it.line,
                          "LD line: expected the glass's wavelength range, min < max, in um");
                rc = -1;
                break;
            }
            p.g.lambda_min = lo;
            p.g.lambda_max = hi;
        }
        /* CC, GC, ED, TD, OD, IT, BD: comments, thermal, other and transmission data. */
    }
    if (rc == 0)
        rc = flush(&p, path, add, ctx, err);
    if (rc == 0 && nglass == 0) {
        lens_errf(err, path, 0, "no glasses (NM lines): not an AGF catalog");
        rc = -1;
    }
    free(text);
    return rc;
}

int agf_read(const char *path, agf_add_fn add, void *ctx, lens_err *err)
{
    char *data;
    size_t len;
    if (import_read_file(path, &data, &len, err) != 0)
        return -1;
    int rc = agf_parse(data, len, path, add, ctx, err);
    free(data);
    return rc;
}
