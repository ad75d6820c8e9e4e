/* bench_perf_measure.c — the performance report's measurements: frames
 * timed in alternating rounds (the plain pipeline, the fast path and
 * llvmpipe), whole processes, and one frame's instructions under callgrind.
 * bench_perf.h.
 */
#include "bench_perf.h"

/* Without valgrind's headers (scripts/install-deps installs them) the
 * requests do nothing, and ctest teaching_instructions says it found no
 * counted frame. */
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h> /* CALLGRIND_ZERO_STATS, CALLGRIND_DUMP_STATS_AT */
#else
#define CALLGRIND_ZERO_STATS
#define CALLGRIND_DUMP_STATS_AT(name) ((void)(name))
#endif
#include "fast_render.h" /* fast_render: the fast path, chosen explicitly */

#include <stdio.h>        /* fprintf, snprintf, fopen, freopen */
#include <stdlib.h>       /* malloc, free, qsort, setenv, strtoull */
#include <string.h>       /* memcmp, strcmp, strncmp */
#include <sys/resource.h> /* struct rusage */
#include <sys/wait.h>     /* wait4, waitpid */
#include <time.h>         /* clock_gettime */
#include <unistd.h>       /* fork, execv, execvp, _exit, getpid */

perf_row perf_rows[PERF_MAX_ROWS];
int perf_row_count;
bool perf_filter_set;
texture_filter perf_filter;
uint64_t perf_instr[RAS_SHADER_COUNT][2][4];

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

/* One frame through the plain pipeline (plain) or the fast path with
 * `threads`, into out: its wall-clock and process CPU ms. Static, so that the
 * frames callgrind counts are compiled as they were in one file. */
static bool render(const ras_scene *scene, ras_scene_assets *assets, ras_scene_shader shader,
                   ras_aa_mode aa, bool plain, int threads, ras_image *out, ras_counters *k,
                   uint64_t *shaded, double *ms, double *cpu) {
    hw3_render_options opt = hw3_render_defaults();
    *shaded = UINT64_MAX; /* the plain pipeline leaves it: it shades what it counts */
    fast_settings settings = {.threads = threads, .shaded = shaded};
    opt.shader = shader;
    if (perf_filter_set) opt.filter = perf_filter;
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

bool measure_rounds(const ras_scene *scene, ras_scene_assets *assets, ras_scene_shader shader,
                    ras_aa_mode aa, perf_contender *cs, int n, int frames, ras_image *expected,
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
            perf_contender *x = &cs[round < 0 ? j : (j + round) % n];
            if (round >= x->frames) continue;
            double ms, cpu;
            if (x->llvm) {
                ok = llvmpipe_frame(x->llvm, shader, aa == RAS_AA_MSAA, &ms, &cpu);
                if (!ok)
                    fprintf(stderr, "bench_perf: llvmpipe (%d threads) did not answer\n",
                            x->threads);
            } else {
                ok = render(scene, assets, shader, aa, x->plain, x->threads,
                            x->plain ? expected : img, &x->k, &x->shaded, &ms, &cpu);
                if (ok && !x->plain)
                    x->identical = x->identical && !memcmp(expected->pixels, img->pixels, bytes);
            }
            if (ok && round >= 0) {
                x->t[round] = ms;
                x->c[round] = cpu;
            }
        }
    for (int i = 0; ok && i < n; i++) {
        perf_contender *x = &cs[i];
        int f = x->frames;
        qsort(x->t, (size_t)f, sizeof *x->t, cmp_double);
        qsort(x->c, (size_t)f, sizeof *x->c, cmp_double);
        *x->r = (perf_row){.mode = x->llvm    ? "llvmpipe"
                                   : x->plain ? "plain"
                                              : "fast",
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
    for (int i = 0; i < n; i++)
        free(cs[i].t);
    return ok;
}

/* ---- whole processes ----------------------------------------------------- */

bool measure_process(char *const argv[], int runs, perf_proc_time *out) {
    double t[64];
    long rss = 0;
    for (int i = 0; i < runs; i++) {
        double t0 = ras_now_ms();
        pid_t pid = fork();
        if (pid < 0) return false;
        if (pid == 0) {
            if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr))
                _exit(126);
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
    *out = (perf_proc_time){t[runs / 2], t[0], t[runs - 1], rss};
    return true;
}

/* ---- instructions (callgrind) --------------------------------------------- */

/* --aa none counts 1x only: tests/bench/teaching_instructions_test.sh. */
int measure_count_frames(const ras_scene *scene, ras_scene_assets *assets, bool plain, bool only_1x,
                         ras_image *img) {
    const ras_aa_mode aas[2] = {RAS_AA_NONE, RAS_AA_MSAA};
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        for (int a = 0; a < (only_1x ? 1 : 2); a++) {
            ras_counters k;
            uint64_t shaded;
            double ms, cpu;
            char name[64];
            snprintf(name, sizeof name, "%s_%s", ras_scene_shader_name((ras_scene_shader)s),
                     a ? "msaa" : "none");
            if (!render(scene, assets, (ras_scene_shader)s, aas[a], plain, 1, img, &k, &shaded, &ms,
                        &cpu))
                return 1;
            CALLGRIND_ZERO_STATS;
            bool ok =
                render(scene, assets, (ras_scene_shader)s, aas[a], plain, 1, img, &k, &shaded, &ms, &cpu);
            CALLGRIND_DUMP_STATS_AT(name);
            if (!ok) return 1;
        }
    return 0;
}

bool measure_callgrind(char *const argv[], int who) {
    char out[256];
    snprintf(out, sizeof out, "/tmp/raster101_callgrind_%d_%d", (int)getpid(), who);
    char opt[300];
    snprintf(opt, sizeof opt, "--callgrind-out-file=%s", out);
    const char *vg[32] = {"valgrind", "--tool=callgrind", opt};
    int n = 3;
    for (int i = 0; argv[i] && n < 31; i++)
        vg[n++] = argv[i];
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
                    perf_instr[s][a][who] = total;
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
