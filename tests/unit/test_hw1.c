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

/* The lecture's product M_ortho · M_persp→ortho written out for the box
 * [-r, r] × [-t, t] × [f, n]: one closed form, so the matrix each mistake makes
 * can be rebuilt from the numbers the mistake puts in (n, f, t, r). */
static mat4s lecture_projection(float n, float f, float t, float r) {
    return ras_mat4_rows(n / r, 0, 0, 0, 0, n / t, 0, 0, 0, 0, (n + f) / (n - f),
                         -2 * n * f / (n - f), 0, 0, 1, 0);
}

/* One mistake: the (n, f, t, r) it writes for fov, aspect, z_near, z_far. */
typedef struct {
    float n, f, t, r;
    const char *hint;
} projection_mistake;

enum { PROJECTION_MISTAKES = 7 };

/* The mistakes students make, in the order a match is named (the first
 * that reproduces the returned matrix). Two share a matrix (the n/f swap and
 * the z scale 2/(f-n)), so their message names both. */
static void projection_mistakes(float fov, float aspect, float zn, float zf,
                                projection_mistake out[PROJECTION_MISTAKES]) {
    float half = tanf(ras_deg_to_rad(fov) * 0.5f), whole = tanf(ras_deg_to_rad(fov));
    float t = zn * half;
    out[0] = (projection_mistake){
        zn, zf, zn * half, zn * half * aspect,
        "x and y are flipped: n = +z_near instead of -z_near, the course framework's habit "
        "n = zNear, f = zFar (positive). n and f are the NEGATIVE z of the planes: n = -z_near, "
        "f = -z_far (here every visible point then gets w < 0 and is clipped away: an empty "
        "picture; the course framework, which does not clip, shows the triangle upside down)"};
    out[1] = (projection_mistake){
        -zn, -zf, -t, -t * aspect,
        "x and y are flipped while z and w are right: the top of the near plane came out "
        "negative, t = n tan(fov/2) with n = -z_near (so r = t aspect is negative too); t is a "
        "length: t = |n| tan(fov/2) = z_near tan(fov/2) (the picture turns 180 degrees)"};
    out[2] = (projection_mistake){
        -zf, -zn, zf * half, zf * half * aspect,
        "only the z row's sign is wrong (x, y and w are right): near maps to z = -1 and far to "
        "+1, so the depth order flips (hw2's depth test then keeps the farther triangle). "
        "Either n and f swapped, the course framework's zNear and zFar exchanged instead of "
        "only negated (n = -z_far, f = -z_near), or the ortho z scale written 2/(f-n) instead "
        "of 2/(n-f): both make this matrix. n = -z_near, f = -z_far"};
    out[3] = (projection_mistake){
        -zn, -zf, zn * whole, zn * whole * aspect,
        "the whole field of view was used: t = |n| tan(fov) instead of |n| tan(fov/2), so the "
        "picture is scaled down about its centre (or squashed to nothing at fov 90, where "
        "tan(fov) is infinite)"};
    out[4] = (projection_mistake){
        -zn, -zf, zn * tanf(fov * 0.5f), zn * tanf(fov * 0.5f) * aspect,
        "the fov was passed to tanf in degrees: t = |n| tan(ras_deg_to_rad(fov) / 2)"};
    out[5] = (projection_mistake){
        -zn, -zf, zn * tanf(fov), zn * tanf(fov) * aspect,
        "the fov was passed to tanf in degrees and whole: t = |n| tan(ras_deg_to_rad(fov) / 2)"};
    out[6] = (projection_mistake){
        -zn, -zf, t, t / aspect,
        "the aspect ratio applied the wrong way: r = t / aspect (or aspect applied to y); "
        "r = t * aspect, the width over the height"};
}

/* The matrix is defined up to sign (M and -M are the same projective map);
 * compare after making w positive for a point straight ahead. */
static mat4s positive_w(mat4s m) {
    vec4s ahead = glms_mat4_mulv(m, (vec4s){{0, 0, -1, 1}});
    return ahead.w < 0 ? glms_mat4_scale(m, -1) : m;
}

static bool has_nan(mat4s m) {
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            if (!isfinite(m.raw[c][r])) return true;
    return false;
}

/* Which rows of got (up to overall sign) differ from the right matrix. */
static bool row_right(mat4s got, mat4s right, int row) {
    for (int c = 0; c < 4; c++)
        if (fabsf(got.raw[c][row] - right.raw[c][row]) > 1e-4f * fmaxf(1, fabsf(right.raw[c][row])))
            return false;
    return true;
}

/* got's z row is the right one negated: near and far exchanged. */
static bool z_row_negated(mat4s got, mat4s right) {
    for (int c = 2; c < 4; c++)
        if (fabsf(got.raw[c][2] + right.raw[c][2]) > 1e-4f * fmaxf(1, fabsf(right.raw[c][2])))
            return false;
    return true;
}

/* The likely mistake, read from what get_projection_matrix returned for these
 * arguments: the mistake whose matrix it is, else which rows are wrong. */
static const char *projection_hint(float fov, float aspect, float zn, float zf, mat4s got) {
    if (ras_mat4_near(got, glms_mat4_identity(), 0))
        return "still the identity: get_projection_matrix is not written yet";
    if (has_nan(got))
        return "the matrix has NaN or infinite entries: a division by zero (n - f, r - l or "
               "t - b) or tan of 90 degrees (the whole fov instead of fov/2)";
    mat4s pg = positive_w(got);
    float half = tanf(ras_deg_to_rad(fov) * 0.5f);
    mat4s right = positive_w(lecture_projection(-zn, -zf, zn * half, zn * half * aspect));
    projection_mistake m[PROJECTION_MISTAKES];
    projection_mistakes(fov, aspect, zn, zf, m);
    for (int i = 0; i < PROJECTION_MISTAKES; i++) {
        mat4s made = positive_w(lecture_projection(m[i].n, m[i].f, m[i].t, m[i].r));
        /* at aspect 1 the aspect mistake makes the right matrix: no evidence */
        if (!ras_mat4_near(made, right, 1e-4f) && ras_mat4_near(pg, made, 1e-4f)) return m[i].hint;
    }
    bool x = row_right(pg, right, 0), y = row_right(pg, right, 1), z = row_right(pg, right, 2),
         w = row_right(pg, right, 3);
    if (!w)
        return "the w row is wrong: it must copy z into w, (0, 0, 1, 0) in the squish matrix, "
               "so that the divide by w makes the perspective";
    if (x && y && !z)
        return z_row_negated(pg, right)
                   ? m[2].hint
                   : "only the z row is wrong (x, y and w are right): the ortho z scale "
                     "2/(n-f) and centre -(n+f)/2, times the squish's (n+f, -nf) row";
    if (!x && !y && z)
        return "only the x and y scales are wrong (z and w are right): the diagonal should be "
               "n/r and n/t, i.e. cot(fov/2)/aspect and cot(fov/2) up to sign, with "
               "t = |n| tan(fov/2) and r = t aspect";
    if (!x && y && z) return m[6].hint;
    return "compare each row with docs/hw1.md section 2: t = |n| tan(fov/2), r = t aspect, "
           "n = -z_near, f = -z_far";
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
    if (ras_mat4_near(positive_w(got), expected, 1e-4f)) return;
    expect_matrix(positive_w(got), expected, 1e-4f,
                  "get_projection_matrix(90, 1, 1, 3), compared up to overall sign",
                  projection_hint(90, 1, 1, 3, got));
}

/* The classic hw1 numbers: corners of the near plane land on the corners of
 * the NDC square, keeping their orientation; near → z = +1, far → z = -1. */
static void test_projection_classic_maps_frustum_to_cube(void **state) {
    (void)state;
    mat4s m = get_projection_matrix(45, 1, 0.1f, 50);
    float t = 0.1f * tanf(ras_deg_to_rad(22.5f));
    vec3s corner = project(m, (vec3s){{t, t, -0.1f}});
    vec3s far_centre = project(m, (vec3s){{0, 0, -50}});
    /* A point off axis: x_ndc = x / (z_dist · tan(fov/2)). */
    vec3s p = project(m, (vec3s){{1, 0, -5}});
    float expected_x = 1.0f / (5.0f * tanf(ras_deg_to_rad(22.5f)));
    bool corner_right =
        fabsf(corner.x - 1) < 1e-3f && fabsf(corner.y - 1) < 1e-3f && fabsf(corner.z - 1) < 1e-3f;
    if (corner_right && fabsf(far_centre.z + 1) < 1e-3f && fabsf(p.x - expected_x) < 1e-4f) return;
    char got[512];
    ras_mat4_format(m, got, sizeof got);
    fail_msg("get_projection_matrix(45, 1, 0.1, 50), after the divide by w:\n"
             "  the near plane's top-right corner (%.5f, %.5f, -0.1): expected (1, 1, 1) "
             "(near maps to z = +1, GAMES101 convention), got (%.4f, %.4f, %.4f)\n"
             "  the far plane's centre (0, 0, -50): expected z = -1, got z = %.4f\n"
             "  the point (1, 0, -5): expected x = %.5f, got x = %.5f\n"
             "the matrix returned (rows as on paper):\n%s"
             "likely mistake: %s",
             t, t, corner.x, corner.y, corner.z, far_centre.z, expected_x, p.x, got,
             projection_hint(45, 1, 0.1f, 50, m));
}

/* aspect 2: x is squeezed by half relative to y. */
static void test_projection_respects_aspect(void **state) {
    (void)state;
    mat4s m = get_projection_matrix(60, 2, 1, 10);
    vec3s p = project(m, (vec3s){{1, 1, -4}});
    if (fabsf(p.x * 2 - p.y) > 1e-4f)
        fail_msg("with aspect 2, x_ndc should be half of y_ndc for (1,1,-4); got x %.5f y "
                 "%.5f; likely mistake: %s",
                 p.x, p.y, projection_hint(60, 2, 1, 10, m));
}

/* Rodrigues' formula as the sum of three matrices, with k used as given (the
 * caller normalises it, or not, to rebuild that mistake). */
static mat4s rodrigues(vec3s k, float rad) {
    float c = cosf(rad), s = sinf(rad);
    mat4s r = glms_mat4_identity();
    const float N[3][3] = {{0, -k.z, k.y}, {k.z, 0, -k.x}, {-k.y, k.x, 0}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.raw[j][i] = (i == j ? c : 0) + (1 - c) * k.raw[i] * k.raw[j] + s * N[i][j];
    return r;
}

static mat4s rotation_expected(vec3s axis, float deg) {
    return rodrigues(glms_vec3_normalize(axis), ras_deg_to_rad(deg));
}

/* What a 3x3 part is, in words: "a rotation by A deg about (x, y, z)", or not
 * a rotation (column lengths, det), so a message says what came. */
static void describe_rotation(mat4s m, char *buf, size_t size) {
    if (has_nan(m)) {
        snprintf(buf, size, "a matrix with NaN or infinite entries (0/0, or acos of more than 1)");
        return;
    }
    vec3s c0 = {{m.raw[0][0], m.raw[0][1], m.raw[0][2]}};
    vec3s c1 = {{m.raw[1][0], m.raw[1][1], m.raw[1][2]}};
    vec3s c2 = {{m.raw[2][0], m.raw[2][1], m.raw[2][2]}};
    float len[3], det = glms_vec3_dot(c0, glms_vec3_cross(c1, c2));
    for (int c = 0; c < 3; c++)
        len[c] = sqrtf(m.raw[c][0] * m.raw[c][0] + m.raw[c][1] * m.raw[c][1] +
                       m.raw[c][2] * m.raw[c][2]);
    bool unit = fabsf(len[0] - 1) < 1e-3f && fabsf(len[1] - 1) < 1e-3f && fabsf(len[2] - 1) < 1e-3f;
    if (!unit || fabsf(det - 1) > 1e-3f) {
        snprintf(buf, size,
                 "not a rotation: its columns have lengths %.4f, %.4f, %.4f and "
                 "its determinant is %.4f (a rotation's are 1)",
                 len[0], len[1], len[2], det);
        return;
    }
    float tr = m.raw[0][0] + m.raw[1][1] + m.raw[2][2];
    float angle = acosf(fmaxf(-1, fminf(1, (tr - 1) / 2)));
    vec3s axis = {
        {m.raw[1][2] - m.raw[2][1], m.raw[2][0] - m.raw[0][2], m.raw[0][1] - m.raw[1][0]}};
    if (glms_vec3_norm(axis) < 1e-4f) {
        snprintf(buf, size, "a rotation by %.1f degrees (its axis cannot be read off)",
                 angle * (float)(180 / RAS_PI));
        return;
    }
    axis = glms_vec3_normalize(axis);
    snprintf(buf, size, "a rotation by %.1f degrees about (%.3f, %.3f, %.3f)",
             angle * (float)(180 / RAS_PI), axis.x, axis.y, axis.z);
}

static const char *const ROTATION_ANGLE_OF_AXIS =
    "an angle computed from the axis with atan/acos (an Euler-style decomposition: tilt the "
    "axis onto z, turn, tilt back): atan(y/z) is 0/0 = NaN for the x axis, and loses the sign "
    "of z, so axes with z < 0 turn the wrong way; Rodrigues' R = cos a I + (1 - cos a) n nT "
    "+ sin a N needs no angle of the axis (or use atan2 and handle y = z = 0)";

/* The likely mistake, read from what get_rotation(axis, deg) returned. */
static const char *rotation_hint(vec3s axis, float deg, mat4s got) {
    float rad = ras_deg_to_rad(deg);
    vec3s k = glms_vec3_normalize(axis);
    if (has_nan(got)) return ROTATION_ANGLE_OF_AXIS;
    if (ras_mat4_near(got, glms_mat4_identity(), 0) && fmodf(deg, 360) != 0)
        return "still the identity: get_rotation is not written yet";
    if (fabsf(glms_vec3_norm(axis) - 1) > 1e-4f && ras_mat4_near(got, rodrigues(axis, rad), 1e-4f))
        return "the axis is not normalised: n nT and N need the UNIT axis (with |axis| != 1 "
               "the result is not a rotation: its columns are not unit vectors); normalise the "
               "axis before using it";
    if (ras_mat4_near(got, rodrigues(k, -rad), 1e-4f))
        return "it turns the other way (the same axis, the angle negated): the sin term of "
               "Rodrigues (sin a N) has the wrong sign, or the cross-product matrix N is "
               "transposed (N = [[0, -nz, ny], [nz, 0, -nx], [-ny, nx, 0]]), or the whole "
               "matrix written transposed";
    if (ras_mat4_near(got, rodrigues(k, deg), 1e-4f))
        return "the angle was passed to cosf/sinf in degrees; convert with ras_deg_to_rad()";
    if (ras_mat4_near(got, rodrigues(glms_vec3_negate(k), rad), 1e-4f))
        return "it turns the other way: the rotation is about the negated axis";
    if (!ras_mat4_near(glms_mat4_mul(glms_mat4_transpose(got), got), glms_mat4_identity(), 1e-3f))
        return "the result is not a rotation (its columns are not unit and perpendicular): the "
               "axis not normalised, or a term of Rodrigues wrong: cos a I, (1 - cos a) n nT "
               "(the outer product: column times row) and sin a N";
    return "a rotation, but not this one: check each term of Rodrigues, R = cos a I + "
           "(1 - cos a) n nT + sin a N, with n the normalised axis";
}

/* expect_matrix for a rotation: the message also says what the returned
 * matrix is (a rotation by which angle about which axis, or not one); the
 * hint is the caller's when its own evidence decides, else read from `got`. */
static void expect_rotation(vec3s axis, float deg, mat4s got, mat4s expected, const char *what,
                            const char *hint) {
    if (ras_mat4_near(got, expected, 1e-5f)) return;
    vec3s k = glms_vec3_normalize(axis);
    char is[200], full[600];
    describe_rotation(got, is, sizeof is);
    snprintf(full, sizeof full,
             "%s\nexpected a rotation by %g degrees about (%.3f, %.3f, %.3f); got %s", what,
             (double)deg, k.x, k.y, k.z, is);
    expect_matrix(got, expected, 1e-5f, full, hint ? hint : rotation_hint(axis, deg, got));
}

/* About the z axis, Rodrigues must agree with the plain z rotation. */
static void test_rotation_about_z_matches_model_matrix(void **state) {
    (void)state;
    const float angles[] = {0, 25, 90, -130, 360};
    for (size_t i = 0; i < sizeof angles / sizeof *angles; i++)
        expect_rotation((vec3s){{0, 0, 1}}, angles[i], get_rotation((vec3s){{0, 0, 1}}, angles[i]),
                        rot_z_rad(ras_deg_to_rad(angles[i])),
                        "get_rotation((0,0,1), angle) vs the z rotation", NULL);
}

/* The axis need not be unit length: (0,0,2) is the same axis as (0,0,1). */
static void test_rotation_normalises_axis(void **state) {
    (void)state;
    vec3s axis = {{0, 0, 2}};
    expect_rotation(axis, 40, get_rotation(axis, 40), rot_z_rad(ras_deg_to_rad(40)),
                    "get_rotation((0,0,2), 40)", NULL);
}

/* 120° about (1,1,1) cycles the axes: x → y → z → x (a fact of the cube's symmetry). */
static void test_rotation_about_diagonal_cycles_axes(void **state) {
    (void)state;
    vec3s axis = {{1, 1, 1}};
    expect_rotation(axis, 120, get_rotation(axis, 120),
                    ras_mat4_rows(0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1),
                    "get_rotation((1,1,1), 120) should map x to y, y to z, z to x", NULL);
}

/* Axes the other rotation tests miss: the x axis (y = z = 0), the y axis
 * (z = 0) and axes with z < 0 — where an angle taken from the axis with
 * atan(y/z) is undefined or loses z's sign. The first three are written by
 * hand; the last is Rodrigues' formula. */
static void test_rotation_any_axis_direction(void **state) {
    (void)state;
    const float deg = 50, c = cosf(ras_deg_to_rad(deg)), s = sinf(ras_deg_to_rad(deg));
    const struct {
        vec3s axis;
        mat4s expected;
        const char *what;
    } cases[] = {
        {{{1, 0, 0}},
         ras_mat4_rows(1, 0, 0, 0, 0, c, -s, 0, 0, s, c, 0, 0, 0, 0, 1),
         "get_rotation((1,0,0), 50), about the x axis"},
        {{{0, 1, 0}},
         ras_mat4_rows(c, 0, s, 0, 0, 1, 0, 0, -s, 0, c, 0, 0, 0, 0, 1),
         "get_rotation((0,1,0), 50), about the y axis"},
        {{{0, 0, -1}},
         rot_z_rad(-ras_deg_to_rad(deg)),
         "get_rotation((0,0,-1), 50), about the negative z axis (clockwise seen from +z)"},
        {{{1, -2, -3}},
         rotation_expected((vec3s){{1, -2, -3}}, deg),
         "get_rotation((1,-2,-3), 50), an axis with z < 0"},
    };
    enum { CASES = sizeof cases / sizeof *cases };
    mat4s got[CASES];
    bool any_nan = false, wrong_exactly_where_z_negative = true;
    int first_wrong = -1;
    for (int i = 0; i < CASES; i++) {
        got[i] = get_rotation(cases[i].axis, deg);
        bool right = ras_mat4_near(got[i], cases[i].expected, 1e-5f);
        any_nan |= has_nan(got[i]);
        if (!right && first_wrong < 0) first_wrong = i;
        if (right == (cases[i].axis.z < 0)) wrong_exactly_where_z_negative = false;
    }
    if (first_wrong < 0) return;
    /* The evidence across the axes decides: NaN for some, or wrong exactly
     * where z < 0, is an angle taken from the axis. */
    const char *hint = any_nan ? ROTATION_ANGLE_OF_AXIS
                       : wrong_exactly_where_z_negative
                           ? "right about the x and y axes, wrong for every axis with z < 0: "
                           : NULL;
    char joined[640];
    if (hint && !any_nan) {
        snprintf(joined, sizeof joined, "%s%s", hint, ROTATION_ANGLE_OF_AXIS);
        hint = joined;
    }
    expect_rotation(cases[first_wrong].axis, deg, got[first_wrong], cases[first_wrong].expected,
                    cases[first_wrong].what, hint);
}

/* Composition: two turns about one axis add up, R(a)·R(b) = R(a+b). */
static void test_rotation_composes(void **state) {
    (void)state;
    vec3s axis = {{0.3f, -0.5f, 0.8f}};
    mat4s once = get_rotation(axis, 85);
    mat4s composed = glms_mat4_mul(get_rotation(axis, 35), get_rotation(axis, 50));
    expect_matrix(composed, once, 1e-5f,
                  "get_rotation(axis, 35) * get_rotation(axis, 50) vs get_rotation(axis, 85)",
                  rotation_hint(axis, 85, once));
    /* and it is a rotation: it keeps lengths and the axis itself. */
    vec4s a = glms_mat4_mulv(once, glms_vec4(axis, 0));
    if (fabsf(a.x - axis.x) > 1e-5f || fabsf(a.y - axis.y) > 1e-5f || fabsf(a.z - axis.z) > 1e-5f)
        fail_msg("get_rotation((0.3, -0.5, 0.8), 85) must leave its own axis put: expected "
                 "(0.3000, -0.5000, 0.8000), got (%.4f, %.4f, %.4f); likely mistake: %s",
                 a.x, a.y, a.z, rotation_hint(axis, 85, once));
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
        cmocka_unit_test(test_rotation_any_axis_direction),
        cmocka_unit_test(test_rotation_composes),
    };
    return RAS_RUN_TESTS("hw1", tests, NULL, NULL);
}
