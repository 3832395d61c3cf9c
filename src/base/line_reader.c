/* Bounded line reading in blocks (see line_reader.h). */
#include "base/line_reader.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void line_reader_init(line_reader *r, FILE *f, const char *path, size_t max)
{
    memset(r, 0, sizeof *r);
    r->f = f;
    r->path = path;
    r->max = max;
    /* A pipe or a device is read with read(2), which returns what has arrived: fread
     * would wait for a whole block, and a stream fed row by row would get no answer. */
    struct stat st;
    int fd = fileno(f);
    r->fd = fd >= 0 && fstat(fd, &st) == 0 && !S_ISREG(st.st_mode) ? fd : -1;
}

void line_reader_free(line_reader *r)
{
    free(r->blk);
    r->blk = r->buf = NULL;
    r->cap = r->len = r->pos = r->end = 0;
}

/* Reads more bytes after end: how many, 0 at the end of the input, -1 on an error. */
static long fill(line_reader *r)
{
    size_t want = r->cap - 1 - r->end; /* one byte kept for the NUL */
    if (r->fd >= 0) {
        for (;;) {
            ssize_t n = read(r->fd, r->blk + r->end, want);
            if (n >= 0)
                return (long)n;
            if (errno != EINTR)
                return -1;
        }
    }
    size_t n = fread(r->blk + r->end, 1, want, r->f);
    return n == 0 && ferror(r->f) ? -1 : (long)n;
}

/* Drops a UTF-8 byte-order mark at the start of the first line (editors on some
 * systems write one); a partial mark is kept as text and refused by the reader. */
static void drop_bom(line_reader *r)
{
    if (r->line == 1 && r->len >= 3 && memcmp(r->buf, "\xEF\xBB\xBF", 3) == 0) {
        r->buf += 3;
        r->len -= 3;
    }
}

static int read_error(line_reader *r, long line, lens_err *err)
{
    lens_errf(err, r->path, line, "read error: %s", strerror(errno ? errno : EIO));
    return LINE_FAIL;
}

/* Moves the unread bytes to the start of the block and reads more: 1, or 0 at the end
 * of the input, or LINE_FAIL. */
static int refill(line_reader *r, lens_err *err)
{
    if (!r->blk) {
        r->cap = r->max + 8 + LINE_BLOCK_BYTES;
        if (!(r->blk = malloc(r->cap))) {
            lens_errf(err, r->path, r->line + 1, "out of memory");
            return LINE_FAIL;
        }
    }
    if (r->eof)
        return 0;
    memmove(r->blk, r->blk + r->pos, r->end - r->pos);
    r->end -= r->pos;
    r->pos = 0;
    errno = 0;
    long n = fill(r);
    if (n < 0)
        return read_error(r, r->end > 0 || r->skip_rest ? r->line + !r->skip_rest : 0, err);
    r->end += (size_t)n;
    r->eof = n == 0;
    return n > 0;
}

/* The rest of a line refused as too long, up to its end (a stream may go on). */
static int skip_rest(line_reader *r, lens_err *err)
{
    while (r->skip_rest) {
        char *q = memchr(r->blk + r->pos, '\n', r->end - r->pos);
        if (q) {
            r->pos = (size_t)(q - r->blk) + 1;
            r->skip_rest = 0;
            break;
        }
        r->pos = r->end;
        int st = refill(r, err);
        if (st < 0)
            return st;
        if (st == 0)
            r->skip_rest = 0;
    }
    return LINE_OK;
}

int line_next(line_reader *r, lens_err *err)
{
    r->len = 0;
    if (r->skip_rest && skip_rest(r, err) < 0)
        return LINE_FAIL;
    /* A BOM may take 3 bytes past max on line 1: it is dropped afterwards. */
    const size_t limit = r->max + (r->line == 0 ? 3 : 0);
    char *q = NULL;
    for (;;) {
        if (r->blk && (q = memchr(r->blk + r->pos, '\n', r->end - r->pos)))
            break;
        if (r->blk && r->end - r->pos > limit) {
            /* Said now, from the bytes that are in: the line may never end. */
            r->line++;
            r->skip_rest = 1;
            r->pos = r->end;
            lens_errf(err, r->path, r->line, "line longer than %zu bytes", r->max);
            return LINE_BAD;
        }
        int st = refill(r, err);
        if (st < 0)
            return st;
        if (st == 0)
            break;
    }
    if (!q && r->pos == r->end)
        return LINE_END;
    size_t at = r->pos, stop = q ? (size_t)(q - r->blk) : r->end;
    r->pos = q ? stop + 1 : stop;
    r->line++;
    r->buf = r->blk + at;
    r->len = stop - at;
    r->buf[r->len] = '\0'; /* the '\n', or the byte kept after the block */
    const char *nul = memchr(r->buf, '\0', r->len);
    if (r->len && r->buf[r->len - 1] == '\r')
        r->buf[--r->len] = '\0';
    drop_bom(r);
    if (stop - at > limit || r->len > r->max) {
        lens_errf(err, r->path, r->line, "line longer than %zu bytes", r->max);
        return LINE_BAD;
    }
    if (nul) {
        lens_errf(err, r->path, r->line, "NUL byte at column %ld (not a text file?)",
                  (long)(nul - (r->blk + at)) + 1);
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
