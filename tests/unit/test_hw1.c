/* test_hw1.c — hw1_transform: model, projection and rotation matrices.
 *
 * Built twice: against solution/transform.c (must pass, in `make test`) and
 * against the student's transform.c (graded). Every failure prints what was
 * expected, what came, and the mistake that usually produces it.
 */
#include "ras_math.h"
#include "transform.h"

#include <math.h>
#include <setjmp.h> /* cmocka needs these three before cmocka.h */
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "ras_test_main.h" /* RAS_RUN_TESTS: one test per process for the grader */

#define TOL 1e-5f

/* Fails with both matrices printed and a hint. */
static void expect_matrix(mat4s got, mat4s expected, float tol, const char *what,
                          const char *hint) {
    if (ras_mat4_near(got, expected, tol)) return;
    char g[512], e[512];
    ras_mat4_format(got, g, sizeof g);
    ras_mat4_format(expected, e, sizeof e);
    fail_msg("%s\nexpected (rows as on paper):\n%sgot:\n%slikely mistake: %s", what, e, g, hint);
}

/* Rotation about z by `rad` RADIANS, written out independently of the solution. */
static mat4s rot_z_rad(float rad) {
    float c = cosf(rad), s = sinf(rad);
    return ras_mat4_rows(c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1);
}

static const char *model_hint(mat4s got, float deg) {
    if (ras_mat4_near(got, rot_z_rad(deg), 1e-4f))
        return "the angle was passed to cosf/sinf in degrees; convert with ras_deg_to_rad()";
    if (ras_mat4_near(got, rot_z_rad(-ras_deg_to_rad(deg)), 1e-4f))
        return "the rotation goes clockwise: the -sin belongs in row 0, column 1";
    if (ras_mat4_near(got, glms_mat4_transpose(rot_z_rad(ras_deg_to_rad(deg))), 1e-4f))
        return "the matrix is transposed: ras_mat4_rows takes the rows in reading order";
    if (ras_mat4_near(got, glms_mat4_identity(), 0))
        return "still the identity: get_model_matrix is not written yet";
    return "compare with the rotation matrix in docs/hw1.md, section 1";
}

/* A test whose right answer is the identity passes on the stub's placeholder
 * (the identity) too: it counts only once the function turns something.
 * Checked after the test's own case, so a wrong answer there is named first;
 * any rotation by 37 degrees, right or wrong, is not the identity. */
static void expect_not_placeholder(mat4s turned, const char *call, const char *function) {
    if (!ras_mat4_near(turned, glms_mat4_identity(), 1e-6f)) return;
    fail_msg("%s returned the identity: that is the stub's placeholder, so this test, whose "
             "right answer is also the identity, cannot count yet; likely mistake: %s is not "
             "written yet (or ignores its angle)",
             call, function);
}

/* 0 degrees is no rotation at all. */
static void test_model_matrix_zero_is_identity(void **state) {
    (void)state;
    mat4s m = get_model_matrix(0);
    expect_matrix(m, glms_mat4_identity(), TOL, "get_model_matrix(0)", model_hint(m, 0));
    expect_not_placeholder(get_model_matrix(37), "get_model_matrix(37)", "get_model_matrix");
}

/* 90 degrees turns +x into +y (counter-clockwise seen from +z). */
static void test_model_matrix_90_turns_x_into_y(void **state) {
    (void)state;
    mat4s m = get_model_matrix(90);
    expect_matrix(m, ras_mat4_rows(0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1), TOL,
                  "get_model_matrix(90)", model_hint(m, 90));
}

/* -30 degrees: cos 30° = 0.8660254, sin 30° = 0.5, worked by hand. */
static void test_model_matrix_minus_30(void **state) {
    (void)state;
    mat4s m = get_model_matrix(-30);
    expect_matrix(
        m, ras_mat4_rows(0.8660254f, 0.5f, 0, 0, -0.5f, 0.8660254f, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1),
        TOL, "get_model_matrix(-30)", model_hint(m, -30));
}

/* A full turn comes back to the identity (float rounding aside). */
static void test_model_matrix_360_is_identity(void **state) {
    (void)state;
    mat4s m = get_model_matrix(360);
    expect_matrix(m, glms_mat4_identity(), 1e-5f, "get_model_matrix(360)", model_hint(m, 360));
    expect_not_placeholder(get_model_matrix(37), "get_model_matrix(37)", "get_model_matrix");
}

/* The matrix is defined up to sign (M and -M are the same projective map);
 * compare after making w positive for a point straight ahead. */
static mat4s positive_w(mat4s m) {
    vec4s ahead = glms_mat4_mulv(m, (vec4s){{0, 0, -1, 1}});
    return ahead.w < 0 ? glms_mat4_scale(m, -1) : m;
}

static vec3s project(mat4s m, vec3s p) {
    vec4s c = glms_mat4_mulv(m, glms_vec4(p, 1));
    return (vec3s){{c.x / c.w, c.y / c.w, c.z / c.w}};
}

/* fov 90°, aspect 1, near 1, far 3, worked by hand (docs/hw1.md, section 2):
 * n = -1, f = -3, t = |n| tan 45° = 1, r = 1;
 * persp→ortho = [-1 0 0 0; 0 -1 0 0; 0 0 -4 -3; 0 0 1 0];
 * ortho = scale(1/r, 1/t, 2/(n-f) = 1) · translate(0, 0, -(n+f)/2 = 2)
 *       = [1 0 0 0; 0 1 0 0; 0 0 1 2; 0 0 0 1];
 * product = [-1 0 0 0; 0 -1 0 0; 0 0 -2 -3; 0 0 1 0] (or its negative). */
static void test_projection_matches_hand_worked_matrix(void **state) {
    (void)state;
    mat4s got = get_projection_matrix(90, 1, 1, 3);
    mat4s expected = ras_mat4_rows(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2, 3, 0, 0, -1, 0);
    const char *hint = "see docs/hw1.md section 2";
    mat4s flipped_n = positive_w(get_projection_matrix(90, 1, -1, -3));
    if (ras_mat4_near(got, glms_mat4_identity(), 0))
        hint = "still the identity: get_projection_matrix is not written yet";
    else if (fabsf(ras_mat4_at(positive_w(got), 0, 0) + 1) < 1e-4f)
        hint = "x and y are flipped: n = +z_near instead of -z_near. n and f must be the "
               "NEGATIVE z of the planes, n = -z_near, f = -z_far (here every visible point "
               "then gets w < 0 and is clipped away: an empty picture; the course framework, "
               "which does not clip, shows the triangle upside down)";
    else if (ras_mat4_near(positive_w(got), flipped_n, 1e-4f))
        hint = "n and f have the wrong sign";
    else if (fabsf(ras_mat4_at(got, 0, 0)) < 1e-3f && fabsf(ras_mat4_at(got, 1, 1)) < 1e-3f &&
             fabsf(fabsf(ras_mat4_at(got, 3, 2)) - 1) < 1e-4f)
        hint = "x and y are squashed to 0 at fov 90: the whole field of view was used, and "
               "tan(90 deg) is infinite; the top of the near plane is t = |n| tan(fov / 2)";
    /* the z row alone: x, y and w right, z's sign or scale wrong */
    mat4s z_negated = expected, pg = positive_w(got);
    bool others_right = true;
    for (int c = 0; c < 4; c++) {
        z_negated.raw[c][2] = -z_negated.raw[c][2];
        for (int r = 0; r < 4; r++)
            if (r != 2 && fabsf(pg.raw[c][r] - expected.raw[c][r]) > 1e-4f) others_right = false;
    }
    if (!ras_mat4_near(pg, expected, 1e-4f) && others_right && !strstr(hint, "identity"))
        hint = ras_mat4_near(pg, z_negated, 1e-4f)
                   ? "only the z row's sign is wrong (x, y and w are right): near maps to -1 "
                     "and far to +1, so the depth order flips; the z row is ((n+f)/(n-f), "
                     "-2nf/(n-f)) up to the overall sign, with n = -z_near, f = -z_far"
                   : "only the z row is wrong (x, y and w are right): the ortho z scale "
                     "2/(n-f) and centre -(n+f)/2, times the squish's (n+f, -nf) row";
    expect_matrix(positive_w(got), expected, 1e-4f,
                  "get_projection_matrix(90, 1, 1, 3), compared up to overall sign", hint);
}

/* The classic hw1 numbers: corners of the near plane land on the corners of
 * the NDC square, keeping their orientation; near → z = +1, far → z = -1. */
static void test_projection_classic_maps_frustum_to_cube(void **state) {
    (void)state;
    mat4s m = get_projection_matrix(45, 1, 0.1f, 50);
    float t = 0.1f * tanf(ras_deg_to_rad(22.5f));
    vec3s corner = project(m, (vec3s){{t, t, -0.1f}});
    if (fabsf(corner.x + 1) < 1e-3f && fabsf(corner.y + 1) < 1e-3f)
        fail_msg("the near plane's top-right corner landed at (%.3f, %.3f): x and y flipped "
                 "(w < 0: the picture is empty here, clipped away; upside down in the course "
                 "framework); likely mistake: n = +z_near instead of -z_near",
                 corner.x, corner.y);
    assert_true(fabsf(corner.x - 1) < 1e-3f && fabsf(corner.y - 1) < 1e-3f);
    if (fabsf(corner.z - 1) > 1e-3f)
        fail_msg("the near plane should map to z = +1 (GAMES101 convention), got z = %.4f; "
                 "likely mistake: the ortho z scale 2/(n-f) or the centre -(n+f)/2",
                 corner.z);
    vec3s far_centre = project(m, (vec3s){{0, 0, -50}});
    if (fabsf(far_centre.z + 1) > 1e-3f)
        fail_msg("the far plane should map to z = -1, got z = %.4f", far_centre.z);
    /* A point halfway off axis: x_ndc = x / (z_dist · tan(fov/2)). */
    vec3s p = project(m, (vec3s){{1, 0, -5}});
    float expected_x = 1.0f / (5.0f * tanf(ras_deg_to_rad(22.5f)));
    if (fabsf(p.x - expected_x) > 1e-4f)
        fail_msg("(1, 0, -5) should land at x_ndc = %.5f, got %.5f; likely mistake: the fov "
                 "was used whole instead of halved, or in degrees",
                 expected_x, p.x);
}

/* aspect 2: x is squeezed by half relative to y. */
static void test_projection_respects_aspect(void **state) {
    (void)state;
    mat4s m = get_projection_matrix(60, 2, 1, 10);
    vec3s p = project(m, (vec3s){{1, 1, -4}});
    if (fabsf(p.x * 2 - p.y) > 1e-4f)
        fail_msg("with aspect 2, x_ndc should be half of y_ndc for (1,1,-4); got x %.5f y "
                 "%.5f; likely mistake: r = t / aspect, or aspect applied to y",
                 p.x, p.y);
}

/* About the z axis, Rodrigues must agree with the plain z rotation. */
static void test_rotation_about_z_matches_model_matrix(void **state) {
    (void)state;
    const float angles[] = {0, 25, 90, -130, 360};
    for (size_t i = 0; i < sizeof angles / sizeof *angles; i++) {
        mat4s got = get_rotation((vec3s){{0, 0, 1}}, angles[i]);
        expect_matrix(got, rot_z_rad(ras_deg_to_rad(angles[i])), 1e-5f,
                      "get_rotation((0,0,1), angle) vs the z rotation",
                      ras_mat4_near(got, glms_mat4_identity(), 0) && angles[i] != 0
                          ? "still the identity: get_rotation is not written yet"
                      : ras_mat4_near(got, rot_z_rad(-ras_deg_to_rad(angles[i])), 1e-5f)
                          ? "it turns the other way: the sin term of Rodrigues (sin a N) has the "
                            "wrong sign, or the cross-product matrix N is transposed (N = [[0, "
                            "-nz, ny], [nz, 0, -nx], [-ny, nx, 0]])"
                          : "Rodrigues: R = cos a I + (1-cos a) n nT + sin a N");
    }
}

/* The axis need not be unit length: (0,0,2) is the same axis as (0,0,1). */
static void test_rotation_normalises_axis(void **state) {
    (void)state;
    expect_matrix(get_rotation((vec3s){{0, 0, 2}}, 40), rot_z_rad(ras_deg_to_rad(40)), 1e-5f,
                  "get_rotation((0,0,2), 40)", "normalise the axis before using it");
}

/* 120° about (1,1,1) cycles the axes: x → y → z → x (a fact of the cube's symmetry). */
static void test_rotation_about_diagonal_cycles_axes(void **state) {
    (void)state;
    mat4s r = get_rotation((vec3s){{1, 1, 1}}, 120);
    expect_matrix(r, ras_mat4_rows(0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1), 1e-5f,
                  "get_rotation((1,1,1), 120) should map x to y, y to z, z to x",
                  "check the sign of the sin term (the cross-product matrix N)");
}

/* Composition: two turns about one axis add up, R(a)·R(b) = R(a+b). */
static void test_rotation_composes(void **state) {
    (void)state;
    vec3s axis = {{0.3f, -0.5f, 0.8f}};
    mat4s composed = glms_mat4_mul(get_rotation(axis, 35), get_rotation(axis, 50));
    expect_matrix(composed, get_rotation(axis, 85), 1e-5f,
                  "get_rotation(axis, 35) * get_rotation(axis, 50) vs get_rotation(axis, 85)",
                  "the result is not a rotation about the axis: check n nT and N");
    /* and it is a rotation: it keeps lengths and the axis itself. */
    vec4s a = glms_mat4_mulv(get_rotation(axis, 85), glms_vec4(axis, 0));
    if (fabsf(a.x - axis.x) > 1e-5f || fabsf(a.y - axis.y) > 1e-5f || fabsf(a.z - axis.z) > 1e-5f)
        fail_msg("the axis must stay put under its own rotation: got (%.4f, %.4f, %.4f)", a.x, a.y,
                 a.z);
    expect_not_placeholder(get_rotation(axis, 37), "get_rotation((0.3, -0.5, 0.8), 37)",
                           "get_rotation");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_model_matrix_zero_is_identity),
        cmocka_unit_test(test_model_matrix_90_turns_x_into_y),
        cmocka_unit_test(test_model_matrix_minus_30),
        cmocka_unit_test(test_model_matrix_360_is_identity),
        cmocka_unit_test(test_projection_matches_hand_worked_matrix),
        cmocka_unit_test(test_projection_classic_maps_frustum_to_cube),
        cmocka_unit_test(test_projection_respects_aspect),
        cmocka_unit_test(test_rotation_about_z_matches_model_matrix),
        cmocka_unit_test(test_rotation_normalises_axis),
        cmocka_unit_test(test_rotation_about_diagonal_cycles_axes),
        cmocka_unit_test(test_rotation_composes),
    };
    return RAS_RUN_TESTS("hw1", tests, NULL, NULL);
}
