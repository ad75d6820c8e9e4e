/* ras_triangle.h — one triangle as the rasterizer sees it (after stage 3).
 *
 * v[i] is in SCREEN space: x, y in pixels (y up, pixel centres at +0.5),
 * z = depth, smaller is closer: in [0, 1] (0 = near plane) with the default
 * depth format, in [−1, 0) with RAS_DEPTH_INV_W (stage3_setup.h; either is
 * affine in screen space, so interpolate it linearly), and w = the vertex's
 * clip-space w (> 0; the view-space distance along -z for a perspective
 * camera). Keep w: perspective-correct interpolation needs 1/w (hw3).
 * The other arrays are the per-vertex varyings, still un-divided.
 */
#ifndef RAS_TRIANGLE_H
#define RAS_TRIANGLE_H

#include "ras_math.h"

/* The sub-pixel grid a rasterizer snaps corners to before coverage: 1/256 px
 * (8 bits, as D3D and llvmpipe; hw2's reference and the fast renderer).
 * Stage 3 takes inverse_w depth at the snapped positions (stage3_setup.h). */
#define RAS_SUBPIXEL_ONE 256.0

typedef struct ras_triangle {
    vec4s v[3];        /* screen x, y; depth z; clip w */
    vec3s color[3];    /* [0, 1] */
    vec3s normal[3];   /* view space, unit length at the vertices */
    vec2s uv[3];       /* texture coordinates */
    vec3s view_pos[3]; /* view-space position (for lighting) */
} ras_triangle;

/* Twice the signed area in screen space: > 0 when counter-clockwise (y up). */
static inline float ras_triangle_area2(const ras_triangle *t) {
    return (t->v[1].x - t->v[0].x) * (t->v[2].y - t->v[0].y) -
           (t->v[2].x - t->v[0].x) * (t->v[1].y - t->v[0].y);
}

#endif
