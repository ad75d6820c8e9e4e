/* ras_texture.h — textures: an image plus how it is addressed, and mip levels.
 *
 * Conventions:
 *   - texel (i, j): i = column from the left, j = row from the BOTTOM, so that
 *     v = 0 is the bottom of the picture (the OBJ/OpenGL convention; the image
 *     file's row 0 is the top, so a lookup reads image row height-1-j);
 *   - texel centres sit at (i + 0.5) / width: continuous coordinate
 *     u_img = u * width - 0.5 puts texel i's centre at u_img = i;
 *   - wrap: RAS_WRAP_REPEAT or RAS_WRAP_CLAMP (clamp-to-edge); lookups never
 *     read outside the image, whatever u, v are (NaN reads texel 0).
 * Mip levels are built only when asked (trilinear filtering needs them).
 * Ownership: *_create / *_load return heap objects freed by ras_texture_destroy.
 */
#ifndef RAS_TEXTURE_H
#define RAS_TEXTURE_H

#include <assert.h>

#include "ras_error.h"
#include "ras_image.h"

typedef enum ras_wrap { RAS_WRAP_REPEAT, RAS_WRAP_CLAMP } ras_wrap;

#define RAS_TEXTURE_MAX_LEVELS 16

typedef struct ras_texture {
    int width, height;  /* level 0 */
    vec3s *texels;      /* level 0, row j = 0 is the bottom row (v = 0) */
    ras_wrap wrap;
    int level_count;    /* 1 until ras_texture_build_mips() */
    int level_width[RAS_TEXTURE_MAX_LEVELS], level_height[RAS_TEXTURE_MAX_LEVELS];
    vec3s *levels[RAS_TEXTURE_MAX_LEVELS]; /* levels[0] == texels */
} ras_texture;

/* From an image (copied, flipped so row 0 is the bottom). */
ras_texture *ras_texture_from_image(const ras_image *img, ras_wrap wrap, ras_error *err);
ras_texture *ras_texture_load(const char *path, ras_wrap wrap, ras_error *err);
void ras_texture_destroy(ras_texture *tex);

/* Built-in textures (no files needed). */
ras_texture *ras_texture_create_checker(int size, int squares, vec3s a, vec3s b);
ras_texture *ras_texture_create_brick(int size);
/* A height map in [0,1] (grey): smooth bumps, for bump and displacement mapping. */
ras_texture *ras_texture_create_bumps(int size, int bumps);

/* Box-filtered mip chain down to 1x1 (idempotent); false on OOM. */
bool ras_texture_build_mips(ras_texture *tex);

/* Texel at integer (i, j) of a level after wrapping: never out of bounds. */
vec3s ras_texture_texel(const ras_texture *tex, int level, int i, int j);

/* Nearest-texel lookup (given to students as the worked example). */
vec3s ras_texture_sample_nearest(const ras_texture *tex, float u, float v);

/* Wraps an integer texel index into [0, n) by the texture's wrap mode.
 * Defined here so that it inlines: a bilinear lookup makes four of these
 * calls, and as a call each cost more than the arithmetic it wraps. */
static inline int ras_texture_wrap_index(ras_wrap wrap, int i, int n) {
    assert(n > 0);
    if ((unsigned)i < (unsigned)n) return i; /* already inside: most calls */
    if (wrap == RAS_WRAP_CLAMP) return i < 0 ? 0 : n - 1;
    /* C's % truncates toward zero, so -1 % n is -1: shift negatives up. */
    int r = i % n;
    return r < 0 ? r + n : r;
}

#endif
