/* Ideal projections through GeographicLib's geodesic routines (see projection.h). */
#include "sparselens/projection.h"

#include <geodesic.h>
#include <math.h>
#include <string.h>

static const char *const names[PROJ_COUNT] = {"rectilinear", "equidistant", "equisolid",
                                              "stereographic", "orthographic"};

const char *proj_name(proj_kind k)
{
    return k >= 0 && k < PROJ_COUNT ? names[k] : "unknown";
}

int proj_parse(const char *name, proj_kind *k)
{
    for (int i = 0; i < PROJ_COUNT; i++)
        if (strcmp(name, names[i]) == 0) {
            *k = (proj_kind)i;
            return 0;
        }
    return -1;
}

/* A direction as a point on the unit sphere: the optical axis (0, 0, 1) at latitude 0,
 * longitude 0; +y towards the north pole, +x towards east. */
static void to_latlon(const double d[3], double *lat, double *lon)
{
    double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double s = d[1] / n;
    *lat = asin(s > 1 ? 1 : s < -1 ? -1 : s) * (180 / M_PI);
    *lon = atan2(d[0], d[2]) * (180 / M_PI);
}

typedef struct {
    double s12, azi1, m12, M12;
} geo;

static geo inverse_from_axis(double lat, double lon)
{
    struct geod_geodesic g;
    geod_init(&g, 1.0, 0.0); /* unit sphere: distances are angles in radians */
    geo r;
    double azi2, M21, S12;
    geod_geninverse(&g, 0.0, 0.0, lat, lon, &r.s12, &r.azi1, &azi2, &r.m12, &r.M12, &M21, &S12);
    return r;
}

double proj_angle(const double a[3], const double b[3])
{
    double lat1, lon1, lat2, lon2;
    to_latlon(a, &lat1, &lon1);
    to_latlon(b, &lat2, &lon2);
    struct geod_geodesic g;
    geod_init(&g, 1.0, 0.0);
    double s12;
    geod_inverse(&g, lat1, lon1, lat2, lon2, &s12, 0, 0);
    return s12;
}

/* Radius from the geodesic quantities; the Gnomonic and AzimuthalEquidistant classes
 * use m12/M12 and s12 the same way. */
static double radius_of(proj_kind k, double f, const geo *q)
{
    double t = q->s12;
    switch (k) {
    case PROJ_RECTILINEAR:
        return q->M12 > 1e-12 ? f * q->m12 / q->M12 : NAN; /* no image at 90 degrees */
    case PROJ_EQUIDISTANT:
        return f * t;
    case PROJ_EQUISOLID:
        return 2 * f * sin(t / 2);
    case PROJ_STEREOGRAPHIC:
        return t < M_PI ? 2 * f * tan(t / 2) : NAN;
    case PROJ_ORTHOGRAPHIC:
        return t <= M_PI / 2 ? f * sin(t) : NAN;
    default:
        return NAN;
    }
}

double proj_radius(proj_kind k, double f, double theta)
{
    if (!(theta >= 0 && theta <= M_PI))
        return NAN;
    /* Along the equator, so that the whole range 0..180 degrees is one longitude. */
    geo q = inverse_from_axis(0.0, theta * (180 / M_PI));
    return radius_of(k, f, &q);
}

int proj_point(proj_kind k, double f, const double dir[3], double xy[2])
{
    double lat, lon;
    to_latlon(dir, &lat, &lon);
    geo q = inverse_from_axis(lat, lon);
    double r = radius_of(k, f, &q);
    if (!isfinite(r)) {
        xy[0] = xy[1] = NAN;
        return -1;
    }
    double a = q.azi1 * (M_PI / 180);
    xy[0] = r * sin(a);
    xy[1] = r * cos(a);
    return 0;
}

double proj_theta(proj_kind k, double f, double r)
{
    double q = r / f;
    switch (k) {
    case PROJ_RECTILINEAR:
        return atan(q);
    case PROJ_EQUIDISTANT:
        return q >= 0 && q <= M_PI ? q : NAN;
    case PROJ_EQUISOLID:
        return q >= 0 && q <= 2 ? 2 * asin(q / 2) : NAN;
    case PROJ_STEREOGRAPHIC:
        return 2 * atan(q / 2);
    case PROJ_ORTHOGRAPHIC:
        return q >= 0 && q <= 1 ? asin(q) : NAN;
    default:
        return NAN;
    }
}
