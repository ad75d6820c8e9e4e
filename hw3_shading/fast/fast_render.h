/* fast/fast_render.h — the fast renderer (hw3_fast). RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * A renderer for hw3_render's hook (scene.h, hw3_renderer): screen tiles on
 * threads, chosen explicitly (hw3_shading_ref --renderer fast, bench_perf,
 * test_fast_path). The result — image and counters — is the teaching
 * pipeline's, bit for bit; only the ms_* timings and buffer_bytes differ. It
 * keeps private copies of reference functions (fast_blinn_phong and others:
 * fast_render.c), and test_fast_path holds them equal. See fast_render.c and
 * docs/performance.md.
 */
#ifndef RAS_FAST_RENDER_H
#define RAS_FAST_RENDER_H

#include "scene.h"

typedef struct hw3_fast_settings {
    int threads; /* workers; 0 = $RAS_THREADS, else one per CPU */
    /* Not NULL: the number of fragments the fast path shaded for their
     * colour. It shades only those still visible when their screen tile is
     * drawn (the others' colours would be overwritten; the shaders it cannot
     * batch — trilinear texturing, or no lights — may also shade
     * one hidden fragment per object and worker to learn its counts, not
     * included here), while the counters report the teaching pipeline's
     * work, which shades every fragment that passes a depth test
     * (docs/performance.md). */
    uint64_t *shaded;
} hw3_fast_settings;

/* The fast renderer with these settings (NULL: the defaults), for
 * hw3_render_options.renderer; it keeps the pointer. It declines (the
 * teaching pipeline draws) culling, float edges and depth formats other than
 * z01. */
hw3_renderer hw3_fast_renderer(hw3_fast_settings *settings);

#endif
