/* bench_accuracy_harness.c — the accuracy report's measurement harness: its
 * settings and rows, the --check assertions, pipelines with the reference
 * hooks, and the timing of frames (bench_accuracy.h).
 */
#include "bench_accuracy.h"
#include "rasterizer.h"   /* hw2 reference: resolve_pixel */
#include "stage3_setup.h" /* ras_viewport */

#include <math.h>   /* log10, isfinite, INFINITY, NAN */
#include <stdarg.h> /* va_list */
#include <stdio.h>  /* fprintf, snprintf */
#include <stdlib.h> /* malloc, free, qsort, exit */
#include <string.h> /* strcmp, strlen */
#include <time.h>   /* clock_gettime */

acc_settings acc_opt;
acc_row acc_rows[ACC_MAX_ROWS];
int acc_row_count;
static int failures;

void acc_progress(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fputs("bench_accuracy: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

void acc_check(bool ok, const char *fmt, ...) {
    if (!acc_opt.check) return;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "  check %s: ", ok ? "ok  " : "FAIL");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    if (!ok) failures++;
}

int acc_failures(void) { return failures; }

acc_row *acc_new_row(const char *section, const char *scene, const char *option) {
    if (acc_row_count >= ACC_MAX_ROWS) {
        fprintf(stderr, "bench_accuracy: too many rows\n");
        exit(2);
    }
    /* A truncated name would no longer be found by acc_find_row. */
    if (strlen(option) >= sizeof acc_rows[0].option || strlen(scene) >= sizeof acc_rows[0].scene) {
        fprintf(stderr, "bench_accuracy: row name too long: %s / %s\n", scene, option);
        exit(2);
    }
    acc_row *r = &acc_rows[acc_row_count++];
    *r = (acc_row){.med = NAN,
                   .min = NAN,
                   .max = NAN,
                   .rel = NAN,
                   .rmse_all = NAN,
                   .psnr_all = NAN,
                   .rmse_edge = NAN,
                   .psnr_edge = NAN,
                   .cracks = NAN,
                   .doubles = NAN,
                   .v_max = NAN,
                   .formula = NAN,
                   .uv_max_texels = NAN,
                   .uv_rms_texels = NAN,
                   .wrong = NAN,
                   .bytes = NAN,
                   .samples = 1};
    snprintf(r->section, sizeof r->section, "%s", section);
    snprintf(r->scene, sizeof r->scene, "%s", scene);
    snprintf(r->option, sizeof r->option, "%s", option);
    return r;
}

/* rel = fastest frame / the fastest frame of the cheapest timed row of the
 * same section and scene: on a shared machine the fastest frame is the one
 * least disturbed by other load (cache and memory contention survive even
 * CPU-time measurement), so the ratio is more repeatable than the medians'. */
void acc_fill_relative_times(void) {
    for (int i = 0; i < acc_row_count; i++) {
        double best = INFINITY;
        for (int j = 0; j < acc_row_count; j++)
            if (!strcmp(acc_rows[i].section, acc_rows[j].section) &&
                !strcmp(acc_rows[i].scene, acc_rows[j].scene) && acc_rows[j].min < best)
                best = acc_rows[j].min;
        if (isfinite(acc_rows[i].min) && best > 0) acc_rows[i].rel = acc_rows[i].min / best;
    }
}

acc_row *acc_find_row(const char *section, const char *scene, const char *option) {
    for (int i = 0; i < acc_row_count; i++)
        if (!strcmp(acc_rows[i].section, section) && !strcmp(acc_rows[i].scene, scene) &&
            !strcmp(acc_rows[i].option, option))
            return &acc_rows[i];
    return NULL;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
double acc_rnd(void) { /* xorshift64*, uniform in [0, 1) */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

void acc_die_oom(void *p) {
    if (!p) {
        fprintf(stderr, "bench_accuracy: out of memory\n");
        exit(2);
    }
}

double acc_psnr(double rmse) { return rmse > 0 ? 20 * log10(1.0 / rmse) : INFINITY; }

const mat4s *acc_identity(void) {
    static mat4s m;
    static bool done;
    if (!done) m = glms_mat4_identity();
    done = true;
    return &m;
}

ras_pipeline *acc_make_pipeline(int w, int h, ras_aa_mode aa, ras_pattern_kind kind, int count,
                                ras_rasterize_fn rasterize, unsigned varyings, ras_shade_fn shade,
                                void *user, vec3s clear) {
    ras_error err = {{0}};
    ras_pipeline_config cfg = {.width = w,
                               .height = h,
                               .clear_color = clear,
                               .aa = aa,
                               .varyings = varyings,
                               .rasterize = rasterize,
                               .resolve = resolve_pixel,
                               .shade = shade,
                               .shade_user = user};
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

void acc_draw_mesh_frame(void *ctx) {
    acc_mesh_frame *f = ctx;
    ras_error err = {{0}};
    ras_pipeline_begin_frame(f->p);
    for (int i = 0; i < f->mesh_count; i++)
        if (!ras_pipeline_draw_mesh(f->p, f->meshes[i], *acc_identity(), f->view, f->projection,
                                    &err)) {
            fprintf(stderr, "bench_accuracy: %s\n", err.msg);
            exit(2);
        }
    ras_pipeline_end_frame(f->p, f->img);
}

/* This thread's CPU time in ms: unlike the wall clock it does not count the
 * time the thread waits while other processes run, so a busy machine
 * disturbs it far less. */
static double cpu_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

void acc_time_group(acc_timed *t, int n) {
    int reps = acc_opt.repeats;
    double *ts = malloc((size_t)n * (size_t)reps * sizeof *ts);
    acc_die_oom(ts);
    for (int i = 0; i < n; i++)
        acc_draw_mesh_frame(&t[i].f);
    for (int k = 0; k < reps; k++)
        for (int i = 0; i < n; i++) {
            double t0 = cpu_ms();
            acc_draw_mesh_frame(&t[i].f);
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

ras_mesh *acc_screen_mesh(const acc_pt *v, const float *z, int tri_count, int w, int h,
                          vec3s color) {
    ras_mesh *m = ras_mesh_create((size_t)tri_count * 3, (size_t)tri_count);
    acc_die_oom(m);
    for (int i = 0; i < tri_count * 3; i++) {
        m->positions[i] = (vec3s){
            {(float)(2 * v[i].x / w - 1), (float)(2 * v[i].y / h - 1), z ? z[i / 3] : 0.0f}};
        m->colors[i] = color;
        m->indices[i] = (unsigned)i;
    }
    return m;
}

void acc_screen_triangles(const ras_mesh *m, mat4s view, mat4s projection, int w, int h,
                          vec4s *out /* 3 per triangle */) {
    ras_clip_vertex *cv = malloc(m->vertex_count * sizeof *cv);
    acc_die_oom(cv);
    ras_vertex_transform(m, *acc_identity(), view, projection, RAS_VARYING_COLOR, cv);
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            out[3 * t + k] = ras_viewport(cv[m->indices[3 * t + k]].p_clip, w, h);
    free(cv);
}
