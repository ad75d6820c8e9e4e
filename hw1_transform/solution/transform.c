/* solution/transform.c — hw1 reference implementation of transform.h.
 * RASTER101-SOLUTION: this marker must never appear in a student handout. */
#include "transform.h"

#include <math.h> /* sinf, cosf, tanf, fabsf */

mat4s get_model_matrix(float rotation_angle_deg) {
    float a = ras_deg_to_rad(rotation_angle_deg);
    float c = cosf(a), s = sinf(a);
    return ras_mat4_rows(c, -s, 0, 0,
                         s, c, 0, 0,
                         0, 0, 1, 0,
                         0, 0, 0, 1);
}

mat4s get_projection_matrix(float eye_fov_deg, float aspect_ratio, float z_near, float z_far) {
    /* The lecture's construction: squish the frustum into a box, then map the
     * box to the canonical cube. n and f are z coordinates, hence negative. */
    float n = -z_near, f = -z_far;
    float t = fabsf(n) * tanf(ras_deg_to_rad(eye_fov_deg) * 0.5f), b = -t;
    float r = t * aspect_ratio, l = -r;
    mat4s persp_to_ortho = ras_mat4_rows(n, 0, 0, 0,
                                         0, n, 0, 0,
                                         0, 0, n + f, -n * f,
                                         0, 0, 1, 0);
    mat4s scale = ras_mat4_rows(2 / (r - l), 0, 0, 0,
                                0, 2 / (t - b), 0, 0,
                                0, 0, 2 / (n - f), 0,
                                0, 0, 0, 1);
    mat4s centre = ras_mat4_rows(1, 0, 0, -(r + l) / 2,
                                 0, 1, 0, -(t + b) / 2,
                                 0, 0, 1, -(n + f) / 2,
                                 0, 0, 0, 1);
    return ras_mat4_mul(ras_mat4_mul(scale, centre), persp_to_ortho);
}

mat4s get_rotation(vec3s axis, float angle_deg) {
    vec3s k = glms_vec3_normalize(axis);
    float a = ras_deg_to_rad(angle_deg);
    float c = cosf(a), s = sinf(a), C = 1.0f - c;
    /* Rodrigues: R = c I + (1 - c) k kᵀ + s [k]ₓ, written out element by element. */
    return ras_mat4_rows(c + C * k.x * k.x, C * k.x * k.y - s * k.z, C * k.x * k.z + s * k.y, 0,
                         C * k.y * k.x + s * k.z, c + C * k.y * k.y, C * k.y * k.z - s * k.x, 0,
                         C * k.z * k.x - s * k.y, C * k.z * k.y + s * k.x, c + C * k.z * k.z, 0,
                         0, 0, 0, 1);
}
