/* bench_accuracy_report.c — the accuracy report's text: accuracy.csv (every
 * row), accuracy.md (the tables with what they mean, per section) and the
 * same tables on stdout. bench_accuracy.h.
 */
#include "bench_accuracy.h"
#include "ras_io.h" /* ras_io_report: the reports are written atomically */

#include <math.h>   /* isfinite, isnan, isinf, fmax, fmin, INFINITY, NAN */
#include <stdio.h>  /* fprintf, snprintf, fopen, FILE */
#include <string.h> /* strcmp, strncmp, strchr, strcspn */
#include <unistd.h> /* sysconf */

/* ---- output: text helpers ---------------------------------------------------- */

static void fmt_ms(double v, char *buf, size_t n) {
    if (!isfinite(v))
        snprintf(buf, n, "—");
    else if (v < 1)
        snprintf(buf, n, "%.3f", v);
    else if (v < 100)
        snprintf(buf, n, "%.2f", v);
    else
        snprintf(buf, n, "%.0f", v);
}

static void fmt_bytes(double b, char *buf, size_t n) {
    if (!isfinite(b))
        snprintf(buf, n, "—");
    else if (b >= 1 << 20)
        snprintf(buf, n, "%.1f MiB", b / (1 << 20));
    else
        snprintf(buf, n, "%.0f KiB", b / 1024);
}

static void fmt_g(double v, const char *f, char *buf, size_t n) {
    if (isnan(v))
        snprintf(buf, n, "—");
    else if (isinf(v))
        snprintf(buf, n, "∞");
    else
        snprintf(buf, n, f, v);
}

/* "12.3 (11.9–13.0)" */
static void fmt_time(const acc_row *r, char *buf, size_t n) {
    char a[20], b[20], c[20];
    fmt_ms(r->med, a, sizeof a), fmt_ms(r->min, b, sizeof b), fmt_ms(r->max, c, sizeof c);
    if (isfinite(r->med))
        snprintf(buf, n, "%s (%s–%s)", a, b, c);
    else
        snprintf(buf, n, "—");
}

void report_machine(char *buf, size_t n) {
    char model[256] = "unknown CPU";
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (f) {
        char line[512];
        while (fgets(line, sizeof line, f))
            if (!strncmp(line, "model name", 10)) {
                char *c = strchr(line, ':');
                if (c) {
                    c += 1 + (c[1] == ' ');
                    c[strcspn(c, "\n")] = 0;
                    snprintf(model, sizeof model, "%s", c);
                }
                break;
            }
        fclose(f);
    }
    /* The load says how much other work shared the CPUs: with more runnable
     * processes than CPUs, even CPU-time measurements suffer from cache and
     * memory contention, and only the ratios within one table block hold. */
    double load = NAN;
    f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf", &load) != 1) load = NAN;
        fclose(f);
    }
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    if (isfinite(load))
        snprintf(buf, n,
                 "%s, %ld logical CPUs (single-threaded run); 1-minute load average at the end "
                 "%.2f (this run counts about 1)%s",
                 model, cpus, load,
                 load > cpus ? ": the machine was busy, trust ratios, not milliseconds" : "");
    else
        snprintf(buf, n, "%s, %ld logical CPUs (single-threaded run)", model, cpus);
}

/* ---- output: CSV, Markdown, stdout --------------------------------------------------- */

static void csv_num(FILE *f, double v) {
    if (isnan(v))
        fputs(",", f);
    else
        fprintf(f, ",%.6g", v);
}

bool report_write_csv(const char *path) {
    ras_io_report report; /* written whole or not at all (ras_io.h) */
    FILE *f = ras_io_report_open(&report);
    if (!f) return false;
    fputs("section,scene,option,samples,time_ms_median,time_ms_min,time_ms_max,time_rel,"
          "rmse_all,psnr_all_db,rmse_edge,psnr_edge_db,cracks,double_hits,"
          "worst_v_error,formula,uv_max_texels,uv_rms_texels,wrong_fraction,buffer_bytes\n",
          f);
    for (int i = 0; i < acc_row_count; i++) {
        const acc_row *r = &acc_rows[i];
        fprintf(f, "%s,\"%s\",\"%s\",%d", r->section, r->scene, r->option, r->samples);
        double v[] = {r->med,           r->min,           r->max,       r->rel,
                      r->rmse_all,      r->psnr_all,      r->rmse_edge, r->psnr_edge,
                      r->cracks,        r->doubles,       r->v_max,     r->formula,
                      r->uv_max_texels, r->uv_rms_texels, r->wrong,     r->bytes};
        for (size_t k = 0; k < sizeof v / sizeof v[0]; k++)
            csv_num(f, v[k]);
        fputc('\n', f);
    }
    return ras_io_report_commit(&report, path, NULL);
}

void report_scenes_of(const char *section, char out[][40], int *n, int max) {
    *n = 0;
    for (int i = 0; i < acc_row_count; i++) {
        if (strcmp(acc_rows[i].section, section)) continue;
        bool seen = false;
        for (int k = 0; k < *n; k++)
            seen = seen || !strcmp(out[k], acc_rows[i].scene);
        if (!seen && *n < max) snprintf(out[(*n)++], 40, "%s", acc_rows[i].scene);
    }
}

static void table_aa(FILE *f, const char *scene) {
    fprintf(f, "\n**%s**\n\n", scene);
    fprintf(
        f, "| option | samples | ms/frame median (min–max) | × time | RMSE all | PSNR all dB | "
           "RMSE edge | PSNR edge dB | buffers |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < acc_row_count; i++) {
        const acc_row *r = &acc_rows[i];
        if (strcmp(r->section, "aa") || strcmp(r->scene, scene)) continue;
        char t[80], b[32];
        fmt_time(r, t, sizeof t), fmt_bytes(r->bytes, b, sizeof b);
        fprintf(f, "| %s | %d | %s | %.2f | %.4f | %.1f | %.4f | %.1f | %s |\n", r->option,
                r->samples, t, r->rel, r->rmse_all, r->psnr_all, r->rmse_edge, r->psnr_edge, b);
    }
}

static void table_edges(FILE *f) {
    fprintf(f, "| scene | edge functions | ms/frame median (min–max) | × time | cracks | double "
               "hits | buffers |\n"
               "|---|---|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < acc_row_count; i++) {
        const acc_row *r = &acc_rows[i];
        if (strcmp(r->section, "edges")) continue;
        char t[80], b[32];
        fmt_time(r, t, sizeof t), fmt_bytes(r->bytes, b, sizeof b);
        fprintf(f, "| %s | %s | %s | %.2f | %.0f | %.0f | %s |\n", r->scene, r->option, t, r->rel,
                r->cracks, r->doubles, b);
    }
}

static void table_interp(FILE *f) {
    fprintf(f, "| depth ratio | interpolation | ms/frame median (min–max) | × time | worst v error "
               "(of the v range) | formula (√k−1)/(√k+1) | worst \\|Δuv\\| texels | RMS \\|Δuv\\| "
               "texels |\n"
               "|---|---|---:|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < acc_row_count; i++) {
        const acc_row *r = &acc_rows[i];
        if (strcmp(r->section, "interp")) continue;
        char t[80], a[32], b[32], c[32];
        fmt_time(r, t, sizeof t);
        fmt_g(r->v_max, "%.2g", a, sizeof a), fmt_g(r->uv_max_texels, "%.3g", b, sizeof b);
        fmt_g(r->uv_rms_texels, "%.3g", c, sizeof c);
        fprintf(f, "| %s | %s | %s | %.2f | %s | %.4f | %s | %s |\n", r->scene, r->option, t,
                r->rel, a, r->formula, b, c);
    }
}

static void table_filter(FILE *f) {
    fprintf(f,
            "| scene | filter | ms/frame median (min–max) | × time | RMSE | PSNR dB | buffers |\n"
            "|---|---|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < acc_row_count; i++) {
        const acc_row *r = &acc_rows[i];
        if (strcmp(r->section, "filter")) continue;
        char t[80], b[32];
        fmt_time(r, t, sizeof t), fmt_bytes(r->bytes, b, sizeof b);
        fprintf(f, "| %s | %s | %s | %.2f | %.4f | %.1f | %s |\n", r->scene, r->option, t, r->rel,
                r->rmse_all, r->psnr_all, b);
    }
}

/* Wrong fractions per δ; the pipeline rows also get their time at
 * DEPTH_TIME_SCENE (the two formats interleaved, × time against the faster). */
static void table_depth(FILE *f) {
    fprintf(f, "| depth encoding |");
    for (int d = 0; d < DEPTH_DELTA_COUNT; d++)
        fprintf(f, " δ = %g |", DEPTH_DELTAS[d]);
    fprintf(f, " ms/frame median (min–max), δ = 0.01 | × time |\n|---|");
    for (int d = 0; d < DEPTH_DELTA_COUNT; d++)
        fprintf(f, "---:|");
    fprintf(f, "---:|---:|\n");
    for (int e = 0; e < DEPTH_ENCODING_COUNT; e++) {
        fprintf(f, "| %s |", DEPTH_ENCODINGS[e]);
        for (int d = 0; d < DEPTH_DELTA_COUNT; d++) {
            char scene[40];
            snprintf(scene, sizeof scene, "delta = %g", DEPTH_DELTAS[d]);
            acc_row *r = acc_find_row("depth", scene, DEPTH_ENCODINGS[e]);
            fprintf(f, " %.2f%% |", r ? 100 * r->wrong : NAN);
        }
        acc_row *r = acc_find_row("depth", DEPTH_TIME_SCENE, DEPTH_ENCODINGS[e]);
        char t[80];
        if (r && isfinite(r->med)) {
            fmt_time(r, t, sizeof t);
            fprintf(f, " %s | %.2f |\n", t, r->rel);
        } else {
            fprintf(f, " untimed | — |\n");
        }
    }
}

/* The table of section 5b: per gap, the mean over the 24 cells of each kind,
 * then before's and after's worst excess over the bound. */
static void order_table(FILE *f) {
    fprintf(f, "| relative gap | before: mean | after: mean | bound: mean | before: worst excess "
               "over the bound (distance, tilt), cells above it | after: worst excess, cells |\n"
               "|---:|---:|---:|---:|---:|---:|\n");
    for (int gi = 0; gi < ORDER_G; gi++) {
        fprintf(f, "| %.2g | %.2f%% | %.2f%% | %.2f%% |", ORDER_GAP[gi],
                100 * order_mean(ORDER_BEFORE, gi), 100 * order_mean(ORDER_AFTER, gi),
                100 * order_mean(ORDER_ROUNDED, gi));
        for (int k = 0; k < 2; k++) {
            int wd, wt, cells;
            double e = order_excess(k, gi, &wd, &wt, &cells);
            if (cells)
                fprintf(f, " %.2f%% (%g, %g°), %d of %d |", 100 * e, ORDER_DIST[wd], ORDER_TILT[wt],
                        cells, ORDER_D * ORDER_T);
            else
                fprintf(f, " 0.00%%, 0 of %d |", ORDER_D * ORDER_T);
        }
        fprintf(f, "\n");
    }
}

/* The time ratio inverse_w / z01 (fastest frames), min and max over the δ
 * from `first` on. */
static void depth_time_ratio_range(int first, double *lo, double *hi) {
    *lo = INFINITY, *hi = -INFINITY;
    for (int d = first; d < DEPTH_DELTA_COUNT; d++) {
        char scene[40];
        snprintf(scene, sizeof scene, "delta = %g", DEPTH_DELTAS[d]);
        acc_row *z = acc_find_row("depth", scene, DEPTH_ENCODINGS[0]);
        acc_row *i = acc_find_row("depth", scene, DEPTH_ENCODINGS[1]);
        if (!z || !i || !(z->min > 0)) continue;
        double q = i->min / z->min;
        *lo = fmin(*lo, q), *hi = fmax(*hi, q);
    }
}

/* The title and how the run was made. */
static void md_header(FILE *f, const char *machine_name, const char *date, double total_s) {
    fprintf(f,
            "# What accuracy costs: a measured report\n\n"
            "Generated by `make bench-accuracy` (`tests/bench/bench_accuracy.c`) — do not edit by "
            "hand; "
            "regenerate it on your machine to see your own numbers.\n\n"
            "- machine: %s\n- date: %s\n- build: %s, one thread; the whole run took %.0f s%s\n"
            "- every time is the **median of %d frames** rendered in-process after one warm-up "
            "frame (min–max in brackets), measured as the thread's CPU time (so other load on "
            "the machine disturbs it little) with the options of a table block interleaved "
            "frame by frame; **× time** divides by the cheapest option of the same table "
            "block, using each option's fastest frame (the one least disturbed by other load: "
            "cache and memory contention survive even CPU-time measurement); ratios transfer "
            "between machines better than milliseconds do\n"
            "- the images are rendered by the reference solutions (hw1/hw2/hw3 `solution/`); "
            "every ground truth is computed outside the pipeline\n"
            "- raw numbers: [accuracy.csv](accuracy.csv)\n",
            machine_name, date,
#ifdef __OPTIMIZE__
            "optimised (the default RelWithDebInfo build, -O2)",
#else
            "NOT optimised (a Debug build: the times are not representative)",
#endif
            total_s, acc_opt.quick ? " (**--quick**: small images, few repeats)" : "",
            acc_opt.repeats);
}

/* Section 1, its tables and charts, and what they mean. */
static void md_aa(FILE *f) {
    char aa_scenes[4][40];
    int n_aa;
    report_scenes_of("aa", aa_scenes, &n_aa, 4);
    fprintf(
        f, "\n## 1. Anti-aliasing: coverage error vs samples\n\n"
           "Two scenes. *Thin triangles*: one white sliver (0.3–3 px wide) at a random angle in "
           "each cell of a grid, on black — no two overlap, so the truth is **exact**: every "
           "triangle (snapped to 1/256 px like the rasterizer) clipped to every pixel square, "
           "the covered area summed. *hw2 scene*: the two triangles of `hw2_rasterize`; the near "
           "one hides part of the far one, both are flat-coloured, so the truth is exact too: "
           "near ∩ pixel, plus far ∩ pixel minus far ∩ near ∩ pixel, each times its colour. Error "
           "is the RMSE of the resolved pixel value (0..1; the hw2 scene averages R, G, B) against "
           "that truth, over all pixels and over the *edge pixels* (truth strictly between "
           "empty and full); PSNR = 20·log10(1/RMSE). Buffers are colour + depth per sample.\n");
    for (int s = 0; s < n_aa; s++) {
        table_aa(f, aa_scenes[s]);
        fprintf(f, "\n![%s](img/accuracy_aa_%d.png)\n", aa_scenes[s], s);
    }
    if (n_aa > 0) {
        const char *thin = aa_scenes[0];
        acc_row *none = acc_find_row("aa", thin, "none (1 sample)");
        acc_row *m4 = acc_find_row("aa", thin, "MSAA standard 4x"),
                *s4 = acc_find_row("aa", thin, "SSAA standard 4x");
        acc_row *m16 = acc_find_row("aa", thin, "MSAA standard 16x"),
                *s16 = acc_find_row("aa", thin, "SSAA standard 16x");
        acc_row *o4 = acc_find_row("aa", thin, "MSAA ordered 2x2"),
                *m8 = acc_find_row("aa", thin, "MSAA standard 8x");
        acc_row *o64 = acc_find_row("aa", thin, "MSAA ordered 8x8"),
                *s64 = acc_find_row("aa", thin, "SSAA ordered 8x8");
        char mem64[32], mem1[32];
        fmt_bytes(o64->bytes, mem64, sizeof mem64), fmt_bytes(none->bytes, mem1, sizeof mem1);
        fprintf(f,
                "\n**What it means.** On the thin triangles, MSAA 4x (standard pattern) buys "
                "%.1f dB on edge pixels (edge RMSE %.3f → %.3f) for %.2f× the time of no AA; "
                "SSAA 4x gives exactly the same picture here for %.2f×. At 16x: %.1f dB for "
                "%.2f× (MSAA) or %.2f× (SSAA); the 8x8 ordered grid, %.1f dB for %.2f× (MSAA) or "
                "%.2f× (SSAA), with %s of buffers instead of %s. MSAA and SSAA store the same "
                "samples and resolve them the same way, so with flat colours their error is "
                "identical: they differ only in how often they call the shader (once per pixel vs "
                "once per covered sample). With the trivial vertex-colour shader used here shading "
                "is the cheap part, so the two cost about the same (the differences between "
                "their rows are mostly timing noise) and both are dominated by testing every "
                "sample of every pixel of each triangle's bounding box and by clearing and "
                "resolving the sample buffers; with hw3's texture and lighting shaders SSAA's "
                "cost grows with the shader, MSAA's barely does. Edge error falls roughly like "
                "1/√samples, about 3 dB per doubling of the samples, while the time and the "
                "memory double.\n",
                acc_psnr(m4->rmse_edge) - acc_psnr(none->rmse_edge), none->rmse_edge, m4->rmse_edge,
                m4->rel, s4->rel, acc_psnr(m16->rmse_edge) - acc_psnr(none->rmse_edge), m16->rel,
                s16->rel, acc_psnr(o64->rmse_edge) - acc_psnr(none->rmse_edge), o64->rel, s64->rel,
                mem64, mem1);
        fprintf(f, "\n**Against the numbers quoted in DESIGN.md** (edge-pixel RMSE vs exact area, "
                   "measured there on other scenes):\n\n"
                   "| samples | DESIGN.md | thin triangles | hw2 scene |\n|---|---:|---:|---:|\n");
        static const struct {
            const char *name, *expected;
        } cmp[] = {{"none (1 sample)", "0.25"},
                   {"MSAA ordered 2x2", "0.088"},
                   {"MSAA standard 4x", "0.094 (0.079 near-axis)"},
                   {"MSAA standard 8x", "0.059"},
                   {"MSAA standard 16x", "0.03–0.045"},
                   {"MSAA ordered 8x8", "—"}};
        for (size_t i = 0; i < sizeof cmp / sizeof cmp[0]; i++) {
            acc_row *a = acc_find_row("aa", thin, cmp[i].name);
            acc_row *b = n_aa > 1 ? acc_find_row("aa", aa_scenes[1], cmp[i].name) : NULL;
            fprintf(f, "| %s | %s | %.3f | %s%.3f |\n", cmp[i].name, cmp[i].expected,
                    a ? a->rmse_edge : NAN, b ? "" : "—", b ? b->rmse_edge : NAN);
        }
        fprintf(f,
                "\nOn the thin triangles, 1 sample gives %.3f, 2x2 ordered %.3f and 8x %.3f. "
                "The thin scene's edge pixels include many where a sliver only grazes a pixel "
                "or lies wholly inside it (a sliver narrower than a pixel has *no* interior "
                "pixels); a single sample gets such a pixel entirely right or entirely wrong, "
                "which is why its errors run ~10%% above DESIGN.md's long-edge figures. The hw2 "
                "scene has six long straight edges (one exactly horizontal, two at 45°), so its "
                "per-pattern numbers depend on those few angles — the ordered 2x2 grid beats the "
                "standard 4x pattern there, unlike on random angles; and its errors are in "
                "colour, where the triangles differ from the black background by 0.7–0.9 and "
                "from each other by only 0.1–0.2, so they come out lower than pure coverage "
                "errors. Compare the trend, not the third digit.\n",
                none->rmse_edge, o4->rmse_edge, m8->rmse_edge);
        (void)s4;
    }
}

/* Section 2. */
static void md_edges(FILE *f) {
    char sc[8][40];
    int n;
    report_scenes_of("edges", sc, &n, 8);
    fprintf(f,
            "\n## 2. Edge precision: float vs fixed-point edge functions\n\n"
            "Every triangle of a closed mesh is drawn with SSAA 2x2 (4 samples per pixel) and "
            "each one slightly nearer than the last, so *every* triangle that covers a sample "
            "reaches the shader there; a counting shader records how many did. Inside the "
            "union of the triangles every sample must be hit exactly once: 0 is a **crack** (the "
            "background shows through), ≥ 2 a **double hit** (blending and transparency draw "
            "that sample twice). Times are frames at one sample per pixel with the vertex-colour "
            "shader, where coverage dominates.\n\n");
    table_edges(f);
    if (n >= 1) {
        acc_row *fx = acc_find_row("edges", sc[0], "fixed 24.8, top-left (reference)");
        acc_row *fl = acc_find_row("edges", sc[0], "float, >= 0 test");
        fprintf(f,
                "\n**What it means.** The float edge function evaluates a shared edge twice, "
                "once from each triangle, with different rounding: on the fan that gives "
                "%.0f double hits and %.0f cracks among %d×%d×4 samples (DESIGN.md quotes "
                "~240–370 on its 3000-sliver fan; the count grows with the number of samples "
                "that lie within rounding distance of a shared edge, so it depends on the "
                "image size, the sample count and where the fan sits; a > 0 test would turn "
                "the double hits into cracks). The float rows are drawn by the benchmark's "
                "own float-edge rasterizer (`tests/bench/bench_float_edges.c`, the way a first "
                "rasterizer is written); the reference has no float mode. The reference snaps "
                "the vertices to 1/256 px before its `inside_triangle` and "
                "`compute_barycentric_2d` see them: every edge function is then a whole number "
                "of 1/65536 px², computed exactly (in double), and the top-left rule gives "
                "each sample exactly on an edge to one triangle: 0 and 0, on both meshes. "
                "DESIGN.md expects exact coverage to cost 1.1–1.4× a float loop; here the "
                "reference takes %.2f× the float rasterizer's time — both evaluate the three "
                "edge functions from the vertices at every sample, the reference with the "
                "triangle's area worked out once. Either way watertightness is not where the "
                "time goes.\n",
                fl ? fl->doubles : NAN, fl ? fl->cracks : NAN, acc_opt.quick ? 256 : 512,
                acc_opt.quick ? 256 : 512, fx && fl ? fx->med / fl->med : NAN);
    }
}

/* Section 3. */
static void md_interp(FILE *f) {
    fprintf(f,
            "\n## 3. Interpolation: affine vs perspective-correct\n\n"
            "A rectangle recedes from view depth w0 = 1 at the bottom of the screen to w1 = k at "
            "the top; v runs from 0 (near edge) to 1 (far edge), u across, on a 256×256 texture. "
            "The truth is the analytic mapping: the ray through each pixel centre hits the "
            "plane, and the hit's UV is read off the rectangle. Along the rectangle's sides v "
            "goes from 0 to 1 while w goes from w0 to w1, exactly the case of the formula "
            "(√k−1)/(√k+1) for the worst affine error. Times render the same plane with an unlit "
            "bilinear texture.\n\n");
    table_interp(f);
    acc_row *a2 = acc_find_row("interp", "w1/w0 = 2", "affine (screen-space)");
    acc_row *a8 = acc_find_row("interp", "w1/w0 = 8", "affine (screen-space)");
    acc_row *p8 = acc_find_row("interp", "w1/w0 = 8", "perspective-correct");
    if (a2 && a8 && p8)
        fprintf(f,
                "\n![interpolation error](img/accuracy_interp.png)\n\n"
                "**What it means.** Affine interpolation (what a pipeline that forces w = 1 "
                "silently does) is wrong by up to %.3f of the texture's range at a depth "
                "ratio of 2 — %.0f texels of a 256-texel texture — and by %.3f (%.0f texels) "
                "at 8, matching the formula to the pixel grid's resolution. Perspective-"
                "correct interpolation is exact up to float rounding (worst %.2g texels) and "
                "costs %.2f× the affine frame: one divide per fragment. There is no reason "
                "ever to skip it; the affine picture is the classic \"texture swims and "
                "bends along the diagonal\" bug.\n",
                a2->v_max, a2->uv_max_texels, a8->v_max, a8->uv_max_texels, p8->uv_max_texels,
                p8->rel);
}

/* Section 4. */
static void md_filter(FILE *f) {
    char sc[8][40];
    int n;
    report_scenes_of("filter", sc, &n, 8);
    fprintf(f,
            "\n## 4. Texture filtering on a receding floor\n\n"
            "A floor from 1 to 40 units ahead of a camera 1 unit above it, one 256×256 texture "
            "tile per 8 units (repeat), rendered without AA. The truth per pixel is the average "
            "of %d×%d bilinear lookups of level 0 at the exact (ray–plane) UV of sub-pixel "
            "positions — a box filter over the pixel. Error: RMSE of the colour (0..1, averaged "
            "over R, G, B) over the pixels wholly on the floor. Trilinear's mip chain is built "
            "once, before timing.\n\n",
            acc_opt.quick ? 8 : 16, acc_opt.quick ? 8 : 16);
    table_filter(f);
    if (n >= 1) {
        acc_row *rn = acc_find_row("filter", sc[0], "nearest"),
                *rb = acc_find_row("filter", sc[0], "bilinear");
        acc_row *rt = acc_find_row("filter", sc[0], "trilinear");
        fprintf(f,
                "\n![texture filtering](img/accuracy_filter.png)\n\n"
                "**What it means.** Far away, one pixel covers many texels; nearest and bilinear "
                "read one spot of them and return noise (aliasing, moiré), so their error is "
                "dominated by the distance, not by the filter: on the checker, nearest %.4f and "
                "bilinear %.4f. Trilinear reads a pre-averaged mip level sized to the pixel's "
                "footprint and gets %.4f (%.1f dB better than nearest) for %.2f× the time of "
                "nearest (bilinear: %.2f×). Its remaining error is blur: the footprint on a "
                "floor is long and thin, and isotropic mip-mapping picks the level for the "
                "long side (anisotropic filtering would fix that).\n",
                rn->rmse_all, rb->rmse_all, rt->rmse_all, rt->psnr_all - rn->psnr_all, rt->rel,
                rb->rel);
    }
}

/* Section 5. */
static void md_depth(FILE *f) {
    fprintf(f,
            "\n## 5. Depth precision near the far plane\n\n"
            "Two parallel planes tilted away from the camera (view depth 30 at the bottom of "
            "the screen to 49 at the top; near 0.1, far %.0f, the hw2 camera's numbers), the "
            "second one δ farther along the view axis, drawn first, so a tie goes to the wrong "
            "plane. Each cell is the fraction of pixels where the farther plane wins. The first "
            "two rows are the pipeline's two depth formats (`common/pipeline/stage3_setup.h`), "
            "rendered "
            "by the reference rasterizer, which interpolates the per-vertex depth in float and "
            "keeps the smaller; both are timed, interleaved frame by frame. The pipeline has no "
            "fixed-point depth buffer, so the other rows are *what-ifs* computed from the "
            "exact depth of each plane at the pixel centre with only the storage rounding of "
            "that encoding — lower bounds, untimed.\n\n",
            DEPTH_FAR);
    table_depth(f);
    const char *D1 = "delta = 0.0001", *D3 = "delta = 0.0003";
    acc_row *z1 = acc_find_row("depth", D1, DEPTH_ENCODINGS[0]);
    acc_row *z3 = acc_find_row("depth", D3, DEPTH_ENCODINGS[0]);
    acc_row *z10 = acc_find_row("depth", "delta = 0.001", DEPTH_ENCODINGS[0]);
    acc_row *z30 = acc_find_row("depth", "delta = 0.003", DEPTH_ENCODINGS[0]);
    acc_row *i10 = acc_find_row("depth", "delta = 0.001", DEPTH_ENCODINGS[1]);
    acc_row *e1 = acc_find_row("depth", D1, DEPTH_ENCODINGS[2]);
    acc_row *e3 = acc_find_row("depth", D3, DEPTH_ENCODINGS[2]);
    acc_row *r1 = acc_find_row("depth", D1, DEPTH_ENCODINGS[4]);
    double inv_worst = 0;
    for (int d = 0; d < DEPTH_DELTA_COUNT; d++) {
        char scene[40];
        snprintf(scene, sizeof scene, "delta = %g", DEPTH_DELTAS[d]);
        acc_row *r = acc_find_row("depth", scene, DEPTH_ENCODINGS[1]);
        if (r) inv_worst = fmax(inv_worst, r->wrong);
    }
    /* Time ratios where both formats do the same work: from the first δ
     * at which z01 is right on 99% of the pixels. */
    int first_right = DEPTH_DELTA_COUNT - 1;
    for (int d = DEPTH_DELTA_COUNT - 1; d >= 0; d--) {
        char scene[40];
        snprintf(scene, sizeof scene, "delta = %g", DEPTH_DELTAS[d]);
        acc_row *r = acc_find_row("depth", scene, DEPTH_ENCODINGS[0]);
        if (!r || !(r->wrong < 0.01)) break;
        first_right = d;
    }
    double lo, hi;
    depth_time_ratio_range(first_right, &lo, &hi);
    acc_row *zt = acc_find_row("depth", DEPTH_TIME_SCENE, DEPTH_ENCODINGS[0]);
    acc_row *it = acc_find_row("depth", DEPTH_TIME_SCENE, DEPTH_ENCODINGS[1]);
    acc_row *i1 = acc_find_row("depth", D1, DEPTH_ENCODINGS[1]);
    if (z1 && z3 && z10 && z30 && i10 && e1 && e3 && r1 && zt && it && i1) {
        char tz[80], ti[80];
        fmt_time(zt, tz, sizeof tz);
        fmt_time(it, ti, sizeof ti);
        fprintf(f,
                "\n**What it means.** With z in [0, 1] and near = 0.1, depth spends almost all "
                "of its range close to the camera: at 40 units a step of δ changes z by only "
                "about near·δ/d² = 6·10⁻⁵·δ, while float's steps just below 1 are 6·10⁻⁸. "
                "Stored exactly and rounded once, float z would still lose %.0f%% of the "
                "pixels at δ = 0.0001 and %.0f%% at 0.0003 (24-bit fixed point, the classic "
                "GPU depth buffer, has the same step near 1 and fares the same). The "
                "pipeline's z01 does worse than that bound — %.0f%% wrong at δ = 0.0001, "
                "%.0f%% at 0.0003, %.1f%% at 0.001, %.2f%% at 0.003 — because it computes z "
                "in float (the projection's z row, the divide by w, (1 − z)/2, then "
                "interpolation across the triangle) and every step rounds by about as much "
                "as the whole gap.\n\n"
                "The pipeline's **inverse_w** format (`\"depth\": \"inverse_w\"` in a scene "
                "file, `RAS_DEPTH_INV_W` in `ras_pipeline_config`) stores −near/w: reversed-z "
                "with the far plane at infinity, negated so that the rasterizer's \"smaller "
                "is closer\" test does not change. It is one division from w per vertex; 1/w "
                "is affine in screen space, so the rasterizer's linear interpolation is "
                "exact; and distant depths sit next to 0, where floats are dense, so the "
                "relative step is the same ~10⁻⁷ at every distance while the planes differ "
                "by δ/d ≥ 2·10⁻⁶ even at δ = 0.0001. Measured: %.2f%% wrong at worst over "
                "all δ. Its time, where both formats are right and so do the same work: "
                "%.2f× that of z01 at δ = 0.01 (%s ms against %s ms), %.2f–%.2f× over "
                "δ ≥ %g. The only extra work is one division per vertex (8 vertices a "
                "frame here), so a few percent either way is the noise of the machine. At "
                "δ = 0.0001 inverse_w takes %.2f× the time of z01, and that is the price of "
                "the right answer, not of the format: with z01 the nearer plane (drawn "
                "second) fails the depth test on %.0f%% of the pixels and is never "
                "written, with inverse_w it is written everywhere. Reversed-z needs float to "
                "pay off: stored as 24-bit "
                "fixed point, near/w has steps of 6·10⁻⁸ everywhere and at 40 units the gap "
                "is near·δ/d², as for z01, so it would lose %.0f%% at δ = 0.0001. View "
                "depth w itself is not a format: it is not affine in screen space (a "
                "rasterizer interpolating it linearly puts the midpoint of an edge from "
                "w = 1 to 4 at 2.5 instead of 1.6), and interpolated correctly, as "
                "1/(interpolated 1/w), it orders surfaces exactly as inverse_w does. "
                "Without changing formats the cheapest fix is the near plane: z01's "
                "resolution at distance d scales with near/d², so near = 1 instead of 0.1 "
                "buys a factor 10.\n",
                100 * e1->wrong, 100 * e3->wrong, 100 * z1->wrong, 100 * z3->wrong,
                100 * z10->wrong, 100 * z30->wrong, 100 * inv_worst, it->min / zt->min, ti, tz, lo,
                hi, DEPTH_DELTAS[first_right], i1->min / z1->min, 100 * z1->wrong, 100 * r1->wrong);
    }
}

/* Section 5b. */
static void md_order(FILE *f) {
    int g14 = 1, d1000 = 3, t45 = 2; /* the cell issue #27 quoted */
    int wd, wt, cells;
    double worst_before = order_worst(ORDER_BEFORE, ORDER_G - 1, &wd, &wt, &cells);
    int cells_before = cells;
    int e_wd, e_wt, e_cells;
    double e6 = order_excess(ORDER_AFTER, 3, &e_wd, &e_wt, &e_cells);
    fprintf(f,
            "\n### 5b. inverse_w's order at every distance and tilt\n\n"
            "Two parallel planes z = −D − y·tan(tilt) in view space at distance d = 1, 10, "
            "100, 1000 and tilts 0, 30, 45, 60, 75, 85°, the second one a relative gap "
            "farther (D = d·(1 + gap)), turned 37° about the view axis so that its corners "
            "snap differently from the first one's (as two meshes' do), drawn first, in "
            "inverse_w (near 0.1, far 1e6, %d×%d pixels). Each cell is the fraction of the "
            "samples both planes cover where the farther one wins. *Before* builds each "
            "clipped triangle's depth as setup did until issue #27, −near/w of each "
            "unsnapped corner, while the rasterizer computes coverage and the "
            "barycentrics it interpolates depth with on the corners snapped to 1/256 px; "
            "*after* is the pipeline now: `common/pipeline/stage3_setup.c` gives each corner the "
            "depth of its triangle's own plane (in double) at its snapped position, so "
            "depth is interpolated from the same positions as coverage. The *bound* is the "
            "exact depth of each quad as the pipeline is given it (its float clip-space "
            "corners, solved in double) rounded once to float: no arithmetic after the "
            "vertex stage can do better, and where it loses order too the float input "
            "itself no longer separates the planes. Means over the 24 cells, and the "
            "worst excess over the bound:\n\n",
            acc_opt.quick ? 64 : 128, acc_opt.quick ? 64 : 128);
    order_table(f);
    fprintf(f,
            "\n**What it means.** Before, the snap moved each corner by up to 1/512 px in "
            "x and y while its depth stayed where it was, which tilts the interpolated "
            "depth plane by a different amount for each triangle: at gaps of 1e-6 and "
            "4e-6 of the distance the farther plane still won %.2f%% and %.2f%% of the "
            "samples on average (at 4e-6 up to %.2f%% in the worst cell, %g, %g°, and %d of "
            "24 cells lost some), where the bound loses %.2f%% and %.2f%%. After, the "
            "pipeline loses order only where its input already does: at 1e-6 within "
            "%.2f%% of the samples of the bound in every cell (worst %g, %g°), none at "
            "4e-6; at 3e-7 %.2f%% on average (bound %.2f%%, before %.2f%%). That is the "
            "statement of `common/pipeline/stage3_setup.h` now: inverse_w keeps the order of two "
            "surfaces as far as their float clip-space corners carry it, at every "
            "distance and tilt measured here, from a gap of about 1e-6 of their distance "
            "(everywhere from 4e-6); at 1e-6 the input's own rounding (the vertex "
            "transform in float, on the steep tilts) already loses %.2f%% of the samples "
            "on average. Below 3e-7 the gap is one or two float steps and no format keeps "
            "it: the bound itself loses %.2f%% at 1.4e-7 and %.2f%% at 1e-7, and after "
            "(%.2f%%, %.2f%%) is no better than before (%.2f%%, %.2f%%) there, on a "
            "full run a little worse: the corrected corner depth follows each cut "
            "corner's float position, which before cancelled between two planes cut "
            "along the same line — the cell "
            "issue #27 quoted (%g, %g°, gap %.2g) is before %.2f%%, after %.2f%%, bound "
            "%.2f%% in this geometry. z01 is unchanged (its reference buffers too): its "
            "loss is its encoding's (section 5), far larger than the snap's.\n",
            100 * order_mean(ORDER_BEFORE, 3), 100 * order_mean(ORDER_BEFORE, 4),
            100 * worst_before, ORDER_DIST[wd], ORDER_TILT[wt], cells_before,
            100 * order_mean(ORDER_ROUNDED, 3), 100 * order_mean(ORDER_ROUNDED, 4), 100 * e6,
            ORDER_DIST[e_wd], ORDER_TILT[e_wt], 100 * order_mean(ORDER_AFTER, 2),
            100 * order_mean(ORDER_ROUNDED, 2), 100 * order_mean(ORDER_BEFORE, 2),
            100 * order_mean(ORDER_ROUNDED, 3), 100 * order_mean(ORDER_ROUNDED, 1),
            100 * order_mean(ORDER_ROUNDED, 0), 100 * order_mean(ORDER_AFTER, 1),
            100 * order_mean(ORDER_AFTER, 0), 100 * order_mean(ORDER_BEFORE, 1),
            100 * order_mean(ORDER_BEFORE, 0), ORDER_DIST[d1000], ORDER_TILT[t45], ORDER_GAP[g14],
            100 * order_fraction(ORDER_BEFORE, g14, d1000, t45),
            100 * order_fraction(ORDER_AFTER, g14, d1000, t45),
            100 * order_fraction(ORDER_ROUNDED, g14, d1000, t45));
}

bool report_write_markdown(const char *path, const char *machine_name, const char *date,
                           double total_s) {
    ras_io_report report; /* written whole or not at all (ras_io.h) */
    FILE *f = ras_io_report_open(&report);
    if (!f) return false;
    md_header(f, machine_name, date, total_s);
    md_aa(f);
    md_edges(f);
    md_interp(f);
    md_filter(f);
    md_depth(f);
    md_order(f);
    fprintf(f, "\n## How to regenerate\n\n"
               "    make bench-accuracy            # full run into docs/ (a few minutes)\n"
               "    build/bin/bench_accuracy --quick --out /tmp/acc   # small and fast\n"
               "    build/bin/bench_accuracy --quick --check          # what `make test` runs\n");
    return ras_io_report_commit(&report, path, NULL);
}

void report_print_tables(void) {
    char aa_scenes[4][40];
    int n_aa;
    report_scenes_of("aa", aa_scenes, &n_aa, 4);
    printf("\n== 1. anti-aliasing ==\n");
    for (int s = 0; s < n_aa; s++)
        table_aa(stdout, aa_scenes[s]);
    printf("\n== 2. edge precision ==\n");
    table_edges(stdout);
    printf("\n== 3. interpolation ==\n");
    table_interp(stdout);
    printf("\n== 4. texture filtering ==\n");
    table_filter(stdout);
    printf("\n== 5. depth precision (fraction of pixels wrong) ==\n");
    table_depth(stdout);
    printf("\n== 5b. inverse_w order: parallel planes, worst over distance x tilt ==\n");
    order_table(stdout);
}
