/* lens-eval's stream (eval_run.h): rows are read in chunks and evaluated with
 * poly_eval_batch, so a file of any size runs in constant memory at batch speed.
 * Input columns that are neither inputs nor outputs of the system (an id, say) are
 * carried through as text, after the predictions. */
#include "sparselens/eval_run.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CHUNK 4096

void eval_run_options_default(eval_run_options *opt)
{
    memset(opt, 0, sizeof *opt);
    eval_report_options_default(&opt->ropt);
}

typedef struct {
    const poly_system *sys;
    const char **names;  /* the system's inputs, then its outputs */
    int nin, nout, ncols, eta;
    int lam_col;          /* the rows' lambda column when the system is at one wavelength */
    double lam;           /* that wavelength (its meta lambda) */
    int *map_in, *map_ref;
    double *row, *in, *pred, *ref, *outrow;
    unsigned char *pass, *bad;
    char *text;          /* the chunk's pass-through fields, row r at text + text_at[r] */
    size_t *text_at, text_len, text_cap;
} ctx_t;

/* Appends the last row's pass-through fields to the chunk's text. */
static int keep_text(ctx_t *c, const samples_reader *rd, size_t row)
{
    size_t need = samples_passthrough_text(rd, NULL, 0) + 1;
    if (c->text_len + need > c->text_cap) {
        size_t cap = 2 * (c->text_len + need) + 256;
        char *t = realloc(c->text, cap);
        if (!t)
            return -1;
        c->text = t, c->text_cap = cap;
    }
    c->text_at[row] = c->text_len;
    samples_passthrough_text(rd, c->text + c->text_len, need);
    c->text[c->text_len + need - 1] = '\0';
    c->text_len += need;
    return 0;
}

static void flush(ctx_t *c, size_t n, FILE *out, const eval_run_options *opt, eval_report *rep)
{
    poly_eval_batch(c->sys, n, c->in, c->pred, c->pass);
    for (size_t r = 0; r < n; r++) {
        const double *in = c->in + r * (size_t)c->nin;
        double *pred = c->pred + r * (size_t)c->nout;
        if (rep) {
            if (!c->bad[r]) {
                const double *ref = c->ref + r * (size_t)c->nout;
                eval_report_add(rep, in, pred, c->pass[r], ref,
                                eval_reference_passes(c->sys, ref));
            }
            continue;
        }
        double *o = c->outrow;
        if (c->bad[r]) {
            for (int k = 0; k < c->nin + c->nout; k++)
                o[k] = NAN;
        } else {
            memcpy(o, in, (size_t)c->nin * sizeof(double));
            for (int k = 0; k < c->nout; k++)
                o[c->nin + k] = opt->raw || c->pass[r] ? pred[k] : NAN;
            if (!opt->raw && !c->pass[r] && c->eta >= 0)
                o[c->nin + c->eta] = 0;
        }
        samples_write_filter_row_text(out, o, c->nin + c->nout, c->text + c->text_at[r]);
    }
    c->text_len = 0;
}

static void ctx_free(ctx_t *c)
{
    free(c->names);
    free(c->map_in);
    free(c->map_ref);
    free(c->row);
    free(c->in);
    free(c->pred);
    free(c->ref);
    free(c->outrow);
    free(c->pass);
    free(c->bad);
    free(c->text);
    free(c->text_at);
}

static int ctx_init(ctx_t *c, const poly_system *sys, const samples_reader *rd, lens_err *err)
{
    c->sys = sys;
    c->nin = poly_ninputs(sys);
    c->nout = poly_noutputs(sys);
    c->ncols = samples_ncols(rd);
    c->eta = poly_output_index(sys, "out_eta");
    c->names = malloc((size_t)(c->nin + c->nout) * sizeof *c->names);
    c->map_in = malloc((size_t)c->nin * sizeof(int));
    c->map_ref = malloc((size_t)c->nout * sizeof(int));
    c->row = malloc((size_t)(c->ncols > 0 ? c->ncols : 1) * sizeof(double));
    c->in = malloc(CHUNK * (size_t)c->nin * sizeof(double));
    c->pred = malloc(CHUNK * (size_t)c->nout * sizeof(double));
    c->ref = malloc(CHUNK * (size_t)c->nout * sizeof(double));
    c->outrow = malloc((size_t)(c->nin + c->nout) * sizeof(double));
    c->pass = malloc(CHUNK);
    c->bad = malloc(CHUNK);
    c->text_at = malloc(CHUNK * sizeof *c->text_at);
    if (!c->names || !c->map_in || !c->map_ref || !c->row || !c->in || !c->pred || !c->ref ||
        !c->outrow || !c->pass || !c->bad || !c->text_at) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    for (int i = 0; i < c->nin; i++)
        c->names[i] = poly_input_name(sys, i);
    for (int o = 0; o < c->nout; o++)
        c->names[c->nin + o] = poly_output_name(sys, o);
    return 0;
}

/* The report's reference columns (named as the outputs), or the predictions' header. */
static int start_output(ctx_t *c, samples_reader *rd, FILE *out, const eval_run_options *opt,
                        eval_report **rep, lens_err *err)
{
    if (!opt->report) {
        if (samples_passthrough(rd, c->names, c->nin + c->nout, err) < 0)
            return -1;
        samples_write_filter_header(out, c->names, c->nin + c->nout, rd);
        return 0;
    }
    for (int o = 0; o < c->nout; o++) {
        c->map_ref[o] = samples_find(rd, c->names[c->nin + o]);
        if (c->map_ref[o] < 0) {
            lens_errf(err, samples_path(rd), 0,
                      "no reference column '%s': --report needs the traced outputs "
                      "(a lens-trace test set)",
                      c->names[c->nin + o]);
            return -1;
        }
    }
    *rep = eval_report_new(c->sys, &opt->ropt);
    if (!*rep) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    return 0;
}

/* Row n of the chunk from the row just read (got: samples_next's answer): its inputs and
 * references, or marked bad (reported, evaluated as zeros, never written or counted);
 * a good row outside the training domain is counted per input. */
static void take_row(ctx_t *c, size_t n, int got, lens_err *rowerr, const samples_reader *rd,
                     const eval_run_options *opt, eval_run_stats *st)
{
    double *in = c->in + n * (size_t)c->nin;
    c->bad[n] = got <= 0;
    if (got > 0) {
        for (int i = 0; i < c->nin; i++)
            in[i] = c->row[c->map_in[i]];
        for (int i = 0; i < c->nin && !c->bad[n]; i++)
            if (!isfinite(in[i])) {
                lens_errf(rowerr, samples_path(rd), samples_line(rd),
                          "input '%s' is not a finite number", c->names[i]);
                c->bad[n] = 1;
            }
        if (opt->report)
            for (int o = 0; o < c->nout; o++)
                c->ref[n * (size_t)c->nout + (size_t)o] = c->row[c->map_ref[o]];
    }
    if (c->bad[n]) {
        st->bad_rows++;
        for (int i = 0; i < c->nin; i++)
            in[i] = 0;
        if (opt->on_bad_row)
            opt->on_bad_row(opt->ctx, rowerr);
    } else if (c->lam_col >= 0) { /* a pass-through column: vals has nan, the text the number */
        const double lam = samples_field_number(rd, c->lam_col);
        st->other_lambda += !(fabs(lam - c->lam) <= 1e-12 * c->lam);
    }
    if (!c->bad[n] && !poly_in_domain(c->sys, in)) {
        const int lens_passes =
            opt->report && eval_reference_passes(c->sys, c->ref + n * (size_t)c->nout);
        st->outside++;
        st->outside_passing += lens_passes;
        for (int i = 0; i < c->nin && i < 64; i++) {
            double lo, hi;
            poly_get_domain(c->sys, i, &lo, &hi);
            if (!(in[i] >= lo && in[i] <= hi)) {
                st->outside_input[i]++;
                st->outside_passing_input[i] += lens_passes;
            }
        }
    }
    st->rows++;
}

int eval_run(const poly_system *sys, samples_reader *rd, FILE *out, const eval_run_options *opt,
             eval_run_stats *st, lens_err *err)
{
    ctx_t c = {0};
    memset(st, 0, sizeof *st);
    st->lens_known = opt->report;
    int rc = -1;
    eval_report *rep = NULL;
    if (ctx_init(&c, sys, rd, err) != 0 || samples_map(rd, c.names, c.nin, c.map_in, err) != 0 ||
        start_output(&c, rd, out, opt, &rep, err) != 0)
        goto done;
    /* the report compares outputs traced to the same place (lens-trace --to) */
    const char *sys_frame = poly_get_meta(sys, "trace_frame"), *set_frame = samples_meta(rd, "frame");
    if (opt->report && sys_frame && set_frame && strcmp(sys_frame, set_frame) != 0) {
        lens_errf(err, samples_path(rd), 0, "'# frame: %s': the test set was traced to the %s, "
                  "the system's samples to the %s (lens-trace --to %s)", set_frame,
                  strcmp(set_frame, "stop") ? "outer pupil" : "stop",
                  strcmp(sys_frame, "stop") ? "outer pupil" : "stop", sys_frame);
        goto done;
    }
    /* one wavelength (lens-fit's meta lambda, lambda not an input): rays at others */
    const char *lam = poly_get_meta(sys, "lambda");
    char *end = NULL;
    c.lam_col = -1;
    st->lambda = NAN;
    if (lam && poly_input_index(sys, "lambda") < 0 && (c.lam = strtod(lam, &end)) > 0 &&
        end != lam && isfinite(c.lam)) {
        st->lambda = c.lam;
        c.lam_col = samples_find(rd, "lambda");
    }
    size_t n = 0;
    for (;;) {
        lens_err rowerr;
        int got = samples_next(rd, c.row, &rowerr);
        if (got == 0)
            break;
        if (got == SAMPLES_FAIL) {
            flush(&c, n, out, opt, rep); /* the rows before it are good */
            *err = rowerr;
            goto done;
        }
        if (!opt->report && keep_text(&c, rd, n) != 0) {
            lens_errf(err, NULL, 0, "out of memory");
            goto done;
        }
        take_row(&c, n, got, &rowerr, rd, opt, st);
        if (++n == CHUNK) {
            flush(&c, n, out, opt, rep);
            n = 0;
        }
    }
    flush(&c, n, out, opt, rep);
    table_out t;
    if (rep)
        table_out_begin(&t, out, opt->json, opt->precision, 6);
    /* malformed rows: said on stderr row by row (on_bad_row); the report says how many it
     * left out, the JSON's warnings too */
    char bad[160];
    const char *warn[1] = {bad};
    snprintf(bad, sizeof bad, "%zu of %zu rows malformed, left out of the report", st->bad_rows,
             st->rows);
    if (rep)
        eval_report_set_outside(rep, st->outside, st->outside_passing);
    if (rep && (eval_report_print(&t, rep) != 0 ||
                (table_out_end(&t, warn, st->bad_rows ? 1 : 0), ferror(out)))) {
        const int saved = errno;
        if (ferror(out)) /* a full disk, a closed pipe: not memory */
            lens_errf(err, NULL, 0, "write error: %s", strerror(saved ? saved : EIO));
        else
            lens_errf(err, NULL, 0, "out of memory writing the report");
        goto done;
    }
    rc = 0;
done:
    eval_report_free(rep);
    ctx_free(&c);
    return rc;
}
