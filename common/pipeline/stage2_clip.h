/* stage2_clip.h — stage 2: clipping in homogeneous (clip) space, before the divide.
 *
 * Why before the divide: a vertex behind the eye has w < 0, and dividing by it
 * flips the vertex to the other side of the screen (the inverted triangle
 * across the screen); w = 0 gives Inf/NaN. Sutherland–Hodgman against:
 *   w >= RAS_CLIP_W_EPSILON      (never divide by ~0 or a negative w)
 *   -w <= z <= w                 (near and far planes)
 *   |x| <= G w, |y| <= G w       (a guard band G = RAS_CLIP_GUARD times the
 *                                 viewport: keeps screen coordinates inside
 *                                 the fixed-point range; the rasterizer clamps
 *                                 to the screen itself, so nothing visible is cut)
 * Attributes are interpolated linearly in clip space, which is exact there.
 *
 * Every plane is decided on the vertex's exact position in double
 * (ras_clip_vertex.p_exact: the vertex transform's product in double), and
 * with the camera's far distance (ras_clip_triangle_far) the far plane is
 * w <= far, the view depth itself: a float matrix's z row cannot say where
 * far is once near / far is below about 1e-7, and a float clip position
 * cannot say on which side of an edge-on triangle 1e-9 from the eye a pixel
 * lies (issue #42, B1 and B2).
 *
 * The contract, for any finite input: every corner of a RAS_CLIP_SPLIT
 * polygon is finite and inside all seven planes exactly (ras_clip_outcode
 * gives 0; in particular w >= RAS_CLIP_W_EPSILON; with a far distance, plane
 * 2 is w <= far, and z is clamped into [-w, w]). A cut is computed in
 * double and then put exactly on its plane (w = ε or far, z = ±w, x or y = ±G·w),
 * the polygon is tested against each plane as it stands after the previous
 * cuts (a new corner is clipped by every later plane it violates), and the
 * last rounding of a corner cut by a later plane, which can leave it an ulp
 * outside an earlier one, is clamped back. tests/unit/test_clip.c holds this
 * over 300 000 random legal cameras and 200 000 raw clip-space triangles.
 */
#ifndef RAS_STAGE2_CLIP_H
#define RAS_STAGE2_CLIP_H

#include "stage1_vertex.h"

#define RAS_CLIP_W_EPSILON 1e-5f
#define RAS_CLIP_GUARD 8.0f
/* A triangle clipped by 7 planes has at most 3 + 7 corners. */
#define RAS_CLIP_MAX_VERTICES 10

typedef enum ras_clip_result {
    RAS_CLIP_INSIDE,  /* untouched: out[0..2] is the input */
    RAS_CLIP_SPLIT,   /* cut by at least one plane: a convex polygon */
    RAS_CLIP_OUTSIDE, /* nothing left */
} ras_clip_result;

/* The planes a clip-space point is outside of: bit k for plane k (0 = w
 * epsilon, 1-2 = far and near, 3-6 = the guard band's sides); 0 = inside all.
 * A triangle is RAS_CLIP_INSIDE exactly when its corners' codes or to 0 and
 * RAS_CLIP_OUTSIDE at once when they and to non-zero, so a caller that draws
 * many triangles over shared vertices can code each vertex once. */
unsigned ras_clip_outcode(vec4s p_clip);

/* The same decided on the vertex's exact position (p_exact, or p_clip
 * widened when the vertex has none) in double, with plane 2 the far test
 * w <= z_far when z_far > 0 (the camera's far distance; w is the view
 * depth) and z >= -w otherwise. This is the classification
 * ras_clip_triangle_far clips by. */
unsigned ras_clip_vertex_outcode(const ras_clip_vertex *v, double z_far);

/* Clips one triangle; writes the convex polygon to out and its size to *count.
 * No far distance: plane 2 is z >= -w. */
ras_clip_result ras_clip_triangle(const ras_clip_vertex *a, const ras_clip_vertex *b,
                                  const ras_clip_vertex *c,
                                  ras_clip_vertex out[RAS_CLIP_MAX_VERTICES], int *count);

/* The same with the far plane at w = z_far (> 0; 0: z >= -w), every plane
 * decided and every cut made on the exact positions in double (issue #42:
 * the far plane at near / far = 1e-7, edge-on triangles 1e-9 from the
 * eye). The contract above holds for the corners of a RAS_CLIP_SPLIT
 * polygon; a RAS_CLIP_INSIDE triangle's corners have w <= z_far and may have
 * z a little below -w (between the float matrix's far plane and the true
 * one), which setup's depth clamp takes to the far plane's depth. */
ras_clip_result ras_clip_triangle_far(const ras_clip_vertex *a, const ras_clip_vertex *b,
                                      const ras_clip_vertex *c, double z_far,
                                      ras_clip_vertex out[RAS_CLIP_MAX_VERTICES], int *count);

#endif
