/* test_clip.c — the clipper's contract (common/pipeline/stage2_clip.h) under extreme
 * but legal cameras, and the rasterizer's exact range (stage4_raster.h).
 *
 * Groups:
 *   scenes    the scenes that broke the clipper (near 0.01 or 0.1 with far 1e6, a tip
 *             just in front of the eye, a far edge at 900 000): drawn through
 *             the whole pipeline (hw1's projection, stage 2 clipping, setup,
 *             hw2's reference rasterizer) and compared pixel by pixel with an
 *             independent ray cast in double precision;
 *   contract  a randomized search (fixed seed, a fixed number of scenes, no
 *             timing) over legal cameras — near from 1e-12, far up to 1e6 —
 *             and triangles around, in front of, behind and far from the eye:
 *             every corner the clipper emits is finite, has w >= ε, lies on
 *             the inner side of all seven planes, and lands inside the
 *             rasterizer's exact range after the viewport;
 *   range     the rasterizer's range at its limit: a triangle with a vertex
 *             exactly at ±RAS_RASTER_MAX_COORD is drawn exactly, one a step
 *             beyond is refused and counted, through the pipeline and through
 *             ras_raster_check_range's message.
 *
 * The ray cast is the ground truth, not the pipeline's own arithmetic: per
 * pixel centre a ray from the eye through the image plane (the camera's fov
 * and aspect, in double), intersected with the world-space triangle
 * (Möller–Trumbore in double), counted when the hit lies between the near and
 * far distances. A pixel whose answer changes within ±0.01 px of its centre
 * (five rays) is on an edge and accepts either answer.
 *
 * Randomness: a fixed-seed splitmix64, so failures reproduce.
 */
#include <setjmp.h> /* cmocka needs these before cmocka.h */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ras_test_main.h"

#include "ras_pipeline.h"
#include "rasterizer.h" /* hw2 reference: rasterize_triangle */
#include "stage2_clip.h"
#include "transform.h" /* hw1 reference: get_projection_matrix */

#include <math.h>   /* tan, fabs, INFINITY, isfinite */
#include <stdio.h>  /* printf, snprintf */
#include <stdlib.h> /* calloc, free */
#include <string.h> /* strstr */

#define CHECK(cond, ...)                                                     \
    do {                                                                     \
        if (!(cond)) fail_msg(__VA_ARGS__);                                  \
    } while (0)

#define PI 3.14159265358979323846

/* ---- fixed-seed PRNG (splitmix64) --------------------------------------- */

typedef struct rng {
    uint64_t s;
} rng;

static uint64_t rng_next(rng *r) {
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double rng_uniform(rng *r, double lo, double hi) {
    return lo + (hi - lo) * ((double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0));
}

/* 10^[lo, hi], uniform in the exponent */
static double rng_log(rng *r, double lo_exp, double hi_exp) {
    return pow(10.0, rng_uniform(r, lo_exp, hi_exp));
}

/* ---- a scene: the fixed GAMES101 camera (eye, looking down -z) ---------- */

typedef struct scene {
    double eye[3];
    double fov_deg, z_near, z_far;
    int width, height;
    double tri[3][3]; /* world space */
} scene;

/* What a scene file's camera gives the pipeline: hw1's projection (the
 * reference's), the fixed view, in float, as ras_vertex_transform does. */
static mat4s scene_mvp(const scene *s) {
    mat4s proj = get_projection_matrix((float)s->fov_deg, (float)s->width / (float)s->height,
                                       (float)s->z_near, (float)s->z_far);
    vec3s eye = {{(float)s->eye[0], (float)s->eye[1], (float)s->eye[2]}};
    return ras_mat4_mul(ras_projection_normalize_w(proj), ras_view_matrix_eye(eye));
}

static void scene_clip_vertices(const scene *s, ras_clip_vertex v[3]) {
    mat4s mvp = scene_mvp(s);
    for (int i = 0; i < 3; i++) {
        vec4s p = {{(float)s->tri[i][0], (float)s->tri[i][1], (float)s->tri[i][2], 1.0f}};
        v[i] = (ras_clip_vertex){.p_clip = ras_mat4_mulv(mvp, p),
                                 .color = {{1, 1, 1}},
                                 .normal = {{0, 0, 1}}};
    }
}

/* The ray cast: does the ray through screen point (sx, sy) hit the triangle
 * between the near and the far distance? The float scene values are what the
 * pipeline sees, so they are the inputs here too (widened exactly). */
static bool ray_hits(const scene *s, double sx, double sy) {
    double t = tan((double)(float)s->fov_deg * PI / 360.0);
    double aspect = (double)((float)s->width / (float)s->height);
    double d[3] = {(2 * sx / s->width - 1) * t * aspect, (2 * sy / s->height - 1) * t, -1};
    double a[3], e1[3], e2[3];
    for (int i = 0; i < 3; i++) {
        double eye = (double)(float)s->eye[i];
        a[i] = (double)(float)s->tri[0][i] - eye;
        e1[i] = (double)(float)s->tri[1][i] - eye - a[i];
        e2[i] = (double)(float)s->tri[2][i] - eye - a[i];
    }
    double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                   d[0] * e2[1] - d[1] * e2[0]};
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0) return false;
    double o[3] = {-a[0], -a[1], -a[2]}; /* the eye, relative to corner 0 */
    double u = (o[0] * p[0] + o[1] * p[1] + o[2] * p[2]) / det;
    double q[3] = {o[1] * e1[2] - o[2] * e1[1], o[2] * e1[0] - o[0] * e1[2],
                   o[0] * e1[1] - o[1] * e1[0]};
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    double dist = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det; /* -z_view of the hit */
    return u >= 0 && v >= 0 && u + v <= 1 && dist >= (double)(float)s->z_near &&
           dist <= (double)(float)s->z_far;
}

enum { RC_OUT = 0, RC_IN = 1, RC_EDGE = 2 };

static int raycast_pixel(const scene *s, int x, int y) {
    const double tol = 0.01;
    double cx = x + 0.5, cy = y + 0.5;
    bool c = ray_hits(s, cx, cy);
    if (ray_hits(s, cx - tol, cy) != c || ray_hits(s, cx + tol, cy) != c ||
        ray_hits(s, cx, cy - tol) != c || ray_hits(s, cx, cy + tol) != c)
        return RC_EDGE;
    return c ? RC_IN : RC_OUT;
}

typedef struct comparison {
    long lit, truth_in, truth_edge, holes, extra;
    ras_counters k;
} comparison;

/* Draws the scene through the pipeline (no AA) and compares the covered
 * pixels (depth written) with the ray cast. */
static comparison compare_with_raycast(const scene *s, ras_depth_format depth) {
    ras_pipeline_config cfg = {.width = s->width,
                               .height = s->height,
                               .rasterize = rasterize_triangle,
                               .resolve = resolve_pixel,
                               .depth = depth,
                               .z_near = (float)s->z_near};
    ras_error err;
    ras_pipeline *p = ras_pipeline_create(&cfg, &err);
    if (!p) fail_msg("test setup: %s", err.msg);
    ras_clip_vertex v[3];
    scene_clip_vertices(s, v);
    ras_pipeline_draw_clip_triangle(p, &v[0], &v[1], &v[2]);
    comparison c = {.k = p->counters};
    for (int y = 0; y < s->height; y++)
        for (int x = 0; x < s->width; x++) {
            float z = p->fb->depth[ras_fb_sample_index(p->fb, x, y, 0)];
            bool lit = z != INFINITY;
            int truth = raycast_pixel(s, x, y);
            c.lit += lit;
            c.truth_in += truth == RC_IN;
            c.truth_edge += truth == RC_EDGE;
            c.holes += truth == RC_IN && !lit;
            c.extra += truth == RC_OUT && lit;
            if (lit)
                CHECK(depth == RAS_DEPTH_Z01 ? z >= 0 && z <= 1 : z >= -1 && z <= 0,
                      "depth %g stored at (%d, %d)", (double)z, x, y);
        }
    ras_pipeline_destroy(p);
    return c;
}

static void assert_matches_raycast(const scene *s, const char *what) {
    for (int f = 0; f < RAS_DEPTH_FORMAT_COUNT; f++) {
        comparison c = compare_with_raycast(s, (ras_depth_format)f);
        printf("%s (%s): %ld pixels lit, ray cast %ld inside + %ld on an edge; %ld holes, "
               "%ld extra\n",
               what, ras_depth_format_name((ras_depth_format)f), c.lit, c.truth_in,
               c.truth_edge, c.holes, c.extra);
        CHECK(c.truth_in > 0, "%s: test setup: the ray cast sees nothing", what);
        CHECK(c.holes == 0 && c.extra == 0,
              "%s (%s): %ld of the ray cast's %ld pixels missing and %ld lit outside it "
              "(%ld lit); expected the pipeline to light exactly the ray cast's pixels. "
              "Likely: a clipped corner with a wrong w or depth (stage2_clip.c)",
              what, ras_depth_format_name((ras_depth_format)f), c.holes, c.truth_in, c.extra,
              c.lit);
        CHECK(c.k.triangles_rejected_nonfinite == 0,
              "%s: %llu triangles rejected as non-finite", what,
              (unsigned long long)c.k.triangles_rejected_nonfinite);
    }
}

/* ---- scenes ----------------------------------------------------------------- */

/* Issue #27: a tip just in front of the eye, a far edge at 900 000, far 1e6,
 * the default near 0.1. The float cut gave the corner w = 0.125 instead of
 * 0.1 and depth 0.25 instead of 0, and lost 16 of the 84 true pixels. */
static void test_clip_scene_tip_near_far_edge(void **state) {
    (void)state;
    scene s = {.eye = {0, 0, 5}, .fov_deg = 45, .z_near = 0.1, .z_far = 1e6,
               .width = 700, .height = 700,
               .tri = {{0.01, 0.01, 4.95}, {-50, -1, -900000}, {50, -1, -900000}}};
    assert_matches_raycast(&s, "tip at 4.95, far edge at -9e5, near 0.1, far 1e6");
}

/* The same with the tip at 4.995 and near 0.01: the whole triangle vanished
 * ("triangles_rejected_nonfinite": 2). */
static void test_clip_scene_tip_closer_near_001(void **state) {
    (void)state;
    scene s = {.eye = {0, 0, 5}, .fov_deg = 45, .z_near = 0.01, .z_far = 1e6,
               .width = 700, .height = 700,
               .tri = {{0.01, 0.01, 4.995}, {-50, -1, -900000}, {50, -1, -900000}}};
    assert_matches_raycast(&s, "tip at 4.995, far edge at -9e5, near 0.01, far 1e6");
}

/* Found by a random search on the float clipper (near 0.01, far 1e6, a tip
 * within 0.01 of the eye, the far corners at 1e5 and 5e5): it emitted a
 * corner with w = 0, which setup then rejected or stretched across the frame. */
static void test_clip_scene_found_by_search(void **state) {
    (void)state;
    scene s = {.eye = {0, 0, 5}, .fov_deg = 45, .z_near = 0.01, .z_far = 1e6,
               .width = 256, .height = 256,
               .tri = {{0.0116474076, -0.0897293307, 4.99015045},
                       {73827.3668, -70968.9836, -548216.739},
                       {6956.36316, -6231.19753, -65193.7945}}};
    assert_matches_raycast(&s, "near 0.01, far 1e6, tip 0.01 from the eye, far corners");
}

/* ---- the contract ------------------------------------------------------------ */

static bool corner_in_contract(vec4s p, char *why, size_t size) {
    if (!ras_vec4_finite(p)) {
        snprintf(why, size, "not finite");
        return false;
    }
    if (!(p.w >= RAS_CLIP_W_EPSILON)) {
        snprintf(why, size, "w = %g < %g", (double)p.w, (double)RAS_CLIP_W_EPSILON);
        return false;
    }
    unsigned code = ras_clip_outcode(p);
    if (code) {
        snprintf(why, size, "outside plane mask 0x%x", code);
        return false;
    }
    return true;
}

/* A random legal scene (what a scene file takes: near > 0, far > near and
 * at most 1e6, coordinates within ±1e6): near from 1e-12 to 1, far up to
 * 1e6 (a quarter of them exactly 1e6), a fov of 1..170°, frames up to
 * RAS_IMAGE_MAX_SIDE, corners anywhere from just around the eye to beyond
 * the far plane, in front and behind. */
static void random_scene(rng *g, scene *s) {
    s->eye[0] = rng_uniform(g, -10, 10);
    s->eye[1] = rng_uniform(g, -10, 10);
    s->eye[2] = rng_uniform(g, -10, 10);
    s->fov_deg = rng_uniform(g, 1, 170);
    s->width = 1 + (int)rng_uniform(g, 0, RAS_IMAGE_MAX_SIDE);
    s->height = 1 + (int)rng_uniform(g, 0, RAS_IMAGE_MAX_SIDE);
    s->z_near = rng_log(g, -12, 0);
    s->z_far = rng_uniform(g, 0, 1) < 0.25 ? 1e6 : fmin(1e6, s->z_near * rng_log(g, 0.3, 12));
    for (int i = 0; i < 3; i++) {
        /* distance ahead: from behind the eye to past far, log-spread */
        double kind = rng_uniform(g, 0, 1);
        double ahead = kind < 0.15   ? -rng_log(g, -6, 3)
                       : kind < 0.5  ? s->z_near * rng_uniform(g, 0, 3)
                       : kind < 0.85 ? fmin(rng_log(g, -6, 0.1) * s->z_far, 9.9e5)
                                     : rng_log(g, -3, 5.9);
        double side = rng_log(g, -6, 5.9);
        double xs = side * rng_uniform(g, -1, 1), ys = side * rng_uniform(g, -1, 1);
        s->tri[i][0] = s->eye[0] + xs;
        s->tri[i][1] = s->eye[1] + ys;
        s->tri[i][2] = s->eye[2] - ahead;
    }
}

/* 300 000 random legal scenes: no emitted corner outside the contract, and
 * every corner's viewport position inside the rasterizer's exact range;
 * every other scene clipped with its far distance (w <= far). */
static void test_clip_contract_random_cameras(void **state) {
    (void)state;
    rng g = {0x27c11bULL};
    const long scenes = 300000;
    long split = 0, corners = 0, bad = 0, bad_w = 0, out_of_range = 0;
    char first[256] = "";
    double worst_w = INFINITY;
    scene worst = {0};
    for (long n = 0; n < scenes; n++) {
        scene s;
        random_scene(&g, &s);
        ras_clip_vertex v[3], out[RAS_CLIP_MAX_VERTICES];
        scene_clip_vertices(&s, v);
        if (!ras_vec4_finite(v[0].p_clip) || !ras_vec4_finite(v[1].p_clip) ||
            !ras_vec4_finite(v[2].p_clip))
            continue; /* the pipeline rejects it before clipping */
        int count = 0;
        /* every other scene with the camera's far distance, as the pipeline
         * clips (w <= far in double, stage2_clip.h) */
        double far = n & 1 ? (double)(float)s.z_far : 0.0;
        ras_clip_result r = ras_clip_triangle_far(&v[0], &v[1], &v[2], far, out, &count);
        if (r == RAS_CLIP_OUTSIDE) continue;
        split += r == RAS_CLIP_SPLIT;
        for (int i = 0; i < count; i++) {
            corners++;
            char why[96];
            if (out[i].p_clip.w < worst_w) worst_w = out[i].p_clip.w, worst = s;
            bool in_far = true;
            if (far > 0 && !((double)out[i].p_clip.w <= far)) {
                snprintf(why, sizeof why, "w = %.9g beyond far %.9g", (double)out[i].p_clip.w,
                         far);
                in_far = false;
            }
            /* with far, an untouched corner may lie between the float matrix's
             * far plane and the true one (z < -w; stage2_clip.h) */
            bool planes = far > 0 && r == RAS_CLIP_INSIDE;
            if (!in_far || (!planes && !corner_in_contract(out[i].p_clip, why, sizeof why))) {
                bad_w += !(out[i].p_clip.w >= RAS_CLIP_W_EPSILON);
                if (!bad++)
                    snprintf(first, sizeof first,
                             "scene %ld (near %g, far %g), corner %d (%g, %g, %g, %g): %s", n,
                             s.z_near, s.z_far, i, (double)out[i].p_clip.x,
                             (double)out[i].p_clip.y, (double)out[i].p_clip.z,
                             (double)out[i].p_clip.w, why);
                continue;
            }
            vec4s q = ras_viewport(out[i].p_clip, s.width, s.height);
            if (!(fabsf(q.x) <= RAS_RASTER_MAX_COORD && fabsf(q.y) <= RAS_RASTER_MAX_COORD)) {
                if (!out_of_range++ && !bad)
                    snprintf(first, sizeof first, "scene %ld: corner %d at (%g, %g) px", n, i,
                             (double)q.x, (double)q.y);
            }
        }
    }
    printf("%ld scenes: %ld split, %ld corners emitted, %ld outside the contract (%ld of them "
           "with w < %g), %ld beyond the rasterizer's range; smallest w emitted %g\n",
           scenes, split, corners, bad, bad_w, (double)RAS_CLIP_W_EPSILON, out_of_range, worst_w);
    if (getenv("RAS_CLIP_SHOW_WORST"))
        printf("  smallest-w scene: eye (%.9g %.9g %.9g) fov %.9g near %.9g far %.9g %dx%d tri "
               "(%.9g %.9g %.9g) (%.9g %.9g %.9g) (%.9g %.9g %.9g)\n",
               worst.eye[0], worst.eye[1], worst.eye[2], worst.fov_deg, worst.z_near,
               worst.z_far, worst.width, worst.height, worst.tri[0][0], worst.tri[0][1],
               worst.tri[0][2], worst.tri[1][0], worst.tri[1][1], worst.tri[1][2],
               worst.tri[2][0], worst.tri[2][1], worst.tri[2][2]);
    CHECK(split > scenes / 10, "test setup: only %ld of %ld scenes were cut", split, scenes);
    CHECK(bad == 0 && out_of_range == 0,
          "%ld corners outside the clipper's contract (w >= %g, inside all seven planes, "
          "w <= far when clipped with it) and "
          "%ld beyond the rasterizer's range; first: %s",
          bad, (double)RAS_CLIP_W_EPSILON, out_of_range, first);
}

/* Clip-space triangles straight, of every magnitude a float holds (no camera):
 * the contract does not depend on the projection having made the input. */
static void test_clip_contract_random_clip_space(void **state) {
    (void)state;
    rng g = {0xc11b27ULL};
    const long tris = 200000;
    long bad = 0, split = 0;
    char first[256] = "";
    for (long n = 0; n < tris; n++) {
        ras_clip_vertex v[3] = {0}, out[RAS_CLIP_MAX_VERTICES];
        double scale = rng_log(&g, -8, 30);
        for (int i = 0; i < 3; i++) {
            double c[4];
            for (int j = 0; j < 4; j++)
                c[j] = rng_uniform(&g, -1, 1) * (rng_uniform(&g, 0, 1) < 0.3 ? scale : 1.0);
            /* often on a plane, or a hair from one */
            if (rng_uniform(&g, 0, 1) < 0.3) c[2] = c[3] * (rng_uniform(&g, 0, 1) < 0.5 ? 1 : -1);
            if (rng_uniform(&g, 0, 1) < 0.2) c[0] = RAS_CLIP_GUARD * c[3];
            v[i].p_clip = (vec4s){{(float)c[0], (float)c[1], (float)c[2], (float)c[3]}};
        }
        int count = 0;
        ras_clip_result r = ras_clip_triangle(&v[0], &v[1], &v[2], out, &count);
        split += r == RAS_CLIP_SPLIT;
        for (int i = 0; i < count; i++) {
            char why[96];
            if (!corner_in_contract(out[i].p_clip, why, sizeof why) && !bad++)
                snprintf(first, sizeof first, "triangle %ld, corner %d: %s", n, i, why);
        }
    }
    printf("%ld clip-space triangles: %ld split, %ld corners outside the contract\n", tris,
           split, bad);
    CHECK(bad == 0, "%ld corners outside the clipper's contract; first: %s", bad, first);
}

/* ---- the rasterizer's range ------------------------------------------------- */

/* Samples of a 64x32 frame covered when the screen-space triangle
 * (x[i], y[i]) goes through the pipeline's stage 4 (its range check, then
 * hw2's reference rasterizer); *k gets the counters, *refused the pipeline's
 * message when it refused the triangle ("" otherwise). */
static long draw_screen(const double x[3], const double y[3], bool *covered, ras_counters *k,
                        char *refused, size_t size) {
    ras_pipeline_config cfg = {.width = 64, .height = 32, .rasterize = rasterize_triangle,
                               .resolve = resolve_pixel};
    ras_error err;
    ras_pipeline *p = ras_pipeline_create(&cfg, &err);
    if (!p) fail_msg("test setup: %s", err.msg);
    ras_triangle t = {0};
    for (int i = 0; i < 3; i++) {
        t.v[i] = (vec4s){{(float)x[i], (float)y[i], 0.5f, 1.0f}};
        t.color[i] = (vec3s){{1, 1, 1}};
    }
    ras_pipeline_draw_screen_triangle(p, &t);
    long n = 0;
    for (int py = 0; py < 32; py++)
        for (int px = 0; px < 64; px++)
            n += covered[py * 64 + px] =
                p->fb->depth[ras_fb_sample_index(p->fb, px, py, 0)] != INFINITY;
    *k = p->counters;
    snprintf(refused, size, "%s", p->has_refused ? p->refused.msg : "");
    ras_pipeline_destroy(p);
    return n;
}

/* A wedge whose far corners lie exactly at -2^17 and +2^17 px is drawn
 * exactly: every pixel centre as an exact integer edge test on the 1/256 px
 * grid says (the corners are on that grid, so snapping moves nothing; no
 * centre lies on an edge, so the fill rule does not enter). One float step
 * further out, the pipeline refuses the same wedge, counts it, and its
 * message names the corner and where it is. */
static void test_raster_range_at_limit(void **state) {
    (void)state;
    const double L = RAS_RASTER_MAX_COORD;
    double x[3] = {-L, L, 32.25}, y[3] = {-130.5, 153.75, 22.75};
    int64_t X[3], Y[3];
    for (int i = 0; i < 3; i++) X[i] = (int64_t)(x[i] * 256), Y[i] = (int64_t)(y[i] * 256);
    int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    bool got[64 * 32];
    ras_counters k;
    char refused[sizeof(ras_error)];
    long lit = draw_screen(x, y, got, &k, refused, sizeof refused);
    long expected = 0, wrong = 0;
    for (int py = 0; py < 32; py++)
        for (int px = 0; px < 64; px++) {
            int64_t sx = px * 256 + 128, sy = py * 256 + 128;
            bool in = true;
            for (int e = 0; e < 3; e++) {
                int a = (e + 1) % 3, b = (e + 2) % 3;
                /* |terms| < 2^26 * 2^26: exact in int64 */
                int64_t E = (X[b] - X[a]) * (sy - Y[a]) - (Y[b] - Y[a]) * (sx - X[a]);
                CHECK(E != 0, "test setup: centre (%d, %d) lies on an edge", px, py);
                in = in && (area > 0 ? E > 0 : E < 0);
            }
            expected += in;
            wrong += in != got[py * 64 + px];
        }
    printf("wedge with corners at +-2^17 px: %ld pixels lit, %ld expected, %ld wrong\n", lit,
           expected, wrong);
    CHECK(expected > 0 && expected < 64 * 32, "test setup: %ld of the frame expected", expected);
    CHECK(wrong == 0 && k.triangles_rejected_range == 0 && !*refused,
          "corners exactly at the rasterizer's range +-%.0f px: %ld pixels wrong (%ld lit, "
          "%ld expected), %llu refused; expected exact coverage, nothing refused",
          L, wrong, lit, expected, (unsigned long long)k.triangles_rejected_range);

    for (int corner = 0; corner < 2; corner++) {
        double xs[3] = {x[0], x[1], x[2]};
        xs[corner] = nextafterf((float)xs[corner], corner ? INFINITY : -INFINITY);
        lit = draw_screen(xs, y, got, &k, refused, sizeof refused);
        CHECK(lit == 0 && k.triangles_rejected_range == 1 && k.triangles_rasterized == 0 &&
                  k.samples_tested == 0,
              "corner %d one float step beyond the range (%.9g px): %ld pixels lit, %llu "
              "refused, %llu rasterized; expected it refused and nothing drawn",
              corner, xs[corner], lit, (unsigned long long)k.triangles_rejected_range,
              (unsigned long long)k.triangles_rasterized);
        char where[64];
        snprintf(where, sizeof where, "corner %d at screen (%.9g,", corner,
                 (double)(float)xs[corner]);
        CHECK(strstr(refused, where) && strstr(refused, "131072"),
              "the refusal should name %s and the range 131072, got: \"%s\"", where, refused);
        printf("refused: %s\n", refused);
    }
    /* A NaN is out of every range too (the pipeline rejects it earlier). */
    ras_triangle t = {0};
    t.v[2].y = NAN;
    CHECK(!ras_raster_check_range(&t, NULL), "a NaN corner passed the range check");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clip_scene_tip_near_far_edge),
        cmocka_unit_test(test_clip_scene_tip_closer_near_001),
        cmocka_unit_test(test_clip_scene_found_by_search),
        cmocka_unit_test(test_clip_contract_random_cameras),
        cmocka_unit_test(test_clip_contract_random_clip_space),
        cmocka_unit_test(test_raster_range_at_limit),
    };
    return RAS_RUN_TESTS("clip", tests, NULL, NULL);
}
