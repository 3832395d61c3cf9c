/* Helpers shared by the importer tests: an independent first-order calculation from a
 * prescription table (2x2 matrices written out here, not paraxial.c's), and surface
 * comparisons. Included by test_import_*.c only. */
#ifndef IMPORT_CHECK_H
#define IMPORT_CHECK_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/glass.h"
#include "sparselens/lens.h"
#include "sparselens/paraxial.h"

#define DATA "tests/data/import/"

/* Focal length and back focal length of the surfaces R[i] (0 = flat), thicknesses t[i]
 * and indices n[i] after each surface, in air: the system matrix M = product of
 * refraction [[1,0],[-(n'-n)/R,1]] and transfer [[1,t/n],[0,1]] matrices acting on
 * (y, n u); efl = -1/C and bfl = -A/C. */
static inline void table_first_order(int ns, const double *R, const double *t, const double *n,
                              double *efl, double *bfl)
{
    double A = 1, B = 0, C = 0, D = 1, before = 1;
    for (int i = 0; i < ns; i++) {
        double phi = R[i] != 0 ? (n[i] - before) / R[i] : 0;
        /* refraction: [[1,0],[-phi,1]] * M */
        C -= phi * A;
        D -= phi * B;
        if (i + 1 < ns) { /* transfer: [[1,t/n],[0,1]] * M */
            A += t[i] / n[i] * C;
            B += t[i] / n[i] * D;
        }
        before = n[i];
    }
    (void)B;
    (void)D;
    *efl = -1 / C;
    *bfl = -A / C;
}

static inline paraxial_data first_order(const lens_t *lens)
{
    paraxial_data p;
    lens_err err;
    if (paraxial_compute(lens, GLASS_D_LINE, &p, &err) != 0)
        fail_msg("paraxial_compute: %s", err.msg);
    return p;
}

static inline int near_rel(double a, double b, double rel)
{
    return fabs(a - b) <= rel * fabs(b);
}

#define assert_near(a, b, tol)                                                             \
    do {                                                                                   \
        double a_ = (a), b_ = (b);                                                         \
        if (!(fabs(a_ - b_) <= (tol)))                                                     \
            fail_msg("%s = %.12g, expected %.12g (tol %g)", #a, a_, b_, (double)(tol));    \
    } while (0)

static inline char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        fail_msg("cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    if (!buf || fread(buf, 1, (size_t)n, f) != (size_t)n)
        fail_msg("cannot read %s", path);
    fclose(f);
    buf[n] = '\0';
    *len = (size_t)n;
    return buf;
}

/* Two readings of one design must agree surface by surface. */
static inline void assert_same_lens(const lens_t *a, const lens_t *b, double tol)
{
    assert_int_equal(a->nsurf, b->nsurf);
    assert_int_equal(a->stop, b->stop);
    for (size_t i = 0; i < a->nsurf; i++) {
        const lens_surface *x = &a->surf[i], *y = &b->surf[i];
        double cx = isfinite(x->radius) ? 1 / x->radius : 0, cy = isfinite(y->radius) ? 1 / y->radius : 0;
        if (fabs(cx - cy) > tol * 1e-2 || fabs(x->thickness - y->thickness) > tol ||
            fabs(x->semi_diameter - y->semi_diameter) > tol || fabs(x->conic - y->conic) > tol ||
            fabs(x->medium.nd - y->medium.nd) > 1e-9 || x->medium.kind != y->medium.kind)
            fail_msg("surface %zu differs: R %g/%g t %g/%g sd %g/%g nd %g/%g", i + 1, x->radius,
                     y->radius, x->thickness, y->thickness, x->semi_diameter, y->semi_diameter,
                     x->medium.nd, y->medium.nd);
        for (int k = 0; k < LENS_ASPHERE_TERMS; k++)
            if (fabs(x->asphere[k] - y->asphere[k]) > 1e-12 * (1 + fabs(x->asphere[k])))
                fail_msg("surface %zu: a%d %g vs %g", i + 1, 2 * k + 4, x->asphere[k],
                         y->asphere[k]);
    }
}


/* Cuts of a design file at about 23 places: each prefix parses to a lens or to a message,
 * never a crash (the sanitizer build checks the memory side). */
typedef int (*check_parser)(const char *data, size_t len, const char *path,
                            const lens_load_options *opt, lens_t *lens, lens_err *err);
static inline void check_truncations(check_parser parse, const char *path, const char *data,
                                     size_t len, const lens_load_options *opt)
{
    size_t step = len / 23 + 1;
    for (size_t cut = 0; cut < len; cut += step) {
        lens_t lens;
        lens_err err;
        if (parse(data, cut, path, opt, &lens, &err) == 0)
            lens_free(&lens);
        else
            assert_true(strlen(err.msg) > 0);
    }
}

#endif
