/* Conversions between lens-frame rays and the parametrisations of trace.h:
 * sensor (x, y, u, v), outer-pupil sphere frame, and stop plane. */
#include <math.h>

#include "sparselens/intersect.h"
#include "sparselens/ray_frames.h"

void ray_from_sensor(const lens_t *lens, const double xyuv[4], lens_ray *r)
{
    double u = xyuv[2], v = xyuv[3];
    double inv = 1.0 / sqrt(u * u + v * v + 1.0);
    r->o[0] = xyuv[0];
    r->o[1] = xyuv[1];
    r->o[2] = lens_total_track(lens);
    r->d[0] = u * inv;
    r->d[1] = v * inv;
    r->d[2] = -inv;
}

void ray_to_sensor(const lens_t *lens, const lens_ray *r, double xyuv[4])
{
    /* Described by the reversed direction, so that from-then-to is the identity. */
    double zs = lens_total_track(lens);
    double t = (zs - r->o[2]) / r->d[2];
    if (r->o[2] == zs)
        t = 0;
    xyuv[0] = r->o[0] + t * r->d[0];
    xyuv[1] = r->o[1] + t * r->d[1];
    xyuv[2] = -r->d[0] / r->d[2];
    xyuv[3] = -r->d[1] / r->d[2];
    if (!(r->d[2] > 0))
        xyuv[0] = xyuv[1] = xyuv[2] = xyuv[3] = NAN;
}

void ray_to_outer(const lens_t *lens, const lens_ray *r, double xyuv[4])
{
    double n[3], ex[3], ey[3];
    surface_normal(&lens->surf[0], r->o[0], r->o[1], n);
    xyuv[0] = r->o[0];
    xyuv[1] = r->o[1];
    if (lens_outer_frame(n, ex, ey)) {
        xyuv[2] = xyuv[3] = NAN;
        return;
    }
    xyuv[2] = r->d[0] * ex[0] + r->d[1] * ex[1] + r->d[2] * ex[2];
    xyuv[3] = r->d[0] * ey[0] + r->d[1] * ey[1] + r->d[2] * ey[2];
}

int ray_from_outer(const lens_t *lens, const double xyuv[4], lens_ray *r)
{
    const lens_surface *s = &lens->surf[0];
    double x = xyuv[0], y = xyuv[1], u = xyuv[2], v = xyuv[3];
    double z = lens_sag(s, x * x + y * y);
    double w2 = 1.0 - u * u - v * v;
    double n[3], ex[3], ey[3];
    if (!isfinite(z) || !(w2 >= 0) || !isfinite(x) || !isfinite(y))
        return -1;
    surface_normal(s, x, y, n);
    if (lens_outer_frame(n, ex, ey))
        return -1;
    double w = sqrt(w2);
    r->o[0] = x;
    r->o[1] = y;
    r->o[2] = lens->vertex_z[0] + z;
    for (int k = 0; k < 3; k++)
        r->d[k] = u * ex[k] + v * ey[k] + w * n[k];
    return 0;
}

void ray_to_stop(const lens_t *lens, const lens_ray *r, double xyuv[4])
{
    (void)lens;
    xyuv[0] = r->o[0];
    xyuv[1] = r->o[1];
    if (r->d[2] < 0) {
        xyuv[2] = r->d[0] / -r->d[2];
        xyuv[3] = r->d[1] / -r->d[2];
    } else {
        xyuv[2] = xyuv[3] = NAN;
    }
}

int outer_of_object_ray(const lens_t *lens, const lens_ray *r, double outer[4])
{
    double t, p[3], nrm[3];
    if (intersect_surface(&lens->surf[0], lens->vertex_z[0], r->o, r->d, INFINITY, &t, p, nrm) !=
        ISECT_HIT)
        return -1;
    lens_ray back = {{p[0], p[1], p[2]}, {-r->d[0], -r->d[1], -r->d[2]}};
    ray_to_outer(lens, &back, outer);
    return isfinite(outer[0] + outer[1] + outer[2] + outer[3]) ? 0 : -1;
}
