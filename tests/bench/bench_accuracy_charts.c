/* bench_accuracy_charts.c — the accuracy report's charts (img/accuracy_*.png):
 * error against time for anti-aliasing and texture filtering, the affine
 * error against the depth ratio, drawn with bench_plot.h from the rows.
 * bench_accuracy.h.
 */
#include "bench_accuracy.h"
#include "bench_plot.h"

#include <math.h>   /* sqrt, pow, fmax, fmin, isfinite, INFINITY, NAN */
#include <stdio.h>  /* snprintf */
#include <string.h> /* strcmp */

static const vec3s COLORS[] = {{{0.35f, 0.75f, 1.0f}},
                               {{1.0f, 0.62f, 0.25f}},
                               {{0.45f, 0.9f, 0.45f}},
                               {{1.0f, 0.4f, 0.5f}},
                               {{0.8f, 0.6f, 1.0f}}};

static void range_of(const double *v, int n, double *lo, double *hi) {
    *lo = INFINITY, *hi = -INFINITY;
    for (int i = 0; i < n; i++)
        if (isfinite(v[i]) && v[i] > 0) *lo = fmin(*lo, v[i]), *hi = fmax(*hi, v[i]);
}

bool charts_aa(const char *scene, const char *path, ras_error *err) {
    static const struct {
        const char *prefix, *legend;
        int n;
        const char *names[5];
        const char *labels[5];
    } fam[4] = {
        {"MSAA",
         "MSAA ordered",
         4,
         {"none (1 sample)", "MSAA ordered 2x2", "MSAA ordered 4x4", "MSAA ordered 8x8"},
         {"", "2x2", "4x4", "8x8"}},
        {"MSAA",
         "MSAA standard",
         5,
         {"none (1 sample)", "MSAA standard 2x", "MSAA standard 4x", "MSAA standard 8x",
          "MSAA standard 16x"},
         {"", "2x", "4x", "8x", "16x"}},
        {"SSAA",
         "SSAA ordered",
         4,
         {"none (1 sample)", "SSAA ordered 2x2", "SSAA ordered 4x4", "SSAA ordered 8x8"},
         {"", "2x2", "4x4", "8x8"}},
        {"SSAA",
         "SSAA standard",
         5,
         {"none (1 sample)", "SSAA standard 2x", "SSAA standard 4x", "SSAA standard 8x",
          "SSAA standard 16x"},
         {"", "2x", "4x", "8x", "16x"}},
    };
    double xs[4][5], ys[4][5], all_x[20], all_y[20];
    int m = 0;
    for (int f = 0; f < 4; f++)
        for (int i = 0; i < fam[f].n; i++) {
            acc_row *r = acc_find_row("aa", scene, fam[f].names[i]);
            xs[f][i] = r ? r->rel : NAN;
            ys[f][i] = r ? r->rmse_edge : NAN;
            all_x[m] = xs[f][i], all_y[m++] = ys[f][i];
        }
    double x0, x1, y0, y1;
    range_of(all_x, m, &x0, &x1);
    range_of(all_y, m, &y0, &y1);
    char title[256];
    snprintf(title, sizeof title, "Anti-aliasing: edge error vs time (%s)", scene);
    bench_plot *p = bench_plot_create(860, 540, title, "time per frame, x the cheapest (log)",
                                      "edge-pixel RMSE (log)", x0 / 1.25, x1 * 1.6, true, y0 / 1.4,
                                      y1 * 1.3, true, err);
    if (!p) return false;
    for (int f = 0; f < 4; f++) {
        bench_plot_series(p, xs[f], ys[f], fam[f].n, COLORS[f], true, true, fam[f].legend);
        /* SSAA lands on MSAA's errors: label MSAA only, ordered grids above
         * the point, standard patterns below it. */
        for (int i = 1; i < fam[f].n && f < 2; i++)
            bench_plot_text_offset(p, xs[f][i], ys[f][i], 7, f == 0 ? -7 : 16, fam[f].labels[i]);
    }
    bench_plot_text(p, xs[0][0], ys[0][0], "no AA");
    bool ok = bench_plot_save(p, path, err);
    bench_plot_destroy(p);
    return ok;
}

bool charts_interp(const char *path, ras_error *err) {
    double k[4], meas[4], formula_k[64], formula_v[64], persp[4];
    static const double ks[4] = {1.1, 2, 4, 8};
    for (int i = 0; i < 4; i++) {
        char scene[40];
        snprintf(scene, sizeof scene, "w1/w0 = %g", ks[i]);
        acc_row *a = acc_find_row("interp", scene, "affine (screen-space)");
        acc_row *pc = acc_find_row("interp", scene, "perspective-correct");
        k[i] = ks[i];
        meas[i] = a ? a->v_max : NAN;
        persp[i] = pc ? fmax(pc->v_max, 1e-7) : NAN;
    }
    for (int i = 0; i < 64; i++) {
        formula_k[i] = 1.05 * pow(10 / 1.05, i / 63.0);
        double s = sqrt(formula_k[i]);
        formula_v[i] = (s - 1) / (s + 1);
    }
    bench_plot *p =
        bench_plot_create(860, 500, "Interpolation: worst v error vs depth ratio", "w1 / w0 (log)",
                          "worst |v error| / v range (log)", 1.05, 10, true, 1e-6, 1, true, err);
    if (!p) return false;
    bench_plot_legend_bottom(p);
    bench_plot_series(p, formula_k, formula_v, 64, COLORS[4], true, false,
                      "formula (sqrt(k)-1)/(sqrt(k)+1)");
    bench_plot_series(p, k, meas, 4, COLORS[1], false, true, "affine, measured");
    bench_plot_series(p, k, persp, 4, COLORS[0], true, true, "perspective-correct, measured");
    bool ok = bench_plot_save(p, path, err);
    bench_plot_destroy(p);
    return ok;
}

bool charts_filter(const char *path, ras_error *err) {
    double xs[2][3], ys[2][3], all_x[6] = {0}, all_y[6] = {0}; /* range_of reads m */
    int m = 0, s = 0;
    char scenes[2][40];
    for (int i = 0; i < acc_row_count && s < 2; i++)
        if (!strcmp(acc_rows[i].section, "filter") && !strcmp(acc_rows[i].option, "nearest"))
            snprintf(scenes[s++], 40, "%s", acc_rows[i].scene);
    static const char *names[3] = {"nearest", "bilinear", "trilinear"};
    for (int t = 0; t < s; t++)
        for (int f = 0; f < 3; f++) {
            acc_row *r = acc_find_row("filter", scenes[t], names[f]);
            xs[t][f] = r ? r->rel : NAN;
            ys[t][f] = r ? r->rmse_all : NAN;
            all_x[m] = xs[t][f], all_y[m++] = ys[t][f];
        }
    double x0, x1, y0, y1;
    range_of(all_x, m, &x0, &x1);
    range_of(all_y, m, &y0, &y1);
    bench_plot *p =
        bench_plot_create(860, 500, "Texture filtering: error vs time on a receding floor",
                          "time per frame, x the cheapest (log)", "RMSE vs truth (log)", x0 / 1.15,
                          x1 * 1.5, true, y0 / 1.5, y1 * 1.5, true, err);
    if (!p) return false;
    for (int t = 0; t < s; t++) {
        bench_plot_series(p, xs[t], ys[t], 3, COLORS[t], true, true, scenes[t]);
        for (int f = 0; f < 3; f++)
            bench_plot_text(p, xs[t][f], ys[t][f], names[f]);
    }
    bool ok = bench_plot_save(p, path, err);
    bench_plot_destroy(p);
    return ok;
}
