/* C code for a polynomial system (lens-fit --emit c, lens-eval --emit c): one function
 * that repeats poly_eval's arithmetic exactly (poly_impl.h): the same scaled inputs,
 * part selection, products in the same pairs, and the same plan of four interleaved
 * partial sums, so compiled without floating-point contraction it gives the same bits. */
#include "poly/poly_impl.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int c_identifier(const char *s)
{
    if (!s || !(isalpha((unsigned char)*s) || *s == '_'))
        return 0;
    for (; *s; s++)
        if (!(isalnum((unsigned char)*s) || *s == '_'))
            return 0;
    return 1;
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

/* Comment text must not close the comment: names come from the file. */
static void comment_name(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (s[0] == '*' && s[1] == '/')
            fputs("* /", f), s++;
        else
            fputc(*s, f);
    }
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
        comment_name(f, s->inputs[i]);
        fputs(" */\n", f);
    }
}

/* Pass circle c as a C condition on the outputs in array var: one text for the scalar
 * function and the batch loop, so both test exactly the same expression. */
static void emit_circle(FILE *f, const poly_system *s, int c, const char *var)
{
    const poly_circle *k = &s->circles[c];
    fprintf(f, "%s[%d] * %s[%d] + %s[%d] * %s[%d] <= ", var, k->a, var, k->a, var, k->b, var, k->b);
    num(f, k->radius);
    fputs(" * ", f);
    num(f, k->radius);
}

static int emit_part(FILE *f, const poly_system *s, const poly_part *p, const char *outfmt);

/* NAME_batch: one part goes in blocks of 8 rays through one loop without branches, which
 * compilers vectorise; several parts (and the last rays) go ray by ray through NAME. */
static int emit_batch(FILE *f, const poly_system *s, const char *func)
{
    const int nin = s->nin, nout = s->nout;
    fprintf(f,
            "\n/* %s on n rays: in holds n rows of %d inputs, out gets n rows of %d outputs\n"
            " * and pass (unless NULL) n flags, the values of %s ray by ray. */\n"
            "void %s_batch(size_t n, const double *restrict in, double *restrict out,\n"
            "    unsigned char *restrict pass)\n{\n"
            "    size_t b = 0;\n",
            func, nin, nout, func, func);
    if (s->nparts == 1) {
        fputs("    for (; b + 8 <= n; b += 8) {\n        double ", f);
        for (int i = 0; i < nin; i++)
            fprintf(f, "%sx%d[8]", i ? ", " : "", i);
        fputs(";\n        double ", f);
        for (int o = 0; o < nout; o++)
            fprintf(f, "%sy%d[8]", o ? ", " : "", o);
        fputs(";\n        for (int r = 0; r < 8; r++) {\n", f);
        for (int i = 0; i < nin; i++)
            fprintf(f, "            x%d[r] = in[(b + r) * %d + %d];\n", i, nin, i);
        fputs("        }\n        for (int r = 0; r < 8; r++) {\n", f);
        fputs("            const double m0 = 1;\n            (void)m0;\n", f);
        emit_scaled_inputs(f, s, "            ", "x%d[r]");
        if (emit_part(f, s, &s->parts[0], "y%d[r]") != 0)
            return -1;
        fputs("        }\n        for (int r = 0; r < 8; r++) {\n", f);
        fprintf(f, "            double *o = out + (b + r) * %d;\n", nout);
        for (int o = 0; o < nout; o++)
            fprintf(f, "            o[%d] = y%d[r];\n", o, o);
        fputs("            if (pass)\n                pass[b + r] = (unsigned char)(1", f);
        for (int o = 0; o < nout; o++)
            fprintf(f, " && isfinite(o[%d])", o);
        for (int c = 0; c < s->ncircles; c++) {
            fputs("\n                    && ", f);
            emit_circle(f, s, c, "o");
        }
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
        poly_format_monomial(f, s, m->exps + (size_t)k * (size_t)nin);
        fputs(" */\n", f);
    }
    for (int o = 0; o < s->nout; o++) {
        const poly_out_terms *ot = &p->out[o];
        const int t0 = pl->start[o], ns = pl->nsingle[o];
        fprintf(f, "        { /* ");
        comment_name(f, s->outputs[o]);
        fprintf(f, ": %d terms */\n", ot->nterms);
        fputs("            double a0 = 0, a1 = 0, a2 = 0, a3 = 0;\n", f);
        /* the plan's order: single terms, then fused ones, each run from sum a0 on */
        for (int q = t0; q < pl->start[o + 1]; q++) {
            int t = pl->src[q], k = ot->slot[t];
            fprintf(f, "            a%d += ", (q - t0 - (q - t0 >= ns ? ns : 0)) % POLY_NSUMS);
            num(f, ot->coef[t]);
            if (q - t0 < ns)
                fprintf(f, " * m%d;\n", k);
            else
                fprintf(f, " * (m%d * m%d);\n", m->a[k], m->b[k]);
        }
        fputs("            ", f);
        fprintf(f, outfmt, o);
        fputs(" = (a0 + a1) + (a2 + a3);\n        }\n", f);
    }
    free(fused);
    return 0;
}

/* The frame and transforms around NAME_core (poly_frame.c), as the same expressions in
 * the same order; the pass test on the final outputs. */
static void emit_frame(FILE *f, const poly_system *s, const char *func)
{
    const int nin = s->nin, nout = s->nout;
    fprintf(f, "    double t[%d];\n", nin);
    for (int i = 0; i < nin; i++)
        fprintf(f, "    t[%d] = in[%d];\n", i, i);
    if (s->frame == POLY_FRAME_MERIDIONAL)
        fprintf(f,
                "    /* the meridional frame: the sensor point rotated onto +x */\n"
                "    const double fr = sqrt(in[%d] * in[%d] + in[%d] * in[%d]);\n"
                "    const double fi = 1 / fr;\n"
                "    const double fc = fr > 0 ? in[%d] * fi : 1, fs = fr > 0 ? in[%d] * fi : 0;\n"
                "    t[%d] = fr;\n    t[%d] = 0;\n"
                "    t[%d] = fc * in[%d] + fs * in[%d];\n"
                "    t[%d] = fc * in[%d] - fs * in[%d];\n"
                "    (void)fc;\n    (void)fs;\n",
                s->ix, s->ix, s->iy, s->iy, s->ix, s->iy, s->ix, s->iy, s->iu, s->iu, s->iv,
                s->iv, s->iv, s->iu);
    for (int i = 0; i < nin; i++)
        if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE) {
            fprintf(f, "    t[%d] = 1 / (t[%d] * t[%d]); /* ", i, i, i);
            comment_name(f, s->inputs[i]);
            fputs(": inverse-square */\n", f);
        }
    fprintf(f, "    %s_core(t, out);\n", func);
    if (s->frame == POLY_FRAME_MERIDIONAL && s->nplain > 0) {
        fputs("    /* outputs outside the frame: the inputs through their transforms only */\n", f);
        fprintf(f, "    double p[%d], op[%d];\n", nin, nout);
        for (int i = 0; i < nin; i++) {
            if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE)
                fprintf(f, "    p[%d] = 1 / (in[%d] * in[%d]);\n", i, i, i);
            else
                fprintf(f, "    p[%d] = in[%d];\n", i, i);
        }
        fprintf(f, "    %s_core%s(p, op);\n", func, s->vplain ? "_plain" : "");
        for (int o = 0; o < nout; o++)
            if (s->plain[o])
                fprintf(f, "    out[%d] = op[%d];\n", o, o);
    }
    for (int k = 0; k < s->npairs; k++) {
        int a = s->pair[2 * k], b = s->pair[2 * k + 1];
        fprintf(f,
                "    {\n        const double a = out[%d], b = out[%d];\n"
                "        out[%d] = fc * a - fs * b;\n        out[%d] = fs * a + fc * b;\n    }\n",
                a, b, a, b);
    }
    fprintf(f, "    for (int o = 0; o < %d; o++)\n        if (!isfinite(out[o]))\n            return 0;\n",
            nout);
    for (int c = 0; c < s->ncircles; c++) {
        fputs("    if (!(", f);
        emit_circle(f, s, c, "out");
        fputs("))\n        return 0;\n", f);
    }
    fputs("    return 1;\n}\n", f);
}

/* The polynomials of s on in[] into out[]: scaled inputs, part choice, the sums. */
static int emit_core_body(FILE *f, const poly_system *s, int voids)
{
    fputs("    const double m0 = 1;\n", f);
    emit_scaled_inputs(f, s, "    ", "in[%d]");
    for (int i = 0; voids && i < s->nin; i++) /* a view may not use every input */
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

int poly_emit_c(FILE *f, const poly_system *s, const char *func)
{
    if (!c_identifier(func))
        return -1;
    const int nin = s->nin, nout = s->nout;
    fputs("/* Generated by sparselens (lens-fit / lens-eval --emit c); do not edit.\n * Lens: ",
          f);
    comment_name(f, s->lens_name);
    if (s->lens_path[0]) {
        fputs(" (", f);
        comment_name(f, s->lens_path);
        fputs(")", f);
    }
    fputs("\n * in[]: ", f);
    for (int i = 0; i < nin; i++) {
        fprintf(f, "%s[%d] ", i ? ", " : "", i);
        comment_name(f, s->inputs[i]);
    }
    fputs("\n * out[]:", f);
    for (int o = 0; o < nout; o++) {
        fprintf(f, "%s[%d] ", o ? ", " : " ", o);
        comment_name(f, s->outputs[o]);
    }
    fprintf(f,
            "\n * Returns 1 if the ray passes the lens, 0 if not (out[] is filled either way).\n"
            " * %s_batch does the same for many rays, several times faster (vectorised).\n"
            " * Compile without floating-point contraction (-ffp-contract=off, the default\n"
            " * with -std=c99 or -std=c11) to get exactly the values of lens-eval. */\n"
            "#include <math.h>\n#include <stddef.h>\n\n",
            func);
    const poly_system *const whole = s;
    const int act = poly_frame_active(s) && s->nparts > 0;
    if (act && s->vframe) {
        /* the two views evaluation runs (poly_impl.h), for the same sums */
        fprintf(f, "static void %s_core_plain(const double in[%d], double out[%d])\n{\n", func,
                nin, nout);
        if (emit_core_body(f, s->vplain, 1) != 0)
            return -1;
        fputs("}\n\n", f);
        s = s->vframe; /* NAME_core below; the frame itself is taken from the caller's */
    }
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
    if (emit_core_body(f, s, act) != 0)
        return -1;
    if (act) {
        fputs("}\n\n", f);
        fprintf(f, "int %s(const double in[%d], double out[%d])\n{\n", func, nin, nout);
        emit_frame(f, whole, func);
        /* with a frame, the batch function goes ray by ray (same values, not vectorised) */
        fprintf(f,
                "\n/* %s on n rays: in holds n rows of %d inputs, out gets n rows of %d outputs\n"
                " * and pass (unless NULL) n flags, the values of %s ray by ray. */\n"
                "void %s_batch(size_t n, const double *restrict in, double *restrict out,\n"
                "    unsigned char *restrict pass)\n{\n"
                "    for (size_t r = 0; r < n; r++) {\n"
                "        int p = %s(in + r * %d, out + r * %d);\n"
                "        if (pass)\n            pass[r] = (unsigned char)p;\n    }\n}\n",
                func, nin, nout, func, func, func, nin, nout);
        return ferror(f) ? -1 : 0;
    }
    fputs("    for (int o = 0; o < ", f);
    fprintf(f, "%d; o++)\n        if (!isfinite(out[o]))\n            return 0;\n", nout);
    for (int c = 0; c < s->ncircles; c++) {
        fputs("    if (!(", f);
        emit_circle(f, s, c, "out");
        fputs("))\n        return 0;\n", f);
    }
    fputs("    return 1;\n}\n", f);
    return emit_batch(f, s, func) != 0 || ferror(f) ? -1 : 0;
}
