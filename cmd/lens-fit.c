/* lens-fit: fits an adaptive sparse polynomial system to a sample file (see
 * man lens-fit). Argument parsing, reading and printing only; the fit is fit_system. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sparselens/cli.h"
#include "sparselens/fit_cli.h"
#include "sparselens/outfile.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"


static const char *prog = "lens-fit";

/* Splits "a,b,c" into names (pointers into a copy). */
static int split_list(const char *opt, const char *s, char **copy, const char ***names)
{
    *copy = strdup(s);
    int n = 1;
    for (const char *p = s; *p; p++)
        n += *p == ',';
    *names = malloc((size_t)n * sizeof **names);
    if (!*copy || !*names)
        diag_die(prog, "out of memory");
    int k = 0;
    for (char *tok = strtok(*copy, ","); tok; tok = strtok(NULL, ","))
        (*names)[k++] = tok;
    if (k == 0 || k != n)
        diag_die(prog, "%s: expected a comma-separated list of column names, got '%s'", opt, s);
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
    for (char *p = buf; *p; p++)
        if (*p == ' ' || *p == '\t' || *p == '#')
            *p = '_';
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

int main(int argc, char **argv)
{
    fit_cli c;
    fit_cli_default(&c);
    const char *operand[1];
    if (opt_parse(&fit_command, argc, argv, &c, operand, 1) == 1)
        c.samples_path = operand[0];
    fit_options opt = c.fit;
    const char *inputs_s = c.inputs, *outputs_s = c.outputs ? c.outputs : "out_x,out_y,out_u,out_v,out_eta";
    const char *path = c.samples_path, *outpath = c.out_path, *emit = c.emit_c ? "c" : NULL,
               *lens = c.lens, *fname = c.name;
    int quiet = c.quiet, outputs_given = c.outputs != NULL;
    const char *tol_s = c.tolerance, *frame_s = c.frame, *lxf_s = c.lambda_transform;
    const char *except_s = c.frame_except;
    cli_check_output(prog, outpath);
    /* Everything below is released at `done`, on success and on every error, so that a
     * leak checker sees none either way. */
    lens_err err;
    int rc = 1;
    char *incopy = NULL, *outcopy = NULL, *default_out = NULL;
    const char **in_names = NULL, **out_names = NULL;
    double *tols = NULL, *in = NULL, *out = NULL, *vals = NULL;
    unsigned char *plain = NULL;
    int *inmap = NULL, *outmap = NULL;
    poly_system *sys = NULL;
    samples_reader *r = samples_open(path, &err);
    if (!r)
        goto fail;
    /* Hits on the stop (ap_*) and on clipping surfaces (sN_*, lens-trace --clip-columns)
     * in the samples: fit them too, so the system gets their pass circles and rays
     * blocked there do not pass it. */
    if (!outputs_given) {
        default_out = clip_outputs(r, outputs_s);
        if (!default_out)
            diag_die(prog, "out of memory");
        outputs_s = default_out;
    }
    int nin = split_list("--inputs", inputs_s, &incopy, &in_names);
    int nout = split_list("--outputs", outputs_s, &outcopy, &out_names);

    /* --tolerance T (every output) or name=T,name=T (those outputs only). */
    if (tol_s && strchr(tol_s, '=')) {
        char *tcopy;
        const char **items;
        int nt = split_list("--tolerance", tol_s, &tcopy, &items);
        tols = calloc((size_t)nout, sizeof *tols);
        if (!tols)
            diag_die(prog, "out of memory");
        for (int t = 0; t < nt; t++) {
            char *eq = strchr(items[t], '=');
            if (!eq)
                diag_die(prog, "--tolerance: expected name=T, got '%s'", items[t]);
            *eq = '\0';
            int o = 0;
            while (o < nout && strcmp(out_names[o], items[t]) != 0)
                o++;
            if (o == nout)
                diag_die(prog, "--tolerance: '%s' is not among the outputs", items[t]);
            if (parse_double(eq + 1, &tols[o]) != 0)
                diag_die(prog, "--tolerance: '%s' is not a finite number", eq + 1);
            if (tols[o] < 0)
                diag_die(prog, "--tolerance: must not be negative, not %s", eq + 1);
        }
        opt.output_tolerance = tols;
        free(items);
        free(tcopy);
    } else if (tol_s) {
        if (parse_double(tol_s, &opt.tolerance) != 0)
            diag_die(prog, "--tolerance: '%s' is not a finite number", tol_s);
        if (opt.tolerance < 0)
            diag_die(prog, "--tolerance: must not be negative, not %s", tol_s);
    }

    inmap = malloc((size_t)nin * sizeof *inmap);
    outmap = malloc((size_t)nout * sizeof *outmap);
    if (!inmap || !outmap)
        diag_die(prog, "out of memory");
    if (samples_map(r, in_names, nin, inmap, &err) != 0 ||
        samples_map(r, out_names, nout, outmap, &err) != 0)
        goto fail;
    /* Blocked rays are marked by out_eta 0 even when out_eta is not fitted; a lambda
     * column that is not an input must hold a single wavelength (a system without
     * lambda cannot represent dispersion, so mixing wavelengths would be averaged). */
    int ceta = samples_find(r, "out_eta"), clam = -1;
    int lam_is_input = 0;
    for (int i = 0; i < nin; i++)
        lam_is_input |= strcmp(in_names[i], "lambda") == 0;
    if (!lam_is_input)
        clam = samples_find(r, "lambda");
    double lam0 = NAN;
    long lam_line = 0;

    size_t cap = 4096, count = 0, blocked = 0;
    in = malloc(cap * (size_t)nin * sizeof *in);
    out = malloc(cap * (size_t)nout * sizeof *out);
    vals = malloc((size_t)samples_ncols(r) * sizeof *vals);
    if (!in || !out || !vals)
        diag_die(prog, "out of memory");
    int st;
    while ((st = samples_next(r, vals, &err)) != 0) {
        if (st < 0)
            goto fail;
        if (count == cap) {
            cap *= 2;
            double *nin_ = realloc(in, cap * (size_t)nin * sizeof *in);
            if (nin_)
                in = nin_;
            double *nout_ = realloc(out, cap * (size_t)nout * sizeof *out);
            if (nout_)
                out = nout_;
            if (!nin_ || !nout_)
                diag_die(prog, "out of memory");
        }
        for (int i = 0; i < nin; i++) {
            double x = vals[inmap[i]];
            if (!isfinite(x)) {
                lens_errf(&err, samples_path(r), samples_line(r),
                          "input %s is %g (inputs must be finite)", in_names[i], x);
                goto fail;
            }
            in[count * nin + i] = x;
        }
        int pass = ceta < 0 || vals[ceta] > 0;
        for (int o = 0; o < nout; o++) {
            out[count * nout + o] = pass ? vals[outmap[o]] : NAN;
            pass &= isfinite(vals[outmap[o]]) != 0;
        }
        blocked += !pass;
        if (clam >= 0 && pass) {
            double l = vals[clam];
            if (isnan(lam0)) {
                lam0 = l;
                lam_line = samples_line(r);
            } else if (l != lam0) {
                lens_errf(&err, samples_path(r), samples_line(r),
                          "lambda %g differs from %g (line %ld), but lambda is not among "
                          "--inputs: add it, or trace a single wavelength",
                          l, lam0, lam_line);
                goto fail;
            }
        }
        count++;
    }
    char lens_buf[256];
    lens_name_from(lens ? lens : path, lens_buf, sizeof lens_buf);
    samples_close(r);
    r = NULL;
    if (count == 0) {
        lens_errf(&err, path, 0, "no samples (the file has no data rows)");
        goto fail;
    }

    /* auto: the meridional frame where the inputs and outputs allow it (every lens
     * sparselens traces is rotationally symmetric), 1/lambda^2 where lambda is fitted:
     * both lower the held-out error on every lens measured (reports/fit.md). */
    {
        poly_system *probe = poly_new("probe", nin, in_names, nout, out_names);
        plain = calloc((size_t)nout, 1);
        if (!probe || !plain) {
            poly_free(probe);
            lens_errf(&err, NULL, 0, "bad or repeated column names in --inputs or --outputs");
            goto fail;
        }
        if (*except_s) {
            char *ecopy;
            const char **en;
            int ne = split_list("--frame-except", except_s, &ecopy, &en);
            for (int k = 0; k < ne; k++) {
                int o = poly_output_index(probe, en[k]);
                if (o >= 0)
                    plain[o] = 1; /* names not among the outputs: nothing to exempt */
            }
            free(en);
            free(ecopy);
        }
        int can = poly_set_frame(probe, POLY_FRAME_MERIDIONAL) == 0;
        for (int o = 0; can && o < nout; o++)
            if (plain[o])
                poly_set_output_plain(probe, o, 1);
        can = can && poly_frame_check(probe) == 0;
        poly_free(probe);
        opt.frame_plain = plain;
        if (strcmp(frame_s, "auto") == 0)
            opt.frame = can ? POLY_FRAME_MERIDIONAL : POLY_FRAME_NONE;
        else if ((opt.frame = poly_frame_parse(frame_s)) == POLY_FRAME_MERIDIONAL && !can) {
            lens_errf(&err, NULL, 0, "--frame meridional needs inputs x, y, u, v and outputs in "
                                     "pairs (..._x with ..._y, ..._u with ..._v)");
            goto fail;
        }
        opt.lambda_transform = strcmp(lxf_s, "auto") == 0 ? (lam_is_input ? POLY_XFORM_INVERSE_SQUARE
                                                                          : POLY_XFORM_IDENTITY)
                                                          : poly_xform_parse(lxf_s);
        if (opt.lambda_transform != POLY_XFORM_IDENTITY && !lam_is_input) {
            lens_errf(&err, NULL, 0, "--lambda-transform %s needs lambda among --inputs", lxf_s);
            goto fail;
        }
    }
    int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
    if (!quiet)
        fprintf(stderr, "lens-fit: %zu samples (%zu blocked), %d inputs, %d outputs, "
                        "<= %d terms of degree <= %d, %d thread%s\n",
                count, blocked, nin, nout, opt.max_terms, opt.max_degree, threads,
                threads == 1 ? "" : "s");
    opt.verbose = !quiet && opt.max_parts > 1;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    sys = fit_system(lens_buf, nin, in_names, nout, out_names, count, in, out,
                                  &opt, &err);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (!sys)
        goto fail;
    if (clam >= 0 && !isnan(lam0)) {
        char buf[64];
        snprintf(buf, sizeof buf, "%.17g", lam0);
        poly_set_meta(sys, "lambda", buf);
    }
    outfile *of = outfile_open(outpath, &err);
    if (!of)
        goto fail;
    int wrc = emit ? poly_emit_c(outfile_stream(of), sys, fname) : poly_write(outfile_stream(of), sys);
    if (wrc != 0) {
        outfile_abort(of);
        lens_errf(&err, outpath, 0, "cannot write the system%s",
                  emit ? " (is --name a C identifier?)" : "");
        goto fail;
    }
    if (outfile_commit(of, &err) != 0)
        goto fail;
    if (!quiet) {
        double secs = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        fprintf(stderr, "lens-fit: %s; %s part%s; fit time %.3f s\n", poly_get_meta(sys, "fit_samples"),
                poly_get_meta(sys, "fit_parts"), strcmp(poly_get_meta(sys, "fit_parts"), "1") ? "s" : "",
                secs);
        for (int o = 0; o < nout; o++) {
            char key[256];
            snprintf(key, sizeof key, "fit_%s", out_names[o]);
            const char *m = poly_get_meta(sys, key);
            snprintf(key, sizeof key, "part_jump_%s", out_names[o]);
            const char *j = poly_get_meta(sys, key);
            fprintf(stderr, "lens-fit: %-8s %s%s%s\n", out_names[o], m ? m : "",
                    j ? " largest_part_jump " : "", j ? j : "");
        }
    }
    rc = 0;
    goto done;
fail:
    diag_print(prog, &err);
done:
    if (r)
        samples_close(r);
    poly_free(sys);
    free(in); free(out); free(vals); free(inmap); free(outmap);
    free(in_names); free(out_names); free(tols); free(plain); free(incopy); free(outcopy);
    free(default_out);
    return rc;
}
