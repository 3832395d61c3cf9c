/* The monomial tables and evaluation plans of a system's parts (poly_impl.h): each
 * monomial a slot built as the product of two earlier ones, and a plan that keeps the
 * products several terms share and fuses the others into their one term. */
#include "poly/poly_impl.h"

#include <stdlib.h>
#include <string.h>

void poly_terms_free(poly_out_terms *t, int n)
{
    if (t)
        for (int o = 0; o < n; o++) {
            free(t[o].exps);
            free(t[o].coef);
            free(t[o].slot);
        }
    free(t);
}

void poly_mono_free(poly_mono *m)
{
    free(m->exps);
    free(m->a);
    free(m->b);
    free(m->depth);
    free(m->used_by);
    index_hash_free(&m->index);
}

void poly_plan_free(poly_plan *pl)
{
    free(pl->prod);
    free(pl->order);
    free(pl->start);
    free(pl->nsingle);
    free(pl->coef);
    free(pl->fa);
    free(pl->fb);
    free(pl->src);
    free(pl->nquad);
    free(pl->npair);
    free(pl->vslot);
    poly_fast_free(pl->fast);
    memset(pl, 0, sizeof *pl);
}

/* Grows array ptr to count elements (returns -1 from the caller when out of memory). */
#define GROW(ptr, count)                                                                   \
    do {                                                                                   \
        void *grown_ = realloc((ptr), (size_t)(count) * sizeof *(ptr));                    \
        if (!grown_)                                                                       \
            return -1;                                                                     \
        (ptr) = grown_;                                                                    \
    } while (0)

/* Appends a slot holding monomial e computed as slot a * slot b. */
static int append_slot(poly_mono *m, int nin, const int *e, int a, int b)
{
    if (m->nslots + 1 > m->cap) {
        int nc = m->cap ? m->cap * 2 : 32;
        GROW(m->exps, (size_t)nc * (size_t)nin);
        GROW(m->a, nc);
        GROW(m->b, nc);
        GROW(m->depth, nc);
        GROW(m->used_by, nc);
        m->cap = nc;
    }
    if (index_hash_add(&m->index, index_hash_bytes(e, (size_t)nin * sizeof(int)), m->nslots) != 0)
        return -1;
    int k = m->nslots++;
    memcpy(m->exps + (size_t)k * (size_t)nin, e, (size_t)nin * sizeof(int));
    m->used_by[k] = 0;
    m->a[k] = a;
    m->b[k] = b;
    m->depth[k] = a < 0 ? 0 : 1 + (m->depth[a] > m->depth[b] ? m->depth[a] : m->depth[b]);
    return k;
}

/* Slot 0 the constant, slots 1..nin the scaled inputs. */
int poly_mono_init(poly_mono *m, int nin)
{
    int *e = calloc((size_t)nin, sizeof(int));
    if (!e)
        return -1;
    int ok = append_slot(m, nin, e, -1, -1) == 0;
    for (int i = 0; ok && i < nin; i++) {
        e[i] = 1;
        ok = append_slot(m, nin, e, -1, -1) == 1 + i;
        e[i] = 0;
    }
    free(e);
    return ok ? 0 : -1;
}

struct slot_key {
    const poly_mono *m;
    int nin;
    const int *e;
};

static int same_slot(const void *ctx, int k)
{
    const struct slot_key *q = ctx;
    return memcmp(q->m->exps + (size_t)k * (size_t)q->nin, q->e, (size_t)q->nin * sizeof(int)) == 0;
}

int poly_mono_find(const poly_mono *m, int nin, const int *e)
{
    struct slot_key q = {m, nin, e};
    return index_hash_find(&m->index, index_hash_bytes(e, (size_t)nin * sizeof(int)), same_slot, &q);
}

/* The slot holding monomial e, created (with the slots it is built from) if missing. */
int poly_mono_ensure(poly_mono *m, int nin, const int *e)
{
    int k = poly_mono_find(m, nin, e);
    if (k >= 0)
        return k;
    int last = -1, nz = 0;
    for (int i = 0; i < nin; i++)
        if (e[i]) {
            last = i;
            nz++;
        }
    int f[64];
    int *g = nin <= 64 ? f : malloc((size_t)nin * sizeof(int));
    if (!g)
        return -1;
    memcpy(g, e, (size_t)nin * sizeof(int));
    int a, b;
    if (nz == 1) { /* s_i^k = s_i^(k-1) * s_i; k >= 2 here since slots 1..nin hold s_i */
        g[last] -= 1;
        a = poly_mono_ensure(m, nin, g);
        memset(g, 0, (size_t)nin * sizeof(int));
        g[last] = 1;
        b = poly_mono_ensure(m, nin, g);
    } else { /* (e without its last factor) * s_last^e_last */
        g[last] = 0;
        a = poly_mono_ensure(m, nin, g);
        memset(g, 0, (size_t)nin * sizeof(int));
        g[last] = e[last];
        b = poly_mono_ensure(m, nin, g);
    }
    if (g != f)
        free(g);
    if (a < 0 || b < 0)
        return -1;
    return append_slot(m, nin, e, a, b);
}

/* Appends a term (exponents e, or none for derivative sums) to a sum. */
int poly_terms_push(poly_out_terms *ot, int nin, const int *e, double coef, int slot)
{
    if (ot->nterms + 1 > ot->cap) {
        int nc = ot->cap ? ot->cap * 2 : 16;
        if (e)
            GROW(ot->exps, (size_t)nc * (size_t)nin);
        GROW(ot->coef, nc);
        GROW(ot->slot, nc);
        ot->cap = nc;
    }
    int t = ot->nterms++;
    if (e)
        memcpy(ot->exps + (size_t)t * (size_t)nin, e, (size_t)nin * sizeof(int));
    ot->coef[t] = coef;
    ot->slot[t] = slot;
    return 0;
}

/* Scratch of poly_plan_build, over all outputs. */
typedef struct {
    int *cidx; /* per slot: its value number, -1 when fused (never stored) */
    int *fz;   /* an output's fused terms: (term, first factor, shared factor) each, then
                  from fz + 3 (nt + 1) on the order they are grouped in */
    int *cnt;  /* per value: how many of the output's fused terms have it as a factor */
    char *done; /* per fused term: grouped already */
} plan_work;

static void plan_work_free(plan_work *w)
{
    free(w->cidx);
    free(w->fz);
    free(w->cnt);
    free(w->done);
}

/* The plan's arrays and the scratch for ns slots, nout outputs and nt terms. */
static int plan_alloc(poly_plan *n, plan_work *w, int ns, int nout, int nt)
{
    n->prod = malloc(2 * (size_t)ns * sizeof(int));
    n->order = malloc((size_t)ns * sizeof(int));
    n->start = malloc((size_t)(nout + 1) * sizeof(int));
    n->nsingle = malloc((size_t)nout * sizeof(int));
    n->coef = malloc((size_t)(nt + 1) * sizeof(double));
    n->fa = malloc((size_t)(nt + 1) * sizeof(int));
    n->fb = malloc((size_t)(nt + 1) * sizeof(int));
    n->src = malloc((size_t)(nt + 1) * sizeof(int));
    n->nquad = malloc((size_t)(nout + 1) * sizeof(int));
    n->npair = malloc((size_t)(nout + 1) * sizeof(int));
    n->vslot = malloc((size_t)(ns + 1) * sizeof(int));
    w->cidx = malloc((size_t)ns * sizeof(int));
    w->fz = malloc(4 * (size_t)(nt + 1) * sizeof(int));
    w->cnt = calloc((size_t)ns + 1, sizeof(int));
    w->done = calloc((size_t)nt + 1, 1);
    return n->prod && n->order && n->start && n->nsingle && n->coef && n->fa && n->fb &&
                   n->src && n->nquad && n->npair && n->vslot && w->cidx && w->fz && w->cnt &&
                   w->done
               ? 0
               : -1;
}

/* The values a ray computes: the product slots in depth order (n->order), and of them
 * the ones kept (n->prod, n->vslot, their numbers in cidx); a product that one term
 * alone uses and nothing is built from is fused into that term (cidx -1). */
static int plan_values(poly_plan *n, int *cidx, const poly_mono *m, int nin, int nout,
                       const poly_out_terms *sums)
{
    const int ns = m->nslots;
    int *uses = calloc((size_t)ns, sizeof(int));   /* terms using the slot */
    int *factor = calloc((size_t)ns, sizeof(int)); /* slots built from it */
    if (!uses || !factor) {
        free(uses);
        free(factor);
        return -1;
    }
    int maxd = 0, no = 0;
    for (int k = 1 + nin; k < ns; k++)
        if (m->depth[k] > maxd)
            maxd = m->depth[k];
    for (int d = 1; d <= maxd; d++)
        for (int k = 1 + nin; k < ns; k++)
            if (m->depth[k] == d)
                n->order[no++] = k;
    for (int o = 0; o < nout; o++)
        for (int t = 0; t < sums[o].nterms; t++)
            uses[sums[o].slot[t]]++;
    for (int k = 1 + nin; k < ns; k++) {
        factor[m->a[k]]++;
        factor[m->b[k]]++;
    }
    for (int k = 0; k <= nin && k < ns; k++)
        cidx[k] = n->vslot[k] = k;
    n->nvals = 1 + nin;
    for (int j = 0; j < no; j++) {
        int k = n->order[j];
        cidx[k] = -1;
        if (uses[k] == 1 && factor[k] == 0)
            continue; /* fused into its one term */
        /* factors come first in depth order, and factors are always kept */
        n->prod[2 * n->nprod] = cidx[m->a[k]];
        n->prod[2 * n->nprod + 1] = cidx[m->b[k]];
        n->nprod++;
        n->vslot[n->nvals] = k;
        cidx[k] = n->nvals++;
    }
    free(uses);
    free(factor);
    return 0;
}

/* Sorts an output's nf fused terms (fz) by their shared factor, the one more of them
 * have (the table's second factor on a tie): groups in the order of their first term,
 * terms in add order. Returns the grouped order (indices into fz). */
static const int *plan_group(plan_work *w, int nf, int nt)
{
    int *fz = w->fz, *cnt = w->cnt;
    for (int f = 0; f < nf; f++) {
        cnt[fz[3 * f + 1]]++;
        cnt[fz[3 * f + 2]]++;
    }
    for (int f = 0; f < nf; f++)
        if (cnt[fz[3 * f + 1]] > cnt[fz[3 * f + 2]]) {
            int a = fz[3 * f + 1];
            fz[3 * f + 1] = fz[3 * f + 2];
            fz[3 * f + 2] = a;
        }
    for (int f = 0; f < nf; f++)
        cnt[fz[3 * f + 1]] = cnt[fz[3 * f + 2]] = 0;
    int *gr = fz + 3 * (nt + 1), ngr = 0;
    for (int f = 0; f < nf; f++) {
        if (w->done[f])
            continue;
        for (int g = f; g < nf; g++)
            if (!w->done[g] && fz[3 * g + 2] == fz[3 * f + 2]) {
                gr[ngr++] = g;
                w->done[g] = 1;
            }
    }
    memset(w->done, 0, (size_t)nf);
    return gr;
}

/* Output o's planned terms from planned term q on (returns the next q): its single terms
 * in add order, then its fused ones, the quads of every group, then the pairs, then the
 * lone terms. */
static int plan_output(poly_plan *n, plan_work *w, const poly_mono *m,
                       const poly_out_terms *ot, int o, int q, int nt)
{
    const int *cidx = w->cidx;
    int *fz = w->fz, nf = 0;
    n->start[o] = q;
    for (int t = 0; t < ot->nterms; t++) {
        const int k = ot->slot[t];
        if (cidx[k] >= 0) {
            n->coef[q] = ot->coef[t];
            n->fa[q] = cidx[k];
            n->fb[q] = 0;
            n->src[q++] = t;
        } else {
            fz[3 * nf] = t;
            fz[3 * nf + 1] = cidx[m->a[k]];
            fz[3 * nf + 2] = cidx[m->b[k]];
            nf++;
        }
    }
    n->nsingle[o] = q - n->start[o];
    const int *gr = plan_group(w, nf, nt);
    n->nquad[o] = n->npair[o] = 0;
    for (int pass = 4; pass >= 1; pass /= 2)
        for (int i = 0, j; i < nf; i = j) {
            for (j = i; j < nf && fz[3 * gr[j] + 2] == fz[3 * gr[i] + 2]; j++)
                ; /* gr[i .. j - 1]: one group */
            const int nq = (j - i) / 4 * 4, np = (j - i - nq) / 2 * 2;
            const int from = pass == 4 ? i : pass == 2 ? i + nq : i + nq + np;
            const int to = pass == 4 ? i + nq : pass == 2 ? i + nq + np : j;
            n->nquad[o] += pass == 4 ? nq / 4 : 0;
            n->npair[o] += pass == 2 ? np / 2 : 0;
            for (int g = from; g < to; g++) {
                const int f = gr[g], t = fz[3 * f];
                n->coef[q] = ot->coef[t];
                n->fa[q] = fz[3 * f + 1];
                n->fb[q] = fz[3 * f + 2];
                n->src[q++] = t;
            }
        }
    return q;
}

/* The plan of poly_impl.h for nout sums over table m: which products are kept (and their
 * compact numbers), each output's single terms, then its fused ones. */
int poly_plan_build(poly_plan *pl, const poly_mono *m, int nin, int nout,
                    const poly_out_terms *sums)
{
    int nt = 0;
    for (int o = 0; o < nout; o++)
        nt += sums[o].nterms;
    poly_plan n = {0};
    plan_work w = {0};
    if (plan_alloc(&n, &w, m->nslots, nout, nt) != 0 ||
        plan_values(&n, w.cidx, m, nin, nout, sums) != 0) {
        plan_work_free(&w);
        poly_plan_free(&n);
        return -1;
    }
    n.nout = nout;
    int q = 0;
    for (int o = 0; o < nout; o++)
        q = plan_output(&n, &w, m, &sums[o], o, q, nt);
    n.start[nout] = q;
    n.fast = poly_fast_build(nin, nout, sums);
    plan_work_free(&w);
    poly_plan_free(pl);
    *pl = n;
    return 0;
}

/* The kept value of dp whose monomial with value u's makes e (u a kept value, 0 the
 * constant), or -1; fa its number. */
static int split_over(const poly_plan *dp, const poly_mono *dm, const int *val, int nin,
                      const int *e, int u, int *g)
{
    const int *eu = dm->exps + (size_t)dp->vslot[u] * (size_t)nin;
    for (int i = 0; i < nin; i++)
        if ((g[i] = e[i] - eu[i]) < 0)
            return -1;
    const int k = poly_mono_find(dm, nin, g);
    return k >= 0 ? val[k] : -1;
}

/* The values of nout sums (exponents in sums) as items over the derivative plan dp's
 * kept values (table dm): each term c s^e as c v[a] v[b] with a, b kept and their
 * monomials adding up to e, v[b] preferably an input (e - 1_i is often kept: its
 * derivative term). Then the values cost no products of their own: the batch Jacobian
 * runs vp after dp on the same values. Grouped by b as poly_plan_build groups (quads,
 * pairs, lone terms; no single terms). -1 when a term has no such split or out of
 * memory (vp then has start NULL: not built). */
int poly_plan_values_over(poly_plan *vp, const poly_plan *dp, const poly_mono *dm, int nin,
                          int nout, const poly_out_terms *sums)
{
    poly_plan_free(vp);
    int nt = 0, g[POLY_MAX_INPUTS];
    for (int o = 0; o < nout; o++)
        nt += sums[o].nterms;
    poly_plan n = {0};
    plan_work w = {0};
    int *val = malloc(((size_t)dm->nslots + 1) * sizeof(int));
    if (!val || plan_alloc(&n, &w, dm->nslots + 1, nout, nt) != 0 || nin > POLY_MAX_INPUTS) {
        free(val);
        plan_work_free(&w);
        poly_plan_free(&n);
        return -1;
    }
    for (int k = 0; k < dm->nslots; k++)
        val[k] = -1;
    for (int k = 0; k < dp->nvals; k++)
        val[dp->vslot[k]] = k;
    n.nvals = dp->nvals;
    n.nout = nout;
    int q = 0, ok = 1;
    for (int o = 0; o < nout && ok; o++) {
        const poly_out_terms *ot = &sums[o];
        int nf = 0;
        n.start[o] = q;
        for (int t = 0; t < ot->nterms && ok; t++) {
            const int *e = ot->exps + (size_t)t * (size_t)nin;
            int a = -1, b = 0;
            for (int i = 0; i < nin && a < 0; i++)
                if (e[i] || i == nin - 1)
                    a = split_over(dp, dm, val, nin, e, b = e[i] ? 1 + i : 0, g);
            for (int u = 1 + nin; u < dp->nvals && a < 0; u++)
                a = split_over(dp, dm, val, nin, e, b = u, g);
            ok = a >= 0;
            w.fz[3 * nf] = t;
            w.fz[3 * nf + 1] = a;
            w.fz[3 * nf + 2] = b;
            nf++;
        }
        n.nsingle[o] = 0;
        n.nquad[o] = n.npair[o] = 0;
        /* groups by b in the order of their first term (plan_output's passes) */
        int *gr = w.fz + 3 * (nt + 1), ngr = 0;
        for (int f = 0; f < nf; f++)
            if (!w.done[f])
                for (int h = f; h < nf; h++)
                    if (!w.done[h] && w.fz[3 * h + 2] == w.fz[3 * f + 2]) {
                        gr[ngr++] = h;
                        w.done[h] = 1;
                    }
        memset(w.done, 0, (size_t)nf);
        for (int pass = 4; pass >= 1 && ok; pass /= 2)
            for (int i = 0, j; i < nf; i = j) {
                for (j = i; j < nf && w.fz[3 * gr[j] + 2] == w.fz[3 * gr[i] + 2]; j++)
                    ;
                const int nq = (j - i) / 4 * 4, np = (j - i - nq) / 2 * 2;
                const int from = pass == 4 ? i : pass == 2 ? i + nq : i + nq + np;
                const int to = pass == 4 ? i + nq : pass == 2 ? i + nq + np : j;
                n.nquad[o] += pass == 4 ? nq / 4 : 0;
                n.npair[o] += pass == 2 ? np / 2 : 0;
                for (int h = from; h < to; h++) {
                    const int f = gr[h];
                    n.coef[q] = ot->coef[w.fz[3 * f]];
                    n.fa[q] = w.fz[3 * f + 1];
                    n.fb[q] = w.fz[3 * f + 2];
                    n.src[q++] = w.fz[3 * f];
                }
            }
    }
    n.start[nout] = q;
    free(val);
    plan_work_free(&w);
    if (!ok) {
        poly_plan_free(&n);
        return -1;
    }
    *vp = n;
    return 0;
}
