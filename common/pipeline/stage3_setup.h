/* stage3_setup.h — stage 3: perspective divide and viewport → screen space.
 *
 * x_screen = (x_ndc + 1) · width / 2, y_screen = (y_ndc + 1) · height / 2
 * (y up; the buffers do the image y-flip). w is kept (clip w) for perspective
 * correction. The depth the rasterizer interpolates and compares ("smaller is
 * closer", buffer cleared to +INFINITY) depends on the depth format:
 *
 *   RAS_DEPTH_Z01 (default): depth = (1 − z_ndc) / 2. That minus sign is the
 *     GAMES101 viewport fix: with the course's projection the near plane lands
 *     at z_ndc = +1, so without it larger would be closer and the two hw2
 *     triangles swap. With it, 0 is the near plane, 1 the far plane; depth is
 *     clamped to [0, 1] (float clipping can leave a cut vertex a rounding
 *     error outside the near or far plane).
 *
 *   RAS_DEPTH_INV_W: depth = −z_near / w, in [−1, 0): −1 at the near plane,
 *     → 0 at infinity. This is reversed-z with an infinite far plane (GPUs
 *     store z_near / w, 1 = near) negated so that smaller is still closer and
 *     the rasterizer's contract does not change. Why it is better:
 *       - 1/w is affine in screen space (like z/w), so interpolating it with
 *         screen-space barycentrics is exact, as the rasterizer does;
 *       - it is computed straight from w with one rounding (a division),
 *         instead of the projection's z row, the divide and 1 − z, which
 *         each round near 1 by about as much as two distant surfaces differ;
 *       - far surfaces get values near 0, where floats are dense: relative
 *         precision is the same at every distance, while Z01's step near 1 is
 *         a fixed 6e-8, i.e. z_near·δ/d² collapses with the distance d;
 *       - each corner's depth is taken at the position the rasterizer snaps
 *         it to (1/RAS_SUBPIXEL_ONE px), on the triangle's own depth plane
 *         (computed in double; ras_setup_triangle_depth), so depth is
 *         interpolated from the same positions as coverage. Without that the
 *         snap tilts each triangle's depth plane its own way by up to 1/512
 *         px of slope, and two parallel surfaces swapped order at gaps of
 *         1e-6 to 4e-6 of their distance.
 *     Measured (the accuracy report's §5b, instructors' edition: parallel
 *     planes at distances 1–1000, tilts 0–85°, turned so that their corners
 *     snap differently): two surfaces keep their order as far as their
 *     float clip-space corners carry it — everywhere from a gap of 4e-6 of their distance, and at
 *     1e-6 within 0.2% of the samples of what the exact depths of those
 *     corners, rounded once, keep (at 3e-7 about as well as those exact
 *     depths on average); below that the gap is one or two float steps and
 *     nothing keeps it.
 *     z_near must be the projection's near distance (the w of a point on the
 *     near plane); a vertex the clipper cut a rounding error nearer than that
 *     is clamped to −1. The far plane is still clipped by stage 2; the
 *     encoding just does not depend on it.
 *     View depth w itself is NOT offered: w is not affine in screen space
 *     (it is 1/(affine)), so interpolating it linearly between the vertices
 *     bends it — for a triangle with w from 1 to 4 the midpoint of an edge
 *     gets 2.5 instead of 1.6 — and intersecting surfaces would meet in the
 *     wrong place.
 */
#ifndef RAS_STAGE3_SETUP_H
#define RAS_STAGE3_SETUP_H

#include "ras_triangle.h"
#include "stage1_vertex.h"

typedef enum ras_depth_format {
    RAS_DEPTH_Z01,   /* (1 − z_ndc) / 2 in [0, 1]: the GAMES101 viewport (default) */
    RAS_DEPTH_INV_W, /* −z_near / w in [−1, 0): reversed-z, infinite far, negated */
} ras_depth_format;
#define RAS_DEPTH_FORMAT_COUNT 2

/* "z01", "inverse_w" (the names scene files use); "?" out of range. */
const char *ras_depth_format_name(ras_depth_format format);
/* The same names in enum order, for parsers: ras_names_depth (ras_names.h). */

/* Screen-space vertex from a clip-space one (w > 0 guaranteed by stage 2),
 * with RAS_DEPTH_Z01 depth. */
vec4s ras_viewport(vec4s p_clip, int width, int height);

/* The same with the depth in `format`; z_near is used by RAS_DEPTH_INV_W only
 * (> 0). x, y and w are the same in every format. */
vec4s ras_viewport_depth(vec4s p_clip, int width, int height, ras_depth_format format,
                         float z_near);

/* Builds the screen-space triangle a, b, c (RAS_DEPTH_Z01 depth); false when
 * any coordinate or varying is NaN/Inf (the triangle must be rejected, not
 * drawn). */
bool ras_setup_triangle(const ras_clip_vertex *a, const ras_clip_vertex *b,
                        const ras_clip_vertex *c, int width, int height, ras_triangle *out);

/* The same with the depth in `format` (see ras_viewport_depth). With
 * RAS_DEPTH_INV_W each corner's z is the triangle's depth plane at the
 * corner's snapped x, y (see above; a triangle too thin to define its plane
 * that finely keeps ras_viewport_depth's z); x, y, w and Z01 depth are
 * ras_viewport_depth's. */
bool ras_setup_triangle_depth(const ras_clip_vertex *a, const ras_clip_vertex *b,
                              const ras_clip_vertex *c, int width, int height,
                              ras_depth_format format, float z_near, ras_triangle *out);

#endif
