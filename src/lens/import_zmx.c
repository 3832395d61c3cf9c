/* Zemax OpticStudio .zmx reader (sequential mode). See lens-import(5).
 *
 * A .zmx file is a list of keyword lines: system data at the left margin, then one
 * "SURF n" block per surface (object = SURF 0, image = the last), its properties
 * indented. Conventions match sparselens's: CURV is 1/radius, positive when the centre
 * of curvature lies towards the image; DISZ is the axial distance to the next surface;
 * GLAS is the medium after the surface; DIAM holds the semi-diameter despite its name.
 * Lengths are in the file's lens units (UNIT) and converted to mm here; an even-asphere
 * coefficient on r^(2i) has units length^(1-2i) and is scaled accordingly. */
#include "sparselens/import_design.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lens/import_common.h"
#include "sparselens/numparse.h"

#define ZMX_MAX_TOK 64
#define ZMX_NPARM 9 /* PARM 1..8 used by the even asphere (r^2 .. r^16) */
#define ZMX_MAX_FIELDS LENS_MAX_FIELDS
#define ZMX_MAX_WAVES LENS_MAX_WAVES

typedef struct {
    long line;      /* the SURF line */
    int number;     /* Zemax surface number */
    char type[24];
    double curv, disz, diam, clap, coni;
    double parm[ZMX_NPARM];
    int stop;
    int has_glas, model;
    char glas[48];
    long glas_line;
    double nd, vd;
    char refuse[160]; /* why this surface cannot be modelled (first reason) */
    long refuse_line;
} zsurf;

typedef struct {
    import_system sys; /* path, lens, skips, unit, epd, fno */
    zsurf *s;
    size_t ns, cap;
    int ftype, nfields, nwaves, pwav;
    double xfield[ZMX_MAX_FIELDS], yfield[ZMX_MAX_FIELDS];
    int nx, ny;
    double wave[ZMX_MAX_WAVES], wweight[ZMX_MAX_WAVES];
    int nwave_read, has_weights;
    int mnum;
    char gcat[100];
} zmx_state;

static int num(const char *s, double *v)
{
    if (import_eq(s, "INFINITY") || import_eq(s, "INF")) {
        *v = INFINITY;
        return 0;
    }
    return parse_double(s, v);
}

/* Keywords that only concern display, file bookkeeping or analysis settings: they do
 * not change the optics, so they are not worth a warning. */
static const char *const silent_system_keys[] = {
    "VERS", "PFIL", "LANG", "ENVD", "GFAC", "RAIM", "PUSH", "SDMA", "OMMA", "ROPD",
    "HYPR", "PICB", "FWGN", "FWGT", "POLS", "GLRS", "GSTD", "COFN", "SURP", "BLNK",
    "NOTE", "WWGT", "WWGN", "VDSZ", "SCOL", "SLAB", "RWRE", "BLNS", "TOLE", "MAZH",
    "PPAR", "DMFS", "EFFL", "SDMS", "NSCD", "NSCS", "FIMP", "MAZH",
    "XFLM", "YFLM", "FWGM", "FTYM", "DBDT", NULL};

static const char *const silent_surface_keys[] = {"HIDE", "MIRR", "SLAB", "COMM", "POPS", "MEMA",
                                                  "PZUP", "FLAP", "XDAT", "VPAR", "PPAR", "BLNK",
                                                  "SCOL", "COLR", "FIMP", "OEMA", "MAZH", NULL};

static void refuse(zsurf *z, long line, const char *fmt, const char *what)
{
    if (z->refuse[0])
        return;
    snprintf(z->refuse, sizeof z->refuse, fmt, what);
    z->refuse_line = line;
}

static int surface_key(zmx_state *st, zsurf *z, char **tok, int n, long line, lens_err *err)
{
    const char *k = tok[0];
    double v;
    if (import_eq(k, "TYPE")) {
        snprintf(z->type, sizeof z->type, "%s", n > 1 ? tok[1] : "");
    } else if (import_eq(k, "CURV")) {
        if (import_number(&st->sys, tok, n, 1, line, &z->curv, err) != 0)
            return -1;
    } else if (import_eq(k, "DISZ")) {
        if (import_number(&st->sys, tok, n, 1, line, &z->disz, err) != 0)
            return -1;
    } else if (import_eq(k, "DIAM")) {
        if (import_number(&st->sys, tok, n, 1, line, &z->diam, err) != 0)
            return -1;
    } else if (import_eq(k, "CLAP")) {
        /* CLAP min-radius max-radius ...: a circular clear aperture. */
        if (import_number(&st->sys, tok, n, 2, line, &z->clap, err) != 0)
            return -1;
        if (n > 1 && parse_double(tok[1], &v) == 0 && v > 0)
            import_skip(&st->sys.skips, "annular aperture inner radius");
    } else if (import_eq(k, "CONI")) {
        if (import_number(&st->sys, tok, n, 1, line, &z->coni, err) != 0)
            return -1;
    } else if (import_eq(k, "PARM")) {
        double idx;
        if (import_number(&st->sys, tok, n, 1, line, &idx, err) != 0)
            return -1;
        if (import_number(&st->sys, tok, n, 2, line, &v, err) != 0)
            return -1;
        if (idx >= 0 && idx < ZMX_NPARM && idx == floor(idx))
            z->parm[(int)idx] = v;
        else if (v != 0)
            refuse(z, line, "%s", "a surface parameter sparselens does not model");
    } else if (import_eq(k, "STOP")) {
        z->stop = 1;
    } else if (import_eq(k, "GLAS")) {
        if (n < 2) {
            lens_errf(err, st->sys.path, line, "GLAS without a glass name");
            return -1;
        }
        z->has_glas = 1;
        z->glas_line = line;
        if (import_copy_name(z->glas, sizeof z->glas, tok[1], "glass name", st->sys.path, line,
                             err) != 0)
            return -1;
        z->nd = z->vd = NAN;
        if (n > 5) {
            num(tok[4], &z->nd);
            num(tok[5], &z->vd);
        }
        z->model = strcmp(tok[1], "___BLANK") == 0 || (n > 2 && strcmp(tok[2], "1") == 0);
        if (import_eq(tok[1], "MIRROR"))
            refuse(z, line, "%s", "is a mirror (MIRROR): reflecting systems are not supported");
    } else if (import_eq(k, "COAT")) {
        import_skip(&st->sys.skips, "coatings");
    } else if (import_eq(k, "IGNR")) {
        if (import_any_nonzero(tok, n, 1))
            refuse(z, line, "%s", "is marked 'ignore this surface'; remove it in the design first");
    } else if (import_eq(k, "OBSC") || import_eq(k, "OBDC")) {
        import_skip(&st->sys.skips, "obscurations");
    } else if (import_eq(k, "SQAP") || import_eq(k, "ELAP") || import_eq(k, "UDAP")) {
        import_skip(&st->sys.skips, "non-circular apertures (DIAM used)");
    } else if (!strncmp(k, "DEC", 3) || !strncmp(k, "TILT", 4) || !strncmp(k, "SCB", 3)) {
        /* Tilt/decentre of a surface: harmless when all zero, refused otherwise. */
        if (import_any_nonzero(tok, n, 1))
            refuse(z, line, "%s", "is tilted or decentred; sparselens models centred systems only");
    } else if (import_eq(k, "TOL") || !strncmp(k, "TOL", 3)) {
        import_skip(&st->sys.skips, "tolerance data");
    } else if (!import_eq_any(k, silent_surface_keys)) {
        import_skip_word(&st->sys.skips, "surface keyword", k);
    }
    return 0;
}

static int system_key(zmx_state *st, char **tok, int n, long line, lens_err *err)
{
    const char *k = tok[0];
    double v;
    if (import_eq(k, "MODE")) {
        if (n > 1 && !import_eq(tok[1], "SEQ")) {
            lens_errf(err, st->sys.path, line,
                      "MODE %s: a non-sequential file; sparselens reads sequential systems only",
                      tok[1]);
            return -1;
        }
    } else if (import_eq(k, "UNIT")) {
        const char *u = n > 1 ? tok[1] : "MM";
        if (import_eq(u, "MM"))
            st->sys.unit = 1;
        else if (import_eq(u, "CM"))
            st->sys.unit = 10;
        else if (import_eq(u, "IN"))
            st->sys.unit = 25.4;
        else if (import_eq(u, "METER") || import_eq(u, "M"))
            st->sys.unit = 1000;
        else {
            lens_errf(err, st->sys.path, line, "UNIT %s: unknown lens unit (MM, CM, IN or METER)", u);
            return -1;
        }
    } else if (import_eq(k, "ENPD")) {
        if (n > 1 && parse_double(tok[1], &v) == 0)
            st->sys.epd = v;
    } else if (import_eq(k, "FNUM")) {
        if (n > 1 && parse_double(tok[1], &v) == 0)
            st->sys.fno = v;
    } else if (import_eq(k, "OBNA") || import_eq(k, "FLOA")) {
        import_skip(&st->sys.skips, "aperture given as object NA or float by stop (stop DIAM used)");
    } else if (import_eq(k, "FTYP")) {
        long a;
        if (n > 1 && parse_long(tok[1], &a) == 0)
            st->ftype = (int)a;
        if (n > 3 && parse_long(tok[3], &a) == 0)
            st->nfields = (int)a;
        if (n > 4 && parse_long(tok[4], &a) == 0)
            st->nwaves = (int)a;
    } else if (import_eq(k, "XFLN") || import_eq(k, "YFLN") || import_eq(k, "XFIE") ||
               import_eq(k, "YFIE")) {
        int y = toupper((unsigned char)k[0]) == 'Y';
        if (import_numbers(tok, n, y ? st->yfield : st->xfield, y ? &st->ny : &st->nx,
                           ZMX_MAX_FIELDS))
            import_skip(&st->sys.skips, "fields past the 32nd");
    } else if (import_eq(k, "WAVM")) {
        long i;
        if (n > 2 && parse_long(tok[1], &i) == 0 && i >= 1 && i <= ZMX_MAX_WAVES &&
            parse_double(tok[2], &v) == 0) {
            st->wave[i - 1] = v;
            st->wweight[i - 1] = 1;
            if (n > 3 && parse_double(tok[3], &v) == 0 && v >= 0) {
                st->wweight[i - 1] = v;
                st->has_weights = 1;
            }
            if (i > st->nwave_read)
                st->nwave_read = (int)i;
        }
    } else if (import_eq(k, "WAVL") || import_eq(k, "WAVN")) {
        if (import_numbers(tok, n, st->wave, &st->nwave_read, ZMX_MAX_WAVES))
            import_skip(&st->sys.skips, "wavelengths past the 32nd");
        if (st->nwaves == 0)
            st->nwaves = st->nwave_read;
    } else if (import_eq(k, "PWAV")) {
        long i;
        if (n > 1 && parse_long(tok[1], &i) == 0)
            st->pwav = (int)i;
    } else if (import_eq(k, "GCAT")) {
        /* Zemax's catalog names (SCHOTT OHARA ...): glasses are looked up by name in the
         * catalogs given instead; the names help the missing-glass message. */
        size_t o = 0;
        for (int i = 1; i < n && o + 1 < sizeof st->gcat; i++) {
            int w = snprintf(st->gcat + o, sizeof st->gcat - o, "%s%s", i > 1 ? " " : "", tok[i]);
            if (w < 0)
                break;
            o += (size_t)w;
        }
    } else if (import_eq(k, "MNUM")) {
        long m;
        if (n > 1 && parse_long(tok[1], &m) == 0)
            st->mnum = (int)m;
    } else if (import_eq(k, "CONF") || import_eq(k, "CONG") || import_eq(k, "MOFF")) {
        import_skip(&st->sys.skips, "multi-configuration operands");
    } else if (!strncmp(k, "TOL", 3)) {
        import_skip(&st->sys.skips, "tolerance operands");
    } else if (!strncmp(k, "NSO", 3) || import_eq(k, "NSCO")) {
        import_skip(&st->sys.skips, "non-sequential objects");
    } else if (!strncmp(k, "MFE", 3) || import_eq(k, "MNCA") || import_eq(k, "OPER")) {
        import_skip(&st->sys.skips, "merit function");
    } else if (!strncmp(k, "VD", 2) || !strncmp(k, "VC", 2) || import_eq(k, "VANN")) {
        if (import_any_nonzero(tok, n, 1))
            import_skip(&st->sys.skips, "field vignetting factors");
    } else if (!import_eq_any(k, silent_system_keys)) {
        import_skip_word(&st->sys.skips, "keyword", k);
    }
    return 0;
}

/* A flat air-to-air surface with nothing else on it changes no ray: Zemax files are full
 * of them (dummies, reference planes). */
static int is_dummy(const zsurf *z, int air_before)
{
    if (z->stop || !air_before || z->curv != 0 || z->clap > 0)
        return 0;
    if (z->has_glas && !import_eq(z->glas, "AIR"))
        return 0;
    if (import_eq(z->type, "COORDBRK"))
        return 1; /* nonzero ones were refused already */
    if (z->coni != 0)
        return 0;
    for (int i = 1; i < ZMX_NPARM; i++)
        if (z->parm[i] != 0 && import_eq(z->type, "EVENASPH"))
            return 0;
    return 1;
}

static int check_type(zmx_state *st, zsurf *z)
{
    (void)st;
    if (!z->type[0] || import_eq(z->type, "STANDARD"))
        return 0;
    if (import_eq(z->type, "EVENASPH")) {
        if (z->parm[1] != 0)
            refuse(z, z->line, "%s",
                   "has an r^2 asphere term (PARM 1), which sparselens's even asphere lacks");
        else if (z->parm[7] != 0 || z->parm[8] != 0)
            refuse(z, z->line, "%s",
                   "has r^14/r^16 asphere terms (PARM 7, 8); sparselens stops at r^12");
        return 0;
    }
    if (import_eq(z->type, "COORDBRK")) {
        for (int i = 1; i <= 5; i++)
            if (z->parm[i] != 0) {
                refuse(z, z->line, "%s",
                       "is a coordinate break with a decentre or tilt; sparselens models "
                       "centred systems only");
                break;
            }
        return 0;
    }
    char why[96];
    snprintf(why, sizeof why, "has TYPE %.24s (sparselens reads STANDARD and EVENASPH)", z->type);
    refuse(z, z->line, "%s", why);
    return 0;
}

/* The file's fields and wavelengths, into the lens and its notes. */
static int fields_and_waves(zmx_state *st, lens_err *err)
{
    int nf = st->nfields > 0 && st->nfields <= ZMX_MAX_FIELDS ? st->nfields : (st->ny > st->nx ? st->ny : st->nx);
    if (nf > st->ny)
        nf = st->ny;
    if (st->nfields <= 0) /* no count in the file: the unused slots are the trailing zeros */
        while (nf > 1 && st->yfield[nf - 1] == 0 && (nf > st->nx || st->xfield[nf - 1] == 0))
            nf--;
    static const char *const kind[] = {"angle (deg)", "object height", "paraxial image height",
                                       "real image height"};
    static const lens_field_kind fk[] = {LENS_FIELD_ANGLE, LENS_FIELD_OBJECT_HEIGHT,
                                         LENS_FIELD_IMAGE_HEIGHT, LENS_FIELD_REAL_IMAGE_HEIGHT};
    int known = st->ftype >= 0 && st->ftype <= 3;
    import_fields_note(st->sys.lens, known ? kind[st->ftype] : "other", st->xfield, st->nx,
                       st->yfield, nf);
    int nw = st->nwaves > 0 && st->nwaves <= st->nwave_read ? st->nwaves : st->nwave_read;
    import_waves_note(st->sys.lens, st->wave, nw, 1, st->pwav);
    if (!st->has_weights)
        for (int i = 0; i < nw; i++)
            st->wweight[i] = 1;
    if (import_set_fields(st->sys.lens, known ? fk[st->ftype] : LENS_FIELD_NONE, st->xfield,
                          st->nx, st->yfield, known ? nf : 0, err) != 0)
        return -1;
    return import_set_waves(st->sys.lens, st->wave, st->wweight, nw, st->pwav, err);
}

static int build(void *state, const lens_load_options *opt, lens_err *err)
{
    zmx_state *st = state;
    lens_t *lens = st->sys.lens;
    if (st->ns < 3) {
        lens_errf(err, st->sys.path, 0,
                  "%zu surfaces: a .zmx lens needs an object, at least one lens surface and "
                  "an image surface",
                  st->ns);
        return -1;
    }
    for (size_t i = 0; i < st->ns; i++) {
        check_type(st, &st->s[i]);
        if (st->s[i].refuse[0]) {
            lens_errf(err, st->sys.path, st->s[i].refuse_line, "surface %d %s", st->s[i].number,
                      st->s[i].refuse);
            return -1;
        }
    }
    const zsurf *obj = &st->s[0], *img = &st->s[st->ns - 1];
    if (obj->has_glas && !import_eq(obj->glas, "AIR")) {
        lens_errf(err, st->sys.path, obj->glas_line,
                  "object space is %s, not air; sparselens models lenses in air", obj->glas);
        return -1;
    }
    if (isfinite(obj->disz) && obj->disz < 1e9)
        lens_add_note(lens, "object at %g mm in the file; read for an object at infinity",
                    obj->disz * st->sys.unit);
    if (img->curv != 0)
        import_skip(&st->sys.skips, "curved image surface (flat sensor used)");
    if (st->mnum > 1)
        lens_add_note(lens, "%d configurations in the file; the first is read", st->mnum);

    import_glass_ctx gl;
    import_glass_init(&gl, opt, st->sys.path);
    snprintf(gl.maker_catalogs, sizeof gl.maker_catalogs, "%s", st->gcat);
    double u = st->sys.unit;
    int air_before = 1, merged = 0, have_stop = 0, stop_clap = 0;
    for (size_t i = 1; i + 1 < st->ns; i++) {
        const zsurf *z = &st->s[i];
        if (!isfinite(z->disz)) {
            import_glass_free(&gl);
            lens_errf(err, st->sys.path, z->line, "surface %d: thickness must be finite", z->number);
            return -1;
        }
        if (is_dummy(z, air_before)) {
            if (lens->nsurf > 0)
                lens->surf[lens->nsurf - 1].thickness += z->disz * u;
            merged++;
            continue;
        }
        lens_surface *s = lens_add_surface_at(lens, st->sys.path, z->line, err);
        if (!s) {
            import_glass_free(&gl);
            return -1;
        }
        s->radius = import_radius(z->curv, u);
        s->thickness = z->disz * u;
        s->semi_diameter = (z->clap > 0 ? z->clap : z->diam) * u;
        s->conic = z->coni;
        if (import_eq(z->type, "EVENASPH"))
            for (int a = 0; a < LENS_ASPHERE_TERMS; a++) {
                /* PARM a+2 multiplies r^(2a+4), in lens units^(-2a-3). */
                s->asphere[a] = z->parm[a + 2] * pow(u, -(2.0 * a + 3.0));
            }
        s->is_stop = z->stop;
        have_stop |= z->stop;
        if (z->stop)
            stop_clap = z->clap > 0;
        if (!z->has_glas || import_eq(z->glas, "AIR")) {
            s->medium = glass_air();
            strcpy(s->material, "air");
        } else if (z->model) {
            if (import_glass_model(s, z->nd, z->vd, st->sys.path, z->glas_line, err) != 0) {
                import_glass_free(&gl);
                return -1;
            }
        } else if (import_glass_lookup(&gl, z->glas, z->nd, z->vd, st->sys.path, z->glas_line, s,
                                       err) != 0) {
            import_glass_free(&gl);
            return -1;
        }
        air_before = s->medium.kind == GLASS_AIR;
    }
    import_glass_note(&gl, lens);
    import_glass_free(&gl);
    if (lens->nsurf == 0) {
        lens_errf(err, st->sys.path, 0, "no lens surfaces between object and image");
        return -1;
    }
    if (!have_stop) {
        lens->surf[0].is_stop = 1;
        lens_add_note(lens, "no STOP surface in the file; the first surface is the stop");
    }
    if (merged)
        lens_add_note(lens, "%d flat air-to-air dummy surface%s merged into the gaps", merged,
                    merged > 1 ? "s" : "");
    /* Surfaces without DIAM (or DIAM 0): Zemax sizes them from the rays. */
    int *missing = calloc(lens->nsurf, sizeof *missing);
    if (!missing) {
        lens_errf(err, st->sys.path, 0, "out of memory");
        return -1;
    }
    for (size_t i = 0; i < lens->nsurf; i++)
        missing[i] = !(lens->surf[i].semi_diameter > 0);
    int rc = fields_and_waves(st, err);
    if (rc == 0)
        rc = import_size_apertures(lens, missing, st->sys.epd * u, st->sys.fno, "DIAM", "ENPD or FNUM", err);
    free(missing);
    if (rc != 0)
        return -1;
    return import_finish(lens, &st->sys.skips, st->sys.fno, "FNUM", st->sys.epd * u, "ENPD", stop_clap, err);
}

/* A SURF line: the next surface block. */
static zsurf *new_surface(zmx_state *st, char **tok, int n, long line, lens_err *err)
{
    long no;
    if (n < 2 || parse_long(tok[1], &no) != 0 || no != (long)st->ns) {
        lens_errf(err, st->sys.path, line, "SURF %s: expected surface number %zu",
                  n > 1 ? tok[1] : "", st->ns);
        return NULL;
    }
    zsurf *z = import_push((void **)&st->s, &st->cap, &st->ns, sizeof *st->s, st->sys.path,
                           line, err);
    if (!z)
        return NULL;
    z->line = line;
    z->number = (int)no;
    z->nd = z->vd = NAN;
    return z;
}

/* Keyword lines at the left margin are system data; indented ones under a SURF line
 * belong to that surface. */
static int read_lines(void *state, char *text, lens_err *err)
{
    zmx_state *st = state;
    import_lines it = {text, 0};
    char *line, *tok[ZMX_MAX_TOK];
    zsurf *cur = NULL;
    int rc = 0, seen_vers = 0;
    while (rc == 0 && (line = import_next_line(&it))) {
        int indented = line[0] == ' ' || line[0] == '\t';
        /* The name is the rest of its line, blanks inside included: taken before the
         * line is split into tokens in place. */
        const char *name = import_rest_after(line, "NAME");
        if (name && !(cur && indented)) {
            import_set_name(st->sys.lens, name);
            cur = NULL;
            continue;
        }
        int n = import_tokens(line, tok, ZMX_MAX_TOK);
        if (n == 0)
            continue;
        if (n > ZMX_MAX_TOK) {
            import_skip(&st->sys.skips, "words past the 64th of a line");
            n = ZMX_MAX_TOK;
        }
        if (import_eq(tok[0], "VERS"))
            seen_vers = 1;
        if (import_eq(tok[0], "SURF")) {
            cur = new_surface(st, tok, n, it.line, err);
            rc = cur ? 0 : -1;
        } else if (cur && indented) {
            rc = surface_key(st, cur, tok, n, it.line, err);
        } else {
            cur = NULL;
            rc = system_key(st, tok, n, it.line, err);
        }
    }
    if (rc == 0 && !seen_vers && st->ns == 0) {
        lens_errf(err, st->sys.path, 0, "not a Zemax .zmx file (no VERS line and no SURF blocks)");
        rc = -1;
    }
    return rc;
}

static void free_state(void *state)
{
    free(((zmx_state *)state)->s);
}

static const import_format zmx_format = {"Zemax", 1, sizeof(zmx_state), read_lines, build,
                                         free_state};

int lens_parse_zmx(const char *data, size_t len, const char *path,
                   const lens_load_options *opt, lens_t *lens, lens_err *err)
{
    return import_parse(data, len, path, opt, lens, &zmx_format, err);
}

int lens_read_zmx(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                  lens_err *err)
{
    return import_read_parse(f, path, opt, lens, err, lens_parse_zmx);
}
