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
 *                      (RENDER_ESTIMATOR_FULL, render_full_weight) evaluates both, and
 *                      tests/unit/render/test_render_full.c shows the weights agree to rounding.
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
 * The full estimator (render_full_weight), Eq. 3 = L W_e G-bar / (p_A(s0) p_A(s1)), with
 * the chain of Eq. 5-7 made exact for this parametrisation:
 *   s0' -> s_f   |A| = |det d(out_x, out_y) / d(u, v)| at fixed s0 (the pupil point moves
 *                by (du, dv) mm), from the system's Jacobian (poly_eval_jacobian; the
 *                exact map: central differences of the tracer). The supplement's block
 *                d(out_x, out_y) / d(x, y) is taken at fixed (u, v), along which a camera
 *                sample does not move; tests compare both blocks with the exact tracer.
 *                |J_all|: area on the front element per d out_x d out_y (its sag; the
 *                lens-to-scene half turn has determinant 1), from the frames.
 *   s_f -> s1    |ds1/dsf|: the ray field over the front element, d(ray)/d(out_x, out_y)
 *                = d(ray)/d(u, v) A^-1, carried to the scene surface at s1 (projected
 *                along the ray onto its tangent plane). Eq. 5's closed form
 *                cos^2(theta_sf) / cos^2(theta_s1) leaves out the distance and the
 *                spread of the ray field; here the Jacobian is computed. Needs A
 *                invertible: where |A| = 0 the chain breaks (Eq. 13 is used, counted).
 *   Eq. 8        p_A(s1) = p_A(s0') / (|ds1/dsf| |J_all| |A|) (the supplement writes the
 *                Jacobian as a factor; a density divides by it);
 *   Eq. 12       G-bar = P_a T_r cos(theta_s0) cos(theta_s0') / |s0' - s0|^2 /
 *                (|J_all| |A| |ds1/dsf|), the projected solid angle at s0 per area at s1
 *                (equal, by the conservation of etendue, to dw_perp(s1) / dA(s0)).
 *   Their ratio is Eq. 13's weight; the factors are exposed in render_full_terms.
 */
#include "sparselens/render.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/glass.h"
#include "sparselens/trace.h"

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

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double cross_norm(const double a[3], const double b[3])
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
    return sqrt(x * x + y * y + z * z);
}

int render_full_weight(const lens_t *lens, const double in[5], const double o[4],
                       const double jac[16], double pdf, double eta, const double s1[3],
                       const double n1[3], render_full_terms *t)
{
    memset(t, 0, sizeof *t);
    /* |A|: the line-pupil point s0' = s0 + (u, v, -1) mm moves by (du, dv) mm at fixed s0 */
    double a00 = jac[0 * 4 + 2], a01 = jac[0 * 4 + 3], a10 = jac[1 * 4 + 2], a11 = jac[1 * 4 + 3];
    double detA = a00 * a11 - a01 * a10;
    t->A = fabs(detA);
    /* the frames: the ray (s_f, d) leaving the front element as a function of o, by
     * central differences of ray_from_outer (steps 1e-5 mm and 1e-6) */
    lens_ray r, rp, rm;
    if (!(t->A > 0) || ray_from_outer(lens, o, &r)) return -1;
    double D[4][6];
    for (int k = 0; k < 4; k++) {
        double h = k < 2 ? 1e-5 : 1e-6, op[4] = {o[0], o[1], o[2], o[3]},
               om[4] = {o[0], o[1], o[2], o[3]};
        op[k] += h, om[k] -= h;
        if (ray_from_outer(lens, op, &rp) || ray_from_outer(lens, om, &rm)) return -1;
        for (int j = 0; j < 3; j++) {
            D[k][j] = (rp.o[j] - rm.o[j]) / (2 * h);
            D[k][3 + j] = (rp.d[j] - rm.d[j]) / (2 * h);
        }
    }
    /* everything in the scene frame (a rotation: lengths and areas stay) */
    double Tx[3], Ty[3], sf[3], d[3];
    render_lens_to_scene(D[0], Tx);
    render_lens_to_scene(D[1], Ty);
    render_lens_to_scene(r.o, sf);
    render_lens_to_scene(r.d, d);
    /* |J_all|: area on the front element per d out_x d out_y (its sag tilts it) */
    t->J_all = cross_norm(Tx, Ty);
    /* the ray field over the front element at fixed s0: d d / d(out_x, out_y) =
     * (d d / d(u, v)) A^-1, with d d / d(u, v) = sum_k (d d / d o_k) (d o_k / d(u, v)) */
    double ddu[3] = {0, 0, 0}, ddv[3] = {0, 0, 0}, dl[2][3];
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 3; j++) {
            ddu[j] += D[k][3 + j] * jac[4 * k + 2];
            ddv[j] += D[k][3 + j] * jac[4 * k + 3];
        }
    render_lens_to_scene(ddu, dl[0]);
    render_lens_to_scene(ddv, dl[1]);
    double ddx[3], ddy[3]; /* A^-1 = [a11 -a01; -a10 a00] / detA */
    for (int j = 0; j < 3; j++) {
        ddx[j] = (dl[0][j] * a11 - dl[1][j] * a10) / detA;
        ddy[j] = (-dl[0][j] * a01 + dl[1][j] * a00) / detA;
    }
    /* s1 = s_f + tau d on the scene surface: moving s_f moves s1 by P (ds_f + tau dd),
     * P projecting along d onto the surface's tangent plane */
    double q[3] = {s1[0] - sf[0], s1[1] - sf[1], s1[2] - sf[2]};
    double tau = dot3(q, d), nd = dot3(n1, d);
    if (!(fabs(nd) > 0)) return -1;
    double e1[3], e2[3];
    for (int j = 0; j < 3; j++) e1[j] = Tx[j] + tau * ddx[j], e2[j] = Ty[j] + tau * ddy[j];
    double p1 = dot3(n1, e1) / nd, p2 = dot3(n1, e2) / nd;
    for (int j = 0; j < 3; j++) e1[j] -= d[j] * p1, e2[j] -= d[j] * p2;
    t->ds1_dsf = cross_norm(e1, e2) / t->J_all;
    /* Eq. 8: p_A(s1) = p_A(s0') / |d s1 / d s0'|, |d s1 / d s0'| = |ds1/dsf| |J_all| |A| */
    double u = in[2], v = in[3];
    t->cos_s0 = 1 / sqrt(1 + u * u + v * v);
    t->cos_s0p = t->cos_s0; /* the pupil plane is parallel to the sensor */
    double dist2 = 1 + u * u + v * v; /* |s0' - s0|^2, mm^2 */
    double jac_s1 = t->ds1_dsf * t->J_all * t->A;
    t->pA_s1 = pdf / jac_s1;
    /* Eq. 12: cos(theta_s0) dw_s0 / dA(s1), dw_s0 = cos(theta_s0') dA(s0') / |s0' - s0|^2 */
    t->G = t->cos_s0 * t->cos_s0p / dist2 / jac_s1;
    /* Eq. 3 with W_e / p_A(s0) = 1 */
    t->weight = eta * t->G / t->pA_s1;
    return isfinite(t->weight) && t->weight > 0 && isfinite(t->pA_s1) && t->pA_s1 > 0 ? 0 : -1;
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
