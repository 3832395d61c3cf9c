#ifndef RENDER_RENDER_LENS_SIMD_H
#define RENDER_RENDER_LENS_SIMD_H
/* The polynomial path's camera rays at the front surface eight at a time
 * (render_lens_simd.c): render_lens.c's front_ray on a spherical front surface (curvature
 * c, vertex at z0, kc = (1 + conic) c^2 with conic 0), each lane its operations in order, so the
 * rays are front_ray's bit for bit. X holds the outer-pupil points (x y u v, coordinate
 * k of ray i at X[k * stride + i]), O and D the rays' origins and directions likewise;
 * status[i] is 0 for a ray, 1 where front_ray fails (u^2 + v^2 > 1), 2 where front_ray
 * hands the point to ray_from_outer (off the surface's sphere, or not finite). m is a
 * multiple of 8. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define RENDER_LENS_SIMD 1
/* 1 when the kernel may run (AVX-512F) */
int render_lens_simd_ok(void);
void render_simd_front(double c, double kc, double z0, int m, int stride, const double *X,
                       double *O, double *D, unsigned char *status);
#else
#define RENDER_LENS_SIMD 0
#endif

#endif
