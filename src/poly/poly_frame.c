/* What evaluation does around the polynomial core (man 5 lens-poly, "frame" and
 * "transform"): the meridional frame of a rotationally symmetric lens, per-input
 * transforms, and the public poly_eval* functions that apply them.
 *
 * Why a frame: the outputs of a rotationally symmetric lens are rotation-equivariant
 * functions of the ray. Rotating each ray so its sensor point lies on +x removes one
 * input (y' = 0) and with it every term that only expresses the symmetry, so the term
 * budget goes to the lens's real aberrations. The sensor radius r = x' is scaled
 * without an offset by the fitter, since the outputs are odd or even in it.
 *
 * Every path (scalar, batch, Jacobian, emitted C) computes the same expressions in the
 * same order (the batch path in its kernel, poly_eval_kernel.h, on columns of rays): r = sqrt(x*x + y*y), c = x * (1 / r), s = y * (1 / r) (c = 1, s = 0 on the axis),
 * u' = c*u + s*v, v' = c*v - s*u; outputs a = c*a' - s*b', b = s*a' + c*b'. The pass
 * test is made on the final outputs, rotated back, in every path. */
#include "poly/poly_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *poly_frame_name(int frame)
{
    return frame == POLY_FRAME_NONE ? "none" : frame == POLY_FRAME_MERIDIONAL ? "meridional" : NULL;
}

const char *poly_xform_name(int xform)
{
    return xform == POLY_XFORM_IDENTITY         ? "identity"
           : xform == POLY_XFORM_INVERSE_SQUARE ? "inverse-square"
                                                : NULL;
}

int poly_frame_parse(const char *name)
{
    for (int f = 0; f <= POLY_FRAME_MERIDIONAL; f++)
        if (strcmp(name, poly_frame_name(f)) == 0)
            return f;
    return -1;
}

int poly_xform_parse(const char *name)
{
    for (int x = 0; x <= POLY_XFORM_INVERSE_SQUARE; x++)
        if (strcmp(name, poly_xform_name(x)) == 0)
            return x;
    return -1;
}

/* The partner of output o under the rotation ("out_x" -> "out_y"), -1 if o has none
 * by name, -2 if it should have one that is missing. *first: o is the pair's a. */
static int partner(const poly_system *s, int o, int *first)
{
    const char *n = s->outputs[o];
    size_t len = strlen(n);
    if (len < 2 || n[len - 2] != '_')
        return -1;
    char last = n[len - 1], other;
    switch (last) {
    case 'x': other = 'y'; *first = 1; break;
    case 'y': other = 'x'; *first = 0; break;
    case 'u': other = 'v'; *first = 1; break;
    case 'v': other = 'u'; *first = 0; break;
    default: return -1;
    }
    for (int q = 0; q < s->nout; q++)
        if (q != o && strncmp(s->outputs[q], n, len - 1) == 0 && s->outputs[q][len - 1] == other &&
            s->outputs[q][len] == '\0')
            return q;
    return -2;
}

/* s->neighbour_pairs from s->pair (poly_impl.h). */
static void set_neighbour_pairs(poly_system *s)
{
    uint64_t bits = 0;
    for (int k = 0; k < s->npairs; k++) {
        const int a = s->pair[2 * k], b = s->pair[2 * k + 1];
        if (b != a + 1 || b >= 64) {
            bits = 0;
            break;
        }
        bits |= (uint64_t)1 << a;
    }
    s->neighbour_pairs = bits;
}

/* The rotated pairs: outputs ..._x/..._y and ..._u/..._v computed in the frame.
 * strict: -1 when an output in the frame lacks its partner in the frame. */
static int rebuild_pairs(poly_system *s, int strict)
{
    int *pair = malloc((size_t)(s->nout + 1) * sizeof *pair);
    if (!pair)
        return -1;
    int np = 0;
    for (int o = 0; o < s->nout; o++) {
        if (s->plain && s->plain[o])
            continue;
        int first = 0, q = partner(s, o, &first);
        if (q == -1)
            continue;
        if (q == -2 || (s->plain && s->plain[q])) {
            if (strict) {
                free(pair);
                return -1;
            }
            continue;
        }
        if (first) {
            pair[2 * np] = o;
            pair[2 * np + 1] = q;
            np++;
        }
    }
    free(s->pair);
    s->pair = pair;
    s->npairs = np;
    set_neighbour_pairs(s);
    return 0;
}

/* The views (poly_impl.h): copies of the inputs, scaling and parts, each with the
 * terms of its own outputs. No frame, transform or pass circle: poly_eval_part and the
 * batch kernel apply them. On failure there are no views, and evaluation runs the
 * whole system twice. */
static void rebuild_views(poly_system *s)
{
    poly_free(s->vframe);
    poly_free(s->vplain);
    s->vframe = s->vplain = NULL;
    if (s->frame == POLY_FRAME_NONE || s->nplain == 0)
        return;
    poly_system *v[2];
    for (int k = 0; k < 2; k++) {
        v[k] = poly_new(s->lens_name, s->nin, (const char *const *)s->inputs, s->nout,
                        (const char *const *)s->outputs);
        if (!v[k]) {
            poly_free(v[0]);
            return;
        }
        for (int i = 0; i < s->nin; i++)
            poly_set_scaling(v[k], i, s->offset[i], s->scale[i]);
        poly_bulk_begin(v[k]); /* planned once at the end, not per term */
    }
    int ok = 1;
    for (int p = 0; ok && p < s->nparts; p++)
        for (int k = 0; k < 2; k++)
            ok &= poly_add_part(v[k], s->parts[p].rmin, s->parts[p].rmax) == p;
    for (int p = 0; ok && p < s->nparts; p++)
        for (int o = 0; ok && o < s->nout; o++) {
            const poly_out_terms *ot = &s->parts[p].out[o];
            for (int t = 0; ok && t < ot->nterms; t++)
                ok &= poly_add_term(v[s->plain[o] ? 1 : 0], p, o, ot->exps + (size_t)t * s->nin,
                                    ot->coef[t]) == 0;
        }
    for (int k = 0; k < 2; k++)
        ok &= poly_bulk_end(v[k]) == 0;
    if (!ok) {
        poly_free(v[0]);
        poly_free(v[1]);
        return;
    }
    s->vframe = v[0];
    s->vplain = v[1];
}

void poly_frame_on_change(poly_system *s)
{
    if (s->vframe || (s->frame != POLY_FRAME_NONE && s->nplain > 0))
        rebuild_views(s);
}

void poly_frame_on_term(poly_system *s, int part, int o, const int *exps, double coef)
{
    if (!s->vframe)
        return;
    if (poly_add_term(s->plain[o] ? s->vplain : s->vframe, part, o, exps, coef) != 0)
        rebuild_views(s); /* out of memory there: start over (or run without views) */
}

int poly_set_frame(poly_system *s, int frame)
{
    if (frame == POLY_FRAME_NONE) {
        s->frame = frame;
        s->npairs = 0;
        set_neighbour_pairs(s);
        s->nplain = 0;
        free(s->plain);
        s->plain = NULL;
        rebuild_views(s);
        return 0;
    }
    if (frame != POLY_FRAME_MERIDIONAL || s->ix < 0 || s->iy < 0 || s->iu < 0 || s->iv < 0)
        return -1;
    unsigned char *plain = s->plain ? s->plain : calloc((size_t)s->nout, 1);
    if (!plain)
        return -1;
    s->plain = plain;
    if (rebuild_pairs(s, 1) != 0)
        return -1;
    s->frame = frame;
    rebuild_views(s);
    return 0;
}

int poly_set_output_plain(poly_system *s, int o, int plain)
{
    if (s->frame == POLY_FRAME_NONE || o < 0 || o >= s->nout || !s->plain)
        return -1;
    s->nplain += (plain != 0) - (s->plain[o] != 0);
    s->plain[o] = plain != 0;
    rebuild_views(s);
    return rebuild_pairs(s, 0);
}

int poly_get_output_plain(const poly_system *s, int o)
{
    return s->plain && o >= 0 && o < s->nout ? s->plain[o] : 0;
}

int poly_frame_check(const poly_system *s)
{
    if (s->frame == POLY_FRAME_NONE)
        return 0;
    return rebuild_pairs((poly_system *)s, 1);
}

int poly_get_frame(const poly_system *s) { return s->frame; }

int poly_set_transform(poly_system *s, int i, int xform)
{
    if (i < 0 || i >= s->nin || !poly_xform_name(xform))
        return -1;
    s->nxform += (xform != POLY_XFORM_IDENTITY) - (s->xform[i] != POLY_XFORM_IDENTITY);
    s->xform[i] = xform;
    return 0;
}

int poly_get_transform(const poly_system *s, int i) { return s->xform[i]; }

/* The rotation into the frame alone (t = in without a frame). */
void poly_frame_rotate(const poly_system *s, const double *in, double *t, double *cs)
{
    memcpy(t, in, (size_t)s->nin * sizeof *t);
    cs[0] = 1;
    cs[1] = 0;
    if (s->frame == POLY_FRAME_MERIDIONAL) {
        const double u = in[s->iu], v = in[s->iv];
        double r, c, sn;
        poly_frame_angle(in[s->ix], in[s->iy], &r, &c, &sn);
        t[s->ix] = r;
        t[s->iy] = 0;
        t[s->iu] = c * u + sn * v;
        t[s->iv] = c * v - sn * u;
        cs[0] = c;
        cs[1] = sn;
    }
}

void poly_frame_in(const poly_system *s, const double *in, double *t, double *cs)
{
    poly_frame_rotate(s, in, t, cs);
    poly_frame_transform(s, t);
}

void poly_frame_out(const poly_system *s, const double *cs, double *out)
{
    poly_frame_turn_back(s, cs[0], cs[1], out);
}

void poly_frame_out_inverse(const poly_system *s, const double *cs, double *out)
{
    const double c = cs[0], sn = cs[1];
    for (int k = 0; k < s->npairs; k++) {
        double a = out[s->pair[2 * k]], b = out[s->pair[2 * k + 1]];
        out[s->pair[2 * k]] = c * a + sn * b;
        out[s->pair[2 * k + 1]] = c * b - sn * a;
    }
}

int poly_eval(const poly_system *s, const double *in, double *out)
{
    return poly_eval_part(s, s->nparts ? poly_select_part(s, in) : -1, in, out);
}


/* The inputs of the outputs outside the frame: the transforms alone. */
void poly_frame_plain_in(const poly_system *s, const double *in, double *t)
{
    memcpy(t, in, (size_t)s->nin * sizeof *t);
    poly_frame_transform(s, t);
}

void poly_frame_take_plain(const poly_system *s, const double *from, double *out)
{
    for (int o = 0; o < s->nout; o++)
        if (s->plain[o])
            out[o] = from[o];
}

int poly_eval_part(const poly_system *s, int part, const double *in, double *out)
{
    if (!poly_frame_active(s))
        return poly_eval_part_core(s, part, in, out);
    const int nin = s->nin, nout = s->nout, np = s->frame && s->nplain;
    if (!np && part >= 0 && part < s->nparts) {
        int p = poly_fast_eval(s->parts[part].plan.fast, s, in, out);
        if (p >= 0)
            return p;
    }
    double cs[2], buf[64];
    double *t = 2 * nin + nout <= 64 ? buf : malloc((size_t)(2 * nin + nout) * sizeof *t);
    if (!t) {
        for (int o = 0; o < nout; o++)
            out[o] = NAN;
        return 0;
    }
    double *tp = t + nin, *op = tp + nin;
    poly_frame_in(s, in, t, cs);
    /* the views' values only: the pass test is made once, on the final outputs */
    poly_eval_values_core(s->vframe ? s->vframe : s, part, t, out);
    if (np) {
        poly_frame_plain_in(s, in, tp);
        poly_eval_values_core(s->vplain ? s->vplain : s, part, tp, op);
        poly_frame_take_plain(s, op, out);
    }
    /* on the frame's values, as every path: the turn back keeps each pair's radius,
     * and the batch kernel need not turn the pairs it does not write */
    const int pass = poly_passes(s, out);
    poly_frame_out(s, cs, out);
    if (t != buf)
        free(t);
    return pass;
}

/* The batch kernel applies the frame and transforms itself, in the same order as
 * poly_eval_part above (poly_eval_kernel.h), one pass over the rays for both views. */
void poly_eval_batch(const poly_system *s, size_t count, const double *in, double *out,
                     unsigned char *pass)
{
    poly_eval_batch_core(s, count, in, out, pass);
}

/* The transforms of the inputs, in place. */
void poly_frame_transform(const poly_system *s, double *t)
{
    for (int i = 0; s->nxform && i < s->nin; i++)
        if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE)
            t[i] = 1 / (t[i] * t[i]);
}
