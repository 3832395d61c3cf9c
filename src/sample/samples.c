/* Streaming reader and writer of sample files (man 5 lens-samples). */
#include "sparselens/samples.h"

#include "base/line_reader.h"
#include "base/numtext.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SAMPLES_MAX_META 32

struct samples_reader {
    FILE *f;
    int owns;
    char path[512];
    long line;     /* current line number */
    long row_line; /* line of the last row returned */
    int ncols;
    char *names[SAMPLES_MAX_COLS];
    /* The field that holds each column: its place in the last '# columns:' line read (a
     * second one, from files joined by cat, may order the same columns otherwise). */
    int col_field[SAMPLES_MAX_COLS];
    long header_line; /* the first '# columns:' line */
    line_reader lr;
    char *buf; /* the current line (lr.buf) */
    /* The fields of the last row: where each starts in buf, and its length. */
    int nfields;
    size_t field_at[SAMPLES_MAX_COLS];
    int field_len[SAMPLES_MAX_COLS];
    /* Columns a filter carries to its output as they are (samples_passthrough): any
     * text, never parsed, nan in vals. */
    unsigned char opaque[SAMPLES_MAX_COLS];
    int npass, pass[SAMPLES_MAX_COLS];
    /* "# key: value" comments before the header (samples_meta) */
    int nmeta;
    char *meta_key[SAMPLES_MAX_META], *meta_value[SAMPLES_MAX_META];
};

/* Keeps a "# key: value" comment (key a word of letters, digits, '-' and '_'); the
 * first of a key wins. Other comments are ignored. */
static void keep_meta(samples_reader *r, const char *s)
{
    size_t k = strspn(s, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_");
    if (k == 0 || s[k] != ':' || r->nmeta == SAMPLES_MAX_META)
        return;
    for (int i = 0; i < r->nmeta; i++)
        if (strlen(r->meta_key[i]) == k && strncmp(r->meta_key[i], s, k) == 0)
            return;
    const char *v = s + k + 1;
    v += strspn(v, " \t");
    size_t n = strlen(v);
    while (n > 0 && (v[n - 1] == ' ' || v[n - 1] == '\t'))
        n--;
    char *key = strndup(s, k), *value = strndup(v, n);
    if (!key || !value) {
        free(key);
        free(value);
        return;
    }
    r->meta_key[r->nmeta] = key;
    r->meta_value[r->nmeta++] = value;
}

const char *samples_meta(const samples_reader *r, const char *key)
{
    for (int i = 0; i < r->nmeta; i++)
        if (strcmp(r->meta_key[i], key) == 0)
            return r->meta_value[i];
    return NULL;
}

static const char *display(const samples_reader *r)
{
    return r->path;
}

/* line_next's codes; r->buf is the line when LINE_OK. */
static int next_line(samples_reader *r, lens_err *err)
{
    int st = line_next(&r->lr, err);
    r->line = r->lr.line;
    r->buf = r->lr.buf;
    return st;
}

static int is_blank(const char *s)
{
    return s[strspn(s, " \t")] == '\0';
}

/* The names of a '# columns:' line into names[] (strdup'ed; the caller frees them):
 * how many, or -1 with err set (none, too many, one twice, out of memory). */
static int parse_names(const samples_reader *r, const char *text, char **names, lens_err *err)
{
    char *copy = strdup(text);
    int n = 0;
    if (!copy)
        goto oom;
    for (char *save, *tok = strtok_r(copy, " \t", &save); tok; tok = strtok_r(NULL, " \t", &save)) {
        if (n == SAMPLES_MAX_COLS) {
            lens_errf(err, display(r), r->line, "more than %d columns", SAMPLES_MAX_COLS);
            goto fail;
        }
        for (int i = 0; i < n; i++)
            if (strcmp(names[i], tok) == 0) {
                lens_errf(err, display(r), r->line, "column '%s' named twice", tok);
                goto fail;
            }
        if (!(names[n] = strdup(tok)))
            goto oom;
        n++;
    }
    free(copy);
    if (n == 0) {
        lens_errf(err, display(r), r->line, "'# columns:' names no columns");
        return -1;
    }
    return n;
oom:
    lens_errf(err, display(r), r->line, "out of memory");
fail:
    free(copy);
    for (int i = 0; i < n; i++)
        free(names[i]);
    return -1;
}

static int parse_header(samples_reader *r, const char *text, lens_err *err)
{
    int n = parse_names(r, text, r->names, err);
    if (n < 0)
        return -1;
    r->ncols = n;
    r->header_line = r->line;
    for (int i = 0; i < n; i++)
        r->col_field[i] = i;
    return 0;
}

/* A '# columns:' line after the rows of a first file (files joined by cat): the same
 * columns in any order switch the fields' order for the rows that follow, so each column
 * keeps its values and its place in the output; other columns are refused, since what
 * was written before could not describe the rows after. */
static int switch_header(samples_reader *r, const char *text, lens_err *err)
{
    char *names[SAMPLES_MAX_COLS];
    int n = parse_names(r, text, names, err);
    if (n < 0)
        return -1;
    int field[SAMPLES_MAX_COLS], rc = 0;
    const char *odd = NULL;
    for (int c = 0; c < r->ncols && !odd; c++) {
        field[c] = -1;
        for (int k = 0; k < n && field[c] < 0; k++)
            if (strcmp(names[k], r->names[c]) == 0)
                field[c] = k;
        if (field[c] < 0)
            odd = r->names[c];
    }
    if (odd || n != r->ncols) {
        if (!odd) /* all the first's columns are there: one is new */
            for (int k = 0; k < n && !odd; k++)
                odd = samples_find(r, names[k]) < 0 ? names[k] : NULL;
        lens_errf(err, display(r), r->line,
                  "a second '# columns:' line %s column '%s' (the first, at line %ld, %s): "
                  "joined sample files must have the same columns",
                  samples_find(r, odd) < 0 ? "adds" : "lacks", odd, r->header_line,
                  samples_find(r, odd) < 0 ? "lacks it" : "has it");
        rc = -1;
    } else {
        memcpy(r->col_field, field, sizeof(int) * (size_t)n);
    }
    for (int k = 0; k < n; k++)
        free(names[k]);
    return rc;
}

/* "columns:" after the '#' of a comment line, or NULL. */
static const char *columns_text(const char *comment)
{
    const char *s = comment + 1;
    s += strspn(s, " \t");
    return strncmp(s, "columns:", 8) == 0 ? s + 8 : NULL;
}

samples_reader *samples_open(const char *path, lens_err *err)
{
    samples_reader *r = calloc(1, sizeof *r);
    if (!r) {
        lens_errf(err, path, 0, "out of memory");
        return NULL;
    }
    if (strcmp(path, "-") == 0) {
        r->f = stdin;
        snprintf(r->path, sizeof r->path, "<stdin>");
    } else {
        r->f = fopen(path, "r");
        r->owns = 1;
        snprintf(r->path, sizeof r->path, "%s", path);
        if (!r->f) {
            lens_errf(err, path, 0, "cannot open: %s", strerror(errno));
            free(r);
            return NULL;
        }
    }
    line_reader_init(&r->lr, r->f, r->path, LINE_MAX_BYTES);
    for (;;) {
        int st = next_line(r, err);
        if (st < 0) {
            samples_close(r);
            return NULL;
        }
        if (st == LINE_END) {
            lens_errf(err, display(r), 0,
                      r->line == 0 ? "empty file: expected a '# columns:' header line"
                                   : "no '# columns:' header line");
            samples_close(r);
            return NULL;
        }
        const char *s = r->buf + strspn(r->buf, " \t");
        if (*s == '#') {
            s++;
            s += strspn(s, " \t");
            if (strncmp(s, "columns:", 8) == 0) {
                if (parse_header(r, s + 8, err) != 0) {
                    samples_close(r);
                    return NULL;
                }
                return r;
            }
            keep_meta(r, s);
            continue;
        }
        if (is_blank(s))
            continue;
        lens_errf(err, display(r), r->line,
                  "data before the '# columns:' header line (sample files name their columns)");
        samples_close(r);
        return NULL;
    }
}

int samples_ncols(const samples_reader *r) { return r->ncols; }
const char *samples_colname(const samples_reader *r, int i) { return r->names[i]; }
long samples_line(const samples_reader *r) { return r->row_line; }
const char *samples_path(const samples_reader *r) { return r->path; }

int samples_find(const samples_reader *r, const char *name)
{
    for (int i = 0; i < r->ncols; i++)
        if (strcmp(r->names[i], name) == 0)
            return i;
    return -1;
}

int samples_map(const samples_reader *r, const char *const *names, int n, int *map, lens_err *err)
{
    for (int i = 0; i < n; i++) {
        map[i] = samples_find(r, names[i]);
        if (map[i] < 0) {
            lens_errf(err, display(r), 0, "no column '%s' (columns are found by name)", names[i]);
            return -1;
        }
    }
    return 0;
}

/* Splits the row in buf into fields (kept in place: buf is not changed). Returns the
 * number of fields, counting those past SAMPLES_MAX_COLS without recording them. */
static int split_fields(samples_reader *r, const char *s)
{
    int k = 0;
    for (s += strspn(s, " \t"); *s; s += strspn(s, " \t"), k++) {
        size_t len = strcspn(s, " \t");
        if (k < SAMPLES_MAX_COLS) {
            r->field_at[k] = (size_t)(s - r->buf);
            r->field_len[k] = len > 1000000 ? 1000000 : (int)len;
        }
        s += len;
    }
    r->nfields = k < SAMPLES_MAX_COLS ? k : SAMPLES_MAX_COLS;
    return k;
}

static int parse_field(const samples_reader *r, int k, double *v)
{
    return numtext_parse(r->buf + r->field_at[k], (size_t)r->field_len[k], v);
}

double samples_field_number(const samples_reader *r, int col)
{
    double v;
    if (col < 0 || col >= r->ncols || r->col_field[col] >= r->nfields ||
        parse_field(r, r->col_field[col], &v) != 0)
        return NAN;
    return v;
}

int samples_next(samples_reader *r, double *vals, lens_err *err)
{
    for (;;) {
        int st = next_line(r, err);
        if (st == LINE_END)
            return 0;
        if (st != LINE_OK) {
            r->row_line = r->line;
            r->nfields = 0; /* pass-through columns of this row: nan */
            for (int i = 0; i < r->ncols; i++)
                vals[i] = NAN;
            return st == LINE_FAIL ? SAMPLES_FAIL : -1;
        }
        char *s = r->buf + strspn(r->buf, " \t");
        if (*s == '#') {
            const char *names = columns_text(s);
            if (names && switch_header(r, names, err) != 0) {
                r->row_line = r->line;
                r->nfields = 0;
                for (int i = 0; i < r->ncols; i++)
                    vals[i] = NAN;
                return SAMPLES_FAIL;
            }
            continue;
        }
        if (*s == '\0')
            continue;
        r->row_line = r->line;
        for (int i = 0; i < r->ncols; i++)
            vals[i] = NAN;
        int k = split_fields(r, s);
        if (k != r->ncols) {
            lens_errf(err, display(r), r->line, "%d fields, expected %d (%s ...)", k, r->ncols,
                      r->names[0]);
            return -1;
        }
        for (int i = 0; i < k; i++) {
            const int f = r->col_field[i];
            if (r->opaque[i])
                continue;
            if (parse_field(r, f, &vals[i]) != 0) {
                for (int j = 0; j < r->ncols; j++)
                    vals[j] = NAN;
                lens_errf(err, display(r), r->line, "field %d ('%.*s') is not a number", f + 1,
                          r->field_len[f] < 40 ? r->field_len[f] : 40, r->buf + r->field_at[f]);
                return -1;
            }
        }
        return 1;
    }
}

int samples_passthrough(samples_reader *r, const char *const *written, int nwritten,
                        lens_err *err)
{
    r->npass = 0;
    for (int i = 0; i < r->ncols; i++) {
        int known = 0;
        for (int j = 0; j < nwritten && !known; j++)
            known = strcmp(r->names[i], written[j]) == 0;
        r->opaque[i] = !known;
        if (!known)
            r->pass[r->npass++] = i;
    }
    /* what a filter writes is a sample file too: one this reader could not read back
     * would end a pipeline at the next command */
    if (nwritten + r->npass > SAMPLES_MAX_COLS) {
        lens_errf(err, display(r), r->line, "the output would have %d columns (%d written and "
                  "%d passed through), more than a sample file holds (%d); drop some input "
                  "columns", nwritten + r->npass, nwritten, r->npass, SAMPLES_MAX_COLS);
        return -1;
    }
    return r->npass;
}

const char *samples_passthrough_name(const samples_reader *r, int k)
{
    return r->names[r->pass[k]];
}

size_t samples_passthrough_text(const samples_reader *r, char *buf, size_t cap)
{
    size_t n = 0;
    for (int k = 0; k < r->npass; k++) {
        int c = r->col_field[r->pass[k]];
        /* a row with too few fields still gets a field in every column */
        const char *tok = c < r->nfields ? r->buf + r->field_at[c] : "nan";
        int len = c < r->nfields ? r->field_len[c] : 3;
        int w = snprintf(n < cap ? buf + n : NULL, n < cap ? cap - n : 0, " %.*s", len, tok);
        n += (size_t)w;
    }
    return n;
}

void samples_write_passthrough(FILE *f, const samples_reader *r)
{
    for (int k = 0; k < r->npass; k++) {
        int c = r->col_field[r->pass[k]];
        if (c < r->nfields)
            fprintf(f, " %.*s", r->field_len[c], r->buf + r->field_at[c]);
        else
            fputs(" nan", f);
    }
}

void samples_close(samples_reader *r)
{
    if (!r)
        return;
    if (r->owns && r->f)
        fclose(r->f);
    for (int i = 0; i < r->ncols; i++)
        free(r->names[i]);
    for (int i = 0; i < r->nmeta; i++) {
        free(r->meta_key[i]);
        free(r->meta_value[i]);
    }
    line_reader_free(&r->lr);
    free(r);
}

static void write_names(FILE *f, const char *const *names, int n)
{
    for (int i = 0; i < n; i++)
        fprintf(f, " %s", names[i]);
}

void samples_write_header(FILE *f, const char *const *names, int n)
{
    fputs("# columns:", f);
    write_names(f, names, n);
    fputc('\n', f);
}

void samples_write_filter_header(FILE *f, const char *const *names, int n, const samples_reader *r)
{
    fputs("# columns:", f);
    write_names(f, names, n);
    for (int k = 0; k < r->npass; k++)
        fprintf(f, " %s", r->names[r->pass[k]]);
    fputc('\n', f);
}

/* Each number the shortest of %.15g/%.17g that reads back to the same double: exact,
 * and readable where the value is short (0.5 rather than 0.50000000000000000);
 * non-finite ones as nan, inf, -inf (numtext_format). */
size_t samples_format_values(char *buf, const double *vals, int n)
{
    size_t k = 0;
    for (int i = 0; i < n; i++) {
        if (i)
            buf[k++] = ' ';
        k += numtext_format(vals[i], buf + k);
    }
    return k;
}

/* One fwrite a row (of up to 64 numbers; a longer row in pieces). */
static void write_values(FILE *f, const double *vals, int n)
{
    char buf[SAMPLES_MAX_COLS * (NUMTEXT_MAX + 1) + 1];
    for (int i = 0; i < n; i += SAMPLES_MAX_COLS) {
        const int m = n - i < SAMPLES_MAX_COLS ? n - i : SAMPLES_MAX_COLS;
        size_t k = i ? 1 : 0;
        buf[0] = ' ';
        k += samples_format_values(buf + k, vals + i, m);
        fwrite(buf, 1, k, f);
    }
}

void samples_write_row(FILE *f, const double *vals, int n)
{
    write_values(f, vals, n);
    fputc('\n', f);
}

void samples_write_filter_row(FILE *f, const double *vals, int n, const samples_reader *r)
{
    write_values(f, vals, n);
    samples_write_passthrough(f, r);
    fputc('\n', f);
}

void samples_write_filter_row_text(FILE *f, const double *vals, int n, const char *passthrough)
{
    write_values(f, vals, n);
    fputs(passthrough, f);
    fputc('\n', f);
}
