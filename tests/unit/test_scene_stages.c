/* test_scene_stages.c — the pipeline runs only what a scene calls for, and
 * --stats says so: counters of small scenes rendered through the real
 * reference pipeline (hw3_ref: scene file → ras_scene_load_assets → hw3_render).
 *
 * Every expected number is worked out by hand from the geometry, not read
 * back from a run:
 *   - FULL: one triangle (-6,-4,0) (6,-4,0) (0,8,0) seen from (0,0,5) with a
 *     45° field of view. At distance 5 the view spans ±5·tan 22.5° = ±2.071
 *     units, and the triangle's edges pass outside that square (the left edge
 *     is at x = -2.96 where y = 2.071), so every sample of the 64×64 frame is
 *     covered by this one triangle: 4096 pixels. Its corners project to
 *     |x_ndc| <= 2.9, inside the guard band (8), so it is not clipped into a
 *     fan: one triangle, one bounding box = the whole frame.
 *   - HALF: (0,-6,0) (0,6,0) (-12,0,0): the edge x = 0 projects to screen
 *     x = 32 exactly, and the other two edges pass outside the view (y = 4.96
 *     at x = -2.071), so the left half is covered: 32 × 64 = 2048 pixels, and
 *     no sample (centre 0.5, ordered 4x at 0.25 / 0.75) lies on x = 32.
 *   - buffers: a colour is a vec3s (12 bytes), a depth a float (4 bytes),
 *     per sample (ras_framebuffer.h).
 *   - taps (shading.h, texture_sample and height_sample): nearest reads 1
 *     texel, bilinear 4, trilinear 8 (two levels); bump reads the height map
 *     3 times per fragment. A 64×64 texture has mip levels 32, 16, 8, 4, 2, 1:
 *     6 built.
 *   - ambient only: ka·I_a = 0.005 · 10 = 0.05 (the scene-file defaults).
 */
#include <setjmp.h> /* required by cmocka.h */
#include <stdarg.h> /* required by cmocka.h */
#include <stddef.h> /* required by cmocka.h */
#include <stdint.h> /* required by cmocka.h */

#include <cmocka.h>

#include "ras_test_main.h"

#include "ras_builtin_scenes.h"
#include "scene.h"

#include <math.h>   /* fabsf */
#include <stdio.h>  /* snprintf, fopen */
#include <stdlib.h> /* malloc, free */
#include <string.h> /* strcmp, strstr */

#define W 64
#define PIXELS (W * W)
#define FULL "[[-6, -4, 0], [6, -4, 0], [0, 8, 0]]"
#define HALF "[[0, -6, 0], [0, 6, 0], [-12, 0, 0]]"
#define LIGHT "{\"position\": [2, 3, 4], \"intensity\": 20}"
#define CHECKER "\"texture\": {\"builtin\": \"checker\", \"size\": 64, \"squares\": 4}"
#define BUMPS "\"height_map\": {\"builtin\": \"bumps\", \"size\": 64, \"bumps\": 4}"

/* One object (a triangle with `vertices`) and the given material, lights,
 * shader, filter and aa members, 64×64. */
typedef struct spec {
    const char *vertices, *material, *lights, *shader, *filter, *aa;
} spec;

typedef struct frame {
    ras_counters k;
    ras_image *image;
    unsigned varyings; /* hw3_frame_varyings */
} frame;

static void scene_text(const spec *s, char *buf, size_t size) {
    int n =
        snprintf(buf, size,
                 "{\"image\": {\"width\": %d, \"height\": %d},\n"
                 " \"camera\": {\"eye\": [0, 0, 5], \"fov_deg\": 45, \"near\": 0.1, \"far\": 50},\n"
                 " \"objects\": [{\"shape\": \"triangle\", \"vertices\": %s,\n"
                 "               \"material\": {%s}}],\n"
                 " \"lights\": [%s], \"shader\": \"%s\", \"filter\": \"%s\", \"aa\": {%s}}\n",
                 W, W, s->vertices, s->material ? s->material : "", s->lights ? s->lights : "",
                 s->shader, s->filter ? s->filter : "bilinear", s->aa ? s->aa : "");
    assert_true(n > 0 && (size_t)n < size);
}

/* The spec's frame, drawn by hw3_render from a freshly parsed scene. */
static frame render(const spec *s) {
    char text[2048];
    scene_text(s, text, sizeof text);
    ras_error err = {{0}};
    ras_scene *rs = ras_scene_parse(text, "stages.json", NULL, &err);
    if (!rs) fail_msg("the test scene does not parse: %s\n%s", err.msg, text);
    ras_scene_assets *assets = ras_scene_load_assets(rs, &err);
    if (!assets) fail_msg("ras_scene_load_assets: %s", err.msg);
    hw3_render_options opt = hw3_render_options_from_ras(rs);
    frame f = {.varyings = hw3_frame_varyings(rs, assets, opt.shader)};
    f.image = ras_image_create(W, W, &err);
    assert_non_null(f.image);
    if (!hw3_render(rs, assets, &opt, f.image, &f.k, &err)) fail_msg("hw3_render: %s", err.msg);
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(rs);
    return f;
}

static bool ran(const frame *f, unsigned stage) { return (f->k.stages_run & stage) != 0; }

/* ---- anti-aliasing: sample buffers and shading rate ----------------------- */

static void test_aa_none_has_no_sample_buffers(void **state) {
    (void)state;
    frame f = render(&(spec){.vertices = FULL, .shader = "normal"});
    /* one sample per pixel: 4096 × (12 + 4) bytes, nothing per sample */
    assert_int_equal(sizeof(vec3s), 12);
    assert_int_equal(f.k.buffer_bytes, 65536);
    assert_int_equal(f.k.samples_tested, PIXELS);
    assert_int_equal(f.k.samples_covered, PIXELS);
    assert_int_equal(f.k.fragments_shaded, PIXELS);
    assert_false(ran(&f, RAS_STAGE_RESOLVE)); /* one sample: nothing to resolve */
    ras_image_destroy(f.image);
}

static void test_msaa4_buffers_are_four_samples(void **state) {
    (void)state;
    frame f = render(
        &(spec){.vertices = FULL, .shader = "normal", .aa = "\"mode\": \"msaa\", \"samples\": 4"});
    assert_int_equal(f.k.buffer_bytes, 4 * 65536);
    assert_true(ran(&f, RAS_STAGE_RESOLVE));
    ras_image_destroy(f.image);
}

static void test_msaa_shades_once_per_pixel(void **state) {
    (void)state;
    frame f = render(
        &(spec){.vertices = FULL, .shader = "normal", .aa = "\"mode\": \"msaa\", \"samples\": 4"});
    /* one triangle whose box is the frame: every sample tested once and covered */
    assert_int_equal(f.k.samples_tested, 4 * PIXELS);
    assert_int_equal(f.k.samples_covered, 4 * PIXELS);
    assert_int_equal(f.k.fragments_shaded, PIXELS); /* not 4 × */
    ras_image_destroy(f.image);

    f = render(
        &(spec){.vertices = HALF, .shader = "normal", .aa = "\"mode\": \"msaa\", \"samples\": 4"});
    assert_int_equal(f.k.samples_covered, 4 * PIXELS / 2);
    assert_int_equal(f.k.fragments_shaded, PIXELS / 2); /* the covered pixels */
    assert_true(f.k.samples_tested >= f.k.samples_covered && f.k.samples_tested % 4 == 0);
    ras_image_destroy(f.image);
}

static void test_ssaa_shades_every_sample(void **state) {
    (void)state;
    frame f = render(
        &(spec){.vertices = FULL, .shader = "normal", .aa = "\"mode\": \"ssaa\", \"samples\": 4"});
    assert_int_equal(f.k.buffer_bytes, 4 * 65536);
    assert_int_equal(f.k.samples_tested, 4 * PIXELS);
    assert_int_equal(f.k.fragments_shaded, 4 * PIXELS);
    ras_image_destroy(f.image);

    f = render(
        &(spec){.vertices = HALF, .shader = "normal", .aa = "\"mode\": \"ssaa\", \"samples\": 4"});
    assert_int_equal(f.k.fragments_shaded, 4 * PIXELS / 2);
    ras_image_destroy(f.image);

    f = render(&(spec){.vertices = HALF, .shader = "normal"});
    assert_int_equal(f.k.fragments_shaded, PIXELS / 2); /* no AA: the centre samples */
    ras_image_destroy(f.image);
}

/* ---- textures: no map, no fetch, no UV --------------------------------------- */

static void test_untextured_scene_fetches_no_texels(void **state) {
    (void)state;
    /* The texture shader with trilinear filtering, but nothing to sample. */
    frame f = render(
        &(spec){.vertices = FULL, .shader = "texture", .filter = "trilinear", .lights = LIGHT});
    assert_int_equal(f.k.fragments_shaded, PIXELS);
    assert_int_equal(f.k.texels_fetched, 0);
    assert_int_equal(f.k.mip_levels_built, 0);
    assert_false(ran(&f, RAS_STAGE_TEXTURE));
    assert_false(ran(&f, RAS_STAGE_MIPMAP));
    /* no UVs: the normal and the view position, per fragment */
    assert_int_equal(f.varyings & RAS_VARYING_UV, 0);
    assert_int_equal(f.k.varyings_interpolated, 2 * PIXELS);
    ras_image_destroy(f.image);
}

static void test_height_map_alone_is_no_colour_texture(void **state) {
    (void)state;
    /* The texture shader reads colour maps only: a height map is not read. */
    frame f =
        render(&(spec){.vertices = FULL, .shader = "texture", .material = BUMPS, .lights = LIGHT});
    assert_int_equal(f.k.texels_fetched, 0);
    assert_int_equal(f.varyings & RAS_VARYING_UV, 0);
    assert_int_equal(f.k.varyings_interpolated, 2 * PIXELS);
    ras_image_destroy(f.image);
}

static void test_texels_are_fragments_times_taps(void **state) {
    (void)state;
    static const struct {
        const char *filter;
        uint64_t taps, mips;
    } cases[] = {{"nearest", 1, 0}, {"bilinear", 4, 0}, {"trilinear", 8, 6}};
    for (int i = 0; i < 3; i++) {
        frame f = render(&(spec){.vertices = FULL,
                                 .shader = "texture",
                                 .material = CHECKER,
                                 .filter = cases[i].filter,
                                 .lights = LIGHT});
        assert_int_equal(f.k.fragments_shaded, PIXELS);
        if (f.k.texels_fetched != PIXELS * cases[i].taps)
            fail_msg("%s: %llu texels for %d fragments, expected %llu taps each", cases[i].filter,
                     (unsigned long long)f.k.texels_fetched, PIXELS,
                     (unsigned long long)cases[i].taps);
        assert_int_equal(f.k.mip_levels_built, cases[i].mips);
        assert_true(ran(&f, RAS_STAGE_TEXTURE));
        assert_int_equal(ran(&f, RAS_STAGE_MIPMAP), cases[i].mips > 0);
        assert_int_equal(f.k.varyings_interpolated, 3 * PIXELS); /* normal, view pos, UV */
        ras_image_destroy(f.image);
    }
    /* MSAA shades once per pixel, so it fetches once per pixel too. */
    frame f = render(&(spec){.vertices = FULL,
                             .shader = "texture",
                             .material = CHECKER,
                             .lights = LIGHT,
                             .aa = "\"mode\": \"msaa\", \"samples\": 4"});
    assert_int_equal(f.k.texels_fetched, 4 * PIXELS); /* bilinear × 4096 fragments */
    ras_image_destroy(f.image);
}

static void test_bump_reads_the_height_map_three_times(void **state) {
    (void)state;
    frame f = render(&(spec){.vertices = FULL, .shader = "bump", .material = BUMPS});
    assert_int_equal(f.k.texels_fetched, 3 * 4 * PIXELS); /* h(u,v), h(u+1/W,v), h(u,v+1/H) */
    assert_true(ran(&f, RAS_STAGE_BUMP));
    assert_int_equal(f.k.varyings_interpolated, 2 * PIXELS); /* normal, UV */
    ras_image_destroy(f.image);

    f = render(&(spec){.vertices = FULL, .shader = "bump", .material = BUMPS, .filter = "nearest"});
    assert_int_equal(f.k.texels_fetched, 3 * PIXELS);
    ras_image_destroy(f.image);

    /* no height map: no bump work, no UVs */
    f = render(&(spec){.vertices = FULL, .shader = "bump"});
    assert_int_equal(f.k.texels_fetched, 0);
    assert_false(ran(&f, RAS_STAGE_BUMP));
    assert_int_equal(f.k.varyings_interpolated, PIXELS); /* the normal only */
    ras_image_destroy(f.image);
}

/* ---- lights: none, no lighting stage ------------------------------------------ */

static void test_no_lights_no_lighting(void **state) {
    (void)state;
    frame f = render(&(spec){.vertices = FULL, .shader = "phong"});
    assert_false(ran(&f, RAS_STAGE_LIGHTING));
    assert_int_equal(f.k.lighting_evaluations, 0);
    /* the view position only serves the lights: the normal alone is interpolated */
    assert_int_equal(f.varyings, RAS_VARYING_NORMAL);
    assert_int_equal(f.k.varyings_interpolated, PIXELS);
    /* what is left is the ambient term, ka · I_a = 0.005 · 10 */
    vec3s c = ras_image_get(f.image, W / 2, W / 2);
    assert_true(fabsf(c.x - 0.05f) < 1e-6f && fabsf(c.y - 0.05f) < 1e-6f &&
                fabsf(c.z - 0.05f) < 1e-6f);
    ras_image_destroy(f.image);

    f = render(&(spec){.vertices = FULL, .shader = "phong", .lights = LIGHT "," LIGHT});
    assert_true(ran(&f, RAS_STAGE_LIGHTING));
    assert_int_equal(f.k.lighting_evaluations, 2 * PIXELS);
    assert_int_equal(f.k.varyings_interpolated, 2 * PIXELS);
    ras_image_destroy(f.image);
}

static void test_unlit_shader_no_lighting(void **state) {
    (void)state;
    frame f =
        render(&(spec){.vertices = FULL, .shader = "normal", .lights = LIGHT, .material = CHECKER});
    unsigned never = RAS_STAGE_LIGHTING | RAS_STAGE_TEXTURE | RAS_STAGE_BUMP | RAS_STAGE_MIPMAP |
                     RAS_STAGE_RESOLVE | RAS_STAGE_WIREFRAME;
    assert_int_equal(f.k.stages_run & never, 0);
    assert_int_equal(f.k.stages_run, RAS_STAGE_VERTEX | RAS_STAGE_CLIP | RAS_STAGE_SETUP |
                                         RAS_STAGE_RASTER | RAS_STAGE_FRAGMENT);
    assert_int_equal(f.k.texels_fetched, 0);
    assert_int_equal(f.k.varyings_interpolated, PIXELS);
    ras_image_destroy(f.image);
}

/* ---- how the scene reaches the shaders ------------------------------------------ */

/* A phong frame of two cubes under one light, given in `space` at `pos`. */
static ras_image *lit_cubes(const char *space, const char *pos) {
    char text[512];
    snprintf(text, sizeof text,
             "{\"image\": {\"width\": %d, \"height\": %d}, \"camera\": {\"eye\": [1, 2, 5]},"
             " \"objects\": [{\"shape\": \"cube\", \"transform\": {\"translate\": [0.5, 2, 0]}},"
             " {\"shape\": \"cube\", \"transform\": {\"translate\": [1.5, 2, 0]}}],"
             " \"lights\": [{\"position\": %s, \"space\": \"%s\"}], \"shader\": \"phong\"}",
             W, W, pos, space);
    ras_error err = {{0}};
    ras_scene *rs = ras_scene_parse(text, "lights.json", NULL, &err);
    ras_scene_assets *assets = rs ? ras_scene_load_assets(rs, &err) : NULL;
    if (!assets) fail_msg("%s", err.msg);
    hw3_render_options opt = hw3_render_options_from_ras(rs);
    ras_image *img = ras_image_create(W, W, &err);
    assert_non_null(img);
    if (!hw3_render(rs, assets, &opt, img, NULL, &err)) fail_msg("hw3_render: %s", err.msg);
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(rs);
    return img;
}

/* The shaders light in view space: a world light is moved there. The fixed
 * view translates by -eye, so a world light at (1,2,15) seen from (1,2,5) is
 * the view light (0,0,10), bit for bit; and the light does matter (one at
 * (0,0,-10), behind the cubes, draws another picture). */
static void test_world_lights_move_to_view_space(void **state) {
    (void)state;
    ras_image *world = lit_cubes("world", "[1, 2, 15]"), *view = lit_cubes("view", "[0, 0, 10]");
    ras_image *behind = lit_cubes("view", "[0, 0, -10]");
    size_t bytes = sizeof(vec3s) * PIXELS;
    assert_memory_equal(world->pixels, view->pixels, bytes);
    assert_memory_not_equal(view->pixels, behind->pixels, bytes);
    ras_image_destroy(world);
    ras_image_destroy(view);
    ras_image_destroy(behind);
}

/* The material is per object, and kd when given is the base colour. */
static void test_material_is_per_object(void **state) {
    (void)state;
    ras_error err = {{0}};
    ras_scene *rs =
        ras_scene_parse("{\"objects\": [{\"shape\": \"cube\"},"
                        " {\"shape\": \"cube\", \"material\": {\"ka\": 0.5, \"ks\": 0.25, \"p\": "
                        "8, \"kd\": 0.75, \"color\": [0.1, 0.2, 0.3]}}]}",
                        "material.json", NULL, &err);
    ras_scene_assets *assets = rs ? ras_scene_load_assets(rs, &err) : NULL;
    if (!assets) fail_msg("%s", err.msg);
    fragment_shader_payload p[2] = {0};
    for (int i = 0; i < 2; i++)
        hw3_object_material(rs, assets, i, &p[i]);
    assert_true(p[0].ka.x == 0.005f && p[0].p == 150 && p[0].color.x == 1);
    assert_true(p[1].ka.x == 0.5f && p[1].ks.y == 0.25f && p[1].p == 8 && p[1].color.z == 0.75f);
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(rs);
}

/* --model's scene: the model file takes the first object's place; --fit
 * replaces its scale; the texture doubles as the height map unless --height
 * names one (the course loads hmap.jpg as "the texture"). */
static void test_model_scene_takes_the_files(void **state) {
    (void)state;
    ras_error err = {{0}};
    ras_scene *s =
        ras_builtin_scene_with_model("hw3_model", "spot.obj", "spot.png", NULL, true, &err);
    if (!s) fail_msg("%s", err.msg);
    const ras_scene_object *o = &s->objects[0];
    assert_int_equal(o->shape, RAS_SHAPE_MODEL);
    assert_string_equal(o->params.model_path, "spot.obj");
    assert_true(o->params.fit == RAS_BUILTIN_MODEL_FIT && o->scale.x == 1);
    assert_int_equal(o->material.texture.kind, RAS_MAP_FILE);
    assert_string_equal(o->material.height_map.path, "spot.png");
    ras_scene_destroy(s);
    s = ras_builtin_scene_with_model("hw3_model", "spot.obj", NULL, NULL, false, &err);
    if (!s) fail_msg("%s", err.msg);
    o = &s->objects[0];
    assert_true(o->params.fit == 0 && o->scale.x == 2.5f);
    assert_int_equal(o->material.texture.kind, RAS_MAP_CHECKER);
    assert_int_equal(o->material.height_map.kind, RAS_MAP_BUMPS);
    ras_scene_destroy(s);
}

/* ---- the built-in default scene ---------------------------------------------------- */

static char *read_file(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)n + 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
        free(text);
        text = NULL;
    }
    if (text) text[n] = '\0';
    fclose(f);
    return text;
}

static void test_builtin_scenes_are_the_files(void **state) {
    (void)state;
    const char *names[] = {"hw1_classic", "hw2_classic", "hw3_default", "hw3_model"};
    for (int i = 0; i < 4; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/scenes/%s.json", RAS_SOURCE_DIR, names[i]);
        char *file = read_file(path);
        assert_non_null(file);
        const char *built_in = ras_builtin_scene_text(names[i]);
        if (!built_in || strcmp(built_in, file))
            fail_msg("the built-in %s differs from %s: re-run cmake", names[i], path);
        free(file);
        ras_error err = {{0}};
        ras_scene *s = ras_builtin_scene_load(names[i], &err);
        if (!s) fail_msg("%s", err.msg);
        ras_scene_destroy(s);
    }
    assert_null(ras_builtin_scene_text("nope"));
}

/* "depth": "inverse_w" reaches hw3's pipeline: two parallel triangles at view
 * depth 45 and 45 − 0.0001, the farther (blue) listed first. With the
 * default z01 their depths differ by n·δ/d² ≈ 5e-9, a twelfth of a float
 * step, so rounding decides each pixel and some go to the farther one (12%
 * here, docs/accuracy.md §5 has the full picture), while inverse_w shows the
 * nearer (red) everywhere. inverse_w also takes the
 * plain pipeline (the fast path draws z01 only): its buffers are one frame. */
static void test_depth_key_reaches_the_pipeline(void **state) {
    (void)state;
    for (int inv = 0; inv < 2; inv++) {
        char text[1024];
        snprintf(text, sizeof text,
                 "{\"image\": {\"width\": %d, \"height\": %d}, \"depth\": \"%s\",\n"
                 " \"objects\": [\n"
                 "  {\"shape\": \"triangle\", \"vertices\": [[-99, -99, -40], [99, -99, -40], "
                 "[0, 99, -40]], \"material\": {\"color\": [0, 0, 1]}},\n"
                 "  {\"shape\": \"triangle\", \"vertices\": [[-99, -99, -39.9999], [99, -99, "
                 "-39.9999], [0, 99, -39.9999]], \"material\": {\"color\": [1, 0, 0]}}],\n"
                 " \"lights\": [{\"position\": [0, 0, 0], \"intensity\": 500}], "
                 "\"shader\": \"phong\"}",
                 W, W, inv ? "inverse_w" : "z01");
        ras_error err = {{0}};
        ras_scene *rs = ras_scene_parse(text, "depth.json", NULL, &err);
        if (!rs) fail_msg("the test scene does not parse: %s\n%s", err.msg, text);
        ras_scene_assets *assets = ras_scene_load_assets(rs, &err);
        assert_non_null(assets);
        hw3_render_options opt = hw3_render_options_from_ras(rs);
        assert_int_equal(opt.depth, inv ? RAS_DEPTH_INV_W : RAS_DEPTH_Z01);
        ras_image *img = ras_image_create(W, W, &err);
        assert_non_null(img);
        ras_counters k;
        assert_true(hw3_render(rs, assets, &opt, img, &k, &err));
        int red = 0, blue = 0;
        for (int i = 0; i < PIXELS; i++) {
            red += img->pixels[i].x > img->pixels[i].z;
            blue += img->pixels[i].z > img->pixels[i].x;
        }
        printf("depth %s: %d red (nearer) and %d blue (farther) pixels\n",
               inv ? "inverse_w" : "z01", red, blue);
        assert_int_equal(red + blue, PIXELS); /* the triangles cover the view */
        if (inv) {
            assert_int_equal(blue, 0);
            assert_int_equal(k.buffer_bytes, (uint64_t)PIXELS * (sizeof(vec3s) + sizeof(float)));
        } else {
            assert_true(blue > 0);
        }
        ras_image_destroy(img);
        ras_scene_assets_destroy(assets);
        ras_scene_destroy(rs);
    }
}

/* hw3 draws the core's shaders from normal on: flat (hw2's unlit colour) and a
 * value past the last are refused with a message naming the five, by the
 * teaching frame and (declining first) the fast path; a scene file's "flat"
 * becomes the default, normal, and --shader flat does not parse. */
static void test_flat_shader_refused(void **state) {
    (void)state;
    ras_error err = {{0}};
    ras_scene *rs =
        ras_scene_parse("{\"image\": {\"width\": 8, \"height\": 8}, \"shader\": \"flat\","
                        " \"objects\": [{\"shape\": \"cube\"}]}",
                        "flat.json", NULL, &err);
    assert_non_null(rs);
    ras_scene_assets *assets = ras_scene_load_assets(rs, &err);
    assert_non_null(assets);
    hw3_render_options opt = hw3_render_options_from_ras(rs);
    assert_int_equal(opt.shader, RAS_SHADER_NORMAL);
    ras_scene_shader parsed = RAS_SHADER_PHONG;
    assert_false(hw3_shader_parse("flat", &parsed, &err));
    assert_int_equal(parsed, RAS_SHADER_PHONG);
    assert_non_null(
        strstr(err.msg, "--shader expects normal, phong, texture, bump or displacement"));
    ras_image *img = ras_image_create(8, 8, &err);
    assert_non_null(img);
    const ras_scene_shader refused[2] = {RAS_SHADER_FLAT, RAS_SHADER_COUNT};
    for (int k = 0; k < 2; k++) {
        opt.shader = refused[k];
        assert_null(hw3_shader_function(opt.shader));
        assert_int_equal(hw3_shader_varyings(opt.shader), 0);
        err = (ras_error){{0}};
        assert_false(hw3_render(rs, assets, &opt, img, NULL, &err));
        printf("shader %d: %s\n", (int)opt.shader, err.msg);
        assert_non_null(
            strstr(err.msg, k ? "hw3 has no shader \"?\": expected normal, phong, "
                                "texture, bump or displacement"
                              : "hw3 has no shader \"flat\" (hw2's unlit colour): "
                                "expected normal, phong, texture, bump or displacement"));
    }
    ras_image_destroy(img);
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(rs);
}

/* ---- the shell's frame: a kept pipeline draws as a new one ---------------- */

/* The shell (ras_app_draw_frame) keeps its pipeline while the program's
 * configuration is equal and only clears it (ras_pipeline_begin_frame); the
 * window's keys that change no configuration (a/d, the mouse) draw that
 * way. hw3's hooks, as main.c has them, over options the test sets. */
typedef struct shell_frame {
    hw3_render_options opt;
    hw3_frame frame;
} shell_frame;

static bool shell_configure(ras_app *app, ras_pipeline_config *cfg, ras_error *err) {
    shell_frame *sf = app->user;
    if (!hw3_frame_setup(app->scene, app->assets, &sf->opt, &sf->frame, err)) return false;
    *cfg = hw3_frame_config(app->scene, &sf->opt, &sf->frame);
    return true;
}

static bool shell_draw(ras_app *app, ras_pipeline *p, ras_error *err) {
    shell_frame *sf = app->user;
    return hw3_frame_draw(app->scene, app->assets, sf->opt.angle_deg, &sf->frame, p, err);
}

/* The counters as --stats prints them, without the times. */
static void counters_text(const ras_counters *k, char *buf, size_t size) {
    ras_counters_format_json(k, buf, size);
    char *ms = strstr(buf, ", \"ms\"");
    assert_non_null(ms);
    *ms = '\0';
}

static void test_shell_kept_pipeline_draws_as_new(void **state) {
    (void)state;
    static const ras_app_hooks hooks = {.program = "test",
                                        .configure = shell_configure,
                                        .draw = shell_draw,
                                        .features = RAS_APP_STEP};
    ras_error err = {{0}};
    ras_scene *rs = ras_scene_load_or_builtin(NULL, "hw3_default", &err);
    if (!rs) fail_msg("the built-in scene: %s", err.msg);
    rs->width = rs->height = W;
    ras_scene_assets *assets = ras_scene_load_assets(rs, &err);
    if (!assets) fail_msg("ras_scene_load_assets: %s", err.msg);
    shell_frame kept = {.opt = hw3_render_options_from_ras(rs)}, fresh;
    kept.opt.shader = RAS_SHADER_PHONG;
    kept.opt.aa = RAS_AA_MSAA;
    assert_true(ras_sample_pattern_make(RAS_PATTERN_STANDARD, 4, &kept.opt.pattern, NULL));
    /* the buffer view shows overdraw: the shell keeps the frame's buffers,
     * the fragment stage's too */
    ras_app a = {.hooks = &hooks,
                 .scene = rs,
                 .assets = assets,
                 .user = &kept,
                 .step = {.buffer = RAS_APP_BUFFER_OVERDRAW}};
    ras_app b = a;
    a.image = ras_image_create(W, W, &err);
    b.image = ras_image_create(W, W, &err);
    assert_true(a.image && b.image);
    if (!ras_app_draw_frame(&a, &err)) fail_msg("frame 1: %s", err.msg);
    const ras_pipeline *first = a.pipeline;
    /* frame 2: turned — the same configuration, so the same pipeline (the
     * fragment stage's buffers cleared again) */
    kept.opt.angle_deg = 40;
    if (!ras_app_draw_frame(&a, &err)) fail_msg("frame 2: %s", err.msg);
    assert_ptr_equal(a.pipeline, first);
    /* the same frame from a new pipeline */
    fresh = kept;
    b.user = &fresh;
    if (!ras_app_draw_frame(&b, &err)) fail_msg("the new pipeline's frame: %s", err.msg);
    assert_ptr_not_equal(b.pipeline, a.pipeline);
    const ras_framebuffer *fa = a.pipeline->fb, *fb = b.pipeline->fb;
    size_t n = (size_t)W * W * (size_t)fa->samples;
    assert_int_equal(fa->samples, 4);
    assert_memory_equal(a.image->pixels, b.image->pixels, (size_t)W * W * sizeof(vec3s));
    assert_memory_equal(fa->color, fb->color, n * sizeof(vec3s));
    assert_memory_equal(fa->depth, fb->depth, n * sizeof(float));
    assert_non_null(a.pipeline->overdraw);
    assert_memory_equal(a.pipeline->overdraw, b.pipeline->overdraw, (size_t)W * W * sizeof(float));
    assert_non_null(a.pipeline->fragment.normal); /* phong: normal and view depth */
    assert_memory_equal(a.pipeline->fragment.normal, b.pipeline->fragment.normal,
                        (size_t)W * W * 3 * sizeof(float));
    assert_memory_equal(a.pipeline->fragment.view_depth, b.pipeline->fragment.view_depth,
                        (size_t)W * W * sizeof(float));
    char ka[2048], kb[2048];
    counters_text(a.counters, ka, sizeof ka);
    counters_text(b.counters, kb, sizeof kb);
    assert_string_equal(ka, kb);
    assert_true(a.counters->fragments_shaded > 0);
    /* another configuration (16 samples): a new pipeline, made before the
     * kept one is freed, so its address differs */
    assert_true(ras_sample_pattern_make(RAS_PATTERN_STANDARD, 16, &kept.opt.pattern, NULL));
    if (!ras_app_draw_frame(&a, &err)) fail_msg("frame 3: %s", err.msg);
    assert_ptr_not_equal(a.pipeline, first);
    assert_int_equal(a.pipeline->fb->samples, 16);
    /* the step view is the shell's as --dump is: hw3's configure sets neither */
    a.step.on = true, a.step.limit = 3;
    if (!ras_app_draw_frame(&a, &err)) fail_msg("the step view's frame: %s", err.msg);
    assert_int_equal(a.counters->triangles_rasterized, 3);
    assert_true(a.pipeline->has_last);
    ras_pipeline_destroy(a.pipeline);
    ras_pipeline_destroy(b.pipeline);
    ras_image_destroy(a.image);
    ras_image_destroy(b.image);
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(rs);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_aa_none_has_no_sample_buffers),
        cmocka_unit_test(test_msaa4_buffers_are_four_samples),
        cmocka_unit_test(test_msaa_shades_once_per_pixel),
        cmocka_unit_test(test_ssaa_shades_every_sample),
        cmocka_unit_test(test_untextured_scene_fetches_no_texels),
        cmocka_unit_test(test_height_map_alone_is_no_colour_texture),
        cmocka_unit_test(test_texels_are_fragments_times_taps),
        cmocka_unit_test(test_bump_reads_the_height_map_three_times),
        cmocka_unit_test(test_no_lights_no_lighting),
        cmocka_unit_test(test_unlit_shader_no_lighting),
        cmocka_unit_test(test_world_lights_move_to_view_space),
        cmocka_unit_test(test_material_is_per_object),
        cmocka_unit_test(test_model_scene_takes_the_files),
        cmocka_unit_test(test_builtin_scenes_are_the_files),
        cmocka_unit_test(test_depth_key_reaches_the_pipeline),
        cmocka_unit_test(test_flat_shader_refused),
        cmocka_unit_test(test_shell_kept_pipeline_draws_as_new),
    };
    return RAS_RUN_TESTS("scene_stages", tests, NULL, NULL);
}
