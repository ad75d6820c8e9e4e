/* stage6_resolve.c — see stage6_resolve.h. */
#include "stage6_resolve.h"

#include <assert.h>
#include <string.h> /* memcpy */

bool ras_resolve_frame(const ras_framebuffer *fb, ras_resolve_fn resolve, ras_image *out) {
    assert(out->width == fb->width && out->height == fb->height);
    if (fb->samples == 1) {
        /* One sample a pixel, rows in the image's order: the buffer IS the image. */
        memcpy(out->pixels, fb->color, (size_t)fb->width * (size_t)fb->height * sizeof *out->pixels);
        return false;
    }
    if (!resolve) {
        /* Sample 0 of each pixel; the buffer's row order is already the image's. */
        for (int i = 0; i < fb->width * fb->height; i++)
            out->pixels[i] = fb->color[(size_t)i * (size_t)fb->samples];
        return false;
    }
    for (int y = 0; y < fb->height; y++)
        for (int x = 0; x < fb->width; x++)
            out->pixels[ras_fb_pixel_index(fb, x, y)] = resolve(fb, x, y);
    return true;
}
