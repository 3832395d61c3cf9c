/* The README's library example: a lens's first-order data and, through its lens camera,
 * the light a uniform emitter of radiance 1 gives the sensor (the mean weight of camera
 * rays over it: the relative illumination). Build it with the installed library:
 *   cc examples/exposure.c $(pkg-config --cflags --libs sparselens) -o exposure
 *   ./exposure dgauss.50mm 36 24 */
#include <stdio.h>
#include <stdlib.h>

#include <sparselens.h>

static double uniform(void) { return rand() / (RAND_MAX + 1.0); }

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: exposure LENS SENSOR_W SENSOR_H\n");
        return 2;
    }
    lens_t lens;
    lens_err err;
    paraxial_data p;
    lens_camera *cam = NULL;
    if (lens_load(argv[1], NULL, &lens, &err) ||
        paraxial_compute(&lens, GLASS_D_LINE, &p, &err) ||
        !(cam = lens_camera_new(&lens, NULL, atof(argv[2]), atof(argv[3]), GLASS_D_LINE,
                                GLASS_D_LINE, &err))) {
        fprintf(stderr, "exposure: %s\n", err.msg);
        return 1;
    }
    const int n = 100000;
    double sum = 0, org[3], dir[3];
    for (int k = 0; k < n; k++) {
        double sx = uniform(), sy = uniform(), r1 = uniform(), r2 = uniform();
        sum += lens_camera_ray(cam, sx, sy, GLASS_D_LINE, r1, r2, org, dir);
    }
    printf("%s: efl %.2f mm, f/%.2f, mean camera-ray weight %.4f\n", lens.name, p.efl,
           p.fnumber, sum / n);
    lens_camera_free(cam);
    lens_free(&lens);
    return 0;
}
