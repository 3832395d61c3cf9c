/* Polynomial systems: construction, parts, terms and metadata (see poly_impl.h); the
 * monomial tables and evaluation plans the terms are kept in are poly_plan.c's. */
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
    s->inv_scale = calloc((size_t)ninputs, sizeof(double));
    s->off_scaled = calloc((size_t)ninputs, sizeof(double));
    s->lo = calloc((size_t)ninputs, sizeof(double));
    s->hi = calloc((size_t)ninputs, sizeof(double));
    s->xform = calloc((size_t)ninputs, sizeof(int)); /* identity (poly_frame.c) */
    if (!s->lens_name || !s->lens_path || !s->inputs || !s->outputs || !s->offset ||
        !s->scale || !s->inv_scale || !s->off_scaled || !s->lo || !s->hi || !s->xform) {
        poly_free(s);
        return NULL;
    }
    for (int i = 0; i < ninputs; i++) {
        s->inputs[i] = dupstr(inputs[i]);
        if (!s->inputs[i]) {
            poly_free(s);
            return NULL;
        }
        s->scale[i] = s->inv_scale[i] = 1;
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

static void free_part(poly_part *p, int nin, int nout)
{
    if (!p->own)
        return; /* the shared empty tables: freed with the system */
    poly_terms_free(p->out, nout);
    poly_terms_free(p->dout, nout * nin);
    poly_mono_free(&p->mono);
    poly_mono_free(&p->dmono);
    poly_plan_free(&p->plan);
    poly_plan_free(&p->dplan);
    poly_plan_free(&p->vplan);
}

void poly_free(poly_system *s)
{
    if (!s)
        return;
    for (int p = 0; p < s->nparts; p++)
        free_part(&s->parts[p], s->nin, s->nout);
    free(s->parts);
    if (s->empty)
        free_part(s->empty, s->nin, s->nout);
    free(s->empty);
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
    free(s->inv_scale);
    free(s->off_scaled);
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
    s->inv_scale[i] = 1 / scale;
    s->off_scaled[i] = offset * s->inv_scale[i];
    poly_frame_on_change(s);
}

void poly_set_domain(poly_system *s, int i, double lo, double hi)
{
    if (i < 0 || i >= s->nin || isnan(lo) || isnan(hi) || lo > hi)
        return;
    s->lo[i] = lo;
    s->hi[i] = hi;
}

/* The part's vplan (poly_impl.h) after its dplan; left unbuilt (start NULL) where a term
 * has no split over dplan's values or memory runs out: the batch Jacobian then runs
 * the whole value plan, as the one-ray one does then. */
static void values_plan(const poly_system *s, poly_part *p)
{
    poly_plan_values_over(&p->vplan, &p->dplan, &p->dmono, s->nin, s->nout, p->out);
}

/* Tables for a part without terms: no terms, the monomial tables with the constant and
 * the inputs, empty plans. 0, or -1 when out of memory (nothing left allocated). */
static int part_tables(const poly_system *s, poly_part *p)
{
    memset(p, 0, sizeof *p);
    p->own = 1;
    p->out = calloc((size_t)s->nout, sizeof *p->out);
    p->dout = calloc((size_t)s->nout * (size_t)s->nin, sizeof *p->dout);
    if (!p->out || !p->dout || poly_mono_init(&p->mono, s->nin) != 0 ||
        poly_mono_init(&p->dmono, s->nin) != 0 ||
        poly_plan_build(&p->plan, &p->mono, s->nin, s->nout, p->out) != 0 ||
        poly_plan_build(&p->dplan, &p->dmono, s->nin, s->nout * s->nin, p->dout) != 0) {
        free_part(p, s->nin, s->nout);
        return -1;
    }
    values_plan(s, p);
    return 0;
}

/* A part's own tables, made at its first term: until then it reads the shared empty
 * ones, so parts a file declares cost memory only with the terms they hold. */
static int own_tables(const poly_system *s, poly_part *p)
{
    if (p->own)
        return 0;
    poly_part q;
    if (part_tables(s, &q) != 0)
        return -1;
    q.rmin = p->rmin;
    q.rmax = p->rmax;
    *p = q;
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
    if (!s->empty) {
        poly_part *e = malloc(sizeof *e);
        if (!e || part_tables(s, e) != 0) {
            free(e);
            return -1;
        }
        s->empty = e;
    }
    poly_part *np = realloc(s->parts, (size_t)(s->nparts + 1) * sizeof *np);
    if (!np)
        return -1;
    s->parts = np;
    poly_part *p = &s->parts[s->nparts];
    *p = *s->empty;
    p->own = 0;
    p->rmin = rmin;
    p->rmax = rmax;
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
    if (own_tables(s, p) != 0)
        return -1;
    poly_out_terms *ot = &p->out[output];
    const int nin = s->nin;
    size_t n = (size_t)nin;
    const uint64_t bit = (uint64_t)1 << output;
    int slot = poly_mono_find(&p->mono, nin, exps);
    if (slot >= 0 && (p->mono.used_by[slot] & bit))
        return -1; /* a monomial the output already has */
    if (slot < 0)
        slot = poly_mono_ensure(&p->mono, nin, exps);
    if (slot < 0 || poly_terms_push(ot, nin, exps, coef, slot) != 0)
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
        int ds = poly_mono_ensure(&p->dmono, nin, e);
        ok = ds >= 0 && poly_terms_push(&p->dout[output * nin + i], nin, NULL, coef * exps[i], ds) == 0;
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
    if (!ok || poly_plan_build(&p->plan, &p->mono, nin, s->nout, p->out) != 0 ||
        poly_plan_build(&p->dplan, &p->dmono, nin, s->nout * nin, p->dout) != 0) {
        ot->nterms--;
        for (int i = 0; i < nin && i < 64; i++)
            if (added[i])
                p->dout[output * nin + i].nterms--;
        poly_plan_build(&p->plan, &p->mono, nin, s->nout, p->out);
        poly_plan_build(&p->dplan, &p->dmono, nin, s->nout * nin, p->dout);
        values_plan(s, p);
        return -1;
    }
    values_plan(s, p);
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
        if (!p->own)
            continue; /* the shared empty plans are built */
        if (poly_plan_build(&p->plan, &p->mono, s->nin, s->nout, p->out) != 0 ||
            poly_plan_build(&p->dplan, &p->dmono, s->nin, s->nout * s->nin, p->dout) != 0)
            return -1;
        values_plan(s, p);
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

int poly_passes(const poly_system *s, const double *out)
{
    for (int o = 0; o < s->nout; o++)
        if (!isfinite(out[o]))
            return 0;
    return poly_in_circles(s, out);
}

int poly_circle_covers(const poly_system *s, int o)
{
    for (int c = 0; c < s->ncircles; c++)
        if (isfinite(s->circles[c].radius * s->circles[c].radius) &&
            (s->circles[c].a == o || s->circles[c].b == o))
            return 1;
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
