#ifndef SPARSELENS_FILE_FIELDS_H
#define SPARSELENS_FILE_FIELDS_H
/* What a design file states beyond its surfaces (Zemax YFLN/YAN/WAVM, CODE V YAN/YIM/WL,
 * kept in lens_t by the importers) as the defaults of the commands. */
#include "sparselens/imaging.h"
#include "sparselens/lens.h"

/* The file's primary wavelength (um): the one it marks, else its first, else the d line. */
double lens_file_primary_wave(const lens_t *lens);

/* The file's fields as the analyses take them (imaging.h): angles in degrees for an
 * object at infinity (image heights turned into the angles that image there, at the
 * primary wavelength), object heights in mm for a finite object; ascending, each once.
 * At most max. 0 when the file gives none for that kind of object; -1 with err set. */
int lens_file_fields(const lens_t *lens, double object_distance, double *field, int max,
                     lens_err *err);

/* Without a sensor size, the one the file's largest field implies: 3:2, its corner 3 %
 * beyond where that field's chief ray lands (as a 36x24 sensor's corner is the edge of
 * a 21.6 mm image circle), so that a system fitted over it images that field.
 * A file that states the axis alone gets the sensor of a 1 degree half field. 1 when
 * set, 0 when the lens has a sensor or the file no field, -1 with err set when the
 * largest field images nowhere. */
int lens_sensor_from_fields(lens_t *lens, lens_err *err);
#endif
