/* ras_todo.c — see ras_todo.h. */
#include "ras_todo.h"

#include <stdio.h> /* fprintf */

void ras_todo_notice(bool *shown, const char *function, const char *handout_section) {
    if (*shown) return;
    *shown = true;
    fprintf(stderr,
            "TODO: %s() is not written yet — it returns a placeholder for now (written it? "
            "then delete its two notice lines). See %s.\n",
            function, handout_section);
}
