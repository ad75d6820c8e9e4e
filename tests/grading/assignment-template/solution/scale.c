/* solution/scale.c — hwX reference implementation of scale.h.
 * RASTER101-SOLUTION: this marker must never appear in a student handout. */
#include "scale.h"

mat4s get_scale_matrix(float factor) {
    return ras_mat4_rows(factor, 0, 0, 0,
                         0, factor, 0, 0,
                         0, 0, factor, 0,
                         0, 0, 0, 1);
}
