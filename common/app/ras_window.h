/* ras_window.h — the window's keys, mouse and closing (ras_viewer.h shows the pictures).
 *
 * A thin C face of cv_bridge's highgui calls. Programs must ask
 * ras_window_available() first: without a display they render headless or
 * say what to do, because highgui would abort the process.
 */
#ifndef RAS_WINDOW_H
#define RAS_WINDOW_H

#include "ras_error.h"
#include "ras_image.h"

bool ras_window_available(void);

/* A key (lower 8 bits), -1 when none came within ms, -2 when the window was closed. */
int ras_window_wait_key(const char *title, int ms);

/* The mouse position in image pixels, false while it has not been over the window. */
bool ras_window_mouse(const char *title, int *col, int *row);

void ras_window_close(const char *title);

#define RAS_KEY_ESC 27

#endif
