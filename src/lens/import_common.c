/* Shared machinery of the prescription and catalog importers (see import_common.h). */
#include "base/line_reader.h"
#include "lens/import_common.h"

#include "sparselens/numparse.h"
#include "sparselens/input_file.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define IMPORT_MAX_FILE (64L << 20)

/* One code point as UTF-8; unpaired surrogates become '?', so a damaged file stays text. */
static size_t put_utf8(unsigned long c, char *o)
{
    if (c < 0x80) {
        o[0] = (char)c;
        return 1;
    }
    if (c < 0x800) {
        o[0] = (char)(0xC0 | (c >> 6));
        o[1] = (char)(0x80 | (c & 0x3F));
        return 2;
    }
    if (c >= 0xD800 && c < 0xE000) {
        o[0] = '?';
        return 1;
    }
    if (c < 0x10000) {
        o[0] = (char)(0xE0 | (c >> 12));
        o[1] = (char)(0x80 | ((c >> 6) & 0x3F));
        o[2] = (char)(0x80 | (c & 0x3F));
        return 3;
    }
    o[0] = (char)(0xF0 | (c >> 18));
    o[1] = (char)(0x80 | ((c >> 12) & 0x3F));
    o[2] = (char)(0x80 | ((c >> 6) & 0x3F));
    o[3] = (char)(0x80 | (c & 0x3F));
    return 4;
}

static char *decode_utf16(const unsigned char *d, size_t len, int big_endian, size_t *out_len)
{
    size_t nunits = len / 2;
    /* Each code unit becomes at most 3 bytes (a surrogate pair, 2 units, 4 bytes). */
    char *out = malloc(nunits * 3 + 1);
    if (!out)
        return NULL;
    size_t o = 0;
    for (size_t i = 0; i < nunits; i++) {
        unsigned long u = big_endian ? (unsigned long)d[2 * i] << 8 | d[2 * i + 1]
                                     : (unsigned long)d[2 * i + 1] << 8 | d[2 * i];
        if (u >= 0xD800 && u < 0xDC00 && i + 1 < nunits) {
            unsigned long v = big_endian ? (unsigned long)d[2 * i + 2] << 8 | d[2 * i + 3]
                                         : (unsigned long)d[2 * i + 3] << 8 | d[2 * i + 2];
            if (v >= 0xDC00 && v < 0xE000) {
                u = 0x10000 + ((u - 0xD800) << 10) + (v - 0xDC00);
                i++;
            }
        }
        o += put_utf8(u, out + o);
    }
    out[o] = '\0';
    *out_len = o;
    return out;
}

char *import_decode(const char *data, size_t len, size_t *out_len)
{
    const unsigned char *d = (const unsigned char *)data;
    if (len >= 2 && d[0] == 0xFF && d[1] == 0xFE)
        return decode_utf16(d + 2, len - 2, 0, out_len);
    if (len >= 2 && d[0] == 0xFE && d[1] == 0xFF)
        return decode_utf16(d + 2, len - 2, 1, out_len);
    /* UTF-16 LE without a BOM: ASCII text with every second byte zero. */
    if (len >= 4 && d[0] != 0 && d[1] == 0 && d[2] != 0 && d[3] == 0)
        return decode_utf16(d, len, 0, out_len);
    size_t skip = (len >= 3 && d[0] == 0xEF && d[1] == 0xBB && d[2] == 0xBF) ? 3 : 0;
    char *out = malloc(len - skip + 1);
    if (!out)
        return NULL;
    memcpy(out, d + skip, len - skip);
    out[len - skip] = '\0';
    *out_len = len - skip;
    return out;
}

int import_read_stream(FILE *f, const char *path, char **data, size_t *len, lens_err *err)
{
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        if (n == cap) {
            if ((long)cap >= IMPORT_MAX_FILE) {
                free(buf);
                lens_errf(err, path, 0, "larger than %ld MB: not a prescription or catalog",
                          IMPORT_MAX_FILE >> 20);
                return -1;
            }
            char *nb = realloc(buf, cap * 2);
            if (!nb) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0)
            break;
    }
    if (!buf) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    if (ferror(f)) {
        free(buf);
        lens_errf(err, path, 0, "read error");
        return -1;
    }
    *data = buf;
    *len = n;
    return 0;
}

int import_read_file(const char *path, char **data, size_t *len, lens_err *err)
{
    FILE *f = input_open(path, err);
    if (!f)
        return -1;
    int rc = import_read_stream(f, path, data, len, err);
    fclose(f);
    return rc;
}

int import_check_lines(const char *text, size_t len, const char *path, lens_err *err)
{
    const char *p = text, *end = text + len;
    for (long line = 1;; line++) {
        const char *e = p;
        while (e < end && *e != '\r' && *e != '\n')
            e++;
        if (line_check(p, (size_t)(e - p), LINE_MAX_BYTES, path, line, err) != LINE_OK)
            return -1;
        if (e == end)
            return 0;
        p = e + ((e[0] == '\r' && e + 1 < end && e[1] == '\n') ? 2 : 1);
    }
}

int import_read_parse(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                      lens_err *err, import_parser parse)
{
    char *data;
    size_t len;
    lens_init(lens);
    if (import_read_stream(f, path, &data, &len, err) != 0)
        return -1;
    int rc = parse(data, len, path, opt, lens, err);
    free(data);
    return rc;
}

void *import_push(void **array, size_t *cap, size_t *n, size_t size, const char *path,
                  long line, lens_err *err)
{
    if (*n == *cap) {
        size_t nc = *cap ? 2 * *cap : 16;
        void *a = realloc(*array, nc * size);
        if (!a) {
            lens_errf(err, path, line, "out of memory");
            return NULL;
        }
        *array = a;
        *cap = nc;
    }
    char *item = (char *)*array + (*n)++ * size;
    memset(item, 0, size);
    return item;
}

int import_any_nonzero(char **tok, int n, int from)
{
    for (int i = from; i < n; i++) {
        double v;
        if (parse_double(tok[i], &v) == 0 && v != 0)
            return 1;
    }
    return 0;
}

int import_numbers(char **tok, int n, double *dst, int *count, int max)
{
    int left = 0;
    double v;
    for (int i = 1; i < n; i++) {
        if (*count < max && parse_double(tok[i], &dst[*count]) == 0)
            (*count)++;
        else if (*count == max && parse_double(tok[i], &v) == 0 && v != 0)
            left++;
    }
    return left;
}

char *import_next_line(import_lines *it)
{
    if (!it->p || !*it->p)
        return NULL;
    char *start = it->p, *e = start;
    while (*e && *e != '\n' && *e != '\r')
        e++;
    if (*e == '\r' && e[1] == '\n')
        *e++ = '\0';
    if (*e) {
        *e = '\0';
        it->p = e + 1;
    } else {
        it->p = e;
    }
    it->line++;
    return start;
}

int import_tokens(char *line, char **tok, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        while (*p && isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        char *start;
        if (*p == '"' || *p == '\'') {
            char q = *p++;
            start = p;
            while (*p && *p != q)
                p++;
        } else {
            start = p;
            while (*p && !isspace((unsigned char)*p))
                p++;
        }
        if (*p)
            *p++ = '\0';
        if (n < max)
            tok[n] = start;
        n++;
    }
    return n;
}

int import_eq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (toupper((unsigned char)*a) != toupper((unsigned char)*b))
            return 0;
    return *a == *b;
}

int import_eq_any(const char *a, const char *const *words)
{
    for (; *words; words++)
        if (import_eq(a, *words))
            return 1;
    return 0;
}

const char *import_rest_after(const char *line, const char *keyword)
{
    const char *p = line + strspn(line, " \t");
    size_t k = strlen(keyword);
    if (strncasecmp(p, keyword, k) != 0 || (p[k] && p[k] != ' ' && p[k] != '\t'))
        return NULL;
    p += k;
    return p + strspn(p, " \t");
}

int import_copy_name(char *dst, size_t cap, const char *name, const char *what,
                     const char *path, long line, lens_err *err)
{
    size_t n = strlen(name);
    if (n < cap) {
        memcpy(dst, name, n + 1);
        return 0;
    }
    lens_errf(err, path, line, "%s '%.20s...' is longer than %zu characters", what, name,
              cap - 1);
    return -1;
}

void import_set_name(lens_t *lens, const char *name)
{
    size_t n = strlen(name), room = sizeof lens->name - 1;
    if (n <= room) {
        memcpy(lens->name, name, n + 1);
        return;
    }
    snprintf(lens->name, sizeof lens->name, "%.*s...", (int)(room - 3), name);
    lens_add_note(lens, "name shortened from %zu characters", n);
}

void import_skip_word(import_skips *sk, const char *what, const char *word)
{
    char label[IMPORT_SKIP_LABEL];
    snprintf(label, sizeof label, "%s %.40s%s", what, word, strlen(word) > 40 ? "..." : "");
    import_skip(sk, label);
}

void import_skip(import_skips *sk, const char *label)
{
    for (int i = 0; i < sk->n; i++)
        if (strcmp(sk->label[i], label) == 0) {
            sk->count[i]++;
            return;
        }
    if (sk->n < IMPORT_MAX_SKIPS - 1) {
        snprintf(sk->label[sk->n], sizeof sk->label[0], "%s", label);
        sk->count[sk->n++] = 1;
        return;
    }
    /* Out of slots: the last one gathers the rest, so nothing goes unmentioned. */
    if (sk->n == IMPORT_MAX_SKIPS - 1) {
        snprintf(sk->label[sk->n], sizeof sk->label[0], "other features");
        sk->count[sk->n++] = 0;
    }
    sk->count[IMPORT_MAX_SKIPS - 1]++;
}

void import_skips_note(const import_skips *sk, lens_t *lens)
{
    if (sk->n == 0)
        return;
    char buf[sizeof lens->notes];
    size_t o = (size_t)snprintf(buf, sizeof buf, "skipped:");
    for (int i = 0; i < sk->n && o < sizeof buf; i++) {
        int w = sk->count[i] > 1
                    ? snprintf(buf + o, sizeof buf - o, "%s %s (%d)", i ? "," : "", sk->label[i],
                               sk->count[i])
                    : snprintf(buf + o, sizeof buf - o, "%s %s", i ? "," : "", sk->label[i]);
        if (w < 0)
            break;
        o += (size_t)w;
    }
    lens_add_note(lens, "%s", buf);
}

/* Control characters become '?', and blanks at both ends go: what the native format's
 * header lines can carry and read back unchanged. */
static void clean_line(char *s, size_t cap)
{
    for (char *p = s; *p; p++)
        if ((unsigned char)*p < 0x20 || (unsigned char)*p == 0x7F)
            *p = '?';
    char *b = s;
    while (*b == ' ')
        b++;
    size_t n = strlen(b);
    while (n && b[n - 1] == ' ')
        n--;
    memmove(s, b, n);
    s[n] = '\0';
    if (!n && cap > 1) {
        s[0] = '?';
        s[1] = '\0';
    }
}

void import_clean_text(lens_t *lens)
{
    if (lens->name[0])
        clean_line(lens->name, sizeof lens->name);
    clean_line(lens->source, sizeof lens->source);
    char out[sizeof lens->notes], line[sizeof lens->notes];
    size_t o = 0;
    for (const char *p = lens->notes; *p;) {
        size_t n = strcspn(p, "\n");
        memcpy(line, p, n);
        line[n] = '\0';
        clean_line(line, sizeof line);
        int w = snprintf(out + o, sizeof out - o, "%s%s", o ? "\n" : "", line);
        if (w < 0 || (size_t)w >= sizeof out - o)
            break;
        o += (size_t)w;
        p += n;
        if (*p == '\n')
            p++;
    }
    out[o] = '\0';
    memcpy(lens->notes, out, o + 1);
}

