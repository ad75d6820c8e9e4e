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
