/* lens-render: render a scene through a lens (man 1 lens-render). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/render_cli.h"

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
    render_cli c;
    render_cli_default(&c);
    const char *operand[1];
    if (opt_parse(&render_command, argc, argv, &c, operand, 1) == 0)
        diag_die(prog, "no scene given (see --help)");
    render_options o = c.run;
    int quiet = c.quiet;
    o.scene = operand[0];
    if (!o.exr && !o.emit_camera) diag_die(prog, "no output image: give -o IMAGE.exr");
    cli_check_output(prog, o.exr);
    /* the image must not be written over what it is compared with (the run would then
     * compare it with itself: rms 0) */
    cli_check_not_input(prog, o.exr, o.reference);
    cli_check_not_input(prog, o.exr, o.noise_against);
    if (o.exr && o.png && strcmp(o.exr, o.png) == 0)
        diag_die(prog, "--png: '%s' is also the EXR (-o): give the picture its own name", o.png);
    progress_state ps = {-1};
    if (!quiet) o.log = stderr;
    o.figures = stderr; /* asked for by name: shown with -q too */
    if (!quiet && cli_progress_wanted()) {
        o.progress = progress;
        o.progress_ctx = &ps;
    }
    o.load = lens_cli_options_get(&c.lens);
    render_stats st;
    lens_err err;
    int rc = render_run(&o, &st, &err);
    lens_cli_options_free(&c.lens);
    if (rc) {
        diag_print(prog, &err);
        return 1;
    }
    if (!quiet && !o.emit_camera) {
        fprintf(stderr, "time %.3f s (processor %.3f s), %.4g camera rays/s, %.1f%% of camera rays "
                "passed the lens\n", st.seconds, st.cpu_seconds, st.camera_rays / (st.seconds > 0 ? st.seconds : 1e-9),
                st.camera_rays > 0 ? 100 * st.passed_rays / st.camera_rays : 0);
    }
    return 0;
}
