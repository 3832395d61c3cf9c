#ifndef RENDER_SCENE_LIGHT_BLOCK_H
#define RENDER_SCENE_LIGHT_BLOCK_H
/* scene_direct_mis for many points at once (scene_light.c): lens-render shades a block's
 * lit hits together, so that each emitter's selection weight, the light samples on
 * disks and on spheres seen from outside, the BSDF sample's direction, the shadow rays
 * and the BSDF rays run eight points a step
 * (scene_light_simd.h); the choices between them stay per point. The terms are those of
 * scene_direct_mis at each point, bit for bit: point i is h[i] with the uniforms
 * u[5 i .. 5 i + 4], its terms into t[i]. */
#include "sparselens/scene.h"

void scene_direct_mis_many(const scene_t *s, int m, const scene_hit *h, const double *u,
                           scene_light_terms *t);

#endif
