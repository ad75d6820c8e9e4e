/* fuzz_target.h — the one entry point every fuzz target implements.
 *
 * Each tests/fuzz/fuzz_<name>.c defines LLVMFuzzerTestOneInput. It is built
 * twice (tests/fuzz/CMakeLists.txt):
 *   - with clang -fsanitize=fuzzer,address,undefined as a libFuzzer binary
 *     (RAS_FUZZ=ON, see scripts/fuzz), which searches for crashing inputs;
 *   - with the normal compiler and replay_main.c as fuzz_replay_<name>, a
 *     ctest test (label hardcases) that feeds every file of
 *     tests/fuzz/corpus/<name>/ to the same function: the seeds and every
 *     crash input ever found stay regression tests without libFuzzer.
 * A target returns 0; it aborts (via fuzz_check) when an invariant breaks.
 */
#ifndef RAS_FUZZ_TARGET_H
#define RAS_FUZZ_TARGET_H

#include <stddef.h> /* size_t */
#include <stdint.h> /* uint8_t */
#include <stdio.h>  /* fprintf */
#include <stdlib.h> /* abort */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* An invariant of the code under test: print and abort (libFuzzer saves the input). */
#define fuzz_check(cond, ...)                                                        \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "fuzz invariant failed: %s (%s:%d): ", #cond, __FILE__,  \
                    __LINE__);                                                       \
            fprintf(stderr, __VA_ARGS__);                                            \
            fprintf(stderr, "\n");                                                   \
            abort();                                                                 \
        }                                                                            \
    } while (0)

/* Writes data to a new temporary file whose name ends in `ext` (".obj"...);
 * returns the malloc'd path (caller unlinks and frees) or NULL. */
char *fuzz_write_temp(const uint8_t *data, size_t size, const char *ext);

#endif
