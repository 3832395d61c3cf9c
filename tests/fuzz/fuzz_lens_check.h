/* What every lens reader's fuzz target checks once a lens was accepted: it writes in
 * the native format and reads back to the same surfaces (and the written text is a fixed
 * point), and the exact tracer, given a few sensor rays, never reports a passed ray with
 * a non-finite output (design.md: NaN never reaches an output unannounced). */
#ifndef SPARSELENS_FUZZ_LENS_CHECK_H
#define SPARSELENS_FUZZ_LENS_CHECK_H
#include <math.h>

#include "fuzz_common.h"
#include "sparselens/lens.h"
#include "sparselens/paraxial.h"
#include "sparselens/trace.h"

static inline char *fuzz_lens_text(const lens_t *lens, size_t *len)
{
    char *text = NULL;
    FILE *m = open_memstream(&text, len);
    FUZZ_CHECK(m != NULL);
    lens_write(m, lens);
    fclose(m);
    return text;
}

/* Reads text back as a native lens (aborts if it does not read). */
static inline void fuzz_reread(const char *text, size_t len, const lens_load_options *opt,
                               lens_t *back)
{
    fuzz_stream s;
    lens_err err;
    FUZZ_CHECK(fuzz_stream_open(&s, (const uint8_t *)text, len) == 0);
    int rc = lens_read_native(s.f, "roundtrip.lens", opt, back, &err);
    fuzz_stream_close(&s);
    if (rc != 0)
        fprintf(stderr, "written lens does not read back: %s\n---\n%s---\n", err.msg, text);
    FUZZ_CHECK(rc == 0);
}

/* Surfaces equal bit for bit (numbers are written so that they read back exactly). */
static inline int fuzz_same_surface(const lens_surface *a, const lens_surface *b)
{
    if (memcmp(&a->radius, &b->radius, sizeof a->radius) ||
        memcmp(&a->thickness, &b->thickness, sizeof a->thickness) ||
        memcmp(&a->semi_diameter, &b->semi_diameter, sizeof a->semi_diameter) ||
        a->conic != b->conic || a->is_stop != b->is_stop)
        return 0;
    for (int k = 0; k < LENS_ASPHERE_TERMS; k++)
        if (a->asphere[k] != b->asphere[k])
            return 0;
    return 1;
}

static inline void fuzz_check_lens(const lens_t *lens, const lens_load_options *opt)
{
    /* write, read back: the same surfaces; write again, read, write: the same text (the
     * header may be normalised once, e.g. trailing blanks of a name, never the numbers) */
    size_t len1 = 0, len2 = 0, len3 = 0;
    char *t1 = fuzz_lens_text(lens, &len1);
    lens_t back, back2;
    fuzz_reread(t1, len1, opt, &back);
    FUZZ_CHECK(back.nsurf == lens->nsurf);
    FUZZ_CHECK(back.stop == lens->stop);
    for (size_t i = 0; i < lens->nsurf; i++)
        FUZZ_CHECK(fuzz_same_surface(&lens->surf[i], &back.surf[i]));
    char *t2 = fuzz_lens_text(&back, &len2);
    fuzz_reread(t2, len2, opt, &back2);
    char *t3 = fuzz_lens_text(&back2, &len3);
    FUZZ_CHECK(len2 == len3 && memcmp(t2, t3, len2) == 0);
    free(t1);
    free(t2);
    free(t3);
    lens_free(&back);
    lens_free(&back2);
    lens_err err;

    paraxial_data p;
    (void)paraxial_compute(lens, GLASS_D_LINE, &p, &err);

    double *n = malloc(lens->nsurf * sizeof *n);
    FUZZ_CHECK(n != NULL);
    if (lens_indices(lens, GLASS_D_LINE, n, &err) == 0) {
        const double rays[][4] = {{0, 0, 0, 0}, {0, 0, 0.05, 0}, {1, 0.5, -0.1, 0.02},
                                  {5, -3, 0.3, 0.4}, {0, 0, 1e3, 0}};
        for (size_t i = 0; i < sizeof rays / sizeof *rays; i++)
            for (int target = 0; target < 2; target++) {
                double out[4];
                trace_result r = trace_sample(lens, n, target ? TRACE_TO_STOP : TRACE_TO_OUTER,
                                              rays[i], out);
                if (r.status == TRACE_PASSED) {
                    for (int k = 0; k < 4; k++)
                        FUZZ_CHECK(isfinite(out[k]));
                    FUZZ_CHECK(r.transmittance >= 0 && r.transmittance <= 1);
                }
            }
    }
    free(n);
}

/* The whole target for a stream lens reader with lens_read_native's signature: the
 * shipped glass catalog, one read per input, and on success the lens checks above;
 * on failure the error must be one non-empty line. */
#define FUZZ_LENS_READER_TARGET(reader, name)                                             \
    int LLVMFuzzerInitialize(int *argc, char ***argv)                                     \
    {                                                                                     \
        (void)argc;                                                                       \
        (void)argv;                                                                       \
        fuzz_use_shipped_catalog();                                                       \
        return 0;                                                                         \
    }                                                                                     \
    int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)                          \
    {                                                                                     \
        fuzz_stream s;                                                                    \
        if (fuzz_stream_open(&s, data, size))                                             \
            return 0;                                                                     \
        lens_t lens;                                                                      \
        lens_err err;                                                                     \
        lens_init(&lens);                                                                 \
        int rc = reader(s.f, name, NULL, &lens, &err);                                    \
        fuzz_stream_close(&s);                                                            \
        if (rc == 0)                                                                      \
            fuzz_check_lens(&lens, NULL);                                                 \
        else                                                                              \
            FUZZ_CHECK(err.msg[0] != 0 && strchr(err.msg, '\n') == NULL);                 \
        lens_free(&lens);                                                                 \
        return 0;                                                                         \
    }

#endif
