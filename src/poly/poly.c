/* Polynomial systems: construction, metadata and the evaluation plan (see poly_impl.h). */
#include "poly/poly_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static char *dupstr(const char *s)
{
    size_t n = strlen(s ? s : "") + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s ? s : "", n);
    return d;
}

/* A copy on one line, without surrounding blanks: what the file format can hold and
 * give back unchanged. */
static char *one_line(const char *s)
{
    char *d = dupstr(s);
    if (!d)
        return NULL;
    for (char *c = d; *c; c++)
        if (*c == '\n' || *c == '\r' || *c == '\t')
            *c = ' ';
    char *b = d;
    while (*b == ' ')
        b++;
    size_t n = strlen(b);
    while (n > 0 && b[n - 1] == ' ')
        n--;
    memmove(d, b, n);
    d[n] = '\0';
    return d;
}

static int valid_name(const char *s)
{
    if (!s || !*s)
        return 0;
    for (const char *p = s; *p; p++)
        if (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == '#')
            return 0;
    return 1;
}

static int name_index(char *const *names, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], name) == 0)
            return i;
    return -1;
}

poly_system *poly_new(const char *lens_name, int ninputs, const char *const *inputs,
                      int noutputs, const char *const *outputs)
{
    if (ninputs < 1 || noutputs < 1 || ninputs > POLY_MAX_INPUTS ||
        noutputs > POLY_MAX_OUTPUTS || !inputs || !outputs)
        return NULL;
    for (int i = 0; i < ninputs; i++)
        if (!valid_name(inputs[i]) || name_index((char *const *)inputs, i, inputs[i]) >= 0)
            return NULL;
    for (int o = 0; o < noutputs; o++)
        if (!valid_name(outputs[o]) || name_index((char *const *)outputs, o, outputs[o]) >= 0)
            return NULL;
    poly_system *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->nin = ninputs;
    s->nout = noutputs;
    s->lens_name = one_line(lens_name);
    s->lens_path = dupstr("");
    s->inputs = calloc((size_t)ninputs, sizeof *s->inputs);
    s->outputs = calloc((size_t)noutputs, sizeof *s->outputs);
    s->offset = calloc((size_t)ninputs, sizeof(double));
    s->scale = calloc((size_t)ninputs, sizeof(double));
    s->lo = calloc((size_t)ninputs, sizeof(double));
    s->hi = calloc((size_t)ninputs, sizeof(double));
    s->xform = calloc((size_t)ninputs, sizeof(int)); /* identity (poly_frame.c) */
    if (!s->lens_name || !s->lens_path || !s->inputs || !s->outputs || !s->offset ||
        !s->scale || !s->lo || !s->hi || !s->xform) {
        poly_free(s);
        return NULL;
    }
    for (int i = 0; i < ninputs; i++) {
        s->inputs[i] = dupstr(inputs[i]);
        if (!s->inputs[i]) {
            poly_free(s);
            return NULL;
        }
        s->scale[i] = 1;
        s->lo[i] = -INFINITY;
        s->hi[i] = INFINITY;
    }
    for (int o = 0; o < noutputs; o++) {
        s->outputs[o] = dupstr(outputs[o]);
        if (!s->outputs[o]) {
            poly_free(s);
            return NULL;
        }
    }
    s->ix = name_index(s->inputs, ninputs, "x");
    s->iy = name_index(s->inputs, ninputs, "y");
    s->iu = name_index(s->inputs, ninputs, "u");
    s->iv = name_index(s->inputs, ninputs, "v");
    return s;
}

static void free_terms(poly_out_terms *t, int n)
{
    if (t)
        for (int o = 0; o < n; o++) {
            free(t[o].exps);
            free(t[o].coef);
            free(t[o].slot);
        }
    free(t);
}

static void free_mono(poly_mono *m)
{
    free(m->exps);
    free(m->a);
    free(m->b);
    free(m->depth);
    free(m->used_by);
    index_hash_free(&m->index);
}

static void free_plan(poly_plan *pl)
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
    memset(pl, 0, sizeof *pl);
}

static void free_part(poly_part *p, int nin, int nout)
{
    free_terms(p->out, nout);
    free_terms(p->dout, nout * nin);
    free_mono(&p->mono);
    free_mono(&p->dmono);
    free_plan(&p->plan);
    free_plan(&p->dplan);
}

void poly_free(poly_system *s)
{
    if (!s)
        return;
    for (int p = 0; p < s->nparts; p++)
        free_part(&s->parts[p], s->nin, s->nout);
    free(s->parts);
    if (s->inputs)
        for (int i = 0; i < s->nin; i++)
            free(s->inputs[i]);
    if (s->outputs)
        for (int o = 0; o < s->nout; o++)
            free(s->outputs[o]);
    for (int m = 0; m < s->nmeta; m++) {
        free(s->meta_key[m]);
        free(s->meta_val[m]);
    }
    free(s->meta_key);
    free(s->meta_val);
    free(s->inputs);
    free(s->outputs);
    free(s->offset);
    free(s->scale);
    free(s->lo);
    free(s->hi);
    free(s->xform);
    free(s->pair);
    free(s->plain);
    poly_free(s->vframe);
    poly_free(s->vplain);
    free(s->circles);
    free(s->lens_name);
    free(s->lens_path);
    free(s);
}

const char *poly_lens_name(const poly_system *s) { return s->lens_name; }
const char *poly_lens_path(const poly_system *s) { return s->lens_path; }
int poly_ninputs(const poly_system *s) { return s->nin; }
int poly_noutputs(const poly_system *s) { return s->nout; }
const char *poly_input_name(const poly_system *s, int i) { return s->inputs[i]; }
const char *poly_output_name(const poly_system *s, int o) { return s->outputs[o]; }
int poly_input_index(const poly_system *s, const char *name)
{
    return name_index(s->inputs, s->nin, name);
}
int poly_output_index(const poly_system *s, const char *name)
{
    return name_index(s->outputs, s->nout, name);
}

void poly_set_lens_path(poly_system *s, const char *path)
{
    char *d = one_line(path);
    if (!d)
        return;
    free(s->lens_path);
    s->lens_path = d;
}

void poly_set_scaling(poly_system *s, int i, double offset, double scale)
{
    /* A zero or non-finite scale would make every monomial non-finite: keep the old one. */
    if (i < 0 || i >= s->nin || !isfinite(offset) || !isfinite(scale) || scale == 0)
        return;
    s->offset[i] = offset;
    s->scale[i] = scale;
    poly_frame_on_change(s);
}

void poly_set_domain(poly_system *s, int i, double lo, double hi)
{
    if (i < 0 || i >= s->nin || isnan(lo) || isnan(hi) || lo > hi)
        return;
    s->lo[i] = lo;
    s->hi[i] = hi;
}

/* ---- parts, monomial tables and plans ---- */

/* Appends a slot holding monomial e computed as slot a * slot b. */
static int append_slot(poly_mono *m, int nin, const int *e, int a, int b)
{
    if (m->nslots + 1 > m->cap) {
        int nc = m->cap ? m->cap * 2 : 32;
        int *ne = realloc(m->exps, (size_t)nc * (size_t)nin * sizeof(int));
        if (!ne)
            return -1;
        m->exps = ne;
        int *na = realloc(m->a, (size_t)nc * sizeof(int));
        if (!na)
            return -1;
        m->a = na;
        int *nb = realloc(m->b, (size_t)nc * sizeof(int));
        if (!nb)
            return -1;
        m->b = nb;
        int *nd = realloc(m->depth, (size_t)nc * sizeof(int));
        if (!nd)
            return -1;
        m->depth = nd;
        uint64_t *nu = realloc(m->used_by, (size_t)nc * sizeof(uint64_t));
        if (!nu)
            return -1;
        m->used_by = nu;
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
static int init_mono(poly_mono *m, int nin)
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

static int find_slot(const poly_mono *m, int nin, const int *e)
{
    struct slot_key q = {m, nin, e};
    return index_hash_find(&m->index, index_hash_bytes(e, (size_t)nin * sizeof(int)), same_slot, &q);
}

/* The slot holding monomial e, created (with the slots it is built from) if missing. */
static int ensure_slot(poly_mono *m, int nin, const int *e)
{
    int k = find_slot(m, nin, e);
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
        a = ensure_slot(m, nin, g);
        memset(g, 0, (size_t)nin * sizeof(int));
        g[last] = 1;
        b = ensure_slot(m, nin, g);
    } else { /* (e without its last factor) * s_last^e_last */
        g[last] = 0;
        a = ensure_slot(m, nin, g);
        memset(g, 0, (size_t)nin * sizeof(int));
        g[last] = e[last];
        b = ensure_slot(m, nin, g);
    }
    if (g != f)
        free(g);
    if (a < 0 || b < 0)
        return -1;
    return append_slot(m, nin, e, a, b);
}

/* Appends a term (exponents e, or none for derivative sums) to a sum. */
static int push_term(poly_out_terms *ot, int nin, const int *e, double coef, int slot)
{
    if (ot->nterms + 1 > ot->cap) {
        int nc = ot->cap ? ot->cap * 2 : 16;
        if (e) {
            int *ne = realloc(ot->exps, (size_t)nc * (size_t)nin * sizeof(int));
            if (!ne)
                return -1;
            ot->exps = ne;
        }
        double *nco = realloc(ot->coef, (size_t)nc * sizeof(double));
        if (!nco)
            return -1;
        ot->coef = nco;
        int *ns = realloc(ot->slot, (size_t)nc * sizeof(int));
        if (!ns)
            return -1;
        ot->slot = ns;
        ot->cap = nc;
    }
    int t = ot->nterms++;
    if (e)
        memcpy(ot->exps + (size_t)t * (size_t)nin, e, (size_t)nin * sizeof(int));
    ot->coef[t] = coef;
    ot->slot[t] = slot;
    return 0;
}

/* The plan of poly_impl.h for nout sums over table m: which products are kept (and their
 * compact numbers), each output's single terms, then its fused ones. */
static int build_plan(poly_plan *pl, const poly_mono *m, int nin, int nout,
                      const poly_out_terms *sums)
{
    const int ns = m->nslots;
    int nt = 0;
    for (int o = 0; o < nout; o++)
        nt += sums[o].nterms;
    poly_plan n = {0};
    int *uses = calloc((size_t)ns, sizeof(int));   /* terms using the slot */
    int *factor = calloc((size_t)ns, sizeof(int)); /* slots built from it */
    int *cidx = malloc((size_t)ns * sizeof(int));  /* compact number, -1 if not kept */
    n.prod = malloc(2 * (size_t)ns * sizeof(int));
    n.order = malloc((size_t)ns * sizeof(int));
    n.start = malloc((size_t)(nout + 1) * sizeof(int));
    n.nsingle = malloc((size_t)nout * sizeof(int));
    n.coef = malloc((size_t)(nt + 1) * sizeof(double));
    n.fa = malloc((size_t)(nt + 1) * sizeof(int));
    n.fb = malloc((size_t)(nt + 1) * sizeof(int));
    n.src = malloc((size_t)(nt + 1) * sizeof(int));
    n.nquad = malloc((size_t)(nout + 1) * sizeof(int));
    n.npair = malloc((size_t)(nout + 1) * sizeof(int));
    n.vslot = malloc((size_t)(ns + 1) * sizeof(int));
    int *fz = malloc(4 * (size_t)(nt + 1) * sizeof(int)); /* fused terms: t, a, b; order */
    int *cnt = calloc((size_t)ns + 1, sizeof(int));       /* per value: fused factors */
    char *done = calloc((size_t)nt + 1, 1);                /* fused terms grouped */
    if (!uses || !factor || !cidx || !n.prod || !n.order || !n.start || !n.nsingle ||
        !n.coef || !n.fa || !n.fb || !n.src || !n.nquad || !n.npair || !n.vslot || !fz ||
        !cnt || !done) {
        free(uses);
        free(factor);
        free(cidx);
        free(fz);
        free(cnt);
        free(done);
        free_plan(&n);
        return -1;
    }
    int maxd = 0, no = 0;
    for (int k = 1 + nin; k < ns; k++)
        if (m->depth[k] > maxd)
            maxd = m->depth[k];
    for (int d = 1; d <= maxd; d++)
        for (int k = 1 + nin; k < ns; k++)
            if (m->depth[k] == d)
                n.order[no++] = k;
    for (int o = 0; o < nout; o++)
        for (int t = 0; t < sums[o].nterms; t++)
            uses[sums[o].slot[t]]++;
    for (int k = 1 + nin; k < ns; k++) {
        factor[m->a[k]]++;
        factor[m->b[k]]++;
    }
    for (int k = 0; k <= nin && k < ns; k++)
        cidx[k] = n.vslot[k] = k;
    n.nvals = 1 + nin;
    for (int j = 0; j < no; j++) {
        int k = n.order[j];
        cidx[k] = -1;
        if (uses[k] == 1 && factor[k] == 0)
            continue; /* fused into its one term */
        /* factors come first in depth order, and factors are always kept */
        n.prod[2 * n.nprod] = cidx[m->a[k]];
        n.prod[2 * n.nprod + 1] = cidx[m->b[k]];
        n.nprod++;
        n.vslot[n.nvals] = k;
        cidx[k] = n.nvals++;
    }
    n.nout = nout;
    int q = 0;
    for (int o = 0; o < nout; o++) {
        const poly_out_terms *ot = &sums[o];
        n.start[o] = q;
        for (int t = 0; t < ot->nterms; t++)
            if (cidx[ot->slot[t]] >= 0) {
                n.coef[q] = ot->coef[t];
                n.fa[q] = cidx[ot->slot[t]];
                n.fb[q] = 0;
                n.src[q++] = t;
            }
        n.nsingle[o] = q - n.start[o];
        /* the fused terms and their factors; the shared factor: the one more of them
         * have (the table's second factor on a tie) */
        int nf = 0;
        for (int t = 0; t < ot->nterms; t++)
            if (cidx[ot->slot[t]] < 0) {
                int k = ot->slot[t];
                fz[3 * nf] = t;
                fz[3 * nf + 1] = cidx[m->a[k]];
                fz[3 * nf + 2] = cidx[m->b[k]];
                cnt[fz[3 * nf + 1]]++;
                cnt[fz[3 * nf + 2]]++;
                nf++;
            }
        for (int f = 0; f < nf; f++)
            if (cnt[fz[3 * f + 1]] > cnt[fz[3 * f + 2]]) {
                int a = fz[3 * f + 1];
                fz[3 * f + 1] = fz[3 * f + 2];
                fz[3 * f + 2] = a;
            }
        for (int f = 0; f < nf; f++)
            cnt[fz[3 * f + 1]] = cnt[fz[3 * f + 2]] = 0;
        /* gr: the fused terms group by group (groups by first term, terms in add order) */
        int *gr = fz + 3 * (nt + 1), ngr = 0;
        for (int f = 0; f < nf; f++) {
            if (done[f])
                continue;
            for (int g = f; g < nf; g++)
                if (!done[g] && fz[3 * g + 2] == fz[3 * f + 2]) {
                    gr[ngr++] = g;
                    done[g] = 1;
                }
        }
        memset(done, 0, (size_t)nf);
        /* the quads of every group, then the pairs, then the lone terms */
        n.nquad[o] = n.npair[o] = 0;
        for (int pass = 4; pass >= 1; pass /= 2)
            for (int i = 0, j; i < ngr; i = j) {
                for (j = i; j < ngr && fz[3 * gr[j] + 2] == fz[3 * gr[i] + 2]; j++)
                    ; /* gr[i .. j - 1]: one group */
                const int nq = (j - i) / 4 * 4, np = (j - i - nq) / 2 * 2;
                const int from = pass == 4 ? i : pass == 2 ? i + nq : i + nq + np;
                const int to = pass == 4 ? i + nq : pass == 2 ? i + nq + np : j;
                n.nquad[o] += pass == 4 ? nq / 4 : 0;
                n.npair[o] += pass == 2 ? np / 2 : 0;
                for (int g = from; g < to; g++) {
                    const int f = gr[g], t = fz[3 * f];
                    n.coef[q] = ot->coef[t];
                    n.fa[q] = fz[3 * f + 1];
                    n.fb[q] = fz[3 * f + 2];
                    n.src[q++] = t;
                }
            }
    }
    n.start[nout] = q;
    free(uses);
    free(factor);
    free(cidx);
    free(fz);
    free(cnt);
    free(done);
    free_plan(pl);
    *pl = n;
    return 0;
}

int poly_add_part(poly_system *s, double rmin, double rmax)
{
    if (!(rmin >= 0) || !(rmax > rmin) || isinf(rmin))
        return -1;
    if (rmin > 0 && (s->ix < 0 || s->iy < 0))
        return -1;
    if (s->nparts >= POLY_MAX_PARTS)
        return -1;
    for (int q = 0; q < s->nparts; q++)
        if (rmin < s->parts[q].rmax && s->parts[q].rmin < rmax)
            return -1;
    poly_part *np = realloc(s->parts, (size_t)(s->nparts + 1) * sizeof *np);
    if (!np)
        return -1;
    s->parts = np;
    poly_part *p = &s->parts[s->nparts];
    memset(p, 0, sizeof *p);
    p->rmin = rmin;
    p->rmax = rmax;
    p->out = calloc((size_t)s->nout, sizeof *p->out);
    p->dout = calloc((size_t)s->nout * (size_t)s->nin, sizeof *p->dout);
    if (!p->out || !p->dout || init_mono(&p->mono, s->nin) != 0 ||
        init_mono(&p->dmono, s->nin) != 0 ||
        build_plan(&p->plan, &p->mono, s->nin, s->nout, p->out) != 0 ||
        build_plan(&p->dplan, &p->dmono, s->nin, s->nout * s->nin, p->dout) != 0) {
        free_part(p, s->nin, s->nout);
        return -1;
    }
    s->nparts++;
    if (!s->bulk)
        poly_frame_on_change(s);
    return s->nparts - 1;
}

int poly_add_term(poly_system *s, int part, int output, const int *exps, double coef)
{
    if (part < 0 || part >= s->nparts || output < 0 || output >= s->nout || !exps ||
        !isfinite(coef))
        return -1;
    int deg = 0;
    for (int i = 0; i < s->nin; i++) {
        if (exps[i] < 0 || exps[i] > POLY_MAX_DEGREE)
            return -1;
        deg += exps[i];
    }
    if (deg > POLY_MAX_DEGREE)
        return -1;
    poly_part *p = &s->parts[part];
    poly_out_terms *ot = &p->out[output];
    const int nin = s->nin;
    size_t n = (size_t)nin;
    const uint64_t bit = (uint64_t)1 << output;
    int slot = find_slot(&p->mono, nin, exps);
    if (slot >= 0 && (p->mono.used_by[slot] & bit))
        return -1; /* a monomial the output already has */
    if (slot < 0)
        slot = ensure_slot(&p->mono, nin, exps);
    if (slot < 0 || push_term(ot, nin, exps, coef, slot) != 0)
        return -1;
    /* d/ds_i (c s^e) = (c e_i) s^(e - 1_i); c e_i is exact for the small e_i allowed
     * unless it overflows, which the Jacobian then reports as inf */
    int g[64];
    int *e = nin <= 64 ? g : malloc(n * sizeof(int));
    int ok = e != NULL;
    int added[64] = {0};
    for (int i = 0; ok && i < nin; i++) {
        if (exps[i] == 0)
            continue;
        memcpy(e, exps, n * sizeof(int));
        e[i]--;
        int ds = ensure_slot(&p->dmono, nin, e);
        ok = ds >= 0 && push_term(&p->dout[output * nin + i], nin, NULL, coef * exps[i], ds) == 0;
        if (ok && i < 64)
            added[i] = 1;
    }
    if (e != g)
        free(e);
    if (ok && s->bulk) {
        p->mono.used_by[slot] |= bit;
        return 0;
    }
    /* Replanned on every term: cheap at the sizes fits have, and the system is ready
     * to evaluate at any point of building. */
    if (!ok || build_plan(&p->plan, &p->mono, nin, s->nout, p->out) != 0 ||
        build_plan(&p->dplan, &p->dmono, nin, s->nout * nin, p->dout) != 0) {
        ot->nterms--;
        for (int i = 0; i < nin && i < 64; i++)
            if (added[i])
                p->dout[output * nin + i].nterms--;
        build_plan(&p->plan, &p->mono, nin, s->nout, p->out);
        build_plan(&p->dplan, &p->dmono, nin, s->nout * nin, p->dout);
        return -1;
    }
    p->mono.used_by[slot] |= bit;
    poly_frame_on_term(s, part, output, exps, coef);
    return 0;
}

void poly_bulk_begin(poly_system *s)
{
    s->bulk = 1;
}

int poly_bulk_end(poly_system *s)
{
    s->bulk = 0;
    for (int q = 0; q < s->nparts; q++) {
        poly_part *p = &s->parts[q];
        if (build_plan(&p->plan, &p->mono, s->nin, s->nout, p->out) != 0 ||
            build_plan(&p->dplan, &p->dmono, s->nin, s->nout * s->nin, p->dout) != 0)
            return -1;
    }
    poly_frame_on_change(s);
    return 0;
}

int poly_add_pass_circle(poly_system *s, int a, int b, double radius)
{
    if (a < 0 || a >= s->nout || b < 0 || b >= s->nout || !(radius > 0) || isnan(radius))
        return -1;
    poly_circle *nc = realloc(s->circles, (size_t)(s->ncircles + 1) * sizeof *nc);
    if (!nc)
        return -1;
    s->circles = nc;
    s->circles[s->ncircles++] = (poly_circle){a, b, radius};
    return 0;
}

/* Values are kept on one line in the file: line breaks become spaces. */
void poly_set_meta(poly_system *s, const char *key, const char *value)
{
    if (!valid_name(key))
        return;
    for (int m = 0; m < s->nmeta; m++)
        if (strcmp(s->meta_key[m], key) == 0) {
            char *v = one_line(value);
            if (v) {
                free(s->meta_val[m]);
                s->meta_val[m] = v;
            }
            return;
        }
    poly_append_meta(s, key, value);
}

int poly_append_meta(poly_system *s, const char *key, const char *value)
{
    if (!valid_name(key))
        return -1;
    /* Room doubles at powers of two: n appends cost O(n). */
    int n = s->nmeta;
    if ((n & (n - 1)) == 0) {
        size_t cap = n ? 2 * (size_t)n : 1;
        char **nk = realloc(s->meta_key, cap * sizeof *nk);
        if (!nk)
            return -1;
        s->meta_key = nk;
        char **nv = realloc(s->meta_val, cap * sizeof *nv);
        if (!nv)
            return -1;
        s->meta_val = nv;
    }
    char *v = one_line(value), *k = dupstr(key);
    if (!v || !k) {
        free(v);
        free(k);
        return -1;
    }
    s->meta_key[n] = k;
    s->meta_val[n] = v;
    s->nmeta = n + 1;
    return 0;
}

const char *poly_get_meta(const poly_system *s, const char *key)
{
    for (int m = 0; m < s->nmeta; m++)
        if (strcmp(s->meta_key[m], key) == 0)
            return s->meta_val[m];
    return NULL;
}

int poly_nmeta(const poly_system *s) { return s->nmeta; }
const char *poly_meta_key(const poly_system *s, int i) { return s->meta_key[i]; }

/* ---- read access ---- */

int poly_nparts(const poly_system *s) { return s->nparts; }

void poly_part_range(const poly_system *s, int part, double *rmin, double *rmax)
{
    *rmin = s->parts[part].rmin;
    *rmax = s->parts[part].rmax;
}

int poly_nterms(const poly_system *s, int part, int output)
{
    return s->parts[part].out[output].nterms;
}

void poly_get_term(const poly_system *s, int part, int output, int t, int *exps, double *coef)
{
    const poly_out_terms *ot = &s->parts[part].out[output];
    if (exps)
        memcpy(exps, ot->exps + (size_t)t * (size_t)s->nin, (size_t)s->nin * sizeof(int));
    if (coef)
        *coef = ot->coef[t];
}

void poly_get_scaling(const poly_system *s, int i, double *offset, double *scale)
{
    *offset = s->offset[i];
    *scale = s->scale[i];
}

void poly_get_domain(const poly_system *s, int i, double *lo, double *hi)
{
    *lo = s->lo[i];
    *hi = s->hi[i];
}

int poly_npass_circles(const poly_system *s) { return s->ncircles; }

void poly_get_pass_circle(const poly_system *s, int c, int *a, int *b, double *radius)
{
    *a = s->circles[c].a;
    *b = s->circles[c].b;
    *radius = s->circles[c].radius;
}

int poly_max_degree(const poly_system *s, int output)
{
    int best = 0;
    for (int p = 0; p < s->nparts; p++) {
        const poly_out_terms *ot = &s->parts[p].out[output];
        for (int t = 0; t < ot->nterms; t++) {
            int d = 0;
            for (int i = 0; i < s->nin; i++)
                d += ot->exps[(size_t)t * (size_t)s->nin + (size_t)i];
            if (d > best)
                best = d;
        }
    }
    return best;
}

int poly_nmonomials(const poly_system *s, int part)
{
    return s->parts[part].mono.nslots - 1 - s->nin;
}

int poly_part_for_radius(const poly_system *s, double r)
{
    int best = 0;
    double bestd = INFINITY;
    for (int p = 0; p < s->nparts; p++) {
        const poly_part *q = &s->parts[p];
        if (r >= q->rmin && r < q->rmax)
            return p;
        double d = r < q->rmin ? q->rmin - r : r - q->rmax;
        if (d < bestd) {
            bestd = d;
            best = p;
        }
    }
    return best;
}

int poly_select_part(const poly_system *s, const double *in)
{
    if (s->nparts <= 1 || s->ix < 0 || s->iy < 0)
        return 0;
    double x = in[s->ix], y = in[s->iy];
    return poly_part_for_radius(s, sqrt(x * x + y * y));
}

int poly_part_of(const poly_system *s, const double *in) { return poly_select_part(s, in); }

int poly_in_domain(const poly_system *s, const double *in)
{
    for (int i = 0; i < s->nin; i++)
        if (!(in[i] >= s->lo[i] && in[i] <= s->hi[i]))
            return 0;
    return 1;
}
