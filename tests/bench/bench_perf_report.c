/* bench_perf_report.c — the performance report's text: the rows on stdout,
 * docs/performance.md (the prose of bench_perf.md.in, then the measured
 * tables: every row, the goals, llvmpipe beside the project's renderers and
 * the course framework's instruction counts) and docs/performance.csv.
 * bench_perf.h.
 */
#include "bench_perf.h"
#include "ras_io.h" /* ras_io_report: the report is written atomically */

#include <stdio.h>  /* fprintf, snprintf, fopen, fread, fwrite */
#include <stdlib.h> /* getloadavg */
#include <string.h> /* strcmp, strncmp, strchr, strcspn, strlen */
#include <time.h>   /* time, strftime, gmtime */
#include <unistd.h> /* sysconf */

bool perf_on_spot;

bool perf_is_llvmpipe(const perf_row *r) { return r->mode[0] == 'l'; }

const char *report_aa_label(ras_aa_mode aa) {
    return aa == RAS_AA_MSAA ? "MSAA 4x" : aa == RAS_AA_SSAA ? "SSAA 4x" : "1x";
}

void report_print_row(FILE *f, const perf_row *r, bool md) {
    double ns = r->fragments ? r->median * 1e6 / (double)r->fragments : 0;
    if (perf_is_llvmpipe(r)) { /* no counters: its own work is not the teaching pipeline's */
        const char *check = !r->checked     ? ""
                            : r->check.pass ? "within tolerance"
                                            : "**OUTSIDE tolerance**";
        if (md)
            fprintf(
                f, "| %s | %s | llvmpipe | %d | %.2f | %.2f | %.2f | %.2f | — | — | — | — | %s |\n",
                ras_scene_shader_name(r->shader), report_aa_label(r->aa), r->threads, r->median, r->min,
                r->max, r->cpu_median, check);
        else
            fprintf(f, "%-12s %-8s %-8s %2d %9.2f %9.2f %9.2f %9.2f  %s\n",
                    ras_scene_shader_name(r->shader), report_aa_label(r->aa), "llvmpipe", r->threads,
                    r->median, r->min, r->max, r->cpu_median,
                    r->checked
                        ? (r->check.pass ? "pixels within tolerance" : "pixels OUTSIDE tolerance")
                        : "");
        return;
    }
    if (md)
        fprintf(
            f,
            "| %s | %s | %s | %d | %.2f | %.2f | %.2f | %.2f | %llu | %llu | %.1f | %.1f | %s |\n",
            ras_scene_shader_name(r->shader), report_aa_label(r->aa), r->mode, r->threads, r->median,
            r->min, r->max, r->cpu_median, (unsigned long long)r->fragments,
            (unsigned long long)r->shaded, ns, (double)r->buffer_bytes / 1048576.0,
            r->identical ? "yes" : "**NO**");
    else
        fprintf(f, "%-12s %-8s %-8s %2d %9.2f %9.2f %9.2f %9.2f %9llu %9llu %8.1f %8.1f %s\n",
                ras_scene_shader_name(r->shader), report_aa_label(r->aa), r->mode, r->threads, r->median,
                r->min, r->max, r->cpu_median, (unsigned long long)r->fragments,
                (unsigned long long)r->shaded, ns, (double)r->buffer_bytes / 1048576.0,
                r->identical ? "same" : "DIFFERENT");
}

static void machine_name(char *buf, size_t size) {
    snprintf(buf, size, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f) return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, "model name", 10)) {
            char *colon = strchr(line, ':');
            if (colon) {
                colon += 2;
                colon[strcspn(colon, "\n")] = 0;
                snprintf(buf, size, "%s", colon);
            }
            break;
        }
    fclose(f);
}

/* ---- llvmpipe beside the project's renderers ------------------------------ */

static const perf_row *find_row(ras_scene_shader shader, ras_aa_mode aa, const char *mode, int threads) {
    for (int i = 0; i < perf_row_count; i++)
        if (perf_rows[i].shader == shader && perf_rows[i].aa == aa &&
            !strcmp(perf_rows[i].mode, mode) && perf_rows[i].threads == threads)
            return &perf_rows[i];
    return NULL;
}

/* The llvmpipe row a row is compared with: same shader, AA and thread count. */
static const perf_row *llvmpipe_peer(const perf_row *r) {
    return find_row(r->shader, r->aa, "llvmpipe", r->threads);
}

static void print_ms(FILE *f, const perf_row *r) {
    if (r)
        fprintf(f, " %.2f |", r->median);
    else
        fprintf(f, " — |");
}

static void print_ratio(FILE *f, const perf_row *r, const perf_row *l) {
    if (r && l && l->median > 0)
        fprintf(f, " %.2f |", r->median / l->median);
    else
        fprintf(f, " — |");
}

static bool same_check(const llvmpipe_check *a, const llvmpipe_check *b) {
    return a->covered_ours == b->covered_ours && a->covered_llvmpipe == b->covered_llvmpipe &&
           a->covered_one == b->covered_one && a->mean_diff == b->mean_diff &&
           a->bad_fraction == b->bad_fraction && a->max_diff == b->max_diff && a->pass == b->pass;
}

/* The course's C++ framework (GAMES101, a completed solution built -O2),
 * measured in issue 18 on the spot cow, 700×700, one thread: one frame's
 * instructions counted with callgrind, million. The framework cannot be
 * built here (it is not ours to ship: Eigen, OpenCV 4 C++ and the course's
 * code), so its figures are these constants; they hold for the spot cow only. */
static const double course_framework_minstr[RAS_SHADER_COUNT] = {
    [RAS_SHADER_NORMAL] = 76.6, [RAS_SHADER_PHONG] = 143.0,        [RAS_SHADER_TEXTURE] = 168.3,
    [RAS_SHADER_BUMP] = 125.1,  [RAS_SHADER_DISPLACEMENT] = 178.6,
};

/* The teaching pipeline's instructions beside the framework's (1x). */
static void report_framework(FILE *f) {
    bool counted = true;
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        counted = counted && perf_instr[s][0][0] && perf_instr[s][0][3];
    if (!counted) return;
    fprintf(f, "\n### The teaching pipeline against the course's framework\n\n");
    if (!perf_on_spot) {
        fprintf(f, "The course framework's figures are for the spot cow: run `make bench-perf "
                   "INSTRUCTIONS=1 SPOT=…/spot` to compare. The teaching pipeline on this model, "
                   "1x, million instructions: ");
        for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
            fprintf(f, "%s%s %.1f (nearest lookups %.1f)", s ? ", " : "",
                    ras_scene_shader_name((ras_scene_shader)s), perf_instr[s][0][0] / 1e6,
                    perf_instr[s][0][3] / 1e6);
        fprintf(f, ".\n");
        return;
    }
    fprintf(f,
            "One frame at 1x on one thread, million instructions (callgrind). The framework: "
            "GAMES101's C++ code, a completed solution built -O2, measured once (issue 18) — "
            "its texture lookups read the nearest texel; the teaching pipeline's default is "
            "bilinear (4 texels), so it is also counted with `--filter nearest`, the same work "
            "as the framework's. This build is %s%s; the default build (RelWithDebInfo, -O2, "
            "as the framework) executes more: its counts, change by change, are in \"The "
            "teaching pipeline against the course's framework (issue 18, item 3)\" above. "
            "`tests/bench/teaching_instructions_test.sh` (ctest `teaching_instructions`, "
            "-O2) keeps them from growing.\n\n",
            RAS_BUILD_TYPE, !strcmp(RAS_BUILD_TYPE, "Release") ? " (-O3)" : "");
    fprintf(f, "| shader | framework | teaching, bilinear (default) | ÷ framework | teaching, "
               "nearest | ÷ framework |\n|---|---:|---:|---:|---:|---:|\n");
    int at_or_below = 0, at_or_below_nearest = 0;
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++) {
        double fw = course_framework_minstr[s], b = perf_instr[s][0][0] / 1e6,
               n = perf_instr[s][0][3] / 1e6;
        fprintf(f, "| %s | %.1f | %.1f | %.2f | %.1f | %.2f |\n", ras_scene_shader_name((ras_scene_shader)s),
                fw, b, b / fw, n, n / fw);
        at_or_below += b <= fw;
        at_or_below_nearest += n <= fw;
    }
    fprintf(f,
            "\nAt or below the framework's count: %d of %d shaders with bilinear lookups, %d of "
            "%d with nearest.\n",
            at_or_below, RAS_SHADER_COUNT - RAS_SHADER_NORMAL, at_or_below_nearest, RAS_SHADER_COUNT - RAS_SHADER_NORMAL);
}

/* llvmpipe's times beside the project's renderers, who is faster. */
static void report_llvmpipe_times(FILE *f, const char *renderer) {
    const ras_aa_mode aas[2] = {RAS_AA_NONE, RAS_AA_MSAA};
    fprintf(f,
            "\n### Against llvmpipe\n\n%s, through OSMesa (`tests/bench/bench_llvmpipe.c`), "
            "`LP_NUM_THREADS` 1 and 2, timed in the same rounds as the rows above. Median ms "
            "of a frame; a ratio below 1 means the project's renderer is faster than "
            "llvmpipe on the same number of threads (the teaching pipeline has one).\n\n",
            renderer);
    fprintf(f, "| shader | AA | teaching pipeline | fast, 1 thread | fast, 2 threads | llvmpipe, "
               "1 thread | llvmpipe, 2 threads | teaching ÷ llvmpipe (1) | fast ÷ llvmpipe (1) | "
               "fast ÷ llvmpipe (2) | faster (1 / 2 threads) | CPU ms, fast / llvmpipe (1) | "
               "CPU ratio (1) |\n"
               "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|\n");
    int fast_wins = 0, fast_total = 0, plain_wins = 0, plain_total = 0, cpu_wins = 0, cpu_total = 0;
    char fast_losses[1024] = "", plain_list[1024] = "";
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        for (int a = 0; a < 2; a++) {
            const perf_row *p = find_row((ras_scene_shader)s, aas[a], "plain", 1),
                           *f1 = find_row((ras_scene_shader)s, aas[a], "fast", 1),
                           *f2 = find_row((ras_scene_shader)s, aas[a], "fast", 2),
                           *l1 = find_row((ras_scene_shader)s, aas[a], "llvmpipe", 1),
                           *l2 = find_row((ras_scene_shader)s, aas[a], "llvmpipe", 2);
            if (!l1 && !l2) continue;
            fprintf(f, "| %s | %s |", ras_scene_shader_name((ras_scene_shader)s), report_aa_label(aas[a]));
            print_ms(f, p), print_ms(f, f1), print_ms(f, f2), print_ms(f, l1), print_ms(f, l2);
            print_ratio(f, p, l1), print_ratio(f, f1, l1), print_ratio(f, f2, l2);
            const char *w[2] = {"—", "—"};
            for (int th = 0; th < 2; th++) {
                const perf_row *fr = th ? f2 : f1, *lr = th ? l2 : l1;
                if (!fr || !lr) continue;
                bool win = fr->median < lr->median;
                w[th] = win ? "fast" : "**llvmpipe**";
                fast_wins += win;
                fast_total++;
                if (!win) {
                    size_t len = strlen(fast_losses);
                    snprintf(fast_losses + len, sizeof fast_losses - len, "%s%s %s on %d thread%s",
                             len ? ", " : "", ras_scene_shader_name((ras_scene_shader)s),
                             report_aa_label(aas[a]), th + 1, th ? "s" : "");
                }
            }
            if (p && l1) {
                plain_total++;
                if (p->median < l1->median) {
                    plain_wins++;
                    size_t len = strlen(plain_list);
                    snprintf(plain_list + len, sizeof plain_list - len, "%s%s %s", len ? ", " : "",
                             ras_scene_shader_name((ras_scene_shader)s), report_aa_label(aas[a]));
                }
            }
            fprintf(f, " %s / %s |", w[0], w[1]);
            if (f1 && l1 && l1->cpu_median > 0) {
                fprintf(f, " %.2f / %.2f | %.2f |\n", f1->cpu_median, l1->cpu_median,
                        f1->cpu_median / l1->cpu_median);
                cpu_total++;
                cpu_wins += f1->cpu_median < l1->cpu_median;
            } else {
                fprintf(f, " — | — |\n");
            }
        }
    fprintf(f,
            "\n**In this run the fast path is faster than llvmpipe in %d of %d comparisons** "
            "(shader × AA × thread count)%s%s. **The teaching pipeline (1 thread) is faster "
            "than llvmpipe on 1 thread in %d of %d**%s%s.\n",
            fast_wins, fast_total, fast_wins < fast_total ? "; llvmpipe is faster on " : "",
            fast_losses, plain_wins, plain_total, plain_wins ? ": " : "", plain_list);
    fprintf(f,
            "By processor time on one thread (the CPU columns: what the frame cost, without "
            "the time other processes took the CPU), the fast path costs less than llvmpipe "
            "in %d of %d shader × AA pairs.\n",
            cpu_wins, cpu_total);
}

/* One frame's instructions beside llvmpipe's (--instructions). */
static void report_llvmpipe_instructions(FILE *f) {
    const ras_aa_mode aas[2] = {RAS_AA_NONE, RAS_AA_MSAA};
    bool counted = false;
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        counted = counted || perf_instr[s][0][2];
    if (counted) {
        fprintf(f,
                "\n#### Instructions per frame\n\nOne frame on one thread, counted with "
                "callgrind (`--instructions`: the same whatever else the machine does — exact "
                "and repeatable for the project's renderers, within 0.4 %% between runs for "
                "llvmpipe, whose count includes its threads' waiting; llvmpipe with "
                "`LP_NUM_THREADS=1`, its binning and its rasterizer thread together), million:\n\n"
                "| shader | AA | teaching pipeline | fast path | llvmpipe | teaching ÷ llvmpipe | "
                "fast ÷ llvmpipe |\n|---|---|---:|---:|---:|---:|---:|\n");
        int fewer = 0;
        for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
            for (int a = 0; a < 2; a++) {
                const uint64_t *c = perf_instr[s][a];
                if (!c[2]) continue;
                fprintf(f, "| %s | %s | %.1f | %.1f | %.1f | %.2f | %.2f |\n",
                        ras_scene_shader_name((ras_scene_shader)s), report_aa_label(aas[a]), c[0] / 1e6,
                        c[1] / 1e6, c[2] / 1e6, (double)c[0] / (double)c[2],
                        (double)c[1] / (double)c[2]);
                fewer += c[1] < c[2];
            }
        fprintf(f,
                "\nThe fast path executes fewer instructions than llvmpipe in %d of 10 shader × "
                "AA pairs. Instructions are not time: llvmpipe's JIT code is 256-bit AVX2 (8 "
                "lanes per instruction), the project's SSE2 (4 lanes) or scalar.\n",
                fewer);
    }
}

/* llvmpipe's pixels against the plain pipeline's. */
static void report_llvmpipe_pixels(FILE *f) {
    fprintf(
        f,
        "\n#### Same pixels?\n\nllvmpipe's frame against the plain pipeline's "
        "(`llvmpipe_compare`, tolerances in `tests/bench/bench_llvmpipe.h`): covered pixels, and "
        "on the pixels both cover the mean absolute difference per channel and the share "
        "of pixels with a channel more than %d levels (of 255) apart. Tolerances: coverage "
        "± %.1f %%; 1x mean ≤ %.1f, share ≤ %.0f %%; MSAA 4x mean ≤ %.1f, share ≤ %.0f %%.\n\n",
        LLVMPIPE_BAD_LEVELS, 100 * LLVMPIPE_MAX_COVERAGE_DIFF, LLVMPIPE_MAX_MEAN_DIFF_1X,
        100 * LLVMPIPE_MAX_BAD_FRACTION_1X, LLVMPIPE_MAX_MEAN_DIFF_MSAA,
        100 * LLVMPIPE_MAX_BAD_FRACTION_MSAA);
    fprintf(f,
            "| shader | AA | llvmpipe threads | covered (project) | covered (llvmpipe) | "
            "coverage Δ | mean Δ, levels | pixels > %d levels | max Δ | result |\n"
            "|---|---|---|---:|---:|---:|---:|---:|---:|---|\n",
            LLVMPIPE_BAD_LEVELS);
    for (int i = 0; i < perf_row_count; i++) {
        const perf_row *r = &perf_rows[i];
        if (!perf_is_llvmpipe(r) || !r->checked) continue;
        const llvmpipe_check *c = &r->check;
        /* llvmpipe draws the same image on 1 and 2 threads: one line then */
        const perf_row *two = r->threads == 1 ? find_row(r->shader, r->aa, "llvmpipe", 2) : NULL;
        bool same = two && two->checked && same_check(&two->check, c);
        if (r->threads == 2) {
            const perf_row *one = find_row(r->shader, r->aa, "llvmpipe", 1);
            if (one && one->checked && same_check(&one->check, c)) continue;
        }
        fprintf(f, "| %s | %s | %s | %ld | %ld | %.2f %% | %.3f | %.2f %% | %d | %s |\n",
                ras_scene_shader_name(r->shader), report_aa_label(r->aa),
                same              ? "1, 2"
                : r->threads == 1 ? "1"
                                  : "2",
                c->covered_ours, c->covered_llvmpipe, 100 * c->coverage_diff, c->mean_diff,
                100 * c->bad_fraction, c->max_diff,
                c->pass ? "within tolerance" : "**OUTSIDE tolerance**");
    }
}

/* The side-by-side tables of docs/performance.md: times, ratios, who is faster,
 * and the pixel check. */
static void report_llvmpipe(FILE *f, const char *renderer) {
    report_llvmpipe_times(f, renderer);
    report_llvmpipe_instructions(f);
    report_llvmpipe_pixels(f);
}

bool report_write_csv(const char *path) {
    ras_io_report report;
    FILE *f = ras_io_report_open(&report);
    if (!f) return false;
    fprintf(f,
            "shader,aa,renderer,threads,ms_median,ms_min,ms_max,instructions,ratio_to_llvmpipe\n");
    for (int i = 0; i < perf_row_count; i++) {
        const perf_row *r = &perf_rows[i], *l = llvmpipe_peer(r);
        const char *aa = r->aa == RAS_AA_MSAA ? "msaa4" : r->aa == RAS_AA_SSAA ? "ssaa4" : "none";
        const char *who = perf_is_llvmpipe(r) ? "llvmpipe"
                          : r->mode[0] == 'p' ? "teaching_pipeline"
                                              : "fast_path";
        fprintf(f, "%s,%s,%s,%d,%.3f,%.3f,%.3f,", ras_scene_shader_name(r->shader), aa, who, r->threads,
                r->median, r->min, r->max);
        if (r->instructions) fprintf(f, "%llu", (unsigned long long)r->instructions);
        fprintf(f, ",");
        if (l && l->median > 0) fprintf(f, "%.3f", r->median / l->median);
        fprintf(f, "\n");
    }
    ras_error err = {{0}};
    if (!ras_io_report_commit(&report, path, &err)) {
        fprintf(stderr, "bench_perf: %s\n", err.msg);
        return false;
    }
    fprintf(stderr, "bench_perf: wrote %s\n", path);
    return true;
}

/* The report's prose (how the fast path differs and why) lives in
 * tests/bench/bench_perf.md.in; the measured tables follow it. */
static bool copy_intro(FILE *out) {
    FILE *in = fopen(RAS_SOURCE_DIR "/tests/bench/bench_perf.md.in", "r");
    if (!in) return false;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, in)) > 0)
        fwrite(buf, 1, n, out);
    fclose(in);
    return true;
}

/* The measured part's opening: the machine, the build, the load, every row. */
static void report_rows(FILE *f, const perf_report *rep) {
    char cpu[256], date[64];
    machine_name(cpu, sizeof cpu);
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d", gmtime(&now));
    fprintf(f, "\n## Measured (one run)\n\n");
    fprintf(f,
            "Machine: %s, %ld CPUs online; %s, compiler %s, %s. Model: %s, %zu triangles. "
            "%d timed frames per row (after 2 warm-up frames); a frame is one whole "
            "`hw3_render` call (setup, raster, shading, resolve into the image). Date %s.\n\n",
            cpu, sysconf(_SC_NPROCESSORS_ONLN), RAS_BUILD_TYPE, __VERSION__, "`make bench-perf`",
            rep->model_name, rep->triangles, rep->frames, date);
    double load[3] = {0, 0, 0};
    if (getloadavg(load, 3) == 3)
        fprintf(f,
                "Load average when the report was written: %.2f (1 min), %.2f (5 min) on "
                "%ld CPUs.\n\n",
                load[0], load[1], sysconf(_SC_NPROCESSORS_ONLN));
    fprintf(f, "| shader | AA | mode | threads | median ms | min ms | max ms | CPU ms | "
               "fragments shaded | really shaded | ns/fragment | buffers MiB | same image as "
               "plain |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < perf_row_count; i++)
        report_print_row(f, &perf_rows[i], true);
    fprintf(f, "\n\"fragments shaded\" is the counter `fragments_shaded`, the same for both "
               "paths: the teaching pipeline shades every fragment that passes a depth test. "
               "\"really shaded\" is what the path shaded: the fast path shades only the "
               "fragments still visible when their tile is drawn. ns/fragment is the median "
               "frame time over the fragments shaded (the counter; the whole "
               "frame, not the shader alone). \"CPU ms\" is the median processor time of a "
               "frame summed over all the process's threads (CLOCK_PROCESS_CPUTIME_ID): time "
               "spent preempted by other processes is not in it, so on a busy machine it is the "
               "steadier figure; with 2 threads it is the work of both. \"buffers\" is the colour "
               "and depth memory the "
               "frame held: the plain pipeline's full-screen framebuffer (samples per pixel × "
               "16 bytes × 700²), the fast path's per-thread tile buffers.\n");
}

/* The goals the report checks, from the rows above. */
static void report_goals(FILE *f, const perf_report *rep) {
    const perf_row *g[RAS_SHADER_COUNT][3][3] = {{{0}}}; /* shader, aa, 0 plain / 1-2 threads */
    for (int i = 0; i < perf_row_count; i++) {
        if (perf_is_llvmpipe(&perf_rows[i])) continue; /* their own section, below */
        int a = perf_rows[i].aa == RAS_AA_MSAA ? 1 : perf_rows[i].aa == RAS_AA_SSAA ? 2 : 0;
        int m = perf_rows[i].mode[0] == 'p' ? 0 : perf_rows[i].threads;
        g[perf_rows[i].shader][a][m] = &perf_rows[i];
    }
    const perf_row *ph = g[RAS_SHADER_PHONG][0][2], *tx = g[RAS_SHADER_TEXTURE][0][2];
    fprintf(f, "\n### Goals\n\n| goal | measured | met |\n|---|---|---|\n");
    fprintf(f,
            "| Blinn-Phong ≤ 2 ms at 1x, 2 threads | %.2f ms (1 thread %.2f ms, CPU %.2f ms; "
            "plain %.2f ms) | %s |\n",
            ph->median, g[RAS_SHADER_PHONG][0][1]->median, g[RAS_SHADER_PHONG][0][1]->cpu_median,
            g[RAS_SHADER_PHONG][0][0]->median, ph->median <= 2.0 ? "yes" : "no");
    fprintf(f,
            "| texture ≤ 2.5 ms at 1x, 2 threads | %.2f ms (1 thread %.2f ms, CPU %.2f ms; "
            "plain %.2f ms) | %s |\n",
            tx->median, g[RAS_SHADER_TEXTURE][0][1]->median,
            g[RAS_SHADER_TEXTURE][0][1]->cpu_median, g[RAS_SHADER_TEXTURE][0][0]->median,
            tx->median <= 2.5 ? "yes" : "no");
    /* The AA ratios are judged on the 1-thread rows' CPU time: on a busy
     * machine the wall-clock ratios of noisy medians say little. */
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++) {
        double m = g[s][1][1]->cpu_median / g[s][0][1]->cpu_median;
        double q = g[s][2][1]->cpu_median / g[s][0][1]->cpu_median;
        double mw = g[s][1][2]->median / g[s][0][2]->median;
        double qw = g[s][2][2]->median / g[s][0][2]->median;
        fprintf(f,
                "| %s: MSAA 4x ≤ 1.5× 1x; SSAA 4x ≈ 4× (1-thread CPU time) | MSAA %.2f×, "
                "SSAA %.2f× (2-thread wall clock: %.2f×, %.2f×) | %s |\n",
                ras_scene_shader_name((ras_scene_shader)s), m, q, mw, qw, m <= 1.5 ? "yes" : "no");
    }
    if (rep->have_proc) {
        double frame = g[RAS_SHADER_PHONG][0][2]->median;
        fprintf(f,
                "| whole process `hw3_shading_ref --model … --shader phong -o out.png` ≤ "
                "loading (`--version`) + one frame | %.1f ms vs %.1f + %.1f = %.1f ms "
                "(plain pipeline: %.1f ms) | %s |\n",
                rep->p_render.median, rep->p_version.median, frame, rep->p_version.median + frame,
                rep->p_plain.median,
                rep->p_render.median <= rep->p_version.median + frame ? "yes" : "no");
        fprintf(f,
                "\nWhole processes (wall clock, median of 15 runs, max RSS): `--version` "
                "%.1f ms / %ld KiB; `-o out.png` fast %.1f ms / %ld KiB; plain "
                "(without `--renderer fast`) %.1f ms / %ld KiB. The render also loads the model "
                "(assimp) "
                "and the texture (PNG decode) and encodes the PNG, which `--version` does not: "
                "that I/O, not the frame, makes most of the difference.\n",
                rep->p_version.median, rep->p_version.max_rss_kb, rep->p_render.median,
                rep->p_render.max_rss_kb, rep->p_plain.median, rep->p_plain.max_rss_kb);
    }
}

bool report_write_markdown(const char *path, const perf_report *rep) {
    ras_io_report report; /* written whole or not at all (ras_io.h) */
    FILE *f = ras_io_report_open(&report);
    if (!f) {
        fprintf(stderr, "bench_perf: cannot write %s: out of memory\n", path);
        return false;
    }
    if (!copy_intro(f)) fprintf(f, "# Performance\n");
    report_rows(f, rep);
    report_goals(f, rep);
    if (rep->any_llvm) report_llvmpipe(f, rep->llvm_renderer);
    report_framework(f);
    fprintf(f,
            "\nEvery fast image was compared with the plain image of the same row "
            "byte for byte: %s. The benchmark process peaked at %ld KiB RSS.\n",
            rep->all_identical ? "all identical" : "**SOME DIFFER**", rep->peak_rss_kb);
    ras_error werr = {{0}};
    if (!ras_io_report_commit(&report, path, &werr)) {
        fprintf(stderr, "bench_perf: %s\n", werr.msg);
        return false;
    }
    fprintf(stderr, "bench_perf: wrote %s\n", path);
    return true;
}
