/* The direct light's arithmetic, eight points a step (scene_light_simd.h). Why: the
 * renderer shades a block of hundreds of points, and one point at a time the selection
 * weights (a root, a quotient and for a sphere a second root per emitter), the light
 * sample on its emitter, the BSDF direction, and the shadow and BSDF rays' tests against
 * every object were most of the direct light's time, bound by the latency of roots and
 * quotients. The lanes mirror scene_light.c, scene_geometry.c and render_math.h operation
 * for operation; a select stands for each branch, with the comparison's NaN outcome of
 * the scalar test; a ray's tests go on past a blocker (the scalar search stops there: the
 * same answer). */
#include "render/scene_light_simd.h"

#include <math.h>

#define EPS_T 1e-6 /* mm: as scene_geometry.c */

#if SCENE_SIMD
#include <immintrin.h>
#define AVX512 __attribute__((target("avx512f")))

typedef __m512d vd;

AVX512 static inline vd vset(double x)
{
    return _mm512_set1_pd(x);
}

AVX512 static inline vd vneg(vd x)
{
    return _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(x),
                                                _mm512_castpd_si512(_mm512_set1_pd(-0.0))));
}

/* rm_pos: x where x > 0, else 0 (NaN too) */
AVX512 static inline vd vpos(vd x)
{
    return _mm512_maskz_mov_pd(_mm512_cmp_pd_mask(x, _mm512_setzero_pd(), _CMP_GT_OQ), x);
}

/* rm_dot3(a, b): (a0 b0 + a1 b1) + a2 b2 */
AVX512 static inline vd vdot(vd a0, vd a1, vd a2, vd b0, vd b1, vd b2)
{
    return _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(a0, b0), _mm512_mul_pd(a1, b1)),
                         _mm512_mul_pd(a2, b2));
}

AVX512 static inline void load3(const double *X, int stride, int i, vd v[3])
{
    for (int k = 0; k < 3; k++) v[k] = _mm512_loadu_pd(X + k * stride + i);
}

AVX512 void scene_simd_select(const scene_object *o, int m, int stride, const double *P,
                              const double *N, double *sel)
{
    const vd one = vset(1), two_pi = vset(2 * M_PI), zero = _mm512_setzero_pd();
    const vd ox = vset(o->p[0]), oy = vset(o->p[1]), oz = vset(o->p[2]), r2 = vset(o->r2);
    const vd rad = vset(o->radius), lum = vset(o->lum), pi_r2 = vset(M_PI * o->r2);
    const vd on0 = vset(o->n[0]), on1 = vset(o->n[1]), on2 = vset(o->n[2]);
    for (int i = 0; i < m; i += 8) {
        vd q0 = _mm512_sub_pd(ox, _mm512_loadu_pd(P + i));
        vd q1 = _mm512_sub_pd(oy, _mm512_loadu_pd(P + stride + i));
        vd q2 = _mm512_sub_pd(oz, _mm512_loadu_pd(P + 2 * stride + i));
        vd n0 = _mm512_loadu_pd(N + i), n1 = _mm512_loadu_pd(N + stride + i);
        vd n2 = _mm512_loadu_pd(N + 2 * stride + i);
        vd d2 = vdot(q0, q1, q2, q0, q1, q2), d = _mm512_sqrt_pd(d2);
        vd inv = _mm512_div_pd(one, d), inv2 = _mm512_mul_pd(inv, inv), omega;
        __mmask8 ok = _mm512_cmp_pd_mask(d, zero, _CMP_GT_OQ);
        if (o->kind == OBJ_SPHERE) {
            vd far = _mm512_sqrt_pd(vpos(_mm512_sub_pd(one, _mm512_mul_pd(r2, inv2))));
            far = _mm512_mul_pd(two_pi, _mm512_sub_pd(one, far));
            omega = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(d, rad, _CMP_LE_OQ), far, two_pi);
        } else { /* a disk (select_weight gives other kinds 0) */
            vd cl = _mm512_mul_pd(vneg(vdot(on0, on1, on2, q0, q1, q2)), inv);
            ok &= _mm512_cmp_pd_mask(cl, zero, _CMP_NLE_UQ);
            omega = _mm512_mul_pd(_mm512_mul_pd(pi_r2, cl), inv2);
            omega = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(omega, two_pi, _CMP_NLT_UQ), omega,
                                         two_pi);
        }
        vd cosf = _mm512_add_pd(vpos(_mm512_mul_pd(vdot(n0, n1, n2, q0, q1, q2), inv)), vset(0.05));
        vd w = _mm512_mul_pd(_mm512_mul_pd(lum, omega), cosf);
        _mm512_storeu_pd(sel + i, _mm512_maskz_mov_pd(ok, w));
    }
}

/* scene_light.c's choose_light on eight points: the weights' sum (in the emitters'
 * order), the emitter the walk stops at and its probability */
AVX512 void scene_simd_choose(int ne, int m, int stride, const double *sel, const double *u0,
                              double *total, int *j, double *P)
{
    const vd zero = _mm512_setzero_pd();
    for (int i = 0; i < m; i += 8) {
        vd tot = zero, acc = zero, jj = zero;
        for (int e = 0; e < ne; e++) tot = _mm512_add_pd(tot, _mm512_loadu_pd(sel + e * stride + i));
        vd x = _mm512_mul_pd(_mm512_loadu_pd(u0 + i), tot), sj = ne ? _mm512_loadu_pd(sel + i) : zero;
        __mmask8 walking = 0xff;
        for (int e = 0; e + 1 < ne; e++) {
            vd se = _mm512_loadu_pd(sel + e * stride + i), next = _mm512_add_pd(acc, se);
            walking &= _mm512_cmp_pd_mask(next, x, _CMP_LE_OQ) | _mm512_cmp_pd_mask(se, zero, _CMP_EQ_OQ);
            acc = _mm512_mask_blend_pd(walking, acc, next);
            jj = _mm512_mask_blend_pd(walking, jj, vset(e + 1));
            sj = _mm512_mask_blend_pd(walking, sj, _mm512_loadu_pd(sel + (e + 1) * stride + i));
        }
        double jd[8];
        _mm512_storeu_pd(jd, jj);
        _mm512_storeu_pd(total + i, tot);
        _mm512_storeu_pd(P + i, _mm512_div_pd(sj, tot));
        for (int l = 0; l < 8; l++) j[i + l] = (int)jd[l];
    }
}

/* rm_sincos_turn, lane by lane: the quadrant as (n mod 4) in doubles (n is whole) */
AVX512 __attribute__((always_inline)) static inline void sincos8(vd t, vd *s, vd *c)
{
    vd q = _mm512_mul_pd(vset(4), t);
    vd n = _mm512_roundscale_pd(_mm512_add_pd(q, vset(0.5)), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    vd x = _mm512_mul_pd(_mm512_sub_pd(q, n), vset(1.5707963267948966)), x2 = _mm512_mul_pd(x, x);
    static const double ks[7] = {-1.0 / 6, 1.0 / 120, -1.0 / 5040, 1.0 / 362880, -1.0 / 39916800,
                                 1.0 / 6227020800, -1.0 / 1307674368000};
    static const double kc[9] = {1, -0.5, 1.0 / 24, -1.0 / 720, 1.0 / 40320, -1.0 / 3628800,
                                 1.0 / 479001600, -1.0 / 87178291200, 1.0 / 20922789888000};
    vd ps = vset(ks[6]), pc = vset(kc[8]);
    for (int k = 5; k >= 0; k--) ps = _mm512_add_pd(vset(ks[k]), _mm512_mul_pd(x2, ps));
    for (int k = 7; k >= 0; k--) pc = _mm512_add_pd(vset(kc[k]), _mm512_mul_pd(x2, pc));
    vd sn = _mm512_add_pd(x, _mm512_mul_pd(_mm512_mul_pd(x, x2), ps)), cs = pc;
    vd quad = _mm512_sub_pd(n, _mm512_mul_pd(vset(4), _mm512_roundscale_pd(
                                                        _mm512_mul_pd(n, vset(0.25)),
                                                        _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)));
    __mmask8 q1 = _mm512_cmp_pd_mask(quad, vset(1), _CMP_EQ_OQ);
    __mmask8 q2 = _mm512_cmp_pd_mask(quad, vset(2), _CMP_EQ_OQ);
    __mmask8 q3 = _mm512_cmp_pd_mask(quad, vset(3), _CMP_EQ_OQ);
    vd nsn = vneg(sn), ncs = vneg(cs);
    *s = _mm512_mask_blend_pd(q3, _mm512_mask_blend_pd(q2, _mm512_mask_blend_pd(q1, sn, cs), nsn), ncs);
    *c = _mm512_mask_blend_pd(q3, _mm512_mask_blend_pd(q2, _mm512_mask_blend_pd(q1, cs, nsn), ncs), sn);
}

/* rm_frame(n, t, b), and the direction c n + r (cs t + sn b) about n (a cone's or the
 * cosine lobe's, as scene_light.c writes them) */
AVX512 static inline void vlobe(const vd n[3], vd c, vd r, vd sn, vd cs, vd w[3])
{
    const vd one = vset(1), mone = vset(-1);
    vd s = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(n[2], _mm512_setzero_pd(), _CMP_GE_OQ), mone, one);
    vd a = _mm512_div_pd(mone, _mm512_add_pd(s, n[2])), cc = _mm512_mul_pd(_mm512_mul_pd(n[0], n[1]), a);
    vd t[3] = {_mm512_add_pd(one, _mm512_mul_pd(_mm512_mul_pd(_mm512_mul_pd(s, n[0]), n[0]), a)),
               _mm512_mul_pd(s, cc), _mm512_mul_pd(vneg(s), n[0])};
    vd b[3] = {cc, _mm512_add_pd(s, _mm512_mul_pd(_mm512_mul_pd(n[1], n[1]), a)), vneg(n[1])};
    for (int k = 0; k < 3; k++) {
        vd side = _mm512_add_pd(_mm512_mul_pd(cs, t[k]), _mm512_mul_pd(sn, b[k]));
        w[k] = _mm512_add_pd(_mm512_mul_pd(c, n[k]), _mm512_mul_pd(r, side));
    }
}

AVX512 void scene_simd_bsdf_dir(int m, int stride, const double *N, const double *u3,
                                const double *u4, double *W, double *ct)
{
    const vd one = vset(1);
    for (int i = 0; i < m; i += 8) {
        vd a3 = _mm512_loadu_pd(u3 + i), n[3], w[3], sn, cs;
        load3(N, stride, i, n);
        vd r = _mm512_sqrt_pd(a3), c = _mm512_sqrt_pd(vpos(_mm512_sub_pd(one, a3)));
        sincos8(_mm512_loadu_pd(u4 + i), &sn, &cs);
        vlobe(n, c, r, sn, cs, w);
        for (int k = 0; k < 3; k++) _mm512_storeu_pd(W + k * stride + i, w[k]);
        _mm512_storeu_pd(ct + i, c);
    }
}

/* sample_light on sphere o from points outside it (P, normals N, uniforms U1, U2): a
 * direction in the cone the sphere fills, its end Q on the sphere, the pdf; cr and the
 * shadow flag as scene_simd_disk_light */
AVX512 void scene_simd_sphere_light(const scene_object *o, int m, int stride, const double *P,
                                    const double *N, const double *U1, const double *U2, double *Q,
                                    double *pdf, double *cr, unsigned char *shadow)
{
    const vd one = vset(1), zero = _mm512_setzero_pd(), r2 = vset(o->r2);
    for (int i = 0; i < m; i += 8) {
        vd p[3], n[3], c[3], axis[3], w[3], sn, cs, q[3];
        load3(P, stride, i, p);
        load3(N, stride, i, n);
        for (int k = 0; k < 3; k++) c[k] = _mm512_sub_pd(vset(o->p[k]), p[k]);
        vd d2 = vdot(c[0], c[1], c[2], c[0], c[1], c[2]);
        sincos8(_mm512_loadu_pd(U2 + i), &sn, &cs);
        vd id = _mm512_div_pd(one, _mm512_sqrt_pd(d2));
        for (int k = 0; k < 3; k++) axis[k] = _mm512_mul_pd(c[k], id);
        vd cos_max = _mm512_sqrt_pd(_mm512_sub_pd(one, _mm512_div_pd(r2, d2)));
        vd one_minus = _mm512_sub_pd(one, cos_max);
        vd ct = _mm512_sub_pd(one, _mm512_mul_pd(_mm512_loadu_pd(U1 + i), one_minus));
        vd st = _mm512_sqrt_pd(vpos(_mm512_sub_pd(one, _mm512_mul_pd(ct, ct))));
        vlobe(axis, ct, st, sn, cs, w);
        /* the nearer root of |p + s w - centre| = r */
        vd bb = vdot(c[0], c[1], c[2], w[0], w[1], w[2]);
        vd disc = vpos(_mm512_sub_pd(_mm512_mul_pd(bb, bb), _mm512_sub_pd(d2, r2)));
        vd sr = _mm512_sub_pd(bb, _mm512_sqrt_pd(disc)), qo[3];
        for (int k = 0; k < 3; k++) {
            q[k] = _mm512_add_pd(p[k], _mm512_mul_pd(sr, w[k]));
            qo[k] = _mm512_sub_pd(q[k], vset(o->p[k]));
            _mm512_storeu_pd(Q + k * stride + i, q[k]);
        }
        vd pd = _mm512_div_pd(one, _mm512_mul_pd(vset(2 * M_PI), one_minus));
        vd cc = vdot(n[0], n[1], n[2], w[0], w[1], w[2]);
        vd facing = vneg(vdot(qo[0], qo[1], qo[2], w[0], w[1], w[2])); /* scene_emitted */
        __mmask8 sh = _mm512_cmp_pd_mask(pd, zero, _CMP_GT_OQ) & _mm512_cmp_pd_mask(cc, zero, _CMP_GT_OQ) &
                      _mm512_cmp_pd_mask(facing, zero, _CMP_NLE_UQ);
        _mm512_storeu_pd(pdf + i, pd);
        _mm512_storeu_pd(cr + i, cc);
        for (int l = 0; l < 8; l++) shadow[i + l] = sh >> l & 1;
    }
}
/* sample_light and light_pdf on disk o from the points P (normals N) with the uniforms
 * U1, U2, and try_light's tests: the end Q, the pdf, the cosine cr at the point, and
 * whether the shadow ray decides (pdf > 0, cr > 0, the disk faces the point) */
AVX512 void scene_simd_disk_light(const scene_object *o, int m, int stride, const double *P,
                                  const double *N, const double *U1, const double *U2, double *Q,
                                  double *pdf, double *cr, unsigned char *shadow)
{
    const vd zero = _mm512_setzero_pd(), rad = vset(o->radius);
    const vd on[3] = {vset(o->n[0]), vset(o->n[1]), vset(o->n[2])};
    for (int i = 0; i < m; i += 8) {
        vd p[3], n[3], e[3], w[3], sn, cs;
        load3(P, stride, i, p);
        load3(N, stride, i, n);
        sincos8(_mm512_loadu_pd(U2 + i), &sn, &cs);
        vd r = _mm512_mul_pd(rad, _mm512_sqrt_pd(_mm512_loadu_pd(U1 + i)));
        for (int k = 0; k < 3; k++) {
            vd side = _mm512_add_pd(_mm512_mul_pd(cs, vset(o->e1[k])), _mm512_mul_pd(sn, vset(o->e2[k])));
            vd q = _mm512_add_pd(vset(o->p[k]), _mm512_mul_pd(r, side));
            _mm512_storeu_pd(Q + k * stride + i, q);
            e[k] = _mm512_sub_pd(q, p[k]);
        }
        vd dq2 = vdot(e[0], e[1], e[2], e[0], e[1], e[2]), dq = _mm512_sqrt_pd(dq2);
        vd iq = _mm512_div_pd(vset(1), dq);
        for (int k = 0; k < 3; k++) w[k] = _mm512_mul_pd(e[k], iq);
        vd dn = vdot(on[0], on[1], on[2], w[0], w[1], w[2]), cl = _mm512_abs_pd(dn);
        vd den = _mm512_mul_pd(_mm512_mul_pd(_mm512_mul_pd(cl, vset(M_PI)), rad), rad);
        __mmask8 ok = _mm512_cmp_pd_mask(dq, zero, _CMP_GT_OQ) & _mm512_cmp_pd_mask(cl, zero, _CMP_GT_OQ);
        vd pd = _mm512_maskz_mov_pd(ok, _mm512_div_pd(dq2, den));
        /* a failed draw leaves the direction 0 (try_light's start) */
        vd c = _mm512_maskz_mov_pd(_mm512_cmp_pd_mask(dq, zero, _CMP_GT_OQ),
                                   vdot(n[0], n[1], n[2], w[0], w[1], w[2]));
        __mmask8 sh = _mm512_cmp_pd_mask(pd, zero, _CMP_GT_OQ) & _mm512_cmp_pd_mask(c, zero, _CMP_GT_OQ) &
                      _mm512_cmp_pd_mask(vneg(dn), zero, _CMP_NLE_UQ);
        _mm512_storeu_pd(pdf + i, pd);
        _mm512_storeu_pd(cr + i, c);
        for (int l = 0; l < 8; l++) shadow[i + l] = sh >> l & 1;
    }
}

/* hit_object (scene_geometry.c) on eight rays (org, d): t, or INFINITY */
AVX512 __attribute__((always_inline)) static inline vd hit8(const scene_object *o, const vd org[3],
                                                            const vd d[3], vd tmin, vd tmax)
{
    const vd inf = vset(INFINITY), zero = _mm512_setzero_pd();
    if (o->kind == OBJ_SPHERE) {
        vd oc[3] = {_mm512_sub_pd(org[0], vset(o->p[0])), _mm512_sub_pd(org[1], vset(o->p[1])),
                    _mm512_sub_pd(org[2], vset(o->p[2]))};
        vd b = vdot(oc[0], oc[1], oc[2], d[0], d[1], d[2]);
        vd cc = _mm512_sub_pd(vdot(oc[0], oc[1], oc[2], oc[0], oc[1], oc[2]), vset(o->r2));
        vd disc = _mm512_sub_pd(_mm512_mul_pd(b, b), cc), sq = _mm512_sqrt_pd(disc), nb = vneg(b);
        vd t0 = _mm512_sub_pd(nb, sq), t1 = _mm512_add_pd(nb, sq);
        vd t = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(t1, tmin, _CMP_GT_OQ), inf, t1);
        t = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(t0, tmin, _CMP_GT_OQ), t, t0);
        return _mm512_mask_blend_pd(_mm512_cmp_pd_mask(disc, zero, _CMP_NLT_UQ), inf, t);
    }
    vd n0 = vset(o->n[0]), n1 = vset(o->n[1]), n2 = vset(o->n[2]);
    vd den = vdot(d[0], d[1], d[2], n0, n1, n2);
    vd q0 = _mm512_sub_pd(vset(o->p[0]), org[0]), q1 = _mm512_sub_pd(vset(o->p[1]), org[1]);
    vd q2 = _mm512_sub_pd(vset(o->p[2]), org[2]), num = vdot(q0, q1, q2, n0, n1, n2);
    __mmask8 npos = _mm512_cmp_pd_mask(num, zero, _CMP_GT_OQ);
    __mmask8 ok = (npos & _mm512_cmp_pd_mask(den, zero, _CMP_GT_OQ)) |
                  (~npos & _mm512_cmp_pd_mask(num, zero, _CMP_LT_OQ) &
                   _mm512_cmp_pd_mask(den, zero, _CMP_LT_OQ));
    ok &= _mm512_cmp_pd_mask(_mm512_abs_pd(num), _mm512_mul_pd(tmax, _mm512_abs_pd(den)), _CMP_NGE_UQ);
    vd t = _mm512_div_pd(num, den);
    ok &= _mm512_cmp_pd_mask(t, tmin, _CMP_GT_OQ);
    if (o->kind == OBJ_DISK) {
        vd h0 = _mm512_sub_pd(_mm512_add_pd(org[0], _mm512_mul_pd(t, d[0])), vset(o->p[0]));
        vd h1 = _mm512_sub_pd(_mm512_add_pd(org[1], _mm512_mul_pd(t, d[1])), vset(o->p[1]));
        vd h2 = _mm512_sub_pd(_mm512_add_pd(org[2], _mm512_mul_pd(t, d[2])), vset(o->p[2]));
        ok &= _mm512_cmp_pd_mask(vdot(h0, h1, h2, h0, h1, h2), vset(o->r2), _CMP_NGT_UQ);
    }
    return _mm512_mask_blend_pd(ok, inf, t);
}

AVX512 void scene_simd_visible(const scene_t *s, int m, int stride, const double *A,
                               const double *B, unsigned char *vis)
{
    const vd eps = vset(EPS_T), zero = _mm512_setzero_pd();
    for (int i = 0; i < m; i += 8) {
        vd a[3], b[3], d[3];
        load3(A, stride, i, a);
        load3(B, stride, i, b);
        for (int k = 0; k < 3; k++) d[k] = _mm512_sub_pd(b[k], a[k]);
        vd len = _mm512_sqrt_pd(vdot(d[0], d[1], d[2], d[0], d[1], d[2]));
        vd inv = _mm512_div_pd(vset(1), len);
        for (int k = 0; k < 3; k++) d[k] = _mm512_mul_pd(d[k], inv);
        vd tmax = _mm512_sub_pd(_mm512_mul_pd(len, vset(1 - 1e-9)), eps);
        __mmask8 blocked = 0;
        for (size_t o = 0; o < s->nobj; o++)
            blocked |= _mm512_cmp_pd_mask(hit8(&s->obj[o], a, d, eps, tmax), tmax, _CMP_LT_OQ);
        blocked &= _mm512_cmp_pd_mask(len, zero, _CMP_GT_OQ);
        for (int l = 0; l < 8; l++) vis[i + l] = !(blocked >> l & 1);
    }
}

AVX512 void scene_simd_emitter(const scene_t *s, int m, int stride, const double *O,
                               const double *D, int *which, double *t)
{
    const vd eps = vset(EPS_T), inf = vset(INFINITY);
    for (int i = 0; i < m; i += 8) {
        vd org[3], d[3], best = inf, wh = vset(-1);
        load3(O, stride, i, org);
        load3(D, stride, i, d);
        for (size_t o = 0; o < s->nobj; o++) {
            if (!s->obj[o].emitter) continue;
            vd tt = hit8(&s->obj[o], org, d, eps, best);
            __mmask8 nearer = _mm512_cmp_pd_mask(tt, best, _CMP_LT_OQ);
            best = _mm512_mask_blend_pd(nearer, best, tt);
            wh = _mm512_mask_blend_pd(nearer, wh, vset((double)o));
        }
        /* a non-emitter in front (ties to the lower index, as scene_intersect_emitter) */
        __mmask8 blocked = 0;
        for (size_t o = 0; o < s->nobj; o++) {
            if (s->obj[o].emitter) continue;
            vd tt = hit8(&s->obj[o], org, d, eps, inf);
            blocked |= _mm512_cmp_pd_mask(tt, best, _CMP_LT_OQ) |
                       (_mm512_cmp_pd_mask(tt, best, _CMP_EQ_OQ) &
                        _mm512_cmp_pd_mask(vset((double)o), wh, _CMP_LT_OQ));
        }
        double w8[8];
        _mm512_storeu_pd(w8, wh);
        _mm512_storeu_pd(t + i, best);
        for (int l = 0; l < 8; l++) which[i + l] = blocked >> l & 1 ? -1 : (int)w8[l];
    }
}

AVX512 void scene_simd_camera(const scene_t *s, int m, int stride, const double *O, const double *D,
                              double tmin, int *which, double *t)
{
    const vd t0 = vset(tmin);
    for (int i = 0; i < m; i += 8) {
        vd org[3], d[3], best = vset(INFINITY), wh = vset(-1);
        load3(O, stride, i, org);
        load3(D, stride, i, d);
        for (int sphere = 0; sphere < 2; sphere++) /* scene_intersect_listed's order */
            for (size_t o = 0; o < s->nobj; o++) {
                if ((s->obj[o].kind == OBJ_SPHERE) != sphere) continue;
                vd tt = hit8(&s->obj[o], org, d, t0, best);
                __mmask8 nearer = _mm512_cmp_pd_mask(tt, best, _CMP_LT_OQ);
                best = _mm512_mask_blend_pd(nearer, best, tt);
                wh = _mm512_mask_blend_pd(nearer, wh, vset((double)o));
            }
        double w8[8];
        _mm512_storeu_pd(w8, wh);
        _mm512_storeu_pd(t + i, best);
        for (int l = 0; l < 8; l++) which[i + l] = (int)w8[l];
    }
}
#endif

int scene_simd_ok(void)
{
#if SCENE_SIMD
    static int ok = -1;
    if (ok < 0) ok = __builtin_cpu_supports("avx512f") != 0;
    return ok;
#else
    return 0;
#endif
}
