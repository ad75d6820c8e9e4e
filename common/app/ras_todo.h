/* ras_todo.h — the friendly notice a student stub prints until it is written.
 *
 * Each stub keeps a `static bool shown` and calls ras_todo_notice(&shown, ...):
 * the first call prints one line to stderr naming the function and the
 * handout section, later calls stay quiet, and the program keeps running with
 * the stub's placeholder result. This is the one place common/ prints: its
 * whole job is to talk to the student.
 */
#ifndef RAS_TODO_H
#define RAS_TODO_H

#include <stdbool.h>

void ras_todo_notice(bool *shown, const char *function, const char *handout_section);

#endif
