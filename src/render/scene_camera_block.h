#ifndef RENDER_SCENE_CAMERA_BLOCK_H
#define RENDER_SCENE_CAMERA_BLOCK_H
/* scene_intersect_camera for a block's camera rays at once (scene_cull.c): where the
 * processor has AVX-512, eight rays a step (scene_simd_camera), with the hits, objects
 * and ray parameters of scene_intersect_camera, bit for bit. Ray i is O[3 i ..],
 * D[3 i ..]; hit[i] is 1 and h[i] its record where it meets the scene. */
#include "sparselens/scene.h"

void scene_intersect_camera_many(const scene_t *s, const scene_cull *c, int m, const double *O,
                                 const double *D, double tmin, scene_hit *h, unsigned char *hit);

#endif
