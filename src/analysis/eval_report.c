/* Fitting-error report (eval_report.h). All errors are kept so the p99 is exact; a
 * test set of 1e5 rays and 5 outputs takes a few MB. */
#include "sparselens/eval_report.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/eval_passage.h"

#define ARCMIN_PER_RAD (180.0 * 60.0 / 3.14159265358979323846)

typedef struct {
    int output;  /* system output */
    int partner; /* the other direction component, -1 if none; -2 for non-angle rows */
    int angle;   /* 1: error as an angle in arcminutes */
    const char *unit;
} row_kind;

struct eval_report {
    const poly_system *sys;
    eval_report_options opt;
    int nrows;
    row_kind *rows;
    size_t n, cap; /* rays that both pass */
    double *err;   /* n x nrows */
    double *radius;
    size_t total, both, false_pass, false_block, neither;
    size_t outside, outside_lens_pass; /* rays outside the training domain, and those of
                                          them the lens passes (extrapolated values that
                                          reach the picture) */
    int nbound;    /* part boundaries (parts sorted by rmin, neighbours touching) */
    int *below, *above; /* the parts on either side of boundary b */
    double *jump;  /* nbound x noutputs: the largest |difference| seen at the boundary */
    double *rbound;
    eval_passage passage;
};



void eval_report_options_default(eval_report_options *opt)
{
    opt->nbins = 8;
    opt->rmax = 0;
    opt->dirs = EVAL_DIR_UNIT;
}

static char last_letter(const char *name)
{
    size_t n = strlen(name);
    return n ? name[n - 1] : 0;
}

/* The name with its last letter replaced by c ("out_u" -> "out_v"). */
static int partner_of(const poly_system *s, const char *name, char c)
{
    char buf[256];
    size_t n = strlen(name);
    if (n == 0 || n >= sizeof buf)
        return -1;
    memcpy(buf, name, n + 1);
    buf[n - 1] = c;
    return poly_output_index(s, buf);
}

eval_report *eval_report_new(const poly_system *s, const eval_report_options *opt)
{
    eval_report *r = calloc(1, sizeof *r);
    if (!r)
        return NULL;
    r->sys = s;
    eval_passage_init(&r->passage, s);
    if (opt)
        r->opt = *opt;
    else
        eval_report_options_default(&r->opt);
    if (r->opt.nbins < 1)
        r->opt.nbins = 1;
    int nout = poly_noutputs(s);
    r->rows = calloc((size_t)nout * 2, sizeof *r->rows);
    if (!r->rows) {
        free(r);
        return NULL;
    }
    for (int o = 0; o < nout; o++) {
        const char *name = poly_output_name(s, o);
        char c = last_letter(name);
        row_kind k = {o, -2, 0, "1"};
        if (c == 'x' || c == 'y')
            k.unit = "mm";
        r->rows[r->nrows++] = k;
        if (c == 'u' || c == 'v') {
            k.partner = partner_of(s, name, c == 'u' ? 'v' : 'u');
            k.angle = 1;
            k.unit = "arcmin";
            r->rows[r->nrows++] = k;
        }
    }
    /* Boundaries: where one part's rmax is another's rmin. */
    int np = poly_nparts(s);
    if (np > 1) {
        r->below = calloc((size_t)np, sizeof(int));
        r->above = calloc((size_t)np, sizeof(int));
        r->rbound = calloc((size_t)np, sizeof(double));
        r->jump = calloc((size_t)np * (size_t)nout, sizeof(double));
        if (!r->below || !r->above || !r->rbound || !r->jump) {
            eval_report_free(r);
            return NULL;
        }
        for (int p = 0; p < np; p++)
            for (int q = 0; q < np; q++) {
                double a0, a1, b0, b1;
                poly_part_range(s, p, &a0, &a1);
                poly_part_range(s, q, &b0, &b1);
                if (a1 == b0) {
                    r->below[r->nbound] = p;
                    r->above[r->nbound] = q;
                    r->rbound[r->nbound++] = a1;
                }
            }
        /* in order of radius */
        for (int i = 1; i < r->nbound; i++)
            for (int j = i; j > 0 && r->rbound[j - 1] > r->rbound[j]; j--) {
                double t = r->rbound[j];
                r->rbound[j] = r->rbound[j - 1];
                r->rbound[j - 1] = t;
                int u = r->below[j];
                r->below[j] = r->below[j - 1];
                r->below[j - 1] = u;
                u = r->above[j];
                r->above[j] = r->above[j - 1];
                r->above[j - 1] = u;
            }
    }
    return r;
}

void eval_report_free(eval_report *r)
{
    if (!r)
        return;
    eval_passage_free(&r->passage);
    free(r->rows);
    free(r->err);
    free(r->radius);
    free(r->below);
    free(r->above);
    free(r->jump);
    free(r->rbound);
    free(r);
}

int eval_reference_passes(const poly_system *s, const double *ref)
{
    for (int o = 0; o < poly_noutputs(s); o++)
        if (!isfinite(ref[o]))
            return 0;
    int e = poly_output_index(s, "out_eta");
    return e < 0 || ref[e] > 0;
}

static void direction(eval_dir_kind kind, double a, double b, double d[3])
{
    if (kind == EVAL_DIR_SLOPE) {
        double n = sqrt(a * a + b * b + 1);
        d[0] = a / n;
        d[1] = b / n;
        d[2] = 1 / n;
    } else {
        d[0] = a;
        d[1] = b;
        double w = 1 - a * a - b * b;
        d[2] = w > 0 ? sqrt(w) : 0;
    }
}

/* Angle between two directions, accurate also when tiny (atan2 of |cross| and dot). */
static double angle(const double p[3], const double q[3])
{
    double c[3] = {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2],
                   p[0] * q[1] - p[1] * q[0]};
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                 p[0] * q[0] + p[1] * q[1] + p[2] * q[2]);
}

void eval_report_set_outside(eval_report *r, size_t outside, size_t lens_passes)
{
    r->outside = outside;
    r->outside_lens_pass = lens_passes;
}

int eval_report_add(eval_report *r, const double *in, const double *pred, int sys_pass,
                    const double *ref, int lens_pass)
{
    r->total++;
    if (eval_passage_add(&r->passage, in, pred, sys_pass, ref, lens_pass) != 0)
        return -1;
    if (sys_pass && !lens_pass) {
        r->false_pass++;
        return 0;
    }
    if (!sys_pass && lens_pass) {
        r->false_block++;
        return 0;
    }
    if (!sys_pass) {
        r->neither++;
        return 0;
    }
    r->both++;
    if (r->n == r->cap) {
        size_t nc = r->cap ? r->cap * 2 : 1024;
        double *ne = realloc(r->err, nc * (size_t)r->nrows * sizeof(double));
        if (!ne)
            return -1;
        r->err = ne;
        double *nr = realloc(r->radius, nc * sizeof(double));
        if (!nr)
            return -1;
        r->radius = nr;
        r->cap = nc;
    }
    double *e = r->err + r->n * (size_t)r->nrows;
    for (int k = 0; k < r->nrows; k++) {
        const row_kind *rk = &r->rows[k];
        int o = rk->output;
        if (!rk->angle) {
            e[k] = fabs(pred[o] - ref[o]);
            continue;
        }
        /* the reference direction against the one with only this component predicted */
        int first = last_letter(poly_output_name(r->sys, o)) == 'u';
        double other = rk->partner >= 0 ? ref[rk->partner] : 0;
        double dp[3], dr[3];
        if (first) {
            direction(r->opt.dirs, pred[o], other, dp);
            direction(r->opt.dirs, ref[o], other, dr);
        } else {
            direction(r->opt.dirs, other, pred[o], dp);
            direction(r->opt.dirs, other, ref[o], dr);
        }
        e[k] = angle(dp, dr) * ARCMIN_PER_RAD;
    }
    int ix = poly_input_index(r->sys, "x"), iy = poly_input_index(r->sys, "y");
    double rr = ix >= 0 && iy >= 0 ? sqrt(in[ix] * in[ix] + in[iy] * in[iy]) : NAN;
    r->radius[r->n] = rr;
    r->n++;
    /* The ray moved radially onto each boundary, evaluated by the parts on both sides,
     * where both pass it there: a ray the system blocks at the boundary shows only
     * extrapolated values, no jump a picture sees (counted, fisheye-ii's 3-part fit
     * jumped 1.04 mm in out_x, 100 times its jump on the rays it passes). */
    if (r->nbound > 0 && rr > 0) {
        int nin = poly_ninputs(r->sys), nout = poly_noutputs(r->sys);
        double buf[3 * 64];
        if (nin > 64 || nout > 64)
            return 0;
        double *moved = buf, *pa = buf + 64, *pb = buf + 128;
        memcpy(moved, in, (size_t)nin * sizeof(double));
        for (int b = 0; b < r->nbound; b++) {
            moved[ix] = in[ix] * r->rbound[b] / rr;
            moved[iy] = in[iy] * r->rbound[b] / rr;
            const int pass_a = poly_eval_part(r->sys, r->below[b], moved, pa);
            const int pass_b = poly_eval_part(r->sys, r->above[b], moved, pb);
            for (int o = 0; o < nout && pass_a && pass_b; o++) {
                double d = fabs(pa[o] - pb[o]);
                if (d > r->jump[(size_t)b * (size_t)nout + (size_t)o])
                    r->jump[(size_t)b * (size_t)nout + (size_t)o] = d;
            }
        }
    }
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct {
    size_t n;
    double rms, mean, p99, max;
} stats;

/* Statistics of row k over the rays whose radius lies in [lo, hi) (or all, if !bin). */
static stats row_stats(const eval_report *r, int k, int bin, double lo, double hi, int last,
                       double *buf)
{
    stats st = {0, NAN, NAN, NAN, NAN};
    size_t n = 0;
    double ss = 0, sum = 0;
    for (size_t i = 0; i < r->n; i++) {
        if (bin) {
            double rr = r->radius[i];
            if (!(rr >= lo && (rr < hi || (last && rr <= hi))))
                continue;
        }
        double e = r->err[i * (size_t)r->nrows + (size_t)k];
        buf[n++] = e;
        ss += e * e;
        sum += e;
    }
    st.n = n;
    if (n == 0)
        return st;
    qsort(buf, n, sizeof *buf, cmp_double);
    st.rms = sqrt(ss / (double)n);
    st.mean = sum / (double)n;
    size_t rank = (size_t)ceil(0.99 * (double)n); /* nearest rank, 1-based */
    if (rank < 1)
        rank = 1;
    st.p99 = buf[rank - 1];
    st.max = buf[n - 1];
    return st;
}

static void put_stats(table_out *t, const stats *st)
{
    table_out_int(t, (long long)st->n);
    double v[] = {st->rms, st->mean, st->p99, st->max};
    for (int k = 0; k < 4; k++)
        table_out_num(t, v[k], 0);
}

/* A row's unique key: the output's name and its unit ("out_x_mm", "out_u_arcmin"; a
 * dimensionless error, unit 1, keeps the bare name: "out_u", "out_eta"). */
static void put_key(table_out *t, const char *output, const char *unit)
{
    char key[300];
    if (strcmp(unit, "1") == 0)
        snprintf(key, sizeof key, "%s", output);
    else
        snprintf(key, sizeof key, "%s_%s", output, unit);
    table_out_str(t, key);
}

static void write_radius_bins(table_out *t, const eval_report *r, double *buf)
{
    double rmax = r->opt.rmax;
    if (!(rmax > 0)) {
        rmax = 0;
        for (size_t i = 0; i < r->n; i++)
            if (r->radius[i] > rmax)
                rmax = r->radius[i];
    }
    static const char *const cols[] = {"key", "rmin_mm", "rmax_mm", "rays", "rms", "mean",
                                       "p99", "max", "unit"};
    table_out_table(t, "error_by_radius",
                    "error by sensor radius sqrt(x^2 + y^2) in mm, bins [rmin, rmax)", cols, 9);
    for (int k = 0; k < r->nrows; k++)
        for (int b = 0; b < r->opt.nbins; b++) {
            double lo = rmax * b / r->opt.nbins, hi = rmax * (b + 1) / r->opt.nbins;
            stats st = row_stats(r, k, 1, lo, hi, b == r->opt.nbins - 1, buf);
            put_key(t, poly_output_name(r->sys, r->rows[k].output), r->rows[k].unit);
            table_out_num(t, lo, 0);
            table_out_num(t, hi, 0);
            put_stats(t, &st);
            table_out_str(t, r->rows[k].unit);
            table_out_row_end(t);
        }
}

static void write_part_jumps(table_out *t, const eval_report *r)
{
    int nout = poly_noutputs(r->sys);
    static const char *const cols[] = {"key", "radius_mm", "jump", "unit"};
    table_out_table(t, "part_jumps",
                    "part boundaries: the largest jump between the neighbouring parts' values,\n"
                    "over the passing rays moved radially onto the boundary (where both\n"
                    "parts pass them)", cols, 4);
    for (int o = 0; o < nout; o++) {
        char c = last_letter(poly_output_name(r->sys, o));
        const char *unit = c == 'x' || c == 'y' ? "mm" : "1";
        for (int b = 0; b < r->nbound; b++) {
            put_key(t, poly_output_name(r->sys, o), unit);
            table_out_num(t, r->rbound[b], 0);
            table_out_num(t, r->jump[(size_t)b * (size_t)nout + (size_t)o], 0);
            table_out_str(t, unit);
            table_out_row_end(t);
        }
    }
}

static void count(table_out *t, const char *key, size_t n)
{
    table_out_str(t, key);
    table_out_int(t, (long long)n);
    table_out_row_end(t);
}

int eval_report_print(table_out *t, const eval_report *r)
{
    double *buf = malloc((r->n ? r->n : 1) * sizeof(double));
    if (!buf)
        return -1;
    static const char *const cols[] = {"key", "rays", "rms", "mean", "p99", "max", "unit"};
    table_out_table(t, "error", NULL, cols, 7);
    for (int k = 0; k < r->nrows; k++) {
        stats st = row_stats(r, k, 0, 0, 0, 0, buf);
        put_key(t, poly_output_name(r->sys, r->rows[k].output), r->rows[k].unit);
        put_stats(t, &st);
        table_out_str(t, r->rows[k].unit);
        table_out_row_end(t);
    }
    if (poly_input_index(r->sys, "x") >= 0 && poly_input_index(r->sys, "y") >= 0)
        write_radius_bins(t, r, buf);
    else if (!t->json)
        fputs("\n# error by sensor radius: the system has no inputs x and y: no radius bins\n",
              t->f);
    if (r->nbound > 0)
        write_part_jumps(t, r);
    table_out_keys(t, "passage",
                   "passage: false_pass = the system lets through what the lens blocks,\n"
                   "false_block = the reverse; light_* the same as shares of the light the lens\n"
                   "passes (see man lens-eval)");
    count(t, "rays", r->total);
    count(t, "both_pass", r->both);
    /* false blocks are measured on any ray the lens passes; false passes need rays it
     * blocks (a --passing-only test set has none) */
    if (eval_passage_measured(&r->passage))
        count(t, "false_pass", r->false_pass);
    count(t, "false_block", r->false_block);
    if (eval_passage_measured(&r->passage))
        count(t, "both_block", r->neither);
    count(t, "outside_domain", r->outside);
    count(t, "outside_domain_lens_passes", r->outside_lens_pass);
    eval_passage_write(t, &r->passage);
    free(buf);
    return ferror(t->f) ? -1 : 0;
}

int eval_report_write(FILE *f, const eval_report *r)
{
    table_out t;
    table_out_begin(&t, f, 0, 0, 6);
    int rc = eval_report_print(&t, r);
    table_out_end(&t, NULL, 0);
    return rc;
}
