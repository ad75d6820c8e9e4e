/* ras_error.h — how common/ reports bad input.
 *
 * Functions that can fail on bad input (a missing file, a malformed model, a
 * number out of range) return false (or NULL) and fill a ras_error with one
 * sentence: what was expected, what came, and what to do. Programmer errors
 * (a NULL where the contract says non-NULL) are asserts instead.
 * common/ never prints and never calls exit(): only a program's main does.
 */
#ifndef RAS_ERROR_H
#define RAS_ERROR_H

#include <stdbool.h>
#include <stddef.h> /* size_t */

typedef struct ras_error {
    char msg[1024];
} ras_error;

/* Formats the message; a NULL err is allowed and ignored. Returns false so a
 * caller can write `return ras_error_set(err, "...")`. A message longer than
 * msg holds is shortened with ras_error_shorten, never cut at its end. */
bool ras_error_set(ras_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* Shortens text in place to fit `cap` bytes (its NUL included) by cutting its
 * longest words (paths, in practice) in the middle, "head[...]tail", keeping
 * at least 48 bytes of each; only when no word is long enough is the end
 * cut. Returns the new length. What every message with a long path needs:
 * the reason and the key around the path survive. */
size_t ras_error_shorten(char *text, size_t cap);

#endif
