/* grade_priv.h — the state raster101-grade's modules share (private to
 * tests/grading/grade_*.c): the grading (grader), its processes (run_result,
 * job) and its results (item, assignment_result). docs/grading.md.
 *
 * The grader by job, in the order a grading goes (grade_main.c tells it):
 *   grade_main.c        the command line and the phases, one after another
 *   grade_intake.c      what a grading is given: the rubric, the sandbox's
 *                       folders, the submission's notes, the drawn variants
 *   grade_assignment.c  one assignment: its tests' chunks and its pictures in
 *                       one batch of sandboxed runs, then their verdicts
 *   grade_run.c         running: processes, the sandbox, the batch of jobs,
 *                       the tests' chunks (tests_prepare)
 *   grade_tests.c       judging the tests (tests_finish, --sanitize, a build
 *                       that failed)
 *   grade_images.c      judging a picture (grade_image)
 *   grade_evidence.c    the buffers' evidence for a picture (buffer_evidence)
 *   grade_attribute.c   whose code a whole-chain picture's failure is
 *   grade_report.c      results.json, scores.csv, failures.txt, cmocka.xml,
 *                       report.md and the table on stdout
 *   grade_results.c     the items a grading scores (add_item, junit_case)
 *   grade_text.c        what a report quotes: student text made safe, the
 *                       one-line reasons
 *   grade_base.c        strings, files, lists, the clock
 * The trusted side (this program) never shares a process with student code:
 * that runs in tests/grading/sandbox, started by grade_run.c.
 */
#ifndef RAS_GRADING_GRADE_PRIV_H
#define RAS_GRADING_GRADE_PRIV_H

#include <cjson/cJSON.h>
#include <stdbool.h>

/* ---------------------------------------------------------------- processes */

typedef enum run_kind { RUN_EXITED, RUN_SIGNALED, RUN_TIMEOUT, RUN_NOT_STARTED } run_kind;

typedef struct run_result {
    run_kind kind;
    int code; /* exit status or signal number */
    double seconds;
} run_result;

/* One process for run_jobs: its command, environment and output file. */
typedef struct job {
    char *argv[120];
    char store[16][4200]; /* strings argv and env point into */
    const char *env[8];
    char out_path[4096];
    char rw[4096]; /* its sandbox's writable folder */
    double limit;
    long mem_mb;
    run_result rr;
    const cJSON *args;   /* an image's program arguments, as chosen for this grading */
    char extra_ro[4096]; /* one more read-only folder in its sandbox ("": none) */
    /* A job to run right after this one in the same child of run_jobs (a
     * chunk's trusted replay after its worker), `between` first: so one
     * chunk's replay overlaps the other chunks' workers. */
    struct job *then;
    void (*between)(const struct job *j, void *arg);
    void *between_arg;
    /* and after `then`, with between_arg (NULL: nothing) */
    void (*after)(const struct job *j, void *arg);
} job;

/* ---------------------------------------------------------------- results */

typedef struct item {
    char *name; /* test name or "image NAME" */
    bool is_image;
    bool counted; /* false: reported but not in the score */
    bool passed;
    bool default_weight;
    double score, max_score;
    char *status; /* PASS, FAIL, CRASH, TIMEOUT, TODO, BUILD, SKIP */
    char *reason; /* one line for the table */
    char *output; /* everything for the student */
    char *xml;    /* JUnit <testcase> for tests */
    /* images: paths relative to OUT */
    char *img_expected, *img_got, *img_diff, *img_crop;
    /* the first buffer that differs (--dump): its name and pictures */
    char *buf_name, *buf_ref, *buf_got, *buf_diff;
    /* the student file, function and TODO numbers the item checks (the
     * rubric's "where"; points into the rubric); NULL when it names none */
    const char *where;
} item;

typedef struct assignment_result {
    char *id, *title;
    bool graded;
    char *note; /* why not graded, or remarks */
    item *items;
    int n_items, cap_items;
    double score, max_score;
    double seconds;
} assignment_result;

/* ---------------------------------------------------------------- the grading */

/* Images given buffer evidence per grading: each costs two more renders. */
enum { EVIDENCE_MAX = 24 };

typedef struct grader {
    const char *source, *build, *out, *variant;
    /* The student's side: the pristine tree and its build, both read-only in
     * the sandbox, and the work folder where each run gets its own writable
     * folder. Nothing of the trusted side (source, build, out) is visible. */
    const char *student_tree, *student_build, *work;
    /* --own: each assignment's programs and test worker linked with the
     * reference of the earlier assignments (tests/grading/grade, step 2b), as
     * OWN/refK.../bin and OWN/refK.../tests; NULL when there are none. */
    const char *own;
    /* --sanitized-build (grade --sanitize): the student's test workers built
     * with AddressSanitizer and UBSan in the sandbox; NULL: no such pass. */
    const char *sanitized;
    long sandbox_uid;  /* -1: not root, runs stay this user's */
    int runs;          /* numbers the run folders */
    int evidence_runs; /* images given buffer evidence so far (at most EVIDENCE_MAX) */
    int jobs;          /* sandboxed runs at once */
    cJSON *rubric;
    double default_points, test_limit, render_limit;
    long mem_mb;
    /* --notes: what tests/grading/grade found in the submission (a missing or
     * misnamed file, a link it refused), escaped, shown first; NULL: none */
    char *notes;
    /* --seed: the keyed hash of the course's secret and the student's
     * identity (tests/grading/grade --student-id), from which the variants
     * are drawn: the same student always gets the same pictures, whatever
     * bytes they change; without it, the kernel's random */
    unsigned long long seed;
    bool has_seed;
    cJSON *drawn; /* the argument lists drawn for this grading (owned) */
    const char *only[8];
    int n_only;
    /* --build-failed / --chain-unlinked: the assignment's build log; with
     * chain_unlinked its own file compiled and only the link with the
     * student's earlier files failed */
    const char *failed_hw[8], *failed_log[8];
    bool chain_unlinked[8];
    int n_failed;
} grader;

#endif
