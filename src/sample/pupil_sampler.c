/* Pupil-aware direction sampling (see pupil_sampler.h for the method). */
#include "sparselens/pupil_sampler.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/trace.h"
#include "sparselens/trace_packet.h"

/* Probe wavelengths spread evenly over the range: the passing set moves with the
 * wavelength, and where it is a thin crescent (fisheyes near the edge of the image
 * circle) three probes left gaps between their sets wider than the dilation. */
enum { MAX_LAMBDAS = 5, COARSE = 64 };

/* A run of occupied cells along a grid row: columns i0 .. i0 + n - 1 of row j, after
 * cum occupied cells in index order (row by row). */
typedef struct {
    int cum;
    short i0, j;
} pupil_run;

/* The occupied cells are kept as a bitmap (the density test: a bit a cell) and as runs
 * (drawing the k-th occupied cell: a guide table gives a run at or just before it, no
 * search, no division): both a few kB a set, so that a render's accesses, spread over
 * every set a row of pixels meets, stay in the cache (a list of cell indices was 4
 * bytes a cell, random access). */
enum { GUIDE = 256 };
typedef struct {
    double u0, v0, du, dv; /* grid origin (lower corner) and cell size */
    int g;                 /* cells per side */
    uint64_t *occ;         /* g*g occupancy bits, row v, column u: bit c of word c / 64 */
    pupil_run *runs;       /* nruns + 1 (a sentinel with cum = count) */
    int nruns;
    int *row_run;          /* g + 1: row j's runs are row_run[j] .. row_run[j + 1] - 1 */
    int guide[GUIDE];      /* the run holding cell m count / GUIDE */
    double guide_scale;    /* GUIDE / count */
    int count;   /* occupied cells */
    double area; /* count * du * dv */
    double inv_du, inv_dv, inv_cell; /* 1 / du, 1 / dv, 1 / (du dv): a draw multiplies */
} pupil_set;

static int occupied(const pupil_set *set, size_t c)
{
    return (int)(set->occ[c / 64] >> (c % 64) & 1);
}

/* The runs, count and area of a set whose bitmap is filled. */
static int set_finish(pupil_set *set)
{
    int g = set->g;
    set->count = set->nruns = 0;
    for (int j = 0; j < g; j++)
        for (int i = 0; i < g; i++)
            set->nruns += occupied(set, (size_t)j * g + i) && (i == 0 || !occupied(set, (size_t)j * g + i - 1));
    set->runs = malloc((size_t)(set->nruns + 1) * sizeof *set->runs);
    if (!set->runs)
        return -1;
    int r = 0;
    for (int j = 0; j < g; j++)
        for (int i = 0; i < g; i++) {
            if (!occupied(set, (size_t)j * g + i))
                continue;
            if (i == 0 || !occupied(set, (size_t)j * g + i - 1))
                set->runs[r++] = (pupil_run){set->count, (short)i, (short)j};
            set->count++;
        }
    set->runs[r] = (pupil_run){set->count, 0, 0}; /* a sentinel: the end of the last run */
    set->row_run = malloc((size_t)(g + 1) * sizeof *set->row_run);
    if (!set->row_run)
        return -1;
    for (int j = 0, q = 0; j <= g; j++) {
        while (q < set->nruns && set->runs[q].j < j)
            q++;
        set->row_run[j] = q;
    }
    set->area = set->count * set->du * set->dv;
    set->inv_du = 1 / set->du, set->inv_dv = 1 / set->dv, set->inv_cell = 1 / (set->du * set->dv);
    set->guide_scale = set->count ? (double)GUIDE / set->count : 0;
    for (int m = 0, q = 0; m < GUIDE && set->count; m++) {
        long k = (long)m * set->count / GUIDE;
        while (set->runs[q + 1].cum <= k)
            q++;
        set->guide[m] = q;
    }
    return 0;
}

/* The k-th occupied cell (0 <= k < count), column i and row j: from the guide's run,
 * a step or two either way (the runs are longer than a guide's stride, and the scale's
 * rounding may land one bucket off). */
static void set_cell(const pupil_set *set, int k, int *i, int *j)
{
    int m = (int)(k * set->guide_scale);
    int r = set->guide[m < GUIDE ? m : GUIDE - 1];
    while (set->runs[r].cum > k)
        r--;
    while (set->runs[r + 1].cum <= k)
        r++;
    *i = set->runs[r].i0 + (k - set->runs[r].cum);
    *j = set->runs[r].j;
}

struct pupil_sampler {
    int nr;
    double rmax, r_scale; /* r_scale = (nr - 1) / rmax: a radius to its set */
    pupil_set *sets;
};

/* Whom build_set asks which directions pass: the exact lens (lens_probe, the packet
 * tracer at the probe wavelengths) or a caller's function (pupil_sampler_build_probe). */
typedef struct {
    const lens_t *lens; /* NULL for a caller's probe: then fn, ctx, rear_dist, rear_radius */
    int nl;
    double *n[MAX_LAMBDAS];
    pupil_probe_fn fn;
    void *ctx;
    double rear_dist, rear_radius;
} prober;

/* Marks pass[k] = 1 for the sensor rays (x, 0, u[k], v[k]), k < m, that pass at any of
 * the probe wavelengths. Rays go through the packet tracer TRACE_LANES at a time. */
static void lens_probe(const prober *p, double x, int m, const double *u, const double *v,
                       unsigned char *pass)
{
    for (int k0 = 0; k0 < m; k0 += TRACE_LANES) {
        int cnt = m - k0 < TRACE_LANES ? m - k0 : TRACE_LANES;
        for (int l = 0; l < p->nl; l++) {
            lens_ray r[TRACE_LANES];
            trace_result res[TRACE_LANES];
            const double *nl[TRACE_LANES];
            int idx[TRACE_LANES], c = 0;
            for (int k = k0; k < k0 + cnt; k++) {
                if (pass[k])
                    continue;
                double in[4] = {x, 0, u[k], v[k]};
                ray_from_sensor(p->lens, in, &r[c]);
                nl[c] = p->n[l];
                idx[c++] = k;
            }
            if (!c)
                break;
            trace_packet_to_object(p->lens, nl, c, r, 0, res, NULL);
            for (int k = 0; k < c; k++)
                if (res[k].status == TRACE_PASSED)
                    pass[idx[k]] = 1;
        }
    }
}

static void probe(const prober *p, double x, int m, const double *u, const double *v,
                  unsigned char *pass)
{
    if (p->lens)
        lens_probe(p, x, m, u, v, pass);
    else
        p->fn(p->ctx, x, m, u, v, pass);
}

/* Probes the cell centres of a g x g grid at origin (u0, v0), cell (du, dv). */
static void probe_grid(const prober *p, double x, int g, double u0, double v0, double du,
                       double dv, unsigned char *pass)
{
    double u[g], v[g];
    memset(pass, 0, (size_t)g * g);
    for (int j = 0; j < g; j++) {
        for (int i = 0; i < g; i++) {
            u[i] = u0 + (i + 0.5) * du;
            v[i] = v0 + (j + 0.5) * dv;
        }
        probe(p, x, g, u, v, pass + (size_t)j * g);
    }
}

/* A box in (u, v) that holds every passing direction from (r, 0): a passing ray crosses
 * the rear surface inside its semi-diameter, between the nearest and farthest z that
 * surface reaches there (a caller's probe: the plane at rear_dist, within rear_radius). */
static void outer_box(const prober *p, double r, double box[4])
{
    double sd, dmin, dmax;
    if (p->lens) {
        const lens_t *lens = p->lens;
        size_t k = lens->nsurf - 1;
        const lens_surface *s = &lens->surf[k];
        double T = lens_total_track(lens);
        double zmin = INFINITY, zmax = -INFINITY;
        sd = s->semi_diameter;
        for (int i = 0; i <= 32; i++) {
            double h = sd * i / 32.0, z = lens->vertex_z[k] + lens_sag(s, h * h);
            zmin = fmin(zmin, z);
            zmax = fmax(zmax, z);
        }
        /* D = distance from the sensor to the crossing; guard a rear surface that nearly
         * touches the sensor. */
        dmin = fmax(T - zmax, 1e-3), dmax = fmax(T - zmin, 1e-3);
    } else {
        sd = p->rear_radius;
        dmin = dmax = p->rear_dist;
    }
    box[0] = fmin((-sd - r) / dmin, (-sd - r) / dmax);
    box[1] = fmax((sd - r) / dmin, (sd - r) / dmax);
    box[2] = -sd / dmin;
    box[3] = sd / dmin;
}

static int build_set(const prober *p, double r, int g, pupil_set *set)
{
    double box[4];
    outer_box(p, r, box);
    /* Coarse probe over the whole box for the extent of the passing set. */
    double cu = (box[1] - box[0]) / COARSE, cv = (box[3] - box[2]) / COARSE;
    int imin = COARSE, imax = -1, jmin = COARSE, jmax = -1;
    unsigned char coarse[COARSE * COARSE];
    probe_grid(p, r, COARSE, box[0], box[2], cu, cv, coarse);
    for (int j = 0; j < COARSE; j++)
        for (int i = 0; i < COARSE; i++)
            if (coarse[j * COARSE + i]) {
                imin = i < imin ? i : imin;
                imax = i > imax ? i : imax;
                jmin = j < jmin ? j : jmin;
                jmax = j > jmax ? j : jmax;
            }
    memset(set, 0, sizeof *set);
    set->g = g;
    if (imax < 0)
        return 0; /* nothing passes from this radius */
    /* Fine grid over the extent grown by 1.5 coarse cells (partly covered cells). */
    set->u0 = box[0] + (imin - 1.5) * cu;
    set->v0 = box[2] + (jmin - 1.5) * cv;
    set->du = (imax - imin + 4) * cu / g;
    set->dv = (jmax - jmin + 4) * cv / g;
    unsigned char *hit = calloc((size_t)g * g, 1);
    set->occ = calloc(((size_t)g * g + 63) / 64, sizeof *set->occ);
    if (!hit || !set->occ) {
        free(hit);
        return -1;
    }
    probe_grid(p, r, g, set->u0, set->v0, set->du, set->dv, hit);
    /* Dilate by one cell: a cell whose centre misses may still be partly inside. */
    for (int j = 0; j < g; j++)
        for (int i = 0; i < g; i++) {
            int on = 0;
            for (int b = j - 1; b <= j + 1 && !on; b++)
                for (int a = i - 1; a <= i + 1 && !on; a++)
                    on = a >= 0 && a < g && b >= 0 && b < g && hit[b * g + a];
            if (on)
                set->occ[((size_t)j * g + i) / 64] |= 1ull << (((size_t)j * g + i) % 64);
        }
    free(hit);
    return set_finish(set);
}

void pupil_sampler_free(pupil_sampler *ps)
{
    if (!ps)
        return;
    for (int i = 0; i < ps->nr && ps->sets; i++) {
        free(ps->sets[i].occ);
        free(ps->sets[i].runs);
        free(ps->sets[i].row_run);
    }
    free(ps->sets);
    free(ps);
}

static int check_options(const pupil_sampler_options *opt, lens_err *err)
{
    if (!(opt->sensor_radius > 0) || !isfinite(opt->sensor_radius)) {
        lens_errf(err, NULL, 0, "pupil sampler: sensor radius must be positive");
        return -1;
    }
    if (!(opt->lambda_min > 0) || !(opt->lambda_max >= opt->lambda_min)) {
        lens_errf(err, NULL, 0, "pupil sampler: bad wavelength range %g..%g", opt->lambda_min,
                  opt->lambda_max);
        return -1;
    }
    return 0;
}

/* The tabulated sets, one per radius, in parallel. */
static pupil_sampler *build_sets(const prober *p, const pupil_sampler_options *opt,
                                 lens_err *err)
{
    pupil_sampler *ps = calloc(1, sizeof *ps);
    if (!ps) {
        lens_errf(err, NULL, 0, "out of memory");
        return NULL;
    }
    ps->nr = opt->radii > 1 ? opt->radii : 64;
    ps->rmax = opt->sensor_radius;
    ps->r_scale = (ps->nr - 1) / ps->rmax;
    int g = opt->grid > 0 ? opt->grid : 96;
    ps->sets = calloc((size_t)ps->nr, sizeof *ps->sets);
    int failed = !ps->sets;
    if (!failed) {
        int nth = opt->threads;
#pragma omp parallel for schedule(dynamic, 1) num_threads(nth > 0 ? nth : omp_get_max_threads()) reduction(| : failed)
        for (int i = 0; i < ps->nr; i++)
            failed |= build_set(p, ps->rmax * i / (ps->nr - 1), g, &ps->sets[i]) != 0;
    }
    if (failed) {
        lens_errf(err, NULL, 0, "out of memory");
        pupil_sampler_free(ps);
        return NULL;
    }
    return ps;
}

pupil_sampler *pupil_sampler_build(const lens_t *lens, const pupil_sampler_options *opt,
                                   lens_err *err)
{
    if (check_options(opt, err))
        return NULL;
    prober p = {.lens = lens};
    double lam[MAX_LAMBDAS];
    for (int l = 0; l < MAX_LAMBDAS; l++)
        lam[l] = opt->lambda_min + (opt->lambda_max - opt->lambda_min) * l / (MAX_LAMBDAS - 1);
    p.nl = opt->lambda_max > opt->lambda_min ? MAX_LAMBDAS : 1;
    pupil_sampler *ps = NULL;
    int l = 0, bad = 0;
    for (; l < p.nl && !bad; l++) {
        p.n[l] = malloc(lens->nsurf * sizeof *p.n[l]);
        if (!p.n[l])
            lens_errf(err, NULL, 0, "out of memory");
        bad = !p.n[l] || lens_indices(lens, lam[l], p.n[l], err);
    }
    if (!bad)
        ps = build_sets(&p, opt, err);
    for (int m = 0; m < l; m++)
        free(p.n[m]);
    return ps;
}

pupil_sampler *pupil_sampler_build_probe(pupil_probe_fn fn, void *ctx, double rear_dist,
                                         double rear_radius, const pupil_sampler_options *opt,
                                         lens_err *err)
{
    if (check_options(opt, err))
        return NULL;
    if (!fn || !(rear_dist > 0) || !(rear_radius > 0)) {
        lens_errf(err, NULL, 0, "pupil sampler: no probe, or a bad rear plane (%g mm, radius %g mm)",
                  rear_dist, rear_radius);
        return NULL;
    }
    prober p = {.fn = fn, .ctx = ctx, .rear_dist = rear_dist, .rear_radius = rear_radius};
    return build_sets(&p, opt, err);
}

/* The cache file: a magic line, then per set its grid and its occupancy as a bitmap
 * (the runs are rebuilt from it as build_set made them),
 * binary in the machine's byte order (a cache, read back on the machine that wrote it). */
static const char cache_magic[16] = "pupil_sampler 2";

int pupil_sampler_write(FILE *f, const pupil_sampler *ps)
{
    int ok = fwrite(cache_magic, sizeof cache_magic, 1, f) == 1 &&
             fwrite(&ps->nr, sizeof ps->nr, 1, f) == 1 && fwrite(&ps->rmax, sizeof ps->rmax, 1, f) == 1;
    for (int i = 0; ok && i < ps->nr; i++) {
        const pupil_set *s = &ps->sets[i];
        double w[4] = {s->u0, s->v0, s->du, s->dv};
        int gc[2] = {s->g, s->count};
        ok = fwrite(w, sizeof w, 1, f) == 1 && fwrite(gc, sizeof gc, 1, f) == 1;
        if (!ok || !s->count)
            continue;
        size_t nb = ((size_t)s->g * s->g + 7) / 8;
        unsigned char *bits = calloc(nb, 1);
        if (!bits)
            return -1;
        for (size_t c = 0; c < (size_t)s->g * s->g; c++)
            if (occupied(s, c))
                bits[c / 8] |= (unsigned char)(1u << (c % 8));
        ok = fwrite(bits, 1, nb, f) == nb;
        free(bits);
    }
    return ok ? 0 : -1;
}

pupil_sampler *pupil_sampler_read(FILE *f, lens_err *err)
{
    char magic[sizeof cache_magic];
    pupil_sampler *ps = calloc(1, sizeof *ps);
    int ok = ps && fread(magic, sizeof magic, 1, f) == 1 && !memcmp(magic, cache_magic, sizeof magic) &&
             fread(&ps->nr, sizeof ps->nr, 1, f) == 1 && fread(&ps->rmax, sizeof ps->rmax, 1, f) == 1 &&
             ps->nr > 1 && ps->nr <= 1 << 16 && ps->rmax > 0 && isfinite(ps->rmax);
    if (ok)
        ps->r_scale = (ps->nr - 1) / ps->rmax;
    if (ok && !(ps->sets = calloc((size_t)ps->nr, sizeof *ps->sets)))
        ok = 0;
    for (int i = 0; ok && i < ps->nr; i++) {
        pupil_set *s = &ps->sets[i];
        double w[4];
        int gc[2];
        ok = fread(w, sizeof w, 1, f) == 1 && fread(gc, sizeof gc, 1, f) == 1 && gc[0] > 0 &&
             gc[0] <= 4096 && gc[1] >= 0 && gc[1] <= gc[0] * gc[0] && w[2] > 0 && w[3] > 0 &&
             isfinite(w[0]) && isfinite(w[1]) && isfinite(w[2]) && isfinite(w[3]);
        if (!ok)
            break;
        s->u0 = w[0], s->v0 = w[1], s->du = w[2], s->dv = w[3], s->g = gc[0];
        if (gc[1] == 0)
            continue;
        size_t n = (size_t)s->g * s->g, nb = (n + 7) / 8;
        unsigned char *bits = malloc(nb);
        s->occ = calloc((n + 63) / 64, sizeof *s->occ);
        ok = bits && s->occ && fread(bits, 1, nb, f) == nb;
        for (size_t c = 0; ok && c < n; c++)
            if (bits[c / 8] >> (c % 8) & 1)
                s->occ[c / 64] |= 1ull << (c % 64);
        free(bits);
        ok = ok && set_finish(s) == 0 && s->count == gc[1];
    }
    if (!ok) {
        lens_errf(err, NULL, 0, "pupil sampler: not a cached sampler, or a damaged one");
        pupil_sampler_free(ps);
        return NULL;
    }
    return ps;
}

/* 1 when (u, v), in the frame of the point (r, 0), lies in an occupied cell of set. */
static int in_set(const pupil_set *set, double u, double v)
{
    if (!set->count)
        return 0;
    double fi = floor((u - set->u0) * set->inv_du), fj = floor((v - set->v0) * set->inv_dv);
    if (!(fi >= 0 && fi < set->g && fj >= 0 && fj < set->g))
        return 0;
    return occupied(set, (size_t)fj * set->g + (size_t)fi);
}

/* The two tabulated radii around r, and the rotation taking (r, 0) to (x, y). */
static int locate(const pupil_sampler *ps, double x, double y, int *j, double *c, double *s)
{
    /* sqrt, not hypot, and products, not quotients: a draw a camera sample, and these
     * were a third of its time (x and y are sensor millimetres: no overflow) */
    double r = sqrt(x * x + y * y);
    if (!(r <= ps->rmax * (1 + 1e-12)))
        return -1;
    double t = r * ps->r_scale;
    int k = (int)t;
    *j = k > ps->nr - 2 ? ps->nr - 2 : k;
    if (r > 0) {
        double inv = 1 / r;
        *c = x * inv;
        *s = y * inv;
    } else {
        *c = 1;
        *s = 0;
    }
    return 0;
}

/* What both samplers share: the two sets around the point's radius, and one random
 * number picking one of them in proportion to area, reduced to the cell count t within
 * the chosen set.  Returns -1 where nothing can be drawn. */
typedef struct {
    const pupil_set *set, *other;
    double total, cells, c, s;
    int k, ci, cj; /* the cell the count falls in, and its grid place */
} pupil_draw;

static int draw_set(const pupil_sampler *ps, double x, double y, double rnd, pupil_draw *d)
{
    int j;
    if (locate(ps, x, y, &j, &d->c, &d->s))
        return -1;
    const pupil_set *a = &ps->sets[j], *b = &ps->sets[j + 1];
    d->total = a->area + b->area;
    if (!(d->total > 0))
        return -1;
    double t = rnd * d->total;
    d->set = a;
    d->other = b;
    if (t >= a->area || a->count == 0) {
        d->set = b;
        d->other = a;
        t = t - a->area > 0 ? t - a->area : 0; /* fmax(.., 0), inline (a draw a sample) */
    }
    d->cells = t * d->set->inv_cell;
    d->k = (int)d->cells;
    if (d->k >= d->set->count)
        d->k = d->set->count - 1;
    set_cell(d->set, d->k, &d->ci, &d->cj);
    return 0;
}

/* Turns the set-frame point back to (u, v) and gives the mixture's density there:
 * 1/total in each set that holds the point. */
static void finish_draw(const pupil_draw *d, double up, double vp, double *u, double *v, double *pdf)
{
    *u = d->c * up - d->s * vp;
    *v = d->s * up + d->c * vp;
    *pdf = (1 + in_set(d->other, up, vp)) / d->total;
}

int pupil_sampler_sample(const pupil_sampler *ps, double x, double y, const double rnd[2],
                         double *u, double *v, double *pdf)
{
    pupil_draw d;
    *u = *v = NAN;
    *pdf = 0;
    /* One number picks the set (in proportion to area), the cell and the position
     * across it; the other the position along it. */
    if (draw_set(ps, x, y, rnd[0], &d))
        return -1;
    const pupil_set *set = d.set;
    double fu = fmin(d.cells - d.k, 1);
    finish_draw(&d, set->u0 + (d.ci + fu) * set->du, set->v0 + (d.cj + rnd[1]) * set->dv, u, v, pdf);
    return 0;
}

int pupil_sampler_sample_rows(const pupil_sampler *ps, double x, double y, const double rnd[2],
                              double *u, double *v, double *pdf)
{
    pupil_draw d;
    *u = *v = NAN;
    *pdf = 0;
    /* rnd[1] picks the set (in proportion to area) and, in it, the row and the height
     * across it, row by row in cell order: uniform over the set, monotone in v */
    if (draw_set(ps, x, y, rnd[1], &d))
        return -1;
    const pupil_set *set = d.set;
    int cj = d.cj;
    const pupil_run *row = set->runs + set->row_run[cj], *end = set->runs + set->row_run[cj + 1];
    int nrow = end->cum - row->cum;
    double fv = (d.cells - row->cum) / nrow, fu;
    fv = fv < 1 ? fv : 1; /* fmin(.., 1) and, below, fmax(.., 0), inline */
    /* rnd[0] the position along the row's occupied cells: monotone in u */
    double t1 = rnd[0] * nrow;
    int q = (int)t1;
    if (q >= nrow)
        q = nrow - 1;
    fu = t1 - q < 1 ? t1 - q : 1;
    while (row + 1 < end && row[1].cum <= row->cum + q)
        q -= row[1].cum - row->cum, row++;
    finish_draw(&d, set->u0 + (row->i0 + q + fu) * set->du, set->v0 + (cj + (fv > 0 ? fv : 0)) * set->dv,
                u, v, pdf);
    return 0;
}

double pupil_sampler_pdf(const pupil_sampler *ps, double x, double y, double u, double v)
{
    int j;
    double c, s;
    if (locate(ps, x, y, &j, &c, &s) || !isfinite(u) || !isfinite(v))
        return 0;
    double up = c * u + s * v, vp = -s * u + c * v;
    const pupil_set *sets[2] = {&ps->sets[j], &ps->sets[j + 1]};
    double total = sets[0]->area + sets[1]->area, pdf = 0;
    if (!(total > 0))
        return 0;
    for (int m = 0; m < 2; m++)
        pdf += in_set(sets[m], up, vp) / total;
    return pdf;
}
