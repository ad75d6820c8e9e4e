/* fast/fast_render.h — the fast renderer (library fast). RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * hw3's frame drawn in screen tiles on threads, organised like Mesa's
 * llvmpipe (fast_priv.h lists its stages), and chosen explicitly: by
 * hw3_shading_ref --renderer fast (fast_hw3.c), bench_perf and the tests.
 * The result — image and counters — is the teaching pipeline's (hw3_render),
 * bit for bit; only the ms_* timings and buffer_bytes differ. It keeps
 * private copies of some reference functions for speed; fast/README.md
 * lists every one with the test that holds it equal. See docs/performance.md.
 */
#ifndef RAS_FAST_RENDER_H
#define RAS_FAST_RENDER_H

#include "scene.h"

typedef struct fast_settings {
    int threads; /* workers; 0 = $RAS_THREADS, else one per CPU */
    /* Not NULL: the number of fragments the fast path shaded for their
     * colour. It shades only those still visible when their screen tile is
     * drawn (the others' colours would be overwritten; the shaders it cannot
     * batch — trilinear texturing, or no lights — may also shade
     * one hidden fragment per object and worker to learn its counts, not
     * included here), while the counters report the teaching pipeline's
     * work, which shades every fragment that passes a depth test
     * (docs/performance.md). Left as it was when the frame is declined. */
    uint64_t *shaded;
} fast_settings;

/* hw3_render's frame — the same arguments, image and counters — drawn by the
 * fast renderer (settings NULL: the defaults). 1: drawn; 0: failed (err set:
 * bad sizes, out of memory); -1: declined, nothing done — the caller draws
 * the frame with hw3_render. It declines culling, depth formats other than
 * z01, scenes of more than 64 objects, and frames whose buffers are kept
 * (opt->dump_dir; the program's window and --dump are the shell's, fast_hw3.c). */
int fast_render(const ras_scene *scene, ras_scene_assets *assets, const hw3_render_options *opt,
                const fast_settings *settings, ras_image *out, ras_counters *stats, ras_error *err);

#endif
