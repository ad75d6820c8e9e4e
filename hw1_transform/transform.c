/* transform.c — hw1: YOUR implementation of transform.h.
 *
 * Each function returns a placeholder (the identity) and prints a one-time
 * notice until you write it. Read docs/hw1.md first; run the tests with
 * `make grade HW=1` or `(cd build && ctest -L hw1)`.
 */
/* When you write a function, DELETE its two notice lines (`static bool shown;`
 * and `ras_todo_notice(...)`): the grader gives no points to a test during
 * which a notice was printed, however right the result. */
#include "transform.h"

#include "ras_todo.h"

#include <math.h> /* sinf, cosf, tanf */

mat4s get_model_matrix(float rotation_angle_deg) {
    static bool shown;
    ras_todo_notice(&shown, "get_model_matrix", "docs/hw1.md, section 1 (model matrix)");
    /* TODO(hw1) 1. Convert the angle to radians (ras_deg_to_rad): sinf/cosf
     *              take radians, and 20 "radians" spins the triangle wildly.
     * TODO(hw1) 2. Return the rotation about z with ras_mat4_rows(), written
     *              row by row as on paper: the top-left 2x2 block is
     *              [cos -sin; sin cos]; z and w are left alone. */
    (void)rotation_angle_deg;
    return glms_mat4_identity();
}

mat4s get_projection_matrix(float eye_fov_deg, float aspect_ratio, float z_near, float z_far) {
    static bool shown;
    ras_todo_notice(&shown, "get_projection_matrix",
                    "docs/hw1.md, section 2 (projection matrix)");
    /* TODO(hw1) 1. The near and far planes sit at n = -z_near and f = -z_far
     *              (the camera looks down -z; the arguments are distances).
     * TODO(hw1) 2. Squish the frustum into a box: the persp->ortho matrix
     *              [n 0 0 0; 0 n 0 0; 0 0 n+f -n*f; 0 0 1 0].
     * TODO(hw1) 3. Map the box to [-1,1]^3: top t = |n| * tan(fov/2) (fov in
     *              radians!), right r = t * aspect; scale by 2/(r-l), 2/(t-b),
     *              2/(n-f) after moving the centre to the origin.
     * TODO(hw1) 4. Return ortho * persp2ortho (glms_mat4_mul(a, b) is a * b).
     *              Check: a point up and to the right must stay up and right;
     *              if your triangle is upside down, look at the sign of n. */
    (void)eye_fov_deg;
    (void)aspect_ratio;
    (void)z_near;
    (void)z_far;
    return glms_mat4_identity();
}

mat4s get_rotation(vec3s axis, float angle_deg) {
    static bool shown;
    ras_todo_notice(&shown, "get_rotation", "docs/hw1.md, section 4 (bonus: any axis)");
    /* TODO(hw1, bonus) 1. Normalise the axis n (glms_vec3_normalize).
     * TODO(hw1, bonus) 2. Rodrigues: R = cos(a) I + (1 - cos(a)) n n^T + sin(a) N,
     *                     where N is the cross-product matrix
     *                     [0 -nz ny; nz 0 -nx; -ny nx 0].
     * TODO(hw1, bonus) 3. Put R in the top-left 3x3 of a 4x4 with 1 in the corner. */
    (void)axis;
    (void)angle_deg;
    return glms_mat4_identity();
}
