/* cv_bridge.h — the only door to OpenCV (C++), for image files and windows.
 *
 * OpenCV 4 has no C API for imgcodecs or highgui (imgcodecs_c.h is an #error
 * stub), so cv_bridge.cpp wraps the few calls we need in extern "C"
 * functions. Pixel buffers cross the door as 8-bit RGB, row-major, top row
 * first, 3 bytes per pixel (the bridge swaps to OpenCV's BGR inside).
 * Errors come back as false/NULL plus a message in `err`; no C++ exception
 * ever crosses into C.
 */
#ifndef CV_BRIDGE_H
#define CV_BRIDGE_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Encodes and writes; the format follows the file's extension. */
bool cv_bridge_write_rgb8(const char *path, int width, int height, const uint8_t *rgb,
                          char *err, int err_size);

/* True when this OpenCV build has an encoder for the file's extension. */
bool cv_bridge_can_write(const char *path);

/* Reads and decodes into a malloc'ed RGB buffer the caller frees with free(). */
uint8_t *cv_bridge_read_rgb8(const char *path, int *width, int *height, char *err,
                             int err_size);

/* Windows (highgui). cv_bridge_display_available() is false when there is no
 * X display: callers must check it first, because highgui aborts the process
 * when it cannot open one. */
bool cv_bridge_display_available(void);
bool cv_bridge_window_show(const char *title, int width, int height, const uint8_t *rgb,
                           char *err, int err_size);
/* Waits up to `ms` milliseconds (0 = forever) for a key; -1 when none came.
 * Returns -2 when the window was closed by the user. */
int cv_bridge_window_wait_key(const char *title, int ms);
void cv_bridge_window_close(const char *title);

/* Mouse position over the window in image pixels (top-left origin), or false
 * when the mouse has not been over it yet. */
bool cv_bridge_window_mouse(const char *title, int *col, int *row);

/* Draws a line of text onto an RGB buffer (for the on-screen status line). */
void cv_bridge_draw_text(uint8_t *rgb, int width, int height, int col, int row,
                         const char *text, double scale);

#ifdef __cplusplus
}
#endif
#endif
