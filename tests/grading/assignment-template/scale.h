/* scale.h — hwX: a matrix that scales a model about its origin.
 *
 * Implemented twice with the same signature: scale.c (yours, TODOs) and the
 * reference solution (instructors' edition only). Build matrices with
 * ras_mat4_rows(), which takes the 16 numbers in the order you read them on
 * paper.
 */
#ifndef RAS_HWX_SCALE_H
#define RAS_HWX_SCALE_H

#include "ras_math.h"

/* Uniform scale by `factor` about the origin: x, y and z are multiplied by
 * it, w is left alone. */
mat4s get_scale_matrix(float factor);

#endif
