/* Wavefronts over the pupil: optical path differences by path lengths or by integrating
 * ray errors (wavefront.h). */
#include "sparselens/wavefront.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/paraxial.h"
#include "sparselens/ray_bundle.h"
#include "sparselens/ray_path.h"

void wavefront_free(wavefront *wf)
{
    free(wf->amp);
    free(wf->opd);
    free(wf->sensor);
    free(wf->path);
    memset(wf, 0, sizeof *wf);
}

/* Share of the cell [x0, x0 + h] x [y0, y0 + h] inside the unit disc (8 x 8 samples;
 * cells wholly inside or outside are decided from their corners). */
static double disc_coverage(double x0, double y0, double h)
{
    double nx = fabs(x0) < fabs(x0 + h) ? x0 : x0 + h, ny = fabs(y0) < fabs(y0 + h) ? y0 : y0 + h;
    double fx = fabs(x0) > fabs(x0 + h) ? x0 : x0 + h, fy = fabs(y0) > fabs(y0 + h) ? y0 : y0 + h;
    if (x0 < 0 && x0 + h > 0)
        nx = 0;
    if (y0 < 0 && y0 + h > 0)
        ny = 0;
    if (nx * nx + ny * ny >= 1)
        return 0;
    if (fx * fx + fy * fy <= 1)
        return 1;
    int in = 0;
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++) {
            double x = x0 + (i + 0.5) * h / 8, y = y0 + (j + 0.5) * h / 8;
            in += x * x + y * y <= 1;
        }
    return in / 64.0;
}

/* The exact trace with the optical path: from the start plane (or object point) to the
 * last surface; r ends there with its direction in image space. */
static int trace_path_length(const imaging *im, const double *n, lens_ray *r, double *opl)
{
    /* object at infinity: from the plane through the origin normal to the beam;
     * finite: aim_from_object starts the rays at the object point */
    *opl = isinf(im->object_distance) ? r->d[0] * r->o[0] + r->d[1] * r->o[1] + r->d[2] * r->o[2] : 0;
    if (ray_path(im->lens, n, r, NULL, opl, NULL) != (int)im->lens->nsurf)
        return -1;
    return r->d[2] > 0 ? 0 : -1;
}

/* The pupil's scale in direction cosines per unit of normalised pupil, per axis: the
 * secant between the outermost passing cells of the two central rows (x) or columns
 * (y). The cutoff of the diffraction MTF is set by the beam's marginal rays; a
 * least-squares slope over the whole disc averages the pupil's distortion in and
 * overstates the exit NA where the map from stop to direction is not linear (+1.6% on
 * a telephoto). */
static void scale_fit(wavefront *wf)
{
    int n = wf->n;
    /* the two strips either side of the meridian (one when n is odd): a tilt across a
     * strip cancels between them */
    int strip[2] = {(n - 1) / 2, n / 2}, strips = strip[0] == strip[1] ? 1 : 2;
    for (int a = 0; a < 2; a++) {
        double sum_c[2] = {0, 0}, sum_p[2] = {0, 0}; /* the low and the high end */
        int ends = 0;
        for (int q = 0; q < strips; q++) {
            int first = -1, last = -1;
            for (int i = 0; i < n; i++)
                if (wf->amp[a == 0 ? (size_t)strip[q] * n + i : (size_t)i * n + strip[q]] > 0) {
                    if (first < 0)
                        first = i;
                    last = i;
                }
            if (first < 0 || last == first)
                continue;
            int end[2] = {first, last};
            for (int e = 0; e < 2; e++) {
                size_t k = a == 0 ? (size_t)strip[q] * n + end[e] : (size_t)end[e] * n + strip[q];
                const double *sr = wf->sensor + 4 * k;
                sum_c[e] += -sr[2 + a] / sqrt(1 + sr[2] * sr[2] + sr[3] * sr[3]);
                sum_p[e] += -1 + (end[e] + 0.5) * 2.0 / n;
            }
            ends++;
        }
        wf->scale[a] = ends > 0 ? (sum_c[1] - sum_c[0]) / (sum_p[1] - sum_p[0]) : NAN;
    }
}

static void remove_piston(wavefront *wf)
{
    double sw = 0, s = 0;
    size_t nn = (size_t)wf->n * wf->n;
    for (size_t k = 0; k < nn; k++)
        if (wf->amp[k] > 0)
            sw += wf->amp[k], s += wf->amp[k] * wf->opd[k];
    for (size_t k = 0; k < nn; k++)
        wf->opd[k] = wf->amp[k] > 0 ? wf->opd[k] - s / sw : 0;
}

/* The reference chief ray moved to the plane dz along +z, and the reference point. */
static void reference_point(const wavefront *wf, double dz, double P[3])
{
    P[0] = wf->ref_chief[0] - dz * wf->ref_chief[2];
    P[1] = wf->ref_chief[1] - dz * wf->ref_chief[3];
    P[2] = wf->sensor_z + dz;
}

/* The reference sphere's radius: from the reference point to where the reference chief
 * ray crosses the exit pupil plane. */
static double sphere_radius(const wavefront *wf, const double P[3])
{
    double back = P[2] - wf->exit_z;
    return fabs(back) * sqrt(1 + wf->ref_chief[2] * wf->ref_chief[2] + wf->ref_chief[3] * wf->ref_chief[3]);
}

static int opd_by_path(wavefront *wf, double dz)
{
    double P[3];
    reference_point(wf, dz, P);
    double R = sphere_radius(wf, P);
    size_t nn = (size_t)wf->n * wf->n;
    for (size_t k = 0; k < nn; k++) {
        if (wf->amp[k] <= 0)
            continue;
        const double *q = wf->path + 7 * k;
        double v[3] = {q[0] - P[0], q[1] - P[1], q[2] - P[2]};
        double b = v[0] * q[3] + v[1] * q[4] + v[2] * q[5];
        double disc = b * b - (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + R * R;
        if (!(disc >= 0)) {
            wf->amp[k] = 0;
            continue;
        }
        /* the sphere is met before the reference point, where the converging wave is */
        double t = -b - sqrt(disc);
        wf->opd[k] = q[6] + wf->n_image * t;
    }
    remove_piston(wf);
    return 0;
}

/* Monomial exponents of the fitted OPD, degrees 1 .. WAVEFRONT_DEGREE. */
static int monomials(int e[][2])
{
    int k = 0;
    for (int d = 1; d <= WAVEFRONT_DEGREE; d++)
        for (int i = d; i >= 0; i--)
            e[k][0] = i, e[k][1] = d - i, k++;
    return k;
}

static double ipow(double x, int e)
{
    double r = 1;
    while (e-- > 0)
        r *= x;
    return r;
}

static int opd_by_rays(wavefront *wf, double dz)
{
    int e[(WAVEFRONT_DEGREE + 1) * (WAVEFRONT_DEGREE + 2) / 2][2];
    int nt = monomials(e);
    double P[3];
    reference_point(wf, dz, P);
    double R = sphere_radius(wf, P);
    size_t nn = (size_t)wf->n * wf->n, m = 0;
    for (size_t k = 0; k < nn; k++)
        m += wf->amp[k] > 0;
    if (m * 2 < (size_t)nt)
        return -1;
    size_t rows = 2 * m;
    double *A = calloc(rows * (size_t)nt, sizeof *A), *rhs = calloc(rows, sizeof *rhs);
    double *lm = malloc(sizeof(double) * 2 * nn);
    if (!A || !rhs || !lm) {
        free(A), free(rhs), free(lm);
        return -1;
    }
    /* centre of the direction cosines: the reference chief ray's */
    double cn = sqrt(1 + wf->ref_chief[2] * wf->ref_chief[2] + wf->ref_chief[3] * wf->ref_chief[3]);
    double L0 = -wf->ref_chief[2] / cn, M0 = -wf->ref_chief[3] / cn;
    double a = wf->scale[0], b = wf->scale[1];
    size_t r = 0;
    for (size_t k = 0; k < nn; k++) {
        if (wf->amp[k] <= 0)
            continue;
        const double *s = wf->sensor + 4 * k;
        double norm = sqrt(1 + s[2] * s[2] + s[3] * s[3]);
        double l = (-s[2] / norm - L0) / a, mm = (-s[3] / norm - M0) / b;
        lm[2 * k] = l, lm[2 * k + 1] = mm;
        double ex = s[0] - dz * s[2] - P[0], ey = s[1] - dz * s[3] - P[1];
        /* dW/dl = a dW/dL = -a n' ex; dW/dm = -b n' ey; rows scaled by the weight */
        double w = sqrt(wf->amp[k]);
        for (int t = 0; t < nt; t++) {
            int i = e[t][0], j = e[t][1];
            A[(size_t)t * rows + r] = w * (i ? i * ipow(l, i - 1) * ipow(mm, j) : 0);
            A[(size_t)t * rows + r + 1] = w * (j ? j * ipow(l, i) * ipow(mm, j - 1) : 0);
        }
        rhs[r] = -w * a * wf->n_image * ex;
        rhs[r + 1] = -w * b * wf->n_image * ey;
        r += 2;
    }
    lapack_int info = LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', (lapack_int)rows, nt, 1, A, (lapack_int)rows,
                                    rhs, (lapack_int)rows);
    if (info == 0)
        for (size_t k = 0; k < nn; k++) {
            if (wf->amp[k] <= 0)
                continue;
            double w = 0;
            for (int t = 0; t < nt; t++)
                w += rhs[t] * ipow(lm[2 * k], e[t][0]) * ipow(lm[2 * k + 1], e[t][1]);
            /* The integral is the path to the foot of the perpendicular from the
             * reference point on the ray (its gradient is exactly -n' times the error);
             * the sphere is met sqrt(R^2 - rho^2) before that foot instead of R. */
            const double *s = wf->sensor + 4 * k;
            double norm = sqrt(1 + s[2] * s[2] + s[3] * s[3]);
            double d[3] = {-s[2] / norm, -s[3] / norm, 1 / norm};
            double e[3] = {s[0] - dz * s[2] - P[0], s[1] - dz * s[3] - P[1], 0};
            double ed = e[0] * d[0] + e[1] * d[1];
            double rho2 = e[0] * e[0] + e[1] * e[1] - ed * ed;
            wf->opd[k] = w + wf->n_image * (R - sqrt(fmax(R * R - rho2, 0)));
        }
    free(A), free(rhs), free(lm);
    if (info != 0)
        return -1;
    remove_piston(wf);
    return 0;
}

int wavefront_refocus(wavefront *wf, double dz)
{
    return wf->method == WAVEFRONT_PATH ? opd_by_path(wf, dz) : opd_by_rays(wf, dz);
}

double wavefront_rms(const wavefront *wf)
{
    double sw = 0, s = 0;
    for (size_t k = 0; k < (size_t)wf->n * wf->n; k++)
        if (wf->amp[k] > 0)
            sw += wf->amp[k], s += wf->amp[k] * wf->opd[k] * wf->opd[k];
    return sw > 0 ? sqrt(s / sw) : NAN;
}

/* Rays of the grid through the exact lens with their path lengths. */
static void trace_paths(const imaging *im, const ray_bundle *b, wavefront *wf, const size_t *cell)
{
    const lens_t *lens = im->lens;
    double zs = lens_total_track(lens) + im->sensor_shift;
#pragma omp parallel for schedule(dynamic, 16)
    for (size_t i = 0; i < b->count; i++) {
        size_t k = cell[i];
        lens_ray r = b->ray[i];
        double opl, *q = wf->path + 7 * k, *s = wf->sensor + 4 * k;
        if (!b->aimed[i] || trace_path_length(im, b->n, &r, &opl) != 0) {
            wf->amp[k] = 0;
            continue;
        }
        memcpy(q, r.o, sizeof r.o);
        memcpy(q + 3, r.d, sizeof r.d);
        q[6] = opl;
        /* the sensor ray on the model's plane, as trace.h writes it */
        double t = (zs - r.o[2]) / r.d[2];
        s[0] = r.o[0] + t * r.d[0], s[1] = r.o[1] + t * r.d[1];
        s[2] = -r.d[0] / r.d[2], s[3] = -r.d[1] / r.d[2];
    }
}

int wavefront_trace(const imaging *im, double field, double lambda, int n, wavefront_method method,
                    const double ref_chief[4], wavefront *wf, lens_err *err)
{
    memset(wf, 0, sizeof *wf);
    if (method == WAVEFRONT_PATH && im->sys) {
        lens_errf(err, NULL, 0, "path lengths need the exact lens (a system gives rays only)");
        return -1;
    }
    size_t nn = (size_t)n * n;
    wf->n = n, wf->lambda = lambda, wf->method = method;
    memcpy(wf->ref_chief, ref_chief, sizeof wf->ref_chief);
    wf->amp = calloc(nn, sizeof(double));
    wf->opd = calloc(nn, sizeof(double));
    wf->sensor = malloc(sizeof(double) * 4 * nn);
    wf->path = method == WAVEFRONT_PATH ? malloc(sizeof(double) * 7 * nn) : NULL;
    double *pupil = malloc(sizeof(double) * 2 * nn);
    size_t *cell = malloc(sizeof(size_t) * nn);
    int *ok = malloc(sizeof(int) * nn);
    double *s = malloc(sizeof(double) * 4 * nn);
    ray_bundle b = {0};
    int rc = -1;
    if (!wf->amp || !wf->opd || !wf->sensor || (method == WAVEFRONT_PATH && !wf->path) || !pupil || !cell ||
        !ok || !s) {
        lens_errf(err, NULL, 0, "out of memory");
        goto out;
    }
    const lens_t *lens = im->lens;
    paraxial_data pd;
    if (bundle_chief(im, field, lambda, wf->chief, err) != 0 ||
        paraxial_compute(lens, lambda, &pd, err) != 0)
        goto out;
    wf->sensor_z = lens_total_track(lens) + im->sensor_shift;
    wf->exit_z = lens->vertex_z[lens->nsurf - 1] + (isfinite(pd.exit_pupil_z) ? pd.exit_pupil_z : 1e5);
    /* the cells with some of the stop in them */
    size_t count = 0;
    double h = 2.0 / n;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            size_t k = (size_t)j * n + i;
            double c = disc_coverage(-1 + i * h, -1 + j * h, h);
            wf->amp[k] = c;
            if (c <= 0)
                continue;
            pupil[2 * count] = -1 + (i + 0.5) * h, pupil[2 * count + 1] = -1 + (j + 0.5) * h;
            cell[count++] = k;
        }
    if (bundle_aim(im, field, lambda, pupil, count, &b, err) != 0)
        goto out;
    wf->n_image = b.n[lens->nsurf - 1];
    for (size_t k = 0; k < 4 * nn; k++)
        wf->sensor[k] = NAN;
    double t0 = bundle_clock();
    if (method == WAVEFRONT_PATH) {
        trace_paths(im, &b, wf, cell);
    } else {
        bundle_image(im, &b, wf->chief, s, ok);
        for (size_t i = 0; i < count; i++) {
            if (ok[i])
                memcpy(wf->sensor + 4 * cell[i], s + 4 * i, sizeof(double) * 4);
            else
                wf->amp[cell[i]] = 0;
        }
    }
    for (size_t k = 0; k < nn; k++)
        wf->passed += wf->amp[k] > 0;
    if (wf->passed < 3) {
        lens_errf(err, NULL, 0, "field %g: fewer than 3 pupil cells pass at %g um", field, lambda);
        goto out;
    }
    scale_fit(wf);
    if (wavefront_refocus(wf, 0) != 0) {
        lens_errf(err, NULL, 0, "field %g at %g um: the wavefront fit failed", field, lambda);
        goto out;
    }
    wf->seconds = bundle_clock() - t0;
    rc = 0;
out:
    bundle_free(&b);
    free(pupil), free(cell), free(ok), free(s);
    if (rc != 0)
        wavefront_free(wf);
    return rc;
}
