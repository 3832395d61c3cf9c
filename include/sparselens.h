#ifndef SPARSELENS_H
#define SPARSELENS_H
/* libsparselens, the public API (man 3 sparselens): the only headers `make install` puts
 * in PREFIX/include, and every function they declare is exported by libsparselens.so
 * (its version script is made from them); the other headers of include/sparselens/ are
 * the commands' and are not installed.
 *
 *   load a lens        lens.h      lens_load, lens_free; paraxial.h: paraxial_compute
 *   trace              trace.h     trace_sample (one ray), trace_batch
 *   fit                fit.h       fit_system (samples in memory), fit_system_file
 *   evaluate a system  poly.h      poly_read, poly_eval, poly_eval_batch, poly_free
 *   a lens camera      camera.h    lens_camera_new, lens_camera_ray, lens_camera_rays
 *
 * Build with `pkg-config --cflags --libs sparselens`. Each header has extern "C" guards. */
#include "sparselens/diag.h"
#include "sparselens/glass.h"
#include "sparselens/lens.h"
#include "sparselens/ray_frames.h"
#include "sparselens/paraxial.h"
#include "sparselens/trace.h"
#include "sparselens/poly.h"
#include "sparselens/fit.h"
#include "sparselens/camera.h"

#endif
