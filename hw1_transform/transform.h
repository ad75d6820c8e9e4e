/* transform.h — hw1: the matrices that place a triangle on the screen.
 *
 * Implemented twice with the same signatures: transform.c (yours, TODOs) and
 * the reference solution (instructors' edition only). See docs/hw1.md.
 *
 * Conventions: right-handed world; the camera looks down -z; angles in
 * DEGREES; z_near and z_far are POSITIVE distances (the visible depths are
 * z in [-z_far, -z_near]). Build matrices with ras_mat4_rows(), which takes
 * the 16 numbers in the order you read them on paper.
 */
#ifndef RAS_HW1_TRANSFORM_H
#define RAS_HW1_TRANSFORM_H

#include "ras_math.h"

/* Rotation by rotation_angle_deg degrees about the z axis
 * (counter-clockwise seen from +z). */
mat4s get_model_matrix(float rotation_angle_deg);

/* Perspective projection: eye_fov_deg is the full vertical field of view in
 * degrees, aspect_ratio = width / height. After dividing by w, the view
 * frustum maps to the cube [-1, 1]³ with the NEAR plane at z = +1 and the far
 * plane at z = -1 (the GAMES101 lecture convention); x and y keep their
 * orientation (a point up-right of the view axis lands up-right). Either sign
 * of the whole matrix is accepted: M and -M are the same projective map. */
mat4s get_projection_matrix(float eye_fov_deg, float aspect_ratio, float z_near, float z_far);

/* Bonus: rotation by angle_deg degrees about `axis` through the origin
 * (Rodrigues' formula). The axis need not be unit length. */
mat4s get_rotation(vec3s axis, float angle_deg);

#endif
