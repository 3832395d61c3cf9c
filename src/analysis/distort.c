/* Distortion curve, relative illumination, grid map and OpenCV model fits (distort.h). */
#include "sparselens/distort.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/paraxial.h"
#include "sparselens/sampling.h"

int distort_scale(const imaging *im, double lambda, double *scale, lens_err *err)
{
    paraxial_data p;
    if (paraxial_compute(im->lens, lambda, &p, err) != 0)
        return -1;
    if (!isfinite(p.efl) || fabs(p.efl) > 1e9) {
        lens_errf(err, im->lens->path[0] ? im->lens->path : NULL, 0,
                  "the lens has no finite focal length: no ideal image to compare with");
        return -1;
    }
    if (isinf(im->object_distance)) {
        *scale = p.efl;
        return 0;
    }
    /* Paraxial chief ray from a unit object height (the point (0, -1, -D)) towards the
     * centre of the entrance pupil; its height on the (shifted) sensor plane per unit
     * object height is the magnification. */
    const lens_t *l = im->lens;
    double *n = malloc(sizeof(double) * l->nsurf);
    if (!n || lens_indices(l, lambda, n, err) != 0) {
        free(n);
        if (!n)
            lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    double D = im->object_distance, u = 1.0 / (D + p.entrance_pupil_z);
    double y0 = -1 + D * u, y, nu;
    paraxial_trace_forward(l, n, y0, u, &y, &nu);
    free(n);
    /* nu is n' u' in the last medium, air */
    *scale = y + im->sensor_shift * nu;
    return 0;
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The irradiance at sensor point (x, y) of the shifted plane for an object of uniform
 * radiance: the integral of P T cos^4(theta) du dv over every sensor direction that can
 * pass (sampling.h's full disc), on an m x m grid of cell centres; through the system
 * (its own passage and out_eta, clamped to [0, 1], 1 without it) or the exact lens.
 * Forward from the sensor: no ray is inverted, so neither the axis of a meridional
 * system (exact there only to its fit error) nor a Newton stall passes light the system
 * does not. NAN when out of memory. */
static double irradiance(const imaging *im, double lambda, double x, double y, int m)
{
    const poly_system *sys = im->sys;
    const lens_t *lens = im->lens;
    int nin = sys ? poly_ninputs(sys) : 5, nout = sys ? poly_noutputs(sys) : 5;
    int ix = 0, iy = 1, iu = 2, iv = 3, il = 4, ieta = 4;
    if (sys) {
        ix = poly_input_index(sys, "x"), iy = poly_input_index(sys, "y");
        iu = poly_input_index(sys, "u"), iv = poly_input_index(sys, "v");
        il = poly_input_index(sys, "lambda"), ieta = poly_output_index(sys, "out_eta");
        if (ix < 0 || iy < 0 || iu < 0 || iv < 0)
            return NAN;
    }
    double D = lens_total_track(lens) + im->sensor_shift - lens->vertex_z[lens->nsurf - 1];
    double rd = full_disc_radius(lens, hypot(x, y) + fabs(im->sensor_shift)) / D;
    double h = 2 * rd / m, dz = im->sensor_shift, sum = 0;
    /* the directions go through in chunks, so that memory stays bounded at any m */
    enum { CHUNK = 16384 };
    /* a system's rows hold out_eta alone (the pass test needs no stored output) */
    const int ncol = sys ? ieta >= 0 : nout, icol = sys ? 0 : 4;
    double *in = calloc((size_t)CHUNK * (size_t)nin, sizeof *in);
    double *out = malloc((size_t)CHUNK * (size_t)(ncol ? ncol : 1) * sizeof *out);
    unsigned char *pass = malloc(CHUNK);
    lens_err err;
    if (!in || !out || !pass) {
        free(in), free(out), free(pass);
        return NAN;
    }
    for (long cell = 0, total = (long)m * m; cell < total;) {
        size_t n = 0;
        for (; cell < total && n < CHUNK; cell++) {
            double du = -rd + (cell / m + 0.5) * h, dv = -rd + (cell % m + 0.5) * h;
            if (du * du + dv * dv > rd * rd)
                continue;
            double u = -x / D + du, v = -y / D + dv, *row = in + n++ * (size_t)nin;
            /* the ray through (x, y) on the shifted plane crosses the file's plane at
             * (x + dz u, y + dz v) (imaging.h) */
            row[ix] = x + dz * u, row[iy] = y + dz * v, row[iu] = u, row[iv] = v;
            if (il >= 0)
                row[il] = lambda;
        }
        if (sys)
            poly_eval_batch_outputs(sys, n, in, ncol, &ieta, out, pass);
        else if (trace_batch(lens, TRACE_TO_OUTER, n, in, out, NULL, 0, &err) != 0)
            n = 0;
        for (size_t k = 0; k < n; k++) {
            const double *row = in + k * (size_t)nin, *o = out + k * (size_t)ncol;
            double q = 1 + row[iu] * row[iu] + row[iv] * row[iv];
            double eta = sys ? (pass[k] ? (ieta >= 0 ? fmin(fmax(o[icol], 0), 1) : 1) : 0)
                             : (o[icol] > 0 ? o[icol] : 0);
            sum += eta / (q * q);
        }
    }
    free(in), free(out), free(pass);
    return sum * h * h;
}

int distort_illumination_irradiance(const imaging *im, double lambda, int nf, int ris,
                                    distort_row *rows)
{
    int m = 8 * ris;
    double e0 = irradiance(im, lambda, 0, 0, m);
    if (!(e0 > 0))
        return -1;
    for (int i = 0; i < nf; i++)
        if (isfinite(rows[i].h_real))
            rows[i].rel_illum = irradiance(im, lambda, rows[i].x_real, rows[i].h_real, m) / e0;
    return 0;
}

int distort_curve(const imaging *im, double lambda, const double *field, int nf, int ris,
                  distort_row *rows, lens_err *err)
{
    double scale;
    if (distort_scale(im, lambda, &scale, err) != 0)
        return -1;
    double *n = malloc(sizeof(double) * im->lens->nsurf);
    if (!n || imaging_indices(im, lambda, n, err) != 0) {
        if (!n)
            lens_errf(err, NULL, 0, "out of memory");
        free(n);
        return -1;
    }
    int finite = !isinf(im->object_distance), rc = -1;
    for (int i = 0; i < nf; i++) {
        distort_row *r = &rows[i];
        double f = field[i], s[4];
        memset(r, 0, sizeof *r);
        r->field = f;
        if (!finite && !(f >= 0 && f < 180)) {
            lens_errf(err, NULL, 0, "field %g deg: fields are angles from 0 to 180 degrees", f);
            goto out;
        }
        if (finite && f < 0) {
            lens_errf(err, NULL, 0, "field %g mm: object heights must not be negative", f);
            goto out;
        }
        if (imaging_chief(im, n, lambda, f, s, err) != 0) {
            /* the other fields still have their rows: this one is nan, and says why */
            snprintf(r->why, sizeof r->why, "%s", err->msg);
            r->h_real = r->x_real = r->dist_pct = r->rel_illum = NAN;
            r->h_ideal = finite ? scale * f : proj_radius(PROJ_RECTILINEAR, scale, f * M_PI / 180);
            for (int k = 0; k < PROJ_COUNT; k++)
                r->map_pct[k] = NAN;
            continue;
        }
        r->h_real = s[1], r->x_real = s[0];
        double theta = f * M_PI / 180;
        r->h_ideal = finite ? scale * f : proj_radius(PROJ_RECTILINEAR, scale, theta);
        r->dist_pct = f == 0 ? 0 : 100 * (r->h_real - r->h_ideal) / r->h_ideal;
        for (int k = 0; k < PROJ_COUNT; k++) {
            double hi = finite ? NAN : proj_radius((proj_kind)k, scale, theta);
            r->map_pct[k] = f == 0 && !finite ? 0 : 100 * (r->h_real - hi) / hi;
        }
        r->rel_illum = NAN;
    }
    if (ris > 0 && distort_illumination_irradiance(im, lambda, nf, ris, rows) != 0) {
        lens_errf(err, NULL, 0, im->sys ? "the system passes no light on the axis"
                                        : "no light reaches the axis of the sensor");
        goto out;
    }
    rc = 0;
out:
    free(n);
    return rc;
}

proj_kind distort_best_mapping(const distort_row *rows, int nf, double *rms_pct)
{
    proj_kind best = PROJ_RECTILINEAR;
    double bestv = INFINITY;
    for (int k = 0; k < PROJ_COUNT; k++) {
        double s = 0;
        int m = 0;
        for (int i = 0; i < nf; i++)
            if (rows[i].field != 0 && !rows[i].why[0]) {
                s += rows[i].map_pct[k] * rows[i].map_pct[k];
                m++;
            }
        double v = m ? sqrt(s / m) : 0;
        if (isnan(v))
            continue; /* the projection has no image for some field */
        if (v < bestv)
            bestv = v, best = (proj_kind)k;
    }
    *rms_pct = bestv;
    return best;
}

/* (fisheye-ii against its default system: 2.83% over the lens's ten fields against
 * 1.76% over the system's nine had been compared; 1.77% for the lens over those nine) */
int distort_best_mappings(const distort_row *rows, int nm, int nf, proj_kind *best,
                          double *rms_pct)
{
    distort_row *mine = malloc((size_t)(nf > 0 ? nf : 1) * sizeof *mine);
    if (!mine)
        return -1;
    int left_out = 0;
    for (int i = 0; i < nf; i++) {
        int missing = 0;
        for (int m = 0; m < nm; m++)
            missing |= rows[m * nf + i].why[0] != 0;
        left_out += missing && nm > 1;
    }
    for (int m = 0; m < nm; m++) {
        memcpy(mine, rows + m * nf, (size_t)nf * sizeof *mine);
        for (int i = 0; i < nf; i++)
            for (int q = 0; q < nm; q++)
                if (rows[q * nf + i].why[0] && !mine[i].why[0])
                    snprintf(mine[i].why, sizeof mine[i].why, "not imaged by another model");
        best[m] = distort_best_mapping(mine, nf, &rms_pct[m]);
    }
    free(mine);
    return left_out;
}

int distort_grid(const imaging *im, double lambda, proj_kind k, double scale, double half_w,
                 double half_h, int nx, int ny, double *pts)
{
    double *n = malloc(sizeof(double) * im->lens->nsurf);
    if (!n || imaging_indices(im, lambda, n, NULL) != 0) {
        free(n);
        return 0;
    }
    int good = 0, finite = !isinf(im->object_distance);
#pragma omp parallel for collapse(2) reduction(+ : good) schedule(dynamic, 4)
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            double *p = pts + 4 * (j * nx + i);
            double x = nx > 1 ? -half_w + 2 * half_w * i / (nx - 1) : 0;
            double y = ny > 1 ? -half_h + 2 * half_h * j / (ny - 1) : 0;
            p[0] = x, p[1] = y, p[2] = p[3] = NAN;
            lens_ray r;
            double s[4], eta, rr = hypot(x, y);
            if (finite) {
                /* the object point whose ideal image is (x, y) */
                double P[3] = {-x / scale, -y / scale, -im->object_distance};
                if (aim_from_object(im->lens, n, NULL, P, 0, 0, &r) != 0)
                    continue;
            } else {
                double t = rr > 0 ? proj_theta(k, scale, rr) : 0;
                if (!isfinite(t))
                    continue;
                double d[3] = {rr > 0 ? sin(t) * x / rr : 0, rr > 0 ? sin(t) * y / rr : 0, cos(t)};
                if (aim_from_object(im->lens, n, d, NULL, 0, 0, &r) != 0)
                    continue;
            }
            if (!imaging_trace(im, n, lambda, &r, NULL, s, &eta))
                continue;
            p[2] = s[0], p[3] = s[1];
            good++;
        }
    free(n);
    return good;
}

/* Object points of one calibration view: the plane n . P = 1 (n unit) in the camera
 * frame, in a frame of its own (origin n, axes in the plane), for the directions that
 * meet it at a good angle. OpenCV's calibration estimates a pose per view, and one
 * plane alone leaves pose and distortion entangled (a fisheye fit from one view does
 * not even recover exact synthetic coefficients); several tilted planes do. */
static size_t plane_view(const double n[3], const double *dir, const double *pix_in, size_t cnt,
                         double *obj, double *pix)
{
    double e1[3] = {1 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2]};
    double m = sqrt(dot(e1, e1));
    for (int k = 0; k < 3; k++)
        e1[k] /= m;
    double e2[3] = {n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]};
    size_t v = 0;
    for (size_t i = 0; i < cnt; i++) {
        double c = dot(n, dir + 3 * i);
        if (c < 0.25)
            continue;
        double q[3];
        for (int k = 0; k < 3; k++)
            q[k] = dir[3 * i + k] / c - n[k];
        obj[3 * v] = dot(q, e1), obj[3 * v + 1] = dot(q, e2), obj[3 * v + 2] = 0;
        pix[2 * v] = pix_in[2 * i], pix[2 * v + 1] = pix_in[2 * i + 1];
        v++;
    }
    return v;
}

int distort_opencv(const imaging *im, double lambda, int fisheye, proj_kind k, const double *pts,
                   int npts, double scale, double half_w, double half_h, int width, int height,
                   double max_deg, cv_camera_fit *fit, lens_err *err)
{
    if (!isinf(im->object_distance)) {
        lens_errf(err, NULL, 0, "the OpenCV check needs an object at infinity");
        return -1;
    }
    (void)half_h;
    double pitch = 2 * half_w / width; /* mm per pixel */
    /* The focal length the mapping actually has near the axis on this sensor plane (a
     * sensor off the paraxial focus scales every height): h / theta of a chief ray at a
     * twentieth of a degree. The fisheye fit holds it fixed. */
    double *n = malloc(sizeof(double) * im->lens->nsurf), s[4], f_eff = scale;
    const double small = 0.05 * M_PI / 180;
    if (n && imaging_indices(im, lambda, n, NULL) == 0 &&
        imaging_chief(im, n, lambda, 0.05, s, NULL) == 0 && s[1] > 0)
        f_eff = s[1] / small;
    free(n);
    enum { NVIEWS = 5 };
    double *dir = malloc(sizeof(double) * 3 * (size_t)npts);
    double *pin = malloc(sizeof(double) * 2 * (size_t)npts);
    double *obj = malloc(sizeof(double) * 3 * NVIEWS * (size_t)npts);
    double *pix = malloc(sizeof(double) * 2 * NVIEWS * (size_t)npts);
    if (!dir || !pin || !obj || !pix) {
        free(dir), free(pin), free(obj), free(pix);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    size_t m = 0;
    for (int i = 0; i < npts; i++) {
        const double *p = pts + 4 * i;
        if (!isfinite(p[2]) || !isfinite(p[3]))
            continue;
        double r = hypot(p[0], p[1]), t = r > 0 ? proj_theta(k, scale, r) : 0;
        if (!(t < max_deg * M_PI / 180))
            continue;
        dir[3 * m] = r > 0 ? sin(t) * p[0] / r : 0;
        dir[3 * m + 1] = r > 0 ? sin(t) * p[1] / r : 0;
        dir[3 * m + 2] = cos(t);
        pin[2 * m] = width / 2.0 + p[2] / pitch;
        pin[2 * m + 1] = height / 2.0 + p[3] / pitch;
        m++;
    }
    const double a = 35 * M_PI / 180, sa = sin(a), ca = cos(a);
    const double normals[NVIEWS][3] = {{0, 0, 1}, {sa, 0, ca}, {-sa, 0, ca}, {0, sa, ca}, {0, -sa, ca}};
    size_t counts[NVIEWS], total = 0;
    int nv = 0;
    for (int v = 0; v < NVIEWS; v++) {
        size_t c = plane_view(normals[v], dir, pin, m, obj + 3 * total, pix + 2 * total);
        if (c >= 12)
            counts[nv++] = c, total += c;
    }
    int rc;
    if (nv == 0) {
        lens_errf(err, NULL, 0, "too few grid points for the OpenCV fit");
        rc = -1;
    } else {
        rc = fisheye ? cv_fit_fisheye(width, height, f_eff / pitch, 0, nv, counts, obj, pix, fit, err)
                     : cv_fit_brown(width, height, f_eff / pitch, nv, counts, obj, pix, fit, err);
    }
    free(dir), free(pin), free(obj), free(pix);
    return rc;
}
