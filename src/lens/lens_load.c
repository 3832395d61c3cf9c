/* lens_load: picks the reader by the format asked for, else by file extension, else by
 * content (always by content on stdin, which has no name). Readers for more formats are
 * one row each in `readers`. */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "sparselens/data_path.h"
#include "sparselens/input_file.h"
#include "sparselens/import_design.h"
#include "sparselens/import_table.h"
#include "lens/import_common.h"
#include "sparselens/lens.h"

/* Every reader: parse f (named path in messages) into a lens that lens_finish accepted. */
typedef int (*lens_reader)(FILE *f, const char *path, const lens_load_options *opt,
                           lens_t *lens, lens_err *err);

static const struct {
    const char *name; /* for --lens-format and lens->format */
    const char *ext;
    lens_reader read;
} readers[] = {
    {"lens", ".lens", lens_read_native},
    {"fx", ".fx", lens_read_fx},
    {"pbrt", ".dat", lens_read_pbrt},
    {"zmx", ".zmx", lens_read_zmx},
    {"seq", ".seq", lens_read_seq},
};
#define NREADERS (sizeof readers / sizeof *readers)

const char *const lens_formats = "lens, fx, pbrt, zmx, seq";

int lens_format_known(const char *name)
{
    if (!name || strcasecmp(name, "auto") == 0)
        return 1;
    for (size_t i = 0; i < NREADERS; i++)
        if (strcasecmp(name, readers[i].name) == 0)
            return 1;
    return 0;
}

static int has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext);
    return n >= m && strcasecmp(path + n - m, ext) == 0;
}

/* One line of text, lower-cased and without leading blanks, into out. */
static const char *next_line(const char *p, const char *end, char *out, size_t cap)
{
    while (p < end && isspace((unsigned char)*p))
        p++;
    size_t n = 0;
    while (p < end && *p != '\n' && *p != '\r') {
        if (n + 1 < cap)
            out[n++] = (char)tolower((unsigned char)*p);
        p++;
    }
    out[n] = '\0';
    return p;
}

/* sniff's answer for a polynomial system (a .poly), which no reader takes */
#define SNIFF_SYSTEM ((size_t)-1)

/* By content: a "lens-poly" first line is a polynomial system, not a lens; a UTF-16 byte-order mark or a VERS/SURF line means Zemax, an RDM/LEN/SO
 * line CODE V, an "iris" or "abbe" line .fx; rows of exactly four numbers mean pbrt;
 * anything else is read as the native format, whose messages then explain. */
static size_t sniff(const char *data, size_t len)
{
    const unsigned char *u = (const unsigned char *)data;
    if (len >= 2 && ((u[0] == 0xFF && u[1] == 0xFE) || (u[0] == 0xFE && u[1] == 0xFF)))
        return 3;
    int numeric4 = 0, other = 0;
    char line[1024];
    for (const char *p = data, *end = data + len; p < end;) {
        p = next_line(p, end, line, sizeof line);
        if (!line[0] || line[0] == '#')
            continue;
        if (!strncmp(line, "lens-poly", 9) && (!line[9] || line[9] == ' ' || line[9] == '\t'))
            return SNIFF_SYSTEM;
        if (strstr(line, "iris") || strstr(line, "abbe"))
            return 1;
        if (!strncmp(line, "vers ", 5) || !strncmp(line, "surf ", 5))
            return 3;
        if (!strncmp(line, "rdm", 3) || !strncmp(line, "len", 3) || !strncmp(line, "so ", 3))
            return 4;
        double a, b, c, d;
        char extra;
        if (sscanf(line, "%lf %lf %lf %lf %c", &a, &b, &c, &d, &extra) == 4)
            numeric4++;
        else
            other++;
    }
    return numeric4 > 0 && other == 0 ? 2 : 0;
}

/* Reads the whole of path ("-": stdin) into memory, picks the reader (by format, else by
 * content) and runs it on the buffer. */
static int load_by_content(const char *path, int is_stdin, const char *format,
                           const lens_load_options *opt, lens_t *lens, lens_err *err)
{
    char *data;
    size_t len;
    if ((is_stdin ? import_read_stream(stdin, path, &data, &len, err)
                  : import_read_file(path, &data, &len, err)) != 0)
        return -1;
    size_t k = 0;
    if (format) {
        while (strcasecmp(format, readers[k].name) != 0)
            k++;
    } else {
        k = sniff(data, len);
    }
    if (k == SNIFF_SYSTEM) {
        free(data);
        lens_errf(err, path, 0, "a polynomial system (man 5 lens-poly), not a lens: lens-spot "
                  "and lens-distort show it, with the lens it records");
        return -1;
    }
    /* fmemopen refuses an empty buffer: an empty input is read from /dev/null instead. */
    FILE *f = len ? fmemopen(data, len, "r") : fopen("/dev/null", "r");
    if (!f) {
        free(data);
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    int rc = readers[k].read(f, path, opt, lens, err);
    fclose(f);
    free(data);
    if (rc == 0)
        snprintf(lens->format, sizeof lens->format, "%s", readers[k].name);
    return rc;
}

int lens_find_file(const char *name, char *buf, size_t n)
{
    const char *exts[NREADERS + 1] = {0};
    for (size_t i = 0; i < NREADERS; i++)
        exts[i] = readers[i].ext;
    return data_find("lenses", "SPARSELENS_LENS_PATH", name, exts, buf, n);
}

int lens_load(const char *path, const lens_load_options *opt, lens_t *lens, lens_err *err)
{
    lens_init(lens);
    const char *format = opt && opt->format && strcasecmp(opt->format, "auto") != 0
                             ? opt->format : NULL;
    if (format && !lens_format_known(format)) {
        lens_errf(err, path, 0, "unknown lens format '%s' (%s, or auto)", format, lens_formats);
        return -1;
    }
    int is_stdin = strcmp(path, "-") == 0;
    /* A name that is not a file here is a lens name: ./, $SPARSELENS_LENS_PATH, then
     * the shipped lenses (data_path.h), each with any reader's extension. */
    char found[PATH_MAX + 64];
    if (!is_stdin) {
        if (!path[0]) {
            lens_errf(err, NULL, 0, "an empty lens name");
            return -1;
        }
        if (lens_find_file(path, found, sizeof found) == 0)
            path = found;
        else if (access(path, F_OK) != 0) { /* one too long to copy is taken as it is */
            lens_errf(err, path, 0, "no such lens file, nor a lens of that name in ./, "
                                    "$SPARSELENS_LENS_PATH or the shipped lenses");
            return -1;
        }
    }
    size_t k = NREADERS;
    for (size_t i = 0; i < NREADERS && !is_stdin && !format; i++)
        if (has_ext(path, readers[i].ext))
            k = i;
    if (k == NREADERS)
        return load_by_content(path, is_stdin, format, opt, lens, err);
    FILE *f = input_open(path, err);
    if (!f)
        return -1;
    int rc = readers[k].read(f, path, opt, lens, err);
    fclose(f);
    if (rc == 0)
        snprintf(lens->format, sizeof lens->format, "%s", readers[k].name);
    return rc;
}
