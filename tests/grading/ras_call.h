/* ras_call.h — the thin layer between the assignment tests and the student's
 * functions, so that grading never decides a verdict in a process that runs
 * student code (docs/grading.md, "Threat model").
 *
 * The same test file (tests/unit/test_hwN.c) is built three ways:
 *   test_hwN_student / _ref   plain: the tests call the functions directly
 *                             (students' own `ctest`, `make test`);
 *   test_hwN_worker           student code + tests/grading/ras_call.c in RECORD mode,
 *                             linked with `-Wl,--wrap=` for every function of
 *                             the student's API (the rows of
 *                             ras_call_table.h): each call the test makes
 *                             (directly or through given code such as the
 *                             pipeline) is written to $RAS_RECORD with what the
 *                             call returned and what it wrote. Runs in the
 *                             sandbox; its own pass/fail means nothing;
 *   test_hwN_replay           NO student code: tests/grading/ras_call.c in REPLAY mode
 *                             defines those functions and answers each call
 *                             from the record ($RAS_REPLAY). The checks, the
 *                             expected values and the messages run here, in
 *                             the trusted process: that is the verdict.
 * Calls made from inside a recorded call (the student's own helpers, the
 * shaders inside hw3_render) are not recorded: only what the test sees.
 *
 * Tests use two hooks, both no-ops in plain builds:
 *   ras_call_watch(p, n)   rasterize_triangle's record also covers [p, p+n)
 *                          (the canaries around a guarded framebuffer, so a
 *                          write outside the frame is replayed too);
 *                          ras_call_watch(NULL, 0) forgets them all.
 *   ras_call_recording()   true in the worker: a test may skip steps that
 *                          need files the sandbox hides (the reference
 *                          images) once the student's calls are done.
 */
#ifndef RAS_CALL_H
#define RAS_CALL_H

#include <stdbool.h> /* bool */
#include <stddef.h>  /* size_t */
#include <stdlib.h>  /* getenv */

/* Defined only in worker and replay builds (tests/grading/ras_call.c). */
void ras_call_watch_impl(void *p, size_t n) __attribute__((weak));

static inline void ras_call_watch(void *p, size_t n) {
    if (ras_call_watch_impl) ras_call_watch_impl(p, n);
}

static inline bool ras_call_recording(void) {
    const char *r = getenv("RAS_RECORD");
    return r && *r;
}

#endif
