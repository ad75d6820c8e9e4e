/* cv_bridge.h — the only door to OpenCV (C++), for image files and windows.
 *
 * OpenCV 4 has no C API for imgcodecs or highgui (imgcodecs_c.h is an #error
 * stub), so cv_bridge.cpp wraps the few calls we need in extern "C"
 * functions. Pixel buffers cross the door as 8-bit RGB, row-major, top row
 * first, 3 bytes per pixel (the bridge swaps to OpenCV's BGR inside).
 * Errors come back as false/NULL plus a message in `err`; no C++ exception
 * ever crosses into C.
 *
 * Loaded only when used. cv_bridge.cpp is built alone into a module,
 * libraster101_cv.so, the only thing linked against OpenCV (and libstdc++);
 * the programs link cv_bridge_load.c, which implements the functions below
 * by opening the module with dlopen on the first call that needs OpenCV: a
 * window, a non-PNG image file, a float (.pfm) file, text drawn on a picture.
 * PNG files never need it (ras_png.h), and cv_bridge_display_available() is
 * a plain getenv. So a program that writes a PNG, or only prints --version,
 * loads none of OpenCV's ~150 libraries (common/README.md, "What is loaded
 * when").
 */
#ifndef RAS_CV_BRIDGE_H
#define RAS_CV_BRIDGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Encodes in memory, the format following `ext` (".png", ".bmp", ...):
 * a malloc'ed buffer the caller frees, *len its size; NULL and err on failure.
 * Writing the bytes is ras_io_write_atomic's job. */
uint8_t *cv_bridge_encode_rgb8(const char *ext, int width, int height, const uint8_t *rgb,
                               size_t *len, char *err, int err_size);

/* Decodes an encoded image in memory, only to check it: true and its size
 * when it decodes. */
bool cv_bridge_decode_size(const uint8_t *data, size_t len, int *width, int *height);

/* True when this OpenCV build has an encoder for the file's extension. */
bool cv_bridge_can_write(const char *path);

/* Decodes an encoded image (a whole file's bytes) into a malloc'ed RGB buffer
 * the caller frees with free(). Reading the file is the caller's job
 * (ras_io_read_file: regular files only); the message does not name it. */
uint8_t *cv_bridge_decode_rgb8(const uint8_t *data, size_t len, int *width, int *height,
                               char *err, int err_size);

/* Float images (1 or 3 channels, row-major, top row first, RGB order) to and
 * from an uncompressed exact format (".pfm"): read back bit for bit, ±Inf and
 * NaN included (--dump's buffers). The decoder gives malloc'd data or NULL
 * with err set; PFM has no compression, so its size is bounded by `len`. */
uint8_t *cv_bridge_encode_f32(const char *ext, int width, int height, int channels,
                              const float *data, size_t *len, char *err, int err_size);
float *cv_bridge_decode_f32(const uint8_t *data, size_t len, int *width, int *height,
                            int *channels, char *err, int err_size);

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

/* Why the module could not be loaded ("" when it is, or was never needed). */
const char *cv_bridge_load_error(void);

/* Between cv_bridge_load.c and the module: the module exports one function,
 * CV_BRIDGE_MODULE_SYMBOL, returning this table; `abi` must be
 * CV_BRIDGE_ABI (a module from another build is refused). */
#define CV_BRIDGE_ABI 1
#define CV_BRIDGE_MODULE_SYMBOL "cv_bridge_module_table"
typedef struct cv_bridge_table {
    int abi;
    uint8_t *(*encode_rgb8)(const char *ext, int width, int height, const uint8_t *rgb, size_t *len,
                            char *err, int err_size);
    bool (*decode_size)(const uint8_t *data, size_t len, int *width, int *height);
    bool (*can_write)(const char *path);
    uint8_t *(*decode_rgb8)(const uint8_t *data, size_t len, int *width, int *height, char *err,
                            int err_size);
    uint8_t *(*encode_f32)(const char *ext, int width, int height, int channels, const float *data,
                           size_t *len, char *err, int err_size);
    float *(*decode_f32)(const uint8_t *data, size_t len, int *width, int *height, int *channels,
                         char *err, int err_size);
    bool (*window_show)(const char *title, int width, int height, const uint8_t *rgb, char *err,
                        int err_size);
    int (*window_wait_key)(const char *title, int ms);
    void (*window_close)(const char *title);
    bool (*window_mouse)(const char *title, int *col, int *row);
    void (*draw_text)(uint8_t *rgb, int width, int height, int col, int row, const char *text,
                      double scale);
} cv_bridge_table;
const cv_bridge_table *cv_bridge_module_table(void);

#ifdef __cplusplus
}
#endif
#endif
