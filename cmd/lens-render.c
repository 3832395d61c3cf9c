/* lens-render: render a scene through a lens (man 1 lens-render). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/diag.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/render_run.h"

static const char *usage =
    "usage: lens-render SCENE -o IMAGE.exr [--png PREVIEW.png] [--exact] [--spp N]\n"
    "                   [--threads N] [--cache DIR] [--rear-sampling] [--reference REF.exr]\n"
    "                   [--seed N] [--noise-against OTHER.exr]\n"
    "                   [--estimator eq13|full] [--quiet]\n"
    "Renders SCENE (man 5 lens-scene) through its lens with the Monte Carlo estimator of\n"
    "the supplement (Eq. 13): camera rays start on the pixel, take their direction from\n"
    "the line pupil, cross the lens by a polynomial system fitted for the effects the\n"
    "scene needs (cached), or by exact tracing with --exact, and gather light by\n"
    "next-event estimation. Writes R, G, B float channels to IMAGE.exr.\n"
    "  -o FILE            the OpenEXR image (required)\n"
    "  --png FILE         an 8-bit preview (exposed to the 99th percentile, sRGB)\n"
    "  --exact            trace every camera ray exactly instead of a polynomial system\n"
    "  --spp N            samples per pixel (default: the scene's)\n"
    "  --threads N        threads (default: all)\n"
    "  --cache DIR        fitted systems (default $XDG_CACHE_HOME/sparselens)\n"
    "  --rear-sampling    draw directions over the rear element instead of the line pupil\n"
    "  --reference FILE   print the RMS error against this image (same size)\n"
    "  --seed N           random seed (default: the scene's)\n"
    "  --noise-against F  print the noise figure against F, a render with another seed\n"
    "  --estimator E      eq13 (default): the simplified weight of Eq. 13; full: Eq. 3 with\n"
    "                     G-bar (Eq. 12) and p_A(s1) (Eq. 8) evaluated, |A| from the\n"
    "                     system's Jacobian (the same image, slower: a check)\n"
    "  --quiet            no decisions, progress or figures on stderr\n"
    LENS_CLI_OPTIONS_HELP;

typedef struct {
    int last;
} progress_state;

static void progress(void *ctx, double done)
{
    progress_state *p = ctx;
    int pct = (int)(100 * done);
    if (pct == p->last) return;
    p->last = pct;
    fprintf(stderr, "\rlens-render: %3d%%", pct);
    if (pct == 100) fputc('\n', stderr);
    fflush(stderr);
}

int main(int argc, char **argv)
{
    const char *prog = "lens-render";
    render_options o = {0};
    int quiet = 0;
    const char *v;
    lens_cli_options lopt;
    lens_cli_options_init(&lopt);
    for (int i = 1; i < argc; i++) {
        if (lens_cli_options_take(prog, argc, argv, &i, &lopt)) continue;
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) cli_help(usage);
        else if (cli_opt(prog, argc, argv, &i, "-o", &v)) o.exr = v;
        else if (cli_opt(prog, argc, argv, &i, "--png", &v)) o.png = v;
        else if (cli_opt(prog, argc, argv, &i, "--spp", &v)) o.spp = cli_count(prog, "--spp", v, 1, 1L << 30);
        else if (cli_opt(prog, argc, argv, &i, "--threads", &v))
            o.threads = (int)cli_count(prog, "--threads", v, 1, 1024);
        else if (cli_opt(prog, argc, argv, &i, "--cache", &v)) o.cache_dir = v;
        else if (cli_opt(prog, argc, argv, &i, "--reference", &v)) o.reference = v;
        else if (cli_opt(prog, argc, argv, &i, "--noise-against", &v)) o.noise_against = v;
        else if (cli_opt(prog, argc, argv, &i, "--seed", &v))
            o.seed = (unsigned long)cli_count(prog, "--seed", v, 1, 1L << 62);
        else if (cli_opt(prog, argc, argv, &i, "--estimator", &v)) {
            if (!strcmp(v, "full")) o.estimator = RENDER_ESTIMATOR_FULL;
            else if (!strcmp(v, "eq13")) o.estimator = RENDER_ESTIMATOR_EQ13;
            else diag_die(prog, "--estimator: '%s' is not eq13 or full", v);
        }
        else if (!strcmp(argv[i], "--exact")) o.exact = 1;
        else if (!strcmp(argv[i], "--rear-sampling")) o.rear_sampling = 1;
        else if (!strcmp(argv[i], "--quiet")) quiet = 1;
        else if (argv[i][0] == '-' && argv[i][1]) diag_die(prog, "unknown option '%s' (see --help)", argv[i]);
        else if (!o.scene) o.scene = argv[i];
        else diag_die(prog, "one scene only ('%s' is extra)", argv[i]);
    }
    if (!o.scene) diag_die(prog, "no scene given (see --help)");
    if (!o.exr) diag_die(prog, "no output image: give -o IMAGE.exr");
    progress_state ps = {-1};
    if (!quiet) o.log = stderr;
    if (!quiet && cli_progress_wanted()) {
        o.progress = progress;
        o.progress_ctx = &ps;
    }
    o.load = lens_cli_options_get(&lopt);
    render_stats st;
    lens_err err;
    int rc = render_run(&o, &st, &err);
    lens_cli_options_free(&lopt);
    if (rc) {
        diag_print(prog, &err);
        return 1;
    }
    if (!quiet) {
        fprintf(stderr, "time %.3f s, %.4g camera rays/s, %.1f%% of camera rays passed the lens\n",
                st.seconds, st.camera_rays / (st.seconds > 0 ? st.seconds : 1e-9),
                st.camera_rays > 0 ? 100 * st.passed_rays / st.camera_rays : 0);
    }
    return 0;
}
