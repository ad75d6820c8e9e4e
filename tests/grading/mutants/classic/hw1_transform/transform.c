/* transform.c — hw1, a classic GAMES101-style solution (tests/grading/mutants/classic).
 *
 * Written the way a student of the course writes it, independently of
 * hw1_transform/solution/: the fairness check of `make mutants` grades it and
 * it must get full marks. Not shipped in the handout.
 * RASTER101-SOLUTION: this marker must never appear in a student handout.
 */
#include "transform.h"

#include <math.h>

mat4s get_model_matrix(float rotation_angle_deg) {
    float a = ras_deg_to_rad(rotation_angle_deg);
    mat4s model = ras_mat4_rows(cosf(a), -sinf(a), 0, 0,
                                sinf(a), cosf(a), 0, 0,
                                0, 0, 1, 0,
                                0, 0, 0, 1);
    return model;
}

mat4s get_projection_matrix(float eye_fov_deg, float aspect_ratio, float z_near, float z_far) {
    float n = -z_near;
    float f = -z_far;
    float t = fabsf(n) * tanf(ras_deg_to_rad(eye_fov_deg) / 2.0f);
    float b = -t;
    float r = t * aspect_ratio;
    float l = -r;

    mat4s persp2ortho = ras_mat4_rows(n, 0, 0, 0,
                                      0, n, 0, 0,
                                      0, 0, n + f, -n * f,
                                      0, 0, 1, 0);
    mat4s ortho_translate = ras_mat4_rows(1, 0, 0, -(r + l) / 2,
                                          0, 1, 0, -(t + b) / 2,
                                          0, 0, 1, -(n + f) / 2,
                                          0, 0, 0, 1);
    mat4s ortho_scale = ras_mat4_rows(2 / (r - l), 0, 0, 0,
                                      0, 2 / (t - b), 0, 0,
                                      0, 0, 2 / (n - f), 0,
                                      0, 0, 0, 1);
    mat4s ortho = glms_mat4_mul(ortho_scale, ortho_translate);
    return glms_mat4_mul(ortho, persp2ortho);
}

mat4s get_rotation(vec3s axis, float angle_deg) {
    float a = ras_deg_to_rad(angle_deg);
    vec3s n = glms_vec3_normalize(axis);
    float c = cosf(a), s = sinf(a);

    /* R = cos(a) I + (1 - cos(a)) n n^T + sin(a) N */
    float I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    float nnT[3][3] = {{n.x * n.x, n.x * n.y, n.x * n.z},
                       {n.y * n.x, n.y * n.y, n.y * n.z},
                       {n.z * n.x, n.z * n.y, n.z * n.z}};
    float N[3][3] = {{0, -n.z, n.y},
                     {n.z, 0, -n.x},
                     {-n.y, n.x, 0}};
    float R[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            R[i][j] = c * I[i][j] + (1 - c) * nnT[i][j] + s * N[i][j];

    return ras_mat4_rows(R[0][0], R[0][1], R[0][2], 0,
                         R[1][0], R[1][1], R[1][2], 0,
                         R[2][0], R[2][1], R[2][2], 0,
                         0, 0, 0, 1);
}
