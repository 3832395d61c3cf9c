/* Where a system's lens file is (poly.h: poly_find_lens_file). */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "sparselens/poly.h"

/* The base name of path without its extension, into buf. */
static void stem(const char *path, char *buf, size_t len)
{
    const char *base = strrchr(path, '/');
    snprintf(buf, len, "%s", base ? base + 1 : path);
    char *dot = strrchr(buf, '.');
    if (dot && dot != buf)
        *dot = '\0';
}

const char *poly_lens_mismatch(const poly_system *sys, const char *lens_name,
                               const char *lens_path, char *buf, size_t len)
{
    const char *name = poly_lens_name(sys), *path = poly_lens_path(sys);
    char lens_stem[256] = "", sys_stem[256] = "";
    if (lens_path && lens_path[0])
        stem(lens_path, lens_stem, sizeof lens_stem);
    if (path[0])
        stem(path, sys_stem, sizeof sys_stem);
    if (!name[0] || strcmp(name, "unknown") == 0 || strcmp(name, lens_name) == 0 ||
        (lens_stem[0] && strcmp(name, lens_stem) == 0) ||
        (sys_stem[0] && strcmp(sys_stem, lens_stem) == 0))
        return NULL;
    snprintf(buf, len, "the system was fitted to '%.200s'%s%.200s%s, not to this lens '%.200s'",
             name, path[0] ? " (" : "", path, path[0] ? ")" : "", lens_name);
    return buf;
}

static int readable(const char *path)
{
    return access(path, R_OK) == 0;
}

int poly_find_lens_file(const poly_system *sys, const char *poly_path,
                        int (*find)(const char *name, char *buf, size_t n), char *buf,
                        size_t len, lens_err *err)
{
    const char *lp = poly_lens_path(sys), *name = poly_lens_name(sys);
    if (!lp || !*lp) {
        lens_errf(err, poly_path, 0, "the system records no lens file (lens '%s'; systems "
                  "fitted to lens-trace's samples do)", name);
        return -1;
    }
    /* a path buf cannot hold whole is no candidate: never a cut name */
    if (strlen(lp) < len && snprintf(buf, len, "%s", lp) >= 0 && readable(buf))
        return 0;
    /* a relative path may be relative to the .poly file, moved together with it */
    const char *slash = strrchr(poly_path, '/');
    if (lp[0] != '/' && slash) {
        int n = snprintf(buf, len, "%.*s/%s", (int)(slash - poly_path), poly_path, lp);
        if (n >= 0 && (size_t)n < len && readable(buf))
            return 0;
    }
    if (find && find(lp, buf, len) == 0 && readable(buf))
        return 0;
    lens_errf(err, poly_path, 0, "the lens file the system was fitted to (lens '%s', "
              "lens-path %s) is not found", name, lp);
    return -1;
}
