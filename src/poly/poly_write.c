/* The .poly text format written (man 5 lens-poly; poly_io.c reads it). Coefficients,
 * scalings and ranges are written with up to 17 significant digits, which reads back to
 * the same double, so a re-read system evaluates bit-identically (poly_impl.h says why
 * the evaluation order does not depend on anything but the file's contents). */
#include "poly/poly_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The shortest decimal that reads back as exactly v (17 digits always would; fewer
 * keep 0.6 from printing as 0.59999999999999998). */
void poly_format_number(char *buf, size_t len, double v)
{
    if (isinf(v)) {
        snprintf(buf, len, "%s", v > 0 ? "inf" : "-inf");
        return;
    }
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, len, "%.*g", prec, v);
        if (prec == 17 || strtod(buf, NULL) == v)
            break;
    }
}

static void put_num(FILE *f, double v)
{
    char buf[40];
    poly_format_number(buf, sizeof buf, v);
    fputs(buf, f);
}

void poly_format_monomial(FILE *f, const poly_system *s, const int *e,
                          void (*put_name)(FILE *, const char *))
{
    int any = 0;
    for (int i = 0; i < s->nin; i++) {
        if (!e[i])
            continue;
        if (any) /* spaced inside a C comment: a name beginning with '/' ends none */
            fputs(put_name ? " * " : "*", f);
        if (put_name)
            put_name(f, s->inputs[i]);
        else
            fputs(s->inputs[i], f);
        if (e[i] > 1)
            fprintf(f, "^%d", e[i]);
        any = 1;
    }
    if (!any)
        fputc('1', f);
}

int poly_write(FILE *f, const poly_system *s)
{
    fprintf(f, "# sparselens polynomial system (man 5 lens-poly)\n");
    fprintf(f, "lens-poly %d\n", POLY_FORMAT_VERSION);
    fprintf(f, "lens %s\n", s->lens_name);
    if (s->lens_path[0])
        fprintf(f, "lens-path %s\n", s->lens_path);
    fputs("inputs", f);
    for (int i = 0; i < s->nin; i++)
        fprintf(f, " %s", s->inputs[i]);
    fputs("\noutputs", f);
    for (int o = 0; o < s->nout; o++)
        fprintf(f, " %s", s->outputs[o]);
    fputs("\n# monomials are of s = (input - offset) / scale; the domain is the training range\n"
          "#       input offset scale domain-min domain-max\n", f);
    for (int i = 0; i < s->nin; i++) {
        fprintf(f, "scaling %s ", s->inputs[i]);
        put_num(f, s->offset[i]);
        fputc(' ', f);
        put_num(f, s->scale[i]);
        fputc(' ', f);
        put_num(f, s->lo[i]);
        fputc(' ', f);
        put_num(f, s->hi[i]);
        fputc('\n', f);
    }
    /* Only when asked for: a system without them is written as before. */
    if (s->frame != POLY_FRAME_NONE) {
        fprintf(f, "frame %s", poly_frame_name(s->frame));
        for (int o = 0, first = 1; o < s->nout; o++)
            if (s->plain && s->plain[o]) {
                fprintf(f, "%s %s", first ? " except" : "", s->outputs[o]);
                first = 0;
            }
        fputc('\n', f);
    }
    for (int i = 0; i < s->nin; i++)
        if (s->xform[i] != POLY_XFORM_IDENTITY)
            fprintf(f, "transform %s %s\n", s->inputs[i], poly_xform_name(s->xform[i]));
    for (int c = 0; c < s->ncircles; c++) {
        fprintf(f, "pass %s %s ", s->outputs[s->circles[c].a], s->outputs[s->circles[c].b]);
        put_num(f, s->circles[c].radius);
        fputc('\n', f);
    }
    for (int m = 0; m < s->nmeta; m++)
        fprintf(f, "meta %s %s\n", s->meta_key[m], s->meta_val[m]);
    for (int p = 0; p < s->nparts; p++) {
        const poly_part *q = &s->parts[p];
        fprintf(f, "# part %d: sensor radius in [rmin, rmax)\npart ", p);
        put_num(f, q->rmin);
        fputc(' ', f);
        put_num(f, q->rmax);
        fputc('\n', f);
        for (int o = 0; o < s->nout; o++) {
            const poly_out_terms *ot = &q->out[o];
            fprintf(f, "output %s %d\n#", s->outputs[o], ot->nterms);
            for (int i = 0; i < s->nin; i++)
                fprintf(f, " %s", s->inputs[i]);
            fputs(" coefficient\n", f);
            for (int t = 0; t < ot->nterms; t++) {
                const int *e = ot->exps + (size_t)t * (size_t)s->nin;
                for (int i = 0; i < s->nin; i++)
                    fprintf(f, "%s%d", i ? " " : "  ", e[i]);
                fputc(' ', f);
                put_num(f, ot->coef[t]);
                fputs("  # ", f);
                poly_format_monomial(f, s, e, NULL);
                fputc('\n', f);
            }
        }
    }
    fputs("end\n", f);
    return ferror(f) ? -1 : 0;
}
