/* The .poly text format (man 5 lens-poly). Coefficients, scalings and ranges are
 * written with 17 significant digits, which reads back to the same double, so a
 * re-read system evaluates bit-identically (poly_impl.h says why the evaluation order
 * does not depend on anything but the file's contents). */
#include "poly/poly_impl.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define POLY_FORMAT_VERSION 1

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

void poly_format_monomial(FILE *f, const poly_system *s, const int *e)
{
    int any = 0;
    for (int i = 0; i < s->nin; i++) {
        if (!e[i])
            continue;
        fprintf(f, "%s%s", any ? "*" : "", s->inputs[i]);
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
                poly_format_monomial(f, s, e);
                fputc('\n', f);
            }
        }
    }
    fputs("end\n", f);
    return ferror(f) ? -1 : 0;
}

/* ---- reading ---- */

typedef struct {
    const char *name;
    long line;
    lens_err *err;
} rd;

#define FAIL(...)                                                                          \
    do {                                                                                   \
        lens_errf(R->err, R->name, R->line, __VA_ARGS__);                                  \
        return -1;                                                                         \
    } while (0)

/* Splits line in place into whitespace tokens, stopping at '#'. */
static int tokenize(char *line, char **tok, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        while (*p && isspace((unsigned char)*p))
            p++;
        if (!*p || *p == '#')
            break;
        if (n == max)
            return max + 1;
        tok[n++] = p;
        while (*p && !isspace((unsigned char)*p))
            p++;
        if (*p)
            *p++ = '\0';
    }
    return n;
}

/* A finite number, or inf / -inf where allow_inf. */
static int num(rd *R, const char *t, const char *what, int allow_inf, double *v)
{
    if (allow_inf && (strcmp(t, "inf") == 0 || strcmp(t, "+inf") == 0)) {
        *v = INFINITY;
        return 0;
    }
    if (allow_inf && strcmp(t, "-inf") == 0) {
        *v = -INFINITY;
        return 0;
    }
    if (parse_double(t, v) != 0)
        FAIL("%s '%s' is not a finite number", what, t);
    return 0;
}

static char *rest_of_line(char *line, const char *key)
{
    char *p = line;
    while (isspace((unsigned char)*p))
        p++;
    p += strlen(key);
    while (isspace((unsigned char)*p))
        p++;
    char *e = p + strlen(p);
    while (e > p && isspace((unsigned char)e[-1]))
        *--e = '\0';
    return p;
}

static int find_name(char *const *names, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], name) == 0)
            return i;
    return -1;
}

typedef struct {
    char *lens;
    char *path;
    int nin, nout;
    char **in, **out;
} header;

static void header_free(header *h)
{
    free(h->lens);
    free(h->path);
    for (int i = 0; i < h->nin; i++)
        free(h->in[i]);
    for (int o = 0; o < h->nout; o++)
        free(h->out[o]);
    free(h->in);
    free(h->out);
}

static int name_list(rd *R, char **tok, int n, const char *what, int *count, char ***names)
{
    if (*names)
        FAIL("'%s' given twice", what);
    if (n < 2)
        FAIL("'%s' names no %s", what, what);
    *names = calloc((size_t)(n - 1), sizeof(char *));
    if (!*names)
        FAIL("out of memory");
    for (int k = 1; k < n; k++) {
        if (find_name(*names, k - 1, tok[k]) >= 0)
            FAIL("%s '%s' is named twice", what, tok[k]);
        (*names)[k - 1] = strdup(tok[k]);
        if (!(*names)[k - 1])
            FAIL("out of memory");
        *count = k;
    }
    return 0;
}

static int read_body(FILE *f, rd *R, poly_system **out)
{
    char *line = NULL;
    size_t cap = 0;
    header h = {0};
    poly_system *s = NULL;
    int rc = -1, have_version = 0, part = -1, ended = 0;
    char **tok = NULL;
    int maxtok = 0;
    int *exps = NULL;
    int *seen = NULL; /* outputs already given in the current part */
    for (;;) {
        errno = 0;
        ssize_t len = getline(&line, &cap, f);
        if (len < 0) {
            if (ferror(f)) {
                lens_errf(R->err, R->name, 0, "read error");
                goto done;
            }
            break;
        }
        R->line++;
        if (memchr(line, '\0', (size_t)len)) {
            lens_errf(R->err, R->name, R->line, "binary data (a NUL byte) in a text file");
            goto done;
        }
        char *copy = strdup(line);
        if (!copy) {
            lens_errf(R->err, R->name, R->line, "out of memory");
            goto done;
        }
        int need = (int)(len / 2) + 2;
        if (need > maxtok) {
            char **nt = realloc(tok, (size_t)need * sizeof *nt);
            if (!nt) {
                free(copy);
                lens_errf(R->err, R->name, R->line, "out of memory");
                goto done;
            }
            tok = nt;
            maxtok = need;
        }
        int n = tokenize(line, tok, maxtok);
        if (n == 0) {
            free(copy);
            continue;
        }
        if (ended) {
            free(copy);
            lens_errf(R->err, R->name, R->line, "text after 'end'");
            goto done;
        }
        const char *k = tok[0];
        int bad = 0;
        if (!have_version) {
            long v;
            if (strcmp(k, "lens-poly") != 0 || n != 2)
                bad = (lens_errf(R->err, R->name, R->line,
                                 "not a polynomial system: expected 'lens-poly %d' first",
                                 POLY_FORMAT_VERSION),
                       1);
            else if (parse_long(tok[1], &v) != 0 || v != POLY_FORMAT_VERSION)
                bad = (lens_errf(R->err, R->name, R->line,
                                 "format version '%s' is not supported (this reads %d)", tok[1],
                                 POLY_FORMAT_VERSION),
                       1);
            have_version = 1;
        } else if (!s && strcmp(k, "lens") == 0) {
            free(h.lens);
            h.lens = strdup(rest_of_line(copy, "lens"));
        } else if (!s && strcmp(k, "lens-path") == 0) {
            free(h.path);
            h.path = strdup(rest_of_line(copy, "lens-path"));
        } else if (!s && strcmp(k, "inputs") == 0) {
            bad = name_list(R, tok, n, "inputs", &h.nin, &h.in) != 0;
        } else if (!s && strcmp(k, "outputs") == 0) {
            bad = name_list(R, tok, n, "outputs", &h.nout, &h.out) != 0;
        } else if (strcmp(k, "lens") == 0 || strcmp(k, "lens-path") == 0 ||
                   strcmp(k, "inputs") == 0 || strcmp(k, "outputs") == 0) {
            bad = (lens_errf(R->err, R->name, R->line, "'%s' must come before scaling, pass, "
                                                        "meta and part lines", k),
                   1);
        } else {
            /* everything else needs the header complete */
            if (!s) {
                if (!h.in || !h.out) {
                    lens_errf(R->err, R->name, R->line, "'%s' before the %s line", k,
                              h.in ? "outputs" : "inputs");
                    free(copy);
                    goto done;
                }
                s = poly_new(h.lens ? h.lens : "", h.nin, (const char *const *)h.in, h.nout,
                             (const char *const *)h.out);
                if (!s) {
                    lens_errf(R->err, R->name, R->line,
                              "bad input or output names (empty, or with '#')");
                    free(copy);
                    goto done;
                }
                if (h.path)
                    poly_set_lens_path(s, h.path);
                exps = calloc((size_t)h.nin, sizeof(int));
                seen = calloc((size_t)h.nout, sizeof(int));
                if (!exps || !seen) {
                    lens_errf(R->err, R->name, R->line, "out of memory");
                    free(copy);
                    goto done;
                }
            }
            if (strcmp(k, "scaling") == 0) {
                double off, sc, lo, hi;
                int i;
                if (n != 6)
                    bad = (lens_errf(R->err, R->name, R->line,
                                     "scaling needs: INPUT OFFSET SCALE DOMAIN-MIN DOMAIN-MAX"),
                           1);
                else if ((i = find_name(h.in, h.nin, tok[1])) < 0)
                    bad = (lens_errf(R->err, R->name, R->line, "unknown input '%s'", tok[1]), 1);
                else if (num(R, tok[2], "offset", 0, &off) || num(R, tok[3], "scale", 0, &sc) ||
                         num(R, tok[4], "domain minimum", 1, &lo) ||
                         num(R, tok[5], "domain maximum", 1, &hi))
                    bad = 1;
                else if (sc == 0)
                    bad = (lens_errf(R->err, R->name, R->line, "scale of '%s' is 0", tok[1]), 1);
                else if (lo > hi)
                    bad = (lens_errf(R->err, R->name, R->line,
                                     "domain of '%s' is empty (min > max)", tok[1]),
                           1);
                else {
                    poly_set_scaling(s, i, off, sc);
                    poly_set_domain(s, i, lo, hi);
                }
            } else if (strcmp(k, "frame") == 0) {
                int fr, o = -1;
                if (n < 2 || n == 3 || (n > 3 && strcmp(tok[2], "except") != 0))
                    bad = (lens_errf(R->err, R->name, R->line,
                                     "frame needs: none|meridional [except OUTPUT...]"),
                           1);
                else if ((fr = poly_frame_parse(tok[1])) < 0)
                    bad = (lens_errf(R->err, R->name, R->line, "unknown frame '%s'", tok[1]), 1);
                else if (fr == POLY_FRAME_NONE && n > 2)
                    bad = (lens_errf(R->err, R->name, R->line, "frame none takes no outputs"), 1);
                else {
                    /* the exceptions first: the pairs left in the frame must be whole */
                    if (fr != POLY_FRAME_NONE && s->ix >= 0 && s->iy >= 0 && s->iu >= 0 &&
                        s->iv >= 0) {
                        s->frame = fr;
                        if (!s->plain)
                            s->plain = calloc((size_t)h.nout, 1);
                        for (int q = 3; q < n && s->plain && !bad; q++)
                            if ((o = find_name(h.out, h.nout, tok[q])) < 0)
                                bad = (lens_errf(R->err, R->name, R->line,
                                                 "unknown output '%s'", tok[q]),
                                       1);
                            else
                                poly_set_output_plain(s, o, 1);
                    }
                    if (!bad && poly_set_frame(s, fr) != 0)
                        bad = (lens_errf(R->err, R->name, R->line,
                                         "frame %s needs inputs x, y, u, v and the outputs in "
                                         "it in pairs (..._x with ..._y, ..._u with ..._v)",
                                         tok[1]),
                               1);
                }
            } else if (strcmp(k, "transform") == 0) {
                int i, xf;
                if (n != 3)
                    bad = (lens_errf(R->err, R->name, R->line,
                                     "transform needs: INPUT identity|inverse-square"),
                           1);
                else if ((i = find_name(h.in, h.nin, tok[1])) < 0)
                    bad = (lens_errf(R->err, R->name, R->line, "unknown input '%s'", tok[1]), 1);
                else if ((xf = poly_xform_parse(tok[2])) < 0)
                    bad = (lens_errf(R->err, R->name, R->line, "unknown transform '%s'", tok[2]), 1);
                else
                    poly_set_transform(s, i, xf);
            } else if (strcmp(k, "pass") == 0) {
                double r;
                int a, b;
                if (n != 4)
                    bad = (lens_errf(R->err, R->name, R->line, "pass needs: OUTPUT OUTPUT RADIUS"),
                           1);
                else if ((a = find_name(h.out, h.nout, tok[1])) < 0 ||
                         (b = find_name(h.out, h.nout, tok[2])) < 0)
                    bad = (lens_errf(R->err, R->name, R->line, "unknown output '%s'",
                                     find_name(h.out, h.nout, tok[1]) < 0 ? tok[1] : tok[2]),
                           1);
                else if (num(R, tok[3], "radius", 0, &r))
                    bad = 1;
                else if (poly_add_pass_circle(s, a, b, r) != 0)
                    bad = (lens_errf(R->err, R->name, R->line, "pass radius must be > 0"), 1);
            } else if (strcmp(k, "meta") == 0) {
                if (n < 2)
                    bad = (lens_errf(R->err, R->name, R->line, "meta needs: KEY VALUE"), 1);
                else {
                    char *v = rest_of_line(copy, "meta");
                    v += strlen(tok[1]);
                    while (isspace((unsigned char)*v))
                        v++;
                    poly_set_meta(s, tok[1], v);
                }
            } else if (strcmp(k, "part") == 0) {
                double a, b;
                if (n != 3)
                    bad = (lens_errf(R->err, R->name, R->line, "part needs: RMIN RMAX"), 1);
                else if (num(R, tok[1], "rmin", 0, &a) || num(R, tok[2], "rmax", 1, &b))
                    bad = 1;
                else if ((part = poly_add_part(s, a, b)) < 0)
                    bad = (lens_errf(R->err, R->name, R->line,
                                     "bad part [%s, %s): needs 0 <= rmin < rmax, no overlap "
                                     "with another part, and inputs x and y unless rmin is 0",
                                     tok[1], tok[2]),
                           1);
                else
                    memset(seen, 0, (size_t)h.nout * sizeof(int));
            } else if (strcmp(k, "output") == 0) {
                int o;
                long nt;
                if (part < 0)
                    bad = (lens_errf(R->err, R->name, R->line, "output before any part line"), 1);
                else if (n != 3)
                    bad = (lens_errf(R->err, R->name, R->line, "output needs: NAME NTERMS"), 1);
                else if ((o = find_name(h.out, h.nout, tok[1])) < 0)
                    bad = (lens_errf(R->err, R->name, R->line, "unknown output '%s'", tok[1]), 1);
                else if (seen[o])
                    bad = (lens_errf(R->err, R->name, R->line,
                                     "output '%s' given twice in this part", tok[1]),
                           1);
                else if (parse_long(tok[2], &nt) != 0 || nt < 0 || nt > 10000000)
                    bad = (lens_errf(R->err, R->name, R->line, "bad term count '%s'", tok[2]), 1);
                else {
                    seen[o] = 1;
                    /* the next nt non-comment lines are its terms */
                    long got = 0;
                    while (!bad && got < nt) {
                        ssize_t l2 = getline(&line, &cap, f);
                        if (l2 < 0) {
                            bad = (lens_errf(R->err, R->name, R->line + 1,
                                             "end of file inside the terms of '%s' (%ld of %ld)",
                                             h.out[o], got, nt),
                                   1);
                            break;
                        }
                        R->line++;
                        if ((size_t)l2 + 2 > (size_t)maxtok * 2) {
                            int nm = (int)(l2 / 2) + 2;
                            char **nt2 = realloc(tok, (size_t)nm * sizeof *nt2);
                            if (!nt2) {
                                bad = (lens_errf(R->err, R->name, R->line, "out of memory"), 1);
                                break;
                            }
                            tok = nt2;
                            maxtok = nm;
                        }
                        int m = tokenize(line, tok, maxtok);
                        if (m == 0)
                            continue;
                        if (m != h.nin + 1) {
                            bad = (lens_errf(R->err, R->name, R->line,
                                             "a term needs %d exponents and a coefficient, "
                                             "found %d fields",
                                             h.nin, m),
                                   1);
                            break;
                        }
                        int deg = 0;
                        for (int i = 0; i < h.nin && !bad; i++) {
                            long e;
                            if (parse_long(tok[i], &e) != 0 || e < 0)
                                bad = (lens_errf(R->err, R->name, R->line,
                                                 "exponent of %s '%s' is not a whole number >= 0",
                                                 h.in[i], tok[i]),
                                       1);
                            else if (e > POLY_MAX_DEGREE || deg + e > POLY_MAX_DEGREE)
                                bad = (lens_errf(R->err, R->name, R->line,
                                                 "degree past the limit of %d", POLY_MAX_DEGREE),
                                       1);
                            else {
                                exps[i] = (int)e;
                                deg += (int)e;
                            }
                        }
                        double c;
                        if (bad)
                            break;
                        if (num(R, tok[h.nin], "coefficient", 0, &c)) {
                            bad = 1;
                            break;
                        }
                        if (poly_add_term(s, part, o, exps, c) != 0) {
                            bad = (lens_errf(R->err, R->name, R->line,
                                             "the same monomial twice in '%s'", h.out[o]),
                                   1);
                            break;
                        }
                        got++;
                    }
                }
            } else if (strcmp(k, "end") == 0) {
                if (n != 1)
                    bad = (lens_errf(R->err, R->name, R->line, "text after 'end'"), 1);
                ended = 1;
            } else {
                bad = (lens_errf(R->err, R->name, R->line, "unknown keyword '%s'", k), 1);
            }
        }
        free(copy);
        if (bad)
            goto done;
    }
    if (!have_version)
        lens_errf(R->err, R->name, 0, "empty file: not a polynomial system");
    else if (!s)
        lens_errf(R->err, R->name, R->line + 1, "end of file before the %s line",
                  !h.in ? "inputs" : !h.out ? "outputs" : "first part");
    else if (!ended)
        lens_errf(R->err, R->name, R->line + 1, "end of file without 'end' (truncated?)");
    else if (s->nparts == 0)
        lens_errf(R->err, R->name, R->line, "no part: a system needs at least one");
    else {
        *out = s;
        s = NULL;
        rc = 0;
    }
done:
    poly_free(s);
    header_free(&h);
    free(line);
    free(tok);
    free(exps);
    free(seen);
    return rc;
}

int poly_read_stream(FILE *f, const char *name, poly_system **sys, lens_err *err)
{
    rd R = {name ? name : "-", 0, err};
    *sys = NULL;
    return read_body(f, &R, sys);
}

int poly_read(const char *path, poly_system **sys, lens_err *err)
{
    *sys = NULL;
    if (strcmp(path, "-") == 0)
        return poly_read_stream(stdin, "-", sys, err);
    FILE *f = fopen(path, "r");
    if (!f) {
        lens_errf(err, path, 0, "%s", strerror(errno));
        return -1;
    }
    int rc = poly_read_stream(f, path, sys, err);
    fclose(f);
    return rc;
}
