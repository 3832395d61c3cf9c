/* Surface-by-surface tracing with hits and optical path (ray_path.h). */
#include "sparselens/ray_path.h"

#include <math.h>
#include <string.h>

#include "sparselens/intersect.h"
#include "sparselens/refract.h"

int ray_path(const lens_t *lens, const double *n, lens_ray *r, double *pts, double *opl, int *clip_hit)
{
    double n1 = 1, L = 0;
    if (clip_hit)
        *clip_hit = 0;
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *s = &lens->surf[i];
        double t, p[3], nrm[3], T;
        /* unclipped, so a vignetted ray can still be drawn to where it is stopped */
        if (intersect_surface(s, lens->vertex_z[i], r->o, r->d, INFINITY, &t, p, nrm) != ISECT_HIT)
            return (int)i;
        if (pts)
            memcpy(pts + 3 * i, p, sizeof p);
        if (p[0] * p[0] + p[1] * p[1] > s->semi_diameter * s->semi_diameter) {
            if (clip_hit)
                *clip_hit = 1;
            return (int)i;
        }
        L += n1 * t;
        memcpy(r->o, p, sizeof p);
        if (n[i] != n1 && refract(r->d, nrm, n1, n[i], r->d, &T) != 0)
            return (int)i;
        n1 = n[i];
    }
    if (opl)
        *opl += L;
    return (int)lens->nsurf;
}
