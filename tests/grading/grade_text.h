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
/* student output, at most `cap` bytes, each line marked "│ " (owned) */
char *student_text(const char *raw, size_t cap);
/* a sealed run's verdict: one fixed sentence for a pass, one for any other
 * end, nothing of how the run went (owned) */
char *sealed_text(bool passed);
/* text (owned, consumed) with the work folder written as "WORK" */
char *without_work_path(const char *work, char *text);

#endif
