/* The full estimator of the supplement (render.h's RENDER_ESTIMATOR_FULL):
 * Eq. 3 = L W_e G-bar / (p_A(s0) p_A(s1)), W_e / p_A(s0) = 1, with G-bar (Eq. 12) and
 * p_A(s1) (Eq. 8) each computed from its own terms, so that their ratio is Eq. 13's
 * weight only where the lens map conserves etendue (exactly for the tracer, to the
 * fit's accuracy for a system): it checks Eq. 13 instead of restating it.
 *
 * Both are built on the ray leaving the front element, (s_f, d), and its derivatives
 * over the sensor ray in = (x, y, u, v): the lens map's Jacobian d o / d in (the
 * system's poly_eval_jacobian; the exact map: central differences of the tracer) times
 * the frames' d (s_f, d) / d o (central differences of ray_from_outer). They hold the
 * two different points of the path fixed:
 *
 *   Eq. 8, s0 fixed (the camera sample moves the line-pupil point s0' = s0 + (u, v, -1)
 *   mm by (du, dv) mm):
 *     |A|       = |det d(out_x, out_y) / d(u, v)|, line pupil -> front element;
 *     |J_all|   area on the front element per d out_x d out_y (its sag; the lens-to-scene
 *               half turn has determinant 1);
 *     |ds1/dsf| the ray field over the front element, d(ray)/d(out_x, out_y) =
 *               d(ray)/d(u, v) A^-1, carried to the scene surface at s1 (projected along
 *               the ray onto its tangent plane). Eq. 5's closed form cos^2(theta_sf) /
 *               cos^2(theta_s1) leaves out the distance and the spread of the ray field.
 *     p_A(s1) = p_A(s0') / (|ds1/dsf| |J_all| |A|): the supplement writes the Jacobian
 *               as a factor; a density divides by it.
 *
 *   Eq. 12, s1 fixed (G is Eq. 10's d w_perp(s1) / dA(s0): the sensor point moves, and
 *   the ray from it that still reaches s1 sweeps the front element):
 *     |A_s1|    = |det d(out_x, out_y) / d(x, y)| along the rays through s1: (u, v) follow
 *               (x, y) so that the ray keeps meeting s1. The supplement takes the block at
 *               fixed (u, v), along which the ray leaves s1 (tests compare);
 *     G-bar   = P_a T_r |J_all| |A_s1| cos(theta_sf) cos(theta_s1) / |s_f - s1|^2: the
 *               area swept on the front element per sensor area, the solid angle it
 *               subtends at s1, projected on s1's surface. Eq. 12 has no cos(theta_s1)
 *               and divides by cos(theta_s0), a sensor area measured across the ray: with
 *               W_e per sensor area (render.c) the projection belongs at s1, where Eq. 10
 *               puts the perp.
 *
 * Their ratio G-bar / p_A(s1) = P_a T_r cos^4(theta_s0) / p(u, v) is etendue
 * conservation, cos(theta_s0) dw_s0 dA(s0) = cos(theta_s1) dw_s1 dA(s1), with
 * cos(theta_s0) dw_s0 = cos^4(theta_s0) du dv (render.c).
 * Where a chain breaks (|A| = 0, or s1 exactly in focus so that no sensor motion keeps
 * the ray on it) the caller falls back to Eq. 13 and counts it. */
#include "sparselens/render.h"

#include <math.h>
#include <string.h>

#include "sparselens/trace.h"

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

static double cross_norm(const double a[3], const double b[3])
{
    double c[3];
    cross3(a, b, c);
    return sqrt(dot3(c, c));
}

/* The ray leaving the front element and its derivatives, in the scene frame. */
typedef struct {
    double sf[3], d[3];
    double Tx[3], Ty[3];        /* d s_f / d(out_x, out_y): the front element's tangents */
    double dsf[4][3], dd[4][3]; /* d s_f / d in_i, d d / d in_i over in = (x, y, u, v) */
} front_ray;

static int front_ray_eval(const lens_t *lens, const double o[4], const double jac[16], front_ray *f)
{
    lens_ray r, rp, rm;
    if (ray_from_outer(lens, o, &r)) return -1;
    double D[4][6]; /* d (s_f, d) / d o_k, steps 1e-5 mm and 1e-6 */
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
    render_lens_to_scene(r.o, f->sf);
    render_lens_to_scene(r.d, f->d);
    render_lens_to_scene(D[0], f->Tx);
    render_lens_to_scene(D[1], f->Ty);
    for (int i = 0; i < 4; i++) {
        double ps[3] = {0, 0, 0}, pd[3] = {0, 0, 0};
        for (int k = 0; k < 4; k++)
            for (int j = 0; j < 3; j++) {
                ps[j] += D[k][j] * jac[4 * k + i];
                pd[j] += D[k][3 + j] * jac[4 * k + i];
            }
        render_lens_to_scene(ps, f->dsf[i]);
        render_lens_to_scene(pd, f->dd[i]);
    }
    return 0;
}

/* |ds1/dsf| at fixed s0: s1 = s_f + tau d on the scene surface; moving s_f moves s1 by
 * P (ds_f + tau dd), P projecting along d onto the surface's tangent plane. */
static double ds1_dsf_fixed_s0(const front_ray *f, const double jac[16], double J_all,
                               const double s1[3], const double n1[3])
{
    double a00 = jac[0 * 4 + 2], a01 = jac[0 * 4 + 3], a10 = jac[1 * 4 + 2], a11 = jac[1 * 4 + 3];
    double detA = a00 * a11 - a01 * a10;
    /* the ray field over the front element: d d / d(out_x, out_y) = (d d / d(u, v)) A^-1 */
    double ddx[3], ddy[3];
    for (int j = 0; j < 3; j++) {
        ddx[j] = (f->dd[2][j] * a11 - f->dd[3][j] * a10) / detA;
        ddy[j] = (-f->dd[2][j] * a01 + f->dd[3][j] * a00) / detA;
    }
    double q[3] = {s1[0] - f->sf[0], s1[1] - f->sf[1], s1[2] - f->sf[2]};
    double tau = dot3(q, f->d), nd = dot3(n1, f->d);
    if (!(fabs(nd) > 0)) return NAN;
    double e1[3], e2[3];
    for (int j = 0; j < 3; j++) e1[j] = f->Tx[j] + tau * ddx[j], e2[j] = f->Ty[j] + tau * ddy[j];
    double p1 = dot3(n1, e1) / nd, p2 = dot3(n1, e2) / nd;
    for (int j = 0; j < 3; j++) e1[j] -= f->d[j] * p1, e2[j] -= f->d[j] * p2;
    return cross_norm(e1, e2) / J_all;
}

/* G (Eq. 10-12) at fixed s1. The ray stays on s1 while the component across d of
 * w = ds_f + tau dd vanishes (tau = |s1 - s_f| along the ray); w's columns W_xy, W_uv
 * over (x, y) and (u, v) then give (du, dv) = K (dx, dy), K = -W_uv^+ W_xy (normal
 * equations of the 3 x 2 system: its columns lie in the plane across d, no basis
 * needed), and the front element's coordinates move by J_xy + J_uv K. */
static int g_fixed_s1(const front_ray *f, const double jac[16], const double s1[3],
                      const double n1[3], render_full_terms *t)
{
    double q[3] = {s1[0] - f->sf[0], s1[1] - f->sf[1], s1[2] - f->sf[2]};
    double tau = dot3(q, f->d), w[4][3];
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 3; j++) w[i][j] = f->dsf[i][j] + tau * f->dd[i][j];
        double along = dot3(w[i], f->d);
        for (int j = 0; j < 3; j++) w[i][j] -= along * f->d[j];
    }
    double m00 = dot3(w[2], w[2]), m01 = dot3(w[2], w[3]), m11 = dot3(w[3], w[3]);
    double det = m00 * m11 - m01 * m01;
    if (!(det > 0)) return -1; /* s1 in focus: the rays through it all come from s0 */
    double K[2][2];
    for (int c = 0; c < 2; c++) {
        double r0 = dot3(w[2], w[c]), r1 = dot3(w[3], w[c]);
        K[0][c] = -(m11 * r0 - m01 * r1) / det;
        K[1][c] = -(-m01 * r0 + m00 * r1) / det;
    }
    double B[2][2];
    for (int k = 0; k < 2; k++)
        for (int c = 0; c < 2; c++)
            B[k][c] = jac[4 * k + c] + jac[4 * k + 2] * K[0][c] + jac[4 * k + 3] * K[1][c];
    t->A_s1 = fabs(B[0][0] * B[1][1] - B[0][1] * B[1][0]);
    double nf[3];
    cross3(f->Tx, f->Ty, nf);
    t->cos_sf = fabs(dot3(nf, f->d)) / sqrt(dot3(nf, nf));
    t->cos_s1 = fabs(dot3(n1, f->d));
    t->dist_f1 = sqrt(dot3(q, q));
    t->G = t->J_all * t->A_s1 * t->cos_sf * t->cos_s1 / (t->dist_f1 * t->dist_f1);
    return 0;
}

int render_full_weight(const lens_t *lens, const double in[5], const double o[4],
                       const double jac[16], double pdf, double eta, const double s1[3],
                       const double n1[3], render_full_terms *t)
{
    memset(t, 0, sizeof *t);
    t->A = fabs(jac[0 * 4 + 2] * jac[1 * 4 + 3] - jac[0 * 4 + 3] * jac[1 * 4 + 2]);
    front_ray f;
    if (!(t->A > 0) || front_ray_eval(lens, o, jac, &f)) return -1;
    t->J_all = cross_norm(f.Tx, f.Ty);
    t->ds1_dsf = ds1_dsf_fixed_s0(&f, jac, t->J_all, s1, n1);
    /* Eq. 8 */
    t->pA_s1 = pdf / (t->ds1_dsf * t->J_all * t->A);
    double u = in[2], v = in[3];
    t->cos_s0 = 1 / sqrt(1 + u * u + v * v);
    t->cos_s0p = t->cos_s0; /* the pupil plane is parallel to the sensor */
    /* Eq. 12 */
    if (g_fixed_s1(&f, jac, s1, n1, t)) return -1;
    /* Eq. 3 with W_e / p_A(s0) = 1 */
    t->weight = eta * t->G / t->pA_s1;
    return isfinite(t->weight) && t->weight > 0 && isfinite(t->pA_s1) && t->pA_s1 > 0 ? 0 : -1;
}
