/* C code for a polynomial system (lens-fit --emit c, lens-eval --emit c): one function
 * that repeats poly_eval's arithmetic exactly (poly_impl.h): the same scaled inputs,
 * part selection, products in the same pairs, and the same four interleaved partial
 * sums, so compiled without floating-point contraction it gives the same bits. */
#include "poly_impl.h"

#include <ctype.h>
#include <math.h>
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

static void emit_part(FILE *f, const poly_system *s, const poly_part *p)
{
    const int nin = s->nin;
    for (int j = 0; j < p->nslots - 1 - nin; j++) {
        int k = p->order[j];
        fprintf(f, "        const double m%d = m%d * m%d; /* ", k, p->slot_a[k], p->slot_b[k]);
        poly_format_monomial(f, s, p->slot_exps + (size_t)k * (size_t)nin);
        fputs(" */\n", f);
    }
    for (int o = 0; o < s->nout; o++) {
        const poly_out_terms *ot = &p->out[o];
        fprintf(f, "        { /* ");
        comment_name(f, s->outputs[o]);
        fprintf(f, ": %d terms */\n", ot->nterms);
        fputs("            double a0 = 0, a1 = 0, a2 = 0, a3 = 0;\n", f);
        for (int t = 0; t < ot->nterms; t++) {
            fprintf(f, "            a%d += ", t % POLY_NSUMS);
            num(f, ot->coef[t]);
            fprintf(f, " * m%d;\n", ot->slot[t]);
        }
        fprintf(f, "            out[%d] = (a0 + a1) + (a2 + a3);\n        }\n", o);
    }
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
                "    const double fc = fr > 0 ? in[%d] / fr : 1, fs = fr > 0 ? in[%d] / fr : 0;\n"
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
        fprintf(f, "    %s_core(p, op);\n", func);
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
        fprintf(f, "    if (!(out[%d] * out[%d] + out[%d] * out[%d] <= ", s->circles[c].a,
                s->circles[c].a, s->circles[c].b, s->circles[c].b);
        num(f, s->circles[c].radius);
        fputs(" * ", f);
        num(f, s->circles[c].radius);
        fputs("))\n        return 0;\n", f);
    }
    fputs("    return 1;\n}\n", f);
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
    fputs("\n * Returns 1 if the ray passes the lens, 0 if not (out[] is filled either way).\n"
          " * Compile without floating-point contraction (-ffp-contract=off, the default\n"
          " * with -std=c99 or -std=c11) to get exactly the values of lens-eval. */\n"
          "#include <math.h>\n\n",
          f);
    const int act = poly_frame_active(s) && s->nparts > 0;
    if (act) /* the polynomials alone; the function below wraps the frame around them */
        fprintf(f, "static void %s_core(const double in[%d], double out[%d])\n{\n", func, nin,
                nout);
    else
        fprintf(f, "int %s(const double in[%d], double out[%d])\n{\n", func, nin, nout);
    if (s->nparts == 0) {
        for (int o = 0; o < nout; o++)
            fprintf(f, "    out[%d] = NAN;\n", o);
        fputs("    (void)in;\n    return 0;\n}\n", f);
        return ferror(f) ? -1 : 0;
    }
    fputs("    const double m0 = 1;\n", f);
    for (int i = 0; i < nin; i++) {
        fprintf(f, "    const double m%d = (in[%d] - ", 1 + i, i);
        num(f, s->offset[i]);
        fputs(") / ", f);
        num(f, s->scale[i]);
        fputs("; /* ", f);
        comment_name(f, s->inputs[i]);
        fputs(" */\n", f);
    }
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
        emit_part(f, s, &s->parts[p]);
        fputs("        break;\n    }\n", f);
    }
    fputs("    }\n", f);
    if (act) {
        fputs("}\n\n", f);
        fprintf(f, "int %s(const double in[%d], double out[%d])\n{\n", func, nin, nout);
        emit_frame(f, s, func);
        return ferror(f) ? -1 : 0;
    }
    fputs("    for (int o = 0; o < ", f);
    fprintf(f, "%d; o++)\n        if (!isfinite(out[o]))\n            return 0;\n", nout);
    for (int c = 0; c < s->ncircles; c++) {
        fprintf(f, "    if (!(out[%d] * out[%d] + out[%d] * out[%d] <= ", s->circles[c].a,
                s->circles[c].a, s->circles[c].b, s->circles[c].b);
        num(f, s->circles[c].radius);
        fputs(" * ", f);
        num(f, s->circles[c].radius);
        fputs("))\n        return 0;\n", f);
    }
    fputs("    return 1;\n}\n", f);
    return ferror(f) ? -1 : 0;
}
