/* bench_perf.h — private to the performance report (bench_perf): what its
 * modules share. Not an API; nothing outside tests/bench/bench_perf*.c
 * includes it.
 *
 * The program, by job:
 *   bench_perf.c          the command line: the scene, the rows to measure,
 *                         the instruction counts and whole processes, the files
 *   bench_perf_measure.c  timing frames in alternating rounds, whole processes,
 *                         and callgrind's instruction counts
 *   bench_perf_report.c   the rows on stdout, docs/performance.md (the prose of
 *                         bench_perf.md.in, then the measured tables) and the CSV
 */
#ifndef RAS_BENCH_PERF_H
#define RAS_BENCH_PERF_H

#include "bench_llvmpipe.h" /* llvmpipe beside the project's renderers */
#include "scene.h"

#include <stdbool.h> /* bool */
#include <stdint.h>  /* uint64_t */
#include <stdio.h>   /* FILE */

#ifndef RAS_BINARY_DIR
#define RAS_BINARY_DIR "."
#endif
#ifndef RAS_SOURCE_DIR
#define RAS_SOURCE_DIR "."
#endif
#ifndef RAS_BUILD_TYPE
#define RAS_BUILD_TYPE "unknown build type"
#endif

/* ---- the rows of the report --------------------------------------------------- */

typedef struct perf_row {
    const char *mode; /* "plain", "fast" or "llvmpipe" */
    int threads;
    ras_scene_shader shader;
    ras_aa_mode aa;
    double median, min, max;
    double cpu_median;  /* process CPU time per frame, all threads: robust to a busy machine */
    uint64_t fragments; /* the counters' fragments_shaded: the teaching pipeline's */
    uint64_t shaded;    /* the fragments this path really shaded */
    size_t buffer_bytes;
    bool identical; /* fast rows: the image equals the plain one; llvmpipe: the check passed */
    bool checked;   /* llvmpipe rows: `check` holds the pixel check against plain */
    uint64_t instructions; /* one frame, callgrind (--instructions); 0: not counted */
    llvmpipe_check check;
} perf_row;

#define PERF_MAX_ROWS 128
extern perf_row perf_rows[PERF_MAX_ROWS];
extern int perf_row_count;

bool perf_is_llvmpipe(const perf_row *r);

/* --filter: the texture lookups of every frame (default: the scene's). */
extern bool perf_filter_set;
extern texture_filter perf_filter;

/* --spot: the course framework's figures apply (bench_perf_report.c). */
extern bool perf_on_spot;

/* perf_instr[shader][aa][renderer]: 0 teaching pipeline, 1 fast path, 2 llvmpipe,
 * 3 teaching pipeline with nearest lookups (the course framework's). */
extern uint64_t perf_instr[RAS_SHADER_COUNT][2][4];

/* ---- measuring (bench_perf_measure.c) -------------------------------------------- */

/* One renderer of a round: the plain pipeline, the fast path or llvmpipe. */
typedef struct perf_contender {
    bool plain;
    int threads;
    llvmpipe_child *llvm; /* not NULL: llvmpipe, in that side process */
    int frames;           /* timed frames (the plain row of a filtered run: 1) */
    perf_row *r;
    double *t, *c; /* wall-clock and CPU ms per timed frame */
    ras_counters k;
    uint64_t shaded;
    bool identical;
} perf_contender;

/* Times the contenders of one shader and AA in alternating rounds: two
 * warm-up rounds in the given order (plain first: it draws `expected`, the
 * reference image), then `frames` rounds of one frame each, the order turned
 * by one every round. Every fast frame is compared with `expected` (outside
 * the timing). Fills each contender's row. */
bool measure_rounds(const ras_scene *scene, ras_scene_assets *assets, ras_scene_shader shader,
                    ras_aa_mode aa, perf_contender *cs, int n, int frames, ras_image *expected,
                    ras_image *img);

typedef struct perf_proc_time {
    double median, min, max; /* ms, wall clock */
    long max_rss_kb;
} perf_proc_time;

/* Runs argv `runs` times (at most 64), its output to /dev/null. */
bool measure_process(char *const argv[], int runs, perf_proc_time *out);

/* --count-frames: one frame of every shader at 1x and MSAA 4x (only 1x with
 * only_1x), each after a warm-up frame, between a zeroing of callgrind's
 * counters and a dump named SHADER_none / SHADER_msaa. The exit status. */
int measure_count_frames(const ras_scene *scene, ras_scene_assets *assets, bool plain, bool only_1x,
                         ras_image *img);

/* Runs argv under callgrind (LP_NUM_THREADS=1) and reads its dumps into
 * perf_instr[..][..][who]. */
bool measure_callgrind(char *const argv[], int who);

/* ---- the report (bench_perf_report.c) ---------------------------------------------- */

const char *report_aa_label(ras_aa_mode aa);
/* One row: a Markdown table line (md) or a line of the stdout table. */
void report_print_row(FILE *f, const perf_row *r, bool md);

/* What the Markdown report says beside the rows. */
typedef struct perf_report {
    const char *model_name;
    size_t triangles;
    int frames;
    bool have_proc; /* the whole-process timings below were measured */
    perf_proc_time p_version, p_render, p_plain;
    bool any_llvm;
    const char *llvm_renderer;
    bool all_identical;
    long peak_rss_kb;
} perf_report;

/* docs/performance.md: bench_perf.md.in, then the measured tables. */
bool report_write_markdown(const char *path, const perf_report *rep);
/* docs/performance.csv: one line per row. */
bool report_write_csv(const char *path);

#endif
