/* Stop hits for the ap_x, ap_y sample columns: the stop frame of the tracer
 * (TRACE_TO_STOP) already positions a ray on the stop surface, so both functions reuse
 * it and keep only the position. */
#include <math.h>
#include <stdlib.h>

#include "sparselens/trace.h"
#include "sparselens/trace_stop.h"

int trace_stop_hit(const lens_t *lens, const double *n, const double in[4], double ap[2])
{
    double out[4];
    trace_result res = trace_sample(lens, n, TRACE_TO_STOP, in, out);
    int ok = res.status == TRACE_PASSED && isfinite(out[0]) && isfinite(out[1]);
    ap[0] = ok ? out[0] : NAN;
    ap[1] = ok ? out[1] : NAN;
    return ok;
}

int trace_stop_batch(const lens_t *lens, size_t count, const double *in, double *ap,
                     int threads, lens_err *err)
{
    double *out = malloc((count ? count : 1) * 5 * sizeof *out);
    if (!out) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int rc = trace_batch(lens, TRACE_TO_STOP, count, in, out, NULL, threads, err);
    for (size_t i = 0; i < count; i++) {
        /* out_eta > 0 exactly when the ray reached the stop inside its semi-diameter. */
        int ok = out[5 * i + 4] > 0 && isfinite(out[5 * i]) && isfinite(out[5 * i + 1]);
        ap[2 * i] = ok ? out[5 * i] : NAN;
        ap[2 * i + 1] = ok ? out[5 * i + 1] : NAN;
    }
    free(out);
    return rc;
}
