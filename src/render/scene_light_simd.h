#ifndef RENDER_SCENE_LIGHT_SIMD_H
#define RENDER_SCENE_LIGHT_SIMD_H
/* The direct light's per-point arithmetic that does not branch on the point
 * (scene_light_simd.c): eight points at a time in AVX-512 registers where the processor
 * has them. Each lane does the operations of scene_light.c's scalar code in the same
 * order (sums, products, quotients and square roots rounded alike; no fused multiply-add:
 * the build contracts none), so a block's values are those of the per-point code, bit for
 * bit. Arrays are structure of arrays: coordinate k of point i at X[k * stride + i]; m is
 * a multiple of 8. */
#include "sparselens/scene.h"

/* 1 when the kernels below may run (AVX-512F present and compiled for). */
int scene_simd_ok(void);

/* The hit record of object which at ray parameter t of (o, d), as the intersection
 * functions fill it (scene_geometry.c). */
void scene_fill_hit(const scene_t *s, int which, double t, const double o[3], const double d[3],
                    scene_hit *hit);

/* Compiled for x86-64 by GCC or clang; elsewhere scene_light.c goes point by point. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define SCENE_SIMD 1

/* The selection weight (scene_light.c's select_weight) of emitter o at the m points P
 * with unit normals N, into sel[i]. */
void scene_simd_select(const scene_object *o, int m, int stride, const double *P, const double *N,
                       double *sel);

/* The light sample's choice at m points from the selection weights of ne emitters
 * (sel[e * stride + i]) and the uniforms u0: the weights' sum into total, the emitter
 * drawn (scene_light.c's choose_light) into j, its probability into P. */
void scene_simd_choose(int ne, int m, int stride, const double *sel, const double *u0,
                       double *total, int *j, double *P);

/* The BSDF sample's direction (cosine-weighted about N from the uniforms u3, u4) into W,
 * its cosine into ct. */
void scene_simd_bsdf_dir(int m, int stride, const double *N, const double *u3, const double *u4,
                         double *W, double *ct);

/* The light sample on disk o from the m points P (normals N) with the uniforms U1, U2
 * (scene_light.c's sample_light and light_pdf): its end Q, pdf, the cosine cr at the
 * point, and shadow[i] = 1 where its shadow ray decides the term (pdf > 0, cr > 0, the
 * disk faces the point). */
void scene_simd_disk_light(const scene_object *o, int m, int stride, const double *P,
                           const double *N, const double *U1, const double *U2, double *Q,
                           double *pdf, double *cr, unsigned char *shadow);

/* The same on sphere o from points outside it (d^2 > r^2 (1 + 1e-12)): a direction in
 * the cone the sphere fills (sample_light's first branch). */
void scene_simd_sphere_light(const scene_object *o, int m, int stride, const double *P,
                             const double *N, const double *U1, const double *U2, double *Q,
                             double *pdf, double *cr, unsigned char *shadow);

/* scene_visible(s, A_i, B_i) for the m segments, into vis[i]. */
void scene_simd_visible(const scene_t *s, int m, int stride, const double *A, const double *B,
                        unsigned char *vis);

/* scene_intersect_emitter(s, O_i, D_i, 1e-6): the emitter reached (-1: none, or a
 * non-emitter in front) into which[i], its ray parameter into t[i]. */
void scene_simd_emitter(const scene_t *s, int m, int stride, const double *O, const double *D,
                        int *which, double *t);

/* The nearest hit of the m rays (O_i, D_i) beyond tmin over the scene's planes and disks
 * and then its spheres, each in the scene's order (scene_intersect_listed with every
 * sphere listed): the object (-1: none) into which[i], the ray parameter into t[i]. */
void scene_simd_camera(const scene_t *s, int m, int stride, const double *O, const double *D,
                       double tmin, int *which, double *t);
#else
#define SCENE_SIMD 0
#endif

#endif
