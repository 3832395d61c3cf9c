/* fit_system: the frame and input transforms around fit_system_core (fit.c).
 *
 * The samples are taken through the same steps evaluation applies (poly_frame_in on a
 * system that already carries the frame and transforms), the core fits the
 * polynomials in those variables (in the meridional frame without the input y, which
 * is 0 there, and with the radius x scaled without an offset: the outputs are odd or
 * even in it), and the result is copied into a system over the original inputs that
 * evaluates the same steps around it. The domain recorded is the range of the raw
 * inputs. Without a frame or transform this is fit_system_core itself. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/fit.h"
#include "fit/fit_internal.h"

static int find_name(int n, const char *const *names, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], name) == 0)
            return i;
    return -1;
}

/* The usable-row rule of fit_system_core: every output finite, out_eta > 0. */
static int usable(const double *yo, int nout, int ieta)
{
    for (int o = 0; o < nout; o++)
        if (!isfinite(yo[o]))
            return 0;
    return ieta < 0 || yo[ieta] > 0;
}

/* The radius of the pass circle of output pair (a, b): the furthest hit of a passing row
 * (0 if none passes). */
static double pass_radius(const double *out, size_t count, int noutputs, int ieta, int a, int b)
{
    double rmax = 0;
    for (size_t r = 0; r < count; r++) {
        const double *yo = out + r * (size_t)noutputs;
        if (usable(yo, noutputs, ieta))
            rmax = fmax(rmax, hypot(yo[a], yo[b]));
    }
    return rmax;
}

/* The partner of a passage output (..._x <-> ..._y), -1 if absent. */
static int partner(int noutputs, const char *const *outputs, const char *name)
{
    char buf[256];
    size_t len = strlen(name);
    if (len == 0 || len >= sizeof buf)
        return -1;
    memcpy(buf, name, len + 1);
    buf[len - 1] = buf[len - 1] == 'x' ? 'y' : 'x';
    return find_name(noutputs, outputs, buf);
}

/* One group of outputs fitted by the core: in the frame (frame = 1: inputs without y,
 * outputs rotated into the frame) or outside it (the inputs through the transforms).
 * Copies its parts, terms and pass circles into sys. A passage group (clip = 1) is
 * fitted on every row where its outputs are finite, as one part copied into every part
 * of sys (its rows are not the others', so neither would its cuts be), with the
 * passage tolerance, and gets circles around the hits of the passing rows. */
static int fit_group(poly_system *sys, int in_frame, int clip, const int *outs, int ng, int ninputs,
                     const char *const *inputs, const char *const *outputs, int noutputs,
                     size_t count, const double *in, const double *out, const fit_options *opt,
                     lens_err *err)
{
    int frame = in_frame && poly_get_frame(sys) == POLY_FRAME_MERIDIONAL;
    int iy = frame ? poly_input_index(sys, "y") : -1;
    int ix = frame ? poly_input_index(sys, "x") : -1;
    int ieta = find_name(noutputs, outputs, "out_eta");
    int nc = ninputs - frame; /* the core's inputs: all but y in the frame */
    int rc = -1;
    const char **cnames = malloc((size_t)nc * sizeof *cnames);
    const char **gnames = malloc((size_t)ng * sizeof *gnames);
    int *cmap = malloc((size_t)nc * sizeof *cmap); /* core input k is input cmap[k] */
    double *cin = malloc((count ? count : 1) * (size_t)nc * sizeof *cin);
    double *cout = malloc((count ? count : 1) * (size_t)ng * sizeof *cout);
    double *t = malloc((size_t)ninputs * sizeof *t), *yo = malloc((size_t)noutputs * sizeof *yo);
    int *e = malloc((size_t)ninputs * sizeof *e), *ce = malloc((size_t)(nc + 1) * sizeof *ce);
    poly_system *core = NULL;
    if (!cnames || !gnames || !cmap || !cin || !cout || !t || !yo || !e || !ce) {
        lens_errf(err, NULL, 0, "out of memory");
        goto out;
    }
    for (int i = 0, k = 0; i < ninputs; i++)
        if (i != iy) {
            cnames[k] = inputs[i];
            cmap[k++] = i;
        }
    for (int g = 0; g < ng; g++)
        gnames[g] = outputs[outs[g]];
    for (size_t r = 0; r < count; r++) {
        const double *x = in + r * (size_t)ninputs;
        double cs[2];
        poly_frame_in(sys, x, t, cs);
        if (!frame) /* the transforms alone */
            for (int i = 0; i < ninputs; i++)
                t[i] = poly_get_transform(sys, i) == POLY_XFORM_INVERSE_SQUARE ? 1 / (x[i] * x[i])
                                                                               : x[i];
        for (int k = 0; k < nc; k++)
            cin[r * (size_t)nc + k] = t[cmap[k]];
        memcpy(yo, out + r * (size_t)noutputs, (size_t)noutputs * sizeof *yo);
        int ok = usable(yo, noutputs, ieta);
        for (int g = 0; clip && g < ng; g++)
            ok = (g == 0 || ok) && isfinite(yo[outs[g]]);
        if (ok && frame)
            poly_frame_out_inverse(sys, cs, yo);
        /* a ray another output or out_eta blocks is left out here too */
        for (int g = 0; g < ng; g++)
            cout[r * (size_t)ng + g] = ok ? yo[outs[g]] : NAN;
    }
    fit_options co = *opt;
    co.frame = frame ? POLY_FRAME_MERIDIONAL : POLY_FRAME_NONE;
    double gtol[64]; /* per-output tolerances of this group's outputs */
    if (opt->output_tolerance || clip) {
        if (ng > 64) {
            lens_errf(err, NULL, 0, "at most 64 outputs with per-output tolerances");
            goto out;
        }
        for (int g = 0; g < ng; g++) {
            gtol[g] = opt->output_tolerance ? opt->output_tolerance[outs[g]] : opt->tolerance;
            int q = partner(noutputs, outputs, outputs[outs[g]]);
            if (clip && !(opt->output_tolerance && gtol[g] > 0) && opt->passage_tolerance > 0 &&
                q >= 0)
                gtol[g] = opt->passage_tolerance *
                          pass_radius(out, count, noutputs, ieta, outs[g], q);
        }
        co.output_tolerance = gtol;
    }
    if (clip) {
        co.max_parts = 1;
        co.force_parts = 1;
    }
    if (frame) {
        int kx = ix < iy ? ix : ix - 1;
        if (kx < 32)
            co.no_offset |= 1u << kx;
    }
    /* The second group (outside the frame) uses the scaling the first one chose (one
     * scaling per input; y, absent from the frame, is its own) and its number of
     * radial parts, cut by the same rule on the same rows. */
    double *sc = NULL;
    if (poly_nparts(sys) > 0) {
        sc = malloc((size_t)nc * 2 * sizeof *sc);
        if (!sc) {
            lens_errf(err, NULL, 0, "out of memory");
            goto out;
        }
        int sy = poly_get_frame(sys) == POLY_FRAME_MERIDIONAL ? poly_input_index(sys, "y") : -1;
        for (int k = 0; k < nc; k++) {
            poly_get_scaling(sys, cmap[k], sc + 2 * k, sc + 2 * k + 1);
            if (cmap[k] == sy)
                sc[2 * k] = sc[2 * k + 1] = NAN;
        }
        co.scaling = sc;
        if (!clip)
            co.force_parts = poly_nparts(sys);
    }
    core = fit_system_core(poly_lens_name(sys), nc, cnames, ng, gnames, count, cin, cout, &co, err);
    free(sc);
    if (!core)
        goto out;
    /* The core's polynomials over the original inputs (y: exponent 0, scale 1). */
    for (int k = 0; k < nc; k++) {
        double off, scale;
        poly_get_scaling(core, k, &off, &scale);
        poly_set_scaling(sys, cmap[k], off, scale);
    }
    int first = poly_nparts(sys) == 0;
    if (clip) { /* one part, the same polynomial in every part of sys */
        if (first)
            poly_add_part(sys, 0, INFINITY);
        for (int p = 0; p < poly_nparts(sys); p++)
            for (int g = 0; g < ng; g++)
                for (int tt = 0; tt < poly_nterms(core, 0, g); tt++) {
                    double coef;
                    poly_get_term(core, 0, g, tt, ce, &coef);
                    memset(e, 0, (size_t)ninputs * sizeof *e);
                    for (int k = 0; k < nc; k++)
                        e[cmap[k]] = ce[k];
                    if (poly_add_term(sys, p, outs[g], e, coef) != 0) {
                        lens_errf(err, NULL, 0, "out of memory");
                        goto out;
                    }
                }
        for (int g = 0; g < ng; g++) {
            int q = partner(noutputs, outputs, outputs[outs[g]]);
            double rad = q >= 0 ? pass_radius(out, count, noutputs, ieta, outs[g], q) : 0;
            if (outputs[outs[g]][strlen(outputs[outs[g]]) - 1] == 'x' && rad > 0)
                poly_add_pass_circle(sys, outs[g], q, rad * (1 + 1e-9));
        }
        for (int m = 0; m < poly_nmeta(core); m++) {
            const char *key = poly_meta_key(core, m), *val = poly_get_meta(core, key);
            if (!strcmp(key, "fit_samples"))
                poly_set_meta(sys, "passage_samples", val);
            else if (!poly_get_meta(sys, key) || !strcmp(key, "fit_flags"))
                poly_set_meta(sys, key, val);
        }
        rc = 0;
        goto out;
    }
    if (!first && poly_nparts(sys) != poly_nparts(core)) {
        lens_errf(err, NULL, 0, "the outputs in and outside the frame chose different radial "
                                "parts: fit them separately or use --frame none");
        goto out;
    }
    for (int p = 0; p < poly_nparts(core); p++) {
        double rmin, rmax, a, b;
        poly_part_range(core, p, &rmin, &rmax);
        if (first)
            poly_add_part(sys, rmin, rmax);
        poly_part_range(sys, p, &a, &b);
        /* the same rings; the radius may differ in the last bit (hypot in one, sqrt
         * of the frame in the other): the first group's bounds stand */
        if (fabs(a - rmin) > 1e-9 * (1 + fabs(a)) ||
            (isfinite(b) ? fabs(b - rmax) > 1e-9 * (1 + fabs(b)) : b != rmax)) {
            lens_errf(err, NULL, 0, "the outputs in and outside the frame chose different "
                                    "radial parts: fit them separately or use --frame none");
            goto out;
        }
        for (int g = 0; g < ng; g++)
            for (int tt = 0; tt < poly_nterms(core, p, g); tt++) {
                double coef;
                poly_get_term(core, p, g, tt, ce, &coef);
                memset(e, 0, (size_t)ninputs * sizeof *e);
                for (int k = 0; k < nc; k++)
                    e[cmap[k]] = ce[k];
                if (poly_add_term(sys, p, outs[g], e, coef) != 0) {
                    lens_errf(err, NULL, 0, "out of memory");
                    goto out;
                }
            }
    }
    for (int c = 0; c < poly_npass_circles(core); c++) {
        int a, b;
        double radius;
        poly_get_pass_circle(core, c, &a, &b, &radius);
        poly_add_pass_circle(sys, outs[a], outs[b], radius);
    }
    for (int m = 0; m < poly_nmeta(core); m++) {
        const char *key = poly_meta_key(core, m), *val = poly_get_meta(core, key);
        if (poly_get_meta(sys, key) && strcmp(key, "fit_flags") != 0 &&
            strcmp(key, "fit_samples") != 0 && strcmp(key, "fit_parts") != 0)
            continue;
        poly_set_meta(sys, key, val);
    }
    rc = 0;
out:
    poly_free(core);
    free(cnames); free(gnames); free(cmap); free(cin); free(cout); free(t); free(yo); free(e);
    free(ce);
    return rc;
}

poly_system *fit_system(const char *lens_name, int ninputs, const char *const *inputs,
                        int noutputs, const char *const *outputs, size_t count, const double *in,
                        const double *out, const fit_options *opt, lens_err *err)
{
    int ilam = ninputs > 0 && inputs ? find_name(ninputs, inputs, "lambda") : -1;
    int xf = ilam >= 0 ? opt->lambda_transform : POLY_XFORM_IDENTITY;
    int npassage = 0;
    for (int o = 0; o < noutputs && outputs; o++)
        npassage += fit_is_passage_output(outputs[o]);
    if (opt->frame == POLY_FRAME_NONE && xf == POLY_XFORM_IDENTITY && npassage == 0)
        return fit_system_core(lens_name, ninputs, inputs, noutputs, outputs, count, in, out,
                               opt, err);
    if (!poly_frame_name(opt->frame) || !poly_xform_name(opt->lambda_transform)) {
        lens_errf(err, NULL, 0, "unknown frame or transform");
        return NULL;
    }
    poly_system *sys = poly_new(lens_name, ninputs, inputs, noutputs, outputs);
    if (!sys) {
        lens_errf(err, NULL, 0, "bad input or output names, or out of memory");
        return NULL;
    }
    int bad = poly_set_frame(sys, opt->frame) != 0;
    for (int o = 0; !bad && opt->frame && opt->frame_plain && o < noutputs; o++)
        if (opt->frame_plain[o])
            bad = poly_set_output_plain(sys, o, 1) != 0;
    if (bad || poly_frame_check(sys) != 0) {
        lens_errf(err, NULL, 0,
                  "the meridional frame needs inputs x, y, u, v and the outputs in it in "
                  "pairs (..._x with ..._y, ..._u with ..._v)");
        poly_free(sys);
        return NULL;
    }
    if (ilam >= 0)
        poly_set_transform(sys, ilam, xf);
    int *outs = malloc((size_t)noutputs * sizeof *outs);
    double *lo = malloc((size_t)ninputs * sizeof *lo), *hi = malloc((size_t)ninputs * sizeof *hi);
    if (!outs || !lo || !hi) {
        lens_errf(err, NULL, 0, "out of memory");
        goto fail;
    }
    for (size_t r = 0; r < count; r++)
        for (int i = 0; i < ninputs; i++)
            if (!isfinite(in[r * (size_t)ninputs + i])) {
                lens_errf(err, NULL, 0, "sample %zu: input %s is not finite", r + 1, inputs[i]);
                goto fail;
            }
    /* in the frame first (it chooses the parts), then the outputs outside it; the
     * passage outputs last (they take the others' scaling and parts) */
    for (int grp = 0; grp < 4; grp++) {
        int in_frame = grp % 2 == 0, clip = grp >= 2, ng = 0;
        for (int o = 0; o < noutputs; o++)
            if ((poly_get_output_plain(sys, o) == 0) == in_frame &&
                fit_is_passage_output(outputs[o]) == clip)
                outs[ng++] = o;
        if (ng && fit_group(sys, in_frame, clip, outs, ng, ninputs, inputs, outputs, noutputs,
                            count, in, out, opt, err) != 0)
            goto fail;
    }
    /* The domain: the raw inputs of the usable rows. */
    int ieta = find_name(noutputs, outputs, "out_eta");
    for (int i = 0; i < ninputs; i++) {
        lo[i] = INFINITY;
        hi[i] = -INFINITY;
    }
    for (size_t r = 0; r < count; r++)
        if (usable(out + r * (size_t)noutputs, noutputs, ieta))
            for (int i = 0; i < ninputs; i++) {
                lo[i] = fmin(lo[i], in[r * (size_t)ninputs + i]);
                hi[i] = fmax(hi[i], in[r * (size_t)ninputs + i]);
            }
    for (int i = 0; i < ninputs; i++)
        if (lo[i] <= hi[i])
            poly_set_domain(sys, i, lo[i], hi[i]);
    /* Held-out errors of a pair in the frame are radial and sagittal; what a user
     * compares with is the error per lens-frame coordinate, which for rays spread
     * evenly in angle is sqrt((radial^2 + sagittal^2) / 2) for both. */
    for (int o = 0; opt->frame && o < noutputs; o++) {
        int q;
        char key[256], kq[256], m1[256], m2[256];
        size_t l = strlen(outputs[o]);
        if (poly_get_output_plain(sys, o) || l < 2 || outputs[o][l - 2] != '_' ||
            (outputs[o][l - 1] != 'x' && outputs[o][l - 1] != 'u'))
            continue;
        snprintf(kq, sizeof kq, "%s", outputs[o]);
        kq[l - 1] = outputs[o][l - 1] == 'x' ? 'y' : 'v';
        q = find_name(noutputs, outputs, kq);
        snprintf(key, sizeof key, "fit_%s", outputs[o]);
        snprintf(kq, sizeof kq, "fit_%s", outputs[q]);
        const char *va = poly_get_meta(sys, key), *vb = poly_get_meta(sys, kq);
        int ta, da, tb, db;
        double ha, hb, tola, tolb;
        if (!va || !vb ||
            sscanf(va, "terms %d degree %d holdout_rms %lf tolerance %lf", &ta, &da, &ha, &tola) != 4 ||
            sscanf(vb, "terms %d degree %d holdout_rms %lf tolerance %lf", &tb, &db, &hb, &tolb) != 4)
            continue;
        double h = sqrt(0.5 * (ha * ha + hb * hb));
        snprintf(m1, sizeof m1, "terms %d degree %d holdout_rms %.6g tolerance %.6g frame_holdout_rms %.6g",
                 ta, da, h, tola, ha);
        snprintf(m2, sizeof m2, "terms %d degree %d holdout_rms %.6g tolerance %.6g frame_holdout_rms %.6g",
                 tb, db, h, tolb, hb);
        poly_set_meta(sys, key, m1);
        poly_set_meta(sys, kq, m2);
    }
    {
        const char *ff = poly_get_meta(sys, "fit_flags");
        char buf[1400], ex[600] = "";
        for (int o = 0, n = 0; o < noutputs; o++)
            if (poly_get_output_plain(sys, o)) {
                size_t l = strlen(ex);
                snprintf(ex + l, sizeof ex - l, "%s%s", n++ ? "," : " --frame-except ", outputs[o]);
            }
        snprintf(buf, sizeof buf, "%s --frame %s%s --lambda-transform %s", ff ? ff : "",
                 poly_frame_name(opt->frame), ex, poly_xform_name(xf));
        poly_set_meta(sys, "fit_flags", buf);
    }
    free(outs); free(lo); free(hi);
    return sys;
fail:
    poly_free(sys);
    free(outs); free(lo); free(hi);
    return NULL;
}
