/* The option tables of the designer commands (design_cli.h, options.h). */
#include "sparselens/design_cli.h"

#include <string.h>

const opt_spec design_cli_table[] = {
    {.type = OPT_GROUP, 0, sizeof(imaging_cli), .group = imaging_cli_field_table},
    {0, "png", "FILE", OPT_STRING, OPT_AT(imaging_cli, png), .help = "the picture",
     .man =
     "Written to a temporary name and renamed when complete.\n"},
    {.type = OPT_GROUP, 0, sizeof(imaging_cli), .group = imaging_cli_table},
    {0}};

static const opt_spec fan_table[] = {
    {0, "points", "N", OPT_INT, OPT_AT(fan_cli, points), .lo = 2, .hi = 100001,
     .help = "rays per fan, evenly from -1 to 1 of the pupil", .def = "21"},
    {.type = OPT_GROUP, OPT_AT(fan_cli, im), .group = design_cli_table},
    {.type = OPT_GROUP, OPT_AT(fan_cli, out), .group = output_cli_table},
    {0}};

const opt_command fan_command = {
    "lens-fan", "LENS|SYSTEM.poly [options]",
    "Ray fans: the transverse ray error (um) on the sensor against the normalised pupil "
    "coordinate, tangential (ey against py) and sagittal (ex against px), per field and "
    "wavelength, measured from the chief ray of the primary wavelength.",
    fan_table};

void fan_cli_default(fan_cli *o)
{
    memset(o, 0, sizeof *o);
    imaging_cli_default(&o->im, "F,d,C");
    o->points = 21;
}

static const opt_spec field_table[] = {
    {0, "delta", "D", OPT_DOUBLE, OPT_AT(field_cli, delta), .lo = 1e-6, .hi = 0.5,
     .help = "the close rays pass the stop at D times its radius from the chief ray",
     .def = "0.01",
     .man =
     "Symmetric pairs make the error of the finite difference of order D squared.\n"},
    {0, "focal-shift", "N", OPT_INT, OPT_AT(field_cli, focal_shift), .lo = 2, .hi = 10000,
     .help = "instead of the field curves: the chromatic focal shift at N wavelengths "
             "spanning --wavelengths"},
    {.type = OPT_GROUP, OPT_AT(field_cli, im), .group = design_cli_table},
    {.type = OPT_GROUP, OPT_AT(field_cli, out), .group = output_cli_table},
    {0}};

const opt_command field_command = {
    "lens-field", "LENS|SYSTEM.poly [options]",
    "Field curves from real rays: tangential and sagittal focus against field (mm along "
    "the axis from the sensor plane), astigmatism, the Petzval focus, distortion and "
    "lateral colour; or the chromatic focal shift against wavelength.",
    field_table};

void field_cli_default(field_cli *o)
{
    memset(o, 0, sizeof *o);
    imaging_cli_default(&o->im, "F,d,C");
    o->delta = 0.01;
}

static const opt_choice wavefronts[] = {{"path", WAVEFRONT_PATH}, {"rays", WAVEFRONT_RAYS}, {NULL, 0}};

static const opt_spec mtf_table[] = {
    {0, "pixel", "UM", OPT_POSITIVE, OPT_AT(mtf_cli, pixel_um), .lo = 0.01, .hi = 10000,
     .help = "the sensor's pixel pitch in um: frequencies end at its Nyquist frequency, "
             "1000 / (2 UM) cycles/mm",
     .def = "5",
     .man = "From 0.01 to 10000 um (Nyquist 50000 to 0.05 cycles/mm); a pitch outside\n"
            "that range, whose frequencies no lens passes or no sensor has, is refused.\n"},
    {0, "steps", "N", OPT_INT, OPT_AT(mtf_cli, steps), .lo = 1, .hi = 10000,
     .help = "frequency intervals from 0 to Nyquist", .def = "10"},
    {0, "grid", "N", OPT_INT, OPT_AT(mtf_cli, grid), .lo = 8, .hi = 512,
     .help = "pupil cells across for the wavefront", .def = "64",
     .man =
     "The FFT is twice as wide (rounded up to a power of two); the closed-form check of\n"
     "a perfect pupil holds to about 1e-3 at 64.\n"},
    {0, "wavefront", NULL, OPT_CHOICE, OPT_AT(mtf_cli, wavefront), .choices = wavefronts,
     .help = "the lens's wavefront: optical path lengths, or integrated ray errors as for a "
             "fitted system",
     .def = "path"},
    {0, "through-focus", "FREQ", OPT_POSITIVE, OPT_AT(mtf_cli, through_focus), .lo = 1e-6,
     .hi = 1e5, .help = "instead: the MTF at FREQ cycles/mm against the sensor plane's shift",
     .man = "FREQ from 1e-6 to 1e5 cycles/mm (no lens passes more; outside the range the\n"
            "transfer has no meaning and is refused).\n"},
    {0, "focus-range", "MM", OPT_POSITIVE, OPT_AT(mtf_cli, focus_range), .lo = 1e-6, .hi = 1000,
     .help = "through focus from -MM to +MM about the sensor plane", .def = "0.1",
     .man = "MM from 1e-6 to 1000.\n"},
    {0, "focus-steps", "N", OPT_INT, OPT_AT(mtf_cli, focus_steps), .lo = 2, .hi = 10001,
     .help = "planes through focus", .def = "21"},
    {.type = OPT_GROUP, OPT_AT(mtf_cli, im), .group = design_cli_table},
    {.type = OPT_GROUP, OPT_AT(mtf_cli, out), .group = output_cli_table},
    {0}};

const opt_command mtf_command = {
    "lens-mtf", "LENS|SYSTEM.poly [options]",
    "MTF, tangential and sagittal, per field and wavelength and for all wavelengths: "
    "diffraction (from the wavefront, the PSF by FFT) and geometric (from the spot), from "
    "0 to the sensor's Nyquist frequency; or through focus at one frequency.",
    mtf_table};

void mtf_cli_default(mtf_cli *o)
{
    memset(o, 0, sizeof *o);
    imaging_cli_default(&o->im, "F,d,C");
    o->pixel_um = 5, o->steps = 10, o->grid = 64, o->wavefront = WAVEFRONT_PATH;
    o->focus_range = 0.1, o->focus_steps = 21;
}

static const opt_spec layout_table[] = {
    {0, "rays", "N", OPT_INT, OPT_AT(layout_cli, rays), .lo = 1, .hi = 1001,
     .help = "rays per field, spread evenly over the part of the stop's meridian whose rays "
             "reach the sensor", .def = "7"},
    {0, "full-stop", NULL, OPT_FLAG, OPT_AT(layout_cli, full_stop),
     .help = "spread the rays over the whole meridian of the stop instead, vignetted ones too "
             "(drawn up to the surface that stops them)"},
    {0, "svg", "FILE", OPT_STRING, OPT_AT(layout_cli, svg), .help = "the picture as SVG",
     .man =
     "Exact coordinates in mm (one SVG unit per millimetre, the page at 1:1); readable and "
     "editable as text.\n"},
    {0, "width", "PX", OPT_INT, OPT_AT(layout_cli, width), .lo = 200, .hi = 10000,
     .help = "PNG width in pixels", .def = "1200"},
    {.type = OPT_GROUP, OPT_AT(layout_cli, im), .group = design_cli_table},
    {.type = OPT_GROUP, OPT_AT(layout_cli, out), .group = output_cli_table},
    {0}};

const opt_command layout_command = {
    "lens-layout", "LENS|SYSTEM.poly [options]",
    "The meridional section of a lens: elements with their real sags and edges, the stop, "
    "the sensor, and bundles of traced rays per field in colours; the surfaces and the rays "
    "as text, the picture as PNG and SVG.",
    layout_table};

void layout_cli_default(layout_cli *o)
{
    memset(o, 0, sizeof *o);
    imaging_cli_default(&o->im, "F,d,C");
    o->rays = 7, o->width = 1200;
}
