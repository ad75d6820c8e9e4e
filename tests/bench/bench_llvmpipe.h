/* bench_llvmpipe.h — the classic hw3 scene through Mesa's llvmpipe, beside
 * the project's renderers (issue 18, item 1).
 *
 * The comparator program, tests/bench/bench_llvmpipe.c (built only when pkg-config
 * finds OSMesa), renders hw3_shading --model's scene (scenes/hw3_model.json)
 * — the same mesh, camera, lights, material and texture — through OpenGL 3.3 core on OSMesa
 * with GLSL ports of the five shaders of hw3_shading/solution/shading.c,
 * indexed geometry, no AA or MSAA 4x. llvmpipe reads LP_NUM_THREADS once,
 * when its screen is created, so each thread count is its own process:
 * bench_perf starts one per thread count (llvmpipe_start) and asks it for
 * frames between its own, frame by frame, over a pipe.
 *
 * This file's functions (tests/bench/bench_llvmpipe_client.c) need no OpenGL:
 * bench_perf links them whether or not OSMesa is installed.
 *
 * Protocol (one line per request on the child's stdin, text replies on its
 * stdout; started as `bench_llvmpipe --serve --model OBJ [--texture PNG]`):
 *   "frame SHADER AA"  renders one frame (AA: none | msaa), replies
 *                      "MS CPU_MS": wall-clock and process CPU time of the
 *                      frame (clear, draw, MSAA resolve, glFinish)
 *   "image SHADER AA"  renders one frame, replies "image W H" and then W·H·4
 *                      bytes RGBA, top row first (alpha: covered fraction)
 *   "quit"
 * The first line the child writes is "ready RENDERER" (GL_RENDERER).
 */
#ifndef RAS_BENCH_LLVMPIPE_H
#define RAS_BENCH_LLVMPIPE_H

#include "ras_image.h"
#include "scene.h" /* ras_scene_shader */

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct llvmpipe_child llvmpipe_child;

/* Starts `program --serve --model MODEL [--texture TEXTURE]` with
 * LP_NUM_THREADS=threads and waits for its "ready" line; `renderer` gets the
 * GL_RENDERER string. NULL (and a message on stderr) when it does not start. */
llvmpipe_child *llvmpipe_start(const char *program, int threads, const char *model,
                               const char *texture, char *renderer, size_t renderer_size);
bool llvmpipe_frame(llvmpipe_child *c, ras_scene_shader shader, bool msaa, double *ms, double *cpu_ms);
/* rgba: width·height·4 bytes, top row first. */
bool llvmpipe_image(llvmpipe_child *c, ras_scene_shader shader, bool msaa, int width, int height,
                    uint8_t *rgba);
void llvmpipe_stop(llvmpipe_child *c); /* NULL-safe */

/* ---- the pixel check ------------------------------------------------------ */

/* The tolerances (justified in tests/bench/bench_perf.md.in, "Against llvmpipe").
 * Coverage, both: the covered-pixel counts differ by at most 0.5 % (both
 * rasterize with the top-left rule at pixel centres, and MSAA uses the D3D
 * standard 4x positions in both, so they agree exactly on the scenes
 * measured; the margin is for other scenes' ties). Colour, on the pixels
 * both cover: without AA both shade every pixel at its centre, so the mean
 * absolute channel difference must be at most 1.0 level of 255 and at most
 * 1 % of the pixels may differ by more than 8 levels in some channel (the
 * remaining differences are llvmpipe's 8-bit texture filtering and its
 * pow/normalize approximations). With MSAA 4x a pixel that a triangle covers
 * only in part is shaded at a point each implementation chooses (OpenGL's
 * centroid: "any point" inside; the project: the covered, visible sample
 * nearest the centre), and on the teapot's high-frequency bump map that
 * moves whole texels: mean at most 3.0 levels, at most 15 % of the pixels
 * beyond 8. A shader port passes when both of its checks pass. */
#define LLVMPIPE_MAX_COVERAGE_DIFF 0.005
#define LLVMPIPE_BAD_LEVELS 8
#define LLVMPIPE_MAX_MEAN_DIFF_1X 1.0
#define LLVMPIPE_MAX_BAD_FRACTION_1X 0.01
#define LLVMPIPE_MAX_MEAN_DIFF_MSAA 3.0
#define LLVMPIPE_MAX_BAD_FRACTION_MSAA 0.15

typedef struct llvmpipe_check {
    long covered_ours, covered_llvmpipe; /* pixels with any sample covered */
    long covered_both, covered_one;      /* in both; in exactly one */
    double coverage_diff;                /* |ours − llvmpipe| / ours */
    double mean_diff;                    /* mean |Δ| per channel, 8-bit levels, covered in both */
    double bad_fraction;                 /* of covered_both: some channel differs by > BAD_LEVELS */
    int max_diff;                        /* largest channel difference, levels */
    bool pass;
} llvmpipe_check;

/* ours: the project's frame (floats, clear colour `clear` where nothing is
 * drawn — covered means "not exactly the clear colour", which the five shaders
 * never return on the classic scene: its ambient term and (n+1)/2 are never
 * 0); rgba: llvmpipe's frame, covered where alpha > 0. */
void llvmpipe_compare(const ras_image *ours, vec3s clear, const uint8_t *rgba, bool msaa,
                      llvmpipe_check *out);

/* The built-in Bézier teapot as an OBJ (bench_perf's model without --spot),
 * so it goes through exactly the classic model scene the spot cow does. */
bool bench_write_teapot_obj(const char *path);

#endif
