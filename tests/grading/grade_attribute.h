/* grade_attribute.h — whose code a failure of the student's whole chain is
 * (tests/grading/grade_*.c; docs/grading.md, "Whose code a grade
 * measures"): the picture rendered again with one earlier assignment's
 * reference swapped in at a time, the answer leading the integration item.
 */
#ifndef RAS_GRADING_GRADE_ATTRIBUTE_H
#define RAS_GRADING_GRADE_ATTRIBUTE_H

#include "grade_priv.h"

/* it (an integration item of assignment `id` that lost points) opens with
 * whose code causes it; graded: the own-code run, own_passed its verdict;
 * whole: the whole chain's run; as[0, n_as): the assignments graded so far,
 * for their first lost point */
void attribute_image(grader *g, item *it, const cJSON *img, const char *dir, const char *id,
                     const job *graded, const job *whole, bool own_passed,
                     const assignment_result *as, int n_as);

#endif
