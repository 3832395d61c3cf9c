/* lens-distort: distortion curve, relative illumination, grid map and OpenCV camera
 * model check of a lens or a polynomial system (man lens-distort). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "distort.h"
#include "outfile.h"
#include "spot_run.h"

static const char *const prog = "lens-distort";

static const char *const usage =
    "usage: lens-distort LENS|SYSTEM.poly [options]\n"
    "Distortion of real chief rays (aimed through the stop centre) against f tan(theta)\n"
    "and the fisheye projections, relative illumination, grid map, OpenCV model fits.\n"
    "  --fields LIST          field angles in degrees, or object heights in mm with\n"
    "                         --object-distance; default 11 fields up to the largest\n"
    "  --object-distance MM   finite object, MM in front of the first vertex\n"
    "  --wavelengths LIST     um values or Fraunhofer names; the middle one is used\n"
    "                         (default d)\n"
    "  --focus file|paraxial|best   sensor plane (default file)\n"
    "  --illum-rays N         rays across a bundle for relative illumination (default 32;\n"
    "                         0 skips it)\n"
    "  --grid N               grid map points per side (default 17)\n"
    "  --mapping NAME         ideal projection of the grid map: rectilinear, equidistant,\n"
    "                         equisolid, stereographic, orthographic (default: the one\n"
    "                         the lens follows best)\n"
    "  --sensor WxH           sensor size in mm for the grid map (default: the lens\n"
    "                         header's, else a square inscribed in the largest field)\n"
    "  --exaggerate K         displacement factor in the picture (default: automatic)\n"
    "  --map FILE             write the grid displacement field as text ('-': stdout)\n"
    "  --png FILE             grid map picture\n"
    "  --opencv WxH           fit OpenCV's Brown-Conrady and fisheye models for a sensor\n"
    "                         of WxH pixels; prints coefficients and residuals\n"
    "  --compare SYSTEM.poly  also through a fitted system, beside the lens\n"
    "  --lens LENS            the lens of a SYSTEM.poly given as the first argument\n"
    "  --help\n";

static double nice_factor(double x)
{
    if (!(x > 1))
        return 1;
    double e = pow(10, floor(log10(x))), m = x / e;
    return (m < 2 ? 1 : m < 5 ? 2 : 5) * e;
}

int main(int argc, char **argv)
{
    const char *input = NULL, *fields_s = NULL, *dist_s = NULL, *wl_s = "d", *focus_s = "file",
               *illum_s = "32", *grid_s = "17", *mapping_s = NULL, *sensor_s = NULL, *exag_s = NULL,
               *map_path = NULL, *png = NULL, *opencv_s = NULL, *compare = NULL, *lens_path = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            cli_help(usage);
        if (cli_opt(prog, argc, argv, &i, "--fields", &fields_s) ||
            cli_opt(prog, argc, argv, &i, "--object-distance", &dist_s) ||
            cli_opt(prog, argc, argv, &i, "--wavelengths", &wl_s) ||
            cli_opt(prog, argc, argv, &i, "--focus", &focus_s) ||
            cli_opt(prog, argc, argv, &i, "--illum-rays", &illum_s) ||
            cli_opt(prog, argc, argv, &i, "--grid", &grid_s) ||
            cli_opt(prog, argc, argv, &i, "--mapping", &mapping_s) ||
            cli_opt(prog, argc, argv, &i, "--sensor", &sensor_s) ||
            cli_opt(prog, argc, argv, &i, "--exaggerate", &exag_s) ||
            cli_opt(prog, argc, argv, &i, "--map", &map_path) ||
            cli_opt(prog, argc, argv, &i, "--png", &png) ||
            cli_opt(prog, argc, argv, &i, "--opencv", &opencv_s) ||
            cli_opt(prog, argc, argv, &i, "--compare", &compare) ||
            cli_opt(prog, argc, argv, &i, "--lens", &lens_path))
            continue;
        if (argv[i][0] == '-' && argv[i][1] != '\0')
            diag_die(prog, "unknown option '%s' (see --help)", argv[i]);
        if (input)
            diag_die(prog, "one lens or system expected, got '%s' and '%s'", input, argv[i]);
        input = argv[i];
    }
    if (!input)
        diag_die(prog, "no lens given (see --help)");
    lens_err err;
    double wl[IMAGING_MAX_WAVELENGTHS];
    int nl = wavelengths_parse(wl_s, wl, IMAGING_MAX_WAVELENGTHS, &err);
    if (nl < 0)
        diag_die(prog, "--wavelengths: %s", err.msg);
    double lambda = wl[nl / 2];
    focus_mode focus = FOCUS_FILE;
    if (strcmp(focus_s, "paraxial") == 0)
        focus = FOCUS_PARAXIAL;
    else if (strcmp(focus_s, "best") == 0)
        focus = FOCUS_BEST;
    else if (strcmp(focus_s, "file") != 0)
        diag_die(prog, "--focus: '%s' is not file, paraxial or best", focus_s);
    int ris = (int)cli_count(prog, "--illum-rays", illum_s, 0, 2000);
    int ng = (int)cli_count(prog, "--grid", grid_s, 2, 501);
    proj_kind mapping = PROJ_RECTILINEAR;
    if (mapping_s && proj_parse(mapping_s, &mapping) != 0)
        diag_die(prog, "--mapping: '%s' is not rectilinear, equidistant, equisolid, stereographic "
                       "or orthographic", mapping_s);
    double sw = NAN, sh = NAN, exag = NAN, cvw = 0, cvh = 0;
    if (sensor_s) {
        cli_pair(prog, "--sensor", sensor_s, 'x', &sw, &sh);
        if (!(sw > 0 && sh > 0))
            diag_die(prog, "--sensor: width and height must be positive");
    }
    if (exag_s)
        exag = cli_positive(prog, "--exaggerate", exag_s);
    if (opencv_s) {
        cli_pair(prog, "--opencv", opencv_s, 'x', &cvw, &cvh);
        if (!(cvw >= 16 && cvh >= 16 && cvw <= 100000 && cvh <= 100000) || cvw != floor(cvw) ||
            cvh != floor(cvh))
            diag_die(prog, "--opencv: give the sensor size in whole pixels, e.g. 1920x1080");
    }
    double dist = dist_s ? cli_positive(prog, "--object-distance", dist_s) : INFINITY;
    int finite = isfinite(dist);
    if (opencv_s && finite)
        diag_die(prog, "--opencv needs an object at infinity");

    imaging_models models;
    if (imaging_models_load(input, compare, lens_path, &models, &err) != 0) {
        diag_print(prog, &err);
        return 1;
    }
    imaging im[2];
    const char *names[2];
    int nm = imaging_models_setup(&models, dist, im, names);
    double field[IMAGING_MAX_FIELDS];
    int nf;
    if (fields_s) {
        nf = numbers_parse(fields_s, "field", field, IMAGING_MAX_FIELDS, &err);
        if (nf < 0)
            diag_die(prog, "--fields: %s", err.msg);
    } else {
        double three[3];
        if (imaging_default_fields(&im[0], lambda, three, &err) < 0)
            diag_die(prog, "%s", err.msg);
        nf = 11;
        for (int i = 0; i < nf; i++)
            field[i] = round(three[2] * i / (nf - 1) * 100) / 100;
    }
    /* the sensor plane */
    double shift = 0;
    if (focus != FOCUS_FILE) {
        spot_request rq = {.im = {im[0]}, .model_names = {names[0]}, .nmodels = 1, .field = field,
                           .nfields = nf, .lambda = &lambda, .nl = 1, .primary = 0, .focus = focus,
                           .pattern = PUPIL_HEXAPOLAR, .rays = 100, .seed = 1};
        spot_report rep;
        if (spot_run(&rq, &rep, &err) != 0)
            diag_die(prog, "%s", err.msg);
        shift = rep.sensor_shift;
        spot_report_free(&rep);
    }
    for (int m = 0; m < nm; m++)
        im[m].sensor_shift = shift;

    distort_row *rows = calloc((size_t)(nm * nf), sizeof *rows);
    double scale = NAN;
    if (!rows)
        diag_die(prog, "out of memory");
    if (distort_scale(&im[0], lambda, &scale, &err) != 0)
        diag_die(prog, "%s", err.msg);
    for (int m = 0; m < nm; m++)
        if (distort_curve(&im[m], lambda, field, nf, ris, rows + m * nf, &err) != 0)
            diag_die(prog, "%s%s%s", m ? names[m] : "", m ? ": " : "", err.msg);
    printf("# columns: model %s h_real_mm h_ideal_mm distortion_pct rel_illum", finite ? "field_mm" : "field_deg");
    if (!finite)
        for (int k = 1; k < PROJ_COUNT; k++)
            printf(" %s_pct", proj_name((proj_kind)k));
    printf("\n");
    for (int m = 0; m < nm; m++)
        for (int i = 0; i < nf; i++) {
            const distort_row *r = rows + m * nf + i;
            printf("%s %.10g %.9g %.9g %.6f %.5f", names[m], r->field, r->h_real, r->h_ideal,
                   r->dist_pct, r->rel_illum);
            if (!finite)
                for (int k = 1; k < PROJ_COUNT; k++)
                    printf(" %.6f", r->map_pct[k]);
            printf("\n");
        }
    if (shift != 0)
        printf("# sensor plane moved %.9g mm along the axis (--focus %s)\n", shift, focus_s);
    if (finite) {
        printf("# ideal height: paraxial magnification %.9g x object height, at %.7g um\n", scale, lambda);
    } else {
        printf("# ideal heights with f = %.9g mm (paraxial focal length at %.7g um)\n", scale, lambda);
        for (int m = 0; m < nm; m++) {
            double rms;
            proj_kind best = distort_best_mapping(rows + m * nf, nf, &rms);
            printf("# best mapping (%s): %s, rms distortion %.4g %% over the fields\n", names[m],
                   proj_name(best), rms);
            if (m == 0 && !mapping_s)
                mapping = best;
        }
    }

    int rc = 0;
    if (png || map_path || opencv_s) {
        if (!(sw > 0)) {
            if (isfinite(models.lens.sensor_w) && isfinite(models.lens.sensor_h))
                sw = models.lens.sensor_w, sh = models.lens.sensor_h;
            else {
                double hmax = 0;
                for (int i = 0; i < nf; i++)
                    hmax = fmax(hmax, fabs(rows[i].h_real));
                sw = sh = 2 * hmax / sqrt(2.0);
            }
        }
        if (!(sw > 0))
            diag_die(prog, "no sensor size for the grid map: give --sensor WxH or non-zero --fields");
        double *pts[2] = {NULL, NULL};
        for (int m = 0; m < nm; m++) {
            pts[m] = malloc(sizeof(double) * 4 * (size_t)(ng * ng));
            if (!pts[m])
                diag_die(prog, "out of memory");
            if (distort_grid(&im[m], lambda, mapping, scale, sw / 2, sh / 2, ng, ng, pts[m]) == 0)
                diag_die(prog, "no point of the %s grid map reaches the sensor", names[m]);
        }
        if (map_path) {
            outfile *of = outfile_open(map_path, &err);
            if (!of)
                diag_die(prog, "%s", err.msg);
            FILE *f = outfile_stream(of);
            fprintf(f, "# grid map of %s: ideal %s image points (f or magnification %.9g) and "
                       "where the chief rays land; nan where none does\n",
                    input, proj_name(mapping), scale);
            fprintf(f, "# columns: model x_ideal_mm y_ideal_mm x_real_mm y_real_mm dx_um dy_um\n");
            for (int m = 0; m < nm; m++)
                for (int i = 0; i < ng * ng; i++) {
                    const double *p = pts[m] + 4 * i;
                    fprintf(f, "%s %.12g %.12g %.12g %.12g %.6g %.6g\n", names[m], p[0], p[1], p[2], p[3],
                            (p[2] - p[0]) * 1e3, (p[3] - p[1]) * 1e3);
                }
            if (outfile_commit(of, &err) != 0)
                diag_die(prog, "%s", err.msg);
        }
        if (png) {
            double maxd = 0;
            for (int m = 0; m < nm; m++)
                for (int i = 0; i < ng * ng; i++) {
                    const double *p = pts[m] + 4 * i;
                    if (isfinite(p[2]))
                        maxd = fmax(maxd, hypot(p[2] - p[0], p[3] - p[1]));
                }
            /* automatic: the largest displacement drawn at about a tenth of the half width */
            double factor = isfinite(exag) ? exag
                            : maxd > 0       ? nice_factor(0.1 * fmax(sw, sh) / 2 / maxd)
                                             : 1;
            char title[300];
            snprintf(title, sizeof title, "%s  distortion grid map (%s ideal, %.4g um)",
                     models.lens.name[0] ? models.lens.name : input, proj_name(mapping), lambda);
            if (distort_write_png(png, title, nm, names, (const double *const *)pts, ng, ng, sw / 2,
                                  sh / 2, factor, &err) != 0) {
                diag_print(prog, &err);
                rc = 1;
            } else
                printf("# grid map %s: %dx%d points over %gx%g mm, displacement exaggerated x%g\n",
                       png, ng, ng, sw, sh, factor);
        }
        if (opencv_s)
            for (int m = 0; m < nm && rc == 0; m++)
                for (int fe = 0; fe < 2; fe++) {
                    cv_camera_fit fit;
                    if (distort_opencv(&im[m], lambda, fe, pts[m], ng * ng, scale, sw / 2, sh / 2,
                                       (int)cvw, (int)cvh, fe ? 85 : 80, &fit, &err) != 0) {
                        printf("# opencv-%s (%s): %s\n", fe ? "fisheye" : "brown", names[m], err.msg);
                        continue;
                    }
                    if (fe)
                        printf("# opencv-fisheye (%s): fx %.8g fy %.8g cx %.8g cy %.8g k1 %.8g k2 %.8g "
                               "k3 %.8g k4 %.8g rms_px %.4g max_px %.4g\n",
                               names[m], fit.fx, fit.fy, fit.cx, fit.cy, fit.k[0], fit.k[1], fit.k[2],
                               fit.k[3], fit.rms, fit.max_err);
                    else
                        printf("# opencv-brown (%s): fx %.8g fy %.8g cx %.8g cy %.8g k1 %.8g k2 %.8g "
                               "p1 %.8g p2 %.8g k3 %.8g rms_px %.4g max_px %.4g\n",
                               names[m], fit.fx, fit.fy, fit.cx, fit.cy, fit.k[0], fit.k[1], fit.k[2],
                               fit.k[3], fit.k[4], fit.rms, fit.max_err);
                }
        free(pts[0]), free(pts[1]);
    }
    free(rows);
    imaging_models_free(&models);
    return rc;
}
