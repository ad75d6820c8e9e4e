/* ras_window.h — showing a picture in a window, with a status line.
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

/* Shows img (status drawn in the top-left corner when non-NULL). */
bool ras_window_show(const char *title, const ras_image *img, const char *status,
                     ras_error *err);

/* A key (lower 8 bits), -1 when none came within ms, -2 when the window was closed. */
int ras_window_wait_key(const char *title, int ms);

/* The mouse position in image pixels, false while it has not been over the window. */
bool ras_window_mouse(const char *title, int *col, int *row);

void ras_window_close(const char *title);

#define RAS_KEY_ESC 27

#endif
