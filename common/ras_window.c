/* ras_window.c — see ras_window.h. */
#include "ras_window.h"

#include "cv_bridge.h"

#include <stdlib.h> /* malloc, free */

bool ras_window_available(void) { return cv_bridge_display_available(); }

bool ras_window_show(const char *title, const ras_image *img, const char *status,
                     ras_error *err) {
    uint8_t *rgb = malloc((size_t)img->width * (size_t)img->height * 3);
    if (!rgb) return ras_error_set(err, "out of memory showing the window");
    ras_image_to_rgb8(img, rgb);
    if (status)
        cv_bridge_draw_text(rgb, img->width, img->height, 8, 20, status, 0.5);
    char msg[512] = "";
    bool ok = cv_bridge_window_show(title, img->width, img->height, rgb, msg, sizeof msg);
    free(rgb);
    if (!ok) return ras_error_set(err, "%s", msg);
    return true;
}

int ras_window_wait_key(const char *title, int ms) { return cv_bridge_window_wait_key(title, ms); }

bool ras_window_mouse(const char *title, int *col, int *row) {
    return cv_bridge_window_mouse(title, col, row);
}

void ras_window_close(const char *title) { cv_bridge_window_close(title); }
