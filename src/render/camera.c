/* The camera-ray API (camera.h) over the renderer's pieces: the lens map of
 * render_lens.h, the line pupil of render.h and the weight of render_ray_weight. */
#include "sparselens/camera.h"

#include <math.h>
#include <stdlib.h>

#include "sparselens/render.h"
#include "sparselens/render_lens.h"

struct lens_camera {
    render_camera cam;
    render_lens_ctx *ctx;
    render_sampler smp;
};

lens_camera *lens_camera_new(const lens_t *lens, const poly_system *sys, double sensor_w,
                             double sensor_h, double lambda_min, double lambda_max,
                             lens_err *err)
{
    char why[400];
    if (sys && poly_lens_mismatch(sys, lens->name, lens->path, why, sizeof why)) {
        lens_errf(err, lens->path, 0, "%s: a camera needs the system fitted to its lens", why);
        return NULL;
    }
    lens_camera *c = calloc(1, sizeof *c);
    if (!c) {
        lens_errf(err, lens->path, 0, "out of memory");
        return NULL;
    }
    c->ctx = sys ? render_lens_poly(sys, lens, sensor_w, sensor_h, &c->cam, err)
                 : render_lens_exact(lens, sensor_w, sensor_h, &c->cam, err);
    if (!c->ctx || render_sampler_lens(&c->smp, lens, lambda_min, lambda_max,
                                       0.5 * hypot(sensor_w, sensor_h), 0, err)) {
        lens_camera_free(c);
        return NULL;
    }
    return c;
}

void lens_camera_free(lens_camera *c)
{
    if (!c) return;
    render_sampler_free(&c->smp);
    render_lens_free(c->ctx);
    free(c);
}

int lens_camera_set_blades(lens_camera *c, int blades, double rotation, lens_err *err)
{
    return render_lens_set_blades(c->ctx, blades, rotation, err);
}

#define CHUNK 64
size_t lens_camera_rays(const lens_camera *c, size_t n, const double *samples, double *rays)
{
    const render_camera *cam = &c->cam;
    double in[CHUNK * 5], org[CHUNK * 3], dir[CHUNK * 3], eta[CHUNK], pdf[CHUNK];
    unsigned char pass[CHUNK];
    size_t passed = 0;
    for (size_t r0 = 0; r0 < n; r0 += CHUNK) {
        size_t m = n - r0 < CHUNK ? n - r0 : CHUNK;
        for (size_t i = 0; i < m; i++) {
            const double *s = samples + LENS_CAMERA_SAMPLE * (r0 + i);
            double *row = in + 5 * i;
            row[0] = (s[0] - 0.5) * cam->sensor_w;
            row[1] = (s[1] - 0.5) * cam->sensor_h;
            row[4] = s[2];
            pdf[i] = render_sampler_sample_2d(&c->smp, row[0], row[1], s[3], s[4], &row[2], &row[3]);
        }
        cam->map_batch(cam->ctx, m, in, org, dir, eta, pass);
        for (size_t i = 0; i < m; i++) {
            double *ray = rays + LENS_CAMERA_RAY * (r0 + i);
            ray[7] = pdf[i];
            if (!(pdf[i] > 0) || !pass[i]) {
                for (int k = 0; k < 6; k++) ray[k] = NAN;
                ray[6] = 0;
                continue;
            }
            render_lens_to_scene(org + 3 * i, ray);
            render_lens_to_scene(dir + 3 * i, ray + 3);
            ray[6] = render_ray_weight(in[5 * i + 2], in[5 * i + 3], pdf[i], eta[i]);
            passed++;
        }
    }
    return passed;
}

double lens_camera_ray(const lens_camera *c, double sx, double sy, double lambda, double r1,
                       double r2, double org[3], double dir[3])
{
    double sample[LENS_CAMERA_SAMPLE] = {sx, sy, lambda, r1, r2}, ray[LENS_CAMERA_RAY];
    lens_camera_rays(c, 1, sample, ray);
    for (int k = 0; k < 3; k++) org[k] = ray[k], dir[k] = ray[3 + k];
    return ray[6];
}
