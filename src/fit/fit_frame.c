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

/* One group of outputs on its way through the core: its inputs (in the frame: all but
 * y) and outputs. */
typedef struct {
    int frame;            /* fitted in the meridional frame */
    int clip;             /* a passage group */
    const int *outs;      /* the group's outputs among the system's */
    int ng, ninputs, noutputs, nc;
    int ieta;
    const char **cnames;  /* the core's inputs */
    const char **gnames;  /* the core's outputs */
    int *cmap;            /* core input k is input cmap[k] */
    double *cin, *cout;   /* count x nc, count x ng */
} group;

static void group_free(group *g)
{
    free(g->cnames); free(g->gnames); free(g->cmap); free(g->cin); free(g->cout);
}

/* The core's rows: the inputs through the frame or the transforms, the outputs rotated
 * into the frame; nan outputs where a ray does not count for the group. */
static int group_rows(group *g, const poly_system *sys, const char *const *inputs,
                      const char *const *outputs, size_t count, const double *in,
                      const double *out, lens_err *err)
{
    int ninputs = g->ninputs, noutputs = g->noutputs, nc = g->nc, ng = g->ng;
    int iy = g->frame ? poly_input_index(sys, "y") : -1;
    double *t = malloc((size_t)ninputs * sizeof *t), *yo = malloc((size_t)noutputs * sizeof *yo);
    g->cnames = malloc((size_t)nc * sizeof *g->cnames);
    g->gnames = malloc((size_t)ng * sizeof *g->gnames);
    g->cmap = malloc((size_t)nc * sizeof *g->cmap);
    g->cin = malloc((count ? count : 1) * (size_t)nc * sizeof *g->cin);
    g->cout = malloc((count ? count : 1) * (size_t)ng * sizeof *g->cout);
    if (!t || !yo || !g->cnames || !g->gnames || !g->cmap || !g->cin || !g->cout) {
        free(t); free(yo);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    for (int i = 0, k = 0; i < ninputs; i++)
        if (i != iy) {
            g->cnames[k] = inputs[i];
            g->cmap[k++] = i;
        }
    for (int q = 0; q < ng; q++)
        g->gnames[q] = outputs[g->outs[q]];
    for (size_t r = 0; r < count; r++) {
        const double *x = in + r * (size_t)ninputs;
        double cs[2];
        poly_frame_in(sys, x, t, cs);
        if (!g->frame) /* the transforms alone */
            for (int i = 0; i < ninputs; i++)
                t[i] = poly_get_transform(sys, i) == POLY_XFORM_INVERSE_SQUARE ? 1 / (x[i] * x[i])
                                                                               : x[i];
        for (int k = 0; k < nc; k++)
            g->cin[r * (size_t)nc + k] = t[g->cmap[k]];
        memcpy(yo, out + r * (size_t)noutputs, (size_t)noutputs * sizeof *yo);
        int ok = usable(yo, noutputs, g->ieta);
        for (int q = 0; g->clip && q < ng; q++)
            ok = (q == 0 || ok) && isfinite(yo[g->outs[q]]);
        if (ok && g->frame)
            poly_frame_out_inverse(sys, cs, yo);
        /* a ray another output or out_eta blocks is left out here too */
        for (int q = 0; q < ng; q++)
            g->cout[r * (size_t)ng + q] = ok ? yo[g->outs[q]] : NAN;
    }
    free(t); free(yo);
    return 0;
}

/* The core's options for the group: per-output tolerances (a passage output's from the
 * passage tolerance and its pass radius), no parts for passage, no offset on the
 * frame's radius x, and, once a first group has fitted, its scaling and parts (*sc, to
 * be freed by the caller). gtol holds 64 tolerances. */
static int group_options(const group *g, const poly_system *sys, const char *const *outputs,
                         size_t count, const double *out, const fit_options *opt,
                         fit_options *co, double *gtol, double **sc, lens_err *err)
{
    int ng = g->ng, nc = g->nc, noutputs = g->noutputs;
    *co = *opt;
    co->frame = g->frame ? POLY_FRAME_MERIDIONAL : POLY_FRAME_NONE;
    if (opt->output_tolerance || g->clip) {
        if (ng > 64) {
            lens_errf(err, NULL, 0, "at most 64 outputs with per-output tolerances");
            return -1;
        }
        for (int q = 0; q < ng; q++) {
            int o = g->outs[q];
            gtol[q] = opt->output_tolerance ? opt->output_tolerance[o] : opt->tolerance;
            int p = partner(noutputs, outputs, outputs[o]);
            if (g->clip && !(opt->output_tolerance && gtol[q] > 0) &&
                opt->passage_tolerance > 0 && p >= 0)
                gtol[q] = opt->passage_tolerance * pass_radius(out, count, noutputs, g->ieta, o, p);
        }
        co->output_tolerance = gtol;
    }
    if (g->clip) {
        co->max_parts = 1;
        co->force_parts = 1;
    }
    if (g->frame) {
        int ix = poly_input_index(sys, "x"), iy = poly_input_index(sys, "y");
        int kx = ix < iy ? ix : ix - 1;
        if (kx < 32)
            co->no_offset |= 1u << kx;
    }
    /* The second group (outside the frame) uses the scaling the first one chose (one
     * scaling per input; y, absent from the frame, is its own) and its number of
     * radial parts, cut by the same rule on the same rows. */
    *sc = NULL;
    if (poly_nparts(sys) > 0) {
        *sc = malloc((size_t)nc * 2 * sizeof **sc);
        if (!*sc) {
            lens_errf(err, NULL, 0, "out of memory");
            return -1;
        }
        int sy = poly_get_frame(sys) == POLY_FRAME_MERIDIONAL ? poly_input_index(sys, "y") : -1;
        for (int k = 0; k < nc; k++) {
            poly_get_scaling(sys, g->cmap[k], *sc + 2 * k, *sc + 2 * k + 1);
            if (g->cmap[k] == sy)
                (*sc)[2 * k] = (*sc)[2 * k + 1] = NAN;
        }
        co->scaling = *sc;
        if (!g->clip)
            co->force_parts = poly_nparts(sys);
    }
    return 0;
}

/* Part cp of the core's polynomials into part sp of sys, over the original inputs
 * (y: exponent 0). */
static int copy_terms(poly_system *sys, int sp, const poly_system *core, int cp, const group *g,
                      lens_err *err)
{
    int e[POLY_MAX_INPUTS + 1], ce[POLY_MAX_INPUTS + 1];
    for (int q = 0; q < g->ng; q++)
        for (int tt = 0; tt < poly_nterms(core, cp, q); tt++) {
            double coef;
            poly_get_term(core, cp, q, tt, ce, &coef);
            memset(e, 0, (size_t)g->ninputs * sizeof *e);
            for (int k = 0; k < g->nc; k++)
                e[g->cmap[k]] = ce[k];
            if (poly_add_term(sys, sp, g->outs[q], e, coef) != 0) {
                lens_errf(err, NULL, 0, "out of memory");
                return -1;
            }
        }
    return 0;
}

/* A passage group's one part, the same polynomial in every part of sys (its rows are
 * not the others', so neither would its cuts be), with circles around the hits of the
 * passing rows. */
static int take_clip_group(poly_system *sys, const poly_system *core, const group *g,
                           const char *const *outputs, size_t count, const double *out,
                           lens_err *err)
{
    int noutputs = g->noutputs;
    if (poly_nparts(sys) == 0)
        poly_add_part(sys, 0, INFINITY);
    for (int p = 0; p < poly_nparts(sys); p++)
        if (copy_terms(sys, p, core, 0, g, err) != 0)
            return -1;
    for (int q = 0; q < g->ng; q++) {
        const char *name = outputs[g->outs[q]];
        int p = partner(noutputs, outputs, name);
        double rad = p >= 0 ? pass_radius(out, count, noutputs, g->ieta, g->outs[q], p) : 0;
        if (name[strlen(name) - 1] == 'x' && rad > 0)
            poly_add_pass_circle(sys, g->outs[q], p, rad * (1 + 1e-9));
    }
    for (int m = 0; m < poly_nmeta(core); m++) {
        const char *key = poly_meta_key(core, m), *val = poly_get_meta(core, key);
        if (!strcmp(key, "fit_samples"))
            poly_set_meta(sys, "passage_samples", val);
        else if (!poly_get_meta(sys, key) || !strcmp(key, "fit_flags"))
            poly_set_meta(sys, key, val);
    }
    return 0;
}

/* A group's parts: the first group's cut the rings, a later one must cut the same. */
static int take_group(poly_system *sys, const poly_system *core, const group *g, lens_err *err)
{
    int first = poly_nparts(sys) == 0;
    if (!first && poly_nparts(sys) != poly_nparts(core)) {
        lens_errf(err, NULL, 0, "the outputs in and outside the frame chose different radial "
                                "parts: fit them separately or use --frame none");
        return -1;
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
            return -1;
        }
        if (copy_terms(sys, p, core, p, g, err) != 0)
            return -1;
    }
    for (int c = 0; c < poly_npass_circles(core); c++) {
        int a, b;
        double radius;
        poly_get_pass_circle(core, c, &a, &b, &radius);
        poly_add_pass_circle(sys, g->outs[a], g->outs[b], radius);
    }
    for (int m = 0; m < poly_nmeta(core); m++) {
        const char *key = poly_meta_key(core, m), *val = poly_get_meta(core, key);
        if (poly_get_meta(sys, key) && strcmp(key, "fit_flags") != 0 &&
            strcmp(key, "fit_samples") != 0 && strcmp(key, "fit_parts") != 0)
            continue;
        poly_set_meta(sys, key, val);
    }
    return 0;
}

/* One group of outputs fitted by the core: in the frame (frame = 1: inputs without y,
 * outputs rotated into the frame) or outside it (the inputs through the transforms).
 * Copies its parts, terms and pass circles into sys. A passage group (clip = 1) is
 * fitted on every row where its outputs are finite, as one part copied into every part
 * of sys, with the passage tolerance, and gets circles around the hits of the passing
 * rows. */
static int fit_group(poly_system *sys, int in_frame, int clip, const int *outs, int ng, int ninputs,
                     const char *const *inputs, const char *const *outputs, int noutputs,
                     size_t count, const double *in, const double *out, const fit_options *opt,
                     lens_err *err)
{
    group g = {0};
    g.frame = in_frame && poly_get_frame(sys) == POLY_FRAME_MERIDIONAL;
    g.clip = clip;
    g.outs = outs;
    g.ng = ng;
    g.ninputs = ninputs;
    g.noutputs = noutputs;
    g.nc = ninputs - g.frame; /* the core's inputs: all but y in the frame */
    g.ieta = find_name(noutputs, outputs, "out_eta");
    int rc = -1;
    poly_system *core = NULL;
    fit_options co;
    double gtol[64], *sc = NULL;
    if (group_rows(&g, sys, inputs, outputs, count, in, out, err) != 0 ||
        group_options(&g, sys, outputs, count, out, opt, &co, gtol, &sc, err) != 0)
        goto out;
    core = fit_system_core(poly_lens_name(sys), g.nc, g.cnames, ng, g.gnames, count, g.cin,
                           g.cout, &co, err);
    if (!core)
        goto out;
    for (int k = 0; k < g.nc; k++) {
        double off, scale;
        poly_get_scaling(core, k, &off, &scale);
        poly_set_scaling(sys, g.cmap[k], off, scale);
    }
    rc = clip ? take_clip_group(sys, core, &g, outputs, count, out, err)
              : take_group(sys, core, &g, err);
out:
    free(sc);
    poly_free(core);
    group_free(&g);
    return rc;
}

/* Held-out errors of a pair in the frame are radial and sagittal; what a user
 * compares with is the error per lens-frame coordinate, which for rays spread evenly in
 * angle is sqrt((radial^2 + sagittal^2) / 2) for both. */
static void frame_holdout_meta(poly_system *sys, int noutputs, const char *const *outputs,
                               const fit_options *opt)
{
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
}

/* fit_flags: the core's, with the frame and the transform. */
static void record_frame_flags(poly_system *sys, int noutputs, const char *const *outputs,
                               const fit_options *opt, int xf)
{
    const char *ff = poly_get_meta(sys, "fit_flags");
    char buf[1400], ex[600] = "";
    for (int o = 0, n = 0; o < noutputs; o++)
        if (poly_get_output_plain(sys, o)) {
            size_t l = strlen(ex);
            snprintf(ex + l, sizeof ex - l, "%s%s", n++ ? "," : " --frame-except ", outputs[o]);
        }
    char pt[64] = ""; /* with passage hits among the outputs: how finely they were fitted */
    for (int o = 0; o < noutputs; o++)
        if (fit_is_passage_output(outputs[o])) {
            snprintf(pt, sizeof pt, " --passage-tolerance %.17g%s", opt->passage_tolerance,
                     opt->drop_circles ? "" : " --keep-circles");
            break;
        }
    snprintf(buf, sizeof buf, "%s --frame %s%s --lambda-transform %s%s", ff ? ff : "",
             poly_frame_name(opt->frame), ex, poly_xform_name(xf), pt);
    poly_set_meta(sys, "fit_flags", buf);
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
    frame_holdout_meta(sys, noutputs, outputs, opt);
    record_frame_flags(sys, noutputs, outputs, opt, xf);
    if (opt->drop_circles && npassage > 0) {
        /* the lens's verdict on each row */
        unsigned char *lens_pass = malloc(count ? count : 1);
        poly_system *kept = NULL;
        if (lens_pass) {
            for (size_t r = 0; r < count; r++)
                lens_pass[r] = (unsigned char)usable(out + r * (size_t)noutputs, noutputs, ieta);
            kept = fit_drop_circles(sys, count, in, lens_pass);
            free(lens_pass);
        }
        if (!kept) {
            lens_errf(err, NULL, 0, "out of memory");
            goto fail;
        }
        sys = kept;
    }
    free(outs); free(lo); free(hi);
    return sys;
fail:
    poly_free(sys);
    free(outs); free(lo); free(hi);
    return NULL;
}
