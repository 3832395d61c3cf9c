#ifndef SPARSELENS_SCENE_H
#define SPARSELENS_SCENE_H
/* Scenes for lens-render (man 5 lens-scene): a camera, a few diffuse objects and some
 * emitters, in plain text.
 *
 * Scene frame (mm): the vertex of the lens's front element is the origin, the camera
 * looks along +z (objects have z > 0), x to the right, y up. The lens frame of lens.h
 * (z towards the sensor) is this frame turned half a turn about y:
 *   scene (x, y, z) = lens (-x, y, -z).
 * The image is upright: pixel (0, 0) is the top-left corner of the picture. */
#include <limits.h>
#include <stddef.h>

#include "sparselens/diag.h"

typedef enum { SCENE_GREY, SCENE_RGB, SCENE_SPECTRAL } scene_mode;
typedef enum { TEX_CONSTANT, TEX_CHECKER, TEX_IMAGE } texture_kind;
typedef enum { OBJ_PLANE, OBJ_SPHERE, OBJ_DISK } object_kind;
typedef enum { EFFECT_AUTO = -1, EFFECT_OFF = 0, EFFECT_ON = 1 } effect_setting;

typedef struct {
    texture_kind kind;
    double a[3], b[3]; /* constant: a; checker: squares of a and b */
    double size;       /* checker square / image width, mm */
    int w, h;          /* image texture: pixels (rgb floats in [0, 1], row 0 at the top) */
    float *pix;
} scene_texture;

/* A diffuse surface, or an emitter when emit[] is non-zero (emitters do not reflect).
 * plane: infinite through p with normal n; disk: the part of that plane within radius;
 * sphere: centre p, radius. An emitter disk emits on the side its normal points to. */
typedef struct {
    object_kind kind;
    double p[3], n[3], radius;
    scene_texture tex;
    double emit[3]; /* radiance per channel (W sr^-1 m^-2 in arbitrary units) */
    long line;      /* scene line, for messages */
    /* derived when the object is read (the hot loops test them a few times a sample):
     * radius squared, 1 for an emitter, the emission's luminance, and a plane's or
     * disk's tangent frame (where a light sample on a disk starts) */
    double r2, lum, e1[3], e2[3];
    int emitter;
} scene_object;

typedef struct {
    /* PATH_MAX holds any path open() takes; a longer one is refused, never cut */
    char path[PATH_MAX];   /* the scene file */
    char camera[PATH_MAX]; /* lens file or .poly, resolved against the scene's directory */
    int camera_is_poly;
    double sensor_w, sensor_h; /* mm; NAN: from the lens file's header */
    int width, height;     /* pixels */
    double focus;          /* mm in front of the front vertex; INFINITY; NAN = as the lens file has it */
    double fstop;          /* NAN = as the lens file has it */
    long focus_line, fstop_line; /* their scene lines, for messages; 0 when not given */
    scene_mode mode;
    long spp;
    unsigned long seed;
    effect_setting transmittance, vignetting, dispersion;
    int blades;            /* 0: a round stop; else the polygon of render_lens_set_blades */
    double blade_rotation; /* degrees */
    int filter_tent;       /* 0: box (the pixel); 1: tent of filter_radius pixels */
    double filter_radius;
    size_t nobj;
    scene_object *obj;
} scene_t;

void scene_init(scene_t *s);
void scene_free(scene_t *s);
/* Reads a scene; every error is "FILE:LINE: what is wrong". 0 on success. */
int scene_load(const char *path, scene_t *s, lens_err *err);
int scene_parse(const char *text, const char *path, scene_t *s, lens_err *err);
const char *scene_mode_name(scene_mode m);

/* --- geometry (scene_geometry.c) --- */
typedef struct {
    double t;     /* ray parameter */
    double p[3];  /* hit point */
    double n[3];  /* unit normal facing the incoming ray */
    int obj;      /* object index, -1 for none */
} scene_hit;

/* Nearest hit of o + t d (d unit) with tmin < t < tmax; 1 if any. */
int scene_intersect(const scene_t *s, const double o[3], const double d[3], double tmin,
                    double tmax, scene_hit *hit);
/* scene_intersect when only an emitter matters (a BSDF sample's light): 1 and the hit
 * when the nearest hit is an emitter, else 0 (what scene_intersect finds then, with
 * only the emitters tested in full and the rest tested for blocking up to the nearest
 * emitter: most such rays meet no emitter and cost one loop over the emitters). */
int scene_intersect_emitter(const scene_t *s, const double o[3], const double d[3],
                            double tmin, scene_hit *hit);
/* The same over the objects that are not spheres and the listed spheres only
 * (scene_cull.c chooses them). */
int scene_intersect_listed(const scene_t *s, const int *spheres, int nlisted, const double o[3],
                           const double d[3], double tmin, double tmax, scene_hit *hit);

/* Camera rays leave the lens within a small ball around the origin (the front element):
 * a grid over their directions lists, per cell, the spheres such a ray can meet, so
 * that a scene of many small emitters (bokeh) is not tested sphere by sphere
 * (scene_cull.c). NULL when the scene has no spheres (or memory runs out): then
 * scene_intersect_camera is scene_intersect. */
typedef struct scene_cull scene_cull;
scene_cull *scene_cull_new(const scene_t *s, double origin_radius);
void scene_cull_free(scene_cull *c);
/* scene_intersect for a ray whose origin lies within origin_radius of the origin. */
int scene_intersect_camera(const scene_t *s, const scene_cull *c, const double o[3],
                           const double d[3], double tmin, scene_hit *hit);

/* 1 when nothing blocks the segment between a and b (shadow rays). */
int scene_visible(const scene_t *s, const double a[3], const double b[3]);
/* Diffuse albedo (r g b) of object obj at point p: all three channels at once, so that a
 * texture is looked up once per hit. */
void scene_albedo(const scene_t *s, int obj, const double p[3], double rgb[3]);
/* Radiance (rgb) that emitter obj sends from its point p in direction w (unit, away
 * from p); returns 0 (and zeros) for the back of an emitter and for non-emitters. */
int scene_emitted(const scene_t *s, int obj, const double p[3], const double w[3],
                  double rgb[3]);
int scene_is_emitter(const scene_object *o);
/* Uniform point on emitter obj (its area): position, outward unit normal, pdf = 1/area. */
void scene_sample_emitter(const scene_t *s, int obj, double u1, double u2, double p[3],
                          double n[3], double *pdf_area);
/* Reflected radiance (rgb) at diffuse point p (normal n, facing the viewer) by
 * next-event estimation: one sample (u[2j], u[2j+1]) on each emitter j that has an area
 * (disks, spheres); an unbiased estimate of albedo/pi * sum over emitters of the
 * integral of L_e cos cos' / d^2 dA. Infinite emitting planes are only seen directly. */
void scene_direct(const scene_t *s, int obj, const double p[3], const double n[3],
                  const double *u, double rgb[3]);
size_t scene_emitter_count(const scene_t *s);

/* Direct light at a diffuse hit h (scene_light.c): one light sample (an emitter chosen by
 * its estimated contribution, spheres by solid angle) and one cosine-weighted BSDF sample,
 * combined by multiple importance sampling; five uniforms u (selection, light 2, BSDF 2).
 * The reflected radiance is albedo(h) * sum over the terms of w[i] * L_e of emitter[i],
 * per channel or per wavelength alike: the terms depend on geometry only. Handles at most
 * 64 emitters for light sampling (the rest are found by the BSDF sample). */
typedef struct {
    int n;
    int emitter[2];
    double w[2];
} scene_light_terms;
void scene_direct_mis(const scene_t *s, const scene_hit *h, const double u[5],
                      scene_light_terms *t);

/* Bounds a scene file shares with the command line (man 5 lens-scene): samples per
 * pixel (as --spp), and colour values (albedo, emit), which the 32-bit float image
 * must hold after summing. */
#define SCENE_MAX_SPP 1073741824L
#define SCENE_MAX_VALUE 1e30
/* Positions within +-SCENE_MAX_MM, sizes (radii, texture widths, checker squares) from
 * SCENE_MIN_MM to SCENE_MAX_MM: 1 nm to 1000 km, far past any scene and well inside
 * what the intersections resolve in double precision. */
#define SCENE_MAX_MM 1e9
#define SCENE_MIN_MM 1e-6
/* Each ray is tested against every object (no acceleration structure): the time of a
 * sample grows with the count, about 0.25 ms per 1000 objects. */
#define SCENE_MAX_OBJECTS 10000

#endif
