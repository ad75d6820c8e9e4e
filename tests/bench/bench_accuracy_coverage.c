/* bench_accuracy_coverage.c — sections 1 and 2 of the accuracy report:
 * anti-aliasing (every AA mode and pattern on thin triangles and on the hw2
 * scene, against exact pixel coverage) and edge precision (the reference's
 * fixed-point edges against float edge functions: cracks and double hits on
 * shared edges). bench_accuracy.h.
 */
#include "bench_accuracy.h"
#include "bench_float_edges.h" /* the float-edge rasterizer, this benchmark's own */
#include "rasterizer.h"        /* hw2 reference: rasterize_triangle */
#include "transform.h"         /* hw1 reference: get_projection_matrix */

#include <math.h>   /* sqrt, fabs, cos, sin, hypot, INFINITY */
#include <stdlib.h> /* malloc, calloc, free */
#include <string.h> /* strcmp, strncmp, memcpy */

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

/* RMSE over all pixels and over edge pixels; `channels` 1 = red only. */
static void image_error(const ras_image *img, const vec3s *truth, const bool *edge, int channels,
                        acc_row *r) {
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
    r->psnr_all = acc_psnr(r->rmse_all);
    r->psnr_edge = acc_psnr(r->rmse_edge);
}

static void run_aa_options(const char *scene, ras_mesh *const *meshes, int mesh_count, mat4s view,
                           mat4s projection, int w, int h, unsigned varyings, const vec3s *truth,
                           const bool *edge, int channels) {
    ras_image *img = ras_image_create(w, h, NULL);
    acc_die_oom(img);
    acc_timed t[AA_OPTION_COUNT];
    for (int i = 0; i < AA_OPTION_COUNT; i++) {
        const aa_option *o = &AA_OPTIONS[i];
        t[i].f = (acc_mesh_frame){.p = acc_make_pipeline(w, h, o->aa, o->kind, o->count,
                                                         rasterize_triangle, varyings, NULL, NULL,
                                                         (vec3s){{0, 0, 0}}),
                                  .meshes = meshes,
                                  .mesh_count = mesh_count,
                                  .view = view,
                                  .projection = projection,
                                  .img = img};
        t[i].r = acc_new_row("aa", scene, o->name);
        t[i].r->samples = o->count;
    }
    acc_progress("aa / %s: timing %d options x %d rounds", scene, AA_OPTION_COUNT, acc_opt.repeats);
    acc_time_group(t, AA_OPTION_COUNT);
    for (int i = 0; i < AA_OPTION_COUNT; i++) {
        acc_draw_mesh_frame(&t[i].f);
        image_error(img, truth, edge, channels, t[i].r);
        ras_pipeline_destroy(t[i].f.p);
    }
    ras_image_destroy(img);
}

/* Thin isosceles triangles at random angles, one per grid cell (so none
 * overlap and the exact area is the truth). */
void coverage_aa_thin_triangles(void) {
    int size = acc_opt.quick ? 192 : 512, cell = acc_opt.quick ? 24 : 32, per = size / cell,
        n = per * per;
    acc_pt *v = malloc((size_t)n * 3 * sizeof *v);
    acc_die_oom(v);
    for (int cy = 0; cy < per; cy++)
        for (int cx = 0; cx < per; cx++) {
            double a = 2 * RAS_PI * acc_rnd(), len = cell * (0.55 + 0.35 * acc_rnd());
            double wd = 0.3 + 2.7 * acc_rnd();
            double ox = (cx + 0.5) * cell + (acc_rnd() - 0.5) * 2,
                   oy = (cy + 0.5) * cell + (acc_rnd() - 0.5) * 2;
            double dx = cos(a), dy = sin(a);
            acc_pt *t = &v[3 * (cy * per + cx)];
            t[0] = (acc_pt){ox + dx * len / 2, oy + dy * len / 2};
            t[1] = (acc_pt){ox - dx * len / 2 - dy * wd / 2, oy - dy * len / 2 + dx * wd / 2};
            t[2] = (acc_pt){ox - dx * len / 2 + dy * wd / 2, oy - dy * len / 2 - dx * wd / 2};
        }
    ras_mesh *m = acc_screen_mesh(v, NULL, n, size, size, (vec3s){{1, 1, 1}});
    free(v);
    /* Truth: each snapped screen triangle clipped to every pixel it touches. */
    vec4s *tri = malloc((size_t)n * 3 * sizeof *tri);
    double *cov = calloc((size_t)size * size, sizeof *cov);
    vec3s *truth = malloc((size_t)size * size * sizeof *truth);
    bool *edge = malloc((size_t)size * size * sizeof *edge);
    acc_die_oom(tri), acc_die_oom(cov), acc_die_oom(truth), acc_die_oom(edge);
    acc_screen_triangles(m, *acc_identity(), *acc_identity(), size, size, tri);
    double area_sum = 0, cov_sum = 0;
    for (int t = 0; t < n; t++) {
        acc_pt p[3];
        truth_snapped_ccw(&tri[3 * t], p);
        area_sum += truth_poly_area(p, 3);
        truth_add_coverage(cov, size, size, p, 3, 1.0);
    }
    long edges = 0;
    for (int i = 0; i < size * size; i++) {
        cov_sum += cov[i];
        truth[i] = (vec3s){{(float)cov[i], (float)cov[i], (float)cov[i]}};
        edge[i] = cov[i] > 1e-9 && cov[i] < 1 - 1e-9;
        edges += edge[i];
    }
    acc_check(fabs(area_sum - cov_sum) < 1e-6 * area_sum,
              "thin triangles: pixel areas add up to the triangles' area (%.6f vs %.6f)", cov_sum,
              area_sum);
    char scene[40];
    snprintf(scene, sizeof scene, "thin triangles %dx%d", size, size);
    acc_progress("aa / %s: %d triangles, %ld edge pixels", scene, n, edges);
    run_aa_options(scene, &m, 1, *acc_identity(), *acc_identity(), size, size, RAS_VARYING_COLOR,
                   truth, edge, 1);
    free(tri), free(cov), free(truth), free(edge);
    ras_mesh_destroy(m);
}

/* The classic hw2 scene (hw2_rasterize/main.c): the near triangle hides part
 * of the far one; both are flat-coloured, so the truth is exact: near ∩ pixel,
 * plus (far ∩ pixel) − (far ∩ near ∩ pixel), plus the rest as background. */
void coverage_aa_hw2_scene(void) {
    static const vec3s pos[2][3] = {{{{2, 0, -2}}, {{0, 2, -2}}, {{-2, 0, -2}}},
                                    {{{3.5f, -1, -5}}, {{2.5f, 1.5f, -5}}, {{-1, 0.5f, -5}}}};
    static const vec3s col[2] = {{{217 / 255.0f, 238 / 255.0f, 185 / 255.0f}},
                                 {{185 / 255.0f, 217 / 255.0f, 238 / 255.0f}}};
    int size = acc_opt.quick ? 140 : 700;
    ras_mesh *m[2];
    for (int i = 0; i < 2; i++)
        m[i] = ras_mesh_create_triangle(pos[i][0], pos[i][1], pos[i][2], col[i]);
    acc_die_oom(m[0]), acc_die_oom(m[1]);
    mat4s view = ras_view_matrix_eye((vec3s){{0, 0, 5}});
    mat4s proj = get_projection_matrix(45, 1, 0.1f, 50);
    acc_pt tri[2][3];
    for (int i = 0; i < 2; i++) {
        vec4s s[3];
        acc_screen_triangles(m[i], view, proj, size, size, s);
        truth_snapped_ccw(s, tri[i]);
    }
    acc_pt far_and_near[ACC_POLY_MAX];
    int nfn = truth_clip_convex(tri[1], 3, tri[0], 3, far_and_near);
    double *a_near = calloc((size_t)size * size, sizeof(double));
    double *a_far = calloc((size_t)size * size, sizeof(double));
    vec3s *truth = malloc((size_t)size * size * sizeof *truth);
    bool *edge = malloc((size_t)size * size * sizeof *edge);
    acc_die_oom(a_near), acc_die_oom(a_far), acc_die_oom(truth), acc_die_oom(edge);
    truth_add_coverage(a_near, size, size, tri[0], 3, 1.0);
    truth_add_coverage(a_far, size, size, tri[1], 3, 1.0);
    if (nfn >= 3) truth_add_coverage(a_far, size, size, far_and_near, nfn, -1.0);
    long edges = 0;
    for (int i = 0; i < size * size; i++) {
        double an = a_near[i], af = a_far[i], bg = 1 - an - af;
        truth[i] =
            glms_vec3_add(glms_vec3_scale(col[0], (float)an), glms_vec3_scale(col[1], (float)af));
        (void)bg; /* the background is black */
        edge[i] = !(an > 1 - 1e-9 || af > 1 - 1e-9 || an + af < 1e-9);
        edges += edge[i];
    }
    char scene[40];
    snprintf(scene, sizeof scene, "hw2 scene %dx%d", size, size);
    acc_progress("aa / %s: %ld edge pixels", scene, edges);
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
    acc_die_oom(img);
    /* Time: one sample per pixel, plain vertex colour — coverage dominates. */
    acc_timed t[2];
    for (int e = 0; e < 2; e++) {
        t[e].f = (acc_mesh_frame){
            .p = acc_make_pipeline(size, size, RAS_AA_NONE, RAS_PATTERN_ORDERED, 1, modes[e],
                                   RAS_VARYING_COLOR, NULL, NULL, (vec3s){{0, 0, 0}}),
            .meshes = &m,
            .mesh_count = 1,
            .view = *acc_identity(),
            .projection = *acc_identity(),
            .img = img};
        t[e].r = acc_new_row("edges", scene, names[e]);
        t[e].r->samples = 4;
    }
    acc_progress("edges / %s: timing", scene);
    acc_time_group(t, 2);
    for (int e = 0; e < 2; e++) {
        ras_pipeline_destroy(t[e].f.p);
        acc_row *r = t[e].r;
        acc_mesh_frame f = t[e].f;
        acc_progress("edges / %s: counting hits, %s", scene, names[e]);
        /* Count: SSAA 2x2 with the counting shader. */
        ras_sample_pattern pat;
        ras_sample_pattern_make(RAS_PATTERN_ORDERED, 4, &pat, NULL);
        hit_counter hc = {.w = size,
                          .h = size,
                          .pattern = &pat,
                          .count = calloc((size_t)size * size * 4, sizeof(unsigned short))};
        acc_die_oom(hc.count);
        f.p = acc_make_pipeline(size, size, RAS_AA_SSAA, RAS_PATTERN_ORDERED, 4, modes[e],
                                RAS_VARYING_COLOR, count_hit, &hc, (vec3s){{0, 0, 0}});
        acc_draw_mesh_frame(&f);
        long cracks = 0, doubles = 0;
        for (int y = 0; y < size; y++)
            for (int x = 0; x < size; x++)
                for (int k = 0; k < 4; k++) {
                    unsigned c = hc.count[((size_t)(size - 1 - y) * size + x) * 4 + k];
                    if (c >= 2)
                        doubles++;
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

void coverage_edge_precision(void) {
    int size = acc_opt.quick ? 256 : 512;
    /* The fan: n slivers around the centre; each shares both long edges. */
    int n = acc_opt.quick ? 1000 : 3000;
    double cx = size / 2.0 + 0.123, cy = size / 2.0 + 0.377, rad = size * 0.47;
    acc_pt *v = malloc((size_t)n * 3 * sizeof *v);
    float *z = malloc((size_t)n * sizeof *z);
    acc_die_oom(v), acc_die_oom(z);
    for (int i = 0; i < n; i++) {
        double a0 = 2 * RAS_PI * i / n, a1 = 2 * RAS_PI * (i + 1) / n;
        v[3 * i] = (acc_pt){cx, cy};
        v[3 * i + 1] = (acc_pt){cx + rad * cos(a0), cy + rad * sin(a0)};
        v[3 * i + 2] = (acc_pt){cx + rad * cos(a1), cy + rad * sin(a1)};
        z[i] = (float)(-0.9 + 1.8 * i / n); /* each triangle nearer than the last */
    }
    ras_mesh *fan = acc_screen_mesh(v, z, n, size, size, (vec3s){{1, 1, 1}});
    fan_shape fs = {cx, cy, rad * cos(RAS_PI / n)};
    char scene[40];
    snprintf(scene, sizeof scene, "fan of %d slivers", n);
    run_edge_modes(scene, fan, size, inside_fan, &fs);
    ras_mesh_destroy(fan);
    free(v), free(z);
    /* The jittered grid: g×g quads, inner corners moved at random. */
    int g = acc_opt.quick ? 20 : 40, tris = 2 * g * g;
    double m0 = 16.25, step = (size - 32.5) / g;
    acc_pt *corner = malloc((size_t)(g + 1) * (g + 1) * sizeof *corner);
    v = malloc((size_t)tris * 3 * sizeof *v);
    z = malloc((size_t)tris * sizeof *z);
    acc_die_oom(corner), acc_die_oom(v), acc_die_oom(z);
    for (int j = 0; j <= g; j++)
        for (int i = 0; i <= g; i++) {
            bool inner = i > 0 && j > 0 && i < g && j < g;
            /* ±0.15 of a cell keeps every triangle counter-clockwise, so
             * the triangles tile the square without overlapping. */
            corner[j * (g + 1) + i] =
                (acc_pt){m0 + step * (i + (inner ? 0.3 * (acc_rnd() - 0.5) : 0)),
                         m0 + step * (j + (inner ? 0.3 * (acc_rnd() - 0.5) : 0))};
        }
    int t = 0, clockwise = 0;
    for (int j = 0; j < g; j++)
        for (int i = 0; i < g; i++) {
            acc_pt a = corner[j * (g + 1) + i], b = corner[j * (g + 1) + i + 1];
            acc_pt c = corner[(j + 1) * (g + 1) + i + 1], d = corner[(j + 1) * (g + 1) + i];
            acc_pt q[2][3] = {{a, b, c}, {a, c, d}};
            for (int k = 0; k < 2; k++, t++) {
                memcpy(&v[3 * t], q[k], sizeof q[k]);
                clockwise += !(truth_poly_area(q[k], 3) > 0);
                z[t] = (float)(-0.9 + 1.8 * t / tris);
            }
        }
    acc_check(clockwise == 0, "jittered grid: no folded triangle (%d of %d)", clockwise, tris);
    ras_mesh *grid = acc_screen_mesh(v, z, tris, size, size, (vec3s){{1, 1, 1}});
    box_shape bs = {m0, m0, m0 + step * g, m0 + step * g};
    snprintf(scene, sizeof scene, "jittered grid %dx%d (%d triangles)", g, g, tris);
    run_edge_modes(scene, grid, size, inside_box, &bs);
    ras_mesh_destroy(grid);
    free(corner), free(v), free(z);
}

/* ---- the orderings that must hold ---------------------------------------------- */

void coverage_check_aa(void) {
    for (int i = 0; i < acc_row_count; i++) {
        if (strcmp(acc_rows[i].section, "aa") || strcmp(acc_rows[i].option, AA_OPTIONS[0].name))
            continue;
        const char *scene = acc_rows[i].scene;
        bool thin = !strncmp(scene, "thin", 4);
        static const char *const ordered[4] = {"none (1 sample)", "MSAA ordered 2x2",
                                               "MSAA ordered 4x4", "MSAA ordered 8x8"};
        static const char *const standard[5] = {"none (1 sample)", "MSAA standard 2x",
                                                "MSAA standard 4x", "MSAA standard 8x",
                                                "MSAA standard 16x"};
        /* Thin triangles have edges at every angle: every step must help. The
         * hw2 scene has six edges, so only big steps are asserted. */
        for (int k = 1; k < 4; k++) {
            acc_row *a = acc_find_row("aa", scene, ordered[thin ? k - 1 : 0]),
                    *b = acc_find_row("aa", scene, ordered[k]);
            if (!thin && k != 3) continue;
            acc_check(b->rmse_edge < a->rmse_edge, "aa %s: edge RMSE %s %.4f < %s %.4f", scene,
                      b->option, b->rmse_edge, a->option, a->rmse_edge);
        }
        for (int k = 1; k < 5; k++) {
            if (!thin && k != 2 && k != 4) continue;
            acc_row *a = acc_find_row("aa", scene, standard[thin ? k - 1 : k - 2]);
            acc_row *b = acc_find_row("aa", scene, standard[k]);
            acc_check(b->rmse_edge < a->rmse_edge, "aa %s: edge RMSE %s %.4f < %s %.4f", scene,
                      b->option, b->rmse_edge, a->option, a->rmse_edge);
        }
        for (int k = 1; k < AA_OPTION_COUNT; k++) {
            if (AA_OPTIONS[k].aa != RAS_AA_MSAA) continue;
            char ss[48];
            snprintf(ss, sizeof ss, "SSAA%s", AA_OPTIONS[k].name + 4);
            acc_row *m = acc_find_row("aa", scene, AA_OPTIONS[k].name),
                    *s = acc_find_row("aa", scene, ss);
            acc_check(fabs(m->rmse_edge - s->rmse_edge) < 1e-3,
                      "aa %s: flat colours, so %s and %s agree (%.4f vs %.4f)", scene, m->option,
                      s->option, m->rmse_edge, s->rmse_edge);
        }
    }
}

void coverage_check_edges(void) {
    for (int i = 0; i < acc_row_count; i++) {
        if (strcmp(acc_rows[i].section, "edges") || strncmp(acc_rows[i].option, "fixed", 5))
            continue;
        acc_check(acc_rows[i].cracks == 0 && acc_rows[i].doubles == 0,
                  "edges %s: fixed point has no cracks (%.0f) and no double hits (%.0f)",
                  acc_rows[i].scene, acc_rows[i].cracks, acc_rows[i].doubles);
    }
}
