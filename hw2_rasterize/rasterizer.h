/* rasterizer.h — hw2: from a screen-space triangle to covered, depth-tested samples.
 *
 * Implemented twice with the same signatures: rasterizer.c (yours, TODOs) and
 * the reference solution (instructors' edition only). The pipeline
 * (common/pipeline/ras_pipeline.h) calls rasterize_triangle() for every triangle after
 * clipping and the viewport, and resolve_pixel() for every pixel when there are
 * several samples.
 * See docs/hw2.md, and common/pipeline/stage4_raster.h for the contract.
 *
 * Conventions: screen y grows up; pixel (x, y) covers [x, x+1) × [y, y+1) and
 * its centre is (x + 0.5, y + 0.5); depth: smaller is closer.
 *
 * Range: the pipeline hands rasterize_triangle only triangles whose corners
 * lie within ±RAS_RASTER_MAX_COORD = 2^17 px in x and y (stage4_raster.h);
 * there coverage must be exact (the reference's 1/256-px snap makes its
 * double edge functions exact). A triangle with a corner beyond is refused
 * by the pipeline with a message naming the corner, and counted
 * (triangles_rejected_range); it never reaches this code.
 */
#ifndef RAS_HW2_RASTERIZER_H
#define RAS_HW2_RASTERIZER_H

#include "stage4_raster.h"

/* Is the point (x, y) — any float position, so it serves sub-samples — inside
 * the triangle t (screen x, y of t->v[])? Either winding. A degenerate
 * (zero-area) triangle contains nothing. */
bool inside_triangle(float x, float y, const ras_triangle *t);

/* Screen-space barycentric coordinates (α, β, γ) of (x, y) in t: α+β+γ = 1 and
 * the point is α·v0 + β·v1 + γ·v2. Returns false (and leaves *bary as 0) when
 * the triangle is degenerate, instead of dividing by zero. */
bool compute_barycentric_2d(float x, float y, const ras_triangle *t, vec3s *bary);

/* Draws t into ctx->fb: coverage for each sample of ctx->pattern, depth test
 * per sample, colour from ctx->shade (per pixel for NONE/MSAA, per sample for
 * SSAA) or the interpolated vertex colour. */
void rasterize_triangle(const ras_triangle *t, const ras_raster_ctx *ctx);

/* The colour of screen pixel (x, y): the box-filtered average of its samples. */
vec3s resolve_pixel(const ras_framebuffer *fb, int x, int y);

#endif
