/* ras_draw.c — see ras_draw.h. */
#include "ras_draw.h"

#include <math.h> /* lroundf, isfinite */

/* Liang–Barsky: clip segment a→b to [lo, hi] on both axes; false if nothing is
 * left. In double: with endpoints at ±1e9 a float t loses whole pixels. */
static bool clip_segment(vec2s *a, vec2s *b, double lo_x, double hi_x, double lo_y,
                         double hi_y) {
    double t0 = 0.0, t1 = 1.0;
    double dx = (double)b->x - a->x, dy = (double)b->y - a->y;
    const double p[4] = {-dx, dx, -dy, dy};
    const double q[4] = {a->x - lo_x, hi_x - a->x, a->y - lo_y, hi_y - a->y};
    for (int i = 0; i < 4; i++) {
        if (p[i] == 0.0) {
            if (q[i] < 0.0) return false;
            continue;
        }
        double t = q[i] / p[i];
        if (p[i] < 0.0) {
            if (t > t1) return false;
            if (t > t0) t0 = t;
        } else {
            if (t < t0) return false;
            if (t < t1) t1 = t;
        }
    }
    vec2s na = {{(float)(a->x + t0 * dx), (float)(a->y + t0 * dy)}};
    vec2s nb = {{(float)(a->x + t1 * dx), (float)(a->y + t1 * dy)}};
    *a = na;
    *b = nb;
    return true;
}

long ras_draw_line(ras_framebuffer *fb, vec2s a, vec2s b, vec3s color) {
    if (!ras_vec2_finite(a) || !ras_vec2_finite(b)) return 0;
    /* Pixel x covers [x, x+1): the screen's pixel centres span [0.5, w-0.5]. */
    if (!clip_segment(&a, &b, 0.0, fb->width - 1e-3, 0.0, fb->height - 1e-3))
        return 0;
    int x0 = (int)a.x, y0 = (int)a.y, x1 = (int)b.x, y1 = (int)b.y;
    int dx = x1 > x0 ? x1 - x0 : x0 - x1, sx = x0 < x1 ? 1 : -1;
    int dy = y1 > y0 ? y0 - y1 : y1 - y0, sy = y0 < y1 ? 1 : -1;
    int e = dx + dy;
    long written = 0;
    for (;;) {
        fb->color[ras_fb_sample_index(fb, x0, y0, 0)] = color;
        written++;
        if (x0 == x1 && y0 == y1) break;
        int e2 = 2 * e;
        if (e2 >= dy) {
            e += dy;
            x0 += sx;
        }
        if (e2 <= dx) {
            e += dx;
            y0 += sy;
        }
    }
    return written;
}
