/* C code for a polynomial system (lens-fit --emit c, lens-eval --emit c): one function
 * that repeats poly_eval's arithmetic exactly (poly_impl.h): the same scaled inputs,
 * part selection, products in the same pairs, and the same plan of four interleaved
 * partial sums, so compiled without floating-point contraction it gives the same bits. */
#include "poly/poly_impl.h"

#include "sparselens/escape.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int poly_c_name_ok(const char *name)
{
    const char *why;
    return text_c_prefix_ok(name, &why);
}

int poly_c_name_check(const char *name, lens_err *err)
{
    const char *why;
    if (text_c_prefix_ok(name, &why))
        return 0;
    if (name && *name && strspn(name, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                      "0123456789_") == strlen(name))
        lens_errf(err, NULL, 0, "--name: '%s' cannot name the generated C: %s", name, why);
    else
        lens_errf(err, NULL, 0, "--name: %s", why);
    return -1;
}

static void num(FILE *f, double v)
{
    char buf[40];
    if (isinf(v)) {
        fputs(v > 0 ? "INFINITY" : "-INFINITY", f);
        return;
    }
    poly_format_number(buf, sizeof buf, v);
    /* "(-0.5)" keeps "a - -0.5" and "x * -1" unambiguous to a reader */
    if (v < 0 || (v == 0 && signbit(v)))
        fprintf(f, "(%s)", buf);
    else
        fputs(buf, f);
}

/* m1.. = the scaled inputs (poly_scale_column), input i read as srcfmt with i. */
static void emit_scaled_inputs(FILE *f, const poly_system *s, const char *indent,
                               const char *srcfmt)
{
    for (int i = 0; i < s->nin; i++) {
        fprintf(f, "%sconst double m%d = (", indent, 1 + i);
        fprintf(f, srcfmt, i);
        fputs(" - ", f);
        num(f, s->offset[i]);
        fputs(") * (1.0 / ", f);
        num(f, s->scale[i]);
        fputs("); /* ", f);
        text_c_comment(f, s->inputs[i]);
        fputs(" */\n", f);
    }
}

static int emit_part(FILE *f, const poly_system *s, const poly_part *p, const char *outfmt);

/* The kept products in depth order, then per output its terms in the plan's order, a
 * fused term multiplying its monomial in place as the plan does. */
static int emit_part(FILE *f, const poly_system *s, const poly_part *p, const char *outfmt)
{
    const int nin = s->nin;
    const poly_mono *m = &p->mono;
    const poly_plan *pl = &p->plan;
    char *fused = calloc((size_t)m->nslots, 1);
    if (!fused)
        return -1;
    for (int o = 0; o < s->nout; o++)
        for (int q = pl->start[o] + pl->nsingle[o]; q < pl->start[o + 1]; q++)
            fused[p->out[o].slot[pl->src[q]]] = 1;
    for (int j = 0; j < m->nslots - 1 - nin; j++) {
        int k = pl->order[j];
        if (fused[k])
            continue;
        fprintf(f, "        const double m%d = m%d * m%d; /* ", k, m->a[k], m->b[k]);
        poly_format_monomial(f, s, m->exps + (size_t)k * (size_t)nin, text_c_comment);
        fputs(" */\n", f);
    }
    for (int o = 0; o < s->nout; o++) {
        const poly_out_terms *ot = &p->out[o];
        const int t0 = pl->start[o], ns = pl->nsingle[o];
        fprintf(f, "        { /* ");
        text_c_comment(f, s->outputs[o]);
        fprintf(f, ": %d terms */\n", ot->nterms);
        if (ot->nterms == 0) {
            fputs("            ", f);
            fprintf(f, outfmt, o);
            fputs(" = 0;\n        }\n", f);
            continue;
        }
        /* from -0, as the library (poly_impl.h): a compiler takes the first term as is */
        fputs("            double a0 = -0.0, a1 = -0.0, a2 = -0.0, a3 = -0.0;\n", f);
        /* the plan's runs (poly_impl.h): single terms, then the fused ones by quads,
         * pairs and lone terms, each run from sum a0 on */
        int q = t0;
        for (int i = 0; i < ns; i++, q++) {
            fprintf(f, "            a%d += ", i % POLY_NSUMS);
            num(f, ot->coef[pl->src[q]]);
            fprintf(f, " * m%d;\n", ot->slot[pl->src[q]]);
        }
        const int nq = pl->nquad[o], np = pl->npair[o];
        const int nl = pl->start[o + 1] - t0 - ns - 4 * nq - 2 * np;
        for (int w = 4; w >= 1; w /= 2)
            for (int i = 0; i < (w == 4 ? nq : w == 2 ? np : nl); i++, q += w) {
                fprintf(f, "            a%d += %s", i % POLY_NSUMS, w == 4 ? "((" : "(");
                for (int j = 0; j < w; j++) {
                    fputs(j == 0 ? "" : j == 2 ? ") + (" : " + ", f);
                    num(f, ot->coef[pl->src[q + j]]);
                    fprintf(f, " * m%d", pl->vslot[pl->fa[q + j]]);
                }
                fprintf(f, "%s * m%d;\n", w == 4 ? "))" : ")", pl->vslot[pl->fb[q]]);
            }
        fputs("            ", f);
        fprintf(f, outfmt, o);
        fputs(" = (a0 + a1) + (a2 + a3);\n        }\n", f);
    }
    free(fused);
    return 0;
}

/* Input i as the C text of srcfmt ("in[%d]", "x%d[r]"). */
static const char *src_of(char *buf, size_t len, const char *srcfmt, int i)
{
    snprintf(buf, len, srcfmt, i);
    return buf;
}

/* The values of the pass test (poly_passes) on the outputs named by outfmt ("out[%d]",
 * "y%d[r]"), before the frame turns them back, as liblens tests them: fin, a sum of
 * v - v over the outputs no circle covers (0 when they are finite: inf - inf and nan
 * are nan), and cqC, circle C's a * a + b * b, each declared as decl ("const double "
 * in the scalar function) and indexed by at ("[r]": the batch's arrays of a block, so
 * that its loop over the block's rays keeps only arithmetic on doubles, which compilers
 * vectorise; a test in it, or a flag of another type, kept GCC 12 from it: bench_poly,
 * 2.5 times the kernel's time). emit_pass_compare then tests them; one text for both
 * functions, so both give the same flags. */
static void emit_pass_values(FILE *f, const poly_system *s, const char *ind, const char *outfmt,
                             const char *decl, const char *at)
{
    char a[64], b[64];
    fprintf(f, "%s%sfin%s = 0", ind, decl, at);
    for (int o = 0; o < s->nout; o++)
        if (!poly_circle_covers(s, o)) {
            src_of(a, sizeof a, outfmt, o);
            fprintf(f, " + (%s - %s)", a, a);
        }
    fputs(";\n", f);
    for (int c = 0; c < s->ncircles; c++) {
        src_of(a, sizeof a, outfmt, s->circles[c].a);
        src_of(b, sizeof b, outfmt, s->circles[c].b);
        fprintf(f, "%s%scq%d%s = %s * %s + %s * %s;\n", ind, decl, c, at, a, a, b, b);
    }
}

/* The pass test on emit_pass_values' values (indexed by at), as one C expression: the
 * comparisons joined by &, every one made (which one a blocked ray fails is data, and
 * && is a branch on it, as poly_in_circles says). */
static void emit_pass_compare(FILE *f, const poly_system *s, const char *ind, const char *at)
{
    fprintf(f, "(fin%s == 0)", at);
    for (int c = 0; c < s->ncircles; c++) {
        fprintf(f, "\n%s& (cq%d%s <= ", ind, c, at);
        num(f, s->circles[c].radius);
        fputs(" * ", f);
        num(f, s->circles[c].radius);
        fputs(")", f);
    }
}

/* The frame's angle (poly_frame.c): the sensor radius fr of the sensor point (x, y)
 * (C texts), and its cosine fc and sine fs; fc = 1, fs = 0 on the axis. */
static void emit_frame_angle(FILE *f, const char *ind, const char *x, const char *y)
{
    fprintf(f,
            "%sconst double fr = sqrt(%s * %s + %s * %s);\n"
            "%sconst double fi = 1 / fr;\n"
            "%sconst double fc = fr > 0 ? %s * fi : 1, fs = fr > 0 ? %s * fi : 0;\n",
            ind, x, x, y, y, ind, ind, x, y);
}

/* The inputs of the core in t[] (rotated into the frame, then transformed) and, with
 * outputs outside the frame, those of the plain view in p[] (transformed only), as
 * poly_frame_in does; input i is srcfmt with i. With angle, fr, fc and fs are that
 * C text with "r", "c", "s" (the batch loop's arrays), else computed here. */
static void emit_frame_in(FILE *f, const poly_system *s, const char *ind, const char *srcfmt,
                          const char *angle)
{
    const int nin = s->nin;
    char a[64], b[64];
    fprintf(f, "%sdouble t[%d];\n", ind, nin);
    for (int i = 0; i < nin; i++)
        fprintf(f, "%st[%d] = %s;\n", ind, i, src_of(a, sizeof a, srcfmt, i));
    if (s->frame == POLY_FRAME_MERIDIONAL) {
        fprintf(f, "%s/* the meridional frame: the sensor point rotated onto +x */\n", ind);
        if (angle)
            fprintf(f, "%sconst double fr = %s, fc = %s, fs = %s;\n", ind,
                    src_of(a, sizeof a, angle, 'r'), src_of(b, sizeof b, angle, 'c'),
                    src_of(b + 32, 32, angle, 's'));
        else
            emit_frame_angle(f, ind, src_of(a, sizeof a, srcfmt, s->ix),
                             src_of(b, sizeof b, srcfmt, s->iy));
        fprintf(f, "%st[%d] = fr;\n%st[%d] = 0;\n", ind, s->ix, ind, s->iy);
        /* c v - s u written c v + (-s) u: the same bits (IEEE subtracts by adding the
         * negation), but no add beside a subtract of the same products, which GCC 12's
         * SLP vectoriser fuses into vfmaddsub even where contraction is off (at -O2
         * -march=native: test_poly_emit saw the last bit of out_y move) */
        fprintf(f, "%sconst double fn = -fs;\n", ind);
        const char *u = src_of(a, sizeof a, srcfmt, s->iu), *v = src_of(b, sizeof b, srcfmt, s->iv);
        fprintf(f, "%st[%d] = fc * %s + fs * %s;\n%st[%d] = fc * %s + fn * %s;\n", ind, s->iu, u,
                v, ind, s->iv, v, u);
    } else {
        fprintf(f, "%sconst double fc = 1, fs = 0, fn = -0.0;\n", ind);
    }
    fprintf(f, "%s(void)fc;\n%s(void)fs;\n%s(void)fn;\n", ind, ind, ind);
    for (int i = 0; i < nin; i++)
        if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE) {
            fprintf(f, "%st[%d] = 1 / (t[%d] * t[%d]); /* ", ind, i, i, i);
            text_c_comment(f, s->inputs[i]);
            fputs(": inverse-square */\n", f);
        }
    if (s->frame == POLY_FRAME_MERIDIONAL && s->nplain > 0) {
        fprintf(f, "%s/* outputs outside the frame: the inputs through their transforms only */\n",
                ind);
        fprintf(f, "%sdouble p[%d];\n", ind, nin);
        for (int i = 0; i < nin; i++) {
            const char *x = src_of(a, sizeof a, srcfmt, i);
            if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE)
                fprintf(f, "%sp[%d] = 1 / (%s * %s);\n", ind, i, x, x);
            else
                fprintf(f, "%sp[%d] = %s;\n", ind, i, x);
        }
    }
}

/* The output pairs turned back out of the frame, in the array of outfmt (c a - s b
 * as c a + (-s) b: see emit_frame_in). */
static void emit_frame_out(FILE *f, const poly_system *s, const char *ind, const char *outfmt)
{
    char a[64], b[64];
    for (int k = 0; k < s->npairs; k++) {
        src_of(a, sizeof a, outfmt, s->pair[2 * k]);
        src_of(b, sizeof b, outfmt, s->pair[2 * k + 1]);
        fprintf(f,
                "%s{\n%s    const double a = %s, b = %s;\n"
                "%s    %s = fc * a + fn * b;\n%s    %s = fs * a + fc * b;\n%s}\n",
                ind, ind, a, b, ind, a, ind, b, ind);
    }
}

/* The frame and transforms around NAME_core (poly_frame.c), as the same expressions in
 * the same order; the pass test on the frame's values, before they turn back. */
static void emit_frame(FILE *f, const poly_system *s, const char *func)
{
    const int nout = s->nout;
    emit_frame_in(f, s, "    ", "in[%d]", NULL);
    fprintf(f, "    %s_core(t, out);\n", func);
    if (s->frame == POLY_FRAME_MERIDIONAL && s->nplain > 0) {
        fprintf(f, "    double op[%d];\n", nout);
        fprintf(f, "    %s_core%s(p, op);\n", func, s->vplain ? "_plain" : "");
        for (int o = 0; o < nout; o++)
            if (s->plain[o])
                fprintf(f, "    out[%d] = op[%d];\n", o, o);
    }
    emit_pass_values(f, s, "    ", "out[%d]", "const double ", "");
    fputs("    const int pass = ", f);
    emit_pass_compare(f, s, "        ", "");
    fputs(";\n", f);
    emit_frame_out(f, s, "    ", "out[%d]");
    fputs("    return pass;\n}\n", f);
}

/* One view's polynomials (part 0) inside the block loop: its scaled inputs from srcfmt,
 * its sums into outfmt, in a scope of their own. */
static int emit_block_view(FILE *f, const poly_system *v, const char *srcfmt, const char *outfmt)
{
    fputs("            {\n            const double m0 = 1;\n            (void)m0;\n", f);
    emit_scaled_inputs(f, v, "            ", srcfmt);
    for (int i = 0; i < v->nin; i++) /* a view may not use every input */
        fprintf(f, "            (void)m%d;\n", 1 + i);
    if (emit_part(f, v, &v->parts[0], outfmt) != 0)
        return -1;
    fputs("            }\n", f);
    return 0;
}

/* NAME_batch: one part goes in blocks of 8 rays through one loop without branches, which
 * compilers vectorise, the frame and transforms included. The frame's angle is found in
 * a scalar loop of its own: sqrt may set errno, and a select after an ordered compare
 * (it may trap), both keep a loop scalar. Several parts, or views that could not be
 * built, and the last rays go ray by ray through NAME. */
static int emit_batch(FILE *f, const poly_system *s, const char *func)
{
    const int nin = s->nin, nout = s->nout;
    const int act = poly_frame_active(s), views = act && s->frame && s->nplain > 0;
    const int blocks = s->nparts == 1 && (!views || s->vframe);
    const poly_system *core = views ? s->vframe : s;
    fprintf(f,
            "\n/* %s on n rays: in holds n rows of %d inputs, out gets n rows of %d outputs\n"
            " * and pass (unless NULL) n flags, the values of %s ray by ray. With GCC on\n"
            " * x86-64 also compiled for AVX-512 and AVX2, the clone picked when the program\n"
            " * loads (the same bits: no contraction into FMA in ISO C mode). */\n"
            "#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && __GNUC__ >= 12\n"
            "__attribute__((target_clones(\"arch=x86-64-v4\", \"arch=x86-64-v3\", \"default\")))\n"
            "#endif\n"
            "void %s_batch(size_t n, const double *%s_restrict in, double *%s_restrict out,\n"
            "    unsigned char *%s_restrict pass)\n{\n"
            "    size_t b = 0;\n",
            func, nin, nout, func, func, func, func, func);
    if (blocks) {
        fputs("    for (; b + 8 <= n; b += 8) {\n        double ", f);
        for (int i = 0; i < nin; i++)
            fprintf(f, "%sx%d[8]", i ? ", " : "", i);
        fputs(";\n        double ", f);
        for (int o = 0; o < nout; o++)
            fprintf(f, "%sy%d[8]", o ? ", " : "", o);
        fputs(";\n        for (int r = 0; r < 8; r++) {\n", f);
        for (int i = 0; i < nin; i++)
            fprintf(f, "            x%d[r] = in[(b + r) * %d + %d];\n", i, nin, i);
        fputs("        }\n", f);
        if (act && s->frame == POLY_FRAME_MERIDIONAL) {
            char x[16], y[16];
            fputs("        double fr8[8], fc8[8], fs8[8];\n"
                  "        for (int r = 0; r < 8; r++) {\n", f);
            emit_frame_angle(f, "            ", src_of(x, sizeof x, "x%d[r]", s->ix),
                             src_of(y, sizeof y, "x%d[r]", s->iy));
            fputs("            fr8[r] = fr;\n            fc8[r] = fc;\n            fs8[r] = fs;\n"
                  "        }\n", f);
        }
        fputs("        double fin[8]", f); /* the pass test's values, in the frame */
        for (int c = 0; c < s->ncircles; c++)
            fprintf(f, ", cq%d[8]", c);
        fputs(";\n        for (int r = 0; r < 8; r++) {\n", f);
        if (act) {
            emit_frame_in(f, s, "            ", "x%d[r]", "f%c8[r]");
            if (emit_block_view(f, core, "t[%d]", "y%d[r]") != 0)
                return -1;
            if (views) {
                fprintf(f, "            double q[%d];\n", nout);
                if (emit_block_view(f, s->vplain, "p[%d]", "q[%d]") != 0)
                    return -1;
                for (int o = 0; o < nout; o++)
                    if (s->plain[o])
                        fprintf(f, "            y%d[r] = q[%d];\n", o, o);
            }
            emit_pass_values(f, s, "            ", "y%d[r]", "", "[r]");
            emit_frame_out(f, s, "            ", "y%d[r]");
        } else {
            if (emit_block_view(f, s, "x%d[r]", "y%d[r]") != 0)
                return -1;
            emit_pass_values(f, s, "            ", "y%d[r]", "", "[r]");
        }
        fputs("        }\n        for (int r = 0; r < 8; r++) {\n", f);
        fprintf(f, "            double *o = out + (b + r) * %d;\n", nout);
        for (int o = 0; o < nout; o++)
            fprintf(f, "            o[%d] = y%d[r];\n", o, o);
        fputs("            if (pass)\n                pass[b + r] = (unsigned char)(", f);
        emit_pass_compare(f, s, "                    ", "[r]");
        fputs(");\n        }\n    }\n", f);
    }
    fprintf(f,
            "    for (; b < n; b++) {\n"
            "        int p = %s(in + b * %d, out + b * %d);\n"
            "        if (pass)\n"
            "            pass[b] = (unsigned char)p;\n"
            "    }\n}\n",
            func, nin, nout);
    return 0;
}

/* The polynomials of s on in[] into out[]: scaled inputs, part choice, the sums. */
static int emit_core_body(FILE *f, const poly_system *s)
{
    fputs("    const double m0 = 1;\n", f);
    emit_scaled_inputs(f, s, "    ", "in[%d]");
    for (int i = 0; i < s->nin; i++) /* no term may use an input */
        fprintf(f, "    (void)m%d;\n", 1 + i);
    fputs("    (void)m0;\n", f);
    if (s->nparts > 1 && s->ix >= 0 && s->iy >= 0) {
        /* the same search as poly_part_for_radius: the containing part, else the nearest */
        fprintf(f, "    static const double rmin[%d] = {", s->nparts);
        for (int p = 0; p < s->nparts; p++) {
            fputs(p ? ", " : "", f);
            num(f, s->parts[p].rmin);
        }
        fprintf(f, "};\n    static const double rmax[%d] = {", s->nparts);
        for (int p = 0; p < s->nparts; p++) {
            fputs(p ? ", " : "", f);
            num(f, s->parts[p].rmax);
        }
        fprintf(f,
                "};\n"
                "    const double r = sqrt(in[%d] * in[%d] + in[%d] * in[%d]); /* sensor radius */\n"
                "    int part = 0;\n"
                "    double bestd = INFINITY;\n"
                "    for (int p = 0; p < %d; p++) {\n"
                "        if (r >= rmin[p] && r < rmax[p]) {\n"
                "            part = p;\n"
                "            break;\n"
                "        }\n"
                "        double d = r < rmin[p] ? rmin[p] - r : r - rmax[p];\n"
                "        if (d < bestd) {\n"
                "            bestd = d;\n"
                "            part = p;\n"
                "        }\n"
                "    }\n",
                s->ix, s->ix, s->iy, s->iy, s->nparts);
    } else {
        fputs("    const int part = 0;\n", f);
    }
    fputs("    switch (part) {\n", f);
    for (int p = 0; p < s->nparts; p++) {
        if (p == s->nparts - 1)
            fputs("    default: { /* sensor radius in [", f);
        else
            fprintf(f, "    case %d: { /* sensor radius in [", p);
        num(f, s->parts[p].rmin);
        fputs(", ", f);
        num(f, s->parts[p].rmax);
        fputs(") */\n", f);
        if (emit_part(f, s, &s->parts[p], "out[%d]") != 0)
            return -1;
        fputs("        break;\n    }\n", f);
    }
    fputs("    }\n", f);
    return 0;
}

/* Before each one-ray function: GCC's tuning for this machine's cores (-march=native
 * on a Rocket Lake / Ice Lake Xeon) spills the many doubles of a sum into integer
 * registers (vmovq there and back: 175 of them in the 5-output fisheye-ii function),
 * and one call went from 63 ns at -O2 to 77 at -O3 -march=native; the generic tuning
 * keeps the instruction set and gives 64. Tuning does not change the arithmetic. */
static void emit_one_ray_tuning(FILE *f)
{
    fputs("#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)\n"
          "__attribute__((target(\"tune=generic\")))\n"
          "#endif\n",
          f);
}

/* The part of a path after its last '/': a build's absolute path is no business of a
 * generated file. */
static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* What the system holds, for the file's reader: terms, degree, parts. */
static void emit_size(FILE *f, const poly_system *s)
{
    long terms = 0;
    int degree = 0;
    for (int p = 0; p < s->nparts; p++)
        for (int o = 0; o < s->nout; o++)
            terms += s->parts[p].out[o].nterms;
    for (int o = 0; o < s->nout; o++)
        if (poly_max_degree(s, o) > degree)
            degree = poly_max_degree(s, o);
    fprintf(f, " * This system: %ld terms of degree <= %d over %d part%s, %d pass circle%s.\n", terms,
            degree, s->nparts, s->nparts == 1 ? "" : "s", s->ncircles, s->ncircles == 1 ? "" : "s");
}

/* The file's opening comment: the lens, the arrays' columns. */
static void emit_opening(FILE *f, const poly_system *s, const char *func, const char *what)
{
    fprintf(f, "/* Generated by sparselens (lens-fit / lens-eval --emit c); do not edit.\n"
               " * %s\n * Lens: ", what);
    text_c_comment(f, s->lens_name);
    if (s->lens_path[0]) {
        fputs(" (", f);
        text_c_comment(f, base_name(s->lens_path));
        fputs(")", f);
    }
    fprintf(f, "\n * %s(in, out): in[]: ", func);
    for (int i = 0; i < s->nin; i++) {
        fprintf(f, "%s[%d] ", i ? ", " : "", i);
        text_c_comment(f, s->inputs[i]);
    }
    fputs("\n * out[]:", f);
    for (int o = 0; o < s->nout; o++) {
        fprintf(f, "%s[%d] ", o ? ", " : " ", o);
        text_c_comment(f, s->outputs[o]);
    }
    fputs("\n", f);
    emit_size(f, s);
}

/* The declarations of poly_emit_c's file, in C and C++. */
static void emit_declarations(FILE *f, const poly_system *s, const char *func)
{
    fprintf(f,
            "#ifdef __cplusplus\nextern \"C\" {\n#endif\n"
            "int %s(const double in[%d], double out[%d]);\n"
            "void %s_batch(size_t n, const double *in, double *out, unsigned char *pass);\n"
            "#ifdef __cplusplus\n}\n#endif\n",
            func, s->nin, s->nout, func);
}

int poly_emit_c_header(FILE *f, const poly_system *s, const char *func)
{
    if (!poly_c_name_ok(func))
        return -1;
    emit_opening(f, s, func, "The declarations of its C file.");
    fputs(" * Returns 1 if the ray passes the lens, 0 if not (out[] is filled either way). */\n", f);
    char guard[96];
    size_t k = 0;
    for (; func[k] && k < sizeof guard - 3; k++)
        guard[k] = (char)toupper((unsigned char)func[k]);
    memcpy(guard + k, "_H", 3);
    fprintf(f, "#ifndef %s\n#define %s\n#include <stddef.h>\n\n", guard, guard);
    emit_declarations(f, s, func);
    fprintf(f, "\n#endif\n");
    return ferror(f) ? -1 : 0;
}

static int emit_functions(FILE *f, const poly_system *s, const char *func);

int poly_emit_c(FILE *f, const poly_system *s, const char *func)
{
    if (!poly_c_name_ok(func))
        return -1;
    emit_opening(f, s, func, "C11 and C++ (compiled as either, the functions have C linkage).");
    fprintf(f,
            " * Returns 1 if the ray passes the lens, 0 if not (out[] is filled either way).\n"
            " * %s_batch does the same for many rays, in blocks of 8 that compilers vectorise.\n"
            " * Compile without floating-point contraction (-ffp-contract=off, the default\n"
            " * with -std=c99 or -std=c11) to get exactly the values of lens-eval. */\n"
            "#include <math.h>\n#include <stddef.h>\n\n"
            "#ifdef __cplusplus\n#define %s_restrict __restrict\nextern \"C\" {\n#else\n"
            "#define %s_restrict restrict\n#endif\n",
            func, func, func);
    emit_declarations(f, s, func);
    fputs("\n", f);
    int rc = emit_functions(f, s, func);
    fprintf(f, "\n#undef %s_restrict\n#ifdef __cplusplus\n}\n#endif\n", func);
    return rc != 0 || ferror(f) ? -1 : 0;
}

/* The functions themselves: the one-ray function (with its views), then the batch. */
static int emit_functions(FILE *f, const poly_system *s, const char *func)
{
    const int nin = s->nin, nout = s->nout;
    const poly_system *const whole = s;
    const int act = poly_frame_active(s) && s->nparts > 0;
    if (act && s->vframe) {
        /* the two views evaluation runs (poly_impl.h), for the same sums */
        emit_one_ray_tuning(f);
        fprintf(f, "static void %s_core_plain(const double in[%d], double out[%d])\n{\n", func,
                nin, nout);
        if (emit_core_body(f, s->vplain) != 0)
            return -1;
        fputs("}\n\n", f);
        s = s->vframe; /* NAME_core below; the frame itself is taken from the caller's */
    }
    emit_one_ray_tuning(f);
    if (act) /* the polynomials alone; the function below wraps the frame around them */
        fprintf(f, "static void %s_core(const double in[%d], double out[%d])\n{\n", func, nin,
                nout);
    else
        fprintf(f, "int %s(const double in[%d], double out[%d])\n{\n", func, nin, nout);
    if (s->nparts == 0) {
        for (int o = 0; o < nout; o++)
            fprintf(f, "    out[%d] = NAN;\n", o);
        fputs("    (void)in;\n    return 0;\n}\n", f);
        return emit_batch(f, s, func) != 0 || ferror(f) ? -1 : 0;
    }
    if (emit_core_body(f, s) != 0)
        return -1;
    if (act) {
        fputs("}\n\n", f);
        emit_one_ray_tuning(f);
        fprintf(f, "int %s(const double in[%d], double out[%d])\n{\n", func, nin, nout);
        emit_frame(f, whole, func);
        return emit_batch(f, whole, func) != 0 || ferror(f) ? -1 : 0;
    }
    emit_pass_values(f, s, "    ", "out[%d]", "const double ", "");
    fputs("    return ", f);
    emit_pass_compare(f, s, "        ", "");
    fputs(";\n}\n", f);
    return emit_batch(f, s, func) != 0 || ferror(f) ? -1 : 0;
}
