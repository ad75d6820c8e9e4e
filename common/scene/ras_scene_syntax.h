/* ras_scene_syntax.h — what is wrong with a scene file that is not JSON
 * (private to ras_scene*.c).
 *
 * When cJSON cannot parse the text, ras_scene_syntax_error turns the point
 * where it stopped into a message with line:column, what was expected and
 * what came, and a hint for the usual slips: a trailing comma, a comment,
 * single quotes, an unquoted key, NaN or Infinity, a missing ',' between two
 * values, an unclosed '{', '[' or string:
 *     scene.json:4:17: JSON syntax error: expected a value after ',', got '}' (JSON allows no
 *     trailing comma: remove the ',')
 */
#ifndef RAS_SCENE_SYNTAX_H
#define RAS_SCENE_SYNTAX_H

#include "ras_error.h"

#include <stdbool.h>
#include <stddef.h> /* size_t */

/* The 1-based line and column (in characters, not UTF-8 bytes) of byte `off`
 * of text. */
void ras_scene_syntax_line_col(const char *text, size_t off, int *line, int *col);

/* Sets err to the syntax error at byte `off` of text (len bytes, `file` for
 * the message: "file:line:col: JSON syntax error: ..."); returns false. */
bool ras_scene_syntax_error(const char *file, const char *text, size_t len, size_t off,
                            ras_error *err);

#endif
