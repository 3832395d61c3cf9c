#ifndef SPARSELENS_POLY_IMPL_H
#define SPARSELENS_POLY_IMPL_H
/* The layout of a poly_system, shared by poly.c (building), poly_io.c (the text format),
 * poly_eval.c and poly_emit_c.c. Nothing outside those files includes this.
 *
 * Evaluation plan. Each part keeps a list of "slots", values computed once per ray:
 *   slot 0          the constant 1
 *   slot 1 + i      the scaled input s_i
 *   later slots     products slot[a] * slot[b], appended in an order where a, b < slot.
 * A monomial's value is defined canonically by its exponent tuple alone: a pure power
 * s_i^k is s_i^(k-1) * s_i; a mixed monomial is (the monomial with its last non-zero
 * exponent removed) * (that pure power). So the value of a term never depends on the
 * order terms were added in, which is what makes a written and re-read system evaluate
 * bit-identically, and lets the emitted C repeat the same products. Every output of a
 * part then is a dot product of its coefficients with the slots of its monomials,
 * summed in a fixed order (POLY_NSUMS below). */
#include "poly.h"

typedef struct {
    int nterms, cap;
    int *exps;    /* nterms x ninputs */
    double *coef; /* nterms */
    int *slot;    /* nterms: the slot holding the term's monomial */
    int *fa, *fb; /* nterms: the batch path's factors, term = coef * (v[fa] * v[fb]) */
} poly_out_terms;

typedef struct {
    double rmin, rmax;
    poly_out_terms *out; /* noutputs */
    int nslots, slotcap;
    int *slot_exps; /* nslots x ninputs: the monomial each slot holds */
    int *slot_a, *slot_b; /* factors of product slots (-1 for slot 0 and the inputs) */
    int *depth;           /* longest chain of products leading to the slot */
    int *order;           /* the product slots by depth: neighbours rarely wait on each
                             other, so their multiplies overlap in the pipeline */
    /* The batch path stores only the slots it must: a monomial that one term alone uses
     * and nothing is built from is multiplied inside that term, coef * (v[a] * v[b]),
     * which is the same product, saving a store and a load. Other terms read their
     * slot as coef * (v[slot] * v[0]), exact since v[0] = 1. */
    int nstored;
    int *stored; /* nstored product slots, by depth */
} poly_part;

/* Outputs sum their terms in POLY_NSUMS interleaved partial sums (term t goes to sum
 * t % POLY_NSUMS), added as (s0 + s1) + (s2 + s3): independent additions run in
 * parallel where one running sum would wait on every add. */
#define POLY_NSUMS 4

typedef struct {
    int a, b;
    double radius;
} poly_circle;

struct poly_system {
    char *lens_name, *lens_path;
    int nin, nout;
    char **inputs, **outputs;
    double *offset, *scale, *lo, *hi;
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
    int nparts;
    poly_part *parts;
    int ncircles;
    poly_circle *circles;
    int nmeta;
    char **meta_key, **meta_val;
};

/* The part a ray at sensor radius r belongs to (the nearest one if none contains r). */
int poly_part_for_radius(const poly_system *sys, double r);
int poly_select_part(const poly_system *sys, const double *in);

/* The polynomial core of evaluation (poly_eval.c): the system's inputs are taken as
 * already in the frame and transformed, the outputs are left in the frame. poly_frame.c
 * wraps them into the public poly_eval* functions. */
int poly_eval_part_core(const poly_system *sys, int part, const double *in, double *out);
void poly_eval_batch_core(const poly_system *sys, size_t count, const double *in, double *out,
                          unsigned char *pass);
int poly_eval_jacobian_core(const poly_system *sys, const double *in, double *out, double *jac);

/* Hooks of the builders in poly.c: a change of scaling or parts rebuilds the views, a
 * new term is added to its view. */
void poly_frame_on_change(poly_system *s);
void poly_frame_on_term(poly_system *s, int part, int output, const int *exps, double coef);

/* 1 when evaluation needs the frame or a transform around the core. */
static inline int poly_frame_active(const poly_system *s) { return s->frame != 0 || s->nxform > 0; }

/* Shortest decimal that reads back as v ("inf" / "-inf" for infinities); buf >= 32. */
void poly_format_number(char *buf, size_t len, double v);
/* "x^2*u" for exponents e ("1" for the constant). */
void poly_format_monomial(FILE *f, const poly_system *s, const int *e);

#endif
