/* Text or JSON tables (see table_out.h). */
#include "sparselens/table_out.h"

#include "sparselens/escape.h"

#include <math.h>
#include <string.h>

/* Round-off about zero: differences of values of size `scale` that cancel leave a few
 * units in the last place of that size; 1e-12 of it is far below any figure printed. */
#define ROUNDOFF 1e-12

void table_out_format(char *buf, size_t len, double v, double scale, int digits)
{
    if (isnan(v)) {
        snprintf(buf, len, "nan");
        return;
    }
    if (isinf(v)) {
        snprintf(buf, len, v > 0 ? "inf" : "-inf");
        return;
    }
    if (v == 0 || (isfinite(scale) && fabs(v) <= ROUNDOFF * fabs(scale)))
        v = 0;
    snprintf(buf, len, "%.*g", digits, v);
    if (strcmp(buf, "-0") == 0)
        snprintf(buf, len, "0");
}

void table_out_begin(table_out *t, FILE *f, int json, int precision, int default_precision)
{
    memset(t, 0, sizeof *t);
    t->f = f, t->json = json;
    t->precision = precision > 0 ? precision : default_precision;
    t->user_precision = precision > 0;
    if (json)
        fputc('{', f);
}

static void close_table(table_out *t)
{
    if (!t->in_table)
        return;
    if (t->json && !t->flat)
        fputs(t->as_object ? "}" : "\n]", t->f);
    t->in_table = 0;
}

static void start(table_out *t, const char *name, const char *note)
{
    close_table(t);
    t->flat = name == NULL;
    if (t->json && t->flat) {
        t->nrows = t->ntables; /* the pairs join the top object: a comma before the next */
        t->ntables++, t->ncells = 0, t->in_table = 1;
        return;
    }
    if (t->json) {
        fprintf(t->f, "%s\n", t->ntables ? "," : "");
        text_json(t->f, name);
        fputs(t->as_object ? ": {" : ": [", t->f);
    } else if (t->flat) {
        if (t->ntables)
            fputc('\n', t->f);
        t->ntables++, t->nrows = 0, t->ncells = 0, t->in_table = 1;
        return;
    } else {
        if (t->ntables)
            fputc('\n', t->f);
        for (const char *p = note; p && *p;) {
            size_t n = strcspn(p, "\n");
            fputs("# ", t->f);
            text_line_n(t->f, p, n);
            fputc('\n', t->f);
            p += n + (p[n] == '\n');
        }
        if (t->ntables) /* the first table is the command's main one: "# columns:" first */
        {
            fputs("# table: ", t->f);
            text_line(t->f, name);
            fputc('\n', t->f);
        }
    }
    t->ntables++, t->nrows = 0, t->ncells = 0, t->in_table = 1;
}

void table_out_table(table_out *t, const char *name, const char *note, const char *const *columns,
                     int ncolumns)
{
    close_table(t);
    t->as_object = 0;
    start(t, name, note);
    t->columns = columns, t->ncolumns = ncolumns;
    if (!t->json) {
        fputs("# columns:", t->f);
        for (int i = 0; i < ncolumns; i++)
        {
            fputc(' ', t->f);
            text_line(t->f, columns[i]);
        }
        fputc('\n', t->f);
    }
}

void table_out_keys(table_out *t, const char *name, const char *note)
{
    static const char *const kv[] = {"key", "value"};
    close_table(t);
    t->as_object = 1;
    start(t, name, note);
    t->columns = kv, t->ncolumns = 2;
    if (!t->json && name)
        fputs("# columns: key value\n", t->f);
}

/* Before a cell: the separator, and in JSON the column's name (or, for key-value
 * tables, nothing: the key cell is the name). */
static void cell(table_out *t)
{
    if (!t->json) {
        if (t->ncells)
            fputc(' ', t->f);
        return;
    }
    if (t->as_object) {
        if (t->ncells == 0)
            fputs(t->nrows ? ",\n " : "\n ", t->f);
        else
            fputs(": ", t->f);
        return;
    }
    fputs(t->ncells == 0 ? (t->nrows ? ",\n {" : "\n {") : ", ", t->f);
    text_json(t->f, t->ncells < t->ncolumns ? t->columns[t->ncells] : "extra");
    fputs(": ", t->f);
}

void table_out_str(table_out *t, const char *s)
{
    cell(t);
    if (t->json)
        text_json(t->f, s);
    else
        text_line(t->f, s); /* a name from an input file never forges a line */
    t->ncells++;
}

static void number_text(table_out *t, const char *text, double v)
{
    cell(t);
    if (t->json && !isfinite(v))
        fputs("null", t->f);
    else
        fputs(text, t->f);
    t->ncells++;
}

void table_out_num(table_out *t, double v, double scale)
{
    char buf[64];
    table_out_format(buf, sizeof buf, v, scale, t->precision);
    number_text(t, buf, v);
}

void table_out_fmt(table_out *t, double v, double scale, const char *fmt)
{
    if (t->user_precision) {
        table_out_num(t, v, scale);
        return;
    }
    char buf[64];
    table_out_format(buf, sizeof buf, v, scale, 1); /* nan, inf, round-off to 0 */
    if (isfinite(v) && strcmp(buf, "0") != 0)
        snprintf(buf, sizeof buf, fmt, v);
    else if (isfinite(v))
        snprintf(buf, sizeof buf, fmt, 0.0);
    number_text(t, buf, v);
}

void table_out_int(table_out *t, long long v)
{
    char buf[32];
    snprintf(buf, sizeof buf, "%lld", v);
    number_text(t, buf, 0);
}

void table_out_unit(table_out *t, const char *unit)
{
    if (t->json)
        return;
    fprintf(t->f, " %s", unit);
}

void table_out_row_end(table_out *t)
{
    if (!t->json)
        fputc('\n', t->f);
    else if (!t->as_object)
        fputc('}', t->f);
    else if (t->ncells % 2) /* a key without its value */
        fputs(": null", t->f);
    t->nrows++;
    t->ncells = 0;
}

void table_out_end(table_out *t, const char *const *warnings, int nwarnings)
{
    close_table(t);
    if (!t->json)
        return;
    fprintf(t->f, "%s\n\"warnings\": [", t->ntables ? "," : "");
    for (int i = 0; i < nwarnings; i++) {
        fputs(i ? ", " : "", t->f);
        text_json(t->f, warnings[i]);
    }
    fputs("]\n}\n", t->f);
}

void table_out_key_str(table_out *t, const char *key, const char *value)
{
    table_out_str(t, key);
    table_out_str(t, value);
    table_out_row_end(t);
}

void table_out_key_num(table_out *t, const char *key, double v)
{
    table_out_str(t, key);
    table_out_num(t, v, 0);
    table_out_row_end(t);
}

void table_out_key_int(table_out *t, const char *key, long long v)
{
    table_out_str(t, key);
    table_out_int(t, v);
    table_out_row_end(t);
}
