/* A generated C file with its header (emit_files.h), through two outfiles committed
 * together: the header first, so that a C file never stands without its header. */
#include "sparselens/emit_files.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/outfile.h"

int emit_header_path(const char *path, char *buf, size_t len)
{
    size_t n = strlen(path);
    int dot_c = n > 2 && strcmp(path + n - 2, ".c") == 0;
    size_t stem = dot_c ? n - 2 : n;
    if (stem + 3 > len)
        return -1;
    memcpy(buf, path, stem);
    memcpy(buf + stem, ".h", 3);
    return 0;
}

/* One file written by fn; 0, or -1 with err and the file discarded. */
static outfile *write_one(const char *path, int (*fn)(FILE *, void *, lens_err *), void *ctx,
                          lens_err *err)
{
    outfile *of = outfile_open(path, err);
    if (!of)
        return NULL;
    err->msg[0] = 0;
    if (fn(outfile_stream(of), ctx, err) != 0 || ferror(outfile_stream(of))) {
        if (err->msg[0])
            outfile_abort(of);
        else
            outfile_abort_write_error(of, errno, err);
        return NULL;
    }
    return of;
}

int emit_c_files(const char *path, int (*body)(FILE *f, void *ctx, lens_err *err),
                 int (*header)(FILE *f, void *ctx, lens_err *err), void *ctx, lens_err *err)
{
    outfile *h = NULL;
    if (strcmp(path, "-") != 0) {
        size_t len = strlen(path) + 3;
        char *hpath = malloc(len);
        if (!hpath) {
            lens_errf(err, path, 0, "out of memory");
            return -1;
        }
        emit_header_path(path, hpath, len);
        if (strcmp(hpath, path) == 0) { /* cannot be: ".h" is added or replaces ".c" */
            free(hpath);
            return -1;
        }
        h = write_one(hpath, header, ctx, err);
        free(hpath);
        if (!h)
            return -1;
    }
    outfile *c = write_one(path, body, ctx, err);
    if (!c) {
        if (h)
            outfile_abort(h);
        return -1;
    }
    if (h && outfile_commit(h, err) != 0) {
        outfile_abort(c);
        return -1;
    }
    return outfile_commit(c, err);
}

typedef struct {
    const poly_system *sys;
    const char *name;
} poly_job;

static int poly_body(FILE *f, void *ctx, lens_err *err)
{
    (void)err;
    const poly_job *j = ctx;
    return poly_emit_c(f, j->sys, j->name);
}

static int poly_header(FILE *f, void *ctx, lens_err *err)
{
    (void)err;
    const poly_job *j = ctx;
    return poly_emit_c_header(f, j->sys, j->name);
}

int emit_poly_c_files(const poly_system *sys, const char *path, const char *name,
                      lens_err *err)
{
    poly_job j = {sys, name};
    return emit_c_files(path, poly_body, poly_header, &j, err);
}
