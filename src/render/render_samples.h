#ifndef RENDER_RENDER_SAMPLES_H
#define RENDER_RENDER_SAMPLES_H
/* Low-discrepancy sample points for one pixel's n camera samples (render_samples.c).
 *
 * Each dimension pair of sample k is point perm_d(k) of the first two Sobol dimensions
 * (a (0, 2)-sequence: for n a power of two, every elementary interval of area 1/n holds
 * one point), Owen-scrambled: a random but stratification-keeping flip of each binary
 * digit, keyed per pixel and dimension. A single dimension is jittered stratification:
 * stratum perm_d(k) of n, a random point within it. perm_d is a pseudo-random
 * permutation of [0, n) and the rotation a pseudo-random shift, both keyed by (pixel
 * seed, dimension): the permutation decorrelates the dimension pairs from each other
 * (without it the pupil point would be a function of the pixel point), and the
 * scramble makes every sample uniformly distributed, so each pixel's estimate stays
 * unbiased. */
#include <stdint.h>

/* A key per pixel from the scene's seed and the pixel index. */
uint64_t ld_pixel_key(uint64_t seed, uint64_t pixel);

/* The keys of a pixel's dimensions, derived once per pixel (LD_DIMS pairs and singles). */
#define LD_DIMS 4
/* a permutation's key and the three words permute derives from it (made once a pixel) */
typedef struct {
    uint64_t k1, m2, k3, m1;
} ld_perm;
typedef struct {
    ld_perm perm2[LD_DIMS], perm1[LD_DIMS];
    uint64_t scr_a[LD_DIMS], scr_b[LD_DIMS], jit1[LD_DIMS];
} ld_pixel;
void ld_pixel_init(ld_pixel *p, uint64_t key);
/* As ld_2d and ld_1d, for dim < LD_DIMS, with the pixel's keys. */
void ld_2d_px(const ld_pixel *p, int dim, uint64_t n, uint64_t k, double out[2]);
/* Two pairs of one sample at once (a, b: dimensions dim_a, dim_b), as two ld_2d_px. */
void ld_2d_px2(const ld_pixel *p, int dim_a, int dim_b, uint64_t n, uint64_t k, double a[2],
               double b[2]);
double ld_1d_px(const ld_pixel *p, int dim, uint64_t n, uint64_t k);
/* ld_2d_px and ld_1d_px for samples k0 .. k0 + count - 1 of the pixel (as many calls,
 * the same values, four samples at a time), sample c's values at out + c * stride. */
void ld_2d_run(const ld_pixel *p, int dim, uint64_t n, uint64_t k0, int count, double *out,
               int stride);
void ld_1d_run(const ld_pixel *p, int dim, uint64_t n, uint64_t k0, int count, double *out,
               int stride);
/* Sample k of n in dimension pair dim (its two coordinates in [0, 1)). */
void ld_2d(uint64_t key, int dim, uint64_t n, uint64_t k, double out[2]);
/* Sample k of n in the single dimension dim. */
double ld_1d(uint64_t key, int dim, uint64_t n, uint64_t k);

#endif
