/* ras_texture.c — textures: images addressed by (u, v), built-in patterns, mips.
 *
 * Notes:
 *   - Texels are stored bottom row first (row j = 0 is v = 0), so the image
 *     is flipped once here and no lookup has to remember to flip.
 *   - Every lookup turns a float coordinate into an index in float/double
 *     arithmetic first and only converts a value already known to be in
 *     range: casting a NaN or a huge float to int is undefined behaviour in
 *     C, and on x86 gives INT_MIN, which a modulo then turns negative.
 *   - Procedural textures are deterministic (a small integer hash instead of
 *     rand()), so reference images are reproducible on every machine.
 *
 *   - A loaded texture keeps the decoder's bytes as level 0 (ras_texture.h
 *     says why and what it saves); its lookups and mips read each byte as
 *     the float ras_byte_to_unit gives, so they equal the float texture's.
 *
 * Dependencies: ras_image (copying from images, loading files), cglm.
 */
#include "ras_texture.h"

#include <assert.h> /* assert */
#include <math.h>   /* floor, fmod, cos, sqrt, isnan */
#include <stdint.h> /* uint32_t */
#include <stdlib.h> /* calloc, malloc, free */
#include <string.h> /* memcpy */

/* ------------------------------------------------------------------------ */
/* Creation and destruction                                                  */

/* The texels' floats for each byte: b / 255.0f folded by the compiler, which
 * rounds as the division at run time does (IEEE single, to nearest);
 * test_texture checks every entry against ras_byte_to_unit. */
#define UNIT1(b) ((b) / 255.0f)
#define UNIT4(b) UNIT1(b), UNIT1((b) + 1), UNIT1((b) + 2), UNIT1((b) + 3)
#define UNIT16(b) UNIT4(b), UNIT4((b) + 4), UNIT4((b) + 8), UNIT4((b) + 12)
#define UNIT64(b) UNIT16(b), UNIT16((b) + 16), UNIT16((b) + 32), UNIT16((b) + 48)
const float ras_texel_unit[256] = {UNIT64(0), UNIT64(64), UNIT64(128), UNIT64(192)};

double ras_texture_level0_bytes(ras_texel_format format, double w, double h) {
    return w * h * (format == RAS_TEXELS_RGB8 ? 3.0 : (double)sizeof(vec3s));
}

/* Levels 1.. hold a quarter, a sixteenth, ... of level 0's texels: a third
 * of them in all (a bound: odd sides round down). */
double ras_texture_mip_bytes(double w, double h) { return w * h * (double)sizeof(vec3s) / 3.0; }

/* A texture of w x h texels at level 0 with no texel storage yet, or NULL. */
static ras_texture *alloc_header(int w, int h, ras_wrap wrap) {
    if (w < 1 || h < 1 || w > RAS_IMAGE_MAX_SIDE || h > RAS_IMAGE_MAX_SIDE) return NULL;
    ras_texture *tex = calloc(1, sizeof *tex);
    if (!tex) return NULL;
    tex->width = w;
    tex->height = h;
    tex->wrap = wrap;
    tex->level_count = 1;
    tex->level_width[0] = w;
    tex->level_height[0] = h;
    return tex;
}

/* A FLOAT texture with room for w x h texels at level 0, or NULL. The texels
 * are not initialised: every caller below writes all of them. */
static ras_texture *alloc(int w, int h, ras_wrap wrap) {
    ras_texture *tex = alloc_header(w, h, wrap);
    if (!tex) return NULL;
    tex->format = RAS_TEXELS_FLOAT;
    tex->texels = malloc((size_t)w * (size_t)h * sizeof *tex->texels);
    if (!tex->texels) {
        free(tex);
        return NULL;
    }
    tex->levels[0] = tex->texels;
    return tex;
}

/* Why a texture of w x h texels could not be made. */
static void cannot_make(int w, int h, ras_error *err) {
    ras_error_set(err,
                  "cannot make a texture from a %dx%d image: expected 1..%d texels per side "
                  "and enough memory — use a smaller image",
                  w, h, RAS_IMAGE_MAX_SIDE);
}

ras_texture *ras_texture_from_image(const ras_image *img, ras_wrap wrap, ras_error *err) {
    assert(img);
    ras_texture *tex = alloc(img->width, img->height, wrap);
    if (!tex) {
        cannot_make(img->width, img->height, err);
        return NULL;
    }
    for (int j = 0; j < tex->height; j++) {
        int row = tex->height - 1 - j; /* image row 0 is the top, texel row 0 the bottom */
        for (int i = 0; i < tex->width; i++)
            tex->texels[(size_t)j * (size_t)tex->width + (size_t)i] = ras_image_get(img, i, row);
    }
    return tex;
}

/* Turns the rows of a w x h RGB8 picture upside down, in place, through
 * one row of scratch (memcpy's wide copies: a byte loop cost 3.5
 * instructions a byte); false when the scratch cannot be had. */
static bool flip_rows_rgb8(uint8_t *rgb, int w, int h) {
    size_t row = (size_t)w * 3;
    uint8_t *tmp = malloc(row);
    if (!tmp) return false;
    for (int j = 0; j < h / 2; j++) {
        uint8_t *a = rgb + (size_t)j * row, *b = rgb + (size_t)(h - 1 - j) * row;
        memcpy(tmp, a, row);
        memcpy(a, b, row);
        memcpy(b, tmp, row);
    }
    free(tmp);
    return true;
}

ras_texture *ras_texture_from_rgb8(uint8_t *rgb, int w, int h, ras_wrap wrap, ras_error *err) {
    assert(rgb);
    ras_texture *tex = alloc_header(w, h, wrap);
    /* The decoder's buffer becomes level 0: no second copy of the picture,
     * and no float one, at any moment. Image row 0 is the top, texel row 0
     * the bottom. */
    if (!tex || !flip_rows_rgb8(rgb, w, h)) {
        cannot_make(w, h, err);
        free(rgb);
        free(tex);
        return NULL;
    }
    tex->format = RAS_TEXELS_RGB8;
    tex->texels8 = rgb;
    return tex;
}

ras_texture *ras_texture_load(const char *path, ras_wrap wrap, ras_error *err) {
    assert(path);
    int w = 0, h = 0;
    /* the decoder's bytes become the texture: nothing made beside them
     * (mips are counted when they are built) */
    uint8_t *rgb = ras_image_load_rgb8_making(path, 0.0, &w, &h, err);
    if (!rgb) return NULL;
    return ras_texture_from_rgb8(rgb, w, h, wrap, err);
}

void ras_texture_destroy(ras_texture *tex) {
    if (!tex) return;
    for (int l = 1; l < tex->level_count && l < RAS_TEXTURE_MAX_LEVELS; l++) free(tex->levels[l]);
    free(tex->texels);
    free(tex->texels8);
    free(tex);
}

/* ------------------------------------------------------------------------ */
/* Built-in textures                                                         */

/* Integer hash (a variant of Chris Wellons' "lowbias32"): a few multiplies
 * give well-mixed bits, without rand()'s hidden global state. */
static uint32_t hash_u32(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

/* Hash of a 2D integer cell to [0, 1). */
static float hash01(uint32_t a, uint32_t b) {
    uint32_t h = hash_u32(a * 0x9E3779B9U ^ hash_u32(b + 0x632BE5ABU));
    return (float)(h >> 8) / 16777216.0f;
}

ras_texture *ras_texture_create_checker(int size, int squares, vec3s a, vec3s b) {
    if (squares < 1) squares = 1;
    if (squares > size) squares = size; /* a square smaller than a texel cannot be drawn */
    ras_texture *tex = alloc(size, size, RAS_WRAP_REPEAT);
    if (!tex) return NULL;
    for (int j = 0; j < size; j++)
        for (int i = 0; i < size; i++) {
            /* In 64 bits: i * squares can exceed INT_MAX for large sizes. */
            long long si = (long long)i * squares / size, sj = (long long)j * squares / size;
            tex->texels[(size_t)j * (size_t)size + (size_t)i] = ((si + sj) % 2 == 0) ? a : b;
        }
    return tex;
}

ras_texture *ras_texture_create_brick(int size) {
    ras_texture *tex = alloc(size, size, RAS_WRAP_REPEAT);
    if (!tex) return NULL;
    /* 8 courses of 4 bricks, every other course shifted by half a brick;
     * both counts divide the tile, so the texture repeats without a seam. */
    const int courses = 8, per_course = 4;
    const float mortar_v = 0.08f;               /* fraction of a course height */
    const float mortar_u = mortar_v * 0.5f;     /* a brick is twice as wide as high */
    const vec3s mortar = {{0.78f, 0.76f, 0.70f}};
    const vec3s brick = {{0.62f, 0.26f, 0.18f}};
    for (int j = 0; j < size; j++) {
        float y = ((float)j + 0.5f) / (float)size * (float)courses;
        int course = (int)y;
        float fy = y - (float)course;
        for (int i = 0; i < size; i++) {
            float x = ((float)i + 0.5f) / (float)size * (float)per_course + (course % 2 ? 0.5f : 0.0f);
            int col = (int)x;
            float fx = x - (float)col;
            vec3s c;
            if (fy < mortar_v || fx < mortar_u) {
                c = mortar;
            } else {
                /* The column index is wrapped so the half brick cut at the
                 * right edge has the colour of its other half on the left. */
                uint32_t id_col = (uint32_t)(col % per_course), id_row = (uint32_t)course;
                float shade = 0.80f + 0.35f * hash01(id_col, id_row);
                float grain = 0.94f + 0.06f * hash01((uint32_t)i, (uint32_t)j + 7919U);
                c = glms_vec3_scale(brick, shade * grain);
            }
            tex->texels[(size_t)j * (size_t)size + (size_t)i] = c;
        }
    }
    return tex;
}

ras_texture *ras_texture_create_bumps(int size, int bumps) {
    if (bumps < 1) bumps = 1;
    ras_texture *tex = alloc(size, size, RAS_WRAP_REPEAT);
    if (!tex) return NULL;
    /* One round bump per cell of a bumps x bumps grid: height
     * (1 + cos(pi r / R)) / 2 inside radius R, 0 outside. The profile has a
     * zero slope at the rim and the top, so the height and its gradient (what
     * bump mapping uses) are continuous and the tile repeats seamlessly. */
    const double radius = 0.45; /* in cell units: a flat gap between bumps */
    for (int j = 0; j < size; j++)
        for (int i = 0; i < size; i++) {
            double x = ((double)i + 0.5) / size * bumps, y = ((double)j + 0.5) / size * bumps;
            double dx = x - floor(x) - 0.5, dy = y - floor(y) - 0.5;
            double r = sqrt(dx * dx + dy * dy) / radius;
            float h = r >= 1.0 ? 0.0f : (float)(0.5 * (1.0 + cos(RAS_PI * r)));
            tex->texels[(size_t)j * (size_t)size + (size_t)i] = (vec3s){{h, h, h}};
        }
    return tex;
}

/* ------------------------------------------------------------------------ */
/* Mip levels                                                                */

/* Source index range [*first, *last] that destination index d of a level
 * with n_dst entries covers in a level with n_src entries: 2 texels, 3 for
 * the last one when n_src is odd (the leftover row/column folds in), 1 when
 * the source is a single texel already. */
static void mip_span(int d, int n_src, int n_dst, int *first, int *last) {
    if (n_src == 1) {
        *first = *last = 0;
        return;
    }
    *first = 2 * d;
    *last = 2 * d + 1;
    if (d == n_dst - 1 && (n_src % 2) == 1) *last = 2 * d + 2;
}

bool ras_texture_build_mips(ras_texture *tex) {
    assert(tex);
    if (tex->level_count > 1) return true; /* already built */
    tex->levels[0] = tex->texels; /* NULL for RGB8: level 1 is read through the table */
    tex->level_width[0] = tex->width;
    tex->level_height[0] = tex->height;
    int count = 1;
    while (count < RAS_TEXTURE_MAX_LEVELS) {
        int sw = tex->level_width[count - 1], sh = tex->level_height[count - 1];
        if (sw == 1 && sh == 1) break;
        int dw = sw > 1 ? sw / 2 : 1, dh = sh > 1 ? sh / 2 : 1;
        vec3s *dst = malloc((size_t)dw * (size_t)dh * sizeof *dst);
        if (!dst) {
            for (int l = 1; l < count; l++) {
                free(tex->levels[l]);
                tex->levels[l] = NULL;
            }
            tex->level_count = 1;
            return false;
        }
        const vec3s *src = tex->levels[count - 1];
        const uint8_t *src8 = count == 1 ? ras_texture_level0_rgb8(tex) : NULL;
        for (int y = 0; y < dh; y++) {
            int y0, y1;
            mip_span(y, sh, dh, &y0, &y1);
            for (int x = 0; x < dw; x++) {
                int x0, x1;
                mip_span(x, sw, dw, &x0, &x1);
                vec3s sum = glms_vec3_zero();
                for (int yy = y0; yy <= y1; yy++)
                    for (int xx = x0; xx <= x1; xx++) {
                        size_t k = (size_t)yy * (size_t)sw + (size_t)xx;
                        /* a byte's float is the one the float texture held:
                         * the same sums, the same mips */
                        vec3s t = src8 ? ras_texture_texel0(tex, k) : src[k];
                        sum = glms_vec3_add(sum, t);
                    }
                float n = (float)((y1 - y0 + 1) * (x1 - x0 + 1));
                dst[(size_t)y * (size_t)dw + (size_t)x] = glms_vec3_scale(sum, 1.0f / n);
            }
        }
        tex->levels[count] = dst;
        tex->level_width[count] = dw;
        tex->level_height[count] = dh;
        count++;
    }
    tex->level_count = count;
    return true;
}

/* ------------------------------------------------------------------------ */
/* Addressing                                                                */

vec3s ras_texture_texel(const ras_texture *tex, int level, int i, int j) {
    assert(tex);
    if (level < 0) level = 0;
    if (level >= tex->level_count) level = tex->level_count - 1;
    int w = level == 0 ? tex->width : tex->level_width[level];
    int h = level == 0 ? tex->height : tex->level_height[level];
    i = ras_texture_wrap_index(tex->wrap, i, w);
    j = ras_texture_wrap_index(tex->wrap, j, h);
    size_t k = (size_t)j * (size_t)w + (size_t)i;
    return level == 0 ? ras_texture_texel0(tex, k) : tex->levels[level][k];
}

/* floor(t * n) as an index already wrapped into [0, n). NaN and infinities
 * give 0 under REPEAT (no meaningful texel) and the nearer edge under CLAMP
 * for infinities; finite values of any size are reduced in double first
 * (fmod is exact), so the int conversion below only sees values in range. */
static inline int coord_to_index(ras_wrap wrap, float t, int n) {
    /* float * int (<= 2^14) is exact in double's 53-bit mantissa. */
    double p = (double)t * (double)n;
    if (fabs(p) < 0x1p30) {
        /* The usual case, in ints: floor by truncation (a step down for a
         * negative non-integer), then wrap (clamp or repeat) — the same index
         * as below without floor's and fmod's library calls. */
        int i = (int)p;
        if ((double)i > p) i--;
        return ras_texture_wrap_index(wrap, i, n);
    }
    double x = floor(p);
    if (isnan(x)) return 0;
    if (wrap == RAS_WRAP_CLAMP) {
        if (x < 0.0) return 0;
        if (x > (double)(n - 1)) return n - 1;
        return (int)x;
    }
    if (!isfinite(x)) return 0;
    double r = fmod(x, (double)n); /* in (-n, n), an integer */
    return ras_texture_wrap_index(wrap, (int)r, n);
}

vec3s ras_texture_sample_nearest(const ras_texture *tex, float u, float v) {
    assert(tex);
    /* Texel i covers u in [i/W, (i+1)/W): its centre is at u_img = u*W - 0.5
     * = i, and the nearest texel to u_img is floor(u_img + 0.5) = floor(u*W). */
    int i = coord_to_index(tex->wrap, u, tex->width);
    int j = coord_to_index(tex->wrap, v, tex->height);
    return ras_texture_texel0(tex, (size_t)j * (size_t)tex->width + (size_t)i);
}
