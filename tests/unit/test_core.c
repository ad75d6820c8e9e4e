/* test_core.c — the core library: math helpers, sample patterns, buffers,
 * clipping, viewport, line drawing, the command-line parser, image files and
 * the wireframe pipeline. No assignment code is linked here.
 */
#include "ras_app.h"
#include "ras_cli.h"
#include "ras_names.h"
#include "ras_draw.h"
#include "ras_dump.h"
#include "ras_image.h"
#include "ras_io.h"
#include "ras_job.h"
#include "ras_pipeline.h"
#include "stage2_clip.h"
#include "stage3_setup.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>   /* SIGABRT, SIGSEGV */
#include <sys/stat.h> /* chmod, stat */
#include <sys/vfs.h>  /* statfs: is /dev/shm a tmpfs */
#include <time.h> /* clock_gettime */
#include <unistd.h>

#include <cmocka.h>

/* ras_mat4_rows reads like paper: element (row 0, col 3) is the 4th argument. */
static void test_math_rows_constructor_is_row_major(void **state) {
    (void)state;
    mat4s t = ras_mat4_rows(1, 0, 0, 7, 0, 1, 0, 8, 0, 0, 1, 9, 0, 0, 0, 1);
    assert_float_equal(ras_mat4_at(t, 0, 3), 7, 0);
    assert_float_equal(t.raw[3][0], 7, 0); /* cglm: column 3, row 0 */
    vec4s p = glms_mat4_mulv(t, (vec4s){{1, 2, 3, 1}});
    if (p.x != 8 || p.y != 10 || p.z != 12)
        fail_msg("a translation by (7,8,9) moved (1,2,3) to (%g,%g,%g), expected (8,10,12)",
                 p.x, p.y, p.z);
}

/* max_diff treats NaN as infinitely different, so a NaN matrix never "matches". */
static void test_math_nan_never_near(void **state) {
    (void)state;
    mat4s a = glms_mat4_identity(), b = a;
    b.raw[1][2] = NAN;
    assert_false(ras_mat4_near(a, b, 1e9f));
}

/* ras_mat4_mulv and ras_mat4_mul add their four products in one fixed order
 * (cglm 0.8's, which drew the reference images), whatever cglm is installed:
 * 1 + 2^-24 + 2^-24 + 2^-24 rounds to 1 + 2^-22 added from w down to x, to
 * 1 + 2^-23 as cglm 0.7's (x + y) + (z + w), and to 1 from x up to w. */
static void test_math_products_fixed_rounding_order(void **state) {
    (void)state;
    const float tiny = 0x1p-24f;
    mat4s ones = ras_mat4_rows(1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
    vec4s p = ras_mat4_mulv(ones, (vec4s){{1, tiny, tiny, tiny}});
    if (p.x != 1 + 0x1p-22f)
        fail_msg("ras_mat4_mulv added 1 + 3 * 2^-24 to %a; expected %a (w + z, then y, then x)",
                 (double)p.x, (double)(1 + 0x1p-22f));
    vec3s q = ras_mat4_mulv3(ones, (vec3s){{1, tiny, tiny}}, tiny);
    assert_true(q.x == p.x);
    mat4s column = ras_mat4_rows(1, tiny, tiny, tiny, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
    mat4s m = ras_mat4_mul(column, ras_mat4_rows(1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0));
    if (ras_mat4_at(m, 0, 0) != 1)
        fail_msg("ras_mat4_mul added 1 + 3 * 2^-24 to %a; expected 1 (x + y, then z, then w)",
                 (double)ras_mat4_at(m, 0, 0));
    /* And they are the products: a rotation and a translation compose. */
    mat4s r = glms_rotate_make(0.7f, (vec3s){{1, 2, 3}});
    mat4s t = ras_mat4_rows(1, 0, 0, 7, 0, 1, 0, 8, 0, 0, 1, 9, 0, 0, 0, 1);
    assert_true(ras_mat4_near(ras_mat4_mul(t, r), glms_mat4_mul(t, r), 1e-6f));
    vec4s v = {{0.3f, -1.2f, 2.5f, 1}};
    vec4s a = ras_mat4_mulv(r, v), b = glms_mat4_mulv(r, v);
    for (int k = 0; k < 4; k++)
        assert_float_equal(a.raw[k], b.raw[k], 1e-6f);
}

/* Ordered grids sit at ((i+0.5)/n, (j+0.5)/n); standard 4x is D3D's table read y-up. */
/* A message longer than ras_error holds loses the middle of its longest
 * word (the path), never the reason after it; short messages are untouched. */
static void test_error_long_path_cut_in_the_middle(void **state) {
    (void)state;
    char path[1201];
    memset(path, 'p', sizeof path - 1);
    path[0] = '/';
    memcpy(path + sizeof path - 7, "/m.obj", 7);
    ras_error err;
    ras_error_set(&err, "could not read model '%s': it is an OBJ file, but %s", path,
                  "a face names a vertex that does not exist");
    size_t n = strlen(err.msg);
    assert_true(n < sizeof err.msg);
    assert_non_null(strstr(err.msg, "could not read model '/ppp"));
    assert_non_null(strstr(err.msg, "[...]"));
    assert_non_null(strstr(err.msg, "/m.obj': it is an OBJ file, but a face names a vertex that "
                                    "does not exist"));
    ras_error_set(&err, "short '%s' stays", "x");
    assert_string_equal(err.msg, "short 'x' stays");
    /* no long word at all: only then is the end cut */
    char words[3000] = "";
    for (int i = 0; i < 500; i++) strcat(words, "ab ");
    ras_error_set(&err, "%s", words);
    assert_int_equal(strlen(err.msg), sizeof err.msg - 1);
}

static void test_sample_patterns_positions(void **state) {
    (void)state;
    ras_sample_pattern p;
    ras_error err;
    assert_true(ras_sample_pattern_make(RAS_PATTERN_ORDERED, 4, &p, &err));
    assert_int_equal(p.count, 4);
    assert_float_equal(p.offsets[0].x, 0.25, 1e-7);
    assert_float_equal(p.offsets[3].y, 0.75, 1e-7);
    assert_true(ras_sample_pattern_make(RAS_PATTERN_STANDARD, 4, &p, &err));
    /* D3D (-2,-6)/16 from the centre → (0.5 - 0.125, 0.5 - 0.375). */
    assert_float_equal(p.offsets[0].x, 0.375, 1e-7);
    assert_float_equal(p.offsets[0].y, 0.125, 1e-7);
    const int counts[] = {2, 8, 16};
    for (int k = 0; k < 3; k++) {
        assert_true(ras_sample_pattern_make(RAS_PATTERN_STANDARD, counts[k], &p, &err));
        vec2s mean = {{0, 0}};
        for (int s = 0; s < p.count; s++) {
            assert_true(p.offsets[s].x >= 0 && p.offsets[s].x < 1);
            assert_true(p.offsets[s].y >= 0 && p.offsets[s].y < 1);
            mean = glms_vec2_add(mean, p.offsets[s]);
        }
        /* The 2x..16x tables are balanced around the pixel centre within 1/16 px. */
        assert_true(fabsf(mean.x / p.count - 0.5f) <= 1 / 16.0f);
    }
    assert_false(ras_sample_pattern_make(RAS_PATTERN_ORDERED, 8, &p, &err));
    assert_non_null(strstr(err.msg, "16 (4x4)"));
}

/* Screen (x, y) with y up maps to the image row height-1-y; samples are consecutive. */
static void test_framebuffer_index_math(void **state) {
    (void)state;
    ras_framebuffer *fb = ras_framebuffer_create(5, 3, 4, NULL);
    assert_non_null(fb);
    assert_int_equal(ras_fb_pixel_index(fb, 0, 0), 10); /* bottom-left → last row */
    assert_int_equal(ras_fb_pixel_index(fb, 4, 2), 4);  /* top-right → first row */
    assert_int_equal(ras_fb_sample_index(fb, 4, 0, 3), 14 * 4 + 3);
    assert_int_equal(fb->bytes, (size_t)5 * 3 * 4 * (sizeof(vec3s) + sizeof(float)));
    assert_true(isinf(fb->depth[0]) && fb->depth[0] > 0);
    ras_framebuffer_destroy(fb);
    ras_error err;
    assert_null(ras_framebuffer_create(0, 3, 1, &err));
    assert_non_null(strstr(err.msg, "0x3"));
}

static ras_clip_vertex cv(float x, float y, float z, float w) {
    return (ras_clip_vertex){.p_clip = {{x, y, z, w}}, .color = {{1, 1, 1}}};
}

/* A triangle inside the volume is passed through untouched. */
static void test_clip_inside_untouched(void **state) {
    (void)state;
    ras_clip_vertex a = cv(0, 0, 0, 1), b = cv(0.5f, 0, 0, 1), c = cv(0, 0.5f, 0, 1);
    ras_clip_vertex out[RAS_CLIP_MAX_VERTICES];
    int n;
    assert_int_equal(ras_clip_triangle(&a, &b, &c, out, &n), RAS_CLIP_INSIDE);
    assert_int_equal(n, 3);
}

/* One vertex behind the eye (w < 0): the result is a quad with every w > 0 and
 * no vertex on the wrong side — no inverted triangle across the screen. */
static void test_clip_one_vertex_behind_eye(void **state) {
    (void)state;
    ras_clip_vertex a = cv(0, 0, 0.5f, 1), b = cv(0.5f, 0, 0.5f, 1), c = cv(0, 0.5f, 2, -1);
    ras_clip_vertex out[RAS_CLIP_MAX_VERTICES];
    int n;
    assert_int_equal(ras_clip_triangle(&a, &b, &c, out, &n), RAS_CLIP_SPLIT);
    assert_int_equal(n, 4);
    for (int i = 0; i < n; i++) {
        assert_true(out[i].p_clip.w >= RAS_CLIP_W_EPSILON);
        assert_true(out[i].p_clip.z <= out[i].p_clip.w + 1e-6f);
        vec4s s = ras_viewport(out[i].p_clip, 100, 100);
        assert_true(ras_vec4_finite(s));
    }
}

/* Two vertices behind: a smaller triangle remains. Wholly behind: nothing. */
static void test_clip_two_behind_and_all_behind(void **state) {
    (void)state;
    ras_clip_vertex a = cv(0, 0, 0.5f, 1), b = cv(0.5f, 0, 2, -1), c = cv(0, 0.5f, 2, -1);
    ras_clip_vertex out[RAS_CLIP_MAX_VERTICES];
    int n;
    assert_int_equal(ras_clip_triangle(&a, &b, &c, out, &n), RAS_CLIP_SPLIT);
    assert_int_equal(n, 3);
    ras_clip_vertex d = cv(0, 0, 2, -1);
    assert_int_equal(ras_clip_triangle(&d, &b, &c, out, &n), RAS_CLIP_OUTSIDE);
    assert_int_equal(n, 0);
}

/* A vertex with w = 0 exactly never reaches the divide. */
static void test_clip_w_zero(void **state) {
    (void)state;
    ras_clip_vertex a = cv(0, 0, 0, 1), b = cv(0.5f, 0, 0, 1), c = cv(0.3f, 0.3f, 0, 0);
    ras_clip_vertex out[RAS_CLIP_MAX_VERTICES];
    int n;
    ras_clip_triangle(&a, &b, &c, out, &n);
    for (int i = 0; i < n; i++) assert_true(out[i].p_clip.w >= RAS_CLIP_W_EPSILON);
}

/* The viewport negates z: near (z_ndc = +1) → depth 0, far (−1) → depth 1. */
static void test_viewport_depth_smaller_is_closer(void **state) {
    (void)state;
    vec4s near_pt = ras_viewport((vec4s){{0, 0, 2, 2}}, 700, 700);
    vec4s far_pt = ras_viewport((vec4s){{0, 0, -3, 3}}, 700, 700);
    assert_float_equal(near_pt.z, 0, 1e-7);
    assert_float_equal(far_pt.z, 1, 1e-7);
    assert_float_equal(near_pt.x, 350, 1e-4);
    assert_float_equal(near_pt.w, 2, 0); /* clip w kept for perspective correction */
}

/* Lines with endpoints far off-screen or NaN are clipped or dropped, never written outside. */
static void test_draw_line_clips_safely(void **state) {
    (void)state;
    ras_framebuffer *fb = ras_framebuffer_create(16, 8, 1, NULL);
    vec3s white = {{1, 1, 1}};
    assert_int_equal(ras_draw_line(fb, (vec2s){{-1e9f, 4.5f}}, (vec2s){{1e9f, 4.5f}}, white), 16);
    assert_int_equal(ras_draw_line(fb, (vec2s){{NAN, 0}}, (vec2s){{3, 3}}, white), 0);
    assert_int_equal(ras_draw_line(fb, (vec2s){{-5, -5}}, (vec2s){{-1, -1}}, white), 0);
    /* (0.5,0.5)→(3.5,3.5): the diagonal, 4 pixels, pixel (2,2) included. */
    assert_int_equal(ras_draw_line(fb, (vec2s){{0.5f, 0.5f}}, (vec2s){{3.5f, 3.5f}}, white), 4);
    assert_float_equal(fb->color[ras_fb_pixel_index(fb, 2, 2)].x, 1, 0);
    ras_framebuffer_destroy(fb);
}

static ras_cli_status parse(ras_cli *cli, ras_error *err, unsigned accepted, int argc,
                            const char **argv) {
    return ras_cli_parse(argc, (char **)argv, accepted, cli, err);
}

/* Flags parse into fields; the classic positional form leaves the file positional. */
static void test_cli_parses_values(void **state) {
    (void)state;
    ras_cli cli;
    ras_error err;
    const char *argv[] = {"p", "-r", "20", "--aa", "msaa", "--samples", "4", "out.png"};
    assert_int_equal(parse(&cli, &err, RAS_OPT_ANGLE | RAS_OPT_AA, 8, argv), RAS_CLI_RUN);
    assert_float_equal(cli.angle, 20, 0);
    assert_int_equal(cli.aa, RAS_AA_MSAA);
    assert_int_equal(cli.samples, 4);
    assert_int_equal(cli.positional_count, 1);
    assert_string_equal(cli.positional[0], "out.png");
}

/* Unknown flags, flags of another program, bad numbers: clear errors naming the input. */
static void test_cli_rejects_bad_input(void **state) {
    (void)state;
    ras_cli cli;
    ras_error err;
    const char *unknown[] = {"p", "--frobnicate"};
    assert_int_equal(parse(&cli, &err, RAS_OPT_ANGLE, 2, unknown), RAS_CLI_ERROR);
    assert_non_null(strstr(err.msg, "--frobnicate"));
    const char *other[] = {"p", "--aa", "msaa"};
    assert_int_equal(parse(&cli, &err, RAS_OPT_ANGLE, 3, other), RAS_CLI_ERROR);
    assert_non_null(strstr(err.msg, "does not apply"));
    const char *nan_angle[] = {"p", "-r", "nan"};
    assert_int_equal(parse(&cli, &err, RAS_OPT_ANGLE, 3, nan_angle), RAS_CLI_ERROR);
    assert_non_null(strstr(err.msg, "'nan'"));
    const char *missing[] = {"p", "-o"};
    assert_int_equal(parse(&cli, &err, RAS_OPT_ANGLE, 2, missing), RAS_CLI_ERROR);
    assert_non_null(strstr(err.msg, "needs a value"));
    const char *axis[] = {"p", "--axis", "0,0,0"};
    assert_int_equal(parse(&cli, &err, RAS_OPT_ANGLE, 3, axis), RAS_CLI_ERROR);
    const char *help[] = {"p", "--help"};
    assert_int_equal(parse(&cli, &err, RAS_OPT_ANGLE, 2, help), RAS_CLI_HELP);
}

/* One set of rules for every program (ras_app_resolve): flags over the
 * scene; --samples N alone is MSAA; 2 and 8 samples take the standard
 * pattern without --pattern; --aa none with --samples N > 1 is an error;
 * every name comes from ras_names. */
static void test_app_resolve_one_rule_set(void **state) {
    (void)state;
    ras_app_hooks hooks = {.program = "p", .options = RAS_OPT_AA | RAS_OPT_SHADING};
    ras_cli cli;
    ras_error err;
    ras_app_settings set;
    const char *eight[] = {"p", "--samples", "8", "--shader", "bump", "--filter", "nearest"};
    assert_int_equal(parse(&cli, &err, hooks.options, 7, eight), RAS_CLI_RUN);
    assert_true(ras_app_resolve(&hooks, &cli, NULL, &set, &err));
    assert_int_equal(set.aa, RAS_AA_MSAA);
    assert_int_equal(set.pattern_kind, RAS_PATTERN_STANDARD);
    assert_int_equal(set.samples, 8);
    assert_int_equal(ras_app_settings_pattern(&set).count, 8);
    assert_int_equal(set.shader, RAS_SHADER_BUMP);
    assert_int_equal(set.filter, RAS_FILTER_NEAREST);
    const char *none[] = {"p", "--aa", "none", "--samples", "4"};
    assert_int_equal(parse(&cli, &err, hooks.options, 5, none), RAS_CLI_RUN);
    assert_false(ras_app_resolve(&hooks, &cli, NULL, &set, &err));
    assert_non_null(strstr(err.msg, "--aa none draws one sample"));
    const char *flat[] = {"p", "--shader", "flat"}; /* hw2's colour is no --shader */
    assert_int_equal(parse(&cli, &err, hooks.options, 3, flat), RAS_CLI_ERROR);
    assert_non_null(strstr(err.msg, "--shader expects normal, phong, texture, bump or "
                                    "displacement; got 'flat'"));
    char list[64];
    assert_string_equal(ras_names_list(&ras_names_aa, 0, list, sizeof list), "none, msaa or ssaa");
    assert_int_equal(ras_name_find(&ras_names_depth, "inverse_w", 0), RAS_DEPTH_INV_W);
    assert_string_equal(ras_name_of(&ras_names_cull, 99), "?");
}

/* PNG round trip is exact at 8 bits; a failed write leaves no file behind. */
static void test_image_roundtrip_and_failed_write(void **state) {
    (void)state;
    char dir[] = "/tmp/raster101-test-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[256];
    snprintf(path, sizeof path, "%s/img.png", dir);
    ras_image *img = ras_image_create(3, 2, NULL);
    ras_image_set(img, 0, 0, (vec3s){{1, 0, 0}});
    ras_image_set(img, 2, 1, (vec3s){{0, 128 / 255.0f, 1}});
    ras_error err;
    assert_true(ras_image_save(img, path, &err));
    ras_image *back = ras_image_load(path, &err);
    assert_non_null(back);
    assert_int_equal(back->width, 3);
    assert_float_equal(ras_image_get(back, 0, 0).x, 1, 0);
    assert_float_equal(ras_image_get(back, 2, 1).y, 128 / 255.0f, 1e-6);
    char bad[256];
    snprintf(bad, sizeof bad, "%s/no-such-folder/img.png", dir);
    assert_false(ras_image_save(img, bad, &err));
    assert_non_null(strstr(err.msg, "no-such-folder"));
    assert_null(ras_image_load(bad, &err));
    assert_non_null(strstr(err.msg, "could not read"));
    assert_int_equal(access(bad, F_OK), -1);
    remove(path);
    rmdir(dir);
    ras_image_destroy(img);
    ras_image_destroy(back);
}

/* ras_io_write_atomic's verify callback: the bytes must be the expected ones. */
typedef struct verify_seen {
    const char *expect;
    int calls;
    bool refuse;
} verify_seen;
static bool verify_bytes(const void *data, size_t len, void *ctx, ras_error *err) {
    verify_seen *v = ctx;
    v->calls++;
    if (v->refuse || len != strlen(v->expect) || memcmp(data, v->expect, len) != 0)
        return ras_error_set(err, "not the bytes meant");
    return true;
}

/* An atomic write on disk and in memory (a tmpfs, where the file is not read
 * back: the pages are the ones just written) writes the same bytes, has the
 * verify callback see exactly them, and leaves nothing when it refuses. */
static void test_atomic_write_on_disk_and_in_memory(void **state) {
    (void)state;
    char disk[] = "/tmp/raster101-test-XXXXXX", mem[] = "/dev/shm/raster101-test-XXXXXX";
    struct statfs fs;
    bool have_tmpfs = statfs("/dev/shm", &fs) == 0 && fs.f_type == 0x01021994 && mkdtemp(mem);
    assert_non_null(mkdtemp(disk));
    const char *dirs[2] = {disk, have_tmpfs ? mem : NULL};
    for (int k = 0; k < 2; k++) {
        if (!dirs[k]) continue;
        char path[256];
        snprintf(path, sizeof path, "%s/file.txt", dirs[k]);
        const char *text = "raster101 atomic write\n";
        verify_seen v = {text, 0, false};
        ras_error err = {{0}};
        assert_true(ras_io_write_atomic(path, "test file", text, strlen(text), verify_bytes, &v, &err));
        assert_int_equal(v.calls, 1);
        size_t len = 0;
        char *back = ras_io_read_file(path, "test file", 1024, &len, &err);
        assert_non_null(back);
        assert_int_equal(len, strlen(text));
        assert_memory_equal(back, text, len);
        free(back);
        /* refused: the earlier file stays as it was, no temporary file left */
        verify_seen no = {"other bytes", 0, true};
        assert_false(ras_io_write_atomic(path, "test file", "other bytes", 11, verify_bytes, &no, &err));
        assert_non_null(strstr(err.msg, "does not decode"));
        back = ras_io_read_file(path, "test file", 1024, &len, &err);
        assert_non_null(back);
        assert_memory_equal(back, text, strlen(text));
        free(back);
        remove(path);
        assert_int_equal(rmdir(dirs[k]), 0); /* empty: no temporary file stayed */
    }
    if (!have_tmpfs) print_message("(/dev/shm is not a tmpfs here: only the disk case ran)\n");
}

/* The size read from a file's header (the memory budget's estimate, before
 * decoding) is the size the file decodes to, in every format the programs
 * write; a replaced file keeps its permissions and no temporary file stays. */
static void test_image_header_size_matches_decode(void **state) {
    (void)state;
    char dir[] = "/tmp/raster101-test-XXXXXX";
    assert_non_null(mkdtemp(dir));
    static const char *const ext[] = {"png", "jpg", "bmp", "ppm", "tif"};
    ras_image *img = ras_image_create(37, 23, NULL);
    ras_error err;
    for (size_t k = 0; k < sizeof ext / sizeof *ext; k++) {
        char path[256];
        snprintf(path, sizeof path, "%s/img.%s", dir, ext[k]);
        assert_true(ras_image_save(img, path, &err));
        long w = 0, h = 0;
        assert_true(ras_image_peek_file(path, &w, &h));
        assert_int_equal(w, 37);
        assert_int_equal(h, 23);
        int dw = 0, dh = 0;
        uint8_t *rgb = ras_image_load_rgb8(path, &dw, &dh, &err);
        assert_non_null(rgb);
        assert_int_equal(dw, 37);
        assert_int_equal(dh, 23);
        free(rgb);
        assert_int_equal(chmod(path, 0640), 0);
        assert_true(ras_image_save(img, path, &err)); /* over the old one */
        struct stat st;
        assert_int_equal(stat(path, &st), 0);
        assert_int_equal(st.st_mode & 0777, 0640);
        remove(path);
    }
    assert_int_equal(rmdir(dir), 0); /* empty: no .img.png-XXXXXX left */
    ras_image_destroy(img);
}

/* The wireframe pipeline runs only vertex/clip/setup/wireframe: no raster, no resolve. */
static void test_pipeline_wireframe_runs_only_its_stages(void **state) {
    (void)state;
    ras_pipeline_config cfg = {.width = 64, .height = 64, .wireframe = true,
                               .wire_color = {{1, 1, 1}}};
    ras_error err;
    ras_pipeline *p = ras_pipeline_create(&cfg, &err);
    assert_non_null(p);
    ras_mesh *tri = ras_mesh_create_triangle((vec3s){{-0.5f, -0.5f, 0}}, (vec3s){{0.5f, -0.5f, 0}},
                                             (vec3s){{0, 0.5f, 0}}, (vec3s){{1, 1, 1}});
    ras_pipeline_begin_frame(p);
    /* An orthographic-ish projection: identity with w = 1. */
    assert_true(ras_pipeline_draw_mesh(p, tri, glms_mat4_identity(), glms_mat4_identity(),
                                       glms_mat4_identity(), &err));
    ras_image *img = ras_image_create(64, 64, NULL);
    ras_pipeline_end_frame(p, img);
    unsigned expected = RAS_STAGE_VERTEX | RAS_STAGE_CLIP | RAS_STAGE_SETUP | RAS_STAGE_WIREFRAME;
    assert_int_equal(p->counters.stages_run, expected);
    assert_int_equal(p->counters.lines_drawn, 3);
    assert_int_equal(p->counters.buffer_bytes, (size_t)64 * 64 * (sizeof(vec3s) + sizeof(float)));
    /* The bottom edge at y_ndc = -0.5 → screen y 16 → image row 47, lit at the centre column. */
    assert_float_equal(ras_image_get(img, 32, 47).x, 1, 0);
    assert_float_equal(ras_image_get(img, 32, 32).x, 0, 0); /* inside: not filled */
    ras_image_destroy(img);
    ras_mesh_destroy(tri);
    ras_pipeline_destroy(p);
}

/* NaN vertices are rejected and counted; nothing is drawn. */
static void test_pipeline_rejects_nan(void **state) {
    (void)state;
    ras_pipeline_config cfg = {.width = 32, .height = 32, .wireframe = true};
    ras_pipeline *p = ras_pipeline_create(&cfg, NULL);
    ras_clip_vertex a = cv(NAN, 0, 0, 1), b = cv(0.5f, 0, 0, 1), c = cv(0, 0.5f, 0, 1);
    ras_pipeline_draw_clip_triangle(p, &a, &b, &c);
    assert_int_equal(p->counters.triangles_rejected_nonfinite, 1);
    assert_int_equal(p->counters.lines_drawn, 0);
    ras_pipeline_destroy(p);
}

/* A filled pipeline without a rasterizer, or AA without a resolve hook, is refused. */
static void test_pipeline_config_checked(void **state) {
    (void)state;
    ras_error err;
    ras_pipeline_config cfg = {.width = 32, .height = 32};
    assert_null(ras_pipeline_create(&cfg, &err));
    assert_non_null(strstr(err.msg, "rasterize"));
}

/* ---- stage 5: the fragment stage ------------------------------------------- */

/* Interpolation hooks that count their calls and remember the mode, with
 * the plain screen-space sums (what hw3's interpolate_* give with w = 1). */
static int g_interp_calls;
static bool g_interp_persp;
static vec3s sum_vec3(const ras_triangle *t, vec3s b, const vec3s a[3], bool persp) {
    (void)t;
    g_interp_calls++, g_interp_persp = persp;
    return (vec3s){{a[0].x * b.x + a[1].x * b.y + a[2].x * b.z,
                    a[0].y * b.x + a[1].y * b.y + a[2].y * b.z,
                    a[0].z * b.x + a[1].z * b.y + a[2].z * b.z}};
}
static vec2s sum_vec2(const ras_triangle *t, vec3s b, const vec2s a[3], bool persp) {
    (void)t;
    g_interp_calls++, g_interp_persp = persp;
    return (vec2s){{a[0].x * b.x + a[1].x * b.y + a[2].x * b.z,
                    a[0].y * b.x + a[1].y * b.y + a[2].y * b.z}};
}
static ras_varyings g_seen;
static vec3s record_varyings(const ras_varyings *v, void *user) {
    g_seen = *v;
    ++*(int *)user;
    return (vec3s){{1, 0, 0}};
}
/* A rasterizer that hands over one fragment, at pixel (1, 0). */
static void one_fragment(const ras_triangle *t, const ras_raster_ctx *ctx) {
    ras_fragment f = {.x = 1, .y = 0, .bary = {{0.5f, 0.25f, 0.25f}}};
    ctx->shade(t, &f, ctx->shade_user);
}

static void test_fragment_stage_interpolates_the_mask(void **state) {
    (void)state;
    ras_error err = {{0}};
    int shaded = 0;
    ras_pipeline_config cfg = {.width = 3, .height = 2,
                               .varyings = RAS_VARYING_NORMAL | RAS_VARYING_UV,
                               .rasterize = one_fragment, .interpolate_vec3 = sum_vec3,
                               .uv_gradients = true, .shader = record_varyings,
                               .shader_user = &shaded, .dump = true};
    assert_null(ras_pipeline_create(&cfg, &err)); /* uv, but no interpolate_vec2 */
    assert_non_null(strstr(err.msg, "interpolate_vec2"));
    cfg.interpolate_vec2 = sum_vec2;
    ras_pipeline *p = ras_pipeline_create(&cfg, &err);
    assert_non_null(p);
    ras_triangle t = {.v = {{{0, 0, 0.5f, 1}}, {{3, 0, 0.5f, 1}}, {{0, 2, 0.5f, 1}}},
                      .normal = {{{0, 0, 2}}, {{0, 0, 2}}, {{0, 0, 2}}},
                      .uv = {{{0, 0}}, {{1, 0}}, {{0, 1}}},
                      .view_pos = {{{9, 9, -9}}, {{9, 9, -9}}, {{9, 9, -9}}}};
    g_interp_calls = 0;
    ras_pipeline_draw_screen_triangle(p, &t);
    assert_int_equal(shaded, 1);
    /* normal and uv, and uv twice more for its change per pixel; no view_pos */
    assert_int_equal(g_interp_calls, 4);
    assert_true(g_interp_persp);
    assert_int_equal(p->counters.varyings_interpolated, 2);
    assert_true(g_seen.normal.x == 0 && g_seen.normal.y == 0 && g_seen.normal.z == 1);
    assert_true(g_seen.uv.x == 0.25f && g_seen.uv.y == 0.25f);
    assert_true(g_seen.view_pos.x == 0 && g_seen.view_pos.y == 0 && g_seen.view_pos.z == 0);
    /* one pixel right: λ += (-1/3, 1/3, 0); one up: λ += (-1/2, 0, 1/2) */
    assert_float_equal(g_seen.duv_dx.x, 1.0f / 3, 1e-6f);
    assert_float_equal(g_seen.duv_dx.y, 0, 1e-6f);
    assert_float_equal(g_seen.duv_dy.x, 0, 1e-6f);
    assert_float_equal(g_seen.duv_dy.y, 0.5f, 1e-6f);
    /* kept as the pipeline's buffers, top row first: pixel (1, 0) is entry 4 */
    ras_dump_buffer b;
    float *owned = NULL;
    assert_true(ras_pipeline_buffer(p, "normal", &b, &owned));
    assert_true(b.channels == 3 && b.width == 3 && b.height == 2 && owned == NULL);
    assert_true(b.data[12] == 0 && b.data[13] == 0 && b.data[14] == 1 && isinf(b.data[0]));
    assert_true(ras_pipeline_buffer(p, "uv", &b, &owned));
    assert_true(b.data[12] == 0.25f && b.data[13] == 0.25f && b.data[14] == 0);
    assert_false(ras_pipeline_buffer(p, "view_depth", &b, &owned)); /* not interpolated */
    assert_true(ras_pipeline_buffer(p, "overdraw", &b, &owned) && b.data[4] == 1);
    ras_pipeline_begin_frame(p); /* a new frame: nothing shaded yet */
    assert_true(ras_pipeline_buffer(p, "normal", &b, &owned) && isinf(b.data[12]));
    ras_pipeline_destroy(p);
    /* affine, without --dump: no buffers kept */
    cfg.affine = true, cfg.dump = false;
    p = ras_pipeline_create(&cfg, &err);
    assert_non_null(p);
    ras_pipeline_draw_screen_triangle(p, &t);
    assert_false(g_interp_persp);
    assert_false(ras_pipeline_buffer(p, "normal", &b, &owned));
    ras_pipeline_destroy(p);
}

/* The shell keeps its pipeline while two configurations are equal
 * (ras_app_draw_frame): equal by value, whatever the padding holds; any one
 * field changed, or a float's sign bit, makes them differ; the sample
 * offsets count only as far as the pattern's count. */
static void dummy_hook(void) {}
static void test_pipeline_config_equal_by_fields(void **state) {
    (void)state;
    ras_pipeline_config a, b;
    memset(&a, 0x00, sizeof a);
    memset(&b, 0xa5, sizeof b); /* other padding */
    ras_pipeline_config base = {.width = 8, .height = 6, .clear_color = {{0.1f, 0.2f, 0.3f}},
                                .aa = RAS_AA_MSAA, .cull = RAS_CULL_BACK,
                                .depth = RAS_DEPTH_INV_W, .z_near = 0.1f, .z_far = 50,
                                .varyings = 3,
                                .shade_user = &base, .dump = true,
                                .step = true, .step_triangles = 5};
    assert_true(ras_sample_pattern_make(RAS_PATTERN_STANDARD, 4, &base.pattern, NULL));
#define SET_FIELDS(c)                                                                             \
    do {                                                                                          \
        c.width = base.width, c.height = base.height, c.clear_color = base.clear_color;            \
        c.wireframe = base.wireframe, c.wire_color = base.wire_color, c.aa = base.aa;             \
        c.pattern.kind = base.pattern.kind, c.pattern.count = base.pattern.count;                 \
        for (int k = 0; k < base.pattern.count; k++)                                              \
            c.pattern.offsets[k] = base.pattern.offsets[k];                                       \
        c.cull = base.cull, c.depth = base.depth, c.z_near = base.z_near, c.z_far = base.z_far;   \
        c.varyings = base.varyings, c.rasterize = base.rasterize, c.resolve = base.resolve;       \
        c.interpolate_vec3 = base.interpolate_vec3, c.interpolate_vec2 = base.interpolate_vec2;   \
        c.affine = base.affine, c.uv_gradients = base.uv_gradients, c.shader = base.shader;       \
        c.shader_user = base.shader_user;                                                         \
        c.shade = base.shade, c.shade_user = base.shade_user, c.dump = base.dump;                 \
        c.step = base.step, c.step_triangles = base.step_triangles;                               \
    } while (0)
    SET_FIELDS(a);
    SET_FIELDS(b);
#undef SET_FIELDS
    assert_true(ras_pipeline_config_equal(&a, &b)); /* offsets past 4 differ: not read */
    assert_true(ras_pipeline_config_equal(&a, &a));
    ras_pipeline_config c;
#define DIFFERS(change)                                                                           \
    do {                                                                                          \
        c = a;                                                                                    \
        change;                                                                                   \
        if (ras_pipeline_config_equal(&a, &c) || ras_pipeline_config_equal(&c, &a))               \
            fail_msg("equal after %s", #change);                                                  \
    } while (0)
    DIFFERS(c.width = 9);
    DIFFERS(c.height = 7);
    DIFFERS(c.clear_color.z = 0.31f);
    DIFFERS(c.wireframe = true);
    DIFFERS(c.wire_color.x = 1);
    DIFFERS(c.aa = RAS_AA_SSAA);
    DIFFERS(c.pattern.kind = RAS_PATTERN_ORDERED);
    DIFFERS(c.pattern.count = 2);
    DIFFERS(c.z_far = 51);
    DIFFERS(c.pattern.offsets[3].y += 0.125f);
    DIFFERS(c.cull = RAS_CULL_FRONT);
    DIFFERS(c.depth = RAS_DEPTH_Z01);
    DIFFERS(c.z_near = 0.2f);
    DIFFERS(c.varyings = 1);
    DIFFERS(c.rasterize = (ras_rasterize_fn)dummy_hook);
    DIFFERS(c.resolve = (ras_resolve_fn)dummy_hook);
    DIFFERS(c.interpolate_vec3 = (ras_interpolate_vec3_fn)dummy_hook);
    DIFFERS(c.interpolate_vec2 = (ras_interpolate_vec2_fn)dummy_hook);
    DIFFERS(c.affine = true);
    DIFFERS(c.uv_gradients = true);
    DIFFERS(c.shader = (ras_fragment_shader_fn)dummy_hook);
    DIFFERS(c.shader_user = &c);
    DIFFERS(c.shade = (ras_shade_fn)dummy_hook);
    DIFFERS(c.shade_user = &c);
    DIFFERS(c.dump = false);
    DIFFERS(c.step = false);
    DIFFERS(c.step_triangles = 6);
    a.clear_color.x = 0.0f;
    DIFFERS(c.clear_color.x = -0.0f); /* bits: another clear (ras_pipeline_create) */
#undef DIFFERS
}

/* ------------------------------------------------------------------------ */
/* Jobs in a child process (ras_job_run_child: the model importer's shield)  */

typedef struct child_plan {
    size_t bytes;   /* written, a counting pattern */
    int exit_code;  /* returned */
    int raise_sig;  /* raised after writing, when non-zero */
    double sleep_s; /* slept before writing */
} child_plan;

static int child_by_plan(void *arg, int fd) {
    const child_plan *p = arg;
    if (p->sleep_s > 0) usleep((useconds_t)(p->sleep_s * 1e6));
    unsigned char chunk[4096];
    for (size_t done = 0; done < p->bytes;) {
        size_t n = p->bytes - done < sizeof chunk ? p->bytes - done : sizeof chunk;
        for (size_t i = 0; i < n; i++) chunk[i] = (unsigned char)((done + i) * 7);
        if (write(fd, chunk, n) != (ssize_t)n) return 99;
        done += n;
    }
    if (p->raise_sig) raise(p->raise_sig);
    return p->exit_code;
}

static ras_job_child_status run_plan(child_plan plan, double seconds, size_t max_bytes,
                                     size_t *len, int *code, int *sig) {
    unsigned char *out;
    ras_job_child_status st =
        ras_job_run_child(child_by_plan, &plan, seconds, max_bytes, &out, len, code, sig);
    if (st == RAS_JOB_CHILD_DONE) {
        for (size_t i = 0; i < *len; i++)
            if (out[i] != (unsigned char)(i * 7)) fail_msg("byte %zu came back changed", i);
    } else if (out || *len) {
        fail_msg("a child that did not finish left %zu bytes for the caller", *len);
    }
    free(out);
    return st;
}

/* All it writes comes back, past the pipe's 64 KiB, with its exit code. */
static void test_job_child_returns_all_it_wrote(void **state) {
    (void)state;
    size_t len;
    int code, sig;
    assert_int_equal(run_plan((child_plan){3u << 20, 5, 0, 0}, 30, 4u << 20, &len, &code, &sig),
                     RAS_JOB_CHILD_DONE);
    assert_int_equal(len, 3u << 20);
    assert_int_equal(code, 5);
    assert_int_equal(sig, 0);
    assert_int_equal(run_plan((child_plan){0, 0, 0, 0}, 30, 16, &len, &code, &sig),
                     RAS_JOB_CHILD_DONE);
    assert_int_equal(len, 0);
}

/* A crash (an abort, a segfault) ends the child, not the caller, and is named. */
static void test_job_child_crash_is_reported(void **state) {
    (void)state;
    size_t len;
    int code, sig;
    assert_int_equal(run_plan((child_plan){100, 0, SIGABRT, 0}, 30, 1024, &len, &code, &sig),
                     RAS_JOB_CHILD_CRASHED);
    assert_int_equal(sig, SIGABRT);
    assert_int_equal(run_plan((child_plan){0, 0, SIGSEGV, 0}, 30, 1024, &len, &code, &sig),
                     RAS_JOB_CHILD_CRASHED);
    assert_int_equal(sig, SIGSEGV);
}

/* A child past its time is killed, and the caller does not wait for it. */
static void test_job_child_late_is_killed(void **state) {
    (void)state;
    size_t len;
    int code, sig;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    assert_int_equal(run_plan((child_plan){10, 0, 0, 20.0}, 0.2, 1024, &len, &code, &sig),
                     RAS_JOB_CHILD_LATE);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double waited = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-9;
    if (waited > 10) fail_msg("waited %.1f s for a child given 0.2 s (it sleeps 20 s)", waited);
    assert_int_equal(sig, SIGKILL);
}

/* More than max_bytes: killed, nothing kept. */
static void test_job_child_too_big_is_refused(void **state) {
    (void)state;
    size_t len;
    int code, sig;
    assert_int_equal(run_plan((child_plan){1u << 20, 0, 0, 0}, 30, 1000, &len, &code, &sig),
                     RAS_JOB_CHILD_TOO_BIG);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_math_rows_constructor_is_row_major),
        cmocka_unit_test(test_math_nan_never_near),
        cmocka_unit_test(test_error_long_path_cut_in_the_middle),
        cmocka_unit_test(test_math_products_fixed_rounding_order),
        cmocka_unit_test(test_sample_patterns_positions),
        cmocka_unit_test(test_framebuffer_index_math),
        cmocka_unit_test(test_clip_inside_untouched),
        cmocka_unit_test(test_clip_one_vertex_behind_eye),
        cmocka_unit_test(test_clip_two_behind_and_all_behind),
        cmocka_unit_test(test_clip_w_zero),
        cmocka_unit_test(test_viewport_depth_smaller_is_closer),
        cmocka_unit_test(test_draw_line_clips_safely),
        cmocka_unit_test(test_cli_parses_values),
        cmocka_unit_test(test_cli_rejects_bad_input),
        cmocka_unit_test(test_app_resolve_one_rule_set),
        cmocka_unit_test(test_pipeline_config_equal_by_fields),
        cmocka_unit_test(test_image_roundtrip_and_failed_write),
        cmocka_unit_test(test_atomic_write_on_disk_and_in_memory),
        cmocka_unit_test(test_image_header_size_matches_decode),
        cmocka_unit_test(test_pipeline_wireframe_runs_only_its_stages),
        cmocka_unit_test(test_pipeline_rejects_nan),
        cmocka_unit_test(test_pipeline_config_checked),
        cmocka_unit_test(test_fragment_stage_interpolates_the_mask),
        cmocka_unit_test(test_job_child_returns_all_it_wrote),
        cmocka_unit_test(test_job_child_crash_is_reported),
        cmocka_unit_test(test_job_child_late_is_killed),
        cmocka_unit_test(test_job_child_too_big_is_refused),
    };
    return cmocka_run_group_tests_name("core", tests, NULL, NULL);
}
