/* grade_assignment.h — one assignment of the rubric graded, and the
 * grading's results so far (tests/grading/grade_*.c): its tests' chunks and
 * its pictures in one batch of sandboxed runs (grade_run.h), then the
 * verdicts (grade_tests.h, grade_images.h), each picture with points drawn
 * again by the student's whole chain for the integration part, whose
 * failures say whose code causes them (grade_attribute.h).
 */
#ifndef RAS_GRADING_GRADE_ASSIGNMENT_H
#define RAS_GRADING_GRADE_ASSIGNMENT_H

#include "grade_priv.h"

/* The results of a grading, in the rubric's order, the integration part last. */
typedef struct grading {
    assignment_result *as; /* the assignments graded so far */
    int n;
    /* The integration part: the images with points again, rendered by the
     * student's whole chain, each failure attributed (attribute_image). */
    assignment_result integration;
    double integration_points; /* per image (rubric integration_points_per_image) */
    double total, max_total;
} grading;

/* room for n_assignments, nothing graded yet */
void grading_begin(grading *gr, const grader *g, int n_assignments);
/* whether the command line asks for assignment `id` (every one without --hw) */
bool grading_wants(const grader *g, const char *id);
/* assignment asg graded into gr->as[gr->n++] */
void grade_assignment(grader *g, grading *gr, const cJSON *asg);
/* the integration part, when it has items, as the last result */
void grading_end(const grader *g, grading *gr);

#endif
