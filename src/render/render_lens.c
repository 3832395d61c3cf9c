/* Lens maps for the renderer: exact tracing and polynomial systems (render_lens.h). */
#include "sparselens/render_lens.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/glass.h"
#include "sparselens/paraxial.h"
#include "sparselens/trace.h"

#include "render/render_lens_simd.h"

#define LAMBDA_CACHE 4 /* the d line and the three rgb band wavelengths */

struct render_lens_ctx {
    const lens_t *lens;
    const poly_system *sys;
    int nsurf;
    /* exact: indices at the wavelengths used most (grey and rgb modes) */
    double cache_lambda[LAMBDA_CACHE];
    double *cache_n; /* LAMBDA_CACHE x nsurf */
    /* poly: where the inputs and outputs are */
    int nin, nout, in_idx[5], out_idx[5];
    /* an aperture of blades: a regular polygon inscribed in the stop's circle, tested at
     * the ray's stop hit (exact: traced; poly: outputs ap_x ap_y); 0 blades: the circle */
    int blades, ap_idx[2];
    /* the outputs the batch maps read (poly_eval_batch_outputs): out_x .. out_v, then
     * out_eta and ap_x ap_y where they are used, at row places eta_at and ap_at (-1:
     * not read); the passage outputs are only tested, never stored */
    int sel[7], nsel, eta_at, ap_at;
    double blade_n[RENDER_MAX_BLADES][2], apothem;
    /* the front surface for front_ray: curvature, (1 + conic) c^2, vertex z; plain = a
     * conic without aspheric terms (else ray_from_outer) */
    double front_c, front_kc, front_z;
    int front_plain, front_sphere;
};

/* The stop hit (x, y) inside the blades' polygon: within the apothem along every edge's
 * normal. */
static int in_blades(const render_lens_ctx *c, double x, double y)
{
    for (int k = 0; k < c->blades; k++)
        if (x * c->blade_n[k][0] + y * c->blade_n[k][1] > c->apothem) return 0;
    return 1;
}

/* Exact: the ray's stop hit (a trace to the stop) inside the blades. */
static int exact_blades(const render_lens_ctx *c, const double *n, const double in[4])
{
    if (!c->blades) return 1;
    double st[4];
    trace_result t = trace_sample(c->lens, n, TRACE_TO_STOP, in, st);
    return t.status == TRACE_PASSED && in_blades(c, st[0], st[1]);
}

static int poly_blades(const render_lens_ctx *c, const double *y)
{
    return !c->blades || in_blades(c, y[c->ap_idx[0]], y[c->ap_idx[1]]);
}

/* poly_blades on a row of the selected outputs (select_outputs) */
static int sel_blades(const render_lens_ctx *c, const double *row)
{
    return !c->blades || in_blades(c, row[c->ap_at], row[c->ap_at + 1]);
}

/* The outputs the batch maps read, in the order of their rows. */
static void select_outputs(render_lens_ctx *c)
{
    c->nsel = 0;
    for (int k = 0; k < 4; k++) c->sel[c->nsel++] = c->out_idx[k];
    c->eta_at = c->out_idx[4] >= 0 ? c->nsel : -1;
    if (c->eta_at >= 0) c->sel[c->nsel++] = c->out_idx[4];
    c->ap_at = c->blades ? c->nsel : -1;
    if (c->blades) c->sel[c->nsel++] = c->ap_idx[0], c->sel[c->nsel++] = c->ap_idx[1];
}

int render_lens_set_blades(render_lens_ctx *c, int blades, double rotation, lens_err *err)
{
    if (blades && (blades < 3 || blades > RENDER_MAX_BLADES)) {
        lens_errf(err, c->lens->path, 0, "blades: %d is not in 3 .. %d", blades, RENDER_MAX_BLADES);
        return -1;
    }
    if (blades && c->sys) {
        c->ap_idx[0] = poly_output_index(c->sys, "ap_x");
        c->ap_idx[1] = poly_output_index(c->sys, "ap_y");
        if (c->ap_idx[0] < 0 || c->ap_idx[1] < 0) {
            lens_errf(err, poly_lens_path(c->sys), 0, "blades need the system's stop hit "
                      "(outputs ap_x ap_y)");
            return -1;
        }
    }
    c->blades = blades;
    double R = c->lens->surf[c->lens->stop].semi_diameter;
    c->apothem = R * cos(M_PI / (blades ? blades : 1));
    for (int k = 0; k < blades; k++) {
        double a = rotation + (k + 0.5) * 2 * M_PI / blades; /* edge k's normal */
        c->blade_n[k][0] = cos(a), c->blade_n[k][1] = sin(a);
    }
    if (c->sys) select_outputs(c);
    return 0;
}

static void fill_camera(render_camera *cam, render_lens_ctx *c, render_map_fn fn,
                        const lens_t *lens, double sw, double sh)
{
    memset(cam, 0, sizeof *cam);
    cam->map = fn;
    cam->ctx = c;
    cam->sensor_w = sw;
    cam->sensor_h = sh;
    const lens_surface *rear = &lens->surf[lens->nsurf - 1];
    cam->rear_dist = rear->thickness;
    cam->rear_radius = rear->semi_diameter;
    cam->lens = lens;
}

/* Indices at lambda: from the cache when it is one of the usual wavelengths. */
static const double *indices(const render_lens_ctx *c, double lambda, double *scratch)
{
    for (int k = 0; k < LAMBDA_CACHE; k++)
        if (c->cache_lambda[k] == lambda) return c->cache_n + (size_t)k * c->nsurf;
    for (int i = 0; i < c->nsurf; i++)
        scratch[i] = glass_index_unchecked(&c->lens->surf[i].medium, lambda);
    return scratch;
}

static int map_exact(void *ctx, const double in[5], double org[3], double dir[3], double *eta)
{
    const render_lens_ctx *c = ctx;
    double scratch[c->nsurf];
    const double *n = indices(c, in[4], scratch);
    lens_ray r;
    if (!exact_blades(c, n, in)) return 0;
    ray_from_sensor(c->lens, in, &r);
    trace_result res = trace_to_object(c->lens, n, &r, 0);
    if (res.status != TRACE_PASSED) return 0;
    memcpy(org, r.o, sizeof r.o);
    memcpy(dir, r.d, sizeof r.d);
    *eta = res.transmittance;
    return 1;
}

/* Inputs and outputs a camera's system may have (a passage pair per surface that limits
 * the beam: up to 8 of them, render_fit.c). */
#define MAX_IN 16
#define MAX_OUT 24

static int map_poly(void *ctx, const double in[5], double org[3], double dir[3], double *eta)
{
    const render_lens_ctx *c = ctx;
    double x[MAX_IN], y[MAX_OUT];
    for (int i = 0; i < c->nin; i++) x[i] = 0;
    for (int k = 0; k < 5; k++)
        if (c->in_idx[k] >= 0) x[c->in_idx[k]] = in[k];
    if (!poly_eval(c->sys, x, y) || !poly_blades(c, y)) return 0; /* P_a: pass circles, blades */
    double outer[4];
    for (int k = 0; k < 4; k++) outer[k] = y[c->out_idx[k]];
    *eta = c->out_idx[4] >= 0 ? y[c->out_idx[4]] : 1;
    if (!(*eta > 0)) return 0;
    if (*eta > 1) *eta = 1; /* a fitted transmittance may overshoot slightly */
    lens_ray r;
    if (ray_from_outer(c->lens, outer, &r)) return 0;
    memcpy(org, r.o, sizeof r.o);
    memcpy(dir, r.d, sizeof r.d);
    return 1;
}

/* ray_from_outer(c->lens, xyuv) on a front surface without aspheric terms: the sag and
 * its slope share one square root and the constants are made once (lens_sag and
 * lens_sag_slope each find 1 / R and their own root, and sum a zero asphere): value for
 * value. On a sphere (conic 0) the unit normal and the tangent frame need no further root
 * and one quotient (the same ray to rounding). A camera ray of the polynomial path pays
 * this where the exact tracer has its ray already. */
static int front_ray(const render_lens_ctx *c, const double xyuv[4], lens_ray *r)
{
    double x = xyuv[0], y = xyuv[1], u = xyuv[2], v = xyuv[3], h2 = x * x + y * y;
    double disc = 1.0 - c->front_kc * h2;
    if (!c->front_plain || !(disc > 0) || !isfinite(x) || !isfinite(y))
        return ray_from_outer(c->lens, xyuv, r); /* as before, and -1 where disc <= 0 */
    double w2 = 1.0 - u * u - v * v;
    if (!(w2 >= 0)) return -1;
    double sq = sqrt(disc), n[3], z;
    if (c->front_sphere) { /* the unit normal is (c x, c y, -sqrt(disc)) as it stands */
        n[0] = c->front_c * x, n[1] = c->front_c * y, n[2] = -sq;
        z = c->front_c * h2 * (1 / (1 + sq));
    } else {
        double sl = c->front_c / (2.0 * sq) + 0.0, a = 2.0 * x * sl, b = 2.0 * y * sl;
        double inv = 1.0 / sqrt(a * a + b * b + 1.0);
        n[0] = a * inv, n[1] = b * inv, n[2] = -inv;
        z = c->front_c * h2 / (1.0 + sq) + 0.0;
    }
    double ex[3], ey[3], w = sqrt(w2);
    lens_outer_frame(n, ex, ey); /* n.z < 0 here */
    r->o[0] = x;
    r->o[1] = y;
    r->o[2] = c->front_z + z;
    for (int j = 0; j < 3; j++) r->d[j] = u * ex[j] + v * ey[j] + w * n[j];
    return 0;
}

static void map_exact_batch(void *ctx, size_t n, const double *in, double *org, double *dir,
                            double *eta, unsigned char *pass)
{
    for (size_t r = 0; r < n; r++)
        pass[r] = (unsigned char)map_exact(ctx, in + 5 * r, org + 3 * r, dir + 3 * r, eta + r);
}

/* The batch maps go POLY_CHUNK rays a call, a whole block of lens-render's
 * (render_image.c's 512 samples): a call's set-up is small now (scratch on the stack),
 * but long calls keep the kernel in its widest blocks. */
#define POLY_CHUNK 512

/* The system's input rows of m camera samples (x y u v lambda each). */
static void poly_inputs(const render_lens_ctx *c, size_t m, const double *in, double *x)
{
    for (size_t r = 0; r < m; r++) {
        double *row = x + r * c->nin;
        for (int i = 0; i < c->nin; i++) row[i] = 0;
        for (int k = 0; k < 5; k++)
            if (c->in_idx[k] >= 0) row[c->in_idx[k]] = in[5 * r + k];
    }
}

/* Outer-pupil coordinates and their Jacobian, for the full estimator (render.h).
 * Exact: central differences of the tracer (steps 1e-5 mm in x, y and 1e-6 in u, v:
 * rounding and truncation both near 1e-10 relative); a step the lens blocks leaves the
 * Jacobian unknown (-1). */
static int exact_outer(const render_lens_ctx *c, const double *n, const double in[4], double o[4],
                       double *eta)
{
    trace_result r = trace_sample(c->lens, n, TRACE_TO_OUTER, in, o);
    *eta = r.transmittance;
    return r.status == TRACE_PASSED && exact_blades(c, n, in);
}

static int outer_exact(void *ctx, const double in[5], double o[4], double jac[16], double *eta)
{
    const render_lens_ctx *c = ctx;
    double scratch[c->nsurf];
    const double *n = indices(c, in[4], scratch);
    if (!exact_outer(c, n, in, o, eta)) return 0;
    if (!jac) return 1;
    for (int i = 0; i < 4; i++) {
        double h = i < 2 ? 1e-5 : 1e-6, a[4], b[4], e;
        double ip[4] = {in[0], in[1], in[2], in[3]}, im[4] = {in[0], in[1], in[2], in[3]};
        ip[i] += h, im[i] -= h;
        if (!exact_outer(c, n, ip, a, &e) || !exact_outer(c, n, im, b, &e)) {
            for (int k = 0; k < 16; k++) jac[k] = NAN;
            return 1;
        }
        for (int k = 0; k < 4; k++) jac[4 * k + i] = (a[k] - b[k]) / (2 * h);
    }
    return 1;
}

/* Polynomial: poly_eval_jacobian, whose outputs and pass flag are poly_eval's. */
static int outer_poly(void *ctx, const double in[5], double o[4], double jac[16], double *eta)
{
    const render_lens_ctx *c = ctx;
    double x[MAX_IN], y[MAX_OUT], J[MAX_OUT * MAX_IN];
    for (int i = 0; i < c->nin; i++) x[i] = 0;
    for (int k = 0; k < 5; k++)
        if (c->in_idx[k] >= 0) x[c->in_idx[k]] = in[k];
    int pass = jac ? poly_eval_jacobian(c->sys, x, y, J) : poly_eval(c->sys, x, y);
    for (int k = 0; k < 4; k++) o[k] = y[c->out_idx[k]];
    *eta = c->out_idx[4] >= 0 ? y[c->out_idx[4]] : 1;
    if (!pass || !(*eta > 0) || !poly_blades(c, y)) return 0;
    if (*eta > 1) *eta = 1; /* as map_poly */
    if (jac)
        for (int k = 0; k < 4; k++)
            for (int i = 0; i < 4; i++) jac[4 * k + i] = J[c->out_idx[k] * c->nin + c->in_idx[i]];
    return 1;
}

/* front_ray for the m rows of the selected outputs y that pass (pass[r] is cleared where
 * it fails), into org and dir: a spherical front surface's rays eight at a time where the
 * processor can (render_simd_front), the rest one by one. */
#define FRONT_STEP 64
static void front_rays(const render_lens_ctx *c, size_t m, const double *y, unsigned char *pass,
                       double *org, double *dir)
{
    size_t r = 0;
#if RENDER_LENS_SIMD
    double X[4 * FRONT_STEP], O[3 * FRONT_STEP], D[3 * FRONT_STEP];
    unsigned char st[FRONT_STEP];
    size_t list[FRONT_STEP];
    while (c->front_sphere && render_lens_simd_ok() && r < m) {
        int n = 0;
        for (; r < m && n < FRONT_STEP; r++) {
            if (!pass[r]) continue;
            for (int k = 0; k < 4; k++) X[k * FRONT_STEP + n] = y[r * c->nsel + k];
            list[n++] = r;
        }
        int n8 = (n + 7) / 8 * 8;
        for (int l = n; l < n8; l++) /* lanes past n repeat lane 0 */
            for (int k = 0; k < 4; k++) X[k * FRONT_STEP + l] = X[k * FRONT_STEP];
        if (n) render_simd_front(c->front_c, c->front_kc, c->front_z, n8, FRONT_STEP, X, O, D, st);
        for (int l = 0; l < n; l++) {
            size_t q = list[l];
            lens_ray ray;
            if (st[l] == 2 && !front_ray(c, y + q * c->nsel, &ray)) { /* off the sphere: as before */
                memcpy(org + 3 * q, ray.o, sizeof ray.o), memcpy(dir + 3 * q, ray.d, sizeof ray.d);
                continue;
            }
            if (st[l]) {
                pass[q] = 0;
                continue;
            }
            for (int k = 0; k < 3; k++) org[3 * q + k] = O[k * FRONT_STEP + l], dir[3 * q + k] = D[k * FRONT_STEP + l];
        }
    }
#endif
    for (; r < m; r++) {
        lens_ray ray;
        if (!pass[r]) continue;
        if (front_ray(c, y + r * c->nsel, &ray)) {
            pass[r] = 0;
            continue;
        }
        memcpy(org + 3 * r, ray.o, sizeof ray.o);
        memcpy(dir + 3 * r, ray.d, sizeof ray.d);
    }
}

/* n rays through the system in chunks: poly_eval_batch_outputs for the pass test and
 * the outputs the maps read (the values and flags of poly_eval, bit for bit); then with
 * jac NULL the rays of map_poly (org, dir), else the outer-pupil values of outer_poly
 * (o) and, by poly_eval_jacobian_batch_outputs, the derivatives of the four alone. */
static void poly_batch(void *ctx, size_t n, const double *in, double *org, double *dir,
                       double *o, double *jac, double *eta, unsigned char *pass)
{
    const render_lens_ctx *c = ctx;
    const size_t chunk = n < POLY_CHUNK ? n : POLY_CHUNK, ni = (size_t)c->nin;
    double *x = malloc(chunk * (ni + c->nsel + (jac ? 4 * ni : 0)) * sizeof *x);
    double *y = x + chunk * ni, *J = y + chunk * c->nsel;
    for (size_t r = 0; !x && r < n; r++) /* no memory: ray by ray, the same values */
        pass[r] = (unsigned char)(jac ? outer_poly(ctx, in + 5 * r, o + 4 * r, jac + 16 * r, eta + r)
                                      : map_poly(ctx, in + 5 * r, org + 3 * r, dir + 3 * r, eta + r));
    for (size_t r0 = 0; x && r0 < n; r0 += chunk) {
        size_t m = n - r0 < chunk ? n - r0 : chunk;
        poly_inputs(c, m, in + 5 * r0, x);
        poly_eval_batch_outputs(c->sys, m, x, c->nsel, c->sel, y, pass + r0);
        if (jac) poly_eval_jacobian_batch_outputs(c->sys, m, x, 4, c->sel, J);
        for (size_t r = 0; r < m; r++) {
            const double *yr = y + r * c->nsel;
            size_t q = r0 + r;
            double e = c->eta_at >= 0 ? yr[c->eta_at] : 1;
            if (!(e > 0) || !sel_blades(c, yr)) pass[q] = 0;
            if (jac) { /* every ray's values, as outer_poly */
                memcpy(o + 4 * q, yr, 4 * sizeof *yr);
                eta[q] = e > 1 ? 1 : e;
                for (int k = 0; k < 4; k++)
                    for (int i = 0; i < 4; i++)
                        jac[16 * q + 4 * k + i] = J[(r * 4 + k) * ni + c->in_idx[i]];
                continue;
            }
            eta[q] = e > 1 ? 1 : e; /* a fitted transmittance may overshoot slightly */
        }
        if (!jac) front_rays(c, m, y, pass + r0, org + 3 * r0, dir + 3 * r0);
    }
    free(x);
}

static void map_poly_batch(void *ctx, size_t n, const double *in, double *org, double *dir,
                           double *eta, unsigned char *pass)
{
    poly_batch(ctx, n, in, org, dir, NULL, NULL, eta, pass);
}

/* The full estimator's lens part for n rays (render.h). */
static void outer_poly_batch(void *ctx, size_t n, const double *in, double *o, double *jac,
                             double *eta, unsigned char *pass)
{
    poly_batch(ctx, n, in, NULL, NULL, o, jac, eta, pass);
}

render_lens_ctx *render_lens_exact(const lens_t *lens, double sw, double sh,
                                   render_camera *cam, lens_err *err)
{
    render_lens_ctx *c = calloc(1, sizeof *c);
    if (c) c->cache_n = malloc(LAMBDA_CACHE * lens->nsurf * sizeof *c->cache_n);
    if (!c || !c->cache_n) {
        render_lens_free(c);
        lens_errf(err, lens->path, 0, "out of memory");
        return NULL;
    }
    c->lens = lens;
    c->nsurf = (int)lens->nsurf;
    /* the d line is required; a band wavelength outside some glass's range is left out
     * of the cache (render_run checks the range a colour scene needs) */
    for (int k = 0; k < LAMBDA_CACHE; k++) {
        double lam = k == 0 ? GLASS_D_LINE : render_channel_lambda(k - 1);
        lens_err e2;
        c->cache_lambda[k] = NAN;
        if (lens_indices(lens, lam, c->cache_n + (size_t)k * c->nsurf, k == 0 ? err : &e2) == 0)
            c->cache_lambda[k] = lam;
        else if (k == 0) {
            render_lens_free(c);
            return NULL;
        }
    }
    fill_camera(cam, c, map_exact, lens, sw, sh);
    cam->map_batch = map_exact_batch;
    cam->outer = outer_exact;
    return c;
}

render_lens_ctx *render_lens_poly(const poly_system *sys, const lens_t *lens, double sw,
                                  double sh, render_camera *cam, lens_err *err)
{
    static const char *const in_names[5] = {"x", "y", "u", "v", "lambda"};
    static const char *const out_names[5] = {"out_x", "out_y", "out_u", "out_v", "out_eta"};
    render_lens_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        lens_errf(err, NULL, 0, "out of memory");
        return NULL;
    }
    c->lens = lens;
    c->sys = sys;
    c->nsurf = (int)lens->nsurf;
    c->nin = poly_ninputs(sys);
    c->nout = poly_noutputs(sys);
    if (c->nin > MAX_IN || c->nout > MAX_OUT) {
        lens_errf(err, poly_lens_path(sys), 0, "system has too many inputs or outputs to render");
        free(c);
        return NULL;
    }
    for (int k = 0; k < 5; k++) {
        c->in_idx[k] = poly_input_index(sys, in_names[k]);
        c->out_idx[k] = poly_output_index(sys, out_names[k]);
        if (k < 4 && (c->in_idx[k] < 0 || c->out_idx[k] < 0)) {
            lens_errf(err, NULL, 0, "the system lacks input '%s' or output '%s' (it must map "
                      "the sensor to the outer pupil)", in_names[k], out_names[k]);
            free(c);
            return NULL;
        }
    }
    select_outputs(c);
    const lens_surface *f = &lens->surf[0];
    c->front_c = isfinite(f->radius) ? 1.0 / f->radius : 0.0; /* as lens_sag's */
    c->front_kc = (1.0 + f->conic) * c->front_c * c->front_c;
    c->front_z = lens->vertex_z[0];
    c->front_plain = 1;
    for (int i = 0; i < LENS_ASPHERE_TERMS; i++) c->front_plain &= f->asphere[i] == 0;
    c->front_sphere = c->front_plain && f->conic == 0;
    fill_camera(cam, c, map_poly, lens, sw, sh);
    cam->map_batch = map_poly_batch;
    cam->outer = outer_poly;
    cam->outer_batch = outer_poly_batch;
    return c;
}

void render_lens_free(render_lens_ctx *c)
{
    if (!c) return;
    free(c->cache_n);
    free(c);
}

int render_lens_setup(lens_t *lens, double focus, double fstop, lens_err *err)
{
    if (!isnan(fstop) && lens_set_fnumber(lens, fstop, err)) return -1;
    if (!isnan(focus)) {
        double t;
        if (paraxial_focus_thickness(lens, GLASS_D_LINE, focus, &t, err)) return -1;
        if (!(t > 0)) {
            lens_errf(err, lens->path, 0, "the lens cannot focus at %g mm", focus);
            return -1;
        }
        lens->surf[lens->nsurf - 1].thickness = t;
        if (lens_finish(lens, err)) return -1;
    }
    return 0;
}
