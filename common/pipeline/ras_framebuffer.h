/* ras_framebuffer.h — the colour and depth buffers the rasterizer writes.
 *
 * Layout (the GAMES101 get_index, stated once):
 *   - screen space has y growing UP; pixel (x, y) covers [x, x+1) × [y, y+1);
 *   - memory is row-major with the TOP image row first, so screen pixel (x, y)
 *     lives at pixel index (height - 1 - y) * width + x — the same index as the
 *     image pixel (col x, row height-1-y) of ras_image;
 *   - each pixel owns `samples` consecutive entries (sample s of pixel i is
 *     entry i * samples + s), in both the colour and the depth buffer. With no
 *     anti-aliasing samples == 1 and these are plain per-pixel buffers: no
 *     per-sample memory is allocated unless the scene asks for AA;
 *   - depth: smaller is closer, in the pipeline's depth format (stage3_setup.h:
 *     z01 runs 0 at near to 1 at far, inverse_w −1 at near towards 0 far away);
 *     cleared to +INFINITY so the first fragment always wins in either.
 */
#ifndef RAS_FRAMEBUFFER_H
#define RAS_FRAMEBUFFER_H

#include "ras_error.h"
#include "ras_math.h"

#include <stddef.h> /* size_t */

typedef struct ras_framebuffer {
    int width, height;
    int samples;  /* per pixel, >= 1 */
    vec3s *color; /* width * height * samples */
    float *depth; /* width * height * samples */
    size_t bytes; /* memory held by color + depth, reported by --stats */
} ras_framebuffer;

/* Most samples (width * height * samples per pixel) one frame may hold:
 * 2^27, i.e. 2 GiB of colour and depth (e.g. 8192x8192 with 2 samples, or
 * 2048x2048 with 16). Beyond it --size or --samples asks for more memory than
 * a homework machine has; the programs say so up front instead of failing
 * (or being killed) in the middle of a render. */
#define RAS_FRAME_MAX_SAMPLES (1L << 27)

/* True when a width x height frame with `samples` per pixel is in range (each
 * side 1..RAS_IMAGE_MAX_SIDE, samples 1..RAS_MAX_SAMPLES, at most
 * RAS_FRAME_MAX_SAMPLES in all); otherwise false and err says which limit,
 * and what to change. */
bool ras_framebuffer_check_size(int width, int height, int samples, ras_error *err);

ras_framebuffer *ras_framebuffer_create(int width, int height, int samples, ras_error *err);
void ras_framebuffer_destroy(ras_framebuffer *fb);

/* Every sample to `color`, every depth to +INFINITY. */
void ras_framebuffer_clear(ras_framebuffer *fb, vec3s color);

/* Index of screen pixel (x, y), with the y-flip. Caller keeps x, y in range. */
static inline int ras_fb_pixel_index(const ras_framebuffer *fb, int x, int y) {
    return (fb->height - 1 - y) * fb->width + x;
}

/* Index of sample s of screen pixel (x, y) in color[] and depth[]. */
static inline int ras_fb_sample_index(const ras_framebuffer *fb, int x, int y, int s) {
    return ras_fb_pixel_index(fb, x, y) * fb->samples + s;
}

#endif
