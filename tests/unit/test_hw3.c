/* test_hw3.c — cmocka tests for hw3_shading (shading.h), run twice:
 * test_hw3_ref against solution/shading.c (must pass) and test_hw3_student
 * against the student's shading.c.
 *
 * Groups (docs/hw3.md has the maths behind each):
 *   interp    perspective-correct interpolation on a tilted plane whose screen
 *             vertices are projected here by hand, against the exact UV from a
 *             ray-plane intersection; affine shown wrong by (√k−1)/(√k+1);
 *             the w = 1 pitfall
 *   shaders   one fragment per shader against values worked out by hand (the
 *             arithmetic is in the comments); the ambient-per-light mistake
 *   tbn       the tangent frame at n = (0, ±1, 0): finite, unit, perpendicular
 *   bilinear  texel centres, between centres, edges, u,v = 0, 1, −ε, 1+ε,
 *             NaN, ±1e30, ±Inf, both wraps
 *   stages    each shader reads only its varyings; no texture, no texel
 *   scene     model loading errors; whole images of the default scene against
 *             tests/reference/hw3_*.png, each reference sanity-checked by hand
 * Every failure says what was expected, what came, and the likely mistake.
 *
 * The whole-image tests project with a matrix written out here, not the
 * student's hw1, so hw3 is graded on its own hw1; the rasterizer is the
 * student's hw2 (hw3 builds on it, as in the course).
 */
#include <setjmp.h> /* cmocka needs these before cmocka.h */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ras_builtin_scenes.h"
#include "ras_compare.h"
#include "ras_test_main.h"
#include "scene.h"
#include "shading.h"

#include <math.h>   /* fabs, sqrt, tan, NAN, INFINITY */
#include <stdio.h>  /* snprintf, fopen */
#include <stdlib.h> /* free */
#include <string.h> /* strlen */
#include <unistd.h> /* unlink */

#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) fail_msg(__VA_ARGS__);                                                        \
    } while (0)

static bool near3(vec3s a, vec3s b, float tol) {
    return fabsf(a.x - b.x) <= tol && fabsf(a.y - b.y) <= tol && fabsf(a.z - b.z) <= tol;
}

#define V3(x, y, z) ((vec3s){{(x), (y), (z)}})
#define FMT3 "(%.6f, %.6f, %.6f)"
#define ARG3(v) (double)(v).x, (double)(v).y, (double)(v).z

/* ---- interp: a tilted textured plane, projected by hand --------------------
 *
 * View-space triangle (camera at the origin looking down -z):
 *   P0 = (-1, -1, -2)  uv (0, 0)     clip w = -z = 2
 *   P1 = ( 1, -1, -6)  uv (1, 0)     clip w = 6
 *   P2 = (-1,  1, -2)  uv (0, 1)     clip w = 2
 * A pinhole with focal length F = 50 px on a 100×100 screen:
 *   x_s = 50 + F·X/(−Z), y_s = 50 + F·Y/(−Z)
 *   P0 → (25, 25), P1 → (58.333, 41.667), P2 → (25, 75).
 * The plane is tilted away from the camera (w goes 2 → 6 along P0→P1), so
 * uv is NOT affine in screen space. The exact uv at a screen point: the ray
 * o + τ·d, d = ((x_s−50)/F, (y_s−50)/F, −1), meets the plane at
 * P0 + s·(P1−P0) + t·(P2−P0), and then uv = (s, t). */
static const double P[3][3] = {{-1, -1, -2}, {1, -1, -6}, {-1, 1, -2}};
#define FOCAL 50.0

static ras_triangle tilted_plane(void) {
    ras_triangle t = {0};
    for (int i = 0; i < 3; i++) {
        double w = -P[i][2];
        /* depth: any increasing function of w that is affine in 1/w will do */
        t.v[i] = (vec4s){{(float)(50 + FOCAL * P[i][0] / w), (float)(50 + FOCAL * P[i][1] / w),
                          (float)(1 - 1 / w), (float)w}};
        t.normal[i] = V3(0, 0, 1);
    }
    t.uv[0] = (vec2s){{0, 0}};
    t.uv[1] = (vec2s){{1, 0}};
    t.uv[2] = (vec2s){{0, 1}};
    return t;
}

/* Screen barycentrics of (x, y) in t, in double. */
static vec3s screen_bary(const ras_triangle *t, double x, double y) {
    double x0 = t->v[0].x, y0 = t->v[0].y, x1 = t->v[1].x, y1 = t->v[1].y, x2 = t->v[2].x,
           y2 = t->v[2].y;
    double area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    double l1 = ((x - x0) * (y2 - y0) - (x2 - x0) * (y - y0)) / area;
    double l2 = ((x1 - x0) * (y - y0) - (x - x0) * (y1 - y0)) / area;
    return V3((float)(1 - l1 - l2), (float)l1, (float)l2);
}

/* The exact (s, t) by ray-plane intersection: solve
 * τ·d − s·e1 − t·e2 = P0 with Cramer's rule. */
static void exact_uv(double xs, double ys, double *s, double *t) {
    double d[3] = {(xs - 50) / FOCAL, (ys - 50) / FOCAL, -1};
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = P[1][k] - P[0][k];
        e2[k] = P[2][k] - P[0][k];
    }
    /* columns: d, -e1, -e2; right-hand side P0 */
    double m[3][3], r[3];
    for (int k = 0; k < 3; k++) {
        m[k][0] = d[k];
        m[k][1] = -e1[k];
        m[k][2] = -e2[k];
        r[k] = P[0][k];
    }
#define DET3(a)                                                                                    \
    ((a)[0][0] * ((a)[1][1] * (a)[2][2] - (a)[1][2] * (a)[2][1]) -                                 \
     (a)[0][1] * ((a)[1][0] * (a)[2][2] - (a)[1][2] * (a)[2][0]) +                                 \
     (a)[0][2] * ((a)[1][0] * (a)[2][1] - (a)[1][1] * (a)[2][0]))
    double det = DET3(m);
    double ms[3][3], mt[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            ms[i][j] = mt[i][j] = m[i][j];
    for (int k = 0; k < 3; k++) {
        ms[k][1] = r[k];
        mt[k][2] = r[k];
    }
    *s = DET3(ms) / det;
    *t = DET3(mt) / det;
#undef DET3
}

/* Perspective-correct uv matches the ray-plane intersection everywhere on
 * the tilted plane. */
static void test_interp_tilted_plane_exact(void **state) {
    (void)state;
    ras_triangle t = tilted_plane();
    ras_triangle t_w1 = t, t_z = t;
    for (int i = 0; i < 3; i++) {
        t_w1.v[i].w = 1.0f;
        t_z.v[i].w = t.v[i].z;
    }
    int checked = 0;
    for (double y = 26; y < 74; y += 3.7)
        for (double x = 25.5; x < 58; x += 2.9) {
            vec3s bary = screen_bary(&t, x, y);
            if (bary.x < 0 || bary.y < 0 || bary.z < 0) continue;
            double s, tt;
            exact_uv(x, y, &s, &tt);
            vec2s got = interpolate_vec2(&t, bary, t.uv, true);
            checked++;
            if (fabs(got.x - s) <= 2e-5 && fabs(got.y - tt) <= 2e-5) continue;
            /* What would the classic mistakes give here? */
            vec2s affine = {{bary.y, bary.z}}; /* uv1 = (1,0), uv2 = (0,1) */
            vec2s with_z = interpolate_vec2(&t_z, bary, t.uv, true);
            (void)t_w1;
            const char *hint = "check b_i = λ_i / w_i and the division by their sum";
            /* The affine value first: it is known exactly, while the "divided by
             * z" probe runs the student's own function, which ignores w
             * altogether in the affine mistake and so matches it too. */
            bool is_affine = fabsf(got.x - affine.x) < 1e-5f && fabsf(got.y - affine.y) < 1e-5f;
            if (is_affine)
                hint = "this is the AFFINE value: the 1/w correction is missing (w forced to 1 "
                       "as the course framework's toVector4 does, or `perspective` ignored) — "
                       "the w = 1 pitfall, docs/hw3.md section 1";
            else if (fabsf(got.x - with_z.x) < 1e-4f && fabsf(got.y - with_z.y) < 1e-4f)
                hint = "you divided by the screen depth v[i].z; the correction needs the clip "
                       "w kept in v[i].w";
            fail_msg("interpolate_vec2 on the tilted plane at screen (%.2f, %.2f): expected uv "
                     "(%.6f, %.6f) (ray-plane intersection), got (%.6f, %.6f). Likely mistake: %s",
                     x, y, s, tt, (double)got.x, (double)got.y, hint);
        }
    CHECK(checked > 50, "test setup: only %d points inside the triangle", checked);
}

/* Along an edge whose w ratio is k = w1/w0 = 3, affine interpolation is wrong
 * by at most (√k−1)/(√k+1) = 0.26795, at σ = √k/(√k+1) of the way on screen;
 * the perspective-correct value there is s = σ/k / ((1−σ) + σ/k). */
static void test_interp_affine_error_matches_theory(void **state) {
    (void)state;
    ras_triangle t = tilted_plane();
    double worst = 0, worst_sigma = 0;
    for (int i = 0; i <= 1000; i++) {
        float sigma = (float)i / 1000.0f;
        vec3s bary = V3(1 - sigma, sigma, 0);
        vec2s correct = interpolate_vec2(&t, bary, t.uv, true);
        vec2s affine = interpolate_vec2(&t, bary, t.uv, false);
        CHECK(fabsf(affine.x - sigma) < 1e-6f,
              "interpolate_vec2(perspective = false) at screen fraction %.3f of the edge "
              "uv 0 → 1: expected the affine %.6f, got %.6f. Likely mistake: %s",
              (double)sigma, (double)sigma, (double)affine.x,
              fabsf(affine.x - correct.x) < 1e-6f
                  ? "the 1/w correction applied with perspective = false too: the affine path "
                    "uses the screen barycentrics as they are"
                  : "the affine path must use the screen barycentrics as they are");
        double k = 3.0, s_exact = (sigma / k) / ((1 - sigma) + sigma / k);
        /* the classic wrong weights on this edge (w0 = 2, w1 = 6) */
        double times_w = sigma * 6 / ((1 - sigma) * 2 + sigma * 6), no_sum = sigma / 6;
        CHECK(fabs(correct.x - s_exact) < 2e-6,
              "perspective-correct u at screen fraction %.3f along the edge (w 2 → 6): "
              "expected %.6f = (σ/w1)/((1−σ)/w0 + σ/w1), got %.6f. Likely mistake: %s",
              (double)sigma, s_exact, (double)correct.x,
              fabs(correct.x - sigma) < 2e-6
                  ? "this is the AFFINE value: the 1/w correction is missing (w forced to 1 as "
                    "the course framework's toVector4 does, or `perspective` ignored) — the w = 1 "
                    "pitfall, docs/hw3.md section 1"
              : fabs(correct.x - times_w) < 2e-6
                  ? "the weights multiplied by w: b_i = λ_i / w_i, not λ_i · w_i"
              : fabs(correct.x - no_sum) < 2e-6
                  ? "the weights λ_i / w_i not divided by their sum Σ λ_j / w_j"
                  : "b_i = (λ_i / w_i) / Σ (λ_j / w_j), then attr = Σ b_i · attr_i");
        double e = fabs(affine.x - correct.x);
        if (e > worst) worst = e, worst_sigma = sigma;
    }
    double theory = (sqrt(3.0) - 1) / (sqrt(3.0) + 1), sigma_theory = sqrt(3.0) / (sqrt(3.0) + 1);
    CHECK(fabs(worst - theory) < 1e-4 && fabs(worst_sigma - sigma_theory) < 2e-3,
          "worst affine error along the edge: expected %.5f at σ = %.3f, got %.5f at σ = %.3f. "
          "Likely mistake: the affine and the perspective-correct values differ from the "
          "formulas above by less than the per-point tolerance, but drift: b_i = (λ_i / w_i) / "
          "Σ (λ_j / w_j) in float, without rounding the weights",
          theory, sigma_theory, worst, worst_sigma);
}

/* The w = 1 pitfall: a pipeline that forgets the clip w (w = 1 everywhere)
 * makes perspective_correct_barycentric the identity — and the picture wrong
 * by up to 0.268 of the texture on this plane. */
static void test_interp_w1_pitfall_caught(void **state) {
    (void)state;
    ras_triangle t = tilted_plane(), t_w1 = t;
    for (int i = 0; i < 3; i++)
        t_w1.v[i].w = 1.0f;
    vec3s bary = V3(0.366f, 0.634f, 0.0f); /* σ = √3/(√3+1): the worst point */
    vec3s b_w1 = perspective_correct_barycentric(&t_w1, bary);
    CHECK(near3(b_w1, bary, 1e-6f),
          "with every w = 1, perspective_correct_barycentric should return the screen "
          "barycentrics " FMT3 ", got " FMT3 ". Likely mistake: it does not read t->v[i].w",
          ARG3(bary), ARG3(b_w1));
    vec3s b = perspective_correct_barycentric(&t, bary);
    /* b_1 = (0.634/6) / (0.366/2 + 0.634/6) = 0.10567 / 0.28867 = 0.36605 */
    CHECK(fabsf(b.y - 0.36605f) < 2e-4f && fabsf(b.x + b.y + b.z - 1) < 1e-5f,
          "perspective_correct_barycentric at λ = " FMT3 " with w = (2, 6, 2): expected "
          "(0.63395, 0.36605, 0), got " FMT3 ". %s",
          ARG3(bary), ARG3(b),
          near3(b, bary, 1e-5f)
              ? "Likely mistake: the w = 1 pitfall (the course framework's toVector4 sets w "
                "= 1; here t->v[i].w is the clip w) — the screen barycentrics came back "
                "unchanged"
              : "Likely mistake: b_i = λ_i / w_i, then divide by their sum");
    /* Vertices stay vertices; the result always sums to 1. */
    for (int i = 0; i < 3; i++) {
        vec3s e = {{i == 0, i == 1, i == 2}};
        vec3s g = perspective_correct_barycentric(&t, e);
        CHECK(near3(g, e, 1e-6f),
              "perspective_correct_barycentric at vertex %d: expected " FMT3 ", got " FMT3
              ". Likely mistake: the weights λ_i / w_i must be divided by their sum, so a vertex "
              "keeps weight 1",
              i, ARG3(e), ARG3(g));
    }
    vec3s attr[3] = {V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1)};
    vec3s c = interpolate_vec3(&t, bary, attr, true);
    CHECK(near3(c, b, 1e-5f),
          "interpolate_vec3 of the unit vectors should return the corrected barycentrics " FMT3
          ", got " FMT3 ". Likely mistake: %s",
          ARG3(b), ARG3(c),
          near3(c, bary, 1e-5f) ? "interpolate_vec3 ignores `perspective`: with true it weighs "
                                  "with perspective_correct_barycentric (TODO 1.3)"
                                : "interpolate_vec3 = Σ b_i · attr_i with b the corrected "
                                  "barycentrics (TODO 1.3)");
}

/* ---- shaders ---------------------------------------------------------------- */

static fragment_shader_payload base_payload(void) {
    fragment_shader_payload p = {0};
    p.view_pos = V3(0, 0, -10);
    p.normal = V3(0, 0, 1);
    p.ka = V3(0.005f, 0.005f, 0.005f);
    p.ambient_intensity = V3(10, 10, 10); /* ka·Ia = 0.05 */
    p.ks = V3(0.3f, 0.3f, 0.3f);
    p.p = 4;
    p.kh = 0.2f;
    p.kn = 0.1f;
    p.filter = FILTER_NEAREST;
    /* one light at (4, 0, -7): to it from P = (0,0,-10) is (4, 0, 3), r² = 25,
     * I/r² = 50/25 = 2, l = (0.8, 0, 0.6) */
    p.lights[0] = (light){{{4, 0, -7}}, {{50, 50, 50}}};
    p.light_count = 1;
    return p;
}

/* ---- Blinn-Phong diagnoses: the reference formula with one mistake applied --
 *
 * A failing shader test names the mistake whose colour, computed here in
 * double on the test's own case, is the colour the student's function
 * returned; candidates that give the right colour on the case cannot be
 * told apart there and are skipped. */
typedef struct bp_case {
    double P[3], n[3]; /* the point and its normal (view space) */
    vec3s kd;
    double ks, pw, ambient; /* ks, p and ka·Ia, all grey */
    int lights;
    double L[2][3], I[2];
} bp_case;

enum bp_mistake {
    BP_NO_LIGHTING = 1 << 0,
    BP_AMBIENT_PER_LIGHT = 1 << 1,
    BP_AMBIENT_OVER_R2 = 1 << 2,
    BP_NO_AMBIENT = 1 << 3,
    BP_NO_SPECULAR = 1 << 4,
    BP_REFLECTION = 1 << 5,
    BP_HALF_FROM_UNNORMALISED = 1 << 6,
    BP_HALF_NOT_NORMALISED = 1 << 7,
    BP_L_NOT_NORMALISED = 1 << 8,
    BP_V_NOT_NORMALISED = 1 << 9,
    BP_FIXED_EYE = 1 << 10,
    BP_NO_FALLOFF = 1 << 11,
    BP_FALLOFF_R = 1 << 12,
    BP_SPECULAR_NO_MAX = 1 << 13,
    BP_DIFFUSE_NO_MAX = 1 << 14,
};

/* In the order a message lists them when none matches. */
static const struct {
    unsigned mistake;
    const char *name;
} bp_mistakes[] = {
    {BP_NO_LIGHTING, "no lighting yet — the colour is kd itself (the placeholder)"},
    {BP_AMBIENT_PER_LIGHT,
     "the ambient term added once PER LIGHT; add ka·Ia once, outside the loop (TODO 2.2)"},
    {BP_AMBIENT_OVER_R2,
     "the ambient term divided by r² (ka·Ia / r² for each light): ambient light comes from no "
     "light and has no fall-off; add ka·Ia once, outside the loop (TODO 2.2)"},
    {BP_NO_AMBIENT, "the ambient term ka·Ia is missing"},
    {BP_NO_SPECULAR, "the specular term is missing (ks·(I/r²)·max(0, n·h)^p)"},
    {BP_REFLECTION, "the specular term used the reflection vector (r·v)^p: Blinn-Phong uses the "
                    "half vector h = normalize(l + v)"},
    {BP_HALF_FROM_UNNORMALISED,
     "the half vector from the UNNORMALISED light and view vectors, h = normalize((light − "
     "point) + (−point)), which leans towards the farther of light and eye: normalise l and v "
     "first, then h = normalize(l + v)"},
    {BP_HALF_NOT_NORMALISED, "the half vector h = l + v is not normalised: h = normalize(l + v)"},
    {BP_L_NOT_NORMALISED, "l is not normalised: l = normalize(light − point)"},
    {BP_V_NOT_NORMALISED, "v is not normalised: v = normalize(−point)"},
    {BP_FIXED_EYE, "the viewer at a fixed eye position (the course viewer's eye_pos = (0,0,10)): "
                   "points and lights are in view space, where the camera is the origin, so "
                   "v = normalize(−point) (TODO 2.1)"},
    {BP_NO_FALLOFF, "no 1/r² fall-off: divide the intensity by the squared distance to the light"},
    {BP_FALLOFF_R, "the intensity divided by the distance r, not by r² = (light − point)·(light − "
                   "point)"},
    {BP_SPECULAR_NO_MAX,
     "the specular term pow(n·h, p) without max(0, n·h): with the light behind the surface "
     "n·h < 0, and an even p makes it a highlight; pow(max(0, n·h), p) (TODO 2.4)"},
    {BP_DIFFUSE_NO_MAX, "the diffuse term without max(0, n·l): a light behind the surface darkens "
                        "it; clamp negative dot products (TODO 2.3)"},
};
#define BP_MISTAKES (sizeof bp_mistakes / sizeof *bp_mistakes)

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void unit3(double a[3]) {
    double l = sqrt(dot3(a, a));
    for (int k = 0; k < 3; k++)
        a[k] /= l;
}

/* The specular factor s (before pow) of one light for direction d = light −
 * point, the viewer direction v (unit unless BP_V_NOT_NORMALISED) and its
 * unnormalised form eye − point. */
static double bp_specular_base(unsigned m, const double n[3], const double l[3], const double v[3],
                               const double d[3], const double to_eye[3]) {
    double h[3];
    if (m & BP_REFLECTION) { /* r = 2(n·l)n − l, then r·v */
        double nl = dot3(n, l), r[3];
        for (int k = 0; k < 3; k++)
            r[k] = 2 * nl * n[k] - l[k];
        return dot3(r, v);
    }
    for (int k = 0; k < 3; k++)
        h[k] = m & BP_HALF_FROM_UNNORMALISED ? d[k] + to_eye[k] : l[k] + v[k];
    if (!(m & BP_HALF_NOT_NORMALISED)) unit3(h);
    return dot3(n, h);
}

/* Blinn-Phong of case c with the mistakes m applied (0: the right colour). */
static vec3s bp_colour(const bp_case *c, unsigned m) {
    if (m & BP_NO_LIGHTING) return c->kd;
    const double eye[3] = {0, 0, m & BP_FIXED_EYE ? 10 : 0};
    double n[3] = {c->n[0], c->n[1], c->n[2]}, to_eye[3], v[3];
    unit3(n);
    for (int k = 0; k < 3; k++)
        to_eye[k] = v[k] = eye[k] - c->P[k];
    if (!(m & BP_V_NOT_NORMALISED)) unit3(v);
    bool per_light = m & (BP_AMBIENT_PER_LIGHT | BP_AMBIENT_OVER_R2);
    double grey = per_light || (m & BP_NO_AMBIENT) ? 0 : c->ambient, diffuse = 0;
    for (int i = 0; i < c->lights; i++) {
        double d[3], l[3];
        for (int k = 0; k < 3; k++)
            d[k] = l[k] = c->L[i][k] - c->P[k];
        double r2 = dot3(d, d);
        grey += m & BP_AMBIENT_PER_LIGHT ? c->ambient
                : m & BP_AMBIENT_OVER_R2 ? c->ambient / r2
                                         : 0;
        if (!(m & BP_L_NOT_NORMALISED)) unit3(l);
        double fall = m & BP_NO_FALLOFF  ? c->I[i]
                      : m & BP_FALLOFF_R ? c->I[i] / sqrt(r2)
                                         : c->I[i] / r2;
        double nl = dot3(n, l), s = bp_specular_base(m, n, l, v, d, to_eye);
        diffuse += fall * (m & BP_DIFFUSE_NO_MAX ? nl : fmax(0, nl));
        if (!(m & BP_NO_SPECULAR))
            grey += c->ks * fall * pow(m & BP_SPECULAR_NO_MAX ? s : fmax(0, s), c->pw);
    }
    return V3((float)(grey + c->kd.x * diffuse), (float)(grey + c->kd.y * diffuse),
              (float)(grey + c->kd.z * diffuse));
}

static bool bp_near(vec3s a, vec3s b) {
    float tol = 1e-4f * (1 + fmaxf(fabsf(b.x), fmaxf(fabsf(b.y), fabsf(b.z))));
    return near3(a, b, tol);
}

static float dist3(vec3s a, vec3s b) { return glms_vec3_norm(glms_vec3_sub(a, b)); }

/* Appends the names of the mistakes (bits of m) to out, joined by "; and ". */
static void bp_names(char *out, size_t size, unsigned m) {
    for (size_t i = 0; i < BP_MISTAKES; i++)
        if (m & bp_mistakes[i].mistake) {
            size_t used = strlen(out);
            snprintf(out + used, size - used, "%s%s", used ? "; and " : "", bp_mistakes[i].name);
        }
}

/* The likely mistake behind `got` on case c, written into out: the one
 * mistake (or, when none, the pair) whose colour is got; when several give
 * got, all of them; when none, what was observed and the nearest candidates
 * in order. */
static const char *bp_diagnose(const bp_case *c, vec3s got, char *out, size_t size) {
    vec3s right = bp_colour(c, 0);
    unsigned found[8];
    int nfound = 0;
    for (int pairs = 0; pairs < 2 && nfound == 0; pairs++)
        for (size_t i = 0; i < BP_MISTAKES; i++)
            for (size_t j = pairs ? i + 1 : i; j < (pairs ? BP_MISTAKES : i + 1); j++) {
                unsigned m = bp_mistakes[i].mistake | bp_mistakes[j].mistake;
                vec3s cand = bp_colour(c, m);
                if (!bp_near(cand, right) && bp_near(got, cand) && nfound < 8) found[nfound++] = m;
            }
    out[0] = '\0';
    if (nfound == 1) {
        if (found[0] & (found[0] - 1)) snprintf(out, size, "two mistakes together: ");
        bp_names(out, size, found[0]);
        return out;
    }
    if (nfound > 1) {
        snprintf(out, size, "one of these %d, which give exactly this colour here: ", nfound);
        for (int k = 0; k < nfound; k++) {
            size_t used = strlen(out);
            snprintf(out + used, size - used, "%s(%d) ", k ? "; " : "", k + 1);
            bp_names(out, size, found[k]);
        }
        return out;
    }
    /* none: the nearest three single mistakes, nearest first */
    size_t order[BP_MISTAKES];
    for (size_t i = 0; i < BP_MISTAKES; i++)
        order[i] = i;
    for (size_t i = 1; i < BP_MISTAKES; i++)
        for (size_t j = i; j > 0 && dist3(got, bp_colour(c, bp_mistakes[order[j]].mistake)) <
                                        dist3(got, bp_colour(c, bp_mistakes[order[j - 1]].mistake));
             j--) {
            size_t t = order[j];
            order[j] = order[j - 1], order[j - 1] = t;
        }
    vec3s diff = glms_vec3_sub(got, right);
    snprintf(out, size,
             "no single classic mistake (nor two together) gives this colour here; observed: got "
             "− expected = " FMT3 "%s. Nearest first, check:",
             ARG3(diff),
             fabsf(diff.x - diff.y) < 1e-4f && fabsf(diff.y - diff.z) < 1e-4f
                 ? " (grey: the ambient or the specular term, which do not depend on kd)"
                 : " (not grey: a term multiplied by kd, the diffuse one)");
    for (int k = 0; k < 3; k++) {
        size_t used = strlen(out);
        vec3s cand = bp_colour(c, bp_mistakes[order[k]].mistake);
        snprintf(out + used, size - used, " (%d) %s (would give " FMT3 ")", k + 1,
                 bp_mistakes[order[k]].name, ARG3(cand));
    }
    return out;
}

/* The case of a payload from base_payload (kd, ks, p, ambient grey), whose
 * right colour the test worked by hand as `hand`. */
static bp_case bp_case_of(const fragment_shader_payload *p, vec3s kd, vec3s hand) {
    bp_case c = {.kd = kd,
                 .ks = p->ks.x,
                 .pw = p->p,
                 .ambient = p->ka.x * p->ambient_intensity.x,
                 .lights = p->light_count};
    for (int k = 0; k < 3; k++)
        c.P[k] = p->view_pos.raw[k], c.n[k] = p->normal.raw[k];
    for (int i = 0; i < c.lights; i++) {
        c.I[i] = p->lights[i].intensity.x;
        for (int k = 0; k < 3; k++)
            c.L[i][k] = p->lights[i].position.raw[k];
    }
    /* a test-setup check: the test's hand-worked colour agrees with bp_colour */
    CHECK(bp_near(bp_colour(&c, 0), hand),
          "test setup: the hand-worked colour " FMT3 " and the test's formula " FMT3 " differ",
          ARG3(hand), ARG3(bp_colour(&c, 0)));
    return c;
}

/* The worked example: (n + 1) / 2. */
static void test_shader_normal(void **state) {
    (void)state;
    fragment_shader_payload p = base_payload();
    vec3s c = normal_fragment_shader(&p);
    CHECK(near3(c, V3(0.5f, 0.5f, 1), 1e-6f),
          "normal (0,0,1): expected (0.5, 0.5, 1), got " FMT3 ". Likely mistake: the normal "
          "shader (given) was changed: it returns (normalize(n) + 1) / 2",
          ARG3(c));
    p.normal = V3(0.6f, 0, 0.8f);
    c = normal_fragment_shader(&p);
    CHECK(near3(c, V3(0.8f, 0.5f, 0.9f), 1e-6f),
          "normal (0.6,0,0.8): expected (0.8, 0.5, 0.9), got " FMT3 ". Likely mistake: the "
          "normal shader (given) was changed: it returns (normalize(n) + 1) / 2",
          ARG3(c));
}

/* One light, all three terms. P = (0,0,-10), n = (0,0,1), v = (0,0,1).
 *   ambient  ka·Ia = 0.005·10 = 0.05
 *   diffuse  kd·(I/r²)·max(0, n·l) = kd·2·0.6 = kd·1.2 = (0.6, 0.3, 0.12) for kd = (0.5, 0.25, 0.1)
 *   h = normalize(l + v) = normalize(0.8, 0, 1.6) = (0.44721, 0, 0.89443), n·h = 0.89443
 *   specular ks·(I/r²)·(n·h)^p = 0.3·2·0.89443⁴ = 0.3·2·0.64 = 0.384
 *   total    (1.034, 0.734, 0.554) */
static void test_shader_blinn_phong_one_light(void **state) {
    (void)state;
    fragment_shader_payload p = base_payload();
    p.color = V3(0.5f, 0.25f, 0.1f);
    vec3s c = phong_fragment_shader(&p);
    vec3s want = V3(1.034f, 0.734f, 0.554f);
    if (near3(c, want, 1e-4f)) {
        /* The same normal at length 2.5 (interpolated or perturbed normals are
         * not unit): blinn_phong_lighting must normalise it itself. */
        vec3s c2 = blinn_phong_lighting(&p, p.color, p.view_pos, V3(0, 0, 2.5f));
        CHECK(near3(c2, want, 1e-4f),
              "blinn_phong_lighting with the normal (0, 0, 2.5) instead of (0, 0, 1): expected "
              "the same " FMT3 ", got " FMT3 ". Likely mistake: the normal is not normalised "
              "(n = normalize(normal), TODO 2.1)",
              ARG3(want), ARG3(c2));
        return;
    }
    char hint[2048];
    bp_case bc = bp_case_of(&p, p.color, want);
    fail_msg("Blinn-Phong, one light at (4,0,-7), I = 50, P = (0,0,-10), n = (0,0,1), "
             "kd = (0.5,0.25,0.1), ks = 0.3, p = 4, ka·Ia = 0.05: expected " FMT3 ", got " FMT3
             ". Likely mistake: %s",
             ARG3(want), ARG3(c), bp_diagnose(&bc, c, hint, sizeof hint));
}

/* Blinn-Phong of one light in double (the test's own arithmetic), with the
 * viewer at `eye` (view space): the point's colour for kd, ks, p, ka·Ia. */
static vec3s blinn_phong_double(vec3s kd, const double P[3], const double n[3],
                                const double light_pos[3], double I, double ks, double pw,
                                double ambient, const double eye[3]) {
    double d[3], v[3], r2 = 0, vl = 0;
    for (int k = 0; k < 3; k++)
        d[k] = light_pos[k] - P[k], r2 += d[k] * d[k];
    for (int k = 0; k < 3; k++)
        v[k] = eye[k] - P[k], vl += v[k] * v[k];
    double l[3], h[3], hl = 0, nl = 0, nh = 0;
    for (int k = 0; k < 3; k++)
        l[k] = d[k] / sqrt(r2), v[k] /= sqrt(vl), h[k] = l[k] + v[k];
    for (int k = 0; k < 3; k++)
        hl += h[k] * h[k];
    for (int k = 0; k < 3; k++)
        nl += n[k] * l[k], nh += n[k] * h[k] / sqrt(hl);
    double spec = ks * I / r2 * pow(fmax(0, nh), pw), diff = I / r2 * fmax(0, nl);
    return V3((float)(ambient + kd.x * diff + spec), (float)(ambient + kd.y * diff + spec),
              (float)(ambient + kd.z * diff + spec));
}

/* A point OFF the view axis: the viewer direction is normalize(−point) (the
 * camera at the view-space origin), which only here differs from the course
 * viewer's fixed eye_pos = (0, 0, 10). */
static void test_shader_viewer_off_axis(void **state) {
    (void)state;
    fragment_shader_payload p = base_payload();
    p.color = V3(0.5f, 0.25f, 0.1f);
    p.view_pos = V3(3, 0, -4);
    p.p = 8;
    p.lights[0] = (light){{{6, 0, -1}}, {{50, 50, 50}}};
    const double P[3] = {3, 0, -4}, n[3] = {0, 0, 1}, L[3] = {6, 0, -1};
    const double origin[3] = {0, 0, 0};
    vec3s want = blinn_phong_double(p.color, P, n, L, 50, 0.3, 8, 0.05, origin);
    vec3s c = phong_fragment_shader(&p);
    char hint[2048];
    bp_case bc = bp_case_of(&p, p.color, want);
    CHECK(near3(c, want, 1e-4f),
          "Blinn-Phong at the off-axis point P = (3, 0, -4), n = (0,0,1), one light at (6,0,-1), "
          "I = 50, kd = (0.5,0.25,0.1), ks = 0.3, p = 8: expected " FMT3 ", got " FMT3
          ". Likely mistake: %s",
          ARG3(want), ARG3(c), bp_diagnose(&bc, c, hint, sizeof hint));
}

/* Ambient once: two lights at grazing incidence (n·l = 0, and (n·h)^150 =
 * 0.7071^150 ≈ 2.4e-23) contribute nothing, so the colour is ka·Ia = 0.05 —
 * 0.10 when the ambient term sits inside the light loop. */
static void test_shader_ambient_once_not_per_light(void **state) {
    (void)state;
    fragment_shader_payload p = base_payload();
    p.color = V3(1, 1, 1);
    p.p = 150;
    p.lights[0] = (light){{{10, 0, -10}}, {{500, 500, 500}}};
    p.lights[1] = (light){{{0, 10, -10}}, {{500, 500, 500}}};
    p.light_count = 2;
    vec3s c = phong_fragment_shader(&p);
    char hint[2048];
    bp_case bc = bp_case_of(&p, p.color, V3(0.05f, 0.05f, 0.05f));
    CHECK(near3(c, V3(0.05f, 0.05f, 0.05f), 1e-5f),
          "two grazing lights add nothing, so expected only the ambient (0.05, 0.05, 0.05), "
          "got " FMT3 ". Likely mistake: %s",
          ARG3(c), bp_diagnose(&bc, c, hint, sizeof hint));
}

/* The classic GAMES101 numbers at P = (0,0,-10), n = (0,0,1):
 *   light 1 (20,20,20): d = (20,20,30), r² = 1700, I/r² = 0.294118, n·l = 30/41.2311 = 0.727607
 *   light 2 (−20,20,0): d = (−20,20,10), r² = 900,  I/r² = 0.555556, n·l = 10/30 = 0.333333
 *   diffuse factor 0.294118·0.727607 + 0.555556·0.333333 = 0.399187
 *   specular: n·h = 0.92941 and 0.81650, ^150 → 1.7e-5 and 6e-14: ≈ 0
 *   kd = (148,121,92)/255 → 0.05 + kd·0.399187 = (0.281689, 0.239422, 0.194024) */
static void test_shader_blinn_phong_classic_numbers(void **state) {
    (void)state;
    fragment_shader_payload p = base_payload();
    p.color = V3(148 / 255.0f, 121 / 255.0f, 92 / 255.0f);
    p.ks = V3(0.7937f, 0.7937f, 0.7937f);
    p.p = 150;
    p.lights[0] = (light){{{20, 20, 20}}, {{500, 500, 500}}};
    p.lights[1] = (light){{{-20, 20, 0}}, {{500, 500, 500}}};
    p.light_count = 2;
    vec3s c = phong_fragment_shader(&p);
    vec3s want = V3(0.281689f, 0.239422f, 0.194024f);
    char hint[2048];
    bp_case bc = bp_case_of(&p, p.color, want);
    CHECK(near3(c, want, 1e-4f),
          "Blinn-Phong with the GAMES101 lights and material: expected " FMT3 ", got " FMT3
          ". Likely mistake: %s",
          ARG3(want), ARG3(c), bp_diagnose(&bc, c, hint, sizeof hint));
}

/* A light behind the surface: n = (0.6, 0, 0.8) at P = (0,0,-10), the light
 * 5 units along l = −n at (−3, 0, −14), I/r² = 50/25 = 2. n·l = −1, so no
 * diffuse; h = normalize(l + v) = normalize(−0.6, 0, 0.2) = (−0.948683, 0,
 * 0.316228), n·h = −0.316228 < 0, so no specular either: only the ambient
 * (0.05, 0.05, 0.05). Without max(0, ·) the EVEN exponent p = 2 turns n·h < 0
 * into (n·h)² = 0.1 and a highlight of 0.3·2·0.1 = 0.06: 0.11. */
static void test_shader_blinn_phong_light_behind(void **state) {
    (void)state;
    fragment_shader_payload p = base_payload();
    p.color = V3(0.5f, 0.25f, 0.1f);
    p.normal = V3(0.6f, 0, 0.8f);
    p.p = 2;
    p.lights[0] = (light){{{-3, 0, -14}}, {{50, 50, 50}}};
    vec3s c = phong_fragment_shader(&p);
    vec3s want = V3(0.05f, 0.05f, 0.05f);
    char hint[2048];
    bp_case bc = bp_case_of(&p, p.color, want);
    CHECK(near3(c, want, 1e-4f),
          "Blinn-Phong with the light behind the surface (n = (0.6,0,0.8) at P = (0,0,-10), "
          "light at (-3,0,-14), n·l = -1, n·h = -0.316, I = 50, ks = 0.3, p = 2): expected "
          "only the ambient " FMT3 ", got " FMT3 ". Likely mistake: %s",
          ARG3(want), ARG3(c), bp_diagnose(&bc, c, hint, sizeof hint));
}

/* A 2×2 texture, built from an image whose TOP row is (red, green) and bottom
 * row (blue-ish (0.2,0.4,0.6), white): v = 0 is the bottom. */
static ras_texture *two_by_two(ras_wrap wrap) {
    ras_image *img = ras_image_create(2, 2, NULL);
    assert_non_null(img);
    ras_image_set(img, 0, 0, V3(1, 0, 0));
    ras_image_set(img, 1, 0, V3(0, 1, 0));
    ras_image_set(img, 0, 1, V3(0.2f, 0.4f, 0.6f));
    ras_image_set(img, 1, 1, V3(1, 1, 1));
    ras_error err = {{0}};
    ras_texture *tex = ras_texture_from_image(img, wrap, &err);
    ras_image_destroy(img);
    CHECK(tex, "test setup: %s", err.msg);
    return tex;
}

/* kd from the texture: uv (0.25, 0.25) is the bottom-left texel (0.2,0.4,0.6).
 * Same light as the one-light test: 0.05 + kd·1.2 + 0.384 = (0.674, 0.914, 1.154). */
static void test_shader_texture_kd_from_texture(void **state) {
    (void)state;
    ras_texture *tex = two_by_two(RAS_WRAP_CLAMP);
    fragment_shader_payload p = base_payload();
    p.color = V3(0, 0, 0);
    p.texture = tex;
    p.uv = (vec2s){{0.25f, 0.25f}};
    vec3s c = texture_fragment_shader(&p);
    vec3s want = V3(0.674f, 0.914f, 1.154f);
    char lighting[2048];
    bp_case bc = bp_case_of(&p, V3(0.2f, 0.4f, 0.6f), want);
    const char *hint = lighting;
    if (near3(c, V3(0.434f, 0.434f, 0.434f), 1e-4f))
        hint = "the texture was not read: kd is still payload->color";
    else if (near3(c, V3(1.634f, 0.434f, 0.434f), 1e-4f))
        hint = "v flipped twice: the texture already stores the bottom row at v = 0";
    else if (strncmp(bp_diagnose(&bc, c, lighting, sizeof lighting), "no single", 9) == 0)
        hint = "kd is not the texel (0.2, 0.4, 0.6) read at uv with texture_sample(payload, "
               "payload->texture, payload->uv), or the lighting differs from section 2 in a way "
               "no classic mistake explains";
    ras_texture_destroy(tex);
    CHECK(near3(c, want, 1e-4f),
          "texture shader at uv (0.25, 0.25) of a 2x2 texture whose bottom-left texel is "
          "(0.2, 0.4, 0.6): expected " FMT3 ", got " FMT3 ". Likely mistake: %s",
          ARG3(want), ARG3(c), hint);
}

/* A 4×4 height map whose grey level is 0.1·i in column i (rows alike). */
static ras_texture *height_ramp(void) {
    ras_image *img = ras_image_create(4, 4, NULL);
    assert_non_null(img);
    for (int r = 0; r < 4; r++)
        for (int i = 0; i < 4; i++)
            ras_image_set(img, i, r, V3(0.1f * i, 0.1f * i, 0.1f * i));
    ras_texture *tex = ras_texture_from_image(img, RAS_WRAP_CLAMP, NULL);
    ras_image_destroy(img);
    assert_non_null(tex);
    return tex;
}

/* A 4×4 height map that rises in u AND in v: grey 0.1·i + 0.04·j in column
 * i, j rows up from the bottom (v grows upward). A map that varies in u only
 * lets a dV that is always 0 (an integer 1 / height, or h(u, v + ...) read
 * at u + ...) pass. */
static ras_texture *height_slope(void) {
    ras_image *img = ras_image_create(4, 4, NULL);
    assert_non_null(img);
    for (int r = 0; r < 4; r++)
        for (int i = 0; i < 4; i++) {
            float g = 0.1f * (float)i + 0.04f * (float)(3 - r);
            ras_image_set(img, i, r, V3(g, g, g));
        }
    ras_texture *tex = ras_texture_from_image(img, RAS_WRAP_CLAMP, NULL);
    ras_image_destroy(img);
    assert_non_null(tex);
    return tex;
}

/* The bitangent tangent_frame returned, against the three ways it is
 * written: n × t (right), t × n, and n ∘ t (element-wise, glms_vec3_mul). */
typedef enum bitangent_kind { B_RIGHT, B_T_CROSS_N, B_ELEMENTWISE, B_OTHER } bitangent_kind;

static bitangent_kind bitangent_of(vec3s n, vec3s t, vec3s b) {
    if (near3(b, glms_vec3_cross(n, t), 1e-5f)) return B_RIGHT;
    if (near3(b, glms_vec3_cross(t, n), 1e-5f)) return B_T_CROSS_N;
    if (near3(b, glms_vec3_mul(n, t), 1e-5f)) return B_ELEMENTWISE;
    return B_OTHER;
}

#define B_T_CROSS_N_MISTAKE                                                                        \
    "the bitangent b = t × n in tangent_frame: it is b = n × t (glms_vec3_cross(n, t), "         \
    "TODO 5.3); the reversed order negates b and with it dV's term in n' = n − dU·t − dV·b"
#define B_ELEMENTWISE_MISTAKE                                                                      \
    "the bitangent computed element-wise in tangent_frame, b = n ∘ t (glms_vec3_mul multiplies " \
    "component by component): it is the cross product b = n × t (glms_vec3_cross(n, t), TODO "    \
    "5.3); element-wise, b is (0, 0, 0) wherever n and t have no common axis, so dV's term "       \
    "vanishes"

/* The likely mistake of a bumped normal whose dV term is 0 (`zero`) or
 * negated (`negated`), from the student's tangent_frame at n. */
static const char *bump_dv_mistake(vec3s n, bool negated) {
    vec3s t, b;
    tangent_frame(n, &t, &b);
    bitangent_kind k = bitangent_of(n, t, b);
    if (negated)
        return k == B_T_CROSS_N ? B_T_CROSS_N_MISTAKE
                                : "the sign of dV's term: n' = TBN·(−dU, −dV, 1) = n − dU·t − dV·b "
                                  "(your tangent_frame's b = n × t is right here, so either the "
                                  "sign, or a frame bump_normal builds itself with b = t × n)";
    return k == B_ELEMENTWISE
               ? B_ELEMENTWISE_MISTAKE
               : "dV is always 0 (your tangent_frame's b is not 0 here): the v step 1/height "
                 "computed in integers (1 / h is 0), or h(u, v + 1/height) read at the same v";
}

/* Bump, nearest filter, uv (0.375, 0.5), n = (0,0,1):
 *   h(u,v) = 255·|(0.1,0.1,0.1)| = 255·0.173205 = 44.1673 (column 1)
 *   h(u + 1/4, v) = 88.3346 (column 2), h(u, v + 1/4) = 44.1673 (same column)
 *   dU = kh·kn·(88.3346 − 44.1673) = 0.02·44.1673 = 0.883346, dV = 0
 *   t = (x·y/s, s, z·y/s) with s = √(x²+z²) = 1 → (0, 1, 0); b = n × t = (−1, 0, 0)
 *   n' = normalize(−dU·t − dV·b + n) = normalize(0, −0.883346, 1) = (0, −0.662040, 0.749469)
 *   colour (n' + 1)/2 = (0.5, 0.168980, 0.874734) */
static void test_shader_bump(void **state) {
    (void)state;
    ras_texture *hm = height_ramp();
    fragment_shader_payload p = base_payload();
    p.height_map = hm;
    p.uv = (vec2s){{0.375f, 0.5f}};
    vec3s n = bump_normal(&p);
    vec3s c = bump_fragment_shader(&p);
    ras_texture_destroy(hm);
    vec3s want_n = V3(0, -0.662040f, 0.749469f);
    const char *hint = "see the arithmetic above this test (docs/hw3.md section 5)";
    if (near3(n, V3(0, 0, 1), 1e-5f))
        hint = "the normal was not perturbed";
    else if (near3(n, V3(0, 0.662040f, 0.749469f), 1e-4f))
        hint = "sign: the perturbed normal is TBN·(−dU, −dV, 1)";
    else if (near3(n, V3(0.662040f, 0, 0.749469f), 1e-4f) ||
             near3(n, V3(-0.662040f, 0, 0.749469f), 1e-4f))
        hint = "dU and dV swapped (u and v swapped): dU steps u by 1/width and multiplies t, "
               "dV steps v by 1/height and multiplies b (TBN = [t b n]; t = (0,1,0) here); "
               "swapping the steps or swapping t and b gives the same normal";
    CHECK(near3(n, want_n, 1e-4f),
          "bump_normal on a height ramp (dU = 0.883346, dV = 0) at n = (0,0,1): expected " FMT3
          ", got " FMT3 ". Likely mistake: %s",
          ARG3(want_n), ARG3(n), hint);
    CHECK(near3(c, V3(0.5f, 0.168980f, 0.874734f), 1e-4f),
          "bump shader colour: expected (n'+1)/2 = (0.5, 0.168980, 0.874734), got " FMT3
          ". Likely mistake: %s",
          ARG3(c),
          near3(c, want_n, 1e-4f) ? "bump_fragment_shader returned n' itself: the colour is "
                                    "(n' + 1) / 2, as normal_fragment_shader shows"
                                  : "bump_fragment_shader must return (bump_normal(payload) + 1) "
                                    "/ 2");
    /* On height_slope at uv (0.375, 0.375) (column 1, row 1 from the bottom):
     *   h = 255·√3·0.14, h(u + 1/4, v) = 255·√3·0.24, h(u, v + 1/4) = 255·√3·0.18
     *   dU = 0.02·255·√3·0.10 = 0.883346, dV = 0.02·255·√3·0.04 = 0.353338
     *   n' = normalize(dV, −dU, 1) = (0.255992, −0.639980, 0.724495) */
    hm = height_slope();
    p.height_map = hm;
    p.uv = (vec2s){{0.375f, 0.375f}};
    n = bump_normal(&p);
    ras_texture_destroy(hm);
    want_n = V3(0.255992f, -0.639980f, 0.724495f);
    hint = "see the arithmetic above this test (docs/hw3.md section 5)";
    if (near3(n, V3(0, -0.662040f, 0.749469f), 1e-4f))
        hint = bump_dv_mistake(V3(0, 0, 1), false);
    else if (near3(n, V3(0.639980f, -0.255992f, 0.724495f), 1e-4f))
        hint = "dU and dV swapped (u and v swapped): dU steps u by 1/width and multiplies t, "
               "dV steps v by 1/height and multiplies b";
    else if (near3(n, V3(-0.255992f, -0.639980f, 0.724495f), 1e-4f))
        hint = bump_dv_mistake(V3(0, 0, 1), true);
    CHECK(near3(n, want_n, 1e-4f),
          "bump_normal on a height map rising in u and in v (dU = 0.883346, dV = 0.353338) at "
          "n = (0,0,1): expected " FMT3 ", got " FMT3 ". Likely mistake: %s",
          ARG3(want_n), ARG3(n), hint);
}

/* Displacement on the same ramp: p' = P + kn·h·n = (0,0,−10 + 0.1·44.1673) =
 * (0, 0, −5.583270); light at (0,0,10), I = 100: r² = 15.583270² = 242.8383,
 * I/r² = 0.411797; l = v = h = (0,0,1); n'·l = n'·h = 0.749469 (n' from the bump
 * test). kd = 0.5, ks = 0.3, p = 4:
 *   0.05 + 0.5·0.411797·0.749469 + 0.3·0.411797·0.749469⁴ = 0.05 + 0.154315 + 0.038977 = 0.243292
 * Without the displacement (P unchanged, r² = 400): 0.167347. Without the bump
 * (n = (0,0,1)): 0.379437. */
static void test_shader_displacement(void **state) {
    (void)state;
    ras_texture *hm = height_ramp();
    fragment_shader_payload p = base_payload();
    p.height_map = hm;
    p.uv = (vec2s){{0.375f, 0.5f}};
    p.color = V3(0.5f, 0.5f, 0.5f);
    p.lights[0] = (light){{{0, 0, 10}}, {{100, 100, 100}}};
    vec3s c = displacement_fragment_shader(&p);
    ras_texture_destroy(hm);
    const char *hint = "see the arithmetic above this test (docs/hw3.md section 6)";
    if (fabsf(c.x - 0.167347f) < 1e-4f)
        hint = "the point was not displaced: p' = p + kn·h·n";
    else if (fabsf(c.x - 0.379437f) < 1e-4f)
        hint = "the normal was not bumped: use bump_normal";
    CHECK(fabsf(c.x - 0.243292f) < 1e-4f && fabsf(c.y - c.x) < 1e-6f && fabsf(c.z - c.x) < 1e-6f,
          "displacement on a height ramp (h = 44.1673, kn = 0.1): expected (0.243292, 0.243292, "
          "0.243292), got " FMT3 ". Likely mistake: %s",
          ARG3(c), hint);
}

/* ---- tbn --------------------------------------------------------------------- */

static void check_frame(vec3s n, bool perpendicular) {
    vec3s t, b;
    tangent_frame(n, &t, &b);
    CHECK(ras_vec3_finite(t) && ras_vec3_finite(b),
          "tangent_frame at n = " FMT3 ": expected finite t and b, got t = " FMT3 ", b = " FMT3
          ". Likely mistake: at n = (0, ±1, 0) the course formula divides 0 by 0; use any unit "
          "t perpendicular to n there",
          ARG3(n), ARG3(t), ARG3(b));
    CHECK(fabsf(glms_vec3_norm(t) - 1) < 1e-4f,
          "tangent_frame at n = " FMT3 ": |t| = %.6f, expected 1. Likely mistake: %s", ARG3(n),
          (double)glms_vec3_norm(t),
          glms_vec3_norm(t) < 1e-6f ? "t = (0, 0, 0) at the pole: pick a unit t perpendicular to "
                                      "n there, e.g. (1, 0, 0) (TODO 5.2)"
                                    : "t is not a unit vector: t = (x·y/s, s, z·y/s) with s = "
                                      "√(x² + z²) is unit for a unit n (TODO 5.1)");
    if (perpendicular)
        CHECK(fabsf(glms_vec3_dot(t, n)) < 1e-4f,
              "tangent_frame at n = " FMT3 ": t = " FMT3 " is not perpendicular to n (t·n = %.6f)"
              ". Likely mistake: at n = (0, ±1, 0) the fallback t must be perpendicular to n, "
              "e.g. (1, 0, 0) (TODO 5.2)",
              ARG3(n), ARG3(t), (double)glms_vec3_dot(t, n));
    vec3s want_b = glms_vec3_cross(n, t);
    bitangent_kind k = bitangent_of(n, t, b);
    CHECK(k == B_RIGHT,
          "tangent_frame at n = " FMT3 ": expected b = n × t = " FMT3 ", got " FMT3
          ". Likely mistake: %s",
          ARG3(n), ARG3(want_b), ARG3(b),
          k == B_T_CROSS_N     ? B_T_CROSS_N_MISTAKE
          : k == B_ELEMENTWISE ? B_ELEMENTWISE_MISTAKE
                               : "b = glms_vec3_cross(n, t) of the unit n and t (TODO 5.3)");
}

/* The poles n = (0, ±1, 0) and their neighbourhood give finite frames. */
static void test_tbn_at_poles_finite(void **state) {
    (void)state;
    check_frame(V3(0, 1, 0), true);
    check_frame(V3(0, -1, 0), true);
    check_frame(glms_vec3_normalize(V3(1e-9f, 1, 0)), false);
    check_frame(glms_vec3_normalize(V3(0, -1, 1e-7f)), false);
    check_frame(glms_vec3_normalize(V3(1e-3f, 1, -1e-3f)), false);
    /* the bump shader itself on the floor's normal: finite */
    ras_texture *hm = height_ramp();
    fragment_shader_payload p = base_payload();
    p.height_map = hm;
    p.uv = (vec2s){{0.375f, 0.5f}};
    p.normal = V3(0, 1, 0);
    vec3s c = bump_fragment_shader(&p);
    ras_texture_destroy(hm);
    CHECK(ras_vec3_finite(c),
          "bump shader at n = (0,1,0): expected a finite colour, got NaN/Inf " FMT3
          ". Likely mistake: bump_normal builds its own frame with the course formula, 0/0 at "
          "the pole: use tangent_frame (TODO 5.4)",
          ARG3(c));
}

/* The course formula away from the poles: n = (1,2,2)/3, s = √5/3 = 0.745356,
 * t = ((2/9)/s, s, (4/9)/s) = (0.298142, 0.745356, 0.596285). */
static void test_tbn_formula(void **state) {
    (void)state;
    vec3s n = V3(1 / 3.0f, 2 / 3.0f, 2 / 3.0f), t, b;
    tangent_frame(n, &t, &b);
    CHECK(near3(t, V3(0.298142f, 0.745356f, 0.596285f), 1e-5f),
          "tangent_frame((1,2,2)/3): expected t = (0.298142, 0.745356, 0.596285) (the course "
          "formula), got " FMT3 ". Likely mistake: %s",
          ARG3(t),
          near3(t, V3(0.298142f, -0.745356f, 0.596285f), 1e-5f)
              ? "the middle component's sign: t = (x·y/s, s, z·y/s), s = √(x² + z²) (TODO 5.1)"
              : "t = (x·y/s, s, z·y/s) with s = √(x² + z²) (the course's formula, TODO 5.1)");
}

/* ---- bilinear ------------------------------------------------------------------ */

/* 4×2 texture: texel (i, j) = (i/4, j/2, 0.3), j = 0 the bottom row (v = 0). */
/* The ramp's texels sit between guard texels of an impossible colour
 * (GUARD: 9, -9, 9), so a lookup that reads one texel past either end of the
 * array, instead of going through ras_texture_texel (which wraps or clamps),
 * brings GUARD back into the result, where it is named. */
#define GUARD_TEXELS 8
#define GUARD V3(9, -9, 9)

static ras_texture *ramp4x2(ras_wrap wrap) {
    ras_image *img = ras_image_create(4, 2, NULL);
    assert_non_null(img);
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 4; i++)
            ras_image_set(img, i, 1 - j, V3(i / 4.0f, j / 2.0f, 0.3f));
    ras_texture *tex = ras_texture_from_image(img, wrap, NULL);
    ras_image_destroy(img);
    assert_non_null(tex);
    vec3s *block = malloc((2 * GUARD_TEXELS + 8) * sizeof *block);
    assert_non_null(block);
    for (int k = 0; k < 2 * GUARD_TEXELS + 8; k++)
        block[k] = GUARD;
    memcpy(block + GUARD_TEXELS, tex->texels, 8 * sizeof *block);
    free(tex->texels);
    tex->texels = tex->levels[0] = block + GUARD_TEXELS;
    return tex;
}

/* Frees the guarded block (ras_texture_destroy frees texels itself). */
static void ramp_destroy(ras_texture *tex) {
    free(tex->texels - GUARD_TEXELS);
    tex->texels = tex->levels[0] = NULL;
    ras_texture_destroy(tex);
}

/* Did a guard texel take part in c? The ramp's blue is 0.3 everywhere and
 * its green never below 0. */
static bool read_past_the_edge(vec3s c) { return c.z > 0.3f + 1e-4f || c.y < -1e-4f; }

#define PAST_THE_EDGE                                                                              \
    "read outside the texture: a guard texel placed just before or after the texel array "         \
    "came back, so an index went one past the edge (i0 + 1 = W or j0 + 1 = H, or -1). "            \
    "Read the four texels through ras_texture_texel(tex, 0, i, j), which wraps or clamps "         \
    "(TODO 4.3): reading tex->texels directly reads memory that is not the texture"

/* ---- bilinear diagnoses: the reference lookup on the ramp with one mistake ---
 * The four corners of a lookup, in the course's names. */
static const char *const corner_names[4] = {
    "bottom-left texel (i0, j0) (the course's u00)", "bottom-right texel (i0+1, j0) (u10)",
    "top-left texel (i0, j0+1) (u01)", "top-right texel (i0+1, j0+1) (u11)"};

typedef struct bl_variant {
    float shift_x, shift_y; /* the half-texel shift per axis: −0.5 is right */
    bool flip_v;            /* v read from the top */
    int corner, from;       /* corner `corner` reads corner `from`'s texel (−1: none) */
} bl_variant;

#define BL_RIGHT ((bl_variant){-0.5f, -0.5f, false, -1, -1})

static int ramp_index(ras_wrap wrap, int i, int n) {
    if (wrap == RAS_WRAP_REPEAT) return ((i % n) + n) % n;
    return i < 0 ? 0 : i >= n ? n - 1 : i;
}

static float ramp_coord(ras_wrap wrap, float u) {
    if (!isfinite(u)) return 0;
    return wrap == RAS_WRAP_REPEAT ? u - floorf(u) : fminf(fmaxf(u, 0), 1);
}

/* The 4x2 ramp's bilinear value at (u, v) with the mistake m applied. */
static vec3s ramp_bilinear(ras_wrap wrap, float u, float v, bl_variant m) {
    float x = ramp_coord(wrap, u) * 4 + m.shift_x;
    float y = ramp_coord(wrap, m.flip_v ? 1 - v : v) * 2 + m.shift_y;
    int i0 = (int)floorf(x), j0 = (int)floorf(y);
    vec3s c[4];
    for (int k = 0; k < 4; k++) {
        int i = ramp_index(wrap, i0 + (k & 1), 4), j = ramp_index(wrap, j0 + (k >> 1), 2);
        c[k] = V3(i / 4.0f, j / 2.0f, 0.3f);
    }
    if (m.corner >= 0) c[m.corner] = c[m.from];
    float s = x - (float)i0, t = y - (float)j0;
    vec3s bottom = glms_vec3_lerp(c[0], c[1], s), top = glms_vec3_lerp(c[2], c[3], s);
    return glms_vec3_lerp(bottom, top, t);
}

/* The candidates: each variant with the mistake it shows. */
typedef struct bl_candidate {
    bl_variant m;
    const char *mistake;
} bl_candidate;

#define BL_NO_SHIFT "half-texel shift missing: texel centres are at u·W − 0.5, not u·W"
#define BL_WRONG_SIGN                                                                              \
    "the half-texel shift with the wrong sign: x = u·W + 0.5 reads a whole texel too far right "  \
    "(and up); texel centres are at x = u·W − 0.5, y = v·H − 0.5 (TODO 4.2)"
#define BL_CORNER_TWICE                                                                            \
    "one corner texel read twice: the %s read as the %s, so one of the four texels is never "      \
    "read; the corners are (i0, j0), (i0+1, j0), (i0, j0+1), (i0+1, j0+1) (TODO 4.3)"

static int bl_candidates(bl_candidate *out) {
    int n = 0;
    const float sx[] = {0, -0.5f, 0}, sy[] = {0, 0, -0.5f};
    for (int k = 0; k < 3; k++) { /* no shift on both axes, on x only, on y only */
        out[n++] = (bl_candidate){{sx[k], sy[k], false, -1, -1}, BL_NO_SHIFT};
        out[n++] = (bl_candidate){{sx[k] ? -0.5f : 0.5f, sy[k] ? -0.5f : 0.5f, false, -1, -1},
                                  BL_WRONG_SIGN};
    }
    out[n++] = (bl_candidate){{-0.5f, -0.5f, true, -1, -1},
                              "v is flipped: the texture already stores the bottom row at v = 0"};
    for (int c = 0; c < 4; c++)
        for (int f = 0; f < 4; f++)
            if (c != f) out[n++] = (bl_candidate){{-0.5f, -0.5f, false, c, f}, NULL};
    return n;
}

static void bl_name(const bl_candidate *c, char *out, size_t size) {
    if (c->mistake)
        snprintf(out, size, "%s", c->mistake);
    else
        snprintf(out, size, BL_CORNER_TWICE, corner_names[c->m.corner], corner_names[c->m.from]);
}

/* Which candidates give `got` at (u, v) and, when more than one does, also
 * the student's value at a point whose four weights all differ (x = 1.25,
 * y = 0.75, inside the ramp), which tells them apart. */
static const char *bl_diagnose(const ras_texture *tex, float u, float v, vec3s got, char *out,
                               size_t size) {
    bl_candidate cand[32];
    int n = bl_candidates(cand), match[32], nm = 0;
    vec3s right = ramp_bilinear(tex->wrap, u, v, BL_RIGHT);
    for (int k = 0; k < n; k++) {
        vec3s val = ramp_bilinear(tex->wrap, u, v, cand[k].m);
        if (!near3(val, right, 1e-5f) && near3(val, got, 1e-5f)) match[nm++] = k;
    }
    if (nm > 1) {
        const float pu = 1.75f / 4, pv = 1.25f / 2;
        vec3s probe = texture_sample_bilinear(tex, pu, pv);
        int kept = 0;
        for (int k = 0; k < nm; k++)
            if (near3(ramp_bilinear(tex->wrap, pu, pv, cand[match[k]].m), probe, 1e-5f))
                match[kept++] = match[k];
        if (kept > 0) nm = kept;
    }
    out[0] = '\0';
    for (int k = 0; k < nm; k++) {
        char one[512];
        bl_name(&cand[match[k]], one, sizeof one);
        if (strstr(out, one)) continue; /* the same mistake on another axis */
        size_t used = strlen(out);
        snprintf(out + used, size - used, "%s%s", used ? "; or " : "", one);
    }
    if (!out[0])
        snprintf(out, size,
                 "none of the classic mistakes gives this value here (a missing or wrong-signed "
                 "half-texel shift, v flipped, a corner texel read twice); check x = u·W − 0.5, "
                 "y = v·H − 0.5, then i0 = floor(x), s = x − i0, the four corners wrapped, "
                 "lerp along x, then along y");
    return out;
}

static void expect_bilinear(const ras_texture *tex, float u, float v, vec3s want,
                            const char *what) {
    vec3s got = texture_sample_bilinear(tex, u, v);
    if (near3(got, want, 1e-5f)) return;
    char why[2048];
    const char *hint = why;
    if (read_past_the_edge(got))
        hint = PAST_THE_EDGE;
    else if (strncmp(bl_diagnose(tex, u, v, got, why, sizeof why), "none", 4) == 0 &&
             near3(got, ras_texture_sample_nearest(tex, u, v), 1e-6f))
        hint = "this is the nearest texel: blend the four neighbours";
    fail_msg("texture_sample_bilinear(%s) at (u, v) = (%g, %g) on the 4x2 ramp texel (i,j) = "
             "(i/4, j/2, 0.3), %s: expected " FMT3 ", got " FMT3 ". Likely mistake: %s",
             what, (double)u, (double)v, tex->wrap == RAS_WRAP_CLAMP ? "clamp" : "repeat",
             ARG3(want), ARG3(got), hint);
}

/* The stub's placeholder is the nearest texel, which is right wherever a
 * test's answer is one texel (at an edge with clamp, for garbage
 * coordinates): such a test counts only once bilinear blends. (0.3, 0.3) on
 * the ramp is x = 0.7, y = 0.1 between four centres: (0.175, 0.05, 0.3),
 * and any blend differs from the nearest texel (0.25, 0, 0.3). Checked after
 * the test's own cases, so a wrong answer there is named first. */
static void expect_blends(const ras_texture *tex) {
    vec3s got = texture_sample_bilinear(tex, 0.3f, 0.3f);
    vec3s nearest = ras_texture_sample_nearest(tex, 0.3f, 0.3f);
    CHECK(!near3(got, nearest, 1e-4f),
          "texture_sample_bilinear(0.3, 0.3) on the 4x2 ramp: expected a blend of four texels, "
          "(0.175, 0.05, 0.3), got the nearest texel " FMT3 ". The nearest texel is the stub's "
          "placeholder, right at this test's points only, so this test counts once bilinear "
          "blends. Likely mistake: texture_sample_bilinear is not written yet (TODO(hw3) "
          "4.2-4.4)",
          ARG3(got));
}

/* At texel centres bilinear returns the texel itself; between centres the
 * average. u = (i + 0.5)/4, v = (j + 0.5)/2. */
static void test_bilinear_centres_and_between(void **state) {
    (void)state;
    ras_texture *tex = ramp4x2(RAS_WRAP_CLAMP);
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 4; i++)
            expect_bilinear(tex, (i + 0.5f) / 4, (j + 0.5f) / 2, V3(i / 4.0f, j / 2.0f, 0.3f),
                            "texel centre");
    /* u = 0.25: x = 0.5, halfway between texels 0 and 1 → 0.125; v = 0.25: y = 0 → row 0 */
    expect_bilinear(tex, 0.25f, 0.25f, V3(0.125f, 0, 0.3f), "between two centres");
    /* u = 0.5, v = 0.5: x = 1.5, y = 0.5 → (0.375, 0.25) */
    expect_bilinear(tex, 0.5f, 0.5f, V3(0.375f, 0.25f, 0.3f), "between four centres");
    /* a quarter of the way: x = 1.25, y = 0.25 → (0.3125, 0.125) */
    expect_bilinear(tex, 1.75f / 4, 0.75f / 2, V3(0.3125f, 0.125f, 0.3f), "a quarter between");
    ramp_destroy(tex);
}

/* Clamp-to-edge: u = 0 and u = −ε read the first column, u = 1 and 1 + ε the
 * last; v likewise for rows. */
static void test_bilinear_edges_clamp(void **state) {
    (void)state;
    ras_texture *tex = ramp4x2(RAS_WRAP_CLAMP);
    const float eps = 1e-4f;
    /* the top-right corner first: there an index + 1 leaves the array, the
     * most specific symptom of a lookup that does not clamp */
    float ue[] = {1, 1 + eps, 7};
    for (int k = 0; k < 3; k++)
        expect_bilinear(tex, ue[k], 0.75f, V3(0.75f, 0.5f, 0.3f), "right edge");
    float us[] = {0, -eps, -3};
    for (int k = 0; k < 3; k++)
        expect_bilinear(tex, us[k], 0.25f, V3(0, 0, 0.3f), "left edge");
    expect_bilinear(tex, 0.125f, 0, V3(0, 0, 0.3f), "bottom edge v = 0");
    expect_bilinear(tex, 0.125f, 1, V3(0, 0.5f, 0.3f), "top edge v = 1");
    expect_bilinear(tex, 0.125f, 1 + eps, V3(0, 0.5f, 0.3f), "above the top edge");
    expect_blends(tex);
    ramp_destroy(tex);
}

/* Repeat: u = 0 sits halfway between the last and the first column:
 * (0.75 + 0)/2 = 0.375; so do u = 1, −ε (almost) and 1 + ε (almost). */
static void test_bilinear_edges_repeat(void **state) {
    (void)state;
    ras_texture *tex = ramp4x2(RAS_WRAP_REPEAT);
    expect_bilinear(tex, 0, 0.25f, V3(0.375f, 0, 0.3f), "u = 0 wraps");
    expect_bilinear(tex, 1, 0.25f, V3(0.375f, 0, 0.3f), "u = 1 wraps");
    expect_bilinear(tex, 2.625f, 0.25f, V3(0.5f, 0, 0.3f), "u = 2.625 is u = 0.625");
    expect_bilinear(tex, -0.375f, 0.25f, V3(0.5f, 0, 0.3f), "u = -0.375 is u = 0.625");
    vec3s a = texture_sample_bilinear(tex, -1e-4f, 0.25f),
          b = texture_sample_bilinear(tex, 1 + 1e-4f, 0.25f);
    CHECK(fabsf(a.x - 0.375f) < 2e-3f && fabsf(b.x - 0.375f) < 2e-3f,
          "repeat just outside [0,1]: expected ≈ 0.375 on both sides of the seam, got %.5f "
          "(u = −ε) and %.5f (u = 1 + ε). Likely mistake: repeat keeps the fraction u − floor(u) "
          "(TODO 4.1), then the texel index i0 + 1 = W wraps to 0",
          (double)a.x, (double)b.x);
    ramp_destroy(tex);
}

/* Garbage coordinates never read out of bounds and never return garbage:
 * every result lies inside the texture's range (R in [0, 0.75]). */
static void test_bilinear_nan_and_huge(void **state) {
    (void)state;
    const float bad[] = {NAN, -NAN, INFINITY, -INFINITY, 1e30f, -1e30f, 3e9f, -2.5e9f};
    for (int w = 0; w < 2; w++) {
        ras_texture *tex = ramp4x2(w ? RAS_WRAP_REPEAT : RAS_WRAP_CLAMP);
        for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
            for (size_t j = 0; j < sizeof bad / sizeof *bad; j++) {
                float uv[2][2] = {{bad[i], 0.5f}, {0.5f, bad[j]}};
                for (int k = 0; k < 3; k++) {
                    float u = k == 2 ? bad[i] : uv[k][0], v = k == 2 ? bad[j] : uv[k][1];
                    vec3s c = texture_sample_bilinear(tex, u, v);
                    CHECK(ras_vec3_finite(c) && c.x >= 0 && c.x <= 0.75f && c.y >= 0 &&
                              c.y <= 0.5f && fabsf(c.z - 0.3f) < 1e-6f,
                          "texture_sample_bilinear(%g, %g) (%s) returned " FMT3
                          ", not a colour of the texture. Likely mistake: %s",
                          (double)u, (double)v, w ? "repeat" : "clamp", ARG3(c),
                          read_past_the_edge(c) && ras_vec3_finite(c)
                              ? PAST_THE_EDGE
                              : "NaN/huge u or v converted to int (undefined) — make them "
                                "safe first (TODO 4.1)");
                }
            }
        expect_blends(tex);
        ramp_destroy(tex);
    }
}

/* Bonus (reference): trilinear with no minification is bilinear; with a
 * footprint of the whole texture it is the texture's average. */
static void test_trilinear_levels(void **state) {
    (void)state;
    ras_texture *tex = ras_texture_create_checker(64, 8, V3(1, 1, 1), V3(0, 0, 0));
    assert_non_null(tex);
    assert_true(ras_texture_build_mips(tex));
    vec2s uv = {{0.3f, 0.6f}}, zero = {{0, 0}};
    vec3s a = texture_sample_trilinear(tex, uv, zero, zero);
    vec3s b = texture_sample_bilinear(tex, uv.x, uv.y);
    CHECK(near3(a, b, 1e-6f),
          "trilinear without minification: expected bilinear " FMT3 ", got " FMT3
          ". Likely mistake: with ρ ≤ 1 (magnified) the level is 0, and level 0 is "
          "texture_sample_bilinear (TODO 7.2)",
          ARG3(b), ARG3(a));
    vec2s big = {{1, 0}}, big_y = {{0, 1}};
    vec3s c = texture_sample_trilinear(tex, uv, big, big_y);
    CHECK(near3(c, V3(0.5f, 0.5f, 0.5f), 0.02f),
          "trilinear with one pixel covering the whole texture: expected the average grey "
          "(0.5, 0.5, 0.5), got " FMT3 ". Likely mistake: level = log2(ρ) with ρ in texels",
          ARG3(c));
    /* minified past the last level (ρ = 8·64 texels: log2 = 9 > 6, the 1×1
     * level): the level is clamped to the last one, never read past it */
    vec2s huge = {{8, 0}}, huge_y = {{0, 8}};
    vec3s d = texture_sample_trilinear(tex, uv, huge, huge_y);
    CHECK(near3(d, V3(0.5f, 0.5f, 0.5f), 0.02f),
          "trilinear minified past the last mip level (8 texture widths per pixel): expected "
          "the 1x1 level's average grey (0.5, 0.5, 0.5), got " FMT3 ". Likely mistake: the "
          "level not clamped to level_count - 1 (TODO 7.2)",
          ARG3(d));
    ras_texture_destroy(tex);
}

/* ---- stages: only what the shader needs runs -------------------------------- */

static mat4s hand_projection(float fov_deg, float aspect, float n_dist, float f_dist) {
    /* GAMES101 perspective, n = −near, f = −far, written out:
     * [n/r 0 0 0; 0 n/t 0 0; 0 0 (n+f)/(n−f) −2nf/(n−f); 0 0 1 0] with
     * t = near·tan(fov/2), r = t·aspect (times −1: w > 0 in front, same map). */
    double t = n_dist * tan(fov_deg * RAS_PI / 360.0), r = t * aspect;
    double n = -n_dist, f = -f_dist;
    return ras_mat4_rows((float)(n / r), 0, 0, 0, 0, (float)(n / t), 0, 0, 0, 0,
                         (float)((n + f) / (n - f)), (float)(-2 * n * f / (n - f)), 0, 0, 1, 0);
}

/* The program's default scene, scenes/hw3_default.json as built in. */
static ras_scene *g_scene;
static ras_scene_assets *g_assets;

static int group_setup(void **state) {
    (void)state;
    ras_error err = {{0}};
    g_scene = ras_builtin_scene_load("hw3_default", &err);
    g_assets = g_scene ? ras_scene_load_assets(g_scene, &err) : NULL;
    if (!g_assets) fprintf(stderr, "test_hw3: %s\n", err.msg);
    return g_assets ? 0 : -1;
}

static int group_teardown(void **state) {
    (void)state;
    ras_scene_assets_destroy(g_assets);
    ras_scene_destroy(g_scene);
    return 0;
}

/* The default scene drawn at width x height (the same camera and aspect: a
 * scene copy whose image size alone differs). */
static ras_image *render_at(ras_scene_shader shader, texture_filter filter, ras_counters *stats,
                            int width, int height) {
    hw3_render_options opt = hw3_render_defaults();
    opt.shader = shader;
    opt.filter = filter;
    opt.projection = hand_projection;
    ras_error err = {{0}};
    ras_scene sized = *g_scene;
    sized.width = width, sized.height = height;
    ras_image *img = ras_image_create(width, height, &err);
    assert_non_null(img);
    CHECK(hw3_render(&sized, g_assets, &opt, img, stats, &err),
          "hw3_render(%s): %s. Likely mistake: hw3_render (the handout's code) rejected its input: "
          "the message above says which",
          ras_scene_shader_name(shader), err.msg);
    return img;
}
static ras_image *render(ras_scene_shader shader, texture_filter filter, ras_counters *stats) {
    return render_at(shader, filter, stats, g_scene->width, g_scene->height);
}

/* Fragments as the fragment stage counts them (common/pipeline/
 * stage5_fragment.c adds one per varying it interpolates), not hw2's fragments_shaded: in the
 * student edition hw2 is the student's, and a test of hw3 must not depend on
 * what another assignment counts. */
static uint64_t hw3_fragments(const ras_counters *k, ras_scene_shader shader) {
    unsigned n = (unsigned)__builtin_popcount((unsigned)hw3_shader_varyings(shader));
    return n ? k->varyings_interpolated / n : 0;
}

/* The normal shader reads normals only: no texels, no lighting, no mip levels;
 * phong lights but fetches nothing; texture fetches. Counted on the default
 * scene at a quarter of its size (175 x 175): every relation holds per
 * fragment, and a full frame cost the graded tests' worker a third of its
 * time for the same verdict (issue 37). */
static ras_image *render_small(ras_scene_shader shader, texture_filter filter, ras_counters *k) {
    return render_at(shader, filter, k, g_scene->width / 4, g_scene->height / 4);
}
static void test_stages_only_what_the_shader_needs(void **state) {
    (void)state;
    CHECK(hw3_shader_varyings(RAS_SHADER_NORMAL) == RAS_VARYING_NORMAL &&
              hw3_shader_varyings(RAS_SHADER_PHONG) ==
                  (RAS_VARYING_NORMAL | RAS_VARYING_VIEW_POS) &&
              hw3_shader_varyings(RAS_SHADER_BUMP) == (RAS_VARYING_NORMAL | RAS_VARYING_UV),
          "varyings masks: normal reads NORMAL; phong NORMAL|VIEW_POS; bump NORMAL|UV. Likely "
          "mistake: the masks are given: hw3_shader_varyings was changed");
    ras_counters k;
    ras_image_destroy(render_small(RAS_SHADER_NORMAL, FILTER_TRILINEAR, &k));
    CHECK(k.texels_fetched == 0 && k.lighting_evaluations == 0 && k.mip_levels_built == 0 &&
              !(k.stages_run & (RAS_STAGE_TEXTURE | RAS_STAGE_LIGHTING | RAS_STAGE_MIPMAP)),
          "normal shader: expected no texels, lighting or mips, got %llu texels, %llu lighting, "
          "%llu mip levels. Likely mistake: the normal shader must read only the normal: no "
          "texture, no lighting (it is given)",
          (unsigned long long)k.texels_fetched, (unsigned long long)k.lighting_evaluations,
          (unsigned long long)k.mip_levels_built);
    CHECK(k.varyings_interpolated > 0,
          "normal shader: no fragment reached the shader. Likely mistake: nothing was drawn: see "
          "the hw2 tests (the rasterizer) and interpolate_vec3 (TODO 1.3)");
    ras_image_destroy(render_small(RAS_SHADER_PHONG, FILTER_BILINEAR, &k));
    uint64_t frags = hw3_fragments(&k, RAS_SHADER_PHONG);
    CHECK(k.texels_fetched == 0 && k.lighting_evaluations == 2 * frags,
          "phong: expected 0 texels and 2 lighting evaluations per fragment, got %llu texels, "
          "%llu evaluations for %llu fragments. Likely mistake: blinn_phong_lighting does not "
          "count its work (TODO 2.5: stages_run |= RAS_STAGE_LIGHTING, lighting_evaluations += "
          "light_count)",
          (unsigned long long)k.texels_fetched, (unsigned long long)k.lighting_evaluations,
          (unsigned long long)frags);
    ras_image_destroy(render_small(RAS_SHADER_TEXTURE, FILTER_NEAREST, &k));
    frags = hw3_fragments(&k, RAS_SHADER_TEXTURE);
    CHECK(k.texels_fetched == frags,
          "texture, nearest: one texel per fragment expected, got %llu for %llu. Likely mistake: "
          "with FILTER_NEAREST texture_fragment_shader reads one texel a fragment through "
          "texture_sample (TODO 3.1)",
          (unsigned long long)k.texels_fetched, (unsigned long long)frags);
}

/* ---- scene: loading errors ---------------------------------------------------- */

static void write_file(const char *path, const char *text) {
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* --model's scene (scenes/hw3_model.json around a file) and its assets; NULL
 * and err when a file does not load. */
static ras_scene *model_scene(const char *model, const char *texture, bool fit,
                              ras_scene_assets **assets, ras_error *err) {
    ras_scene *s = ras_builtin_scene_with_model("hw3_model", model, texture, NULL, fit, err);
    *assets = s ? ras_scene_load_assets(s, err) : NULL;
    if (*assets) return s;
    ras_scene_destroy(s);
    return NULL;
}

/* A quad's scene drawn with the texture shader at 64 x 64 and the hand-made
 * projection; NULL, said in err, when hw3_render fails. */
static ras_image *quad_frame(ras_scene *s, ras_scene_assets *a, ras_counters *k, ras_error *err) {
    s->width = s->height = 64;
    hw3_render_options opt = hw3_render_defaults();
    opt.shader = RAS_SHADER_TEXTURE;
    opt.projection = hand_projection;
    ras_image *img = ras_image_create(64, 64, NULL);
    if (img && hw3_render(s, a, &opt, img, k, err)) return img;
    ras_image_destroy(img);
    return NULL;
}

/* The quad of the test wound the other way (so the scene's lights reach
 * its front after the scene's turn: the other way it shows only ambient,
 * which has no kd), u along x, with a texture red for u < 0.5 and blue
 * above, written into `dir`: its two halves must differ in their dominant
 * colour. The stub's texture shader ignores the texture (one colour
 * everywhere): the rest of the test holds for it, so this is what makes it
 * count only once the shader reads the texture. */
static void expect_quad_textured(const char *dir) {
    char tex_path[300], quad[300];
    snprintf(tex_path, sizeof tex_path, "%s/halves.png", dir);
    snprintf(quad, sizeof quad, "%s/quad_back.obj", dir);
    write_file(quad, "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "f 1/1 4/4 3/3 2/2\n");
    ras_error err = {{0}};
    ras_image *halves = ras_image_create(8, 8, &err);
    assert_non_null(halves);
    for (int row = 0; row < 8; row++)
        for (int col = 0; col < 8; col++)
            ras_image_set(halves, col, row, col < 4 ? V3(0.9f, 0.1f, 0.1f) : V3(0.1f, 0.1f, 0.9f));
    CHECK(ras_image_save(halves, tex_path, &err), "test setup: %s", err.msg);
    ras_image_destroy(halves);
    ras_scene_assets *a = NULL;
    ras_scene *s = model_scene(quad, tex_path, true, &a, &err);
    CHECK(s,
          "the quad with the texture %s should load: %s. Likely mistake: model loading (scene.c) "
          "is the handout's code, not a TODO: tell the course staff",
          tex_path, err.msg);
    ras_counters k;
    ras_image *img = quad_frame(s, a, &k, &err);
    CHECK(img,
          "render the textured quad: %s. Likely mistake: hw3_render failed with the message above",
          err.msg);
    /* the quad fills the middle of the frame: a quarter in from each side */
    vec3s left = ras_image_get(img, 20, 32), right = ras_image_get(img, 44, 32);
    bool left_red = left.x > left.z, right_red = right.x > right.z;
    ras_image_destroy(img);
    ras_scene_assets_destroy(a);
    ras_scene_destroy(s);
    CHECK(left_red != right_red,
          "the fitted quad with a texture red on its left half (u < 0.5) and blue on its right: "
          "expected one red and one blue half, got " FMT3 " at pixel (20, 32) and " FMT3
          " at (44, 32). One colour on both halves is the stub's placeholder (the texture "
          "ignored), so this test counts once the texture is read. Likely mistake: "
          "texture_fragment_shader does not take kd from the texture (TODO(hw3) 3.1), or the "
          "texture coordinates are not interpolated (TODO(hw3) 1.5)",
          ARG3(left), ARG3(right));
}

/* A missing or malformed model or texture is an error with a message, not a
 * crash and not an empty picture. A quad OBJ without normals loads and fits. */
/* Its files live in a folder the setup makes and the teardown removes, so a
 * failing check (which leaves the test at once) leaves nothing in /tmp. */
static const char *const quads_files[] = {"bad.obj", "quad.obj", "halves.png", "quad_back.obj"};
static int quads_setup(void **state) {
    char *dir = strdup("/tmp/raster101_hw3_XXXXXX");
    if (!dir || !mkdtemp(dir)) {
        free(dir);
        return -1;
    }
    *state = dir;
    return 0;
}
static int quads_teardown(void **state) {
    char *dir = *state, path[300];
    for (size_t i = 0; i < sizeof quads_files / sizeof quads_files[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, quads_files[i]);
        unlink(path);
    }
    rmdir(dir);
    free(dir);
    return 0;
}

static void test_scene_model_errors_and_quads(void **state) {
    const char *dir = *state;
    ras_error err = {{0}};
    ras_scene_assets *a = NULL;
    ras_scene *s = model_scene("/nonexistent/model.obj", NULL, false, &a, &err);
    CHECK(!s && strlen(err.msg) > 0,
          "a missing model must fail with a message. Likely mistake: model loading (scene.c) is "
          "the handout's code, not a TODO: tell the course staff");
    char bad[256], quad[256];
    snprintf(bad, sizeof bad, "%s/bad.obj", dir);
    snprintf(quad, sizeof quad, "%s/quad.obj", dir);
    write_file(bad, "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
    write_file(quad, "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "f 1/1 2/2 3/3 4/4\n");
    err.msg[0] = '\0';
    s = model_scene(bad, NULL, false, &a, &err);
    CHECK(!s && strlen(err.msg) > 0,
          "an OBJ with an out-of-range index must fail with a message. Likely mistake: model "
          "loading (scene.c) is the handout's code, not a TODO: tell the course staff");
    err.msg[0] = '\0';
    s = model_scene(quad, "/nonexistent/tex.png", false, &a, &err);
    CHECK(!s && strlen(err.msg) > 0,
          "a missing texture must fail with a message. Likely mistake: model loading (scene.c) is "
          "the handout's code, not a TODO: tell the course staff");
    s = model_scene(quad, NULL, true, &a, &err);
    CHECK(s,
          "a quad OBJ without normals should load: %s. Likely mistake: model loading (scene.c) is "
          "the handout's code, not a TODO: tell the course staff",
          err.msg);
    CHECK(a->meshes[0]->triangle_count == 2,
          "the quad should become 2 triangles, got %zu. Likely mistake: model loading (scene.c) is "
          "the handout's code, not a TODO: tell the course staff",
          a->meshes[0]->triangle_count);
    ras_counters k;
    ras_image *img = quad_frame(s, a, &k, &err);
    CHECK(img, "render the quad: %s. Likely mistake: hw3_render failed with the message above",
          err.msg);
    CHECK(hw3_fragments(&k, RAS_SHADER_TEXTURE) > 500,
          "the fitted quad should cover much of a 64x64 frame; %llu fragments shaded. Likely "
          "mistake: the quad was not drawn: see the hw2 tests (the rasterizer) and the "
          "interpolators (TODO 1)",
          (unsigned long long)hw3_fragments(&k, RAS_SHADER_TEXTURE));
    ras_image_destroy(img);
    ras_scene_assets_destroy(a);
    ras_scene_destroy(s);
    expect_quad_textured(dir);
}

/* ---- scene: whole images and their references ---------------------------------- */

/* The sanity checks below test the repository's reference images, not the
 * student's code. */
#define REF_NOT_YOURS                                                                              \
    ". Likely mistake: not yours: this checks the course's reference image, which is "             \
    "damaged or stale; tell the course staff"

static ras_image *load_reference(ras_scene_shader shader) {
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/reference/hw3_%s.png", RAS_SOURCE_DIR,
             ras_scene_shader_name(shader));
    ras_error err = {{0}};
    ras_image *img = ras_image_load(path, &err);
    CHECK(img, "reference image missing: %s (make reference-images writes it)" REF_NOT_YOURS,
          err.msg);
    return img;
}

static int byte(float v) { return ras_unit_to_byte(v); }

/* Is the 8-bit pixel within tol levels of c in every channel? */
static bool pixel_is(const ras_image *img, int col, int row, vec3s c, int tol) {
    vec3s p = ras_image_get(img, col, row);
    return abs(byte(p.x) - byte(c.x)) <= tol && abs(byte(p.y) - byte(c.y)) <= tol &&
           abs(byte(p.z) - byte(c.z)) <= tol;
}

static void expect_pixel(const ras_image *img, int col, int row, vec3s c, int tol,
                         const char *what) {
    vec3s p = ras_image_get(img, col, row);
    CHECK(pixel_is(img, col, row, c, tol),
          "%s: pixel (%d, %d) expected " FMT3 " (within %d/255), got " FMT3 REF_NOT_YOURS, what,
          col, row, ARG3(c), tol, ARG3(p));
}

/* Blinn-Phong in double, written out again here so the reference images are
 * checked against arithmetic that does not come from the solution. */
static vec3s hand_blinn_phong(vec3s kd, const double P3[3], const double n[3]) {
    const double lights[2][3] = {{20, 20, 20}, {-20, 20, 0}};
    double c[3] = {0.05, 0.05, 0.05}, vlen = sqrt(P3[0] * P3[0] + P3[1] * P3[1] + P3[2] * P3[2]);
    double v[3] = {-P3[0] / vlen, -P3[1] / vlen, -P3[2] / vlen};
    for (int i = 0; i < 2; i++) {
        double d[3], l[3], h[3], r2 = 0, hl = 0;
        for (int k = 0; k < 3; k++)
            d[k] = lights[i][k] - P3[k], r2 += d[k] * d[k];
        for (int k = 0; k < 3; k++)
            l[k] = d[k] / sqrt(r2), h[k] = l[k] + v[k];
        for (int k = 0; k < 3; k++)
            hl += h[k] * h[k];
        double nl = 0, nh = 0;
        for (int k = 0; k < 3; k++)
            nl += n[k] * l[k], nh += n[k] * h[k] / sqrt(hl);
        double kdv[3] = {kd.x, kd.y, kd.z};
        for (int k = 0; k < 3; k++)
            c[k] += kdv[k] * 500 / r2 * fmax(0, nl) + 0.7937 * 500 / r2 * pow(fmax(0, nh), 150);
    }
    return V3((float)c[0], (float)c[1], (float)c[2]);
}

/* Independent facts about the default scene (700×700, fov 45, eye (0,0,10)):
 *   - the top-centre pixel (350, 5) is background: exactly the clear colour;
 *   - the floor (y = −3.3, normal (0,1,0)) fills the bottom centre: at image
 *     (350, 690), screen y = 9.5, y_ndc = 9.5/350 − 1 = −0.972857, distance
 *     d = 3.3/(0.972857·tan 22.5°) = 8.189183, view point (0.004846, −3.3, −8.189183);
 *   - the sphere (radius 1.2, centre (−1.9, 1.75, −10) in view space): the point
 *     facing the camera, (−1.9, 1.75, −8.8), projects to x_ndc = −1.9/8.8·2.414214
 *     = −0.521251, y_ndc = 0.480101 → screen (167.6, 518.0) → image (167, 181),
 *     where the normal is (0, 0, 1) → colour (0.5, 0.5, 1). */
#define FLOOR_COL 350
#define FLOOR_ROW 690
static const double floor_point[3] = {0.004846, -3.3, -8.189183};
static const double up[3] = {0, 1, 0};

static void sanity_background(const ras_image *img, const char *name) {
    expect_pixel(img, 350, 5, g_scene->clear_color, 0, name);
    expect_pixel(img, 10, 300, g_scene->clear_color, 0, name);
}

static void sanity_normal(const ras_image *ref) {
    sanity_background(ref, "hw3_normal background");
    expect_pixel(ref, 167, 181, V3(0.5f, 0.5f, 1), 3,
                 "hw3_normal: the sphere's point facing the camera has n = (0,0,1)");
    expect_pixel(ref, FLOOR_COL, FLOOR_ROW, V3(0.5f, 1, 0.5f), 1,
                 "hw3_normal: the floor's normal is (0,1,0)");
}

static void sanity_phong(const ras_image *ref) {
    sanity_background(ref, "hw3_phong background");
    /* floor kd = 0.7: 0.05 + 0.7·(diffuse) + specular = 0.416624 */
    expect_pixel(ref, FLOOR_COL, FLOOR_ROW, hand_blinn_phong(V3(0.7f, 0.7f, 0.7f), floor_point, up),
                 2, "hw3_phong: Blinn-Phong of the floor point (0.0048, -3.3, -8.189)");
}

static void sanity_texture(const ras_image *ref) {
    sanity_background(ref, "hw3_texture background");
    /* Image (436, 690): x_ndc = 436.5/350 − 1 = 0.247143, x = 0.247143·8.189183·
     * tan 22.5° = 0.838328 — mid-square: the floor's 24 checker squares are
     * 40/24 = 1.667 wide, so squares end at x = 0 and 1.667; along z the point
     * (z = 1.81) is 2.5 squares from the floor's near edge (z = 6). Its kd is one
     * of the two checker colours, not a blend. */
    const double P3[3] = {0.838328, -3.3, -8.189183};
    vec3s a = hand_blinn_phong(V3(0.85f, 0.85f, 0.85f), P3, up);
    vec3s b = hand_blinn_phong(V3(0.2f, 0.25f, 0.35f), P3, up);
    CHECK(pixel_is(ref, 436, FLOOR_ROW, a, 2) || pixel_is(ref, 436, FLOOR_ROW, b, 2),
          "hw3_texture: the floor pixel (436, 690) should be Blinn-Phong with one of the checker "
          "colours: " FMT3 " or " FMT3 ", got " FMT3 REF_NOT_YOURS,
          ARG3(a), ARG3(b), ARG3(ras_image_get(ref, 436, FLOOR_ROW)));
}

/* A bumped normal is still a unit normal: n = 2c − 1 has length 1 (within the
 * 8-bit rounding) everywhere it is drawn; NaN would give black, |n| = √3. */
static void sanity_bump(const ras_image *ref) {
    sanity_background(ref, "hw3_bump background");
    long drawn = 0;
    for (int r = 0; r < ref->height; r++)
        for (int c = 0; c < ref->width; c++) {
            if (pixel_is(ref, c, r, g_scene->clear_color, 0)) continue;
            vec3s p = ras_image_get(ref, c, r);
            drawn++;
            float len = glms_vec3_norm(glms_vec3_subs(glms_vec3_scale(p, 2), 1));
            CHECK(fabsf(len - 1) < 0.03f,
                  "hw3_bump: pixel (%d, %d) = " FMT3 " is not the colour of a unit normal "
                  "(NaN at n = (0,±1,0)?)" REF_NOT_YOURS,
                  c, r, ARG3(p));
        }
    CHECK(drawn > 200000, "hw3_bump: only %ld pixels drawn" REF_NOT_YOURS, drawn);
}

static void sanity_displacement(const ras_image *ref) {
    sanity_background(ref, "hw3_displacement background");
    /* Lit, not black and not NaN: the floor pixel is within a factor of two of
     * the plain Blinn-Phong value (the bumps tilt the normal, kn·h ≤ 0.22 moves it). */
    vec3s want = hand_blinn_phong(V3(0.7f, 0.7f, 0.7f), floor_point, up);
    vec3s got = ras_image_get(ref, FLOOR_COL, FLOOR_ROW);
    CHECK(got.x > 0.5f * want.x && got.x < 2 * want.x,
          "hw3_displacement: the floor pixel " FMT3
          " should be near Blinn-Phong " FMT3 REF_NOT_YOURS,
          ARG3(got), ARG3(want));
}

typedef struct image_case {
    ras_scene_shader shader;
    void (*sanity)(const ras_image *ref);
    ras_compare_kind kind;
    double threshold; /* dB for PSNR, SSIM otherwise (as tests/grading/rubric.json) */
    const char *hint;
} image_case;

static const image_case image_cases[RAS_SHADER_COUNT] = {
    [RAS_SHADER_NORMAL] =
        {RAS_SHADER_NORMAL, sanity_normal, RAS_COMPARE_PSNR, 35,
         "the normal shader is given: check the interpolated normals (perspective-correct, "
         "section 1)"},
    [RAS_SHADER_PHONG] =
        {RAS_SHADER_PHONG, sanity_phong, RAS_COMPARE_PSNR, 35,
         "Blinn-Phong (section 2): ambient once, 1/r², the half vector, normalised vectors"},
    [RAS_SHADER_TEXTURE] =
        {RAS_SHADER_TEXTURE, sanity_texture, RAS_COMPARE_PSNR, 33,
         "texture (section 3) with bilinear filtering (section 4); a bent floor checkerboard "
         "means affine UVs (section 1)"},
    [RAS_SHADER_BUMP] =
        {RAS_SHADER_BUMP, sanity_bump, RAS_COMPARE_SSIM, 0.97,
         "bump mapping (section 5): the tangent frame, dU/dV, and the sign of TBN·(−dU, −dV, 1)"},
    [RAS_SHADER_DISPLACEMENT] =
        {RAS_SHADER_DISPLACEMENT, sanity_displacement, RAS_COMPARE_SSIM, 0.97,
         "displacement (section 6): move the point along the original normal, light with the "
         "bumped one"},
};

static void check_image(ras_scene_shader shader) {
    const image_case *ic = &image_cases[shader];
    /* Rendered first: in grading the student's frame is recorded in a sandbox
     * that has no reference images (tests/grading/ras_call.h). */
    ras_image *got = render(shader, FILTER_BILINEAR, NULL);
    ras_image *ref = load_reference(shader);
    ic->sanity(ref);
    ras_compare_options opt = ras_compare_defaults(ic->kind);
    if (ic->kind == RAS_COMPARE_PSNR)
        opt.min_psnr_db = ic->threshold;
    else
        opt.min_ssim = ic->threshold;
    ras_compare_result res;
    ras_error err = {{0}};
    bool ok = ras_compare_images(ref, got, &opt, &res, &err);
    ras_image_destroy(ref);
    ras_image_destroy(got);
    CHECK(ok, "hw3_%s: cannot compare: %s", ras_scene_shader_name(shader), err.msg);
    CHECK(res.pass,
          "hw3_%s: the default scene against tests/reference/hw3_%s.png (expected) — %s. "
          "Likely mistake: %s",
          ras_scene_shader_name(shader), ras_scene_shader_name(shader), res.summary, ic->hint);
}

static void test_image_normal(void **state) {
    (void)state;
    check_image(RAS_SHADER_NORMAL);
}
static void test_image_phong(void **state) {
    (void)state;
    check_image(RAS_SHADER_PHONG);
}
static void test_image_texture(void **state) {
    (void)state;
    check_image(RAS_SHADER_TEXTURE);
}
static void test_image_bump(void **state) {
    (void)state;
    check_image(RAS_SHADER_BUMP);
}
static void test_image_displacement(void **state) {
    (void)state;
    check_image(RAS_SHADER_DISPLACEMENT);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_interp_tilted_plane_exact),
        cmocka_unit_test(test_interp_affine_error_matches_theory),
        cmocka_unit_test(test_interp_w1_pitfall_caught),
        cmocka_unit_test(test_shader_normal),
        cmocka_unit_test(test_shader_blinn_phong_one_light),
        cmocka_unit_test(test_shader_viewer_off_axis),
        cmocka_unit_test(test_shader_ambient_once_not_per_light),
        cmocka_unit_test(test_shader_blinn_phong_classic_numbers),
        cmocka_unit_test(test_shader_blinn_phong_light_behind),
        cmocka_unit_test(test_shader_texture_kd_from_texture),
        cmocka_unit_test(test_shader_bump),
        cmocka_unit_test(test_shader_displacement),
        cmocka_unit_test(test_tbn_at_poles_finite),
        cmocka_unit_test(test_tbn_formula),
        cmocka_unit_test(test_bilinear_centres_and_between),
        cmocka_unit_test(test_bilinear_edges_clamp),
        cmocka_unit_test(test_bilinear_edges_repeat),
        cmocka_unit_test(test_bilinear_nan_and_huge),
        cmocka_unit_test(test_trilinear_levels),
        cmocka_unit_test(test_stages_only_what_the_shader_needs),
        cmocka_unit_test_setup_teardown(test_scene_model_errors_and_quads, quads_setup,
                                        quads_teardown),
        cmocka_unit_test(test_image_normal),
        cmocka_unit_test(test_image_phong),
        cmocka_unit_test(test_image_texture),
        cmocka_unit_test(test_image_bump),
        cmocka_unit_test(test_image_displacement),
    };
    return RAS_RUN_TESTS("hw3", tests, group_setup, group_teardown);
}
