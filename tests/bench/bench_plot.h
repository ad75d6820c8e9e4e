/* bench_plot.h — a tiny chart maker for the accuracy report (bench_accuracy).
 *
 * Draws scatter/line charts into a ras_image (lines and dots in C, soft-edged)
 * and writes them as PNG through the OpenCV bridge, which also draws the text.
 * Axes may be logarithmic; ticks are placed at 1, 2, 5 × 10^k (log) or at a
 * round step (linear). Dark background, white text (the bridge's text style).
 *
 *   bench_plot *p = bench_plot_create(800, 500, "title", "x label", "y label",
 *                                     x0, x1, true, y0, y1, true, &err);
 *   bench_plot_series(p, xs, ys, n, colour, true, true, "legend name");
 *   bench_plot_text(p, x, y, "label");      // at data coordinates
 *   bench_plot_save(p, "out.png", &err);
 *   bench_plot_destroy(p);
 */
#ifndef RAS_BENCH_PLOT_H
#define RAS_BENCH_PLOT_H

#include "ras_error.h"
#include "ras_image.h"

typedef struct bench_plot bench_plot;

/* A chart of width × height pixels whose data area spans [x0, x1] × [y0, y1]
 * (log axes need positive bounds). NULL and err on a bad size or range. */
bench_plot *bench_plot_create(int width, int height, const char *title, const char *xlabel,
                              const char *ylabel, double x0, double x1, bool logx, double y0,
                              double y1, bool logy, ras_error *err);
void bench_plot_destroy(bench_plot *p);

/* n points; `line` joins them in order, `points` marks each; a non-empty
 * `legend` adds an entry to the legend box. Non-finite or out-of-axis (log
 * of ≤ 0) points are skipped. */
void bench_plot_series(bench_plot *p, const double *x, const double *y, int n, vec3s color,
                       bool line, bool points, const char *legend);

/* Text left-aligned at a data point (nudged right and up of it). */
void bench_plot_text(bench_plot *p, double x, double y, const char *text);
/* The same, with the text's baseline-left corner at (dcol, drow) pixels from the point. */
void bench_plot_text_offset(bench_plot *p, double x, double y, int dcol, int drow,
                            const char *text);

/* Moves the legend from the upper-right to the lower-right corner. */
void bench_plot_legend_bottom(bench_plot *p);

bool bench_plot_save(const bench_plot *p, const char *path, ras_error *err);

#endif
