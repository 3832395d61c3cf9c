#ifndef SPARSELENS_PROJECTION_H
#define SPARSELENS_PROJECTION_H
/* Ideal lens projections (how a distortion-free lens of focal length f would map the
 * direction of an object point to an image height), computed through GeographicLib's
 * geodesic C API on a unit sphere (src/analysis/projection.c is the only file that includes it).
 *
 * A direction is a unit vector in the lens frame (lens.h: z along the optical axis,
 * towards the sensor); the projection centre is the axis (0, 0, 1). On the unit sphere
 * the geodesic from the centre to the direction has length s12 = theta (the field
 * angle), azimuth azi1, reduced length m12 = sin(theta) and geodesic scale
 * M12 = cos(theta). As in GeographicLib's own classes:
 *   rectilinear  (Gnomonic)              r = f m12 / M12      (= f tan theta)
 *   equidistant  (AzimuthalEquidistant)  r = f s12            (= f theta)
 * and from the angle theta:
 *   equisolid     r = 2 f sin(theta / 2)
 *   stereographic r = 2 f tan(theta / 2)
 *   orthographic  r = f sin(theta)
 * The image point lies at azimuth azi1 from the y axis towards the x axis (the object
 * side view; a real lens inverts it, callers flip signs as their frame needs). */

typedef enum {
    PROJ_RECTILINEAR,
    PROJ_EQUIDISTANT,
    PROJ_EQUISOLID,
    PROJ_STEREOGRAPHIC,
    PROJ_ORTHOGRAPHIC,
    PROJ_COUNT
} proj_kind;

const char *proj_name(proj_kind k); /* "rectilinear", "equidistant", ... */
int proj_parse(const char *name, proj_kind *k); /* 0 on success */

/* The angle between two directions (need not be unit length), radians, from the
 * geodesic distance on the unit sphere. */
double proj_angle(const double a[3], const double b[3]);

/* Ideal image height for field angle theta (radians, 0..pi); NAN where the projection
 * has no image (rectilinear at theta >= 90 degrees, orthographic past 90 degrees). */
double proj_radius(proj_kind k, double f, double theta);

/* Ideal image point of a direction (need not be unit length). 0 on success; -1 (xy
 * NAN) where the projection has no image. */
int proj_point(proj_kind k, double f, const double dir[3], double xy[2]);

/* The field angle (radians) whose ideal image height is r: the inverse of proj_radius,
 * in closed form (GeographicLib's reverse projections need a centre and azimuth, which
 * add nothing on the axis of symmetry). NAN outside the projection's range. */
double proj_theta(proj_kind k, double f, double r);

#endif
