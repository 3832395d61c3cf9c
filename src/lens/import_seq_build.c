/* CODE V .seq reader, second half: the lens built from the surfaces and system data
 * import_seq.c read (glass codes, private glasses, catalog glasses; clear apertures from
 * paraxial rays where the file gives none, import_aperture.c; the fields, wavelengths
 * and notes). */
#include "lens/import_seq.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/numparse.h"

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

static int find_private(const seq_state *st, const char *name)
{
    for (int i = 0; i < st->nprv; i++)
        if (import_eq(st->prv[i].name, name))
            return i;
    return -1;
}

/* The medium after surface q into s: air, a fictitious glass code, a private glass or a
 * catalog glass. */
static int surface_glass(seq_state *st, import_glass_ctx *gl, const qsurf *q, lens_surface *s,
                         lens_err *err)
{
    const char *path = st->sys.path;
    double nd, vd;
    int pk;
    if (!q->glass[0] || import_eq(q->glass, "AIR")) {
        s->medium = glass_air();
        strcpy(s->material, "air");
        return 0;
    }
    if (fictitious(q->glass, &nd, &vd)) {
        /* A code always carries V_d: 0 there is not "no dispersion" but a bad code. */
        char what[64];
        snprintf(what, sizeof what, "glass %.40s", q->glass);
        if (glass_check_ndvd(nd, vd, what, path, q->glass_line, err) != 0)
            return -1;
        return import_glass_model(s, nd, vd, path, q->glass_line, err);
    }
    if ((pk = find_private(st, q->glass)) >= 0) {
        const seq_private_glass *g = &st->prv[pk];
        if (g->why[0]) {
            lens_errf(err, path, q->glass_line, "private glass %s %s", q->glass, g->why);
            return -1;
        }
        if (g->tabulated) {
            s->medium = g->glass;
            s->medium.embedded = 1; /* in no catalog: a lens file written carries it */
            snprintf(s->medium.name, sizeof s->medium.name, "%s", q->glass);
            snprintf(s->material, sizeof s->material, "%s", q->glass);
            lens_add_note(st->sys.lens, "private glass %s: the Schott formula fitted to its "
                          "indices over %g-%g um (largest misfit %.2g)", q->glass,
                          g->glass.lambda_min, g->glass.lambda_max, g->residual);
            return 0;
        }
        if (import_glass_model(s, g->nd, g->vd, path, q->glass_line, err) != 0)
            return -1;
        lens_add_note(st->sys.lens, "private glass %s as %s%s", q->glass, s->material,
                      g->vd > 0 ? " (n_d/V_d model)" : " (no dispersion)");
        return 0;
    }
    return import_glass_lookup(gl, q->glass, NAN, NAN, path, q->glass_line, s, err);
}

/* The lens surfaces st->s[first..end) appended to the lens; missing[i] set where lens
 * surface i has no clear aperture (CIR) in the file. */
static int add_surfaces(seq_state *st, const lens_load_options *opt, size_t first, size_t end,
                        int *missing, lens_err *err)
{
    lens_t *lens = st->sys.lens;
    import_glass_ctx gl;
    import_glass_init(&gl, opt, st->sys.path);
    double u = st->sys.unit;
    int have_stop = 0, rc = 0;
    for (size_t i = first; i < end && rc == 0; i++) {
        const qsurf *q = &st->s[i];
        lens_surface *s = lens_add_surface_at(lens, st->sys.path, q->line, err);
        if (!s) {
            rc = -1;
            break;
        }
        if (q->given_radius)
            s->radius = q->radius != 0 ? q->radius * u : INFINITY;
        else
            s->radius = import_radius(q->curv, u);
        s->thickness = q->thick * u;
        s->semi_diameter = q->cir * u;
        missing[lens->nsurf - 1] = !(q->cir > 0);
        s->conic = q->conic;
        for (int a = 0; a < LENS_ASPHERE_TERMS; a++)
            s->asphere[a] = q->asph[a] * pow(u, -(2.0 * a + 3.0));
        s->is_stop = q->stop;
        have_stop |= q->stop;
        rc = surface_glass(st, &gl, q, s, err);
    }
    if (rc == 0) {
        import_glass_note(&gl, lens);
        if (!have_stop) {
            lens->surf[0].is_stop = 1;
            lens_add_note(lens, "no STO in the file; the first surface is the stop");
        }
    }
    import_glass_free(&gl);
    return rc;
}

/* Refused surfaces, the object surface and the image surface: the range [*first, *end)
 * of lens surfaces in st->s. */
static int check_surfaces(seq_state *st, size_t *first, size_t *end, lens_err *err)
{
    lens_t *lens = st->sys.lens;
    for (size_t i = 0; i < st->ns; i++)
        if (st->s[i].refuse[0]) {
            lens_errf(err, st->sys.path, st->s[i].refuse_line, "surface %zu %s", i,
                      st->s[i].refuse);
            return -1;
        }
    *first = st->ns && st->s[0].kind == 'O' ? 1 : 0;
    *end = st->ns && st->s[st->ns - 1].kind == 'I' ? st->ns - 1 : st->ns;
    if (*end <= *first) {
        lens_errf(err, st->sys.path, 0, "no lens surfaces (S lines) in the file");
        return -1;
    }
    if (*first == 1) {
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
    const qsurf *img = &st->s[*end];
    if (*end < st->ns && (img->given_radius ? img->radius : img->curv) != 0)
        import_skip(&st->sys.skips, "curved image surface (flat sensor used)");
    return 0;
}

int seq_build(void *state, const lens_load_options *opt, lens_err *err)
{
    seq_state *st = state;
    lens_t *lens = st->sys.lens;
    size_t first, end;
    if (check_surfaces(st, &first, &end, err) != 0)
        return -1;
    int *missing = calloc(end - first, sizeof *missing);
    if (!missing) {
        lens_errf(err, st->sys.path, 0, "out of memory");
        return -1;
    }
    int rc = add_surfaces(st, opt, first, end, missing, err), missing_cir = 0;
    int missing_stop_cir = rc == 0 ? missing[lens->stop >= 0 ? lens->stop : 0] : 0;
    for (size_t i = 0; rc == 0 && i < lens->nsurf; i++) {
        missing_cir += missing[i];
        if (lens->surf[i].is_stop)
            missing_stop_cir = missing[i];
    }
    double um[SEQ_MAX_LIST];
    for (int i = 0; i < st->nwl; i++)
        um[i] = st->wl[i] / 1000;
    if (rc == 0)
        rc = import_set_fields(lens, st->fkind, NULL, 0, st->yan, st->nyan, err);
    if (rc == 0)
        rc = import_set_waves(lens, um, st->nwtw == st->nwl ? st->wtw : NULL, st->nwl, st->ref,
                              err);
    if (rc == 0 && missing_cir)
        rc = import_size_apertures(lens, missing, st->sys.epd * st->sys.unit, st->sys.fno,
                                   "CIR", "EPD or FNO", err);
    free(missing);
    if (rc != 0)
        return -1;
    import_fields_note(lens, st->field_kind, NULL, 0, st->yan, st->nyan);
    import_waves_note(lens, st->wl, st->nwl, 1000, st->ref);
    return import_finish(lens, &st->sys.skips, st->sys.fno, "FNO", st->sys.epd * st->sys.unit,
                         "EPD", !missing_stop_cir, err);
}
