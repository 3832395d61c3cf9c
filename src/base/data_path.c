/* Finding shipped files by name (see data_path.h). */
#include "sparselens/data_path.h"

#include <limits.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A lookup takes only regular files: a directory or a FIFO named like a lens (or the
 * directory "DIR/" that an empty name makes) is passed over, never opened. */
static int readable_file(const char *p)
{
    struct stat st;
    return p[0] && stat(p, &st) == 0 && S_ISREG(st.st_mode) && access(p, R_OK) == 0;
}

/* A name given exactly is taken as it is whatever it is (the opener refuses what
 * cannot be read, with a message that says what it is). */
static int exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

/* dir/file (+ ext) into buf if readable; "/x/bin/../lenses/..." reads badly in
 * messages, so shipped paths are normalised. */
static int try_path(const char *dir, const char *file, const char *ext, int normalise, char *buf,
                    size_t n)
{
    char cand[PATH_MAX + 64];
    int len = snprintf(cand, sizeof cand, "%s%s%s%s", dir ? dir : "", dir ? "/" : "", file,
                       ext ? ext : "");
    if (len < 0 || (size_t)len >= sizeof cand || !readable_file(cand))
        return 0;
    char real[PATH_MAX];
    const char *out = normalise && realpath(cand, real) ? real : cand;
    if (strlen(out) >= n)
        return 0;
    memcpy(buf, out, strlen(out) + 1);
    return 1;
}

/* name, then name + each extension, in dir. */
static int try_names(const char *dir, const char *name, const char *const *exts, int normalise,
                     char *buf, size_t n)
{
    if (try_path(dir, name, NULL, normalise, buf, n))
        return 1;
    for (size_t i = 0; exts && exts[i]; i++)
        if (try_path(dir, name, exts[i], normalise, buf, n))
            return 1;
    return 0;
}

static int find_shipped(const char *kind, const char *name, const char *const *exts, char *buf,
                        size_t n)
{
    char exe[PATH_MAX];
    ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (len > 0) {
        exe[len] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash) {
            *slash = '\0';
            static const char *const rel[] = {"/..", "/../share/sparselens", "/../.."};
            for (size_t i = 0; i < sizeof rel / sizeof *rel; i++) {
                char dir[PATH_MAX + 64];
                snprintf(dir, sizeof dir, "%s%s/%s", exe, rel[i], kind);
                if (try_names(dir, name, exts, 1, buf, n))
                    return 0;
            }
        }
    }
#ifdef SPARSELENS_DATADIR
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%s/%s", SPARSELENS_DATADIR, kind);
    if (try_names(dir, name, exts, 1, buf, n))
        return 0;
#endif
    return -1;
}

int data_shipped_file(const char *kind, const char *file, char *buf, size_t n)
{
    return find_shipped(kind, file, NULL, buf, n);
}

int data_find(const char *kind, const char *env, const char *name, const char *const *exts,
              char *buf, size_t n)
{
    /* No name names nothing (not the directories searched). */
    if (!name[0])
        return -1;
    /* what exists is taken as it is, and so is a path anchored to a directory; one
     * that buf cannot hold whole is not copied (-1: the caller keeps the name) */
    if (exists(name) || name[0] == '/' || !strncmp(name, "./", 2) ||
        !strncmp(name, "../", 3)) {
        if (strlen(name) >= n)
            return -1;
        memcpy(buf, name, strlen(name) + 1);
        return 0;
    }
    if (try_names(NULL, name, exts, 0, buf, n)) /* ./NAME.ext */
        return 0;
    const char *list = env ? getenv(env) : NULL;
    while (list && *list) {
        size_t dl = strcspn(list, ":");
        char dir[PATH_MAX];
        if (dl > 0 && dl < sizeof dir) {
            memcpy(dir, list, dl);
            dir[dl] = '\0';
            if (try_names(dir, name, exts, 0, buf, n))
                return 0;
        }
        list += dl + (list[dl] == ':');
    }
    return find_shipped(kind, name, exts, buf, n);
}
