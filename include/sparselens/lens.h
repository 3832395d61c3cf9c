#ifndef SPARSELENS_LENS_H
#define SPARSELENS_LENS_H
/* The lens model: a sequence of rotationally symmetric surfaces, object side first.
 *
 * Frame (used by every module): z is the optical axis; z = 0 at the vertex of the
 * first (object-side) surface; z grows towards the sensor. The sensor plane is at
 * z = lens_total_track(). x and y complete a right-handed frame. Lengths in mm.
 *
 * Surface sag, measured along +z from the vertex, at radial distance h:
 *   z(h) = c h^2 / (1 + sqrt(1 - (1 + k) c^2 h^2)) + a4 h^4 + a6 h^6 + ... + a12 h^12
 * with c = 1/radius (0 for a flat surface). radius > 0: centre of curvature behind the
 * vertex (towards the sensor). */
#include <limits.h>
#include <stddef.h>
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/glass.h"

/* Room for any path open() takes: PATH_MAX where the C library defines it (a strict
 * -std=c11 build of a user's program may hide it), else Linux's 4096. */
#ifdef PATH_MAX
#define LENS_PATH_MAX PATH_MAX
#else
#define LENS_PATH_MAX 4096
#endif

#ifdef __cplusplus
extern "C" {
#endif

#define LENS_ASPHERE_TERMS 5 /* a4, a6, a8, a10, a12 */

typedef struct {
    double radius;        /* mm; INFINITY when flat */
    double thickness;     /* axial distance to the next surface; last: to the sensor */
    double semi_diameter; /* clear aperture radius, mm */
    double conic;         /* k; 0 = sphere */
    double asphere[LENS_ASPHERE_TERMS]; /* a4 .. a12 */
    int is_stop;          /* the aperture stop (at most one surface) */
    glass_t medium;       /* medium after the surface (towards the sensor) */
    char material[48];    /* the material as written: "air", "stop", "N-BK7", "1.62/60.3" */
    long line;            /* source line, for messages; 0 if none */
} lens_surface;

/* What a design file's field list measures (lens_t.field_kind). */
typedef enum {
    LENS_FIELD_NONE = 0,      /* no fields given */
    LENS_FIELD_ANGLE,         /* degrees, object at infinity */
    LENS_FIELD_OBJECT_HEIGHT, /* mm */
    LENS_FIELD_IMAGE_HEIGHT,  /* paraxial image height, mm */
    LENS_FIELD_REAL_IMAGE_HEIGHT /* real (chief ray) image height, mm */
} lens_field_kind;

/* The most fields and wavelengths a lens records: more than Zemax (12 fields, 24
 * wavelengths) and CODE V (25 fields, 21 wavelengths) allow; an importer refuses more. */
#define LENS_MAX_FIELDS 32
#define LENS_MAX_WAVES 32

typedef struct {
    char name[128];
    char source[512];
    char path[LENS_PATH_MAX]; /* file it was read from (any path open() takes fits) */
    char format[8];        /* the reader lens_load used ("lens", "zmx", ...); "" if none */
    double focal;          /* nominal focal length from the header, mm; NAN if unknown */
    double fnumber;        /* nominal f-number from the header; NAN if unknown */
    double sensor_w, sensor_h; /* sensor size, mm; NAN if unknown */
    /* The design file's own fields and wavelengths: the defaults of the analyses. */
    lens_field_kind field_kind;
    int nfields;
    double field_x[LENS_MAX_FIELDS], field_y[LENS_MAX_FIELDS]; /* in field_kind's unit */
    int nwaves;
    double wave_um[LENS_MAX_WAVES], wave_weight[LENS_MAX_WAVES];
    int primary_wave;      /* 1-based index into wave_um; 0: none given */
    char notes[1024];      /* importer notes (skipped parts), written as "# note:" lines */
    size_t nsurf;
    lens_surface *surf;
    int stop;              /* index of the stop surface */
    double *vertex_z;      /* z of each surface vertex (filled by lens_finish) */
} lens_t;

typedef struct {
    const char *const *catalogs; /* extra glass catalogs (AGF or .catalog), NULL-terminated; may be NULL */
    int ndvd_fallback;           /* a missing glass given with nd/Vd falls back to the model, with a warning */
    const char *format;          /* "lens", "fx", "pbrt", "zmx", "seq"; NULL or "auto": guess */
} lens_load_options;

/* Reads any supported prescription (.lens, pbrt .dat, .fx, Zemax .zmx, CODE V .seq) from
 * path, or from stdin when path is "-". The format is opt->format when given, else the
 * file's extension, else (an unknown extension, or stdin) the content. 0 on success; on
 * failure err holds "FILE:LINE: what is wrong" and *lens is left empty. opt may be NULL. */
int lens_load(const char *path, const lens_load_options *opt, lens_t *lens, lens_err *err);

/* Where lens_load finds the lens a user named: a file that exists, or a name (dgauss.50mm)
 * looked up with each reader's extension in ./, $SPARSELENS_LENS_PATH and the shipped
 * lenses (data_path.h). 0 with the path in buf, -1 if none. */
int lens_find_file(const char *name, char *buf, size_t n);

/* The format names lens_load knows, for messages ("lens, fx, pbrt, zmx, seq"), and whether
 * name is one of them (or "auto", or NULL). */
extern const char *const lens_formats;
int lens_format_known(const char *name);

/* Parses the project's own format from a stream (path is used in messages). */
int lens_read_native(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                     lens_err *err);

/* Checks a freshly built lens (a stop, positive semi-diameters, finite numbers,
 * surfaces that do not cross within their apertures) and fills vertex_z. */
int lens_finish(lens_t *lens, lens_err *err);

/* The smallest axial gap between surfaces i and i+1 (the edge thickness of an element,
 * or the air between two) over heights up to the smaller semi-diameter, and the height
 * where it occurs; lens_finish refuses a lens where one is negative beyond rounding. */
double lens_min_gap(const lens_t *lens, size_t i, double *at_h);

/* Writes the lens in the project's format: header, then one surface per line.
 * Numbers are written with enough digits to read back exactly. */
int lens_write(FILE *f, const lens_t *lens);

void lens_free(lens_t *lens);
int lens_copy(lens_t *dst, const lens_t *src);

/* Appends a surface (importers); returns its pointer or NULL on allocation failure. */
lens_surface *lens_add_surface(lens_t *lens);
/* The same for readers: the surface gets source line `line`; on allocation failure err
 * says "path:line: out of memory". */
lens_surface *lens_add_surface_at(lens_t *lens, const char *path, long line, lens_err *err);
void lens_init(lens_t *lens); /* empty lens, NAN metadata */

double lens_total_track(const lens_t *lens); /* first vertex to sensor plane */
double lens_sag(const lens_surface *s, double h2);      /* sag at h^2 = x^2 + y^2 */
/* d(sag)/d(h^2): the surface normal is proportional to (2x dsag, 2y dsag, -1). */
double lens_sag_slope(const lens_surface *s, double h2);
int lens_surface_is_aspheric(const lens_surface *s);

/* The slowest f-number a lens is stopped down to: a stop of 1/20000 of the focal length
 * (2.5 um for 50 mm), past which spots and transfers are of nothing but diffraction and
 * the stop's radius underflows towards 0 (f/1e308: no ray passes, figures nan). */
#define LENS_FNUMBER_MAX 1e4
/* Scales the stop's semi-diameter so that the paraxial f-number becomes fnumber, from
 * the lens' widest to LENS_FNUMBER_MAX; else -1 with err giving that range. */
int lens_set_fnumber(lens_t *lens, double fnumber, lens_err *err);

/* Refractive index after each surface (n[i], i < nsurf) at lambda; object space is air.
 * 0 on success, -1 (err set) for a wavelength outside some glass's range. */
int lens_indices(const lens_t *lens, double lambda_um, double *n, lens_err *err);

#ifdef __cplusplus
}
#endif

#endif
