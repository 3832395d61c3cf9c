#ifndef RENDER_RENDER_SAMPLES_H
#define RENDER_RENDER_SAMPLES_H
/* Low-discrepancy sample points for one pixel's n camera samples (render_samples.c).
 *
 * Each dimension pair (or single dimension) of sample k is point perm_d(k) of a rank-1
 * lattice sequence, Cranley-Patterson rotated: the R2 sequence (Roberts 2018) in 2D,
 * the golden-ratio sequence in 1D. The first n points of either are stratified for any
 * n, so the pixel's n samples cover each 2D projection evenly. perm_d is a pseudo-random
 * permutation of [0, n) and the rotation a pseudo-random shift, both keyed by (pixel
 * seed, dimension): they decorrelate the dimensions from each other (without them the
 * pupil point would be a fixed shift of the pixel point) and make every sample
 * uniformly distributed, so each pixel's estimate stays unbiased. */
#include <stdint.h>

/* A key per pixel from the scene's seed and the pixel index. */
uint64_t ld_pixel_key(uint64_t seed, uint64_t pixel);
/* Sample k of n in dimension pair dim (its two coordinates in [0, 1)). */
void ld_2d(uint64_t key, int dim, uint64_t n, uint64_t k, double out[2]);
/* Sample k of n in the single dimension dim. */
double ld_1d(uint64_t key, int dim, uint64_t n, uint64_t k);

#endif
