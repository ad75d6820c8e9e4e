/* ras_window.c — see ras_window.h. */
#include "ras_window.h"

#include "cv_bridge.h"

bool ras_window_available(void) { return cv_bridge_display_available(); }

int ras_window_wait_key(const char *title, int ms) { return cv_bridge_window_wait_key(title, ms); }

bool ras_window_mouse(const char *title, int *col, int *row) {
    return cv_bridge_window_mouse(title, col, row);
}

void ras_window_close(const char *title) { cv_bridge_window_close(title); }
