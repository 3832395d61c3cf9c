/* lens-trace's job (trace_run.h): the columns (the stop's and the clip surfaces' hits,
 * chosen by a pilot trace or given), the preamble, then generation or the filter. */
#include "sparselens/trace_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/escape.h"
#include "sparselens/sampling.h"
#include "sparselens/trace.h"
#include "sparselens/clip_pilot.h"
#include "sparselens/trace_clip.h"

static const char *const base_columns[] = {"x", "y", "u", "v", "lambda",
                                           "out_x", "out_y", "out_u", "out_v", "out_eta",
                                           "ap_x", "ap_y"};
enum { NCOLS = 10, NCOLS_STOP = 12 };
/* Rays of the pilot trace that picks the clip surfaces, and its seed: fixed, so that a
 * training and a test set traced with different --seed get the same columns. A surface
 * is modelled while it alone would let through >= CLIP_MIN_SHARE of the light: a tenth
 * of the 0.5 % a system may disagree on in all (reports/vignetting.md). */
enum { PILOT_RAYS = 65536, PILOT_SEED = 20161, MAX_CLIP = 8 };
#define CLIP_MIN_SHARE 0.0005

typedef struct {
    const char *lens_path;
    long count;
    unsigned long seed;
    sampling_strategy strategy;
    double lambda_min, lambda_max, sensor_w, sensor_h;
    trace_target target;
    int all, threads, from_stdin, stop_columns, clip_columns;
    const char *clip_list;
    int nclip, *clip;        /* clip surfaces, 0-based (besides the stop) */
    int *sel;                /* the stop, then the clip surfaces (clip = sel + 1) */
    double *clip_share;      /* pilot: light share per surface (trace_clip.h), or NULL */
    double clip_leak;        /* pilot: light no modelled surface blocks */
    char **names;            /* column names */
    double fnumber;          /* --fnumber, or NAN */
    const trace_run_hooks *hooks;
} trace_args;

static int ncols(const trace_args *a)
{
    return (a->stop_columns ? NCOLS_STOP : NCOLS) + 2 * a->nclip;
}

/* A path with a control byte is not recorded: escaped, it would name another file. */
static int has_control(const char *s)
{
    for (; *s; s++)
        if ((unsigned char)*s < 0x20 || *s == 0x7f)
            return 1;
    return 0;
}

static void write_preamble(FILE *f, const lens_t *lens, const trace_args *a)
{
    /* names from the command line and the lens file, escaped: none forges a line */
    fputs("# lens-trace ", f);
    text_line(f, a->lens_path);
    fputs(": lens ", f);
    text_line(f, lens->name[0] ? lens->name : "-");
    fprintf(f, ", frame %s", a->target == TRACE_TO_STOP ? "stop" : "outer");
    if (!a->from_stdin)
        fprintf(f, ", sampling %s, seed %lu, lambda %g:%g um, sensor %gx%g mm",
                sampling_strategy_name(a->strategy), a->seed, a->lambda_min, a->lambda_max,
                a->sensor_w, a->sensor_h);
    fputc('\n', f);
    /* What lens-fit records in a system, so that the system finds its lens again; the
     * path as given, so that the same command gives the same file anywhere. */
    fputs("# lens: ", f);
    text_line(f, lens->name[0] ? lens->name : "-");
    fputc('\n', f);
    if (strcmp(a->lens_path, "-") != 0 && !has_control(a->lens_path))
        fprintf(f, "# lens-path: %s\n", a->lens_path);
    /* where out_x .. out_v are (--to): lens-fit records it, lens-eval --report and the
     * commands that show a system check it */
    fprintf(f, "# frame: %s\n", a->target == TRACE_TO_STOP ? "stop" : "outer");
    if (!isnan(a->fnumber))
        fprintf(f, "# fnumber: %.10g (the stop stopped down by --fnumber)\n", a->fnumber);
    /* lens-fit reads this line: a system's passage is complete only from a pilot */
    if (a->clip_share) {
        fprintf(f, "# passage: full (pilot of %d rays over the full ray space, shares of the "
                "light the lens passes): stop %d blocks %.3g%%", PILOT_RAYS, lens->stop + 1,
                100 * a->clip_share[lens->stop]);
        if (a->target == TRACE_TO_OUTER)
            fprintf(f, ", front 1 %.3g%%", 100 * a->clip_share[0]);
        for (int k = 0; k < a->nclip; k++)
            fprintf(f, ", %d +%.3g%%", a->clip[k] + 1, 100 * a->clip_share[a->clip[k]]);
        fprintf(f, "; unmodelled %.3g%%\n", 100 * a->clip_leak);
    } else {
        fprintf(f, "# passage: partial (%s)\n", a->clip_list ? "clip surfaces given, no pilot"
                                                : a->stop_columns ? "stop columns only"
                                                                  : "no passage columns");
    }
}

static void sampling_setup(const trace_args *a, sampling_options *so)
{
    *so = sampling_defaults();
    so->strategy = a->strategy;
    so->sensor_w = a->sensor_w;
    so->sensor_h = a->sensor_h;
    so->lambda_min = a->lambda_min;
    so->lambda_max = a->lambda_max;
    so->seed = a->seed;
    so->threads = a->threads;
}

/* The clip surfaces: those given, or those a pilot trace finds blocking rays. */
static int choose_clip(const lens_t *lens, trace_args *a, lens_err *err)
{
    if (a->clip_list) {
        const char *p = a->clip_list;
        while (*p) {
            char *end;
            long s = strtol(p, &end, 10);
            if (end == p || (*end && *end != ',') || s < 1 || (size_t)s > lens->nsurf) {
                lens_errf(err, NULL, 0, "--clip-surfaces: expected surface numbers 1..%zu "
                          "separated by commas, not '%s'", lens->nsurf, a->clip_list);
                return -1;
            }
            int dup = (int)s - 1 == lens->stop; /* the stop has ap_x ap_y already */
            for (int k = 0; k < a->nclip; k++)
                dup |= a->clip[k] == (int)s - 1;
            if (!dup)
                a->clip[a->nclip++] = (int)s - 1;
            p = *end ? end + 1 : end;
        }
        return 0;
    }
    if (isnan(a->sensor_w)) { /* filter mode on a lens without a sensor: the stop alone */
        a->clip_columns = 0;
        return 0;
    }
    sampling_options so;
    sampling_setup(a, &so);
    so.seed = PILOT_SEED;
    a->clip_share = malloc(lens->nsurf * sizeof *a->clip_share);
    if (!a->clip_share) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int k = trace_clip_pilot(lens, &so, PILOT_RAYS, CLIP_MIN_SHARE, a->target == TRACE_TO_OUTER,
                             MAX_CLIP, a->clip_share, a->clip, &a->clip_leak, err);
    if (k < 0)
        return -1;
    a->nclip = k;
    return 0;
}

static int make_names(trace_args *a, lens_err *err)
{
    int nc = ncols(a), nb = a->stop_columns ? NCOLS_STOP : NCOLS;
    a->names = calloc((size_t)nc, sizeof *a->names);
    if (!a->names)
        goto oom;
    for (int k = 0; k < nb; k++)
        a->names[k] = (char *)base_columns[k];
    for (int k = 0; k < 2 * a->nclip; k++) {
        a->names[nb + k] = malloc(32);
        if (!a->names[nb + k])
            goto oom;
        snprintf(a->names[nb + k], 32, "s%d_%c", a->clip[k / 2] + 1, k % 2 ? 'y' : 'x');
    }
    return 0;
oom:
    lens_errf(err, NULL, 0, "out of memory");
    return -1;
}

static void free_names(trace_args *a)
{
    if (a->names) {
        int nb = a->stop_columns ? NCOLS_STOP : NCOLS;
        for (int k = 0; k < 2 * a->nclip; k++)
            free(a->names[nb + k]);
    }
    free(a->names);
    free(a->sel);
    free(a->clip_share);
}

/* Generation: rays are made in index order, so the first N passing rays of a seed are
 * the same whatever the chunk size or thread count. */
static int generate(const lens_t *lens, const trace_args *a, FILE *f, lens_err *err)
{
    sampling_options so;
    sampling_setup(a, &so);
    ray_generator *g = ray_generator_new(lens, &so, err);
    if (!g)
        return -1;
    const size_t chunk = 1 << 16;
    double *in = malloc(chunk * 5 * sizeof *in), *out = malloc(chunk * 5 * sizeof *out);
    int nsel = a->stop_columns + a->nclip; /* the stop, then the clip surfaces */
    double *hits = malloc(chunk * 2 * (size_t)(nsel ? nsel : 1) * sizeof *hits);
    double *row = malloc((size_t)ncols(a) * sizeof *row);
    if (!in || !out || !hits || !row) {
        lens_errf(err, NULL, 0, "out of memory");
        free(in);
        free(out);
        free(hits);
        free(row);
        ray_generator_free(g);
        return -1;
    }
    long written = 0;
    size_t next = 0;
    /* A lens that passes almost nothing would loop for ever: give up after 1000 rays
     * per wanted ray, which no usable sampling comes near. */
    size_t give_up = (size_t)a->count * 1000 + chunk;
    int rc = 0;
    while (written < a->count) {
        if (next >= give_up) {
            lens_errf(err, a->lens_path, 0, "only %ld of %zu traced rays pass the lens; "
                      "check the sensor size and the lens", written, next);
            rc = -1;
            break;
        }
        size_t n = chunk;
        if (a->all && (size_t)(a->count - written) < n)
            n = (size_t)(a->count - written);

        if (ray_generator_fill(g, next, n, in, err) != 0 ||
            trace_batch(lens, a->target, n, in, out, NULL, a->threads, err) != 0 ||
            (nsel && trace_surfaces_batch(lens, nsel, a->sel + !a->stop_columns, n, in, hits,
                                          a->threads, err) != 0)) {
            rc = -1;
            break;
        }
        next += n;
        if (next == n) {
            /* Nothing is written before the first chunk shows that enough rays pass: a
             * refusal after the header (or after some rows) would leave a sample file
             * that looks whole on stdout. */
            size_t pass = 0;
            for (size_t i = 0; i < n; i++)
                pass += out[5 * i + 4] > 0;
            if (!a->all && (double)a->count * (double)n > (double)pass * (double)give_up) {
                lens_errf(err, a->lens_path, 0, "only %zu of the first %zu traced rays pass "
                          "the lens, too few for %ld passing rays (at most 1000 traced per "
                          "ray); check the sensor size, the f-number and the lens",
                          pass, n, a->count);
                rc = -1;
                break;
            }
            write_preamble(f, lens, a);
            samples_write_header(f, (const char *const *)a->names, ncols(a));
        }
        for (size_t i = 0; i < n && written < a->count; i++) {
            if (!a->all && !(out[5 * i + 4] > 0))
                continue;
            memcpy(row, in + 5 * i, 5 * sizeof *row);
            memcpy(row + 5, out + 5 * i, 5 * sizeof *row);
            memcpy(row + NCOLS, hits + 2 * (size_t)nsel * i, 2 * (size_t)nsel * sizeof *row);
            samples_write_row(f, row, ncols(a));
            written++;
        }
        if (a->hooks && a->hooks->progress)
            a->hooks->progress(a->hooks->ctx, written, a->count, (long)next);
    }
    free(in);
    free(out);
    free(hits);
    free(row);
    ray_generator_free(g);
    return rc;
}

static void bad_row(const trace_args *a, const lens_err *err)
{
    if (a->hooks && a->hooks->on_bad_row)
        a->hooks->on_bad_row(a->hooks->ctx, err);
}

/* Filter: one output row per input row; a bad row becomes a row of nan, is reported
 * with its line, and makes the exit status non-zero at the end. Input columns that the
 * trace does not write (an id, say) follow the traced ones, as they were. */
static const char *const stream_columns[] = {"x", "y", "u", "v", "lambda"};

static int filter(const lens_t *lens, const trace_args *a, samples_reader *r, FILE *f,
                  long *bad_rows, lens_err *err)
{
    int map[5];
    if (samples_map(r, stream_columns, 5, map, err) != 0)
        return -1;
    samples_write_filter_header(f, (const char *const *)a->names, ncols(a), r);
    int nc = samples_ncols(r);
    double *vals = malloc((size_t)nc * sizeof *vals);
    double *n = malloc(lens->nsurf * sizeof *n);
    double *row = malloc((size_t)ncols(a) * sizeof *row);
    double cached_lambda = NAN;
    int cached_ok = 0;
    lens_err cached_err = {{0}};
    int st;
    int failed = 0;
    while (vals && n && row && (st = samples_next(r, vals, err)) != 0) {
        if (st == SAMPLES_FAIL) {
            failed = 1; /* the rest of the stream is lost: an error, not an end */
            break;
        }
        for (int k = 0; k < ncols(a); k++)
            row[k] = NAN;
        if (st < 0) {
            bad_row(a, err);
            ++*bad_rows;
            samples_write_filter_row(f, row, ncols(a), r);
            continue;
        }
        for (int k = 0; k < 5; k++)
            row[k] = vals[map[k]];
        int finite = 1;
        for (int k = 0; k < 5; k++)
            finite &= isfinite(row[k]) != 0;
        if (!finite) {
            lens_err e;
            lens_errf(&e, samples_path(r), samples_line(r),
                      "x, y, u, v and lambda must be finite numbers");
            bad_row(a, &e);
            ++*bad_rows;
        } else {
            if (row[4] != cached_lambda) {
                cached_lambda = row[4];
                cached_ok = lens_indices(lens, row[4], n, &cached_err) == 0;
            }
            if (!cached_ok) {
                lens_err e;
                lens_errf(&e, samples_path(r), samples_line(r), "%s", cached_err.msg);
                bad_row(a, &e);
                ++*bad_rows;
            } else {
                trace_result res = trace_sample(lens, n, a->target, row, row + 5);
                row[9] = res.status == TRACE_PASSED ? res.transmittance : 0.0;
                if (a->stop_columns)
                    trace_surface_hit(lens, lens->stop, n, row, row + NCOLS);
                for (int k = 0, nb = a->stop_columns ? NCOLS_STOP : NCOLS; k < a->nclip; k++)
                    trace_surface_hit(lens, a->clip[k], n, row, row + nb + 2 * k);
            }
        }
        samples_write_filter_row(f, row, ncols(a), r);
    }
    int rc = (vals && n && row && !failed) ? 0 : -1;
    if (rc && !failed)
        lens_errf(err, NULL, 0, "out of memory");
    free(vals);
    free(n);
    free(row);
    return rc;
}

void trace_default_band(const lens_t *lens, double *lo, double *hi)
{
    /* The visible band, widened to the file's wavelengths; then narrowed to where every
     * glass has data, but never past the file's own wavelengths (those are an error
     * where a glass has none). Wider than the file's: analyses at its F and C lines
     * then sit inside a fitted system's band, not on its edge. */
    double flo = INFINITY, fhi = -INFINITY;
    for (int i = 0; i < lens->nwaves; i++)
        flo = fmin(flo, lens->wave_um[i]), fhi = fmax(fhi, lens->wave_um[i]);
    *lo = fmin(0.4, flo), *hi = fmax(0.7, fhi);
    for (size_t i = 0; i < lens->nsurf; i++) {
        const glass_t *g = &lens->surf[i].medium;
        if (g->lambda_min > 0 && isfinite(g->lambda_min))
            *lo = fmax(*lo, fmin(g->lambda_min, flo));
        if (g->lambda_max > 0 && isfinite(g->lambda_max))
            *hi = fmin(*hi, fmax(g->lambda_max, fhi));
    }
}

int trace_run(const trace_cli *o, const lens_t *lens, samples_reader *in, FILE *out,
              const trace_run_hooks *hooks, long *bad_rows, lens_err *err)
{
    /* the passage columns: all the pilot finds unless less is asked for */
    int cols_none = o->no_passage_columns, cols_stop = o->stop_columns && !o->clip_columns;
    trace_args a = {.lens_path = o->lens_path, .count = o->count,
                    .seed = o->seed, .strategy = o->strategy, .lambda_min = o->lambda[0],
                    .lambda_max = o->lambda[1], .sensor_w = o->sensor.w,
                    .sensor_h = o->sensor.h, .target = o->target, .all = !o->passing_only,
                    .threads = o->threads, .from_stdin = o->from_stdin,
                    .stop_columns = !cols_none || o->clip_list,
                    .clip_columns = (!cols_none && !cols_stop) || o->clip_list,
                    .clip_list = o->clip_list, .fnumber = o->fnumber, .hooks = hooks};
    *bad_rows = 0;
    if (isnan(a.lambda_min)) /* the band the design file states, else the visible */
        trace_default_band(lens, &a.lambda_min, &a.lambda_max);
    if (isnan(a.sensor_w)) {
        a.sensor_w = lens->sensor_w;
        a.sensor_h = lens->sensor_h;
    }
    if (!a.from_stdin && isnan(a.sensor_w)) {
        lens_errf(err, a.lens_path, 0, "no sensor size in the lens header; give --sensor WxH");
        return -1;
    }
    a.sel = malloc((lens->nsurf + 1) * sizeof *a.sel);
    if (!a.sel) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    a.sel[0] = lens->stop;
    a.clip = a.sel + 1;
    int rc = -1;
    int map[5]; /* a stream's columns before anything is written (stdout has no undo) */
    if ((!a.from_stdin || samples_map(in, stream_columns, 5, map, err) == 0) &&
        (!a.clip_columns || choose_clip(lens, &a, err) == 0) && make_names(&a, err) == 0 &&
        (!a.from_stdin || samples_passthrough(in, (const char *const *)a.names, ncols(&a), err) >= 0)) {
        if (a.from_stdin) {
            write_preamble(out, lens, &a);
            rc = filter(lens, &a, in, out, bad_rows, err);
        } else {
            rc = generate(lens, &a, out, err); /* writes the preamble when rays pass */
        }
    }
    free_names(&a);
    return rc;
}
