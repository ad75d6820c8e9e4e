/* grade_run.h — how raster101-grade runs things (tests/grading/grade_*.c):
 * a process with its output captured and its limits, a batch of them a few
 * at a time, the sandbox's command line for a run of student code, and the
 * jobs made of them: a chunk of an assignment's tests (its sandboxed worker,
 * then the trusted replay that decides), a picture's program, the trusted
 * reference program. Nothing here judges.
 */
#ifndef RAS_GRADING_GRADE_RUN_H
#define RAS_GRADING_GRADE_RUN_H

#include "grade_base.h"
#include "grade_priv.h"

#include <stddef.h>

/* ---------------------------------------------------------------- processes */

/* argv with output captured to out_path, env added, wall-clock and
 * address-space (MB, 0 = none) limits; its whole process group killed at the end */
run_result run_limited(char *const argv[], const char *const env[], const char *out_path,
                       double limit_s, long mem_mb);
/* the jobs, `parallel` at a time (each job's `then` right after it) */
void run_jobs(job *jobs, int n, int parallel);
/* a signal in words, with what it most likely means */
const char *signal_text(int sig);
/* how a sandboxed run ended, in the words of a test's fate */
void fate_text(run_result rr, double limit, char *buf, size_t size);
/* a fate's words back into a run_result */
run_result fate_parse(const char *fate);

/* ---------------------------------------------------------------- limits */

/* the clock's backstop for `cpu_s` seconds of processor time */
double wall_backstop(double cpu_s);
/* a test's limit on the clock */
double test_wall(const grader *g);

/* ---------------------------------------------------------------- the sandbox */

/* j->argv as "tests/grading/sandbox ... --" in a fresh run folder j->rw;
 * returns the next argv index */
int sandbox_job(const grader *g, job *j, double limit_s, const char *const env[]);
/* the numbers of the assignments hwN builds on, earliest first ("12" for
 * hw3), into digits; false when it builds on none */
bool own_chain(const char *id, char *digits, size_t size);
/* whether hwN builds on assignment `other` ("hw2") */
bool own_chain_has(const char *id, const char *other);
/* the folder of hwN's own-code link with the reference of `refs` (NULL: every
 * assignment it builds on) into dir; false when there is none */
bool own_dir(const grader *g, const char *id, const char *refs, char *dir, size_t size);
/* assignment id's tests dealt to `chunks` chunks by the rubric's measured
 * costs (test_costs_ms), the costliest first to the least loaded:
 * chunk_of[i] is test i's chunk, the same at every grading of a rubric */
void deal_tests(const grader *g, const char *id, const name_list *names, int chunks, int *chunk_of);
/* how many tests chunk_of gives to `chunk` */
int chunk_size(int n, const int *chunk_of, int chunk);
/* the names of `chunk`, one a line in the program's order, into path */
void write_chunk_list(const char *path, const name_list *names, const int *chunk_of, int chunk);
/* a sandboxed chunk of a test worker: the tests i with chunk_of[i] == chunk */
void worker_job(const grader *g, job *w, const char *bin, const char *own, const name_list *names,
                const int *chunk_of, int chunk, double per_test, double wall,
                const char *const extra[]);
/* a picture's program in the sandbox, -o into its run folder (j->args set) */
void image_job(const grader *g, const cJSON *img, job *j, const char *own, const char *tag);
/* A trusted reference program's run kept for later gradings (the trusted
 * build's BUILD/grade-cache/KIND: "references" for the variants' pictures,
 * "dumps" for the evidence's --dump folders): its key text into `key` (the
 * program and the module it opens, each by what any rebuild changes: device,
 * inode, size, modification and change times to the nanosecond; then the
 * arguments, one a line) and the entry's path without extension into
 * `entry` (BUILD/grade-cache/KIND/HASH, the FNV-1a of the key). An entry
 * holds its whole key and serves only when that matches byte for byte. */
void reference_cache_key(const grader *g, const char *kind, const char *program,
                         const cJSON *args, sbuf *key, char *entry, size_t size);
/* The line of such a key that names `path` as it is now ("PATH DEV INO SIZE
 * MTIME CTIME", or "PATH absent"). */
void cache_identity(sbuf *key, const char *path);
/* the trusted reference program, outside the sandbox */
run_result reference_render(const grader *g, const char *program, const cJSON *args,
                            const char *out_png, const char *dump_dir, const char *log);

/* ---------------------------------------------------------------- the tests' chunks */

struct chunk_fates;

/* An assignment's tests in flight: tests_prepare makes the jobs (a worker per
 * chunk, its replay chained after it), the caller runs them together with
 * the assignment's pictures (so a core a short chunk frees draws a picture),
 * tests_finish reads the verdicts. */
typedef struct test_batch {
    name_list names;
    char *listing;
    int n, chunks;
    job *workers, *replays;
    int *chunk_of;
    struct chunk_fates *fates;
    /* what the jobs' argv point to, so it lives as long as they do */
    char xml_dir[4096], own[4096], replay_bin[4096], worker_bin[4300];
} test_batch;

/* b's jobs for assignment a (its test list from the trusted replay program);
 * false, with a->note said, when there is no list */
bool tests_prepare(const grader *g, assignment_result *a, const char *dir, test_batch *b);
/* b's jobs for the tests `names` of a on the student's whole chain (their
 * own build, no reference code: nothing in it is sealed), into DIR/xml-whole-chain;
 * false when there is no such worker or no name */
bool tests_prepare_whole_chain(const grader *g, assignment_result *a, const char *dir,
                               const name_list *names, test_batch *b);

#endif
