/* Output files that appear complete or not at all (see outfile.h).
 * A regular file (or a name that does not exist yet) is written to PATH.tmp.PID beside
 * it and renamed over it when complete, so a crashed run leaves an obviously stale
 * file rather than a truncated PATH. A symlink is followed: the temporary file goes
 * beside the file it points to, which is replaced, and the link stays a link. Anything
 * else (a FIFO, a character device such as /dev/null) is written in place: renaming
 * over it would replace the device or leave the reader of the FIFO with nothing.
 * Paths are held whole, however long: the system, not a buffer, says what is too long.
 * Pending temporary names are kept in a table that the handlers of the terminating
 * signals, and an exit handler (libgomp exits when it cannot start threads), unlink. */
#include "sparselens/outfile.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define OUTFILE_MAX_PENDING 64
#define OUTFILE_MAX_LINKS 40 /* as the kernel's own limit on a chain of symlinks */

struct outfile {
    FILE *f;
    int is_stdout;
    int in_place; /* written straight into a FIFO or device */
    char *path;   /* as given, for messages */
    char *target; /* the file replaced: path with its symlinks followed */
    char *tmp;
};

/* Handler state: each slot is set (to a complete string) or cleared by one pointer
 * store outside the handlers, which only read it (unlink is async-signal-safe). */
static char *volatile pending[OUTFILE_MAX_PENDING];
static volatile sig_atomic_t handlers_installed;

static void unlink_pending(void)
{
    for (int i = 0; i < OUTFILE_MAX_PENDING; i++) {
        char *p = pending[i];
        if (p)
            unlink(p);
    }
}

static void on_signal(int sig)
{
    unlink_pending();
    signal(sig, SIG_DFL);
    raise(sig);
}

static void install_handlers(void)
{
    if (handlers_installed)
        return;
    handlers_installed = 1;
    /* Every signal whose default action ends the process, except the crashes
     * (SIGSEGV, SIGBUS, ...), which the sanitizers report. */
    static const int sigs[] = {SIGINT,  SIGTERM, SIGHUP,  SIGQUIT, SIGPIPE,   SIGXCPU,
                               SIGXFSZ, SIGALRM, SIGABRT, SIGUSR1, SIGUSR2, SIGVTALRM,
                               SIGPROF};
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++) {
        struct sigaction old;
        /* A signal the caller ignores (a shell's SIGPIPE, SIGQUIT) stays ignored, but
         * INT, TERM and HUP always end the run: a script's background job has SIGINT
         * ignored, and `kill -INT` must still stop it cleanly. */
        if (i >= 3 && sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
            continue;
        sigaction(sigs[i], &sa, NULL);
    }
    atexit(unlink_pending);
}

static int track(const char *tmp)
{
    install_handlers();
    char *copy = strdup(tmp);
    if (!copy)
        return -1;
    for (int i = 0; i < OUTFILE_MAX_PENDING; i++)
        if (!pending[i]) {
            pending[i] = copy;
            return 0;
        }
    free(copy);
    return -1; /* more pending outputs than any command writes at once */
}

static void untrack(const char *tmp)
{
    for (int i = 0; i < OUTFILE_MAX_PENDING; i++) {
        char *p = pending[i];
        if (p && strcmp(p, tmp) == 0) {
            pending[i] = NULL;
            free(p);
            return;
        }
    }
}

/* path with every symlink of its last component followed (a dangling link gives the
 * name it points to, which is then created). NULL with errno set on failure. */
static char *follow_links(const char *path)
{
    char *cur = strdup(path);
    for (int n = 0; cur; n++) {
        struct stat st;
        if (lstat(cur, &st) != 0 || !S_ISLNK(st.st_mode))
            return cur;
        if (n == OUTFILE_MAX_LINKS) {
            free(cur);
            errno = ELOOP;
            return NULL;
        }
        size_t cap = (size_t)st.st_size + 1 > 256 ? (size_t)st.st_size + 1 : 256;
        char *link = malloc(cap);
        ssize_t len = link ? readlink(cur, link, cap) : -1;
        if (len < 0 || (size_t)len >= cap) {
            free(link);
            free(cur);
            if (len >= 0)
                errno = EAGAIN; /* the link changed while it was read */
            return NULL;
        }
        link[len] = '\0';
        char *next;
        const char *slash = strrchr(cur, '/');
        if (link[0] == '/' || !slash) {
            next = link;
        } else { /* relative to the directory holding the link */
            size_t dir = (size_t)(slash - cur) + 1;
            next = malloc(dir + (size_t)len + 1);
            if (next) {
                memcpy(next, cur, dir);
                memcpy(next + dir, link, (size_t)len + 1);
            }
            free(link);
        }
        free(cur);
        cur = next;
    }
    return NULL;
}

/* Where the output goes: *target (caller frees) and whether it is written in place. */
static int resolve(const char *path, char **target, int *in_place, lens_err *err)
{
    *target = follow_links(path);
    if (!*target) {
        lens_errf(err, path, 0, "cannot write: %s", strerror(errno));
        return -1;
    }
    struct stat st;
    *in_place = 0;
    if (stat(*target, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            lens_errf(err, path, 0, "cannot write: is a directory");
            free(*target);
            *target = NULL; /* the callers free it too */
            return -1;
        }
        *in_place = !S_ISREG(st.st_mode);
    }
    return 0;
}

static char *tmp_name(const char *target)
{
    /* Keep the extension last: OpenCV and OpenEXR choose the format by it. */
    const char *slash = strrchr(target, '/');
    const char *dot = strrchr(target, '.');
    if (!dot || (slash && dot < slash) || dot == (slash ? slash + 1 : target))
        dot = target + strlen(target);
    size_t n = strlen(target) + 32;
    char *tmp = malloc(n);
    if (tmp)
        snprintf(tmp, n, "%.*s.tmp.%ld%s", (int)(dot - target), target, (long)getpid(), dot);
    return tmp;
}

int outfile_tmp_path(const char *path, char *tmp, size_t tmplen)
{
    char *target = follow_links(path);
    char *name = target ? tmp_name(target) : NULL;
    free(target);
    if (!name || strlen(name) >= tmplen || track(name) != 0) {
        free(name);
        return -1;
    }
    memcpy(tmp, name, strlen(name) + 1);
    free(name);
    return 0;
}

/* Copies the finished file tmp into target, a FIFO or device that must not be replaced. */
static int copy_into(const char *tmp, const char *target)
{
    int in = open(tmp, O_RDONLY), out = open(target, O_WRONLY | O_TRUNC);
    int rc = in < 0 || out < 0 ? -1 : 0;
    char buf[1 << 16];
    ssize_t got;
    while (rc == 0 && (got = read(in, buf, sizeof buf)) != 0) {
        if (got < 0) {
            rc = errno == EINTR ? 0 : -1;
            continue;
        }
        for (ssize_t off = 0, w; rc == 0 && off < got; off += w > 0 ? w : 0)
            if ((w = write(out, buf + off, (size_t)(got - off))) < 0 && errno != EINTR)
                rc = -1;
    }
    int saved = errno;
    if (in >= 0)
        close(in);
    if (out >= 0 && close(out) != 0 && rc == 0)
        rc = -1;
    else
        errno = saved;
    return rc;
}

int outfile_commit_path(const char *tmp, const char *path, lens_err *err)
{
    char *target = NULL;
    int in_place = 0, rc = resolve(path, &target, &in_place, err);
    if (rc == 0 && (in_place ? copy_into(tmp, target) : rename(tmp, target)) != 0) {
        lens_errf(err, path, 0, "cannot write: %s", strerror(errno));
        rc = -1;
    }
    if (rc != 0 || in_place)
        unlink(tmp);
    untrack(tmp);
    free(target);
    return rc;
}

void outfile_discard_path(const char *tmp)
{
    unlink(tmp);
    untrack(tmp);
}

static void outfile_free(outfile *of)
{
    free(of->path);
    free(of->target);
    free(of->tmp);
    free(of);
}

outfile *outfile_open(const char *path, lens_err *err)
{
    outfile *of = calloc(1, sizeof *of);
    if (!of || !(of->path = strdup(path))) {
        lens_errf(err, path, 0, "out of memory");
        free(of);
        return NULL;
    }
    if (strcmp(path, "-") == 0) {
        of->f = stdout;
        of->is_stdout = 1;
        return of;
    }
    if (resolve(path, &of->target, &of->in_place, err) != 0) {
        outfile_free(of);
        return NULL;
    }
    if (of->in_place) {
        of->f = fopen(of->target, "w");
    } else if ((of->tmp = tmp_name(of->target)) && track(of->tmp) == 0) {
        /* O_EXCL: never write through a name someone else put there */
        int fd = open(of->tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
        of->f = fd >= 0 ? fdopen(fd, "w") : NULL;
        if (!of->f) {
            int saved = errno;
            if (fd >= 0) {
                close(fd);
                unlink(of->tmp);
            }
            untrack(of->tmp);
            errno = saved;
        }
    } else {
        errno = ENOMEM;
    }
    if (!of->f) {
        lens_errf(err, path, 0, "cannot write: %s", strerror(errno));
        outfile_free(of);
        return NULL;
    }
    return of;
}

int outfile_check(const char *path, lens_err *err)
{
    if (strcmp(path, "-") == 0)
        return 0;
    char *target;
    int in_place;
    if (resolve(path, &target, &in_place, err) != 0)
        return -1;
    int rc = 0;
    if (in_place) {
        /* Not opened: a reader of a FIFO would take the close for the end of the data. */
        if (access(target, W_OK) != 0) {
            lens_errf(err, path, 0, "cannot write: %s", strerror(errno));
            rc = -1;
        }
    } else {
        outfile *of = outfile_open(path, err);
        if (!of)
            rc = -1;
        outfile_abort(of);
    }
    free(target);
    return rc;
}

FILE *outfile_stream(outfile *of)
{
    return of->f;
}

int outfile_commit(outfile *of, lens_err *err)
{
    int rc = 0;
    if (of->is_stdout) {
        if (fflush(stdout) != 0 || ferror(stdout)) {
            lens_errf(err, "<stdout>", 0, "write error: %s", strerror(errno));
            diag_stdout_error_reported();
            rc = -1;
        }
        outfile_free(of);
        return rc;
    }
    int bad = ferror(of->f);
    errno = bad ? EIO : 0;
    if (fclose(of->f) != 0 || bad) {
        lens_errf(err, of->path, 0, "write error: %s", strerror(errno));
        if (of->tmp)
            outfile_discard_path(of->tmp);
        outfile_free(of);
        return -1;
    }
    if (!of->in_place) {
        if (rename(of->tmp, of->target) != 0) {
            lens_errf(err, of->path, 0, "cannot write: %s", strerror(errno));
            unlink(of->tmp);
            rc = -1;
        }
        untrack(of->tmp);
    }
    outfile_free(of);
    return rc;
}

void outfile_abort_write_error(outfile *of, int code, lens_err *err)
{
    lens_errf(err, of->is_stdout ? "<stdout>" : of->path, 0, "write error: %s",
              strerror(code ? code : EIO));
    if (of->is_stdout)
        diag_stdout_error_reported();
    outfile_abort(of);
}

void outfile_abort(outfile *of)
{
    if (!of)
        return;
    if (!of->is_stdout) {
        fclose(of->f);
        if (of->tmp)
            outfile_discard_path(of->tmp);
    }
    outfile_free(of);
}

void outfile_remove(const char *path)
{
    struct stat st;
    if (path && strcmp(path, "-") != 0 && stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
        char *target = follow_links(path); /* the file written, not a link to it */
        unlink(target ? target : path);
        free(target);
    }
}
