/* Vignetting surfaces (see trace_clip.h).
 *
 * The tracer already ends a trace on the stop surface and reports where a ray died, so
 * nothing here touches the kernel: the census reads trace_result.surface, and a hit on
 * surface N is the stop trace of a view of the lens whose "stop" index is N (the
 * kernel uses that index only to end the trace and to name the status). */
#include <math.h>
#include <stdlib.h>

#include "sparselens/trace.h"
#include "sparselens/trace_clip.h"
#include "sparselens/trace_stop.h"

int trace_clip_census(const lens_t *lens, size_t count, const double *in, double *share,
                      int threads, lens_err *err)
{
    size_t m = count ? count : 1;
    double *out = malloc(m * 5 * sizeof *out);
    trace_result *res = malloc(m * sizeof *res);
    size_t *blocked = calloc(lens->nsurf, sizeof *blocked);
    if (!out || !res || !blocked) {
        free(out);
        free(res);
        free(blocked);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int rc = trace_batch(lens, TRACE_TO_OUTER, count, in, out, res, threads, err);
    for (size_t i = 0; i < count; i++) {
        trace_status st = res[i].status;
        int s = res[i].surface;
        if ((st == TRACE_CLIPPED || st == TRACE_STOPPED) && s >= 0 && (size_t)s < lens->nsurf)
            blocked[s]++;
    }
    for (size_t s = 0; s < lens->nsurf; s++)
        share[s] = count ? (double)blocked[s] / (double)count : 0.0;
    free(out);
    free(res);
    free(blocked);
    return rc;
}

int trace_clip_choose(const lens_t *lens, const double *share, double min_share,
                      int skip_front, int *surf)
{
    int k = 0;
    for (size_t s = 0; s < lens->nsurf; s++) {
        if ((int)s == lens->stop || (s == 0 && skip_front))
            continue;
        if (share[s] >= min_share)
            surf[k++] = (int)s;
    }
    return k;
}

int trace_surface_batch(const lens_t *lens, int surf, size_t count, const double *in,
                        double *hit, int threads, lens_err *err)
{
    lens_t view = *lens; /* shallow: the surfaces are shared and read only */
    view.stop = surf;
    return trace_stop_batch(&view, count, in, hit, threads, err);
}

int trace_surface_hit(const lens_t *lens, int surf, const double *n, const double in[4],
                      double hit[2])
{
    lens_t view = *lens;
    view.stop = surf;
    return trace_stop_hit(&view, n, in, hit);
}

int trace_clip_pilot(const lens_t *lens, const sampling_options *so, size_t rays,
                     double min_share, int skip_front, double *share, int *surf,
                     lens_err *err)
{
    double *in = malloc((rays ? rays : 1) * 5 * sizeof *in);
    if (!in) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    ray_generator *g = ray_generator_new(lens, so, err);
    int k = -1;
    if (g && ray_generator_fill(g, 0, rays, in, err) == 0 &&
        trace_clip_census(lens, rays, in, share, so->threads, err) == 0)
        k = trace_clip_choose(lens, share, min_share, skip_front, surf);
    if (g)
        ray_generator_free(g);
    free(in);
    return k;
}
