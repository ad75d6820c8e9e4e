/* test_dump.c — --dump's buffer files (common/pipeline/ras_dump.h, ras_pipeline_dump)
 * checked against the buffers in memory:
 *
 *   exact       depth.pfm read back is the framebuffer's depth bit for bit
 *               (+INF where nothing was drawn); a buffer with NaN and -INF
 *               too; coverage.pfm is (depth != +INF) per sample
 *   hand-worked overdraw of a far quad and a near triangle drawn after it is
 *               2 inside the triangle, 1 elsewhere on the quad, 0 outside;
 *               drawn before it, 1 (the far one fails the depth test)
 *   existence   no coverage file without anti-aliasing, no file at all for a
 *               wireframe; the sidecar's size, range and empty count are the
 *               ones computed here; the picture is the frame plus its legend
 *   hw3         the fragment stage's buffers exist exactly for the varyings
 *               the shader reads (phong: normal and view_depth, no uv;
 *               texture: uv too); where something was drawn the normal is a
 *               unit vector, elsewhere +INF; dumping changes no pixel
 *   compare     a dump against itself is the same; with isolated depths
 *               changed, "in speckles"; with one row changed, "along a row";
 *               with a triangle missing, "where only one drew"
 *   vertices    hw1's vertices.json: a hand-worked vertex through a model
 *               translation, an identity view and a projection that halves x
 *               and sets w = 2: world, eye, clip, NDC and screen by hand
 *   errors      --dump on a file says it expects a folder
 *   legend      one value is said as one value, a range as its two ends
 */
#include <setjmp.h> /* cmocka needs these before cmocka.h */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ras_test_main.h"

#include "ras_builtin_scenes.h"
#include "ras_dump.h"
#include "ras_image.h"
#include "ras_io.h"
#include "ras_mesh.h"
#include "ras_pipeline.h"
#include "rasterizer.h" /* hw2 reference: rasterize_triangle, resolve_pixel */
#include "scene.h"      /* hw3: hw3_render with dump_dir */

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) fail_msg(__VA_ARGS__);                                                        \
    } while (0)

enum { W = 24, H = 16 };

/* A fresh folder under /tmp for one test. */
static void temp_dir(char *dir, size_t size) {
    snprintf(dir, size, "/tmp/raster101-test-dump-XXXXXX");
    assert_non_null(mkdtemp(dir));
}

static void remove_dir(const char *dir) {
    char cmd[512];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static bool exists(const char *dir, const char *file) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    return access(path, F_OK) == 0;
}

/* A clip-space vertex at NDC (x, y) with clip w = 1 and NDC depth z. */
static ras_clip_vertex vtx(float x, float y, float z) {
    ras_clip_vertex v = {0};
    v.p_clip = (vec4s){{x, y, z, 1}};
    v.color = (vec3s){{1, 1, 1}};
    return v;
}

static ras_pipeline *pipeline(ras_aa_mode aa, int samples) {
    ras_pipeline_config cfg = {.width = W,
                               .height = H,
                               .aa = aa,
                               .rasterize = rasterize_triangle,
                               .resolve = resolve_pixel,
                               .dump = true};
    ras_error err = {{0}};
    cfg.pattern = ras_sample_pattern_center();
    if (samples > 1)
        CHECK(ras_sample_pattern_make(RAS_PATTERN_ORDERED, samples, &cfg.pattern, &err),
              "pattern: %s", err.msg);
    ras_pipeline *p = ras_pipeline_create(&cfg, &err);
    CHECK(p, "pipeline: %s", err.msg);
    return p;
}

/* A far quad over the left of the screen (two triangles; its right edge at
 * NDC 0.55 is screen x = 18.6, inside pixel column 18),
 * and a near triangle in its middle, drawn in the given order. */
static void draw_scene(ras_pipeline *p, bool near_first) {
    /* NDC z: larger is nearer here (depth z01 = (1 - z_ndc) / 2, smaller
     * is closer), so the quad at -0.5 (depth 0.75) is behind the triangle at
     * 0.5 (depth 0.25) */
    ras_clip_vertex q[4] = {vtx(-1, -1, -0.5f), vtx(0.55f, -1, -0.5f), vtx(0.55f, 1, -0.5f),
                            vtx(-1, 1, -0.5f)};
    ras_clip_vertex t[3] = {vtx(-0.6f, -0.6f, 0.5f), vtx(0.2f, -0.6f, 0.5f),
                            vtx(-0.2f, 0.6f, 0.5f)};
    if (near_first) ras_pipeline_draw_clip_triangle(p, &t[0], &t[1], &t[2]);
    ras_pipeline_draw_clip_triangle(p, &q[0], &q[1], &q[2]);
    ras_pipeline_draw_clip_triangle(p, &q[0], &q[2], &q[3]);
    if (!near_first) ras_pipeline_draw_clip_triangle(p, &t[0], &t[1], &t[2]);
}

/* A JSON file of a dump, parsed (the test fails when it is missing or bad). */
static cJSON *read_json(const char *dir, const char *file) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    ras_error err = {{0}};
    size_t len = 0;
    char *text = ras_io_read_file(path, "dump description", 1 << 20, &len, &err);
    CHECK(text, "%s: %s", file, err.msg);
    cJSON *j = cJSON_ParseWithLength(text, len);
    free(text);
    CHECK(j, "%s is not JSON", file);
    return j;
}

static float *read_back(const char *dir, const char *name, int *w, int *h, int *ch) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s.pfm", dir, name);
    ras_error err = {{0}};
    float *f = ras_dump_read_pfm(path, w, h, ch, &err);
    CHECK(f, "%s.pfm: %s", name, err.msg);
    return f;
}

static void test_dump_depth_exact_and_overdraw(void **state) {
    (void)state;
    char dir[64];
    temp_dir(dir, sizeof dir);
    for (int order = 0; order < 2; order++) {
        ras_pipeline *p = pipeline(RAS_AA_NONE, 1);
        draw_scene(p, order == 1);
        int written = 0;
        ras_error err = {{0}};
        CHECK(ras_pipeline_dump(p, dir, &written, &err), "dump: %s", err.msg);
        assert_int_equal(written, 2); /* depth and overdraw; no coverage at 1x */
        CHECK(!exists(dir, "coverage.pfm") && !exists(dir, "coverage.png"),
              "a frame without anti-aliasing has no coverage buffer, yet coverage files exist");
        int w, h, ch;
        float *depth = read_back(dir, "depth", &w, &h, &ch);
        assert_int_equal(w, W);
        assert_int_equal(h, H);
        assert_int_equal(ch, 1);
        CHECK(memcmp(depth, p->fb->depth, sizeof(float) * W * H) == 0,
              "depth.pfm differs from the depth buffer in memory");
        free(depth);
        float *over = read_back(dir, "overdraw", &w, &h, &ch);
        /* Screen pixel (x, y): the near triangle covers NDC x -0.6..0.2 at
         * the bottom; pixel (6, 5) has its centre (6.5, 5.5) at NDC
         * (-0.458, -0.3125), inside it; pixel (2, 14) is on the quad only;
         * pixel (22, 8) is right of the quad (NDC x 0.875 > 0.55). */
        int in_both = ras_fb_pixel_index(p->fb, 6, 5), quad_only = ras_fb_pixel_index(p->fb, 2, 14),
            outside = ras_fb_pixel_index(p->fb, 22, 8);
        float want = order == 1 ? 1.0f : 2.0f;
        CHECK(over[in_both] == want,
              "overdraw where the near triangle is %s the far quad: expected %g, got %g",
              order == 1 ? "drawn before (the quad fails the depth test)" : "drawn after",
              (double)want, (double)over[in_both]);
        CHECK(over[quad_only] == 1.0f && over[outside] == 0.0f,
              "overdraw on the quad only: expected 1 and 0 outside, got %g and %g",
              (double)over[quad_only], (double)over[outside]);
        CHECK(memcmp(over, p->overdraw, sizeof(float) * W * H) == 0,
              "overdraw.pfm differs from the count in memory");
        free(over);
        /* the sidecar: sizes, the range and the empty count, computed here */
        char path[512];
        ras_error e2 = {{0}};
        cJSON *j = read_json(dir, "depth.json");
        double lo = INFINITY, hi = -INFINITY;
        long empty = 0;
        for (int i = 0; i < W * H; i++) {
            float d = p->fb->depth[i];
            if (d == INFINITY) {
                empty++;
                continue;
            }
            lo = d < lo ? d : lo;
            hi = d > hi ? d : hi;
        }
        cJSON *range = cJSON_GetArrayItem(cJSON_GetObjectItem(j, "range"), 0);
        CHECK(cJSON_GetObjectItem(j, "width")->valueint == W &&
                  cJSON_GetObjectItem(j, "samples")->valueint == 1 &&
                  !strcmp(cJSON_GetObjectItem(j, "buffer")->valuestring, "depth"),
              "depth.json: wrong size, samples or name");
        CHECK(fabs(cJSON_GetArrayItem(range, 0)->valuedouble - lo) < 1e-7 &&
                  fabs(cJSON_GetArrayItem(range, 1)->valuedouble - hi) < 1e-7,
              "depth.json range [%g, %g], expected [%g, %g]",
              cJSON_GetArrayItem(range, 0)->valuedouble, cJSON_GetArrayItem(range, 1)->valuedouble,
              lo, hi);
        CHECK((long)cJSON_GetObjectItem(j, "empty_entries")->valuedouble == empty,
              "depth.json: %g empty entries, expected %ld",
              cJSON_GetObjectItem(j, "empty_entries")->valuedouble, empty);
        cJSON_Delete(j);
        /* the picture: the frame and the legend below it; nothing drawn at
         * the right edge, so black there */
        snprintf(path, sizeof path, "%s/depth.png", dir);
        ras_image *img = ras_image_load(path, &e2);
        CHECK(img, "depth.png: %s", e2.msg);
        CHECK(img->width == W && img->height > H,
              "depth.png is %dx%d, expected %d wide and a "
              "legend below %d rows",
              img->width, img->height, W, H);
        vec3s c = ras_image_get(img, W - 1, 0);
        CHECK(c.x == 0 && c.y == 0 && c.z == 0, "an empty pixel of depth.png is not black");
        ras_image_destroy(img);
        ras_pipeline_destroy(p);
    }
    remove_dir(dir);
}

static void test_dump_coverage_per_sample(void **state) {
    (void)state;
    char dir[64];
    temp_dir(dir, sizeof dir);
    ras_pipeline *p = pipeline(RAS_AA_MSAA, 4);
    draw_scene(p, false);
    int written = 0;
    ras_error err = {{0}};
    CHECK(ras_pipeline_dump(p, dir, &written, &err), "dump: %s", err.msg);
    /* depth, coverage, overdraw and the per-sample colour */
    assert_int_equal(written, 4);
    int w, h, ch;
    /* sample_colour holds exactly the framebuffer's colour of every sample
     * (what the resolve averages: an MSAA colour mistake shows there) */
    float *col = read_back(dir, "sample_colour", &w, &h, &ch);
    CHECK(w == W * 4 && h == H && ch == 3, "sample_colour.pfm is %dx%d (%d channels), expected "
                                           "%dx%d with 3",
          w, h, ch, W * 4, H);
    for (int i = 0; i < W * H * 4; i++)
        for (int k = 0; k < 3; k++)
            CHECK(col[3 * i + k] == p->fb->color[i].raw[k],
                  "sample_colour entry %d channel %d is %g, the framebuffer holds %g", i, k,
                  (double)col[3 * i + k], (double)p->fb->color[i].raw[k]);
    free(col);
    float *cov = read_back(dir, "coverage", &w, &h, &ch);
    CHECK(w == W * 4 && h == H && ch == 1, "coverage.pfm is %dx%d (%d channels), expected %dx%d", w,
          h, ch, W * 4, H);
    long partial = 0;
    for (int i = 0; i < W * H * 4; i++)
        CHECK(cov[i] == (p->fb->depth[i] != INFINITY ? 1.0f : 0.0f),
              "coverage entry %d is %g, but the depth there is %g", i, (double)cov[i],
              (double)p->fb->depth[i]);
    for (int i = 0; i < W * H; i++) {
        float s = cov[4 * i] + cov[4 * i + 1] + cov[4 * i + 2] + cov[4 * i + 3];
        partial += s > 0 && s < 4;
    }
    /* Hand-worked: the near triangle lies on the quad, so its edges cover
     * nothing new; the quad's right edge at x = 18.6 splits column 18 (the
     * ordered 4x samples at x + 0.25 and x + 0.75: 18.25 in, 18.75 out), and
     * only that column, all H rows. */
    CHECK(partial == H, "pixels partly covered: expected %d (column 18), got %ld", H, partial);
    float *depth = read_back(dir, "depth", &w, &h, &ch);
    CHECK(w == W * 4 && memcmp(depth, p->fb->depth, sizeof(float) * W * H * 4) == 0,
          "per-sample depth.pfm differs from the depth buffer in memory");
    free(depth);
    free(cov);
    ras_pipeline_destroy(p);
    remove_dir(dir);
}

static void test_dump_wireframe_writes_nothing(void **state) {
    (void)state;
    char dir[64];
    temp_dir(dir, sizeof dir);
    ras_pipeline_config cfg = {.width = W, .height = H, .wireframe = true, .dump = true};
    ras_pipeline *p = ras_pipeline_create(&cfg, NULL);
    assert_non_null(p);
    draw_scene(p, false);
    int written = -1;
    assert_true(ras_pipeline_dump(p, dir, &written, NULL));
    assert_int_equal(written, 0);
    CHECK(!exists(dir, "depth.pfm"), "a wireframe has no depth buffer, yet depth.pfm exists");
    ras_pipeline_destroy(p);
    remove_dir(dir);
}

/* NaN, ±INF and the smallest subnormal survive the file bit for bit, in one
 * channel and in three. */
static void test_dump_exact_special_values(void **state) {
    (void)state;
    char dir[64];
    temp_dir(dir, sizeof dir);
    float v[2 * 3 * 3];
    const float special[] = {NAN, INFINITY, -INFINITY, 1e-45f, -0.0f, 0.1f, 3.4e38f, -1, 0.5f};
    for (int i = 0; i < 18; i++)
        v[i] = special[i % 9];
    for (int ch = 1; ch <= 3; ch += 2) {
        ras_dump_buffer b = {.name = "special",
                             .what = "test values",
                             .units = "none",
                             .width = 3,
                             .height = ch == 1 ? 6 : 2,
                             .samples = 1,
                             .channels = ch,
                             .data = v,
                             .style = ch == 1 ? RAS_DUMP_SCALAR : RAS_DUMP_VECTOR};
        ras_error err = {{0}};
        CHECK(ras_dump_write(dir, &b, &err), "write: %s", err.msg);
        int w, h, c;
        float *back = read_back(dir, "special", &w, &h, &c);
        CHECK(w == 3 && h == b.height && c == ch && memcmp(back, v, sizeof v) == 0,
              "%d-channel special values did not come back bit for bit", ch);
        free(back);
    }
    remove_dir(dir);
}

static void test_dump_hw3_fragment_buffers(void **state) {
    (void)state;
    const char *shaders[2] = {"phong", "texture"};
    for (int k = 0; k < 2; k++) {
        char dir[64];
        temp_dir(dir, sizeof dir);
        ras_error err = {{0}};
        ras_scene *scene = ras_builtin_scene_load("hw3_default", &err);
        ras_scene_assets *assets = scene ? ras_scene_load_assets(scene, &err) : NULL;
        CHECK(assets, "default scene: %s", err.msg);
        scene->width = 96, scene->height = 72;
        hw3_render_options opt = hw3_render_defaults();
        assert_true(hw3_shader_parse(shaders[k], &opt.shader, &err));
        ras_image *plain = ras_image_create(96, 72, NULL), *dumped = ras_image_create(96, 72, NULL);
        assert_true(plain && dumped);
        CHECK(hw3_render(scene, assets, &opt, plain, NULL, &err), "render: %s", err.msg);
        opt.dump_dir = dir;
        CHECK(hw3_render(scene, assets, &opt, dumped, NULL, &err), "render with --dump: %s",
              err.msg);
        CHECK(memcmp(plain->pixels, dumped->pixels, sizeof(vec3s) * 96 * 72) == 0,
              "%s: the picture changed when its buffers were dumped", shaders[k]);
        bool want_uv = k == 1;
        CHECK(exists(dir, "depth.pfm") && exists(dir, "overdraw.pfm") &&
                  exists(dir, "normal.pfm") && exists(dir, "view_depth.pfm") &&
                  exists(dir, "uv.pfm") == want_uv && !exists(dir, "coverage.pfm"),
              "%s: expected depth, overdraw, normal, view_depth%s and no coverage", shaders[k],
              want_uv ? ", uv" : " and no uv (the shader reads no texture)");
        int w, h, ch;
        float *n = read_back(dir, "normal", &w, &h, &ch);
        float *d = read_back(dir, "depth", &w, &h, &ch);
        long drawn = 0;
        for (int i = 0; i < 96 * 72; i++) {
            double len = sqrt((double)n[3 * i] * n[3 * i] + (double)n[3 * i + 1] * n[3 * i + 1] +
                              (double)n[3 * i + 2] * n[3 * i + 2]);
            if (d[i] == INFINITY)
                CHECK(n[3 * i] == INFINITY, "%s: a normal at pixel %d where nothing was drawn",
                      shaders[k], i);
            else {
                drawn++;
                CHECK(fabs(len - 1) < 1e-5, "%s: normal at pixel %d has length %g, not 1",
                      shaders[k], i, len);
            }
        }
        CHECK(drawn > 96 * 72 / 10, "%s: only %ld pixels drawn", shaders[k], drawn);
        free(n);
        free(d);
        ras_image_destroy(plain);
        ras_image_destroy(dumped);
        ras_scene_assets_destroy(assets);
        ras_scene_destroy(scene);
        remove_dir(dir);
    }
}

/* Writes `depth` (W x H) as the depth buffer of a dump in dir. */
static void write_depth(const char *dir, const float *depth) {
    ras_dump_buffer b = {.name = "depth",
                         .what = "test",
                         .units = "test",
                         .width = W,
                         .height = H,
                         .samples = 1,
                         .channels = 1,
                         .data = depth,
                         .style = RAS_DUMP_SCALAR,
                         .empty = INFINITY,
                         .has_empty = true};
    ras_error err = {{0}};
    CHECK(ras_dump_write(dir, &b, &err), "write: %s", err.msg);
}

static void test_dump_compare_patterns(void **state) {
    (void)state;
    char ref[64], got[64];
    temp_dir(ref, sizeof ref);
    temp_dir(got, sizeof got);
    ras_pipeline *p = pipeline(RAS_AA_NONE, 1);
    draw_scene(p, false);
    float base[W * H], d[W * H];
    memcpy(base, p->fb->depth, sizeof base);
    ras_pipeline_destroy(p);
    write_depth(ref, base);
    ras_dump_difference diff;
    ras_error err = {{0}};
    write_depth(got, base);
    CHECK(ras_dump_compare(ref, got, "depth", &diff, &err), "compare: %s", err.msg);
    CHECK(diff.pixels_differ == 0, "a dump against itself: %ld pixels differ", diff.pixels_differ);
    /* 5 isolated pixels on the quad, far apart: speckle */
    memcpy(d, base, sizeof d);
    const int spots[5][2] = {{2, 2}, {8, 3}, {3, 10}, {12, 12}, {16, 6}};
    for (int k = 0; k < 5; k++)
        d[spots[k][1] * W + spots[k][0]] += 0.01f;
    write_depth(got, d);
    CHECK(ras_dump_compare(ref, got, "depth", &diff, &err), "compare: %s", err.msg);
    CHECK(diff.pixels_differ == 5 && !strcmp(diff.pattern, "in speckles") && diff.first_col == 2 &&
              diff.first_row == 2,
          "5 isolated depths changed: expected 5 pixels 'in speckles', the first at (2, 2), row by "
          "row; got "
          "%ld '%s' at (%d, %d)",
          diff.pixels_differ, diff.pattern, diff.first_col, diff.first_row);
    /* image row 7 wrong along its whole width: a line (W = 24 pixels) */
    memcpy(d, base, sizeof d);
    for (int x = 0; x < W; x++)
        d[7 * W + x] = d[7 * W + x] == INFINITY ? 0.5f : d[7 * W + x] + 0.1f;
    write_depth(got, d);
    CHECK(ras_dump_compare(ref, got, "depth", &diff, &err), "compare: %s", err.msg);
    CHECK(!strcmp(diff.pattern, "along a row") && diff.line == 7,
          "row 7 changed: expected 'along a row' 7, got '%s' %d", diff.pattern, diff.line);
    /* everything drawn missing: only the reference drew */
    for (int i = 0; i < W * H; i++)
        d[i] = INFINITY;
    write_depth(got, d);
    CHECK(ras_dump_compare(ref, got, "depth", &diff, &err), "compare: %s", err.msg);
    CHECK(!strcmp(diff.pattern, "where only one drew") && diff.drawn_in_one == diff.pixels_differ,
          "nothing drawn: expected 'where only one drew', got '%s' (%ld of %ld)", diff.pattern,
          diff.drawn_in_one, diff.pixels_differ);
    /* a file larger than the reference's is not read */
    char path[160];
    snprintf(path, sizeof path, "%s/depth.pfm", got);
    FILE *f = fopen(path, "ab");
    assert_non_null(f);
    static char pad[8192];
    fwrite(pad, 1, sizeof pad, f);
    fclose(f);
    CHECK(!ras_dump_compare(ref, got, "depth", &diff, &err) && strstr(err.msg, "more than"),
          "an oversized buffer file: expected a refusal, got '%s'", err.msg);
    remove_dir(ref);
    remove_dir(got);
}

static double at(const cJSON *v, const char *step, int k) {
    return cJSON_GetArrayItem(cJSON_GetObjectItem(v, step), k)->valuedouble;
}

static void test_dump_vertices_hand_worked(void **state) {
    (void)state;
    char dir[64];
    temp_dir(dir, sizeof dir);
    ras_mesh *m = ras_mesh_create_triangle((vec3s){{1, 2, 3}}, (vec3s){{0, 0, 0}},
                                           (vec3s){{0, 1, 0}}, (vec3s){{1, 1, 1}});
    assert_non_null(m);
    mat4s model = glms_translate_make((vec3s){{1, 0, -5}});
    /* x' = x/2, y' = y, z' = z, w' = 2 (a fixed w, easy to divide by) */
    mat4s proj = glms_mat4_zero();
    proj.m00 = 0.5f, proj.m11 = 1, proj.m22 = 1, proj.m33 = 2; /* m[column][row] */
    ras_error err = {{0}};
    CHECK(ras_dump_vertices(dir, "vertices", m, model, glms_mat4_identity(), proj, W, H, &err),
          "dump: %s",
          err.msg);
    ras_mesh_destroy(m);
    cJSON *j = read_json(dir, "vertices.json");
    const cJSON *v = cJSON_GetArrayItem(cJSON_GetObjectItem(j, "vertices"), 0);
    /* (1, 2, 3) moved by (1, 0, -5): world (2, 2, -2); the view is the
     * identity; clip = (1, 2, -2, 2); NDC = (0.5, 1, -1); screen x =
     * (0.5 + 1) / 2 * 24 = 18, y = (1 + 1) / 2 * 16 = 16 */
    const double want[][4] = {{2, 2, -2}, {2, 2, -2}, {1, 2, -2, 2}, {0.5, 1, -1}, {18, 16}};
    const char *steps[] = {"world", "eye", "clip", "ndc", "screen"};
    const int count[] = {3, 3, 4, 3, 2};
    for (int s = 0; s < 5; s++)
        for (int k = 0; k < count[s]; k++)
            CHECK(fabs(at(v, steps[s], k) - want[s][k]) < 1e-5,
                  "vertices.json: %s[%d] is %g, expected %g (by hand)", steps[s], k,
                  at(v, steps[s], k), want[s][k]);
    cJSON_Delete(j);
    remove_dir(dir);
}

static void test_dump_dir_must_be_a_folder(void **state) {
    (void)state;
    char dir[64], file[128];
    temp_dir(dir, sizeof dir);
    snprintf(file, sizeof file, "%s/a-file", dir);
    FILE *f = fopen(file, "w");
    assert_non_null(f);
    fclose(f);
    ras_error err = {{0}};
    CHECK(!ras_dump_prepare_dir(file, &err) && strstr(err.msg, "expects a folder"),
          "--dump on a file: expected 'expects a folder', got '%s'", err.msg);
    char sub[160];
    snprintf(sub, sizeof sub, "%s/new", dir);
    CHECK(ras_dump_prepare_dir(sub, &err), "--dump into a new folder: %s", err.msg);
    remove_dir(dir);
}

/* A legend names a range only where there is one: a difference buffer whose
 * every drawn entry is 1 said "1 (blue) .. 1 (red)", two colours its picture
 * never shows. */
static void test_dump_legend_one_value(void **state) {
    (void)state;
    float one[4] = {INFINITY, 1, 1, INFINITY}, two[4] = {INFINITY, 1, 3, INFINITY};
    ras_dump_buffer b = {.name = "difference",
                         .what = "",
                         .units = "",
                         .width = 2,
                         .height = 2,
                         .samples = 1,
                         .channels = 1,
                         .data = one,
                         .style = RAS_DUMP_SCALAR,
                         .empty = INFINITY,
                         .has_empty = true};
    uint8_t rgb[2 * 2 * 3];
    char text[160];
    ras_dump_paint(&b, rgb, text, sizeof text);
    CHECK(strstr(text, "1 wherever drawn (one value") && !strstr(text, "(blue)"),
          "every drawn entry 1: expected the legend to say one value, got '%s'", text);
    b.data = two;
    ras_dump_paint(&b, rgb, text, sizeof text);
    CHECK(strstr(text, "1 (blue) .. 3 (red)"),
          "entries 1 and 3: expected the legend '1 (blue) .. 3 (red)', got '%s'", text);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dump_depth_exact_and_overdraw),
        cmocka_unit_test(test_dump_coverage_per_sample),
        cmocka_unit_test(test_dump_wireframe_writes_nothing),
        cmocka_unit_test(test_dump_exact_special_values),
        cmocka_unit_test(test_dump_hw3_fragment_buffers),
        cmocka_unit_test(test_dump_compare_patterns),
        cmocka_unit_test(test_dump_vertices_hand_worked),
        cmocka_unit_test(test_dump_dir_must_be_a_folder),
        cmocka_unit_test(test_dump_legend_one_value),
    };
    return RAS_RUN_TESTS("dump", tests, NULL, NULL);
}
