/* bench_plot.c — see bench_plot.h. */
#include "bench_plot.h"

#include "cv_bridge.h" /* cv_bridge_draw_text */

#include <math.h>   /* log10, floor, pow, sqrt, isfinite */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* calloc, free, malloc */
#include <string.h> /* strncpy */

#define MAX_TEXTS 256
#define MAX_LEGEND 12
#define TEXT_LEN 64

typedef struct text_item {
    int col, row;
    double scale;
    char s[TEXT_LEN];
} text_item;

struct bench_plot {
    ras_image *img;
    double x0, x1, y0, y1;
    bool logx, logy;
    int left, right, top, bottom; /* data area in image pixels (inclusive) */
    text_item texts[MAX_TEXTS];
    int text_count;
    char legend[MAX_LEGEND][TEXT_LEN];
    vec3s legend_color[MAX_LEGEND];
    int legend_count;
    bool legend_bottom; /* legend in the lower-right corner instead of the upper */
};

static const vec3s BACKGROUND = {{0.11f, 0.12f, 0.14f}};
static const vec3s AXIS = {{0.75f, 0.75f, 0.78f}};
static const vec3s GRID = {{0.22f, 0.23f, 0.26f}};

static void add_text(bench_plot *p, int col, int row, double scale, const char *s) {
    if (p->text_count >= MAX_TEXTS) return;
    text_item *t = &p->texts[p->text_count++];
    t->col = col;
    t->row = row;
    t->scale = scale;
    snprintf(t->s, sizeof t->s, "%s", s);
}

/* Blends colour c into pixel (col, row) with weight a in [0, 1]. */
static void blend(ras_image *img, int col, int row, vec3s c, float a) {
    if (col < 0 || row < 0 || col >= img->width || row >= img->height || a <= 0) return;
    if (a > 1) a = 1;
    vec3s *d = &img->pixels[row * img->width + col];
    *d = glms_vec3_add(glms_vec3_scale(*d, 1 - a), glms_vec3_scale(c, a));
}

/* A soft disc of radius r at a sub-pixel position. */
static void dot(ras_image *img, double cx, double cy, double r, vec3s c) {
    for (int row = (int)floor(cy - r - 1); row <= (int)ceil(cy + r + 1); row++)
        for (int col = (int)floor(cx - r - 1); col <= (int)ceil(cx + r + 1); col++) {
            double d = sqrt((col + 0.5 - cx) * (col + 0.5 - cx) + (row + 0.5 - cy) * (row + 0.5 - cy));
            blend(img, col, row, c, (float)(r + 0.5 - d));
        }
}

/* A line of the given half-width, soft-edged: distance-to-segment coverage. */
static void line(ras_image *img, double ax, double ay, double bx, double by, double hw, vec3s c) {
    double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
    int c0 = (int)floor(fmin(ax, bx) - hw - 1), c1 = (int)ceil(fmax(ax, bx) + hw + 1);
    int r0 = (int)floor(fmin(ay, by) - hw - 1), r1 = (int)ceil(fmax(ay, by) + hw + 1);
    for (int row = r0; row <= r1; row++)
        for (int col = c0; col <= c1; col++) {
            double px = col + 0.5 - ax, py = row + 0.5 - ay;
            double t = len2 > 0 ? (px * dx + py * dy) / len2 : 0;
            t = t < 0 ? 0 : t > 1 ? 1 : t;
            double ex = px - t * dx, ey = py - t * dy;
            blend(img, col, row, c, (float)(hw + 0.5 - sqrt(ex * ex + ey * ey)));
        }
}

static double map_axis(double v, double lo, double hi, bool log_axis) {
    if (log_axis) return (log10(v) - log10(lo)) / (log10(hi) - log10(lo));
    return (v - lo) / (hi - lo);
}

static bool to_pixel(const bench_plot *p, double x, double y, double *col, double *row) {
    if (!isfinite(x) || !isfinite(y) || (p->logx && x <= 0) || (p->logy && y <= 0)) return false;
    *col = p->left + map_axis(x, p->x0, p->x1, p->logx) * (p->right - p->left);
    *row = p->bottom - map_axis(y, p->y0, p->y1, p->logy) * (p->bottom - p->top);
    return true;
}

static void format_tick(double v, char *buf, size_t size) {
    double a = fabs(v);
    if (a == 0) snprintf(buf, size, "0");
    else if (a >= 1e4 || a < 1e-3) snprintf(buf, size, "%.0e", v);
    else if (a >= 10) snprintf(buf, size, "%.0f", v);
    else if (a >= 1) snprintf(buf, size, "%.3g", v);
    else snprintf(buf, size, "%.3g", v);
}

/* Tick values along one axis: 1, 2, 5 × 10^k on log axes (only 1 × 10^k when
 * the range spans more than four decades), a 1-2-5 step on linear ones. */
static int ticks(double lo, double hi, bool log_axis, double *out, int max) {
    int n = 0;
    if (log_axis) {
        bool sparse = log10(hi / lo) > 4;
        static const double m[3] = {1, 2, 5};
        for (int k = (int)floor(log10(lo)); k <= (int)ceil(log10(hi)); k++)
            for (int i = 0; i < (sparse ? 1 : 3); i++) {
                double v = m[i] * pow(10, k);
                if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9) && n < max) out[n++] = v;
            }
        return n;
    }
    double raw = (hi - lo) / 6, mag = pow(10, floor(log10(raw))), step = mag;
    if (raw / mag > 5) step = 10 * mag;
    else if (raw / mag > 2) step = 5 * mag;
    else if (raw / mag > 1) step = 2 * mag;
    for (double v = ceil(lo / step) * step; v <= hi + step * 1e-9 && n < max; v += step)
        out[n++] = fabs(v) < step * 1e-9 ? 0 : v;
    return n;
}

bench_plot *bench_plot_create(int width, int height, const char *title, const char *xlabel,
                              const char *ylabel, double x0, double x1, bool logx, double y0,
                              double y1, bool logy, ras_error *err) {
    if (!(x1 > x0) || !(y1 > y0) || (logx && x0 <= 0) || (logy && y0 <= 0)) {
        ras_error_set(err, "chart '%s': expected an increasing, positive-on-log-axes range; "
                           "got x [%g, %g], y [%g, %g]", title, x0, x1, y0, y1);
        return NULL;
    }
    ras_image *img = ras_image_create(width, height, err);
    if (!img) return NULL;
    bench_plot *p = calloc(1, sizeof *p);
    if (!p) {
        ras_image_destroy(img);
        ras_error_set(err, "out of memory for a chart");
        return NULL;
    }
    *p = (bench_plot){.img = img, .x0 = x0, .x1 = x1, .y0 = y0, .y1 = y1, .logx = logx,
                      .logy = logy, .left = 78, .right = width - 24, .top = 64,
                      .bottom = height - 58};
    ras_image_fill(img, BACKGROUND);
    double tv[64];
    char buf[32];
    int n = ticks(x0, x1, logx, tv, 64);
    for (int i = 0; i < n; i++) {
        double c, r;
        to_pixel(p, tv[i], y0, &c, &r);
        line(img, c, p->top, c, p->bottom, 0.5, GRID);
        line(img, c, p->bottom, c, p->bottom + 5, 0.5, AXIS);
        format_tick(tv[i], buf, sizeof buf);
        add_text(p, (int)c - 4 * (int)strlen(buf), p->bottom + 22, 0.42, buf);
    }
    n = ticks(y0, y1, logy, tv, 64);
    for (int i = 0; i < n; i++) {
        double c, r;
        to_pixel(p, x0, tv[i], &c, &r);
        line(img, p->left, r, p->right, r, 0.5, GRID);
        line(img, p->left - 5, r, p->left, r, 0.5, AXIS);
        format_tick(tv[i], buf, sizeof buf);
        add_text(p, p->left - 10 - 8 * (int)strlen(buf), (int)r + 5, 0.42, buf);
    }
    line(img, p->left, p->bottom, p->right, p->bottom, 0.6, AXIS);
    line(img, p->left, p->top, p->left, p->bottom, 0.6, AXIS);
    add_text(p, 12, 26, 0.6, title);
    add_text(p, (p->left + p->right) / 2 - 4 * (int)strlen(xlabel), height - 14, 0.5, xlabel);
    add_text(p, 12, p->top - 12, 0.45, ylabel);
    return p;
}

void bench_plot_destroy(bench_plot *p) {
    if (!p) return;
    ras_image_destroy(p->img);
    free(p);
}

void bench_plot_series(bench_plot *p, const double *x, const double *y, int n, vec3s color,
                       bool join, bool points, const char *legend) {
    double pc = 0, pr = 0;
    bool have_prev = false;
    for (int i = 0; i < n; i++) {
        double c, r;
        if (!to_pixel(p, x[i], y[i], &c, &r)) {
            have_prev = false;
            continue;
        }
        if (join && have_prev) line(p->img, pc, pr, c, r, 1.0, color);
        pc = c;
        pr = r;
        have_prev = true;
    }
    if (points)
        for (int i = 0; i < n; i++) {
            double c, r;
            if (to_pixel(p, x[i], y[i], &c, &r)) {
                dot(p->img, c, r, 4.5, BACKGROUND);
                dot(p->img, c, r, 3.5, color);
            }
        }
    if (legend && legend[0] && p->legend_count < MAX_LEGEND) {
        snprintf(p->legend[p->legend_count], TEXT_LEN, "%s", legend);
        p->legend_color[p->legend_count++] = color;
    }
}

void bench_plot_text(bench_plot *p, double x, double y, const char *text) {
    bench_plot_text_offset(p, x, y, 7, -6, text);
}

void bench_plot_text_offset(bench_plot *p, double x, double y, int dcol, int drow,
                            const char *text) {
    double c, r;
    if (to_pixel(p, x, y, &c, &r)) add_text(p, (int)c + dcol, (int)r + drow, 0.38, text);
}

void bench_plot_legend_bottom(bench_plot *p) { p->legend_bottom = true; }

bool bench_plot_save(const bench_plot *p, const char *path, ras_error *err) {
    const bench_plot *q = p;
    int w = q->img->width, h = q->img->height;
    uint8_t *rgb = malloc((size_t)w * (size_t)h * 3);
    if (!rgb) return ras_error_set(err, "out of memory writing %s", path);
    ras_image *img = ras_image_clone(q->img);
    if (!img) {
        free(rgb);
        return ras_error_set(err, "out of memory writing %s", path);
    }
    /* The legend: top-right, one swatch and name per series. */
    int lx = q->right - 230, ly = q->top + 10;
    if (q->legend_bottom) ly = q->bottom - 12 - 20 * (q->legend_count - 1);
    for (int i = 0; i < q->legend_count; i++) {
        line(img, lx, ly + 20 * i, lx + 24, ly + 20 * i, 1.5, q->legend_color[i]);
        dot(img, lx + 12, ly + 20 * i, 3.5, q->legend_color[i]);
    }
    ras_image_to_rgb8(img, rgb);
    ras_image_destroy(img);
    for (int i = 0; i < q->text_count; i++)
        cv_bridge_draw_text(rgb, w, h, q->texts[i].col, q->texts[i].row, q->texts[i].s,
                            q->texts[i].scale);
    for (int i = 0; i < q->legend_count; i++)
        cv_bridge_draw_text(rgb, w, h, lx + 32, ly + 20 * i + 5, q->legend[i], 0.42);
    bool ok = ras_image_save_rgb8(rgb, w, h, path, err);
    free(rgb);
    return ok;
}
