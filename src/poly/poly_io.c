/* The .poly reader (man 5 lens-poly); poly_write.c writes the format. */
#include "poly/poly_impl.h"

#include "base/line_reader.h"
#include "sparselens/numparse.h"
#include "sparselens/input_file.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* One function per keyword. The reader's cost is linear in the file: names and meta
 * keys are found by hashing, terms are added in bulk (planned once at the end), and a
 * part costs memory for what the header declares (at most POLY_MAX_INPUTS inputs,
 * POLY_MAX_OUTPUTS outputs, POLY_MAX_PARTS parts: man 5 lens-poly). */

typedef struct {
    char *lens;
    char *path;
    int nin, nout;
    char **in, **out;
    index_hash in_index, out_index;
} header;

typedef struct {
    const char *name;
    long line;
    lens_err *err;
    line_reader lr;
    char *raw;       /* the current line as read (tokenising cuts the line in place) */
    size_t raw_cap;
    char **tok;      /* its tokens */
    int ntok, maxtok;
    header h;
    poly_system *s;
    int have_version, part, ended; /* have_version: the version read, 0 before it */
    int *exps;       /* one term's exponents */
    int *seen;       /* outputs already given in the current part */
    index_hash meta; /* meta keys given so far */
    long passage_full_line; /* the line of "meta passage full", 0 without one */
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

/* The next line with tokens into R->tok/R->ntok (0 tokens: blank or comment).
 * 1, 0 at the end, -1 on error (err set: too long, a NUL byte, a read error). */
static int next_line(rd *R)
{
    int st = line_next(&R->lr, R->err);
    if (st == LINE_END)
        return 0;
    if (st != LINE_OK)
        return -1;
    R->line = R->lr.line;
    size_t len = R->lr.len;
    if (len + 1 > R->raw_cap) {
        char *nr = realloc(R->raw, len + 1);
        if (!nr)
            FAIL("out of memory");
        R->raw = nr;
        R->raw_cap = len + 1;
    }
    memcpy(R->raw, R->lr.buf, len + 1);
    int need = (int)(len / 2) + 2;
    if (need > R->maxtok) {
        char **nt = realloc(R->tok, (size_t)need * sizeof *nt);
        if (!nt)
            FAIL("out of memory");
        R->tok = nt;
        R->maxtok = need;
    }
    R->ntok = tokenize(R->lr.buf, R->tok, R->maxtok);
    return 1;
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

/* The text after key and the blanks that follow it, end blanks removed, in R->raw. */
static char *rest_of_line(rd *R, const char *key)
{
    char *p = R->raw;
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

struct name_key {
    char *const *names;
    const char *name;
};

static int same_name(const void *ctx, int i)
{
    const struct name_key *k = ctx;
    return strcmp(k->names[i], k->name) == 0;
}

static int find_name(const index_hash *index, char *const *names, const char *name)
{
    struct name_key k = {names, name};
    return index_hash_find(index, index_hash_bytes(name, strlen(name)), same_name, &k);
}

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
    index_hash_free(&h->in_index);
    index_hash_free(&h->out_index);
}

static int name_list(rd *R, const char *what, int limit, int *count, char ***names,
                     index_hash *index)
{
    char **tok = R->tok;
    int n = R->ntok;
    if (*names)
        FAIL("'%s' given twice", what);
    if (n < 2)
        FAIL("'%s' names no %s", what, what);
    if (n - 1 > limit)
        FAIL("%d %s: at most %d", n - 1, what, limit);
    *names = calloc((size_t)(n - 1), sizeof(char *));
    if (!*names)
        FAIL("out of memory");
    for (int k = 1; k < n; k++) {
        if (find_name(index, *names, tok[k]) >= 0)
            FAIL("%s '%s' is named twice", what, tok[k]);
        (*names)[k - 1] = strdup(tok[k]);
        if (!(*names)[k - 1] || index_hash_add(index, index_hash_bytes(tok[k], strlen(tok[k])), k - 1) != 0)
            FAIL("out of memory");
        *count = k;
    }
    return 0;
}

static int key_version(rd *R)
{
    long v;
    if (strcmp(R->tok[0], "lens-poly") != 0 || R->ntok != 2)
        FAIL("not a polynomial system: expected 'lens-poly %d' first", POLY_FORMAT_VERSION);
    if (parse_long(R->tok[1], &v) != 0 || v < 1 || v > POLY_FORMAT_VERSION)
        FAIL("format version '%s' is not supported (this reads 1 to %d)", R->tok[1],
             POLY_FORMAT_VERSION);
    R->have_version = (int)v;
    return 0;
}

/* lens, lens-path, inputs, outputs: 1 when k is one of them (handled or refused). */
static int header_key(rd *R, const char *k, int *bad)
{
    header *h = &R->h;
    char **dst = strcmp(k, "lens") == 0 ? &h->lens : strcmp(k, "lens-path") == 0 ? &h->path : NULL;
    int names = strcmp(k, "inputs") == 0 || strcmp(k, "outputs") == 0;
    if (!dst && !names)
        return 0;
    if (R->s) {
        lens_errf(R->err, R->name, R->line, "'%s' must come before scaling, pass, meta and "
                                            "part lines", k);
        *bad = 1;
    } else if (dst) {
        free(*dst);
        *dst = strdup(rest_of_line(R, k));
        if (!*dst)
            *bad = (lens_errf(R->err, R->name, R->line, "out of memory"), 1);
    } else if (k[0] == 'i') {
        *bad = name_list(R, "inputs", POLY_MAX_INPUTS, &h->nin, &h->in, &h->in_index) != 0;
    } else {
        *bad = name_list(R, "outputs", POLY_MAX_OUTPUTS, &h->nout, &h->out, &h->out_index) != 0;
        if (!*bad && R->have_version == 1 && find_name(&h->out_index, h->out, "out_u") >= 0 &&
            find_name(&h->out_index, h->out, "out_v") >= 0) {
            /* its directions are in a frame no tracer here produces any more: wrong,
             * not merely old */
            lens_errf(R->err, R->name, R->line,
                      "a lens-poly 1 system: its out_u, out_v are in the outer-pupil frame of "
                      "earlier versions, which did not turn with the ray; fit it again");
            *bad = 1;
        }
    }
    return 1;
}

/* The system, once the header is complete (at the first line that needs it). */
static int start_system(rd *R)
{
    header *h = &R->h;
    if (!h->in || !h->out)
        FAIL("'%s' before the %s line", R->tok[0], h->in ? "outputs" : "inputs");
    R->s = poly_new(h->lens ? h->lens : "", h->nin, (const char *const *)h->in, h->nout,
                    (const char *const *)h->out);
    if (!R->s)
        FAIL("bad input or output names (empty, or with '#')");
    poly_bulk_begin(R->s);
    if (h->path)
        poly_set_lens_path(R->s, h->path);
    R->exps = calloc((size_t)h->nin, sizeof(int));
    R->seen = calloc((size_t)h->nout, sizeof(int));
    if (!R->exps || !R->seen)
        FAIL("out of memory");
    return 0;
}

static int input_index(rd *R, const char *name)
{
    int i = find_name(&R->h.in_index, R->h.in, name);
    if (i < 0)
        FAIL("unknown input '%s'", name);
    return i;
}

static int output_index(rd *R, const char *name)
{
    int o = find_name(&R->h.out_index, R->h.out, name);
    if (o < 0)
        FAIL("unknown output '%s'", name);
    return o;
}

static int key_scaling(rd *R)
{
    char **tok = R->tok;
    double off, sc, lo, hi;
    int i;
    if (R->ntok != 6)
        FAIL("scaling needs: INPUT OFFSET SCALE DOMAIN-MIN DOMAIN-MAX");
    if ((i = input_index(R, tok[1])) < 0 || num(R, tok[2], "offset", 0, &off) ||
        num(R, tok[3], "scale", 0, &sc) || num(R, tok[4], "domain minimum", 1, &lo) ||
        num(R, tok[5], "domain maximum", 1, &hi))
        return -1;
    if (sc == 0)
        FAIL("scale of '%s' is 0", tok[1]);
    if (lo > hi)
        FAIL("domain of '%s' is empty (min > max)", tok[1]);
    poly_set_scaling(R->s, i, off, sc);
    poly_set_domain(R->s, i, lo, hi);
    return 0;
}

static int key_frame(rd *R)
{
    char **tok = R->tok;
    int n = R->ntok, fr;
    poly_system *s = R->s;
    if (n < 2 || n == 3 || (n > 3 && strcmp(tok[2], "except") != 0))
        FAIL("frame needs: none|meridional [except OUTPUT...]");
    if ((fr = poly_frame_parse(tok[1])) < 0)
        FAIL("unknown frame '%s'", tok[1]);
    if (fr == POLY_FRAME_NONE && n > 2)
        FAIL("frame none takes no outputs");
    /* the exceptions first: the pairs left in the frame must be whole */
    if (fr != POLY_FRAME_NONE && s->ix >= 0 && s->iy >= 0 && s->iu >= 0 && s->iv >= 0) {
        s->frame = fr;
        if (!s->plain && !(s->plain = calloc((size_t)R->h.nout, 1)))
            FAIL("out of memory");
        for (int q = 3; q < n; q++) {
            int o = output_index(R, tok[q]);
            if (o < 0)
                return -1;
            poly_set_output_plain(s, o, 1);
        }
    }
    if (poly_set_frame(s, fr) != 0)
        FAIL("frame %s needs inputs x, y, u, v and the outputs in it in pairs (..._x with "
             "..._y, ..._u with ..._v)", tok[1]);
    return 0;
}

static int key_transform(rd *R)
{
    int i, xf;
    if (R->ntok != 3)
        FAIL("transform needs: INPUT identity|inverse-square");
    if ((i = input_index(R, R->tok[1])) < 0)
        return -1;
    if ((xf = poly_xform_parse(R->tok[2])) < 0)
        FAIL("unknown transform '%s'", R->tok[2]);
    poly_set_transform(R->s, i, xf);
    return 0;
}

static int key_pass(rd *R)
{
    double r;
    int a, b;
    if (R->ntok != 4)
        FAIL("pass needs: OUTPUT OUTPUT RADIUS");
    if ((a = output_index(R, R->tok[1])) < 0 || (b = output_index(R, R->tok[2])) < 0 ||
        num(R, R->tok[3], "radius", 0, &r))
        return -1;
    if (poly_add_pass_circle(R->s, a, b, r) != 0)
        FAIL("pass radius must be > 0");
    return 0;
}

struct meta_key {
    const poly_system *s;
    const char *key;
};

static int same_meta(const void *ctx, int m)
{
    const struct meta_key *k = ctx;
    return strcmp(poly_meta_key(k->s, m), k->key) == 0;
}

static int key_meta(rd *R)
{
    if (R->ntok < 2)
        FAIL("meta needs: KEY VALUE");
    const char *key = R->tok[1];
    uint64_t h = index_hash_bytes(key, strlen(key));
    struct meta_key k = {R->s, key};
    if (index_hash_find(&R->meta, h, same_meta, &k) >= 0)
        FAIL("meta '%s' given twice", key);
    char *v = rest_of_line(R, "meta");
    v += strlen(key);
    while (isspace((unsigned char)*v))
        v++;
    /* the values the commands act on are checked here, where their line is known */
    double f;
    if (strcmp(key, "fnumber") == 0 && (parse_double(v, &f) != 0 || !(f > 0)))
        FAIL("meta fnumber '%s' is not an f-number > 0", v);
    if (strcmp(key, "passage") == 0 && strcmp(v, "full") == 0)
        R->passage_full_line = R->line;
    if (poly_append_meta(R->s, key, v) != 0 || index_hash_add(&R->meta, h, poly_nmeta(R->s) - 1) != 0)
        FAIL("out of memory");
    return 0;
}

static int key_part(rd *R)
{
    double a, b;
    if (R->ntok != 3)
        FAIL("part needs: RMIN RMAX");
    if (num(R, R->tok[1], "rmin", 0, &a) || num(R, R->tok[2], "rmax", 1, &b))
        return -1;
    if (poly_nparts(R->s) >= POLY_MAX_PARTS)
        FAIL("more than %d parts", POLY_MAX_PARTS);
    /* parts are few (POLY_MAX_PARTS): the overlap test may scan them */
    if ((R->part = poly_add_part(R->s, a, b)) < 0)
        FAIL("bad part [%s, %s): needs 0 <= rmin < rmax, no overlap with another part, and "
             "inputs x and y unless rmin is 0", R->tok[1], R->tok[2]);
    memset(R->seen, 0, (size_t)R->h.nout * sizeof(int));
    return 0;
}

/* One term line (its tokens in R->tok) of output o. */
static int read_term(rd *R, int o)
{
    const header *h = &R->h;
    char **tok = R->tok;
    if (R->ntok != h->nin + 1)
        FAIL("a term needs %d exponents and a coefficient, found %d fields", h->nin, R->ntok);
    int deg = 0;
    for (int i = 0; i < h->nin; i++) {
        long e;
        if (parse_long(tok[i], &e) != 0 || e < 0)
            FAIL("exponent of %s '%s' is not a whole number >= 0", h->in[i], tok[i]);
        if (e > POLY_MAX_DEGREE || deg + e > POLY_MAX_DEGREE)
            FAIL("degree past the limit of %d", POLY_MAX_DEGREE);
        R->exps[i] = (int)e;
        deg += (int)e;
    }
    double c;
    if (num(R, tok[h->nin], "coefficient", 0, &c))
        return -1;
    if (poly_add_term(R->s, R->part, o, R->exps, c) != 0)
        FAIL("the same monomial twice in '%s' (or out of memory)", h->out[o]);
    return 0;
}

static int key_output(rd *R)
{
    int o;
    long nt;
    if (R->part < 0)
        FAIL("output before any part line");
    if (R->ntok != 3)
        FAIL("output needs: NAME NTERMS");
    if ((o = output_index(R, R->tok[1])) < 0)
        return -1;
    if (R->seen[o])
        FAIL("output '%s' given twice in this part", R->tok[1]);
    if (parse_long(R->tok[2], &nt) != 0 || nt < 0 || nt > 10000000)
        FAIL("bad term count '%s'", R->tok[2]);
    R->seen[o] = 1;
    /* the next nt non-comment lines are its terms; memory grows with the terms read,
     * never with the count declared */
    for (long got = 0; got < nt;) {
        int st = next_line(R);
        if (st < 0)
            return -1;
        if (st == 0) {
            lens_errf(R->err, R->name, R->line + 1,
                      "end of file inside the terms of '%s' (%ld of %ld)", R->h.out[o], got, nt);
            return -1;
        }
        if (R->ntok == 0)
            continue;
        if (read_term(R, o) != 0)
            return -1;
        got++;
    }
    return 0;
}

static int key_body(rd *R, const char *k)
{
    static const struct {
        const char *key;
        int (*fn)(rd *R);
    } keys[] = {{"scaling", key_scaling}, {"frame", key_frame}, {"transform", key_transform},
                {"pass", key_pass},       {"meta", key_meta},   {"part", key_part},
                {"output", key_output}};
    if (!R->s && start_system(R) != 0)
        return -1;
    if (strcmp(k, "end") == 0) {
        if (R->ntok != 1)
            FAIL("text after 'end'");
        R->ended = 1;
        return 0;
    }
    for (size_t i = 0; i < sizeof keys / sizeof *keys; i++)
        if (strcmp(k, keys[i].key) == 0)
            return keys[i].fn(R);
    FAIL("unknown keyword '%s'", k);
}

/* What the end of the file says about a file read without error so far. */
static int finish(rd *R, poly_system **out)
{
    if (!R->have_version)
        FAIL("empty file: not a polynomial system");
    R->line++;
    if (!R->s)
        FAIL("end of file before the %s line",
             !R->h.in ? "inputs" : !R->h.out ? "outputs" : "first part");
    if (!R->ended)
        FAIL("end of file without 'end' (truncated?)");
    R->line--;
    if (poly_nparts(R->s) == 0)
        FAIL("no part: a system needs at least one");
    /* a claim of full passage with nothing to stop a ray would pass every ray the lens
     * blocks, and the commands would take it at its word */
    if (R->passage_full_line && poly_npass_circles(R->s) == 0) {
        R->line = R->passage_full_line;
        FAIL("'meta passage full' but no pass circle: a system that models passage has "
             "pass lines (the stop's at least); else 'meta passage partial: REASON'");
    }
    if (poly_bulk_end(R->s) != 0)
        FAIL("out of memory");
    *out = R->s;
    R->s = NULL;
    return 0;
}

static int read_body(FILE *f, rd *R, poly_system **out)
{
    line_reader_init(&R->lr, f, R->name, LINE_MAX_BYTES);
    R->part = -1;
    int rc = -1, st;
    while ((st = next_line(R)) > 0) {
        if (R->ntok == 0)
            continue;
        if (R->ntok > R->maxtok)
            st = (lens_errf(R->err, R->name, R->line, "too many fields"), -1);
        else if (R->ended)
            st = (lens_errf(R->err, R->name, R->line, "text after 'end'"), -1);
        else if (!R->have_version)
            st = key_version(R) == 0 ? 1 : -1;
        else {
            int bad = 0;
            if (!header_key(R, R->tok[0], &bad))
                bad = key_body(R, R->tok[0]) != 0;
            st = bad ? -1 : 1;
        }
        if (st < 0)
            break;
    }
    if (st == 0) {
        if (!R->have_version)
            R->line = 0;
        rc = finish(R, out);
    }
    poly_free(R->s);
    header_free(&R->h);
    line_reader_free(&R->lr);
    index_hash_free(&R->meta);
    free(R->raw);
    free(R->tok);
    free(R->exps);
    free(R->seen);
    return rc;
}

int poly_read_stream(FILE *f, const char *name, poly_system **sys, lens_err *err)
{
    rd R;
    memset(&R, 0, sizeof R);
    R.name = name ? name : "-";
    R.err = err;
    *sys = NULL;
    return read_body(f, &R, sys);
}

int poly_read(const char *path, poly_system **sys, lens_err *err)
{
    *sys = NULL;
    if (strcmp(path, "-") == 0)
        return poly_read_stream(stdin, "-", sys, err);
    FILE *f = input_open(path, err);
    if (!f)
        return -1;
    int rc = poly_read_stream(f, path, sys, err);
    fclose(f);
    return rc;
}
