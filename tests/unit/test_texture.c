/* test_texture.c — cmocka tests for common/ras_texture: addressing (wrap,
 * nearest lookup, the v flip), the built-in textures, the mip chain, and
 * textures kept as bytes (RGB8) looking up what their float twins do.
 *
 * The edge cases (u, v = 0, 1, ±eps, NaN, ±1e30, ±Inf) are the ones that read
 * out of bounds in a naive lookup; the suite is meant to run under ASan, so an
 * out-of-bounds read fails here even when it happens to return a plausible
 * colour.
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#endif

#include <setjmp.h> /* required by cmocka.h */
#include <stdarg.h> /* required by cmocka.h */
#include <stddef.h> /* required by cmocka.h */
#include <stdint.h> /* required by cmocka.h */

#include <cmocka.h>

#include "ras_texture.h"

#include <limits.h> /* INT_MIN, INT_MAX */
#include <malloc.h> /* malloc_usable_size, mallinfo2 */
#include <math.h>   /* NAN, INFINITY, fabsf, nextafterf */
#include <stdio.h>  /* snprintf, remove */
#include <stdlib.h> /* mkdtemp */
#include <string.h> /* strstr, memcmp, memcpy */
#include <unistd.h> /* rmdir */

/* mallinfo2 is glibc 2.33's (Debian 11 has 2.31); ASan's allocator keeps its
 * own books, so the heap's totals are read only where they mean something. */
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33)) && \
    !defined(__SANITIZE_ADDRESS__)
#define TEST_HAS_MALLINFO2 1
#else
#define TEST_HAS_MALLINFO2 0
#endif

/* ------------------------------------------------------------------------ */
/* Helpers                                                                   */

/* A W x H texture whose texel (i, j) holds (i, j, 0), so a lookup tells
 * exactly which texel it read. */
static ras_texture *make_index_texture(int w, int h, ras_wrap wrap) {
    ras_image *img = ras_image_create(w, h, NULL);
    assert_non_null(img);
    for (int row = 0; row < h; row++)
        for (int col = 0; col < w; col++)
            ras_image_set(img, col, row, (vec3s){{(float)col, (float)(h - 1 - row), 0.0f}});
    ras_error err = {{0}};
    ras_texture *tex = ras_texture_from_image(img, wrap, &err);
    ras_image_destroy(img);
    if (!tex) fail_msg("ras_texture_from_image failed: %s", err.msg);
    return tex;
}

/* Asserts that sampling (u, v) reads texel (want_i, want_j). */
static void expect_nearest(const ras_texture *tex, float u, float v, int want_i, int want_j) {
    vec3s c = ras_texture_sample_nearest(tex, u, v);
    if (c.x != (float)want_i || c.y != (float)want_j)
        fail_msg("%s %dx%d: nearest(u=%g, v=%g) read texel (%g, %g), expected (%d, %d)",
                 tex->wrap == RAS_WRAP_REPEAT ? "REPEAT" : "CLAMP", tex->width, tex->height,
                 (double)u, (double)v, (double)c.x, (double)c.y, want_i, want_j);
}

static void assert_vec3_near(vec3s got, vec3s want, float tol, const char *what) {
    if (!(fabsf(got.x - want.x) <= tol && fabsf(got.y - want.y) <= tol && fabsf(got.z - want.z) <= tol))
        fail_msg("%s: got (%g, %g, %g), expected (%g, %g, %g) within %g", what, (double)got.x,
                 (double)got.y, (double)got.z, (double)want.x, (double)want.y, (double)want.z,
                 (double)tol);
}

static vec3s level_mean(const ras_texture *tex, int level) {
    int w = tex->level_width[level], h = tex->level_height[level];
    double s[3] = {0, 0, 0};
    for (int k = 0; k < w * h; k++)
        for (int c = 0; c < 3; c++) s[c] += tex->levels[level][k].raw[c];
    return (vec3s){{(float)(s[0] / (w * h)), (float)(s[1] / (w * h)), (float)(s[2] / (w * h))}};
}

/* ------------------------------------------------------------------------ */
/* Wrapping                                                                  */

/* REPEAT wraps negative indices up into [0, n) (C's % alone would give negatives). */
static void test_texture_wrap_index_repeat_negative(void **state) {
    (void)state;
    const struct { int i, n, want; } cases[] = {
        {0, 4, 0},  {3, 4, 3},  {4, 4, 0},  {7, 4, 3},       {-1, 4, 3},     {-4, 4, 0},
        {-5, 4, 3}, {-8, 4, 0}, {0, 1, 0},  {-13, 1, 0},     {INT_MIN, 4, 0}, {INT_MIN, 3, 1},
        {INT_MAX, 4, 3},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int got = ras_texture_wrap_index(RAS_WRAP_REPEAT, cases[k].i, cases[k].n);
        if (got != cases[k].want)
            fail_msg("REPEAT wrap_index(%d, n=%d) = %d, expected %d (negative indices must wrap up)",
                     cases[k].i, cases[k].n, got, cases[k].want);
    }
}

/* CLAMP pins indices below 0 to 0 and at or above n to n-1. */
static void test_texture_wrap_index_clamp(void **state) {
    (void)state;
    const struct { int i, n, want; } cases[] = {
        {0, 4, 0}, {3, 4, 3}, {4, 4, 3}, {100, 4, 3}, {-1, 4, 0}, {INT_MIN, 4, 0}, {INT_MAX, 4, 3},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int got = ras_texture_wrap_index(RAS_WRAP_CLAMP, cases[k].i, cases[k].n);
        if (got != cases[k].want)
            fail_msg("CLAMP wrap_index(%d, n=%d) = %d, expected %d", cases[k].i, cases[k].n, got,
                     cases[k].want);
    }
}

/* ras_texture_texel wraps out-of-range integer coordinates by the texture's mode. */
static void test_texture_texel_wraps(void **state) {
    (void)state;
    ras_texture *rep = make_index_texture(4, 3, RAS_WRAP_REPEAT);
    ras_texture *clp = make_index_texture(4, 3, RAS_WRAP_CLAMP);
    assert_vec3_near(ras_texture_texel(rep, 0, -1, -1), (vec3s){{3, 2, 0}}, 0, "REPEAT texel(-1,-1)");
    assert_vec3_near(ras_texture_texel(rep, 0, 9, 7), (vec3s){{1, 1, 0}}, 0, "REPEAT texel(9,7)");
    assert_vec3_near(ras_texture_texel(clp, 0, -1, -1), (vec3s){{0, 0, 0}}, 0, "CLAMP texel(-1,-1)");
    assert_vec3_near(ras_texture_texel(clp, 0, 9, 7), (vec3s){{3, 2, 0}}, 0, "CLAMP texel(9,7)");
    /* A level that does not exist (no mips built) reads level 0, not garbage. */
    assert_vec3_near(ras_texture_texel(rep, 5, 1, 1), (vec3s){{1, 1, 0}}, 0, "texel at a missing level");
    ras_texture_destroy(rep);
    ras_texture_destroy(clp);
}

/* ------------------------------------------------------------------------ */
/* Nearest lookup                                                            */

/* Sampling at each texel's centre ((i+0.5)/W, (j+0.5)/H) reads exactly that texel. */
static void test_texture_nearest_texel_centres(void **state) {
    (void)state;
    ras_texture *tex = make_index_texture(5, 3, RAS_WRAP_REPEAT);
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 5; i++) expect_nearest(tex, (i + 0.5f) / 5.0f, (j + 0.5f) / 3.0f, i, j);
    /* Just inside each texel's left/bottom edge still reads it. */
    for (int i = 0; i < 5; i++) expect_nearest(tex, i / 5.0f + 1e-4f, 0.5f, i, 1);
    ras_texture_destroy(tex);
}

/* REPEAT at the edges and beyond: 0, 1, -eps, 1+eps, NaN, ±1e30, ±Inf never leave the image. */
static void test_texture_nearest_edges_repeat(void **state) {
    (void)state;
    ras_texture *tex = make_index_texture(4, 2, RAS_WRAP_REPEAT);
    const float eps = 1e-6f;
    expect_nearest(tex, 0.0f, 0.0f, 0, 0);
    expect_nearest(tex, 1.0f, 1.0f, 0, 0);         /* floor(W) = W wraps to 0 */
    expect_nearest(tex, -eps, -eps, 3, 1);         /* just left of 0 is the last texel */
    expect_nearest(tex, 1.0f + eps, 1.0f + eps, 0, 0);
    expect_nearest(tex, -nextafterf(0.0f, 1.0f), 0.5f, 3, 1); /* smallest negative float */
    expect_nearest(tex, NAN, NAN, 0, 0);           /* NaN reads texel 0 */
    expect_nearest(tex, NAN, 0.75f, 0, 1);
    expect_nearest(tex, 1e30f, -1e30f, 0, 0);      /* 1e30 is a multiple of 4 and of 2 */
    expect_nearest(tex, INFINITY, -INFINITY, 0, 0);
    expect_nearest(tex, 2.3f, -0.3f, 1, 1);        /* 9.2 → 9 mod 4 = 1; -0.6 → -1 mod 2 = 1 */
    expect_nearest(tex, 16777217.0f, 0.25f, 0, 0); /* large but finite: exact in double */
    ras_texture_destroy(tex);
}

/* CLAMP at the edges and beyond: coordinates outside [0,1] read the edge texel. */
static void test_texture_nearest_edges_clamp(void **state) {
    (void)state;
    ras_texture *tex = make_index_texture(4, 2, RAS_WRAP_CLAMP);
    const float eps = 1e-6f;
    expect_nearest(tex, 0.0f, 0.0f, 0, 0);
    expect_nearest(tex, 1.0f, 1.0f, 3, 1); /* u = 1 must not read index W */
    expect_nearest(tex, -eps, -eps, 0, 0);
    expect_nearest(tex, 1.0f + eps, 1.0f + eps, 3, 1);
    expect_nearest(tex, NAN, NAN, 0, 0);
    expect_nearest(tex, 1e30f, -1e30f, 3, 0);
    expect_nearest(tex, -1e30f, 1e30f, 0, 1);
    expect_nearest(tex, INFINITY, -INFINITY, 3, 0);
    ras_texture_destroy(tex);
}

/* v = 0 is the bottom of the picture: in a 2x2 image with a red top-left pixel, (0.25, 0.75) reads red. */
static void test_texture_v_flip(void **state) {
    (void)state;
    ras_image *img = ras_image_create(2, 2, NULL);
    assert_non_null(img);
    const vec3s red = {{1, 0, 0}}, green = {{0, 1, 0}}, blue = {{0, 0, 1}}, white = {{1, 1, 1}};
    ras_image_set(img, 0, 0, red);   /* top-left in the file's order */
    ras_image_set(img, 1, 0, green); /* top-right */
    ras_image_set(img, 0, 1, blue);  /* bottom-left */
    ras_image_set(img, 1, 1, white); /* bottom-right */
    ras_texture *tex = ras_texture_from_image(img, RAS_WRAP_REPEAT, NULL);
    assert_non_null(tex);
    assert_vec3_near(ras_texture_sample_nearest(tex, 0.25f, 0.75f), red, 0,
                     "(0.25, 0.75) is the top-left: forgetting the v flip reads blue");
    assert_vec3_near(ras_texture_sample_nearest(tex, 0.75f, 0.75f), green, 0, "(0.75, 0.75) top-right");
    assert_vec3_near(ras_texture_sample_nearest(tex, 0.25f, 0.25f), blue, 0, "(0.25, 0.25) bottom-left");
    assert_vec3_near(ras_texture_sample_nearest(tex, 0.75f, 0.25f), white, 0, "(0.75, 0.25) bottom-right");
    /* Texel row j = 0 is the bottom row. */
    assert_vec3_near(ras_texture_texel(tex, 0, 0, 0), blue, 0, "texel (0,0) is the bottom-left pixel");
    assert_vec3_near(ras_texture_texel(tex, 0, 0, 1), red, 0, "texel (0,1) is the top-left pixel");
    ras_texture_destroy(tex);
    ras_image_destroy(img);
}

/* ------------------------------------------------------------------------ */
/* Files                                                                     */

/* Writes IMG to PATH (in the temporary folder DIR) and frees it; the test
 * fails, the folder removed, when it cannot be written. */
static void save_png_or_fail(ras_image *img, const char *dir, const char *path) {
    ras_error err = {{0}};
    bool saved = ras_image_save(img, path, &err);
    ras_image_destroy(img);
    if (!saved) {
        rmdir(dir);
        fail_msg("could not write the test PNG: %s", err.msg);
    }
}

/* A PNG saved and loaded back as a texture keeps its pixels, flipped so v = 0 is the bottom. */
static void test_texture_load_png_roundtrip(void **state) {
    (void)state;
    char dir[] = "/tmp/raster101_test_texture_XXXXXX";
    if (!mkdtemp(dir)) fail_msg("could not create a temporary directory for the PNG");
    char path[256];
    snprintf(path, sizeof path, "%s/tiny.png", dir);
    ras_image *img = ras_image_create(3, 2, NULL);
    assert_non_null(img);
    ras_image_set(img, 0, 0, (vec3s){{1, 0, 0}});
    ras_error err = {{0}};
    save_png_or_fail(img, dir, path);
    ras_texture *tex = ras_texture_load(path, RAS_WRAP_CLAMP, &err);
    remove(path);
    rmdir(dir);
    if (!tex) fail_msg("ras_texture_load of a PNG just written failed: %s", err.msg);
    assert_int_equal(tex->width, 3);
    assert_int_equal(tex->height, 2);
    assert_int_equal(tex->wrap, RAS_WRAP_CLAMP);
    assert_vec3_near(ras_texture_texel(tex, 0, 0, 1), (vec3s){{1, 0, 0}}, 1e-6f,
                     "the image's top-left pixel is texel (0, height-1)");
    assert_vec3_near(ras_texture_texel(tex, 0, 0, 0), (vec3s){{0, 0, 0}}, 1e-6f, "bottom-left is black");
    ras_texture_destroy(tex);
}

/* A missing texture file fails with a message (no crash, no half-made texture). */
static void test_texture_load_missing_file_fails(void **state) {
    (void)state;
    ras_error err = {{0}};
    ras_texture *tex = ras_texture_load("/nonexistent/raster101/no_such_texture.png", RAS_WRAP_REPEAT, &err);
    assert_null(tex);
    if (err.msg[0] == '\0') fail_msg("missing texture file: no error message was set");
    ras_texture_destroy(NULL); /* allowed */
}

/* ------------------------------------------------------------------------ */
/* Built-in textures                                                         */

/* The checker alternates a and b in `squares` squares per side, texel (0,0) being a. */
static void test_texture_checker_pattern(void **state) {
    (void)state;
    const vec3s a = {{1, 1, 1}}, b = {{0, 0, 0}};
    ras_texture *tex = ras_texture_create_checker(64, 8, a, b);
    assert_non_null(tex);
    assert_int_equal(tex->width, 64);
    assert_int_equal(tex->height, 64);
    for (int j = 0; j < 64; j++)
        for (int i = 0; i < 64; i++) {
            vec3s want = ((i / 8 + j / 8) % 2 == 0) ? a : b;
            vec3s got = ras_texture_texel(tex, 0, i, j);
            if (got.x != want.x)
                fail_msg("checker texel (%d, %d) = %g, expected %g (8x8-texel squares, (0,0) = a)",
                         i, j, (double)got.x, (double)want.x);
        }
    ras_texture_destroy(tex);
    assert_null(ras_texture_create_checker(0, 8, a, b));
    assert_null(ras_texture_create_checker(-5, 8, a, b));
    assert_null(ras_texture_create_checker(RAS_IMAGE_MAX_SIDE + 1, 8, a, b));
    tex = ras_texture_create_checker(4, 0, a, b); /* squares < 1 → one square, not a division by 0 */
    assert_non_null(tex);
    ras_texture_destroy(tex);
}

/* Bricks are deterministic, in [0,1], contain mortar and varied brick colours, and tile seamlessly by rows. */
static void test_texture_brick_deterministic(void **state) {
    (void)state;
    ras_texture *t1 = ras_texture_create_brick(128), *t2 = ras_texture_create_brick(128);
    assert_non_null(t1);
    assert_non_null(t2);
    int mortar = 0, brick = 0;
    float rmin = 1, rmax = 0;
    for (int k = 0; k < 128 * 128; k++) {
        vec3s c = t1->texels[k];
        if (c.x != t2->texels[k].x || c.y != t2->texels[k].y || c.z != t2->texels[k].z)
            fail_msg("brick texel %d differs between two calls: the texture must be deterministic", k);
        for (int q = 0; q < 3; q++)
            if (!(c.raw[q] >= 0.0f && c.raw[q] <= 1.0f)) fail_msg("brick texel %d channel %d = %g, outside [0,1]", k, q, (double)c.raw[q]);
        if (c.x - c.z < 0.15f) mortar++; /* greyish */
        else {
            brick++;
            rmin = fminf(rmin, c.x), rmax = fmaxf(rmax, c.x);
        }
    }
    if (mortar == 0 || brick == 0) fail_msg("brick texture has %d mortar and %d brick texels; expected both", mortar, brick);
    if (!(rmax - rmin > 0.05f)) fail_msg("bricks all have the same colour (red in [%g, %g]); expected variation", (double)rmin, (double)rmax);
    ras_texture_destroy(t1);
    ras_texture_destroy(t2);
}

/* Bumps: grey heights in [0,1] reaching both ends, changing smoothly, also across the tile's edge. */
static void test_texture_bumps_range_grey_smooth(void **state) {
    (void)state;
    const int size = 128, bumps = 4;
    ras_texture *tex = ras_texture_create_bumps(size, bumps);
    assert_non_null(tex);
    float lo = 1, hi = 0, worst_step = 0;
    for (int j = 0; j < size; j++)
        for (int i = 0; i < size; i++) {
            vec3s c = ras_texture_texel(tex, 0, i, j);
            if (c.x != c.y || c.y != c.z) fail_msg("bump texel (%d,%d) is not grey: (%g,%g,%g)", i, j, (double)c.x, (double)c.y, (double)c.z);
            if (!(c.x >= 0.0f && c.x <= 1.0f)) fail_msg("bump height %g at (%d,%d) outside [0,1]", (double)c.x, i, j);
            lo = fminf(lo, c.x), hi = fmaxf(hi, c.x);
            /* Neighbours through the wrap too: the tile must repeat without a step. */
            float dx = fabsf(ras_texture_texel(tex, 0, i + 1, j).x - c.x);
            float dy = fabsf(ras_texture_texel(tex, 0, i, j + 1).x - c.x);
            worst_step = fmaxf(worst_step, fmaxf(dx, dy));
        }
    if (!(lo < 0.05f && hi > 0.95f)) fail_msg("bump heights span [%g, %g], expected about [0, 1]", (double)lo, (double)hi);
    /* Steepest slope of the cosine profile: pi / (2 * 0.45) per cell = 0.11 per texel here. */
    if (!(worst_step < 0.15f)) fail_msg("bump height jumps by %g between neighbours; expected a smooth surface (< 0.15)", (double)worst_step);
    ras_texture_destroy(tex);
}

/* ------------------------------------------------------------------------ */
/* Mip levels                                                                */

/* A 5x3 texture gets levels 5x3, 2x1, 1x1 (odd sizes round down, never below 1). */
static void test_texture_mip_sizes_5x3(void **state) {
    (void)state;
    ras_texture *tex = make_index_texture(5, 3, RAS_WRAP_REPEAT);
    assert_int_equal(tex->level_count, 1);
    assert_true(ras_texture_build_mips(tex));
    const int want_w[] = {5, 2, 1}, want_h[] = {3, 1, 1};
    if (tex->level_count != 3) fail_msg("5x3 texture has %d levels, expected 3 (5x3, 2x1, 1x1)", tex->level_count);
    for (int l = 0; l < 3; l++)
        if (tex->level_width[l] != want_w[l] || tex->level_height[l] != want_h[l])
            fail_msg("level %d is %dx%d, expected %dx%d", l, tex->level_width[l], tex->level_height[l], want_w[l], want_h[l]);
    assert_ptr_equal(tex->levels[0], tex->texels);
    /* Level 1, texel 0: columns 0-1 and rows 0-2 (the odd last row folds in) → mean (0.5, 1). */
    assert_vec3_near(tex->levels[1][0], (vec3s){{0.5f, 1.0f, 0.0f}}, 1e-6f, "5x3 → 2x1 texel 0");
    /* Texel 1: columns 2-4 (the odd last column folds in) → mean (3, 1). */
    assert_vec3_near(tex->levels[1][1], (vec3s){{3.0f, 1.0f, 0.0f}}, 1e-6f, "5x3 → 2x1 texel 1");
    assert_vec3_near(tex->levels[2][0], (vec3s){{1.75f, 1.0f, 0.0f}}, 1e-6f, "2x1 → 1x1");
    ras_texture_destroy(tex);
}

/* Box filtering a checker keeps its mean grey at every level, ending in one 0.5 texel. */
static void test_texture_mip_average_preserved_checker(void **state) {
    (void)state;
    ras_texture *tex = ras_texture_create_checker(64, 8, (vec3s){{1, 1, 1}}, (vec3s){{0, 0, 0}});
    assert_non_null(tex);
    assert_true(ras_texture_build_mips(tex));
    assert_int_equal(tex->level_count, 7); /* 64, 32, 16, 8, 4, 2, 1 */
    for (int l = 0; l < tex->level_count; l++) {
        vec3s m = level_mean(tex, l);
        if (fabsf(m.x - 0.5f) > 1e-6f)
            fail_msg("checker mip level %d (%dx%d) has mean %g, expected 0.5", l, tex->level_width[l],
                     tex->level_height[l], (double)m.x);
    }
    assert_int_equal(tex->level_width[6], 1);
    assert_vec3_near(tex->levels[6][0], (vec3s){{0.5f, 0.5f, 0.5f}}, 1e-6f, "the 1x1 level");
    /* Down to 8x8 each texel still lies inside one square: pure black or white. */
    assert_true(tex->levels[3][0].x == 1.0f);
    ras_texture_destroy(tex);
}

/* Building mips twice changes nothing (same levels, same memory) and 1x1 textures need no extra level. */
static void test_texture_mips_idempotent(void **state) {
    (void)state;
    ras_texture *tex = ras_texture_create_checker(16, 2, (vec3s){{1, 0, 0}}, (vec3s){{0, 0, 1}});
    assert_true(ras_texture_build_mips(tex));
    int count = tex->level_count;
    vec3s *l1 = tex->levels[1];
    assert_true(ras_texture_build_mips(tex));
    assert_int_equal(tex->level_count, count);
    assert_ptr_equal(tex->levels[1], l1);
    ras_texture_destroy(tex);

    ras_texture *one = ras_texture_create_checker(1, 1, (vec3s){{1, 0, 0}}, (vec3s){{0, 0, 1}});
    assert_true(ras_texture_build_mips(one));
    assert_int_equal(one->level_count, 1);
    ras_texture_destroy(one);

    /* A 1xN strip halves only the long side. */
    ras_texture *strip = make_index_texture(1, 8, RAS_WRAP_REPEAT);
    assert_true(ras_texture_build_mips(strip));
    assert_int_equal(strip->level_count, 4);
    assert_int_equal(strip->level_width[3], 1);
    assert_int_equal(strip->level_height[3], 1);
    assert_vec3_near(strip->levels[3][0], (vec3s){{0, 3.5f, 0}}, 1e-6f, "1x8 strip averaged to 1x1");
    /* texel() at a mip level wraps with that level's size. */
    assert_vec3_near(ras_texture_texel(strip, 1, 0, -1), strip->levels[1][3], 0, "texel(level 1, 0, -1)");
    ras_texture_destroy(strip);
}


/* ------------------------------------------------------------------------ */
/* Textures kept as bytes (RGB8)                                             */

/* Every entry of the byte table is the float ras_byte_to_unit computes at run
 * time (the compiler folded the table's divisions; a different rounding, or
 * b * (1/255.0f), differs for some bytes and fails here). */
static void test_texel_unit_table_is_byte_to_unit(void **state) {
    (void)state;
    for (int b = 0; b < 256; b++) {
        volatile uint8_t byte = (uint8_t)b; /* computed at run time, not folded */
        float want = ras_byte_to_unit(byte);
        if (memcmp(&want, &ras_texel_unit[b], sizeof want))
            fail_msg("ras_texel_unit[%d] is %.9g, expected ras_byte_to_unit(%d) = %.9g bit for "
                     "bit: fill the table with the same expression",
                     b, (double)ras_texel_unit[b], b, (double)want);
    }
}

/* xorshift64*: reproducible random numbers without rand()'s global state. */
static uint64_t rng_next(uint64_t *s) {
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 0x2545F4914F6CDD1DULL;
}

/* A coordinate: mostly inside [0, 1], sometimes far outside or not finite. */
static float rng_coord(uint64_t *s) {
    static const float odd[] = {0.0f, 1.0f, -0.0f, 1e-7f, -1e-7f, 0.99999994f, 1.00000012f, 1e30f,
                                -1e30f, INFINITY, -INFINITY, NAN, 7.25f, -3.5f};
    uint64_t r = rng_next(s);
    if (r % 8 == 0) return odd[(r >> 8) % (sizeof odd / sizeof odd[0])];
    return (float)((double)(r >> 11) / 9007199254740992.0 * 3.0 - 1.0); /* [-1, 2) */
}

static bool same_vec3(vec3s a, vec3s b) { return !memcmp(&a, &b, sizeof a); }

/* A w x h RGB8 texture of random bytes and its float twin (the same bytes
 * through ras_byte_to_unit into an image, then ras_texture_from_image). */
static void make_twins(int w, int h, ras_wrap wrap, uint64_t *rng, ras_texture **bytes,
                       ras_texture **floats) {
    size_t n = (size_t)w * (size_t)h * 3;
    uint8_t *rgb = malloc(n);
    assert_non_null(rgb);
    for (size_t k = 0; k < n; k++)
        rgb[k] = (uint8_t)(rng_next(rng) >> 56);
    ras_image *img = ras_image_create(w, h, NULL);
    assert_non_null(img);
    for (int row = 0; row < h; row++)
        for (int col = 0; col < w; col++) {
            const uint8_t *p = rgb + ((size_t)row * (size_t)w + (size_t)col) * 3;
            ras_image_set(img, col, row,
                          (vec3s){{ras_byte_to_unit(p[0]), ras_byte_to_unit(p[1]),
                                   ras_byte_to_unit(p[2])}});
        }
    *floats = ras_texture_from_image(img, wrap, NULL);
    ras_image_destroy(img);
    *bytes = ras_texture_from_rgb8(rgb, w, h, wrap, NULL); /* takes rgb */
    assert_non_null(*floats);
    assert_non_null(*bytes);
    assert_int_equal((*bytes)->format, RAS_TEXELS_RGB8);
    assert_int_equal((*floats)->format, RAS_TEXELS_FLOAT);
}

/* An RGB8 texture looks up what its float twin does, bit for bit: texels of
 * every level (indices inside and far outside), nearest lookups at random
 * coordinates (NaN and ±Inf among them), and the mip chain built from the
 * bytes — both wrap modes, odd and even sizes. (Bilinear and trilinear, the
 * solution's and the fast renderer's, are checked on whole pictures in
 * test_fast_path.) */
static void test_rgb8_lookups_equal_float(void **state) {
    (void)state;
    static const int sizes[][2] = {{1, 1}, {2, 3}, {37, 23}, {64, 64}, {255, 3}};
    uint64_t rng = 0x9E3779B97F4A7C15ULL;
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
        for (int wi = 0; wi < 2; wi++) {
            ras_wrap wrap = wi ? RAS_WRAP_CLAMP : RAS_WRAP_REPEAT;
            int w = sizes[si][0], h = sizes[si][1];
            ras_texture *b = NULL, *f = NULL;
            make_twins(w, h, wrap, &rng, &b, &f);
            for (int pass = 0; pass < 2; pass++) { /* before and after the mips */
                for (int k = 0; k < 4000; k++) {
                    int level = (int)(rng_next(&rng) % (uint64_t)b->level_count);
                    int i = (int)(rng_next(&rng) % 301) - 150, j = (int)(rng_next(&rng) % 301) - 150;
                    vec3s got = ras_texture_texel(b, level, i, j);
                    vec3s want = ras_texture_texel(f, level, i, j);
                    if (!same_vec3(got, want))
                        fail_msg("%dx%d %s: texel(level %d, %d, %d) of the RGB8 texture is "
                                 "(%.9g, %.9g, %.9g), its float twin's (%.9g, %.9g, %.9g); "
                                 "expected the same floats",
                                 w, h, wi ? "CLAMP" : "REPEAT", level, i, j, (double)got.x,
                                 (double)got.y, (double)got.z, (double)want.x, (double)want.y,
                                 (double)want.z);
                    float u = rng_coord(&rng), v = rng_coord(&rng);
                    got = ras_texture_sample_nearest(b, u, v);
                    want = ras_texture_sample_nearest(f, u, v);
                    if (!same_vec3(got, want))
                        fail_msg("%dx%d %s: nearest(%.9g, %.9g) of the RGB8 texture differs from "
                                 "its float twin's: expected the same floats",
                                 w, h, wi ? "CLAMP" : "REPEAT", (double)u, (double)v);
                }
                if (pass == 0) {
                    assert_true(ras_texture_build_mips(b));
                    assert_true(ras_texture_build_mips(f));
                    assert_int_equal(b->level_count, f->level_count);
                    assert_int_equal(b->format, RAS_TEXELS_RGB8); /* level 0 stays bytes */
                    for (int l = 1; l < b->level_count; l++) {
                        size_t n = (size_t)b->level_width[l] * (size_t)b->level_height[l];
                        if (memcmp(b->levels[l], f->levels[l], n * sizeof(vec3s)))
                            fail_msg("%dx%d: mip level %d built from bytes differs from the float "
                                     "twin's: expected the same sums of the same floats",
                                     w, h, l);
                    }
                }
            }
            ras_texture_destroy(b);
            ras_texture_destroy(f);
        }
}

/* A file's texture holds its bytes, not floats: a 4096² PNG loaded as a
 * texture is 3 bytes a texel (48 MiB, not the 192 MiB floats took), with no
 * float level 0 beside it, and the file's pixels where they belong. */
static void test_rgb8_texture_holds_three_bytes_a_texel(void **state) {
    (void)state;
    const int n = 4096;
    char dir[] = "/tmp/raster101_test_texture_XXXXXX";
    if (!mkdtemp(dir)) fail_msg("could not create a temporary directory for the PNG");
    char path[256];
    snprintf(path, sizeof path, "%s/big.png", dir);
    ras_image *img = ras_image_create(n, n, NULL);
    assert_non_null(img);
    ras_image_set(img, 0, 0, (vec3s){{1, 0, 0}});             /* top-left */
    ras_image_set(img, n - 1, n - 1, (vec3s){{0, 0, 1}});     /* bottom-right */
    ras_image_set(img, 5, 7, (vec3s){{0.2f, 0.4f, 0.6f}});    /* rounds to bytes */
    ras_error err = {{0}};
    save_png_or_fail(img, dir, path);
#if TEST_HAS_MALLINFO2
    struct mallinfo2 before = mallinfo2();
#endif
    ras_texture *tex = ras_texture_load(path, RAS_WRAP_REPEAT, &err);
#if TEST_HAS_MALLINFO2
    struct mallinfo2 after = mallinfo2();
#endif
    remove(path);
    rmdir(dir);
    if (!tex) fail_msg("ras_texture_load of a %dx%d PNG failed: %s", n, n, err.msg);
    size_t texels = (size_t)n * (size_t)n;
    if (tex->format != RAS_TEXELS_RGB8 || !tex->texels8 || tex->texels || tex->levels[0])
        fail_msg("a texture loaded from a PNG: expected level 0 as bytes only (format RGB8, "
                 "texels8 set, texels and levels[0] NULL), got format %d, texels8 %p, texels %p",
                 (int)tex->format, (void *)tex->texels8, (void *)tex->texels);
    size_t usable = malloc_usable_size(tex->texels8);
    if (usable < 3 * texels || usable > 3 * texels + 65536)
        fail_msg("level 0 of a %dx%d texture is a block of %zu bytes; expected 3 a texel, %zu",
                 n, n, usable, 3 * texels);
#if TEST_HAS_MALLINFO2
    /* everything the load kept (the texture and anything it left behind) */
    double kept = ((double)after.uordblks + (double)after.hblkhd) -
                  ((double)before.uordblks + (double)before.hblkhd);
    if (kept > 3.01 * (double)texels)
        fail_msg("loading a %dx%d texture kept %.0f bytes (%.2f a texel); expected at most "
                 "3.01 a texel: the bytes alone, no float copy",
                 n, n, kept, kept / (double)texels);
#endif
    vec3s top_left = ras_texture_texel(tex, 0, 0, n - 1), bottom_right = ras_texture_texel(tex, 0, n - 1, 0);
    vec3s grey = ras_texture_texel(tex, 0, 5, n - 1 - 7);
    if (!same_vec3(top_left, (vec3s){{1, 0, 0}}) || !same_vec3(bottom_right, (vec3s){{0, 0, 1}}) ||
        !same_vec3(grey, (vec3s){{ras_byte_to_unit(ras_unit_to_byte(0.2f)),
                                  ras_byte_to_unit(ras_unit_to_byte(0.4f)),
                                  ras_byte_to_unit(ras_unit_to_byte(0.6f))}}))
        fail_msg("the 4096² texture's pixels are not where the file has them (flipped so row 0 "
                 "is the bottom): top-left (%g, %g, %g), bottom-right (%g, %g, %g)",
                 (double)top_left.x, (double)top_left.y, (double)top_left.z,
                 (double)bottom_right.x, (double)bottom_right.y, (double)bottom_right.z);
    ras_texture_destroy(tex);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_texture_wrap_index_repeat_negative),
        cmocka_unit_test(test_texture_wrap_index_clamp),
        cmocka_unit_test(test_texture_texel_wraps),
        cmocka_unit_test(test_texture_nearest_texel_centres),
        cmocka_unit_test(test_texture_nearest_edges_repeat),
        cmocka_unit_test(test_texture_nearest_edges_clamp),
        cmocka_unit_test(test_texture_v_flip),
        cmocka_unit_test(test_texture_load_png_roundtrip),
        cmocka_unit_test(test_texture_load_missing_file_fails),
        cmocka_unit_test(test_texture_checker_pattern),
        cmocka_unit_test(test_texture_brick_deterministic),
        cmocka_unit_test(test_texture_bumps_range_grey_smooth),
        cmocka_unit_test(test_texture_mip_sizes_5x3),
        cmocka_unit_test(test_texture_mip_average_preserved_checker),
        cmocka_unit_test(test_texture_mips_idempotent),
        cmocka_unit_test(test_texel_unit_table_is_byte_to_unit),
        cmocka_unit_test(test_rgb8_lookups_equal_float),
        cmocka_unit_test(test_rgb8_texture_holds_three_bytes_a_texel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
