/* Output files that appear complete or not at all (see outfile.h).
 * The temporary name is PATH.tmp.PID so a crashed run leaves an obviously stale file
 * rather than a truncated PATH. Pending temporary names are kept in a small table
 * that the SIGINT/SIGTERM handler unlinks before re-raising the signal. */
#include "sparselens/outfile.h"

#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define OUTFILE_MAX_PENDING 16

struct outfile {
    FILE *f;
    int is_stdout;
    char path[1024];
    char tmp[1100];
};

/* Signal-handler state: written only outside the handler, with signals installed
 * once; the handler only reads it (unlink is async-signal-safe). */
static char pending[OUTFILE_MAX_PENDING][1100];
static volatile sig_atomic_t handlers_installed;

static void on_signal(int sig)
{
    for (int i = 0; i < OUTFILE_MAX_PENDING; i++)
        if (pending[i][0])
            unlink(pending[i]);
    signal(sig, SIG_DFL);
    raise(sig);
}

static void install_handlers(void)
{
    if (handlers_installed)
        return;
    handlers_installed = 1;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
}

static void track(const char *tmp)
{
    install_handlers();
    for (int i = 0; i < OUTFILE_MAX_PENDING; i++)
        if (!pending[i][0]) {
            snprintf(pending[i], sizeof pending[i], "%s", tmp);
            return;
        }
}

static void untrack(const char *tmp)
{
    for (int i = 0; i < OUTFILE_MAX_PENDING; i++)
        if (strcmp(pending[i], tmp) == 0)
            pending[i][0] = '\0';
}

int outfile_tmp_path(const char *path, char *tmp, size_t tmplen)
{
    /* Keep the extension last: OpenCV and OpenEXR choose the format by it. */
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        dot = path + strlen(path);
    int n = snprintf(tmp, tmplen, "%.*s.tmp.%ld%s", (int)(dot - path), path, (long)getpid(), dot);
    if (n < 0 || (size_t)n >= tmplen)
        return -1;
    track(tmp);
    return 0;
}

int outfile_commit_path(const char *tmp, const char *path, lens_err *err)
{
    if (rename(tmp, path) != 0) {
        lens_errf(err, path, 0, "cannot write: %s", strerror(errno));
        unlink(tmp);
        untrack(tmp);
        return -1;
    }
    untrack(tmp);
    return 0;
}

void outfile_discard_path(const char *tmp)
{
    unlink(tmp);
    untrack(tmp);
}

outfile *outfile_open(const char *path, lens_err *err)
{
    outfile *of = calloc(1, sizeof *of);
    if (!of) {
        lens_errf(err, path, 0, "out of memory");
        return NULL;
    }
    if (strcmp(path, "-") == 0) {
        of->f = stdout;
        of->is_stdout = 1;
        return of;
    }
    snprintf(of->path, sizeof of->path, "%s", path);
    if (outfile_tmp_path(path, of->tmp, sizeof of->tmp) != 0) {
        lens_errf(err, path, 0, "path too long");
        free(of);
        return NULL;
    }
    of->f = fopen(of->tmp, "w");
    if (!of->f) {
        lens_errf(err, path, 0, "cannot write: %s", strerror(errno));
        untrack(of->tmp);
        free(of);
        return NULL;
    }
    return of;
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
            rc = -1;
        }
        free(of);
        return rc;
    }
    int bad = ferror(of->f);
    if (fclose(of->f) != 0 || bad) {
        lens_errf(err, of->path, 0, "write error: %s", strerror(errno));
        unlink(of->tmp);
        untrack(of->tmp);
        free(of);
        return -1;
    }
    rc = outfile_commit_path(of->tmp, of->path, err);
    free(of);
    return rc;
}

void outfile_abort(outfile *of)
{
    if (!of)
        return;
    if (!of->is_stdout) {
        fclose(of->f);
        outfile_discard_path(of->tmp);
    }
    free(of);
}
