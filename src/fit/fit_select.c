/* Term selection for one output: greedy forward selection scored by the exact drop in
 * the residual sum of squares, backward elimination, held-out stopping, an exchange
 * pass, and a ladder of degree caps so that more candidates never lose.
 *
 * Everything here works in the metric of the moment table, never on sample columns:
 * <phi_a, phi_b> = moment(a + b). The chosen terms have a Cholesky-like factor R
 * (Phi_S = Q R for an orthonormal Q that is never formed) and for every candidate j
 * the projections c_j = Q^T phi_j are carried along; adding term t with R column
 * (r, rho) gives
 *     c_j,new = (<phi_j, phi_t> - r . c_j) / rho,
 * which is forward substitution with R. From c_j follow the candidate's remainder
 * d_j = |phi_j|^2 - |c_j|^2, its correlation with the residual e_j = <phi_j, y> - c_j.z,
 * and its score e_j^2 / d_j: the exact drop in RSS it would bring. A step costs
 * O(candidates x terms) whatever the number of samples. Cancellation limits how small a
 * remainder can be resolved, so candidates whose remainder falls below DEP of their
 * squared norm count as dependent; the final coefficients are solved by Householder QR
 * on the sample columns (fit_lsq), and the held-out error is measured on samples. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit/fit_internal.h"

#define DEP 1e-11
#define MAX_EXCHANGE_PASSES 8
#define CAP_MARGIN 0.01

enum { AVAIL = 0, CHOSEN = 1, DEPENDENT = 2, OFF = 3 };

/* The chosen terms are in positions 0..k-1 (R is column-major, kcap x kcap). */
typedef struct {
    const fit_basis *b;
    const double *mom, *by, *yh;
    const fit_powers *ho;
    size_t n, nh, nc;
    double yy;
    int kcap, k;
    double *R, *Ri, *z, *C, *dd, *ee, *H, *beta;
    unsigned char *status, *slot_used;
    int *chosen, *hcol; /* hcol[l]: column of H holding the term at position l */
    double *g;
} sel;

#define RR(s, i, j) ((s)->R[(size_t)(j) * (s)->kcap + (i)])

/* Tie-break for equal scores: lower degree, then lower index (deterministic). */
static int better(const sel *s, double sa, int a, double sb, int b)
{
    if (b < 0)
        return 1;
    if (sa != sb)
        return sa > sb;
    if (s->b->deg[a] != s->b->deg[b])
        return s->b->deg[a] < s->b->deg[b];
    return a < b;
}

/* The best available candidate (not skip) and its score, or -1. */
static int pick(sel *s, int skip, double *best)
{
    const double *mom = s->mom;
    int bj = -1;
    double bs = -1;
    for (size_t j = 0; j < s->nc; j++) {
        if (s->status[j] != AVAIL || (int)j == skip)
            continue;
        double g = mom[s->b->gdiag[j]];
        if (!(s->dd[j] > DEP * g)) {
            if (s->dd[j] <= DEP * g)
                s->status[j] = DEPENDENT;
            continue;
        }
        double sc = s->ee[j] * s->ee[j] / s->dd[j];
        if (better(s, sc, (int)j, bs, bj)) {
            bj = (int)j;
            bs = sc;
        }
    }
    *best = bs;
    return bj;
}

/* Appends candidate j after the first k terms. */
static void add(sel *s, int j)
{
    size_t nc = s->nc;
    int k = s->k, nvar = s->b->nvar, kc = s->kcap;
    double rho = sqrt(s->dd[j]);
    const double *cjj = s->C + (size_t)j * kc;
    for (int l = 0; l < k; l++)
        RR(s, l, k) = cjj[l];
    RR(s, k, k) = rho;
    double zk = s->ee[j] / rho;
    s->z[k] = zk;
    const int *aj = s->b->exps + (size_t)j * nvar;
    const double *Rk = s->R + (size_t)k * kc;
    for (size_t i = 0; i < nc; i++) {
        if (s->status[i] == OFF)
            continue;
        const int *ai = s->b->exps + i * nvar;
        int a[FIT_MAX_VARS];
        for (int v = 0; v < nvar; v++)
            a[v] = ai[v] + aj[v];
        double *ci = s->C + i * kc;
        double g = s->mom[fit_lex_rank(&s->b->mom, a)];
        for (int l = 0; l < k; l++)
            g -= Rk[l] * ci[l];
        double c = g / rho;
        ci[k] = c;
        s->dd[i] -= c * c;
        s->ee[i] -= c * zk;
    }
    s->status[j] = CHOSEN;
    s->chosen[k] = j;
    if (s->nh) {
        /* The column slot no other position uses. */
        memset(s->slot_used, 0, (size_t)s->kcap);
        for (int l = 0; l < k; l++)
            s->slot_used[s->hcol[l]] = 1;
        int slot = 0;
        while (s->slot_used[slot])
            slot++;
        s->hcol[k] = slot;
        fit_column(s->ho, aj, s->H + (size_t)slot * s->nh);
    }
    s->k = k + 1;
}

/* Coefficients of the first k terms (R beta = z). */
static void solve_beta(sel *s, int k)
{
    for (int i = k - 1; i >= 0; i--) {
        double t = s->z[i];
        for (int l = i + 1; l < k; l++)
            t -= RR(s, i, l) * s->beta[l];
        s->beta[i] = t / RR(s, i, i);
    }
}

/* Error of the first k terms: held-out RMS measured on the held-out samples, or (without
 * them) the training RMS from |r|^2 = |y|^2 - |z|^2. */
static double err_k(sel *s, int k)
{
    if (!s->nh) {
        double rss = s->yy;
        for (int l = 0; l < k; l++)
            rss -= s->z[l] * s->z[l];
        return sqrt(fmax(rss, 0) / (double)s->n);
    }
    solve_beta(s, k);
    double sse = 0;
    for (size_t i = 0; i < s->nh; i++) {
        double p = 0;
        for (int l = 0; l < k; l++)
            p += s->H[(size_t)s->hcol[l] * s->nh + i] * s->beta[l];
        double d = s->yh[i] - p;
        sse += d * d;
    }
    return sqrt(sse / (double)s->nh);
}

/* Keeps the first k terms: recomputes every candidate's projections by forward
 * substitution in the moment metric, its remainder and its correlation. */
static void reset_to(sel *s, int k)
{
    int kc = s->kcap, nvar = s->b->nvar;
    for (size_t j = 0; j < s->nc; j++)
        if (s->status[j] != OFF)
            s->status[j] = AVAIL;
    for (int l = 0; l < k; l++)
        s->status[s->chosen[l]] = CHOSEN;
    s->k = k;
    for (size_t j = 0; j < s->nc; j++) {
        if (s->status[j] == OFF)
            continue;
        double *cj = s->C + j * kc;
        const int *aj = s->b->exps + j * nvar;
        double d = s->mom[s->b->gdiag[j]], e = s->by[j];
        for (int l = 0; l < k; l++) {
            const int *al = s->b->exps + (size_t)s->chosen[l] * nvar;
            int a[FIT_MAX_VARS];
            for (int v = 0; v < nvar; v++)
                a[v] = aj[v] + al[v];
            double g = s->mom[fit_lex_rank(&s->b->mom, a)];
            for (int i = 0; i < l; i++)
                g -= RR(s, i, l) * cj[i];
            cj[l] = g / RR(s, l, l);
            d -= cj[l] * cj[l];
            e -= cj[l] * s->z[l];
        }
        s->dd[j] = d;
        s->ee[j] = e;
    }
}

/* Swaps terms l and l + 1 and restores the triangle with one Givens rotation, applied
 * alike to R (columns below kend), z and (with_c) every candidate's projections: all
 * are Q^T of something. The held-out columns and the chosen list are permuted. */
static void swap_adjacent(sel *s, int l, int with_c, int kend)
{
    int kc = s->kcap;
    for (int i = 0; i <= l + 1; i++) {
        double t = RR(s, i, l); RR(s, i, l) = RR(s, i, l + 1); RR(s, i, l + 1) = t;
    }
    double a = RR(s, l, l), bb = RR(s, l + 1, l), h = hypot(a, bb), c = a / h, sn = bb / h;
#define ROT(x, y) do { double x_ = (x), y_ = (y); (x) = c * x_ + sn * y_; (y) = -sn * x_ + c * y_; } while (0)
    for (int col = l; col < kend; col++)
        ROT(RR(s, l, col), RR(s, l + 1, col));
    RR(s, l + 1, l) = 0;
    ROT(s->z[l], s->z[l + 1]);
    if (with_c)
        for (size_t j = 0; j < s->nc; j++)
            ROT(s->C[j * kc + l], s->C[j * kc + l + 1]);
#undef ROT
    int t = s->chosen[l]; s->chosen[l] = s->chosen[l + 1]; s->chosen[l + 1] = t;
    t = s->hcol[l]; s->hcol[l] = s->hcol[l + 1]; s->hcol[l + 1] = t;
}

/* Takes the last term out (sign 1) or puts it back (sign -1). */
static void drop_last(sel *s, double sign)
{
    int l = s->k - 1;
    double zl = s->z[l];
    for (size_t j = 0; j < s->nc; j++) {
        double c = s->C[j * s->kcap + l];
        s->dd[j] += sign * c * c;
        s->ee[j] += sign * c * zl;
    }
}

/* One exchange pass: every term in turn is taken out and replaced by the best
 * candidate when that lowers the training RSS. Returns the number of swaps.
 * Taking term p out removes from the span the unit direction g (in Q coordinates)
 * orthogonal to the other terms, g = R^-T e_p / |R^-T e_p|; a candidate's remainder
 * and correlation grow by (g.c_j)^2 and (g.c_j)(g.z), so a trial costs one dot
 * product per candidate and the factors change only when a swap is made. */
static int exchange_pass(sel *s)
{
    int swaps = 0, kc = s->kcap;
    for (int p = s->k - 1; p >= 0; p--) {
        int k = s->k, term = s->chosen[p];
        double *g = s->g, gn = 0, gz = 0;
        for (int l = 0; l < k; l++) {
            double t = l == p ? 1.0 : 0.0;
            for (int i = p; i < l; i++)
                t -= RR(s, i, l) * g[i];
            g[l] = l < p ? 0 : t / RR(s, l, l);
            gn += g[l] * g[l];
        }
        gn = sqrt(gn);
        for (int l = p; l < k; l++) {
            g[l] /= gn;
            gz += g[l] * s->z[l];
        }
        double cur = gz * gz;
        int bj = -1;
        double bs = -1;
        for (size_t j = 0; j < s->nc; j++) {
            if (s->status[j] != AVAIL)
                continue;
            const double *cj = s->C + j * kc;
            double t = 0;
            for (int l = p; l < k; l++)
                t += g[l] * cj[l];
            double d = s->dd[j] + t * t, e = s->ee[j] + t * gz;
            if (!(d > DEP * s->mom[s->b->gdiag[j]]))
                continue;
            double sc = e * e / d;
            if (better(s, sc, (int)j, bs, bj)) {
                bj = (int)j;
                bs = sc;
            }
        }
        if (bj < 0 || !(bs > cur * (1 + 1e-9)))
            continue;
        for (int l = p; l < k - 1; l++)
            swap_adjacent(s, l, 1, k);
        drop_last(s, 1.0);
        s->k = k - 1;
        s->status[term] = AVAIL;
        add(s, bj);
        swaps++;
    }
    return swaps;
}

/* The term whose removal raises the training RSS least, beta_t^2 / [(R^T R)^-1]_tt,
 * among the first k, and that increase. Ties: the later term. */
static int least_useful(sel *s, int k, double *cost_out)
{
    int kc = s->kcap;
    for (int c = 0; c < k; c++)
        for (int i = c; i >= 0; i--) {
            double t = i == c ? 1.0 : 0.0;
            for (int l = i + 1; l <= c; l++)
                t -= RR(s, i, l) * s->Ri[(size_t)c * kc + l];
            s->Ri[(size_t)c * kc + i] = t / RR(s, i, i);
        }
    int worst = -1;
    double wcost = INFINITY;
    for (int t = 0; t < k; t++) {
        double bt = 0, nr = 0;
        for (int c = t; c < k; c++) {
            double ri = s->Ri[(size_t)c * kc + t];
            bt += ri * s->z[c];
            nr += ri * ri;
        }
        double cost = bt * bt / nr;
        if (cost <= wcost) {
            wcost = cost;
            worst = t;
        }
    }
    *cost_out = wcost;
    return worst;
}

/* Floating steps: add the best candidate, then take out the least useful term if that
 * is not the new one. The RSS falls at every step that changes the set (the term taken
 * out costs less than the new one brought), so this ends. These moves reach sets that
 * single exchanges cannot: the addition is judged with every current term present. */
static int float_pass(sel *s, int max_steps)
{
    int moves = 0;
    for (int it = 0; it < max_steps && s->k < s->kcap; it++) {
        double sc;
        int j = pick(s, -1, &sc);
        if (j < 0 || !(sc > 0))
            break;
        int k = s->k;
        add(s, j);
        double cost;
        int w = least_useful(s, k + 1, &cost);
        if (w == k || !(cost < sc * (1 - 1e-9))) {
            w = k; /* the new term is the least useful: undo */
        }
        for (int l = w; l < k; l++)
            swap_adjacent(s, l, 1, k + 1);
        drop_last(s, 1.0);
        s->status[s->chosen[k]] = AVAIL;
        s->k = k;
        if (w == k && s->chosen[k] == j)
            break;
        moves++;
    }
    return moves;
}

/* Backward elimination from k terms: repeatedly removes the term whose removal raises
 * the training RSS least (beta_t^2 / [(R^T R)^-1]_tt), moving it behind the others, so
 * that the first j positions are the j-term model for every j. hist[j] gets its error
 * for j <= jmax. */
static void eliminate(sel *s, int jmax, double *hist)
{
    int kend = s->k;
    while (s->k > 1) {
        int k = s->k;
        double cost;
        int worst = least_useful(s, k, &cost);
        /* Rotating all kend columns keeps R a factor of every stored term, so that
         * each prefix stays the factor of its terms. */
        for (int l = worst; l < k - 1; l++)
            swap_adjacent(s, l, 0, kend);
        s->k = k - 1;
        if (s->k <= jmax)
            hist[s->k] = err_k(s, s->k);
    }
}

/* Drops terms whose removal keeps the error within tol. Greedy selection takes some
 * terms early that later ones make redundant (their coefficients fall to rounding);
 * exchange cannot remove them, as nothing scores above their ~zero contribution. */
static void prune(sel *s, double tol)
{
    for (int pos = s->k - 1; pos >= 0 && s->k > 1; pos--) {
        for (int l = pos; l < s->k - 1; l++)
            swap_adjacent(s, l, 1, s->k);
        if (err_k(s, s->k - 1) <= tol) {
            drop_last(s, 1.0);
            s->status[s->chosen[s->k - 1]] = AVAIL;
            s->k--;
        }
    }
}

/* One selection with the candidates of degree <= cap. */
static void select_capped(sel *s, int cap, int jmax, double tol, int patience, int passes,
                          double *hist, fit_selection *res)
{
    for (size_t j = 0; j < s->nc; j++)
        s->status[j] = s->b->deg[j] > cap ? OFF : AVAIL;
    reset_to(s, 0);
    for (int j = 0; j <= s->kcap; j++)
        hist[j] = INFINITY;
    double besth = err_k(s, 0);
    hist[0] = besth;
    int bestk = 0;
    res->steps = res->swaps = 0;
    while (s->k < s->kcap) {
        double sc;
        int j = pick(s, -1, &sc);
        if (j < 0 || !(sc > 0))
            break;
        add(s, j);
        res->steps++;
        if (s->k > jmax)
            continue; /* sizes past the budget only feed the elimination */
        double h = err_k(s, s->k);
        hist[s->k] = h;
        if (h < besth) {
            besth = h;
            bestk = s->k;
        }
        if (h <= tol)
            break;
        if (s->nh && s->k - bestk >= patience && s->k >= jmax)
            break;
    }
    if (s->k > 1)
        eliminate(s, jmax, hist);
    /* The fewest terms within a hair of the best error over both passes. */
    double hmin = INFINITY;
    for (int k = 1; k <= jmax; k++)
        hmin = fmin(hmin, hist[k]);
    int kstar = 0;
    for (int k = 1; k <= jmax && !kstar; k++)
        if (hist[k] <= hmin * (1 + 1e-3) || hist[k] <= tol)
            kstar = k;
    if (kstar < 1)
        kstar = s->k >= 1 ? 1 : 0;
    reset_to(s, kstar);
    for (int p = 0; p < MAX_EXCHANGE_PASSES && p < passes && s->k > 0; p++) {
        int sw = exchange_pass(s);
        sw += float_pass(s, 4 * s->k);
        res->swaps += sw;
        if (!sw)
            break;
    }
    if (s->k > 0 && err_k(s, s->k) <= tol)
        prune(s, tol);
    res->nterms = s->k;
    res->hold_rms = err_k(s, s->k);
    solve_beta(s, s->k);
    for (int l = 0; l < s->k; l++) {
        res->cand[l] = s->chosen[l];
        res->coef[l] = s->beta[l];
    }
    double rss = s->yy;
    for (int l = 0; l < s->k; l++)
        rss -= s->z[l] * s->z[l];
    res->train_rms = sqrt(fmax(rss, 0) / (double)s->n);
}

void fit_selection_free(fit_selection *s)
{
    free(s->cand);
    free(s->coef);
    s->cand = NULL;
    s->coef = NULL;
}

int fit_select(const fit_basis *b, const double *mom, const double *by,
               const fit_powers *train, const double *ytrain, const fit_powers *hold,
               const double *yhold, const fit_select_opt *o, fit_selection *res)
{
    memset(res, 0, sizeof *res);
    sel s = {0};
    s.b = b;
    s.mom = mom;
    s.by = by;
    s.yh = yhold;
    s.ho = hold;
    s.n = train->n;
    s.nh = hold ? hold->n : 0;
    s.nc = b->cand.count;
    s.yy = fit_dot(ytrain, ytrain, s.n);
    int jmax = o->max_terms;
    /* Forward selection runs past the budget (to twice it), then backward
     * elimination comes back: a set chosen from more terms than it keeps. */
    s.kcap = 2 * jmax;
    if ((size_t)s.kcap > s.nc)
        s.kcap = (int)s.nc;
    if ((size_t)s.kcap > s.n)
        s.kcap = (int)s.n;
    if (jmax > s.kcap)
        jmax = s.kcap;
    if (s.kcap < 1)
        return -1;
    size_t nc = s.nc, km = (size_t)s.kcap;
    s.R = calloc(km * km, sizeof(double));
    s.Ri = calloc(km * km, sizeof(double));
    s.z = calloc(km, sizeof(double));
    s.beta = calloc(km, sizeof(double));
    s.C = calloc(nc * km, sizeof(double));
    s.dd = malloc(nc * sizeof(double));
    s.ee = malloc(nc * sizeof(double));
    s.H = malloc((s.nh ? s.nh : 1) * km * sizeof(double));
    s.status = calloc(nc, 1);
    s.chosen = calloc(km, sizeof(int));
    s.hcol = calloc(km, sizeof(int));
    s.slot_used = calloc(km, 1);
    s.g = calloc(km, sizeof(double));
    double *hist = malloc((km + 1) * sizeof(double));
    fit_selection cur = {0};
    cur.cand = malloc(km * sizeof(int));
    cur.coef = malloc(km * sizeof(double));
    res->cand = malloc(km * sizeof(int));
    res->coef = malloc(km * sizeof(double));
    int rc = -1;
    if (!s.R || !s.Ri || !s.z || !s.beta || !s.C || !s.dd || !s.ee || !s.H ||
        !s.status || !s.chosen || !s.hcol || !s.slot_used || !s.g || !hist || !cur.cand || !cur.coef || !res->cand || !res->coef) {
        fit_selection_free(res);
        goto out;
    }
    /* Below this an output is fitted to rounding: nothing further to gain. */
    double floor_tol = 1e-10 * sqrt(s.yy / (double)s.n);
    double tol = o->tolerance > floor_tol ? o->tolerance : floor_tol;
    /* Degree caps 3, 5, 7, ... below the maximum, and the maximum: the best by
     * held-out error wins, so offering higher degrees can only help (the caps of a
     * lower maximum are a subset). A higher cap must win by CAP_MARGIN on both the
     * held-out and the training error: the held-out error of a few hundred rays is a
     * noisy estimate, the training error alone would not see overfitting, and a
     * smaller difference is noise (parsimony). */
    int D = b->D, first = 1;
    for (int cap = D < 3 ? D : 3; cap <= D; cap = cap + 2 <= D || cap == D ? cap + 2 : D) {
        select_capped(&s, cap, jmax, tol, o->patience, o->exchange_passes, hist, &cur);
        if (first || (cur.hold_rms < res->hold_rms * (1 - CAP_MARGIN) &&
                      cur.train_rms < res->train_rms * (1 - CAP_MARGIN))) {
            int *c = res->cand; double *f = res->coef;
            *res = cur;
            res->cand = c;
            res->coef = f;
            memcpy(res->cand, cur.cand, (size_t)cur.nterms * sizeof(int));
            memcpy(res->coef, cur.coef, (size_t)cur.nterms * sizeof(double));
            first = 0;
        }
        if (cur.hold_rms <= tol)
            break; /* a lower cap already meets the tolerance */
    }
    rc = 0;
out:
    free(s.R); free(s.Ri); free(s.z); free(s.beta); free(s.C); free(s.dd); free(s.ee);
    free(s.H); free(s.status); free(s.chosen); free(s.hcol); free(s.slot_used); free(s.g); free(hist);
    free(cur.cand); free(cur.coef);
    return rc;
}
