/* ras_math.h — small math on cglm's struct API, plus what a student needs on top.
 *
 * Everything is by value (vec3s, vec4s, mat4s). cglm stores matrices
 * column-major: m.m[col][row]. A matrix written on paper is row-major, so
 * ras_mat4_rows() takes the 16 numbers in reading order — the same order as
 * Eigen's comma initializer in the original GAMES101 framework:
 *
 *     mat4s T = ras_mat4_rows(1, 0, 0, tx,
 *                             0, 1, 0, ty,
 *                             0, 0, 1, tz,
 *                             0, 0, 0, 1);
 *
 * Conventions: right-handed world, angles at the public API in degrees.
 */
#ifndef RAS_MATH_H
#define RAS_MATH_H

#include <math.h> /* isfinite */
#include <cglm/struct.h> /* vec3s, mat4s, glms_* */
#include <stdbool.h>

#define RAS_PI 3.14159265358979323846

/* Row-major constructor: arguments in the order you read the matrix on paper. */
mat4s ras_mat4_rows(float a00, float a01, float a02, float a03,
                    float a10, float a11, float a12, float a13,
                    float a20, float a21, float a22, float a23,
                    float a30, float a31, float a32, float a33);

/* a · b and m · v, rounded the same on every system. cglm's glms_mat4_mul
 * and glms_mat4_mulv add their four products in an order that changed
 * between versions: 0.7.9 (Debian 11) adds (x + y) + (z + w), 0.8 and later
 * (Debian 12, 13; SSE2, no FMA) ((w + z) + y) + x for mulv and
 * ((x + y) + z) + w for mul, and its ARM (NEON) path in yet another order,
 * fused in places. A vertex with four non-zero terms (a rotation about no
 * coordinate axis) then lands a few ulps apart, the depth test decides its
 * ties otherwise, and Debian 11's bump and displacement pictures differed
 * from the references in 7 and 1 pixels. These keep cglm 0.8's order, which
 * drew the references, in plain C (-ffp-contract=off: no fused
 * multiply-add), so every cglm version, compiler and CPU gets the same bits. */
static inline vec4s ras_mat4_mulv(mat4s m, vec4s v) {
    vec4s out;
    for (int r = 0; r < 4; r++)
        out.raw[r] =
            ((m.raw[3][r] * v.w + m.raw[2][r] * v.z) + m.raw[1][r] * v.y) + m.raw[0][r] * v.x;
    return out;
}

/* m · (v, w), the x, y, z of it (as glms_mat4_mulv3). */
static inline vec3s ras_mat4_mulv3(mat4s m, vec3s v, float w) {
    vec4s p = ras_mat4_mulv(m, (vec4s){{v.x, v.y, v.z, w}});
    return (vec3s){{p.x, p.y, p.z}};
}

mat4s ras_mat4_mul(mat4s a, mat4s b);

/* Element at (row, col) as on paper, whatever cglm's storage order. */
static inline float ras_mat4_at(mat4s m, int row, int col) { return m.raw[col][row]; }

static inline float ras_deg_to_rad(float deg) { return deg * (float)(RAS_PI / 180.0); }

/* True when every element differs by at most tol. */
bool ras_mat4_near(mat4s a, mat4s b, float tol);

/* Largest |a - b| over the 16 elements. */
float ras_mat4_max_diff(mat4s a, mat4s b);

/* Writes the matrix in reading order, one row per line, into buf. */
void ras_mat4_format(mat4s m, char *buf, int size);

/* True when all components are finite (no NaN, no Inf). Inline: the
 * pipeline asks for every vertex and the bump shader for every fragment. */
static inline bool ras_vec4_finite(vec4s v) {
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z) && isfinite(v.w);
}
static inline bool ras_vec3_finite(vec3s v) {
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}
static inline bool ras_vec2_finite(vec2s v) { return isfinite(v.x) && isfinite(v.y); }

#endif
