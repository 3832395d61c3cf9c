/* lens-mtf: diffraction and geometric MTF of a lens or a polynomial system (man lens-mtf). */
#include <stdio.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/mtf_run.h"

static const char *const prog = "lens-mtf";

static const char *const usage =
    "usage: lens-mtf LENS|SYSTEM.poly [options]\n"
    "MTF, tangential and sagittal, per field and wavelength and for all wavelengths:\n"
    "diffraction (from the wavefront, PSF by FFT) and geometric (from the spot), from 0\n"
    "to the sensor's Nyquist frequency; or through focus at one frequency.\n"
    "  --fields LIST          field angles in degrees (object at infinity) or object\n"
    "                         heights in mm (--object-distance); default 0, 0.7, 1 x max\n"
    "  --object-distance MM   finite object, MM in front of the first vertex\n"
    "  --wavelengths LIST     um values or Fraunhofer names (default F,d,C); the middle\n"
    "                         one is the primary (the reference point of every wavefront)\n"
    "  --focus file|paraxial|best   sensor plane (default file: as in the lens)\n"
    "  --pixel UM             pixel pitch, um: the frequencies end at Nyquist, 1000/(2 UM)\n"
    "                         cycles/mm (default 5)\n"
    "  --steps N              frequency intervals from 0 to Nyquist (default 10)\n"
    "  --grid N               pupil cells across (default 64)\n"
    "  --wavefront path|rays  the lens's wavefront from optical path lengths (default) or\n"
    "                         from ray errors as for a system\n"
    "  --through-focus FREQ   instead: MTF at FREQ cycles/mm against focus shift\n"
    "  --focus-range MM       through focus from -MM to +MM (default 0.1)\n"
    "  --focus-steps N        planes through focus (default 21)\n"
    "  --compare SYSTEM.poly  also through a fitted system: its MTF, difference and time\n"
    "  --lens LENS            the lens of a SYSTEM.poly given as the first argument\n"
    "  --png FILE             picture: a panel per field\n"
    LENS_CLI_OPTIONS_HELP
    "  --help\n";

typedef struct {
    const char *pixel, *steps, *grid, *wavefront, *freq, *range, *fsteps;
} mtf_flags;

static int mtf_flag(const char *p, int argc, char **argv, int *i, void *ctx)
{
    mtf_flags *f = ctx;
    return cli_opt(p, argc, argv, i, "--pixel", &f->pixel) || cli_opt(p, argc, argv, i, "--steps", &f->steps) ||
           cli_opt(p, argc, argv, i, "--grid", &f->grid) ||
           cli_opt(p, argc, argv, i, "--wavefront", &f->wavefront) ||
           cli_opt(p, argc, argv, i, "--through-focus", &f->freq) ||
           cli_opt(p, argc, argv, i, "--focus-range", &f->range) ||
           cli_opt(p, argc, argv, i, "--focus-steps", &f->fsteps);
}

int main(int argc, char **argv)
{
    mtf_flags mf = {"5", "10", "64", "path", NULL, "0.1", "21"};
    imaging_cli a = {.wavelengths = "F,d,C"};
    imaging_cli_parse(prog, usage, argc, argv, &a, mtf_flag, &mf);
    mtf_request rq = {
        .pixel_um = cli_positive(prog, "--pixel", mf.pixel),
        .steps = (int)cli_count(prog, "--steps", mf.steps, 1, 10000),
        .grid = (int)cli_count(prog, "--grid", mf.grid, 8, 512),
        .focus_range = cli_positive(prog, "--focus-range", mf.range),
        .focus_steps = (int)cli_count(prog, "--focus-steps", mf.fsteps, 2, 10001),
    };
    if (strcmp(mf.wavefront, "path") == 0)
        rq.lens_method = WAVEFRONT_PATH;
    else if (strcmp(mf.wavefront, "rays") == 0)
        rq.lens_method = WAVEFRONT_RAYS;
    else
        diag_die(prog, "--wavefront: '%s' is not path or rays", mf.wavefront);
    if (mf.freq)
        rq.focus_freq = cli_positive(prog, "--through-focus", mf.freq);
    imaging_models models;
    double field[IMAGING_MAX_FIELDS];
    design_set_from_cli(prog, &a, &models, field, &rq.set);
    char title[256];
    design_set_title(&a, &models, rq.focus_freq > 0 ? "MTF through focus" : "MTF", title, sizeof title);
    rq.png = a.png, rq.title = title;
    lens_err err;
    int rc = mtf_run(&rq, stdout, NULL, NULL, &err);
    if (rc != 0)
        diag_print(prog, &err);
    imaging_models_free(&models);
    return rc != 0;
}
