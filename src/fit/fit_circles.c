/* Pass circles that decide nothing (fit.h: fit_options.drop_circles). The pilot of
 * lens-trace picks the surfaces a system models greedily, with each rim at its
 * semi-diameter; a fitted system's circle sits at the furthest hit of the passing rays
 * instead, which can lie well inside the rim when a neighbour vignettes first, and then
 * that circle does the neighbour's work. A surface chosen early can so end up blocking
 * nothing the others do not (fisheye-ii's 9 beside 8, dgauss.50mm's 2 and 7): two
 * outputs and 15-40 terms in every evaluation, for no ray. Judged on the training rows
 * with the fitted system itself, so that what is dropped is what that system does: a
 * circle goes when no row the lens blocks is blocked by it alone. Not "when it blocks
 * no more rays rightly than wrongly": that also let circles go that did block rays,
 * and a coarse passage lost what little it had (fisheye-ii at --passage-tolerance 0.03
 * dropped s8, which alone blocked 144 rows the lens blocks and 317 it passes: the worst
 * ring's light in dispute 9.6% -> 36%). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/fit.h"
#include "fit/fit_internal.h"

/* Circle c may be dropped: a pair of hits on a surface sN, not the stop's (lens-render
 * reads ap_x ap_y for the aperture's blades) nor the front's out_x out_y (no outputs of
 * its own). */
static int droppable(const poly_system *sys, int c)
{
    int a, b;
    double radius;
    poly_get_pass_circle(sys, c, &a, &b, &radius);
    const char *name = poly_output_name(sys, a);
    return name[0] == 's' && fit_is_passage_output(name);
}

/* The circles that block each row (count x nc flags) and the rows the system blocks
 * for another reason (an output not finite): other[r]. -1 when out of memory. */
static int census(const poly_system *sys, size_t count, const double *in, unsigned char *blocks,
                  unsigned char *other)
{
    int nout = poly_noutputs(sys), nc = poly_npass_circles(sys);
    double *out = malloc((count ? count : 1) * (size_t)nout * sizeof *out);
    unsigned char *pass = malloc(count ? count : 1);
    if (!out || !pass) {
        free(out);
        free(pass);
        return -1;
    }
    poly_eval_batch(sys, count, in, out, pass);
    for (size_t r = 0; r < count; r++) {
        const double *o = out + r * (size_t)nout;
        int any = 0;
        for (int c = 0; c < nc; c++) {
            int a, b;
            double radius;
            poly_get_pass_circle(sys, c, &a, &b, &radius);
            blocks[r * (size_t)nc + c] = !(o[a] * o[a] + o[b] * o[b] <= radius * radius);
            any |= blocks[r * (size_t)nc + c];
        }
        other[r] = !pass[r] && !any;
    }
    free(out);
    free(pass);
    return 0;
}

poly_system *fit_drop_circles(poly_system *sys, size_t count, const double *in,
                              const unsigned char *lens_pass)
{
    int nc = poly_npass_circles(sys), nout = poly_noutputs(sys), ndrop = 0, judged = 0;
    /* the lens's verdict is known only from an output that a blocked ray lacks (a
     * passage hit exists on both sides of its rim), and only with blocked rows */
    for (int o = 0; o < nout; o++)
        judged |= !fit_is_passage_output(poly_output_name(sys, o));
    size_t nblocked = 0;
    for (size_t row = 0; row < count; row++)
        nblocked += !lens_pass[row];
    if (!judged || nblocked == 0)
        return sys;
    unsigned char *blocks = malloc((count ? count : 1) * (size_t)(nc ? nc : 1));
    unsigned char *other = malloc(count ? count : 1), *kept = malloc((size_t)nc + 1);
    unsigned char *keep = malloc((size_t)nout);
    long *alone = calloc(2 * (size_t)nc + 2, sizeof *alone);
    char note[1024] = "";
    poly_system *r = NULL;
    if (!blocks || !other || !kept || !keep || !alone || census(sys, count, in, blocks, other) != 0)
        goto done;
    memset(kept, 1, (size_t)nc + 1);
    for (;;) {
        /* per circle, the rows it alone blocks: the lens blocks them too (they would
         * pass falsely without it) or passes them (they would pass rightly) */
        memset(alone, 0, (2 * (size_t)nc + 2) * sizeof *alone);
        for (size_t row = 0; row < count; row++) {
            const unsigned char *b = blocks + row * (size_t)nc;
            int only = -1, n = 0;
            for (int c = 0; c < nc && n < 2 && !other[row]; c++)
                if (b[c] && kept[c])
                    only = c, n++;
            if (n == 1)
                alone[2 * only + (lens_pass[row] != 0)]++;
        }
        /* of those that alone block no row the lens blocks, the one that blocks most
         * rows it passes; then the others are counted again without it (two circles
         * that do each other's work: one of them goes) */
        int least = -1;
        for (int c = 0; c < nc; c++)
            if (kept[c] && droppable(sys, c) && alone[2 * c] == 0 &&
                (least < 0 || alone[2 * c + 1] > alone[2 * least + 1]))
                least = c;
        if (least < 0)
            break;
        kept[least] = 0;
        ndrop++;
        int a, b;
        double radius;
        poly_get_pass_circle(sys, least, &a, &b, &radius);
        size_t l = strlen(note);
        const char *name = poly_output_name(sys, a);
        snprintf(note + l, sizeof note - l, "%s%.*s (alone it blocks none of the %zu rows "
                 "the lens blocks, %ld it passes)", l ? ", " : "", (int)strlen(name) - 2, name,
                 nblocked, alone[2 * least + 1]);
    }
    if (ndrop == 0) {
        r = sys;
        goto done;
    }
    memset(keep, 1, (size_t)nout);
    for (int c = 0; c < nc; c++)
        if (!kept[c]) {
            int a, b;
            double radius;
            poly_get_pass_circle(sys, c, &a, &b, &radius);
            keep[a] = keep[b] = 0;
        }
    r = poly_copy_outputs(sys, keep);
    if (r) {
        char val[1200];
        snprintf(val, sizeof val, "%s; of %zu rows", note, count);
        poly_set_meta(r, "fit_dropped_circles", val);
        poly_free(sys);
    }
done:
    free(blocks);
    free(other);
    free(kept);
    free(keep);
    free(alone);
    return r;
}
