/* hw2_figures.c — renders the pictures of docs/hw2.md with the reference
 * rasterizer, so no figure is drawn by hand:
 *
 *   hw2_zoom_aliasing.png  the classic scene where green's edge crosses blue,
 *                          magnified: no AA | MSAA 4x | SSAA 16x
 *   hw2_dark_seam.png      two white triangles sharing an edge, MSAA 4x:
 *                          correct (colour per sample) | the mistake (one
 *                          colour per pixel scaled by coverage)
 *   hw2_z_sign.png         the classic scene: correct | the viewport's z not
 *                          negated (larger looks closer: blue jumps in front)
 *   hw2_fan_cracks.png     a 3000-sliver fan: the reference's fixed-point
 *                          coverage (every sample once) | float edges with
 *                          >= 0 (red: hit twice, yellow: missed), drawn by
 *                          the accuracy benchmark's float-edge rasterizer
 *                          (tests/bench/bench_float_edges.c; the reference has no
 *                          float mode); the counts go to stdout. Instructors'
 *                          edition only: the handout has no float rasterizer
 *
 * The two mistakes are made by wrapping the reference rasterize hook, not by
 * editing it. Usage: hw2_figures [OUTPUT_DIR]   (default docs/img)
 */
#include "ras_pipeline.h"
#include "rasterizer.h"
#include "transform.h"
#ifdef RAS_HAVE_FLOAT_EDGES
#include "bench_float_edges.h" /* bench_rasterize_float_edges */
#endif

#include <math.h>   /* isinf, cos, sin */
#include <stdio.h>  /* printf, fprintf, snprintf */
#include <stdlib.h> /* calloc, free */

static const vec3s GREEN = {{217 / 255.0f, 238 / 255.0f, 185 / 255.0f}};
static const vec3s BLUE = {{185 / 255.0f, 217 / 255.0f, 238 / 255.0f}};
static const vec3s GAP = {{0.5f, 0.5f, 0.5f}};

/* ---- mistakes, as wrappers around the reference hook ---------------------- */

/* The z-sign mistake: depth = (1 + z_ndc)/2 instead of (1 - z_ndc)/2, i.e.
 * every depth d becomes 1 - d. */
static void rasterize_z_not_negated(const ras_triangle *t, const ras_raster_ctx *ctx) {
    ras_triangle flipped = *t;
    for (int i = 0; i < 3; i++) flipped.v[i].z = 1.0f - t->v[i].z;
    rasterize_triangle(&flipped, ctx);
}

/* The dark-seam mistake: coverage counted per sample, but only ONE colour per
 * pixel, scaled by this triangle's coverage, written over the whole pixel. */
static void rasterize_seam(const ras_triangle *t, const ras_raster_ctx *ctx) {
    ras_framebuffer *fb = ctx->fb;
    ras_framebuffer *tmp = ras_framebuffer_create(fb->width, fb->height, fb->samples, NULL);
    if (!tmp) return;
    ras_raster_ctx c = *ctx;
    c.fb = tmp;
    c.counters = NULL;
    rasterize_triangle(t, &c);
    for (int y = 0; y < fb->height; y++)
        for (int x = 0; x < fb->width; x++) {
            int base = ras_fb_sample_index(fb, x, y, 0), cnt = 0;
            vec3s color = {{0, 0, 0}};
            for (int s = 0; s < fb->samples; s++)
                if (!isinf(tmp->depth[base + s])) {
                    cnt++;
                    color = tmp->color[base + s];
                }
            if (!cnt) continue;
            vec3s scaled = glms_vec3_scale(color, (float)cnt / (float)fb->samples);
            for (int s = 0; s < fb->samples; s++) fb->color[base + s] = scaled;
        }
    ras_framebuffer_destroy(tmp);
}

/* ---- rendering ------------------------------------------------------------- */

static ras_pipeline *make_pipeline(int w, int h, ras_aa_mode aa, int samples,
                                   ras_rasterize_fn hook) {
    ras_pipeline_config cfg = {.width = w, .height = h, .aa = aa,
                               .varyings = RAS_VARYING_COLOR, .rasterize = hook,
                               .resolve = resolve_pixel};
    cfg.pattern = ras_sample_pattern_center();
    ras_error err = {{0}};
    if (aa != RAS_AA_NONE && !ras_sample_pattern_make(RAS_PATTERN_ORDERED, samples, &cfg.pattern, &err))
        return NULL;
    return ras_pipeline_create(&cfg, &err);
}

/* The classic scene, as hw2_rasterize draws it. */
static ras_image *render_classic(int side, ras_aa_mode aa, int samples, ras_rasterize_fn hook) {
    ras_pipeline *p = make_pipeline(side, side, aa, samples, hook);
    ras_mesh *g = ras_mesh_create_triangle((vec3s){{2, 0, -2}}, (vec3s){{0, 2, -2}},
                                           (vec3s){{-2, 0, -2}}, GREEN);
    ras_mesh *b = ras_mesh_create_triangle((vec3s){{3.5f, -1, -5}}, (vec3s){{2.5f, 1.5f, -5}},
                                           (vec3s){{-1, 0.5f, -5}}, BLUE);
    ras_image *img = ras_image_create(side, side, NULL);
    if (p && g && b && img) {
        ras_pipeline_begin_frame(p);
        mat4s proj = get_projection_matrix(45, 1, 0.1f, 50);
        mat4s view = ras_view_matrix_eye((vec3s){{0, 0, 5}});
        ras_pipeline_draw_mesh(p, g, glms_mat4_identity(), view, proj, NULL);
        ras_pipeline_draw_mesh(p, b, glms_mat4_identity(), view, proj, NULL);
        ras_pipeline_end_frame(p, img);
    }
    ras_pipeline_destroy(p);
    ras_mesh_destroy(g);
    ras_mesh_destroy(b);
    return img;
}

/* Copies the src window (col0, row0, w, h) magnified `zoom` times into dst at
 * (dc, dr), with a thin grid between magnified pixels when zoom >= 8. */
static void blit_zoom(ras_image *dst, int dc, int dr, const ras_image *src, int col0, int row0,
                      int w, int h, int zoom) {
    for (int r = 0; r < h * zoom; r++)
        for (int c = 0; c < w * zoom; c++) {
            vec3s v = ras_image_get(src, col0 + c / zoom, row0 + r / zoom);
            if (zoom >= 8 && (c % zoom == 0 || r % zoom == 0)) v = glms_vec3_scale(v, 0.85f);
            ras_image_set(dst, dc + c, dr + r, v);
        }
}

/* Panels side by side with a 6-pixel grey gap. */
static ras_image *side_by_side(ras_image **panels, int n, int pw, int ph) {
    ras_image *out = ras_image_create(n * pw + (n - 1) * 6, ph, NULL);
    if (!out) return NULL;
    ras_image_fill(out, GAP);
    for (int i = 0; i < n; i++)
        if (panels[i]) blit_zoom(out, i * (pw + 6), 0, panels[i], 0, 0, pw, ph, 1);
    return out;
}

static bool save(ras_image *img, const char *dir, const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    ras_error err = {{0}};
    bool ok = img && ras_image_save(img, path, &err);
    if (ok) printf("wrote %s\n", path);
    else fprintf(stderr, "hw2_figures: %s: %s\n", path, img ? err.msg : "out of memory");
    ras_image_destroy(img);
    return ok;
}

/* ---- the figures ----------------------------------------------------------- */

static bool figure_zoom(const char *dir) {
    /* Green's right edge crosses blue's top edge near screen (486, 455). */
    const int side = 700, win = 40, zoom = 8, col0 = 466, row0 = side - 1 - 475;
    ras_image *full[3] = {render_classic(side, RAS_AA_NONE, 1, rasterize_triangle),
                          render_classic(side, RAS_AA_MSAA, 4, rasterize_triangle),
                          render_classic(side, RAS_AA_SSAA, 16, rasterize_triangle)};
    ras_image *panels[3];
    for (int i = 0; i < 3; i++) {
        panels[i] = ras_image_create(win * zoom, win * zoom, NULL);
        if (panels[i] && full[i]) blit_zoom(panels[i], 0, 0, full[i], col0, row0, win, win, zoom);
    }
    ras_image *out = side_by_side(panels, 3, win * zoom, win * zoom);
    for (int i = 0; i < 3; i++) {
        ras_image_destroy(full[i]);
        ras_image_destroy(panels[i]);
    }
    return save(out, dir, "hw2_zoom_aliasing.png");
}

static ras_image *render_square(ras_rasterize_fn hook) {
    const int side = 20;
    ras_pipeline *p = make_pipeline(side, side, RAS_AA_MSAA, 4, hook);
    ras_image *img = ras_image_create(side, side, NULL);
    if (!p || !img) {
        ras_pipeline_destroy(p);
        return img;
    }
    ras_pipeline_begin_frame(p);
    /* Two white triangles sharing a slanted diagonal, straight in clip space
     * (w = 1) so the numbers read as NDC. */
    ras_clip_vertex v[4] = {0};
    const float xy[4][2] = {{-0.8f, -0.75f}, {0.8f, -0.8f}, {0.75f, 0.8f}, {-0.8f, 0.7f}};
    for (int i = 0; i < 4; i++) {
        v[i].p_clip = (vec4s){{xy[i][0], xy[i][1], 0, 1}};
        v[i].color = (vec3s){{1, 1, 1}};
    }
    ras_pipeline_draw_clip_triangle(p, &v[0], &v[1], &v[2]);
    ras_pipeline_draw_clip_triangle(p, &v[0], &v[2], &v[3]);
    ras_pipeline_end_frame(p, img);
    ras_pipeline_destroy(p);
    return img;
}

static bool figure_seam(const char *dir) {
    const int side = 20, zoom = 16;
    ras_image *full[2] = {render_square(rasterize_triangle), render_square(rasterize_seam)};
    ras_image *panels[2];
    for (int i = 0; i < 2; i++) {
        panels[i] = ras_image_create(side * zoom, side * zoom, NULL);
        if (panels[i] && full[i]) blit_zoom(panels[i], 0, 0, full[i], 0, 0, side, side, zoom);
    }
    ras_image *out = side_by_side(panels, 2, side * zoom, side * zoom);
    for (int i = 0; i < 2; i++) {
        ras_image_destroy(full[i]);
        ras_image_destroy(panels[i]);
    }
    return save(out, dir, "hw2_dark_seam.png");
}

static bool figure_z_sign(const char *dir) {
    const int side = 350;
    ras_image *panels[2] = {render_classic(side, RAS_AA_MSAA, 4, rasterize_triangle),
                            render_classic(side, RAS_AA_MSAA, 4, rasterize_z_not_negated)};
    ras_image *out = side_by_side(panels, 2, side, side);
    ras_image_destroy(panels[0]);
    ras_image_destroy(panels[1]);
    return save(out, dir, "hw2_z_sign.png");
}

#ifdef RAS_HAVE_FLOAT_EDGES
/* A fan of n thin triangles around a pixel centre, rim vertices on a 1/8-px
 * grid (as coordinates often are: integer or half-pixel models, snapped
 * vertices), so many samples lie EXACTLY on shared edges — where the >= 0
 * test counts them twice. Each triangle is drawn into its own buffer, then
 * every sample's hits are counted. */
#define FAN_CX(side) ((side) * 0.5 + 0.5)
#define FAN_CY(side) ((side) * 0.5 + 0.5)
static float snap(double v) { return (float)(floor(v * 8 + 0.5) / 8); }

static void fan_counts(ras_rasterize_fn rasterize, int n, int side, int *hits) {
    ras_framebuffer *fb = ras_framebuffer_create(side, side, 1, NULL);
    ras_raster_ctx ctx = {.fb = fb, .aa = RAS_AA_NONE, .pattern = ras_sample_pattern_center()};
    double cx = FAN_CX(side), cy = FAN_CY(side), r = side * 0.45;
    for (int i = 0; i < side * side; i++) hits[i] = 0;
    for (int i = 0; i < n && fb; i++) {
        double a0 = 2 * RAS_PI * i / n + 0.1, a1 = 2 * RAS_PI * (i + 1) / n + 0.1;
        ras_triangle t = {0};
        t.v[0] = (vec4s){{(float)cx, (float)cy, 0.5f, 1}};
        t.v[1] = (vec4s){{snap(cx + r * cos(a0)), snap(cy + r * sin(a0)), 0.5f, 1}};
        t.v[2] = (vec4s){{snap(cx + r * cos(a1)), snap(cy + r * sin(a1)), 0.5f, 1}};
        ras_framebuffer_clear(fb, (vec3s){{0, 0, 0}});
        rasterize(&t, &ctx);
        for (int y = 0; y < side; y++)
            for (int x = 0; x < side; x++)
                hits[y * side + x] += !isinf(fb->depth[ras_fb_pixel_index(fb, x, y)]);
    }
    ras_framebuffer_destroy(fb);
}

static bool figure_fan(const char *dir) {
    const int side = 160, n = 3000;
    int *hits = calloc((size_t)(side * side), sizeof *hits);
    ras_image *panels[2] = {ras_image_create(side, side, NULL), ras_image_create(side, side, NULL)};
    bool ok = hits && panels[0] && panels[1];
    const ras_rasterize_fn modes[2] = {rasterize_triangle, bench_rasterize_float_edges};
    const double cx = FAN_CX(side), cy = FAN_CY(side), r = side * 0.45;
    for (int m = 0; m < 2 && ok; m++) {
        fan_counts(modes[m], n, side, hits);
        long twice = 0, missed = 0;
        for (int y = 0; y < side; y++)
            for (int x = 0; x < side; x++) {
                int h = hits[y * side + x];
                /* Well inside the fan's rim, a sample must be hit exactly once. */
                bool inner = hypot(x + 0.5 - cx, y + 0.5 - cy) < r * cos(RAS_PI / n) - 1;
                if (x + 0.5 == cx && y + 0.5 == cy) continue; /* the shared apex: skip */
                vec3s c = h == 0 ? (vec3s){{0, 0, 0}} : (vec3s){{0.35f, 0.45f, 0.35f}};
                if (h > 1) {
                    twice++;
                    c = (vec3s){{1, 0.1f, 0.1f}};
                } else if (inner && h == 0) {
                    missed++;
                    c = (vec3s){{1, 1, 0}};
                }
                ras_image_set(panels[m], x, side - 1 - y, c);
            }
        printf("fan of %d triangles, %dx%d, %s edges: %ld samples hit twice, %ld missed\n", n,
               side, side, m ? "float" : "fixed", twice, missed);
    }
    free(hits);
    ras_image *zoomed[2];
    for (int i = 0; i < 2; i++) {
        zoomed[i] = ras_image_create(side * 2, side * 2, NULL);
        if (zoomed[i] && panels[i]) blit_zoom(zoomed[i], 0, 0, panels[i], 0, 0, side, side, 2);
        ras_image_destroy(panels[i]);
    }
    ras_image *out = ok ? side_by_side(zoomed, 2, side * 2, side * 2) : NULL;
    ras_image_destroy(zoomed[0]);
    ras_image_destroy(zoomed[1]);
    return save(out, dir, "hw2_fan_cracks.png");
}
#endif

int main(int argc, char **argv) {
    const char *dir = argc > 1 ? argv[1] : "docs/img";
    bool ok = figure_zoom(dir);
    ok = figure_seam(dir) && ok;
    ok = figure_z_sign(dir) && ok;
#ifdef RAS_HAVE_FLOAT_EDGES
    ok = figure_fan(dir) && ok;
#endif
    return ok ? 0 : 1;
}
