/* CODE V sequence (.seq) reader: the lens-entry subset described in lens-import(5).
 *
 * A .seq file is a list of commands, several per line when separated by ';'. Surface
 * commands (SO object, S surface, STO stop surface, SI image) start a surface; the
 * commands after them (CIR, ASP with K A B C D E, STO alone, solve flags) qualify the
 * current surface. Conventions match sparselens's: radius positive with the centre of
 * curvature towards the image, thickness to the next surface, glass after the surface.
 * Lengths are in the file's units (DIM M/C/I), converted to mm when the lens is built
 * (import_seq_build.c) from what this file reads. */
#include "base/line_reader.h"
#include "sparselens/import_design.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lens/import_seq.h"
#include "sparselens/numparse.h"

#define SEQ_MAX_TOK 64

static void refuse(qsurf *q, long line, const char *why)
{
    if (q && !q->refuse[0]) {
        snprintf(q->refuse, sizeof q->refuse, "%s", why);
        q->refuse_line = line;
    }
}

static qsurf *new_surface(seq_state *st, int kind, long line, lens_err *err)
{
    qsurf *q = import_push((void **)&st->s, &st->cap, &st->ns, sizeof *st->s, st->sys.path,
                           line, err);
    if (!q)
        return NULL;
    q->line = line;
    q->kind = kind;
    return q;
}

/* S radius thickness [glass]: the surface-defining commands. */
static int define_surface(seq_state *st, qsurf *q, char **tok, int n, long line, lens_err *err)
{
    double v = 0;
    if (n > 1) {
        if (parse_double(tok[1], &v) != 0) {
            lens_errf(err, st->sys.path, line, "%s: expected a radius, found '%s'", tok[0], tok[1]);
            return -1;
        }
        q->given_radius = !st->curvature_mode;
        if (st->curvature_mode)
            q->curv = v;
        else
            q->radius = v;
    }
    if (n > 2) {
        /* "inf" as well as 1e10: other programs that write .seq files (optiland) do */
        if (import_number(&st->sys, tok, n, 2, line, &v, NULL) != 0) {
            lens_errf(err, st->sys.path, line, "%s: expected a thickness, found '%s'", tok[0], tok[2]);
            return -1;
        }
        q->thick = v;
    }
    if (n > 3) {
        if (import_eq(tok[3], "REFL"))
            refuse(q, line, "is a mirror (REFL): reflecting systems are not supported");
        else {
            q->glass_line = line;
            return import_copy_name(q->glass, sizeof q->glass, tok[3], "glass name",
                                    st->sys.path, line, err);
        }
    }
    return 0;
}

/* Index of the PWL wavelength within 1 nm of want (nm), or -1. */
static int pwl_at(const seq_state *st, double want)
{
    for (int i = 0; i < st->npwl; i++)
        if (fabs(st->pwl[i] - want) <= 1.0)
            return i;
    return -1;
}

/* A fitted private glass must give back each tabulated index within this: tables give
 * four or five decimals. */
#define PRIVATE_FIT_TOLERANCE 5e-5

/* Inside PRV ... END: "PWL w1 w2 ..." (nm), then "'NAME' n1 n2 ..." per glass. A glass
 * of three indices or more is the dispersion formula fitted to them; else it becomes the
 * n_d/V_d model when its indices include the d, F and C lines, a bare n_d when only d;
 * otherwise it is kept with the reason, for the error if it is used. */
static int private_glass(seq_state *st, char **tok, int n, long line, lens_err *err)
{
    if (import_eq(tok[0], "END")) {
        st->in_prv = 0;
        return 0;
    }
    if (import_eq(tok[0], "PWL")) {
        st->npwl = 0;
        if (import_numbers(tok, n, st->pwl, &st->npwl, SEQ_MAX_PWL)) {
            lens_errf(err, st->sys.path, line, "PWL: more than %d wavelengths", SEQ_MAX_PWL);
            return -1;
        }
        return 0;
    }
    if (st->nprv == SEQ_MAX_PRIVATE) {
        import_skip(&st->sys.skips, "private glasses past 32");
        return 0;
    }
    double idx[SEQ_MAX_PWL];
    int ni = 0;
    for (int i = 1; i < n && ni < SEQ_MAX_PWL; i++) {
        if (parse_double(tok[i], &idx[ni]) != 0) {
            lens_errf(err, st->sys.path, line, "private glass %s: index '%s' is not a number",
                      tok[0], tok[i]);
            return -1;
        }
        ni++;
    }
    if (ni != st->npwl) {
        lens_errf(err, st->sys.path, line,
                  "private glass %s: %d indices for %d PWL wavelengths", tok[0], ni, st->npwl);
        return -1;
    }
    int d = pwl_at(st, 587.5618), f = pwl_at(st, 486.1327), c = pwl_at(st, 656.2725);
    int k = st->nprv;
    if (import_copy_name(st->prv[k].name, sizeof st->prv[k].name, tok[0], "private glass name",
                         st->sys.path, line, err) != 0)
        return -1;
    st->nprv++;
    st->prv[k].why[0] = '\0';
    st->prv[k].vd = 0;
    st->prv[k].tabulated = 0;
    /* Three indices or more: the formula through them (the d, F and C lines need not be
     * among them), where it meets every one within what a table's digits say. Only the
     * indices over the file's wavelengths (WL, read before PRV), and the nearest one past
     * each end: a table spanning 0.4-1.6 um is rarely smooth enough for one formula, and
     * the band the lens is used in is what its dispersion must be right over. */
    double um[SEQ_MAX_PWL], sel[SEQ_MAX_PWL];
    double wlo = INFINITY, whi = -INFINITY, below = -INFINITY, above = INFINITY;
    for (int i = 0; i < st->nwl; i++)
        wlo = fmin(wlo, st->wl[i]), whi = fmax(whi, st->wl[i]);
    for (int i = 0; i < ni && st->nwl > 0; i++) {
        if (st->pwl[i] < wlo - 1.0) /* within 1 nm is the line itself (486.1 for F) */
            below = fmax(below, st->pwl[i]);
        if (st->pwl[i] > whi + 1.0)
            above = fmin(above, st->pwl[i]);
    }
    int ns = 0;
    for (int i = 0; i < ni; i++)
        if (st->nwl == 0 || (st->pwl[i] >= below && st->pwl[i] <= above)) {
            um[ns] = st->pwl[i] * 1e-3;
            sel[ns++] = idx[i];
        }
    if (ns >= 3 &&
        glass_fit_table(um, sel, ns, &st->prv[k].glass, &st->prv[k].residual) == 0 &&
        st->prv[k].residual <= PRIVATE_FIT_TOLERANCE && isfinite(st->prv[k].glass.nd)) {
        st->prv[k].tabulated = 1;
        return 0;
    }
    if (d < 0) {
        snprintf(st->prv[k].why, sizeof st->prv[k].why,
                 "gives no index at the d line (587.56 nm)");
        return 0;
    }
    st->prv[k].nd = idx[d];
    if (f >= 0 && c >= 0 && idx[f] > idx[c])
        st->prv[k].vd = (idx[d] - 1) / (idx[f] - idx[c]);
    return 0;
}

/* SO (object), S, SI (image) and STO with values start a surface. */
static int start_surface(seq_state *st, char **tok, int n, long line, lens_err *err)
{
    const char *k = tok[0];
    int kind = import_eq(k, "SO") ? 'O' : import_eq(k, "SI") ? 'I' : 'S';
    if (kind == 'O' && st->ns) {
        lens_errf(err, st->sys.path, line, "SO (the object surface) must come first");
        return -1;
    }
    if (kind != 'O' && st->ns == 0) {
        qsurf *o = new_surface(st, 'O', line, err); /* implicit object at infinity */
        if (!o)
            return -1;
        o->thick = INFINITY;
    }
    if (st->ns && st->s[st->ns - 1].kind == 'I') {
        lens_errf(err, st->sys.path, line, "a surface after the image surface SI");
        return -1;
    }
    qsurf *q = new_surface(st, kind, line, err);
    if (!q)
        return -1;
    q->stop = import_eq(k, "STO");
    return define_surface(st, q, tok, n, line, err);
}

/* The asphere coefficient a key sets: A B C D E are r^4 .. r^12; -1 for none. */
static int asphere_key(const char *k)
{
    static const char *const keys[LENS_ASPHERE_TERMS] = {"A", "B", "C", "D", "E"};
    for (int a = 0; a < LENS_ASPHERE_TERMS; a++)
        if (import_eq(k, keys[a]))
            return a;
    return -1;
}

/* F .. J: asphere terms beyond r^12. */
static int high_asphere_key(const char *k)
{
    int c = toupper((unsigned char)k[0]);
    return strlen(k) == 1 && c >= 'F' && c <= 'J';
}

/* Values of the current surface (shape, thickness, aperture, glass). 1 when tok[0] is
 * none of these commands. */
static int surface_value(seq_state *st, qsurf *cur, char **tok, int n, long line, lens_err *err)
{
    static const char *const keys[] = {"K",   "ASP", "CON", "SPH", "CIR",
                                       "CUY", "RDY", "THI", "GLA", NULL};
    const char *k = tok[0];
    int a = asphere_key(k), high = high_asphere_key(k);
    double v;
    if (a < 0 && !high && !import_eq_any(k, keys))
        return 1;
    if (!cur) {
        lens_errf(err, st->sys.path, line, "%s before any surface", k);
        return -1;
    }
    if (a >= 0)
        return import_number(&st->sys, tok, n, 1, line, &cur->asph[a], err);
    if (high) {
        if (import_number(&st->sys, tok, n, 1, line, &v, err) != 0)
            return -1;
        if (v != 0)
            refuse(cur, line, "has asphere terms beyond r^12 (F..J); sparselens stops at r^12");
        return 0;
    }
    if (import_eq(k, "K"))
        return import_number(&st->sys, tok, n, 1, line, &cur->conic, err);
    if (import_eq(k, "CIR")) { /* CIR [Sk] value; CIR EDG, CIR OBS, CIR HOL value */
        if (n > 1 && import_eq(tok[1], "EDG")) { /* the mechanical edge, drawn, not a stop */
            import_skip(&st->sys.skips, "edge apertures (CIR EDG, drawing only)");
            return 0;
        }
        if (n > 1 && (import_eq(tok[1], "OBS") || import_eq(tok[1], "HOL"))) {
            import_skip(&st->sys.skips, "central obscurations and holes (CIR OBS, CIR HOL)");
            return 0;
        }
        return import_number(&st->sys, tok, n, n > 2 ? 2 : 1, line, &cur->cir, err);
    }
    if (import_eq(k, "CUY") || import_eq(k, "RDY")) {
        int rdy = import_eq(k, "RDY");
        if (import_number(&st->sys, tok, n, 1, line, rdy ? &cur->radius : &cur->curv, err) != 0)
            return -1;
        cur->given_radius = rdy;
        return 0;
    }
    if (import_eq(k, "THI"))
        return import_number(&st->sys, tok, n, 1, line, &cur->thick, err);
    if (import_eq(k, "GLA")) {
        cur->glass_line = line;
        if (n > 1)
            return import_copy_name(cur->glass, sizeof cur->glass, tok[1], "glass name",
                                    st->sys.path, line, err);
    }
    return 0; /* ASP, CON, SPH: the surface type; the coefficients that follow say the rest */
}

/* Commands that make the current surface one sparselens cannot model (refused when the
 * lens is built, with their line), and those with nothing optical in them. 1 when
 * tok[0] is none of these. */
static int surface_refusal(qsurf *cur, char **tok, int n, long line)
{
    static const char *const tilts[] = {"ADE", "BDE", "CDE", "XDE", "YDE", "ZDE", NULL};
    static const char *const breaks[] = {"DAR", "BEN", "REV", "RET", "DEC", "TILT", NULL};
    static const char *const shapes[] = {"XYP", "ZRN", "SPS", "TOR", "YTO", "XTO", "DOE",
                                         "HOE", "GRT", "ODD", "AAS", "QCN", NULL};
    /* variable flags, labels, initials, weights, end of entry */
    static const char *const no_optics[] = {"CCY", "THC", "GLC", "KC",  "AC", "BC",
                                            "CC",  "DC",  "EC",  "SLB", "LEN", "GO",
                                            "INI", "WTF", "END", "DOR", NULL};
    const char *k = tok[0];
    if (import_eq(k, "REFL") || import_eq(k, "RMD")) {
        if (import_eq(k, "REFL") || (n > 1 && import_eq(tok[1], "REFL")))
            refuse(cur, line, "is a mirror (REFL): reflecting systems are not supported");
    } else if (import_eq_any(k, tilts)) {
        if (import_any_nonzero(tok, n, 1))
            refuse(cur, line, "is tilted or decentred; sparselens models centred systems only");
    } else if (import_eq_any(k, breaks)) {
        refuse(cur, line, "has a coordinate break (DAR/BEN/REV/RET); sparselens models centred "
                          "systems only");
    } else if (import_eq(k, "DIF") && n > 1 && import_eq_any(tok[1], shapes)) {
        /* DIF DOE, DIF HOE, DIF GRT: a diffractive surface, whose power the lens needs */
        char why[96];
        snprintf(why, sizeof why, "is diffractive (DIF %.8s): sparselens models refraction only",
                 tok[1]);
        refuse(cur, line, why);
    } else if (import_eq_any(k, shapes)) {
        char why[96];
        snprintf(why, sizeof why, "has surface type %.8s (sparselens reads spheres, conics and "
                                  "even aspheres)", k);
        refuse(cur, line, why);
    } else if (!import_eq_any(k, no_optics)) {
        return 1;
    }
    return 0;
}

/* System data the lens does not model: noted as skipped. 1 when tok[0] is none. */
static int skipped_system_data(seq_state *st, char **tok, int n)
{
    static const struct {
        const char *key, *label;
        int when_nonzero; /* only when a value is not 0 */
    } skips[] = {
        {"NAO", "aperture given as NA", 0},
        {"NA", "aperture given as NA", 0},
        {"XAN", "x fields", 1},
        {"XOB", "x fields", 1},
        {"XIM", "x fields", 1},
        {"XRI", "x fields", 1},
        {"VUX", "vignetting factors", 1},
        {"VLX", "vignetting factors", 1},
        {"VUY", "vignetting factors", 1},
        {"VLY", "vignetting factors", 1},
        {"PIM", "paraxial image solve (thickness as written)", 0},
        {"ZOO", "zoom positions", 0},
        {"POS", "zoom positions", 0},
        {"CIN", "coatings", 0},
        {"MLT", "coatings", 0},
        {"COA", "coatings", 0},
        {"TOL", "tolerances", 0},
    };
    for (size_t i = 0; i < sizeof skips / sizeof *skips; i++)
        if (import_eq(tok[0], skips[i].key)) {
            if (!skips[i].when_nonzero || import_any_nonzero(tok, n, 1))
                import_skip(&st->sys.skips, skips[i].label);
            return 0;
        }
    return 1;
}

/* YAN, YOB, YIM, YRI: the fields and what they measure. */
static void fields(seq_state *st, char **tok, int n)
{
    static const char *const keys[] = {"YAN", "YOB", "YIM", "YRI"};
    static const char *const kinds[] = {"angle (deg)", "object height", "paraxial image height",
                                        "real image height"};
    static const lens_field_kind fk[] = {LENS_FIELD_ANGLE, LENS_FIELD_OBJECT_HEIGHT,
                                         LENS_FIELD_IMAGE_HEIGHT, LENS_FIELD_REAL_IMAGE_HEIGHT};
    for (int i = 0; i < 4; i++)
        if (import_eq(tok[0], keys[i])) {
            snprintf(st->field_kind, sizeof st->field_kind, "%s", kinds[i]);
            st->fkind = fk[i];
        }
    st->nyan = 0;
    if (import_numbers(tok, n, st->yan, &st->nyan, SEQ_MAX_LIST))
        import_skip(&st->sys.skips, "fields past the 32nd");
}

/* DIM: the length unit. */
static int dimension(seq_state *st, char **tok, int n, long line, lens_err *err)
{
    const char *u = n > 1 ? tok[1] : "M";
    if (import_eq(u, "M") || import_eq(u, "MM"))
        st->sys.unit = 1;
    else if (import_eq(u, "C") || import_eq(u, "CM"))
        st->sys.unit = 10;
    else if (import_eq(u, "I") || import_eq(u, "IN"))
        st->sys.unit = 25.4;
    else {
        lens_errf(err, st->sys.path, line, "DIM %s: unknown unit (M, C or I; MM, CM or IN)", u);
        return -1;
    }
    return 0;
}

/* Commands about the whole system: units, modes, aperture, wavelengths, fields. */
static int system_command(seq_state *st, char **tok, int n, long line, lens_err *err)
{
    static const char *const field_keys[] = {"YAN", "YOB", "YIM", "YRI", NULL};
    const char *k = tok[0];
    long r;
    if (import_eq(k, "RDM"))
        st->curvature_mode = n > 1 && (import_eq(tok[1], "N") || import_eq(tok[1], "NO"));
    else if (import_eq(k, "CUM"))
        st->curvature_mode = 1;
    else if (import_eq(k, "TITLE") || import_eq(k, "TIT")) {
        if (n > 1)
            import_set_name(st->sys.lens, tok[1]);
    } else if (import_eq(k, "DIM"))
        return dimension(st, tok, n, line, err);
    else if (import_eq(k, "EPD"))
        return import_number(&st->sys, tok, n, 1, line, &st->sys.epd, err);
    else if (import_eq(k, "FNO"))
        return import_number(&st->sys, tok, n, 1, line, &st->sys.fno, err);
    else if (import_eq(k, "WL")) {
        if (import_numbers(tok, n, st->wl, &st->nwl, SEQ_MAX_LIST))
            import_skip(&st->sys.skips, "wavelengths past the 32nd");
    } else if (import_eq(k, "WTW")) {
        st->nwtw = 0;
        import_numbers(tok, n, st->wtw, &st->nwtw, SEQ_MAX_LIST);
    } else if (import_eq(k, "REF")) {
        if (n > 1 && parse_long(tok[1], &r) == 0)
            st->ref = (int)r;
    } else if (import_eq_any(k, field_keys))
        fields(st, tok, n);
    else if (import_eq(k, "PRV")) {
        st->in_prv = 1;
        st->npwl = 0;
    } else if (skipped_system_data(st, tok, n))
        import_skip_word(&st->sys.skips, "command", k);
    return 0;
}

/* One command (a ';'-separated piece of a line). */
static int command(seq_state *st, char **tok, int n, long line, lens_err *err)
{
    const char *k = tok[0];
    qsurf *cur = st->ns ? &st->s[st->ns - 1] : NULL;
    if (k[0] == '!')
        return 0; /* comment */
    if (st->in_prv)
        return private_glass(st, tok, n, line, err);
    if (import_eq(k, "SO") || import_eq(k, "S") || import_eq(k, "SI") ||
        (import_eq(k, "STO") && n > 1))
        return start_surface(st, tok, n, line, err);
    if (import_eq(k, "STO")) {
        if (!cur || cur->kind != 'S') {
            lens_errf(err, st->sys.path, line, "STO before any lens surface");
            return -1;
        }
        cur->stop = 1;
        return 0;
    }
    int rc = surface_value(st, cur, tok, n, line, err);
    if (rc == 1)
        rc = surface_refusal(cur, tok, n, line);
    if (rc == 1)
        rc = system_command(st, tok, n, line, err);
    return rc;
}

/* The next line into joined (room bytes), with the lines it continues: a line ending
 * in '&' continues on the next. *first gets its first line's number. 0 at the end of the
 * text, 1 with a line, -1 (err) when the joined line is too long. */
static int next_joined_line(seq_state *st, import_lines *it, char *joined, size_t room,
                            long *first, lens_err *err)
{
    char *line = import_next_line(it);
    if (!line)
        return 0;
    *first = it->line;
    snprintf(joined, room, "%s", line);
    for (;;) {
        size_t len = strlen(joined);
        while (len && isspace((unsigned char)joined[len - 1]))
            len--;
        if (!len || joined[len - 1] != '&')
            return 1;
        joined[len - 1] = ' ';
        joined[len] = '\0';
        char *more = import_next_line(it);
        if (!more)
            return 1;
        if (len + strlen(more) + 2 >= room) {
            lens_errf(err, st->sys.path, *first, "continued line longer than %d bytes",
                      LINE_MAX_BYTES);
            return -1;
        }
        strcat(joined, " ");
        strcat(joined, more);
    }
}

/* The commands of one line: split at ';' outside quotes; '!' starts a comment that runs
 * to the end of the line. */
static int line_commands(seq_state *st, char *p, long line, lens_err *err)
{
    char *tok[SEQ_MAX_TOK];
    int rc = 0;
    while (rc == 0 && p) {
        char *q = p, quote = 0;
        for (; *q; q++) {
            if (quote) {
                if (*q == quote)
                    quote = 0;
            } else if (*q == '\'' || *q == '"')
                quote = *q;
            else if (*q == ';' || *q == '!')
                break;
        }
        char *next = NULL;
        if (*q == ';') {
            *q = '\0';
            next = q + 1;
        } else if (*q == '!') {
            *q = '\0';
        }
        int n = import_tokens(p, tok, SEQ_MAX_TOK);
        if (n > SEQ_MAX_TOK) {
            import_skip(&st->sys.skips, "words past the 64th of a command");
            n = SEQ_MAX_TOK;
        }
        if (n > 0)
            rc = command(st, tok, n, line, err);
        p = next;
    }
    return rc;
}

static int read_lines(void *state, char *text, lens_err *err)
{
    seq_state *st = state;
    import_lines it = {text, 0};
    /* Lines are at most LINE_MAX_BYTES (import_begin checks), continued ones too. */
    const size_t room = LINE_MAX_BYTES + 1;
    char *joined = malloc(room);
    if (!joined) {
        lens_errf(err, st->sys.path, 0, "out of memory");
        return -1;
    }
    long first = 0;
    int rc;
    while ((rc = next_joined_line(st, &it, joined, room, &first, err)) == 1)
        if ((rc = line_commands(st, joined, first, err)) != 0)
            break;
    free(joined);
    return rc;
}

static void free_state(void *state)
{
    free(((seq_state *)state)->s);
}

static const import_format seq_format = {"CODE V", 1, sizeof(seq_state), read_lines, seq_build,
                                         free_state};

int lens_parse_seq(const char *data, size_t len, const char *path,
                   const lens_load_options *opt, lens_t *lens, lens_err *err)
{
    return import_parse(data, len, path, opt, lens, &seq_format, err);
}

int lens_read_seq(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                  lens_err *err)
{
    return import_read_parse(f, path, opt, lens, err, lens_parse_seq);
}
