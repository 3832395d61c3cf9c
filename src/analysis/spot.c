/* Spot diagrams: pupil sampling, tracing and statistics (see spot.h). */
#include "sparselens/spot.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const pattern_names[] = {"hexapolar", "grid", "random"};

int pupil_pattern_parse(const char *name, pupil_pattern *p)
{
    for (int i = 0; i < 3; i++)
        if (strcmp(name, pattern_names[i]) == 0) {
            *p = (pupil_pattern)i;
            return 0;
        }
    return -1;
}

const char *pupil_pattern_name(pupil_pattern p)
{
    return pattern_names[p];
}

static unsigned long long splitmix(unsigned long long *s)
{
    unsigned long long z = (*s += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

static double uniform(unsigned long long *s)
{
    return (double)(splitmix(s) >> 11) * 0x1.0p-53;
}

size_t pupil_points(pupil_pattern p, size_t rays, unsigned long long seed, double *xy, size_t max)
{
    size_t n = 0;
    if (rays < 1)
        rays = 1;
    if (p == PUPIL_HEXAPOLAR) {
        size_t R = 0;
        while (1 + 3 * R * (R + 1) < rays)
            R++;
        if (n < max)
            xy[2 * n] = xy[2 * n + 1] = 0, n++;
        for (size_t k = 1; k <= R; k++)
            for (size_t j = 0; j < 6 * k && n < max; j++, n++) {
                double r = (double)k / (double)R, a = 2 * M_PI * (double)j / (double)(6 * k);
                xy[2 * n] = r * cos(a), xy[2 * n + 1] = r * sin(a);
            }
    } else if (p == PUPIL_GRID) {
        /* side m points over [-1, 1]: about pi/4 m^2 fall inside the disc */
        int m = (int)ceil(sqrt(4.0 * (double)rays / M_PI));
        if (m < 1)
            m = 1;
        for (int i = 0; i < m; i++)
            for (int j = 0; j < m; j++) {
                double x = m == 1 ? 0 : -1 + 2.0 * (i + 0.5) / m, y = m == 1 ? 0 : -1 + 2.0 * (j + 0.5) / m;
                if (x * x + y * y <= 1 && n < max)
                    xy[2 * n] = x, xy[2 * n + 1] = y, n++;
            }
    } else {
        unsigned long long s = seed;
        for (; n < rays && n < max; n++) {
            double r = sqrt(uniform(&s)), a = 2 * M_PI * uniform(&s);
            xy[2 * n] = r * cos(a), xy[2 * n + 1] = r * sin(a);
        }
    }
    return n;
}

void spot_free(spot *sp)
{
    free(sp->ray);
    free(sp->eta);
    sp->ray = sp->eta = NULL;
    sp->passed = 0;
}

static double angle_between_tangents(const double *a, const double *b)
{
    double da[3] = {a[0], a[1], -1}, db[3] = {b[0], b[1], -1};
    double cx = da[1] * db[2] - da[2] * db[1], cy = da[2] * db[0] - da[0] * db[2],
           cz = da[0] * db[1] - da[1] * db[0];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), da[0] * db[0] + da[1] * db[1] + da[2] * db[2]);
}

void spot_mark_not_imaged(spot *sp)
{
    spot_free(sp);
    sp->rays = 0;
    sp->not_imaged = 1;
    for (int k = 0; k < 4; k++)
        sp->chief[k] = NAN;
    spot_stats(sp);
    sp->vignetted = NAN;
}

void spot_stats(spot *sp)
{
    size_t n = sp->passed;
    sp->vignetted = sp->rays ? 1.0 - (double)n / (double)sp->rays : 0;
    if (n == 0) {
        sp->centroid[0] = sp->centroid[1] = NAN;
        sp->rms_chief = sp->max_chief = sp->rms_centroid = sp->max_centroid = NAN;
        sp->airy = NAN;
        return;
    }
    double cx = 0, cy = 0;
    for (size_t i = 0; i < n; i++)
        cx += sp->ray[4 * i], cy += sp->ray[4 * i + 1];
    cx /= (double)n, cy /= (double)n;
    sp->centroid[0] = cx, sp->centroid[1] = cy;
    double s1 = 0, m1 = 0, s2 = 0, m2 = 0, umax = 0;
    for (size_t i = 0; i < n; i++) {
        const double *r = sp->ray + 4 * i;
        double a = hypot(r[0] - sp->chief[0], r[1] - sp->chief[1]);
        double b = hypot(r[0] - cx, r[1] - cy);
        s1 += a * a, m1 = fmax(m1, a);
        s2 += b * b, m2 = fmax(m2, b);
        umax = fmax(umax, angle_between_tangents(r + 2, sp->chief + 2));
    }
    sp->rms_chief = sqrt(s1 / (double)n), sp->max_chief = m1;
    sp->rms_centroid = sqrt(s2 / (double)n), sp->max_centroid = m2;
    /* lambda in um -> mm */
    sp->airy = umax > 0 && isfinite(sp->lambda) ? 1.22 * sp->lambda * 1e-3 / (2 * sin(umax)) : NAN;
}

void spot_shift(spot *sp, double dz)
{
    for (size_t i = 0; i < sp->passed; i++) {
        sp->ray[4 * i] -= dz * sp->ray[4 * i + 2];
        sp->ray[4 * i + 1] -= dz * sp->ray[4 * i + 3];
    }
    sp->chief[0] -= dz * sp->chief[2];
    sp->chief[1] -= dz * sp->chief[3];
}

double spot_best_shift(const spot *sp, size_t n)
{
    /* position p_i - dz q_i about the centroid: sum |dp - dz dq|^2 = A - 2 dz B + dz^2 C */
    double B = 0, C = 0;
    for (size_t k = 0; k < n; k++) {
        const spot *s = &sp[k];
        size_t m = s->passed;
        if (m < 2)
            continue;
        double pc[2] = {0, 0}, qc[2] = {0, 0};
        for (size_t i = 0; i < m; i++)
            for (int a = 0; a < 2; a++)
                pc[a] += s->ray[4 * i + a] / (double)m, qc[a] += s->ray[4 * i + 2 + a] / (double)m;
        double b = 0, c = 0;
        for (size_t i = 0; i < m; i++)
            for (int a = 0; a < 2; a++) {
                double dp = s->ray[4 * i + a] - pc[a], dq = s->ray[4 * i + 2 + a] - qc[a];
                b += dp * dq, c += dq * dq;
            }
        B += b / (double)m, C += c / (double)m;
    }
    return C > 0 ? B / C : 0;
}

/* A spot's aimed rays and the seeds of their solves through a system, in one block
 * (seed first: every part is aligned for its type). */
typedef struct {
    double *seed, *sol, *eta;
    lens_ray *ray;
    int *aimed, *got;
} aimed_rays;

static void aimed_rays_free(aimed_rays *a)
{
    free(a->seed);
    memset(a, 0, sizeof *a);
}

static int aimed_rays_alloc(aimed_rays *a, size_t np)
{
    size_t m = np ? np : 1;
    a->seed = malloc(m * (9 * sizeof(double) + sizeof(lens_ray) + 2 * sizeof(int)));
    if (!a->seed)
        return -1;
    a->sol = a->seed + 4 * m;
    a->eta = a->sol + 4 * m;
    a->ray = (lens_ray *)(a->eta + m);
    a->aimed = (int *)(a->ray + m);
    a->got = a->aimed + m;
    return 0;
}

/* The aimed rays through the system at once, into spot_trace's rows (x, y, u, v on the
 * shifted sensor, eta, imaged). -1 when memory runs out. */
static int system_rays(const imaging *im, double lambda, aimed_rays *a, size_t np, double *res)
{
    if (imaging_system_batch(im, lambda, np, a->ray, a->aimed, a->seed, 4, 0, a->sol, a->eta,
                             a->got, NULL) != 0)
        return -1;
    for (size_t i = 0; i < np; i++)
        if (a->got[i]) {
            const double *q = a->sol + 4 * i;
            double *o = res + 6 * i;
            o[0] = q[0] - im->sensor_shift * q[2];
            o[1] = q[1] - im->sensor_shift * q[3];
            o[2] = q[2], o[3] = q[3], o[4] = a->eta[i], o[5] = 1;
        }
    return 0;
}

int spot_trace(const imaging *im, double field, double lambda, pupil_pattern pat, size_t rays,
               unsigned long long seed, spot *sp, lens_err *err)
{
    memset(sp, 0, sizeof *sp);
    sp->field = field, sp->lambda = lambda;
    const lens_t *lens = im->lens;
    double *n = malloc(sizeof(double) * lens->nsurf);
    /* hexapolar rounds up to whole rings, grid to whole rows */
    size_t cap = 2 * rays + 64;
    double *xy = malloc(sizeof(double) * 2 * cap);
    sp->ray = malloc(sizeof(double) * 4 * cap);
    sp->eta = malloc(sizeof(double) * cap);
    int rc = -1;
    if (!n || !xy || !sp->ray || !sp->eta) {
        lens_errf(err, NULL, 0, "out of memory");
        goto out;
    }
    if (imaging_indices(im, lambda, n, err) != 0)
        goto out;
    if (imaging_chief(im, n, lambda, field, sp->chief, err) != 0) {
        free(n);
        free(xy);
        spot_free(sp);
        spot_mark_not_imaged(sp);
        return 1;
    }
    size_t np = pupil_points(pat, rays, seed, xy, cap);
    double stop = lens->surf[lens->stop].semi_diameter;
    sp->rays = np;
    /* Rays are independent (aiming is a Newton solve each): traced in parallel into
     * their own slots, then packed in pupil order so the result does not depend on the
     * thread count. */
    double *res = malloc(sizeof(double) * 6 * (np ? np : 1));
    if (!res) {
        lens_errf(err, NULL, 0, "out of memory");
        goto out;
    }
    /* The chief ray was aimed, so the field has a start. */
    aim_object_start start;
    int started = imaging_aim_prepare(im, n, field, &start) == 0;
    /* Through a system the rays are aimed and seeded here and solved together after
     * (system_rays: the batch kernel's Newton steps, where one ray at a time took a
     * one-ray Jacobian each), as imaging_trace would solve each. */
    aimed_rays ar = {0};
    int batch = im->sys && aimed_rays_alloc(&ar, np) == 0;
#pragma omp parallel for schedule(dynamic, 8)
    for (size_t i = 0; i < np; i++) {
        lens_ray r;
        double *o = res + 6 * i;
        /* The rim itself is a grazing case for aiming; stay a hair inside. */
        double sx = xy[2 * i] * stop * (1 - 1e-9), sy = xy[2 * i + 1] * stop * (1 - 1e-9);
        o[5] = 0;
        int a = started && aim_object_to(&start, sx, sy, &r) == 0;
        if (batch) {
            ar.aimed[i] = a;
            if (a) {
                ar.ray[i] = r;
                imaging_seed(im, n, &r, sp->chief, ar.seed + 4 * i);
            }
        } else if (a && imaging_trace(im, n, lambda, &r, sp->chief, o, &o[4])) {
            o[5] = 1;
        }
    }
    if (batch && system_rays(im, lambda, &ar, np, res) != 0) {
        aimed_rays_free(&ar);
        free(res);
        lens_errf(err, NULL, 0, "out of memory");
        goto out;
    }
    aimed_rays_free(&ar);
    for (size_t i = 0; i < np; i++)
        if (res[6 * i + 5] != 0) {
            memcpy(sp->ray + 4 * sp->passed, res + 6 * i, sizeof(double) * 4);
            sp->eta[sp->passed++] = res[6 * i + 4];
        }
    free(res);
    spot_stats(sp);
    rc = 0;
out:
    free(n);
    free(xy);
    if (rc != 0)
        spot_free(sp);
    return rc;
}

int spot_pool(const spot *sp, size_t n, size_t primary, spot *total)
{
    memset(total, 0, sizeof *total);
    size_t m = 0;
    for (size_t k = 0; k < n; k++)
        m += sp[k].passed;
    total->ray = malloc(sizeof(double) * 4 * (m + 1));
    total->eta = malloc(sizeof(double) * (m + 1));
    if (!total->ray || !total->eta) {
        spot_free(total);
        return -1;
    }
    for (size_t k = 0; k < n; k++) {
        if (sp[k].passed > 0) { /* a field with no ray has no arrays to copy from */
            memcpy(total->ray + 4 * total->passed, sp[k].ray, sizeof(double) * 4 * sp[k].passed);
            memcpy(total->eta + total->passed, sp[k].eta, sizeof(double) * sp[k].passed);
        }
        total->passed += sp[k].passed;
        total->rays += sp[k].rays;
    }
    total->field = sp[primary].field;
    total->lambda = NAN;
    memcpy(total->chief, sp[primary].chief, sizeof total->chief);
    spot_stats(total);
    total->airy = sp[primary].airy;
    return 0;
}
