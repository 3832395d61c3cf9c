/* The shared command line of lens-spot and lens-distort (see imaging_cli.h). */
#include "sparselens/imaging_cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"

void imaging_cli_parse(const char *prog, const char *usage, int argc, char **argv,
                       imaging_cli *a, imaging_cli_flag own, void *ctx)
{
    const char *wl = a->wavelengths ? a->wavelengths : "d", *dist = NULL;
    memset(a, 0, sizeof *a);
    a->wavelengths = wl;
    a->focus = "file";
    lens_cli_options_init(&a->lopt);
    for (int i = 1; i < argc; i++) {
        if (lens_cli_common_take(prog, usage, argc, argv, &i, &a->lopt))
            continue;
        if (cli_opt(prog, argc, argv, &i, "--fields", &a->fields) ||
            cli_opt(prog, argc, argv, &i, "--object-distance", &dist) ||
            cli_opt(prog, argc, argv, &i, "--wavelengths", &a->wavelengths) ||
            cli_opt(prog, argc, argv, &i, "--focus", &a->focus) ||
            cli_opt(prog, argc, argv, &i, "--compare", &a->compare) ||
            cli_opt(prog, argc, argv, &i, "--lens", &a->lens) ||
            cli_opt(prog, argc, argv, &i, "--png", &a->png) ||
            (own && own(prog, argc, argv, &i, ctx)))
            continue;
        if (argv[i][0] == '-' && argv[i][1] != '\0')
            diag_die(prog, "unknown option '%s' (see --help)", argv[i]);
        if (a->input)
            diag_die(prog, "one lens or system expected, got '%s' and '%s'", a->input, argv[i]);
        a->input = argv[i];
    }
    if (!a->input)
        diag_die(prog, "no lens given (see --help)");
    lens_err err;
    a->nl = wavelengths_parse(a->wavelengths, a->lambda, IMAGING_MAX_WAVELENGTHS, &err);
    if (a->nl < 0)
        diag_die(prog, "--wavelengths: %s", err.msg);
    if (focus_mode_parse(a->focus, &a->focus_mode) != 0)
        diag_die(prog, "--focus: '%s' is not file, paraxial or best", a->focus);
    a->object_distance = dist ? cli_positive(prog, "--object-distance", dist) : INFINITY;
}

int imaging_cli_load(const char *prog, imaging_cli *a, imaging_models *models, imaging im[2],
                     const char *names[2])
{
    lens_err err;
    int rc = imaging_models_load(a->input, a->compare, a->lens, lens_cli_options_get(&a->lopt),
                                 models, &err);
    lens_cli_options_free(&a->lopt);
    if (rc != 0) {
        diag_print(prog, &err);
        exit(1);
    }
    return imaging_models_setup(models, a->object_distance, im, names);
}

const char *imaging_cli_basename(const imaging_cli *a)
{
    const char *slash = strrchr(a->input, '/');
    return slash ? slash + 1 : a->input;
}
