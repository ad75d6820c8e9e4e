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
 *
 * This file is the command line: the scene, the rows to measure, the
 * instruction counts and whole processes, then the files (bench_perf.h lists
 * the modules).
 */
#include "bench_perf.h"
#include "ras_builtin_scenes.h" /* ras_builtin_scene_with_model: the classic scene */
#include "ras_mesh.h"

#include <stdio.h>        /* printf, fprintf, snprintf, remove */
#include <stdlib.h>       /* malloc, free, strtol, atoi */
#include <string.h>       /* strcmp */
#include <sys/resource.h> /* getrusage, struct rusage */
#include <unistd.h>       /* access, getpid */

typedef struct perf_args {
    const char *spot, *out_path, *csv_path;
    int frames;
    bool quick, use_llvmpipe, count_instructions;
    int count_mode; /* --count-frames: 0 teaching, 1 fast */
    int only_shader, only_aa, only_threads;
} perf_args;

static int usage(void) {
    fprintf(stderr, "usage: bench_perf [--spot DIR] [--frames N] [--out FILE] [--csv FILE] "
                    "[--quick] [--no-llvmpipe] [--instructions] [--shader NAME] "
                    "[--aa none|msaa|ssaa] [--threads 1|2] "
                    "[--filter nearest|bilinear|trilinear]\n");
    return 2;
}

/* The options that take a word: argv[*i] is the option, argv[*i + 1] its
 * value. -1 to go on, else the exit status. */
static int parse_choice(char **argv, int *i, perf_args *a) {
    const char *opt = argv[*i], *v = argv[++*i];
    if (!strcmp(opt, "--count-frames")) {
        a->count_mode = !strcmp(v, "teaching") ? 0 : !strcmp(v, "fast") ? 1 : -2;
        if (a->count_mode < 0) {
            fprintf(stderr, "bench_perf: --count-frames expects teaching or fast\n");
            return 2;
        }
    } else if (!strcmp(opt, "--filter")) {
        ras_error e = {{0}};
        if (!hw3_filter_parse(v, &perf_filter, &e)) {
            fprintf(stderr, "bench_perf: %s\n", e.msg);
            return 2;
        }
        perf_filter_set = true;
    } else if (!strcmp(opt, "--shader")) {
        for (int sh = RAS_SHADER_NORMAL; sh < RAS_SHADER_COUNT; sh++)
            if (!strcmp(v, ras_scene_shader_name((ras_scene_shader)sh))) a->only_shader = sh;
        if (a->only_shader < 0) {
            fprintf(stderr, "bench_perf: unknown shader '%s'\n", v);
            return 2;
        }
    } else if (!strcmp(opt, "--threads")) {
        a->only_threads = atoi(v);
        if (a->only_threads < 1 || a->only_threads > 2) {
            fprintf(stderr, "bench_perf: --threads expects 1 or 2\n");
            return 2;
        }
    } else if (!strcmp(opt, "--aa")) {
        a->only_aa = !strcmp(v, "none") ? 0 : !strcmp(v, "msaa") ? 1 : !strcmp(v, "ssaa") ? 2 : -1;
        if (a->only_aa < 0) {
            fprintf(stderr, "bench_perf: --aa expects none, msaa or ssaa\n");
            return 2;
        }
    } else { /* --frames */
        char *end;
        long n = strtol(v, &end, 10);
        if (*end || n < 1 || n > 1000) {
            fprintf(stderr, "bench_perf: --frames expects 1..1000, got '%s'\n", v);
            return 2;
        }
        a->frames = (int)n;
    }
    return -1;
}

/* -1 to go on, else the exit status. */
static int parse_args(int argc, char **argv, perf_args *a) {
    static const char *const choices[] = {"--count-frames", "--filter", "--shader",
                                          "--threads",      "--aa",     "--frames"};
    *a = (perf_args){
        .frames = 21, .use_llvmpipe = true, .count_mode = -1, .only_shader = -1, .only_aa = -1};
    for (int i = 1; i < argc; i++) {
        bool choice = false;
        for (size_t c = 0; c < sizeof choices / sizeof choices[0]; c++)
            choice = choice || !strcmp(argv[i], choices[c]);
        if (!strcmp(argv[i], "--spot") && i + 1 < argc)
            a->spot = argv[++i];
        else if (!strcmp(argv[i], "--out") && i + 1 < argc)
            a->out_path = argv[++i];
        else if (!strcmp(argv[i], "--quick"))
            a->quick = true;
        else if (!strcmp(argv[i], "--csv") && i + 1 < argc)
            a->csv_path = argv[++i];
        else if (!strcmp(argv[i], "--no-llvmpipe"))
            a->use_llvmpipe = false;
        else if (!strcmp(argv[i], "--instructions"))
            a->count_instructions = true;
        else if (choice && i + 1 < argc) {
            int status = parse_choice(argv, &i, a);
            if (status >= 0) return status;
        } else
            return usage();
    }
    if (a->quick) a->frames = 3;
    return -1;
}

/* The classic scene on the spot cow (--spot) or the built-in teapot, written
 * to a temporary OBJ (tmp_obj, removed by main). */
typedef struct bench_scene {
    char model[1200], texture[1200], tmp_obj[256];
    const char *model_name;
    ras_scene *scene; /* hw3_shading --model's (scenes/hw3_model.json) */
    ras_scene_assets *assets;
} bench_scene;

static bool load_scene(const char *spot, bench_scene *b) {
    ras_error err = {{0}};
    b->tmp_obj[0] = 0;
    if (spot && *spot) {
        snprintf(b->model, sizeof b->model, "%s/spot_triangulated_good.obj", spot);
        snprintf(b->texture, sizeof b->texture, "%s/spot_texture.png", spot);
        b->scene =
            ras_builtin_scene_with_model("hw3_model", b->model, b->texture, NULL, false, &err);
        b->model_name = "spot cow (spot_triangulated_good.obj, spot_texture.png)";
    } else {
        snprintf(b->tmp_obj, sizeof b->tmp_obj, "/tmp/raster101_bench_teapot_%d.obj",
                 (int)getpid());
        if (!bench_write_teapot_obj(b->tmp_obj)) {
            fprintf(stderr, "bench_perf: cannot write %s\n", b->tmp_obj);
            return false;
        }
        snprintf(b->model, sizeof b->model, "%s", b->tmp_obj);
        b->scene = ras_builtin_scene_with_model("hw3_model", b->model, NULL, NULL, false, &err);
        b->model_name =
            "built-in Bézier teapot (6 400 triangles, checker colour map, bumps height map)";
    }
    b->assets = b->scene ? ras_scene_load_assets(b->scene, &err) : NULL;
    if (!b->assets) {
        fprintf(stderr, "bench_perf: %s\n", err.msg);
        return false;
    }
    return true;
}

/* llvmpipe, one side process per thread count (LP_NUM_THREADS is read
 * once per process), on the same model and texture. False when one would
 * not start; llvmpipe is left out, with a word, when it was not built. */
static bool start_llvmpipe(const perf_args *a, const bench_scene *b, llvmpipe_child *llvm[2],
                           char *renderer, size_t renderer_size) {
    char prog[1200];
    snprintf(prog, sizeof prog, "%s/bin/bench_llvmpipe", RAS_BINARY_DIR);
    if (access(prog, X_OK) != 0) {
        fprintf(stderr, "bench_perf: %s was not built (no OSMesa): llvmpipe left out\n", prog);
        return true;
    }
    for (int th = 1; th <= 2; th++) {
        if (a->only_threads && th != a->only_threads) continue;
        llvm[th - 1] = llvmpipe_start(prog, th, b->model, a->spot && *a->spot ? b->texture : NULL,
                                      renderer, renderer_size);
        if (!llvm[th - 1]) return false;
    }
    return true;
}

/* What the rows came to: every fast image identical, every llvmpipe image
 * within tolerance. */
typedef struct verdicts {
    bool all_identical, all_llvm_pass, any_llvm;
} verdicts;

/* The llvmpipe row's pixel check against the plain image. */
static bool check_llvmpipe(perf_contender *c, const bench_scene *b, ras_scene_shader s, ras_aa_mode aa,
                           const ras_image *expected, uint8_t *rgba, verdicts *v) {
    perf_row *r = c->r;
    bool msaa = aa == RAS_AA_MSAA;
    if (!llvmpipe_image(c->llvm, s, msaa, b->scene->width, b->scene->height, rgba)) {
        fprintf(stderr, "bench_perf: no image from llvmpipe\n");
        return false;
    }
    llvmpipe_compare(expected, b->scene->clear_color, rgba, msaa, &r->check);
    r->checked = true;
    r->identical = r->check.pass;
    v->all_llvm_pass = v->all_llvm_pass && r->check.pass;
    v->any_llvm = true;
    return true;
}

/* Every shader × AA of the run: its contenders measured, checked and
 * printed, their rows appended to perf_rows. */
static bool measure_all(const perf_args *a, const bench_scene *b, llvmpipe_child *llvm[2],
                        bool filtered, ras_image *expected, ras_image *img, uint8_t *rgba,
                        verdicts *v) {
    const ras_aa_mode aas[3] = {RAS_AA_NONE, RAS_AA_MSAA, RAS_AA_SSAA};
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        for (int aa = 0; aa < 3; aa++) {
            if ((a->only_shader >= 0 && s != a->only_shader) ||
                (a->only_aa >= 0 && aa != a->only_aa))
                continue;
            /* Filtered runs time the plain path over one frame only: it is
             * the reference image, and stays out of a profile of the fast path. */
            perf_contender cs[5];
            int n = 0;
            cs[n++] =
                (perf_contender){.plain = true, .threads = 1, .frames = filtered ? 1 : a->frames};
            for (int th = 1; th <= 2; th++)
                if (!a->only_threads || th == a->only_threads)
                    cs[n++] = (perf_contender){.threads = th, .frames = a->frames};
            for (int th = 1; th <= 2; th++) /* llvmpipe: no AA and MSAA 4x */
                if (llvm[th - 1] && aas[aa] != RAS_AA_SSAA)
                    cs[n++] =
                        (perf_contender){.threads = th, .llvm = llvm[th - 1], .frames = a->frames};
            if (perf_row_count + n > PERF_MAX_ROWS) return false;
            for (int i = 0; i < n; i++)
                cs[i].r = &perf_rows[perf_row_count + i];
            if (!measure_rounds(b->scene, b->assets, (ras_scene_shader)s, aas[aa], cs, n, a->frames,
                                expected, img))
                return false;
            for (int i = 0; i < n; i++) {
                if (cs[i].llvm) { /* the same pixels? against the plain image */
                    if (!check_llvmpipe(&cs[i], b, (ras_scene_shader)s, aas[aa], expected, rgba, v))
                        return false;
                } else if (!cs[i].plain) {
                    v->all_identical = v->all_identical && cs[i].r->identical;
                }
                report_print_row(stdout, cs[i].r, false);
            }
            perf_row_count += n;
            fflush(stdout);
        }
    return true;
}

/* One frame's instructions, 1 thread, 1x and MSAA 4x (exact and repeatable,
 * whatever else the machine does), into the rows. */
static bool count_instructions(const perf_args *a, bench_scene *b, bool with_llvmpipe) {
    char self[1200], llvm_prog[1200];
    snprintf(self, sizeof self, "%s/bin/bench_perf", RAS_BINARY_DIR);
    snprintf(llvm_prog, sizeof llvm_prog, "%s/bin/bench_llvmpipe", RAS_BINARY_DIR);
    char *spot = (char *)a->spot;
    bool have_spot = spot && *spot;
    char *teaching[] = {self, "--count-frames", "teaching", have_spot ? "--spot" : NULL, spot,
                        NULL};
    char *fast[] = {self, "--count-frames", "fast", have_spot ? "--spot" : NULL, spot, NULL};
    char *nearest[] = {self,       "--count-frames",
                       "teaching", "--filter",
                       "nearest",  have_spot ? "--spot" : NULL,
                       spot,       NULL};
    char *llvmpipe[] = {llvm_prog,  "--count", "--model", b->model, have_spot ? "--texture" : NULL,
                        b->texture, NULL};
    fprintf(stderr, "bench_perf: counting instructions with callgrind (minutes)\n");
    if (!measure_callgrind(teaching, 0) || !measure_callgrind(fast, 1) ||
        !measure_callgrind(nearest, 3) || (with_llvmpipe && !measure_callgrind(llvmpipe, 2)))
        return false;
    for (int i = 0; i < perf_row_count; i++) {
        perf_row *r = &perf_rows[i];
        int aa = r->aa == RAS_AA_MSAA ? 1 : r->aa == RAS_AA_NONE ? 0 : -1;
        if (aa < 0 || r->threads != 1) continue;
        r->instructions = perf_instr[r->shader][aa][perf_is_llvmpipe(r) ? 2
                                                    : r->mode[0] == 'p' ? 0
                                                                        : 1];
    }
    return true;
}

/* Whole processes: the program that only loads (OpenCV and all) and exits,
 * and the program that renders the scene once and writes a PNG, on the fast
 * path and on the teaching pipeline. Sets rep->have_proc. */
static void time_processes(const perf_args *a, bench_scene *b, perf_report *rep) {
    char out_png[256];
    snprintf(out_png, sizeof out_png, "/tmp/raster101_bench_out_%d.png", (int)getpid());
    char prog[1200];
    snprintf(prog, sizeof prog, "%s/bin/hw3_shading_ref", RAS_BINARY_DIR);
    char *v_argv[] = {prog, "--version", NULL};
    /* the fast path is asked for; the program's default is the teaching pipeline */
    char *r_argv[] = {prog, "--model", b->model,     "--shader", "phong",
                      "-o", out_png,   "--renderer", "fast",     NULL};
    char *r6_argv[] = {prog,    "--model", b->model, "--texture",  b->texture, "--shader",
                       "phong", "-o",      out_png,  "--renderer", "fast",     NULL};
    char **render_argv = a->spot ? r6_argv : r_argv;
    rep->have_proc = measure_process(v_argv, 15, &rep->p_version) &&
                     measure_process(render_argv, 15, &rep->p_render);
    if (rep->have_proc) {
        char **end = render_argv;
        while (*end)
            end++;
        end[-2] = NULL; /* without --renderer fast: the teaching pipeline */
        rep->have_proc = measure_process(render_argv, 15, &rep->p_plain);
        end[-2] = "--renderer";
    }
    if (!rep->have_proc) fprintf(stderr, "bench_perf: could not time %s\n", prog);
    remove(out_png);
}

static void print_processes(const perf_report *rep) {
    printf("\nprocess  --version: median %.1f ms (min %.1f)  max RSS %ld KiB\n",
           rep->p_version.median, rep->p_version.min, rep->p_version.max_rss_kb);
    printf("process  -o out.png (fast): median %.1f ms (min %.1f)  max RSS %ld KiB\n",
           rep->p_render.median, rep->p_render.min, rep->p_render.max_rss_kb);
    printf("process  -o out.png (plain): median %.1f ms (min %.1f)  max RSS %ld KiB\n",
           rep->p_plain.median, rep->p_plain.min, rep->p_plain.max_rss_kb);
}

/* Measures every row, then (unless filtered) instructions and whole processes;
 * writes the report and the CSV. The exit status. */
static int run(const perf_args *a, bench_scene *b, bool filtered, ras_image *expected,
               ras_image *img) {
    llvmpipe_child *llvm[2] = {NULL, NULL};
    char llvm_renderer[256] = "";
    if (a->use_llvmpipe && !start_llvmpipe(a, b, llvm, llvm_renderer, sizeof llvm_renderer))
        return 1;
    uint8_t *rgba = malloc((size_t)b->scene->width * (size_t)b->scene->height * 4);
    if (!rgba) return 1;
    verdicts v = {.all_identical = true, .all_llvm_pass = true};
    fprintf(stderr, "bench_perf: %s, %zu triangles, %d frames per row%s%s\n", b->model_name,
            b->assets->meshes[0]->triangle_count, a->frames, llvm_renderer[0] ? "; beside " : "",
            llvm_renderer);
    if (!measure_all(a, b, llvm, filtered, expected, img, rgba, &v)) return 1;
    for (int th = 0; th < 2; th++)
        llvmpipe_stop(llvm[th]);
    free(rgba);
    if (a->count_instructions && !filtered && !count_instructions(a, b, llvm_renderer[0])) return 1;
    perf_report rep = {.model_name = b->model_name,
                       .triangles = b->assets->meshes[0]->triangle_count,
                       .frames = a->frames,
                       .any_llvm = v.any_llvm,
                       .llvm_renderer = llvm_renderer,
                       .all_identical = v.all_identical};
    if (!a->quick && !filtered) time_processes(a, b, &rep);
    if (b->tmp_obj[0]) remove(b->tmp_obj);
    struct rusage self;
    getrusage(RUSAGE_SELF, &self);
    rep.peak_rss_kb = self.ru_maxrss;

    if (rep.have_proc) print_processes(&rep);
    printf("fast images identical to plain: %s\n", v.all_identical ? "yes" : "NO");
    if (v.any_llvm)
        printf("llvmpipe images within tolerance of plain: %s\n", v.all_llvm_pass ? "yes" : "NO");
    if (!filtered && a->out_path && !report_write_markdown(a->out_path, &rep)) return 1;
    if (!filtered && a->csv_path && !report_write_csv(a->csv_path)) return 1;
    return v.all_identical && v.all_llvm_pass ? 0 : 1;
}

int main(int argc, char **argv) {
    perf_args a;
    int status = parse_args(argc, argv, &a);
    if (status >= 0) return status;
    /* A filtered run has no full table: no goals, no report. */
    bool filtered = a.only_shader >= 0 || a.only_aa >= 0 || a.only_threads > 0 || perf_filter_set;
    perf_on_spot = a.spot && *a.spot;

    bench_scene b;
    if (!load_scene(a.spot, &b)) return 1;
    ras_error err = {{0}};
    ras_image *expected = ras_image_create(b.scene->width, b.scene->height, &err);
    ras_image *img = ras_image_create(b.scene->width, b.scene->height, &err);
    if (!expected || !img) return 1;
    if (a.count_mode >= 0) { /* the counting side of --instructions, under callgrind */
        status = measure_count_frames(b.scene, b.assets, a.count_mode == 0, a.only_aa == 0, img);
        if (b.tmp_obj[0]) remove(b.tmp_obj);
        return status;
    }
    status = run(&a, &b, filtered, expected, img);
    ras_image_destroy(expected);
    ras_image_destroy(img);
    ras_scene_assets_destroy(b.assets);
    ras_scene_destroy(b.scene);
    return status;
}
