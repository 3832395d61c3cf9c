/* CODE V sequence (.seq) reader: the lens-entry subset described in lens-import(5).
 *
 * A .seq file is a list of commands, several per line when separated by ';'. Surface
 * commands (SO object, S surface, STO stop surface, SI image) start a surface; the
 * commands after them (CIR, ASP with K A B C D E, STO alone, solve flags) qualify the
 * current surface. Conventions match sparselens's: radius positive with the centre of
 * curvature towards the image, thickness to the next surface, glass after the surface.
 * Lengths are in the file's units (DIM M/C/I) and converted to mm here. */
#include "base/line_reader.h"
#include "sparselens/import_design.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lens/import_common.h"
#include "sparselens/numparse.h"

#define SEQ_MAX_TOK 24
#define SEQ_INFINITE_OBJECT 1e9 /* CODE V writes 1e10 or more for an object at infinity */

typedef struct {
    long line;
    int kind; /* 'O' object, 'S' surface, 'I' image */
    double curv, thick, cir, conic;
    double radius;    /* as written, when given_radius (0: flat) */
    int given_radius; /* radius mode: keep the written radius exact */
    double asph[LENS_ASPHERE_TERMS]; /* A B C D E: r^4 .. r^12 */
    int stop;
    char glass[48];
    long glass_line;
    char refuse[160];
    long refuse_line;
} qsurf;

typedef struct {
    import_system sys; /* path, lens, skips, unit, epd, fno */
    qsurf *s;
    size_t ns, cap;
    int curvature_mode;
    double wl[24];
    int nwl, ref;
    double yan[24];
    int nyan;
    char field_kind[32];
    /* private glass catalog (PRV ... END): indices at the PWL wavelengths */
    int in_prv;
    double pwl[8];
    int npwl;
    struct {
        char name[48];
        double nd, vd; /* vd 0: no F and C indices, a bare index */
        char why[80];  /* non-empty: cannot be used, and why */
    } prv[32];
    int nprv;
} seq_state;

static void refuse(qsurf *q, long line, const char *why)
{
    if (q && !q->refuse[0]) {
        snprintf(q->refuse, sizeof q->refuse, "%s", why);
        q->refuse_line = line;
    }
}

static qsurf *new_surface(seq_state *st, int kind, long line, lens_err *err)
{
    if (import_grow((void **)&st->s, &st->cap, st->ns, sizeof *st->s) != 0) {
        lens_errf(err, st->sys.path, line, "out of memory");
        return NULL;
    }
    qsurf *q = &st->s[st->ns++];
    memset(q, 0, sizeof *q);
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
        if (parse_double(tok[2], &v) != 0) {
            lens_errf(err, st->sys.path, line, "%s: expected a thickness, found '%s'", tok[0], tok[2]);
            return -1;
        }
        q->thick = v;
    }
    if (n > 3) {
        if (import_eq(tok[3], "REFL"))
            refuse(q, line, "is a mirror (REFL); sparselens models refracting lenses only");
        else {
            snprintf(q->glass, sizeof q->glass, "%s", tok[3]);
            q->glass_line = line;
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

/* Inside PRV ... END: "PWL w1 w2 ..." (nm), then "'NAME' n1 n2 ..." per glass. A glass
 * becomes the n_d/V_d model when its indices include the d, F and C lines, a bare n_d
 * when only d; otherwise it is kept with the reason, for the error if it is used. */
static int private_glass(seq_state *st, char **tok, int n, long line, lens_err *err)
{
    if (import_eq(tok[0], "END")) {
        st->in_prv = 0;
        return 0;
    }
    if (import_eq(tok[0], "PWL")) {
        st->npwl = 0;
        for (int i = 1; i < n && st->npwl < 8; i++)
            if (parse_double(tok[i], &st->pwl[st->npwl]) == 0)
                st->npwl++;
        return 0;
    }
    if (st->nprv == 32) {
        import_skip(&st->sys.skips, "private glasses past 32");
        return 0;
    }
    double idx[8];
    int ni = 0;
    for (int i = 1; i < n && ni < 8; i++) {
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
    int k = st->nprv++;
    snprintf(st->prv[k].name, sizeof st->prv[k].name, "%s", tok[0]);
    st->prv[k].why[0] = '\0';
    st->prv[k].vd = 0;
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

/* One command (a ';'-separated piece of a line). */
static int command(seq_state *st, char **tok, int n, long line, lens_err *err)
{
    const char *k = tok[0];
    qsurf *cur = st->ns ? &st->s[st->ns - 1] : NULL;
    double v;
    if (k[0] == '!')
        return 0; /* comment */
    if (st->in_prv)
        return private_glass(st, tok, n, line, err);
    if (import_eq(k, "SO") || import_eq(k, "S") || import_eq(k, "SI") ||
        (import_eq(k, "STO") && n > 1)) {
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
    if (import_eq(k, "STO")) {
        if (!cur || cur->kind != 'S') {
            lens_errf(err, st->sys.path, line, "STO before any lens surface");
            return -1;
        }
        cur->stop = 1;
        return 0;
    }
#define NEED_NUM(i, dst)                                                                   \
    do {                                                                                   \
        if (n <= (i) || parse_double(tok[i], &(dst)) != 0) {                               \
            lens_errf(err, st->sys.path, line, "%s: expected a number, found '%s'", k,         \
                      n > (i) ? tok[i] : "end of line");                                   \
            return -1;                                                                     \
        }                                                                                  \
    } while (0)
#define NEED_SURF()                                                                        \
    do {                                                                                   \
        if (!cur) {                                                                        \
            lens_errf(err, st->sys.path, line, "%s before any surface", k);                   \
            return -1;                                                                     \
        }                                                                                  \
    } while (0)
    static const char *const asph_keys[LENS_ASPHERE_TERMS] = {"A", "B", "C", "D", "E"};
    for (int a = 0; a < LENS_ASPHERE_TERMS; a++)
        if (import_eq(k, asph_keys[a])) {
            NEED_SURF();
            NEED_NUM(1, cur->asph[a]);
            return 0;
        }
    if (import_eq(k, "K")) {
        NEED_SURF();
        NEED_NUM(1, cur->conic);
    } else if (strlen(k) == 1 && toupper((unsigned char)k[0]) >= 'F' &&
               toupper((unsigned char)k[0]) <= 'J') {
        NEED_SURF();
        NEED_NUM(1, v);
        if (v != 0)
            refuse(cur, line, "has asphere terms beyond r^12 (F..J); sparselens stops at r^12");
    } else if (import_eq(k, "ASP") || import_eq(k, "CON") || import_eq(k, "SPH")) {
        NEED_SURF(); /* surface type: the coefficients that follow say the rest */
    } else if (import_eq(k, "CIR")) {
        NEED_SURF();
        NEED_NUM(n > 2 ? 2 : 1, cur->cir); /* CIR [Sk] value */
    } else if (import_eq(k, "CUY")) {
        NEED_SURF();
        NEED_NUM(1, cur->curv);
        cur->given_radius = 0;
    } else if (import_eq(k, "RDY")) {
        NEED_SURF();
        NEED_NUM(1, cur->radius);
        cur->given_radius = 1;
    } else if (import_eq(k, "THI")) {
        NEED_SURF();
        NEED_NUM(1, cur->thick);
    } else if (import_eq(k, "GLA")) {
        NEED_SURF();
        if (n > 1)
            snprintf(cur->glass, sizeof cur->glass, "%s", tok[1]);
        cur->glass_line = line;
    } else if (import_eq(k, "REFL") || import_eq(k, "RMD")) {
        if (import_eq(k, "REFL") || (n > 1 && import_eq(tok[1], "REFL")))
            refuse(cur, line, "is a mirror (REFL); sparselens models refracting lenses only");
    } else if (import_eq(k, "ADE") || import_eq(k, "BDE") || import_eq(k, "CDE") ||
               import_eq(k, "XDE") || import_eq(k, "YDE") || import_eq(k, "ZDE")) {
        if (import_any_nonzero(tok, n, 1))
            refuse(cur, line, "is tilted or decentred; sparselens models centred systems only");
    } else if (import_eq(k, "DAR") || import_eq(k, "BEN") || import_eq(k, "REV") ||
               import_eq(k, "RET") || import_eq(k, "DEC") || import_eq(k, "TILT")) {
        refuse(cur, line, "has a coordinate break (DAR/BEN/REV/RET); sparselens models centred "
                          "systems only");
    } else if (import_eq(k, "XYP") || import_eq(k, "ZRN") || import_eq(k, "SPS") ||
               import_eq(k, "TOR") || import_eq(k, "YTO") || import_eq(k, "XTO") ||
               import_eq(k, "DOE") || import_eq(k, "HOE") || import_eq(k, "GRT") ||
               import_eq(k, "ODD") || import_eq(k, "AAS") || import_eq(k, "QCN")) {
        char why[96];
        snprintf(why, sizeof why, "has surface type %.8s (sparselens reads spheres, conics and "
                                  "even aspheres)", k);
        refuse(cur, line, why);
    } else if (import_eq(k, "CCY") || import_eq(k, "THC") || import_eq(k, "GLC") ||
               import_eq(k, "KC") || import_eq(k, "AC") || import_eq(k, "BC") ||
               import_eq(k, "CC") || import_eq(k, "DC") || import_eq(k, "EC") ||
               import_eq(k, "SLB") || import_eq(k, "LEN") || import_eq(k, "GO") ||
               import_eq(k, "INI") || import_eq(k, "WTW") || import_eq(k, "WTF") ||
               import_eq(k, "END") || import_eq(k, "DOR")) {
        /* variable flags, labels, initials, weights, end of entry: no optical content */
    } else if (import_eq(k, "RDM")) {
        st->curvature_mode = n > 1 && (import_eq(tok[1], "N") || import_eq(tok[1], "NO"));
    } else if (import_eq(k, "CUM")) {
        st->curvature_mode = 1;
    } else if (import_eq(k, "TITLE") || import_eq(k, "TIT")) {
        if (n > 1)
            import_set_name(st->sys.lens, tok[1]);
    } else if (import_eq(k, "DIM")) {
        const char *u = n > 1 ? tok[1] : "M";
        if (import_eq(u, "M"))
            st->sys.unit = 1;
        else if (import_eq(u, "C"))
            st->sys.unit = 10;
        else if (import_eq(u, "I"))
            st->sys.unit = 25.4;
        else {
            lens_errf(err, st->sys.path, line, "DIM %s: unknown unit (M, C or I)", u);
            return -1;
        }
    } else if (import_eq(k, "EPD")) {
        NEED_NUM(1, st->sys.epd);
    } else if (import_eq(k, "FNO")) {
        NEED_NUM(1, st->sys.fno);
    } else if (import_eq(k, "NAO") || import_eq(k, "NA")) {
        import_skip(&st->sys.skips, "aperture given as NA");
    } else if (import_eq(k, "WL")) {
        for (int i = 1; i < n && st->nwl < 24; i++)
            if (parse_double(tok[i], &v) == 0)
                st->wl[st->nwl++] = v;
    } else if (import_eq(k, "REF")) {
        long r;
        if (n > 1 && parse_long(tok[1], &r) == 0)
            st->ref = (int)r;
    } else if (import_eq(k, "YAN") || import_eq(k, "YOB") || import_eq(k, "YIM") ||
               import_eq(k, "YRI")) {
        snprintf(st->field_kind, sizeof st->field_kind, "%s",
                 import_eq(k, "YAN") ? "angle (deg)" : import_eq(k, "YOB") ? "object height"
                 : import_eq(k, "YIM") ? "paraxial image height" : "real image height");
        st->nyan = 0;
        for (int i = 1; i < n && st->nyan < 24; i++)
            if (parse_double(tok[i], &v) == 0)
                st->yan[st->nyan++] = v;
    } else if (import_eq(k, "XAN") || import_eq(k, "XOB") || import_eq(k, "XIM") ||
               import_eq(k, "XRI")) {
        if (import_any_nonzero(tok, n, 1))
            import_skip(&st->sys.skips, "x fields");
    } else if (import_eq(k, "VUX") || import_eq(k, "VLX") || import_eq(k, "VUY") ||
               import_eq(k, "VLY")) {
        if (import_any_nonzero(tok, n, 1))
            import_skip(&st->sys.skips, "vignetting factors");
    } else if (import_eq(k, "PIM")) {
        import_skip(&st->sys.skips, "paraxial image solve (thickness as written)");
    } else if (import_eq(k, "PRV")) {
        st->in_prv = 1;
        st->npwl = 0;
    } else if (import_eq(k, "ZOO") || import_eq(k, "POS")) {
        import_skip(&st->sys.skips, "zoom positions");
    } else if (import_eq(k, "CIN") || import_eq(k, "MLT") || import_eq(k, "COA")) {
        import_skip(&st->sys.skips, "coatings");
    } else if (import_eq(k, "TOL")) {
        import_skip(&st->sys.skips, "tolerances");
    } else {
        import_skip_word(&st->sys.skips, "command", k);
    }
    return 0;
#undef NEED_NUM
#undef NEED_SURF
}

/* CODE V fictitious glasses: a six-digit code nnnvvv (n_d = 1.nnn, V_d = vv.v), with an
 * optional ".maker" suffix, or n_d:V_d. Returns 1 when name is one. */
static int all_digits(const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isdigit((unsigned char)s[i]))
            return 0;
    return n > 0;
}

/* CODE V fictitious glasses: a six-digit code nnnvvv (n_d = 1.nnn, V_d = vv.v), with an
 * optional ".maker" suffix; the two-part code nnnnnn.vvvvvv (n_d = 1.nnnnnn,
 * V_d = vv.vvvv, as CODE V writes it; any number of digits on each side); or n_d:V_d.
 * Returns 1 when name is one. Decimal values are formed as integer / power of ten, so
 * 699301 gives n_d 1.699 exactly as written. */
static int fictitious(const char *name, double *nd, double *vd)
{
    const char *colon = strchr(name, ':');
    if (colon) {
        char a[32], b[32];
        size_t la = (size_t)(colon - name);
        if (la == 0 || la >= sizeof a)
            return 0;
        memcpy(a, name, la);
        a[la] = '\0';
        snprintf(b, sizeof b, "%s", colon + 1);
        return parse_double(a, nd) == 0 && parse_double(b, vd) == 0;
    }
    const char *dot = strchr(name, '.');
    size_t ni = dot ? (size_t)(dot - name) : strlen(name);
    if (dot && all_digits(dot + 1, strlen(dot + 1))) {
        size_t nf = strlen(dot + 1);
        if (!all_digits(name, ni) || ni > 9 || nf < 2 || nf > 9)
            return 0;
        *nd = (double)(strtol(name, NULL, 10) + (long)pow(10, (double)ni)) / pow(10, (double)ni);
        *vd = (double)strtol(dot + 1, NULL, 10) / pow(10, (double)nf - 2);
        return 1;
    }
    if (ni != 6 || !all_digits(name, 6))
        return 0;
    long code = strtol(name, NULL, 10); /* six digits: cannot overflow */
    *nd = (double)(1000 + code / 1000) / 1000.0;
    *vd = (double)(code % 1000) / 10.0;
    return 1;
}

static void notes(seq_state *st)
{
    char buf[400];
    size_t o;
    if (st->nyan > 0) {
        o = (size_t)snprintf(buf, sizeof buf, "fields %s:", st->field_kind);
        for (int i = 0; i < st->nyan && o < sizeof buf; i++) {
            int w = snprintf(buf + o, sizeof buf - o, " %g", st->yan[i]);
            if (w < 0)
                break;
            o += (size_t)w;
        }
        lens_add_note(st->sys.lens, "%s", buf);
    }
    if (st->nwl > 0) {
        o = (size_t)snprintf(buf, sizeof buf, "wavelengths (um):");
        for (int i = 0; i < st->nwl && o < sizeof buf; i++) {
            int w = snprintf(buf + o, sizeof buf - o, " %.7g%s", st->wl[i] / 1000.0,
                             i + 1 == st->ref ? " (primary)" : "");
            if (w < 0)
                break;
            o += (size_t)w;
        }
        lens_add_note(st->sys.lens, "%s", buf);
    }
}

/* Heights of a paraxial ray (y0, nu0 = n u in air) at every surface, d line. */
static void trace_heights(const lens_t *lens, const double *n, double y, double nu, double *ys)
{
    double before = 1.0;
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *s = &lens->surf[i];
        ys[i] = y;
        nu -= y * (isfinite(s->radius) ? 1.0 / s->radius : 0.0) * (n[i] - before);
        y += s->thickness * nu / n[i];
        before = n[i];
    }
}

/* CODE V computes clear apertures itself, so .seq files often give no CIR. The
 * unvignetted beam's paraxial footprint stands in: |marginal| + |chief| height, with the
 * marginal ray at EPD/2 and the chief ray through the stop centre at the largest field
 * angle (the axial beam alone when the fields are not angles). */
static int estimate_apertures(seq_state *st, const int *missing, lens_err *err)
{
    lens_t *lens = st->sys.lens;
    size_t ns = lens->nsurf;
    double *buf = malloc(4 * ns * sizeof *buf);
    if (!buf) {
        lens_errf(err, st->sys.path, 0, "out of memory");
        return -1;
    }
    double *n = buf, *ym = buf + ns, *ya = buf + 2 * ns, *yb = buf + 3 * ns;
    for (size_t i = 0; i < ns; i++) {
        lens_err e;
        if (glass_index(&lens->surf[i].medium, GLASS_D_LINE, &n[i], &e) != 0) {
            lens_errf(err, st->sys.path, lens->surf[i].line, "%s", e.msg);
            free(buf);
            return -1;
        }
    }
    trace_heights(lens, n, 1.0, 0.0, yb); /* for the efl and the chief ray */
    double nu_last = 0, y = 1.0, before = 1.0;
    for (size_t i = 0; i < ns; i++) { /* nu after the last surface */
        const lens_surface *s = &lens->surf[i];
        nu_last -= y * (isfinite(s->radius) ? 1.0 / s->radius : 0.0) * (n[i] - before);
        y += s->thickness * nu_last / n[i];
        before = n[i];
    }
    double efl = nu_last != 0 ? -1.0 / nu_last : NAN;
    double epd = isfinite(st->sys.epd) && st->sys.epd > 0 ? st->sys.epd * st->sys.unit
                 : isfinite(st->sys.fno) && st->sys.fno > 0 ? fabs(efl) / st->sys.fno : NAN;
    if (!(epd > 0) || !isfinite(epd)) {
        free(buf);
        int k = 0;
        for (size_t i = 0; i < ns; i++)
            k += missing[i];
        lens_errf(err, st->sys.path, 0,
                  "%d surface%s without a clear aperture (CIR), and no EPD or FNO to compute "
                  "them from",
                  k, k > 1 ? "s" : "");
        return -1;
    }
    trace_heights(lens, n, epd / 2, 0.0, ym);
    double field = 0;
    int angles = strcmp(st->field_kind, "angle (deg)") == 0;
    for (int i = 0; angles && i < st->nyan; i++)
        field = fmax(field, fabs(st->yan[i]));
    if (field >= 90)
        field = 0;
    double nu0 = tan(field * M_PI / 180);
    trace_heights(lens, n, 0.0, nu0, ya);
    int stop = 0;
    for (size_t i = 0; i < ns; i++)
        if (lens->surf[i].is_stop)
            stop = (int)i;
    double y0 = yb[stop] != 0 ? -ya[stop] / yb[stop] : 0;
    int k = 0;
    for (size_t i = 0; i < ns; i++)
        if (missing[i]) {
            lens->surf[i].semi_diameter = fabs(ym[i]) + fabs(ya[i] + y0 * yb[i]);
            k++;
        }
    lens_add_note(lens,
                  "%d clear aperture%s not in the file, set from paraxial rays (EPD %g mm, "
                  "field %g deg)",
                  k, k > 1 ? "s" : "", epd, field);
    free(buf);
    return 0;
}

static int find_private(const seq_state *st, const char *name)
{
    for (int i = 0; i < st->nprv; i++)
        if (import_eq(st->prv[i].name, name))
            return i;
    return -1;
}

static int build(seq_state *st, const lens_load_options *opt, lens_err *err)
{
    lens_t *lens = st->sys.lens;
    for (size_t i = 0; i < st->ns; i++)
        if (st->s[i].refuse[0]) {
            lens_errf(err, st->sys.path, st->s[i].refuse_line, "surface %zu %s", i, st->s[i].refuse);
            return -1;
        }
    size_t first = st->ns && st->s[0].kind == 'O' ? 1 : 0;
    size_t end = st->ns && st->s[st->ns - 1].kind == 'I' ? st->ns - 1 : st->ns;
    if (end <= first) {
        lens_errf(err, st->sys.path, 0, "no lens surfaces (S lines) in the file");
        return -1;
    }
    if (first == 1) {
        const qsurf *o = &st->s[0];
        if (o->glass[0] && !import_eq(o->glass, "AIR")) {
            lens_errf(err, st->sys.path, o->line,
                      "object space is %s, not air; sparselens models lenses in air", o->glass);
            return -1;
        }
        if (isfinite(o->thick) && fabs(o->thick) < SEQ_INFINITE_OBJECT)
            lens_add_note(lens, "object at %g mm in the file; read for an object at infinity",
                        o->thick * st->sys.unit);
    }
    if (end < st->ns && (st->s[end].given_radius ? st->s[end].radius : st->s[end].curv) != 0)
        import_skip(&st->sys.skips, "curved image surface (flat sensor used)");

    import_glass_ctx gl;
    import_glass_init(&gl, opt, st->sys.path);
    double u = st->sys.unit;
    int have_stop = 0, missing_cir = 0;
    int *missing = calloc(end - first, sizeof *missing);
    if (!missing) {
        import_glass_free(&gl);
        lens_errf(err, st->sys.path, 0, "out of memory");
        return -1;
    }
    for (size_t i = first; i < end; i++) {
        const qsurf *q = &st->s[i];
        lens_surface *s = lens_add_surface_at(lens, st->sys.path, q->line, err);
        if (!s) {
            import_glass_free(&gl);
            free(missing);
            return -1;
        }
        if (q->given_radius)
            s->radius = q->radius != 0 ? q->radius * u : INFINITY;
        else
            s->radius = import_radius(q->curv, u);
        s->thickness = q->thick * u;
        s->semi_diameter = q->cir * u;
        missing[lens->nsurf - 1] = !(q->cir > 0);
        missing_cir += !(q->cir > 0);
        s->conic = q->conic;
        for (int a = 0; a < LENS_ASPHERE_TERMS; a++)
            s->asphere[a] = q->asph[a] * pow(u, -(2.0 * a + 3.0));
        s->is_stop = q->stop;
        have_stop |= q->stop;
        double nd, vd;
        int pk;
        if (!q->glass[0] || import_eq(q->glass, "AIR")) {
            s->medium = glass_air();
            strcpy(s->material, "air");
        } else if (fictitious(q->glass, &nd, &vd)) {
            /* A code always carries V_d: 0 there is not "no dispersion" but a bad code. */
            char what[64];
            snprintf(what, sizeof what, "glass %.40s", q->glass);
            if (glass_check_ndvd(nd, vd, what, st->sys.path, q->glass_line, err) != 0 ||
                import_glass_model(s, nd, vd, st->sys.path, q->glass_line, err) != 0) {
                import_glass_free(&gl);
                free(missing);
                return -1;
            }
        } else if ((pk = find_private(st, q->glass)) >= 0) {
            if (st->prv[pk].why[0]) {
                import_glass_free(&gl);
                free(missing);
                lens_errf(err, st->sys.path, q->glass_line, "private glass %s %s", q->glass,
                          st->prv[pk].why);
                return -1;
            }
            if (import_glass_model(s, st->prv[pk].nd, st->prv[pk].vd, st->sys.path, q->glass_line,
                                   err) != 0) {
                import_glass_free(&gl);
                free(missing);
                return -1;
            }
            lens_add_note(lens, "private glass %s as %s%s", q->glass, s->material,
                          st->prv[pk].vd > 0 ? " (n_d/V_d model)" : " (no dispersion)");
        } else if (import_glass_lookup(&gl, q->glass, NAN, NAN, st->sys.path, q->glass_line, s,
                                       err) != 0) {
            import_glass_free(&gl);
            free(missing);
            return -1;
        }
    }
    import_glass_note(&gl, lens);
    import_glass_free(&gl);
    if (!have_stop) {
        lens->surf[0].is_stop = 1;
        lens_add_note(lens, "no STO in the file; the first surface is the stop");
    }
    int missing_stop_cir = missing[lens->stop >= 0 ? lens->stop : 0];
    for (size_t i = 0; i < lens->nsurf; i++)
        if (lens->surf[i].is_stop)
            missing_stop_cir = missing[i];
    int rc = missing_cir ? estimate_apertures(st, missing, err) : 0;
    free(missing);
    if (rc != 0)
        return -1;
    notes(st);
    return import_finish(lens, &st->sys.skips, st->sys.fno, "FNO", st->sys.epd * u, "EPD", !missing_stop_cir,
                         err);
}

int lens_parse_seq(const char *data, size_t len, const char *path,
                   const lens_load_options *opt, lens_t *lens, lens_err *err)
{
    seq_state st;
    memset(&st, 0, sizeof st);
    char *text = import_begin(data, len, path, "CODE V", lens, &st.sys, err);
    if (!text)
        return -1;

    import_lines it = {text, 0};
    char *line, *tok[SEQ_MAX_TOK];
    int rc = 0;
    /* Lines are at most LINE_MAX_BYTES (import_begin checks), continued ones too. */
    const size_t room = LINE_MAX_BYTES + 1;
    char *joined = malloc(room);
    if (!joined) {
        lens_errf(err, path, 0, "out of memory");
        rc = -1;
    }
    while (rc == 0 && (line = import_next_line(&it))) {
        /* A line ending in '&' continues on the next. */
        long first = it.line;
        snprintf(joined, room, "%s", line);
        for (;;) {
            size_t len = strlen(joined);
            while (len && isspace((unsigned char)joined[len - 1]))
                len--;
            if (!len || joined[len - 1] != '&')
                break;
            joined[len - 1] = ' ';
            joined[len] = '\0';
            char *more = import_next_line(&it);
            if (!more)
                break;
            if (len + strlen(more) + 2 >= room) {
                lens_errf(err, path, first, "continued line longer than %d bytes",
                          LINE_MAX_BYTES);
                rc = -1;
                break;
            }
            strcat(joined, " ");
            strcat(joined, more);
        }
        if (rc != 0)
            break;
        /* Split at ';' outside quotes; each piece is one command. */
        char *p = joined;
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
                *q = '\0'; /* a comment runs to the end of the line */
            }
            int n = import_tokens(p, tok, SEQ_MAX_TOK);
            if (n > 0)
                rc = command(&st, tok, n, first, err);
            p = next;
        }
    }
    free(joined);
    if (rc == 0)
        rc = build(&st, opt, err);
    free(st.s);
    free(text);
    if (rc != 0)
        lens_free(lens);
    return rc;
}

int lens_read_seq(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                  lens_err *err)
{
    return import_read_parse(f, path, opt, lens, err, lens_parse_seq);
}
