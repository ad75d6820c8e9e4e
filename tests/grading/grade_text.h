/* grade_text.h — what raster101-grade's reports quote (tests/grading/grade_*.c):
 * a test's output without cmocka's banners, the one line of a failure that
 * says the most, and anything the student's code printed made safe to show
 * (it can forge no heading, total, table, reading order or JSON).
 */
#ifndef RAS_GRADING_GRADE_TEXT_H
#define RAS_GRADING_GRADE_TEXT_H

#include "grade_base.h"

#include <stdbool.h>
#include <stddef.h>

/* raw without cmocka's banner lines and "ERROR: " prefixes (owned) */
char *clean_output(const char *raw);
/* whether a TODO notice ("... is not written yet") was printed */
bool has_todo_notice(const char *out);
/* the length in bytes of the first `chars` UTF-8 characters of s[0..n) */
size_t utf8_prefix(const char *s, size_t n, size_t chars);
/* the one line of a failure for a table (owned) */
char *reason_line(const char *out);
void xml_escape(sbuf *b, const char *s);
/* whether p[0..n) is a bidirectional control character */
bool is_bidi_control(const unsigned char *p, size_t n);

/* Text from the student's side (what its programs and tests printed, the
 * compiler's lines, pick-files' notes, the replay's words on its values)
 * goes into a report only through these, which make it safe to show
 * anywhere a report puts it (results.json, report.md, failures.txt,
 * cmocka.xml, the table on stdout):
 *   - valid UTF-8: each byte of an invalid sequence (overlong, surrogate,
 *     above U+10FFFF, a stray continuation, FF, FE) becomes U+FFFD;
 *   - no control character but the line break (a tab becomes four spaces, a
 *     CRLF a line break) and no bidi control, zero-width, other format (Cf)
 *     or invisible character: each is shown as "[U+202E]", never acted on;
 *   - no markup: the '<' that would open an HTML tag becomes U+2039, the '>'
 *     of "]]>" U+203A (report.md fences it: grade_report.c);
 *   - the grader's folders (text_hide_path) written as their tokens;
 *   - at most `cap` bytes, cut between characters, then "[... cut ...]".
 * All owned. */
char *safe_text(const char *raw, size_t cap);
/* safe_text, each line marked "│ " as the student's: nothing it prints can
 * forge the report's layout (a heading, a total, a table, a fix line) */
char *student_text(const char *raw, size_t cap);
/* safe_text for an XML document (the trusted replay's cmocka XML, which
 * quotes values): its markup kept, the rest made safe */
char *safe_xml(const char *raw, size_t cap);
/* Why s is not what safe_text writes (a fixed phrase: "invalid UTF-8", "a
 * control character", ...), or NULL when it is; `markup`: tags allowed */
const char *text_unsafe(const char *s, bool markup);
/* Each occurrence of `path` (an absolute folder; its real path too) in
 * later safe text is written as `token` ("WORK"); both must outlive the
 * grading. */
void text_hide_path(const char *path, const char *token);
void text_hide_paths_clear(void);
/* a sealed run's verdict: one fixed sentence for a pass, one for any other
 * end, nothing of how the run went (owned) */
char *sealed_text(bool passed);
/* text (owned, consumed) with the work folder written as "WORK" */
char *without_work_path(const char *work, char *text);

#endif
