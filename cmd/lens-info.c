/* lens-info: first-order data of a lens as "key value" lines, or the lens itself in
 * the project's format (--format lens), optionally refocused (--focus MM). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/info_cli.h"
#include "sparselens/field_of_view.h"
#include "sparselens/paraxial.h"

static const char *prog = "lens-info";

static void print_key(const char *key, double v)
{
    if (isinf(v))
        printf("%s %s\n", key, v > 0 ? "inf" : "-inf");
    else
        printf("%s %.10g\n", key, v == 0 ? 0.0 : v); /* no "-0" */
}

int main(int argc, char **argv)
{
    info_cli o;
    info_cli_default(&o);
    const char *operand[1];
    if (opt_parse(&info_command, argc, argv, &o, operand, 1) == 0)
        diag_die(prog, "no lens given (see --help)");
    const char *path = operand[0];
    double lambda = o.lambda, sw = o.sensor.w, sh = o.sensor.h, focus = o.focus;
    int as_lens = o.as_lens;

    lens_t lens;
    lens_err err;
    cli_load_lens(prog, path, lens_cli_options_get(&o.lens), &lens);
    lens_cli_options_free(&o.lens);
    if (!isnan(sw)) {
        lens.sensor_w = sw;
        lens.sensor_h = sh;
    }
    if (!isnan(focus)) {
        double t;
        if (paraxial_focus_thickness(&lens, lambda, focus, &t, &err) != 0) {
            diag_print(prog, &err);
            return 1;
        }
        lens.surf[lens.nsurf - 1].thickness = t;
        /* Notes about where the sensor was are no longer true: replace them. */
        char kept[sizeof lens.notes] = "";
        for (char *save, *line = strtok_r(lens.notes, "\n", &save); line;
             line = strtok_r(NULL, "\n", &save))
            if (!strstr(line, "focus"))
                snprintf(kept + strlen(kept), sizeof kept - strlen(kept), "%s\n", line);
        snprintf(kept + strlen(kept), sizeof kept - strlen(kept),
                 "sensor refocused by lens-info --focus %g (paraxial, at %g um)", focus, lambda);
        snprintf(lens.notes, sizeof lens.notes, "%s", kept);
        if (lens_finish(&lens, &err) != 0) {
            diag_print(prog, &err);
            return 1;
        }
        as_lens = 1;
    }
    if (as_lens) {
        lens_write(stdout, &lens);
        lens_free(&lens);
        return fflush(stdout) == 0 ? 0 : 1;
    }

    paraxial_data p;
    if (paraxial_compute(&lens, lambda, &p, &err) != 0) {
        diag_print(prog, &err);
        return 1;
    }
    if (p.afocal)
        fprintf(stderr, "%s: warning: %s: the lens has no power (afocal): efl, bfl, ffl and "
                        "fnumber are infinite\n", prog, path);
    printf("name %s\n", lens.name[0] ? lens.name : "-");
    print_key("wavelength", lambda);
    print_key("efl", p.efl);
    print_key("bfl", p.bfl);
    print_key("ffl", p.ffl);
    print_key("fnumber", p.fnumber);
    print_key("entrance_pupil_z", p.entrance_pupil_z);
    print_key("entrance_pupil_diameter", p.entrance_pupil_diameter);
    print_key("exit_pupil_z", p.exit_pupil_z);
    print_key("exit_pupil_diameter", p.exit_pupil_diameter);
    printf("stop_surface %d\n", p.stop_surface);
    print_key("total_track", p.total_track);
    if (isnan(lens.sensor_w)) {
        fprintf(stderr, "%s: warning: %s: no sensor size in the lens header; give --sensor WxH "
                        "for field_of_view_deg\n", prog, path);
        print_key("field_of_view_deg", NAN);
    } else {
        double fov, r_used, r = 0.5 * hypot(lens.sensor_w, lens.sensor_h);
        if (lens_field_of_view(&lens, lambda, r, &fov, &r_used, &err) != 0) {
            diag_print(prog, &err);
            lens_free(&lens);
            return 1;
        }
        if (r_used < r)
            fprintf(stderr, "%s: warning: the sensor diagonal (%.4g mm) reaches past the image circle "
                            "(radius %.4g mm); field_of_view_deg is the image circle's\n",
                    prog, 2 * r, r_used);
        printf("sensor %gx%g\n", lens.sensor_w, lens.sensor_h);
        print_key("field_of_view_deg", fov);
        print_key("image_circle_radius", r_used);
    }
    print_key("sensor_distance", p.sensor_distance);
    print_key("focus_distance", p.focus_distance);
    lens_free(&lens);
    return 0;
}
