/* grade_report.h — what raster101-grade hands back (tests/grading/grade_*.c;
 * docs/grading.md): results.json (Gradescope), scores.csv (one row per item,
 * for tests/grading/grade-all), failures.txt (for tests/grading/run-mutants),
 * hwN/cmocka.xml (JUnit), report.md (with the pictures), each written
 * atomically, and the table on stdout; both open with where to start.
 */
#ifndef RAS_GRADING_GRADE_REPORT_H
#define RAS_GRADING_GRADE_REPORT_H

#include "grade_priv.h"

/* each failing item of a from item `from` on opens with the rubric's "where" */
void mark_where(assignment_result *a, int from, const cJSON *asg, bool integration);
/* the reports into g->out, each text in them first checked to be safe text
 * (grade_text.h: valid UTF-8, no control, bidi control or tag, no folder
 * of the grader's); false when one could not be written (said on stderr) */
bool write_outputs(grader *g, assignment_result *as, int n, double total, double max_total);
/* the table on stdout */
void print_table(const grader *g, assignment_result *as, int n, double total, double max_total);

#endif
