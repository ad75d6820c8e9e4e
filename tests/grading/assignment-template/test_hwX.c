/* test_hwX.c — hwX_template: the scale matrix.
 *
 * Built twice (tests/unit/CMakeLists.txt, raster101_assignment_test):
 * against solution/scale.c (must pass, in `make test`) and against the
 * student's scale.c. Every failure prints what was expected, what came, and
 * the mistake that usually produces it.
 */
#include "ras_math.h"
#include "scale.h"

#include <setjmp.h> /* cmocka needs these three before cmocka.h */
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "ras_test_main.h" /* RAS_RUN_TESTS: one test per process for the grader */

/* Halving moves a point halfway to the origin and leaves w alone. */
static void test_scale_matrix_halves_a_point(void **state) {
    (void)state;
    vec4s p = glms_mat4_mulv(get_scale_matrix(0.5f), (vec4s){{2, 4, -6, 1}});
    if (p.x != 1 || p.y != 2 || p.z != -3 || p.w != 1)
        fail_msg("get_scale_matrix(0.5) * (2, 4, -6, 1): expected (1, 2, -3, 1), got (%g, %g, "
                 "%g, %g)\nlikely mistake: %s",
                 p.x, p.y, p.z, p.w,
                 p.w != 1 ? "w was scaled too: the bottom-right entry stays 1"
                          : "still the identity, or a factor off the diagonal");
}

/* A factor of 1 is no scale at all. */
static void test_scale_matrix_one_is_identity(void **state) {
    (void)state;
    if (!ras_mat4_near(get_scale_matrix(1), glms_mat4_identity(), 0))
        fail_msg("get_scale_matrix(1) must be the identity\nlikely mistake: an entry off the "
                 "diagonal");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scale_matrix_halves_a_point),
        cmocka_unit_test(test_scale_matrix_one_is_identity),
    };
    return RAS_RUN_TESTS("hwX", tests, NULL, NULL);
}
