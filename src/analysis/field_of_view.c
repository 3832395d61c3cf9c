/* Field of view from real chief rays aimed at the stop centre. */
#include "sparselens/field_of_view.h"

#include <math.h>

#include "sparselens/aim.h"
#include "sparselens/trace.h"

int lens_chief_angle(const lens_t *lens, const double *n, double r, double *angle_deg)
{
    double u, v;
    if (aim_from_sensor(lens, n, r, 0, 0, 0, &u, &v) != 0)
        return -1;
    lens_ray ray;
    double xyuv[4] = {r, 0, u, v};
    ray_from_sensor(lens, xyuv, &ray);
    trace_result res = trace_to_object(lens, n, &ray, 0);
    if (res.status != TRACE_PASSED)
        return -1;
    /* The object-space direction points away from the lens (towards -z); its angle
     * from the axis is measured from (0, 0, -1), so it passes 90 degrees smoothly. */
    *angle_deg = atan2(hypot(ray.d[0], ray.d[1]), -ray.d[2]) * 180.0 / M_PI;
    return 0;
}

int lens_field_of_view(const lens_t *lens, double lambda, double r_sensor, double *fov_deg,
                       double *r_used, lens_err *err)
{
    double n[lens->nsurf];
    if (lens_indices(lens, lambda, n, err) != 0)
        return -1;
    double angle;
    if (lens_chief_angle(lens, n, r_sensor, &angle) == 0) {
        *fov_deg = 2 * angle;
        *r_used = r_sensor;
        return 0;
    }
    /* The corner lies outside the image circle: bisect for the largest radius a chief
     * ray reaches. 50 halvings bring the bracket far below a micrometre. */
    double lo = 0, hi = r_sensor;
    if (lens_chief_angle(lens, n, 0, &angle) != 0) {
        lens_errf(err, lens->path[0] ? lens->path : NULL, 0,
                  "no chief ray passes the lens, even on axis");
        return -1;
    }
    for (int i = 0; i < 50; i++) {
        double mid = 0.5 * (lo + hi), a;
        if (lens_chief_angle(lens, n, mid, &a) == 0) {
            lo = mid;
            angle = a;
        } else {
            hi = mid;
        }
    }
    *fov_deg = 2 * angle;
    *r_used = lo;
    return 0;
}
