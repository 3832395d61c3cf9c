/* The shared command line of lens-spot and lens-distort (see imaging_cli.h). */
#include "sparselens/imaging_cli.h"
#include "sparselens/numparse.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/escape.h"
#include "sparselens/file_fields.h"
#include "sparselens/paraxial.h"

/* --fields and --wavelengths as lens-spot and the designer commands have them (lens-distort
 * spaces its fields otherwise and has its own). */
const opt_spec imaging_cli_field_table[] = {
    {0, "fields", "LIST", OPT_STRING, OPT_AT(imaging_cli, fields),
     .help = "field angles in degrees (object at infinity) or object heights in mm "
             "(--object-distance)",
     .def = "the design file's, else 0, 0.7 and 1 times the largest",
     .man =
     "A Zemax or CODE V file's fields (angles, or image heights turned into the angles\n"
     "that image there) are the default for an object at infinity, its object heights for\n"
     "a finite one. Without them the largest field is the half field of view of the sensor\n"
     "diagonal named in the lens header, or, without one, the largest field whose chief ray\n"
     "still reaches the sensor.\n"},
    {0, "wavelengths", "LIST", OPT_STRING, OPT_AT(imaging_cli, wavelengths),
     .help = "um values or Fraunhofer names; the middle one is the primary",
     .def = "the design file's, else F,d,C",
     .man =
     "Wavelengths are 0.2 to 2.5 um; the line names are i h g F' F e d D C' C r A' s t\n"
     "(F = 0.4861327, d = 0.5875618, C = 0.6562725).\n"
     "A Zemax or CODE V file's wavelengths (up to 16) are the default, shortest first,\n"
     "with the primary it marks as the primary.\n"},
    {0}};

const opt_spec imaging_cli_table[] = {
    {0, "object-distance", "MM", OPT_POSITIVE, OPT_AT(imaging_cli, object_distance),
     .help = "a finite object, MM in front of the first vertex", .def = "infinity"},
    {0, "focus", "file|paraxial|best", OPT_STRING, OPT_AT(imaging_cli, focus),
     .help = "the sensor plane: as in the lens file, the paraxial focus, or the plane of "
             "least RMS spot radius",
     .def = "file",
     .man =
     "The paraxial focus is that of the primary wavelength for the object distance; the best\n"
     "plane minimises the sum over fields and wavelengths of the squared RMS radius about the\n"
     "centroid (closed form, since every ray moves linearly with the plane).\n"
     "With\n"
     ".BR \\-\\-compare ,\n"
     "both models are shown on the lens's plane.\n"},
    {0, "compare", "SYSTEM.poly", OPT_STRING, OPT_AT(imaging_cli, compare),
     .help = "also through a fitted system, shown beside the lens",
     .man =
     "Its inputs must be x y u v lambda and its outputs include out_x out_y out_u out_v.\n"
     "A system answers only inside its training domain: a field whose chief ray lands\n"
     "beyond the sensor radius it was fitted over, or a wavelength outside its band, is\n"
     "one it cannot image (nan, a warning naming the domain), never an extrapolation.\n"
     "A system fitted to another lens (neither the lens name nor the lens file it records\n"
     "is this lens's) is shown all the same, with a warning.\n"},
    {0, "lens", "LENS", OPT_STRING, OPT_AT(imaging_cli, lens),
     .help = "the lens of a SYSTEM.poly given as the first argument",
     .man =
     "Use it when the path the system records is not right. Without it the system's\n"
     ".B lens-path\n"
     "is loaded (as written, else relative to the\n"
     ".I .poly\n"
     "file's directory, else as a lens name such as\n"
     ".B dgauss.50mm\n"
     "is looked up,\n"
     ".BR lens-poly (5));\n"
     "when that file is not found the message names the lens and the path.\n"},
    {0, "fnumber", "N", OPT_POSITIVE, OPT_AT(imaging_cli, fnumber),
     .help = "stop the lens down to f-number N (efl over entrance pupil diameter, paraxial, "
             "object at infinity) by scaling the aperture stop's semi-diameter",
     .def = "the lens's own, or the f-number a system records",
     .man = "A lens opens no wider than its stop allows, and is stopped down to f/10000 at\n"
            "most (outside that range an error gives it). A fitted system keeps the\n"
            "aperture it was fitted with; one fitted to samples traced with\n"
            ".B \"lens-trace \\-\\-fnumber\"\n"
            "records that f-number\n"
            ".RB ( \"meta fnumber\" ),\n"
            "and the lens it is shown or compared with is stopped down to it unless\n"
            ".B \\-\\-fnumber\n"
            "is given.\n"
            "The titles of the pictures state the f-number and the focus.\n"},
    {.type = OPT_GROUP, OPT_AT(imaging_cli, lopt), .group = lens_cli_table},
    {0}};

void imaging_cli_default(imaging_cli *a, const char *wavelengths)
{
    memset(a, 0, sizeof *a);
    a->wavelengths = a->wavelengths_default = wavelengths;
    a->focus = "file";
    a->object_distance = INFINITY;
    a->fnumber = NAN;
    lens_cli_options_init(&a->lopt);
}

void imaging_cli_finish(const char *prog, imaging_cli *a, const char *const *operands, int n)
{
    if (n == 0)
        diag_die(prog, "no lens given (see --help)");
    a->input = operands[0];
    /* the table goes to stdout: a closed one is refused before any picture is drawn */
    cli_check_stdout(prog);
    cli_check_output(prog, a->png);
    lens_err err;
    a->nl = wavelengths_parse(a->wavelengths, a->lambda, IMAGING_MAX_WAVELENGTHS, &err);
    if (a->nl < 0)
        diag_die(prog, "--wavelengths: %s", err.msg);
    a->primary = a->nl / 2;
    if (focus_mode_parse(a->focus, &a->focus_mode) != 0)
        diag_die(prog, "--focus: '%s' is not file, paraxial or best", a->focus);
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* The design file's wavelengths in place of the command's default, shortest first
 * (ones the analyses do not take, or more than they hold, leave the default). */
static void file_wavelengths(imaging_cli *a, const lens_t *lens)
{
    int n = lens->nwaves;
    if (n < 1 || n > IMAGING_MAX_WAVELENGTHS)
        return;
    for (int i = 0; i < n; i++)
        if (!(lens->wave_um[i] >= 0.2 && lens->wave_um[i] <= 2.5))
            return;
    double primary = lens_file_primary_wave(lens);
    if (a->nl == 1) {
        a->lambda[0] = primary, a->primary = 0;
        return;
    }
    memcpy(a->lambda, lens->wave_um, sizeof(double) * (size_t)n);
    qsort(a->lambda, (size_t)n, sizeof(double), cmp_double);
    int m = 0;
    for (int i = 0; i < n; i++)
        if (m == 0 || a->lambda[i] != a->lambda[m - 1])
            a->lambda[m++] = a->lambda[i];
    a->nl = m;
    for (int i = 0; i < m; i++)
        if (a->lambda[i] == primary)
            a->primary = i;
}

int imaging_cli_models(imaging_cli *a, imaging_models *models, imaging im[2],
                       const char *names[2], lens_err *err)
{
    int rc = imaging_models_load(a->input, a->compare, a->lens, lens_cli_options_get(&a->lopt),
                                 models, err);
    lens_cli_options_free(&a->lopt);
    if (rc == 0 && a->wavelengths == a->wavelengths_default)
        file_wavelengths(a, &models->lens);
    /* A system fitted to samples of the stopped-down lens records that f-number: the lens
     * it is shown or compared with is stopped down alike, unless --fnumber says. */
    const poly_system *sys = models->sys ? models->sys : models->compare;
    const char *recorded = rc == 0 && sys ? poly_get_meta(sys, "fnumber") : NULL;
    double fnumber = a->fnumber;
    if (isnan(fnumber) && recorded && parse_double(recorded, &fnumber) != 0) {
        lens_errf(err, models->sys ? a->input : a->compare, 0,
                  "meta fnumber '%s' is not a number", recorded);
        rc = -1;
    }
    if (rc == 0 && !isnan(fnumber) && (rc = lens_set_fnumber(&models->lens, fnumber, err)) != 0 &&
        isnan(a->fnumber)) { /* the system's own f-number: it is the file to correct */
        lens_err e = *err;
        lens_errf(err, models->sys ? a->input : a->compare, 0, "meta fnumber: %s", e.msg);
    }
    if (rc != 0) {
        imaging_models_free(models);
        return -1;
    }
    return imaging_models_setup(models, a->object_distance, im, names);
}

int imaging_cli_load(const char *prog, imaging_cli *a, imaging_models *models, imaging im[2],
                     const char *names[2])
{
    lens_err err;
    int n = imaging_cli_models(a, models, im, names, &err);
    if (n < 0) {
        diag_print(prog, &err);
        exit(1);
    }
    return n;
}

const char *imaging_cli_basename(const imaging_cli *a)
{
    const char *slash = strrchr(a->input, '/');
    return slash ? slash + 1 : a->input;
}

void imaging_cli_setup(const imaging_cli *a, const imaging_models *m, double lambda,
                       double sensor_shift, imaging_setup *s)
{
    paraxial_data p;
    lens_err err;
    s->fnumber = s->file_focus_distance = NAN;
    if (paraxial_compute(&m->lens, lambda, &p, &err) == 0)
        s->fnumber = p.fnumber, s->file_focus_distance = p.focus_distance;
    char object[64], sensor[128];
    if (isfinite(a->object_distance))
        snprintf(object, sizeof object, "object at %.4g mm", a->object_distance);
    else
        snprintf(object, sizeof object, "object at infinity");
    if (a->focus_mode == FOCUS_FILE && isinf(s->file_focus_distance))
        snprintf(sensor, sizeof sensor, "sensor as in the file (focused at infinity)");
    else if (a->focus_mode == FOCUS_FILE && s->file_focus_distance < 0 && p.sensor_distance < p.bfl)
        /* no real object is sharp there: say how far short of the infinity focus */
        snprintf(sensor, sizeof sensor, "sensor as in the file (%.3g mm short of the infinity focus)",
                 p.bfl - p.sensor_distance);
    else if (a->focus_mode == FOCUS_FILE && s->file_focus_distance < 0)
        /* behind the infinity focus, on a point inside the lens (a fisheye's front focus
         * lies behind its first surface) */
        snprintf(sensor, sizeof sensor,
                 "sensor as in the file (%.3g mm beyond the infinity focus, focused %.4g mm behind "
                 "the first surface)",
                 p.sensor_distance - p.bfl, -s->file_focus_distance);
    else if (a->focus_mode == FOCUS_FILE)
        snprintf(sensor, sizeof sensor, "sensor as in the file (focused at %.4g mm)",
                 s->file_focus_distance);
    else
        snprintf(sensor, sizeof sensor, "sensor at the %s focus (moved %.3g mm)",
                 a->focus_mode == FOCUS_BEST ? "best" : "paraxial", sensor_shift);
    snprintf(s->text, sizeof s->text, "f/%.3g, %s, %s", s->fnumber, object, sensor);
}

void imaging_setup_print(table_out *t, const imaging_setup *s, const imaging_models *m)
{
    if (!t->json) {
        fputs("# ", t->f);
        text_line(t->f, m->lens.name[0] ? m->lens.name : "lens");
        fputs(": ", t->f);
        text_line(t->f, s->text);
        fputc('\n', t->f);
        return;
    }
    table_out_keys(t, "setup", NULL);
    table_out_key_str(t, "lens", m->lens.name);
    table_out_key_num(t, "fnumber", s->fnumber);
    table_out_key_num(t, "file_focus_distance_mm", s->file_focus_distance);
    table_out_key_str(t, "description", s->text);
}

int imaging_cli_model_warning(const imaging_models *m, report_warning *w)
{
    const poly_system *sys = m->sys ? m->sys : m->compare;
    char why[sizeof *w - 40];
    if (!sys || !poly_lens_mismatch(sys, m->lens.name, m->lens.path, why, sizeof why))
        return 0;
    snprintf(*w, sizeof *w, "%s: its figures here mean little", why);
    return 1;
}

void imaging_cli_end_table(table_out *t, FILE *log, const char *prog,
                           report_warning *warnings, int nwarnings)
{
    const char *list[2 * IMAGING_MAX_FIELDS + 1]; /* the fields' and the model's */
    if (nwarnings > 2 * IMAGING_MAX_FIELDS + 1)
        nwarnings = 2 * IMAGING_MAX_FIELDS + 1;
    for (int k = 0; k < nwarnings; k++) {
        fprintf(log, "%s: warning: %s\n", prog, warnings[k]);
        list[k] = warnings[k];
    }
    table_out_end(t, list, nwarnings);
}
