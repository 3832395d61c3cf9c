/* Reader of pbrt's RealisticCamera lens files (the .dat files in lenses/reference/pbrt):
 *
 *   radius thickness n aperture-diameter
 *
 * - the fourth column is a DIAMETER (pbrt halves it): semi-diameter = value / 2;
 * - radius 0 is the aperture stop (a flat iris); n 0 means air at the stop, n 1 air;
 *   other n are bare indices (no dispersion) of the medium after the surface;
 * - the scaled files give the thickness to the NEXT surface, with 0 on the last row:
 *   "focus decides", so the sensor is put at the paraxial focus for an object at
 *   infinity (d line);
 * - wide.dat gives the distance from the PREVIOUS surface instead (its first row is 0):
 *   a file whose first thickness is 0 is read that way, shifted up one row, and its
 *   sensor distance is again the paraxial focus. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/line_reader.h"
#include "sparselens/import_table.h"
#include "lens/lens_material.h"
#include "sparselens/paraxial.h"
#include "sparselens/numparse.h"

int lens_read_pbrt(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                   lens_err *err)
{
    (void)opt;
    lens_init(lens);
    snprintf(lens->path, sizeof lens->path, "%s", path);
    line_reader lr;
    line_reader_init(&lr, f, path, LINE_MAX_BYTES);
    long line = 0;
    int rc = -1, rd;
    while ((rd = line_next(&lr, err)) == LINE_OK) {
        line = lr.line;
        char *buf = lr.buf;
        char *hash = strchr(buf, '#');
        if (hash && !lens->name[0] && lens->nsurf == 0) {
            /* the first comment with words, before the surfaces, names the lens (pbrt's
             * files open with it: "# D-GAUSS F/2 22deg HFOV") */
            const char *c = hash + 1 + strspn(hash + 1, "# \t");
            size_t n = strcspn(c, "\r\n");
            while (n > 0 && (c[n - 1] == ' ' || c[n - 1] == '\t'))
                n--;
            int words = 0;
            for (size_t i = 0; i < n; i++)
                words |= isalpha((unsigned char)c[i]) != 0;
            if (words && strncasecmp(c, "radius", 6) != 0) /* not the columns' header */
                snprintf(lens->name, sizeof lens->name, "%.*s", (int)n, c);
        }
        if (hash)
            *hash = '\0';
        char *tok[8];
        int nt = 0;
        char *save = NULL;
        for (char *t = strtok_r(buf, " \t\r\n", &save); t && nt < 8; t = strtok_r(NULL, " \t\r\n", &save))
            tok[nt++] = t;
        if (nt == 0)
            continue;
        double v[4];
        if (nt != 4) {
            lens_errf(err, path, line, "expected 4 columns: radius thickness n aperture-diameter "
                                       "(%d found)", nt);
            goto out;
        }
        for (int i = 0; i < 4; i++)
            if (parse_double(tok[i], &v[i]) != 0) {
                lens_errf(err, path, line, "'%s' is not a finite number", tok[i]);
                goto out;
            }
        lens_surface *s = lens_add_surface_at(lens, path, line, err);
        if (!s)
            goto out;
        s->radius = v[0] == 0 ? INFINITY : v[0];
        s->is_stop = v[0] == 0;
        s->thickness = v[1];
        if (v[2] == 0 || v[2] == 1) {
            s->medium = glass_air();
            strcpy(s->material, s->is_stop ? "stop" : "air");
        } else if (glass_check_ndvd(v[2], NAN, "index", path, line, err) == 0) {
            s->medium = glass_constant(v[2]);
            snprintf(s->material, sizeof s->material, "%s", tok[2]);
        } else {
            goto out;
        }
        if (!(v[3] > 0)) {
            lens_errf(err, path, line, "aperture diameter %g must be positive", v[3]);
            goto out;
        }
        s->semi_diameter = v[3] / 2;
    }
    if (rd != LINE_END)
        goto out;
    if (lens->nsurf == 0) {
        lens_errf(err, path, line > 0 ? line : 1, "no surfaces");
        goto out;
    }
    size_t n = lens->nsurf;
    if (n > 1 && lens->surf[0].thickness == 0) {
        for (size_t i = 0; i + 1 < n; i++)
            lens->surf[i].thickness = lens->surf[i + 1].thickness;
        lens->surf[n - 1].thickness = 0;
        lens_add_note(lens, "thickness column read as the distance from the previous surface "
                            "(first row 0)");
    }
    int nstop = 0;
    for (size_t i = 0; i < n; i++)
        nstop += lens->surf[i].is_stop;
    if (nstop == 0) {
        lens_errf(err, path, line, "no aperture stop (no row with radius 0)");
        goto out;
    }
    int focus = lens->surf[n - 1].thickness == 0;
    if (focus)
        lens->surf[n - 1].thickness = 1; /* placeholder while checking the geometry */
    if (lens_finish(lens, err) != 0)
        goto out;
    if (focus) {
        double t;
        if (paraxial_focus_thickness(lens, GLASS_D_LINE, INFINITY, &t, err) != 0)
            goto out;
        lens->surf[n - 1].thickness = t;
        lens_add_note(lens, "sensor at the paraxial focus for an object at infinity (the file "
                            "leaves the last thickness to focus)");
        if (lens_finish(lens, err) != 0)
            goto out;
    }
    rc = 0;
out:
    line_reader_free(&lr);
    if (rc != 0)
        lens_free(lens);
    return rc;
}
