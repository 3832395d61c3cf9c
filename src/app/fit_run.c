/* lens-fit's job (fit_run.h). The steps, each a function below: the columns (inputs,
 * outputs with the samples' passage pairs, tolerances), the rows (blocked rays keep only
 * their passage hits; one wavelength unless lambda is an input), the frame and the
 * wavelength transform (auto: the meridional frame and 1/lambda^2 where they apply),
 * the fit, and what the system records. Everything a job takes is released in
 * fit_job_free, on success and on every error. */
#include "sparselens/fit_run.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "sparselens/escape.h"
#include "sparselens/lens.h"
#include "sparselens/numparse.h"
#include "app/fit_input.h"

typedef struct {
    char *incopy, *outcopy, *default_out, *passage_note;
    const char **in_names, **out_names;
    int nin, nout, unfitted;
    double *tols;
    int *inmap, *outmap;
    double *in, *out, *vals;
    size_t count, blocked;
    int ceta, clam, lam_is_input;
    double lam0;
    char fnumber[64]; /* the samples' "# fnumber:" (lens-trace --fnumber), or "" */
    char frame[16];   /* the samples' "# frame:" (lens-trace --to: outer or stop), or "" */
    unsigned char *plain;
    fit_options opt;
    fit_input_check usable; /* the usable rows' spreads, checked before the fit */
} fit_job;

static void fit_job_free(fit_job *j)
{
    free(j->in); free(j->out); free(j->vals); free(j->inmap); free(j->outmap);
    free(j->in_names); free(j->out_names); free(j->tols); free(j->plain); free(j->incopy);
    free(j->outcopy); free(j->default_out); free(j->passage_note);
    fit_input_check_free(&j->usable);
}

/* Splits "a,b,c" into names (pointers into *copy); the count, or -1 with err set. The
 * caller frees *copy and *names either way. */
static int split_list(const char *opt, const char *s, char **copy, const char ***names,
                      lens_err *err)
{
    *copy = strdup(s);
    int n = 1;
    for (const char *p = s; *p; p++)
        n += *p == ',';
    *names = malloc((size_t)n * sizeof **names);
    if (!*copy || !*names) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int k = 0;
    for (char *tok = strtok(*copy, ","); tok; tok = strtok(NULL, ","))
        (*names)[k++] = tok;
    if (k == 0 || k != n) {
        lens_errf(err, NULL, 0, "%s: expected a comma-separated list of column names, got '%s'",
                  opt, s);
        return -1;
    }
    return k;
}

static void lens_name_from(const char *path, char *buf, size_t len)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    if (strcmp(path, "-") == 0 || !*base)
        base = "unknown";
    snprintf(buf, len, "%s", base);
    char *dot = strrchr(buf, '.');
    if (dot && dot != buf)
        *dot = '\0';
}

/* A lens path relative to the working directory, made relative to the directory of the
 * system written to out_path, so that it is found beside the system from anywhere (the
 * path stays as it is when out_path is in the working directory, is stdout, or when
 * either cannot be resolved; it becomes absolute when the two share no directory). */
static void lens_path_for_output(char *lpath, size_t plen, const char *out_path)
{
    const char *slash = strrchr(out_path, '/');
    if (!lpath[0] || lpath[0] == '/' || !slash)
        return;
    char dir[4096], lens[4096], cwd[4096];
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - out_path), out_path);
    if (!realpath(dir[0] ? dir : "/", dir) || !realpath(lpath, lens) || !getcwd(cwd, sizeof cwd) ||
        strcmp(dir, cwd) == 0 || strcmp(dir, "/") == 0)
        return;
    /* the common leading directories, then one ".." per directory of dir left over */
    size_t common = 0;
    for (size_t i = 0; dir[i] && dir[i] == lens[i]; i++)
        if (dir[i] == '/')
            common = i;
    if (strncmp(dir, lens, strlen(dir)) == 0 && lens[strlen(dir)] == '/')
        common = strlen(dir);
    if (common == 0) { /* nothing shared but the root: the absolute path reads better */
        snprintf(lpath, plen, "%s", lens);
        return;
    }
    char rel[4096] = "";
    for (const char *p = dir + common; *p; p++)
        if (*p == '/')
            strncat(rel, "../", sizeof rel - strlen(rel) - 1);
    strncat(rel, lens + common + 1, sizeof rel - strlen(rel) - 1);
    snprintf(lpath, plen, "%s", rel);
}

/* The lens a system remembers: --lens (a name, or a lens file: then its path too), else
 * the "# lens:" and "# lens-path:" lines lens-trace writes into samples, else the
 * samples file's base name. The path is what lens-spot and lens-distort load when given
 * the system alone. */
static void lens_of_samples(const samples_reader *r, const char *given, const char *path,
                            char *name, size_t nlen, char *lpath, size_t plen)
{
    FILE *probe = given ? fopen(given, "r") : NULL;
    const char *meta_name = samples_meta(r, "lens"), *meta_path = samples_meta(r, "lens-path");
    lpath[0] = '\0';
    if (probe) {
        fclose(probe);
        snprintf(lpath, plen, "%s", given);
        /* the lens's own name, as lens-trace writes it (the file's base name if it has
         * none or does not read: lens-spot reports that when it loads it) */
        lens_t lens;
        lens_err lerr;
        lens_init(&lens);
        if (lens_load(given, NULL, &lens, &lerr) == 0 && lens.name[0])
            snprintf(name, nlen, "%s", lens.name);
        else
            lens_name_from(given, name, nlen);
        lens_free(&lens);
    } else if (given) {
        snprintf(name, nlen, "%s", given);
    } else if (meta_name && strcmp(meta_name, "-") != 0) {
        snprintf(name, nlen, "%s", meta_name);
    } else {
        lens_name_from(meta_path ? meta_path : path, name, nlen);
    }
    if (!probe && meta_path)
        snprintf(lpath, plen, "%s", meta_path);
    for (char *p = name; *p; p++) /* one line in the .poly */
        if (*p == '\n' || *p == '\r' || *p == '\t')
            *p = ' ';
}

/* base, then every x,y column pair of the samples named ap_* or sN_* (digits N). */
static char *clip_outputs(const samples_reader *r, const char *base)
{
    size_t cap = strlen(base) + 1;
    for (int c = 0; c < samples_ncols(r); c++)
        cap += strlen(samples_colname(r, c)) * 2 + 4;
    char *s = malloc(cap);
    if (!s)
        return NULL;
    strcpy(s, base);
    for (int c = 0; c < samples_ncols(r); c++) {
        const char *nm = samples_colname(r, c);
        size_t len = strlen(nm), d = 1;
        while (nm[0] == 's' && d < len && nm[d] >= '0' && nm[d] <= '9')
            d++;
        int clip = (len == 4 && !strncmp(nm, "ap_x", 4)) ||
                   (nm[0] == 's' && d > 1 && d + 2 == len && !strcmp(nm + d, "_x"));
        char yname[256];
        if (!clip || len >= sizeof yname)
            continue;
        memcpy(yname, nm, len + 1);
        yname[len - 1] = 'y';
        if (samples_find(r, yname) < 0)
            continue;
        strcat(s, ",");
        strcat(s, nm);
        strcat(s, ",");
        strcat(s, yname);
    }
    return s;
}

/* --tolerance T (every output) or name=T,name=T (those outputs only). */
static int parse_tolerance(fit_job *j, const char *tol_s, lens_err *err)
{
    if (!tol_s)
        return 0;
    if (!strchr(tol_s, '=')) {
        if (parse_double(tol_s, &j->opt.tolerance) != 0) {
            lens_errf(err, NULL, 0, "--tolerance: '%s' is not a finite number", tol_s);
            return -1;
        }
        if (j->opt.tolerance < 0) {
            lens_errf(err, NULL, 0, "--tolerance: must not be negative, not %s", tol_s);
            return -1;
        }
        return 0;
    }
    char *tcopy;
    const char **items;
    int nt = split_list("--tolerance", tol_s, &tcopy, &items, err), rc = nt < 0 ? -1 : 0;
    j->tols = calloc((size_t)j->nout, sizeof *j->tols);
    if (!j->tols && rc == 0) {
        lens_errf(err, NULL, 0, "out of memory");
        rc = -1;
    }
    for (int t = 0; rc == 0 && t < nt; t++) {
        char *eq = strchr(items[t], '=');
        int o = 0;
        if (eq)
            *eq = '\0';
        while (eq && o < j->nout && strcmp(j->out_names[o], items[t]) != 0)
            o++;
        if (!eq)
            lens_errf(err, NULL, 0, "--tolerance: expected name=T, got '%s'", items[t]);
        else if (o == j->nout)
            lens_errf(err, NULL, 0, "--tolerance: '%s' is not among the outputs", items[t]);
        else if (parse_double(eq + 1, &j->tols[o]) != 0)
            lens_errf(err, NULL, 0, "--tolerance: '%s' is not a finite number", eq + 1);
        else if (j->tols[o] < 0)
            lens_errf(err, NULL, 0, "--tolerance: must not be negative, not %s", eq + 1);
        else
            continue;
        rc = -1;
    }
    j->opt.output_tolerance = j->tols;
    free(items);
    free(tcopy);
    return rc;
}

/* The f-number the samples were traced at, as written: "# fnumber: N (why)" as
 * lens-trace writes it with --fnumber; "" when there is no such line. */
static int samples_fnumber(const samples_reader *r, char *fnumber, size_t len, lens_err *err)
{
    const char *m = samples_meta(r, "fnumber");
    double v;
    fnumber[0] = '\0';
    if (!m)
        return 0;
    size_t n = strcspn(m, " \t");
    if (n < len)
        snprintf(fnumber, len, "%.*s", (int)n, m);
    if (n >= len || parse_double(fnumber, &v) != 0 || !(v > 0)) {
        fnumber[0] = '\0';
        lens_errf(err, samples_path(r), 0, "'# fnumber: %s': expected a positive f-number", m);
        return -1;
    }
    return 0;
}

/* Each column once, and no output that is also an input (a system that predicted x
 * from x would fit, with one term, and write two x columns). Checked before the rows are
 * read, so that a slip in the options costs no time. */
static int check_names(const fit_job *j, lens_err *err)
{
    for (int k = 0; k < j->nin + j->nout; k++) {
        const int out = k >= j->nin;
        const char *a = out ? j->out_names[k - j->nin] : j->in_names[k];
        for (int q = 0; q < k; q++) {
            const int qout = q >= j->nin;
            if (strcmp(a, qout ? j->out_names[q - j->nin] : j->in_names[q]) != 0)
                continue;
            if (out && !qout)
                lens_errf(err, NULL, 0, "--outputs: '%s' is an input (--inputs): a system "
                          "cannot predict its own input", a);
            else
                lens_errf(err, NULL, 0, "%s: '%s' is named twice", out ? "--outputs" : "--inputs", a);
            return -1;
        }
    }
    return 0;
}

/* The columns: inputs, outputs (by default with every passage pair the samples have, so
 * the system gets their pass circles and rays blocked there do not pass it), how many
 * passage columns are left unfitted, the tolerances, and where each is in the rows. */
static int setup_columns(fit_job *j, const fit_cli *o, samples_reader *r, lens_err *err)
{
    const char *outputs_s = o->outputs ? o->outputs : "out_x,out_y,out_u,out_v,out_eta";
    j->default_out = clip_outputs(r, outputs_s);
    if (!j->default_out) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (!o->outputs)
        outputs_s = j->default_out;
    if ((j->nin = split_list("--inputs", o->inputs, &j->incopy, &j->in_names, err)) < 0 ||
        (j->nout = split_list("--outputs", outputs_s, &j->outcopy, &j->out_names, err)) < 0 ||
        check_names(j, err) != 0)
        return -1;
    char *avail_copy;
    const char **avail;
    int na = split_list("--outputs", j->default_out, &avail_copy, &avail, err);
    for (int k = 0; k < na; k++) {
        int found = !fit_is_passage_output(avail[k]);
        for (int q = 0; q < j->nout && !found; q++)
            found = strcmp(avail[k], j->out_names[q]) == 0;
        j->unfitted += !found;
    }
    free(avail);
    free(avail_copy);
    if (na < 0)
        return -1;
    if (samples_meta(r, "passage") && !(j->passage_note = strdup(samples_meta(r, "passage")))) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (samples_fnumber(r, j->fnumber, sizeof j->fnumber, err) != 0 || parse_tolerance(j, o->tolerance, err) != 0)
        return -1;
    const char *frame = samples_meta(r, "frame");
    if (frame && strcmp(frame, "outer") != 0 && strcmp(frame, "stop") != 0) {
        lens_errf(err, samples_path(r), 0, "'# frame: %s': expected outer or stop", frame);
        return -1;
    }
    snprintf(j->frame, sizeof j->frame, "%s", frame ? frame : "");
    j->inmap = malloc((size_t)j->nin * sizeof *j->inmap);
    j->outmap = malloc((size_t)j->nout * sizeof *j->outmap);
    if (!j->inmap || !j->outmap) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (samples_map(r, j->in_names, j->nin, j->inmap, err) != 0 ||
        samples_map(r, j->out_names, j->nout, j->outmap, err) != 0)
        return -1;
    /* Blocked rays are marked by out_eta 0 even when out_eta is not fitted; a lambda
     * column that is not an input must hold a single wavelength (a system without
     * lambda cannot represent dispersion, so mixing wavelengths would be averaged). */
    j->ceta = samples_find(r, "out_eta");
    j->clam = -1;
    for (int i = 0; i < j->nin; i++)
        j->lam_is_input |= strcmp(j->in_names[i], "lambda") == 0;
    if (!j->lam_is_input)
        j->clam = samples_find(r, "lambda");
    return fit_input_check_init(&j->usable, j->nin, j->in_names, err);
}

/* One row into in[] and out[]: a blocked ray keeps only its passage hits
 * (fit_is_passage_output), so the fit learns them on both sides of each rim. */
static int take_row(fit_job *j, const samples_reader *r, long *lam_line, lens_err *err)
{
    const double *vals = j->vals;
    double *in = j->in + j->count * j->nin;
    for (int k = 0; k < j->nin + j->nout; k++) {
        int output = k >= j->nin;
        const char *name = output ? j->out_names[k - j->nin] : j->in_names[k];
        double x = vals[output ? j->outmap[k - j->nin] : j->inmap[k]];
        const char *why = fit_input_bad_value(name, x, output);
        if (why) {
            lens_errf(err, samples_path(r), samples_line(r), "%s %s is %g: %s",
                      output ? "output" : "input", name, x, why);
            return -1;
        }
        if (!output)
            in[k] = x;
    }
    int pass = j->ceta < 0 || vals[j->ceta] > 0;
    for (int o = 0; o < j->nout; o++)
        pass &= fit_is_passage_output(j->out_names[o]) || isfinite(vals[j->outmap[o]]);
    for (int o = 0; o < j->nout; o++)
        j->out[j->count * j->nout + o] =
            pass || fit_is_passage_output(j->out_names[o]) ? vals[j->outmap[o]] : NAN;
    j->blocked += !pass;
    if (pass)
        fit_input_check_row(&j->usable, in, samples_line(r));
    if (j->clam >= 0 && pass) {
        double l = vals[j->clam];
        if (isnan(j->lam0)) {
            j->lam0 = l;
            *lam_line = samples_line(r);
        } else if (l != j->lam0) {
            lens_errf(err, samples_path(r), samples_line(r),
                      "lambda %g differs from %g (line %ld), but lambda is not among "
                      "--inputs: add it, or trace a single wavelength",
                      l, j->lam0, *lam_line);
            return -1;
        }
    }
    j->count++;
    return 0;
}

static int read_rows(fit_job *j, samples_reader *r, lens_err *err)
{
    size_t cap = 4096;
    long lam_line = 0;
    j->lam0 = NAN;
    j->in = malloc(cap * (size_t)j->nin * sizeof *j->in);
    j->out = malloc(cap * (size_t)j->nout * sizeof *j->out);
    j->vals = malloc((size_t)samples_ncols(r) * sizeof *j->vals);
    if (!j->in || !j->out || !j->vals) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int st;
    while ((st = samples_next(r, j->vals, err)) != 0) {
        if (st < 0)
            return -1;
        if (j->count == cap) {
            cap *= 2;
            double *in = realloc(j->in, cap * (size_t)j->nin * sizeof *in);
            if (in)
                j->in = in;
            double *out = realloc(j->out, cap * (size_t)j->nout * sizeof *out);
            if (out)
                j->out = out;
            if (!in || !out) {
                lens_errf(err, NULL, 0, "out of memory");
                return -1;
            }
        }
        if (take_row(j, r, &lam_line, err) != 0)
            return -1;
    }
    return 0;
}

/* auto: the meridional frame where the inputs and outputs allow it (every lens
 * sparselens traces is rotationally symmetric), 1/lambda^2 where lambda is fitted:
 * both lower the held-out error on every lens measured (reports/fit.md). */
static int choose_frame(fit_job *j, const fit_cli *o, lens_err *err)
{
    poly_system *probe = poly_new("probe", j->nin, j->in_names, j->nout, j->out_names);
    j->plain = calloc((size_t)j->nout, 1);
    if (!probe || !j->plain) {
        poly_free(probe);
        lens_errf(err, NULL, 0, "bad or repeated column names in --inputs or --outputs");
        return -1;
    }
    if (*o->frame_except) {
        char *ecopy;
        const char **en;
        int ne = split_list("--frame-except", o->frame_except, &ecopy, &en, err);
        for (int k = 0; k < ne; k++) {
            int q = poly_output_index(probe, en[k]);
            if (q >= 0)
                j->plain[q] = 1; /* names not among the outputs: nothing to exempt */
        }
        free(en);
        free(ecopy);
        if (ne < 0) {
            poly_free(probe);
            return -1;
        }
    }
    int can = poly_set_frame(probe, POLY_FRAME_MERIDIONAL) == 0;
    for (int q = 0; can && q < j->nout; q++)
        if (j->plain[q])
            poly_set_output_plain(probe, q, 1);
    can = can && poly_frame_check(probe) == 0;
    poly_free(probe);
    fit_options *opt = &j->opt;
    opt->frame_plain = j->plain;
    if (strcmp(o->frame, "auto") == 0)
        opt->frame = can ? POLY_FRAME_MERIDIONAL : POLY_FRAME_NONE;
    else if ((opt->frame = poly_frame_parse(o->frame)) == POLY_FRAME_MERIDIONAL && !can) {
        lens_errf(err, NULL, 0, "--frame meridional needs inputs x, y, u, v and outputs in "
                                "pairs (..._x with ..._y, ..._u with ..._v)");
        return -1;
    }
    const char *lxf = o->lambda_transform;
    opt->lambda_transform = strcmp(lxf, "auto") != 0 ? poly_xform_parse(lxf)
                            : j->lam_is_input        ? POLY_XFORM_INVERSE_SQUARE
                                                     : POLY_XFORM_IDENTITY;
    if (opt->lambda_transform != POLY_XFORM_IDENTITY && !j->lam_is_input) {
        lens_errf(err, NULL, 0, "--lambda-transform %s needs lambda among --inputs", lxf);
        return -1;
    }
    return 0;
}

/* What the system remembers: its lens file, the f-number its samples were traced at,
 * the one wavelength of samples without lambda among the inputs, and whether its
 * passage is complete. */
static void record(poly_system *sys, const fit_job *j, const char *lens_path,
                   fit_run_stats *st)
{
    if (lens_path[0])
        poly_set_lens_path(sys, lens_path);
    st->no_lens_path = !lens_path[0];
    if (j->fnumber[0])
        poly_set_meta(sys, "fnumber", j->fnumber);
    if (j->frame[0])
        poly_set_meta(sys, "trace_frame", j->frame);
    if (j->clam >= 0 && !isnan(j->lam0)) {
        char buf[64];
        snprintf(buf, sizeof buf, "%.17g", j->lam0);
        poly_set_meta(sys, "lambda", buf);
    }
    char val[300];
    const char *gap = fit_passage_gap(j->passage_note, j->nout, j->out_names, j->unfitted,
                                      j->blocked, st->passage_gap, sizeof st->passage_gap);
    if (!gap)
        st->passage_gap[0] = '\0';
    snprintf(val, sizeof val, "%s%s", gap ? "partial: " : "full", gap ? gap : "");
    poly_set_meta(sys, "passage", val);
}

poly_system *fit_run(const fit_cli *o, samples_reader *r, FILE *log, fit_run_stats *st,
                     lens_err *err)
{
    fit_job j = {.opt = o->fit};
    j.opt.drop_circles = !o->keep_circles;
    poly_system *sys = NULL;
    memset(st, 0, sizeof *st);
    if (setup_columns(&j, o, r, err) != 0 || read_rows(&j, r, err) != 0)
        goto done;
    char lens_name[256], lens_path[4096];
    lens_of_samples(r, o->lens, o->samples_path, lens_name, sizeof lens_name, lens_path,
                    sizeof lens_path);
    lens_path_for_output(lens_path, sizeof lens_path, o->out_path);
    if (j.count == 0) {
        lens_errf(err, o->samples_path, 0, "no samples (the file has no data rows)");
        goto done;
    }
    if (fit_input_check_columns(&j.usable, samples_path(r), j.count, err) != 0 ||
        choose_frame(&j, o, err) != 0 ||
        (j.opt.frame == POLY_FRAME_MERIDIONAL &&
         fit_input_check_frame(&j.usable, samples_path(r), err) != 0))
        goto done;
    *st = (fit_run_stats){.samples = j.count, .blocked = j.blocked, .nin = j.nin,
                          .nout = j.nout};
    st->threads = j.opt.threads > 0 ? j.opt.threads : omp_get_max_threads();
    if (log)
        fprintf(log, "lens-fit: %zu samples (%zu blocked), %d inputs, %d outputs, "
                     "<= %d terms of degree <= %d, %d thread%s\n",
                j.count, j.blocked, j.nin, j.nout, j.opt.max_terms, j.opt.max_degree,
                st->threads, st->threads == 1 ? "" : "s");
    j.opt.verbose = log && j.opt.max_parts > 1;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    sys = fit_system(lens_name, j.nin, j.in_names, j.nout, j.out_names, j.count, j.in, j.out,
                     &j.opt, err);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    st->seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    if (sys)
        record(sys, &j, lens_path, st);
done:
    fit_job_free(&j);
    return sys;
}

void fit_run_print_summary(FILE *f, const poly_system *sys, const fit_run_stats *st)
{
    const char *parts = poly_get_meta(sys, "fit_parts");
    fprintf(f, "lens-fit: %s; %s part%s; fit time %.3f s\n", poly_get_meta(sys, "fit_samples"),
            parts, strcmp(parts, "1") ? "s" : "", st->seconds);
    for (int o = 0; o < poly_noutputs(sys); o++) {
        char key[256];
        const char *name = poly_output_name(sys, o);
        snprintf(key, sizeof key, "fit_%s", name);
        const char *m = poly_get_meta(sys, key);
        snprintf(key, sizeof key, "part_jump_%s", name);
        const char *jump = poly_get_meta(sys, key);
        fputs("lens-fit: ", f); /* a column name of the samples, escaped */
        text_line(f, name);
        fprintf(f, "%*s %s%s%s\n", strlen(name) < 8 ? (int)(8 - strlen(name)) : 0, "",
                m ? m : "", jump ? " largest_part_jump " : "", jump ? jump : "");
    }
    const char *dropped = poly_get_meta(sys, "fit_dropped_circles");
    if (dropped)
        fprintf(f, "lens-fit: dropped pass circles (rays they alone block; --keep-circles "
                   "keeps them): %s\n", dropped);
}

int fit_run_term_budget(const poly_system *sys, int max_terms, char *msg, size_t n)
{
    double worst = 0;
    const char *which = NULL;
    for (int o = 0; o < poly_noutputs(sys); o++) {
        const char *name = poly_output_name(sys, o);
        if (strcmp(name, "out_x") != 0 && strcmp(name, "out_y") != 0)
            continue;
        char key[64];
        snprintf(key, sizeof key, "fit_%s", name);
        const char *m = poly_get_meta(sys, key);
        int terms, degree;
        double rms;
        if (m && sscanf(m, "terms %d degree %d holdout_rms %lf", &terms, &degree, &rms) == 3 &&
            terms >= max_terms && rms > worst)
            worst = rms, which = name;
    }
    if (!which || !(worst > FIT_TERM_BUDGET_MM))
        return 0;
    snprintf(msg, n, "held-out RMS error of %s is %.3g um with all %d terms: the lens needs "
                     "more (--terms %d follows it more closely, at more time per ray; "
                     "lens-fit(1), ACCURACY)",
             which, worst * 1000, max_terms, max_terms < 50 ? 100 : 2 * max_terms);
    return 1;
}
