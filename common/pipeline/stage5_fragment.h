/* stage5_fragment.h — stage 5: the fragment hand-off from rasterizer to shader.
 *
 * The rasterizer (stage 4, hw2) decides WHERE a triangle is and calls a
 * ras_shade_fn to decide WHAT COLOUR it is there. hw3 supplies the shaders;
 * the pipeline falls back to the interpolated vertex colour.
 * Barycentrics here are SCREEN-space (λ): they interpolate depth (z/w is affine
 * in screen space) but not attributes — those need the 1/w correction (hw3).
 */
#ifndef RAS_STAGE5_FRAGMENT_H
#define RAS_STAGE5_FRAGMENT_H

#include "ras_math.h"
#include "ras_triangle.h"

typedef struct ras_fragment {
    int x, y;    /* screen pixel */
    vec2s p;     /* screen position shaded: the pixel centre, or the sample (SSAA) */
    vec3s bary;  /* screen-space barycentrics of p, summing to 1 */
    float depth; /* interpolated depth at p */
} ras_fragment;

typedef vec3s (*ras_shade_fn)(const ras_triangle *t, const ras_fragment *f, void *user);

/* Screen-space interpolation of the vertex colours (hw2's flat triangles). */
vec3s ras_shade_vertex_color(const ras_triangle *t, const ras_fragment *f, void *user);

#endif
