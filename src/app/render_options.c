/* lens-render's option table (see render_cli.h, options.h). */
#include "sparselens/render_cli.h"

#include <math.h>
#include <string.h>

#include "sparselens/numparse.h"

/* --focus MM or inf: a distance > 0, INFINITY for inf. */
static void set_focus(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    double *d = field;
    if (!strcmp(value, "inf") || !strcmp(value, "infinity")) {
        *d = INFINITY;
        return;
    }
    if (parse_double(value, d) || !(*d > 0) || !isfinite(*d))
        opt_die(prog, spec, "'%s': give a distance > 0 mm, or inf", value);
}

/* --blades N: 0 (the stop's circle) or 3 .. 16. */
static void set_blades(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    int *b = field;
    double n;
    if (parse_double(value, &n) || n != floor(n) || !(n == 0 || (n >= 3 && n <= 16)))
        opt_die(prog, spec, "'%s': give 0 (a round stop) or a count from 3 to 16", value);
    *b = n == 0 ? RENDER_BLADES_ROUND : (int)n;
}

static const opt_choice estimators[] = {
    {"eq13", RENDER_ESTIMATOR_EQ13}, {"full", RENDER_ESTIMATOR_FULL}, {NULL, 0}};

static const opt_spec render_table[] = {
    {'o', "output", "FILE", OPT_STRING, OPT_AT(render_cli, run.exr),
     .help = "the OpenEXR image (required)",
     .man =
     "Written through a temporary file; no partial file is left on failure.\n"},
    {0, "png", "FILE", OPT_STRING, OPT_AT(render_cli, run.png),
     .help = "an 8-bit preview (exposed to the 99th percentile, sRGB)"},
    {0, "exact", NULL, OPT_FLAG, OPT_AT(render_cli, run.exact),
     .help = "trace every camera ray exactly instead of a polynomial system"},
    {0, "spp", "N", OPT_INT, OPT_AT(render_cli, run.spp), .lo = 1, .hi = 1073741824.0,
     .help = "samples per pixel", .def = "the scene's"},
    {0, "threads", "N", OPT_INT, OPT_AT(render_cli, run.threads), .lo = 1, .hi = 1024,
     .help = "threads", .def = "all",
     .man =
     "Pictures do not depend on the number of threads.\n"},
    {0, "cache", "DIR", OPT_STRING, OPT_AT(render_cli, run.cache_dir),
     .help = "where fitted systems and line pupils are kept",
     .def = "$XDG_CACHE_HOME/sparselens, else ~/.cache/sparselens"},
    {0, "rear-sampling", NULL, OPT_FLAG, OPT_AT(render_cli, run.rear_sampling),
     .help = "draw directions over the rear element instead of the line pupil",
     .man =
     "The naive sampler, for comparisons.\n"},
    {0, "reference", "FILE", OPT_STRING, OPT_AT(render_cli, run.reference),
     .help = "print the RMS error against this image (same size)",
     .man =
     "Also its share of the reference's mean; e.g. against an\n"
     ".B \\-\\-exact\n"
     "render at many samples per pixel.\n"},
    {0, "seed", "N", OPT_INT, OPT_AT(render_cli, run.seed), .lo = 1, .hi = 4611686018427387904.0,
     .help = "random seed", .def = "the scene's"},
    {0, "focus", "MM|inf", OPT_CALL, OPT_AT(render_cli, run.focus), .set = set_focus,
     .help = "focus the lens at MM in front of its front vertex (or at infinity) instead of "
             "the scene's focus",
     .def = "the scene's",
     .man =
     "As the scene's\n"
     ".B focus\n"
     "line: the last thickness (lens to sensor) becomes the paraxial one for that distance at\n"
     "the d line. Not with a\n"
     ".I .poly\n"
     "camera, whose focus was fitted.\n"},
    {0, "fstop", "N", OPT_POSITIVE, OPT_AT(render_cli, run.fstop),
     .help = "stop the lens to f-number N instead of the scene's fstop", .def = "the scene's",
     .man =
     "As the scene's\n"
     ".B fstop\n"
     "line: the stop's semi-diameter is scaled to that paraxial f-number, from the lens'\n"
     "widest to f/10000. Not with a\n"
     ".I .poly\n"
     "camera.\n"},
    {0, "blades", "N", OPT_CALL, OPT_AT(render_cli, run.blades), .set = set_blades,
     .help = "an aperture of N blades (3 to 16; 0: the stop's circle) instead of the scene's "
             "blades, at the scene's rotation",
     .def = "the scene's"},
    {0, "noise-against", "FILE", OPT_STRING, OPT_AT(render_cli, run.noise_against),
     .help = "print the noise figure against FILE, a render of the same scene with another "
             "seed"},
    {0, "estimator", NULL, OPT_CHOICE, OPT_AT(render_cli, run.estimator), .choices = estimators,
     .help = "eq13: the simplified weight of Eq. 13; full: Eq. 3 with G-bar (Eq. 12) and "
             "p_A(s1) (Eq. 8) each evaluated from its own terms, from the lens map's Jacobian "
             "(slower: a check of Eq. 13 and of the system's conservation of etendue)",
     .def = "eq13",
     .man =
     "See the estimator above.\n"},
    {0, "emit-camera", "FILE", OPT_STRING, OPT_AT(render_cli, run.emit_camera),
     .help = "write the scene's camera as one C file (system, line pupil, front element, "
             "weight) instead of rendering",
     .man =
     "The module defines\n"
     ".I double NAME_ray(sx, sy, lambda, r1, r2, org[3], dir[3]):\n"
     "the weight of the camera ray from sensor point (sx, sy) (fractions of the sensor, the\n"
     "top-left at 0, 0), with its origin and direction in the scene frame\n"
     ".RB ( lens-scene (5)).\n"
     "It compiles on its own as C11 or C++, its functions with C linkage, and\n"
     ".I FILE.h\n"
     "(for\n"
     ".IR FILE .c)\n"
     "declares them; -o is not needed.\n"},
    {0, "name", "NAME", OPT_STRING, OPT_AT(render_cli, run.camera_name),
     .help = "for --emit-camera: the prefix of every symbol of the module (NAME_ray, "
             "NAME_rays, ...), so that cameras of several lenses link into one program",
     .def = "lens_camera"},
    {'q', "quiet", NULL, OPT_FLAG, OPT_AT(render_cli, quiet),
     .help = "no decisions, progress or timings on stderr (the figures of --reference and "
             "--noise-against still)"},
    {.type = OPT_GROUP, OPT_AT(render_cli, lens), .group = lens_cli_table},
    {0}};

const opt_command render_command = {
    "lens-render", "SCENE -o IMAGE.exr [options]",
    "Renders SCENE (man 5 lens-scene) through its lens with the Monte Carlo estimator of the "
    "supplement (Eq. 13): camera rays start on the pixel, take their direction from the line "
    "pupil, cross the lens by a polynomial system fitted for the effects the scene needs "
    "(cached), or by exact tracing with --exact, and gather light by next-event estimation. "
    "Writes R, G, B float channels to IMAGE.exr.",
    render_table};

void render_cli_default(render_cli *o)
{
    memset(o, 0, sizeof *o);
    lens_cli_options_init(&o->lens);
    o->run.camera_name = "lens_camera";
}
