/* lens_load: picks the reader by file extension, then by content. Readers for more
 * formats (Zemax .zmx, .seq) are one row each in `readers`. */
#include <ctype.h>
#include <string.h>
#include <strings.h>

#include "import.h"
#include "lens.h"
#include "lens_import.h"

static const struct {
    const char *ext;
    lens_reader read;
} readers[] = {
    {".lens", lens_read_native},
    {".fx", lens_read_fx},
    {".dat", lens_read_pbrt},
    {".zmx", lens_read_zmx},
    {".seq", lens_read_seq},
};

static int has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext);
    return n >= m && strcasecmp(path + n - m, ext) == 0;
}

/* Unknown extension (or stdin): an "iris" line means .fx; rows of exactly four numbers
 * mean pbrt; a UTF-16 byte-order mark or a VERS/SURF line means Zemax, an RDM/LEN/SO
 * line CODE V; anything else is read as the native format, whose messages then explain. */
static lens_reader sniff(FILE *f)
{
    char line[1024];
    int numeric4 = 0, other = 0;
    lens_reader r = lens_read_native;
    int c0 = getc(f);
    if (c0 == 0xFF || c0 == 0xFE) {
        rewind(f);
        return lens_read_zmx;
    }
    rewind(f);
    while (fgets(line, sizeof line, f)) {
        char *p = line;
        while (isspace((unsigned char)*p))
            p++;
        if (!*p || *p == '#')
            continue;
        for (char *q = p; *q; q++)
            *q = (char)tolower((unsigned char)*q);
        if (strstr(p, "iris") || strstr(p, "abbe")) {
            r = lens_read_fx;
            break;
        }
        if (!strncmp(p, "vers ", 5) || !strncmp(p, "surf ", 5)) {
            r = lens_read_zmx;
            break;
        }
        if (!strncmp(p, "rdm", 3) || !strncmp(p, "len", 3) || !strncmp(p, "so ", 3)) {
            r = lens_read_seq;
            break;
        }
        double a, b, c, d;
        char extra;
        if (sscanf(p, "%lf %lf %lf %lf %c", &a, &b, &c, &d, &extra) == 4)
            numeric4++;
        else
            other++;
    }
    if (r == lens_read_native && numeric4 > 0 && other == 0)
        r = lens_read_pbrt;
    rewind(f);
    return r;
}

int lens_load(const char *path, const lens_load_options *opt, lens_t *lens, lens_err *err)
{
    lens_init(lens);
    int is_stdin = strcmp(path, "-") == 0;
    FILE *f = is_stdin ? stdin : fopen(path, "r");
    if (!f) {
        lens_errf(err, path, 0, "cannot open the lens file");
        return -1;
    }
    lens_reader read = NULL;
    for (size_t i = 0; i < sizeof readers / sizeof *readers && !is_stdin; i++)
        if (has_ext(path, readers[i].ext))
            read = readers[i].read;
    if (!read)
        read = is_stdin ? lens_read_native : sniff(f);
    int rc = read(f, path, opt, lens, err);
    if (!is_stdin)
        fclose(f);
    return rc;
}
