/* ras_job.h — work with a time limit: a function run on its own thread,
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

/* A limit in seconds from the environment variable `name`: a positive
 * number, else `fallback`. */
double ras_job_seconds(const char *name, double fallback);

#endif
