/* scale.c — hwX: YOUR implementation of scale.h.
 *
 * The function returns a placeholder (the identity) and prints a one-time
 * notice until you write it. Run the tests with `(cd build && ctest -L hwX)`.
 */
/* When you write the function, DELETE its two notice lines (`static bool
 * shown;` and `ras_todo_notice(...)`): the grader gives no points to a test
 * during which a notice was printed, however right the result. */
#include "scale.h"

#include "ras_todo.h"

mat4s get_scale_matrix(float factor) {
    static bool shown;
    ras_todo_notice(&shown, "get_scale_matrix", "the assignment's handout, section 1");
    /* TODO(hwX) 1. Return the diagonal matrix diag(factor, factor, factor, 1)
     *              with ras_mat4_rows(), row by row as on paper. */
    (void)factor;
    return glms_mat4_identity();
}
