/* bench_accuracy.h — private to the accuracy report (bench_accuracy): what its
 * modules share. Not an API; nothing outside tests/bench/bench_accuracy*.c
 * includes it.
 *
 * The program, by job:
 *   bench_accuracy.c            the command line: runs the sections, writes the files
 *   bench_accuracy_harness.c    settings, the rows of the report, --check, pipelines
 *                               with the reference hooks, timing
 *   bench_accuracy_truth.c      ground truths computed outside the pipeline: exact
 *                               polygon areas, rays against planes
 *   bench_accuracy_coverage.c   sections 1-2: anti-aliasing, edge precision
 *   bench_accuracy_texturing.c  sections 3-4: interpolation, texture filtering
 *   bench_accuracy_depth.c      section 5: the depth formats near the far plane
 *   bench_accuracy_order.c      section 5b: inverse_w's order at every distance and tilt
 *   bench_accuracy_charts.c     img/accuracy_*.png
 *   bench_accuracy_report.c     accuracy.csv, accuracy.md and the tables on stdout
 * The sections run once each, in the order of main: they draw from one stream
 * of random numbers (acc_rnd), so the order is part of the results.
 */
#ifndef RAS_BENCH_ACCURACY_H
#define RAS_BENCH_ACCURACY_H

#include "ras_error.h"
#include "ras_pipeline.h"

#include <stdbool.h> /* bool */
#include <stdio.h>   /* FILE */

/* ---- settings and results (bench_accuracy_harness.c) -------------------------- */

typedef struct acc_settings {
    bool quick, check;
    int repeats;
    char out[1024];
} acc_settings;

/* The command line's settings, set by main before any section runs. */
extern acc_settings acc_opt;

/* One row of the report; NAN where a column does not apply. */
typedef struct acc_row {
    char section[16], scene[40], option[48];
    double med, min, max, rel; /* ms per frame; rel = med / cheapest of the scene */
    double rmse_all, psnr_all, rmse_edge, psnr_edge;
    double cracks, doubles;
    double v_max, formula, uv_max_texels, uv_rms_texels;
    double wrong;
    double bytes;
    int samples;
} acc_row;

#define ACC_MAX_ROWS 160
extern acc_row acc_rows[ACC_MAX_ROWS];
extern int acc_row_count;

void acc_progress(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* --check: an ordering that must hold. Never about times. */
void acc_check(bool ok, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The checks that failed so far. */
int acc_failures(void);

/* A new row, all NAN; exits on too many rows or a name too long (a bug in the bench). */
acc_row *acc_new_row(const char *section, const char *scene, const char *option);
acc_row *acc_find_row(const char *section, const char *scene, const char *option);
void acc_fill_relative_times(void);

/* ---- small helpers ---------------------------------------------------------------- */

double acc_rnd(void); /* uniform in [0, 1), one fixed sequence per run */
/* Exits when p is NULL. Not const: gcc would take a const pointer to fresh
 * malloc memory for a read of it (-Wmaybe-uninitialized). */
void acc_die_oom(void *p);
double acc_psnr(double rmse);
const mat4s *acc_identity(void);

/* A pipeline with the reference hooks; exits on failure (a bug in the bench). */
ras_pipeline *acc_make_pipeline(int w, int h, ras_aa_mode aa, ras_pattern_kind kind, int count,
                                ras_rasterize_fn rasterize, unsigned varyings, ras_shade_fn shade,
                                void *user, vec3s clear);

/* A scene drawn as meshes with one set of matrices. */
typedef struct acc_mesh_frame {
    ras_pipeline *p;
    ras_mesh *const *meshes;
    int mesh_count;
    mat4s view, projection;
    ras_image *img;
} acc_mesh_frame;

void acc_draw_mesh_frame(void *ctx);

/* Times a group of frames round-robin — one frame of each option in turn,
 * `repeats` rounds after one warm-up round — so a burst of load on a shared
 * machine hits every option of the group alike and the ratios survive. */
typedef struct acc_timed {
    acc_mesh_frame f;
    acc_row *r;
} acc_timed;

void acc_time_group(acc_timed *t, int n);

/* ---- ground truths (bench_accuracy_truth.c) ------------------------------------- */

typedef struct acc_pt {
    double x, y;
} acc_pt;

#define ACC_POLY_MAX 32

/* Mesh whose positions are already clip coordinates (w = 1) of screen points
 * (bench_accuracy_harness.c). */
ras_mesh *acc_screen_mesh(const acc_pt *v, const float *z, int tri_count, int w, int h,
                          vec3s color);
/* The screen triangles the pipeline will see for mesh m (stage 1 + viewport;
 * bench_accuracy_harness.c). */
void acc_screen_triangles(const ras_mesh *m, mat4s view, mat4s projection, int w, int h,
                          vec4s *out /* 3 per triangle */);

/* poly ∩ convex counter-clockwise polygon `clip`; returns the vertex count. */
int truth_clip_convex(const acc_pt *poly, int n, const acc_pt *clip, int m, acc_pt *out);
double truth_poly_area(const acc_pt *p, int n);
/* The screen triangle as the fixed-point rasterizer sees it: snapped to
 * 1/256 px, counter-clockwise. */
void truth_snapped_ccw(const vec4s v[3], acc_pt out[3]);
/* cov[pixel index] += weight · (area of poly ∩ pixel), over the polygon's box. */
void truth_add_coverage(double *cov, int w, int h, const acc_pt *poly, int n, double weight);

/* The camera of sections 3–5. */
#define ACC_FOV_DEG 45.0
#define ACC_Z_NEAR 0.1f

/* The ray through the centre of screen pixel (x, y) from the view-space
 * origin, with z = -1 (aspect 1). */
void truth_pixel_ray(int x, int y, double sx, double sy, int size, double d[3]);

/* A plane quad with UVs: corners p[0..3] counter-clockwise seen from the
 * camera, UV affine in 3D over the quad. */
typedef struct acc_quad {
    double p[4][3];
    double uv[4][2];
} acc_quad;

ras_mesh *truth_quad_mesh(const acc_quad *q);
/* Ray (origin, direction d) against the quad's plane: the hit's view depth
 * and UV (parallelogram quads: p[3] - p[0] and p[1] - p[0] span it, UV affine).
 * False when the ray misses the plane or the hit is outside the quad. */
bool truth_quad_hit(const acc_quad *q, const double d[3], double *depth, double uv[2]);

/* ---- the sections: each adds its rows; *_check asserts its orderings ------------- */

void coverage_aa_thin_triangles(void); /* 1: thin triangles at random angles */
void coverage_aa_hw2_scene(void);      /* 1: the hw2 scene */
void coverage_edge_precision(void);    /* 2: fixed-point vs float edge functions */
void coverage_check_aa(void);
void coverage_check_edges(void);

void texturing_interpolation(void); /* 3: affine vs perspective-correct UV */
void texturing_filtering(void);     /* 4: nearest / bilinear / trilinear */

/* 5: two planes δ apart near the far plane, per depth encoding. */
#define DEPTH_FAR 50.0
#define DEPTH_DELTA_COUNT 6
extern const double DEPTH_DELTAS[DEPTH_DELTA_COUNT];
#define DEPTH_ENCODING_COUNT 5
#define DEPTH_PIPELINE_COUNT 2 /* the first encodings: the pipeline's formats, timed */
extern const char *const DEPTH_ENCODINGS[DEPTH_ENCODING_COUNT];
/* The δ whose frame times the table shows: one where both formats get every
 * pixel right, so both do the same work. Where z01 is wrong, the nearer
 * plane fails the depth test and is never written: the wrong answer is
 * cheaper, and the time ratio there measures that, not the format. */
#define DEPTH_TIME_SCENE "delta = 0.01"
void depth_precision(void);
void depth_check(void);

/* 5b: inverse_w's order, per relative gap × distance × tilt. */
#define ORDER_D 4
#define ORDER_T 6
#define ORDER_G 5
extern const double ORDER_DIST[ORDER_D], ORDER_TILT[ORDER_T], ORDER_GAP[ORDER_G];
enum { ORDER_BEFORE, ORDER_AFTER, ORDER_ROUNDED, ORDER_KINDS };
void order_run(void);
void order_check(void);
/* The fraction of samples where the farther plane wins, for one cell. */
double order_fraction(int kind, int gi, int di, int ti);
/* The worst fraction of kind k at gap gi over all distances and tilts, and
 * where it is; the number of (distance, tilt) cells with any inversion. */
double order_worst(int k, int gi, int *wd, int *wt, int *cells);
/* Over all distances and tilts at gap gi: the mean fraction of kind k, and
 * the worst excess of kind k over the bound (the pipeline's own loss, beyond
 * what its float input already loses) with its cell. */
double order_mean(int k, int gi);
double order_excess(int k, int gi, int *wd, int *wt, int *cells);

/* ---- output (bench_accuracy_charts.c, bench_accuracy_report.c) ------------------ */

bool charts_aa(const char *scene, const char *path, ras_error *err);
bool charts_interp(const char *path, ras_error *err);
bool charts_filter(const char *path, ras_error *err);

/* The scenes of a section, in the order of their rows (at most max). */
void report_scenes_of(const char *section, char out[][40], int *n, int max);
/* "CPU model, N logical CPUs ...; 1-minute load average ..." */
void report_machine(char *buf, size_t n);
bool report_write_csv(const char *path);
bool report_write_markdown(const char *path, const char *machine_name, const char *date,
                           double total_s);
void report_print_tables(void);

#endif
