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
 *
 * Storage (issue 42 B6: a 9000² grey PNG took 1,162 MB as floats):
 *   - a texture loaded from a file keeps level 0 as the file's own bytes,
 *     3 per texel (format RAS_TEXELS_RGB8, texels8): every accepted file is
 *     decoded to 8 bits a channel (ras_image_load_rgb8), so floats would only
 *     spell out 256 values in 12 bytes. A lookup turns a byte into the float
 *     ras_byte_to_unit gives (ras_texel_unit, a table of exactly those
 *     floats), the value the float texture held: every lookup, picture and
 *     counter is the same bit for bit.
 *   - built-in textures (checker, brick, and bumps' smooth heights) and
 *     ras_texture_from_image keep floats (RAS_TEXELS_FLOAT, texels).
 *   - mip levels are always floats, whatever level 0 is: a box average of
 *     bytes is not a byte, and rounding the levels to bytes changed 0.9-2.1 %
 *     of the pixels of trilinear pictures by 1/255 (docs/robustness.md).
 *     They add 12 B × (1/4 + 1/16 + ...) ≈ 4 B per level-0 texel, and only
 *     when trilinear filtering builds them. So a loaded texture holds 3 B a
 *     texel (7 B with mips), a float one 12 B (16 B): a 9000² texture is
 *     243 MB (567 MB with mips) instead of 972 MB (1,296 MB).
 * Code that reads texels in bulk (the reference lookups) reads level 0
 * through tex->levels / ras_texture_level0_rgb8 (ras_texel_rgb8 for a byte
 * texel), or one texel through ras_texture_texel0; students read through
 * ras_texture_texel.
 */
#ifndef RAS_TEXTURE_H
#define RAS_TEXTURE_H

#include <assert.h>
#include <stdint.h> /* uint8_t */

#include "ras_error.h"
#include "ras_image.h"

typedef enum ras_wrap { RAS_WRAP_REPEAT, RAS_WRAP_CLAMP } ras_wrap;

#define RAS_TEXTURE_MAX_LEVELS 16

/* How level 0's texels are stored. */
typedef enum ras_texel_format {
    RAS_TEXELS_FLOAT, /* vec3s, 12 bytes a texel: built-in textures, ras_texture_from_image */
    RAS_TEXELS_RGB8,  /* R, G, B bytes, 3 a texel: textures loaded from files */
} ras_texel_format;

typedef struct ras_texture {
    int width, height;  /* level 0 */
    ras_texel_format format; /* level 0's; mip levels are always float */
    vec3s *texels;      /* level 0 when FLOAT (else NULL), row j = 0 is the bottom row (v = 0) */
    uint8_t *texels8;   /* level 0 when RGB8 (else NULL), 3 bytes a texel, same order */
    ras_wrap wrap;
    int level_count;    /* 1 until ras_texture_build_mips() */
    int level_width[RAS_TEXTURE_MAX_LEVELS], level_height[RAS_TEXTURE_MAX_LEVELS];
    vec3s *levels[RAS_TEXTURE_MAX_LEVELS]; /* levels[0] == texels (NULL when RGB8); 1.. float */
} ras_texture;

/* ras_byte_to_unit(b) for every byte b: the float an RGB8 texel's channel
 * stands for (a load, where the division would cost a lookup ~20 cycles). */
extern const float ras_texel_unit[256];

/* From an image (copied, flipped so row 0 is the bottom): a FLOAT texture. */
ras_texture *ras_texture_from_image(const ras_image *img, ras_wrap wrap, ras_error *err);
/* From w x h RGB bytes, top row first (ras_image_load_rgb8's layout), which
 * the texture takes over (flipped in place, no copy) or frees on failure: an
 * RGB8 texture. */
ras_texture *ras_texture_from_rgb8(uint8_t *rgb, int w, int h, ras_wrap wrap, ras_error *err);
/* A file through ras_image_load_rgb8 and ras_texture_from_rgb8: RGB8. */
ras_texture *ras_texture_load(const char *path, ras_wrap wrap, ras_error *err);
void ras_texture_destroy(ras_texture *tex);

/* Bytes a w x h texture holds at level 0 in `format`, and its mip chain
 * (always float) adds: the memory budget's estimates (ras_memory.h). */
double ras_texture_level0_bytes(ras_texel_format format, double w, double h);
double ras_texture_mip_bytes(double w, double h);

/* Built-in textures (no files needed). */
ras_texture *ras_texture_create_checker(int size, int squares, vec3s a, vec3s b);
ras_texture *ras_texture_create_brick(int size);
/* A height map in [0,1] (grey): smooth bumps, for bump and displacement mapping. */
ras_texture *ras_texture_create_bumps(int size, int bumps);

/* Box-filtered mip chain down to 1x1 (idempotent); false on OOM. */
bool ras_texture_build_mips(ras_texture *tex);

/* Texel at integer (i, j) of a level after wrapping: never out of bounds. */
vec3s ras_texture_texel(const ras_texture *tex, int level, int i, int j);

/* The RGB8 texel at p (3 bytes) as the floats the float texture held. */
static inline vec3s ras_texel_rgb8(const uint8_t *p) {
    return (vec3s){{ras_texel_unit[p[0]], ras_texel_unit[p[1]], ras_texel_unit[p[2]]}};
}

/* Level 0's texel at row-major index k (j * width + i), in either format. */
static inline vec3s ras_texture_texel0(const ras_texture *tex, size_t k) {
    if (tex->format == RAS_TEXELS_RGB8) return ras_texel_rgb8(tex->texels8 + 3 * k);
    return tex->texels[k];
}

/* Level 0's bytes (3 a texel), or NULL when it is stored as floats. */
static inline const uint8_t *ras_texture_level0_rgb8(const ras_texture *tex) {
    return tex->format == RAS_TEXELS_RGB8 ? tex->texels8 : NULL;
}

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
