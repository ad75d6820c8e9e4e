/* stage3_setup.h — stage 3: perspective divide and viewport → screen space.
 *
 * x_screen = (x_ndc + 1) · width / 2, y_screen = (y_ndc + 1) · height / 2
 * (y up; the buffers do the image y-flip), and depth = (1 − z_ndc) / 2.
 * That minus sign is the GAMES101 viewport fix: with the course's projection
 * the near plane lands at z_ndc = +1, so without it larger would be closer and
 * the two hw2 triangles swap. With it, 0 is the near plane, 1 the far plane,
 * and smaller is closer; depth is clamped to [0, 1] (float clipping can leave
 * a cut vertex a rounding error outside the near or far plane). w is kept (clip w) for perspective correction.
 */
#ifndef STAGE3_SETUP_H
#define STAGE3_SETUP_H

#include "ras_triangle.h"
#include "stage1_vertex.h"

/* Screen-space vertex from a clip-space one (w > 0 guaranteed by stage 2). */
vec4s ras_viewport(vec4s p_clip, int width, int height);

/* Builds the screen-space triangle a, b, c; false when any coordinate or
 * varying is NaN/Inf (the triangle must be rejected, not drawn). */
bool ras_setup_triangle(const ras_clip_vertex *a, const ras_clip_vertex *b,
                        const ras_clip_vertex *c, int width, int height, ras_triangle *out);

#endif
