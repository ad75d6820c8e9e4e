/* test_hw2.c — cmocka tests for hw2_rasterize (rasterizer.h), run twice:
 * test_hw2_ref against solution/rasterizer.c (must pass) and
 * test_hw2_student against the student's rasterizer.c.
 *
 * Groups (docs/hw2.md has the maths behind each):
 *   inside     inside_triangle: inside/outside, both windings, edges and
 *              vertices, degenerate; plus "a sample on a shared edge belongs
 *              to exactly one triangle", tested through rasterize_triangle
 *   bary       compute_barycentric_2d, and the (x, y) vs (x+0.5, y+0.5) mistake
 *   index      the y-flipped buffer layout, and where rasterize_triangle writes
 *   raster     bounding box clamping, NaN/zero-area, depth, counters
 *   resolve    MSAA/SSAA: partial coverage, no dark seam, per-sample depth,
 *              float averaging
 *   scene      the classic two triangles: depth order, and whole images against
 *              tests/reference/hw2_*.png, which are themselves checked against
 *              hand-computed vertex positions (so a wrong reference cannot
 *              bless itself)
 * Every failure says what was expected, what came, and the likely mistake;
 * coverage failures come with a small ASCII raster.
 *
 * These tests call only the hw2 functions and common/: the scene uses a
 * projection matrix written out here, not the student's hw1, so hw2 is graded
 * on its own.
 */
#include <setjmp.h> /* cmocka needs these before cmocka.h */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ras_call.h"      /* ras_call_watch: what grading records */
#include "ras_test_main.h" /* RAS_RUN_TESTS: one test per process for the grader */
#include "ras_compare.h"
#include "ras_pipeline.h"
#include "rasterizer.h"

#include <math.h>   /* INFINITY, isinf, fabs, tan */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* calloc, free */
#include <string.h> /* memset */

/* Fails with a message that says what was expected and what came. */
#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) fail_msg(__VA_ARGS__);                                                        \
    } while (0)

/* ---- builders -------------------------------------------------------------- */

static ras_triangle tri3(float x0, float y0, float x1, float y1, float x2, float y2) {
    ras_triangle t = {0};
    float xs[3] = {x0, x1, x2}, ys[3] = {y0, y1, y2};
    for (int i = 0; i < 3; i++) {
        t.v[i] = (vec4s){{xs[i], ys[i], 0.5f, 1.0f}};
        t.color[i] = (vec3s){{1, 1, 1}};
    }
    return t;
}

static ras_triangle tri_z(ras_triangle t, float z, vec3s color) {
    for (int i = 0; i < 3; i++) {
        t.v[i].z = z;
        t.color[i] = color;
    }
    return t;
}

static ras_sample_pattern pattern(ras_pattern_kind kind, int count) {
    ras_sample_pattern p;
    ras_error err;
    if (!ras_sample_pattern_make(kind, count, &p, &err)) fail_msg("test setup: %s", err.msg);
    return p;
}

static ras_framebuffer *make_fb(int w, int h, int samples) {
    ras_framebuffer *fb = ras_framebuffer_create(w, h, samples, NULL);
    assert_non_null(fb);
    return fb;
}

static ras_raster_ctx make_ctx(ras_framebuffer *fb, ras_aa_mode aa, ras_sample_pattern pat) {
    return (ras_raster_ctx){.fb = fb, .aa = aa, .pattern = pat};
}

static ras_raster_ctx ctx_none(ras_framebuffer *fb) {
    return make_ctx(fb, RAS_AA_NONE, ras_sample_pattern_center());
}

static const vec3s WHITE = {{1, 1, 1}}, BLACK = {{0, 0, 0}}, RED = {{1, 0, 0}}, BLUE = {{0, 0, 1}};

static bool near3(vec3s a, vec3s b, float tol) {
    return fabsf(a.x - b.x) <= tol && fabsf(a.y - b.y) <= tol && fabsf(a.z - b.z) <= tol;
}

/* Double-precision edge function: exact for the small grid coordinates the
 * tests use. > 0 left of a→b (y up). */
static double edge_exact(double ax, double ay, double bx, double by, double px, double py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

/* The exact (double) screen barycentrics of (px, py) in t: each
 * sub-triangle's edge function over the whole's. */
static void exact_bary(const ras_triangle *t, double px, double py, double b[3]) {
    const vec4s *v = t->v;
    double area = edge_exact(v[0].x, v[0].y, v[1].x, v[1].y, v[2].x, v[2].y);
    b[0] = edge_exact(v[1].x, v[1].y, v[2].x, v[2].y, px, py) / area;
    b[1] = edge_exact(v[2].x, v[2].y, v[0].x, v[0].y, px, py) / area;
    b[2] = edge_exact(v[0].x, v[0].y, v[1].x, v[1].y, px, py) / area;
}

/* ---- what the student's functions did: evidence for the diagnoses ----------- */

/* The closed triangle (either winding), decided exactly: the hypotheses below
 * are "the student's answers are what this gives at another point". */
static bool closed_inside_exact(const ras_triangle *t, double px, double py) {
    const vec4s *v = t->v;
    double area = edge_exact(v[0].x, v[0].y, v[1].x, v[1].y, v[2].x, v[2].y);
    if (!(area != 0)) return false;
    double e[3] = {edge_exact(v[1].x, v[1].y, v[2].x, v[2].y, px, py),
                   edge_exact(v[2].x, v[2].y, v[0].x, v[0].y, px, py),
                   edge_exact(v[0].x, v[0].y, v[1].x, v[1].y, px, py)};
    for (int i = 0; i < 3; i++)
        if ((area > 0 ? e[i] : -e[i]) < 0) return false;
    return true;
}

/* Whether (px, py) lies exactly on one of t's edge lines. */
static bool on_an_edge(const ras_triangle *t, double px, double py) {
    const vec4s *v = t->v;
    return edge_exact(v[1].x, v[1].y, v[2].x, v[2].y, px, py) == 0 ||
           edge_exact(v[2].x, v[2].y, v[0].x, v[0].y, px, py) == 0 ||
           edge_exact(v[0].x, v[0].y, v[1].x, v[1].y, px, py) == 0;
}

/* The closed triangle with each edge function truncated to an int first
 * (`int e = ...`): values in (-1, 1) px² become 0, "on the edge". */
static bool truncated_inside_exact(const ras_triangle *t, double px, double py) {
    const vec4s *v = t->v;
    double area = edge_exact(v[0].x, v[0].y, v[1].x, v[1].y, v[2].x, v[2].y);
    if (!(area != 0)) return false;
    double e[3] = {trunc(edge_exact(v[1].x, v[1].y, v[2].x, v[2].y, px, py)),
                   trunc(edge_exact(v[2].x, v[2].y, v[0].x, v[0].y, px, py)),
                   trunc(edge_exact(v[0].x, v[0].y, v[1].x, v[1].y, px, py))};
    for (int i = 0; i < 3; i++)
        if ((area > 0 ? e[i] : -e[i]) < 0) return false;
    return true;
}

/* The course framework's insideTriangle(int x, int y, ...), in the words
 * docs/hw2.md's "Coming from the GAMES101 framework" uses. */
#define INT_SIGNATURE_HABIT                                                                        \
    "insideTriangle taking ints (the course framework's insideTriangle(int x, int y, ...) "       \
    "habit): every sample is tested at its pixel's corner, its position truncated to int, "      \
    "while the barycentrics still use the float position; inside_triangle takes float x, y: "   \
    "pass the sample's float position (x + offset.x, y + offset.y) and keep it float"

#define EDGE_TRUNCATED                                                                             \
    "edge functions truncated to int (`int e = ...`): an edge function between -1 and 1 px² "    \
    "becomes 0, \"on the edge\", so samples up to 1/(edge length) px outside count as inside; "  \
    "keep the edge functions in float (or double)"

#define ADDITIVE_MSAA                                                                              \
    "an ADDITIVE resolve — one colour per pixel with colour x covered / samples added in, so "   \
    "a later triangle adds to what is there instead of replacing it on the samples it wins; "   \
    "write the colour to each sample that passes the depth test (=, not +=) and let "          \
    "resolve_pixel average them"

/* Probes the student's inside_triangle where truncating the point to its
 * pixel corner changes the answer both ways: true when every answer is the
 * corner's. (In grading these calls are recorded like the test's own.) */
static bool inside_answers_at_corner(void) {
    ras_triangle t[2] = {tri3(0.5f, 0.5f, 3.5f, 0.5f, 0.5f, 3.5f),
                         tri3(0.5f, 0.5f, 0.5f, 3.5f, 3.5f, 0.5f)};
    const float pts[][2] = {{0.75f, 0.75f}, {1.5f, 1.25f}, {2.75f, 1.5f}, {3.25f, 0.75f},
                            {1.25f, 2.5f},  {3.9f, 0.9f}};
    bool differs = false;
    for (int w = 0; w < 2; w++)
        for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++) {
            double cx = trunc(pts[i][0]), cy = trunc(pts[i][1]);
            bool corner = closed_inside_exact(&t[w], cx, cy);
            differs = differs || corner != closed_inside_exact(&t[w], pts[i][0], pts[i][1]);
            if (inside_triangle(pts[i][0], pts[i][1], &t[w]) != corner) return false;
        }
    return differs;
}

/* Probes compute_barycentric_2d at the vertices of one triangle in both
 * windings: true when the counter-clockwise one is right and the clockwise
 * one has beta and gamma swapped. */
static bool bary_swapped_for_clockwise(void) {
    ras_triangle ccw = tri3(1, 1, 9, 1, 1, 9), cw = tri3(1, 1, 1, 9, 9, 1);
    for (int i = 0; i < 3; i++) {
        vec3s a = {{0, 0, 0}}, b = {{0, 0, 0}};
        compute_barycentric_2d(ccw.v[i].x, ccw.v[i].y, &ccw, &a);
        compute_barycentric_2d(cw.v[i].x, cw.v[i].y, &cw, &b);
        vec3s want = {{i == 0, i == 1, i == 2}}, swapped = {{want.x, want.z, want.y}};
        if (!near3(a, want, 1e-5f) || !near3(b, swapped, 1e-5f)) return false;
    }
    return true;
}

/* Why a rasterizer draws nothing, from one triangle drawn here with counters
 * and inside_triangle asked about a point well inside it; NULL when neither
 * tells. */
static const char *why_nothing_drawn(void) {
    ras_framebuffer *fb = make_fb(8, 8, 1);
    ras_counters k = {0};
    ras_raster_ctx ctx = ctx_none(fb);
    ctx.counters = &k;
    ras_triangle t = tri_z(tri3(1, 1, 7, 1, 1, 7), 0.5f, WHITE);
    rasterize_triangle(&t, &ctx);
    int drawn = 0;
    for (int i = 0; i < 64; i++)
        drawn += !isinf(fb->depth[i]);
    ras_framebuffer_destroy(fb);
    if (drawn) return NULL;
    if (k.samples_covered > 0 && k.depth_tests_passed == 0)
        return "nothing is drawn: a triangle drawn with counters covered samples and passed no "
               "depth test, so the depth test never passes — with the buffer cleared to +INF, "
               "`z > depth[i]` is the test reversed (smaller is closer: draw when z < depth[i]).";
    if (inside_triangle(2.5f, 2.5f, &t))
        return "nothing is drawn, although inside_triangle accepts (2.5, 2.5) inside the triangle "
               "(1,1),(7,1),(1,7): the depth test never passes (against +INF, `z > depth[i]` is "
               "reversed: draw when z < depth[i]), or depth and colour are not written.";
    return NULL;
}

#define BARY_SWAPPED_CW                                                                            \
    "barycentrics with beta and gamma swapped for CLOCKWISE triangles only "                    \
    "(compute_barycentric_2d is right on a counter-clockwise triangle and returns (a, g, b) on "  \
    "a clockwise one): alpha, beta, gamma are E_12/A, E_20/A, E_01/A in either winding — the "   \
    "sign of A takes care of the winding, swap nothing"

/* ---- ASCII rasters ----------------------------------------------------------- */

/* One character per pixel, top row first: counts[pixel] as '.', '#', '2'..'9';
 * expected[pixel] (when not NULL) marks a missing pixel 'o' and an extra 'x'.
 * counts/expected are indexed by screen (x, y) as y * w + x. */
static void ascii_raster(const int *counts, const int *expected, int w, int h, char *buf,
                         size_t size) {
    size_t n = 0;
    for (int y = h - 1; y >= 0 && n + (size_t)w + 2 < size; y--) {
        for (int x = 0; x < w; x++) {
            int c = counts[y * w + x], e = expected ? expected[y * w + x] : c;
            char ch = c == 0 ? '.' : c == 1 ? '#' : (char)('0' + (c > 9 ? 9 : c));
            if (e == 1 && c == 0) ch = 'o';
            if (e == 0 && c == 1) ch = 'x';
            buf[n++] = ch;
        }
        buf[n++] = '\n';
    }
    buf[n] = '\0';
}
#define ASCII_LEGEND                                                                               \
    "('#' once, '.' never, '2'.. several times, 'o' missing, 'x' extra; top row first)"

/* ---- 1. inside_triangle -------------------------------------------------------- */

/* Points clearly inside and outside, for both windings. */
static void test_inside_basic_both_windings(void **state) {
    (void)state;
    ras_triangle ccw = tri3(1, 1, 9, 1, 1, 9), cw = tri3(1, 1, 1, 9, 9, 1);
    const struct {
        float x, y;
        bool in;
    } pts[] = {{2, 2, true},  {3.5f, 4.25f, true}, {1.5f, 7, true}, {8, 8, false},
               {0, 0, false}, {5, 0.5f, false},    {-3, 4, false},  {5.5f, 5.5f, false}};
    enum { N = sizeof pts / sizeof pts[0] };
    bool a[N], b[N], at_corner = true;
    for (size_t i = 0; i < N; i++) {
        a[i] = inside_triangle(pts[i].x, pts[i].y, &ccw);
        b[i] = inside_triangle(pts[i].x, pts[i].y, &cw);
        /* every answer the closed test's at the point truncated to int */
        bool corner = closed_inside_exact(&ccw, trunc(pts[i].x), trunc(pts[i].y));
        at_corner = at_corner && a[i] == corner && b[i] == corner;
    }
    for (size_t i = 0; i < N; i++) {
        CHECK(a[i] == pts[i].in,
              "inside_triangle(%g, %g) on the counter-clockwise triangle (1,1),(9,1),(1,9): "
              "expected %s, got %s. Likely mistake: %s",
              pts[i].x, pts[i].y, pts[i].in ? "inside" : "outside", a[i] ? "inside" : "outside",
              at_corner ? "every answer of this test is the one for the point truncated to int "
                          "(its pixel corner): " INT_SIGNATURE_HABIT "."
                        : "the edge function's sign (E = (b-a) x (p-a) is > 0 LEFT of a->b with "
                          "y up), or the wrong vertices paired.");
        CHECK(b[i] == pts[i].in,
              "inside_triangle(%g, %g) on the CLOCKWISE triangle (1,1),(1,9),(9,1): expected %s, "
              "got %s. Likely mistake: %s",
              pts[i].x, pts[i].y, pts[i].in ? "inside" : "outside", b[i] ? "inside" : "outside",
              at_corner ? "every answer of this test is the one for the point truncated to int "
                          "(its pixel corner): " INT_SIGNATURE_HABIT "."
                        : "only one winding handled; inside means all three edge functions have "
                          "the same sign as the triangle's area (either sign).");
    }
}

/* The closed triangle: points exactly on an edge or a vertex are inside. */
static void test_inside_on_edges_and_vertices(void **state) {
    (void)state;
    ras_triangle t[2] = {tri3(1, 1, 9, 1, 1, 9), tri3(1, 1, 1, 9, 9, 1)};
    const float pts[][2] = {{1, 1}, {9, 1}, {1, 9}, {5, 1}, {1, 5}, {5, 5}, {3, 7}, {8.5f, 1}};
    for (int w = 0; w < 2; w++)
        for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++)
            CHECK(inside_triangle(pts[i][0], pts[i][1], &t[w]),
                  "inside_triangle(%g, %g) on the %s triangle (1,1),(9,1),(1,9): expected "
                  "inside (the point is exactly on an edge or a vertex, E == 0), got outside. "
                  "Likely mistake: a strict test (E > 0); inside_triangle is the closed "
                  "triangle (the top-left rule for shared edges lives in rasterize_triangle).",
                  pts[i][0], pts[i][1], w ? "clockwise" : "counter-clockwise");
    /* And just outside each edge. */
    const float out[][2] = {{5, 0.99f}, {0.99f, 5}, {5.01f, 5.01f}};
    enum { NOUT = sizeof out / sizeof out[0] };
    bool got[NOUT];
    for (size_t i = 0; i < NOUT; i++)
        got[i] = inside_triangle(out[i][0], out[i][1], &t[0]);
    for (size_t i = 0; i < NOUT; i++) {
        if (!got[i]) continue;
        /* Which rule explains every answer, the probes' too: 0.1 px below
         * the edge y = 1 (E = -0.8) and 0.15 px below (E = -1.2) tell an
         * int edge function from a tolerance; the corner from both. */
        const float probe[][2] = {{5, 0.9f}, {5, 0.85f}, {2.5f, 6.75f}, {6.5f, 3.75f}};
        bool at_corner = true, truncated = true;
        for (size_t k = 0; k < NOUT + 4; k++) {
            const float *q = k < NOUT ? out[k] : probe[k - NOUT];
            bool in = k < NOUT ? got[k] : inside_triangle(q[0], q[1], &t[0]);
            at_corner = at_corner && in == closed_inside_exact(&t[0], trunc(q[0]), trunc(q[1]));
            truncated = truncated && in == truncated_inside_exact(&t[0], q[0], q[1]);
        }
        fail_msg("inside_triangle(%g, %g): expected outside (0.01 px beyond an edge), got "
                 "inside. Likely mistake: %s",
                 out[i][0], out[i][1],
                 at_corner ? "every answer here is the one for the point truncated to int (its "
                             "pixel corner): " INT_SIGNATURE_HABIT "."
                 : truncated
                     ? "every answer here, (5, 0.9) inside and (5, 0.85) outside too, is what "
                       "an int edge function gives: " EDGE_TRUNCATED "."
                     : "a tolerance in the test (inside is E >= 0 exactly), or an edge "
                       "function built from the wrong pair of vertices.");
    }
}

/* A zero-area triangle contains nothing, not even points on its line. */
static void test_inside_degenerate_is_empty(void **state) {
    (void)state;
    ras_triangle line = tri3(0, 0, 4, 4, 8, 8), point = tri3(3, 3, 3, 3, 3, 3);
    ras_triangle nan_tri = tri3(0, 0, NAN, 4, 8, 0);
    CHECK(!inside_triangle(2, 2, &line),
          "inside_triangle(2, 2) on the degenerate triangle (0,0),(4,4),(8,8): expected false, "
          "got true. Likely mistake: no zero-area check — on the triangle's line all three "
          "edge functions are 0, so 'all >= 0' says inside.");
    CHECK(!inside_triangle(3, 3, &point),
          "inside_triangle(3, 3) on a triangle collapsed to the point (3,3): expected false, "
          "got true. Likely mistake: no zero-area check.");
    CHECK(!inside_triangle(1, 1, &nan_tri),
          "inside_triangle on a triangle with a NaN vertex: expected false, got true. Likely "
          "mistake: 'not < 0' instead of '>= 0' (every comparison with NaN is false).");
    /* "false" everywhere is the stub's placeholder: this test counts only
     * once a point well inside a proper triangle is inside (either winding) */
    ras_triangle ccw = tri3(0, 0, 8, 0, 0, 8), cw = tri3(0, 0, 0, 8, 8, 0);
    CHECK(inside_triangle(2.5f, 2.5f, &ccw) || inside_triangle(2.5f, 2.5f, &cw),
          "inside_triangle(2.5, 2.5) on the proper triangle (0,0),(8,0),(0,8), in either "
          "winding: expected true, got false both times. Returning false for every point is "
          "the stub's placeholder, right for degenerate triangles only, so this test counts "
          "once inside_triangle accepts a point inside. Likely mistake: inside_triangle is not "
          "written yet (TODO(hw2) 1-2).");
}

/* Draws each triangle of `tris` into its own cleared buffer and counts, per
 * sample, how many triangles covered it (depth left +INF = not covered). */
static void count_coverage(const ras_triangle *tris, int n, int w, int h, ras_aa_mode aa,
                           ras_sample_pattern pat, int *counts) {
    ras_framebuffer *fb = make_fb(w, h, pat.count);
    ras_raster_ctx ctx = make_ctx(fb, aa, pat);
    memset(counts, 0, sizeof(int) * (size_t)(w * h * pat.count));
    for (int i = 0; i < n; i++) {
        ras_framebuffer_clear(fb, BLACK);
        rasterize_triangle(&tris[i], &ctx);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                for (int s = 0; s < pat.count; s++)
                    if (!isinf(fb->depth[ras_fb_sample_index(fb, x, y, s)]))
                        counts[(y * w + x) * pat.count + s]++;
    }
    ras_framebuffer_destroy(fb);
}

/* What a sample at (px, py) should get: 1 covered exactly once, 0 never,
 * -1 at most once (on the outer boundary, where the fill rule decides). */
typedef int (*expect_fn)(double px, double py, const void *user);

typedef struct fan {
    double cx, cy; /* strictly inside the polygon */
    const double (*pts)[2];
    int n;
} fan;

/* A sample in a closed fan triangle and strictly inside its outer edge is
 * interior to the union (the other two edges are shared or meet at the
 * centre); exact in double for the grid coordinates used. */
static int expect_fan(double px, double py, const void *user) {
    const fan *f = user;
    int expect = 0;
    for (int i = 0; i < f->n && expect != 1; i++) {
        const double *a = f->pts[i], *b = f->pts[(i + 1) % f->n];
        double e_out = edge_exact(a[0], a[1], b[0], b[1], px, py);
        double e1 = edge_exact(f->cx, f->cy, a[0], a[1], px, py);
        double e2 = edge_exact(b[0], b[1], f->cx, f->cy, px, py);
        if (edge_exact(a[0], a[1], b[0], b[1], f->cx, f->cy) < 0) {
            e_out = -e_out;
            e1 = -e1;
            e2 = -e2;
        }
        if (e_out >= 0 && e1 >= 0 && e2 >= 0) expect = e_out > 0 ? 1 : -1;
    }
    return expect;
}

/* The open square (lo, hi)²: once inside, at most once on its border. */
static int expect_square(double px, double py, const void *user) {
    const double *lohi = user;
    if (px > lohi[0] && px < lohi[1] && py > lohi[0] && py < lohi[1]) return 1;
    if (px >= lohi[0] && px <= lohi[1] && py >= lohi[0] && py <= lohi[1]) return -1;
    return 0;
}

/* What a failing coverage shows, decided from the counts and from the
 * student's own functions called on the case's positions. */
typedef struct coverage_evidence {
    bool nothing_drawn, depth_never_passed, inside_accepts; /* no sample written at all */
    bool at_corner;       /* every count the closed test's at the pixel corner */
    bool truncated;       /* every extra sample inside an int-truncated edge function */
    bool bary_swapped_cw; /* compute_barycentric_2d probed: CW triangles permuted */
} coverage_evidence;

static coverage_evidence coverage_hypotheses(const ras_triangle *tris, int ntris, int w, int h,
                                             ras_sample_pattern pat, const int *counts,
                                             expect_fn expect, const void *user) {
    coverage_evidence ev = {.nothing_drawn = true, .at_corner = true, .truncated = true};
    int S = pat.count;
    bool explained = false;
    double in_x = NAN, in_y = NAN;
    const ras_triangle *in_t = NULL;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int s = 0; s < S; s++) {
                double sx = x + pat.offsets[s].x, sy = y + pat.offsets[s].y;
                int got = counts[(y * w + x) * S + s], e = expect(sx, sy, user);
                int corner = 0, exact = 0, trunc_in = 0;
                bool on_edge = false; /* of a triangle: the top-left rule may drop it */
                for (int i = 0; i < ntris; i++) {
                    corner += closed_inside_exact(&tris[i], x, y);
                    on_edge = on_edge || (closed_inside_exact(&tris[i], x, y) &&
                                          on_an_edge(&tris[i], sx, sy));
                    bool in = closed_inside_exact(&tris[i], sx, sy);
                    exact += in;
                    trunc_in += truncated_inside_exact(&tris[i], sx, sy) && !in;
                    if (e == 1 && in && !in_t) in_t = &tris[i], in_x = sx, in_y = sy;
                }
                ev.nothing_drawn = ev.nothing_drawn && got == 0;
                /* at the corner: never where it is outside, at least once where
                 * it is inside, at most as often as it is (the top-left rule may
                 * still drop one of two on a shared edge) */
                if (corner == 0 ? got != 0 : ((got < 1 && !on_edge) || got > corner))
                    ev.at_corner = false;
                bool ok = got <= 1 && (e != 1 || got == 1) && (e != 0 || got == 0);
                if (ok) continue;
                /* a wrong sample: extra coverage only an int edge function
                 * gives, or a shared edge's sample counted by both */
                if (got > 0 && trunc_in > 0 && got <= exact + trunc_in) explained = true;
                else if (!(got == exact && got > 1)) ev.truncated = false;
            }
    ev.truncated = ev.truncated && explained;
    if (ev.nothing_drawn) {
        ev.at_corner = ev.truncated = false;
        if (in_t) {
            ras_framebuffer *fb = make_fb(w, h, S);
            ras_counters k = {0};
            ras_raster_ctx ctx = make_ctx(fb, S > 1 ? RAS_AA_MSAA : RAS_AA_NONE, pat);
            ctx.counters = &k;
            rasterize_triangle(in_t, &ctx);
            ev.depth_never_passed = k.samples_covered > 0 && k.depth_tests_passed == 0;
            ras_framebuffer_destroy(fb);
            ev.inside_accepts = inside_triangle((float)in_x, (float)in_y, in_t);
        }
    }
    if (!ev.nothing_drawn && !ev.at_corner) ev.bary_swapped_cw = bary_swapped_for_clockwise();
    return ev;
}

/* Draws the triangles one by one and checks every sample's count against
 * `expect`; on failure prints the coverage per pixel as ASCII. */
static void check_exactly_once(const char *what, const ras_triangle *tris, int ntris, int w, int h,
                               ras_aa_mode aa, ras_sample_pattern pat, expect_fn expect,
                               const void *user) {
    int S = pat.count;
    int *counts = calloc((size_t)(w * h * S), sizeof *counts);
    int *px_count = calloc((size_t)(w * h), sizeof *px_count);
    int *px_expect = calloc((size_t)(w * h), sizeof *px_expect);
    assert_non_null(counts);
    assert_non_null(px_count);
    assert_non_null(px_expect);
    count_coverage(tris, ntris, w, h, aa, pat, counts);
    int bad_x = -1, bad_y = -1, bad_s = -1, bad_got = 0, bad_exp = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int shown = -1, any = 0;
            for (int s = 0; s < S; s++) {
                int e = expect(x + pat.offsets[s].x, y + pat.offsets[s].y, user);
                int got = counts[(y * w + x) * S + s];
                bool ok = got <= 1 && (e != 1 || got == 1) && (e != 0 || got == 0);
                if (!ok && bad_x < 0) {
                    bad_x = x;
                    bad_y = y;
                    bad_s = s;
                    bad_got = got;
                    bad_exp = e;
                }
                if (!ok && shown < 0) shown = got;
                if (e == 1) px_expect[y * w + x] = 1;
                any = got > any ? got : any;
            }
            /* A pixel shows its first wrong sample, else its largest count. */
            px_count[y * w + x] = shown >= 0 ? shown : any;
            if (shown < 0) px_expect[y * w + x] = px_count[y * w + x];
        }
    if (bad_x >= 0) {
        /* Two mistakes of the loop, not of the edge rule, recognised from the
         * whole pattern: every sample stored upside down (the y-flip), or the
         * only misses in the last column or row of their triangle's box. */
        bool flipped = true, box_edge = true, any_miss = false, any_extra = false;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                for (int s = 0; s < S; s++) {
                    double sx = x + pat.offsets[s].x, sy = y + pat.offsets[s].y;
                    int e = expect(sx, sy, user), got = counts[(y * w + x) * S + s];
                    int mirrored = counts[((h - 1 - y) * w + x) * S + s];
                    if ((e == 1 && mirrored != 1) || (e == 0 && mirrored != 0)) flipped = false;
                    if (e == 0 && got > 0) any_extra = true;
                    if (e != 1 || got != 0) continue;
                    any_miss = true;
                    bool at_edge = false;
                    for (int i = 0; i < ntris && !at_edge; i++) {
                        const vec4s *v = tris[i].v;
                        double e0 = edge_exact(v[0].x, v[0].y, v[1].x, v[1].y, sx, sy),
                               e1 = edge_exact(v[1].x, v[1].y, v[2].x, v[2].y, sx, sy),
                               e2 = edge_exact(v[2].x, v[2].y, v[0].x, v[0].y, sx, sy);
                        bool inside =
                            (e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0);
                        double mx = fmax(fmax(v[0].x, v[1].x), v[2].x),
                               my = fmax(fmax(v[0].y, v[1].y), v[2].y);
                        at_edge = inside && (x == (int)floor(mx) || y == (int)floor(my));
                    }
                    box_edge = box_edge && at_edge;
                }
        /* Samples taken at the ordered 2x2 grid's points whatever the
         * pattern: the coverage is what the grid's positions would give. */
        bool grid = S == 4;
        if (grid) {
            ras_sample_pattern ordered = pattern(RAS_PATTERN_ORDERED, 4);
            bool same_pattern = true;
            for (int k = 0; k < 4; k++)
                same_pattern = same_pattern && ordered.offsets[k].x == pat.offsets[k].x &&
                               ordered.offsets[k].y == pat.offsets[k].y;
            grid = !same_pattern;
            for (int y = 0; y < h && grid; y++)
                for (int x = 0; x < w && grid; x++)
                    for (int k = 0; k < 4 && grid; k++) {
                        int e = expect(x + ordered.offsets[k].x, y + ordered.offsets[k].y, user);
                        int got = counts[(y * w + x) * S + k];
                        if ((e == 1 && got != 1) || (e == 0 && got != 0)) grid = false;
                    }
        }
        coverage_evidence ev = coverage_hypotheses(tris, ntris, w, h, pat, counts, expect, user);
        const char *loop = NULL;
        if (ev.nothing_drawn)
            loop = ev.depth_never_passed
                       ? "nothing was drawn, and your counters say samples were covered but no "
                         "depth test passed: the depth test never passes — with the buffer "
                         "cleared to +INF, `z > depth[i]` is the test reversed (smaller is "
                         "closer: draw when z < depth[i])"
                   : ev.inside_accepts
                       ? "nothing was drawn, although inside_triangle accepts a sample inside "
                         "(called here on its position): the depth test never passes (with the "
                         "buffer cleared to +INF, `z > depth[i]` is the test reversed: draw "
                         "when z < depth[i]), or depth and colour are not written"
                       : "nothing was drawn, and inside_triangle rejects a sample well inside "
                         "(called here on its position): see the inside_triangle tests";
        else if (ev.at_corner)
            loop = "every sample's coverage is what its pixel's corner (x, y) gets: " INT_SIGNATURE_HABIT;
        else if (ev.bary_swapped_cw)
            loop = "the top-left rule read from barycentrics that are wrong on clockwise "
                   "triangles: " BARY_SWAPPED_CW;
        else if (ev.truncated)
            loop = "every wrongly covered sample lies within 1 px² (edge function) outside a "
                   "triangle, where an int edge function is 0: " EDGE_TRUNCATED;
        else if (grid)
            loop = "the coverage is what the ordered 2x2 grid's points (0.25, 0.75) give, but "
                   "this pattern's samples are elsewhere: sample positions written into the "
                   "rasterizer — read ctx->pattern.offsets[k] for k < ctx->pattern.count";
        else if (flipped)
            loop = "the whole coverage is upside down: the rows are stored without the y-flip "
                   "(ras_fb_sample_index flips for you: pass it the screen y, not height-1-y, "
                   "and do not flip again)";
        else if (any_miss && !any_extra && box_edge)
            loop = "every missed sample is in the last column or row of its triangle's bounding "
                   "box: the bounding box's maximum used as an exclusive loop bound (x < x_max) "
                   "— the box holds its maximum, loop with <=";
        char art[2600];
        ascii_raster(px_count, px_expect, w, h, art, sizeof art);
        fail_msg("%s: sample %d of pixel (%d, %d) at (%g, %g) was covered %d times; expected %s. "
                 "Likely mistake: %s\nper pixel %s\n%s",
                 what, bad_s, bad_x, bad_y, bad_x + pat.offsets[bad_s].x,
                 bad_y + pat.offsets[bad_s].y, bad_got,
                 bad_exp == 1   ? "exactly once (it is inside the shape)"
                 : bad_exp == 0 ? "never (it is outside the shape)"
                                : "at most once",
                 loop          ? loop
                 : bad_got > 1 ? "a sample exactly on a shared edge counted by both triangles — "
                                 "apply the top-left rule (docs/hw2.md 3.3): E == 0 counts only "
                                 "on a top or left edge"
                               : "a sample exactly on a shared edge rejected by both triangles "
                                 "(strict > 0 on every edge), or a winding handled wrongly",
                 ASCII_LEGEND, art);
    }
    free(counts);
    free(px_count);
    free(px_expect);
}

/* The fan's triangles, alternating the winding: the rule must not depend on it. */
static int fan_triangles(const fan *f, ras_triangle *tris) {
    for (int i = 0; i < f->n; i++) {
        const double *a = f->pts[i], *b = f->pts[(i + 1) % f->n];
        float cx = (float)f->cx, cy = (float)f->cy;
        tris[i] = i % 2 ? tri3(cx, cy, (float)a[0], (float)a[1], (float)b[0], (float)b[1])
                        : tri3(cx, cy, (float)b[0], (float)b[1], (float)a[0], (float)a[1]);
    }
    return f->n;
}

/* Shared edges through pixel centres. The float inside_triangle cannot decide
 * who owns a point on a shared edge (the closed test says both do, a strict
 * one says neither), so the exactly-once promise is tested through
 * rasterize_triangle, which applies the top-left rule. */
static void test_inside_shared_edge_exactly_once(void **state) {
    (void)state;
    /* A square cut along its diagonal: the centres (x+0.5, x+0.5) are on it. */
    const double lohi[2] = {0.5, 8.5};
    ras_triangle sq[4] = {tri3(0.5f, 0.5f, 8.5f, 0.5f, 8.5f, 8.5f),
                          tri3(0.5f, 0.5f, 8.5f, 8.5f, 0.5f, 8.5f),
                          tri3(0.5f, 0.5f, 8.5f, 8.5f, 8.5f, 0.5f), /* both, clockwise */
                          tri3(0.5f, 0.5f, 0.5f, 8.5f, 8.5f, 8.5f)};
    check_exactly_once("square (0.5,0.5)-(8.5,8.5) cut along its diagonal", sq, 2, 10, 10,
                       RAS_AA_NONE, ras_sample_pattern_center(), expect_square, lohi);
    check_exactly_once("the same square, both triangles clockwise", sq + 2, 2, 10, 10, RAS_AA_NONE,
                       ras_sample_pattern_center(), expect_square, lohi);
    /* Four triangles meeting at a pixel centre: horizontal, vertical and
     * diagonal shared edges through sample points. */
    const double diamond[4][2] = {{8.5, 4.5}, {4.5, 8.5}, {0.5, 4.5}, {4.5, 0.5}};
    fan f = {4.5, 4.5, diamond, 4};
    ras_triangle tris[4];
    check_exactly_once("diamond fan around (4.5, 4.5)", tris, fan_triangles(&f, tris), 10, 10,
                       RAS_AA_NONE, ras_sample_pattern_center(), expect_fan, &f);
}

/* A 12-triangle fan with vertices on a quarter-pixel grid, 4x standard and
 * 4x4 ordered samples: many samples sit exactly on shared edges. Float edge
 * functions are exact at these coordinates, so a correct float top-left rule
 * passes as well as the fixed-point reference. */
static void test_inside_fan_watertight(void **state) {
    (void)state;
    double pts[12][2];
    for (int i = 0; i < 12; i++) {
        double a = 2 * RAS_PI * i / 12;
        pts[i][0] = floor((8.25 + 7 * cos(a)) * 4 + 0.5) / 4;
        pts[i][1] = floor((7.75 + 7 * sin(a)) * 4 + 0.5) / 4;
    }
    fan f = {8.25, 7.75, (const double(*)[2])pts, 12};
    ras_triangle tris[12];
    int n = fan_triangles(&f, tris);
    check_exactly_once("12-triangle fan, 1 sample", tris, n, 17, 16, RAS_AA_NONE,
                       ras_sample_pattern_center(), expect_fan, &f);
    check_exactly_once("12-triangle fan, 4x standard MSAA", tris, n, 17, 16, RAS_AA_MSAA,
                       pattern(RAS_PATTERN_STANDARD, 4), expect_fan, &f);
    check_exactly_once("12-triangle fan, 16x ordered SSAA", tris, n, 17, 16, RAS_AA_SSAA,
                       pattern(RAS_PATTERN_ORDERED, 16), expect_fan, &f);
}

/* Realistic screen coordinates: small triangles hundreds of pixels from the
 * origin, as a 700x700 frame has them. Barycentrics and depth against double.
 * The course's expanded form x*(y1-y2) + (x2-x1)*y + x1*y2 - x2*y1 subtracts
 * products of ~3.6e5 to get areas of ~30: about 1e-3 wrong, which is more than
 * the depth between a torus's front and back (7.8e-4 in z01). */
static double bary_error_near(const float c0[6], float dx, float dy, double *wx, double *wy,
                              double worst_so_far);
static void precision_depth_check(const float c[6]);

static void test_bary_precision_at_600px(void **state) {
    (void)state;
    const float tris[][6] = {{612.3f, 587.1f, 617.9f, 588.4f, 613.2f, 594.6f},
                             {401.7f, 655.2f, 405.1f, 652.9f, 404.4f, 659.8f},
                             {650.2f, 640.6f, 652.9f, 640.9f, 651.0f, 645.3f}};
    double worst = 0, wx = 0, wy = 0;
    size_t wi = 0;
    for (size_t i = 0; i < sizeof tris / sizeof tris[0]; i++) {
        double err = bary_error_near(tris[i], 0, 0, &wx, &wy, worst);
        if (err > worst) worst = err, wi = i;
    }
    /* Cancellation grows with the distance from the origin; a formula that
     * subtracts a vertex first does not care where the triangle is. The
     * worst triangle moved by whole pixels to the origin (exact in float)
     * tells the two apart from the values returned. */
    double near_origin =
        worst > 1e-4 ? bary_error_near(tris[wi], floorf(tris[wi][0]), floorf(tris[wi][1]), NULL,
                                       NULL, 0)
                     : 0;
    CHECK(worst <= 1e-4,
          "compute_barycentric_2d on small triangles near screen (600, 600): off by %.2g at "
          "(%.1f, %.1f) against double (at most 1e-4 expected; a float edge function is off "
          "by about 1e-6 there); the same triangle moved to the origin: off by %.2g. Likely "
          "mistake: %s",
          worst, wx, wy, near_origin,
          near_origin <= 1e-5
              ? "cancellation — right near the origin, wrong at 600 px: the expanded formula "
                "x*(y1-y2) + (x2-x1)*y + x1*y2 - x2*y1, whose products near 3.6e5 cancel to "
                "areas near 30 and lose about 1e-3 (in hw3 back faces then win the depth test: "
                "speckle). Write it as docs/hw2.md does, a vertex taken away before the products: "
                "((x-x0)*(y1-y0) - (x1-x0)*(y-y0)) / area."
              : "wrong near the origin too, so not a rounding matter: the formula itself (see "
                "test_bary_vertices_centroid_sum and test_bary_outside_is_negative).");
    precision_depth_check(tris[0]);
}

/* The largest error of compute_barycentric_2d over the pixel centres around
 * triangle c moved by (-dx, -dy), against double; where, if asked. */
static double bary_error_near(const float c0[6], float dx, float dy, double *wx, double *wy,
                              double worst_so_far) {
    float c[6];
    for (int k = 0; k < 6; k++)
        c[k] = c0[k] - (k % 2 ? dy : dx);
    double worst = 0;
    {
        ras_triangle t = tri3(c[0], c[1], c[2], c[3], c[4], c[5]);
        double area = edge_exact(c[0], c[1], c[2], c[3], c[4], c[5]);
        for (int py = (int)floorf(c0[1]) - 1; py < (int)floorf(c0[5]) + 2; py++)
            for (int px = (int)floorf(c0[0]) - 2; px < (int)floorf(c0[2]) + 2; px++) {
                double x = px + 0.5 - dx, y = py + 0.5 - dy;
                double want[3] = {edge_exact(c[2], c[3], c[4], c[5], x, y) / area,
                                  edge_exact(c[4], c[5], c[0], c[1], x, y) / area,
                                  edge_exact(c[0], c[1], c[2], c[3], x, y) / area};
                vec3s got = {{0, 0, 0}};
                if (!compute_barycentric_2d((float)x, (float)y, &t, &got)) continue;
                double err =
                    fmax(fabs(got.x - want[0]), fmax(fabs(got.y - want[1]), fabs(got.z - want[2])));
                if (err > worst) {
                    worst = err;
                    if (wx && err > worst_so_far) *wx = x + dx, *wy = y + dy;
                }
            }
    }
    return worst;
}

/* The same through the rasterizer: the depth it stores. */
static void precision_depth_check(const float c[6]) {
    ras_framebuffer *fb = make_fb(700, 700, 1);
    ras_raster_ctx ctx = ctx_none(fb);
    const float z[3] = {0.3f, 0.9f, 0.5f};
    ras_triangle t = tri3(c[0], c[1], c[2], c[3], c[4], c[5]);
    for (int k = 0; k < 3; k++)
        t.v[k].z = z[k];
    rasterize_triangle(&t, &ctx);
    /* Against the plane through the vertices as given and through the
     * vertices snapped to 1/256 px (a fixed-point rasterizer's): either is
     * right, and both are far closer than the cancellation's error. */
    double snapped[6], dworst = 0;
    for (int k = 0; k < 6; k++)
        snapped[k] = round((double)c[k] * 256) / 256;
    int seen = 0, negative = 0, at_corner = 0;
    for (int py = 580; py < 600; py++)
        for (int px = 605; px < 625; px++) {
            float d = fb->depth[ras_fb_sample_index(fb, px, py, 0)];
            if (isinf(d)) continue;
            negative += d < 0; /* every depth here is in [0.3, 0.9] */
            double x = px + 0.5, y = py + 0.5, err = INFINITY, corner_err = INFINITY;
            for (int v = 0; v < 2; v++) {
                double q[6];
                for (int k = 0; k < 6; k++)
                    q[k] = v ? snapped[k] : (double)c[k];
                double area = edge_exact(q[0], q[1], q[2], q[3], q[4], q[5]);
                double want = (edge_exact(q[2], q[3], q[4], q[5], x, y) * z[0] +
                               edge_exact(q[4], q[5], q[0], q[1], x, y) * z[1] +
                               edge_exact(q[0], q[1], q[2], q[3], x, y) * z[2]) /
                              area;
                err = fmin(err, fabs(d - want));
                /* the same plane at the pixel's corner */
                double corner = (edge_exact(q[2], q[3], q[4], q[5], px, py) * z[0] +
                                 edge_exact(q[4], q[5], q[0], q[1], px, py) * z[1] +
                                 edge_exact(q[0], q[1], q[2], q[3], px, py) * z[2]) /
                                area;
                corner_err = fmin(corner_err, fabs(d - corner));
            }
            at_corner += corner_err < 2e-5;
            dworst = fmax(dworst, err);
            seen++;
        }
    CHECK(seen > 0 && dworst <= 2e-5,
          "rasterize_triangle, a small triangle near screen (615, 590) with depths 0.3, 0.9, "
          "0.5: %s (at most 2e-5 expected). Likely mistake: %s",
          seen ? "the stored depth is off by more than 2e-5 against double"
               : "nothing drawn, so the depth could not be checked",
          !seen ? "nothing drawn (see the other rasterize tests)."
          : negative == seen
              ? "the depth stored NEGATED (-z): the course framework's negated depth test, "
                "kept; store and compare z as it is (smaller is closer)."
          : at_corner == seen
              ? "every stored depth is the plane's at the pixel's CORNER (x, y), not at the "
                "sample (x + 0.5, y + 0.5): the barycentrics for the depth taken at the loop's "
                "integer (x, y); take them at the position inside_triangle tested."
              : "your compute_barycentric_2d is accurate here (the check above passed), so the "
                "depth is interpolated at another point or with other weights than the "
                "sample's barycentrics: z = alpha*z0 + beta*z1 + gamma*z2 at the tested "
                "position.");
    ras_framebuffer_destroy(fb);
}

/* ---- 2. barycentrics ------------------------------------------------------------ */

static void test_bary_vertices_centroid_sum(void **state) {
    (void)state;
    ras_triangle ts[2] = {tri3(1.5f, 2, 11, 3.25f, 4, 9.5f), tri3(1.5f, 2, 4, 9.5f, 11, 3.25f)};
    for (int w = 0; w < 2; w++) {
        const ras_triangle *t = &ts[w];
        vec3s b;
        for (int i = 0; i < 3; i++) {
            CHECK(compute_barycentric_2d(t->v[i].x, t->v[i].y, t, &b),
                  "compute_barycentric_2d at vertex %d: expected true (a proper triangle), got "
                  "false. Likely mistake: the degenerate check is inverted.",
                  i);
            float e[3] = {i == 0, i == 1, i == 2};
            CHECK(
                fabsf(b.x - e[0]) < 1e-5f && fabsf(b.y - e[1]) < 1e-5f && fabsf(b.z - e[2]) < 1e-5f,
                "compute_barycentric_2d at vertex v%d of a %s triangle: expected (%g, %g, %g), "
                "got (%g, %g, %g). Likely mistake: %s",
                i, w ? "clockwise" : "counter-clockwise", e[0], e[1], e[2], b.x, b.y, b.z,
                w && bary_swapped_for_clockwise()
                    ? BARY_SWAPPED_CW "."
                    : "the coordinates are in the wrong order (alpha belongs to v0 and is the "
                      "area OPPOSITE v0), or divided by the wrong area.");
        }
        float cx = (t->v[0].x + t->v[1].x + t->v[2].x) / 3,
              cy = (t->v[0].y + t->v[1].y + t->v[2].y) / 3;
        compute_barycentric_2d(cx, cy, t, &b);
        CHECK(near3(b, (vec3s){{1 / 3.0f, 1 / 3.0f, 1 / 3.0f}}, 1e-5f),
              "compute_barycentric_2d at the centroid: expected (1/3, 1/3, 1/3), got (%g, %g, %g). "
              "Likely mistake: a wrong edge function or area.",
              b.x, b.y, b.z);
        const float pts[][2] = {{3, 4}, {7.3f, 5.1f}, {20, -3}, {-5, 30}, {0.1f, 0.2f}};
        for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++) {
            compute_barycentric_2d(pts[i][0], pts[i][1], t, &b);
            float sum = b.x + b.y + b.z;
            CHECK(fabsf(sum - 1) < 1e-4f,
                  "compute_barycentric_2d(%g, %g): alpha + beta + gamma = %g, expected 1. "
                  "Likely mistake: one coordinate divided by a different area, or gamma computed "
                  "with the wrong sign.",
                  pts[i][0], pts[i][1], sum);
            /* It reproduces the point. */
            float x = b.x * t->v[0].x + b.y * t->v[1].x + b.z * t->v[2].x;
            float y = b.x * t->v[0].y + b.y * t->v[1].y + b.z * t->v[2].y;
            CHECK(fabsf(x - pts[i][0]) < 1e-3f && fabsf(y - pts[i][1]) < 1e-3f,
                  "compute_barycentric_2d(%g, %g) gave (%g, %g, %g), which maps back to (%g, %g): "
                  "expected the point itself. Likely mistake: coordinates permuted.",
                  pts[i][0], pts[i][1], b.x, b.y, b.z, x, y);
        }
    }
}

static void test_bary_outside_is_negative(void **state) {
    (void)state;
    ras_triangle t = tri3(1, 1, 9, 1, 1, 9);
    const float out[][2] = {{5, -1}, {-1, 5}, {6, 6}, {20, 20}};
    for (size_t i = 0; i < sizeof out / sizeof out[0]; i++) {
        vec3s b;
        compute_barycentric_2d(out[i][0], out[i][1], &t, &b);
        CHECK(b.x < 0 || b.y < 0 || b.z < 0,
              "compute_barycentric_2d(%g, %g), outside the triangle: expected a negative "
              "coordinate, got (%g, %g, %g). Likely mistake: absolute values (fabsf) of the "
              "areas — the sign is what says 'outside'.",
              out[i][0], out[i][1], b.x, b.y, b.z);
    }
}

static void test_bary_degenerate_flagged(void **state) {
    (void)state;
    ras_triangle line = tri3(0, 0, 4, 4, 8, 8), point = tri3(2, 2, 2, 2, 2, 2);
    vec3s b = {{9, 9, 9}};
    bool ok = compute_barycentric_2d(1, 1, &line, &b);
    CHECK(!ok, "compute_barycentric_2d on the zero-area triangle (0,0),(4,4),(8,8): expected "
               "false (degenerate), got true. Likely mistake: no area check before dividing.");
    CHECK(b.x == 0 && b.y == 0 && b.z == 0 && !isnan(b.x),
          "compute_barycentric_2d on a degenerate triangle: expected *bary = (0, 0, 0), got "
          "(%g, %g, %g). Likely mistake: dividing by the zero area (NaN/Inf) instead of "
          "returning early.",
          b.x, b.y, b.z);
    CHECK(!compute_barycentric_2d(2, 2, &point, &b),
          "compute_barycentric_2d on a triangle collapsed to a point: expected false, got true.");
    /* "false" and (0, 0, 0) everywhere is the stub's placeholder: this test
     * counts only once a proper triangle gets barycentrics */
    ras_triangle proper = tri3(0, 0, 8, 0, 0, 8);
    vec3s pb = {{0, 0, 0}};
    bool proper_ok = compute_barycentric_2d(2, 2, &proper, &pb);
    CHECK(proper_ok && !(pb.x == 0 && pb.y == 0 && pb.z == 0),
          "compute_barycentric_2d(2, 2) on the proper triangle (0,0),(8,0),(0,8): expected true "
          "and (0.5, 0.25, 0.25), got %s and (%g, %g, %g). Returning false with (0, 0, 0) is the "
          "stub's placeholder, right for degenerate triangles only, so this test counts once "
          "a proper triangle gets its barycentrics. Likely mistake: compute_barycentric_2d is "
          "not written yet (TODO(hw2) 1-3).",
          proper_ok ? "true" : "false", pb.x, pb.y, pb.z);
}

/* What the shader was handed, per pixel. */
typedef struct recorded {
    int calls;
    int w, h;
    ras_fragment frag[256];
} recorded;

static vec3s record_shade(const ras_triangle *t, const ras_fragment *f, void *user) {
    recorded *r = user;
    if (r->calls < 256) r->frag[r->calls] = *f;
    r->calls++;
    return ras_shade_vertex_color(t, f, NULL);
}

/* Fragments must carry the barycentrics of the pixel CENTRE: the point the
 * inside test used. Taking them at the corner (x, y) shifts every colour and
 * depth by half a pixel. */
static void test_bary_at_pixel_centre(void **state) {
    (void)state;
    ras_framebuffer *fb = make_fb(14, 13, 1);
    recorded rec = {0};
    ras_raster_ctx ctx = ctx_none(fb);
    ctx.shade = record_shade;
    ctx.shade_user = &rec;
    ras_triangle t = tri3(0.75f, 0.5f, 13.25f, 2.5f, 3.5f, 12.25f);
    t.color[0] = RED;
    t.color[1] = (vec3s){{0, 1, 0}};
    t.color[2] = BLUE;
    t.v[0].z = 0.1f, t.v[1].z = 0.5f, t.v[2].z = 0.9f;
    rasterize_triangle(&t, &ctx);
    CHECK(rec.calls > 0,
          "rasterize_triangle with ctx->shade set: expected the shader to be called for each "
          "covered pixel, got 0 calls. Likely mistake: %s",
          why_nothing_drawn() ? why_nothing_drawn()
                              : "ctx->shade ignored (call it, or ras_shade_vertex_color when "
                                "it is NULL), or nothing is drawn yet.");
    for (int i = 0; i < rec.calls && i < 256; i++) {
        const ras_fragment *f = &rec.frag[i];
        double cx = f->x + 0.5, cy = f->y + 0.5;
        double bc[3], bk[3];
        exact_bary(&t, cx, cy, bc);
        exact_bary(&t, f->x, f->y, bk);
        vec3s want = {{(float)bc[0], (float)bc[1], (float)bc[2]}};
        vec3s corner = {{(float)bk[0], (float)bk[1], (float)bk[2]}};
        CHECK(near3(f->bary, want, 1e-4f),
              "fragment of pixel (%d, %d): expected the barycentrics of its centre (%g, %g) = "
              "(%.4f, %.4f, %.4f), got (%.4f, %.4f, %.4f). Likely mistake: %s",
              f->x, f->y, cx, cy, want.x, want.y, want.z, f->bary.x, f->bary.y, f->bary.z,
              near3(f->bary, corner, 1e-4f)
                  ? "barycentrics taken at the pixel CORNER (x, y) while the inside test used "
                    "(x + 0.5, y + 0.5) — use the same point for both."
                  : "the coordinates permuted, or not passed in the fragment.");
        float z = want.x * 0.1f + want.y * 0.5f + want.z * 0.9f;
        CHECK(fabsf(f->depth - z) < 1e-4f,
              "fragment of pixel (%d, %d): expected depth %.5f (interpolated at the centre), "
              "got %.5f. Likely mistake: depth not interpolated with the barycentrics, or taken "
              "at another point.",
              f->x, f->y, z, f->depth);
        float d = fb->depth[ras_fb_sample_index(fb, f->x, f->y, 0)];
        CHECK(fabsf(d - z) < 1e-4f,
              "depth buffer at pixel (%d, %d): expected %.5f, got %.5f. Likely mistake: %s", f->x,
              f->y, z, d,
              fabsf(d + z) < 1e-4f && z != 0
                  ? "the depth stored NEGATED (-z): the course framework's negated depth test, "
                    "kept; here the viewport already negated z (smaller is closer, the buffer "
                    "starts at +INF): store and compare z as it is."
              : fabsf(d - (corner.x * 0.1f + corner.y * 0.5f + corner.z * 0.9f)) < 1e-4f
                  ? "the stored depth is the plane's value at the pixel CORNER (x, y): the "
                    "depth's barycentrics taken at the loop's integer (x, y), not at the sample "
                    "inside_triangle tested (x + 0.5, y + 0.5); use the same point for both."
                  : "the depth stored is not the interpolated one (or stored at another index).");
    }
    ras_framebuffer_destroy(fb);
}

/* The screen depth v[i].z is already z/w, affine in screen space: it is
 * interpolated with the screen barycentrics and nothing else, whatever the
 * vertices' clip w. Every other hw2 test has w = 1 at all three vertices,
 * where the course framework's `z_interpolated *= w_reciprocal` snippet
 * changes nothing; here the three w differ (1, 2, 4), as in hw3's scenes. */
static void test_raster_depth_with_different_w(void **state) {
    (void)state;
    ras_framebuffer *fb = make_fb(14, 13, 1);
    recorded rec = {0};
    ras_raster_ctx ctx = ctx_none(fb);
    ctx.shade = record_shade;
    ctx.shade_user = &rec;
    ras_triangle t = tri3(0.75f, 0.5f, 13.25f, 2.5f, 3.5f, 12.25f);
    const float z[3] = {0.2f, 0.5f, 0.8f}, w[3] = {1.0f, 2.0f, 4.0f};
    for (int i = 0; i < 3; i++)
        t.v[i].z = z[i], t.v[i].w = w[i];
    rasterize_triangle(&t, &ctx);
    CHECK(rec.calls > 0,
          "rasterize_triangle of a triangle whose vertices have w = 1, 2, 4: expected fragments, "
          "got none. Likely mistake: %s",
          why_nothing_drawn() ? why_nothing_drawn()
                              : "the triangle rejected because w is not 1 (w is the clip w, any "
                                "positive value), or nothing is drawn yet.");
    for (int i = 0; i < rec.calls && i < 256; i++) {
        const ras_fragment *f = &rec.frag[i];
        double b[3];
        exact_bary(&t, f->x + 0.5, f->y + 0.5, b);
        double want = b[0] * z[0] + b[1] * z[1] + b[2] * z[2];
        /* the course's snippet: (Σ b·z/w) / (Σ b/w) */
        double snippet = (b[0] * z[0] / w[0] + b[1] * z[1] / w[1] + b[2] * z[2] / w[2]) /
                         (b[0] / w[0] + b[1] / w[1] + b[2] / w[2]);
        float d = fb->depth[ras_fb_sample_index(fb, f->x, f->y, 0)];
        CHECK(fabs(d - want) < 1e-4,
              "depth buffer at pixel (%d, %d) of a triangle with z = 0.2, 0.5, 0.8 and w = 1, 2, "
              "4: expected %.5f (the screen depth v[i].z is z/w already, affine in screen space: "
              "α·z0 + β·z1 + γ·z2 with the screen barycentrics), got %.5f. Likely mistake: %s",
              f->x, f->y, want, d,
              fabs(d + want) < 1e-4
                  ? "the depth stored NEGATED (-z): the course framework's negated depth test, "
                    "kept; here the viewport already negated z (smaller is closer, the buffer "
                    "starts at +INF): store and compare z as it is."
              : fabs(d - snippet) < 1e-4
                  ? "the course framework's `z_interpolated *= w_reciprocal` snippet, which "
                    "divides by an interpolated 1/w: there every w was 1 and it did nothing; "
                    "here v[i].w is the real clip w: interpolate v[i].z and nothing else "
                    "(docs/hw2.md, \"Coming from the GAMES101 framework\")."
                  : "the depth divided or multiplied by w (v[i].z is already divided), or "
                    "interpolated with other weights than the screen barycentrics.");
    }
    ras_framebuffer_destroy(fb);
}

/* ---- 3. index math ---------------------------------------------------------------- */

static void test_index_corners_and_flip(void **state) {
    (void)state;
    ras_framebuffer *fb = make_fb(7, 5, 4);
    const struct {
        int x, y, want;
    } c[] = {{0, 0, 4 * 7}, {6, 0, 4 * 7 + 6}, {0, 4, 0}, {6, 4, 6}, {3, 2, 2 * 7 + 3}};
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        int got = ras_fb_pixel_index(fb, c[i].x, c[i].y);
        CHECK(got == c[i].want,
              "ras_fb_pixel_index(%d, %d) on a 7x5 buffer: expected %d, got %d (screen y grows "
              "up, the buffer's first row is the TOP row: index (h-1-y)*w + x).",
              c[i].x, c[i].y, c[i].want, got);
        for (int s = 0; s < 4; s++)
            CHECK(ras_fb_sample_index(fb, c[i].x, c[i].y, s) == c[i].want * 4 + s,
                  "ras_fb_sample_index(%d, %d, %d): expected %d, got %d (samples of a pixel "
                  "are consecutive).",
                  c[i].x, c[i].y, s, c[i].want * 4 + s, ras_fb_sample_index(fb, c[i].x, c[i].y, s));
    }
    ras_framebuffer_destroy(fb);
}

static void test_index_all_in_range_and_distinct(void **state) {
    (void)state;
    const int sizes[][3] = {{1, 1, 1}, {3, 2, 4}, {5, 7, 16}, {16, 9, 2}, {2, 3, 64}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        ras_framebuffer *fb = make_fb(sizes[k][0], sizes[k][1], sizes[k][2]);
        int n = fb->width * fb->height * fb->samples;
        unsigned char *seen = calloc((size_t)n, 1);
        assert_non_null(seen);
        for (int y = 0; y < fb->height; y++)
            for (int x = 0; x < fb->width; x++)
                for (int s = 0; s < fb->samples; s++) {
                    int i = ras_fb_sample_index(fb, x, y, s);
                    CHECK(i >= 0 && i < n,
                          "sample (%d, %d, %d) of a %dx%d buffer with %d samples: "
                          "index %d is outside 0..%d.",
                          x, y, s, fb->width, fb->height, fb->samples, i, n - 1);
                    CHECK(!seen[i], "samples share index %d: (%d, %d, %d) and an earlier one.", i,
                          x, y, s);
                    seen[i] = 1;
                }
        free(seen);
        ras_framebuffer_destroy(fb);
    }
}

/* A framebuffer whose buffers sit inside larger ones with canaries around
 * them: any write outside the frame is seen (no sanitizer needed). The depth
 * canary is +INF, like a cleared buffer, so a stray depth test passes and the
 * stray write shows. */
#define GUARD 4096
typedef struct guarded {
    ras_framebuffer fb;
    vec3s *color_mem;
    float *depth_mem;
    size_t n;
} guarded;

static void guarded_init(guarded *g, int w, int h, int samples) {
    g->n = (size_t)(w * h * samples);
    g->color_mem = malloc((g->n + 2 * GUARD) * sizeof(vec3s));
    g->depth_mem = malloc((g->n + 2 * GUARD) * sizeof(float));
    assert_non_null(g->color_mem);
    assert_non_null(g->depth_mem);
    for (size_t i = 0; i < g->n + 2 * GUARD; i++) {
        g->color_mem[i] = (vec3s){{7, 7, 7}};
        g->depth_mem[i] = INFINITY;
    }
    g->fb = (ras_framebuffer){.width = w,
                              .height = h,
                              .samples = samples,
                              .color = g->color_mem + GUARD,
                              .depth = g->depth_mem + GUARD};
    ras_framebuffer_clear(&g->fb, BLACK);
    /* In grading, the canaries are part of what rasterize_triangle's record
     * carries, so a write outside the frame is seen by the trusted replay. */
    ras_call_watch(g->color_mem, (g->n + 2 * GUARD) * sizeof(vec3s));
    ras_call_watch(g->depth_mem, (g->n + 2 * GUARD) * sizeof(float));
}

static bool guarded_intact(const guarded *g) {
    for (size_t i = 0; i < GUARD; i++)
        if (!isinf(g->depth_mem[i]) || !isinf(g->depth_mem[GUARD + g->n + i]) ||
            g->color_mem[i].x != 7 || g->color_mem[GUARD + g->n + i].x != 7)
            return false;
    return true;
}

static void guarded_free(guarded *g) {
    ras_call_watch(NULL, 0);
    free(g->color_mem);
    free(g->depth_mem);
}

static int covered_pixels(const ras_framebuffer *fb) {
    int n = 0;
    for (int i = 0; i < fb->width * fb->height * fb->samples; i++)
        n += !isinf(fb->depth[i]);
    return n;
}

/* A triangle covering only the bottom-left pixel must land in the LAST
 * memory row, one covering the top-right pixel in the first. */
static void test_index_rasterizer_writes_flipped(void **state) {
    (void)state;
    guarded g;
    guarded_init(&g, 6, 4, 1);
    ras_raster_ctx ctx = ctx_none(&g.fb);
    ras_triangle bl = tri_z(tri3(0.25f, 0.25f, 0.9f, 0.25f, 0.25f, 0.9f), 0.5f, RED);
    rasterize_triangle(&bl, &ctx);
    int idx = 3 * 6 + 0;
    CHECK(!isinf(g.fb.depth[idx]) && covered_pixels(&g.fb) == 1,
          "a tiny triangle around the centre of screen pixel (0, 0) (bottom-left): expected "
          "exactly buffer index %d written (the last row: (h-1-y)*w + x), got %d samples "
          "written, index %d %s. Likely mistake: %s",
          idx, covered_pixels(&g.fb), idx, isinf(g.fb.depth[idx]) ? "untouched" : "written",
          !isinf(g.fb.depth[0]) ? "no y-flip (y*w + x): use ras_fb_sample_index."
          : covered_pixels(&g.fb) == 0 && inside_answers_at_corner()
              ? "nothing drawn (the triangle holds the centre (0.5, 0.5), not the corner (0, "
                "0)), and inside_triangle, called on other points, answers for each as for its "
                "pixel's corner: " INT_SIGNATURE_HABIT "."
              : "the pixel centre not tested, or nothing drawn yet.");
    ras_framebuffer_clear(&g.fb, BLACK);
    /* the first triangle moved by (5, 3): the centre lies inside, not on an
     * edge, so a strict inside test is as right here as the top-left rule */
    ras_triangle tr = tri_z(tri3(5.25f, 3.25f, 5.9f, 3.25f, 5.25f, 3.9f), 0.5f, RED);
    rasterize_triangle(&tr, &ctx);
    CHECK(!isinf(g.fb.depth[5]) && covered_pixels(&g.fb) == 1,
          "a tiny triangle around the centre of screen pixel (5, 3) (top-right of a 6x4 "
          "frame): expected exactly buffer index 5 written, got %d samples written. Likely "
          "mistake: the y-flip, or x and y swapped.",
          covered_pixels(&g.fb));
    CHECK(guarded_intact(&g), "rasterize_triangle wrote outside the frame's buffers.");
    guarded_free(&g);
    /* 4 samples a pixel: a triangle over all of pixel (5, 3) and nothing of
     * its neighbours writes exactly that pixel's four entries,
     * ras_fb_sample_index(fb, 5, 3, s) = (0*6 + 5)*4 + s */
    guarded_init(&g, 6, 4, 4);
    ras_raster_ctx msaa = make_ctx(&g.fb, RAS_AA_MSAA, pattern(RAS_PATTERN_STANDARD, 4));
    ras_triangle corner = tri_z(tri3(5.01f, 3.01f, 20, 3.01f, 5.01f, 20), 0.5f, RED);
    rasterize_triangle(&corner, &msaa);
    int at_pixel = 0;
    for (int k = 0; k < 4; k++)
        at_pixel += !isinf(g.fb.depth[ras_fb_sample_index(&g.fb, 5, 3, k)]);
    int written = covered_pixels(&g.fb);
    CHECK(at_pixel == 4 && written == 4,
          "4x MSAA, a triangle over all of the top-right pixel (5, 3) of a 6x4 frame: expected "
          "its 4 sample entries written (indices 20..23), got %d of them and %d entries in all. "
          "Likely mistake: %s",
          at_pixel, written,
          written == 4   ? "a wrong stride: sample s of pixel (x, y) is at ((h-1-y)*w + x)*samples "
                           "+ s; use ras_fb_sample_index(fb, x, y, s)"
          : written == 0 ? "nothing drawn with 4 samples"
          : at_pixel == 4 ? "entries of other pixels written by a triangle that reaches past the "
                            "frame's corner: the bounding box not clamped to the screen (TODO 1)"
                          : "samples of the neighbouring pixels written, or some of this one's "
                            "missed: the sample positions are (x + offset.x, y + offset.y)");
    CHECK(guarded_intact(&g), "rasterize_triangle (4 samples, a triangle reaching past the "
                              "frame's top-right corner) wrote outside the frame's buffers. "
                              "Likely mistake: the bounding box not clamped to the screen, or a "
                              "wrong stride (use ras_fb_sample_index(fb, x, y, s)).");
    guarded_free(&g);
}

/* The samples are where ctx->pattern says, not at positions written into the
 * rasterizer: four samples all in the left half of the pixel, under a
 * triangle that covers exactly that half, are all covered. */
static void test_raster_samples_from_pattern(void **state) {
    (void)state;
    ras_framebuffer *fb = make_fb(1, 1, 4);
    ras_sample_pattern pat = pattern(RAS_PATTERN_STANDARD, 4);
    const float left[4][2] = {{0.1f, 0.1f}, {0.2f, 0.7f}, {0.3f, 0.3f}, {0.4f, 0.9f}};
    for (int k = 0; k < 4; k++)
        pat.offsets[k] = (vec2s){{left[k][0], left[k][1]}};
    ras_raster_ctx ctx = make_ctx(fb, RAS_AA_MSAA, pat);
    ras_triangle t = tri_z(tri3(-5, -5, 0.45f, -5, 0.45f, 10), 0.5f, RED);
    rasterize_triangle(&t, &ctx);
    int covered = covered_pixels(fb);
    CHECK(covered == 4,
          "4 samples placed by ctx->pattern at x = 0.1, 0.2, 0.3, 0.4 px in pixel (0, 0), under "
          "a triangle covering x < 0.45: expected all 4 covered, got %d. Likely mistake: %s",
          covered,
          covered == 2   ? "sample positions written into the rasterizer (a 2x2 grid or the "
                           "standard offsets) instead of read from ctx->pattern.offsets[k]"
          : covered == 0 ? "nothing drawn with MSAA (the samples, or the depth test)"
                         : "the sample positions not taken from ctx->pattern.offsets[k] "
                           "(from the pixel's lower-left corner, in pixels)");
    ras_framebuffer_destroy(fb);
}

/* A tiny triangle whose only covered pixel centre sits in the LAST column and
 * row of its bounding box (x from k+0.05 to k+0.95): the classic loop
 * `for (x = floor(min_x); x < floor(max_x); x++)` never visits it. */
static void test_raster_box_maximum_included(void **state) {
    (void)state;
    ras_framebuffer *fb = make_fb(6, 4, 1);
    /* Only a rasterizer that draws at all can show this mistake. */
    ras_raster_ctx big_ctx = ctx_none(fb);
    ras_triangle big = tri_z(tri3(0, 0, 6, 0, 0, 4), 0.5f, RED);
    rasterize_triangle(&big, &big_ctx);
    int drawn = covered_pixels(fb);
    CHECK(drawn > 0, "a triangle over half of a 6x4 frame drew nothing, so the bounding box's "
                     "last row and column cannot be checked yet (see the other rasterize tests)");
    const int pixels[][2] = {{2, 1}, {0, 0}, {5, 3}, {3, 2}};
    for (size_t i = 0; i < sizeof pixels / sizeof pixels[0]; i++) {
        float x = (float)pixels[i][0], y = (float)pixels[i][1];
        ras_framebuffer_clear(fb, BLACK);
        ras_raster_ctx ctx = ctx_none(fb);
        /* below the diagonal from (x+0.05, y+0.2) to (x+0.95, y+0.95): the
         * centre (x+0.5, y+0.5) is inside, 0.075 px from that edge */
        ras_triangle t =
            tri_z(tri3(x + 0.05f, y + 0.2f, x + 0.95f, y + 0.2f, x + 0.95f, y + 0.95f), 0.5f, RED);
        rasterize_triangle(&t, &ctx);
        int idx = ras_fb_sample_index(fb, pixels[i][0], pixels[i][1], 0);
        CHECK(!isinf(fb->depth[idx]) && covered_pixels(fb) == 1,
              "a tiny triangle inside screen pixel (%d, %d), x from %.2f to %.2f, covering its "
              "centre (%.1f, %.1f): expected exactly that pixel drawn, got %d pixels%s. Likely "
              "mistake: %s",
              pixels[i][0], pixels[i][1], (double)x + 0.05, (double)x + 0.95, (double)x + 0.5,
              (double)y + 0.5, covered_pixels(fb), isinf(fb->depth[idx]) ? ", not that one" : "",
              covered_pixels(fb) == 0 && inside_answers_at_corner()
                  ? "nothing drawn, and inside_triangle, called on other points, answers for "
                    "each as for its pixel's corner (the centre here is inside, the corner "
                    "not): " INT_SIGNATURE_HABIT "."
              : covered_pixels(fb) == 0
                  ? "the bounding box's maximum used as an exclusive bound (x < floor(max_x)): "
                    "the last column and row of the box are never visited; loop to "
                    "x <= floor(max_x) (and y likewise), clamped to the screen."
                  : "the pixel centre not used, or the y-flip.");
    }
    ras_framebuffer_destroy(fb);
}

/* ---- 4. rasterize: clamping, rejects, depth ------------------------------------------- */

static void test_raster_clamped_to_screen(void **state) {
    (void)state;
    const int W = 9, H = 7;
    const ras_triangle cases[] = {
        tri3(-1000, -1000, 3000, -1000, -1000, 3000), /* covers the whole frame */
        tri3(-50, 3.2f, 4.5f, -40, 4.5f, 60),         /* sticks out on three sides */
        tri3(-1e7f, -1e7f, 1e7f, -1e7f, 0, 1e7f),     /* far beyond any fixed-point range */
        tri3(30, 30, 40, 30, 30, 40),                 /* wholly off-screen */
        tri3(-40, 2, -30, 2, -35, 5),                 /* wholly left of the screen */
    };
    const int want_all[] = {1, -1, 1, 0, 0}; /* 1 all pixels, 0 none, -1 some */
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        for (int aa = 0; aa < 2; aa++) {
            guarded g;
            ras_sample_pattern pat =
                aa ? pattern(RAS_PATTERN_STANDARD, 4) : ras_sample_pattern_center();
            guarded_init(&g, W, H, pat.count);
            ras_raster_ctx ctx = make_ctx(&g.fb, aa ? RAS_AA_MSAA : RAS_AA_NONE, pat);
            ras_triangle t = tri_z(cases[k], 0.5f, WHITE);
            rasterize_triangle(&t, &ctx);
            CHECK(guarded_intact(&g),
                  "triangle %zu (partly or wholly off-screen): rasterize_triangle wrote outside "
                  "the %dx%d frame's buffers. Likely mistake: the bounding box is not clamped to "
                  "0..width-1 / 0..height-1 (clamp the floats before casting to int).",
                  k, W, H);
            int n = covered_pixels(&g.fb), all = W * H * pat.count;
            CHECK(want_all[k] != 1 || n == all,
                  "triangle %zu covers the whole %dx%d frame: expected all %d samples covered, "
                  "got %d. Likely mistake: %s",
                  k, W, H, all, n,
                  n == 0 && why_nothing_drawn() ? why_nothing_drawn()
                  : !inside_triangle(W / 2 + 0.5f, H / 2 + 0.5f, &t)
                      ? "inside_triangle itself says the frame's centre is outside this "
                        "triangle (called here): its edge functions overflow for corners this "
                        "far out — an int edge function (`int e = ...`) holds at most 2^31 px², "
                        "these reach 10^14; keep them float (or double)."
                      : "the bounding box clamped wrongly (e.g. to the first vertex), or an "
                        "overflow for huge coordinates in the loop.");
            CHECK(want_all[k] != 0 || n == 0,
                  "triangle %zu is wholly off-screen: expected nothing drawn, got %d samples. "
                  "Likely mistake: clamping the box INTO the screen drew its edge pixels; an "
                  "empty box must stay empty.",
                  k, n);
            CHECK(want_all[k] != -1 || (n > 0 && n < all),
                  "triangle %zu is partly on-screen: expected some but not all samples, got %d "
                  "of %d.",
                  k, n, all);
            guarded_free(&g);
        }
    }
}

static void test_raster_rejects_nan_and_zero_area(void **state) {
    (void)state;
    guarded g;
    guarded_init(&g, 8, 8, 1);
    ras_raster_ctx ctx = ctx_none(&g.fb);
    const ras_triangle bad[] = {tri3(1, 1, 7, 7, 4, 4), tri3(2, 2, 2, 2, 2, 2),
                                tri3(NAN, 1, 7, 1, 1, 7), tri3(1, 1, INFINITY, 1, 1, 7),
                                tri3(1, 1, 7, 1, 1, -INFINITY)};
    const char *what[] = {"collinear", "a point", "a NaN x", "an Inf x", "a -Inf y"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        ras_framebuffer_clear(&g.fb, BLACK);
        ras_triangle t = tri_z(bad[k], 0.5f, WHITE);
        rasterize_triangle(&t, &ctx);
        CHECK(covered_pixels(&g.fb) == 0 && guarded_intact(&g),
              "a triangle with %s: expected nothing drawn, got %d pixels%s. Likely mistake: "
              "zero area not rejected, or NaN/Inf turned into a huge int bounding box.",
              what[k], covered_pixels(&g.fb),
              guarded_intact(&g) ? "" : " AND writes outside the buffers");
    }
    /* drawing nothing at all is the stub's placeholder: this test counts
     * only once a proper triangle is drawn */
    ras_framebuffer_clear(&g.fb, BLACK);
    ras_triangle good = tri_z(tri3(1, 1, 7, 1, 1, 7), 0.5f, WHITE);
    rasterize_triangle(&good, &ctx);
    CHECK(covered_pixels(&g.fb) > 0,
          "the proper triangle (1,1),(7,1),(1,7) after the bad ones: expected pixels drawn, got "
          "none. Drawing nothing is the stub's placeholder, right for the bad triangles only, "
          "so this test counts once a proper triangle is drawn. Likely mistake: %s",
          why_nothing_drawn() ? why_nothing_drawn()
                              : "rasterize_triangle is not written yet (TODO(hw2) 1-6), or it "
                                "rejects every triangle.");
    guarded_free(&g);
}

/* Depth: smaller is closer, whichever is drawn first; depth interpolated. */
static void test_raster_depth_test_order(void **state) {
    (void)state;
    ras_framebuffer *fb = make_fb(8, 8, 1);
    ras_raster_ctx ctx = ctx_none(fb);
    ras_triangle near_t = tri_z(tri3(0, 0, 8, 0, 0, 8), 0.2f, RED);
    ras_triangle far_t = tri_z(tri3(0, 0, 8, 0, 0, 8), 0.7f, BLUE);
    /* Both orders first: which one wins in each names the mistake (the last
     * drawn always: no test; the farther always: reversed; nothing: a test
     * that never passes, read from the counters). */
    vec3s c[2];
    float d[2];
    ras_counters k[2];
    for (int order = 0; order < 2; order++) {
        ras_framebuffer_clear(fb, BLACK);
        memset(&k[order], 0, sizeof k[order]);
        ctx.counters = &k[order];
        rasterize_triangle(order ? &far_t : &near_t, &ctx);
        rasterize_triangle(order ? &near_t : &far_t, &ctx);
        c[order] = fb->color[ras_fb_sample_index(fb, 2, 2, 0)];
        d[order] = fb->depth[ras_fb_sample_index(fb, 2, 2, 0)];
    }
    ctx.counters = NULL;
    bool blue[2] = {near3(c[0], BLUE, 1e-6f), near3(c[1], BLUE, 1e-6f)};
    bool red[2] = {near3(c[0], RED, 1e-6f), near3(c[1], RED, 1e-6f)};
    for (int order = 0; order < 2; order++) {
        const char *why =
            blue[0] && blue[1]
                ? "the depth test reversed: the FARTHER sample wins in both orders (smaller is "
                  "closer: draw when z < depth[i]; the course framework's negated z, "
                  "-z < depth or z > depth, is for its own z sign: undo it here)"
            : near3(c[order], glms_vec3_add(RED, BLUE), 1e-6f) && fabsf(d[order] - 0.2f) < 1e-6f
                ? "the depth is right but the colour is red + blue, the SUM of both triangles' "
                  "colours: " ADDITIVE_MSAA
            : blue[0] && red[1] ? "no depth test: the LAST triangle drawn wins in both orders"
            : red[0] && blue[1] ? "the FIRST triangle drawn wins in both orders: the depth "
                                  "buffer is written but the test never lets a later, nearer "
                                  "sample through (compared with the wrong buffer entry?)"
            : isinf(d[order]) && k[order].samples_covered > 0 && k[order].depth_tests_passed == 0
                ? "nothing drawn: your counters say the samples were covered but no depth test "
                  "passed (the buffer is cleared to +INF: z < depth[i] passes the first time)"
            : isinf(d[order]) && inside_triangle(2.5f, 2.5f, &near_t)
                ? "nothing drawn, although inside_triangle accepts the pixel centre (2.5, 2.5): "
                  "the depth test never passes, or the colour and depth are not written"
            : isinf(d[order]) ? "nothing drawn at all: the pixel centre is not covered "
                                "(inside_triangle, TODO 3)"
                              : "the depth buffer not updated after a pass.";
        CHECK(red[order] && fabsf(d[order] - 0.2f) < 1e-6f,
              "two triangles at depth 0.2 (red) and 0.7 (blue), %s drawn first: expected red "
              "with depth 0.2 at pixel (2, 2), got (%g, %g, %g) with depth %g. Likely mistake: "
              "%s",
              order ? "the far one" : "the near one", c[order].x, c[order].y, c[order].z, d[order],
              why);
    }
    /* A sloped triangle: depth follows the plane. */
    ras_framebuffer_clear(fb, BLACK);
    ras_triangle slope = tri3(0, 0, 8, 0, 0, 8);
    slope.v[0].z = 0.1f, slope.v[1].z = 0.9f, slope.v[2].z = 0.5f;
    rasterize_triangle(&slope, &ctx);
    for (int y = 0; y < 8; y++)
        for (int x = 0; x + y < 7; x++) {
            float want = 0.1f + 0.8f * (x + 0.5f) / 8 + 0.4f * (y + 0.5f) / 8;
            float got = fb->depth[ras_fb_sample_index(fb, x, y, 0)];
            CHECK(fabsf(got - want) < 1e-5f,
                  "sloped triangle, pixel (%d, %d): expected depth %.5f (the plane through the "
                  "vertices, at the pixel centre), got %.5f. Likely mistake: %s",
                  x, y, want, got,
                  fabsf(got - (0.1f + 0.8f * x / 8 + 0.4f * y / 8)) < 1e-5f
                      ? "the stored depth is the plane's at the pixel CORNER (x, y): the "
                        "depth's barycentrics taken at the loop's integer (x, y), not at the "
                        "sample inside_triangle tested; use the same point for both."
                      : "depth not interpolated (one vertex's z), or interpolated with other "
                        "weights than the sample's barycentrics.");
        }
    ras_framebuffer_destroy(fb);
}

/* Counters, when given, add up; NULL counters are fine (all tests above). */
static void test_raster_counters(void **state) {
    (void)state;
    ras_framebuffer *fb = make_fb(10, 10, 4);
    ras_counters k = {0};
    ras_raster_ctx ctx = make_ctx(fb, RAS_AA_MSAA, pattern(RAS_PATTERN_ORDERED, 4));
    ctx.counters = &k;
    ras_triangle t = tri_z(tri3(1, 1, 9, 1, 1, 9), 0.5f, WHITE);
    rasterize_triangle(&t, &ctx);
    int covered = covered_pixels(fb);
    /* Covered samples on an empty (+inf) frame that all fail the depth test:
     * the comparison is the wrong way round, whatever else is also wrong. */
    CHECK(!(k.samples_covered > 0 && k.depth_tests_passed == 0 && covered == 0),
          "MSAA 4x, one triangle on an empty frame (depth cleared to +inf): your rasterizer "
          "covered %llu samples and none passed the depth test, so nothing was drawn. Likely "
          "mistake: the depth comparison is reversed (smaller z is closer: draw when "
          "z < depth[i]).",
          (unsigned long long)k.samples_covered);
    /* nothing drawn and nothing counted is the stub's placeholder: every sum
     * below is 0 = 0 there, so this test counts only once the triangle is drawn */
    CHECK(covered > 0,
          "MSAA 4x, one triangle (1,1),(9,1),(1,9) on an empty 10x10 frame: expected samples "
          "drawn, got none (and the counters say %llu covered). Drawing nothing is the stub's "
          "placeholder, and its counters (all 0) add up trivially, so this test counts once "
          "the triangle is drawn. Likely mistake: rasterize_triangle is not written yet "
          "(TODO(hw2) 1-7).",
          (unsigned long long)k.samples_covered);
    CHECK(k.samples_covered == (uint64_t)covered && k.depth_tests_passed == (uint64_t)covered,
          "MSAA 4x, one triangle on an empty frame: expected samples_covered = "
          "depth_tests_passed = %d (the samples written), got %llu and %llu. Likely mistake: "
          "counters not updated (ctx->counters may be NULL: check before adding).",
          covered, (unsigned long long)k.samples_covered, (unsigned long long)k.depth_tests_passed);
    CHECK(k.samples_tested >= k.samples_covered, "samples_tested (%llu) < samples_covered (%llu).",
          (unsigned long long)k.samples_tested, (unsigned long long)k.samples_covered);
    int pixels = 0;
    for (int y = 0; y < 10; y++)
        for (int x = 0; x < 10; x++) {
            int any = 0;
            for (int s = 0; s < 4; s++)
                any |= !isinf(fb->depth[ras_fb_sample_index(fb, x, y, s)]);
            pixels += any;
        }
    CHECK(k.fragments_shaded == (uint64_t)pixels,
          "MSAA shades once per pixel per triangle: expected fragments_shaded = %d (pixels with "
          "a covered sample), got %llu. Likely mistake: shading once per sample (that is SSAA).",
          pixels, (unsigned long long)k.fragments_shaded);
    ras_framebuffer_clear(fb, BLACK);
    k = (ras_counters){0};
    ctx.aa = RAS_AA_SSAA;
    rasterize_triangle(&t, &ctx);
    CHECK(k.fragments_shaded == (uint64_t)covered,
          "SSAA shades once per sample: expected fragments_shaded = %d, got %llu.", covered,
          (unsigned long long)k.fragments_shaded);
    ras_framebuffer_destroy(fb);
}

/* ---- 5. resolve ------------------------------------------------------------------------- */

/* Whether resolve_pixel answers with sample 0 alone: pixel (0, 0) gets its
 * sample 1 coloured (and covered), sample 0 black; covered-only averaging
 * gives the colour, the box filter a share of it, sample 0 black. */
static bool resolves_sample_zero(ras_framebuffer *fb) {
    ras_framebuffer_clear(fb, BLACK);
    fb->color[ras_fb_sample_index(fb, 0, 0, 1)] = WHITE;
    fb->depth[ras_fb_sample_index(fb, 0, 0, 1)] = 0.5f;
    return near3(resolve_pixel(fb, 0, 0), BLACK, 1e-6f);
}

/* resolve_pixel averages in float, over fb->samples (not a hard-coded 4). */
static void test_resolve_box_filter_float(void **state) {
    (void)state;
    const int counts[] = {4, 16};
    for (int c = 0; c < 2; c++) {
        int S = counts[c];
        ras_framebuffer *fb = make_fb(3, 2, S);
        for (int lit = 0; lit <= S; lit++) {
            ras_framebuffer_clear(fb, BLACK);
            for (int s = 0; s < lit; s++) {
                fb->color[ras_fb_sample_index(fb, 2, 1, s)] = (vec3s){{1, 0.5f, 0.25f}};
                fb->depth[ras_fb_sample_index(fb, 2, 1, s)] = 0.5f; /* covered, as drawn */
            }
            vec3s got = resolve_pixel(fb, 2, 1);
            float f = (float)lit / (float)S;
            vec3s want = {{f, 0.5f * f, 0.25f * f}};
            CHECK(near3(got, want, 1e-5f),
                  "resolve_pixel with %d of %d samples coloured (1, 0.5, 0.25) over black: "
                  "expected (%g, %g, %g), got (%g, %g, %g). Likely mistake: %s",
                  lit, S, want.x, want.y, want.z, got.x, got.y, got.z,
                  (lit > 0 && lit < S && got.x == 0)
                      ? "integer division (cnt / 4 is 0 for a partial pixel): divide in float."
                  : (lit > 0 && lit < S && near3(got, (vec3s){{1, 0.5f, 0.25f}}, 1e-5f) &&
                     resolves_sample_zero(fb))
                      ? "resolve_pixel returns sample 0's colour whatever the others hold (a "
                        "pixel whose only coloured sample is sample 1 resolves to sample 0's "
                        "black): one colour kept per pixel, as when colour x covered / 4 is "
                        "ADDED into the pixel's colour; keep a colour per sample and return "
                        "the average of all fb->samples."
                  : (S == 16 && fabsf(got.x - lit / 4.0f) < 1e-5f)
                      ? "the sample count hard-coded as 4: use fb->samples."
                  : (lit > 0 && lit < S && near3(got, (vec3s){{1, 0.5f, 0.25f}}, 1e-5f))
                      ? "the average taken over the covered (or coloured) samples only: every "
                        "sample weighs 1/fb->samples, the black ones too."
                      : "not the box-filter average of the pixel's own samples (check the index "
                        "ras_fb_sample_index(fb, x, y, s)).");
        }
        ras_framebuffer_destroy(fb);
    }
}

/* Renders triangles into a 3x3 frame and resolves pixel (1, 1). */
static vec3s render_pixel(const ras_triangle *tris, int n, ras_aa_mode aa, ras_sample_pattern pat) {
    ras_framebuffer *fb = make_fb(3, 3, pat.count);
    ras_raster_ctx ctx = make_ctx(fb, aa, pat);
    for (int i = 0; i < n; i++)
        rasterize_triangle(&tris[i], &ctx);
    vec3s c = resolve_pixel(fb, 1, 1);
    ras_framebuffer_destroy(fb);
    return c;
}

/* One triangle whose vertical edge x = 1.5 halves pixel (1, 1): half its colour. */
static void test_resolve_half_covered_pixel(void **state) {
    (void)state;
    ras_triangle half =
        tri_z(tri3(-10, -10, 1.5f, -10, 1.5f, 40), 0.5f, (vec3s){{0.8f, 0.6f, 0.4f}});
    const struct {
        ras_aa_mode aa;
        ras_pattern_kind kind;
    } modes[] = {{RAS_AA_MSAA, RAS_PATTERN_ORDERED},
                 {RAS_AA_MSAA, RAS_PATTERN_STANDARD},
                 {RAS_AA_SSAA, RAS_PATTERN_ORDERED},
                 {RAS_AA_SSAA, RAS_PATTERN_STANDARD}};
    /* resolve_pixel alone, on two of four samples written by hand: whether
     * it averages over all the samples or over the covered ones only */
    ras_framebuffer *hand = make_fb(3, 3, 4);
    ras_framebuffer_clear(hand, BLACK);
    for (int s = 0; s < 2; s++) {
        hand->color[ras_fb_sample_index(hand, 1, 1, s)] = (vec3s){{0.8f, 0.6f, 0.4f}};
        hand->depth[ras_fb_sample_index(hand, 1, 1, s)] = 0.5f;
    }
    vec3s hand_resolved = resolve_pixel(hand, 1, 1);
    bool covered_only = fabsf(hand_resolved.x - 0.8f) < 1e-4f;
    /* sample 0 alone gives 0.8 there too: told apart on a pixel whose
     * only covered sample is sample 1 */
    bool sample_zero = covered_only && resolves_sample_zero(hand);
    ras_framebuffer_destroy(hand);
    for (size_t m = 0; m < sizeof modes / sizeof modes[0]; m++) {
        vec3s got = render_pixel(&half, 1, modes[m].aa, pattern(modes[m].kind, 4));
        vec3s want = {{0.4f, 0.3f, 0.2f}};
        CHECK(near3(got, want, 1e-5f),
              "%s 4x %s: a triangle covering the left half of pixel (1, 1) over black: expected "
              "half its colour (0.4, 0.3, 0.2), got (%g, %g, %g). Likely mistake: %s",
              ras_aa_mode_name(modes[m].aa), ras_pattern_kind_name(modes[m].kind), got.x, got.y,
              got.z,
              got.x > 0.79f && inside_answers_at_corner()
                  ? "all four samples covered, and inside_triangle, called on other points, "
                    "answers for each as for its pixel's corner (here (1, 1), inside): "
                    INT_SIGNATURE_HABIT "."
              : got.x == 0
                  ? "nothing resolved: integer division in the resolve, or samples not written."
              : got.x > 0.79f && sample_zero
                  ? "resolve_pixel returns sample 0's colour whatever the others hold (a pixel "
                    "whose only coloured sample is sample 1 resolves to black): one colour kept "
                    "per pixel; keep a colour per sample and return the average of all "
                    "fb->samples."
              : got.x > 0.79f && covered_only
                  ? "the resolve averages over the COVERED samples only (resolve_pixel gives "
                    "0.8 for two of four samples written): divide the sum of all fb->samples "
                    "by fb->samples."
              : got.x > 0.79f ? "coverage tested at the pixel centre only (one sample), or the "
                                "colour written to all samples of a partly covered pixel."
              : fabsf(got.x - 0.2f) < 1e-4f
                  ? "coverage applied twice (coverage²: 0.8 × ½ × ½): the samples already hold "
                    "the colour only where covered and the resolve's average is the coverage; "
                    "do not also scale the colour by the covered fraction."
                  : "samples not placed at (x + offset.x, y + offset.y).");
    }
}

/* Two triangles sharing the diagonal of a white square over black: every
 * pixel of the square must resolve to white — no dark seam. */
static void test_resolve_no_dark_seam(void **state) {
    (void)state;
    const int N = 12;
    const ras_pattern_kind kinds[] = {RAS_PATTERN_ORDERED, RAS_PATTERN_STANDARD};
    const ras_aa_mode modes[] = {RAS_AA_MSAA, RAS_AA_SSAA};
    for (int k = 0; k < 2; k++)
        for (int m = 0; m < 2; m++) {
            ras_sample_pattern pat = pattern(kinds[k], 4);
            ras_framebuffer *fb = make_fb(N, N, 4);
            ras_raster_ctx ctx = make_ctx(fb, modes[m], pat);
            /* A slanted diagonal so it crosses samples at many sub-positions. */
            ras_triangle a = tri_z(tri3(1, 1, 11, 1.3f, 10.7f, 11), 0.5f, WHITE);
            ras_triangle b = tri_z(tri3(1, 1, 10.7f, 11, 1.2f, 10.8f), 0.5f, WHITE);
            rasterize_triangle(&a, &ctx);
            rasterize_triangle(&b, &ctx);
            int seam[12 * 12] = {0}, worst_x = -1, worst_y = -1;
            float worst = 1;
            for (int y = 2; y < 10; y++)
                for (int x = 2; x < 10; x++) {
                    vec3s c = resolve_pixel(fb, x, y);
                    if (c.x < 1 - 1e-5f) {
                        seam[y * N + x] = 2;
                        if (c.x < worst) worst = c.x, worst_x = x, worst_y = y;
                    } else {
                        seam[y * N + x] = 1;
                    }
                }
            if (worst_x >= 0 && covered_pixels(fb) == 0)
                fail_msg("%s 4x %s: two white triangles sharing an edge over black: expected "
                         "every inner pixel white, got nothing drawn (no sample has a depth). "
                         "Likely mistake: nothing is drawn with 4 samples; see the first "
                         "failing rasterize test.",
                         ras_aa_mode_name(modes[m]), ras_pattern_kind_name(kinds[k]));
            if (worst_x >= 0) {
                char art[512];
                ascii_raster(seam, NULL, N, N, art, sizeof art);
                fail_msg("%s 4x %s: two white triangles sharing an edge over black: expected "
                         "every inner pixel white (1.0), got %g at pixel (%d, %d). Likely "
                         "mistake: a DARK SEAM — one colour per pixel scaled by this triangle's "
                         "coverage, so the second triangle overwrites the first's share; keep a "
                         "colour per SAMPLE and resolve by averaging them.\n"
                         "('2' marks dark pixels, '#' white ones, '.' not checked)\n%s",
                         ras_aa_mode_name(modes[m]), ras_pattern_kind_name(kinds[k]), worst,
                         worst_x, worst_y, art);
            }
            ras_framebuffer_destroy(fb);
        }
}

/* Overdraw: a nearer triangle drawn over a farther one REPLACES its colour on
 * the samples it wins, it does not add to it. Two triangles sharing a pixel
 * sum right under an additive resolve (their shares add up to the pixel), so
 * only overdraw shows that mistake. */
static void test_resolve_overdraw_replaces(void **state) {
    (void)state;
    ras_triangle far_full = tri_z(tri3(-10, -10, 40, -10, -10, 40), 0.8f, BLUE);
    ras_triangle near_full = tri_z(tri3(-10, -10, 40, -10, -10, 40), 0.2f, RED);
    ras_triangle near_half = tri_z(tri3(-10, -10, 1.5f, -10, 1.5f, 40), 0.2f, RED);
    const struct {
        ras_aa_mode aa;
        const ras_triangle *near_t;
        float share; /* of the pixel the near triangle covers */
    } cases[] = {{RAS_AA_NONE, &near_full, 1},
                 {RAS_AA_MSAA, &near_full, 1},
                 {RAS_AA_MSAA, &near_half, 0.5f}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ras_sample_pattern pat = cases[i].aa == RAS_AA_NONE ? ras_sample_pattern_center()
                                                            : pattern(RAS_PATTERN_ORDERED, 4);
        ras_triangle tris[2] = {far_full, *cases[i].near_t};
        vec3s got = render_pixel(tris, 2, cases[i].aa, pat);
        float f = cases[i].share;
        vec3s want = {{f, 0, 1 - f}}, sum = {{f, 0, 1}};
        CHECK(near3(got, want, 1e-5f),
              "%s%s: a far blue triangle over all of pixel (1, 1), then a near red one over %s "
              "of it: expected (%g, 0, %g) — red replaces blue where it is nearer — got "
              "(%g, %g, %g). Likely mistake: %s",
              ras_aa_mode_name(cases[i].aa), cases[i].aa == RAS_AA_NONE ? "" : " 4x",
              f == 1 ? "all" : "half", want.x, want.z, got.x, got.y, got.z,
              f < 1 && near3(got, RED, 1e-5f) && inside_answers_at_corner()
                  ? "the near red triangle took all four samples although it covers two, and "
                    "inside_triangle, called on other points, answers for each as for its "
                    "pixel's corner: " INT_SIGNATURE_HABIT "."
              : near3(got, sum, 1e-5f)
                  ? "the pixel is the SUM of both triangles' colours x their covered shares: "
                    ADDITIVE_MSAA "."
              : near3(got, BLUE, 1e-5f)
                  ? "the near red triangle lost everywhere: the depth test (smaller is closer, "
                    "z < depth[i]), see test_raster_depth_test_order."
                  : "the near triangle's colour not written to the samples it won.");
    }
}

/* A near red triangle over 2 of 4 samples, a far blue one over all 4: the
 * pixel is half red, half blue, in either drawing order. */
static void test_resolve_per_sample_depth(void **state) {
    (void)state;
    ras_triangle near_half = tri_z(tri3(-10, -10, 1.5f, -10, 1.5f, 40), 0.2f, RED);
    ras_triangle far_full = tri_z(tri3(-10, -10, 40, -10, -10, 40), 0.8f, BLUE);
    for (int m = 0; m < 2; m++)
        for (int order = 0; order < 2; order++) {
            ras_triangle tris[2] = {order ? far_full : near_half, order ? near_half : far_full};
            ras_aa_mode aa = m ? RAS_AA_SSAA : RAS_AA_MSAA;
            vec3s got = render_pixel(tris, 2, aa, pattern(RAS_PATTERN_ORDERED, 4));
            vec3s want = {{0.5f, 0, 0.5f}};
            CHECK(near3(got, want, 1e-5f),
                  "%s 4x: near red triangle over 2 of 4 samples, far blue one over all, %s drawn "
                  "first: expected (0.5, 0, 0.5), got (%g, %g, %g). Likely mistake: %s",
                  ras_aa_mode_name(aa), order ? "blue" : "red", got.x, got.y, got.z,
                  (order && near3(got, (vec3s){{0.5f, 0, 1}}, 1e-5f))
                      ? "the pixel is the SUM of what each triangle drew, blue x 4/4 + red x "
                        "2/4 = (0.5, 0, 1): " ADDITIVE_MSAA "."
                  : (got.z == 0 && got.x > 0.4f && inside_answers_at_corner())
                      ? "the near red triangle took all four samples although it covers two, "
                        "and inside_triangle, called on other points, answers for each as for "
                        "its pixel's corner: " INT_SIGNATURE_HABIT "."
                  : (got.z == 0 && got.x > 0.4f) ? "depth kept per PIXEL: the near triangle's depth "
                                                 "blocked the far one on samples it does not cover."
                  : got.x == 0 ? "the far triangle overwrote the near one: the depth test per "
                                 "sample (z < depth[sample]) is missing or reversed."
                               : "colour kept per pixel instead of per sample.");
        }
}

/* ---- 6. the classic scene ------------------------------------------------------------------ */

#define SIDE 700

/* The GAMES101 projection for fov 45°, aspect 1, near 0.1, far 50, written
 * out here (n = -0.1, f = -50) so hw2's tests do not depend on hw1. */
static mat4s classic_projection(void) {
    float cot = (float)(1.0 / tan(22.5 * RAS_PI / 180)), n = -0.1f, f = -50;
    return ras_mat4_rows(-cot, 0, 0, 0, 0, -cot, 0, 0, 0, 0, (n + f) / (n - f),
                         -2 * n * f / (n - f), 0, 0, 1, 0);
}

static const float GREEN_POS[3][3] = {{2, 0, -2}, {0, 2, -2}, {-2, 0, -2}};
static const float BLUE_POS[3][3] = {{3.5f, -1, -5}, {2.5f, 1.5f, -5}, {-1, 0.5f, -5}};
static const unsigned char GREEN8[3] = {217, 238, 185}, BLUE8[3] = {185, 217, 238};

static ras_image *render_scene(ras_aa_mode aa, ras_pattern_kind kind, int samples) {
    ras_error err = {{0}};
    ras_pipeline_config cfg = {.width = SIDE,
                               .height = SIDE,
                               .aa = aa,
                               .varyings = RAS_VARYING_COLOR,
                               .rasterize = rasterize_triangle,
                               .resolve = resolve_pixel};
    cfg.pattern = aa == RAS_AA_NONE ? ras_sample_pattern_center() : pattern(kind, samples);
    ras_pipeline *p = ras_pipeline_create(&cfg, &err);
    if (!p) fail_msg("test setup: %s", err.msg);
    ras_mesh *m[2];
    for (int i = 0; i < 2; i++) {
        const float(*v)[3] = i ? BLUE_POS : GREEN_POS;
        const unsigned char *c = i ? BLUE8 : GREEN8;
        m[i] = ras_mesh_create_triangle((vec3s){{v[0][0], v[0][1], v[0][2]}},
                                        (vec3s){{v[1][0], v[1][1], v[1][2]}},
                                        (vec3s){{v[2][0], v[2][1], v[2][2]}},
                                        (vec3s){{c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f}});
        assert_non_null(m[i]);
    }
    ras_pipeline_begin_frame(p);
    for (int i = 0; i < 2; i++)
        assert_true(ras_pipeline_draw_mesh(p, m[i], glms_mat4_identity(),
                                           ras_view_matrix_eye((vec3s){{0, 0, 5}}),
                                           classic_projection(), &err));
    ras_image *img = ras_image_create(SIDE, SIDE, &err);
    assert_non_null(img);
    ras_pipeline_end_frame(p, img);
    ras_pipeline_destroy(p);
    ras_mesh_destroy(m[0]);
    ras_mesh_destroy(m[1]);
    return img;
}

/* Hand projection: eye at z = 5 looking down -z, so a point at world z sits
 * d = 5 - z ahead; x_ndc = x·cot(22.5°)/d, screen x = (x_ndc + 1)·350.
 * (2, 0, -2) → x_ndc = 2·2.41421/7 = 0.68978 → screen x = 591.42. */
static void project_by_hand(const float (*pos)[3], double out[3][2]) {
    double cot = 1.0 / tan(22.5 * RAS_PI / 180);
    for (int i = 0; i < 3; i++) {
        double d = 5 - pos[i][2];
        out[i][0] = (pos[i][0] * cot / d + 1) * SIDE / 2;
        out[i][1] = (pos[i][1] * cot / d + 1) * SIDE / 2;
    }
}

/* Signed distance in pixels from (px, py) to the nearest edge: > 0 inside. */
static double inside_distance(const double v[3][2], double px, double py) {
    double area = edge_exact(v[0][0], v[0][1], v[1][0], v[1][1], v[2][0], v[2][1]);
    double best = INFINITY;
    for (int i = 0; i < 3; i++) {
        const double *a = v[i], *b = v[(i + 1) % 3];
        double len = hypot(b[0] - a[0], b[1] - a[1]);
        double d = edge_exact(a[0], a[1], b[0], b[1], px, py) / len * (area > 0 ? 1 : -1);
        best = d < best ? d : best;
    }
    return best;
}

static bool pixel_is(const ras_image *img, int x, int y, const unsigned char *rgb) {
    vec3s c = ras_image_get(img, x, SIDE - 1 - y);
    return ras_unit_to_byte(c.x) == rgb[0] && ras_unit_to_byte(c.y) == rgb[1] &&
           ras_unit_to_byte(c.z) == rgb[2];
}

/* Independent checks of a classic-scene image, from hand-computed vertex
 * positions only: pixels well inside a triangle have its exact colour, the
 * overlap shows the nearer (green) one, the background is black; with
 * anti-aliasing, pixels straddling green's left edge are mixtures. */
static void check_scene_image(const ras_image *img, const char *what, bool antialiased,
                              bool inside_at_corner) {
    double g[3][2], b[3][2];
    project_by_hand(GREEN_POS, g);
    project_by_hand(BLUE_POS, b);
    static const unsigned char black8[3] = {0, 0, 0};
    long checked = 0, mixtures = 0, edge_pixels = 0;
    for (int y = 0; y < SIDE; y += 3)
        for (int x = 0; x < SIDE; x += 3) {
            double dg = inside_distance(g, x + 0.5, y + 0.5),
                   db = inside_distance(b, x + 0.5, y + 0.5);
            const unsigned char *want = NULL;
            const char *region = NULL;
            if (dg > 1.5)
                want = GREEN8, region = db > 1.5 ? "the overlap (green is nearer)" : "green";
            else if (dg < -1.5 && db > 1.5)
                want = BLUE8, region = "blue only";
            else if (dg < -1.5 && db < -1.5)
                want = black8, region = "background";
            if (!want) continue;
            checked++;
            if (!pixel_is(img, x, y, want)) {
                vec3s c = ras_image_get(img, x, SIDE - 1 - y);
                bool got_blue =
                    ras_unit_to_byte(c.x) == BLUE8[0] && ras_unit_to_byte(c.z) == BLUE8[2];
                fail_msg("%s: screen pixel (%d, %d) (image col %d, row %d) is in %s: expected "
                         "(%d, %d, %d), got (%d, %d, %d). Likely mistake: %s",
                         what, x, y, x, SIDE - 1 - y, region, want[0], want[1], want[2],
                         ras_unit_to_byte(c.x), ras_unit_to_byte(c.y), ras_unit_to_byte(c.z),
                         (want == GREEN8 && got_blue) ? "the depth test reversed — blue drawn over "
                                                        "green (smaller depth is closer)."
                         : want == black8
                             ? "coverage outside the triangle (bounding box filled, or "
                               "an inside test with the wrong sign)."
                             : "missing coverage (a wrong inside test), or a y-flip "
                               "missing (the picture upside down).");
            }
        }
    assert_true(checked > 10000);
    if (!antialiased) return;
    /* Green's left edge, from (108.6, 350) to (350, 591.4), away from blue
     * and from the vertices: pixels whose centre is within 0.4 px of it
     * (on this 45-degree edge the nearest centres are 0.30 px away). */
    for (int y = 380; y < 560; y++)
        for (int x = 100; x < 400; x++) {
            double dg = inside_distance(g, x + 0.5, y + 0.5);
            if (fabs(dg) > 0.4) continue;
            edge_pixels++;
            vec3s c = ras_image_get(img, x, SIDE - 1 - y);
            int gch = ras_unit_to_byte(c.y);
            if (gch > 0 && gch < GREEN8[1]) mixtures++;
        }
    CHECK(edge_pixels > 50 && mixtures * 10 >= edge_pixels * 9,
          "%s: of %ld pixels whose centre lies within 0.4 px of the green triangle's left edge, "
          "expected at least 90%% to mix green and black, got %ld. Likely mistake: %s",
          what, edge_pixels, mixtures,
          inside_at_corner
              ? "every sample of a pixel covered alike, and inside_triangle, called on other "
                "points, answers for each as for its pixel's corner: " INT_SIGNATURE_HABIT "."
              : "samples all at the pixel centre (no anti-aliasing), or the resolve picks one "
                "sample.");
}

static ras_image *load_reference(const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/reference/%s", RAS_SOURCE_DIR, name);
    ras_error err = {{0}};
    ras_image *img = ras_image_load(path, &err);
    if (!img)
        fail_msg("cannot read the reference image %s: %s (regenerate with "
                 "`make reference-images`)",
                 path, err.msg);
    CHECK(img->width == SIDE && img->height == SIDE, "reference %s: expected 700x700, got %dx%d",
          path, img->width, img->height);
    return img;
}

/* The reference PNGs themselves pass the hand-computed checks. */
static void test_scene_reference_images_sane(void **state) {
    (void)state;
    const struct {
        const char *file;
        bool aa;
    } refs[] = {{"hw2_1x.png", false},
                {"hw2_msaa4.png", true},
                {"hw2_ssaa4.png", true},
                {"hw2_msaa4_standard.png", true}};
    for (size_t i = 0; i < sizeof refs / sizeof refs[0]; i++) {
        ras_image *img = load_reference(refs[i].file);
        check_scene_image(img, refs[i].file, refs[i].aa, false);
        ras_image_destroy(img);
    }
}

/* Green (z = -2) is in front of blue (z = -5) where they overlap. */
static void test_scene_depth_order(void **state) {
    (void)state;
    ras_image *img = render_scene(RAS_AA_NONE, RAS_PATTERN_ORDERED, 1);
    /* (350, 400) is inside both triangles by the hand projection. */
    vec3s c = ras_image_get(img, 350, SIDE - 1 - 400);
    CHECK(pixel_is(img, 350, 400, GREEN8),
          "classic scene, screen pixel (350, 400) where both triangles overlap: expected green "
          "(217, 238, 185) in front, got (%d, %d, %d). Likely mistake: %s",
          ras_unit_to_byte(c.x), ras_unit_to_byte(c.y), ras_unit_to_byte(c.z),
          pixel_is(img, 350, 400, BLUE8) ? "the depth test reversed (draw when z < depth)."
          : why_nothing_drawn()          ? why_nothing_drawn()
                                         : "nothing or something else drawn there.");
    check_scene_image(img, "your 1x render", false, false);
    ras_image_destroy(img);
}

static void compare_scene(const char *ref_name, ras_aa_mode aa, ras_pattern_kind kind,
                          int samples) {
    /* Rendered first: in grading the student's frame is recorded in a sandbox
     * that has no reference images (tests/grading/ras_call.h). */
    ras_image *got = render_scene(aa, kind, samples);
    /* the evidence for a diagnosis too: the record ends at the reference */
    bool at_corner = aa != RAS_AA_NONE && inside_answers_at_corner();
    ras_image *want = load_reference(ref_name);
    check_scene_image(got, ref_name, aa != RAS_AA_NONE, at_corner);
    /* Edge-tolerant, and with AA one sample's worth more: a vertex that lands
     * 1/256 px elsewhere (another rounding of the same projection, or float
     * edge functions) flips single samples along the shallow edges — not a
     * bug. A missing, extra or swapped triangle still costs its whole area. */
    ras_compare_options opt = ras_compare_defaults(RAS_COMPARE_EDGE_TOLERANT);
    if (aa != RAS_AA_NONE) opt.tolerance += 255 / samples;
    ras_compare_result res;
    ras_error err = {{0}};
    assert_true(ras_compare_images(want, got, &opt, &res, &err));
    if (!res.pass) {
        char mask[1200];
        ras_compare_ascii_mask(want, got, (vec3s){{0, 0, 0}}, res.worst_col, res.worst_row, 10,
                               mask, sizeof mask, NULL);
        fail_msg("classic scene vs tests/reference/%s: %s\nAround the worst pixel (%d, %d) "
                 "(image col, row), %s:\n%s",
                 ref_name, res.summary, res.worst_col, res.worst_row, RAS_COMPARE_ASCII_LEGEND,
                 mask);
    }
    ras_image_destroy(want);
    ras_image_destroy(got);
}

static void test_scene_matches_reference_1x(void **state) {
    (void)state;
    compare_scene("hw2_1x.png", RAS_AA_NONE, RAS_PATTERN_ORDERED, 1);
}

static void test_scene_matches_reference_msaa4(void **state) {
    (void)state;
    compare_scene("hw2_msaa4.png", RAS_AA_MSAA, RAS_PATTERN_ORDERED, 4);
}

static void test_scene_matches_reference_ssaa4(void **state) {
    (void)state;
    compare_scene("hw2_ssaa4.png", RAS_AA_SSAA, RAS_PATTERN_ORDERED, 4);
}

static void test_scene_matches_reference_msaa4_standard(void **state) {
    (void)state;
    compare_scene("hw2_msaa4_standard.png", RAS_AA_MSAA, RAS_PATTERN_STANDARD, 4);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inside_basic_both_windings),
        cmocka_unit_test(test_inside_on_edges_and_vertices),
        cmocka_unit_test(test_inside_degenerate_is_empty),
        cmocka_unit_test(test_inside_shared_edge_exactly_once),
        cmocka_unit_test(test_inside_fan_watertight),
        cmocka_unit_test(test_bary_vertices_centroid_sum),
        cmocka_unit_test(test_bary_outside_is_negative),
        cmocka_unit_test(test_bary_degenerate_flagged),
        cmocka_unit_test(test_bary_at_pixel_centre),
        cmocka_unit_test(test_raster_depth_with_different_w),
        cmocka_unit_test(test_bary_precision_at_600px),
        cmocka_unit_test(test_index_corners_and_flip),
        cmocka_unit_test(test_index_all_in_range_and_distinct),
        cmocka_unit_test(test_index_rasterizer_writes_flipped),
        cmocka_unit_test(test_raster_box_maximum_included),
        cmocka_unit_test(test_raster_samples_from_pattern),
        cmocka_unit_test(test_raster_clamped_to_screen),
        cmocka_unit_test(test_raster_rejects_nan_and_zero_area),
        cmocka_unit_test(test_raster_depth_test_order),
        cmocka_unit_test(test_raster_counters),
        cmocka_unit_test(test_resolve_box_filter_float),
        cmocka_unit_test(test_resolve_half_covered_pixel),
        cmocka_unit_test(test_resolve_no_dark_seam),
        cmocka_unit_test(test_resolve_per_sample_depth),
        cmocka_unit_test(test_resolve_overdraw_replaces),
        cmocka_unit_test(test_scene_reference_images_sane),
        cmocka_unit_test(test_scene_depth_order),
        cmocka_unit_test(test_scene_matches_reference_1x),
        cmocka_unit_test(test_scene_matches_reference_msaa4),
        cmocka_unit_test(test_scene_matches_reference_ssaa4),
        cmocka_unit_test(test_scene_matches_reference_msaa4_standard),
    };
    return RAS_RUN_TESTS("hw2", tests, NULL, NULL);
}
