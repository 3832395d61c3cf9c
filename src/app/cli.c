#include "sparselens/cli.h"
#include "sparselens/file_fields.h"
#include "sparselens/outfile.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/numparse.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void cli_pair(const char *prog, const opt_spec *spec, const char *s, char sep, double *a,
              double *b)
{
    const char *p = strchr(s, sep);
    if (!p)
        opt_die(prog, spec, "expected A%cB, got '%s'", sep, s);
    char first[64];
    size_t n = (size_t)(p - s);
    if (n >= sizeof first)
        opt_die(prog, spec, "'%s' is too long", s);
    memcpy(first, s, n);
    first[n] = '\0';
    if (parse_double(first, a) != 0 || parse_double(p + 1, b) != 0)
        opt_die(prog, spec, "expected two numbers A%cB, got '%s'", sep, s);
}

void cli_set_size(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    cli_size *s = field;
    cli_pair(prog, spec, value, 'x', &s->w, &s->h);
    if (!(s->w > 0 && s->h > 0))
        opt_die(prog, spec, "sizes must be positive");
}

void cli_load_lens(const char *prog, const char *path, const lens_load_options *opt, lens_t *lens)
{
    lens_err err;
    if (lens_load(path, opt, lens, &err) != 0) {
        diag_print(prog, &err);
        exit(1);
    }
    lens_cli_warn_notes(prog, lens); /* what an importer skipped, one warning line each */
    /* a design file sized by its fields rather than a sensor: the sensor they imply */
    if (lens_sensor_from_fields(lens, &err) < 0) {
        char msg[sizeof err.msg];
        diag_sanitise(msg, sizeof msg, err.msg);
        fprintf(stderr, "%s: warning: %s\n", prog, msg);
    }
}

int cli_progress_wanted(void)
{
    return isatty(STDERR_FILENO);
}

void cli_check_not_input(const char *prog, const char *path, const char *input)
{
    struct stat a, b;
    if (!path || !input || !strcmp(path, "-") || !strcmp(input, "-") || stat(path, &a) != 0 ||
        stat(input, &b) != 0 || a.st_dev != b.st_dev || a.st_ino != b.st_ino || !S_ISREG(a.st_mode))
        return;
    lens_err err;
    lens_errf(&err, path, 0, "is also the input %s: writing there would replace it (-o another "
              "file)", input);
    diag_print(prog, &err);
    exit(1);
}

void cli_check_output(const char *prog, const char *path)
{
    lens_err err;
    if (path && outfile_check(path, &err) != 0) {
        diag_print(prog, &err);
        exit(1);
    }
}

void cli_check_stdout(const char *prog)
{
    int fl = fcntl(STDOUT_FILENO, F_GETFL);
    if (fl != -1 && (fl & O_ACCMODE) == O_RDONLY) {
        fl = -1;
        errno = EBADF;
    }
    if (fl == -1) {
        lens_err err;
        lens_errf(&err, "<stdout>", 0, "cannot write: %s", strerror(errno));
        diag_print(prog, &err);
        diag_stdout_error_reported();
        exit(1);
    }
}

int cli_end_stdout(const char *prog, const char *const *written, int n)
{
    errno = 0;
    if (fflush(stdout) == 0 && !ferror(stdout))
        return 0;
    int code = errno ? errno : EIO;
    /* the table is lost: the pictures of it go too, as any output of a failed run */
    for (int i = 0; i < n; i++)
        outfile_remove(written[i]);
    lens_err err;
    lens_errf(&err, "<stdout>", 0, "write error: %s", strerror(code));
    diag_print(prog, &err);
    diag_stdout_error_reported();
    return 1;
}
