/* stage4_raster.h — stage 4 of the pipeline: coverage, depth test, and the
 * hand-off to the fragment stage. This header is the CONTRACT that hw2 fills:
 * the pipeline calls a ras_rasterize_fn for every screen-space triangle and a
 * ras_resolve_fn for every pixel at the end of the frame. The student
 * (hw2_rasterize/rasterizer.c) and the reference (instructors' edition)
 * implement the same functions; common/ holds no implementation of them.
 *
 * What a rasterizer must do for one triangle (see docs/hw2.md):
 *   for each pixel of the triangle's bounding box, clamped to the screen:
 *     for each sample s of ctx->pattern (pixel (x, y) samples at
 *     (x + offsets[s].x, y + offsets[s].y)):
 *       if the sample is covered and its interpolated depth is smaller than
 *       fb->depth[sample index]: store the depth and the fragment's colour.
 *   The colour comes from ctx->shade (once per pixel for MSAA and NONE, once
 *   per sample for SSAA), or is the interpolated vertex colour when NULL.
 */
#ifndef RAS_STAGE4_RASTER_H
#define RAS_STAGE4_RASTER_H

#include "ras_counters.h"
#include "ras_error.h"
#include "ras_framebuffer.h"
#include "ras_sample_pattern.h"
#include "ras_triangle.h"
#include "stage5_fragment.h"

/* THE RANGE of a rasterizer's input (part of this contract): every corner's
 * screen x and y within ±RAS_RASTER_MAX_COORD = 2^17 px, inclusive. There the
 * reference's 1/256-px snap and its double edge functions are exact (whole
 * numbers of 2^-16 px² below 2^53 of them: the reference rasterizer), so
 * coverage is exact and watertight. Beyond it a triangle is
 * REFUSED, not drawn approximately: the pipeline checks every triangle with
 * ras_raster_check_range before it calls the rasterize hook (student's or
 * reference's), draws nothing of a triangle out of range, counts it in
 * triangles_rejected_range and keeps the first refusal's message, which names
 * the corner and its position (ras_pipeline.refused). The instructors'
 * edition's fast renderer refuses and counts at the same point with the
 * same test. From a scene it cannot happen: the clipper's guard band keeps every
 * corner within 4.5 frames of RAS_IMAGE_MAX_SIDE = 16384 px (73 728 px); a
 * screen-space caller meets it through ras_pipeline_draw_screen_triangle.
 * A rasterizer called straight, outside the pipeline, with coordinates
 * beyond the range is outside this contract (the reference then still clamps
 * its box and never wraps, but its edge functions round). */
#define RAS_RASTER_MAX_COORD 131072.0f

typedef enum ras_aa_mode {
    RAS_AA_NONE, /* one sample at the pixel centre */
    RAS_AA_MSAA, /* coverage and depth per sample, shading once per pixel */
    RAS_AA_SSAA, /* everything per sample */
} ras_aa_mode;

typedef struct ras_raster_ctx {
    ras_framebuffer *fb;
    ras_aa_mode aa;
    ras_sample_pattern pattern; /* pattern.count == fb->samples */
    ras_shade_fn shade; /* NULL: interpolated vertex colour */
    void *shade_user;
    ras_counters *counters; /* may be NULL */
} ras_raster_ctx;

typedef void (*ras_rasterize_fn)(const ras_triangle *t, const ras_raster_ctx *ctx);

/* The final colour of screen pixel (x, y) from its samples. */
typedef vec3s (*ras_resolve_fn)(const ras_framebuffer *fb, int x, int y);

const char *ras_aa_mode_name(ras_aa_mode aa);

/* True when every corner of t lies within ±RAS_RASTER_MAX_COORD in x and y
 * (a NaN does not). Otherwise false, and err (may be NULL) says which corner
 * is where, and the range. */
bool ras_raster_check_range(const ras_triangle *t, ras_error *err);

/* The same test without the message, for per-triangle loops. */
static inline bool ras_raster_in_range(const ras_triangle *t) {
    bool ok = true;
    for (int i = 0; i < 3; i++)
        ok &= t->v[i].x >= -RAS_RASTER_MAX_COORD && t->v[i].x <= RAS_RASTER_MAX_COORD &&
              t->v[i].y >= -RAS_RASTER_MAX_COORD && t->v[i].y <= RAS_RASTER_MAX_COORD;
    return ok;
}

#endif
