/* bench_float_edges.h — the accuracy benchmark's float-edge rasterizer.
 * RASTER101-SOLUTION: a working rasterizer; this marker keeps it (and the
 * benchmark that links it) out of the student handout.
 *
 * The way a first rasterizer is written: plain float edge functions with a
 * closed ">= 0" test, no snapping, no top-left rule. It is NOT part of the
 * student contract (common/pipeline/stage4_raster.h) and the reference does not offer
 * it: it exists so that docs/accuracy.md (tests/bench/bench_accuracy_coverage.c) and the fan
 * figure of docs/hw2.md (hw2_rasterize/tools/hw2_figures.c) can count the
 * samples it covers twice or not at all on shared edges, next to the
 * reference's exact fixed-point coverage, which covers each exactly once.
 */
#ifndef RAS_BENCH_FLOAT_EDGES_H
#define RAS_BENCH_FLOAT_EDGES_H

#include "stage4_raster.h"

/* A ras_rasterize_fn: draws t into ctx->fb with float edge functions. Depth is
 * tested per sample as in the reference; every visible sample is shaded at its
 * own position (SSAA's rule; with RAS_AA_NONE's single centre sample that is
 * the reference's rule too; MSAA is drawn the same way, shading per sample). */
void bench_rasterize_float_edges(const ras_triangle *t, const ras_raster_ctx *ctx);

#endif
