/* Exact sequential tracing through a lens_t (conventions: trace.h, lens.h). */
#include "sparselens/trace.h"

#include <math.h>

#include "sparselens/intersect.h"
#include "sparselens/refract.h"
#include "trace/trace_core.h"
#include "sparselens/trace_packet.h"

const char *trace_status_name(trace_status s)
{
    switch (s) {
    case TRACE_PASSED: return "passed";
    case TRACE_MISSED: return "missed";
    case TRACE_CLIPPED: return "clipped";
    case TRACE_STOPPED: return "stopped";
    case TRACE_TIR: return "tir";
    case TRACE_INVALID: return "invalid";
    }
    return "unknown";
}

static trace_result stopped(trace_status st, int surface)
{
    trace_result res = {st, surface, 0.0};
    return res;
}

trace_result trace_path(const lens_t *lens, const double *n, lens_ray *r, int first, int last,
                        int refract_last, int clip)
{
    if (!isfinite(r->o[0]) || !isfinite(r->o[1]) || !isfinite(r->o[2]) ||
        !isfinite(r->d[0]) || !isfinite(r->d[1]) || !isfinite(r->d[2]))
        return stopped(TRACE_INVALID, first);
    int step = first > last ? -1 : 1;
    double eta = 1.0;
    for (int i = first;; i += step) {
        const lens_surface *s = &lens->surf[i];
        double sd = s->semi_diameter;
        double t, p[3], nrm[3];
        isect_status is = intersect_surface(s, lens->vertex_z[i], r->o, r->d,
                                            clip ? sd * sd : INFINITY, &t, p, nrm);
        if (is == ISECT_MISS)
            return stopped(TRACE_MISSED, i);
        if (is == ISECT_OUTSIDE)
            return stopped(i == lens->stop ? TRACE_STOPPED : TRACE_CLIPPED, i);
        r->o[0] = p[0];
        r->o[1] = p[1];
        r->o[2] = p[2];
        if (i == last && !refract_last)
            break;
        /* Index on the side the ray comes from, and on the side it goes to. */
        double nafter = n[i], nbefore = i > 0 ? n[i - 1] : 1.0;
        double n1 = step > 0 ? nbefore : nafter, n2 = step > 0 ? nafter : nbefore;
        if (n1 != n2) {
            double T;
            if (refract(r->d, nrm, n1, n2, r->d, &T))
                return stopped(TRACE_TIR, i);
            eta *= T;
        }
        if (i == last)
            break;
    }
    trace_result res = {TRACE_PASSED, -1, eta};
    return res;
}

trace_result trace_to_object(const lens_t *lens, const double *n, lens_ray *r, int last)
{
    if (last < 0 || (size_t)last >= lens->nsurf)
        return stopped(TRACE_INVALID, -1);
    /* One lane of the packet tracer, so that single rays and batches agree bit for bit. */
    trace_result res;
    trace_packet_to_object(lens, &n, 1, r, last, &res, NULL);
    return res;
}

trace_result trace_to_sensor(const lens_t *lens, const double *n, lens_ray *r)
{
    int ns = (int)lens->nsurf;
    trace_result res = trace_path(lens, n, r, 0, ns - 1, 1, 1);
    if (res.status != TRACE_PASSED)
        return res;
    /* On to the sensor plane. */
    double zs = lens_total_track(lens);
    if (!(r->d[2] > 0))
        return stopped(TRACE_MISSED, ns);
    double t = (zs - r->o[2]) / r->d[2];
    r->o[0] += t * r->d[0];
    r->o[1] += t * r->d[1];
    r->o[2] = zs;
    return res;
}

trace_result trace_sample(const lens_t *lens, const double *n, trace_target target,
                          const double in[4], double out[4])
{
    lens_ray r;
    ray_from_sensor(lens, in, &r);
    trace_result res;
    double outer[4];
    if (target == TRACE_TO_STOP) {
        res = trace_to_object(lens, n, &r, lens->stop);
        return trace_sample_finish(lens, target, &r, NULL, res, out);
    }
    trace_packet_to_object(lens, &n, 1, &r, 0, &res, outer);
    return trace_sample_finish(lens, target, &r, outer, res, out);
}

trace_result trace_sample_finish(const lens_t *lens, trace_target target, const lens_ray *rr,
                                 const double *outer, trace_result res, double out[4])
{
    lens_ray r = *rr;
    if (res.status != TRACE_PASSED) {
        out[0] = out[1] = out[2] = out[3] = NAN;
        res.transmittance = 0;
        return res;
    }
    if (target == TRACE_TO_STOP)
        ray_to_stop(lens, &r, out);
    else if (outer)
        out[0] = outer[0], out[1] = outer[1], out[2] = outer[2], out[3] = outer[3];
    else
        ray_to_outer(lens, &r, out);
    if (!isfinite(out[0]) || !isfinite(out[1]) || !isfinite(out[2]) || !isfinite(out[3])) {
        /* A frame singularity (outer: normal along y; stop: a ray parallel to the
         * stop plane): flagged, never an unannounced nan. */
        out[0] = out[1] = out[2] = out[3] = NAN;
        return stopped(TRACE_INVALID, target == TRACE_TO_STOP ? lens->stop : 0);
    }
    return res;
}
