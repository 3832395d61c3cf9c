#ifndef SPARSELENS_POLY_IMPL_H
#define SPARSELENS_POLY_IMPL_H
/* The layout of a poly_system, shared by poly.c (building), poly_io.c and poly_write.c
 * (the text format), poly_eval.c and poly_emit_c.c. Nothing outside those files includes
 * this.
 *
 * Monomials. Each part keeps a table of "slots", values computed once per ray:
 *   slot 0          the constant 1
 *   slot 1 + i      the scaled input s_i (poly_scale_column below)
 *   later slots     products slot[a] * slot[b], appended in an order where a, b < slot.
 * A monomial's value is defined canonically by its exponent tuple alone: a pure power
 * s_i^k is s_i^(k-1) * s_i; a mixed monomial is (the monomial with its last non-zero
 * exponent removed) * (that pure power). So the value of a term never depends on the
 * order terms were added in, which is what makes a written and re-read system evaluate
 * bit-identically, and lets the emitted C repeat the same products.
 *
 * Plan. Evaluation runs a flat program (poly_plan) built from the table and the terms:
 * values are numbered compactly (0 the constant, 1 + i the inputs, then only the
 * products that must be kept: a monomial that one term alone uses and nothing is built
 * from is "fused": never stored, its term multiplies its two factors in place). Each
 * output sums first its "single" terms, coef * v[x], in add order; then its fused terms
 * by a shared factor v[b] (of a fused term's two factors the one more fused terms of the
 * output have; groups of the same b in the order of their first term, terms in add
 * order), each group cut into quads, a pair and a lone term:
 *   quad  ((c0 * v[a0] + c1 * v[a1]) + (c2 * v[a2] + c3 * v[a3])) * v[b]
 *   pair  (c0 * v[a0] + c1 * v[a1]) * v[b]
 *   lone  (c0 * v[a0]) * v[b]
 * with every quad of the output first, then every pair, then every lone term. A quad
 * loads 5 values where 4 terms apiece loaded 8: the batch kernel is bound by loads.
 * Within each of the runs (singles, quads, pairs, lone terms) item t goes to partial
 * sum t % POLY_NSUMS, and the output is (s0 + s1) + (s2 + s3). Each partial sum starts
 * at -0, the exact identity of IEEE addition (x + -0 is x for every x; 0 + -0 is 0), so
 * a sum's first item is taken as is: no add, where a start at 0 cost one per sum (a
 * compiler may not drop 0 + x). An output without terms is 0. Independent partial sums
 * let the additions overlap, and fixed-size items keep the loops free of branches that
 * depend on the data. All paths (scalar, batch, Jacobian, emitted C) follow this plan,
 * without contraction into FMA, so they give the same bits. */
#include "sparselens/poly.h"

#include <math.h>
#include <stdint.h>

#include "base/index_hash.h"

#define POLY_NSUMS 4

/* A monomial table (see above). */
typedef struct {
    int nslots, cap;
    int *exps;            /* nslots x ninputs: the monomial each slot holds */
    int *a, *b;           /* factors of product slots (-1 for slot 0 and the inputs) */
    int *depth;           /* longest chain of products leading to the slot */
    uint64_t *used_by;    /* per slot: bit o set when output o has a term on it */
    index_hash index;     /* slot by exponent tuple: finding a monomial is O(1) */
} poly_mono;

/* The one-ray evaluation with vectors (poly_fast.c), built beside each plan. */
typedef struct poly_fast poly_fast;

/* The flat program evaluating nout sums of terms over one monomial table. */
typedef struct {
    int nvals;            /* values per ray: 1 + ninputs + nprod */
    int nprod;
    int *prod;            /* 2 x nprod: value 1 + nin + j = v[prod[2j]] * v[prod[2j+1]] */
    int *order;           /* nslots - 1 - nin: the product slots by depth (the emitter's
                             order: neighbours rarely wait on each other) */
    int nout;
    int *start;           /* nout + 1: terms of output o are start[o] .. start[o+1] - 1 */
    int *nsingle;         /* nout: the first nsingle[o] of them are single terms, then
                             4 nquad[o] in quads, 2 npair[o] in pairs, the rest lone */
    int *nquad, *npair;   /* nout */
    double *coef;         /* per planned term */
    int *fa, *fb;         /* single: coef * v[fa]; fused: coef * v[fa] in an item of
                             factor v[fb] */
    int *src;             /* per planned term: its index in the output's add order */
    int *vslot;           /* nvals: the slot each value holds (the emitter's names) */
    poly_fast *fast;      /* its sums for one ray with vectors; NULL: not built */
} poly_plan;

typedef struct {
    int nterms, cap;
    int *exps;    /* nterms x ninputs */
    double *coef; /* nterms */
    int *slot;    /* nterms: the slot holding the term's monomial */
} poly_out_terms;

typedef struct {
    double rmin, rmax;
    poly_out_terms *out; /* noutputs */
    poly_mono mono;
    poly_plan plan;
    /* The Jacobian: per output o and input i (sum o * ninputs + i) the terms of
     * d out_o / d s_i, coef * e_i times the monomial e - 1_i, over their own table,
     * appended as terms are added (so derivative sums follow add order too). */
    poly_out_terms *dout; /* noutputs x ninputs; exps unused */
    poly_mono dmono;
    poly_plan dplan;
    /* The outputs' values as items over dplan's values, no products of their own
     * (poly_plan_values_over; start NULL: some term has no split there): the batch
     * Jacobian's values for the chain rule through the frame. */
    poly_plan vplan;
    /* 0: the tables above are the system's shared empty ones (poly_system.empty), read
     * only: a part costs no table of its own (about 48 bytes per input and output for
     * the derivative sums) until its first term. 1: its own. */
    int own;
} poly_part;

typedef struct {
    int a, b;
    double radius;
} poly_circle;

struct poly_system {
    char *lens_name, *lens_path;
    int nin, nout;
    char **inputs, **outputs;
    double *offset, *scale, *lo, *hi;
    double *inv_scale, *off_scaled; /* per input: 1 / scale and offset * (1 / scale), kept
                                       by poly_set_scaling (poly_fast.c's scaling, a
                                       multiply-add, without a divide per ray) */
    int ix, iy; /* inputs named x and y (part selection), -1 if absent */
    /* Around the polynomial core (poly_frame.c): a frame rotation of the inputs and
     * outputs, and per-input transforms. Both are off (POLY_FRAME_NONE, identity) in a
     * system that does not ask for them, which then evaluates exactly as before. */
    int frame;      /* POLY_FRAME_* */
    int iu, iv;     /* inputs named u and v (the meridional frame), -1 if absent */
    int *xform;     /* per input: POLY_XFORM_* */
    int nxform;     /* inputs whose transform is not the identity */
    unsigned char *plain; /* per output: 1 = computed outside the frame (at the inputs
                             with their transforms only), as direction components
                             that do not turn with the ray; NULL: none */
    int nplain;
    /* With outputs outside the frame, two views of the system that evaluation runs
     * instead of it: vframe holds only the outputs in the frame, vplain only the others
     * (the rest of their outputs have no terms), so each term is computed once.
     * Kept in step by poly_frame_on_change / poly_frame_on_term (poly_frame.c). */
    poly_system *vframe, *vplain;
    int npairs;     /* output pairs rotated with the frame */
    int *pair;      /* npairs x 2: outputs (a, b) = (..._x, ..._y) or (..._u, ..._v) */
    /* bit a set for each pair (a, a + 1) when every pair is two neighbouring outputs
     * (lens-fit's), else 0: poly_fast.c's, kept with pair by poly_frame.c */
    uint64_t neighbour_pairs;
    int nparts;
    poly_part *parts;
    poly_part *empty; /* the tables of every part without terms, made with the first part */
    int ncircles;
    poly_circle *circles;
    int nmeta;
    char **meta_key, **meta_val;
    int bulk; /* poly_bulk_begin: plans and views wait for poly_bulk_end */
};

/* Building many terms at once (a file being read, the views): between the two calls
 * poly_add_term neither replans the part nor updates the views, so n terms cost O(n)
 * rather than O(n^2); poly_bulk_end makes the system ready to evaluate (0, or -1 when
 * out of memory). Evaluating in between is not allowed. */
void poly_bulk_begin(poly_system *s);
int poly_bulk_end(poly_system *s);
/* poly_set_meta without the search for an existing key: for readers that checked
 * (by hashing) that the key is new. 0, or -1 when out of memory or the key is bad. */
int poly_append_meta(poly_system *s, const char *key, const char *value);

/* The pass test on final outputs (rotated back when there is a frame, so every path,
 * scalar, batch and emitted C, agrees bit for bit): finite, and inside every circle. */
int poly_passes(const poly_system *s, const double *out);
/* 1 when output o is in a pass circle of finite squared radius: a*a + b*b <= r*r then
 * fails for inf and nan, and the test needs no check of o's own for being finite. */
int poly_circle_covers(const poly_system *s, int o);

/* The part a ray at sensor radius r belongs to (the nearest one if none contains r). */
int poly_part_for_radius(const poly_system *sys, double r);
int poly_select_part(const poly_system *sys, const double *in);

/* The polynomial core of evaluation (poly_eval.c): the system's inputs are taken as
 * already in the frame and transformed, the outputs are left in the frame. poly_frame.c
 * wraps them into the public poly_eval* functions. Except poly_eval_batch_core: its
 * kernel applies the frame and transforms of sys itself (per block, in vector
 * registers), so poly_eval_batch is that function alone. */
int poly_eval_part_core(const poly_system *sys, int part, const double *in, double *out);
/* Its values alone, without the pass test (nan and -1 for a missing part or no memory). */
int poly_eval_values_core(const poly_system *sys, int part, const double *in, double *out);
void poly_eval_batch_core(const poly_system *sys, size_t count, const double *in, double *out,
                          unsigned char *pass);
/* Whether every part of s's frame view (s itself without outputs outside the frame) has
 * its vplan: then the batch Jacobian takes the chain rule's values from it, and so does
 * poly_eval_jacobian (poly_eval_jacobian_core's over). */
int poly_jacf_vplan(const poly_system *s);
/* The core's values and derivatives at one ray: the values needv says (NULL: all, and
 * the pass test; else no pass test, 0) and the derivative sums needd says (NULL: all);
 * the others come out 0. over (if not NULL): the values needo says (NULL: all) again,
 * by the part's vplan over the derivative plan's values (nan without a vplan). */
int poly_eval_jacobian_core(const poly_system *sys, const double *in, const unsigned char *needv,
                            const unsigned char *needd, double *out, double *jac, double *over,
                            const unsigned char *needo);
/* The batch Jacobian, derivative sums sel[0 .. nsel - 1] (k = o * nin + i; sel NULL:
 * all) written per ray in that order. _core: of the core alone (inputs taken as in the
 * frame). _frame: of a framed system whose views exist (when it has outputs outside the
 * frame): the kernel applies frame and transforms, runs the frame view's values and
 * derivatives and the plain view's derivatives (of the outputs asked for, and their
 * turned partners), then poly_frame_chain on each block. */
void poly_eval_jacobian_batch_frame(const poly_system *sys, size_t count, const double *in,
                                    int nsel, const int *sel, double *jac);
void poly_eval_jacobian_batch_core(const poly_system *sys, size_t count, const double *in,
                                   int nsel, const int *sel, double *jac);

/* What the chain rule through the frame (poly_frame_chain, poly_frame.c) reads and
 * writes for n rays, as columns: value k of ray r at [k * n + r] (one ray: the rows of
 * the cores; a block of the batch kernel: its columns). */
typedef struct {
    size_t n;
    const double *x;      /* nin: the inputs as given */
    const double *w;      /* nin: rotated into the frame, not transformed */
    const double *c, *sn; /* the rotation */
    const double *o;      /* nout: the frame view's values (of the rotated pairs at least) */
    const double *J, *Jp; /* nout x nin: d out_o / d t_i of the frame and plain views (Jp
                             read only when np) */
    double *g;            /* scratch: 2 nin + 9 columns */
    double *jac;          /* nout x nin: d out_o / d in_i */
    const unsigned char *outs; /* the outputs asked for (with their turned partners),
                                  NULL: all; the others' derivatives are not written */
} poly_chain_cols;
/* jac = d out / d in from the cores' values and derivatives; np: the system has outputs
 * outside the frame (the plain view's). */
void poly_frame_chain(const poly_system *s, int np, const poly_chain_cols *k);
/* 1 when poly_frame_chain takes the meridional form (chain_meridional, poly_jacobian.c),
 * which reads each ray's derivatives before it writes them: then k->jac may be k->J
 * itself (on the axis, whose limit reads k->J after, the d / dx it writes is k->J's:
 * c = 1, s = 0, 1 / r taken as 0). */
int poly_frame_chain_in_place(const poly_system *s, int np);

/* Monomial tables and plans (poly_plan.c). A table's slot 0 is the constant and slots
 * 1..nin the scaled inputs; poly_mono_ensure returns the slot of monomial e, created
 * (with the slots it is built from) if missing, poly_mono_find the slot or -1;
 * poly_terms_push appends a term (exponents e, or NULL for derivative sums) to a sum;
 * poly_plan_build plans nout sums over table m. -1 on failure (out of memory). */
int poly_mono_init(poly_mono *m, int nin);
int poly_mono_find(const poly_mono *m, int nin, const int *e);
int poly_mono_ensure(poly_mono *m, int nin, const int *e);
int poly_terms_push(poly_out_terms *ot, int nin, const int *e, double coef, int slot);
int poly_plan_build(poly_plan *pl, const poly_mono *m, int nin, int nout,
                    const poly_out_terms *sums);
void poly_terms_free(poly_out_terms *t, int n);
void poly_mono_free(poly_mono *m);
void poly_plan_free(poly_plan *pl);
int poly_plan_values_over(poly_plan *vp, const poly_plan *dp, const poly_mono *dm, int nin,
                          int nout, const poly_out_terms *sums);

/* The vector layout of poly_fast.c for nout sums with exponents (NULL: none, e.g. for
 * derivative sums, more than 6 inputs with terms or an exponent above 15, or out of
 * memory); poly_fast_run evaluates one ray's sums from its raw inputs (scaled here), 0,
 * or -1 where it cannot (no AVX-512, f NULL, an output not finite): then the plan's
 * interpreter runs. poly_fast_eval: poly_eval_part whole (frame, transforms, sums,
 * rotation back; the pass flag) for a system without outputs outside its frame whose
 * part's plan has f, or -1 likewise. Both agree with the plan to rounding. */
poly_fast *poly_fast_build(int nin, int nout, const poly_out_terms *sums);
void poly_fast_free(poly_fast *f);
int poly_fast_run(const poly_fast *f, const poly_system *s, const double *in, double *out);
int poly_fast_eval(const poly_fast *f, const poly_system *s, const double *in, double *out);

/* Hooks of the builders in poly.c: a change of scaling or parts rebuilds the views, a
 * new term is added to its view. */
void poly_frame_on_change(poly_system *s);
void poly_frame_on_term(poly_system *s, int part, int output, const int *exps, double coef);

/* The steps of poly_frame_in and poly_eval_part (poly_frame.c), for the Jacobian
 * (poly_jacobian.c): the rotation into the frame alone (t = in without a frame, cs its
 * cos and sin); the transforms in place; the inputs of the outputs outside the frame
 * (the transforms alone); those outputs taken from the plain view's values. */
void poly_frame_rotate(const poly_system *s, const double *in, double *t, double *cs);
void poly_frame_transform(const poly_system *s, double *t);
void poly_frame_plain_in(const poly_system *s, const double *in, double *t);
void poly_frame_take_plain(const poly_system *s, const double *from, double *out);

/* The meridional frame of a ray at sensor point (x, y): its radius r and the cos c and
 * sin s of its angle (1 and 0 on the axis), as every path computes them (the batch
 * kernel in vectors): one divide, not two. */
static inline void poly_frame_angle(double x, double y, double *r, double *c, double *s)
{
    const double rr = sqrt(x * x + y * y), ir = 1 / rr;
    *r = rr;
    *c = rr > 0 ? x * ir : 1;
    *s = rr > 0 ? y * ir : 0;
}

/* The turned pairs of out rotated back by the frame's (c, s) (poly_frame_out). */
static inline void poly_frame_turn_back(const poly_system *sys, double c, double s, double *out)
{
    for (int k = 0; k < sys->npairs; k++) {
        const double a = out[sys->pair[2 * k]], b = out[sys->pair[2 * k + 1]];
        out[sys->pair[2 * k]] = c * a - s * b;
        out[sys->pair[2 * k + 1]] = s * a + c * b;
    }
}

/* The circles of the pass test (poly_passes, after its check that the outputs are
 * finite): 1 when out is inside every one. Every circle tested, no early return: which
 * circle a blocked ray fails is data, and a branch on it is mispredicted. poly_eval on
 * the default fisheye-ii fit (eight circles, 36% of bench_poly's rays blocked), three
 * runs of bench_poly in turn with the build before: 111-116 -> 99-111 ns a ray, 3.04-3.18x
 * -> 2.87-2.95x a batch evaluation. */
static inline int poly_in_circles(const poly_system *s, const double *out)
{
    int in = 1;
    for (int c = 0; c < s->ncircles; c++) {
        const double a = out[s->circles[c].a], b = out[s->circles[c].b], r = s->circles[c].radius;
        in &= a * a + b * b <= r * r;
    }
    return in;
}

/* 1 when evaluation needs the frame or a transform around the core. */
static inline int poly_frame_active(const poly_system *s) { return s->frame != 0 || s->nxform > 0; }

/* The version the .poly writer writes; the reader accepts 1 to it. 2: the outer pupil's
 * out_u, out_v in the tangent frame that turns with the ray (ray_frames.h); version 1
 * systems without both of those outputs read alike (poly_io.c refuses the others). */
#define POLY_FORMAT_VERSION 2

/* Shortest decimal that reads back as v ("inf" / "-inf" for infinities); buf >= 32. */
void poly_format_number(char *buf, size_t len, double v);
/* "x^2*u" for exponents e ("1" for the constant). */
/* put_name writes each input's name (NULL: as it is; the C emitter escapes it for a
 * comment, text_c_comment). */
void poly_format_monomial(FILE *f, const poly_system *s, const int *e,
                          void (*put_name)(FILE *, const char *));

/* The scaled inputs of n rays: x[r] holds input i of ray r and becomes
 * s_i = (x - offset_i) * (1 / scale_i): a multiply, where a divide per ray and input
 * cost the batch path a fifth of its time; 1 / scale_i is rounded once, the same in every
 * path (the emitted C folds the same constant). The only place that maps inputs to the polynomial's
 * variables (with poly_scale_chain, its derivative): every path calls it, the batch path
 * on a whole column of a block, where it compiles to vector code. */
static inline void poly_scale_column(const poly_system *s, int i, double *x, int n)
{
    const double off = s->offset[i], inv = 1 / s->scale[i]; /* locals: x cannot alias them */
    for (int r = 0; r < n; r++)
        x[r] = (x[r] - off) * inv;
}

/* d out / d in_i from g = d out / d s_i (the chain rule through poly_scale_column): a
 * multiply by the same rounded 1 / scale_i, which the batch kernel applies to whole
 * vectors (a divide per derivative had cost it as much as the sums). */
static inline double poly_scale_chain(const poly_system *s, int i, double g)
{
    return g * (1 / s->scale[i]);
}

#endif
