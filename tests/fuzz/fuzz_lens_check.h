/* What every lens reader's fuzz target checks once a lens was accepted: it writes in
 * the native format and reads back to the same surfaces (and the written text is a fixed
 * point), and the exact tracer, given a few sensor rays, never reports a passed ray with
 * a non-finite output (design.md: NaN never reaches an output unannounced). */
#ifndef SPARSELENS_FUZZ_LENS_CHECK_H
#define SPARSELENS_FUZZ_LENS_CHECK_H
#include <math.h>

#include "fuzz_common.h"
#include "lens.h"
#include "paraxial.h"
#include "trace.h"

static inline char *fuzz_lens_text(const lens_t *lens, size_t *len)
{
    char *text = NULL;
    FILE *m = open_memstream(&text, len);
    FUZZ_CHECK(m != NULL);
    lens_write(m, lens);
    fclose(m);
    return text;
}

static inline void fuzz_check_lens(const lens_t *lens, const lens_load_options *opt)
{
    size_t len1 = 0, len2 = 0;
    char *t1 = fuzz_lens_text(lens, &len1);
    fuzz_stream s;
    FUZZ_CHECK(fuzz_stream_open(&s, (const uint8_t *)t1, len1) == 0);
    lens_t back;
    lens_err err;
    int rc = lens_read_native(s.f, "roundtrip.lens", opt, &back, &err);
    fuzz_stream_close(&s);
    if (rc != 0)
        fprintf(stderr, "written lens does not read back: %s\n---\n%s---\n", err.msg, t1);
    FUZZ_CHECK(rc == 0);
    FUZZ_CHECK(back.nsurf == lens->nsurf);
    FUZZ_CHECK(back.stop == lens->stop);
    char *t2 = fuzz_lens_text(&back, &len2);
    FUZZ_CHECK(len1 == len2 && memcmp(t1, t2, len1) == 0);
    free(t1);
    free(t2);
    lens_free(&back);

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

#endif
