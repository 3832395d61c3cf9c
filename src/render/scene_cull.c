/* Direction culling for camera rays (scene.h, scene_cull_new).
 *
 * A ray from a point q with |q| <= rho meets the sphere (c, r) only if its direction
 * lies within the cone of half-angle asin((r + rho) / |c|) around c: the sphere moved by
 * -q lies inside the sphere (c, r + rho). Directions with d_z > 0 are binned by the
 * octahedral map p = (d_x, d_y) / (|d_x| + |d_y| + d_z), which fills the unit diamond
 * without folds; each cell keeps the spheres whose cone overlaps the cone bounding the
 * cell (around its centre direction, out to its farthest corner, widened by half and a
 * hundredth of a radian: the cell is not quite a cap). Rays with d_z <= 0 and scenes
 * without spheres use the full loop. */
#include <math.h>
#include <stdlib.h>

#include "sparselens/scene.h"

#include "render/scene_camera_block.h"
#include "render/scene_light_simd.h"

#define CULL_GRID 64

struct scene_cull {
    int start[CULL_GRID * CULL_GRID + 1]; /* cell k's spheres: list[start[k] .. start[k+1]) */
    int *list;
};

static void dir_of(double px, double py, double d[3])
{
    double a = fabs(px) + fabs(py);
    if (a > 1) px /= a, py /= a, a = 1; /* onto the diamond's edge (d_z = 0) */
    double z = 1 - a, n = sqrt(px * px + py * py + z * z);
    d[0] = px / n, d[1] = py / n, d[2] = z / n;
}

static double angle(const double a[3], const double b[3])
{
    double c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return acos(c > 1 ? 1 : c < -1 ? -1 : c);
}

/* The spheres of cell (i, j), into list (or only counted when list is NULL). */
static int cell_spheres(const scene_t *s, double rho, int i, int j, int *list)
{
    double h = 2.0 / CULL_GRID, x0 = -1 + i * h, y0 = -1 + j * h, c[3], q[3], cell = 0;
    dir_of(x0 + h / 2, y0 + h / 2, c);
    for (int k = 0; k < 4; k++) {
        dir_of(x0 + (k & 1) * h, y0 + (k >> 1) * h, q);
        cell = fmax(cell, angle(c, q));
    }
    cell = 1.5 * cell + 0.01;
    int n = 0;
    for (size_t o = 0; o < s->nobj; o++) {
        const scene_object *ob = &s->obj[o];
        if (ob->kind != OBJ_SPHERE) continue;
        double dist = sqrt(ob->p[0] * ob->p[0] + ob->p[1] * ob->p[1] + ob->p[2] * ob->p[2]);
        int take = dist <= ob->radius + rho;
        if (!take) {
            double u[3] = {ob->p[0] / dist, ob->p[1] / dist, ob->p[2] / dist};
            take = angle(c, u) <= cell + asin((ob->radius + rho) / dist);
        }
        if (take) {
            if (list) list[n] = (int)o;
            n++;
        }
    }
    return n;
}

scene_cull *scene_cull_new(const scene_t *s, double rho)
{
    size_t nsph = 0;
    for (size_t o = 0; o < s->nobj; o++) nsph += s->obj[o].kind == OBJ_SPHERE;
    if (!nsph) return NULL;
    scene_cull *c = malloc(sizeof *c);
    if (!c) return NULL;
    c->start[0] = 0;
    for (int k = 0; k < CULL_GRID * CULL_GRID; k++)
        c->start[k + 1] = c->start[k] + cell_spheres(s, rho, k % CULL_GRID, k / CULL_GRID, NULL);
    c->list = malloc((c->start[CULL_GRID * CULL_GRID] + 1) * sizeof *c->list);
    if (!c->list) {
        free(c);
        return NULL;
    }
    for (int k = 0; k < CULL_GRID * CULL_GRID; k++)
        cell_spheres(s, rho, k % CULL_GRID, k / CULL_GRID, c->list + c->start[k]);
    return c;
}

void scene_cull_free(scene_cull *c)
{
    if (!c) return;
    free(c->list);
    free(c);
}

int scene_intersect_camera(const scene_t *s, const scene_cull *c, const double o[3],
                           const double d[3], double tmin, scene_hit *hit)
{
    if (!c || !(d[2] > 0)) return scene_intersect(s, o, d, tmin, INFINITY, hit);
    double a = fabs(d[0]) + fabs(d[1]) + d[2];
    int i = (int)((d[0] / a + 1) * (CULL_GRID / 2)), j = (int)((d[1] / a + 1) * (CULL_GRID / 2));
    i = i < 0 ? 0 : i >= CULL_GRID ? CULL_GRID - 1 : i;
    j = j < 0 ? 0 : j >= CULL_GRID ? CULL_GRID - 1 : j;
    int k = j * CULL_GRID + i;
    return scene_intersect_listed(s, c->list + c->start[k], c->start[k + 1] - c->start[k], o, d,
                                  tmin, INFINITY, hit);
}

#define MANY 64 /* rays a step of scene_intersect_camera_many */

void scene_intersect_camera_many(const scene_t *s, const scene_cull *c, int m, const double *O,
                                 const double *D, double tmin, scene_hit *h, unsigned char *hit)
{
    int i0 = 0;
#if SCENE_SIMD
    /* culled rays (d_z > 0 with a cull) in the kernel's lanes: every sphere is tested, and
     * those the cell leaves out miss (the cull's cones hold every ray that meets them) */
    double Ob[3 * MANY], Db[3 * MANY], t[MANY];
    int list[MANY], which[MANY];
    for (; c && scene_simd_ok() && i0 < m; i0 += MANY) {
        int n = 0, e = m - i0 < MANY ? m : i0 + MANY;
        for (int i = i0; i < e; i++) {
            const double *o = O + 3 * i, *d = D + 3 * i;
            if (!(d[2] > 0)) {
                hit[i] = (unsigned char)scene_intersect_camera(s, c, o, d, tmin, h + i);
                continue;
            }
            for (int k = 0; k < 3; k++) Ob[k * MANY + n] = o[k], Db[k * MANY + n] = d[k];
            list[n++] = i;
        }
        int n8 = (n + 7) / 8 * 8;
        for (int l = n; l < n8; l++) /* lanes past n repeat lane 0 */
            for (int k = 0; k < 3; k++) Ob[k * MANY + l] = Ob[k * MANY], Db[k * MANY + l] = Db[k * MANY];
        if (n) scene_simd_camera(s, n8, MANY, Ob, Db, tmin, which, t);
        for (int l = 0; l < n; l++) {
            int i = list[l];
            hit[i] = which[l] >= 0;
            if (hit[i]) scene_fill_hit(s, which[l], t[l], O + 3 * i, D + 3 * i, h + i);
        }
    }
#endif
    for (int i = i0; i < m; i++)
        hit[i] = (unsigned char)scene_intersect_camera(s, c, O + 3 * i, D + 3 * i, tmin, h + i);
}
