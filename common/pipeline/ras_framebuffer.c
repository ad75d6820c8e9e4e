/* ras_framebuffer.c — see ras_framebuffer.h. */
#include "ras_framebuffer.h"

#include "ras_image.h"          /* RAS_IMAGE_MAX_SIDE */
#include "ras_memory.h"         /* ras_memory_check */
#include "ras_sample_pattern.h" /* RAS_MAX_SAMPLES */

#include <math.h>   /* INFINITY */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* calloc, malloc, free */

bool ras_framebuffer_check_size(int width, int height, int samples, ras_error *err) {
    if (width < 1 || height < 1 || width > RAS_IMAGE_MAX_SIDE || height > RAS_IMAGE_MAX_SIDE)
        return ras_error_set(err, "frame size %dx%d is out of range: expected 1..%d on each side",
                             width, height, RAS_IMAGE_MAX_SIDE);
    if (samples < 1 || samples > RAS_MAX_SAMPLES)
        return ras_error_set(err, "%d samples per pixel is out of range: expected 1..%d", samples,
                             RAS_MAX_SAMPLES);
    long long n = (long long)width * height * samples;
    if (n > RAS_FRAME_MAX_SAMPLES)
        return ras_error_set(
            err,
            "a %dx%d frame with %d samples per pixel needs %lld million "
            "samples (%.1f GiB); expected at most %ld million (%ld GiB): "
            "use a smaller --size or fewer --samples",
            width, height, samples, n / 1000000,
            (double)n * (sizeof(vec3s) + sizeof(float)) / (1 << 30),
            RAS_FRAME_MAX_SAMPLES / 1000000,
            (long)(RAS_FRAME_MAX_SAMPLES * (long)(sizeof(vec3s) + sizeof(float)) >> 30));
    /* Per-sample colour and depth, the resolved float image, its 8-bit copy,
     * and writing it. */
    char what[96];
    snprintf(what, sizeof what, "a %dx%d frame with %d sample%s per pixel", width, height, samples,
             samples == 1 ? "" : "s");
    return ras_memory_check((double)n * (sizeof(vec3s) + sizeof(float)) +
                                (double)width * height *
                                    (sizeof(vec3s) + 3 + RAS_MEMORY_ENCODE_BYTES_PER_PIXEL),
                            what, "use a smaller --size or fewer --samples", err);
}

ras_framebuffer *ras_framebuffer_create(int width, int height, int samples, ras_error *err) {
    if (!ras_framebuffer_check_size(width, height, samples, err)) return NULL;
    size_t n = (size_t)width * (size_t)height * (size_t)samples;
    ras_framebuffer *fb = calloc(1, sizeof *fb);
    if (fb) {
        fb->color = malloc(n * sizeof *fb->color);
        fb->depth = malloc(n * sizeof *fb->depth);
    }
    if (!fb || !fb->color || !fb->depth) {
        ras_framebuffer_destroy(fb);
        ras_error_set(err, "out of memory for a %dx%d frame with %d samples per pixel", width,
                      height, samples);
        return NULL;
    }
    fb->width = width;
    fb->height = height;
    fb->samples = samples;
    fb->bytes = n * (sizeof *fb->color + sizeof *fb->depth);
    ras_framebuffer_clear(fb, (vec3s){{0, 0, 0}});
    return fb;
}

void ras_framebuffer_destroy(ras_framebuffer *fb) {
    if (!fb) return;
    free(fb->color);
    free(fb->depth);
    free(fb);
}

void ras_framebuffer_clear(ras_framebuffer *fb, vec3s color) {
    size_t n = (size_t)fb->width * (size_t)fb->height * (size_t)fb->samples;
    for (size_t i = 0; i < n; i++) {
        fb->color[i] = color;
        fb->depth[i] = INFINITY;
    }
}
