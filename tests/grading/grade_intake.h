/* grade_intake.h — what a grading is given (tests/grading/grade_*.c).
 * tests/grading/grade has taken the submission in: unpacked and picked
 * inside the sandbox (tests/grading/pick-files), put into the sandbox's tree
 * (tests/grading/manifest) and built there. It hands this program the
 * result: the rubric, the sandbox's folders, what it found in the
 * submission (--notes) and the seed the variants are drawn from (--seed).
 * Here they are read and checked; each check that fails says why on stderr.
 */
#ifndef RAS_GRADING_GRADE_INTAKE_H
#define RAS_GRADING_GRADE_INTAKE_H

#include "grade_priv.h"

/* --list RUBRIC: "hwN program..." per assignment on stdout; the exit status */
int intake_list(const char *rubric_path);
/* g->rubric and the limits it sets; its "assignments", NULL when it has none */
const cJSON *intake_rubric(grader *g, const char *rubric_path);
/* whether every --hw is an assignment of the rubric */
bool intake_only(const grader *g, const cJSON *asgs, const char *rubric_path);
/* whether --out is a folder this program made or has, and can write */
bool intake_out(const grader *g);
/* whether the student's side was given (--work, --student-tree,
 * --student-build); then the grader's folders are hidden from safe text
 * (text_hide_path) and g->notes made the student's text */
bool intake_student_side(grader *g);
/* --notes FILE: what tests/grading/grade found into g->notes, as it is
 * until intake_student_side */
void intake_notes(grader *g, const char *path);
/* the arguments of image img for this grading: a variant's drawn from the
 * seed (owned by g->drawn), else the rubric's */
const cJSON *variant_args(grader *g, const cJSON *img);

#endif
