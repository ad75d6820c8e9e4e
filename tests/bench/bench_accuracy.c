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
 */
#include "bench_float_edges.h" /* the float-edge rasterizer, this benchmark's own */
#include "bench_plot.h"
#include "ras_io.h" /* ras_io_report: the reports are written atomically */
#include "ras_pipeline.h"
#include "ras_texture.h"
#include "rasterizer.h"   /* hw2 reference: rasterize_triangle, resolve_pixel */
#include "scene.h"        /* hw3: hw3_fragment_stage, hw3_shade_fragment */
#include "shading.h"      /* hw3 reference: texture_sample_bilinear, ... */
#include "stage2_clip.h"  /* ras_clip_triangle */
#include "stage3_setup.h" /* ras_viewport */
#include "transform.h"    /* hw1 reference: get_projection_matrix */

#include <errno.h>    /* errno */
#include <math.h>     /* sqrt, log10, fabs, tan, llround */
#include <stdarg.h>   /* va_list */
#include <stdio.h>    /* printf, fprintf, FILE */
#include <stdlib.h>   /* malloc, calloc, free, qsort, strtol */
#include <string.h>   /* strcmp, strncpy */
#include <sys/stat.h> /* mkdir */
#include <time.h>     /* time, strftime */
#include <unistd.h>   /* rmdir, unlink */

/* ---- settings and results -------------------------------------------------- */

typedef struct settings {
    bool quick, check;
    int repeats;
    char out[1024];
} settings;

static settings S;
static int failures;

static void progress(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void progress(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fputs("bench_accuracy: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* --check: an ordering that must hold. Never about times. */
static void check(bool ok, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void check(bool ok, const char *fmt, ...) {
    if (!S.check) return;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "  check %s: ", ok ? "ok  " : "FAIL");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    if (!ok) failures++;
}

/* One row of the report; NAN where a column does not apply. */
typedef struct row {
    char section[16], scene[40], option[48];
    double med, min, max, rel; /* ms per frame; rel = med / cheapest of the scene */
    double rmse_all, psnr_all, rmse_edge, psnr_edge;
    double cracks, doubles;
    double v_max, formula, uv_max_texels, uv_rms_texels;
    double wrong;
    double bytes;
    int samples;
} row;

#define MAX_ROWS 160
static row rows[MAX_ROWS];
static int row_count;

static row *new_row(const char *section, const char *scene, const char *option) {
    if (row_count >= MAX_ROWS) {
        fprintf(stderr, "bench_accuracy: too many rows\n");
        exit(2);
    }
    /* A truncated name would no longer be found by find_row. */
    if (strlen(option) >= sizeof rows[0].option || strlen(scene) >= sizeof rows[0].scene) {
        fprintf(stderr, "bench_accuracy: row name too long: %s / %s\n", scene, option);
        exit(2);
    }
    row *r = &rows[row_count++];
    *r = (row){.med = NAN, .min = NAN, .max = NAN, .rel = NAN, .rmse_all = NAN,
               .psnr_all = NAN, .rmse_edge = NAN, .psnr_edge = NAN, .cracks = NAN,
               .doubles = NAN, .v_max = NAN, .formula = NAN, .uv_max_texels = NAN,
               .uv_rms_texels = NAN, .wrong = NAN, .bytes = NAN, .samples = 1};
    snprintf(r->section, sizeof r->section, "%s", section);
    snprintf(r->scene, sizeof r->scene, "%s", scene);
    snprintf(r->option, sizeof r->option, "%s", option);
    return r;
}

/* rel = fastest frame / the fastest frame of the cheapest timed row of the
 * same section and scene: on a shared machine the fastest frame is the one
 * least disturbed by other load (cache and memory contention survive even
 * CPU-time measurement), so the ratio is more repeatable than the medians'. */
static void fill_relative_times(void) {
    for (int i = 0; i < row_count; i++) {
        double best = INFINITY;
        for (int j = 0; j < row_count; j++)
            if (!strcmp(rows[i].section, rows[j].section) && !strcmp(rows[i].scene, rows[j].scene) &&
                rows[j].min < best)
                best = rows[j].min;
        if (isfinite(rows[i].min) && best > 0) rows[i].rel = rows[i].min / best;
    }
}

static row *find_row(const char *section, const char *scene, const char *option) {
    for (int i = 0; i < row_count; i++)
        if (!strcmp(rows[i].section, section) && !strcmp(rows[i].scene, scene) &&
            !strcmp(rows[i].option, option))
            return &rows[i];
    return NULL;
}

/* ---- timing ---------------------------------------------------------------- */

typedef void (*frame_fn)(void *ctx);

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* ---- small helpers ------------------------------------------------------------ */

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double rnd(void) { /* xorshift64*, uniform in [0, 1) */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

static void die_oom(const void *p) {
    if (!p) {
        fprintf(stderr, "bench_accuracy: out of memory\n");
        exit(2);
    }
}

static double psnr(double rmse) { return rmse > 0 ? 20 * log10(1.0 / rmse) : INFINITY; }

static const mat4s *identity(void) {
    static mat4s m;
    static bool done;
    if (!done) m = glms_mat4_identity();
    done = true;
    return &m;
}

/* A pipeline with the reference hooks; exits on failure (a bug in the bench). */
static ras_pipeline *make_pipeline(int w, int h, ras_aa_mode aa, ras_pattern_kind kind, int count,
                                   ras_rasterize_fn rasterize, unsigned varyings, ras_shade_fn shade,
                                   void *user, vec3s clear) {
    ras_error err = {{0}};
    ras_pipeline_config cfg = {.width = w, .height = h, .clear_color = clear, .aa = aa,
                               .varyings = varyings,
                               .rasterize = rasterize, .resolve = resolve_pixel,
                               .shade = shade, .shade_user = user};
    cfg.pattern = ras_sample_pattern_center();
    if (aa != RAS_AA_NONE && !ras_sample_pattern_make(kind, count, &cfg.pattern, &err)) {
        fprintf(stderr, "bench_accuracy: %s\n", err.msg);
        exit(2);
    }
    ras_pipeline *p = ras_pipeline_create(&cfg, &err);
    if (!p) {
        fprintf(stderr, "bench_accuracy: %s\n", err.msg);
        exit(2);
    }
    return p;
}

/* ---- exact polygon areas ------------------------------------------------------ */

typedef struct pt {
    double x, y;
} pt;

#define POLY_MAX 32

/* Keeps the part of polygon `in` left of the directed line a→b. */
static int clip_half(const pt *in, int n, pt a, pt b, pt *out) {
    int m = 0;
    for (int i = 0; i < n; i++) {
        pt p = in[i], q = in[(i + 1) % n];
        double dp = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        double dq = (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
        if (dp >= 0) out[m++] = p;
        if ((dp >= 0) != (dq >= 0)) {
            double t = dp / (dp - dq);
            out[m++] = (pt){p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
        }
        if (m >= POLY_MAX - 2) break;
    }
    return m;
}

/* poly ∩ convex counter-clockwise polygon `clip`; returns the vertex count. */
static int clip_convex(const pt *poly, int n, const pt *clip, int m, pt *out) {
    pt a[POLY_MAX], b[POLY_MAX];
    memcpy(a, poly, (size_t)n * sizeof *a);
    for (int i = 0; i < m && n > 0; i++) {
        n = clip_half(a, n, clip[i], clip[(i + 1) % m], b);
        memcpy(a, b, (size_t)n * sizeof *a);
    }
    memcpy(out, a, (size_t)n * sizeof *a);
    return n;
}

static double poly_area(const pt *p, int n) {
    double s = 0;
    for (int i = 0; i < n; i++) s += p[i].x * p[(i + 1) % n].y - p[(i + 1) % n].x * p[i].y;
    return 0.5 * s;
}

static double pixel_area(const pt *poly, int n, int x, int y) {
    pt sq[4] = {{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}}, out[POLY_MAX];
    int m = clip_convex(poly, n, sq, 4, out);
    return m >= 3 ? poly_area(out, m) : 0;
}

/* The screen triangle as the fixed-point rasterizer sees it: snapped to
 * 1/256 px, counter-clockwise. */
static void snapped_ccw(const vec4s v[3], pt out[3]) {
    for (int i = 0; i < 3; i++)
        out[i] = (pt){llround((double)v[i].x * 256) / 256.0, llround((double)v[i].y * 256) / 256.0};
    if (poly_area(out, 3) < 0) {
        pt t = out[1];
        out[1] = out[2];
        out[2] = t;
    }
}

/* cov[pixel index] += weight · (area of poly ∩ pixel), over the polygon's box. */
static void add_coverage(double *cov, int w, int h, const pt *poly, int n, double weight) {
    double x0 = poly[0].x, x1 = x0, y0 = poly[0].y, y1 = y0;
    for (int i = 1; i < n; i++) {
        x0 = fmin(x0, poly[i].x), x1 = fmax(x1, poly[i].x);
        y0 = fmin(y0, poly[i].y), y1 = fmax(y1, poly[i].y);
    }
    for (int y = (int)fmax(0, floor(y0)); y <= (int)fmin(h - 1, floor(y1)); y++)
        for (int x = (int)fmax(0, floor(x0)); x <= (int)fmin(w - 1, floor(x1)); x++)
            cov[(h - 1 - y) * w + x] += weight * pixel_area(poly, n, x, y);
}

/* ---- section 1: anti-aliasing ------------------------------------------------- */

typedef struct aa_option {
    const char *name;
    ras_aa_mode aa;
    ras_pattern_kind kind;
    int count;
} aa_option;

static const aa_option AA_OPTIONS[] = {
    {"none (1 sample)", RAS_AA_NONE, RAS_PATTERN_ORDERED, 1},
    {"MSAA ordered 2x2", RAS_AA_MSAA, RAS_PATTERN_ORDERED, 4},
    {"MSAA ordered 4x4", RAS_AA_MSAA, RAS_PATTERN_ORDERED, 16},
    {"MSAA ordered 8x8", RAS_AA_MSAA, RAS_PATTERN_ORDERED, 64},
    {"MSAA standard 2x", RAS_AA_MSAA, RAS_PATTERN_STANDARD, 2},
    {"MSAA standard 4x", RAS_AA_MSAA, RAS_PATTERN_STANDARD, 4},
    {"MSAA standard 8x", RAS_AA_MSAA, RAS_PATTERN_STANDARD, 8},
    {"MSAA standard 16x", RAS_AA_MSAA, RAS_PATTERN_STANDARD, 16},
    {"SSAA ordered 2x2", RAS_AA_SSAA, RAS_PATTERN_ORDERED, 4},
    {"SSAA ordered 4x4", RAS_AA_SSAA, RAS_PATTERN_ORDERED, 16},
    {"SSAA ordered 8x8", RAS_AA_SSAA, RAS_PATTERN_ORDERED, 64},
    {"SSAA standard 2x", RAS_AA_SSAA, RAS_PATTERN_STANDARD, 2},
    {"SSAA standard 4x", RAS_AA_SSAA, RAS_PATTERN_STANDARD, 4},
    {"SSAA standard 8x", RAS_AA_SSAA, RAS_PATTERN_STANDARD, 8},
    {"SSAA standard 16x", RAS_AA_SSAA, RAS_PATTERN_STANDARD, 16},
};
#define AA_OPTION_COUNT (int)(sizeof AA_OPTIONS / sizeof AA_OPTIONS[0])

/* A scene drawn as meshes with one set of matrices. */
typedef struct mesh_frame {
    ras_pipeline *p;
    ras_mesh *const *meshes;
    int mesh_count;
    mat4s view, projection;
    ras_image *img;
} mesh_frame;

static void draw_mesh_frame(void *ctx) {
    mesh_frame *f = ctx;
    ras_error err = {{0}};
    ras_pipeline_begin_frame(f->p);
    for (int i = 0; i < f->mesh_count; i++)
        if (!ras_pipeline_draw_mesh(f->p, f->meshes[i], *identity(), f->view, f->projection, &err)) {
            fprintf(stderr, "bench_accuracy: %s\n", err.msg);
            exit(2);
        }
    ras_pipeline_end_frame(f->p, f->img);
}

/* Times a group of frames round-robin — one frame of each option in turn,
 * `repeats` rounds after one warm-up round — so a burst of load on a shared
 * machine hits every option of the group alike and the ratios survive. */
typedef struct timed {
    mesh_frame f;
    row *r;
} timed;

/* This thread's CPU time in ms: unlike the wall clock it does not count the
 * time the thread waits while other processes run, so a busy machine
 * disturbs it far less. */
static double cpu_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

static void time_group(timed *t, int n) {
    int reps = S.repeats;
    double *ts = malloc((size_t)n * (size_t)reps * sizeof *ts);
    die_oom(ts);
    for (int i = 0; i < n; i++) draw_mesh_frame(&t[i].f);
    for (int k = 0; k < reps; k++)
        for (int i = 0; i < n; i++) {
            double t0 = cpu_ms();
            draw_mesh_frame(&t[i].f);
            ts[i * reps + k] = cpu_ms() - t0;
        }
    for (int i = 0; i < n; i++) {
        double *v = &ts[i * reps];
        qsort(v, (size_t)reps, sizeof *v, cmp_double);
        t[i].r->med = reps % 2 ? v[reps / 2] : 0.5 * (v[reps / 2 - 1] + v[reps / 2]);
        t[i].r->min = v[0];
        t[i].r->max = v[reps - 1];
        t[i].r->bytes = (double)t[i].f.p->fb->bytes;
    }
    free(ts);
}

/* Mesh whose positions are already clip coordinates (w = 1) of screen points. */
static ras_mesh *screen_mesh(const pt *v, const float *z, int tri_count, int w, int h, vec3s color) {
    ras_mesh *m = ras_mesh_create((size_t)tri_count * 3, (size_t)tri_count);
    die_oom(m);
    for (int i = 0; i < tri_count * 3; i++) {
        m->positions[i] = (vec3s){{(float)(2 * v[i].x / w - 1), (float)(2 * v[i].y / h - 1),
                                   z ? z[i / 3] : 0.0f}};
        m->colors[i] = color;
        m->indices[i] = (unsigned)i;
    }
    return m;
}

/* The screen triangles the pipeline will see for mesh m (stage 1 + viewport). */
static void screen_triangles(const ras_mesh *m, mat4s view, mat4s projection, int w, int h,
                             vec4s *out /* 3 per triangle */) {
    ras_clip_vertex *cv = malloc(m->vertex_count * sizeof *cv);
    die_oom(cv);
    ras_vertex_transform(m, *identity(), view, projection, RAS_VARYING_COLOR, cv);
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            out[3 * t + k] = ras_viewport(cv[m->indices[3 * t + k]].p_clip, w, h);
    free(cv);
}

/* RMSE over all pixels and over edge pixels; `channels` 1 = red only. */
static void image_error(const ras_image *img, const vec3s *truth, const bool *edge, int channels,
                        row *r) {
    double s_all = 0, s_edge = 0;
    long n_all = 0, n_edge = 0;
    for (int i = 0; i < img->width * img->height; i++) {
        double e = 0;
        for (int c = 0; c < channels; c++) {
            double d = (double)img->pixels[i].raw[c] - truth[i].raw[c];
            e += d * d;
        }
        e /= channels;
        s_all += e;
        n_all++;
        if (edge[i]) s_edge += e, n_edge++;
    }
    r->rmse_all = sqrt(s_all / n_all);
    r->rmse_edge = n_edge ? sqrt(s_edge / n_edge) : 0;
    r->psnr_all = psnr(r->rmse_all);
    r->psnr_edge = psnr(r->rmse_edge);
}

static void run_aa_options(const char *scene, ras_mesh *const *meshes, int mesh_count, mat4s view,
                           mat4s projection, int w, int h, unsigned varyings, const vec3s *truth,
                           const bool *edge, int channels) {
    ras_image *img = ras_image_create(w, h, NULL);
    die_oom(img);
    timed t[AA_OPTION_COUNT];
    for (int i = 0; i < AA_OPTION_COUNT; i++) {
        const aa_option *o = &AA_OPTIONS[i];
        t[i].f = (mesh_frame){.p = make_pipeline(w, h, o->aa, o->kind, o->count, rasterize_triangle,
                                                 varyings, NULL, NULL, (vec3s){{0, 0, 0}}),
                              .meshes = meshes, .mesh_count = mesh_count, .view = view,
                              .projection = projection, .img = img};
        t[i].r = new_row("aa", scene, o->name);
        t[i].r->samples = o->count;
    }
    progress("aa / %s: timing %d options x %d rounds", scene, AA_OPTION_COUNT, S.repeats);
    time_group(t, AA_OPTION_COUNT);
    for (int i = 0; i < AA_OPTION_COUNT; i++) {
        draw_mesh_frame(&t[i].f);
        image_error(img, truth, edge, channels, t[i].r);
        ras_pipeline_destroy(t[i].f.p);
    }
    ras_image_destroy(img);
}

/* Thin isosceles triangles at random angles, one per grid cell (so none
 * overlap and the exact area is the truth). */
static void aa_thin_triangles(void) {
    int size = S.quick ? 192 : 512, cell = S.quick ? 24 : 32, per = size / cell, n = per * per;
    pt *v = malloc((size_t)n * 3 * sizeof *v);
    die_oom(v);
    for (int cy = 0; cy < per; cy++)
        for (int cx = 0; cx < per; cx++) {
            double a = 2 * RAS_PI * rnd(), len = cell * (0.55 + 0.35 * rnd());
            double wd = 0.3 + 2.7 * rnd();
            double ox = (cx + 0.5) * cell + (rnd() - 0.5) * 2, oy = (cy + 0.5) * cell + (rnd() - 0.5) * 2;
            double dx = cos(a), dy = sin(a);
            pt *t = &v[3 * (cy * per + cx)];
            t[0] = (pt){ox + dx * len / 2, oy + dy * len / 2};
            t[1] = (pt){ox - dx * len / 2 - dy * wd / 2, oy - dy * len / 2 + dx * wd / 2};
            t[2] = (pt){ox - dx * len / 2 + dy * wd / 2, oy - dy * len / 2 - dx * wd / 2};
        }
    ras_mesh *m = screen_mesh(v, NULL, n, size, size, (vec3s){{1, 1, 1}});
    free(v);
    /* Truth: each snapped screen triangle clipped to every pixel it touches. */
    vec4s *tri = malloc((size_t)n * 3 * sizeof *tri);
    double *cov = calloc((size_t)size * size, sizeof *cov);
    vec3s *truth = malloc((size_t)size * size * sizeof *truth);
    bool *edge = malloc((size_t)size * size * sizeof *edge);
    die_oom(tri), die_oom(cov), die_oom(truth), die_oom(edge);
    screen_triangles(m, *identity(), *identity(), size, size, tri);
    double area_sum = 0, cov_sum = 0;
    for (int t = 0; t < n; t++) {
        pt p[3];
        snapped_ccw(&tri[3 * t], p);
        area_sum += poly_area(p, 3);
        add_coverage(cov, size, size, p, 3, 1.0);
    }
    long edges = 0;
    for (int i = 0; i < size * size; i++) {
        cov_sum += cov[i];
        truth[i] = (vec3s){{(float)cov[i], (float)cov[i], (float)cov[i]}};
        edge[i] = cov[i] > 1e-9 && cov[i] < 1 - 1e-9;
        edges += edge[i];
    }
    check(fabs(area_sum - cov_sum) < 1e-6 * area_sum,
          "thin triangles: pixel areas add up to the triangles' area (%.6f vs %.6f)", cov_sum,
          area_sum);
    char scene[40];
    snprintf(scene, sizeof scene, "thin triangles %dx%d", size, size);
    progress("aa / %s: %d triangles, %ld edge pixels", scene, n, edges);
    run_aa_options(scene, &m, 1, *identity(), *identity(), size, size, RAS_VARYING_COLOR, truth,
                   edge, 1);
    free(tri), free(cov), free(truth), free(edge);
    ras_mesh_destroy(m);
}

/* The classic hw2 scene (hw2_rasterize/main.c): the near triangle hides part
 * of the far one; both are flat-coloured, so the truth is exact: near ∩ pixel,
 * plus (far ∩ pixel) − (far ∩ near ∩ pixel), plus the rest as background. */
static void aa_hw2_scene(void) {
    static const vec3s pos[2][3] = {{{{2, 0, -2}}, {{0, 2, -2}}, {{-2, 0, -2}}},
                                    {{{3.5f, -1, -5}}, {{2.5f, 1.5f, -5}}, {{-1, 0.5f, -5}}}};
    static const vec3s col[2] = {{{217 / 255.0f, 238 / 255.0f, 185 / 255.0f}},
                                 {{185 / 255.0f, 217 / 255.0f, 238 / 255.0f}}};
    int size = S.quick ? 140 : 700;
    ras_mesh *m[2];
    for (int i = 0; i < 2; i++) m[i] = ras_mesh_create_triangle(pos[i][0], pos[i][1], pos[i][2], col[i]);
    die_oom(m[0]), die_oom(m[1]);
    mat4s view = ras_view_matrix_eye((vec3s){{0, 0, 5}});
    mat4s proj = get_projection_matrix(45, 1, 0.1f, 50);
    pt tri[2][3];
    for (int i = 0; i < 2; i++) {
        vec4s s[3];
        screen_triangles(m[i], view, proj, size, size, s);
        snapped_ccw(s, tri[i]);
    }
    pt far_and_near[POLY_MAX];
    int nfn = clip_convex(tri[1], 3, tri[0], 3, far_and_near);
    double *a_near = calloc((size_t)size * size, sizeof(double));
    double *a_far = calloc((size_t)size * size, sizeof(double));
    vec3s *truth = malloc((size_t)size * size * sizeof *truth);
    bool *edge = malloc((size_t)size * size * sizeof *edge);
    die_oom(a_near), die_oom(a_far), die_oom(truth), die_oom(edge);
    add_coverage(a_near, size, size, tri[0], 3, 1.0);
    add_coverage(a_far, size, size, tri[1], 3, 1.0);
    if (nfn >= 3) add_coverage(a_far, size, size, far_and_near, nfn, -1.0);
    long edges = 0;
    for (int i = 0; i < size * size; i++) {
        double an = a_near[i], af = a_far[i], bg = 1 - an - af;
        truth[i] = glms_vec3_add(glms_vec3_scale(col[0], (float)an), glms_vec3_scale(col[1], (float)af));
        (void)bg; /* the background is black */
        edge[i] = !(an > 1 - 1e-9 || af > 1 - 1e-9 || an + af < 1e-9);
        edges += edge[i];
    }
    char scene[40];
    snprintf(scene, sizeof scene, "hw2 scene %dx%d", size, size);
    progress("aa / %s: %ld edge pixels", scene, edges);
    run_aa_options(scene, m, 2, view, proj, size, size, RAS_VARYING_COLOR, truth, edge, 3);
    free(a_near), free(a_far), free(truth), free(edge);
    ras_mesh_destroy(m[0]), ras_mesh_destroy(m[1]);
}

/* ---- section 2: edge precision ------------------------------------------------ */

/* Counts every shaded sample: with SSAA and each triangle nearer than the
 * last, every covering triangle reaches the shader once per sample. */
typedef struct hit_counter {
    int w, h;
    const ras_sample_pattern *pattern;
    unsigned short *count; /* per sample, pixel-major like the framebuffer */
} hit_counter;

static vec3s count_hit(const ras_triangle *t, const ras_fragment *f, void *user) {
    (void)t;
    hit_counter *hc = user;
    int best = 0;
    double best_d = INFINITY;
    for (int k = 0; k < hc->pattern->count; k++) {
        double dx = f->p.x - (f->x + hc->pattern->offsets[k].x);
        double dy = f->p.y - (f->y + hc->pattern->offsets[k].y);
        if (dx * dx + dy * dy < best_d) best_d = dx * dx + dy * dy, best = k;
    }
    size_t i = ((size_t)(hc->h - 1 - f->y) * hc->w + f->x) * hc->pattern->count + best;
    if (hc->count[i] < 65535) hc->count[i]++;
    return (vec3s){{1, 1, 1}};
}

typedef bool (*inside_fn)(double x, double y, const void *shape);

typedef struct fan_shape {
    double cx, cy, inradius;
} fan_shape;
static bool inside_fan(double x, double y, const void *shape) {
    const fan_shape *s = shape;
    return hypot(x - s->cx, y - s->cy) < s->inradius - 0.01;
}

typedef struct box_shape {
    double x0, y0, x1, y1;
} box_shape;
static bool inside_box(double x, double y, const void *shape) {
    const box_shape *b = shape;
    return x > b->x0 + 0.01 && x < b->x1 - 0.01 && y > b->y0 + 0.01 && y < b->y1 - 0.01;
}

static void run_edge_modes(const char *scene, ras_mesh *m, int size, inside_fn inside,
                           const void *shape) {
    static const char *names[2] = {"fixed 24.8, top-left (reference)", "float, >= 0 test"};
    /* The reference, and the float-edge rasterizer kept for this comparison. */
    static const ras_rasterize_fn modes[2] = {rasterize_triangle, bench_rasterize_float_edges};
    ras_image *img = ras_image_create(size, size, NULL);
    die_oom(img);
    /* Time: one sample per pixel, plain vertex colour — coverage dominates. */
    timed t[2];
    for (int e = 0; e < 2; e++) {
        t[e].f = (mesh_frame){.p = make_pipeline(size, size, RAS_AA_NONE, RAS_PATTERN_ORDERED, 1,
                                                 modes[e], RAS_VARYING_COLOR, NULL, NULL,
                                                 (vec3s){{0, 0, 0}}),
                              .meshes = &m, .mesh_count = 1, .view = *identity(),
                              .projection = *identity(), .img = img};
        t[e].r = new_row("edges", scene, names[e]);
        t[e].r->samples = 4;
    }
    progress("edges / %s: timing", scene);
    time_group(t, 2);
    for (int e = 0; e < 2; e++) {
        ras_pipeline_destroy(t[e].f.p);
        row *r = t[e].r;
        mesh_frame f = t[e].f;
        progress("edges / %s: counting hits, %s", scene, names[e]);
        /* Count: SSAA 2x2 with the counting shader. */
        ras_sample_pattern pat;
        ras_sample_pattern_make(RAS_PATTERN_ORDERED, 4, &pat, NULL);
        hit_counter hc = {.w = size, .h = size, .pattern = &pat,
                          .count = calloc((size_t)size * size * 4, sizeof(unsigned short))};
        die_oom(hc.count);
        f.p = make_pipeline(size, size, RAS_AA_SSAA, RAS_PATTERN_ORDERED, 4, modes[e],
                            RAS_VARYING_COLOR, count_hit, &hc, (vec3s){{0, 0, 0}});
        draw_mesh_frame(&f);
        long cracks = 0, doubles = 0;
        for (int y = 0; y < size; y++)
            for (int x = 0; x < size; x++)
                for (int k = 0; k < 4; k++) {
                    unsigned c = hc.count[((size_t)(size - 1 - y) * size + x) * 4 + k];
                    if (c >= 2) doubles++;
                    else if (c == 0 && inside(x + pat.offsets[k].x, y + pat.offsets[k].y, shape))
                        cracks++;
                }
        r->cracks = (double)cracks;
        r->doubles = (double)doubles;
        ras_pipeline_destroy(f.p);
        free(hc.count);
    }
    ras_image_destroy(img);
}

static void edge_precision(void) {
    int size = S.quick ? 256 : 512;
    /* The fan: n slivers around the centre; each shares both long edges. */
    int n = S.quick ? 1000 : 3000;
    double cx = size / 2.0 + 0.123, cy = size / 2.0 + 0.377, rad = size * 0.47;
    pt *v = malloc((size_t)n * 3 * sizeof *v);
    float *z = malloc((size_t)n * sizeof *z);
    die_oom(v), die_oom(z);
    for (int i = 0; i < n; i++) {
        double a0 = 2 * RAS_PI * i / n, a1 = 2 * RAS_PI * (i + 1) / n;
        v[3 * i] = (pt){cx, cy};
        v[3 * i + 1] = (pt){cx + rad * cos(a0), cy + rad * sin(a0)};
        v[3 * i + 2] = (pt){cx + rad * cos(a1), cy + rad * sin(a1)};
        z[i] = (float)(-0.9 + 1.8 * i / n); /* each triangle nearer than the last */
    }
    ras_mesh *fan = screen_mesh(v, z, n, size, size, (vec3s){{1, 1, 1}});
    fan_shape fs = {cx, cy, rad * cos(RAS_PI / n)};
    char scene[40];
    snprintf(scene, sizeof scene, "fan of %d slivers", n);
    run_edge_modes(scene, fan, size, inside_fan, &fs);
    ras_mesh_destroy(fan);
    free(v), free(z);
    /* The jittered grid: g×g quads, inner corners moved at random. */
    int g = S.quick ? 20 : 40, tris = 2 * g * g;
    double m0 = 16.25, step = (size - 32.5) / g;
    pt *corner = malloc((size_t)(g + 1) * (g + 1) * sizeof *corner);
    v = malloc((size_t)tris * 3 * sizeof *v);
    z = malloc((size_t)tris * sizeof *z);
    die_oom(corner), die_oom(v), die_oom(z);
    for (int j = 0; j <= g; j++)
        for (int i = 0; i <= g; i++) {
            bool inner = i > 0 && j > 0 && i < g && j < g;
            /* ±0.15 of a cell keeps every triangle counter-clockwise, so
             * the triangles tile the square without overlapping. */
            corner[j * (g + 1) + i] = (pt){m0 + step * (i + (inner ? 0.3 * (rnd() - 0.5) : 0)),
                                           m0 + step * (j + (inner ? 0.3 * (rnd() - 0.5) : 0))};
        }
    int t = 0, clockwise = 0;
    for (int j = 0; j < g; j++)
        for (int i = 0; i < g; i++) {
            pt a = corner[j * (g + 1) + i], b = corner[j * (g + 1) + i + 1];
            pt c = corner[(j + 1) * (g + 1) + i + 1], d = corner[(j + 1) * (g + 1) + i];
            pt q[2][3] = {{a, b, c}, {a, c, d}};
            for (int k = 0; k < 2; k++, t++) {
                memcpy(&v[3 * t], q[k], sizeof q[k]);
                clockwise += !(poly_area(q[k], 3) > 0);
                z[t] = (float)(-0.9 + 1.8 * t / tris);
            }
        }
    check(clockwise == 0, "jittered grid: no folded triangle (%d of %d)", clockwise, tris);
    ras_mesh *grid = screen_mesh(v, z, tris, size, size, (vec3s){{1, 1, 1}});
    box_shape bs = {m0, m0, m0 + step * g, m0 + step * g};
    snprintf(scene, sizeof scene, "jittered grid %dx%d (%d triangles)", g, g, tris);
    run_edge_modes(scene, grid, size, inside_box, &bs);
    ras_mesh_destroy(grid);
    free(corner), free(v), free(z);
}

/* ---- camera helpers shared by sections 3–5 ------------------------------------ */

#define FOV_DEG 45.0
#define Z_NEAR 0.1f

/* The ray through the centre of screen pixel (x, y) from the view-space
 * origin, with z = -1 (aspect 1). */
static void pixel_ray(int x, int y, double sx, double sy, int size, double d[3]) {
    double t = tan(FOV_DEG * RAS_PI / 360.0);
    d[0] = (2 * (x + sx) / size - 1) * t;
    d[1] = (2 * (y + sy) / size - 1) * t;
    d[2] = -1;
}

/* A plane quad with UVs: corners p[0..3] counter-clockwise seen from the
 * camera, UV affine in 3D over the quad. */
typedef struct quad {
    double p[4][3];
    double uv[4][2];
} quad;

static ras_mesh *quad_mesh(const quad *q) {
    ras_mesh *m = ras_mesh_create(4, 2);
    die_oom(m);
    for (int i = 0; i < 4; i++) {
        m->positions[i] = (vec3s){{(float)q->p[i][0], (float)q->p[i][1], (float)q->p[i][2]}};
        m->uvs[i] = (vec2s){{(float)q->uv[i][0], (float)q->uv[i][1]}};
        m->colors[i] = (vec3s){{1, 1, 1}};
        m->normals[i] = (vec3s){{0, 0, 1}};
    }
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    memcpy(m->indices, idx, sizeof idx);
    m->has_uv = true;
    return m;
}

/* Ray (origin, direction d) against the quad's plane: the hit's view depth
 * and UV (parallelogram quads: p[3] - p[0] and p[1] - p[0] span it, UV affine).
 * False when the ray misses the plane or the hit is outside the quad. */
static bool quad_hit(const quad *q, const double d[3], double *depth, double uv[2]) {
    double e1[3], e2[3], n[3];
    for (int i = 0; i < 3; i++) e1[i] = q->p[1][i] - q->p[0][i], e2[i] = q->p[3][i] - q->p[0][i];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double nd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    if (nd == 0) return false;
    double s = (n[0] * q->p[0][0] + n[1] * q->p[0][1] + n[2] * q->p[0][2]) / nd;
    if (!(s > 0)) return false;
    double r[3] = {s * d[0] - q->p[0][0], s * d[1] - q->p[0][1], s * d[2] - q->p[0][2]};
    /* Solve r = a e1 + b e2 by least squares (exact: r lies in the plane). */
    double e11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    double e22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    double e12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    double r1 = r[0] * e1[0] + r[1] * e1[1] + r[2] * e1[2];
    double r2 = r[0] * e2[0] + r[1] * e2[1] + r[2] * e2[2];
    double det = e11 * e22 - e12 * e12;
    double a = (r1 * e22 - r2 * e12) / det, b = (r2 * e11 - r1 * e12) / det;
    *depth = s;
    for (int k = 0; k < 2; k++)
        uv[k] = q->uv[0][k] + a * (q->uv[1][k] - q->uv[0][k]) + b * (q->uv[3][k] - q->uv[0][k]);
    return a >= 0 && a <= 1 && b >= 0 && b <= 1;
}

static vec3s shader_uv(const fragment_shader_payload *payload) {
    return (vec3s){{payload->uv.x, payload->uv.y, 0}};
}

static vec3s shader_unlit_texture(const fragment_shader_payload *payload) {
    return texture_sample(payload, payload->texture, payload->uv);
}

/* ---- section 3: interpolation ------------------------------------------------- */

/* A rectangle receding from view depth w0 = 1 (bottom of the screen) to
 * w1 = k (top), its sides along the view's x: v runs near → far, u across.
 * Along its long edges v changes from 0 to 1 while w goes from w0 to w1, the
 * case of the formula (√k − 1)/(√k + 1). */
static quad receding_rect(double k) {
    double t = tan(FOV_DEG * RAS_PI / 360.0), w0 = 1, w1 = k, a = 0.9 * w0 * t;
    double y0 = -0.9 * w0 * t, y1 = 0.9 * w1 * t;
    quad q = {.p = {{-a, y0, -w0}, {a, y0, -w0}, {a, y1, -w1}, {-a, y1, -w1}},
              .uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    return q;
}

static void interpolation(void) {
    static const double ks[4] = {1.1, 2, 4, 8};
    const int size = S.quick ? 128 : 512, texels = 256;
    ras_texture *tex = ras_texture_create_checker(texels, 8, (vec3s){{0.9f, 0.9f, 0.9f}},
                                                  (vec3s){{0.1f, 0.1f, 0.1f}});
    ras_image *img = ras_image_create(size, size, NULL);
    die_oom(tex), die_oom(img);
    mat4s proj = get_projection_matrix(FOV_DEG, 1, Z_NEAR, 100);
    for (int ki = 0; ki < 4; ki++) {
        double k = ks[ki];
        quad q = receding_rect(k);
        ras_mesh *m = quad_mesh(&q);
        char scene[40];
        snprintf(scene, sizeof scene, "w1/w0 = %g", k);
        /* Time: the plane with an unlit bilinear texture, both modes in turn. */
        hw3_fragment_stage ts[2];
        timed t[2];
        for (int persp = 0; persp < 2; persp++) {
            ts[persp] = (hw3_fragment_stage){.shader = shader_unlit_texture,
                                             .varyings = RAS_VARYING_UV, .perspective = persp,
                                             .base = {.texture = tex, .filter = FILTER_BILINEAR}};
            t[persp].f = (mesh_frame){.p = make_pipeline(size, size, RAS_AA_NONE,
                                                         RAS_PATTERN_ORDERED, 1, rasterize_triangle,
                                                         RAS_VARYING_UV, hw3_shade_fragment,
                                                         &ts[persp], (vec3s){{0, 0, 0}}),
                                      .meshes = &m, .mesh_count = 1, .view = *identity(),
                                      .projection = proj, .img = img};
            t[persp].r = new_row("interp", scene,
                                 persp ? "perspective-correct" : "affine (screen-space)");
        }
        progress("interp / %s: timing", scene);
        time_group(t, 2);
        for (int persp = 0; persp < 2; persp++) {
            ras_pipeline_destroy(t[persp].f.p);
            row *r = t[persp].r;
            mesh_frame f = t[persp].f;
            /* Error: the interpolated UV itself, against the ray-plane hit. */
            hw3_fragment_stage us = {.shader = shader_uv, .varyings = RAS_VARYING_UV,
                                     .perspective = persp};
            f.p = make_pipeline(size, size, RAS_AA_NONE, RAS_PATTERN_ORDERED, 1, rasterize_triangle,
                                RAS_VARYING_UV, hw3_shade_fragment, &us, (vec3s){{0, 0, 0}});
            draw_mesh_frame(&f);
            double v_max = 0, uv_max = 0, sum2 = 0;
            long n = 0;
            for (int y = 0; y < size; y++)
                for (int x = 0; x < size; x++) {
                    double d[3], depth, uv[2];
                    int i = ras_fb_pixel_index(f.p->fb, x, y);
                    if (isinf(f.p->fb->depth[i])) continue;
                    pixel_ray(x, y, 0.5, 0.5, size, d);
                    if (!quad_hit(&q, d, &depth, uv)) continue;
                    vec3s got = f.p->fb->color[i];
                    double du = got.x - uv[0], dv = got.y - uv[1];
                    v_max = fmax(v_max, fabs(dv));
                    uv_max = fmax(uv_max, sqrt(du * du + dv * dv));
                    sum2 += du * du + dv * dv;
                    n++;
                }
            r->v_max = v_max;
            r->formula = (sqrt(k) - 1) / (sqrt(k) + 1);
            r->uv_max_texels = uv_max * texels;
            r->uv_rms_texels = n ? sqrt(sum2 / n) * texels : NAN;
            ras_pipeline_destroy(f.p);
            if (persp)
                check(r->uv_max_texels < 0.05,
                      "interp %s: perspective-correct UV error %.4f texels < 0.05", scene,
                      r->uv_max_texels);
            else
                check(v_max > 0.9 * r->formula && v_max < 1.02 * r->formula + 1e-4,
                      "interp %s: affine worst v error %.4f within [0.9, 1.02] x formula %.4f",
                      scene, v_max, r->formula);
        }
        ras_mesh_destroy(m);
    }
    ras_image_destroy(img);
    ras_texture_destroy(tex);
}

/* ---- section 4: texture filtering ---------------------------------------------- */

static void filtering(void) {
    const int size = S.quick ? 128 : 512, ss = S.quick ? 8 : 16;
    ras_texture *tx[2] = {ras_texture_create_checker(256, 8, (vec3s){{0.92f, 0.9f, 0.85f}},
                                                     (vec3s){{0.12f, 0.14f, 0.2f}}),
                          ras_texture_create_brick(256)};
    static const char *tex_names[2] = {"checker", "brick"};
    ras_image *img = ras_image_create(size, size, NULL);
    vec3s *truth = malloc((size_t)size * size * sizeof *truth);
    bool *valid = malloc((size_t)size * size * sizeof *valid);
    die_oom(tx[0]), die_oom(tx[1]), die_oom(img), die_oom(truth), die_oom(valid);
    /* The floor y = -1 from depth 1 to 40, 40 wide; one texture tile per 8 units. */
    const double tile = 8, zf = 40;
    quad q = {.p = {{-20, -1, -1}, {20, -1, -1}, {20, -1, -zf}, {-20, -1, -zf}},
              .uv = {{0, 0}, {40 / tile, 0}, {40 / tile, (zf - 1) / tile}, {0, (zf - 1) / tile}}};
    ras_mesh *m = quad_mesh(&q);
    mat4s proj = get_projection_matrix(FOV_DEG, 1, Z_NEAR, 100);
    for (int ti = 0; ti < 2; ti++) {
        ras_texture *tex = tx[ti];
        tex->wrap = RAS_WRAP_REPEAT;
        char scene[40];
        snprintf(scene, sizeof scene, "floor, %s %d", tex_names[ti], tex->width);
        progress("filter / %s: ground truth (%dx%d bilinear samples per pixel)", scene, ss, ss);
        long nvalid = 0;
        for (int y = 0; y < size; y++)
            for (int x = 0; x < size; x++) {
                int i = (size - 1 - y) * size + x;
                vec3s sum = {{0, 0, 0}};
                bool all = true;
                for (int sy = 0; sy < ss && all; sy++)
                    for (int sx = 0; sx < ss && all; sx++) {
                        double d[3], depth, uv[2];
                        pixel_ray(x, y, (sx + 0.5) / ss, (sy + 0.5) / ss, size, d);
                        all = quad_hit(&q, d, &depth, uv);
                        if (all)
                            sum = glms_vec3_add(sum, texture_sample_bilinear(tex, (float)uv[0],
                                                                             (float)uv[1]));
                    }
                valid[i] = all;
                nvalid += all;
                truth[i] = glms_vec3_scale(sum, 1.0f / (float)(ss * ss));
            }
        ras_texture_build_mips(tex);
        static const texture_filter filters[3] = {FILTER_NEAREST, FILTER_BILINEAR, FILTER_TRILINEAR};
        hw3_fragment_stage st[3];
        timed t[3];
        for (int fi = 0; fi < 3; fi++) {
            st[fi] = (hw3_fragment_stage){.shader = shader_unlit_texture,
                                          .varyings = RAS_VARYING_UV, .perspective = true,
                                          .base = {.texture = tex, .filter = filters[fi]}};
            t[fi].f = (mesh_frame){.p = make_pipeline(size, size, RAS_AA_NONE, RAS_PATTERN_ORDERED,
                                                      1, rasterize_triangle, RAS_VARYING_UV,
                                                      hw3_shade_fragment, &st[fi],
                                                      (vec3s){{0, 0, 0}}),
                                   .meshes = &m, .mesh_count = 1, .view = *identity(),
                                   .projection = proj, .img = img};
            t[fi].r = new_row("filter", scene, ras_scene_filter_name(filters[fi]));
        }
        progress("filter / %s: timing nearest, bilinear, trilinear", scene);
        time_group(t, 3);
        for (int fi = 0; fi < 3; fi++) {
            row *r = t[fi].r;
            draw_mesh_frame(&t[fi].f);
            ras_pipeline_destroy(t[fi].f.p);
            double s2 = 0;
            for (int i = 0; i < size * size; i++) {
                if (!valid[i]) continue;
                for (int c = 0; c < 3; c++) {
                    double dd = (double)img->pixels[i].raw[c] - truth[i].raw[c];
                    s2 += dd * dd / 3;
                }
            }
            r->rmse_all = nvalid ? sqrt(s2 / nvalid) : NAN;
            r->psnr_all = psnr(r->rmse_all);
        }
        row *rn = find_row("filter", scene, "nearest"), *rb = find_row("filter", scene, "bilinear");
        row *rt = find_row("filter", scene, "trilinear");
        check(rt->rmse_all < rn->rmse_all && rt->rmse_all < rb->rmse_all,
              "filter %s: trilinear RMSE %.4f < bilinear %.4f and nearest %.4f", scene,
              rt->rmse_all, rb->rmse_all, rn->rmse_all);
    }
    ras_mesh_destroy(m);
    free(truth), free(valid);
    ras_image_destroy(img);
    ras_texture_destroy(tx[0]), ras_texture_destroy(tx[1]);
}

/* ---- section 5: depth precision -------------------------------------------------- */

#define DEPTH_FAR 50.0
static const double DELTAS[] = {0.0001, 0.0003, 0.001, 0.003, 0.01, 0.1};
#define DELTA_COUNT 6
/* The two pipeline formats (stage3_setup.h) first, rendered and timed; then
 * what-ifs for storage the pipeline has no mode for. Float view depth w is
 * not among them: w is not affine on screen, so a rasterizer can only get it
 * as 1/(interpolated 1/w), which orders exactly as inverse_w does. */
static const char *const DEPTH_ENCODINGS[] = {
    "pipeline z01: (1−z_ndc)/2, 0 = near",          "pipeline inverse_w: −near/w, −1 = near",
    "what-if: float z01, exact depth rounded once", "what-if: 24-bit unorm z01",
    "what-if: 24-bit unorm near/w (reversed-z)",
};
#define DEPTH_ENCODING_COUNT 5
#define DEPTH_PIPELINE_COUNT 2
static const ras_depth_format DEPTH_FORMATS[DEPTH_PIPELINE_COUNT] = {RAS_DEPTH_Z01,
                                                                     RAS_DEPTH_INV_W};

/* The pipeline's depth of view distance d: (1 − z_ndc)/2 of the GAMES101
 * projection, i.e. f(d − n) / (d (f − n)). */
static double depth01(double d) { return DEPTH_FAR * (d - Z_NEAR) / (d * (DEPTH_FAR - Z_NEAR)); }

/* A plane tilted away from the camera: view depth 30 at the bottom of the
 * screen to 49 at the top, overscanned; `shift` moves it farther along -z. */
static quad depth_plane(double shift) {
    double t = tan(FOV_DEG * RAS_PI / 360.0), d0 = 30, d1 = 49, o = 1.1;
    quad q = {.p = {{-o * d0 * t, -o * d0 * t, -d0 - shift},
                    {o * d0 * t, -o * d0 * t, -d0 - shift},
                    {o * d1 * t, o * d1 * t, -d1 - shift},
                    {-o * d1 * t, o * d1 * t, -d1 - shift}}};
    return q;
}

static void depth_precision(void) {
    const int size = S.quick ? 96 : 256;
    mat4s proj = get_projection_matrix(FOV_DEG, 1, Z_NEAR, (float)DEPTH_FAR);
    ras_image *img[DEPTH_PIPELINE_COUNT];
    for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++) {
        img[e] = ras_image_create(size, size, NULL);
        die_oom(img[e]);
    }
    for (int di = 0; di < DELTA_COUNT; di++) {
        double delta = DELTAS[di];
        char scene[40];
        snprintf(scene, sizeof scene, "delta = %g", delta);
        quad qa = depth_plane(0), qb = depth_plane(delta);
        ras_mesh *near = quad_mesh(&qa), *far = quad_mesh(&qb);
        for (int i = 0; i < 4; i++) {
            near->colors[i] = (vec3s){{1, 0, 0}};
            far->colors[i] = (vec3s){{0, 0, 1}};
        }
        /* The farther plane first: on a tie the nearer one (drawn second)
         * fails the "less than" test — the case that shows the precision. */
        ras_mesh *order[2] = {far, near};
        progress("depth / %s", scene);
        /* Both formats timed in one group (interleaved frame by frame), so
         * their time ratio survives load on the machine. */
        timed t[DEPTH_PIPELINE_COUNT];
        for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++) {
            ras_pipeline *p =
                make_pipeline(size, size, RAS_AA_NONE, RAS_PATTERN_ORDERED, 1, rasterize_triangle,
                              RAS_VARYING_COLOR, NULL, NULL, (vec3s){{0, 0, 0}});
            /* make_pipeline builds z01; the format is a field of the config
             * that ras_pipeline_create copies, so rebuild with it set. */
            if (DEPTH_FORMATS[e] != RAS_DEPTH_Z01) {
                ras_pipeline_config cfg = p->config;
                cfg.depth = DEPTH_FORMATS[e];
                cfg.z_near = Z_NEAR;
                ras_pipeline_destroy(p);
                ras_error err = {{0}};
                p = ras_pipeline_create(&cfg, &err);
                if (!p) {
                    fprintf(stderr, "bench_accuracy: %s\n", err.msg);
                    exit(2);
                }
            }
            t[e].f = (mesh_frame){.p = p,
                                  .meshes = order,
                                  .mesh_count = 2,
                                  .view = *identity(),
                                  .projection = proj,
                                  .img = img[e]};
            t[e].r = new_row("depth", scene, DEPTH_ENCODINGS[e]);
        }
        time_group(t, DEPTH_PIPELINE_COUNT);
        for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++)
            draw_mesh_frame(&t[e].f);
        long wrong_e[DEPTH_ENCODING_COUNT] = {0}, n = 0;
        for (int y = 0; y < size; y++)
            for (int x = 0; x < size; x++) {
                double d[3], da, db, uv[2];
                pixel_ray(x, y, 0.5, 0.5, size, d);
                if (!quad_hit(&qa, d, &da, uv) || !quad_hit(&qb, d, &db, uv)) continue;
                n++;
                for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++) {
                    vec3s c = img[e]->pixels[(size - 1 - y) * size + x];
                    wrong_e[e] += c.z > c.x;
                }
                /* What-ifs from the exact depths: the nearer must be strictly
                 * better after storage rounding (ties go to the first drawn). */
                float za = (float)depth01(da), zb = (float)depth01(db);
                wrong_e[2] += !(za < zb);
                double qa24 = llround(depth01(da) * 16777215.0), qb24 = llround(depth01(db) * 16777215.0);
                wrong_e[3] += !(qa24 < qb24);
                double ra24 = llround(Z_NEAR / da * 16777215.0),
                       rb24 = llround(Z_NEAR / db * 16777215.0);
                wrong_e[4] += !(ra24 > rb24);
            }
        for (int e = 0; e < DEPTH_ENCODING_COUNT; e++) {
            row *re =
                e < DEPTH_PIPELINE_COUNT ? t[e].r : new_row("depth", scene, DEPTH_ENCODINGS[e]);
            re->wrong = n ? (double)wrong_e[e] / n : NAN;
        }
        for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++)
            ras_pipeline_destroy(t[e].f.p);
        ras_mesh_destroy(near), ras_mesh_destroy(far);
    }
    for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++)
        ras_image_destroy(img[e]);
}

/* ---- checks on the AA section -------------------------------------------------- */

static void check_aa(void) {
    for (int i = 0; i < row_count; i++) {
        if (strcmp(rows[i].section, "aa") || strcmp(rows[i].option, AA_OPTIONS[0].name)) continue;
        const char *scene = rows[i].scene;
        bool thin = !strncmp(scene, "thin", 4);
        static const char *const ordered[4] = {"none (1 sample)", "MSAA ordered 2x2",
                                               "MSAA ordered 4x4", "MSAA ordered 8x8"};
        static const char *const standard[5] = {"none (1 sample)", "MSAA standard 2x",
                                                "MSAA standard 4x", "MSAA standard 8x",
                                                "MSAA standard 16x"};
        /* Thin triangles have edges at every angle: every step must help. The
         * hw2 scene has six edges, so only big steps are asserted. */
        for (int k = 1; k < 4; k++) {
            row *a = find_row("aa", scene, ordered[thin ? k - 1 : 0]), *b = find_row("aa", scene, ordered[k]);
            if (!thin && k != 3) continue;
            check(b->rmse_edge < a->rmse_edge, "aa %s: edge RMSE %s %.4f < %s %.4f", scene,
                  b->option, b->rmse_edge, a->option, a->rmse_edge);
        }
        for (int k = 1; k < 5; k++) {
            if (!thin && k != 2 && k != 4) continue;
            row *a = find_row("aa", scene, standard[thin ? k - 1 : k - 2]);
            row *b = find_row("aa", scene, standard[k]);
            check(b->rmse_edge < a->rmse_edge, "aa %s: edge RMSE %s %.4f < %s %.4f", scene,
                  b->option, b->rmse_edge, a->option, a->rmse_edge);
        }
        for (int k = 1; k < AA_OPTION_COUNT; k++) {
            if (AA_OPTIONS[k].aa != RAS_AA_MSAA) continue;
            char ss[48];
            snprintf(ss, sizeof ss, "SSAA%s", AA_OPTIONS[k].name + 4);
            row *m = find_row("aa", scene, AA_OPTIONS[k].name), *s = find_row("aa", scene, ss);
            check(fabs(m->rmse_edge - s->rmse_edge) < 1e-3,
                  "aa %s: flat colours, so %s and %s agree (%.4f vs %.4f)", scene, m->option,
                  s->option, m->rmse_edge, s->rmse_edge);
        }
    }
}

static void check_edges(void) {
    for (int i = 0; i < row_count; i++) {
        if (strcmp(rows[i].section, "edges") || strncmp(rows[i].option, "fixed", 5)) continue;
        check(rows[i].cracks == 0 && rows[i].doubles == 0,
              "edges %s: fixed point has no cracks (%.0f) and no double hits (%.0f)",
              rows[i].scene, rows[i].cracks, rows[i].doubles);
    }
}

static void check_depth(void) {
    double prev = INFINITY;
    for (int di = 0; di < DELTA_COUNT; di++) {
        char scene[40];
        snprintf(scene, sizeof scene, "delta = %g", DELTAS[di]);
        row *p = find_row("depth", scene, DEPTH_ENCODINGS[0]);
        row *inv = find_row("depth", scene, DEPTH_ENCODINGS[1]);
        check(p->wrong <= prev + 0.02, "depth %s: wrong fraction %.4f does not grow with the gap",
              scene, p->wrong);
        check(inv->wrong <= p->wrong,
              "depth %s: pipeline inverse_w wrong fraction (%.4f) <= pipeline z01 (%.4f)", scene,
              inv->wrong, p->wrong);
        prev = p->wrong;
    }
    /* The point of inverse_w: the smallest gap resolves where z01 fails. */
    row *z_small = find_row("depth", "delta = 0.0001", DEPTH_ENCODINGS[0]);
    row *i_small = find_row("depth", "delta = 0.0001", DEPTH_ENCODINGS[1]);
    check(i_small->wrong < 0.01 && z_small->wrong > 0.5,
          "depth delta = 0.0001: inverse_w resolves (%.4f wrong), z01 does not (%.4f wrong)",
          i_small->wrong, z_small->wrong);
    row *big = find_row("depth", "delta = 0.1", DEPTH_ENCODINGS[0]);
    check(big->wrong < 0.01, "depth delta = 0.1: the pipeline resolves (%.4f wrong)", big->wrong);
}

/* ---- section 5b: inverse_w's order at every distance and tilt -------------------- */

/* Two parallel planes z = -D - y·tan(tilt) in view space (the eye at the
 * origin, fov FOV_DEG, near ORDER_NEAR, far ORDER_FAR), the second one a
 * relative gap farther (D = d·(1 + gap)) and drawn first, in inverse_w,
 * 64x64 (--quick) or 128x128 pixels.
 * "Before" builds each clipped triangle's depth the way setup did until
 * issue #27 (-near/w of each unsnapped corner: ras_viewport_depth) and
 * hands it to the pipeline's stage 4; "after" is the pipeline as it is
 * (stage3_setup.c carries the rasterizer's snap into depth). The bound is
 * the exact depth, at the sample, of each quad as the pipeline is given it
 * (its float clip-space corners, solved in double), rounded once to float:
 * what no arithmetic after the vertex stage can beat. The two quads are
 * turned differently about the view axis, as two meshes would be: their
 * corners snap differently. Counted: samples both quads cover where the
 * farther wins. */
static const double ORDER_DIST[] = {1, 10, 100, 1000};
static const double ORDER_TILT[] = {0, 30, 45, 60, 75, 85};
static const double ORDER_GAP[] = {1e-7, 1.4e-7, 3e-7, 1e-6, 4e-6};
#define ORDER_D 4
#define ORDER_T 6
#define ORDER_G 5
#define ORDER_NEAR 0.1
#define ORDER_FAR 1e6
enum { ORDER_BEFORE, ORDER_AFTER, ORDER_ROUNDED, ORDER_KINDS };
static double order_frac[ORDER_KINDS][ORDER_G][ORDER_D][ORDER_T];

typedef struct order_plane {
    ras_clip_vertex v[4]; /* a quad, drawn as (0,1,2) and (0,2,3) */
} order_plane;

/* The quad of plane z = -D - y·tan(tilt): a square in (x, y), turned by
 * `turn` degrees about the view axis (so that two planes' corners, and
 * their snapping, differ as two meshes' would), large enough to cover the
 * frame up to 4 D ahead (farther, the float corners of a steep plane would
 * no longer describe it to a 1e-7 of its distance). */
static order_plane order_make_plane(mat4s mvp, double D, double tilt_deg, double turn_deg,
                                    vec3s color) {
    double t = tan(FOV_DEG * RAS_PI / 360.0), tn = tan(tilt_deg * RAS_PI / 180.0);
    double s_top = t * tn < 0.95 ? fmin(D / (1 - t * tn), 4 * D) : 4 * D;
    double y_lo = -t * D / (1 + t * tn), y_hi = tn > 0 ? (s_top - D) / tn : t * D;
    double cx = 0, cy = (y_lo + y_hi) / 2;
    double half = 1.6 * fmax(t * s_top, (y_hi - y_lo) / 2);
    double c = cos(turn_deg * RAS_PI / 180.0), sn = sin(turn_deg * RAS_PI / 180.0);
    const double sq[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    order_plane q;
    for (int i = 0; i < 4; i++) {
        double u = sq[i][0] * half, v = sq[i][1] * half;
        double x = cx + c * u - sn * v, y = cy + sn * u + c * v, z = -D - y * tn;
        vec4s p = {{(float)x, (float)y, (float)z, 1.0f}};
        q.v[i] = (ras_clip_vertex){
            .p_clip = glms_mat4_mulv(mvp, p), .color = color, .normal = {{0, 0, 1}}};
    }
    return q;
}

/* w of the point of clip-space triangle (a, b, c) that projects to NDC
 * (xn, yn), exactly (a 3x3 solve in double on the float corners); 0 when the
 * point is outside the triangle. */
static double order_clip_hit(vec4s a, vec4s b, vec4s c, double xn, double yn) {
    /* λa + μb + νc with λ + μ + ν = 1: x - xn·w = 0 and y - yn·w = 0 */
    const vec4s v[3] = {a, b, c};
    double r0[3], r1[3];
    for (int i = 0; i < 3; i++) {
        r0[i] = (double)v[i].x - xn * v[i].w;
        r1[i] = (double)v[i].y - yn * v[i].w;
    }
    /* rows: r0·λ = 0, r1·λ = 0, (1,1,1)·λ = 1 → λ ∝ r0 × r1 */
    double l[3] = {r0[1] * r1[2] - r0[2] * r1[1], r0[2] * r1[0] - r0[0] * r1[2],
                   r0[0] * r1[1] - r0[1] * r1[0]};
    double sum = l[0] + l[1] + l[2];
    if (sum == 0) return 0;
    for (int i = 0; i < 3; i++) {
        l[i] /= sum;
        if (l[i] < 0) return 0;
    }
    return l[0] * v[0].w + l[1] * v[1].w + l[2] * v[2].w;
}

/* Stage 2 + the old stage 3 (per-corner -near/w) + the pipeline's stage 4. */
static void order_draw_before(ras_pipeline *p, const ras_clip_vertex *a,
                              const ras_clip_vertex *b, const ras_clip_vertex *c) {
    ras_clip_vertex poly[RAS_CLIP_MAX_VERTICES];
    int n = 0;
    if (ras_clip_triangle(a, b, c, poly, &n) == RAS_CLIP_OUTSIDE) return;
    for (int i = 1; i + 1 < n; i++) {
        const ras_clip_vertex *in[3] = {&poly[0], &poly[i], &poly[i + 1]};
        ras_triangle t = {0};
        for (int k = 0; k < 3; k++) {
            t.v[k] = ras_viewport_depth(in[k]->p_clip, p->fb->width, p->fb->height,
                                        RAS_DEPTH_INV_W, (float)ORDER_NEAR);
            t.color[k] = in[k]->color;
        }
        ras_pipeline_draw_screen_triangle(p, &t);
    }
}

static void order_draw(ras_pipeline *p, const order_plane *q, bool before) {
    const ras_clip_vertex *v = q->v;
    if (before) {
        order_draw_before(p, &v[0], &v[1], &v[2]);
        order_draw_before(p, &v[0], &v[2], &v[3]);
    } else {
        ras_pipeline_draw_clip_triangle(p, &v[0], &v[1], &v[2]);
        ras_pipeline_draw_clip_triangle(p, &v[0], &v[2], &v[3]);
    }
}

static ras_pipeline *order_pipeline(int size) {
    ras_pipeline_config cfg = {.width = size, .height = size, .rasterize = rasterize_triangle,
                               .resolve = resolve_pixel, .depth = RAS_DEPTH_INV_W,
                               .z_near = (float)ORDER_NEAR, .varyings = RAS_VARYING_COLOR};
    ras_pipeline *p = ras_pipeline_create(&cfg, NULL);
    die_oom(p);
    return p;
}

/* -near/w of the quad at screen (sx, sy): exact for its clip-space corners
 * (what the pipeline is given), rounded once; NAN when it misses. */
static float order_exact_depth(const order_plane *q, double sx, double sy, int size) {
    double xn = 2 * sx / size - 1, yn = 2 * sy / size - 1;
    const ras_clip_vertex *v = q->v;
    double w = order_clip_hit(v[0].p_clip, v[1].p_clip, v[2].p_clip, xn, yn);
    if (!(w > 0)) w = order_clip_hit(v[0].p_clip, v[2].p_clip, v[3].p_clip, xn, yn);
    return w > 0 ? (float)(-(double)(float)ORDER_NEAR / w) : NAN;
}

static void depth_order(void) {
    const int size = S.quick ? 64 : 128;
    mat4s proj = ras_projection_normalize_w(
        get_projection_matrix(FOV_DEG, 1, (float)ORDER_NEAR, (float)ORDER_FAR));
    mat4s mvp = glms_mat4_mul(proj, ras_view_matrix_eye((vec3s){{0, 0, 0}}));
    ras_pipeline *mask_near = order_pipeline(size), *mask_far = order_pipeline(size);
    ras_pipeline *both[2] = {order_pipeline(size), order_pipeline(size)};
    const vec3s red = {{1, 0, 0}}, blue = {{0, 0, 1}};
    progress("depth order (inverse_w): %d distances x %d tilts x %d gaps", ORDER_D, ORDER_T,
             ORDER_G);
    for (int gi = 0; gi < ORDER_G; gi++)
        for (int di = 0; di < ORDER_D; di++)
            for (int ti = 0; ti < ORDER_T; ti++) {
                double d = ORDER_DIST[di], D = d * (1 + ORDER_GAP[gi]);
                order_plane nearq = order_make_plane(mvp, d, ORDER_TILT[ti], 0, red);
                order_plane farq = order_make_plane(mvp, D, ORDER_TILT[ti], 37, blue);
                ras_pipeline_begin_frame(mask_near);
                ras_pipeline_begin_frame(mask_far);
                order_draw(mask_near, &nearq, false);
                order_draw(mask_far, &farq, false);
                for (int k = 0; k < 2; k++) {
                    ras_pipeline_begin_frame(both[k]);
                    order_draw(both[k], &farq, k == ORDER_BEFORE);
                    order_draw(both[k], &nearq, k == ORDER_BEFORE);
                }
                long counted = 0, wrong[ORDER_KINDS] = {0};
                for (int y = 0; y < size; y++)
                    for (int x = 0; x < size; x++) {
                        int i = ras_fb_sample_index(mask_near->fb, x, y, 0);
                        if (mask_near->fb->depth[i] == INFINITY ||
                            mask_far->fb->depth[i] == INFINITY)
                            continue;
                        counted++;
                        for (int k = 0; k < 2; k++) wrong[k] += both[k]->fb->color[i].z > 0.5f;
                        float zn = order_exact_depth(&nearq, x + 0.5, y + 0.5, size);
                        float zf = order_exact_depth(&farq, x + 0.5, y + 0.5, size);
                        wrong[ORDER_ROUNDED] += !(zn < zf);
                    }
                for (int k = 0; k < ORDER_KINDS; k++)
                    order_frac[k][gi][di][ti] = counted ? (double)wrong[k] / counted : NAN;
            }
    ras_pipeline_destroy(mask_near);
    ras_pipeline_destroy(mask_far);
    ras_pipeline_destroy(both[0]);
    ras_pipeline_destroy(both[1]);
}

/* The worst fraction of kind k at gap gi over all distances and tilts, and
 * where it is; the number of (distance, tilt) cells with any inversion. */
static double order_worst(int k, int gi, int *wd, int *wt, int *cells) {
    double worst = 0;
    *wd = *wt = 0;
    *cells = 0;
    for (int di = 0; di < ORDER_D; di++)
        for (int ti = 0; ti < ORDER_T; ti++) {
            double f = order_frac[k][gi][di][ti];
            *cells += f > 0;
            if (f > worst) worst = f, *wd = di, *wt = ti;
        }
    return worst;
}

/* Over all distances and tilts at gap gi: the mean fraction of kind k, and
 * the worst excess of kind k over the bound (the pipeline's own loss, beyond
 * what its float input already loses) with its cell. */
static double order_mean(int k, int gi) {
    double sum = 0;
    for (int di = 0; di < ORDER_D; di++)
        for (int ti = 0; ti < ORDER_T; ti++) sum += order_frac[k][gi][di][ti];
    return sum / (ORDER_D * ORDER_T);
}

static double order_excess(int k, int gi, int *wd, int *wt, int *cells) {
    double worst = 0;
    *wd = *wt = 0;
    *cells = 0;
    for (int di = 0; di < ORDER_D; di++)
        for (int ti = 0; ti < ORDER_T; ti++) {
            double e = order_frac[k][gi][di][ti] - order_frac[ORDER_ROUNDED][gi][di][ti];
            *cells += e > 0;
            if (e > worst) worst = e, *wd = di, *wt = ti;
        }
    return worst;
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
                fprintf(f, " %.2f%% (%g, %g°), %d of %d |", 100 * e, ORDER_DIST[wd],
                        ORDER_TILT[wt], cells, ORDER_D * ORDER_T);
            else
                fprintf(f, " 0.00%%, 0 of %d |", ORDER_D * ORDER_T);
        }
        fprintf(f, "\n");
    }
}

static void check_depth_order(void) {
    /* inverse_w loses order only where its float input already does, at
     * every gap from 1e-6 on, and it never does worse than before. */
    for (int gi = 0; gi < ORDER_G; gi++) {
        int wd, wt, cells;
        double e = order_excess(ORDER_AFTER, gi, &wd, &wt, &cells);
        if (ORDER_GAP[gi] >= 1e-6)
            check(e <= 0.01, "depth order gap %g: inverse_w inverts %.4f more of the samples "
                             "than its input's exact depths at distance %g, tilt %g",
                  ORDER_GAP[gi], e, ORDER_DIST[wd], ORDER_TILT[wt]);
        if (ORDER_GAP[gi] >= 3e-7)
            check(order_mean(ORDER_AFTER, gi) <= order_mean(ORDER_BEFORE, gi),
              "depth order gap %g: after (%.4f mean) worse than before (%.4f)", ORDER_GAP[gi],
              order_mean(ORDER_AFTER, gi), order_mean(ORDER_BEFORE, gi));
    }
}

/* ---- output: text helpers ---------------------------------------------------- */

static void fmt_ms(double v, char *buf, size_t n) {
    if (!isfinite(v)) snprintf(buf, n, "—");
    else if (v < 1) snprintf(buf, n, "%.3f", v);
    else if (v < 100) snprintf(buf, n, "%.2f", v);
    else snprintf(buf, n, "%.0f", v);
}

static void fmt_bytes(double b, char *buf, size_t n) {
    if (!isfinite(b)) snprintf(buf, n, "—");
    else if (b >= 1 << 20) snprintf(buf, n, "%.1f MiB", b / (1 << 20));
    else snprintf(buf, n, "%.0f KiB", b / 1024);
}

static void fmt_g(double v, const char *f, char *buf, size_t n) {
    if (isnan(v)) snprintf(buf, n, "—");
    else if (isinf(v)) snprintf(buf, n, "∞");
    else snprintf(buf, n, f, v);
}

/* "12.3 (11.9–13.0)" */
static void fmt_time(const row *r, char *buf, size_t n) {
    char a[20], b[20], c[20];
    fmt_ms(r->med, a, sizeof a), fmt_ms(r->min, b, sizeof b), fmt_ms(r->max, c, sizeof c);
    if (isfinite(r->med)) snprintf(buf, n, "%s (%s–%s)", a, b, c);
    else snprintf(buf, n, "—");
}

static void machine(char *buf, size_t n) {
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

/* ---- output: charts -------------------------------------------------------------- */

static const vec3s COLORS[] = {{{0.35f, 0.75f, 1.0f}}, {{1.0f, 0.62f, 0.25f}}, {{0.45f, 0.9f, 0.45f}},
                               {{1.0f, 0.4f, 0.5f}}, {{0.8f, 0.6f, 1.0f}}};

static void range_of(const double *v, int n, double *lo, double *hi) {
    *lo = INFINITY, *hi = -INFINITY;
    for (int i = 0; i < n; i++)
        if (isfinite(v[i]) && v[i] > 0) *lo = fmin(*lo, v[i]), *hi = fmax(*hi, v[i]);
}

static bool chart_aa(const char *scene, const char *path, ras_error *err) {
    static const struct {
        const char *prefix, *legend;
        int n;
        const char *names[5];
        const char *labels[5];
    } fam[4] = {
        {"MSAA", "MSAA ordered", 4, {"none (1 sample)", "MSAA ordered 2x2", "MSAA ordered 4x4", "MSAA ordered 8x8"}, {"", "2x2", "4x4", "8x8"}},
        {"MSAA", "MSAA standard", 5, {"none (1 sample)", "MSAA standard 2x", "MSAA standard 4x", "MSAA standard 8x", "MSAA standard 16x"}, {"", "2x", "4x", "8x", "16x"}},
        {"SSAA", "SSAA ordered", 4, {"none (1 sample)", "SSAA ordered 2x2", "SSAA ordered 4x4", "SSAA ordered 8x8"}, {"", "2x2", "4x4", "8x8"}},
        {"SSAA", "SSAA standard", 5, {"none (1 sample)", "SSAA standard 2x", "SSAA standard 4x", "SSAA standard 8x", "SSAA standard 16x"}, {"", "2x", "4x", "8x", "16x"}},
    };
    double xs[4][5], ys[4][5], all_x[20], all_y[20];
    int m = 0;
    for (int f = 0; f < 4; f++)
        for (int i = 0; i < fam[f].n; i++) {
            row *r = find_row("aa", scene, fam[f].names[i]);
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

static bool chart_interp(const char *path, ras_error *err) {
    double k[4], meas[4], formula_k[64], formula_v[64], persp[4];
    static const double ks[4] = {1.1, 2, 4, 8};
    for (int i = 0; i < 4; i++) {
        char scene[40];
        snprintf(scene, sizeof scene, "w1/w0 = %g", ks[i]);
        row *a = find_row("interp", scene, "affine (screen-space)");
        row *pc = find_row("interp", scene, "perspective-correct");
        k[i] = ks[i];
        meas[i] = a ? a->v_max : NAN;
        persp[i] = pc ? fmax(pc->v_max, 1e-7) : NAN;
    }
    for (int i = 0; i < 64; i++) {
        formula_k[i] = 1.05 * pow(10 / 1.05, i / 63.0);
        double s = sqrt(formula_k[i]);
        formula_v[i] = (s - 1) / (s + 1);
    }
    bench_plot *p = bench_plot_create(860, 500, "Interpolation: worst v error vs depth ratio",
                                      "w1 / w0 (log)", "worst |v error| / v range (log)", 1.05, 10,
                                      true, 1e-6, 1, true, err);
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

static bool chart_filter(const char *path, ras_error *err) {
    double xs[2][3], ys[2][3], all_x[6], all_y[6];
    int m = 0, s = 0;
    char scenes[2][40];
    for (int i = 0; i < row_count && s < 2; i++)
        if (!strcmp(rows[i].section, "filter") && !strcmp(rows[i].option, "nearest"))
            snprintf(scenes[s++], 40, "%s", rows[i].scene);
    static const char *names[3] = {"nearest", "bilinear", "trilinear"};
    for (int t = 0; t < s; t++)
        for (int f = 0; f < 3; f++) {
            row *r = find_row("filter", scenes[t], names[f]);
            xs[t][f] = r ? r->rel : NAN;
            ys[t][f] = r ? r->rmse_all : NAN;
            all_x[m] = xs[t][f], all_y[m++] = ys[t][f];
        }
    double x0, x1, y0, y1;
    range_of(all_x, m, &x0, &x1);
    range_of(all_y, m, &y0, &y1);
    bench_plot *p = bench_plot_create(860, 500, "Texture filtering: error vs time on a receding floor",
                                      "time per frame, x the cheapest (log)", "RMSE vs truth (log)",
                                      x0 / 1.15, x1 * 1.5, true, y0 / 1.5, y1 * 1.5, true, err);
    if (!p) return false;
    for (int t = 0; t < s; t++) {
        bench_plot_series(p, xs[t], ys[t], 3, COLORS[t], true, true, scenes[t]);
        for (int f = 0; f < 3; f++) bench_plot_text(p, xs[t][f], ys[t][f], names[f]);
    }
    bool ok = bench_plot_save(p, path, err);
    bench_plot_destroy(p);
    return ok;
}

/* ---- output: CSV, Markdown, stdout --------------------------------------------------- */

static void csv_num(FILE *f, double v) {
    if (isnan(v)) fputs(",", f);
    else fprintf(f, ",%.6g", v);
}

static bool write_csv(const char *path) {
    ras_io_report report; /* written whole or not at all (ras_io.h) */
    FILE *f = ras_io_report_open(&report);
    if (!f) return false;
    fputs("section,scene,option,samples,time_ms_median,time_ms_min,time_ms_max,time_rel,"
          "rmse_all,psnr_all_db,rmse_edge,psnr_edge_db,cracks,double_hits,"
          "worst_v_error,formula,uv_max_texels,uv_rms_texels,wrong_fraction,buffer_bytes\n", f);
    for (int i = 0; i < row_count; i++) {
        const row *r = &rows[i];
        fprintf(f, "%s,\"%s\",\"%s\",%d", r->section, r->scene, r->option, r->samples);
        double v[] = {r->med, r->min, r->max, r->rel, r->rmse_all, r->psnr_all, r->rmse_edge,
                      r->psnr_edge, r->cracks, r->doubles, r->v_max, r->formula,
                      r->uv_max_texels, r->uv_rms_texels, r->wrong, r->bytes};
        for (size_t k = 0; k < sizeof v / sizeof v[0]; k++) csv_num(f, v[k]);
        fputc('\n', f);
    }
    return ras_io_report_commit(&report, path, NULL);
}

static void scenes_of(const char *section, char out[][40], int *n, int max) {
    *n = 0;
    for (int i = 0; i < row_count; i++) {
        if (strcmp(rows[i].section, section)) continue;
        bool seen = false;
        for (int k = 0; k < *n; k++) seen = seen || !strcmp(out[k], rows[i].scene);
        if (!seen && *n < max) snprintf(out[(*n)++], 40, "%s", rows[i].scene);
    }
}

static void table_aa(FILE *f, const char *scene) {
    fprintf(f, "\n**%s**\n\n", scene);
    fprintf(f, "| option | samples | ms/frame median (min–max) | × time | RMSE all | PSNR all dB | "
               "RMSE edge | PSNR edge dB | buffers |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < row_count; i++) {
        const row *r = &rows[i];
        if (strcmp(r->section, "aa") || strcmp(r->scene, scene)) continue;
        char t[80], b[32];
        fmt_time(r, t, sizeof t), fmt_bytes(r->bytes, b, sizeof b);
        fprintf(f, "| %s | %d | %s | %.2f | %.4f | %.1f | %.4f | %.1f | %s |\n", r->option,
                r->samples, t, r->rel, r->rmse_all, r->psnr_all, r->rmse_edge, r->psnr_edge, b);
    }
}

static void table_edges(FILE *f) {
    fprintf(f, "| scene | edge functions | ms/frame median (min–max) | × time | cracks | double hits | buffers |\n"
               "|---|---|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < row_count; i++) {
        const row *r = &rows[i];
        if (strcmp(r->section, "edges")) continue;
        char t[80], b[32];
        fmt_time(r, t, sizeof t), fmt_bytes(r->bytes, b, sizeof b);
        fprintf(f, "| %s | %s | %s | %.2f | %.0f | %.0f | %s |\n", r->scene, r->option, t, r->rel,
                r->cracks, r->doubles, b);
    }
}

static void table_interp(FILE *f) {
    fprintf(f, "| depth ratio | interpolation | ms/frame median (min–max) | × time | worst v error "
               "(of the v range) | formula (√k−1)/(√k+1) | worst \\|Δuv\\| texels | RMS \\|Δuv\\| texels |\n"
               "|---|---|---:|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < row_count; i++) {
        const row *r = &rows[i];
        if (strcmp(r->section, "interp")) continue;
        char t[80], a[32], b[32], c[32];
        fmt_time(r, t, sizeof t);
        fmt_g(r->v_max, "%.2g", a, sizeof a), fmt_g(r->uv_max_texels, "%.3g", b, sizeof b);
        fmt_g(r->uv_rms_texels, "%.3g", c, sizeof c);
        fprintf(f, "| %s | %s | %s | %.2f | %s | %.4f | %s | %s |\n", r->scene, r->option, t, r->rel,
                a, r->formula, b, c);
    }
}

static void table_filter(FILE *f) {
    fprintf(f, "| scene | filter | ms/frame median (min–max) | × time | RMSE | PSNR dB | buffers |\n"
               "|---|---|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < row_count; i++) {
        const row *r = &rows[i];
        if (strcmp(r->section, "filter")) continue;
        char t[80], b[32];
        fmt_time(r, t, sizeof t), fmt_bytes(r->bytes, b, sizeof b);
        fprintf(f, "| %s | %s | %s | %.2f | %.4f | %.1f | %s |\n", r->scene, r->option, t, r->rel,
                r->rmse_all, r->psnr_all, b);
    }
}

/* The δ whose frame times the table shows: one where both formats get every
 * pixel right, so both do the same work. Where z01 is wrong, the nearer
 * plane fails the depth test and is never written: the wrong answer is
 * cheaper, and the time ratio there measures that, not the format. */
#define DEPTH_TIME_SCENE "delta = 0.01"

/* Wrong fractions per δ; the pipeline rows also get their time at
 * DEPTH_TIME_SCENE (the two formats interleaved, × time against the faster). */
static void table_depth(FILE *f) {
    fprintf(f, "| depth encoding |");
    for (int d = 0; d < DELTA_COUNT; d++) fprintf(f, " δ = %g |", DELTAS[d]);
    fprintf(f, " ms/frame median (min–max), δ = 0.01 | × time |\n|---|");
    for (int d = 0; d < DELTA_COUNT; d++) fprintf(f, "---:|");
    fprintf(f, "---:|---:|\n");
    for (int e = 0; e < DEPTH_ENCODING_COUNT; e++) {
        fprintf(f, "| %s |", DEPTH_ENCODINGS[e]);
        for (int d = 0; d < DELTA_COUNT; d++) {
            char scene[40];
            snprintf(scene, sizeof scene, "delta = %g", DELTAS[d]);
            row *r = find_row("depth", scene, DEPTH_ENCODINGS[e]);
            fprintf(f, " %.2f%% |", r ? 100 * r->wrong : NAN);
        }
        row *r = find_row("depth", DEPTH_TIME_SCENE, DEPTH_ENCODINGS[e]);
        char t[80];
        if (r && isfinite(r->med)) {
            fmt_time(r, t, sizeof t);
            fprintf(f, " %s | %.2f |\n", t, r->rel);
        } else {
            fprintf(f, " untimed | — |\n");
        }
    }
}

/* The time ratio inverse_w / z01 (fastest frames), min and max over the δ
 * from `first` on. */
static void depth_time_ratio_range(int first, double *lo, double *hi) {
    *lo = INFINITY, *hi = -INFINITY;
    for (int d = first; d < DELTA_COUNT; d++) {
        char scene[40];
        snprintf(scene, sizeof scene, "delta = %g", DELTAS[d]);
        row *z = find_row("depth", scene, DEPTH_ENCODINGS[0]);
        row *i = find_row("depth", scene, DEPTH_ENCODINGS[1]);
        if (!z || !i || !(z->min > 0)) continue;
        double q = i->min / z->min;
        *lo = fmin(*lo, q), *hi = fmax(*hi, q);
    }
}

static bool write_markdown(const char *path, const char *machine_name, const char *date,
                           double total_s) {
    ras_io_report report; /* written whole or not at all (ras_io.h) */
    FILE *f = ras_io_report_open(&report);
    if (!f) return false;
    char aa_scenes[4][40], sc[8][40];
    int n_aa, n;
    scenes_of("aa", aa_scenes, &n_aa, 4);
    fprintf(f, "# What accuracy costs: a measured report\n\n"
               "Generated by `make bench-accuracy` (`tests/bench/bench_accuracy.c`) — do not edit by hand; "
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
            total_s, S.quick ? " (**--quick**: small images, few repeats)" : "", S.repeats);

    /* ---- AA ---- */
    fprintf(f, "\n## 1. Anti-aliasing: coverage error vs samples\n\n"
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
        row *none = find_row("aa", thin, "none (1 sample)");
        row *m4 = find_row("aa", thin, "MSAA standard 4x"), *s4 = find_row("aa", thin, "SSAA standard 4x");
        row *m16 = find_row("aa", thin, "MSAA standard 16x"), *s16 = find_row("aa", thin, "SSAA standard 16x");
        row *o4 = find_row("aa", thin, "MSAA ordered 2x2"), *m8 = find_row("aa", thin, "MSAA standard 8x");
        row *o64 = find_row("aa", thin, "MSAA ordered 8x8"), *s64 = find_row("aa", thin, "SSAA ordered 8x8");
        char mem64[32], mem1[32];
        fmt_bytes(o64->bytes, mem64, sizeof mem64), fmt_bytes(none->bytes, mem1, sizeof mem1);
        fprintf(f, "\n**What it means.** On the thin triangles, MSAA 4x (standard pattern) buys "
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
                psnr(m4->rmse_edge) - psnr(none->rmse_edge), none->rmse_edge, m4->rmse_edge, m4->rel,
                s4->rel, psnr(m16->rmse_edge) - psnr(none->rmse_edge), m16->rel, s16->rel,
                psnr(o64->rmse_edge) - psnr(none->rmse_edge), o64->rel, s64->rel,
                mem64, mem1);
        fprintf(f, "\n**Against the numbers quoted in DESIGN.md** (edge-pixel RMSE vs exact area, "
                   "measured there on other scenes):\n\n"
                   "| samples | DESIGN.md | thin triangles | hw2 scene |\n|---|---:|---:|---:|\n");
        static const struct {
            const char *name, *expected;
        } cmp[] = {{"none (1 sample)", "0.25"}, {"MSAA ordered 2x2", "0.088"},
                   {"MSAA standard 4x", "0.094 (0.079 near-axis)"}, {"MSAA standard 8x", "0.059"},
                   {"MSAA standard 16x", "0.03–0.045"}, {"MSAA ordered 8x8", "—"}};
        for (size_t i = 0; i < sizeof cmp / sizeof cmp[0]; i++) {
            row *a = find_row("aa", thin, cmp[i].name);
            row *b = n_aa > 1 ? find_row("aa", aa_scenes[1], cmp[i].name) : NULL;
            fprintf(f, "| %s | %s | %.3f | %s%.3f |\n", cmp[i].name, cmp[i].expected,
                    a ? a->rmse_edge : NAN, b ? "" : "—", b ? b->rmse_edge : NAN);
        }
        fprintf(f, "\nOn the thin triangles, 1 sample gives %.3f, 2x2 ordered %.3f and 8x %.3f. "
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

    /* ---- edges ---- */
    scenes_of("edges", sc, &n, 8);
    fprintf(f, "\n## 2. Edge precision: float vs fixed-point edge functions\n\n"
               "Every triangle of a closed mesh is drawn with SSAA 2x2 (4 samples per pixel) and "
               "each one slightly nearer than the last, so *every* triangle that covers a sample "
               "reaches the shader there; a counting shader records how many did. Inside the "
               "union of the triangles every sample must be hit exactly once: 0 is a **crack** (the "
               "background shows through), ≥ 2 a **double hit** (blending and transparency draw "
               "that sample twice). Times are frames at one sample per pixel with the vertex-colour "
               "shader, where coverage dominates.\n\n");
    table_edges(f);
    if (n >= 1) {
        row *fx = find_row("edges", sc[0], "fixed 24.8, top-left (reference)");
        row *fl = find_row("edges", sc[0], "float, >= 0 test");
        fprintf(f, "\n**What it means.** The float edge function evaluates a shared edge twice, "
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
                fl ? fl->doubles : NAN, fl ? fl->cracks : NAN, S.quick ? 256 : 512,
                S.quick ? 256 : 512, fx && fl ? fx->med / fl->med : NAN);
    }

    /* ---- interp ---- */
    fprintf(f, "\n## 3. Interpolation: affine vs perspective-correct\n\n"
               "A rectangle recedes from view depth w0 = 1 at the bottom of the screen to w1 = k at "
               "the top; v runs from 0 (near edge) to 1 (far edge), u across, on a 256×256 texture. "
               "The truth is the analytic mapping: the ray through each pixel centre hits the "
               "plane, and the hit's UV is read off the rectangle. Along the rectangle's sides v "
               "goes from 0 to 1 while w goes from w0 to w1, exactly the case of the formula "
               "(√k−1)/(√k+1) for the worst affine error. Times render the same plane with an unlit "
               "bilinear texture.\n\n");
    table_interp(f);
    {
        row *a2 = find_row("interp", "w1/w0 = 2", "affine (screen-space)");
        row *a8 = find_row("interp", "w1/w0 = 8", "affine (screen-space)");
        row *p8 = find_row("interp", "w1/w0 = 8", "perspective-correct");
        if (a2 && a8 && p8)
            fprintf(f, "\n![interpolation error](img/accuracy_interp.png)\n\n"
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

    /* ---- filter ---- */
    scenes_of("filter", sc, &n, 8);
    fprintf(f, "\n## 4. Texture filtering on a receding floor\n\n"
               "A floor from 1 to 40 units ahead of a camera 1 unit above it, one 256×256 texture "
               "tile per 8 units (repeat), rendered without AA. The truth per pixel is the average "
               "of %d×%d bilinear lookups of level 0 at the exact (ray–plane) UV of sub-pixel "
               "positions — a box filter over the pixel. Error: RMSE of the colour (0..1, averaged "
               "over R, G, B) over the pixels wholly on the floor. Trilinear's mip chain is built "
               "once, before timing.\n\n",
            S.quick ? 8 : 16, S.quick ? 8 : 16);
    table_filter(f);
    if (n >= 1) {
        row *rn = find_row("filter", sc[0], "nearest"), *rb = find_row("filter", sc[0], "bilinear");
        row *rt = find_row("filter", sc[0], "trilinear");
        fprintf(f, "\n![texture filtering](img/accuracy_filter.png)\n\n"
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

    /* ---- depth ---- */
    fprintf(f,
            "\n## 5. Depth precision near the far plane\n\n"
            "Two parallel planes tilted away from the camera (view depth 30 at the bottom of "
            "the screen to 49 at the top; near 0.1, far %.0f, the hw2 camera's numbers), the "
            "second one δ farther along the view axis, drawn first, so a tie goes to the wrong "
            "plane. Each cell is the fraction of pixels where the farther plane wins. The first "
            "two rows are the pipeline's two depth formats (`common/pipeline/stage3_setup.h`), rendered "
            "by the reference rasterizer, which interpolates the per-vertex depth in float and "
            "keeps the smaller; both are timed, interleaved frame by frame. The pipeline has no "
            "fixed-point depth buffer, so the other rows are *what-ifs* computed from the "
            "exact depth of each plane at the pixel centre with only the storage rounding of "
            "that encoding — lower bounds, untimed.\n\n",
            DEPTH_FAR);
    table_depth(f);
    {
        const char *D1 = "delta = 0.0001", *D3 = "delta = 0.0003";
        row *z1 = find_row("depth", D1, DEPTH_ENCODINGS[0]);
        row *z3 = find_row("depth", D3, DEPTH_ENCODINGS[0]);
        row *z10 = find_row("depth", "delta = 0.001", DEPTH_ENCODINGS[0]);
        row *z30 = find_row("depth", "delta = 0.003", DEPTH_ENCODINGS[0]);
        row *i10 = find_row("depth", "delta = 0.001", DEPTH_ENCODINGS[1]);
        row *e1 = find_row("depth", D1, DEPTH_ENCODINGS[2]);
        row *e3 = find_row("depth", D3, DEPTH_ENCODINGS[2]);
        row *r1 = find_row("depth", D1, DEPTH_ENCODINGS[4]);
        double inv_worst = 0;
        for (int d = 0; d < DELTA_COUNT; d++) {
            char scene[40];
            snprintf(scene, sizeof scene, "delta = %g", DELTAS[d]);
            row *r = find_row("depth", scene, DEPTH_ENCODINGS[1]);
            if (r) inv_worst = fmax(inv_worst, r->wrong);
        }
        /* Time ratios where both formats do the same work: from the first δ
         * at which z01 is right on 99% of the pixels. */
        int first_right = DELTA_COUNT - 1;
        for (int d = DELTA_COUNT - 1; d >= 0; d--) {
            char scene[40];
            snprintf(scene, sizeof scene, "delta = %g", DELTAS[d]);
            row *r = find_row("depth", scene, DEPTH_ENCODINGS[0]);
            if (!r || !(r->wrong < 0.01)) break;
            first_right = d;
        }
        double lo, hi;
        depth_time_ratio_range(first_right, &lo, &hi);
        row *zt = find_row("depth", DEPTH_TIME_SCENE, DEPTH_ENCODINGS[0]);
        row *it = find_row("depth", DEPTH_TIME_SCENE, DEPTH_ENCODINGS[1]);
        row *i1 = find_row("depth", D1, DEPTH_ENCODINGS[1]);
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
                    100 * z10->wrong, 100 * z30->wrong, 100 * inv_worst, it->min / zt->min, ti, tz,
                    lo, hi, DELTAS[first_right], i1->min / z1->min, 100 * z1->wrong,
                    100 * r1->wrong);
        }
    }
    /* ---- depth order (inverse_w) ---- */
    {
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
                S.quick ? 64 : 128, S.quick ? 64 : 128);
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
                100 * order_mean(ORDER_ROUNDED, 3), 100 * order_mean(ORDER_ROUNDED, 4),
                100 * e6, ORDER_DIST[e_wd], ORDER_TILT[e_wt], 100 * order_mean(ORDER_AFTER, 2),
                100 * order_mean(ORDER_ROUNDED, 2), 100 * order_mean(ORDER_BEFORE, 2),
                100 * order_mean(ORDER_ROUNDED, 3), 100 * order_mean(ORDER_ROUNDED, 1),
                100 * order_mean(ORDER_ROUNDED, 0), 100 * order_mean(ORDER_AFTER, 1),
                100 * order_mean(ORDER_AFTER, 0), 100 * order_mean(ORDER_BEFORE, 1),
                100 * order_mean(ORDER_BEFORE, 0), ORDER_DIST[d1000], ORDER_TILT[t45],
                ORDER_GAP[g14], 100 * order_frac[ORDER_BEFORE][g14][d1000][t45],
                100 * order_frac[ORDER_AFTER][g14][d1000][t45],
                100 * order_frac[ORDER_ROUNDED][g14][d1000][t45]);
    }
    fprintf(f, "\n## How to regenerate\n\n"
               "    make bench-accuracy            # full run into docs/ (a few minutes)\n"
               "    build/bin/bench_accuracy --quick --out /tmp/acc   # small and fast\n"
               "    build/bin/bench_accuracy --quick --check          # what `make test` runs\n");
    return ras_io_report_commit(&report, path, NULL);
}

static void print_tables(void) {
    char aa_scenes[4][40];
    int n_aa;
    scenes_of("aa", aa_scenes, &n_aa, 4);
    printf("\n== 1. anti-aliasing ==\n");
    for (int s = 0; s < n_aa; s++) table_aa(stdout, aa_scenes[s]);
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

/* ---- main ------------------------------------------------------------------------- */

static void usage(FILE *f) {
    fputs("usage: bench_accuracy [--quick] [--check] [--repeats N] [--out DIR]\n"
          "  measures time and error of every accuracy option and writes DIR/accuracy.md,\n"
          "  DIR/accuracy.csv and DIR/img/accuracy_*.png (DIR defaults to docs; with --check\n"
          "  and no --out, a temporary directory that is removed afterwards)\n",
          f);
}

static bool make_dir(const char *path) { return mkdir(path, 0755) == 0 || errno == EEXIST; }

int main(int argc, char **argv) {
    bool out_given = false;
    S.repeats = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) S.quick = true;
        else if (!strcmp(argv[i], "--check")) S.check = true;
        else if (!strcmp(argv[i], "--repeats") && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 1 || v > 64) {
                fprintf(stderr, "bench_accuracy: --repeats expects 1..64, got '%s'\n", argv[i]);
                return 2;
            }
            S.repeats = (int)v;
        } else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            snprintf(S.out, sizeof S.out, "%s", argv[++i]);
            out_given = true;
        } else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return 0;
        } else {
            fprintf(stderr, "bench_accuracy: unknown argument '%s'\n", argv[i]);
            usage(stderr);
            return 2;
        }
    }
    if (!S.repeats) S.repeats = S.quick ? 3 : 9;
    bool temp_out = false;
    if (!out_given) {
        if (S.check) {
            const char *tmp = getenv("TMPDIR");
            snprintf(S.out, sizeof S.out, "%s/raster101-accuracy-XXXXXX", tmp && *tmp ? tmp : "/tmp");
            if (!mkdtemp(S.out)) {
                fprintf(stderr, "bench_accuracy: cannot create a temporary directory %s\n", S.out);
                return 2;
            }
            temp_out = true;
        } else {
            snprintf(S.out, sizeof S.out, "docs");
        }
    }
    char img_dir[1100];
    snprintf(img_dir, sizeof img_dir, "%s/img", S.out);
    if (!make_dir(S.out) || !make_dir(img_dir)) {
        fprintf(stderr, "bench_accuracy: cannot create %s: %s\n", img_dir, strerror(errno));
        return 2;
    }
    double t0 = ras_now_ms();
    progress("%s run, %d repeats per option, output in %s", S.quick ? "quick" : "full", S.repeats,
             S.out);
    aa_thin_triangles();
    aa_hw2_scene();
    edge_precision();
    interpolation();
    filtering();
    depth_precision();
    depth_order();
    fill_relative_times();
    check_aa();
    check_edges();
    check_depth();
    check_depth_order();
    double total_s = (ras_now_ms() - t0) / 1000;

    char machine_name[400], date[64], path[1200];
    machine(machine_name, sizeof machine_name);
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M %Z", localtime(&now));
    ras_error err = {{0}};
    bool ok = true;
    char aa_scenes[4][40];
    int n_aa;
    scenes_of("aa", aa_scenes, &n_aa, 4);
    static const char *files[] = {"img/accuracy_aa_0.png", "img/accuracy_aa_1.png",
                                  "img/accuracy_interp.png", "img/accuracy_filter.png",
                                  "accuracy.csv", "accuracy.md"};
    for (int s = 0; s < n_aa && s < 2 && ok; s++) {
        snprintf(path, sizeof path, "%s/%s", S.out, files[s]);
        ok = chart_aa(aa_scenes[s], path, &err);
    }
    snprintf(path, sizeof path, "%s/%s", S.out, files[2]);
    ok = ok && chart_interp(path, &err);
    snprintf(path, sizeof path, "%s/%s", S.out, files[3]);
    ok = ok && chart_filter(path, &err);
    snprintf(path, sizeof path, "%s/%s", S.out, files[4]);
    if (ok && !write_csv(path)) ok = ras_error_set(&err, "cannot write %s", path);
    snprintf(path, sizeof path, "%s/%s", S.out, files[5]);
    if (ok && !write_markdown(path, machine_name, date, total_s))
        ok = ras_error_set(&err, "cannot write %s", path);
    if (!ok) {
        fprintf(stderr, "bench_accuracy: %s\n", err.msg);
        return 2;
    }
    print_tables();
    printf("\nmachine: %s; %s; %.1f s\n", machine_name, date, total_s);
    progress("wrote %s/accuracy.md, accuracy.csv and img/accuracy_*.png", S.out);
    if (temp_out) {
        for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
            snprintf(path, sizeof path, "%s/%s", S.out, files[i]);
            unlink(path);
        }
        rmdir(img_dir);
        rmdir(S.out);
    }
    if (S.check) {
        fprintf(stderr, "bench_accuracy: %s (%d failed checks)\n", failures ? "FAIL" : "all checks pass",
                failures);
        return failures ? 1 : 0;
    }
    return 0;
}
