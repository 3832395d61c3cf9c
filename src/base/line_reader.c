/* Bounded line reading (see line_reader.h). */
#include "base/line_reader.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

void line_reader_init(line_reader *r, FILE *f, const char *path, size_t max)
{
    memset(r, 0, sizeof *r);
    r->f = f;
    r->path = path;
    r->max = max;
}

void line_reader_free(line_reader *r)
{
    free(r->buf);
    r->buf = NULL;
    r->cap = r->len = 0;
}

static int keep(line_reader *r, int c)
{
    if (r->len + 2 > r->cap) {
        size_t nc = r->cap ? 2 * r->cap : 256;
        if (nc > r->max + 2)
            nc = r->max + 2;
        char *nb = realloc(r->buf, nc);
        if (!nb)
            return -1;
        r->buf = nb;
        r->cap = nc;
    }
    r->buf[r->len++] = (char)c;
    return 0;
}

/* Drops a UTF-8 byte-order mark at the start of the first line (editors on some
 * systems write one); a partial mark is kept as text and refused by the reader. */
static void drop_bom(line_reader *r)
{
    if (r->line == 1 && r->len >= 3 && memcmp(r->buf, "\xEF\xBB\xBF", 3) == 0) {
        memmove(r->buf, r->buf + 3, r->len - 3 + 1); /* with its NUL */
        r->len -= 3;
    }
}

int line_next(line_reader *r, lens_err *err)
{
    r->len = 0;
    int c, any = 0, too_long = 0;
    long nul_at = 0;
    flockfile(r->f);
    while ((c = getc_unlocked(r->f)) != EOF) {
        any = 1;
        if (c == '\n')
            break;
        if (c == '\0' && !nul_at)
            nul_at = (long)r->len + 1;
        if (too_long)
            continue;
        /* A BOM may take 3 bytes past max on line 1: it is dropped afterwards. */
        if (r->len >= r->max + (r->line == 0 ? 3 : 0)) {
            too_long = 1;
            continue;
        }
        if (keep(r, c) != 0) {
            funlockfile(r->f);
            lens_errf(err, r->path, r->line + 1, "out of memory");
            return LINE_FAIL;
        }
    }
    int failed = ferror(r->f);
    funlockfile(r->f);
    if (failed) {
        lens_errf(err, r->path, any ? r->line + 1 : 0, "read error: %s", strerror(errno));
        return LINE_FAIL;
    }
    if (!any)
        return LINE_END;
    r->line++;
    if (r->len && r->buf[r->len - 1] == '\r')
        r->len--;
    if (r->buf)
        r->buf[r->len] = '\0';
    else if (keep(r, '\0') == 0)
        r->len = 0;
    else {
        lens_errf(err, r->path, r->line, "out of memory");
        return LINE_FAIL;
    }
    drop_bom(r);
    if (too_long || r->len > r->max) {
        lens_errf(err, r->path, r->line, "line longer than %zu bytes", r->max);
        return LINE_BAD;
    }
    if (nul_at) {
        lens_errf(err, r->path, r->line, "NUL byte at column %ld (not a text file?)", nul_at);
        return LINE_BAD;
    }
    return LINE_OK;
}

int line_check(const char *s, size_t len, size_t max, const char *path, long line,
               lens_err *err)
{
    if (len > max) {
        lens_errf(err, path, line, "line longer than %zu bytes", max);
        return LINE_BAD;
    }
    const char *nul = memchr(s, '\0', len);
    if (nul) {
        lens_errf(err, path, line, "NUL byte at column %ld (not a text file?)", (long)(nul - s) + 1);
        return LINE_BAD;
    }
    return LINE_OK;
}
