/* test_depth.c — the depth formats of stage 3 (common/pipeline/stage3_setup.h):
 * RAS_DEPTH_Z01, (1 − z_ndc)/2, and RAS_DEPTH_INV_W, −near/w.
 *
 *   hand-worked   near 0.1, far 50: view depths 40 and 40.001 get the same
 *                 float with Z01 and distinct, correctly ordered ones with
 *                 INV_W (the arithmetic is in the test's comments)
 *   exact         −near/w interpolated linearly in screen space is exactly
 *                 −near/w_true at every point of a tilted triangle (checked at
 *                 a hand-picked screen point and at every pixel the reference
 *                 rasterizer stores), while linearly interpolated w is not
 *   z-fighting    the two-plane scene of docs/accuracy.md §5 at δ = 0.0001
 *                 through the real pipeline (hw1 projection, hw2 rasterizer):
 *                 Z01 shows the farther plane almost everywhere, INV_W nowhere
 *   contract      range and clamp per format, the +INFINITY clear is farther
 *                 than any INV_W depth, Z01 through ras_viewport_depth is
 *                 bit for bit ras_viewport's (the Z01-only form), config errors
 */
#include <setjmp.h> /* cmocka needs these before cmocka.h */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ras_test_main.h"

#include "ras_pipeline.h"
#include "rasterizer.h" /* hw2 reference: rasterize_triangle */
#include "stage3_setup.h"
#include "transform.h" /* hw1 reference: get_projection_matrix */

#include <math.h>   /* tan, fabs, sqrt, nextafterf, INFINITY, NAN */
#include <stdio.h>  /* printf */
#include <string.h> /* memcmp, strstr */

#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) fail_msg(__VA_ARGS__);                                                        \
    } while (0)

#define PI 3.14159265358979323846
#define NEAR 0.1f
#define FAR 50.0f
#define FOV_DEG 45.0

/* The GAMES101 projection (hw1's, after ras_projection_normalize_w) written
 * out, in float like the pipeline, for a point on the view axis at distance
 * d: z_clip = A·(−d) + B with A = (f+n)/(f−n), B = 2fn/(f−n); w = d. */
static vec4s clip_on_axis(float d) {
    float A = (FAR + NEAR) / (FAR - NEAR), B = 2.0f * FAR * NEAR / (FAR - NEAR);
    return (vec4s){{0, 0, A * -d + B, d}};
}

/* ---- hand-worked ------------------------------------------------------------ */

/* Z01: depth(d) = (1 − z_ndc)/2 = f/(f−n) · (1 − n/d).
 *   d = 40:     50/49.9 · (1 − 0.0025)        = 0.999498998
 *   d = 40.001: 50/49.9 · (1 − 0.00249993750) = 0.999499061
 *   gap = f/(f−n) · n·δ/d² = 1.002 · 0.1 · 0.001 / 1600 = 6.26e-8,
 * about one float step (2^-24 = 5.96e-8 in [0.5, 1)). Computed in float —
 * z_clip ≈ −39.96 rounds to 3.8e-6, i.e. 9.5e-8 relative, then the divide,
 * 1 − z_ndc and ·0.5 round again — both land on the same float, 0.99949896:
 * the depth test cannot tell them apart.
 * INV_W: depth = −n/d, one division:
 *   d = 40:     −0.1/40     = −0.0025
 *   d = 40.001: −0.1/40.001 = −0.0024999375
 *   gap = n·δ/d² = 6.25e-8, while the float step at 0.0025 is 2^-32 = 2.3e-10:
 * ~270 steps apart, and −0.0025 < −0.0024999375, so the nearer is smaller. */
static void test_depth_hand_worked_40_vs_40_001(void **state) {
    (void)state;
    float d0 = 40.0f, d1 = 40.001f;
    vec4s z0 = ras_viewport_depth(clip_on_axis(d0), 700, 700, RAS_DEPTH_Z01, NEAR);
    vec4s z1 = ras_viewport_depth(clip_on_axis(d1), 700, 700, RAS_DEPTH_Z01, NEAR);
    printf("z01:       40 -> %.9g, 40.001 -> %.9g\n", (double)z0.z, (double)z1.z);
    CHECK(fabs(z0.z - 0.999498998) < 2e-7, "z01 depth of 40: %.9g, expected 0.999498998",
          (double)z0.z);
    CHECK(z0.z == z1.z,
          "z01 separates 40 and 40.001 (%.9g vs %.9g): the float pipeline no "
          "longer rounds as the comment says",
          (double)z0.z, (double)z1.z);

    vec4s i0 = ras_viewport_depth(clip_on_axis(d0), 700, 700, RAS_DEPTH_INV_W, NEAR);
    vec4s i1 = ras_viewport_depth(clip_on_axis(d1), 700, 700, RAS_DEPTH_INV_W, NEAR);
    printf("inverse_w: 40 -> %.9g, 40.001 -> %.9g\n", (double)i0.z, (double)i1.z);
    CHECK(i0.z == -0.0025f, "inverse_w depth of 40: %.9g, expected -0.0025", (double)i0.z);
    CHECK(i0.z < i1.z, "inverse_w: the nearer point (40) must be smaller: %.9g vs %.9g",
          (double)i0.z, (double)i1.z);
    /* The gap is the exact one, n·(d1 − d0)/(d0·d1) with d1 the float 40.001f,
     * to 1% (each depth rounds once, by 2^-33 at most). */
    double gap = (double)i1.z - i0.z, exact = 0.1 * ((double)d1 - d0) / ((double)d0 * d1);
    CHECK(fabs(gap - exact) < 0.01 * exact, "inverse_w gap %.4g, expected %.4g", gap, exact);
    /* x, y and w do not depend on the format. */
    CHECK(i0.x == z0.x && i0.y == z0.y && i0.w == z0.w, "inverse_w changed x, y or w");
}

/* ---- exact interpolation ---------------------------------------------------- */

/* A triangle tilted in depth (w from 1.5 to 9 at its corners), in view space. */
static const double TILTED[3][3] = {{-1.2, -0.9, -1.5}, {2.5, -1.0, -9.0}, {0.3, 3.0, -4.0}};

/* The view-space distance (w) at which the camera ray through screen point
 * (sx, sy) of a size×size image meets the plane of TILTED, in double: the
 * ground truth, independent of the pipeline. */
static double true_w(double sx, double sy, int size) {
    double t = tan(FOV_DEG * PI / 360.0);
    double d[3] = {(2 * sx / size - 1) * t, (2 * sy / size - 1) * t, -1};
    double e1[3], e2[3], n[3];
    for (int i = 0; i < 3; i++)
        e1[i] = TILTED[1][i] - TILTED[0][i], e2[i] = TILTED[2][i] - TILTED[0][i];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double s = (n[0] * TILTED[0][0] + n[1] * TILTED[0][1] + n[2] * TILTED[0][2]) /
               (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]);
    return s; /* the hit is s·d, and d has z = −1: its distance along −z is s */
}

static ras_mesh *tilted_mesh(void) {
    ras_mesh *m = ras_mesh_create(3, 1);
    assert_non_null(m);
    for (int i = 0; i < 3; i++) {
        m->positions[i] = (vec3s){{(float)TILTED[i][0], (float)TILTED[i][1], (float)TILTED[i][2]}};
        m->colors[i] = (vec3s){{1, 1, 1}};
        m->indices[i] = (unsigned)i;
    }
    return m;
}

/* The screen triangle of TILTED as stage 3 builds it. */
static ras_triangle tilted_screen(int size, ras_depth_format format) {
    ras_mesh *m = tilted_mesh();
    mat4s proj = get_projection_matrix((float)FOV_DEG, 1, NEAR, FAR);
    ras_clip_vertex cv[3];
    ras_vertex_transform(m, glms_mat4_identity(), glms_mat4_identity(), proj, RAS_VARYING_COLOR,
                         cv);
    ras_mesh_destroy(m);
    ras_triangle t;
    assert_true(ras_setup_triangle_depth(&cv[0], &cv[1], &cv[2], size, size, format, NEAR, &t));
    return t;
}

/* Screen-space barycentrics of (px, py), in double. */
static void screen_bary(const ras_triangle *t, double px, double py, double l[3]) {
    double x[3], y[3];
    for (int i = 0; i < 3; i++)
        x[i] = t->v[i].x, y[i] = t->v[i].y;
    double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    l[0] = ((x[1] - px) * (y[2] - py) - (x[2] - px) * (y[1] - py)) / area;
    l[1] = ((x[2] - px) * (y[0] - py) - (x[0] - px) * (y[2] - py)) / area;
    l[2] = 1 - l[0] - l[1];
}

/* At the screen midpoint of the edge from corner 0 (w = 1.5) to corner 1
 * (w = 9), λ = (½, ½, 0):
 *   −n/w interpolated = ½(−0.1/1.5 − 0.1/9) = −0.0388889, so w = 2.5714
 *   = 2·1.5·9/(1.5 + 9), the harmonic mean — which is where the camera ray
 * through that screen point meets the edge (1/w is affine on screen).
 * Interpolating w itself would give ½(1.5 + 9) = 5.25: more than twice too
 * far, which is why there is no "view depth w" format. */
static void test_depth_inverse_w_interpolates_exactly(void **state) {
    (void)state;
    const int size = 512;
    ras_triangle t = tilted_screen(size, RAS_DEPTH_INV_W);
    double px = 0.5 * ((double)t.v[0].x + t.v[1].x), py = 0.5 * ((double)t.v[0].y + t.v[1].y);
    double l[3];
    screen_bary(&t, px, py, l);
    double d_interp = l[0] * t.v[0].z + l[1] * t.v[1].z + l[2] * t.v[2].z;
    double w_lin = l[0] * t.v[0].w + l[1] * t.v[1].w + l[2] * t.v[2].w;
    double w = true_w(px, py, size), d_true = -NEAR / w;
    printf("edge midpoint: w true %.6f, from interpolated -n/w %.6f, from interpolated w %.6f\n", w,
           -NEAR / d_interp, w_lin);
    CHECK(fabs(w - 2.0 * 1.5 * 9 / 10.5) < 1e-4, "true w %.6f, expected the harmonic mean 2.5714",
          w);
    CHECK(fabs(d_interp - d_true) <= 1e-6 * fabs(d_true),
          "interpolated -n/w %.9g, expected -n/w_true = %.9g", d_interp, d_true);
    CHECK(fabs(w_lin - w) > 0.5 * w, "linearly interpolated w %.4f should be far from %.4f", w_lin,
          w);

    /* The same through the reference rasterizer: every stored depth is
     * −n/w_true at its pixel centre to float precision. */
    ras_pipeline_config cfg = {.width = size,
                               .height = size,
                               .rasterize = rasterize_triangle,
                               .depth = RAS_DEPTH_INV_W,
                               .z_near = NEAR};
    ras_pipeline *p = ras_pipeline_create(&cfg, NULL);
    assert_non_null(p);
    ras_mesh *m = tilted_mesh();
    mat4s proj = get_projection_matrix((float)FOV_DEG, 1, NEAR, FAR);
    assert_true(
        ras_pipeline_draw_mesh(p, m, glms_mat4_identity(), glms_mat4_identity(), proj, NULL));
    ras_mesh_destroy(m);
    /* The reference snaps vertices to 1/256 px (fixed-point edges) and
     * interpolates over the snapped triangle; stage 3 gives each corner the
     * depth of the triangle's plane at its snapped position (stage3_setup.h),
     * so the stored depth is -n/w_true to float rounding (a few 1e-7 of the
     * depth) — not moved by |∇depth| · (√2/512 px), as it was when each
     * corner kept its unsnapped depth (1.2e-5 relative here then). */
    long n = 0;
    double worst_rel = 0;
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++) {
            /* ras_framebuffer rows are stored top-down: row 0 is the top. */
            float z = p->fb->depth[(size_t)(size - 1 - y) * size + x];
            if (z == INFINITY) continue;
            double dt = -NEAR / true_w(x + 0.5, y + 0.5, size);
            worst_rel = fmax(worst_rel, fabs(z - dt) / fabs(dt));
            n++;
        }
    ras_pipeline_destroy(p);
    printf("rasterized: %ld pixels, worst relative error of -n/w %.2e\n", n, worst_rel);
    CHECK(n > 1000, "the tilted triangle covered only %ld pixels", n);
    CHECK(worst_rel <= 1e-6,
          "stored depth differs from -n/w_true by %.2e of it; expected float rounding only "
          "(<= 1e-6). Likely: the corners' depth not taken at their snapped positions "
          "(stage3_setup.c)",
          worst_rel);
}

/* ---- z-fighting through the pipeline --------------------------------------- */

/* docs/accuracy.md §5: two planes tilted away from the camera (view depth 30
 * at the bottom of the screen to 49 at the top), the second δ farther along
 * −z and drawn first, so a tie shows the farther one. Returns the fraction of
 * pixels showing the farther plane. */
static double zfight_wrong(ras_depth_format format, double delta) {
    const int size = 96;
    double t = tan(FOV_DEG * PI / 360.0), d0 = 30, d1 = 49, o = 1.1;
    ras_mesh *planes[2];
    for (int k = 0; k < 2; k++) {
        double shift = k == 0 ? delta : 0; /* planes[0]: the farther, drawn first */
        double p[4][3] = {{-o * d0 * t, -o * d0 * t, -d0 - shift},
                          {o * d0 * t, -o * d0 * t, -d0 - shift},
                          {o * d1 * t, o * d1 * t, -d1 - shift},
                          {-o * d1 * t, o * d1 * t, -d1 - shift}};
        ras_mesh *m = ras_mesh_create(4, 2);
        assert_non_null(m);
        for (int i = 0; i < 4; i++) {
            m->positions[i] = (vec3s){{(float)p[i][0], (float)p[i][1], (float)p[i][2]}};
            m->colors[i] = k == 0 ? (vec3s){{0, 0, 1}} : (vec3s){{1, 0, 0}};
        }
        static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
        memcpy(m->indices, idx, sizeof idx);
        planes[k] = m;
    }
    ras_pipeline_config cfg = {.width = size,
                               .height = size,
                               .rasterize = rasterize_triangle,
                               .varyings = RAS_VARYING_COLOR,
                               .depth = format,
                               .z_near = NEAR};
    ras_pipeline *p = ras_pipeline_create(&cfg, NULL);
    assert_non_null(p);
    mat4s proj = get_projection_matrix((float)FOV_DEG, 1, NEAR, FAR);
    for (int k = 0; k < 2; k++) {
        assert_true(ras_pipeline_draw_mesh(p, planes[k], glms_mat4_identity(), glms_mat4_identity(),
                                           proj, NULL));
        ras_mesh_destroy(planes[k]);
    }
    long wrong = 0, right = 0;
    for (int i = 0; i < size * size; i++) {
        vec3s c = p->fb->color[i];
        /* Interpolating a constant colour rounds (Σλ is 1 only to a few
         * ulps), so compare with ½, not with 0 and 1. */
        wrong += c.z > 0.5f && c.x < 0.5f;
        right += c.x > 0.5f && c.z < 0.5f;
    }
    ras_pipeline_destroy(p);
    /* Every pixel shows one plane or the other (they overscan the view). */
    assert_int_equal(wrong + right, size * size);
    return (double)wrong / (size * size);
}

static void test_depth_zfighting_delta_1e4(void **state) {
    (void)state;
    double z01 = zfight_wrong(RAS_DEPTH_Z01, 1e-4), inv = zfight_wrong(RAS_DEPTH_INV_W, 1e-4);
    printf("δ = 0.0001: farther plane shown at %.2f%% (z01) and %.2f%% (inverse_w) of pixels\n",
           100 * z01, 100 * inv);
    /* Z01's answer is a coin toss at best: the scene does show the problem. */
    CHECK(z01 > 0.5, "z01 got %.2f%% wrong at δ = 0.0001; docs/accuracy.md says ~100%%", 100 * z01);
    CHECK(inv == 0, "inverse_w got %.2f%% wrong at δ = 0.0001; expected none", 100 * inv);
    /* Both resolve a large gap. */
    CHECK(zfight_wrong(RAS_DEPTH_Z01, 0.1) == 0, "z01 fails at δ = 0.1");
    CHECK(zfight_wrong(RAS_DEPTH_INV_W, 0.1) == 0, "inverse_w fails at δ = 0.1");
}

/* ---- contract ------------------------------------------------------------- */

static void test_depth_range_clamp_and_clear(void **state) {
    (void)state;
    /* The near plane is −1, infinity → 0; a vertex a rounding error nearer
     * than the near plane (as the clipper can leave one) is clamped to −1. */
    CHECK(ras_viewport_depth((vec4s){{0, 0, NEAR, NEAR}}, 8, 8, RAS_DEPTH_INV_W, NEAR).z == -1.0f,
          "the near plane is not -1");
    float below = nextafterf(NEAR, 0);
    CHECK(ras_viewport_depth((vec4s){{0, 0, below, below}}, 8, 8, RAS_DEPTH_INV_W, NEAR).z == -1.0f,
          "a vertex nearer than the near plane is not clamped to -1");
    float far = ras_viewport_depth((vec4s){{0, 0, -1e30f, 1e30f}}, 8, 8, RAS_DEPTH_INV_W, NEAR).z;
    CHECK(far <= 0 && far > -1e-30f, "a vertex at w = 1e30 has depth %g", (double)far);
    /* The buffer's clear value is farther than any INV_W depth. */
    CHECK(far < INFINITY, "+INFINITY (the clear) must be farther than every depth");
    /* NaN is not hidden by the clamp: setup rejects the triangle. */
    CHECK(isnan(ras_viewport_depth((vec4s){{0, 0, 0, NAN}}, 8, 8, RAS_DEPTH_INV_W, NEAR).z),
          "NaN w must give a NaN depth");
    /* Z01 keeps its clamp to [0, 1]. */
    CHECK(ras_viewport_depth((vec4s){{0, 0, 1.001f, 1}}, 8, 8, RAS_DEPTH_Z01, NEAR).z == 0.0f,
          "z01 no longer clamps to 0");
}

/* The default format is the old viewport, bit for bit, through both entry
 * points (the reference images depend on it). */
static void test_depth_z01_is_the_old_viewport(void **state) {
    (void)state;
    static const float zs[] = {-3, -1, -0.3f, 0, 0.25f, 0.999f, 1, 1.5f};
    static const float ws[] = {1e-5f, 0.1f, 1, 3.7f, 40, 1e4f};
    for (size_t i = 0; i < sizeof zs / sizeof zs[0]; i++)
        for (size_t j = 0; j < sizeof ws / sizeof ws[0]; j++) {
            vec4s c = {{0.3f * ws[j], -0.7f * ws[j], zs[i] * ws[j], ws[j]}};
            float inv_w = 1.0f / c.w;
            float depth = (1.0f - c.z * inv_w) * 0.5f; /* the viewport before formats */
            depth = depth < 0 ? 0 : depth > 1 ? 1 : depth;
            vec4s a = ras_viewport(c, 700, 500),
                  b = ras_viewport_depth(c, 700, 500, RAS_DEPTH_Z01, 7);
            CHECK(a.z == depth && memcmp(&a, &b, sizeof a) == 0,
                  "z01 viewport differs at z %g w %g", (double)zs[i], (double)ws[j]);
        }
    ras_pipeline_config cfg = {.width = 4, .height = 4, .rasterize = rasterize_triangle};
    ras_pipeline *p = ras_pipeline_create(&cfg, NULL);
    assert_non_null(p);
    assert_int_equal(p->config.depth, RAS_DEPTH_Z01); /* zero-initialised config = old behaviour */
    ras_pipeline_destroy(p);
}

static void test_depth_config_errors(void **state) {
    (void)state;
    ras_error err = {{0}};
    ras_pipeline_config cfg = {
        .width = 4, .height = 4, .rasterize = rasterize_triangle, .depth = RAS_DEPTH_INV_W};
    assert_null(ras_pipeline_create(&cfg, &err));
    CHECK(strstr(err.msg, "z_near"), "no word about z_near: %s", err.msg);
    cfg.z_near = INFINITY;
    assert_null(ras_pipeline_create(&cfg, &err));
    cfg.depth = (ras_depth_format)7;
    cfg.z_near = 0.1f;
    assert_null(ras_pipeline_create(&cfg, &err));
    assert_string_equal(ras_depth_format_name(RAS_DEPTH_Z01), "z01");
    assert_string_equal(ras_depth_format_name(RAS_DEPTH_INV_W), "inverse_w");
    assert_string_equal(ras_depth_format_name((ras_depth_format)7), "?");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_depth_hand_worked_40_vs_40_001),
        cmocka_unit_test(test_depth_inverse_w_interpolates_exactly),
        cmocka_unit_test(test_depth_zfighting_delta_1e4),
        cmocka_unit_test(test_depth_range_clamp_and_clear),
        cmocka_unit_test(test_depth_z01_is_the_old_viewport),
        cmocka_unit_test(test_depth_config_errors),
    };
    return RAS_RUN_TESTS("depth", tests, NULL, NULL);
}
