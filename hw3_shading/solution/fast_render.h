/* solution/fast_render.h — the reference build's fast frame. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * hw3_render (scene.c) hands the frame here unless the plain teaching pipeline
 * is asked for (hw3_render_options.plain, or RAS_PLAIN=1). The result — image
 * and counters — is the plain pipeline's, bit for bit; only the ms_* timings
 * and buffer_bytes differ. See fast_render.c and docs/performance.md.
 */
#ifndef HW3_FAST_RENDER_H
#define HW3_FAST_RENDER_H

#include "scene.h"

/* False when the plain pipeline is wanted: opt->plain, or RAS_PLAIN set to
 * anything but "" or "0"; or needed: culling, float edges or a depth format
 * other than z01 (the fast path draws none of them). */
bool hw3_fast_wanted(const hw3_render_options *opt);

/* One frame of `scene`: models[i] is object i's model matrix; `stage` holds the
 * shader, its varyings and the per-scene payload fields. Adds this frame's
 * counters to *k (never NULL). False with err on bad sizes or out of memory. */
bool hw3_fast_render(const hw3_scene *scene, const hw3_render_options *opt,
                     const hw3_fragment_stage *stage, const mat4s *models, mat4s view,
                     mat4s projection, ras_image *out, ras_counters *k, ras_error *err);

#endif
