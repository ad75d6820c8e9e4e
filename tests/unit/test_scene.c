/* test_scene.c — cmocka tests for common/ras_scene: the scene-file format,
 * its defaults, its error messages, and the assets a scene names.
 *
 * Scene text for the error cases is inline; files (scenes in sub-folders,
 * models, textures, a too-large file) are written at test time into a
 * private temporary directory made by the group setup and removed by the
 * group teardown. The example scenes are read from RAS_SOURCE_DIR/scenes.
 * RAS_TEST_VERBOSE=1 prints every error message the tests provoke (the
 * messages quoted in docs/scenes.md come from that output).
 */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#endif

#include <setjmp.h> /* required by cmocka.h */
#include <stdarg.h> /* required by cmocka.h; va_list */
#include <stddef.h> /* required by cmocka.h */
#include <stdint.h> /* required by cmocka.h */

#include <cmocka.h>

#include "ras_test_main.h"

#include "ras_image.h"
#include "ras_scene.h"

#include <dirent.h>   /* opendir, readdir */
#include <math.h>     /* fabsf */
#include <stdio.h>    /* snprintf, fopen */
#include <stdlib.h>   /* mkdtemp, calloc, getenv */
#include <string.h>   /* strstr, strlen */
#include <sys/stat.h> /* mkdir, chmod */
#include <unistd.h>   /* rmdir, truncate, geteuid */

/* ------------------------------------------------------------------------ */
/* Fixture: a temporary directory for generated files                       */

#define MAX_FILES 32

typedef struct fixture {
    char dir[256];
    char files[MAX_FILES][512]; /* removed in reverse order: files before their folders */
    int file_count;
} fixture;

static int group_setup(void **state) {
    fixture *fx = calloc(1, sizeof *fx);
    if (!fx) return -1;
    snprintf(fx->dir, sizeof fx->dir, "/tmp/raster101_test_scene_XXXXXX");
    if (!mkdtemp(fx->dir)) {
        free(fx);
        return -1;
    }
    *state = fx;
    return 0;
}

static int group_teardown(void **state) {
    fixture *fx = *state;
    if (!fx) return 0;
    for (int i = fx->file_count - 1; i >= 0; i--)
        remove(fx->files[i]);
    rmdir(fx->dir);
    free(fx);
    return 0;
}

/* <tmpdir>/<name>, remembered for removal. */
static const char *tmp_path(void **state, const char *name) {
    fixture *fx = *state;
    assert_true(fx->file_count < MAX_FILES);
    char full[sizeof fx->files[0]];
    snprintf(full, sizeof full, "%s/%s", fx->dir, name);
    char *path = fx->files[fx->file_count++];
    memcpy(path, full, sizeof full);
    return path;
}

static const char *make_dir(void **state, const char *name) {
    const char *path = tmp_path(state, name);
    if (mkdir(path, 0700) != 0) fail_msg("could not create the test folder %s", path);
    return path;
}

static const char *write_file(void **state, const char *name, const char *text) {
    const char *path = tmp_path(state, name);
    FILE *f = fopen(path, "wb");
    if (!f) fail_msg("could not create the test file %s", path);
    fputs(text, f);
    fclose(f);
    return path;
}

/* ------------------------------------------------------------------------ */
/* Helpers                                                                   */

static ras_scene *parse_ok(const char *text) {
    ras_error err = {{0}};
    ras_scene *s = ras_scene_parse(text, "scene.json", NULL, &err);
    if (!s) fail_msg("expected the scene to parse, but: %s", err.msg);
    return s;
}

static void show(const char *msg) {
    const char *v = getenv("RAS_TEST_VERBOSE");
    if (v && *v && strcmp(v, "0") != 0) printf("    message: %s\n", msg);
}

/* The error must contain every one of the NULL-terminated substrings. */
static void check_msg(const char *msg, va_list ap) {
    show(msg);
    for (const char *want = va_arg(ap, const char *); want; want = va_arg(ap, const char *))
        if (!strstr(msg, want))
            fail_msg("the error message lacks \"%s\"; the whole message was:\n  %s", want, msg);
}

/* Parses text as "scene.json"; it must fail with a message containing each
 * of the substrings (NULL-terminated). */
static void expect_error(const char *text, ...) {
    ras_error err = {{0}};
    ras_scene *s = ras_scene_parse(text, "scene.json", NULL, &err);
    if (s) {
        ras_scene_destroy(s);
        fail_msg("expected an error for this scene, but it parsed:\n%s", text);
    }
    va_list ap;
    va_start(ap, text);
    check_msg(err.msg, ap);
    va_end(ap);
}

static void expect_load_error(const char *path, ...) {
    ras_error err = {{0}};
    ras_scene *s = ras_scene_load(path, &err);
    if (s) {
        ras_scene_destroy(s);
        fail_msg("expected loading %s to fail, but it loaded", path);
    }
    va_list ap;
    va_start(ap, path);
    check_msg(err.msg, ap);
    va_end(ap);
}

static void expect_assets_error(const ras_scene *s, ...) {
    ras_error err = {{0}};
    ras_scene_assets *a = ras_scene_load_assets(s, &err);
    if (a) {
        ras_scene_assets_destroy(a);
        fail_msg("expected loading the assets of %s to fail, but they loaded", s->path);
    }
    va_list ap;
    va_start(ap, s);
    check_msg(err.msg, ap);
    va_end(ap);
}

static void assert_vec3_near(vec3s got, float x, float y, float z, float tol) {
    if (fabsf(got.x - x) > tol || fabsf(got.y - y) > tol || fabsf(got.z - z) > tol)
        fail_msg("expected (%g, %g, %g), got (%g, %g, %g)", (double)x, (double)y, (double)z,
                 (double)got.x, (double)got.y, (double)got.z);
}

#define ONE_CUBE "\"objects\": [{\"shape\": \"cube\"}]"

/* ------------------------------------------------------------------------ */
/* The example scenes                                                        */

/* Every .json file in scenes/ parses, and its meshes and textures can be built. */
static void test_scene_examples_all_load(void **state) {
    (void)state;
    static const char *const expected[] = {
        "hw1_classic.json",         "hw2_classic.json",
        "hw3_default.json",         "textured_teapot_trilinear.json",
        "msaa_thin_triangles.json", "near_plane_crossing.json",
        "bump_sphere.json"};
    int found[sizeof expected / sizeof expected[0]] = {0}, total = 0;
    DIR *d = opendir(RAS_SOURCE_DIR "/scenes");
    assert_non_null(d);
    for (struct dirent *e; (e = readdir(d));) {
        size_t n = strlen(e->d_name);
        if (n < 6 || strcmp(e->d_name + n - 5, ".json")) continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/scenes/%s", RAS_SOURCE_DIR, e->d_name);
        ras_error err = {{0}};
        ras_scene *s = ras_scene_load(path, &err);
        if (!s) fail_msg("example scene %s does not load: %s", e->d_name, err.msg);
        ras_scene_assets *a = ras_scene_load_assets(s, &err);
        if (!a) fail_msg("example scene %s: assets do not load: %s", e->d_name, err.msg);
        assert_int_equal(a->object_count, s->object_count);
        for (int i = 0; i < a->object_count; i++)
            assert_non_null(a->meshes[i]);
        ras_scene_assets_destroy(a);
        ras_scene_destroy(s);
        for (size_t i = 0; i < sizeof expected / sizeof expected[0]; i++)
            if (!strcmp(e->d_name, expected[i])) found[i] = 1;
        total++;
    }
    closedir(d);
    for (size_t i = 0; i < sizeof expected / sizeof expected[0]; i++)
        if (!found[i]) fail_msg("scenes/%s is missing", expected[i]);
    assert_true(total >= 7);
}

/* hw2_classic.json holds exactly the GAMES101 numbers. */
static void test_scene_hw2_classic_values(void **state) {
    (void)state;
    ras_error err = {{0}};
    ras_scene *s = ras_scene_load(RAS_SOURCE_DIR "/scenes/hw2_classic.json", &err);
    if (!s) fail_msg("%s", err.msg);
    assert_int_equal(s->width, 700);
    assert_int_equal(s->height, 700);
    assert_int_equal(s->camera.view, RAS_SCENE_VIEW_FIXED);
    assert_vec3_near(s->camera.eye, 0, 0, 5, 0);
    assert_true(s->camera.fov_deg == 45.0f && s->camera.z_near == 0.1f && s->camera.z_far == 50.0f);
    assert_int_equal(s->object_count, 2);
    assert_int_equal(s->objects[0].shape, RAS_SHAPE_TRIANGLE);
    assert_vec3_near(s->objects[0].params.vertices[0], 2, 0, -2, 0);
    assert_vec3_near(s->objects[0].params.vertices[1], 0, 2, -2, 0);
    assert_vec3_near(s->objects[0].params.vertices[2], -2, 0, -2, 0);
    assert_vec3_near(s->objects[0].material.color, 217 / 255.0f, 238 / 255.0f, 185 / 255.0f, 0);
    assert_vec3_near(s->objects[1].params.vertices[0], 3.5f, -1, -5, 0);
    assert_vec3_near(s->objects[1].params.vertices[1], 2.5f, 1.5f, -5, 0);
    assert_vec3_near(s->objects[1].params.vertices[2], -1, 0.5f, -5, 0);
    assert_vec3_near(s->objects[1].material.color, 185 / 255.0f, 217 / 255.0f, 238 / 255.0f, 0);
    assert_string_equal(s->objects[1].name, "back (blue)");
    assert_int_equal(s->aa, RAS_AA_NONE);
    assert_int_equal(s->shader, RAS_SHADER_FLAT);
    /* The triangle's vertex colours carry the material colour. */
    ras_scene_assets *a = ras_scene_load_assets(s, &err);
    if (!a) fail_msg("%s", err.msg);
    assert_vec3_near(a->meshes[0]->colors[2], 217 / 255.0f, 238 / 255.0f, 185 / 255.0f, 0);
    ras_scene_assets_destroy(a);
    ras_scene_destroy(s);
}

/* ------------------------------------------------------------------------ */
/* Defaults and values                                                       */

/* A scene with one cube gets every documented default. */
static void test_scene_defaults(void **state) {
    (void)state;
    ras_scene *s = parse_ok("{" ONE_CUBE "}");
    assert_int_equal(s->width, 700);
    assert_int_equal(s->height, 700);
    assert_int_equal(s->camera.view, RAS_SCENE_VIEW_FIXED);
    assert_vec3_near(s->camera.eye, 0, 0, 5, 0);
    assert_true(s->camera.fov_deg == 45.0f && s->camera.z_near == 0.1f && s->camera.z_far == 50.0f);
    assert_true(s->model_rotation_deg == 0 && !s->model_rotation_axis_set);
    assert_vec3_near(s->model_rotation_axis, 0, 0, 1, 0);
    assert_int_equal(s->light_count, 0);
    assert_null(s->lights);
    assert_vec3_near(s->ambient, 10, 10, 10, 0);
    assert_int_equal(s->aa, RAS_AA_NONE);
    assert_int_equal(s->pattern.count, 1);
    assert_int_equal(s->shader, RAS_SHADER_FLAT);
    assert_int_equal(s->filter, RAS_FILTER_BILINEAR);
    assert_int_equal(s->cull, RAS_CULL_NONE);
    assert_int_equal(s->depth, RAS_DEPTH_Z01);
    assert_vec3_near(s->clear_color, 0, 0, 0, 0);
    assert_false(s->wireframe);
    assert_null(s->description);
    const ras_scene_object *o = &s->objects[0];
    assert_null(o->name);
    assert_true(o->params.size == 1.0f);
    assert_true(ras_mat4_near(o->model, glms_mat4_identity(), 0));
    const ras_scene_material *m = &o->material;
    assert_vec3_near(m->color, 1, 1, 1, 0);
    assert_int_equal(m->texture.kind, RAS_MAP_NONE);
    assert_int_equal(m->height_map.kind, RAS_MAP_NONE);
    assert_vec3_near(m->ka, 0.005f, 0.005f, 0.005f, 0);
    assert_vec3_near(m->ks, 0.7937f, 0.7937f, 0.7937f, 0);
    assert_false(m->kd_set);
    assert_true(m->p == 150 && m->kh == 0.2f && m->kn == 0.1f);
    assert_true(m->uv_scale.x == 1 && m->uv_scale.y == 1);
    ras_scene_destroy(s);
}

/* Shape parameters default per shape and read per shape. */
static void test_scene_shape_params(void **state) {
    (void)state;
    ras_scene *s = parse_ok("{\"objects\": [{\"shape\": \"sphere\"},"
                            "{\"shape\": \"torus\", \"rings\": 12},"
                            "{\"shape\": \"thin_fan\", \"count\": 10, \"arc_deg\": 90},"
                            "{\"shape\": \"plane\", \"size\": 3, \"divisions\": 4},"
                            "{\"shape\": \"teapot\"}]}");
    assert_true(s->objects[0].params.radius == 1 && s->objects[0].params.stacks == 32 &&
                s->objects[0].params.slices == 64);
    assert_true(s->objects[1].params.rings == 12 && s->objects[1].params.sides == 32 &&
                s->objects[1].params.minor_radius == 0.4f);
    assert_true(s->objects[2].params.count == 10 && s->objects[2].params.arc_deg == 90);
    assert_true(s->objects[3].params.size == 3 && s->objects[3].params.divisions == 4);
    assert_int_equal(s->objects[4].params.divisions, 8);
    ras_scene_destroy(s);
}

/* The transform is T · R_last ⋯ R_first · S, and spin (a matrix, or hw3's turn about
 * y) goes between T and R. */
static void test_scene_transform_order(void **state) {
    (void)state;
    ras_scene *s = parse_ok(
        "{\"objects\": [{\"shape\": \"cube\", \"transform\": {\"translate\": [1, 2, 3],"
        "\"rotate\": [{\"axis\": [1, 0, 0], \"deg\": 25}, {\"axis\": [0, 1, 0], \"deg\": 35}],"
        "\"scale\": [2, 3, 4]}}]}");
    const ras_scene_object *o = &s->objects[0];
    assert_int_equal(o->rotation_count, 2);
    mat4s t = glms_translate_make((vec3s){{1, 2, 3}});
    mat4s rx = glms_rotate_make(ras_deg_to_rad(25), (vec3s){{1, 0, 0}});
    mat4s ry = glms_rotate_make(ras_deg_to_rad(35), (vec3s){{0, 1, 0}});
    mat4s sc = glms_scale_make((vec3s){{2, 3, 4}});
    mat4s want = glms_mat4_mul(glms_mat4_mul(t, glms_mat4_mul(ry, rx)), sc);
    assert_true(ras_mat4_near(o->model, want, 1e-6f));
    mat4s spin = glms_rotate_make(ras_deg_to_rad(90), (vec3s){{0, 0, 1}});
    mat4s want_spin =
        glms_mat4_mul(glms_mat4_mul(glms_mat4_mul(t, spin), glms_mat4_mul(ry, rx)), sc);
    assert_true(ras_mat4_near(ras_scene_model_matrix(o, (ras_scene_spin){.matrix = &spin}),
                              want_spin, 1e-6f));
    mat4s identity = glms_mat4_identity();
    assert_true(ras_mat4_near(ras_scene_model_matrix(o, (ras_scene_spin){.matrix = &identity}),
                              o->model, 0));
    /* hw3's form: the same product, with the turn about y (its last rotation,
     * about +y, joins the turn) */
    mat4s turn = glms_rotate_make(ras_deg_to_rad(-50), (vec3s){{0, 1, 0}});
    mat4s want_turn =
        glms_mat4_mul(glms_mat4_mul(glms_mat4_mul(t, turn), glms_mat4_mul(ry, rx)), sc);
    assert_true(ras_mat4_near(ras_scene_model_matrix(o, (ras_scene_spin){.turn_y_deg = -50}),
                              want_turn, 1e-6f));
    assert_true(ras_mat4_near(ras_scene_model_matrix(o, (ras_scene_spin){.turn_y_deg = 0}),
                              o->model, 1e-6f));
    ras_scene_destroy(s);
}

/* look_at gives glms_lookat; the fixed view is a translation by -eye. */
static void test_scene_camera_views(void **state) {
    (void)state;
    ras_scene *s =
        parse_ok("{\"camera\": {\"eye\": [1, 2, 3], \"look_at\": [0, 0, 0]}," ONE_CUBE "}");
    assert_int_equal(s->camera.view, RAS_SCENE_VIEW_LOOK_AT);
    assert_vec3_near(s->camera.up, 0, 1, 0, 0);
    mat4s want = glms_lookat((vec3s){{1, 2, 3}}, (vec3s){{0, 0, 0}}, (vec3s){{0, 1, 0}});
    assert_true(ras_mat4_near(ras_scene_view_matrix(s), want, 1e-6f));
    ras_scene_destroy(s);
    s = parse_ok("{\"camera\": {\"eye\": [1, 2, 3]}," ONE_CUBE "}");
    assert_true(
        ras_mat4_near(ras_scene_view_matrix(s), ras_view_matrix_eye((vec3s){{1, 2, 3}}), 0));
    ras_scene_destroy(s);
}

/* Materials, maps, lights, AA and the enums read what they say. */
static void test_scene_values_read(void **state) {
    (void)state;
    ras_scene *s = parse_ok(
        "{\"objects\": [{\"shape\": \"sphere\", \"material\": {\"color\": \"#ff8000\","
        "\"ka\": [0.1, 0.2, 0.3], \"kd\": 0.5, \"p\": 32, \"uv_scale\": [2, 3],"
        "\"texture\": {\"builtin\": \"checker\", \"squares\": 4, \"colors\": [[1, 0, 0], "
        "\"#00ff00\"],"
        "\"wrap\": \"clamp\"}, \"height_map\": {\"builtin\": \"bumps\", \"bumps\": 5}}}],"
        "\"lights\": [{\"position\": [1, 2, 3]}, {\"position\": [0, 5, 0], \"intensity\": [1, 2, "
        "3],"
        "\"space\": \"world\"}],"
        "\"ambient\": [1, 2, 3], \"aa\": {\"mode\": \"ssaa\", \"samples\": 8, \"pattern\": "
        "\"standard\"},"
        "\"shader\": \"phong\", \"filter\": \"trilinear\", \"cull\": \"back\","
        "\"clear_color\": [0.1, 0.2, 0.3], \"wireframe\": true,"
        "\"model_rotation\": {\"angle_deg\": 20, \"axis\": [0, 1, 0]}, \"description\": \"d\"}");
    const ras_scene_material *m = &s->objects[0].material;
    assert_vec3_near(m->color, 1, 128 / 255.0f, 0, 0);
    assert_vec3_near(m->ka, 0.1f, 0.2f, 0.3f, 0);
    assert_true(m->kd_set);
    assert_vec3_near(m->kd, 0.5f, 0.5f, 0.5f, 0);
    assert_true(m->p == 32 && m->uv_scale.x == 2 && m->uv_scale.y == 3);
    assert_int_equal(m->texture.kind, RAS_MAP_CHECKER);
    assert_int_equal(m->texture.squares, 4);
    assert_int_equal(m->texture.size, 256);
    assert_int_equal(m->texture.wrap, RAS_WRAP_CLAMP);
    assert_vec3_near(m->texture.colors[1], 0, 1, 0, 0);
    assert_int_equal(m->height_map.kind, RAS_MAP_BUMPS);
    assert_int_equal(m->height_map.bumps, 5);
    assert_int_equal(s->light_count, 2);
    assert_vec3_near(s->lights[0].intensity, 500, 500, 500, 0);
    assert_false(s->lights[0].in_world);
    assert_vec3_near(s->lights[1].intensity, 1, 2, 3, 0);
    assert_true(s->lights[1].in_world);
    assert_vec3_near(s->ambient, 1, 2, 3, 0);
    assert_int_equal(s->aa, RAS_AA_SSAA);
    assert_int_equal(s->pattern.count, 8);
    assert_int_equal(s->pattern.kind, RAS_PATTERN_STANDARD);
    assert_int_equal(s->shader, RAS_SHADER_PHONG);
    assert_int_equal(s->filter, RAS_FILTER_TRILINEAR);
    assert_int_equal(s->cull, RAS_CULL_BACK);
    assert_true(s->wireframe);
    assert_true(s->model_rotation_deg == 20 && s->model_rotation_axis_set);
    assert_string_equal(s->description, "d");
    assert_string_equal(ras_scene_shader_name(s->shader), "phong");
    assert_string_equal(ras_scene_filter_name(s->filter), "trilinear");
    assert_string_equal(ras_scene_cull_name(s->cull), "back");
    assert_string_equal(ras_scene_shape_name(s->objects[0].shape), "sphere");
    ras_scene_destroy(s);
}

/* "depth" picks the depth format (stage3_setup.h) by the names the pipeline
 * reports; like every enum key it is strict: a near miss gets a did-you-mean,
 * a wrong type names the choices. */
static void test_scene_depth_format(void **state) {
    (void)state;
    ras_scene *s = parse_ok("{\"depth\": \"inverse_w\"," ONE_CUBE "}");
    assert_int_equal(s->depth, RAS_DEPTH_INV_W);
    assert_string_equal(ras_depth_format_name(s->depth), "inverse_w");
    ras_scene_destroy(s);
    s = parse_ok("{\"depth\": \"z01\"," ONE_CUBE "}");
    assert_int_equal(s->depth, RAS_DEPTH_Z01);
    assert_string_equal(ras_depth_format_name(s->depth), "z01");
    ras_scene_destroy(s);
    expect_error("{\"depth\": \"inverse-w\"," ONE_CUBE "}",
                 "scene.json: depth: expected one of z01 or inverse_w, got \"inverse-w\"; did "
                 "you mean \"inverse_w\"?",
                 NULL);
    expect_error("{\"depth\": 1," ONE_CUBE "}",
                 "scene.json: depth: expected one of z01 or inverse_w, got a number", NULL);
    expect_error("{\"dept\": \"z01\"," ONE_CUBE "}", "scene.json: dept: unknown key",
                 "did you mean \"depth\"?", NULL);
}

/* MSAA with the default pattern (ordered) and default samples (4) is a 2×2 grid. */
static void test_scene_aa_defaults(void **state) {
    (void)state;
    ras_scene *s = parse_ok("{\"aa\": {\"mode\": \"msaa\"}," ONE_CUBE "}");
    assert_int_equal(s->pattern.kind, RAS_PATTERN_ORDERED);
    assert_int_equal(s->pattern.count, 4);
    ras_scene_destroy(s);
}

/* ------------------------------------------------------------------------ */
/* JSON syntax errors: file:line:column, expected, got                      */

/* A trailing comma names its line and column and says why. */
static void test_scene_syntax_trailing_comma(void **state) {
    (void)state;
    expect_error("{\n  \"objects\": [\n    {\"shape\": \"cube\"},\n  ]\n}",
                 "scene.json:4:3: JSON syntax error", "expected a value after ','", "got ']'",
                 "trailing comma", NULL);
}

/* A missing comma between two members points at the second. */
static void test_scene_syntax_missing_comma(void **state) {
    (void)state;
    expect_error("{\n  \"image\": {\"width\": 10}\n  \"objects\": []\n}",
                 "scene.json:3:3:", "expected ',' or a closing bracket", "a ',' is missing", NULL);
}

/* Comments, single quotes, NaN and unquoted keys each get their own hint. */
static void test_scene_syntax_hints(void **state) {
    (void)state;
    expect_error("{\n  // the camera\n  " ONE_CUBE "}", "scene.json:2:3:", "JSON has no comments",
                 NULL);
    expect_error("{'objects': []}", "scene.json:1:", "double quotes", NULL);
    expect_error("{\"ambient\": NaN, " ONE_CUBE "}", "scene.json:1:13:", "expected a number",
                 "got 'NaN'", "no NaN or Infinity", NULL);
    expect_error("{objects: []}", "scene.json:1:", "expected a key in double quotes", NULL);
    expect_error("{\"wireframe\": tru, " ONE_CUBE "}", "scene.json:1:15:", "expected a value",
                 "got 'tru'", NULL);
}

/* Text that stops early says which bracket or string is left open, and where. */
static void test_scene_syntax_ends_early(void **state) {
    (void)state;
    expect_error("{\n  \"objects\": [\n    {\"shape\": \"cube\"}\n",
                 "scene.json:", "expected ']' to close the '[' at 2:14", "got the end of the text",
                 NULL);
    expect_error("{\"description\": \"abc", "expected '\"' to close the '\"' at 1:17", NULL);
}

/* Columns count characters, not bytes, on lines with UTF-8 text. */
static void test_scene_syntax_column_counts_characters(void **state) {
    (void)state;
    expect_error("{\"description\": \"\xc3\xa9\xc3\xa9\", \"x\": ,}",
                 "scene.json:1:28:", "expected a value after ':', got ','", NULL);
}

/* Empty text and a top level that is not an object are errors. */
static void test_scene_syntax_empty_and_top_level(void **state) {
    (void)state;
    expect_error("", "scene.json: expected a JSON object {...}, got an empty file", NULL);
    expect_error("  \n ", "got only white space", NULL);
    expect_error("[1, 2]",
                 "scene.json: the top level: expected an object {...}, got an array of 2 items",
                 NULL);
    expect_error("{" ONE_CUBE "} trailing", "scene.json:1:34:",
                 "expected the end of the text after the top-level object, got 'trailing'", NULL);
}

/* ------------------------------------------------------------------------ */
/* Semantic errors: file, key path, expected, got                            */

/* The example from the issue, word for word. */
static void test_scene_wrong_type_names_key_path(void **state) {
    (void)state;
    expect_error("{\"objects\": [{\"shape\": \"cube\"}, {\"shape\": \"cube\"}, {\"shape\": "
                 "\"cube\", \"material\": {\"ks\": \"0.7\"}}]}",
                 "scene.json: objects[2].material.ks: expected a number or an array of 3 "
                 "numbers, got a string (\"0.7\")",
                 NULL);
    expect_error("{\"image\": {\"width\": \"700\"}," ONE_CUBE "}",
                 "scene.json: image.width: expected a whole number in 1..8192, got a string "
                 "(\"700\")",
                 NULL);
    expect_error("{\"camera\": {\"eye\": [0, 0]}," ONE_CUBE "}",
                 "scene.json: camera.eye: expected an array of 3 numbers, got an array of 2 items",
                 NULL);
    expect_error("{\"camera\": {\"eye\": [0, null, 5]}," ONE_CUBE "}",
                 "camera.eye[1]: expected a number in [-1e+06, 1e+06], got null", NULL);
    expect_error("{\"wireframe\": 1," ONE_CUBE "}",
                 "scene.json: wireframe: expected true or false, got a number (1)", NULL);
    expect_error("{\"objects\": {\"shape\": \"cube\"}}",
                 "scene.json: objects: expected an array of 1 or more objects, got an object",
                 NULL);
}

/* An unknown key close to a known one gets a did-you-mean. */
static void test_scene_unknown_key_did_you_mean(void **state) {
    (void)state;
    expect_error("{\"camera\": {\"fov\": 45}," ONE_CUBE "}",
                 "scene.json: camera.fov: unknown key \"fov\"; did you mean \"fov_deg\"?", NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"material\": {\"colour\": [1, 0, 0]}}]}",
                 "scene.json: objects[0].material.colour: unknown key \"colour\"; did you mean "
                 "\"color\"?",
                 NULL);
    expect_error("{\"ligths\": []," ONE_CUBE "}", "scene.json: ligths: unknown key",
                 "did you mean \"lights\"?", NULL);
    expect_error("{\"shader\": \"phog\"," ONE_CUBE "}",
                 "scene.json: shader: expected one of flat, normal, phong, texture, bump or "
                 "displacement, got \"phog\"; did you mean \"phong\"?",
                 NULL);
}

/* An unknown key far from every known one lists the keys that are allowed. */
static void test_scene_unknown_key_lists_known(void **state) {
    (void)state;
    expect_error("{\"image\": {\"resolution\": 700}," ONE_CUBE "}",
                 "scene.json: image.resolution: unknown key \"resolution\"; expected one of "
                 "width or height",
                 NULL);
}

/* Another shape's parameter is explained, not just called unknown. */
static void test_scene_other_shape_parameter(void **state) {
    (void)state;
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"radius\": 2}]}",
                 "scene.json: objects[0].radius: shape \"cube\" takes no \"radius\"",
                 "its parameters are size", NULL);
}

/* A key given twice is an error (cJSON would silently keep the first). */
static void test_scene_duplicate_key(void **state) {
    (void)state;
    expect_error("{\"image\": {\"width\": 10, \"width\": 20}," ONE_CUBE "}",
                 "scene.json: image.width: duplicate key \"width\"", NULL);
}

/* Numbers out of range say the range and the value. */
static void test_scene_out_of_range(void **state) {
    (void)state;
    expect_error("{\"camera\": {\"fov_deg\": -45}," ONE_CUBE "}",
                 "scene.json: camera.fov_deg: expected a number in (0, 180), got -45", NULL);
    expect_error("{\"camera\": {\"near\": 10, \"far\": 5}," ONE_CUBE "}",
                 "scene.json: camera.far: expected far > near (10), got 5", NULL);
    expect_error("{\"camera\": {\"near\": 5, \"far\": 5}," ONE_CUBE "}", "expected far > near",
                 NULL);
    expect_error("{\"image\": {\"width\": 0}," ONE_CUBE "}",
                 "scene.json: image.width: expected a whole number in 1..8192, got 0", NULL);
    expect_error("{\"image\": {\"height\": 10000}," ONE_CUBE "}",
                 "image.height: expected a whole number in 1..8192, got 10000", NULL);
    expect_error("{\"image\": {\"height\": 70.5}," ONE_CUBE "}", "got 70.5", NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"material\": {\"color\": [1.5, 0, 0]}}]}",
                 "objects[0].material.color[0]: expected a number in [0, 1], got 1.5", NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"transform\": {\"scale\": 0}}]}",
                 "objects[0].transform.scale: expected a non-zero scale, got 0", NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"transform\": {\"rotate\": "
                 "{\"axis\": [0, 0, 0], \"deg\": 5}}}]}",
                 "objects[0].transform.rotate.axis: expected a non-zero axis", NULL);
    /* issue #42, B3: legal as numbers, 0 or denormal in the float that uses them */
    expect_error("{\"camera\": {\"fov_deg\": 1e-37}," ONE_CUBE "}",
                 "scene.json: camera.fov_deg: expected a field of view whose half angle's "
                 "tangent a float holds", "got 1e-37 degrees", NULL);
    expect_error("{\"camera\": {\"near\": 1e-40}," ONE_CUBE "}",
                 "scene.json: camera.near: expected a magnitude of at least 1.17549e-38",
                 "as a denormal", "got 1e-40", NULL);
    expect_error("{\"camera\": {\"near\": 1e-50}," ONE_CUBE "}", "camera.near:", "as 0",
                 NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"transform\": {\"scale\": 1e-45}}]}",
                 "objects[0].transform.scale: expected a magnitude of at least 1.17549e-38",
                 "got 1e-45", NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"transform\": {\"scale\": "
                 "[1, 1e-39, 1]}}]}",
                 "objects[0].transform.scale[1]: expected a magnitude of at least", NULL);
    expect_error("{\"objects\": [{\"shape\": \"triangle\", \"vertices\": [[0, 0, 0], "
                 "[1, 0, 0], [0, -1e-42, 0]]}]}",
                 "objects[0].vertices[2][1]: expected a magnitude of at least", NULL);
    expect_error("{\"camera\": {\"near\": 1e-36, \"far\": 1}," ONE_CUBE "}",
                 "scene.json: camera.near: expected a near distance whose frustum half width",
                 "got near 1e-36 with fov 45 degrees", NULL);
    expect_error("{\"camera\": {\"near\": 1e-25, \"far\": 1e-14, \"fov_deg\": 90}," ONE_CUBE
                 "}",
                 "scene.json: camera.near: expected near * far to be at least 1.17549e-38",
                 NULL);
    expect_error("{\"camera\": {\"eye\": [0, 0, 5], \"look_at\": [0, 0, 5]}," ONE_CUBE "}",
                 "camera.look_at: expected a point other than the eye", NULL);
    expect_error(
        "{\"camera\": {\"eye\": [0, 0, 5], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]}," ONE_CUBE
        "}",
        "camera.up: expected a direction not parallel to the view direction", NULL);
}

/* JSON has no NaN, but 1e400 reads as infinity and 1e300 overflows a float. */
static void test_scene_huge_numbers(void **state) {
    (void)state;
    expect_error("{\"camera\": {\"far\": 1e400}," ONE_CUBE "}",
                 "scene.json: camera.far: expected a number in (0, 1e+06], got a number too "
                 "large to represent (it reads as infinity)",
                 NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"transform\": {\"translate\": "
                 "[0, -1e300, 0]}}]}",
                 "objects[0].transform.translate[1]: expected a number in [-1e+06, 1e+06], got "
                 "-1e+300",
                 NULL);
    expect_error("{\"image\": {\"width\": 1e10}," ONE_CUBE "}",
                 "image.width: expected a whole number in 1..8192, got 1e+10", NULL);
}

/* Sample counts are checked with ras_sample_pattern_make for the pattern. */
static void test_scene_samples_checked_for_pattern(void **state) {
    (void)state;
    expect_error("{\"aa\": {\"mode\": \"msaa\", \"samples\": 8, \"pattern\": \"ordered\"}," ONE_CUBE
                 "}",
                 "scene.json: aa.samples:", "(pattern \"ordered\")", "8", NULL);
    expect_error(
        "{\"aa\": {\"mode\": \"msaa\", \"samples\": 64, \"pattern\": \"standard\"}," ONE_CUBE "}",
        "aa.samples:", "(pattern \"standard\")", NULL);
    expect_error("{\"aa\": {\"samples\": 4}," ONE_CUBE "}",
                 "scene.json: aa.samples: expected 1 (or no \"samples\") with mode \"none\", got "
                 "4; set \"mode\": \"msaa\" or \"ssaa\"",
                 NULL);
    expect_error("{\"aa\": {\"mode\": \"msaa\", \"samples\": 0}," ONE_CUBE "}",
                 "aa.samples: expected a whole number in 1..64, got 0", NULL);
}

/* 8-bit colours get a hint with the hex spelling. */
static void test_scene_color_8bit_hint(void **state) {
    (void)state;
    expect_error(
        "{\"objects\": [{\"shape\": \"cube\", \"material\": {\"color\": [217, 238, 185]}}]}",
        "objects[0].material.color: expected colour components in [0, 1], got [217, "
        "238, 185]; for 8-bit values write \"#d9eeb9\"",
        NULL);
    expect_error("{\"clear_color\": \"#12345\"," ONE_CUBE "}",
                 "clear_color: expected a colour: an array of 3 numbers in [0, 1] or a "
                 "\"#rrggbb\" string, got a string (\"#12345\")",
                 NULL);
}

/* Missing required keys name the key and what it should hold. */
static void test_scene_missing_required(void **state) {
    (void)state;
    expect_error("{\"image\": {\"width\": 10}}",
                 "scene.json: missing required key \"objects\" (an array of 1 or more objects)",
                 NULL);
    expect_error("{\"objects\": []}",
                 "scene.json: objects: expected 1 or more objects, got an empty array", NULL);
    expect_error("{\"objects\": [{\"shape\": \"triangle\"}]}",
                 "scene.json: objects[0]: missing required key \"vertices\"", NULL);
    expect_error("{\"objects\": [{\"material\": {}}]}",
                 "scene.json: objects[0]: missing required key \"shape\"", "or \"model\"", NULL);
    expect_error("{\"lights\": [{\"intensity\": 5}]," ONE_CUBE "}",
                 "scene.json: lights[0]: missing required key \"position\"", NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"model\": \"a.obj\"}]}",
                 "objects[0]: expected either \"shape\" (a built-in) or \"model\" (a file), got "
                 "both",
                 NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"material\": {\"texture\": {\"wrap\": "
                 "\"clamp\"}}}]}",
                 "objects[0].material.texture: missing required key \"file\" or \"builtin\"", NULL);
    expect_error(
        "{\"objects\": [{\"shape\": \"cube\", \"transform\": {\"rotate\": {\"deg\": 5}}}]}",
        "objects[0].transform.rotate: missing required key \"axis\"", NULL);
}

/* Texture maps: built-in names as strings, keys of another kind, squares > size. */
static void test_scene_map_errors(void **state) {
    (void)state;
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"material\": {\"texture\": \"checker\"}}]}",
                 "objects[0].material.texture:", "write {\"builtin\": \"checker\"}", NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"material\": {\"texture\": {\"builtin\": "
                 "\"brick\", \"squares\": 4}}}]}",
                 "objects[0].material.texture.squares: \"squares\" does not apply to the brick "
                 "texture",
                 NULL);
    expect_error("{\"objects\": [{\"shape\": \"cube\", \"material\": {\"texture\": {\"builtin\": "
                 "\"checker\", \"size\": 4, \"squares\": 8}}}]}",
                 "expected squares <= size (4), got 8 squares", NULL);
    expect_error(
        "{\"objects\": [{\"shape\": \"cube\", \"material\": {\"height_map\": {\"builtin\": "
        "\"bumpz\"}}}]}",
        "objects[0].material.height_map.builtin: expected one of checker, brick or "
        "bumps, got \"bumpz\"; did you mean \"bumps\"?",
        NULL);
}

/* Limits on counts: lights and rotations. */
static void test_scene_count_limits(void **state) {
    (void)state;
    char text[2048] = "{\"lights\": [";
    for (int i = 0; i <= RAS_SCENE_MAX_LIGHTS; i++)
        strcat(text, i ? ", {\"position\": [0, 0, 0]}" : "{\"position\": [0, 0, 0]}");
    strcat(text, "], " ONE_CUBE "}");
    expect_error(text, "scene.json: lights: expected at most 8 lights, got 9", NULL);
}

/* ------------------------------------------------------------------------ */
/* Files                                                                     */

/* A scene file that does not exist, a folder, a NUL byte and a huge file. */
static void test_scene_file_errors(void **state) {
    const char *missing = tmp_path(state, "no_such_scene.json");
    expect_load_error(missing, missing, "cannot open the scene file", "No such file", NULL);
    const char *dir = make_dir(state, "a_folder.json");
    expect_load_error(dir, dir, "expected a scene file, got a folder", NULL);
    const char *nul = tmp_path(state, "nul.json");
    FILE *f = fopen(nul, "wb");
    assert_non_null(f);
    fwrite("{\n \"a\0", 1, 6, f);
    fclose(f);
    expect_load_error(nul, ":2:4: expected JSON text, got a NUL byte", NULL);
    const char *big = write_file(state, "big.json", "{}");
    assert_int_equal(truncate(big, (off_t)RAS_SCENE_MAX_BYTES + 1), 0);
    expect_load_error(
        big, big, "expected a scene file of at most 16 MiB (16777216 bytes), got 16777217 bytes",
        NULL);
}

/* A file we may not read says so (skipped as root, who reads everything). */
static void test_scene_file_unreadable(void **state) {
    if (geteuid() == 0) {
        skip();
        return;
    }
    const char *path = write_file(state, "secret.json", "{" ONE_CUBE "}");
    chmod(path, 0);
    expect_load_error(path, path, "cannot open the scene file", "Permission denied", NULL);
    chmod(path, 0600);
}

/* Syntax errors in a loaded file carry the file's path. */
static void test_scene_file_syntax_error_names_path(void **state) {
    const char *path = write_file(state, "bad.json", "{\n  \"objects\": [,]\n}\n");
    expect_load_error(path, path, ":2:15: JSON syntax error: expected a value after '[', got ','",
                      NULL);
}

/* Model and texture paths resolve against the scene file's folder; absolute
 * paths stay as they are; the assets load from there. */
static void test_scene_relative_paths(void **state) {
    fixture *fx = *state;
    make_dir(state, "models");
    make_dir(state, "scenes");
    write_file(state, "models/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const char *png = tmp_path(state, "scenes/tex.png");
    ras_error err = {{0}};
    ras_image *img = ras_image_create(4, 2, &err);
    assert_non_null(img);
    ras_image_fill(img, (vec3s){{1, 0, 0}});
    assert_true(ras_image_save(img, png, &err));
    ras_image_destroy(img);
    char text[1024];
    snprintf(text, sizeof text,
             "{\"objects\": [{\"model\": \"../models/tri.obj\", \"fit\": 2,"
             " \"material\": {\"texture\": \"tex.png\", \"height_map\": {\"file\": "
             "\"%s/scenes/tex.png\"}}}]}",
             fx->dir);
    const char *scene_path = write_file(state, "scenes/scene.json", text);
    ras_scene *s = ras_scene_load(scene_path, &err);
    if (!s) fail_msg("%s", err.msg);
    char want[600];
    snprintf(want, sizeof want, "%s/scenes/../models/tri.obj", fx->dir);
    assert_string_equal(s->objects[0].params.model_path, want);
    snprintf(want, sizeof want, "%s/scenes/tex.png", fx->dir);
    assert_string_equal(s->objects[0].material.texture.path, want);
    assert_string_equal(s->objects[0].material.height_map.path, want); /* absolute: as is */
    snprintf(want, sizeof want, "%s/scenes", fx->dir);
    assert_string_equal(s->dir, want);
    ras_scene_assets *a = ras_scene_load_assets(s, &err);
    if (!a) fail_msg("%s", err.msg);
    assert_int_equal(a->meshes[0]->triangle_count, 1);
    vec3s lo, hi;
    ras_mesh_bounds(a->meshes[0], &lo, &hi); /* fit 2: the largest extent is 2 */
    assert_true(fabsf(hi.x - lo.x - 2) < 1e-5f);
    assert_int_equal(a->textures[0]->width, 4);
    assert_ptr_equal(a->textures[0], a->height_maps[0]); /* the same file: loaded once */
    assert_int_equal(a->owned_texture_count, 1);
    ras_scene_assets_destroy(a);
    ras_scene_destroy(s);
    /* A scene parsed from text resolves against base_dir. */
    s = ras_scene_parse("{\"objects\": [{\"model\": \"m.obj\"}]}", "inline", "some/dir", &err);
    assert_non_null(s);
    assert_string_equal(s->objects[0].params.model_path, "some/dir/m.obj");
    ras_scene_destroy(s);
}

/* A missing model or texture file is reported with the object and the path. */
static void test_scene_assets_missing_files(void **state) {
    (void)state;
    ras_error err = {{0}};
    ras_scene *s =
        ras_scene_parse("{\"objects\": [{\"shape\": \"cube\"}, {\"model\": \"nope.obj\"}]}",
                        "scene.json", "/nonexistent", &err);
    assert_non_null(s);
    expect_assets_error(s, "scene.json: objects[1].model: cannot load \"/nonexistent/nope.obj\"",
                        NULL);
    ras_scene_destroy(s);
    s = ras_scene_parse("{\"objects\": [{\"shape\": \"cube\", \"material\": {\"texture\": "
                        "{\"builtin\": \"brick\"}}}, {\"shape\": \"cube\", \"material\": "
                        "{\"height_map\": \"h.png\"}}]}",
                        "scene.json", "/nonexistent", &err);
    assert_non_null(s);
    expect_assets_error(s,
                        "scene.json: objects[1].material.height_map: cannot load "
                        "\"/nonexistent/h.png\"",
                        NULL);
    ras_scene_destroy(s);
}

/* Assets: identical built-in maps are shared, colours and uv_scale applied,
 * and the thin fan's inner edges are shared between neighbours. */
static void test_scene_assets_built(void **state) {
    (void)state;
    ras_scene *s =
        parse_ok("{\"objects\": [{\"shape\": \"plane\", \"material\": {\"color\": [0.5, 0.25, 1],"
                 "\"uv_scale\": 4, \"texture\": {\"builtin\": \"checker\", \"wrap\": \"clamp\"}}},"
                 "{\"shape\": \"cube\", \"material\": {\"texture\": {\"builtin\": \"checker\", "
                 "\"wrap\": \"clamp\"},"
                 "\"height_map\": {\"builtin\": \"bumps\"}}},"
                 "{\"shape\": \"thin_fan\", \"count\": 12}]}");
    ras_error err = {{0}};
    ras_scene_assets *a = ras_scene_load_assets(s, &err);
    if (!a) fail_msg("%s", err.msg);
    assert_ptr_equal(a->textures[0], a->textures[1]);
    assert_int_equal(a->textures[0]->wrap, RAS_WRAP_CLAMP);
    assert_non_null(a->height_maps[1]);
    assert_null(a->height_maps[0]);
    assert_null(a->textures[2]);
    assert_int_equal(a->owned_texture_count, 2);
    assert_vec3_near(a->meshes[0]->colors[0], 0.5f, 0.25f, 1, 0);
    float umax = 0;
    for (size_t v = 0; v < a->meshes[0]->vertex_count; v++)
        if (a->meshes[0]->uvs[v].x > umax) umax = a->meshes[0]->uvs[v].x;
    assert_true(fabsf(umax - 4) < 1e-6f);
    const ras_mesh *fan = a->meshes[2];
    assert_int_equal(fan->triangle_count, 12);
    assert_int_equal(fan->vertex_count, 13); /* centre + 12: the circle closes on itself */
    for (size_t t = 0; t < 12; t++) {
        assert_int_equal(fan->indices[3 * t + 2], fan->indices[3 * ((t + 1) % 12) + 1]);
        vec3s n = glms_vec3_cross(
            glms_vec3_sub(fan->positions[fan->indices[3 * t + 1]], fan->positions[0]),
            glms_vec3_sub(fan->positions[fan->indices[3 * t + 2]], fan->positions[0]));
        assert_true(n.z > 0); /* counter-clockwise seen from +z */
    }
    ras_scene_assets_destroy(a);
    ras_scene_destroy(s);
}

/* Destroy functions accept NULL. */
static void test_scene_destroy_null(void **state) {
    (void)state;
    ras_scene_destroy(NULL);
    ras_scene_assets_destroy(NULL);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_examples_all_load),
        cmocka_unit_test(test_scene_hw2_classic_values),
        cmocka_unit_test(test_scene_defaults),
        cmocka_unit_test(test_scene_shape_params),
        cmocka_unit_test(test_scene_transform_order),
        cmocka_unit_test(test_scene_camera_views),
        cmocka_unit_test(test_scene_values_read),
        cmocka_unit_test(test_scene_aa_defaults),
        cmocka_unit_test(test_scene_depth_format),
        cmocka_unit_test(test_scene_syntax_trailing_comma),
        cmocka_unit_test(test_scene_syntax_missing_comma),
        cmocka_unit_test(test_scene_syntax_hints),
        cmocka_unit_test(test_scene_syntax_ends_early),
        cmocka_unit_test(test_scene_syntax_column_counts_characters),
        cmocka_unit_test(test_scene_syntax_empty_and_top_level),
        cmocka_unit_test(test_scene_wrong_type_names_key_path),
        cmocka_unit_test(test_scene_unknown_key_did_you_mean),
        cmocka_unit_test(test_scene_unknown_key_lists_known),
        cmocka_unit_test(test_scene_other_shape_parameter),
        cmocka_unit_test(test_scene_duplicate_key),
        cmocka_unit_test(test_scene_out_of_range),
        cmocka_unit_test(test_scene_huge_numbers),
        cmocka_unit_test(test_scene_samples_checked_for_pattern),
        cmocka_unit_test(test_scene_color_8bit_hint),
        cmocka_unit_test(test_scene_missing_required),
        cmocka_unit_test(test_scene_map_errors),
        cmocka_unit_test(test_scene_count_limits),
        cmocka_unit_test(test_scene_file_errors),
        cmocka_unit_test(test_scene_file_unreadable),
        cmocka_unit_test(test_scene_file_syntax_error_names_path),
        cmocka_unit_test(test_scene_relative_paths),
        cmocka_unit_test(test_scene_assets_missing_files),
        cmocka_unit_test(test_scene_assets_built),
        cmocka_unit_test(test_scene_destroy_null),
    };
    return RAS_RUN_TESTS("scene", tests, group_setup, group_teardown);
}
