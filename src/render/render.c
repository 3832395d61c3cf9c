/* The camera-ray estimator of the supplement (Section 1, Eq. 1-13) and the render loop.
 *
 * What a pixel measures: its mean irradiance,
 *   I_j = integral over the pixel and the hemisphere of W_e L(s0, w0) cos(theta_s0) dw0 dA(s0),
 *   W_e = 1 / A_pixel,
 * where L(s0, w0) is the radiance arriving at sensor point s0 from direction w0 through
 * the lens: T_r times the radiance that leaves the scene point s1 towards the front
 * element point s_f (air on both sides of the lens, so radiance is not rescaled).
 *
 * Eq. 13 of the supplement, term by term, and where each one is in this file:
 *   1/N sum            spp samples per pixel, the mean in render_image.c (N counts rays
 *                      that fail the lens too: they score 0).
 *   W_e / p_A(s0)      = 1: s0 is uniform over the pixel, p_A(s0) = 1/A_pixel = W_e
 *                      (with a tent filter, W_e is the filter and s0 is drawn from it).
 *   P_a                the return value of cam->map (exact: the tracer's status;
 *                      polynomial: the system's pass circles). See render_image.c.
 *   T_r                eta from cam->map when job->use_eta, else the constant
 *                      job->eta_const (the lens's mean transmittance when the scene
 *                      leaves out its variation). See render_image.c.
 *   L                  radiance from s1 towards s_f: L_e if s1 is on an emitter (seen
 *                      directly), else the direct light of scene_direct_mis (one light
 *                      and BSDF sample, combined by MIS: scene_light.c).
 *   p_A(s0')           the line pupil is the plane 1 mm in front of the sensor, where
 *                      s0' = s0 + (u, v, -1) mm; its area measure is du dv, so
 *                      p_A(s0') = p(u, v), the sampler's density (render_sampler.c).
 *   |J_all| |A|        cancel between G-bar (Eq. 12) and p_A(s1) (Eq. 8), as Eq. 13 shows:
 *                      the default weight evaluates neither. --estimator full
 *                      (RENDER_ESTIMATOR_FULL, render_full_weight, render_full.c)
 *                      evaluates both, each from its own terms; they cancel to within
 *                      the lens map's conservation of etendue (tests/unit/render/
 *                      test_render_full.c).
 *   cos(theta_s0) cos^2(theta_s1) cos(theta_sf) / (cos^2(theta_s0') |s_f - s1|^2)
 *                      the remaining geometry. Eq. 5 writes ds1/ds_f as a function of s_f
 *                      alone (cos^2 theta_sf / cos^2 theta_s1), while G (Eq. 10) is
 *                      cos theta_sf / |s_f - s1|^2; done as one exact change of variables
 *                      s0' -> (ray at s_f) -> s1, the same Jacobian of s1 enters G-bar
 *                      and p_A(s1) and every s1- and s_f-factor cancels. What remains is
 *                      the solid angle at s0 seen through the line pupil:
 *                        cos(theta_s0) dw0 = cos(theta_s0) cos(theta_s0') / |s0' - s0|^2 dA(s0')
 *                      and with the pupil plane parallel to the sensor at 1 mm,
 *                      cos(theta_s0') = cos(theta_s0) and |s0' - s0| = 1 / cos(theta_s0):
 *                        = cos^4(theta_s0) du dv.
 *   So one camera ray scores  P_a T_r L cos^4(theta_s0) / p(u, v)   (render_ray_weight),
 *   with cos(theta_s0) = 1 / sqrt(1 + u^2 + v^2). tests/unit/render/test_render.c checks this
 *   weight against a finite-difference solid angle, and the whole estimator against the
 *   closed-form irradiance behind a circular aperture and against rear-element sampling.
 *
 * The full estimator is in render_full.c.
 */
#include "sparselens/render.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void render_lens_to_scene(const double l[3], double s[3])
{
    s[0] = -l[0];
    s[1] = l[1];
    s[2] = -l[2];
}

double render_ray_weight(double u, double v, double pdf_uv, double eta)
{
    double c2 = 1 / (1 + u * u + v * v); /* cos^2(theta_s0) */
    return eta * c2 * c2 / pdf_uv;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double render_noise(int width, int height, const float *a, const float *b)
{
    size_t n = (size_t)width * height, m = 0;
    double *r = malloc((n ? n : 1) * sizeof *r), *rv = malloc((n ? n : 1) * sizeof *rv);
    if (!r || !rv) {
        free(r);
        free(rv);
        return NAN;
    }
    for (size_t i = 0; i < n; i++) {
        double s = 0;
        int lit = 0;
        for (int c = 0; c < 3; c++) {
            double x = a[3 * i + c], y = b[3 * i + c], mean = 0.5 * (x + y);
            if (mean > 0) s += 0.5 * (x - y) * (x - y) / (mean * mean), lit++;
        }
        r[i] = lit ? s / lit : -1;
    }
    for (int py = 0; py < height; py++)
        for (int px = 0; px < width; px++) {
            if (r[(size_t)py * width + px] < 0) continue;
            double s = 0;
            int k = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int x = px + dx, y = py + dy;
                    if (x < 0 || y < 0 || x >= width || y >= height) continue;
                    double q = r[(size_t)y * width + x];
                    if (q >= 0) s += q, k++;
                }
            rv[m++] = s / k;
        }
    double med = NAN;
    if (m) {
        qsort(rv, m, sizeof *rv, cmp_double);
        med = m % 2 ? rv[m / 2] : 0.5 * (rv[m / 2 - 1] + rv[m / 2]);
    }
    free(r);
    free(rv);
    return med;
}
