/* grade_tests.h — raster101-grade's verdicts on an assignment's tests
 * (tests/grading/grade_*.c): each test's item from what its sandboxed worker
 * and its trusted replay left (tests_finish, after grade_run.h's
 * tests_prepare and run_jobs), grade --sanitize's findings added to them,
 * and the items of an assignment whose code does not compile.
 */
#ifndef RAS_GRADING_GRADE_TESTS_H
#define RAS_GRADING_GRADE_TESTS_H

#include "grade_priv.h"
#include "grade_run.h"

/* the verdicts of a batch whose jobs have run, as items of a; frees the batch */
void tests_finish(const grader *g, assignment_result *a, const cJSON *asg, test_batch *b);
/* every test and image of asg as an item lost to the build, with the
 * compiler's error lines from log_path; linked: its own file compiled, only
 * the link with the student's earlier files failed */
void mark_build_failed(const grader *g, assignment_result *a, const cJSON *asg,
                       const char *log_path, bool linked);
/* the linker's first complaint in log_path (a "multiple definition" or an
 * "undefined reference" before any other error line), as safe text of at
 * most 300 bytes; "" when there is none (owned) */
char *first_link_error(const char *log_path);

/* a sealed run's item (it held reference code) reduced to pass or not:
 * `earned` its points (passed, no TODO notice), else the one fixed failure
 * for every way it could have failed */
void seal_verdict(const grader *g, item *it, bool earned);
/* each sealed test of a that failed (items from `from` on) run again on the
 * student's whole chain, in DIR/xml-whole-chain, its message added to the
 * sealed item (the sealed verdict stays) */
void tests_explain_sealed(const grader *g, assignment_result *a, const cJSON *asg, const char *dir,
                          int from);

#endif
