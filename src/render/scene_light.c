/* Direct light at a diffuse point by multiple importance sampling (scene.h,
 * scene_direct_mis): one light sample and one BSDF sample, combined by the power
 * heuristic (Veach 1997, ch. 9).
 *
 *  - light sample: one emitter is chosen with probability P_j proportional to a cheap
 *    estimate of what it sends to the point (its luminance times the solid angle it
 *    fills, times the cosine towards its centre plus a floor); a sphere is then sampled
 *    uniformly within the cone it subtends (pdf 1 / (2 pi (1 - cos theta_max))), a disk
 *    by area (pdf d^2 / (A cos theta_l) per solid angle); one shadow ray.
 *  - BSDF sample: a cosine-weighted direction (pdf cos / pi); if the first thing it meets
 *    is an emitter's front, that emitter's radiance. Emitting infinite planes are only
 *    found this way (they cannot be sampled by area): their weight is 1.
 * Each term's weight w multiplies albedo * L_e of its emitter; for the Lambertian
 * f = albedo / pi, the light term is cos / (pi P_j pdf) times its MIS weight and the BSDF
 * term (f cos / pdf = albedo) is its MIS weight alone. An emitter with P_j = 0 at the
 * point is left to the BSDF sample with weight 1, so the sum stays unbiased. */
#include <math.h>
#include <string.h>

#include "sparselens/scene.h"

#include "render/render_math.h"
#include "render/scene_light_block.h"
#include "render/scene_light_simd.h"

#define EPS_T 1e-6 /* mm: as scene_geometry.c */
#define dot3 rm_dot3

#define frame_of rm_frame

/* The selection weight of emitter o at point p with normal n. */
static double select_weight(const scene_object *o, const double p[3], const double n[3])
{
    double q[3] = {o->p[0] - p[0], o->p[1] - p[1], o->p[2] - p[2]};
    double d2 = dot3(q, q), d = sqrt(d2), omega;
    if (!(d > 0)) return 0;
    double inv = 1 / d, inv2 = inv * inv; /* one quotient: every emitter, every sample */
    if (o->kind == OBJ_SPHERE) {
        omega = d <= o->radius ? 2 * M_PI : 2 * M_PI * (1 - sqrt(rm_pos(1 - o->r2 * inv2)));
    } else if (o->kind == OBJ_DISK) {
        double cl = -dot3(o->n, q) * inv; /* the disk emits towards its normal */
        if (cl <= 0) return 0;
        omega = M_PI * o->r2 * cl * inv2;
        if (!(omega < 2 * M_PI)) omega = 2 * M_PI; /* fmin(2 pi, omega), NaN too */
    } else {
        return 0;
    }
    return o->lum * omega * (rm_pos(dot3(n, q) * inv) + 0.05);
}

/* Solid-angle density with which emitter o's sampling gives direction w from p, hitting
 * it at q with unit normal nq. */
static double light_pdf(const scene_object *o, const double p[3], const double q[3],
                        const double nq[3], const double w[3])
{
    double c[3] = {o->p[0] - p[0], o->p[1] - p[1], o->p[2] - p[2]};
    double e[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, dq2 = dot3(e, e);
    if (o->kind == OBJ_SPHERE) {
        double d2 = dot3(c, c), r2 = o->r2;
        if (d2 > r2 * (1 + 1e-12)) {
            double one_minus = 1 - sqrt(1 - r2 / d2);
            return 1 / (2 * M_PI * one_minus);
        }
        double cl = fabs(dot3(nq, w));
        return cl > 0 ? dq2 / (cl * 4 * M_PI * r2) : 0;
    }
    double cl = fabs(dot3(nq, w));
    return cl > 0 ? dq2 / (cl * M_PI * o->radius * o->radius) : 0;
}

/* Draws direction w towards emitter o from p; q its point there, nq the outward normal.
 * Returns the solid-angle pdf (0: nothing drawn). */
static double sample_light(const scene_object *o, const double p[3], double u1, double u2,
                           double w[3], double q[3], double nq[3])
{
    double c[3] = {o->p[0] - p[0], o->p[1] - p[1], o->p[2] - p[2]};
    double d2 = dot3(c, c), r2 = o->r2, sn, cs;
    rm_sincos_turn(u2, &sn, &cs); /* of phi = 2 pi u2 */
    if (o->kind == OBJ_SPHERE && d2 > r2 * (1 + 1e-12)) {
        double d = sqrt(d2), id = 1 / d, axis[3] = {c[0] * id, c[1] * id, c[2] * id}, t[3], b[3];
        double cos_max = sqrt(1 - r2 / d2), one_minus = 1 - cos_max;
        double ct = 1 - u1 * one_minus, st = sqrt(rm_pos(1 - ct * ct));
        frame_of(axis, t, b);
        for (int k = 0; k < 3; k++) w[k] = ct * axis[k] + st * (cs * t[k] + sn * b[k]);
        /* the nearer root of |p + s w - centre| = r (it exists: w is inside the cone) */
        double bb = dot3(c, w), disc = rm_pos(bb * bb - (d2 - r2)), s = bb - sqrt(disc);
        double ir = 1 / o->radius;
        for (int k = 0; k < 3; k++) q[k] = p[k] + s * w[k], nq[k] = (q[k] - o->p[k]) * ir;
        return 1 / (2 * M_PI * one_minus);
    }
    if (o->kind == OBJ_SPHERE) { /* inside: by area */
        double z = 1 - 2 * u1, r = sqrt(rm_pos(1 - z * z));
        nq[0] = r * cs, nq[1] = r * sn, nq[2] = z;
        for (int k = 0; k < 3; k++) q[k] = o->p[k] + o->radius * nq[k];
    } else {
        double r = o->radius * sqrt(u1); /* the frame made when the disk was read */
        for (int k = 0; k < 3; k++) q[k] = o->p[k] + r * (cs * o->e1[k] + sn * o->e2[k]);
        memcpy(nq, o->n, 3 * sizeof *nq);
    }
    double e[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, dq = sqrt(dot3(e, e));
    if (!(dq > 0)) return 0;
    double iq = 1 / dq;
    for (int k = 0; k < 3; k++) w[k] = e[k] * iq;
    return light_pdf(o, p, q, nq, w);
}

/* A point's light sample before its shadow ray: the emitter j drawn (of idx), its
 * probability P, the direction's pdf, cosine cr at the point and end q; shadow: the
 * shadow ray decides the term (every other test passed). */
typedef struct {
    size_t j;
    double P, pdf, cr, q[3];
    int shadow;
} light_try;

/* The emitter the light sample draws (L->j of idx) and its probability L->P, from the
 * selection weights sel[j * stride] of the emitters idx[j] (j < ne) and their sum;
 * returns 0 when none can be drawn. */
static int choose_light(double u0, const double *sel, size_t stride, size_t ne, double total,
                        light_try *L)
{
    L->shadow = 0;
    if (!(total > 0)) return 0;
    double x = u0 * total, acc = 0;
    size_t j = 0;
    while (j + 1 < ne && (acc + sel[j * stride] <= x || sel[j * stride] == 0)) acc += sel[stride * j++];
    L->j = j;
    L->P = sel[j * stride] / total;
    return 1;
}

/* The chosen emitter's sample at h: direction, pdf, cosine, and whether it faces h. */
static void sample_chosen(const scene_t *s, const scene_hit *h, const double u[5], const int *idx,
                          light_try *L)
{
    const scene_object *o = &s->obj[idx[L->j]];
    double wl[3] = {0, 0, 0}, nq[3], le[3];
    L->pdf = L->P > 0 ? sample_light(o, h->p, u[1], u[2], wl, L->q, nq) : 0;
    L->cr = dot3(h->n, wl);
    double back[3] = {-wl[0], -wl[1], -wl[2]};
    L->shadow = L->pdf > 0 && L->cr > 0 && scene_emitted(s, idx[L->j], L->q, back, le);
}

/* The light sample at h up to its shadow ray. */
static void try_light(const scene_t *s, const scene_hit *h, const double u[5], const double *sel,
                      size_t stride, const int *idx, size_t ne, double total, light_try *L)
{
    if (choose_light(u[0], sel, stride, ne, total, L)) sample_chosen(s, h, u, idx, L);
}

/* The light sample's term, its shadow ray having passed. */
static void light_term(const light_try *L, const int *idx, scene_light_terms *t)
{
    double pl = L->P * L->pdf, pb = L->cr / M_PI;
    t->emitter[t->n] = idx[L->j];
    t->w[t->n++] = L->cr / (M_PI * pl) * pl * pl / (pl * pl + pb * pb);
}

/* The BSDF sample's term at h: direction w, cosine ct, g the emitter it reaches first
 * (scene_intersect_emitter; NULL: none). */
static void bsdf_term(const scene_t *s, const scene_hit *h, const double *sel, size_t stride,
                      const int *idx, size_t ne, double total, const double w[3], double ct,
                      const scene_hit *g, scene_light_terms *t)
{
    if (!g) return;
    const scene_object *o = &s->obj[g->obj];
    double back[3] = {-w[0], -w[1], -w[2]}, le[3];
    if (!scene_emitted(s, g->obj, g->p, back, le)) return;
    double pl = 0;
    if (total > 0 && o->kind != OBJ_PLANE)
        for (size_t j = 0; j < ne; j++)
            if (idx[j] == g->obj) {
                double nq[3];
                for (int k = 0; k < 3; k++) nq[k] = g->n[k];
                pl = sel[j * stride] / total * light_pdf(o, h->p, g->p, nq, w);
            }
    double pb = ct / M_PI;
    t->emitter[t->n] = g->obj;
    t->w[t->n++] = pb * pb / (pb * pb + pl * pl);
}

/* The terms of scene_direct_mis at h, one point: light sample, shadow ray, BSDF sample
 * (direction w, cosine ct drawn from u[3], u[4]) and its ray. */
static void direct_terms(const scene_t *s, const scene_hit *h, const double u[5], const double *sel,
                         size_t stride, const int *idx, size_t ne, double total, const double w[3],
                         double ct, scene_light_terms *t)
{
    light_try L;
    scene_hit g;
    t->n = 0;
    try_light(s, h, u, sel, stride, idx, ne, total, &L);
    if (L.shadow && scene_visible(s, h->p, L.q)) light_term(&L, idx, t);
    int reach = ct > 0 && scene_intersect_emitter(s, h->p, w, EPS_T, &g);
    bsdf_term(s, h, sel, stride, idx, ne, total, w, ct, reach ? &g : NULL, t);
}

/* The emitters light sampling weighs: the first 64 in the scene's order. */
static size_t emitters_of(const scene_t *s, int idx[64])
{
    size_t ne = 0;
    for (size_t i = 0; i < s->nobj && ne < 64; i++)
        if (s->obj[i].emitter) idx[ne++] = (int)i;
    return ne;
}

void scene_direct_mis(const scene_t *s, const scene_hit *h, const double u[5],
                      scene_light_terms *t)
{
    double sel[64], total = 0;
    int idx[64];
    size_t ne = emitters_of(s, idx);
    for (size_t j = 0; j < ne; j++) {
        sel[j] = select_weight(&s->obj[idx[j]], h->p, h->n);
        total += sel[j];
    }
    double r = sqrt(u[3]), ct = sqrt(rm_pos(1 - u[3])), tt[3], bb[3], w[3], sn, cs;
    rm_sincos_turn(u[4], &sn, &cs); /* of phi = 2 pi u[4] */
    frame_of(h->n, tt, bb);
    for (int k = 0; k < 3; k++) w[k] = ct * h->n[k] + r * (cs * tt[k] + sn * bb[k]);
    direct_terms(s, h, u, sel, 1, idx, ne, total, w, ct, t);
}

#if SCENE_SIMD
/* Points a step of scene_direct_mis_many: the kernels' arrays on the stack (the
 * selection weights of up to 64 emitters, 32 KB) */
#define MANY 64

/* Lanes past n repeat lane 0 (the kernels take multiples of eight). */
static int pad8(double *X, int n)
{
    int n8 = (n + 7) / 8 * 8;
    for (int i = n; i < n8; i++)
        for (int k = 0; k < 3; k++) X[k * MANY + i] = X[k * MANY];
    return n8;
}

/* Whether emitter o's light sample from p goes in the kernels' lanes: a disk, or a sphere
 * seen from outside (sample_light's branches without a further branch). */
static int in_lanes(const scene_object *o, const double p[3])
{
    if (o->kind == OBJ_DISK) return 1;
    double c[3] = {o->p[0] - p[0], o->p[1] - p[1], o->p[2] - p[2]};
    return o->kind == OBJ_SPHERE && dot3(c, c) > o->r2 * (1 + 1e-12);
}

/* The light samples of c points (try_light): the emitter drawn per point, then the
 * draws on each disk or sphere for all the points that chose it at once
 * (scene_simd_disk_light, scene_simd_sphere_light); points inside a sphere one by one. */
static void light_samples(const scene_t *s, const scene_hit *h, const double *u, int c,
                          const int *idx, size_t ne, const double *tot, const int *J,
                          const double *Pj, light_try *L)
{
    int start[65] = {0}, next[64], list[MANY];
    unsigned char lane[MANY];
    double P[3 * MANY], N[3 * MANY], U1[MANY], U2[MANY], Q[3 * MANY], pdf[MANY], cr[MANY];
    unsigned char sh[MANY];
    for (int i = 0; i < c; i++) {
        lane[i] = 0;
        L[i].shadow = 0;
        if (!(tot[i] > 0)) continue; /* choose_light's draw, made by scene_simd_choose */
        L[i].j = (size_t)J[i], L[i].P = Pj[i];
        lane[i] = L[i].P > 0 && in_lanes(&s->obj[idx[L[i].j]], h[i].p);
        if (lane[i]) start[L[i].j + 1]++;
        else sample_chosen(s, h + i, u + 5 * i, idx, &L[i]);
    }
    /* the lane points in order of their emitter (a counting sort): one pass, not one
     * per emitter */
    for (size_t j = 0; j < ne; j++) start[j + 1] += start[j], next[j] = start[j];
    for (int i = 0; i < c; i++)
        if (lane[i]) list[next[L[i].j]++] = i;
    for (size_t j = 0; j < ne; j++) {
        int n = start[j + 1] - start[j];
        const int *lj = list + start[j];
        if (!n) continue;
        for (int l = 0; l < n; l++) {
            int i = lj[l];
            for (int k = 0; k < 3; k++) P[k * MANY + l] = h[i].p[k], N[k * MANY + l] = h[i].n[k];
            U1[l] = u[5 * i + 1], U2[l] = u[5 * i + 2];
        }
        for (int l = n; l < (n + 7) / 8 * 8; l++) U1[l] = U1[0], U2[l] = U2[0];
        pad8(P, n);
        const scene_object *o = &s->obj[idx[j]];
        if (o->kind == OBJ_DISK)
            scene_simd_disk_light(o, pad8(N, n), MANY, P, N, U1, U2, Q, pdf, cr, sh);
        else
            scene_simd_sphere_light(o, pad8(N, n), MANY, P, N, U1, U2, Q, pdf, cr, sh);
        for (int l = 0; l < n; l++) {
            light_try *Li = &L[lj[l]];
            for (int k = 0; k < 3; k++) Li->q[k] = Q[k * MANY + l];
            Li->pdf = pdf[l], Li->cr = cr[l], Li->shadow = sh[l];
        }
    }
}

/* The rays of c points' direct light (as direct_terms), each kind for all at once: the
 * light samples, then their shadow rays, then the BSDF rays (direction W, cosine ct). */
static void many_rays(const scene_t *s, const scene_hit *h, const double *u, int c,
                      const double *sel, const int *idx, size_t ne, const double *W,
                      const double *ct, scene_light_terms *t)
{
    light_try L[MANY];
    double tot[MANY], A[3 * MANY], B[3 * MANY], tb[MANY];
    int list[MANY], which[MANY], ns = 0, nb = 0;
    unsigned char vis[MANY];
    /* the emitters' sum and the light sample's choice, eight points a step; A holds the
     * selection uniforms, then the choices' probabilities */
    for (int i = 0; i < (c + 7) / 8 * 8; i++) A[i] = u[5 * (i < c ? i : 0)];
    scene_simd_choose((int)ne, (c + 7) / 8 * 8, MANY, sel, A, tot, which, A + MANY);
    light_samples(s, h, u, c, idx, ne, tot, which, A + MANY, L);
    for (int i = 0; i < c; i++) {
        if (!L[i].shadow) continue;
        for (int k = 0; k < 3; k++) A[k * MANY + ns] = h[i].p[k], B[k * MANY + ns] = L[i].q[k];
        list[ns++] = i;
    }
    if (ns) {
        pad8(A, ns);
        scene_simd_visible(s, pad8(B, ns), MANY, A, B, vis);
    }
    for (int i = 0; i < c; i++) t[i].n = 0;
    for (int k = 0; k < ns; k++)
        if (vis[k]) light_term(&L[list[k]], idx, &t[list[k]]);
    for (int i = 0; i < c; i++) {
        if (!(ct[i] > 0)) continue;
        for (int k = 0; k < 3; k++) A[k * MANY + nb] = h[i].p[k], B[k * MANY + nb] = W[k * MANY + i];
        list[nb++] = i;
    }
    if (nb) {
        pad8(A, nb);
        scene_simd_emitter(s, pad8(B, nb), MANY, A, B, which, tb);
    }
    for (int k = 0, i; k < nb; k++) {
        i = list[k];
        double w[3] = {W[i], W[MANY + i], W[2 * MANY + i]}, o[3] = {h[i].p[0], h[i].p[1], h[i].p[2]};
        scene_hit g;
        if (which[k] < 0) continue;
        scene_fill_hit(s, which[k], tb[k], o, w, &g);
        bsdf_term(s, h + i, sel + i, MANY, idx, ne, tot[i], w, ct[i], &g, &t[i]);
    }
}

/* scene_direct_mis_many in the kernels' lanes, MANY points a step */
static void many_points(const scene_t *s, int m, const scene_hit *h, const double *u,
                        scene_light_terms *t)
{
    int idx[64];
    size_t ne = emitters_of(s, idx);
    double P[3 * MANY], N[3 * MANY], u3[MANY], u4[MANY], W[3 * MANY], ct[MANY], sel[64 * MANY];
    for (int i0 = 0; i0 < m; i0 += MANY) {
        int c = m - i0 < MANY ? m - i0 : MANY, c8 = (c + 7) / 8 * 8;
        for (int i = 0; i < c8; i++) { /* lanes past c repeat the first point */
            const scene_hit *hi = h + i0 + (i < c ? i : 0);
            const double *ui = u + 5 * (size_t)(i0 + (i < c ? i : 0));
            for (int k = 0; k < 3; k++) P[k * MANY + i] = hi->p[k], N[k * MANY + i] = hi->n[k];
            u3[i] = ui[3], u4[i] = ui[4];
        }
        for (size_t j = 0; j < ne; j++) {
            const scene_object *o = &s->obj[idx[j]];
            if (o->kind == OBJ_SPHERE || o->kind == OBJ_DISK)
                scene_simd_select(o, c8, MANY, P, N, sel + j * MANY);
            else
                for (int i = 0; i < c8; i++) sel[j * MANY + i] = 0;
        }
        scene_simd_bsdf_dir(c8, MANY, N, u3, u4, W, ct);
        many_rays(s, h + i0, u + 5 * (size_t)i0, c, sel, idx, ne, W, ct, t + i0);
    }
}
#endif

void scene_direct_mis_many(const scene_t *s, int m, const scene_hit *h, const double *u,
                           scene_light_terms *t)
{
#if SCENE_SIMD
    if (scene_simd_ok()) {
        many_points(s, m, h, u, t);
        return;
    }
#endif
    for (int i = 0; i < m; i++) scene_direct_mis(s, h + i, u + 5 * i, t + i);
}
