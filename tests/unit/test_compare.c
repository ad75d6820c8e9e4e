/* test_compare.c — cmocka tests for ras_compare (image metrics, heatmap,
 * worst-region crop, coverage text). Images are built in memory so each test
 * states exactly what differs. */
#include <setjmp.h> /* cmocka needs these before cmocka.h */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ras_compare.h"

#include <math.h>   /* INFINITY, isinf, log10, fabs */
#include <stdlib.h> /* abs, malloc */
#include <string.h> /* strstr, strcmp, memcmp */

/* Fails with a message that says what was expected and what came. */
#define CHECK(cond, ...)                                                     \
    do {                                                                     \
        if (!(cond)) fail_msg(__VA_ARGS__);                                  \
    } while (0)

/* ---- image builders ------------------------------------------------------ */

static ras_image *make_image(int w, int h, float v) {
    ras_image *img = ras_image_create(w, h, NULL);
    assert_non_null(img);
    ras_image_fill(img, (vec3s){{v, v, v}});
    return img;
}

/* White half-plane left of the slanted line x = x0 + 0.3 * y on black,
 * anti-aliased by 8x8 supersampling. Shifting x0 by a whole pixel shifts
 * every pixel exactly, so the edge-tolerant metric should see no change. */
static ras_image *make_edge(int w, int h, float x0) {
    ras_image *img = make_image(w, h, 0.0f);
    for (int row = 0; row < h; row++) {
        for (int col = 0; col < w; col++) {
            int inside = 0;
            for (int sy = 0; sy < 8; sy++)
                for (int sx = 0; sx < 8; sx++) {
                    float x = col + (sx + 0.5f) / 8.0f, y = row + (sy + 0.5f) / 8.0f;
                    if (x < x0 + 0.3f * y) inside++;
                }
            float v = inside / 64.0f;
            ras_image_set(img, col, row, (vec3s){{v, v, v}});
        }
    }
    return img;
}

static void fill_rect(ras_image *img, int c0, int r0, int w, int h, vec3s c) {
    for (int r = r0; r < r0 + h; r++)
        for (int col = c0; col < c0 + w; col++) ras_image_set(img, col, r, c);
}

/* A smooth, textured image (so SSIM has structure to lose) plus optional
 * deterministic noise of amplitude `noise` (in [0,1] units). */
static ras_image *make_texture(int w, int h, float noise, unsigned seed) {
    ras_image *img = ras_image_create(w, h, NULL);
    assert_non_null(img);
    unsigned s = seed;
    for (int row = 0; row < h; row++) {
        for (int col = 0; col < w; col++) {
            float base = 0.5f + 0.3f * sinf(col * 0.2f) * cosf(row * 0.15f);
            s = s * 1664525u + 1013904223u; /* LCG: same noise on every run */
            float n = noise * (((s >> 8) & 0xffff) / 32767.5f - 1.0f);
            float v = base + n;
            ras_image_set(img, col, row, (vec3s){{v, v * 0.9f, v * 0.8f}});
        }
    }
    return img;
}

static ras_compare_result compare(const ras_image *e, const ras_image *g, ras_compare_kind kind) {
    ras_compare_options opt = ras_compare_defaults(kind);
    ras_compare_result res;
    ras_error err = {{0}};
    bool ok = ras_compare_images(e, g, &opt, &res, &err);
    CHECK(ok, "ras_compare_images(%s) could not compare: %s", ras_compare_kind_name(kind),
          err.msg);
    return res;
}

/* ---- tests --------------------------------------------------------------- */

/* Identical images pass every metric: no bad pixels, PSNR inf, SSIM exactly 1. */
static void test_compare_identical_passes_every_metric(void **state) {
    (void)state;
    ras_image *a = make_texture(40, 30, 0.0f, 1);
    ras_image *b = ras_image_clone(a);
    for (int k = RAS_COMPARE_EXACT; k <= RAS_COMPARE_SSIM; k++) {
        ras_compare_result r = compare(a, b, (ras_compare_kind)k);
        CHECK(r.pass, "%s: identical images should pass; got \"%s\"",
              ras_compare_kind_name((ras_compare_kind)k), r.summary);
        CHECK(r.bad_pixels == 0 && r.max_diff == 0,
              "%s: expected 0 bad pixels and max diff 0, got %ld and %d",
              ras_compare_kind_name((ras_compare_kind)k), r.bad_pixels, r.max_diff);
        CHECK(isinf(r.psnr_db) && r.psnr_db > 0, "expected PSNR +inf, got %g", r.psnr_db);
        CHECK(fabs(r.ssim - 1.0) < 1e-12, "expected SSIM 1, got %.15f", r.ssim);
        CHECK(r.worst_col == -1 && r.worst_row == -1,
              "expected no worst pixel (-1,-1), got (%d,%d)", r.worst_col, r.worst_row);
    }
    ras_image_destroy(a);
    ras_image_destroy(b);
}

/* A one-pixel shift of an anti-aliased edge fails EXACT but costs nothing
 * under EDGE_TOLERANT. */
static void test_compare_edge_shift_fails_exact_passes_edge_tolerant(void **state) {
    (void)state;
    ras_image *e = make_edge(64, 64, 20.0f);
    ras_image *g = make_edge(64, 64, 21.0f);
    ras_compare_result exact = compare(e, g, RAS_COMPARE_EXACT);
    CHECK(!exact.pass && exact.bad_pixels > 0,
          "EXACT should fail on a shifted edge; got \"%s\"", exact.summary);
    ras_compare_result edge = compare(e, g, RAS_COMPARE_EDGE_TOLERANT);
    CHECK(edge.pass, "EDGE_TOLERANT should forgive a 1-pixel shift; got \"%s\"", edge.summary);
    CHECK(edge.max_diff == 0, "a pure 1-pixel shift should cost 0 levels, got %d at (%d,%d)",
          edge.max_diff, edge.worst_col, edge.worst_row);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* A missing 6x6 square fails EDGE_TOLERANT, with the worst pixel inside it
 * and all 36 of its pixels counted (the symmetric check sees every one). */
static void test_compare_missing_square_fails_edge_tolerant(void **state) {
    (void)state;
    ras_image *e = make_edge(64, 64, 20.0f);
    ras_image *g = ras_image_clone(e);
    fill_rect(e, 45, 10, 6, 6, (vec3s){{0.2f, 0.9f, 0.3f}});
    ras_compare_result r = compare(e, g, RAS_COMPARE_EDGE_TOLERANT);
    CHECK(!r.pass, "EDGE_TOLERANT should fail on a missing square; got \"%s\"", r.summary);
    CHECK(r.bad_pixels == 36, "expected the 36 square pixels bad, got %ld (\"%s\")",
          r.bad_pixels, r.summary);
    CHECK(r.worst_col >= 45 && r.worst_col < 51 && r.worst_row >= 10 && r.worst_row < 16,
          "expected the worst pixel inside the square (45..50, 10..15), got (%d,%d)",
          r.worst_col, r.worst_row);
    CHECK(strstr(r.summary, "FAIL") && strstr(r.summary, "worst at (45,10)"),
          "summary should say FAIL and where; got \"%s\"", r.summary);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* A single missing one-pixel line is caught too: the expected-vs-got
 * direction of the symmetric check sees it even though got's neighbourhood
 * contains background. */
static void test_compare_missing_thin_line_fails_edge_tolerant(void **state) {
    (void)state;
    ras_image *e = make_image(32, 32, 0.0f);
    ras_image *g = make_image(32, 32, 0.0f);
    fill_rect(e, 16, 4, 1, 20, (vec3s){{1.0f, 1.0f, 1.0f}});
    ras_compare_result r = compare(e, g, RAS_COMPARE_EDGE_TOLERANT);
    CHECK(!r.pass && r.bad_pixels == 20,
          "expected the 20 pixels of the missing line bad, got %ld (\"%s\")", r.bad_pixels,
          r.summary);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* PSNR by hand: every channel of every pixel off by 10 levels (100 vs 110)
 * gives MSE = 100, so PSNR = 10*log10(255^2/100) = 20*log10(25.5)
 * = 28.1308 dB, below the default 35 dB. */
static void test_compare_psnr_uniform_difference(void **state) {
    (void)state;
    ras_image *e = make_image(20, 10, 100.0f / 255.0f);
    ras_image *g = make_image(20, 10, 110.0f / 255.0f);
    ras_compare_result r = compare(e, g, RAS_COMPARE_PSNR);
    double want = 20.0 * log10(255.0 / 10.0);
    CHECK(fabs(r.psnr_db - want) < 1e-9, "expected PSNR %.6f dB, got %.6f dB", want, r.psnr_db);
    CHECK(fabs(r.psnr_db - 28.1308) < 1e-4, "expected 28.1308 dB, got %.6f dB", r.psnr_db);
    CHECK(r.value == r.psnr_db, "value should be the PSNR for kind PSNR, got %g", r.value);
    CHECK(!r.pass, "28.13 dB < 35 dB should fail; got \"%s\"", r.summary);
    CHECK(r.bad_pixels == 200 && r.max_diff == 10,
          "expected all 200 pixels over 8 levels with max 10, got %ld and %d", r.bad_pixels,
          r.max_diff);
    CHECK(strstr(r.summary, "PSNR 28.1 dB < 35.0 dB required"),
          "summary should state expected vs got; got \"%s\"", r.summary);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* SSIM: itself gives 1; noise lowers it, more noise lowers it more; and
 * swapping the images gives the same value. */
static void test_compare_ssim_noise_and_symmetry(void **state) {
    (void)state;
    ras_image *clean = make_texture(48, 40, 0.0f, 1);
    ras_image *light = make_texture(48, 40, 0.03f, 7);
    ras_image *heavy = make_texture(48, 40, 0.15f, 7);

    ras_compare_result self = compare(clean, clean, RAS_COMPARE_SSIM);
    CHECK(fabs(self.ssim - 1.0) < 1e-12, "SSIM of an image with itself: expected 1, got %.15f",
          self.ssim);

    ras_compare_result l = compare(clean, light, RAS_COMPARE_SSIM);
    ras_compare_result h = compare(clean, heavy, RAS_COMPARE_SSIM);
    CHECK(l.ssim < 1.0 && h.ssim < l.ssim && h.ssim > -1.0,
          "expected 1 > SSIM(light noise) > SSIM(heavy noise) > -1, got %.4f and %.4f", l.ssim,
          h.ssim);
    CHECK(!h.pass && h.ssim < 0.98, "heavy noise should fail SSIM >= 0.98; got \"%s\"",
          h.summary);

    ras_compare_result swapped = compare(heavy, clean, RAS_COMPARE_SSIM);
    CHECK(fabs(swapped.ssim - h.ssim) < 1e-12, "SSIM should be symmetric: %.15f vs %.15f",
          h.ssim, swapped.ssim);
    ras_image_destroy(clean);
    ras_image_destroy(light);
    ras_image_destroy(heavy);
}

/* SSIM in closed form, which pins the window and both constants: on a 2x1
 * image the clipped 11x11 window of either pixel holds both pixels, with
 * normalised weights a = 1/(1+q) (own) and b = q/(1+q) (other), q =
 * exp(-1/(2*1.5^2)). With expected luma (100,100) and got (90,110):
 *   mu_x = 100, sigma_x = sigma_xy = 0, sigma_y^2 = a*b*20^2,
 *   mu_y = 90a + 110b (left pixel) or 110a + 90b (right), so per pixel
 *   SSIM = (2*100*mu_y + C1)/(100^2 + mu_y^2 + C1) * C2/(sigma_y^2 + C2),
 * C1 = 6.5025, C2 = 58.5225; the result is the mean of the two. */
static void test_compare_ssim_closed_form(void **state) {
    (void)state;
    ras_image *e = make_image(2, 1, 100.0f / 255.0f);
    ras_image *g = make_image(2, 1, 0.0f);
    ras_image_set(g, 0, 0, (vec3s){{90.0f / 255.0f, 90.0f / 255.0f, 90.0f / 255.0f}});
    ras_image_set(g, 1, 0, (vec3s){{110.0f / 255.0f, 110.0f / 255.0f, 110.0f / 255.0f}});
    double q = exp(-1.0 / 4.5), a = 1.0 / (1.0 + q), b = q / (1.0 + q);
    double c1 = 6.5025, c2 = 58.5225, vy = a * b * 400.0, want = 0.0;
    double mu[2] = {90.0 * a + 110.0 * b, 110.0 * a + 90.0 * b};
    for (int i = 0; i < 2; i++)
        want += 0.5 * (200.0 * mu[i] + c1) / (10000.0 + mu[i] * mu[i] + c1) * c2 / (vy + c2);
    ras_compare_result r = compare(e, g, RAS_COMPARE_SSIM);
    CHECK(fabs(r.ssim - want) < 1e-9, "expected SSIM %.12f, got %.12f", want, r.ssim);
    CHECK(r.value == r.ssim, "value should be the SSIM for kind SSIM, got %g", r.value);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* Checks combine: an image that passes PSNR >= 35 dB still fails when the
 * caller also limits the pixels off by more than 8 levels. */
static void test_compare_combined_checks(void **state) {
    (void)state;
    ras_image *e = make_image(100, 100, 0.5f);
    ras_image *g = ras_image_clone(e);
    fill_rect(g, 0, 0, 10, 1, (vec3s){{0.5f + 20.0f / 255.0f, 0.5f, 0.5f}});
    ras_compare_options opt = ras_compare_defaults(RAS_COMPARE_PSNR);
    ras_compare_result r;
    ras_error err = {{0}};
    CHECK(ras_compare_images(e, g, &opt, &r, &err) && r.pass,
          "10 pixels off by 20 levels should pass PSNR >= 35 dB; got \"%s\"", r.summary);
    opt.max_bad_fraction = 0.0005; /* 5 of 10000 pixels */
    CHECK(ras_compare_images(e, g, &opt, &r, &err) && !r.pass,
          "with at most 5 pixels over 8 levels allowed, 10 should fail; got \"%s\"",
          r.summary);
    CHECK(strstr(r.summary, "(at most 5 allowed)"), "summary should give the limit; got \"%s\"",
          r.summary);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* EXACT quantises first: differences below half a level are not differences,
 * and a single changed byte is. */
static void test_compare_exact_quantises_to_8_bits(void **state) {
    (void)state;
    ras_image *e = make_image(8, 8, 0.5f);
    ras_image *g = make_image(8, 8, 0.5f + 0.1f / 255.0f);
    ras_compare_result r = compare(e, g, RAS_COMPARE_EXACT);
    CHECK(r.pass, "a 0.1-level difference should vanish at 8 bits; got \"%s\"", r.summary);
    ras_image_set(g, 3, 5, (vec3s){{0.5f, 0.5f + 1.0f / 255.0f, 0.5f}});
    r = compare(e, g, RAS_COMPARE_EXACT);
    CHECK(!r.pass && r.bad_pixels == 1 && r.worst_col == 3 && r.worst_row == 5,
          "expected 1 bad pixel at (3,5), got %ld at (%d,%d)", r.bad_pixels, r.worst_col,
          r.worst_row);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* The heatmap is black exactly where the images agree, coloured elsewhere,
 * and the colour depends only on the difference (fixed scale). */
static void test_compare_heatmap_black_where_equal(void **state) {
    (void)state;
    ras_image *e = make_image(16, 16, 0.2f);
    ras_image *g = ras_image_clone(e);
    ras_image_set(g, 4, 4, (vec3s){{0.2f + 40.0f / 255.0f, 0.2f, 0.2f}});
    ras_image_set(g, 9, 2, (vec3s){{0.2f + 1.0f / 255.0f, 0.2f, 0.2f}});
    ras_error err = {{0}};
    ras_image *heat = ras_compare_heatmap(e, g, RAS_COMPARE_EXACT, &err);
    CHECK(heat != NULL, "heatmap failed: %s", err.msg);
    for (int row = 0; row < 16; row++) {
        for (int col = 0; col < 16; col++) {
            vec3s c = ras_image_get(heat, col, row);
            bool black = c.x == 0.0f && c.y == 0.0f && c.z == 0.0f;
            bool differs = (col == 4 && row == 4) || (col == 9 && row == 2);
            CHECK(black != differs, "heatmap at (%d,%d): expected %s, got (%g,%g,%g)", col, row,
                  differs ? "colour" : "black", c.x, c.y, c.z);
        }
    }
    vec3s one = ras_image_get(heat, 9, 2);
    CHECK(ras_unit_to_byte(one.z) > 0, "a 1-level difference should be visibly blue, got %g",
          one.z);

    /* Same 40-level difference on a different background: same colour. */
    ras_image *e2 = make_image(16, 16, 0.6f);
    ras_image *g2 = ras_image_clone(e2);
    ras_image_set(g2, 0, 0, (vec3s){{0.6f - 40.0f / 255.0f, 0.6f, 0.6f}});
    ras_image *heat2 = ras_compare_heatmap(e2, g2, RAS_COMPARE_EXACT, &err);
    CHECK(heat2 != NULL, "heatmap failed: %s", err.msg);
    vec3s a = ras_image_get(heat, 4, 4), b = ras_image_get(heat2, 0, 0);
    CHECK(a.x == b.x && a.y == b.y && a.z == b.z,
          "a 40-level difference should have one colour: (%g,%g,%g) vs (%g,%g,%g)", a.x, a.y,
          a.z, b.x, b.y, b.z);
    ras_image_destroy(e);
    ras_image_destroy(g);
    ras_image_destroy(heat);
    ras_image_destroy(e2);
    ras_image_destroy(g2);
    ras_image_destroy(heat2);
}

/* The worst-region crop has the documented size, its panels show expected,
 * got and the difference, and a corner position or a tiny image is fine. */
static void test_compare_crop_dimensions_and_panels(void **state) {
    (void)state;
    ras_image *e = make_image(100, 80, 0.0f);
    ras_image *g = ras_image_clone(e);
    ras_image_set(g, 60, 40, (vec3s){{1.0f, 1.0f, 1.0f}});
    ras_compare_result r = compare(e, g, RAS_COMPARE_EXACT);
    ras_error err = {{0}};
    ras_image *crop = ras_compare_crop(e, g, r.kind, r.worst_col, r.worst_row, &err);
    CHECK(crop != NULL, "crop failed: %s", err.msg);
    CHECK(crop->width == 3 * 32 * 8 + 2 * 4 && crop->height == 32 * 8,
          "expected a %dx%d crop, got %dx%d", 3 * 32 * 8 + 2 * 4, 32 * 8, crop->width,
          crop->height);
    CHECK(crop->width == RAS_COMPARE_CROP_WIDTH && crop->height == RAS_COMPARE_CROP_HEIGHT,
          "crop size should match the header's macros");
    /* (60,40) sits at window position (16,16): block (128..135, 128..135). */
    int panel = 32 * 8 + 4;
    vec3s in_expected = ras_image_get(crop, 130, 130);
    vec3s in_got = ras_image_get(crop, panel + 130, 130);
    vec3s in_heat = ras_image_get(crop, 2 * panel + 131, 131);
    vec3s heat_equal = ras_image_get(crop, 2 * panel + 10, 10);
    CHECK(in_expected.x == 0.0f && in_got.x == 1.0f,
          "the worst pixel should be black in the expected panel and white in got, got %g "
          "and %g",
          in_expected.x, in_got.x);
    CHECK(in_heat.x == 1.0f && in_heat.y == 0.0f,
          "a 255-level difference should be red on the heatmap, got (%g,%g,%g)", in_heat.x,
          in_heat.y, in_heat.z);
    CHECK(heat_equal.x == 0.0f && heat_equal.y == 0.0f && heat_equal.z == 0.0f,
          "equal pixels should be black on the heatmap panel, got (%g,%g,%g)", heat_equal.x,
          heat_equal.y, heat_equal.z);
    ras_image_destroy(crop);

    crop = ras_compare_crop(e, g, r.kind, 99, 79, &err);
    CHECK(crop != NULL && crop->width == RAS_COMPARE_CROP_WIDTH,
          "a crop at the corner should work: %s", err.msg);
    ras_image_destroy(crop);

    ras_image *te = make_image(5, 3, 0.0f), *tg = make_image(5, 3, 0.0f);
    crop = ras_compare_crop(te, tg, RAS_COMPARE_EDGE_TOLERANT, -1, -1, &err);
    CHECK(crop != NULL && crop->height == RAS_COMPARE_CROP_HEIGHT,
          "a crop of a 5x3 image should work: %s", err.msg);
    ras_image_destroy(crop);
    ras_image_destroy(te);
    ras_image_destroy(tg);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* Different sizes are an error naming both sizes and which is the reference,
 * for the comparison and for every picture helper. */
static void test_compare_size_mismatch_names_both_sizes(void **state) {
    (void)state;
    ras_image *e = make_image(70, 70, 0.0f);
    ras_image *g = make_image(51, 52, 0.0f);
    ras_compare_options opt = ras_compare_defaults(RAS_COMPARE_PSNR);
    ras_compare_result r;
    ras_error err = {{0}};
    bool ok = ras_compare_images(e, g, &opt, &r, &err);
    CHECK(!ok && !r.pass, "comparing 70x70 with 51x52 should fail");
    CHECK(strstr(err.msg, "expected 70x70 (the reference), got 51x52"),
          "message should name both sizes, got \"%s\"", err.msg);

    err.msg[0] = '\0';
    CHECK(ras_compare_heatmap(e, g, RAS_COMPARE_EXACT, &err) == NULL && strstr(err.msg, "51x52"),
          "heatmap of mismatched sizes should fail naming them, got \"%s\"", err.msg);
    err.msg[0] = '\0';
    CHECK(ras_compare_crop(e, g, RAS_COMPARE_EXACT, 0, 0, &err) == NULL &&
              strstr(err.msg, "51x52"),
          "crop of mismatched sizes should fail naming them, got \"%s\"", err.msg);
    char buf[64];
    err.msg[0] = '\0';
    CHECK(!ras_compare_ascii_mask(e, g, (vec3s){{0, 0, 0}}, 0, 0, 2, buf, sizeof buf, &err) &&
              strstr(err.msg, "51x52") && buf[0] == '\0',
          "ascii mask of mismatched sizes should fail naming them, got \"%s\"", err.msg);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* The coverage text of a hand-made case: expected covers columns 1..2, got
 * columns 2..3, rows 1..3 of a 5x5 image; clipped windows and a short buffer
 * behave as documented. */
static void test_compare_ascii_mask_small_case(void **state) {
    (void)state;
    const vec3s bg = {{0.1f, 0.1f, 0.1f}}, ink = {{0.8f, 0.1f, 0.1f}};
    ras_image *e = make_image(5, 5, 0.1f);
    ras_image *g = make_image(5, 5, 0.1f);
    fill_rect(e, 1, 1, 2, 3, ink);
    fill_rect(g, 2, 1, 2, 3, ink);
    char buf[64];
    ras_error err = {{0}};
    bool ok = ras_compare_ascii_mask(e, g, bg, 2, 2, 2, buf, sizeof buf, &err);
    CHECK(ok, "ascii mask failed: %s", err.msg);
    const char *want = ".....\n"
                       ".-#+.\n"
                       ".-#+.\n"
                       ".-#+.\n"
                       ".....\n";
    CHECK(strcmp(buf, want) == 0, "expected\n%sgot\n%s", want, buf);

    ok = ras_compare_ascii_mask(e, g, bg, 0, 0, 1, buf, sizeof buf, &err);
    CHECK(ok && strcmp(buf, "..\n.-\n") == 0,
          "a window at the corner should be clipped to 2x2, got\n%s", buf);

    char small[10];
    ok = ras_compare_ascii_mask(e, g, bg, 2, 2, 2, small, sizeof small, &err);
    CHECK(!ok && strstr(err.msg, "needs 31 bytes") && small[0] == '\0',
          "a 10-byte buffer should be refused, saying 31 are needed; got \"%s\"", err.msg);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* Defaults are the documented thresholds, and kind names round-trip. */
static void test_compare_defaults_and_names(void **state) {
    (void)state;
    ras_compare_options o = ras_compare_defaults(RAS_COMPARE_EXACT);
    CHECK(o.tolerance == 0 && o.max_bad_fraction == 0.0, "EXACT: expected 0 bad pixels allowed");
    o = ras_compare_defaults(RAS_COMPARE_EDGE_TOLERANT);
    CHECK(o.tolerance == 8 && o.max_bad_fraction > 0.0 && o.max_bad_fraction <= 0.001,
          "EDGE_TOLERANT: expected tolerance 8 and a small fraction, got %d and %g", o.tolerance,
          o.max_bad_fraction);
    o = ras_compare_defaults(RAS_COMPARE_PSNR);
    CHECK(o.min_psnr_db == 35.0 && o.max_bad_fraction == 1.0,
          "PSNR: expected 35 dB and no bad-pixel check, got %g and %g", o.min_psnr_db,
          o.max_bad_fraction);
    o = ras_compare_defaults(RAS_COMPARE_SSIM);
    CHECK(o.min_ssim == 0.98, "SSIM: expected 0.98, got %g", o.min_ssim);

    for (int k = RAS_COMPARE_EXACT; k <= RAS_COMPARE_SSIM; k++) {
        ras_compare_kind parsed;
        const char *name = ras_compare_kind_name((ras_compare_kind)k);
        CHECK(ras_compare_kind_parse(name, &parsed, NULL) && parsed == (ras_compare_kind)k,
              "'%s' should parse back to kind %d", name, k);
    }
    ras_compare_kind parsed;
    ras_error err = {{0}};
    CHECK(!ras_compare_kind_parse("mse", &parsed, &err) && strstr(err.msg, "'mse'") &&
              strstr(err.msg, "ssim"),
          "an unknown name should be refused listing the valid ones, got \"%s\"", err.msg);
}

/* The edge-tolerant difference as the header states it, written out plainly
 * (every neighbour tested against the border): the library's windowed loop
 * must count the same bad pixels at every tolerance; and one comparison
 * (ras_comparison_*) must answer what the three separate calls answer. */
static int brute_channel_max(const uint8_t *a, const uint8_t *b) {
    int d = 0;
    for (int c = 0; c < 3; c++) d = abs(a[c] - b[c]) > d ? abs(a[c] - b[c]) : d;
    return d;
}
static int brute_min(const uint8_t *px, const uint8_t *other, int w, int h, int col, int row) {
    int best = 255;
    for (int dr = -1; dr <= 1; dr++)
        for (int dc = -1; dc <= 1; dc++) {
            int r = row + dr, c = col + dc;
            if (r < 0 || r >= h || c < 0 || c >= w) continue;
            int d = brute_channel_max(px, other + 3 * (r * w + c));
            if (d < best) best = d;
        }
    return best;
}
static void test_comparison_matches_separate_calls_and_the_stated_formula(void **state) {
    (void)state;
    const int w = 37, h = 23;
    ras_image *e = make_texture(w, h, 0.0f, 1), *g = make_texture(w, h, 0.08f, 7);
    fill_rect(g, 0, 0, 5, 4, (vec3s){{1, 0, 0}});    /* a corner block */
    fill_rect(g, w - 3, 9, 3, 14, (vec3s){{0, 1, 0}}); /* on the right and bottom edges */
    uint8_t *eb = malloc(3 * w * h), *gb = malloc(3 * w * h);
    assert_non_null(eb);
    assert_non_null(gb);
    ras_image_to_rgb8(e, eb);
    ras_image_to_rgb8(g, gb);
    int diff[37 * 23];
    for (int row = 0; row < h; row++)
        for (int col = 0; col < w; col++) {
            int i = row * w + col, d = brute_channel_max(eb + 3 * i, gb + 3 * i);
            if (d > 0) {
                int a = brute_min(gb + 3 * i, eb, w, h, col, row);
                int b = brute_min(eb + 3 * i, gb, w, h, col, row);
                d = a > b ? a : b;
            }
            diff[i] = d;
        }
    ras_error err = {{0}};
    ras_comparison *c = ras_comparison_create(e, g, RAS_COMPARE_EDGE_TOLERANT, &err);
    CHECK(c, "ras_comparison_create failed: %s", err.msg);
    for (int tol = 0; tol <= 255; tol += 5) {
        ras_compare_options opt = ras_compare_defaults(RAS_COMPARE_EDGE_TOLERANT);
        opt.tolerance = tol;
        long want = 0;
        for (int i = 0; i < w * h; i++) want += diff[i] > tol;
        ras_compare_result one, sep;
        assert_true(ras_comparison_result(c, &opt, &one, &err));
        assert_true(ras_compare_images(e, g, &opt, &sep, &err));
        CHECK(one.bad_pixels == want && sep.bad_pixels == want,
              "tolerance %d: expected %ld edge-tolerant bad pixels (the header's formula, "
              "brute force), got %ld (one comparison) and %ld (ras_compare_images)",
              tol, want, one.bad_pixels, sep.bad_pixels);
        CHECK(!strcmp(one.summary, sep.summary) && one.ssim == sep.ssim &&
                  one.psnr_db == sep.psnr_db && one.worst_col == sep.worst_col &&
                  one.worst_row == sep.worst_row,
              "tolerance %d: one comparison said '%s', ras_compare_images '%s'", tol, one.summary,
              sep.summary);
    }
    ras_image *h1 = ras_comparison_heatmap(c, &err), *h2 = ras_compare_heatmap(e, g, RAS_COMPARE_EDGE_TOLERANT, &err);
    ras_image *c1 = ras_comparison_crop(c, 2, 3, &err), *c2 = ras_compare_crop(e, g, RAS_COMPARE_EDGE_TOLERANT, 2, 3, &err);
    assert_non_null(h1);
    assert_non_null(h2);
    assert_non_null(c1);
    assert_non_null(c2);
    CHECK(!memcmp(h1->pixels, h2->pixels, sizeof(vec3s) * (size_t)w * h),
          "the comparison's heatmap differs from ras_compare_heatmap's");
    CHECK(c1->width == c2->width && c1->height == c2->height &&
              !memcmp(c1->pixels, c2->pixels, sizeof(vec3s) * (size_t)c1->width * c1->height),
          "the comparison's crop differs from ras_compare_crop's");
    ras_image_destroy(h1);
    ras_image_destroy(h2);
    ras_image_destroy(c1);
    ras_image_destroy(c2);
    ras_comparison_destroy(c);
    free(eb);
    free(gb);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

/* SSIM as the header defines it, per pixel with its own clipped 11x11
 * window (the library smooths separably and skips windows that agree): the
 * same value within rounding on a picture that differs only in a band, so
 * that most windows are skipped and the others are not. */
static double brute_ssim(const ras_image *e, const ras_image *g) {
    int w = e->width, h = e->height;
    double sum = 0;
    for (int row = 0; row < h; row++)
        for (int col = 0; col < w; col++) {
            double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
            for (int dr = -5; dr <= 5; dr++)
                for (int dc = -5; dc <= 5; dc++) {
                    int r = row + dr, c = col + dc;
                    if (r < 0 || r >= h || c < 0 || c >= w) continue;
                    double wk = exp(-(dr * dr + dc * dc) / (2.0 * 1.5 * 1.5));
                    vec3s a = ras_image_get(e, c, r), b = ras_image_get(g, c, r);
                    double x = 0.299 * ras_unit_to_byte(a.x) + 0.587 * ras_unit_to_byte(a.y) +
                               0.114 * ras_unit_to_byte(a.z);
                    double y = 0.299 * ras_unit_to_byte(b.x) + 0.587 * ras_unit_to_byte(b.y) +
                               0.114 * ras_unit_to_byte(b.z);
                    sw += wk, sx += wk * x, sy += wk * y;
                    sxx += wk * x * x, syy += wk * y * y, sxy += wk * x * y;
                }
            double mx = sx / sw, my = sy / sw, vx = sxx / sw - mx * mx, vy = syy / sw - my * my,
                   cxy = sxy / sw - mx * my, c1 = 6.5025, c2 = 58.5225;
            sum += (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
        }
    return sum / ((double)w * h);
}
static void test_compare_ssim_band_matches_per_pixel_windows(void **state) {
    (void)state;
    ras_image *e = make_texture(41, 47, 0.0f, 3), *g = ras_image_clone(e);
    fill_rect(g, 4, 20, 30, 3, (vec3s){{0.9f, 0.1f, 0.3f}});
    ras_compare_result r = compare(e, g, RAS_COMPARE_SSIM);
    double want = brute_ssim(e, g);
    CHECK(fabs(r.ssim - want) < 1e-12 && r.ssim < 0.99,
          "SSIM of a picture against itself with a 30x3 band painted: expected %.15f (every "
          "pixel's own window, brute force), got %.15f",
          want, r.ssim);
    ras_image_destroy(e);
    ras_image_destroy(g);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compare_identical_passes_every_metric),
        cmocka_unit_test(test_compare_edge_shift_fails_exact_passes_edge_tolerant),
        cmocka_unit_test(test_compare_missing_square_fails_edge_tolerant),
        cmocka_unit_test(test_compare_missing_thin_line_fails_edge_tolerant),
        cmocka_unit_test(test_compare_psnr_uniform_difference),
        cmocka_unit_test(test_compare_ssim_noise_and_symmetry),
        cmocka_unit_test(test_compare_ssim_closed_form),
        cmocka_unit_test(test_compare_combined_checks),
        cmocka_unit_test(test_compare_exact_quantises_to_8_bits),
        cmocka_unit_test(test_compare_heatmap_black_where_equal),
        cmocka_unit_test(test_compare_crop_dimensions_and_panels),
        cmocka_unit_test(test_compare_size_mismatch_names_both_sizes),
        cmocka_unit_test(test_compare_ascii_mask_small_case),
        cmocka_unit_test(test_compare_defaults_and_names),
        cmocka_unit_test(test_comparison_matches_separate_calls_and_the_stated_formula),
        cmocka_unit_test(test_compare_ssim_band_matches_per_pixel_windows),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
