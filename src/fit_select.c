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
#define MAX_VERIFY 24

enum { AVAIL = 0, CHOSEN = 1, DEPENDENT = 2 };

typedef struct {
    const fit_basis *b;
    const double *mom, *by, *y, *yh;
    const fit_powers *tr, *ho;
    size_t n, nh, nc;
    int kmax, k;
    double *Q, *R, *z, *r, *C, *dd, *ee, *H, *beta;
    unsigned char *status, *seen;
    int *chosen;
    double *col, *v, *rc, *vbest, *rcbest, *tmp, *score;
} sel;

static double dotn(const double *a, const double *b, size_t n)
{
    double s = 0;
#pragma omp simd reduction(+ : s)
    for (size_t i = 0; i < n; i++)
        s += a[i] * b[i];
    return s;
}

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

static void gram_scores(sel *s, int skip)
{
    const double *mom = s->mom;
    for (size_t j = 0; j < s->nc; j++) {
        double g = mom[s->b->gdiag[j]];
        if (s->status[j] != AVAIL || (int)j == skip || !(s->dd[j] > SCREEN_DEP * g))
            s->score[j] = -1;
        else
            s->score[j] = s->ee[j] * s->ee[j] / s->dd[j];
    }
}

/* Exact score of candidate j against the current k columns of Q: its orthogonal
 * remainder goes to s->v, its projections to s->rc. -1 when dependent. */
static double verify(sel *s, int j)
{
    size_t n = s->n;
    int k = s->k;
    fit_column(s->tr, s->b->exps + (size_t)j * s->b->nvar, s->col);
    double nrm2 = dotn(s->col, s->col, n);
    memcpy(s->v, s->col, n * sizeof *s->v);
    memset(s->rc, 0, (size_t)(k + 1) * sizeof *s->rc);
    for (int pass = 0; pass < 2; pass++)
        for (int l = 0; l < k; l++) {
            const double *q = s->Q + (size_t)l * n;
            double t = dotn(q, s->v, n);
            s->rc[l] += t;
            for (size_t i = 0; i < n; i++)
                s->v[i] -= t * q[i];
        }
    double rho2 = dotn(s->v, s->v, n);
    if (!(rho2 > EXACT_DEP * EXACT_DEP * nrm2))
        return -1;
    double e = dotn(s->v, s->r, n);
    return e * e / rho2;
}

/* Picks the best candidate: moment-metric scores screen, exact scores decide.
 * Returns the candidate (its remainder in vbest/rcbest) or -1; *best its exact score. */
static int pick(sel *s, int skip, double *best)
{
    gram_scores(s, skip);
    memset(s->seen, 0, s->nc);
    int bj = -1;
    double bs = -1;
    for (int it = 0; it < MAX_VERIFY; it++) {
        int j = -1;
        for (size_t i = 0; i < s->nc; i++)
            if (!s->seen[i] && s->score[i] >= 0 && better(s, s->score[i], (int)i, j < 0 ? -1 : s->score[j], j))
                j = (int)i;
        if (j < 0 || (bj >= 0 && bs >= s->score[j]))
            break;
        s->seen[j] = 1;
        double sc = verify(s, j);
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

/* Appends candidate j, whose remainder and projections are in vbest/rcbest. */
static void add(sel *s, int j)
{
    size_t n = s->n, nc = s->nc;
    int k = s->k, nvar = s->b->nvar, kmax = s->kmax;
    double rho = sqrt(dotn(s->vbest, s->vbest, n));
    double *q = s->Q + (size_t)k * n;
    for (size_t i = 0; i < n; i++)
        q[i] = s->vbest[i] / rho;
    double *Rk = s->R + (size_t)k * kmax;
    for (int l = 0; l < k; l++)
        Rk[l] = s->rcbest[l];
    Rk[k] = rho;
    double zk = dotn(q, s->r, n);
    s->z[k] = zk;
    for (size_t i = 0; i < n; i++)
        s->r[i] -= zk * q[i];
    const int *aj = s->b->exps + (size_t)j * nvar;
    for (size_t i = 0; i < nc; i++) {
        const int *ai = s->b->exps + i * nvar;
        int a[FIT_MAX_VARS];
        for (int v = 0; v < nvar; v++)
            a[v] = ai[v] + aj[v];
        double *ci = s->C + i * kmax;
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
}

/* Coefficients of the current model (R beta = z) and its held-out RMS. */
static double hold_rms(sel *s)
{
    int k = s->k, kmax = s->kmax;
    for (int i = k - 1; i >= 0; i--) {
        double t = s->z[i];
        for (int l = i + 1; l < k; l++)
            t -= s->R[(size_t)l * kmax + i] * s->beta[l];
        s->beta[i] = t / s->R[(size_t)i * kmax + i];
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

/* Rebuilds residual, remainders and correlations for the first k terms. */
static void reset_to(sel *s, int k)
{
    for (int l = k; l < s->k; l++)
        s->status[s->chosen[l]] = AVAIL;
    s->k = k;
    for (size_t j = 0; j < s->nc; j++) {
        if (s->status[j] == DEPENDENT)
            s->status[j] = AVAIL;
        const double *cj = s->C + j * s->kmax;
        double d = s->mom[s->b->gdiag[j]], e = s->by[j];
        for (int l = 0; l < k; l++) {
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
 * to R, z, Q and every candidate's projections alike (they are all Q^T of something). */
static void swap_adjacent(sel *s, int l)
{
    int kmax = s->kmax, k = s->k;
    double *Rl = s->R + (size_t)l * kmax, *Rl1 = Rl + kmax;
    for (int i = 0; i <= l + 1; i++) {
        double t = Rl[i]; Rl[i] = Rl1[i]; Rl1[i] = t;
    }
    double a = Rl[l], bb = Rl[l + 1], h = hypot(a, bb), c = a / h, sn = bb / h;
#define ROT(x, y) do { double x_ = (x), y_ = (y); (x) = c * x_ + sn * y_; (y) = -sn * x_ + c * y_; } while (0)
    for (int col = l; col < k; col++)
        ROT(s->R[(size_t)col * kmax + l], s->R[(size_t)col * kmax + l + 1]);
    s->R[(size_t)l * kmax + l + 1] = 0;
    ROT(s->z[l], s->z[l + 1]);
    for (size_t j = 0; j < s->nc; j++)
        ROT(s->C[j * kmax + l], s->C[j * kmax + l + 1]);
    double *q0 = s->Q + (size_t)l * s->n, *q1 = q0 + s->n;
    for (size_t i = 0; i < s->n; i++)
        ROT(q0[i], q1[i]);
#undef ROT
    if (s->nh) {
        double *h0 = s->H + (size_t)l * s->nh, *h1 = h0 + s->nh;
        for (size_t i = 0; i < s->nh; i++) {
            double t = h0[i]; h0[i] = h1[i]; h1[i] = t;
        }
    }
    int t = s->chosen[l]; s->chosen[l] = s->chosen[l + 1]; s->chosen[l + 1] = t;
}

/* Takes the last term out (k -> k-1), keeping its column for a possible undo. */
static void drop_last(sel *s, double sign)
{
    int l = s->k - 1;
    double zl = s->z[l];
    const double *q = s->Q + (size_t)l * s->n;
    for (size_t i = 0; i < s->n; i++)
        s->r[i] += sign * zl * q[i];
    for (size_t j = 0; j < s->nc; j++) {
        double c = s->C[j * s->kmax + l];
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
            swap_adjacent(s, l);
        int last = s->k - 1, term = s->chosen[last];
        double cur = s->z[last] * s->z[last];
        drop_last(s, 1.0);
        s->k = last;
        s->status[term] = AVAIL;
        gram_scores(s, term);
        double gbest = -1;
        for (size_t j = 0; j < s->nc; j++)
            if (s->score[j] > gbest)
                gbest = s->score[j];
        int nj = -1;
        double sc = -1;
        if (gbest > cur * (1 + 1e-9))
            nj = pick(s, term, &sc);
        if (nj >= 0 && sc > cur * (1 + 1e-9)) {
            add(s, nj);
            swaps++;
        } else {
            s->k = last + 1;
            s->status[term] = CHOSEN;
            drop_last(s, -1.0);
        }
    }
    return swaps;
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
            swap_adjacent(s, l);
        int last = s->k - 1;
        double cost = s->z[last] * s->z[last];
        if (rss + cost <= lim) {
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
    s.kmax = o->max_terms;
    if ((size_t)s.kmax > s.nc)
        s.kmax = (int)s.nc;
    if ((size_t)s.kmax > s.n)
        s.kmax = (int)s.n;
    if (s.kmax < 1)
        return -1;
    size_t n = s.n, nc = s.nc, km = (size_t)s.kmax;
    s.Q = malloc(n * km * sizeof(double));
    s.R = calloc(km * km, sizeof(double));
    s.z = calloc(km, sizeof(double));
    s.beta = calloc(km, sizeof(double));
    s.r = malloc(n * sizeof(double));
    s.C = calloc(nc * km, sizeof(double));
    s.dd = malloc(nc * sizeof(double));
    s.ee = malloc(nc * sizeof(double));
    s.score = malloc(nc * sizeof(double));
    s.H = malloc((s.nh ? s.nh : 1) * km * sizeof(double));
    s.status = calloc(nc, 1);
    s.seen = calloc(nc, 1);
    s.chosen = calloc(km, sizeof(int));
    s.col = malloc(n * sizeof(double));
    s.v = malloc(n * sizeof(double));
    s.vbest = malloc(n * sizeof(double));
    s.rc = malloc((km + 1) * sizeof(double));
    s.rcbest = malloc((km + 1) * sizeof(double));
    double *hist = malloc((km + 1) * sizeof(double));
    int rc = -1;
    if (!s.Q || !s.R || !s.z || !s.beta || !s.r || !s.C || !s.dd || !s.ee || !s.score ||
        !s.H || !s.status || !s.seen || !s.chosen || !s.col || !s.v || !s.vbest || !s.rc ||
        !s.rcbest || !hist)
        goto out;
    s.k = 0;
    reset_to(&s, 0);

    double yy = dotn(ytrain, ytrain, n);
    /* Below this an output is fitted to rounding: nothing further to gain. */
    double floor_tol = 1e-10 * sqrt(yy / (double)n);
    double tol = o->tolerance > floor_tol ? o->tolerance : floor_tol;
    double h0 = s.nh ? sqrt(dotn(yhold, yhold, s.nh) / (double)s.nh) : sqrt(yy / (double)n);
    hist[0] = h0;
    double besth = h0;
    int bestk = 0;
    while (s.k < s.kmax) {
        double sc;
        int j = pick(&s, -1, &sc);
        if (j < 0 || !(sc > 0))
            break;
        add(&s, j);
        res->steps++;
        double h = hold_rms(&s);
        if (!s.nh)
            h = sqrt(dotn(s.r, s.r, n) / (double)n);
        hist[s.k] = h;
        if (h < besth) {
            besth = h;
            bestk = s.k;
        }
        if (h <= tol)
            break;
        if (s.nh && s.k - bestk >= o->patience)
            break;
    }
    /* The fewest terms within a hair of the best held-out error. */
    int kstar = bestk;
    for (int k = 1; k <= bestk; k++)
        if (hist[k] <= besth * (1 + 1e-3) || hist[k] <= tol) {
            kstar = k;
            break;
        }
    if (kstar < 1 && s.k >= 1)
        kstar = 1;
    if (kstar < s.k)
        reset_to(&s, kstar);
    for (int p = 0; p < o->exchange_passes && s.k > 0; p++) {
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
    free(s.Q); free(s.R); free(s.z); free(s.beta); free(s.r); free(s.C); free(s.dd);
    free(s.ee); free(s.score); free(s.H); free(s.status); free(s.seen); free(s.chosen);
    free(s.col); free(s.v); free(s.vbest); free(s.rc); free(s.rcbest); free(hist);
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
