/* ras_job.h — work with a time limit: a function run on its own thread
 * (or, for code that may crash, in a child process: ras_job_run_child),
 * waited for at most so many seconds.
 *
 * Decoders and importers cannot be interrupted safely from outside (assimp
 * loops forever on some files; a decoder may hold locks and half-built
 * buffers), so a late job is not killed: the caller stops waiting and
 * reports the limit, and the job, when (if) it ends, discards its own result.
 * The programs exit after such an error, which ends the thread anyway.
 */
#ifndef RAS_JOB_H
#define RAS_JOB_H

#include <stdbool.h>
#include <stddef.h> /* size_t */

/* The work: returns its result (may be NULL). */
typedef void *(*ras_job_fn)(void *arg);
/* Frees a result nobody waits for any more, and `arg`. */
typedef void (*ras_job_discard_fn)(void *result, void *arg);

/* Runs fn(arg) on a new thread with a stack of `stack` bytes (0: the
 * default) and waits at most `seconds`. True with *result when it finished
 * in time (the caller then owns arg and the result); false when the time ran
 * out, and from then on the thread owns arg and calls discard when fn
 * returns. When no thread can be made, fn runs on the caller's thread. */
bool ras_job_run(ras_job_fn fn, void *arg, ras_job_discard_fn discard, size_t stack,
                 double seconds, void **result);

/* What became of a job run in a child process. */
typedef enum ras_job_child_status {
    RAS_JOB_CHILD_DONE,       /* it ended normally: *out holds all it wrote */
    RAS_JOB_CHILD_CRASHED,    /* a signal ended it (*signal_number says which) */
    RAS_JOB_CHILD_LATE,       /* still running after `seconds`: killed */
    RAS_JOB_CHILD_TOO_BIG,    /* it wrote more than max_bytes: killed */
    RAS_JOB_CHILD_NO_PROCESS, /* no child could be made (fork, pipe or memory) */
} ras_job_child_status;

/* Writes the job's result to fd; returns the child's exit status. */
typedef int (*ras_job_child_fn)(void *arg, int fd);

/* Runs fn(arg, fd) in a forked child and collects what it writes to fd,
 * for at most `seconds` and max_bytes. For libraries that may crash on
 * hostile input rather than fail (assimp's importers: stack-protector
 * aborts, segfaults in code no sanitizer sees): the crash ends the child,
 * and a late child is killed rather than left running. The caller should
 * have opened any library the child uses (no dlopen after fork). *out is
 * malloc'd (free it) when DONE; *exit_status is the child's exit code. */
ras_job_child_status ras_job_run_child(ras_job_child_fn fn, void *arg, double seconds,
                                       size_t max_bytes, unsigned char **out, size_t *len,
                                       int *exit_status, int *signal_number);

/* A limit in seconds from the environment variable `name`: a positive
 * number, else `fallback`. */
double ras_job_seconds(const char *name, double fallback);

#endif
