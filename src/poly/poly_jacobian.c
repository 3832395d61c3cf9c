/* The Jacobian through the frame and transforms (poly_eval_jacobian, its batch and its
 * chosen-outputs variants): the cores' derivatives (poly_eval.c, its kernel) and the
 * chain rule of the rotation and the transforms around them, column by column (a
 * kernel block, or one ray), with its limit on the axis. poly_frame.c holds the frame's
 * arithmetic it differentiates. */
#include "poly/poly_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The inputs of the cores for one ray: w rotated into the frame, t = w transformed (the
 * frame view's, as poly_frame_in), p transformed only (the plain view's, when np). */
static void jacobian_inputs(const poly_system *s, int np, const double *in, double *w, double *t,
                            double *p, double *cs)
{
    poly_frame_rotate(s, in, w, cs);
    memcpy(t, w, (size_t)s->nin * sizeof *t);
    poly_frame_transform(s, t);
    if (np)
        poly_frame_plain_in(s, in, p);
}

/* d^2 out_o / d s_i d s_j of part p of v at the scaled inputs sc, term by term (only for
 * rays on the axis, where speed does not matter). */
static double second_derivative(const poly_system *v, int p, int o, int i, int j,
                                const double *sc)
{
    const poly_out_terms *ot = &v->parts[p].out[o];
    double sum = 0;
    for (int t = 0; t < ot->nterms; t++) {
        const int *e = ot->exps + (size_t)t * (size_t)v->nin;
        if (!e[i] || !e[j])
            continue;
        double m = ot->coef[t] * e[i] * e[j];
        for (int q = 0; q < v->nin; q++)
            for (int k = e[q] - (q == i) - (q == j); k > 0; k--)
                m *= sc[q];
        sum += m;
    }
    return sum;
}

/* d out / dy of ray r on the axis (x = y = 0, held at c = 1, s = 0): off the axis, at
 * (r cos t, r sin t), d / dy at t = 0 is (1/r) d / dt, and turning the ray turns the
 * outputs with it while its direction turns against the frame:
 *   d out / dt = J f + f_u' v - f_v' u   (J (a, b) = (-b, a) for a turned pair, 0 else),
 * f the frame view's outputs at (r, u', v'). For a rotationally symmetric lens this
 * vanishes at r = 0, and its limit over r is the derivative of the bracket in r:
 *   d out / dy = J f_r + f_u'r v - f_v'r u,
 * which needs the mixed second derivatives (from the terms). Where the fit is not
 * exactly symmetric, this is the derivative of its symmetric part: the raw one grows
 * as 1/r towards the axis. */
static void axis_limit(const poly_system *s, int np, const poly_chain_cols *k, size_t r)
{
    const size_t n = k->n;
    const int nin = s->nin, ix = s->ix, iy = s->iy, iu = s->iu, iv = s->iv;
    double in[POLY_MAX_INPUTS], sc[POLY_MAX_INPUTS], lim[POLY_MAX_OUTPUTS];
    if (s->nparts == 0)
        return;
    for (int i = 0; i < nin; i++) {
        in[i] = k->x[(size_t)i * n + r];
        sc[i] = k->w[(size_t)i * n + r];
        if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE)
            sc[i] = 1 / (sc[i] * sc[i]);
        poly_scale_column(s, i, &sc[i], 1);
    }
    const poly_system *vf = np && s->vframe ? s->vframe : s;
    const int p = poly_select_part(s, in);
    const double gx = k->g[(size_t)ix * n + r], gu = k->g[(size_t)iu * n + r];
    const double gv = k->g[(size_t)iv * n + r], u = in[iu], v = in[iv];
    const double cu = poly_scale_chain(s, ix, poly_scale_chain(s, iu, 1)) * gx * gu;
    const double cv = poly_scale_chain(s, ix, poly_scale_chain(s, iv, 1)) * gx * gv;
    for (int o = 0; o < s->nout; o++)
        if (!(np && s->plain[o])) {
            lim[o] = second_derivative(vf, p, o, ix, iu, sc) * cu * v -
                     second_derivative(vf, p, o, ix, iv, sc) * cv * u;
            k->jac[(size_t)(o * nin + iy) * n + r] = lim[o];
        }
    for (int q = 0; q < s->npairs; q++) {
        const int a = s->pair[2 * q], b = s->pair[2 * q + 1];
        const double fa = k->J[(size_t)(a * nin + ix) * n + r] * gx;
        const double fb = k->J[(size_t)(b * nin + ix) * n + r] * gx;
        k->jac[(size_t)(a * nin + iy) * n + r] = lim[a] - fb;
        k->jac[(size_t)(b * nin + iy) * n + r] = lim[b] + fa;
    }
}

/* Vector code for whole columns where the machine has it (one clone per instruction set,
 * chosen at load time; only IEEE arithmetic, never contracted, so one ray and many give
 * the same bits on any of them). */
#if (defined(__x86_64__) || defined(__i386__)) && !defined(SPARSELENS_PORTABLE_KERNELS) &&   \
    defined(__GNUC__) && !defined(__clang__)
#define CHAIN_TARGET __attribute__((target_clones("avx512f", "avx2", "default"), optimize("O3")))
#define IVDEP _Pragma("GCC ivdep") /* the columns of one loop never overlap */
#else
#define CHAIN_TARGET
#define IVDEP
#endif

/* The chain rule of the meridional frame without outputs outside it, and without a
 * transform on the inputs it turns (every lens-poly 2 fit): in one pass per output or
 * turned pair, as 2 x 2 rotations. With r, c, s of the frame, u', v' the turned direction
 * and F the frame view's outputs (d_r, d_u', d_v' its derivatives, from k->J):
 *   d/dx = c d_r - (s/r) G,  d/dy = s d_r + (c/r) G,  G = v' d_u' - u' d_v',
 *   d/du = c d_u' - s d_v',  d/dv = s d_u' + c d_v',
 * (d c / dx = s^2 / r, d s / dx = -c s / r, ...; d u' / dx = -s v' / r, ...) and the
 * inputs the frame does not turn through their transforms alone. A turned pair (A, B),
 * out (a, b) = (c A - s B, s A + c B), turns its rows by the same c, s, and adds the
 * rotation's own derivative: (s/r) b, -(s/r) a to the x column, -(c/r) b, (c/r) a to y.
 * On the axis (r = 0: 1/r taken as 0) d / dy is replaced by its limit (axis_limit).
 * The same arithmetic as the general form below to rounding (fewer operations: it cost
 * the batch Jacobian as much as its derivative sums). */
static inline __attribute__((always_inline)) void chain_meridional(const poly_system *s,
                                                                   const poly_chain_cols *k,
                                                                   size_t n)
{
    const int nin = s->nin, nout = s->nout, ix = s->ix, iy = s->iy, iu = s->iu, iv = s->iv;
#define COL(p, i) ((p) + (size_t)(i) * n)
    double *g = k->g, *sir = COL(g, nin), *cir = COL(g, nin + 1);
    const double *c = k->c, *sn = k->sn, *rad = COL(k->w, ix);
    const double *up = COL(k->w, iu), *vp = COL(k->w, iv);
    for (int i = 0; i < nin; i++) { /* d(1/w^2)/dw, or 1 (axis_limit reads them) */
        double *gi = COL(g, i);
        const double *wi = COL(k->w, i);
        if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE)
            IVDEP
            for (size_t r = 0; r < n; r++)
                gi[r] = -2 / (wi[r] * wi[r] * wi[r]);
        else
            IVDEP
            for (size_t r = 0; r < n; r++)
                gi[r] = 1;
    }
    IVDEP
    for (size_t r = 0; r < n; r++) {
        const double ir = rad[r] > 0 ? 1 / rad[r] : 0;
        sir[r] = sn[r] * ir;
        cir[r] = c[r] * ir;
    }
    for (int o = 0; o < nout; o++) {
        int a = o, b = -1; /* a turned pair is done with its first output */
        for (int q = 0; q < s->npairs; q++)
            if (s->pair[2 * q] == o)
                b = s->pair[2 * q + 1];
            else if (s->pair[2 * q + 1] == o)
                a = -1;
        if (a < 0 || (k->outs && !k->outs[o]))
            continue;
        const double *JA = COL(k->J, a * nin), *JB = COL(k->J, (b < 0 ? a : b) * nin);
        double *ja = COL(k->jac, a * nin), *jb = COL(k->jac, (b < 0 ? a : b) * nin);
        const double *A = COL(k->o, a), *B = COL(k->o, b < 0 ? a : b);
        for (int j = 0; j < nin; j++) { /* the inputs the frame does not turn */
            if (j == ix || j == iy || j == iu || j == iv)
                continue;
            const double *gj = COL(g, j), *Ja = COL(JA, j), *Jb = COL(JB, j);
            double *oa = COL(ja, j), *ob = COL(jb, j);
            if (b < 0)
                IVDEP
                for (size_t r = 0; r < n; r++)
                    oa[r] = Ja[r] * gj[r];
            else
                IVDEP
                for (size_t r = 0; r < n; r++) {
                    const double dA = Ja[r] * gj[r], dB = Jb[r] * gj[r];
                    oa[r] = c[r] * dA - sn[r] * dB;
                    ob[r] = sn[r] * dA + c[r] * dB;
                }
        }
        const double *Jar = COL(JA, ix), *Jau = COL(JA, iu), *Jav = COL(JA, iv);
        const double *Jbr = COL(JB, ix), *Jbu = COL(JB, iu), *Jbv = COL(JB, iv);
        double *ax = COL(ja, ix), *ay = COL(ja, iy), *au = COL(ja, iu), *av = COL(ja, iv);
        double *bx = COL(jb, ix), *by = COL(jb, iy), *bu = COL(jb, iu), *bv = COL(jb, iv);
        if (b < 0) {
            IVDEP
            for (size_t r = 0; r < n; r++) { /* read before written: jac may be J */
                const double jr = Jar[r], ju = Jau[r], jv = Jav[r], G = vp[r] * ju - up[r] * jv;
                ax[r] = c[r] * jr - sir[r] * G;
                ay[r] = sn[r] * jr + cir[r] * G;
                au[r] = c[r] * ju - sn[r] * jv;
                av[r] = sn[r] * ju + c[r] * jv;
            }
            continue;
        }
        IVDEP
        for (size_t r = 0; r < n; r++) {
            const double cr = c[r], sr = sn[r];
            const double GA = vp[r] * Jau[r] - up[r] * Jav[r];
            const double GB = vp[r] * Jbu[r] - up[r] * Jbv[r];
            const double Ax = cr * Jar[r] - sir[r] * GA, Ay = sr * Jar[r] + cir[r] * GA;
            const double Au = cr * Jau[r] - sr * Jav[r], Av = sr * Jau[r] + cr * Jav[r];
            const double Bx = cr * Jbr[r] - sir[r] * GB, By = sr * Jbr[r] + cir[r] * GB;
            const double Bu = cr * Jbu[r] - sr * Jbv[r], Bv = sr * Jbu[r] + cr * Jbv[r];
            const double va = cr * A[r] - sr * B[r], vb = sr * A[r] + cr * B[r];
            ax[r] = (cr * Ax - sr * Bx) + sir[r] * vb;
            bx[r] = (sr * Ax + cr * Bx) - sir[r] * va;
            ay[r] = (cr * Ay - sr * By) - cir[r] * vb;
            by[r] = (sr * Ay + cr * By) + cir[r] * va;
            au[r] = cr * Au - sr * Bu;
            bu[r] = sr * Au + cr * Bu;
            av[r] = cr * Av - sr * Bv;
            bv[r] = sr * Av + cr * Bv;
        }
    }
    for (size_t r = 0; r < n; r++) /* on the axis, d / dy as its limit */
        if (rad[r] == 0)
            axis_limit(s, 0, k, r);
#undef COL
}

/* Chain rule: jac = d out / d in from the cores' values and Jacobians. With the frame,
 * t depends on in through the rotation (c and s vary with x and y) and on the transforms;
 * the outputs through the rotation back. On the axis (r = 0) the angle is undefined:
 * there the frame is held at c = 1, s = 0 and d / dy is its limit (axis_limit). The
 * rotation's derivatives
 * are written out rather than multiplied as a matrix: 11 of its 25 entries are not zero.
 * Column by column over the rays: the batch Jacobian runs it on a chunk of rays, in
 * vector registers; poly_eval_jacobian on one. */
static inline __attribute__((always_inline)) void chain(const poly_system *s, int np,
                                                        const poly_chain_cols *k, size_t n)
{
    const int nin = s->nin, nout = s->nout;
    if (poly_frame_chain_in_place(s, np)) {
        chain_meridional(s, k, n);
        return;
    }
#define COL(p, i) ((p) + (size_t)(i) * n)
#define ON(o) (!k->outs || k->outs[o]) /* an output asked for */
    double *g = k->g, *gp = COL(g, nin), *d = COL(g, 2 * nin);
    /* d(1/w^2)/dw at the frame's inputs w, and at in (plain view) */
    for (int i = 0; i < nin; i++) {
        double *gi = COL(g, i), *gpi = COL(gp, i);
        const double *wi = COL(k->w, i), *xi = COL(k->x, i);
        if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE) {
            IVDEP
            for (size_t r = 0; r < n; r++)
                gi[r] = -2 / (wi[r] * wi[r] * wi[r]);
            if (np) /* the plain view's, where in differs from w */
                IVDEP
                for (size_t r = 0; r < n; r++)
                    gpi[r] = wi[r] == xi[r] ? gi[r] : -2 / (xi[r] * xi[r] * xi[r]);
        } else
            IVDEP
            for (size_t r = 0; r < n; r++)
                gi[r] = gpi[r] = 1;
    }
    const int mer = s->frame == POLY_FRAME_MERIDIONAL;
    for (int o = 0; o < nout; o++) /* inputs the frame does not turn: the transforms alone */
        for (int j = 0; j < nin && !(np && s->plain[o]) && ON(o); j++) {
            if (mer && (j == s->ix || j == s->iy || j == s->iu || j == s->iv))
                continue; /* below */
            double *jo = COL(k->jac, o * nin + j);
            const double *Jo = COL(k->J, o * nin + j), *gj = COL(g, j);
            IVDEP
            for (size_t r = 0; r < n; r++)
                jo[r] = Jo[r] * gj[r];
        }
    /* of c and s with respect to x and y, and of u', v' (d r / d (x, y) = (c, s)) */
    double *dc0 = d, *dc1 = COL(d, 1), *ds0 = COL(d, 2), *ds1 = COL(d, 3);
    double *dux = COL(d, 4), *duy = COL(d, 5), *dvx = COL(d, 6), *dvy = COL(d, 7);
    double *zero = COL(d, 8);
    IVDEP
    for (size_t r = 0; r < n; r++)
        zero[r] = 0;
    if (mer) {
        const int ix = s->ix, iy = s->iy, iu = s->iu, iv = s->iv;
        const double *u = COL(k->x, iu), *v = COL(k->x, iv), *rad = COL(k->w, ix);
        const double *c = k->c, *sn = k->sn;
        IVDEP
        for (size_t r = 0; r < n; r++) {
            const double ir = rad[r] > 0 ? 1 / rad[r] : 0; /* poly_frame_rotate's sqrt(x*x + y*y) */
            dc0[r] = sn[r] * sn[r] * ir;
            dc1[r] = -c[r] * sn[r] * ir;
            ds0[r] = -c[r] * sn[r] * ir;
            ds1[r] = c[r] * c[r] * ir;
            dux[r] = dc0[r] * u[r] + ds0[r] * v[r];
            duy[r] = dc1[r] * u[r] + ds1[r] * v[r];
            dvx[r] = dc0[r] * v[r] - ds0[r] * u[r];
            dvy[r] = dc1[r] * v[r] - ds1[r] * u[r];
        }
        for (int o = 0; o < nout; o++) {
            if ((np && s->plain[o]) || !ON(o))
                continue;
            const double *Jx = COL(k->J, o * nin + ix), *Ju = COL(k->J, o * nin + iu);
            const double *Jv = COL(k->J, o * nin + iv);
            const double *gx = COL(g, ix), *gu = COL(g, iu), *gv = COL(g, iv);
            double *jx = COL(k->jac, o * nin + ix), *jy = COL(k->jac, o * nin + iy);
            double *ju = COL(k->jac, o * nin + iu), *jv = COL(k->jac, o * nin + iv);
            IVDEP
            for (size_t r = 0; r < n; r++) {
                const double Jr = Jx[r] * gx[r], Ju_ = Ju[r] * gu[r], Jv_ = Jv[r] * gv[r];
                jx[r] = Jr * c[r] + Ju_ * dux[r] + Jv_ * dvx[r];
                jy[r] = Jr * sn[r] + Ju_ * duy[r] + Jv_ * dvy[r];
                ju[r] = Ju_ * c[r] - Jv_ * sn[r];
                jv[r] = Ju_ * sn[r] + Jv_ * c[r];
            }
        }
    }
    for (int p = 0; p < s->npairs; p++) {
        const int a = s->pair[2 * p], b = s->pair[2 * p + 1];
        if (!ON(a))
            continue; /* partners are asked for together */
        const double *A = COL(k->o, a), *B = COL(k->o, b), *c = k->c, *sn = k->sn;
        for (int j = 0; j < nin; j++) {
            double *ja = COL(k->jac, a * nin + j), *jb = COL(k->jac, b * nin + j);
            const double *dcj = mer && j == s->ix ? dc0 : mer && j == s->iy ? dc1 : zero;
            const double *dsj = mer && j == s->ix ? ds0 : mer && j == s->iy ? ds1 : zero;
            IVDEP
            for (size_t r = 0; r < n; r++) {
                const double dA = ja[r], dB = jb[r];
                ja[r] = c[r] * dA - sn[r] * dB + A[r] * dcj[r] - B[r] * dsj[r];
                jb[r] = sn[r] * dA + c[r] * dB + A[r] * dsj[r] + B[r] * dcj[r];
            }
        }
    }
    if (mer) /* on the axis, d / dy as its limit */
        for (size_t r = 0; r < n; r++)
            if (COL(k->w, s->ix)[r] == 0)
                axis_limit(s, np, k, r);
    if (np) /* outside the frame: the transforms alone, diagonal */
        for (int o = 0; o < nout; o++)
            for (int j = 0; j < nin && s->plain[o] && ON(o); j++) {
                double *jo = COL(k->jac, o * nin + j);
                const double *Jo = COL(k->Jp, o * nin + j), *gj = COL(gp, j);
                IVDEP
                for (size_t r = 0; r < n; r++)
                    jo[r] = Jo[r] * gj[r];
            }
#undef COL
#undef ON
}

int poly_frame_chain_in_place(const poly_system *s, int np)
{
    return s->frame == POLY_FRAME_MERIDIONAL && !np && !s->xform[s->ix] && !s->xform[s->iy] &&
           !s->xform[s->iu] && !s->xform[s->iv];
}

/* The chain rule on n = k->n rays, in vector code; one ray (jacobian_one) compiles the
 * same body with n = 1, where its loops vanish. */
CHAIN_TARGET void poly_frame_chain(const poly_system *s, int np, const poly_chain_cols *k)
{
    chain(s, np, k, k->n);
}

/* With a frame: through the batch kernel, which applies the frame and the transforms,
 * runs the views' values and derivatives and then poly_frame_chain on each block, as
 * poly_eval_jacobian does on one ray (the same arithmetic; with AVX-512 the kernel's
 * sums fused, so to 1e-12 relative). Ray by ray if the views are missing. */
int poly_eval_jacobian_batch_outputs(const poly_system *s, size_t count, const double *in,
                                     int nsel, const int *outputs, double *jac)
{
    const size_t nin = (size_t)s->nin, nout = (size_t)s->nout, nj = nin * nout;
    if (nsel < 0 || (nsel > 0 && !outputs))
        return -1;
    for (int j = 0; j < nsel; j++)
        if (outputs[j] < 0 || outputs[j] >= s->nout)
            return -1;
    int *sel = malloc(((size_t)nsel * nin + 1) * sizeof *sel);
    if (!sel) {
        for (size_t k = 0; k < count * (size_t)nsel * nin; k++)
            jac[k] = NAN;
        return 0;
    }
    for (int j = 0; j < nsel; j++)
        for (size_t i = 0; i < nin; i++)
            sel[(size_t)j * nin + i] = outputs[j] * s->nin + (int)i;
    const int ns = nsel * s->nin;
    if (!poly_frame_active(s)) {
        poly_eval_jacobian_batch_core(s, count, in, ns, sel, jac);
    } else if (!(s->frame && s->nplain) || (s->vframe && s->vplain)) {
        poly_eval_jacobian_batch_frame(s, count, in, ns, sel, jac);
    } else {
        double o[POLY_MAX_OUTPUTS], *j1 = malloc(nj * sizeof *j1);
        for (size_t r = 0; r < count; r++) {
            if (j1)
                poly_eval_jacobian(s, in + r * nin, o, j1);
            for (int k = 0; k < ns; k++)
                jac[r * (size_t)ns + (size_t)k] = j1 ? j1[sel[k]] : NAN;
        }
        free(j1);
    }
    free(sel);
    return 0;
}

void poly_eval_jacobian_batch(const poly_system *s, size_t count, const double *in, double *jac)
{
    int all[POLY_MAX_OUTPUTS];
    for (int o = 0; o < s->nout; o++)
        all[o] = o;
    poly_eval_jacobian_batch_outputs(s, count, in, s->nout, all, jac);
}

int poly_jacf_vplan(const poly_system *s)
{
    const poly_system *vf = s->frame && s->nplain ? s->vframe : s;
    if (!vf)
        return 0;
    for (int p = 0; p < vf->nparts; p++)
        if (!vf->parts[p].vplan.start)
            return 0;
    return vf->nparts > 0;
}

/* poly_eval_jacobian, of the outputs outs says alone (NULL: all, with the pass flag;
 * else 0, and the other outputs' values and derivatives come out 0). outs must hold the
 * turned partner of every output it holds. */
static int jacobian_one(const poly_system *s, const double *in, const unsigned char *outs,
                        double *out, double *jac)
{
    const int nin = s->nin, nout = s->nout, np = s->frame && s->nplain;
    const size_t nn = (size_t)nin, no = (size_t)nout;
    double *buf = malloc((5 * nn + 9 + 2 * nn * no + no) * sizeof *buf);
    unsigned char *need = outs ? malloc(4 * (nn + 1) * no) : NULL;
    if (!buf || (outs && !need)) {
        for (int k = 0; k < nin * nout; k++)
            jac[k] = NAN;
        for (int o = 0; o < nout; o++)
            out[o] = NAN;
        free(buf);
        free(need);
        return 0;
    }
    /* values and derivative sums of the frame view, then of the plain view */
    unsigned char *nv[2] = {NULL, NULL}, *nd[2] = {NULL, NULL};
    for (int v = 0; outs && v < 2; v++) {
        nv[v] = need + (size_t)v * (nn + 1) * no;
        nd[v] = nv[v] + no;
        for (int o = 0; o < nout; o++) {
            nv[v][o] = outs[o] && (np && s->plain[o]) == v;
            for (int i = 0; i < nin; i++)
                nd[v][o * nin + i] = nv[v][o];
        }
    }
    int pass = 0;
    if (!poly_frame_active(s)) {
        pass = poly_eval_jacobian_core(s, in, nv[0], nd[0], out, jac, NULL, NULL);
    } else {
        double *w = buf, *t = w + nn, *p = t + nn, *g = p + nn, *J = g + 2 * nn + 9;
        double *Jp = J + nn * no, *op = Jp + nn * no, cs[2], cv[POLY_MAX_OUTPUTS];
        const poly_system *vf = s->vframe ? s->vframe : s;
        jacobian_inputs(s, np, in, w, t, p, cs);
        /* the chain rule's values as the batch Jacobian takes them (vplan) where it does:
         * of the turned pairs asked for alone */
        const int over = poly_jacf_vplan(s);
        unsigned char turned[POLY_MAX_OUTPUTS] = {0};
        for (int q = 0; q < 2 * s->npairs; q++)
            turned[s->pair[q]] = !outs || outs[s->pair[q]];
        poly_eval_jacobian_core(vf, t, nv[0], nd[0], out, J, over ? cv : NULL, turned);
        if (np)
            poly_eval_jacobian_core(s->vplain ? s->vplain : s, p, nv[1], nd[1], op, Jp, NULL, NULL);
        const poly_chain_cols k = {1, in, w, &cs[0], &cs[1], over ? cv : out, J, Jp, g, jac, outs};
        chain(s, np, &k, 1);
        if (np)
            poly_frame_take_plain(s, op, out);
        pass = !outs && poly_passes(s, out); /* on the frame's values (poly_eval_part) */
        poly_frame_out(s, cs, out);
    }
    free(buf);
    free(need);
    return pass;
}

int poly_eval_jacobian(const poly_system *s, const double *in, double *out, double *jac)
{
    return jacobian_one(s, in, NULL, out, jac);
}

int poly_eval_jacobian_outputs(const poly_system *s, const double *in, int nsel,
                               const int *outputs, double *out, double *jac)
{
    const size_t nin = (size_t)s->nin, nj = nin * (size_t)s->nout;
    unsigned char outs[POLY_MAX_OUTPUTS] = {0};
    if (nsel < 0 || (nsel > 0 && !outputs))
        return -1;
    for (int j = 0; j < nsel; j++) {
        if (outputs[j] < 0 || outputs[j] >= s->nout)
            return -1;
        outs[outputs[j]] = 1;
    }
    for (int k = 0; k < s->npairs; k++) /* a turned output's derivative needs its partner */
        outs[s->pair[2 * k]] = outs[s->pair[2 * k + 1]] =
            outs[s->pair[2 * k]] || outs[s->pair[2 * k + 1]];
    double o[POLY_MAX_OUTPUTS], *j1 = malloc(nj * sizeof *j1);
    if (j1)
        jacobian_one(s, in, outs, o, j1);
    for (int j = 0; j < nsel; j++) {
        out[j] = j1 ? o[outputs[j]] : NAN;
        for (size_t i = 0; i < nin; i++)
            jac[(size_t)j * nin + i] = j1 ? j1[(size_t)outputs[j] * nin + i] : NAN;
    }
    free(j1);
    return 0;
}
