/* ras_error.c — see ras_error.h. */
#include "ras_error.h"

#include <stdarg.h> /* va_list */
#include <stdio.h>  /* vsnprintf */

bool ras_error_set(ras_error *err, const char *fmt, ...) {
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return false;
}
