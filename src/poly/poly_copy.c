/* A system copied with some of its outputs (poly.h: poly_copy_outputs). */
#include "poly/poly_impl.h"

#include <stdlib.h>
#include <string.h>

/* 1 when meta key belongs to an output left out: fit_NAME or part_jump_NAME, not one of
 * lens-fit's keys about the whole fit (an output may be called "flags"). */
static int meta_of_dropped(const poly_system *s, const unsigned char *keep, const char *key)
{
    static const char *const whole[] = {"fit_flags", "fit_samples", "fit_parts",
                                        "fit_dropped_circles"};
    for (size_t k = 0; k < sizeof whole / sizeof *whole; k++)
        if (!strcmp(key, whole[k]))
            return 0;
    for (int o = 0; keep && o < poly_noutputs(s); o++) {
        if (keep[o])
            continue;
        const char *name = poly_output_name(s, o);
        size_t n = strlen(name), k = strlen(key);
        if (k > n && !strcmp(key + k - n, name) &&
            ((k == n + 4 && !strncmp(key, "fit_", 4)) || (k == n + 10 && !strncmp(key, "part_jump_", 10))))
            return 1;
    }
    return 0;
}

poly_system *poly_copy_outputs(const poly_system *s, const unsigned char *keep)
{
    int nin = poly_ninputs(s), nout = poly_noutputs(s), nk = 0;
    const char **in = malloc((size_t)nin * sizeof *in), **out = malloc((size_t)nout * sizeof *out);
    int *to = malloc((size_t)nout * sizeof *to), *ex = malloc((size_t)nin * sizeof *ex);
    poly_system *r = NULL;
    if (!in || !out || !to || !ex)
        goto done;
    for (int i = 0; i < nin; i++)
        in[i] = poly_input_name(s, i);
    for (int o = 0; o < nout; o++) {
        to[o] = !keep || keep[o] ? nk : -1;
        if (to[o] >= 0)
            out[nk++] = poly_output_name(s, o);
    }
    r = nk > 0 ? poly_new(poly_lens_name(s), nin, in, nk, out) : NULL;
    if (!r)
        goto done;
    poly_bulk_begin(r); /* planned once, at the end */
    int bad = poly_set_frame(r, poly_get_frame(s)) != 0;
    if (poly_lens_path(s)[0])
        poly_set_lens_path(r, poly_lens_path(s));
    for (int i = 0; i < nin; i++) {
        double a, b;
        bad |= poly_set_transform(r, i, poly_get_transform(s, i)) != 0;
        poly_get_scaling(s, i, &a, &b);
        poly_set_scaling(r, i, a, b);
        poly_get_domain(s, i, &a, &b);
        poly_set_domain(r, i, a, b);
    }
    for (int o = 0; o < nout; o++)
        if (to[o] >= 0 && poly_get_output_plain(s, o))
            bad |= poly_set_output_plain(r, to[o], 1) != 0;
    for (int p = 0; p < poly_nparts(s) && !bad; p++) {
        double r0, r1;
        poly_part_range(s, p, &r0, &r1);
        int q = poly_add_part(r, r0, r1);
        bad |= q < 0;
        for (int o = 0; o < nout && !bad; o++)
            for (int t = 0; to[o] >= 0 && t < poly_nterms(s, p, o) && !bad; t++) {
                double c;
                poly_get_term(s, p, o, t, ex, &c);
                bad |= poly_add_term(r, q, to[o], ex, c) != 0;
            }
    }
    for (int c = 0; c < poly_npass_circles(s) && !bad; c++) {
        int a, b;
        double radius;
        poly_get_pass_circle(s, c, &a, &b, &radius);
        if (to[a] >= 0 && to[b] >= 0)
            bad |= poly_add_pass_circle(r, to[a], to[b], radius) != 0;
    }
    for (int m = 0; m < poly_nmeta(s); m++) {
        const char *key = poly_meta_key(s, m);
        if (!meta_of_dropped(s, keep, key))
            poly_set_meta(r, key, poly_get_meta(s, key));
    }
    if (bad || poly_bulk_end(r) != 0) {
        poly_free(r);
        r = NULL;
    }
done:
    free(in);
    free(out);
    free(to);
    free(ex);
    return r;
}
