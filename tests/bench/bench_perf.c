/* bench_perf.c — how fast the reference pipeline draws the classic hw3 scene.
 *
 * The scene of GAMES101 assignment 3 (700×700, eye (0,0,10), model
 * R_y(140°)·S(2.5), fov 45, near 0.1, far 50, the classic lights and
 * material) on the spot cow when its folder is given, otherwise on a built-in
 * Bézier teapot of similar size and screen coverage (6 400 triangles, a
 * procedural checker colour map and bumps height map). For every shader
 * (normal, phong, texture, bump, displacement) × AA (none, MSAA 4x, SSAA 4x)
 * it times whole frames (hw3_render: setup, raster, shading, resolve) in the
 * plain teaching pipeline and in the fast path (fast/, fast_render) with 1
 * and 2 threads, and
 * prints median/min/max ms, fragments shaded and ns per fragment. It checks
 * that every fast image equals the plain one bit for bit. Then it times the
 * whole program (hw3_shading_ref -o out.png) against the program that only
 * loads (hw3_shading_ref --version) and records peak memory.
 *
 * Beside them, when bin/bench_llvmpipe was built (OSMesa found), the same
 * scene through Mesa llvmpipe with LP_NUM_THREADS 1 and 2 (a side process
 * each, tests/bench/bench_llvmpipe.h), at 1x and MSAA 4x. All the renderers of a
 * shader and AA are timed in alternating rounds, one frame of each per round
 * (the order turning every round), so a busy spell of the machine falls on
 * all of them alike. llvmpipe's image is checked against the plain one
 * (covered pixels and colour, llvmpipe_compare). MSAA 4x uses the D3D
 * standard positions, llvmpipe's; SSAA 4x the ordered 2x2 grid.
 *
 *   bench_perf [--spot DIR] [--frames N] [--out FILE] [--quick]
 *     --spot DIR   DIR/spot_triangulated_good.obj + DIR/spot_texture.png
 *     --frames N   timed frames per row (default 21, at least 20 for the report)
 *     --out FILE   write the report (docs/performance.md) there
 *     --quick      3 frames, no process timing (a smoke run)
 *     --csv FILE   also write the rows as CSV (docs/performance.csv)
 *     --instructions  also count one frame's instructions with callgrind
 *                  (valgrind) for the teaching pipeline, the fast path and
 *                  llvmpipe on one thread, 1x and MSAA 4x (several minutes)
 *     --count-frames teaching|fast  the counting side of --instructions
 *     --no-llvmpipe  leave llvmpipe out
 *     --filter nearest|bilinear|trilinear  texture lookups of every frame
 *                  (default: the scene's, bilinear); like the three below
 *     --shader NAME, --aa none|msaa|ssaa, --threads 1|2
 *                  only those rows, no process timing and no report (for
 *                  profiling one configuration under perf or callgrind;
 *                  the plain row is then one frame, the reference image)
 */
#include "bench_llvmpipe.h" /* llvmpipe beside the project's renderers */
#include "ras_io.h" /* ras_io_report: the report is written atomically */

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h> /* CALLGRIND_ZERO_STATS, CALLGRIND_DUMP_STATS_AT */
#else /* no valgrind headers (scripts/install-deps installs them): the requests do nothing,
       * and ctest teaching_instructions says it found no counted frame */
#define CALLGRIND_ZERO_STATS
#define CALLGRIND_DUMP_STATS_AT(name) ((void)(name))
#endif
#include "fast_render.h" /* fast_render: the fast path, chosen explicitly */
#include "ras_mesh.h"
#include "ras_builtin_scenes.h" /* ras_builtin_scene_with_model: the classic scene */
#include "scene.h"

#include <math.h>         /* fabs */
#include <stdio.h>        /* printf, fprintf, FILE */
#include <stdlib.h>       /* malloc, free, qsort, strtol */
#include <string.h>       /* memcmp, strcmp */
#include <sys/resource.h> /* getrusage, struct rusage */
#include <sys/wait.h>     /* wait4 */
#include <time.h>         /* time, strftime */
#include <unistd.h>       /* fork, execv, _exit */

#ifndef RAS_BINARY_DIR
#define RAS_BINARY_DIR "."
#endif
#ifndef RAS_SOURCE_DIR
#define RAS_SOURCE_DIR "."
#endif
#ifndef RAS_BUILD_TYPE
#define RAS_BUILD_TYPE "unknown build type"
#endif

typedef struct row {
    const char *mode; /* "plain", "fast" or "llvmpipe" */
    int threads;
    ras_scene_shader shader;
    ras_aa_mode aa;
    double median, min, max;
    double cpu_median; /* process CPU time per frame, all threads: robust to a busy machine */
    uint64_t fragments; /* the counters' fragments_shaded: the teaching pipeline's */
    uint64_t shaded;    /* the fragments this path really shaded */
    size_t buffer_bytes;
    bool identical; /* fast rows: the image equals the plain one; llvmpipe: the check passed */
    bool checked;   /* llvmpipe rows: `check` holds the pixel check against plain */
    uint64_t instructions; /* one frame, callgrind (--instructions); 0: not counted */
    llvmpipe_check check;
} row;

static bool is_llvmpipe(const row *r) {
    return r->mode[0] == 'l';
}

#define MAX_ROWS 128
static row rows[MAX_ROWS];
static int row_count;

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* CPU time of the whole process (every thread), ms. */
static double cpu_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* --filter: the texture lookups of every frame (default: the scene's). */
static bool bench_filter_set;
static texture_filter bench_filter;

static bool render(const ras_scene *scene, ras_scene_assets *assets, ras_scene_shader shader, ras_aa_mode aa, bool plain, int threads,
                   ras_image *out, ras_counters *k, uint64_t *shaded, double *ms, double *cpu) {
    hw3_render_options opt = hw3_render_defaults();
    *shaded = UINT64_MAX; /* the plain pipeline leaves it: it shades what it counts */
    fast_settings settings = {.threads = threads, .shaded = shaded};
    opt.shader = shader;
    if (bench_filter_set) opt.filter = bench_filter;
    opt.aa = aa;
    if (aa != RAS_AA_NONE) {
        ras_error e = {{0}};
        /* MSAA: llvmpipe's positions, so the images can be compared */
        ras_pattern_kind kind = aa == RAS_AA_MSAA ? RAS_PATTERN_STANDARD : RAS_PATTERN_ORDERED;
        if (!ras_sample_pattern_make(kind, 4, &opt.pattern, &e)) return false;
    }
    ras_error err = {{0}};
    double c0 = cpu_ms(), t0 = ras_now_ms();
    int drawn = plain ? -1 : fast_render(scene, assets, &opt, &settings, out, k, &err);
    bool ok = drawn < 0 ? hw3_render(scene, assets, &opt, out, k, &err) : drawn;
    *ms = ras_now_ms() - t0;
    *cpu = cpu_ms() - c0;
    if (!ok) fprintf(stderr, "bench_perf: %s\n", err.msg);
    if (ok && *shaded == UINT64_MAX) *shaded = k->fragments_shaded;
    return ok;
}

/* One renderer of a round: the plain pipeline, the fast path or llvmpipe. */
typedef struct contender {
    bool plain;
    int threads;
    llvmpipe_child *llvm; /* not NULL: llvmpipe, in that side process */
    int frames;           /* timed frames (the plain row of a filtered run: 1) */
    row *r;
    double *t, *c; /* wall-clock and CPU ms per timed frame */
    ras_counters k;
    uint64_t shaded;
    bool identical;
} contender;

/* Times the contenders of one shader and AA in alternating rounds: two
 * warm-up rounds in the given order (plain first: it draws `expected`, the
 * reference image), then `frames` rounds of one frame each, the order turned
 * by one every round. Every fast frame is compared with `expected` (outside
 * the timing). Fills each contender's row. */
static bool measure_rounds(const ras_scene *scene, ras_scene_assets *assets, ras_scene_shader shader,
                           ras_aa_mode aa, contender *cs, int n, int frames, ras_image *expected,
                           ras_image *img) {
    bool ok = true;
    for (int i = 0; i < n; i++) {
        cs[i].t = malloc(sizeof *cs[i].t * 2 * (size_t)frames);
        cs[i].c = cs[i].t ? cs[i].t + frames : NULL;
        cs[i].identical = true;
        ok = ok && cs[i].t;
    }
    size_t bytes = sizeof *img->pixels * (size_t)img->width * (size_t)img->height;
    for (int round = -2; ok && round < frames; round++)
        for (int j = 0; ok && j < n; j++) {
            contender *x = &cs[round < 0 ? j : (j + round) % n];
            if (round >= x->frames) continue;
            double ms, cpu;
            if (x->llvm) {
                ok = llvmpipe_frame(x->llvm, shader, aa == RAS_AA_MSAA, &ms, &cpu);
                if (!ok) fprintf(stderr, "bench_perf: llvmpipe (%d threads) did not answer\n",
                                 x->threads);
            } else {
                ok = render(scene, assets, shader, aa, x->plain, x->threads, x->plain ? expected : img,
                            &x->k, &x->shaded, &ms, &cpu);
                if (ok && !x->plain)
                    x->identical = x->identical && !memcmp(expected->pixels, img->pixels, bytes);
            }
            if (ok && round >= 0) {
                x->t[round] = ms;
                x->c[round] = cpu;
            }
        }
    for (int i = 0; ok && i < n; i++) {
        contender *x = &cs[i];
        int f = x->frames;
        qsort(x->t, (size_t)f, sizeof *x->t, cmp_double);
        qsort(x->c, (size_t)f, sizeof *x->c, cmp_double);
        *x->r = (row){.mode = x->llvm ? "llvmpipe" : x->plain ? "plain" : "fast",
                      .threads = x->threads,
                      .shader = shader,
                      .aa = aa,
                      .median = x->t[f / 2],
                      .min = x->t[0],
                      .max = x->t[f - 1],
                      .cpu_median = x->c[f / 2],
                      .fragments = x->llvm ? 0 : x->k.fragments_shaded,
                      .shaded = x->llvm ? 0 : x->shaded,
                      .buffer_bytes = x->llvm ? 0 : x->k.buffer_bytes,
                      .identical = x->identical};
    }
    for (int i = 0; i < n; i++) free(cs[i].t);
    return ok;
}

static const char *aa_label(ras_aa_mode aa) {
    return aa == RAS_AA_MSAA ? "MSAA 4x" : aa == RAS_AA_SSAA ? "SSAA 4x" : "1x";
}

static void print_row(FILE *f, const row *r, bool md) {
    double ns = r->fragments ? r->median * 1e6 / (double)r->fragments : 0;
    if (is_llvmpipe(r)) { /* no counters: its own work is not the teaching pipeline's */
        const char *check = !r->checked ? "" : r->check.pass ? "within tolerance" : "**OUTSIDE tolerance**";
        if (md)
            fprintf(f, "| %s | %s | llvmpipe | %d | %.2f | %.2f | %.2f | %.2f | — | — | — | — | %s |\n",
                    ras_scene_shader_name(r->shader), aa_label(r->aa), r->threads, r->median, r->min,
                    r->max, r->cpu_median, check);
        else
            fprintf(f, "%-12s %-8s %-8s %2d %9.2f %9.2f %9.2f %9.2f  %s\n",
                    ras_scene_shader_name(r->shader), aa_label(r->aa), "llvmpipe", r->threads, r->median,
                    r->min, r->max, r->cpu_median, r->checked ? (r->check.pass ? "pixels within tolerance" : "pixels OUTSIDE tolerance") : "");
        return;
    }
    if (md)
        fprintf(f,
                "| %s | %s | %s | %d | %.2f | %.2f | %.2f | %.2f | %llu | %llu | %.1f | %.1f | %s |\n",
                ras_scene_shader_name(r->shader), aa_label(r->aa), r->mode, r->threads, r->median, r->min,
                r->max, r->cpu_median, (unsigned long long)r->fragments,
                (unsigned long long)r->shaded, ns,
                (double)r->buffer_bytes / 1048576.0, r->identical ? "yes" : "**NO**");
    else
        fprintf(f, "%-12s %-8s %-8s %2d %9.2f %9.2f %9.2f %9.2f %9llu %9llu %8.1f %8.1f %s\n",
                ras_scene_shader_name(r->shader), aa_label(r->aa), r->mode, r->threads, r->median, r->min,
                r->max, r->cpu_median, (unsigned long long)r->fragments,
                (unsigned long long)r->shaded, ns,
                (double)r->buffer_bytes / 1048576.0, r->identical ? "same" : "DIFFERENT");
}

/* ---- whole processes ----------------------------------------------------- */

typedef struct proc_time {
    double median, min, max; /* ms, wall clock */
    long max_rss_kb;
} proc_time;

static bool time_process(char *const argv[], int runs, proc_time *out) {
    double t[64];
    long rss = 0;
    for (int i = 0; i < runs; i++) {
        double t0 = ras_now_ms();
        pid_t pid = fork();
        if (pid < 0) return false;
        if (pid == 0) {
            if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(126);
            execv(argv[0], argv);
            _exit(127);
        }
        int status;
        struct rusage ru;
        if (wait4(pid, &status, 0, &ru) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
            return false;
        t[i] = ras_now_ms() - t0;
        if (ru.ru_maxrss > rss) rss = ru.ru_maxrss;
    }
    qsort(t, (size_t)runs, sizeof *t, cmp_double);
    *out = (proc_time){t[runs / 2], t[0], t[runs - 1], rss};
    return true;
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

/* ---- instructions (callgrind) --------------------------------------------- */

/* --count-frames: one frame of every shader at 1x and MSAA 4x (only 1x with
 * --aa none: tests/bench/teaching_instructions_test.sh), each after a
 * warm-up frame, between a zeroing of callgrind's counters and a dump named
 * SHADER_none / SHADER_msaa. */
static int count_frames(const ras_scene *scene, ras_scene_assets *assets, bool plain,
                        bool only_1x, ras_image *img) {
    const ras_aa_mode aas[2] = {RAS_AA_NONE, RAS_AA_MSAA};
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        for (int a = 0; a < (only_1x ? 1 : 2); a++) {
            ras_counters k;
            uint64_t shaded;
            double ms, cpu;
            char name[64];
            snprintf(name, sizeof name, "%s_%s", ras_scene_shader_name((ras_scene_shader)s), a ? "msaa" : "none");
            if (!render(scene, assets, (ras_scene_shader)s, aas[a], plain, 1, img, &k, &shaded, &ms, &cpu))
                return 1;
            CALLGRIND_ZERO_STATS;
            bool ok =
                render(scene, assets, (ras_scene_shader)s, aas[a], plain, 1, img, &k, &shaded, &ms, &cpu);
            CALLGRIND_DUMP_STATS_AT(name);
            if (!ok) return 1;
        }
    return 0;
}

/* instr[shader][aa][renderer]: 0 teaching pipeline, 1 fast path, 2 llvmpipe,
 * 3 teaching pipeline with nearest lookups (the course framework's). */
static uint64_t instr[RAS_SHADER_COUNT][2][4];

/* Runs argv under callgrind (LP_NUM_THREADS=1) and reads its dumps into
 * instr[..][..][who]. */
static bool callgrind(char *const argv[], int who) {
    char out[256];
    snprintf(out, sizeof out, "/tmp/raster101_callgrind_%d_%d", (int)getpid(), who);
    char opt[300];
    snprintf(opt, sizeof opt, "--callgrind-out-file=%s", out);
    const char *vg[32] = {"valgrind", "--tool=callgrind", opt};
    int n = 3;
    for (int i = 0; argv[i] && n < 31; i++) vg[n++] = argv[i];
    vg[n] = NULL;
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) return false;
    if (pid == 0) {
        setenv("LP_NUM_THREADS", "1", 1);
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(126);
        execvp("valgrind", (char *const *)vg);
        _exit(127);
    }
    int status;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fprintf(stderr, "bench_perf: callgrind of %s failed (is valgrind installed?)\n", argv[0]);
        return false;
    }
    int found = 0;
    for (int part = 1; part <= 2 * (RAS_SHADER_COUNT - RAS_SHADER_NORMAL); part++) {
        char path[300], line[512], name[128] = "";
        snprintf(path, sizeof path, "%s.%d", out, part);
        FILE *f = fopen(path, "r");
        if (!f) continue;
        unsigned long long total = 0;
        while (fgets(line, sizeof line, f)) {
            if (!strncmp(line, "desc: Trigger: Client Request: ", 31))
                sscanf(line + 31, "%127s", name);
            else if (!strncmp(line, "totals: ", 8))
                total = strtoull(line + 8, NULL, 10);
        }
        fclose(f);
        remove(path);
        for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
            for (int a = 0; a < 2; a++) {
                char want[64];
                snprintf(want, sizeof want, "%s_%s", ras_scene_shader_name((ras_scene_shader)s),
                         a ? "msaa" : "none");
                if (!strcmp(name, want) && total) {
                    instr[s][a][who] = total;
                    found++;
                }
            }
    }
    remove(out);
    if (found != 2 * (RAS_SHADER_COUNT - RAS_SHADER_NORMAL))
        fprintf(stderr, "bench_perf: callgrind of %s: %d of %d frames counted\n", argv[0], found,
                2 * (RAS_SHADER_COUNT - RAS_SHADER_NORMAL));
    return found == 2 * (RAS_SHADER_COUNT - RAS_SHADER_NORMAL);
}

/* ---- llvmpipe beside the project's renderers ------------------------------ */

static const row *find_row(ras_scene_shader shader, ras_aa_mode aa, const char *mode, int threads) {
    for (int i = 0; i < row_count; i++)
        if (rows[i].shader == shader && rows[i].aa == aa && !strcmp(rows[i].mode, mode) &&
            rows[i].threads == threads)
            return &rows[i];
    return NULL;
}

/* The llvmpipe row a row is compared with: same shader, AA and thread count. */
static const row *llvmpipe_peer(const row *r) {
    return find_row(r->shader, r->aa, "llvmpipe", r->threads);
}

static void print_ms(FILE *f, const row *r) {
    if (r) fprintf(f, " %.2f |", r->median);
    else fprintf(f, " — |");
}

static void print_ratio(FILE *f, const row *r, const row *l) {
    if (r && l && l->median > 0) fprintf(f, " %.2f |", r->median / l->median);
    else fprintf(f, " — |");
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
    [RAS_SHADER_NORMAL] = 76.6,       [RAS_SHADER_PHONG] = 143.0,
    [RAS_SHADER_TEXTURE] = 168.3,     [RAS_SHADER_BUMP] = 125.1,
    [RAS_SHADER_DISPLACEMENT] = 178.6,
};
static bool bench_on_spot; /* --spot: the framework's figures apply */

/* The teaching pipeline's instructions beside the framework's (1x). */
static void report_framework(FILE *f) {
    bool counted = true;
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++) counted = counted && instr[s][0][0] && instr[s][0][3];
    if (!counted) return;
    fprintf(f, "\n### The teaching pipeline against the course's framework\n\n");
    if (!bench_on_spot) {
        fprintf(f, "The course framework's figures are for the spot cow: run `make bench-perf "
                   "INSTRUCTIONS=1 SPOT=…/spot` to compare. The teaching pipeline on this model, "
                   "1x, million instructions: ");
        for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
            fprintf(f, "%s%s %.1f (nearest lookups %.1f)", s ? ", " : "",
                    ras_scene_shader_name((ras_scene_shader)s), instr[s][0][0] / 1e6, instr[s][0][3] / 1e6);
        fprintf(f, ".\n");
        return;
    }
    fprintf(f, "One frame at 1x on one thread, million instructions (callgrind). The framework: "
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
        double fw = course_framework_minstr[s], b = instr[s][0][0] / 1e6, n = instr[s][0][3] / 1e6;
        fprintf(f, "| %s | %.1f | %.1f | %.2f | %.1f | %.2f |\n", ras_scene_shader_name((ras_scene_shader)s), fw,
                b, b / fw, n, n / fw);
        at_or_below += b <= fw;
        at_or_below_nearest += n <= fw;
    }
    fprintf(f, "\nAt or below the framework's count: %d of %d shaders with bilinear lookups, %d of "
               "%d with nearest.\n",
            at_or_below, RAS_SHADER_COUNT - RAS_SHADER_NORMAL, at_or_below_nearest,
            RAS_SHADER_COUNT - RAS_SHADER_NORMAL);
}

/* The side-by-side tables of docs/performance.md: times, ratios, who is faster,
 * and the pixel check. */
static void report_llvmpipe(FILE *f, const char *renderer) {
    const ras_aa_mode aas[2] = {RAS_AA_NONE, RAS_AA_MSAA};
    fprintf(f, "\n### Against llvmpipe\n\n%s, through OSMesa (`tests/bench/bench_llvmpipe.c`), "
               "`LP_NUM_THREADS` 1 and 2, timed in the same rounds as the rows above. Median ms "
               "of a frame; a ratio below 1 means the project's renderer is faster than "
               "llvmpipe on the same number of threads (the teaching pipeline has one).\n\n",
            renderer);
    fprintf(f, "| shader | AA | teaching pipeline | fast, 1 thread | fast, 2 threads | llvmpipe, "
               "1 thread | llvmpipe, 2 threads | teaching ÷ llvmpipe (1) | fast ÷ llvmpipe (1) | "
               "fast ÷ llvmpipe (2) | faster (1 / 2 threads) | CPU ms, fast / llvmpipe (1) | "
               "CPU ratio (1) |\n"
               "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|\n");
    int fast_wins = 0, fast_total = 0, plain_wins = 0, plain_total = 0, cpu_wins = 0,
        cpu_total = 0;
    char fast_losses[1024] = "", plain_list[1024] = "";
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        for (int a = 0; a < 2; a++) {
            const row *p = find_row((ras_scene_shader)s, aas[a], "plain", 1),
                      *f1 = find_row((ras_scene_shader)s, aas[a], "fast", 1),
                      *f2 = find_row((ras_scene_shader)s, aas[a], "fast", 2),
                      *l1 = find_row((ras_scene_shader)s, aas[a], "llvmpipe", 1),
                      *l2 = find_row((ras_scene_shader)s, aas[a], "llvmpipe", 2);
            if (!l1 && !l2) continue;
            fprintf(f, "| %s | %s |", ras_scene_shader_name((ras_scene_shader)s), aa_label(aas[a]));
            print_ms(f, p), print_ms(f, f1), print_ms(f, f2), print_ms(f, l1), print_ms(f, l2);
            print_ratio(f, p, l1), print_ratio(f, f1, l1), print_ratio(f, f2, l2);
            const char *w[2] = {"—", "—"};
            for (int th = 0; th < 2; th++) {
                const row *fr = th ? f2 : f1, *lr = th ? l2 : l1;
                if (!fr || !lr) continue;
                bool win = fr->median < lr->median;
                w[th] = win ? "fast" : "**llvmpipe**";
                fast_wins += win;
                fast_total++;
                if (!win) {
                    size_t len = strlen(fast_losses);
                    snprintf(fast_losses + len, sizeof fast_losses - len, "%s%s %s on %d thread%s",
                             len ? ", " : "", ras_scene_shader_name((ras_scene_shader)s), aa_label(aas[a]),
                             th + 1, th ? "s" : "");
                }
            }
            if (p && l1) {
                plain_total++;
                if (p->median < l1->median) {
                    plain_wins++;
                    size_t len = strlen(plain_list);
                    snprintf(plain_list + len, sizeof plain_list - len, "%s%s %s",
                             len ? ", " : "", ras_scene_shader_name((ras_scene_shader)s), aa_label(aas[a]));
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
    fprintf(f, "\n**In this run the fast path is faster than llvmpipe in %d of %d comparisons** "
               "(shader × AA × thread count)%s%s. **The teaching pipeline (1 thread) is faster "
               "than llvmpipe on 1 thread in %d of %d**%s%s.\n",
            fast_wins, fast_total, fast_wins < fast_total ? "; llvmpipe is faster on " : "",
            fast_losses, plain_wins, plain_total, plain_wins ? ": " : "", plain_list);
    fprintf(f, "By processor time on one thread (the CPU columns: what the frame cost, without "
               "the time other processes took the CPU), the fast path costs less than llvmpipe "
               "in %d of %d shader × AA pairs.\n",
            cpu_wins, cpu_total);
    bool counted = false;
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++) counted = counted || instr[s][0][2];
    if (counted) {
        fprintf(f, "\n#### Instructions per frame\n\nOne frame on one thread, counted with "
                   "callgrind (`--instructions`: the same whatever else the machine does — exact "
                   "and repeatable for the project's renderers, within 0.4 %% between runs for "
                   "llvmpipe, whose count includes its threads' waiting; llvmpipe with "
                   "`LP_NUM_THREADS=1`, its binning and its rasterizer thread together), million:\n\n"
                   "| shader | AA | teaching pipeline | fast path | llvmpipe | teaching ÷ llvmpipe | "
                   "fast ÷ llvmpipe |\n|---|---|---:|---:|---:|---:|---:|\n");
        int fewer = 0;
        for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
            for (int a = 0; a < 2; a++) {
                const uint64_t *c = instr[s][a];
                if (!c[2]) continue;
                fprintf(f, "| %s | %s | %.1f | %.1f | %.1f | %.2f | %.2f |\n",
                        ras_scene_shader_name((ras_scene_shader)s), aa_label(aas[a]), c[0] / 1e6, c[1] / 1e6,
                        c[2] / 1e6, (double)c[0] / (double)c[2], (double)c[1] / (double)c[2]);
                fewer += c[1] < c[2];
            }
        fprintf(f, "\nThe fast path executes fewer instructions than llvmpipe in %d of 10 shader × "
                   "AA pairs. Instructions are not time: llvmpipe's JIT code is 256-bit AVX2 (8 "
                   "lanes per instruction), the project's SSE2 (4 lanes) or scalar.\n",
                fewer);
    }
    fprintf(f, "\n#### Same pixels?\n\nllvmpipe's frame against the plain pipeline's "
               "(`llvmpipe_compare`, tolerances in `tests/bench/bench_llvmpipe.h`): covered pixels, and "
               "on the pixels both cover the mean absolute difference per channel and the share "
               "of pixels with a channel more than %d levels (of 255) apart. Tolerances: coverage "
               "± %.1f %%; 1x mean ≤ %.1f, share ≤ %.0f %%; MSAA 4x mean ≤ %.1f, share ≤ %.0f %%.\n\n",
            LLVMPIPE_BAD_LEVELS, 100 * LLVMPIPE_MAX_COVERAGE_DIFF, LLVMPIPE_MAX_MEAN_DIFF_1X,
            100 * LLVMPIPE_MAX_BAD_FRACTION_1X, LLVMPIPE_MAX_MEAN_DIFF_MSAA,
            100 * LLVMPIPE_MAX_BAD_FRACTION_MSAA);
    fprintf(f, "| shader | AA | llvmpipe threads | covered (project) | covered (llvmpipe) | "
               "coverage Δ | mean Δ, levels | pixels > %d levels | max Δ | result |\n"
               "|---|---|---|---:|---:|---:|---:|---:|---:|---|\n",
            LLVMPIPE_BAD_LEVELS);
    for (int i = 0; i < row_count; i++) {
        const row *r = &rows[i];
        if (!is_llvmpipe(r) || !r->checked) continue;
        const llvmpipe_check *c = &r->check;
        /* llvmpipe draws the same image on 1 and 2 threads: one line then */
        const row *two = r->threads == 1 ? find_row(r->shader, r->aa, "llvmpipe", 2) : NULL;
        bool same = two && two->checked && same_check(&two->check, c);
        if (r->threads == 2) {
            const row *one = find_row(r->shader, r->aa, "llvmpipe", 1);
            if (one && one->checked && same_check(&one->check, c)) continue;
        }
        fprintf(f, "| %s | %s | %s | %ld | %ld | %.2f %% | %.3f | %.2f %% | %d | %s |\n",
                ras_scene_shader_name(r->shader), aa_label(r->aa), same ? "1, 2" : r->threads == 1 ? "1" : "2",
                c->covered_ours,
                c->covered_llvmpipe, 100 * c->coverage_diff, c->mean_diff, 100 * c->bad_fraction,
                c->max_diff, c->pass ? "within tolerance" : "**OUTSIDE tolerance**");
    }
}

/* docs/performance.csv: one line per row above. */
static bool write_csv(const char *path) {
    ras_io_report report;
    FILE *f = ras_io_report_open(&report);
    if (!f) return false;
    fprintf(f, "shader,aa,renderer,threads,ms_median,ms_min,ms_max,instructions,ratio_to_llvmpipe\n");
    for (int i = 0; i < row_count; i++) {
        const row *r = &rows[i], *l = llvmpipe_peer(r);
        const char *aa = r->aa == RAS_AA_MSAA ? "msaa4" : r->aa == RAS_AA_SSAA ? "ssaa4" : "none";
        const char *who = is_llvmpipe(r)         ? "llvmpipe"
                          : r->mode[0] == 'p'    ? "teaching_pipeline"
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
    while ((n = fread(buf, 1, sizeof buf, in)) > 0) fwrite(buf, 1, n, out);
    fclose(in);
    return true;
}

int main(int argc, char **argv) {
    const char *spot = NULL, *out_path = NULL, *csv_path = NULL;
    int frames = 21;
    bool quick = false, use_llvmpipe = true, count_instructions = false;
    int count_mode = -1; /* --count-frames: 0 teaching, 1 fast */
    int only_shader = -1, only_aa = -1, only_threads = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--spot") && i + 1 < argc) spot = argv[++i];
        else if (!strcmp(argv[i], "--out") && i + 1 < argc) out_path = argv[++i];
        else if (!strcmp(argv[i], "--quick")) quick = true;
        else if (!strcmp(argv[i], "--csv") && i + 1 < argc) csv_path = argv[++i];
        else if (!strcmp(argv[i], "--no-llvmpipe")) use_llvmpipe = false;
        else if (!strcmp(argv[i], "--instructions")) count_instructions = true;
        else if (!strcmp(argv[i], "--count-frames") && i + 1 < argc) {
            i++;
            count_mode = !strcmp(argv[i], "teaching") ? 0 : !strcmp(argv[i], "fast") ? 1 : -2;
            if (count_mode < 0) {
                fprintf(stderr, "bench_perf: --count-frames expects teaching or fast\n");
                return 2;
            }
        }
        else if (!strcmp(argv[i], "--filter") && i + 1 < argc) {
            ras_error e = {{0}};
            if (!hw3_filter_parse(argv[++i], &bench_filter, &e)) {
                fprintf(stderr, "bench_perf: %s\n", e.msg);
                return 2;
            }
            bench_filter_set = true;
        }
        else if (!strcmp(argv[i], "--shader") && i + 1 < argc) {
            i++;
            for (int sh = RAS_SHADER_NORMAL; sh < RAS_SHADER_COUNT; sh++)
                if (!strcmp(argv[i], ras_scene_shader_name((ras_scene_shader)sh))) only_shader = sh;
            if (only_shader < 0) {
                fprintf(stderr, "bench_perf: unknown shader '%s'\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            only_threads = atoi(argv[++i]);
            if (only_threads < 1 || only_threads > 2) {
                fprintf(stderr, "bench_perf: --threads expects 1 or 2\n");
                return 2;
            }
        } else if (!strcmp(argv[i], "--aa") && i + 1 < argc) {
            i++;
            only_aa = !strcmp(argv[i], "none")   ? 0
                      : !strcmp(argv[i], "msaa") ? 1
                      : !strcmp(argv[i], "ssaa") ? 2
                                                 : -1;
            if (only_aa < 0) {
                fprintf(stderr, "bench_perf: --aa expects none, msaa or ssaa\n");
                return 2;
            }
        } else if (!strcmp(argv[i], "--frames") && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 1 || v > 1000) {
                fprintf(stderr, "bench_perf: --frames expects 1..1000, got '%s'\n", argv[i]);
                return 2;
            }
            frames = (int)v;
        } else {
            fprintf(stderr, "usage: bench_perf [--spot DIR] [--frames N] [--out FILE] [--csv FILE] "
                            "[--quick] [--no-llvmpipe] [--instructions] [--shader NAME] "
                            "[--aa none|msaa|ssaa] [--threads 1|2] "
                            "[--filter nearest|bilinear|trilinear]\n");
            return 2;
        }
    }
    if (quick) frames = 3;
    /* A filtered run has no full table: no goals, no report. */
    bool filtered = only_shader >= 0 || only_aa >= 0 || only_threads > 0 || bench_filter_set;
    bench_on_spot = spot && *spot;
    if (filtered) out_path = csv_path = NULL;

    char model[1200], texture[1200], tmp_obj[256] = "";
    ras_error err = {{0}};
    ras_scene *scene; /* hw3_shading --model's (scenes/hw3_model.json) */
    const char *model_name;
    if (spot && *spot) {
        snprintf(model, sizeof model, "%s/spot_triangulated_good.obj", spot);
        snprintf(texture, sizeof texture, "%s/spot_texture.png", spot);
        scene = ras_builtin_scene_with_model("hw3_model", model, texture, NULL, false, &err);
        model_name = "spot cow (spot_triangulated_good.obj, spot_texture.png)";
    } else {
        snprintf(tmp_obj, sizeof tmp_obj, "/tmp/raster101_bench_teapot_%d.obj", (int)getpid());
        if (!bench_write_teapot_obj(tmp_obj)) {
            fprintf(stderr, "bench_perf: cannot write %s\n", tmp_obj);
            return 1;
        }
        snprintf(model, sizeof model, "%s", tmp_obj);
        scene = ras_builtin_scene_with_model("hw3_model", model, NULL, NULL, false, &err);
        model_name = "built-in Bézier teapot (6 400 triangles, checker colour map, bumps height map)";
    }
    ras_scene_assets *assets = scene ? ras_scene_load_assets(scene, &err) : NULL;
    if (!assets) {
        fprintf(stderr, "bench_perf: %s\n", err.msg);
        return 1;
    }
    ras_image *expected = ras_image_create(scene->width, scene->height, &err);
    ras_image *img = ras_image_create(scene->width, scene->height, &err);
    if (!expected || !img) return 1;

    if (count_mode >= 0) { /* the counting side of --instructions, under callgrind */
        int rc = count_frames(scene, assets, count_mode == 0, only_aa == 0, img);
        if (tmp_obj[0]) remove(tmp_obj);
        return rc;
    }
    /* llvmpipe, one side process per thread count (LP_NUM_THREADS is read
     * once per process), on the same model and texture. */
    llvmpipe_child *llvm[2] = {NULL, NULL};
    char llvm_renderer[256] = "";
    if (use_llvmpipe) {
        char prog[1200];
        snprintf(prog, sizeof prog, "%s/bin/bench_llvmpipe", RAS_BINARY_DIR);
        if (access(prog, X_OK) != 0)
            fprintf(stderr, "bench_perf: %s was not built (no OSMesa): llvmpipe left out\n", prog);
        else
            for (int th = 1; th <= 2; th++) {
                if (only_threads && th != only_threads) continue;
                llvm[th - 1] = llvmpipe_start(prog, th, model, spot && *spot ? texture : NULL,
                                              llvm_renderer, sizeof llvm_renderer);
                if (!llvm[th - 1]) return 1;
            }
    }
    uint8_t *rgba = malloc((size_t)scene->width * (size_t)scene->height * 4);
    if (!rgba) return 1;

    const ras_aa_mode aas[3] = {RAS_AA_NONE, RAS_AA_MSAA, RAS_AA_SSAA};
    bool all_identical = true, all_llvm_pass = true, any_llvm = false;
    fprintf(stderr, "bench_perf: %s, %zu triangles, %d frames per row%s%s\n", model_name,
            assets->meshes[0]->triangle_count, frames, llvm_renderer[0] ? "; beside " : "",
            llvm_renderer);
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        for (int a = 0; a < 3; a++) {
            if ((only_shader >= 0 && s != only_shader) || (only_aa >= 0 && a != only_aa)) continue;
            /* Filtered runs time the plain path over one frame only: it is
             * the reference image, and stays out of a profile of the fast path. */
            contender cs[5];
            int n = 0;
            cs[n++] = (contender){.plain = true, .threads = 1, .frames = filtered ? 1 : frames};
            for (int th = 1; th <= 2; th++)
                if (!only_threads || th == only_threads)
                    cs[n++] = (contender){.threads = th, .frames = frames};
            for (int th = 1; th <= 2; th++) /* llvmpipe: no AA and MSAA 4x */
                if (llvm[th - 1] && aas[a] != RAS_AA_SSAA)
                    cs[n++] = (contender){.threads = th, .llvm = llvm[th - 1], .frames = frames};
            if (row_count + n > MAX_ROWS) return 1;
            for (int i = 0; i < n; i++) cs[i].r = &rows[row_count + i];
            if (!measure_rounds(scene, assets, (ras_scene_shader)s, aas[a], cs, n, frames, expected, img))
                return 1;
            for (int i = 0; i < n; i++) {
                row *r = cs[i].r;
                if (cs[i].llvm) { /* the same pixels? against the plain image */
                    bool msaa = aas[a] == RAS_AA_MSAA;
                    if (!llvmpipe_image(cs[i].llvm, (ras_scene_shader)s, msaa, scene->width,
                                        scene->height, rgba)) {
                        fprintf(stderr, "bench_perf: no image from llvmpipe\n");
                        return 1;
                    }
                    llvmpipe_compare(expected, scene->clear_color, rgba, msaa, &r->check);
                    r->checked = true;
                    r->identical = r->check.pass;
                    all_llvm_pass = all_llvm_pass && r->check.pass;
                    any_llvm = true;
                } else if (!cs[i].plain) {
                    all_identical = all_identical && r->identical;
                }
                print_row(stdout, r, false);
            }
            row_count += n;
            fflush(stdout);
        }
    for (int th = 0; th < 2; th++) llvmpipe_stop(llvm[th]);
    free(rgba);

    /* One frame's instructions, 1 thread, 1x and MSAA 4x (exact and repeatable,
     * whatever else the machine does). */
    if (count_instructions && !filtered) {
        char self[1200], llvm_prog[1200];
        snprintf(self, sizeof self, "%s/bin/bench_perf", RAS_BINARY_DIR);
        snprintf(llvm_prog, sizeof llvm_prog, "%s/bin/bench_llvmpipe", RAS_BINARY_DIR);
        bool have_spot = spot && *spot;
        char *teaching[] = {self, "--count-frames", "teaching", have_spot ? "--spot" : NULL,
                            (char *)spot, NULL};
        char *fast[] = {self, "--count-frames", "fast", have_spot ? "--spot" : NULL, (char *)spot,
                        NULL};
        char *nearest[] = {self, "--count-frames", "teaching", "--filter", "nearest",
                           have_spot ? "--spot" : NULL, (char *)spot, NULL};
        char *llvmpipe[] = {llvm_prog, "--count", "--model", model, have_spot ? "--texture" : NULL,
                            texture, NULL};
        fprintf(stderr, "bench_perf: counting instructions with callgrind (minutes)\n");
        if (!callgrind(teaching, 0) || !callgrind(fast, 1) || !callgrind(nearest, 3) ||
            (llvm_renderer[0] && !callgrind(llvmpipe, 2)))
            return 1;
        for (int i = 0; i < row_count; i++) {
            row *r = &rows[i];
            int a = r->aa == RAS_AA_MSAA ? 1 : r->aa == RAS_AA_NONE ? 0 : -1;
            if (a < 0 || r->threads != 1) continue;
            r->instructions = instr[r->shader][a][is_llvmpipe(r) ? 2 : r->mode[0] == 'p' ? 0 : 1];
        }
    }

    /* Whole processes: the program that only loads (OpenCV and all) and exits,
     * and the program that renders the scene once and writes a PNG. */
    proc_time p_version = {0}, p_render = {0}, p_plain = {0};
    bool have_proc = false;
    char out_png[256];
    snprintf(out_png, sizeof out_png, "/tmp/raster101_bench_out_%d.png", (int)getpid());
    if (!quick && !filtered) {
        char prog[1200];
        snprintf(prog, sizeof prog, "%s/bin/hw3_shading_ref", RAS_BINARY_DIR);
        char *v_argv[] = {prog, "--version", NULL};
        /* the fast path is asked for; the program's default is the teaching pipeline */
        char *r_argv[] = {prog, "--model", model, "--shader", "phong", "-o", out_png,
                          "--renderer", "fast", NULL};
        char *r6_argv[] = {prog, "--model", model, "--texture", texture, "--shader", "phong", "-o",
                           out_png, "--renderer", "fast", NULL};
        char **render_argv = spot ? r6_argv : r_argv;
        have_proc = time_process(v_argv, 15, &p_version) && time_process(render_argv, 15, &p_render);
        if (have_proc) {
            char **end = render_argv;
            while (*end) end++;
            end[-2] = NULL; /* without --renderer fast: the teaching pipeline */
            have_proc = time_process(render_argv, 15, &p_plain);
            end[-2] = "--renderer";
        }
        if (!have_proc) fprintf(stderr, "bench_perf: could not time %s\n", prog);
        remove(out_png);
    }
    if (tmp_obj[0]) remove(tmp_obj);
    struct rusage self;
    getrusage(RUSAGE_SELF, &self);

    if (have_proc) {
        printf("\nprocess  --version: median %.1f ms (min %.1f)  max RSS %ld KiB\n", p_version.median,
               p_version.min, p_version.max_rss_kb);
        printf("process  -o out.png (fast): median %.1f ms (min %.1f)  max RSS %ld KiB\n",
               p_render.median, p_render.min, p_render.max_rss_kb);
        printf("process  -o out.png (plain): median %.1f ms (min %.1f)  max RSS %ld KiB\n",
               p_plain.median, p_plain.min, p_plain.max_rss_kb);
    }
    printf("fast images identical to plain: %s\n", all_identical ? "yes" : "NO");
    if (any_llvm)
        printf("llvmpipe images within tolerance of plain: %s\n", all_llvm_pass ? "yes" : "NO");

    if (out_path) {
        ras_io_report report; /* written whole or not at all (ras_io.h) */
        FILE *f = ras_io_report_open(&report);
        if (!f) {
            fprintf(stderr, "bench_perf: cannot write %s: out of memory\n", out_path);
            return 1;
        }
        char cpu[256], date[64];
        machine_name(cpu, sizeof cpu);
        time_t now = time(NULL);
        strftime(date, sizeof date, "%Y-%m-%d", gmtime(&now));
        if (!copy_intro(f)) fprintf(f, "# Performance\n");
        fprintf(f, "\n## Measured (one run)\n\n");
        fprintf(f, "Machine: %s, %ld CPUs online; %s, compiler %s, %s. Model: %s, %zu triangles. "
                   "%d timed frames per row (after 2 warm-up frames); a frame is one whole "
                   "`hw3_render` call (setup, raster, shading, resolve into the image). Date %s.\n\n",
                cpu, sysconf(_SC_NPROCESSORS_ONLN), RAS_BUILD_TYPE, __VERSION__,
                "`make bench-perf`", model_name, assets->meshes[0]->triangle_count, frames,
                date);
        double load[3] = {0, 0, 0};
        if (getloadavg(load, 3) == 3)
            fprintf(f, "Load average when the report was written: %.2f (1 min), %.2f (5 min) on "
                       "%ld CPUs.\n\n", load[0], load[1], sysconf(_SC_NPROCESSORS_ONLN));
        fprintf(f, "| shader | AA | mode | threads | median ms | min ms | max ms | CPU ms | "
                   "fragments shaded | really shaded | ns/fragment | buffers MiB | same image as "
                   "plain |\n"
                   "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (int i = 0; i < row_count; i++) print_row(f, &rows[i], true);
        fprintf(f,
                "\n\"fragments shaded\" is the counter `fragments_shaded`, the same for both "
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
        /* The goals the report checks, from the rows above. */
        const row *g[RAS_SHADER_COUNT][3][3] = {{{0}}}; /* shader, aa, 0 plain / 1-2 threads */
        for (int i = 0; i < row_count; i++) {
            if (is_llvmpipe(&rows[i])) continue; /* their own section, below */
            int a = rows[i].aa == RAS_AA_MSAA ? 1 : rows[i].aa == RAS_AA_SSAA ? 2 : 0;
            int m = rows[i].mode[0] == 'p' ? 0 : rows[i].threads;
            g[rows[i].shader][a][m] = &rows[i];
        }
        const row *ph = g[RAS_SHADER_PHONG][0][2], *tx = g[RAS_SHADER_TEXTURE][0][2];
        fprintf(f, "\n### Goals\n\n| goal | measured | met |\n|---|---|---|\n");
        fprintf(f,
                "| Blinn-Phong ≤ 2 ms at 1x, 2 threads | %.2f ms (1 thread %.2f ms, CPU %.2f ms; "
                "plain %.2f ms) | %s |\n",
                ph->median, g[RAS_SHADER_PHONG][0][1]->median,
                g[RAS_SHADER_PHONG][0][1]->cpu_median, g[RAS_SHADER_PHONG][0][0]->median,
                ph->median <= 2.0 ? "yes" : "no");
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
        if (have_proc) {
            double frame = g[RAS_SHADER_PHONG][0][2]->median;
            fprintf(f, "| whole process `hw3_shading_ref --model … --shader phong -o out.png` ≤ "
                       "loading (`--version`) + one frame | %.1f ms vs %.1f + %.1f = %.1f ms "
                       "(plain pipeline: %.1f ms) | %s |\n",
                    p_render.median, p_version.median, frame, p_version.median + frame,
                    p_plain.median, p_render.median <= p_version.median + frame ? "yes" : "no");
            fprintf(f, "\nWhole processes (wall clock, median of 15 runs, max RSS): `--version` "
                       "%.1f ms / %ld KiB; `-o out.png` fast %.1f ms / %ld KiB; plain "
                       "(without `--renderer fast`) %.1f ms / %ld KiB. The render also loads the model (assimp) "
                   "and the texture (PNG decode) and encodes the PNG, which `--version` does not: "
                   "that I/O, not the frame, makes most of the difference.\n",
                    p_version.median, p_version.max_rss_kb, p_render.median, p_render.max_rss_kb,
                    p_plain.median, p_plain.max_rss_kb);
        }
        if (any_llvm) report_llvmpipe(f, llvm_renderer);
        report_framework(f);
        fprintf(f, "\nEvery fast image was compared with the plain image of the same row "
                   "byte for byte: %s. The benchmark process peaked at %ld KiB RSS.\n",
                all_identical ? "all identical" : "**SOME DIFFER**", self.ru_maxrss);
        ras_error werr = {{0}};
        if (!ras_io_report_commit(&report, out_path, &werr)) {
            fprintf(stderr, "bench_perf: %s\n", werr.msg);
            return 1;
        }
        fprintf(stderr, "bench_perf: wrote %s\n", out_path);
    }
    if (csv_path && !write_csv(csv_path)) return 1;
    ras_image_destroy(expected);
    ras_image_destroy(img);
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(scene);
    return all_identical && all_llvm_pass ? 0 : 1;
}
