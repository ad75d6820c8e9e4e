/* bench_accuracy.c — what accuracy costs in time: a measured report.
 *
 * Renders test scenes with the reference solutions (hw1/hw2/hw3) under every
 * accuracy option the toolkit offers, measures the time per frame (median of
 * in-process repeats, with min and max) and the error against a ground truth
 * computed independently of the pipeline, and writes
 *   <out>/accuracy.md, <out>/accuracy.csv, <out>/img/accuracy_*.png
 * Sections and their ground truths:
 *   aa      anti-aliasing (none, MSAA/SSAA × ordered 2x2/4x4/8x8, standard
 *           2x/4x/8x/16x) on thin triangles at random angles and on the hw2
 *           scene; truth: exact pixel coverage by clipping each triangle to each
 *           pixel square (the hw2 scene: the far triangle minus the near one)
 *   edges   the reference's exact fixed-point coverage vs float edge functions
 *           (bench_float_edges.c: this benchmark's own rasterizer, not a mode of
 *           the reference): per-sample coverage counts on a sliver fan and a
 *           jittered grid (0 inside = crack, ≥ 2 = double hit)
 *   interp  affine vs perspective-correct UV on a receding plane, against the
 *           analytic ray–plane mapping, at depth ratios w1/w0 = 1.1, 2, 4, 8
 *   filter  nearest / bilinear / trilinear on a receding floor, against 16×16
 *           supersampled bilinear of level 0 (box-filtered per pixel)
 *   depth   two planes δ apart near the far plane: fraction of pixels where the
 *           farther wins, in the pipeline with each depth format (z01 and
 *           inverse_w, timed) and, as what-ifs computed from the exact
 *           depths, for fixed-point encodings the pipeline has no mode for
 *
 *   bench_accuracy [--quick] [--check] [--repeats N] [--out DIR]
 *     --quick   small images, few repeats (seconds)
 *     --check   assert the orderings that must hold (never times); exit 1 on a
 *               failure. Without --out, writes into a temporary directory that
 *               is removed afterwards
 *     --out DIR where the report goes (default: docs)
 * Progress goes to stderr, the tables to stdout at the end.
 *
 * This file is the command line: it parses the options, runs the sections in
 * order (bench_accuracy.h lists the modules), then writes the charts, the CSV
 * and the Markdown and prints the tables.
 */
#include "bench_accuracy.h"

#include <errno.h>    /* errno */
#include <stdio.h>    /* printf, fprintf, FILE */
#include <stdlib.h>   /* strtol, getenv, mkdtemp */
#include <string.h>   /* strcmp, strerror */
#include <sys/stat.h> /* mkdir */
#include <time.h>     /* time, strftime */
#include <unistd.h>   /* rmdir, unlink */

static void usage(FILE *f) {
    fputs("usage: bench_accuracy [--quick] [--check] [--repeats N] [--out DIR]\n"
          "  measures time and error of every accuracy option and writes DIR/accuracy.md,\n"
          "  DIR/accuracy.csv and DIR/img/accuracy_*.png (DIR defaults to docs; with --check\n"
          "  and no --out, a temporary directory that is removed afterwards)\n",
          f);
}

static bool make_dir(const char *path) { return mkdir(path, 0755) == 0 || errno == EEXIST; }

/* The files written, under acc_opt.out; the first two charts are per AA scene. */
static const char *const files[] = {
    "img/accuracy_aa_0.png",   "img/accuracy_aa_1.png", "img/accuracy_interp.png",
    "img/accuracy_filter.png", "accuracy.csv",          "accuracy.md"};
#define FILE_COUNT (sizeof files / sizeof files[0])

/* Fills acc_opt; -1 to go on, else the exit status. */
static int parse_args(int argc, char **argv, bool *out_given) {
    *out_given = false;
    acc_opt.repeats = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick"))
            acc_opt.quick = true;
        else if (!strcmp(argv[i], "--check"))
            acc_opt.check = true;
        else if (!strcmp(argv[i], "--repeats") && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 1 || v > 64) {
                fprintf(stderr, "bench_accuracy: --repeats expects 1..64, got '%s'\n", argv[i]);
                return 2;
            }
            acc_opt.repeats = (int)v;
        } else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            snprintf(acc_opt.out, sizeof acc_opt.out, "%s", argv[++i]);
            *out_given = true;
        } else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return 0;
        } else {
            fprintf(stderr, "bench_accuracy: unknown argument '%s'\n", argv[i]);
            usage(stderr);
            return 2;
        }
    }
    if (!acc_opt.repeats) acc_opt.repeats = acc_opt.quick ? 3 : 9;
    return -1;
}

/* acc_opt.out and its img/: the given folder, a temporary one for --check
 * without --out (*temp_out), else docs. False after saying why. */
static bool make_out_dir(bool out_given, bool *temp_out, char *img_dir, size_t img_size) {
    *temp_out = false;
    if (!out_given) {
        if (acc_opt.check) {
            const char *tmp = getenv("TMPDIR");
            snprintf(acc_opt.out, sizeof acc_opt.out, "%s/raster101-accuracy-XXXXXX",
                     tmp && *tmp ? tmp : "/tmp");
            if (!mkdtemp(acc_opt.out)) {
                fprintf(stderr, "bench_accuracy: cannot create a temporary directory %s\n",
                        acc_opt.out);
                return false;
            }
            *temp_out = true;
        } else {
            snprintf(acc_opt.out, sizeof acc_opt.out, "docs");
        }
    }
    snprintf(img_dir, img_size, "%s/img", acc_opt.out);
    if (!make_dir(acc_opt.out) || !make_dir(img_dir)) {
        fprintf(stderr, "bench_accuracy: cannot create %s: %s\n", img_dir, strerror(errno));
        return false;
    }
    return true;
}

/* Every section in order (they share one stream of random numbers), then
 * the relative times and the checks. */
static void run_sections(void) {
    coverage_aa_thin_triangles();
    coverage_aa_hw2_scene();
    coverage_edge_precision();
    texturing_interpolation();
    texturing_filtering();
    depth_precision();
    order_run();
    acc_fill_relative_times();
    coverage_check_aa();
    coverage_check_edges();
    depth_check();
    order_check();
}

/* The charts, the CSV and the Markdown; false with err set. */
static bool write_files(const char *machine_name, const char *date, double total_s,
                        ras_error *err) {
    char path[1200];
    bool ok = true;
    char aa_scenes[4][40];
    int n_aa;
    report_scenes_of("aa", aa_scenes, &n_aa, 4);
    for (int s = 0; s < n_aa && s < 2 && ok; s++) {
        snprintf(path, sizeof path, "%s/%s", acc_opt.out, files[s]);
        ok = charts_aa(aa_scenes[s], path, err);
    }
    snprintf(path, sizeof path, "%s/%s", acc_opt.out, files[2]);
    ok = ok && charts_interp(path, err);
    snprintf(path, sizeof path, "%s/%s", acc_opt.out, files[3]);
    ok = ok && charts_filter(path, err);
    snprintf(path, sizeof path, "%s/%s", acc_opt.out, files[4]);
    if (ok && !report_write_csv(path)) ok = ras_error_set(err, "cannot write %s", path);
    snprintf(path, sizeof path, "%s/%s", acc_opt.out, files[5]);
    if (ok && !report_write_markdown(path, machine_name, date, total_s))
        ok = ras_error_set(err, "cannot write %s", path);
    return ok;
}

static void remove_out_dir(const char *img_dir) {
    char path[1200];
    for (size_t i = 0; i < FILE_COUNT; i++) {
        snprintf(path, sizeof path, "%s/%s", acc_opt.out, files[i]);
        unlink(path);
    }
    rmdir(img_dir);
    rmdir(acc_opt.out);
}

int main(int argc, char **argv) {
    bool out_given, temp_out;
    int status = parse_args(argc, argv, &out_given);
    if (status >= 0) return status;
    char img_dir[1100];
    if (!make_out_dir(out_given, &temp_out, img_dir, sizeof img_dir)) return 2;
    double t0 = ras_now_ms();
    acc_progress("%s run, %d repeats per option, output in %s", acc_opt.quick ? "quick" : "full",
                 acc_opt.repeats, acc_opt.out);
    run_sections();
    double total_s = (ras_now_ms() - t0) / 1000;

    char machine_name[400], date[64];
    report_machine(machine_name, sizeof machine_name);
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M %Z", localtime(&now));
    ras_error err = {{0}};
    if (!write_files(machine_name, date, total_s, &err)) {
        fprintf(stderr, "bench_accuracy: %s\n", err.msg);
        return 2;
    }
    report_print_tables();
    printf("\nmachine: %s; %s; %.1f s\n", machine_name, date, total_s);
    acc_progress("wrote %s/accuracy.md, accuracy.csv and img/accuracy_*.png", acc_opt.out);
    if (temp_out) remove_out_dir(img_dir);
    if (acc_opt.check) {
        fprintf(stderr, "bench_accuracy: %s (%d failed checks)\n",
                acc_failures() ? "FAIL" : "all checks pass", acc_failures());
        return acc_failures() ? 1 : 0;
    }
    return 0;
}
