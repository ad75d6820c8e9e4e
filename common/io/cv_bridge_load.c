/* cv_bridge_load.c — cv_bridge.h's functions for the C side: the OpenCV
 * module (libraster101_cv.so, built from cv_bridge.cpp) is opened with dlopen
 * on the first call that needs it, so a program that never opens a window or
 * touches a non-PNG file never loads OpenCV (common/README.md, "What is
 * loaded when").
 *
 * Where the module is looked for, first found wins:
 *   1. RAS_CV_BRIDGE, when set (a path to the module);
 *   2. beside the running program (the folder of /proc/self/exe), where the
 *      build puts it with the programs (build/bin/);
 *   3. where this build made it (RAS_CV_BRIDGE_PATH, an absolute path given
 *      by common/CMakeLists.txt), for tests and tools built elsewhere.
 * When none loads, every call fails as OpenCV itself would fail (false, NULL,
 * "window closed") with a message naming the paths tried and dlerror(). */
#include "cv_bridge.h"
#include "ras_memory.h" /* Required for: ras_memory_limit (OpenCV's decoder limit) */

#include <dlfcn.h>   /* dlopen, dlsym, dlerror */
#include <pthread.h> /* pthread_once */
#include <stdio.h>   /* snprintf */
#include <stdlib.h>  /* getenv */
#include <string.h>  /* strrchr */
#include <unistd.h>  /* readlink */

#ifndef RAS_CV_BRIDGE_PATH
#define RAS_CV_BRIDGE_PATH ""
#endif
#define MODULE_NAME "libraster101_cv.so"

static const cv_bridge_table *g_table;
static char g_load_error[1536];
static pthread_once_t g_load_once = PTHREAD_ONCE_INIT;

/* Opens one candidate; appends why not to g_load_error. */
static bool try_open(const char *path) {
    if (!path || !*path) return false;
    /* RTLD_LOCAL: OpenCV's symbols stay the module's. RTLD_LAZY: functions
     * are bound when first called, as at start-up; binding all of the ~150
     * libraries' functions now (RTLD_NOW) cost 40 M instructions more when a
     * JPEG is written (measured in the instructors' edition's start-up
     * report). A missing library still fails here. */
    void *h = dlopen(path, RTLD_LAZY | RTLD_LOCAL);
    const char *why = NULL;
    if (h) {
        union {
            void *p;
            const cv_bridge_table *(*fn)(void);
        } sym = {dlsym(h, CV_BRIDGE_MODULE_SYMBOL)};
        const cv_bridge_table *t = sym.p ? sym.fn() : NULL;
        if (t && t->abi == CV_BRIDGE_ABI) {
            g_table = t;
            return true;
        }
        why = t ? "a module from another build (ABI differs)" : "no " CV_BRIDGE_MODULE_SYMBOL;
        dlclose(h);
    } else {
        why = dlerror();
    }
    size_t used = strlen(g_load_error);
    snprintf(g_load_error + used, sizeof g_load_error - used, "%s%s: %s", used ? "; " : "", path,
             why ? why : "?");
    return false;
}

static void load(void) {
    /* OpenCV reads its decoder limit once, when libopencv_imgcodecs loads:
     * with the module opened here, after main, the program can set it.
     * ras_image's header checks stay the first line of defence. */
    /* The fence is the budget's worth of pixels (at most 2^28): a header
     * that ras_image's parsers read wrong is still stopped by OpenCV's own
     * header call (validateInputImageSize) before pixels are allocated. */
    double pixels = (double)ras_memory_limit() / RAS_MEMORY_DECODE_BYTES_PER_PIXEL;
    char fence[32];
    snprintf(fence, sizeof fence, "%.0f",
             pixels < 268435456.0 ? (pixels > 1 ? pixels : 1) : 268435456.0);
    setenv("OPENCV_IO_MAX_IMAGE_PIXELS", fence, 0);
    if (try_open(getenv("RAS_CV_BRIDGE"))) return;
    char exe[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - sizeof MODULE_NAME - 1);
    if (n > 0) {
        exe[n] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash) {
            memcpy(slash + 1, MODULE_NAME, sizeof MODULE_NAME);
            if (access(exe, F_OK) == 0 && try_open(exe)) return;
        }
    }
    if (try_open(RAS_CV_BRIDGE_PATH)) return;
    if (!*g_load_error)
        snprintf(g_load_error, sizeof g_load_error, "%s was not found beside the program",
                 MODULE_NAME);
}

/* The module's table (g_table), or NULL with the reason in err. */
static const cv_bridge_table *bridge(char *err, int err_size) {
    pthread_once(&g_load_once, load);
    if (!g_table && err && err_size > 0)
        snprintf(err, (size_t)err_size, "OpenCV is not available (the bridge module %s: %s)",
                 MODULE_NAME, g_load_error);
    return g_table;
}

const char *cv_bridge_load_error(void) { return g_table ? "" : g_load_error; }

uint8_t *cv_bridge_encode_rgb8(const char *ext, int width, int height, const uint8_t *rgb,
                               size_t *len, char *err, int err_size) {
    const cv_bridge_table *t = bridge(err, err_size);
    return t ? t->encode_rgb8(ext, width, height, rgb, len, err, err_size) : NULL;
}

bool cv_bridge_decode_size(const uint8_t *data, size_t len, int *width, int *height) {
    const cv_bridge_table *t = bridge(NULL, 0);
    return t && t->decode_size(data, len, width, height);
}

bool cv_bridge_can_write(const char *path) {
    const cv_bridge_table *t = bridge(NULL, 0);
    return t && t->can_write(path);
}

uint8_t *cv_bridge_decode_rgb8(const uint8_t *data, size_t len, int *width, int *height, char *err,
                               int err_size) {
    const cv_bridge_table *t = bridge(err, err_size);
    return t ? t->decode_rgb8(data, len, width, height, err, err_size) : NULL;
}

uint8_t *cv_bridge_encode_f32(const char *ext, int width, int height, int channels,
                              const float *data, size_t *len, char *err, int err_size) {
    const cv_bridge_table *t = bridge(err, err_size);
    return t ? t->encode_f32(ext, width, height, channels, data, len, err, err_size) : NULL;
}

float *cv_bridge_decode_f32(const uint8_t *data, size_t len, int *width, int *height, int *channels,
                            char *err, int err_size) {
    const cv_bridge_table *t = bridge(err, err_size);
    return t ? t->decode_f32(data, len, width, height, channels, err, err_size) : NULL;
}

/* No OpenCV needed: highgui aborts without a display, so callers ask first. */
bool cv_bridge_display_available(void) {
    const char *d = getenv("DISPLAY");
    const char *w = getenv("WAYLAND_DISPLAY");
    return (d && *d) || (w && *w);
}

bool cv_bridge_window_show(const char *title, int width, int height, const uint8_t *rgb, char *err,
                           int err_size) {
    const cv_bridge_table *t = bridge(err, err_size);
    return t && t->window_show(title, width, height, rgb, err, err_size);
}

int cv_bridge_window_wait_key(const char *title, int ms) {
    const cv_bridge_table *t = bridge(NULL, 0);
    return t ? t->window_wait_key(title, ms) : -2;
}

void cv_bridge_window_close(const char *title) {
    /* Never shown means never loaded: nothing to close. */
    if (g_table) g_table->window_close(title);
}

bool cv_bridge_window_mouse(const char *title, int *col, int *row) {
    return g_table && g_table->window_mouse(title, col, row);
}

void cv_bridge_draw_text(uint8_t *rgb, int width, int height, int col, int row, const char *text,
                         double scale) {
    const cv_bridge_table *t = bridge(NULL, 0);
    if (t) t->draw_text(rgb, width, height, col, row, text, scale);
}
