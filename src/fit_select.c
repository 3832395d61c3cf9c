/* Term selection for one output: greedy forward selection scored by the exact drop in
 * the residual sum of squares, held-out stopping, and an exchange pass.
 *
 * The chosen terms are kept as an explicit QR factorisation of their sample columns
 * (modified Gram-Schmidt with one re-orthogonalisation, the "twice is enough" rule),
 * Phi_S = Q R. For every candidate j the projections c_j = Q^T phi_j are carried along
 * in the metric of the moment table: adding term t with R column (r, rho) gives
 *     c_j,new = (<phi_j, phi_t> - r . c_j) / rho,   <phi_j, phi_t> = moment(a_j + a_t),
 * which is forward substitution with R, so its error grows with cond(R), not cond(R)^2.
 * From c_j follow the candidate's remainder d_j = |phi_j|^2 - |c_j|^2 and its
 * correlation with the residual e_j = <phi_j, r>, and its score e_j^2 / d_j: the exact
 * drop in RSS it would bring. These scores only screen: the best few are re-scored
 * exactly on their sample columns before one is taken, so cancellation in the moment
 * arithmetic can reorder near-ties but never admits a dependent column. */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit_internal.h"

/* A candidate whose remainder in the moment metric is below this fraction of its
 * squared norm is out of reach of the moment arithmetic (cancellation); its exact
 * remainder must be above EXACT_DEP of its norm for it to be taken at all. */
#define SCREEN_DEP 1e-11
#define EXACT_DEP 1e-7
#define MAX_VERIFY 16
#define MAX_EXCHANGE_PASSES 8

enum { AVAIL = 0, CHOSEN = 1, DEPENDENT = 2 };

/* The chosen terms in positions 0..k-1. Their orthonormal basis is kept lazily:
 * Q_true = Q[:, 0..m-1] W, so that reordering terms (Givens rotations) costs O(k) on W
 * instead of O(n) on Q; Q is brought up to date only before a term is appended. */
typedef struct {
    const fit_basis *b;
    const double *mom, *by, *y, *yh;
    const fit_powers *tr, *ho;
    size_t n, nh, nc;
    int kcap, k, m, wdirty;
    double *Q, *Qt, *W, *R, *z, *r, *C, *dd, *ee, *H, *beta, *qx, *Ri;
    unsigned char *status;
    int *chosen;
    double *col, *v, *rc, *vbest, *rcbest, *score, *rowtmp;
    int top[MAX_VERIFY];
} sel;

static double dotn(const double *a, const double *b, size_t n)
{
    double s = 0;
#pragma omp simd reduction(+ : s)
    for (size_t i = 0; i < n; i++)
        s += a[i] * b[i];
    return s;
}

#define RR(s, i, j) ((s)->R[(size_t)(j) * (s)->kcap + (i)]) /* column-major */
#define WW(s, i, j) ((s)->W[(size_t)(j) * (s)->kcap + (i)])

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

/* Moment-metric scores; returns how many of the best (up to MAX_VERIFY) are in top[],
 * best first. */
static int gram_top(sel *s, int skip)
{
    const double *mom = s->mom;
    int nt = 0;
    for (size_t j = 0; j < s->nc; j++) {
        double g = mom[s->b->gdiag[j]];
        if (s->status[j] != AVAIL || (int)j == skip || !(s->dd[j] > SCREEN_DEP * g)) {
            s->score[j] = -1;
            continue;
        }
        double sc = s->ee[j] * s->ee[j] / s->dd[j];
        s->score[j] = sc;
        if (nt == MAX_VERIFY && !better(s, sc, (int)j, s->score[s->top[nt - 1]], s->top[nt - 1]))
            continue;
        int pos = nt < MAX_VERIFY ? nt++ : nt - 1;
        while (pos > 0 && better(s, sc, (int)j, s->score[s->top[pos - 1]], s->top[pos - 1])) {
            s->top[pos] = s->top[pos - 1];
            pos--;
        }
        s->top[pos] = (int)j;
    }
    return nt;
}

/* Exact score of candidate j against the span of the first k true basis columns: its
 * orthogonal remainder goes to s->v, its projections on Q's columns to s->rc. With qx
 * (the true column k, just taken out) the span is that of Q[:, 0..m-1] minus qx.
 * -1 when dependent. */
static double verify(sel *s, int j, const double *qx)
{
    size_t n = s->n;
    int m = qx ? s->m : s->k;
    fit_column(s->tr, s->b->exps + (size_t)j * s->b->nvar, s->col);
    double nrm2 = dotn(s->col, s->col, n);
    memcpy(s->v, s->col, n * sizeof *s->v);
    memset(s->rc, 0, (size_t)(m + 1) * sizeof *s->rc);
    for (int pass = 0; pass < 2; pass++)
        for (int l = 0; l < m; l++) {
            const double *q = s->Q + (size_t)l * n;
            double t = dotn(q, s->v, n);
            s->rc[l] += t;
            for (size_t i = 0; i < n; i++)
                s->v[i] -= t * q[i];
        }
    double rho2 = dotn(s->v, s->v, n), e = dotn(s->v, s->r, n);
    if (qx) {
        double a = dotn(qx, s->col, n);
        rho2 += a * a;
        e += a * dotn(qx, s->r, n);
    }
    if (!(rho2 > EXACT_DEP * EXACT_DEP * nrm2))
        return -1;
    return e * e / rho2;
}

/* Picks the best candidate: moment-metric scores screen, exact scores decide.
 * Returns the candidate (with qx == NULL its remainder is in vbest/rcbest) or -1. */
static int pick(sel *s, int skip, const double *qx, double *best)
{
    int nt = gram_top(s, skip), bj = -1;
    double bs = -1;
    for (int it = 0; it < nt; it++) {
        int j = s->top[it];
        if (bj >= 0 && bs >= s->score[j])
            break;
        double sc = verify(s, j, qx);
        if (sc < 0) {
            s->status[j] = DEPENDENT;
            continue;
        }
        if (bj < 0 || better(s, sc, j, bs, bj)) {
            bj = j;
            bs = sc;
            double *t = s->vbest; s->vbest = s->v; s->v = t;
            t = s->rcbest; s->rcbest = s->rc; s->rc = t;
        }
    }
    *best = bs;
    return bj;
}

/* Q[:, 0..ncols-1] <- Q[:, 0..m-1] W[:, 0..ncols-1]; afterwards W = I and m = ncols. */
static void materialize(sel *s, int ncols)
{
    if (s->wdirty) {
        size_t n = s->n;
        memset(s->Qt, 0, n * (size_t)ncols * sizeof *s->Qt);
        for (int c = 0; c < ncols; c++) {
            double *out = s->Qt + (size_t)c * n;
            for (int l = 0; l < s->m; l++) {
                double w = WW(s, l, c);
                if (w == 0)
                    continue;
                const double *q = s->Q + (size_t)l * n;
                for (size_t i = 0; i < n; i++)
                    out[i] += w * q[i];
            }
        }
        double *t = s->Q; s->Q = s->Qt; s->Qt = t;
    }
    s->m = ncols;
    s->wdirty = 0;
    for (int c = 0; c < s->kcap; c++)
        for (int l = 0; l < s->kcap; l++)
            WW(s, l, c) = l == c;
}

/* The true basis column l into out. */
static void qtrue(sel *s, int l, double *out)
{
    size_t n = s->n;
    if (!s->wdirty) {
        memcpy(out, s->Q + (size_t)l * n, n * sizeof *out);
        return;
    }
    memset(out, 0, n * sizeof *out);
    for (int i = 0; i < s->m; i++) {
        double w = WW(s, i, l);
        if (w == 0)
            continue;
        const double *q = s->Q + (size_t)i * n;
        for (size_t t = 0; t < n; t++)
            out[t] += w * q[t];
    }
}

/* Appends candidate j, whose remainder and projections are in vbest/rcbest (computed
 * with W = I and m = k). */
static void add(sel *s, int j)
{
    size_t n = s->n, nc = s->nc;
    int k = s->k, nvar = s->b->nvar, kc = s->kcap;
    double rho = sqrt(dotn(s->vbest, s->vbest, n));
    double *q = s->Q + (size_t)k * n;
    for (size_t i = 0; i < n; i++)
        q[i] = s->vbest[i] / rho;
    for (int l = 0; l < k; l++)
        RR(s, l, k) = s->rcbest[l];
    RR(s, k, k) = rho;
    double zk = dotn(q, s->r, n);
    s->z[k] = zk;
    for (size_t i = 0; i < n; i++)
        s->r[i] -= zk * q[i];
    const int *aj = s->b->exps + (size_t)j * nvar;
    const double *Rk = s->R + (size_t)k * kc;
    for (size_t i = 0; i < nc; i++) {
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
    if (s->nh)
        fit_column(s->ho, aj, s->H + (size_t)k * s->nh);
    s->k = k + 1;
    s->m = k + 1;
}

/* Coefficients of the current model (R beta = z) and its held-out RMS. */
static double hold_rms(sel *s)
{
    int k = s->k;
    for (int i = k - 1; i >= 0; i--) {
        double t = s->z[i];
        for (int l = i + 1; l < k; l++)
            t -= RR(s, i, l) * s->beta[l];
        s->beta[i] = t / RR(s, i, i);
    }
    if (!s->nh)
        return NAN;
    double sse = 0;
    for (size_t i = 0; i < s->nh; i++) {
        double p = 0;
        for (int l = 0; l < k; l++)
            p += s->H[(size_t)l * s->nh + i] * s->beta[l];
        double d = s->yh[i] - p;
        sse += d * d;
    }
    return sqrt(sse / (double)s->nh);
}

/* Training RMS of the first k terms from the projections z = Q^T y. */
static double train_rms(const sel *s, double yy)
{
    double rss = yy;
    for (int l = 0; l < s->k; l++)
        rss -= s->z[l] * s->z[l];
    return sqrt(fmax(rss, 0) / (double)s->n);
}

/* Keeps the first k terms: recomputes their candidates' projections by forward
 * substitution in the moment metric, the remainders, correlations and the residual.
 * Needs the true basis of the first k columns in Q (materialize first). */
static void reset_to(sel *s, int k)
{
    int kc = s->kcap, nvar = s->b->nvar;
    for (size_t j = 0; j < s->nc; j++)
        s->status[j] = AVAIL;
    for (int l = 0; l < k; l++)
        s->status[s->chosen[l]] = CHOSEN;
    s->k = k;
    for (size_t j = 0; j < s->nc; j++) {
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
    memcpy(s->r, s->y, s->n * sizeof *s->r);
    for (int l = 0; l < k; l++) {
        const double *q = s->Q + (size_t)l * s->n;
        for (size_t i = 0; i < s->n; i++)
            s->r[i] -= s->z[l] * q[i];
    }
}

/* Swaps terms l and l + 1 and restores the triangle with one Givens rotation, applied
 * alike to R, z, W and (with_c) every candidate's projections: all are Q^T of
 * something. The held-out columns and the chosen list are permuted. Columns up to k
 * (exclusive) of R are kept consistent. */
static void swap_adjacent(sel *s, int l, int with_c, int k)
{
    int kc = s->kcap;
    for (int i = 0; i <= l + 1; i++) {
        double t = RR(s, i, l); RR(s, i, l) = RR(s, i, l + 1); RR(s, i, l + 1) = t;
    }
    double a = RR(s, l, l), bb = RR(s, l + 1, l), h = hypot(a, bb), c = a / h, sn = bb / h;
#define ROT(x, y) do { double x_ = (x), y_ = (y); (x) = c * x_ + sn * y_; (y) = -sn * x_ + c * y_; } while (0)
    for (int col = l; col < k; col++)
        ROT(RR(s, l, col), RR(s, l + 1, col));
    RR(s, l + 1, l) = 0;
    ROT(s->z[l], s->z[l + 1]);
    if (with_c)
        for (size_t j = 0; j < s->nc; j++)
            ROT(s->C[j * kc + l], s->C[j * kc + l + 1]);
    for (int i = 0; i < s->m; i++)
        ROT(WW(s, i, l), WW(s, i, l + 1));
#undef ROT
    s->wdirty = 1;
    if (s->nh) {
        double *h0 = s->H + (size_t)l * s->nh, *h1 = h0 + s->nh;
        for (size_t i = 0; i < s->nh; i++) {
            double t = h0[i]; h0[i] = h1[i]; h1[i] = t;
        }
    }
    int t = s->chosen[l]; s->chosen[l] = s->chosen[l + 1]; s->chosen[l + 1] = t;
}

/* Takes the last term out (sign 1) or puts it back (sign -1); its true column in qx. */
static void drop_last(sel *s, double sign)
{
    int l = s->k - 1;
    double zl = s->z[l];
    for (size_t i = 0; i < s->n; i++)
        s->r[i] += sign * zl * s->qx[i];
    for (size_t j = 0; j < s->nc; j++) {
        double c = s->C[j * s->kcap + l];
        s->dd[j] += sign * c * c;
        s->ee[j] += sign * c * zl;
    }
}

/* One exchange pass: every term in turn is taken out and replaced by the best
 * candidate when that lowers the training RSS. Returns the number of swaps. */
static int exchange_pass(sel *s)
{
    int swaps = 0;
    for (int pos = s->k - 1; pos >= 0; pos--) {
        for (int l = pos; l < s->k - 1; l++)
            swap_adjacent(s, l, 1, s->k);
        int last = s->k - 1, term = s->chosen[last];
        double cur = s->z[last] * s->z[last];
        qtrue(s, last, s->qx);
        drop_last(s, 1.0);
        s->k = last;
        s->status[term] = AVAIL;
        int nt = gram_top(s, term);
        int nj = -1;
        double sc = -1;
        if (nt > 0 && s->score[s->top[0]] > cur * (1 + 1e-9))
            nj = pick(s, term, s->qx, &sc);
        if (nj >= 0 && sc > cur * (1 + 1e-9)) {
            materialize(s, last);
            if (verify(s, nj, NULL) >= 0) {
                double *t = s->vbest; s->vbest = s->v; s->v = t;
                t = s->rcbest; s->rcbest = s->rc; s->rc = t;
                add(s, nj);
                swaps++;
                continue;
            }
            /* Unreachable in exact arithmetic; fall back to the term we had, whose
             * true column is qx. */
            memcpy(s->Q + (size_t)last * s->n, s->qx, s->n * sizeof *s->qx);
            s->m = last + 1;
        }
        s->k = last + 1;
        s->status[term] = CHOSEN;
        drop_last(s, -1.0);
    }
    return swaps;
}

/* Backward elimination from k terms: repeatedly removes the term whose removal raises
 * the training RSS least (beta_t^2 / [(R^T R)^-1]_tt), moving it behind the others, so
 * that the first j positions are the j-term model for every j. hist[j] gets its
 * held-out RMS for j <= jmax. */
static void eliminate(sel *s, int jmax, double *hist, double yy)
{
    int kc = s->kcap, kend = s->k;
    while (s->k > 1) {
        int k = s->k;
        /* Ri = R^-1 (upper triangular), row norms give the diagonal of (R^T R)^-1. */
        for (int c = 0; c < k; c++) {
            for (int i = c; i >= 0; i--) {
                double t = i == c ? 1.0 : 0.0;
                for (int l = i + 1; l <= c; l++)
                    t -= RR(s, i, l) * s->Ri[(size_t)c * kc + l];
                s->Ri[(size_t)c * kc + i] = t / RR(s, i, i);
            }
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
            if (cost <= wcost) { /* ties: the later term */
                wcost = cost;
                worst = t;
            }
        }
        /* Rotating all kend columns keeps R a factor of every stored term, so that
         * each prefix stays the QR factorisation of its terms. */
        for (int l = worst; l < k - 1; l++)
            swap_adjacent(s, l, 0, kend);
        s->k = k - 1;
        if (s->k <= jmax)
            hist[s->k] = s->nh ? hold_rms(s) : train_rms(s, yy);
    }
}

/* Drops the terms the fit can do without: those whose removal keeps the training RMS
 * within tol. Greedy selection takes some terms early that later ones make redundant
 * (their coefficients fall to rounding); exchange cannot remove them, as nothing
 * scores above their ~zero contribution. */
static void prune(sel *s, double tol)
{
    double lim = tol * tol * (double)s->n;
    double rss = dotn(s->r, s->r, s->n);
    for (int pos = s->k - 1; pos >= 0 && s->k > 1; pos--) {
        for (int l = pos; l < s->k - 1; l++)
            swap_adjacent(s, l, 1, s->k);
        int last = s->k - 1;
        double cost = s->z[last] * s->z[last];
        if (rss + cost <= lim) {
            qtrue(s, last, s->qx);
            drop_last(s, 1.0);
            s->status[s->chosen[last]] = AVAIL;
            s->k = last;
            rss = dotn(s->r, s->r, s->n);
        }
    }
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
    s.y = ytrain;
    s.yh = yhold;
    s.tr = train;
    s.ho = hold;
    s.n = train->n;
    s.nh = hold ? hold->n : 0;
    s.nc = b->cand.count;
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
    size_t n = s.n, nc = s.nc, km = (size_t)s.kcap;
    s.Q = malloc(n * km * sizeof(double));
    s.Qt = malloc(n * km * sizeof(double));
    s.W = calloc(km * km, sizeof(double));
    s.R = calloc(km * km, sizeof(double));
    s.Ri = calloc(km * km, sizeof(double));
    s.z = calloc(km, sizeof(double));
    s.beta = calloc(km, sizeof(double));
    s.r = malloc(n * sizeof(double));
    s.qx = malloc(n * sizeof(double));
    s.C = calloc(nc * km, sizeof(double));
    s.dd = malloc(nc * sizeof(double));
    s.ee = malloc(nc * sizeof(double));
    s.score = malloc(nc * sizeof(double));
    s.H = malloc((s.nh ? s.nh : 1) * km * sizeof(double));
    s.status = calloc(nc, 1);
    s.chosen = calloc(km, sizeof(int));
    s.col = malloc(n * sizeof(double));
    s.v = malloc(n * sizeof(double));
    s.vbest = malloc(n * sizeof(double));
    s.rc = malloc((km + 1) * sizeof(double));
    s.rcbest = malloc((km + 1) * sizeof(double));
    s.rowtmp = malloc((km + 1) * sizeof(double));
    double *hist = malloc((km + 1) * sizeof(double));
    int rc = -1;
    if (!s.Q || !s.Qt || !s.W || !s.R || !s.Ri || !s.z || !s.beta || !s.r || !s.qx || !s.C || !s.dd ||
        !s.ee || !s.score || !s.H || !s.status || !s.chosen || !s.col || !s.v || !s.vbest ||
        !s.rc || !s.rcbest || !s.rowtmp || !hist)
        goto out;
    materialize(&s, 0);
    reset_to(&s, 0);

    double yy = dotn(ytrain, ytrain, n);
    /* Below this an output is fitted to rounding: nothing further to gain. */
    double floor_tol = 1e-10 * sqrt(yy / (double)n);
    double tol = o->tolerance > floor_tol ? o->tolerance : floor_tol;
    double h0 = s.nh ? sqrt(dotn(yhold, yhold, s.nh) / (double)s.nh) : sqrt(yy / (double)n);
    for (size_t j = 0; j <= km; j++)
        hist[j] = INFINITY;
    hist[0] = h0;
    double besth = h0;
    int bestk = 0;
    while (s.k < s.kcap) {
        double sc;
        int j = pick(&s, -1, NULL, &sc);
        if (j < 0 || !(sc > 0))
            break;
        add(&s, j);
        res->steps++;
        double h = hold_rms(&s);
        if (!s.nh)
            h = sqrt(dotn(s.r, s.r, n) / (double)n);
        if (s.k <= jmax)
            hist[s.k] = h;
        if (h < besth) {
            besth = h;
            bestk = s.k;
        }
        if (h <= tol)
            break;
        if (s.nh && s.k - bestk >= o->patience && s.k >= jmax)
            break;
    }
    if (s.k > 1)
        eliminate(&s, jmax, hist, yy);
    /* The fewest terms within a hair of the best held-out error over both passes. */
    double hmin = INFINITY;
    for (int k = 1; k <= jmax; k++)
        hmin = fmin(hmin, hist[k]);
    int kstar = 0;
    for (int k = 1; k <= jmax && !kstar; k++)
        if (hist[k] <= hmin * (1 + 1e-3) || hist[k] <= tol)
            kstar = k;
    if (kstar < 1)
        kstar = s.k >= 1 ? 1 : 0;
    materialize(&s, kstar);
    reset_to(&s, kstar);
    for (int p = 0; p < MAX_EXCHANGE_PASSES && p < o->exchange_passes && s.k > 0; p++) {
        int sw = exchange_pass(&s);
        res->swaps += sw;
        if (!sw)
            break;
    }
    if (s.k > 0 && sqrt(dotn(s.r, s.r, n) / (double)n) <= tol)
        prune(&s, tol);
    res->nterms = s.k;
    res->cand = malloc((size_t)(s.k ? s.k : 1) * sizeof(int));
    res->coef = malloc((size_t)(s.k ? s.k : 1) * sizeof(double));
    if (!res->cand || !res->coef) {
        fit_selection_free(res);
        goto out;
    }
    res->hold_rms = hold_rms(&s);
    for (int l = 0; l < s.k; l++) {
        res->cand[l] = s.chosen[l];
        res->coef[l] = s.beta[l];
    }
    res->train_rms = sqrt(dotn(s.r, s.r, n) / (double)n);
    rc = 0;
out:
    free(s.Q); free(s.Qt); free(s.W); free(s.R); free(s.Ri); free(s.z); free(s.beta); free(s.r);
    free(s.qx); free(s.C); free(s.dd); free(s.ee); free(s.score); free(s.H); free(s.status);
    free(s.chosen); free(s.col); free(s.v); free(s.vbest); free(s.rc); free(s.rcbest);
    free(s.rowtmp); free(hist);
    return rc;
}

double fit_eval_sample(const fit_basis *b, const fit_powers *p, size_t i, int k,
                       const int *cand, const double *coef)
{
    double sum = 0;
    for (int t = 0; t < k; t++) {
        const int *a = b->exps + (size_t)cand[t] * b->nvar;
        double m = coef[t];
        for (int v = 0; v < b->nvar; v++)
            if (a[v])
                m *= fit_pow_row(p, v, a[v])[i];
        sum += m;
    }
    return sum;
}

int fit_lsq(const fit_basis *b, const fit_powers *p, const double *y, int k, const int *cand,
            double *coef)
{
    size_t m = p->n;
    if (k < 1 || m < (size_t)k)
        return -1;
    double *A = malloc(m * (size_t)k * sizeof *A);
    double *B = malloc(m * sizeof *B);
    double *nrm = malloc((size_t)k * sizeof *nrm);
    int rc = -1;
    if (!A || !B || !nrm)
        goto out;
    for (int t = 0; t < k; t++) {
        double *col = A + (size_t)t * m;
        fit_column(p, b->exps + (size_t)cand[t] * b->nvar, col);
        double s = sqrt(dotn(col, col, m));
        if (!(s > 0))
            goto out;
        nrm[t] = s;
        for (size_t i = 0; i < m; i++)
            col[i] /= s;
    }
    memcpy(B, y, m * sizeof *B);
    lapack_int info = LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', (lapack_int)m, k, 1, A,
                                    (lapack_int)m, B, (lapack_int)m);
    if (info != 0)
        goto out;
    double rmax = 0, rmin = INFINITY;
    for (int t = 0; t < k; t++) {
        double d = fabs(A[(size_t)t * m + t]);
        rmax = d > rmax ? d : rmax;
        rmin = d < rmin ? d : rmin;
    }
    if (!(rmin > 1e-13 * rmax))
        goto out;
    for (int t = 0; t < k; t++)
        coef[t] = B[t] / nrm[t];
    rc = 0;
out:
    free(A);
    free(B);
    free(nrm);
    return rc;
}
