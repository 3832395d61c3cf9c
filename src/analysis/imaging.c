/* The imaging set-up shared by the spot and distortion analyses (see imaging.h). */
#include "sparselens/imaging.h"
#include "sparselens/file_fields.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/aim.h"
#include "sparselens/paraxial.h"
#include "sparselens/poly_solve.h"
#include "sparselens/ray_frames.h"
#include "sparselens/numparse.h"

/* Fraunhofer line wavelengths, um (Schott's table of the lines used in glass data). */
static const struct {
    const char *name;
    double um;
} lines[] = {
    {"i", 0.365015},  {"h", 0.404656}, {"g", 0.435835},  {"F'", 0.479991}, {"F", GLASS_F_LINE},
    {"e", 0.546074},  {"d", GLASS_D_LINE}, {"D", 0.5892938}, {"C'", 0.643847}, {"C", GLASS_C_LINE},
    {"r", 0.706519},  {"A'", 0.768195}, {"s", 0.85211},   {"t", 1.01398},
};

static int split(const char *spec, const char *what, char tok[][32], int max, lens_err *err)
{
    if (!spec || !*spec) {
        lens_errf(err, NULL, 0, "empty %s list", what);
        return -1;
    }
    int n = 0;
    const char *p = spec;
    for (;;) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len == 0 || len >= 32) {
            lens_errf(err, NULL, 0, "bad %s list '%s': %s", what, spec,
                      len ? "item too long" : "empty item");
            return -1;
        }
        if (n == max) {
            lens_errf(err, NULL, 0, "too many %ss in '%s' (at most %d)", what, spec, max);
            return -1;
        }
        memcpy(tok[n], p, len);
        tok[n++][len] = '\0';
        if (!e)
            break;
        p = e + 1;
    }
    return n;
}

int wavelengths_parse(const char *spec, double *lambda, int max, lens_err *err)
{
    char tok[IMAGING_MAX_WAVELENGTHS][32];
    int n = split(spec, "wavelength", tok, max < IMAGING_MAX_WAVELENGTHS ? max : IMAGING_MAX_WAVELENGTHS, err);
    for (int i = 0; i < n; i++) {
        int found = 0;
        for (size_t k = 0; k < sizeof lines / sizeof lines[0]; k++)
            if (strcmp(tok[i], lines[k].name) == 0) {
                lambda[i] = lines[k].um;
                found = 1;
            }
        if (found)
            continue;
        if (parse_double(tok[i], &lambda[i]) != 0) {
            lens_errf(err, NULL, 0,
                      "unknown wavelength '%s' (a value in um, or a Fraunhofer line: i h g F' F e d "
                      "D C' C r A' s t)",
                      tok[i]);
            return -1;
        }
        if (lambda[i] < 0.2 || lambda[i] > 2.5) {
            lens_errf(err, NULL, 0, "wavelength %s um is outside 0.2..2.5 um", tok[i]);
            return -1;
        }
    }
    return n;
}

int numbers_parse(const char *spec, const char *what, double *v, int max, lens_err *err)
{
    char (*tok)[32] = malloc(sizeof *tok * (size_t)max);
    if (!tok) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int n = split(spec, what, tok, max, err);
    for (int i = 0; i < n; i++)
        if (parse_double(tok[i], &v[i]) != 0) {
            lens_errf(err, NULL, 0, "bad %s '%s': not a number", what, tok[i]);
            n = -1;
            break;
        }
    free(tok);
    return n;
}

int imaging_indices(const imaging *im, double lambda, double *n, lens_err *err)
{
    return lens_indices(im->lens, lambda, n, err);
}

int imaging_aim_prepare(const imaging *im, const double *n, double field, aim_object_start *st)
{
    if (isinf(im->object_distance)) {
        double a = field * (M_PI / 180);
        double dir[3] = {0, sin(a), cos(a)};
        return aim_object_prepare(im->lens, n, dir, NULL, st) == 0 ? 0 : -1;
    }
    double p[3] = {0, -field, -im->object_distance};
    return aim_object_prepare(im->lens, n, NULL, p, st) == 0 ? 0 : -1;
}

int imaging_object_ray(const imaging *im, const double *n, double field, double sx, double sy,
                       lens_ray *r)
{
    aim_object_start st;
    if (!isfinite(sx) || !isfinite(sy) || imaging_aim_prepare(im, n, field, &st) != 0)
        return -1;
    return aim_object_to(&st, sx, sy, r) == 0 ? 0 : -1;
}

static void shift_sensor(double s[4], double dz)
{
    s[0] -= dz * s[2];
    s[1] -= dz * s[3];
}

/* The exact trace of r: 1 and its sensor ray in s (on the file's plane) with *eta when
 * it passes; else 0, and s the seed of a solve through the system, guess or the axis. */
static int exact_or_guess(const imaging *im, const double *n, const lens_ray *r,
                          const double *guess, double s[4], double *eta)
{
    lens_ray t = *r;
    trace_result res = trace_to_sensor(im->lens, n, &t);
    if (res.status == TRACE_PASSED) {
        ray_to_sensor(im->lens, &t, s);
        *eta = res.transmittance;
        return 1;
    }
    if (guess)
        memcpy(s, guess, sizeof(double) * 4);
    else
        memset(s, 0, sizeof(double) * 4);
    return 0;
}

void imaging_seed(const imaging *im, const double *n, const lens_ray *r, const double *guess,
                  double seed[4])
{
    double eta;
    exact_or_guess(im, n, r, guess, seed, &eta);
}

int imaging_trace(const imaging *im, const double *n, double lambda, const lens_ray *r,
                  const double *guess, double s[4], double *eta)
{
    if (!im->sys) {
        if (!exact_or_guess(im, n, r, NULL, s, eta))
            return 0;
        shift_sensor(s, im->sensor_shift);
        return 1;
    }
    double outer[4], seed[4], sol[4];
    if (outer_of_object_ray(im->lens, r, outer) != 0)
        return 0;
    /* The exact ray is the natural seed; a vignetted one leaves the caller's guess. */
    imaging_seed(im, n, r, guess, seed);
    int pass = 0;
    double e = 1;
    if (poly_solve_sensor(im->sys, lambda, outer, seed, sol, &pass, &e) != 0 || !pass)
        return 0;
    memcpy(s, sol, sizeof sol);
    *eta = e;
    shift_sensor(s, im->sensor_shift);
    return 1;
}

/* Rays per batch solve: a block's Newton iterates are evaluated together, and the blocks
 * go to the threads. */
#define SYSTEM_BLOCK 256

int imaging_system_batch(const imaging *im, double lambda, size_t n, const lens_ray *rays,
                         const int *use, const double *seeds, size_t seed_stride,
                         int max_iter, double *s, double *eta, int *ok, int *blocked)
{
    int failed = 0;
    const size_t nblk = (n + SYSTEM_BLOCK - 1) / SYSTEM_BLOCK;
#pragma omp parallel for schedule(dynamic, 1) reduction(| : failed) if (nblk > 1)
    for (size_t bk = 0; bk < nblk; bk++) {
        double outer[4 * SYSTEM_BLOCK], seed[4 * SYSTEM_BLOCK], lam[SYSTEM_BLOCK];
        double sol[4 * SYSTEM_BLOCK], e[SYSTEM_BLOCK];
        int status[SYSTEM_BLOCK];
        unsigned char pass[SYSTEM_BLOCK];
        size_t row[SYSTEM_BLOCK], m = 0, i0 = bk * SYSTEM_BLOCK;
        for (size_t i = i0; i < n && i < i0 + SYSTEM_BLOCK; i++) {
            ok[i] = 0;
            if (blocked)
                blocked[i] = 0;
            if ((use && !use[i]) || outer_of_object_ray(im->lens, &rays[i], outer + 4 * m) != 0)
                continue;
            if (seeds)
                memcpy(seed + 4 * m, seeds + i * seed_stride, sizeof(double) * 4);
            else
                memset(seed + 4 * m, 0, sizeof(double) * 4);
            lam[m] = lambda;
            row[m++] = i;
        }
        if (m == 0)
            continue;
        if (poly_solve_sensor_batch(im->sys, m, lam, outer, seed, 4, max_iter, sol, status, pass, e) != 0) {
            failed = 1;
            continue;
        }
        for (size_t k = 0; k < m; k++)
            if (status[k] == 0 && !pass[k] && blocked)
                blocked[row[k]] = 1;
            else if (status[k] == 0 && pass[k]) {
                size_t i = row[k];
                ok[i] = 1;
                memcpy(s + 4 * i, sol + 4 * k, sizeof(double) * 4);
                if (eta)
                    eta[i] = e[k];
            }
    }
    return failed ? -1 : 0;
}

static const char *field_unit(const imaging *im)
{
    return isinf(im->object_distance) ? "deg" : "mm";
}

int imaging_chief(const imaging *im, const double *n, double lambda, double field, double s[4],
                  lens_err *err)
{
    lens_ray r;
    double eta;
    if (imaging_object_ray(im, n, field, 0, 0, &r) != 0 ||
        !imaging_trace(im, n, lambda, &r, NULL, s, &eta)) {
        lens_errf(err, NULL, 0,
                  "field %g %s: no chief ray through the stop centre reaches the sensor "
                  "at %g um%s",
                  field, field_unit(im), lambda, im->sys ? " through the system" : "");
        return -1;
    }
    /* A system answers outside what it was fitted over too, by extrapolation: a field
     * whose chief ray lands there is one it cannot image. The domain is on the file's
     * sensor plane, where the ray was before the shift. */
    char why[256];
    if (im->sys && !poly_sensor_in_domain(im->sys, s[0] + im->sensor_shift * s[2],
                                          s[1] + im->sensor_shift * s[3], lambda, why, sizeof why)) {
        lens_errf(err, NULL, 0, "field %g %s at %g um: %s", field, field_unit(im), lambda, why);
        return -1;
    }
    return 0;
}

int imaging_max_field(const imaging *im, double lambda, double limit, double *field,
                      lens_err *err)
{
    double *n = malloc(sizeof(double) * (im->lens->nsurf ? im->lens->nsurf : 1));
    if (!n) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int rc = -1;
    double s[4];
    if (imaging_indices(im, lambda, n, err) != 0 || imaging_chief(im, n, lambda, 0, s, err) != 0)
        goto out;
    /* Coarse scan, then bisection on the last step: the passing range of chief rays is
     * an interval from the axis for every lens we know. */
    double lo = 0, hi = limit;
    int steps = 64;
    for (int i = 1; i <= steps; i++) {
        double f = limit * i / steps;
        if (imaging_chief(im, n, lambda, f, s, NULL) != 0) {
            hi = f;
            break;
        }
        lo = f;
    }
    if (lo < limit)
        for (int i = 0; i < 40; i++) {
            double m = 0.5 * (lo + hi);
            if (imaging_chief(im, n, lambda, m, s, NULL) == 0)
                lo = m;
            else
                hi = m;
        }
    *field = lo;
    rc = 0;
out:
    free(n);
    return rc;
}

int imaging_paraxial_shift(const lens_t *lens, double object_distance, double lambda,
                           double *shift, lens_err *err)
{
    double t;
    if (paraxial_focus_thickness(lens, lambda, object_distance, &t, err) != 0)
        return -1;
    *shift = t - lens->surf[lens->nsurf - 1].thickness;
    return 0;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcmp(s + a - b, suffix) == 0;
}

static int load_system(const char *path, poly_system **sys, lens_err *err)
{
    if (poly_read(path, sys, err) != 0)
        return -1;
    lens_err e2;
    if (poly_solve_check(*sys, &e2) != 0) {
        lens_errf(err, path, 0, "%s", e2.msg);
        poly_free(*sys);
        *sys = NULL;
        return -1;
    }
    return 0;
}

int imaging_models_load(const char *path, const char *compare, const char *lens_path,
                        const lens_load_options *lopt, imaging_models *m, lens_err *err)
{
    memset(m, 0, sizeof *m);
    lens_init(&m->lens);
    if (ends_with(path, ".poly")) {
        if (compare) {
            lens_errf(err, NULL, 0, "--compare needs a lens as the first argument, not a system");
            return -1;
        }
        if (load_system(path, &m->sys, err) != 0)
            return -1;
        char found[4096];
        if (!lens_path &&
            poly_find_lens_file(m->sys, path, lens_find_file, found, sizeof found, err) != 0) {
            lens_err e = *err; /* what these commands can do about it */
            lens_errf(err, NULL, 0, "%s; give it with --lens", e.msg);
            imaging_models_free(m);
            return -1;
        }
        if (lens_load(lens_path ? lens_path : found, lopt, &m->lens, err) != 0) {
            imaging_models_free(m);
            return -1;
        }
    } else {
        if (lens_load(path, lopt, &m->lens, err) != 0)
            return -1;
        if (compare && load_system(compare, &m->compare, err) != 0) {
            imaging_models_free(m);
            return -1;
        }
    }
    /* the grid maps and the sensor-corner field need a sensor: the file's fields give one */
    lens_sensor_from_fields(&m->lens, NULL);
    return 0;
}

void imaging_models_free(imaging_models *m)
{
    poly_free(m->sys);
    poly_free(m->compare);
    lens_free(&m->lens);
    m->sys = m->compare = NULL;
}

int imaging_models_setup(const imaging_models *m, double object_distance, imaging im[2],
                         const char *names[2])
{
    imaging base = {.lens = &m->lens, .sys = NULL, .object_distance = object_distance};
    im[0] = base;
    names[0] = "lens";
    if (m->sys) {
        im[0].sys = m->sys;
        names[0] = "poly";
        return 1;
    }
    if (!m->compare)
        return 1;
    im[1] = base;
    im[1].sys = m->compare;
    names[1] = "poly";
    return 2;
}

int imaging_default_fields(const imaging *im, const double *lambdas, int nl, double *field,
                           lens_err *err)
{
    int k = lens_file_fields(im->lens, im->object_distance, field, IMAGING_MAX_FIELDS, err);
    if (k != 0)
        return k;
    if (!isinf(im->object_distance)) {
        lens_errf(err, NULL, 0, "give --fields (object heights in mm) for a finite object distance");
        return -1;
    }
    double maxf = 179.0, lambda = lambdas[nl / 2];
    for (int i = 0; i < nl; i++) {
        double m;
        if (imaging_max_field(im, lambdas[i], maxf, &m, err) != 0)
            return -1;
        maxf = fmin(maxf, m);
    }
    const lens_t *l = im->lens;
    if (isfinite(l->sensor_w) && isfinite(l->sensor_h)) {
        /* the field whose chief ray lands on the sensor corner, if inside the image */
        double r = 0.5 * hypot(l->sensor_w, l->sensor_h), s[4];
        double *n = malloc(sizeof(double) * l->nsurf);
        if (n && imaging_indices(im, lambda, n, NULL) == 0 &&
            imaging_chief(im, n, lambda, maxf, s, NULL) == 0 && s[1] > r) {
            double lo = 0, hi = maxf;
            for (int i = 0; i < 50; i++) {
                double m = 0.5 * (lo + hi);
                if (imaging_chief(im, n, lambda, m, s, NULL) == 0 && s[1] < r)
                    lo = m;
                else
                    hi = m;
            }
            maxf = lo;
        }
        free(n);
    }
    /* a hair inside the last passing chief ray */
    maxf = floor(maxf * 0.999 * 100) / 100;
    field[0] = 0;
    field[1] = round(0.7 * maxf * 100) / 100;
    field[2] = maxf;
    return maxf > 0 ? 3 : 1;
}
