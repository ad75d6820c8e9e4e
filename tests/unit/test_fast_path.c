/* test_fast_path.c — the fast renderer draws what the teaching pipeline draws.
 *
 * The teaching pipeline (hw3_render: one triangle at a time through
 * rasterize_triangle and the core fragment stage, the reference functions of
 * solution/) is the reference. The fast renderer (fast/, fast_render) keeps
 * private copies of some of those functions for speed (fast/README.md lists
 * them). Every scene × shader × AA mode here must give the same
 * image, byte for byte, and the same counters (all but the timings and the
 * buffer memory) with the teaching pipeline and with the fast renderer on 1,
 * 2 and 3 threads. When a reference function changes and its copy does not,
 * the message names the copy to update. See docs/performance.md.
 */
#include <setjmp.h> /* cmocka needs these three first */
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "ras_test_main.h"
#include "fast_render.h"
#include "test_fast_path_work.h"
#include "ras_builtin_scenes.h"
#include "scene.h"

#include <math.h>   /* tan, pow, sqrt, fabs, fmin, fmax */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* malloc, free */
#include <string.h> /* memcmp */

#define X4_C "fast/fast_shade_x4.c"
#define SHADE_C "fast/fast_shade.c"

/* For each shader, the fast renderer's copies of the reference functions it
 * draws with: the one to update when the pictures drift apart (all of them:
 * fast/README.md). */
static const char *const fast_copies[RAS_SHADER_COUNT] = {
    [RAS_SHADER_NORMAL] =
        "the normal lanes of shade_prepare (" X4_C "), its copy of normal_fragment_shader",
    [RAS_SHADER_PHONG] = "blinn_phong (" SHADE_C ") and its four-lane form in "
                         "light_terms_x4/shade_finish (" X4_C "), copies of blinn_phong_lighting "
                         "and phong_fragment_shader",
    [RAS_SHADER_TEXTURE] = "blinn_phong (" SHADE_C ") and shade_finish (" X4_C "), copies of "
                           "blinn_phong_lighting and texture_fragment_shader, or "
                           "bilinear_x4_footprint/bilinear_x4_blend (" X4_C "), the copy of "
                           "texture_sample_bilinear",
    [RAS_SHADER_BUMP] = "bump_normal_x4 and the bump lanes of shade_prepare (" X4_C "), copies "
                        "of bump_normal, tangent_frame, height_sample and "
                        "bump_fragment_shader, or axis_x4/footprint_of/bilinear_x4_blend, the "
                        "copy of texture_sample_bilinear",
    [RAS_SHADER_DISPLACEMENT] = "bump_normal_x4, the displacement lanes of shade_prepare and "
                                "the four-lane Blinn-Phong in light_terms_x4 (" X4_C
                                "), copies of displacement_fragment_shader, bump_normal, "
                                "height_sample and blinn_phong_lighting",
};
/* What every shader shares. The normal shader is checked first: when it
 * differs, these may be the cause; when a later shader differs, they are not. */
#define FAST_SHARED                                                                           \
    "; or, if the other shaders differ too, the shared copies: setup_fixed (fast/fast_setup.c) " \
    "and the tile variants (fast/fast_rast.c) of rasterize_triangle "                           \
    "(hw2_rasterize/solution/rasterizer.c), resolve4 (fast/fast_tile.c) of resolve_pixel, "     \
    "persp_bary (" SHADE_C ") and weights_x4 (" X4_C ") of perspective_correct_barycentric"

/* The program's default scene (scenes/hw3_default.json as built in) and its
 * meshes and textures; the tests change it, then put it back. */
static ras_scene *scene;
static ras_scene_assets *assets;
static ras_image *teaching_img, *fast_img;

static int group_setup(void **state) {
    (void)state;
    ras_error err = {{0}};
    scene = ras_builtin_scene_load("hw3_default", &err);
    assets = scene ? ras_scene_load_assets(scene, &err) : NULL;
    teaching_img = ras_image_create(700, 700, &err);
    fast_img = ras_image_create(700, 700, &err);
    return assets && teaching_img && fast_img ? 0 : -1;
}

static int group_teardown(void **state) {
    (void)state;
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(scene);
    ras_image_destroy(teaching_img);
    ras_image_destroy(fast_img);
    return 0;
}

/* One frame: the teaching pipeline, or the fast renderer on `threads`. */
static void render(hw3_render_options opt, bool teaching, int threads, ras_image *img,
                   ras_counters *k, uint64_t *shaded) {
    ras_error err = {{0}};
    fast_settings settings = {.threads = threads, .shaded = shaded};
    img->width = scene->width; /* the images are allocated at the largest size */
    img->height = scene->height;
    /* declined (-1): the teaching pipeline draws, and *shaded says so */
    int drawn = teaching ? -1 : fast_render(scene, assets, &opt, &settings, img, k, &err);
    if (drawn < 0) drawn = hw3_render(scene, assets, &opt, img, k, &err);
    if (!drawn) fail_msg("hw3_render: %s", err.msg);
}

/* Teaching vs fast with 1, 2 and 3 threads for every shader and AA mode. */
static void check_all(const char *label, hw3_render_options base) {
    const ras_aa_mode aas[3] = {RAS_AA_NONE, RAS_AA_MSAA, RAS_AA_SSAA};
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++)
        for (int a = 0; a < 3; a++) {
            hw3_render_options opt = base;
            opt.shader = (ras_scene_shader)s;
            opt.aa = aas[a];
            if (opt.aa == RAS_AA_NONE) opt.pattern = ras_sample_pattern_center();
            ras_counters kp, kf;
            uint64_t shaded = 0, shaded_1 = 0;
            render(opt, true, 1, teaching_img, &kp, NULL);
            for (int threads = 1; threads <= 3; threads++) {
                shaded = UINT64_MAX; /* the fast path overwrites it */
                render(opt, false, threads, fast_img, &kf, &shaded);
                char what[160];
                snprintf(what, sizeof what, "%s, %s shader, %s, %d thread(s)", label,
                         ras_scene_shader_name(opt.shader), ras_aa_mode_name(opt.aa), threads);
                size_t bytes =
                    sizeof *teaching_img->pixels * (size_t)scene->width * (size_t)scene->height;
                if (memcmp(teaching_img->pixels, fast_img->pixels, bytes) != 0) {
                    int first = -1, count = 0, pixels = scene->width * scene->height;
                    for (int i = 0; i < pixels; i++)
                        if (memcmp(&teaching_img->pixels[i], &fast_img->pixels[i],
                                   sizeof *teaching_img->pixels)) {
                            if (first < 0) first = i;
                            count++;
                        }
                    fail_msg("fast path differs from the teaching pipeline for shader %s: update "
                             "%s%s (%s: %d of %d pixels differ, the first at col %d, row %d)",
                             ras_scene_shader_name(opt.shader), fast_copies[opt.shader],
                             opt.shader == RAS_SHADER_NORMAL ? FAST_SHARED : "", what, count,
                             pixels, first % scene->width, first / scene->width);
                }
                fast_path_same_work(&kp, &kf, what);
                if (shaded == UINT64_MAX)
                    fail_msg("%s: the fast renderer did not draw (fast_render declined)", what);
                /* Deferred shading shades each fragment still owning a sample
                 * once: never more than the counter (every fragment that
                 * passed a depth test), none when nothing passed, the same
                 * for any thread count, and at 1x (a fragment is one pixel,
                 * a pixel has one owner) at most one per pixel. */
                if (shaded > kf.fragments_shaded || (kf.fragments_shaded > 0) != (shaded > 0))
                    fail_msg("%s: %llu fragments really shaded for %llu counted", what,
                             (unsigned long long)shaded, (unsigned long long)kf.fragments_shaded);
                uint64_t pixels = (uint64_t)scene->width * (uint64_t)scene->height;
                if (opt.aa == RAS_AA_NONE && shaded > pixels)
                    fail_msg("%s: %llu fragments shaded for %d pixels", what,
                             (unsigned long long)shaded, scene->width * scene->height);
                if (threads == 1) shaded_1 = shaded;
                if (shaded != shaded_1)
                    fail_msg("%s: %llu fragments really shaded, %llu with one thread", what,
                             (unsigned long long)shaded, (unsigned long long)shaded_1);
            }
        }
}

static hw3_render_options options(ras_pattern_kind kind, int samples) {
    hw3_render_options opt = hw3_render_defaults();
    ras_error err = {{0}};
    if (!ras_sample_pattern_make(kind, samples, &opt.pattern, &err)) fail_msg("%s", err.msg);
    return opt;
}

/* The default scene (five objects, textures, bump maps) at 700×700, ordered 4x.
 * Sanitizer builds (CI's second step) draw it at 350×350: the 60 frames at
 * full size take minutes under ASan, and a smaller frame still cuts every
 * object across several tiles. */
#ifdef RAS_SANITIZE
#define DEFAULT_SCENE_SIZE 350
#else
#define DEFAULT_SCENE_SIZE 700
#endif
static void test_fast_path_default_scene(void **state) {
    (void)state;
    scene->width = scene->height = DEFAULT_SCENE_SIZE;
    check_all("default scene", options(RAS_PATTERN_ORDERED, 4));
}

/* An odd size (tiles cut by the frame's edges), turned, trilinear, the
 * standard 8x pattern. */
static void test_fast_path_odd_size_trilinear(void **state) {
    (void)state;
    scene->width = 301;
    scene->height = 157;
    hw3_render_options opt = options(RAS_PATTERN_STANDARD, 8);
    opt.angle_deg = 57;
    opt.filter = FILTER_TRILINEAR;
    /* The first trilinear frame builds the mip levels (and counts them): build
     * them here so every compared frame starts from the same scene. */
    ras_counters k;
    hw3_render_options first = opt;
    first.shader = RAS_SHADER_TEXTURE;
    render(first, true, 1, teaching_img, &k, NULL);
    check_all("301x157 trilinear", opt);
    scene->width = scene->height = 700;
}

/* The camera among the objects: triangles cross the near plane and are
 * clipped and split; affine interpolation and nearest filtering. */
static void test_fast_path_clipping_affine(void **state) {
    (void)state;
    vec3s eye = scene->camera.eye;
    scene->width = 256;
    scene->height = 200;
    scene->camera.eye = (vec3s){{1.0f, 1.2f, 0.6f}};
    hw3_render_options opt = options(RAS_PATTERN_STANDARD, 4);
    opt.affine = true;
    opt.filter = FILTER_NEAREST;
    opt.angle_deg = -20;
    ras_counters k;
    render(opt, true, 1, teaching_img, &k, NULL);
    assert_true(k.triangles_clip_split > 0);
    check_all("near-plane clipping, affine", opt);
    scene->camera.eye = eye;
    scene->width = scene->height = 700;
}

/* Materials the default scene lacks: clamped textures (bilinear_x4_footprint's other
 * wrap), a 1×1 colour map, a coloured light (three divisions for its
 * irradiance, not one), then no light at all (the unbatched shaders' path for
 * Blinn-Phong and texture). */
static void test_fast_path_clamp_coloured_light_no_light(void **state) {
    (void)state;
    scene->width = 200;
    scene->height = 160;
    ras_wrap *wraps = malloc((size_t)assets->owned_texture_count * sizeof *wraps);
    assert_non_null(wraps);
    for (int i = 0; i < assets->owned_texture_count; i++) {
        wraps[i] = assets->owned_textures[i]->wrap;
        assets->owned_textures[i]->wrap = RAS_WRAP_CLAMP;
    }
    ras_texture *tiny = ras_texture_create_checker(1, 1, (vec3s){{0.9f, 0.4f, 0.1f}},
                                                   (vec3s){{0.0f, 0.0f, 0.0f}});
    assert_non_null(tiny);
    int textured = -1;
    for (int o = 0; o < scene->object_count && textured < 0; o++)
        if (assets->textures[o]) textured = o;
    assert_true(textured >= 0);
    ras_texture *kept = assets->textures[textured];
    assets->textures[textured] = tiny;
    ras_scene_light first = scene->lights[0];
    int lights = scene->light_count;
    scene->lights[0].intensity = (vec3s){{500.0f, 300.0f, 100.0f}};
    check_all("clamp, 1x1 texture, coloured light", options(RAS_PATTERN_ORDERED, 4));
    scene->light_count = 0;
    check_all("no light", options(RAS_PATTERN_ORDERED, 4));
    scene->light_count = lights;
    scene->lights[0] = first;
    assets->textures[textured] = kept;
    ras_texture_destroy(tiny);
    for (int i = 0; i < assets->owned_texture_count; i++)
        assets->owned_textures[i]->wrap = wraps[i];
    free(wraps);
    scene->width = scene->height = 700;
}

/* The scene's textures rounded to bytes, as an RGB8 texture (what a file
 * gives) and as its float twin (the same bytes' floats). */
typedef struct byte_twins {
    ras_texture *bytes, *floats;
} byte_twins;

static byte_twins byte_twins_of(const ras_texture *t) {
    int w = t->width, h = t->height;
    uint8_t *rgb = malloc((size_t)w * (size_t)h * 3);
    ras_image *img = ras_image_create(w, h, NULL);
    assert_true(rgb && img);
    for (int row = 0; row < h; row++) /* top row first, as a decoder gives */
        for (int i = 0; i < w; i++) {
            vec3s c = ras_texture_texel(t, 0, i, h - 1 - row);
            uint8_t *p = rgb + ((size_t)row * (size_t)w + (size_t)i) * 3;
            p[0] = ras_unit_to_byte(c.x), p[1] = ras_unit_to_byte(c.y), p[2] = ras_unit_to_byte(c.z);
            ras_image_set(img, i, row,
                          (vec3s){{ras_byte_to_unit(p[0]), ras_byte_to_unit(p[1]),
                                   ras_byte_to_unit(p[2])}});
        }
    byte_twins b = {ras_texture_from_rgb8(rgb, w, h, t->wrap, NULL),
                    ras_texture_from_image(img, t->wrap, NULL)};
    ras_image_destroy(img);
    assert_true(b.bytes && b.floats && b.bytes->format == RAS_TEXELS_RGB8);
    return b;
}

/* Points every object's maps at `floats` or `bytes` twins (or back at the
 * originals, `kept`). */
static void use_maps(ras_texture **kept, byte_twins *twins, int use) {
    for (int o = 0; o < scene->object_count; o++)
        for (int which = 0; which < 2; which++) {
            ras_texture **slot = which ? &assets->height_maps[o] : &assets->textures[o];
            int k = 2 * o + which;
            *slot = !kept[k] ? NULL : use == 0 ? kept[k] : use == 1 ? twins[k].floats : twins[k].bytes;
        }
}

/* Textures kept as bytes (loaded files) draw what their float twins draw,
 * in the solution's bilinear, trilinear and bump lookups (bilinear_level,
 * bump_heights: the byte path) and in the fast renderer's (bilinear_x4_blend:
 * its byte path), for every filter: the same picture byte for byte, and
 * teaching = fast. */
static void test_fast_path_rgb8_textures(void **state) {
    (void)state;
    scene->width = scene->height = 256;
    int slots = 2 * scene->object_count;
    ras_texture **kept = calloc((size_t)slots, sizeof *kept);
    byte_twins *twins = calloc((size_t)slots, sizeof *twins);
    ras_image *float_img = ras_image_create(700, 700, NULL);
    assert_true(kept && twins && float_img);
    for (int k = 0; k < slots; k++) {
        kept[k] = k % 2 ? assets->height_maps[k / 2] : assets->textures[k / 2];
        if (kept[k]) twins[k] = byte_twins_of(kept[k]);
    }
    const texture_filter filters[3] = {FILTER_NEAREST, FILTER_BILINEAR, FILTER_TRILINEAR};
    const ras_scene_shader shaders[3] = {RAS_SHADER_TEXTURE, RAS_SHADER_BUMP,
                                         RAS_SHADER_DISPLACEMENT};
    for (int f = 0; f < 3; f++) {
        hw3_render_options opt = options(RAS_PATTERN_ORDERED, 4);
        opt.filter = filters[f];
        opt.angle_deg = 33;
        for (int si = 0; si < 3; si++) {
            opt.shader = shaders[si];
            ras_counters kf, kb;
            use_maps(kept, twins, 1);
            render(opt, true, 1, float_img, &kf, NULL);
            use_maps(kept, twins, 2);
            render(opt, true, 1, teaching_img, &kb, NULL);
            size_t bytes = sizeof *teaching_img->pixels * (size_t)scene->width * (size_t)scene->height;
            if (memcmp(float_img->pixels, teaching_img->pixels, bytes))
                fail_msg("%s shader, %s filter: the textures kept as bytes draw a different "
                         "picture from their float twins; expected the same floats from every "
                         "lookup: check bilinear_level/bump_heights' byte path "
                         "(hw3_shading/solution/shading.c) and ras_texel_unit",
                         ras_scene_shader_name(opt.shader), ras_scene_filter_name((ras_scene_filter)opt.filter));
        }
        use_maps(kept, twins, 2);
        char label[64];
        snprintf(label, sizeof label, "RGB8 textures, %s filter",
                 ras_scene_filter_name((ras_scene_filter)opt.filter));
        check_all(label, opt);
    }
    use_maps(kept, twins, 0);
    for (int k = 0; k < slots; k++) {
        ras_texture_destroy(twins[k].bytes);
        ras_texture_destroy(twins[k].floats);
    }
    free(kept);
    free(twins);
    ras_image_destroy(float_img);
    scene->width = scene->height = 700;
}

/* Extreme but legal cameras: near 0.1 and 0.01 with far 1e6,
 * triangles whose tip lies within 0.05 of the eye and whose far edge lies at
 * 900 000, and a floor 1e6 wide seen from 1e-3 above it with near 1e-4 (far
 * 1e6 is the largest a scene file takes). The
 * clipper cuts them at the near and far planes and the guard band; the old
 * float cut sent corners with w ~ 0 beyond 2^20 px, which the fast path
 * silently skipped while the teaching pipeline drew them. Both must now
 * draw the same pixels and count the same work, on every shader and AA. */
#define MATERIAL                                                                            \
    "\"material\": {\"color\": [0.8, 0.6, 0.3], \"texture\": {\"builtin\": \"checker\", "       \
    "\"size\": 64, \"squares\": 8}, \"height_map\": {\"builtin\": \"bumps\", \"size\": 64, "  \
    "\"bumps\": 4}, \"ks\": 0.5, \"kh\": 4, \"kn\": 0.05}"
static const char *const extreme_scenes[] = {
    "{\"image\": {\"width\": 160, \"height\": 120},"
    " \"camera\": {\"eye\": [0, 0, 5], \"fov_deg\": 45, \"near\": 0.1, \"far\": 1e6},"
    " \"lights\": [{\"position\": [0, 20, 10], \"intensity\": 600}],"
    " \"objects\": [{\"shape\": \"triangle\", \"vertices\": [[0.01, 0.01, 4.95],"
    " [-50, -1, -900000], [50, -1, -900000]], " MATERIAL "}]}",
    "{\"image\": {\"width\": 160, \"height\": 120},"
    " \"camera\": {\"eye\": [0, 0, 5], \"fov_deg\": 45, \"near\": 0.01, \"far\": 1e6},"
    " \"lights\": [{\"position\": [0, 20, 10], \"intensity\": 600}],"
    " \"objects\": [{\"shape\": \"triangle\", \"vertices\": [[0.01, 0.01, 4.995],"
    " [-50, -1, -900000], [50, -1, -900000]], " MATERIAL "},"
    " {\"shape\": \"triangle\", \"vertices\": [[0.0116474076, -0.0897293307, 4.99015045],"
    " [73827.3668, -70968.9836, -548216.739], [6956.36316, -6231.19753, -65193.7945]], "
    MATERIAL "}]}",
    "{\"image\": {\"width\": 128, \"height\": 96},"
    " \"camera\": {\"eye\": [0.3, -0.999, 5], \"look_at\": [0.5, -1, -100], \"fov_deg\": 100,"
    " \"near\": 1e-4, \"far\": 1e6},"
    " \"lights\": [{\"position\": [0, 20, 10], \"intensity\": 600}],"
    " \"objects\": [{\"shape\": \"plane\", \"size\": 1e6, \"divisions\": 3,"
    " \"transform\": {\"translate\": [0, -1, 0]}, " MATERIAL "}]}",
};

static void test_fast_path_extreme_cameras(void **state) {
    (void)state;
    ras_scene *kept_scene = scene;
    ras_scene_assets *kept_assets = assets;
    for (size_t i = 0; i < sizeof extreme_scenes / sizeof *extreme_scenes; i++) {
        ras_error err = {{0}};
        char name[32];
        snprintf(name, sizeof name, "extreme camera %zu", i);
        scene = ras_scene_parse(extreme_scenes[i], name, NULL, &err);
        assets = scene ? ras_scene_load_assets(scene, &err) : NULL;
        if (!assets) {
            ras_scene_destroy(scene);
            scene = kept_scene, assets = kept_assets; /* the group teardown frees those */
            fail_msg("test setup: %s", err.msg);
        }
#ifdef RAS_SANITIZE
        /* half size under the sanitizers, as the default scene (the frames
         * still cut every triangle across several tiles) */
        scene->width /= 2;
        scene->height /= 2;
#endif
        hw3_render_options opt = options(RAS_PATTERN_STANDARD, 4);
        ras_counters k;
        render(opt, true, 1, teaching_img, &k, NULL);
        printf("%s: %llu triangles split by the clipper, %llu rasterized, %llu samples "
               "covered, %llu refused for range\n",
               name, (unsigned long long)k.triangles_clip_split,
               (unsigned long long)k.triangles_rasterized,
               (unsigned long long)k.samples_covered,
               (unsigned long long)k.triangles_rejected_range);
        assert_true(k.triangles_clip_split > 0 && k.samples_covered > 0);
        check_all(name, opt);
        ras_scene_assets_destroy(assets);
        ras_scene_destroy(scene);
    }
    scene = kept_scene;
    assets = kept_assets;
}

/* Issue #42, B1: nothing beyond the far plane is drawn at any legal near
 * and far. A triangle across the view axis at distance × far (eye at the
 * origin, looking down -z, a scale of far on corners at ±distance) for near
 * 1e-3..1, far up to 1e6 (the largest a scene takes) and distance 1.01..3:
 * no sample covered, by the teaching pipeline and the fast renderer, and
 * the same triangle at 0.99 × far covers the frame's middle (the camera
 * sees it; a far plane put too near would fail there). The float far test
 * (z >= -w on the float projection) drew 26% of the frame at near 0.1,
 * far 1e6, distance 1.2. Then legal values whose product leaves the far
 * range: translate 1e6, scale 1e6, corners at 1e6 (a triangle 1e12 away). */
static ras_scene *far_sweep_scene(double near, double far, double m, const char *transform) {
    char json[1024], name[96];
    snprintf(json, sizeof json,
             "{\"image\": {\"width\": 64, \"height\": 48},"
             " \"camera\": {\"eye\": [0, 0, 0], \"fov_deg\": 45, \"near\": %.9g, \"far\": %.9g},"
             " \"objects\": [{\"shape\": \"triangle\", \"vertices\": [[%.9g, %.9g, %.9g],"
             " [%.9g, %.9g, %.9g], [0, %.9g, %.9g]], \"transform\": %s}]}",
             near, far, -m, -m, -m, m, -m, -m, m, -m, transform);
    snprintf(name, sizeof name, "near %g far %g at %g x far", near, far, m);
    ras_error err = {{0}};
    ras_scene *s = ras_scene_parse(json, name, NULL, &err);
    if (!s) fail_msg("test setup: %s: %s", name, err.msg);
    return s;
}

/* Samples covered by the teaching pipeline and by the fast renderer (one
 * and two threads), which must agree. */
static uint64_t far_sweep_covered(ras_scene *s, const char *what) {
    ras_scene *kept_scene = scene;
    ras_scene_assets *kept_assets = assets;
    ras_error err = {{0}};
    scene = s;
    assets = ras_scene_load_assets(s, &err);
    if (!assets) {
        scene = kept_scene, assets = kept_assets;
        fail_msg("test setup: %s: %s", what, err.msg);
    }
    hw3_render_options opt = hw3_render_defaults(); /* the normal shader, no AA */
    ras_counters kt, kf1, kf2;
    render(opt, true, 1, teaching_img, &kt, NULL);
    render(opt, false, 1, fast_img, &kf1, NULL);
    bool same1 = !memcmp(teaching_img->pixels, fast_img->pixels,
                         (size_t)s->width * s->height * sizeof *fast_img->pixels);
    render(opt, false, 2, fast_img, &kf2, NULL);
    bool same2 = !memcmp(teaching_img->pixels, fast_img->pixels,
                         (size_t)s->width * s->height * sizeof *fast_img->pixels);
    ras_scene_assets_destroy(assets);
    scene = kept_scene, assets = kept_assets;
    if (!same1 || !same2 || kt.samples_covered != kf1.samples_covered ||
        kt.samples_covered != kf2.samples_covered)
        fail_msg("%s: the fast renderer drew other pixels than the teaching pipeline (%llu, "
                 "%llu and %llu samples covered); expected the same picture",
                 what, (unsigned long long)kt.samples_covered,
                 (unsigned long long)kf1.samples_covered, (unsigned long long)kf2.samples_covered);
    return kt.samples_covered;
}

static void test_fast_path_far_plane_sweep(void **state) {
    (void)state;
    const double nears[] = {1e-3, 1e-2, 0.1, 1}, fars[] = {1e2, 1e4, 1e5, 1e6};
    const double beyond[] = {1.01, 1.1, 1.2, 1.5, 2, 3};
    long cases = 0, drawn_beyond = 0;
    char first[160] = "";
    for (size_t i = 0; i < sizeof nears / sizeof *nears; i++)
        for (size_t j = 0; j < sizeof fars / sizeof *fars; j++) {
            char transform[64], what[128];
            snprintf(transform, sizeof transform, "{\"scale\": %.9g}", fars[j]);
            snprintf(what, sizeof what, "near %g, far %g, at 0.99 x far", nears[i], fars[j]);
            ras_scene *s = far_sweep_scene(nears[i], fars[j], 0.99, transform);
            uint64_t inside = far_sweep_covered(s, what);
            ras_scene_destroy(s);
            if (inside < 64 * 48 / 4)
                fail_msg("%s: %llu of %d samples covered; expected the triangle in front of "
                         "the far plane drawn across the frame's middle",
                         what, (unsigned long long)inside, 64 * 48);
            for (size_t k = 0; k < sizeof beyond / sizeof *beyond; k++) {
                snprintf(what, sizeof what, "near %g, far %g, at %g x far", nears[i], fars[j],
                         beyond[k]);
                s = far_sweep_scene(nears[i], fars[j], beyond[k], transform);
                uint64_t n = far_sweep_covered(s, what);
                ras_scene_destroy(s);
                cases++;
                if (n && !drawn_beyond++)
                    snprintf(first, sizeof first, "%s: %llu samples", what,
                             (unsigned long long)n);
            }
        }
    /* the products of legal values: 1e6 + 1e6 * 1e6 away */
    ras_scene *s = far_sweep_scene(0.1, 1e6, 1e6, "{\"translate\": [0, 0, -1e6], \"scale\": 1e6}");
    uint64_t n = far_sweep_covered(s, "translate 1e6, scale 1e6, corners at 1e6, far 1e6");
    ras_scene_destroy(s);
    cases++;
    if (n && !drawn_beyond++)
        snprintf(first, sizeof first, "translate 1e6, scale 1e6, corners at 1e6: %llu samples",
                 (unsigned long long)n);
    printf("far plane sweep: %ld triangles beyond far, %ld drawn\n", cases, drawn_beyond);
    if (drawn_beyond)
        fail_msg("%ld of %ld triangles beyond the far plane were drawn; first: %s. Expected "
                 "nothing beyond far (stage2_clip.c: the far test w <= z_far in double)",
                 drawn_beyond, cases, first);
}

/* ---- issue #42, B2: edge-on triangles against a ray cast ------------------ */

/* A splitmix64 with a fixed seed, so a failure reproduces. */
static uint64_t edge_rng_next(uint64_t *s) {
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double edge_uniform(uint64_t *s, double lo, double hi) {
    return lo + (hi - lo) * ((double)(edge_rng_next(s) >> 11) * 0x1p-53);
}
static double edge_log(uint64_t *s, double lo_exp, double hi_exp) {
    return pow(10.0, edge_uniform(s, lo_exp, hi_exp));
}

/* One scene of the random search: the fixed view (eye, looking down -z),
 * the corners as the scene file holds them (floats). */
typedef struct edge_scene {
    float eye[3], fov, near, far;
    int width, height;
    float tri[3][3];
} edge_scene;

/* The ray cast, in double from the float scene values: does the ray
 * through image point (sx, sy) (y up) hit the triangle between near and far? */
static bool edge_ray_hits(const edge_scene *s, double sx, double sy) {
    double t = tan((double)s->fov * 3.14159265358979323846 / 360.0);
    double aspect = (double)((float)s->width / (float)s->height);
    double d[3] = {(2 * sx / s->width - 1) * t * aspect, (2 * sy / s->height - 1) * t, -1};
    double a[3], e1[3], e2[3];
    for (int i = 0; i < 3; i++) {
        a[i] = (double)s->tri[0][i] - s->eye[i];
        e1[i] = (double)s->tri[1][i] - s->eye[i] - a[i];
        e2[i] = (double)s->tri[2][i] - s->eye[i] - a[i];
    }
    double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                   d[0] * e2[1] - d[1] * e2[0]};
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0) return false;
    double o[3] = {-a[0], -a[1], -a[2]};
    double u = (o[0] * p[0] + o[1] * p[1] + o[2] * p[2]) / det;
    double q[3] = {o[1] * e1[2] - o[2] * e1[1], o[2] * e1[0] - o[0] * e1[2],
                   o[0] * e1[1] - o[1] * e1[0]};
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    double dist = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det; /* view depth */
    return u >= 0 && v >= 0 && u + v <= 1 && dist >= s->near && dist <= s->far;
}

/* The four classes of issue #42 B2, each with the triangle seen edge-on:
 * its plane is put 1e-11 of its size from the eye, and the corners' float
 * rounding (as a scene file gives them) then leaves it about that rounding
 * away. 0 a corner inside near, 1 a corner behind
 * the eye, 2 two corners behind, 3 a spike (two corners together far away,
 * the third inside near). The eye within 1000 of the origin (where a float
 * transform cancels), the far corners up to 1e6 from it, near 1e-3..1, far
 * up to 1e6 (a quarter exactly 1e6). */
static void edge_random_scene(uint64_t *g, int cls, edge_scene *s) {
    double eye[3];
    for (int i = 0; i < 3; i++) eye[i] = edge_uniform(g, -1000, 1000);
    s->fov = (float)edge_uniform(g, 20, 120);
    s->width = 48 + (int)edge_uniform(g, 0, 112);
    s->height = 48 + (int)edge_uniform(g, 0, 112);
    s->near = (float)edge_log(g, -3, 0);
    s->far = edge_uniform(g, 0, 1) < 0.25 ? 1e6f : (float)fmin(1e6, s->near * edge_log(g, 2, 9));
    /* corners ahead of the eye (positive: in front), on a plane through
     * eye + 1e-11 * size * normal */
    double ahead[3], side[3][2];
    double far_at = fmin(edge_log(g, 0, 0) * s->far * edge_uniform(g, 0.05, 0.95), 9.8e5);
    for (int i = 0; i < 3; i++) ahead[i] = far_at * edge_uniform(g, 0.2, 1);
    ahead[0] = s->near * edge_uniform(g, 0.01, 0.9); /* class 0 and 3 */
    if (cls == 1 || cls == 2) ahead[0] = -edge_log(g, -3, 3);
    if (cls == 2) ahead[1] = -edge_log(g, -3, 3);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 2; j++)
            side[i][j] = edge_uniform(g, -1, 1) * fmax(fabs(ahead[i]), 1e-3) *
                         (i == 0 ? edge_uniform(g, 0, 1) : 1);
    if (cls == 3) /* a spike: the far corners side by side */
        for (int j = 0; j < 2; j++)
            side[2][j] = side[1][j] + edge_uniform(g, -1e-3, 1e-3) * ahead[1];
    /* the plane through the three offsets, moved to pass 1e-11 of the
     * triangle's size from the eye: each corner shifted along its normal */
    double c[3][3];
    for (int i = 0; i < 3; i++) c[i][0] = side[i][0], c[i][1] = side[i][1], c[i][2] = -ahead[i];
    double u[3], v[3], n[3];
    for (int k = 0; k < 3; k++) u[k] = c[1][k] - c[0][k], v[k] = c[2][k] - c[0][k];
    n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double off = (c[0][0] * n[0] + c[0][1] * n[1] + c[0][2] * n[2]) / nn; /* plane to eye */
    double want = edge_uniform(g, -1, 1) * 1e-11 * far_at;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            s->tri[i][k] = (float)(eye[k] + c[i][k] + (want - off) * n[k] / nn);
    for (int k = 0; k < 3; k++) s->eye[k] = (float)eye[k];
}

static ras_scene *edge_scene_parse(const edge_scene *s) {
    char json[1024];
    snprintf(json, sizeof json,
             "{\"image\": {\"width\": %d, \"height\": %d},"
             " \"camera\": {\"eye\": [%.9g, %.9g, %.9g], \"fov_deg\": %.9g, \"near\": %.9g,"
             " \"far\": %.9g}, \"objects\": [{\"shape\": \"triangle\", \"vertices\":"
             " [[%.9g, %.9g, %.9g], [%.9g, %.9g, %.9g], [%.9g, %.9g, %.9g]]}]}",
             s->width, s->height, s->eye[0], s->eye[1], s->eye[2], s->fov, s->near, s->far,
             s->tri[0][0], s->tri[0][1], s->tri[0][2], s->tri[1][0], s->tri[1][1], s->tri[1][2],
             s->tri[2][0], s->tri[2][1], s->tri[2][2]);
    ras_error err = {{0}};
    ras_scene *rs = ras_scene_parse(json, "edge-on scene", NULL, &err);
    if (!rs) fail_msg("test setup: %s\n%s", err.msg, json);
    return rs;
}

/* The triangle on screen, exactly enough to measure 1 px: clipped to the
 * view depths [near, far] in view space (double), its corners projected in
 * double. n corners, at most 5. */
typedef struct edge_polygon {
    double x[5], y[5];
    int n;
} edge_polygon;

static edge_polygon edge_project(const edge_scene *s) {
    double p[8][3], q[8][3];
    int n = 3;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) p[i][k] = (double)s->tri[i][k] - s->eye[k];
    for (int plane = 0; plane < 2; plane++) { /* depth = -z: >= near, <= far */
        int m = 0;
        for (int i = 0; i < n; i++) {
            const double *a = p[i], *b = p[(i + 1) % n];
            double da = plane ? s->far + a[2] : -a[2] - s->near;
            double db = plane ? s->far + b[2] : -b[2] - s->near;
            if (da >= 0) memcpy(q[m++], a, sizeof q[0]);
            if ((da >= 0) != (db >= 0)) {
                double t = da / (da - db);
                for (int k = 0; k < 3; k++) q[m][k] = a[k] + t * (b[k] - a[k]);
                m++;
            }
        }
        memcpy(p, q, sizeof p);
        n = m;
    }
    edge_polygon e = {.n = n};
    double t = tan((double)s->fov * 3.14159265358979323846 / 360.0);
    double aspect = (double)((float)s->width / (float)s->height);
    for (int i = 0; i < n; i++) {
        e.x[i] = (p[i][0] / -p[i][2] / (t * aspect) + 1) * 0.5 * s->width;
        e.y[i] = (p[i][1] / -p[i][2] / t + 1) * 0.5 * s->height;
    }
    return e;
}

/* Distance from (x, y) to the polygon's outline. */
static double edge_outline_distance(const edge_polygon *e, double x, double y) {
    double best = INFINITY;
    for (int i = 0; i < e->n; i++) {
        double ax = e->x[i], ay = e->y[i];
        double bx = e->x[(i + 1) % e->n], by = e->y[(i + 1) % e->n];
        double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
        double t = len2 > 0 ? ((x - ax) * dx + (y - ay) * dy) / len2 : 0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        best = fmin(best, hypot(x - ax - t * dx, y - ay - t * dy));
    }
    return best;
}

/* Pixels the picture gets wrong by more than 1 px: lit where the ray cast
 * through the centre misses and the triangle's outline is more than 1 px
 * away, or unlit where it hits and the outline is more than 1 px away. */
static long edge_pixels_off(const edge_scene *s, const ras_image *img, long *truth_in) {
    int W = s->width, H = s->height;
    edge_polygon e = edge_project(s);
    long off = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double cx = x + 0.5, cy = y + 0.5;
            bool truth = edge_ray_hits(s, cx, cy);
            vec3s c = img->pixels[(size_t)(H - 1 - y) * W + x];
            bool lit = c.x != 0 || c.y != 0 || c.z != 0;
            *truth_in += truth;
            if (lit != truth && !(e.n >= 3 && edge_outline_distance(&e, cx, cy) <= 1.0)) off++;
        }
    return off;
}

static void test_fast_path_edge_on_raycast(void **state) {
    (void)state;
    static const char *const classes[4] = {"a corner inside near", "a corner behind the eye",
                                           "two corners behind", "a spike"};
#ifdef RAS_SANITIZE
    const int per_class = 150;
#else
    const int per_class = 600;
#endif
    uint64_t g = 0x42b2ULL;
    ras_scene *kept_scene = scene;
    ras_scene_assets *kept_assets = assets;
    long bad = 0, seen = 0, worst = 0, differ = 0;
    char first[1024] = "";
    for (int cls = 0; cls < 4; cls++)
        for (int n = 0; n < per_class; n++) {
            edge_scene s;
            edge_random_scene(&g, cls, &s);
            ras_error err = {{0}};
            scene = edge_scene_parse(&s);
            assets = ras_scene_load_assets(scene, &err);
            if (!assets) fail_msg("test setup: %s", err.msg);
            hw3_render_options opt = hw3_render_defaults();
            ras_counters kt, kf;
            render(opt, true, 1, teaching_img, &kt, NULL);
            render(opt, false, 2, fast_img, &kf, NULL);
            differ += memcmp(teaching_img->pixels, fast_img->pixels,
                             (size_t)s.width * s.height * sizeof *fast_img->pixels) != 0;
            long truth_in = 0, off = edge_pixels_off(&s, teaching_img, &truth_in);
            seen += truth_in > 0;
            if (off > worst) worst = off;
            if (off && !bad++)
                snprintf(first, sizeof first,
                         "%s, scene %d: %ld pixels off (ray cast %ld); eye (%.9g %.9g %.9g) fov "
                         "%.9g near %.9g far %.9g %dx%d, corners (%.9g %.9g %.9g) (%.9g %.9g "
                         "%.9g) (%.9g %.9g %.9g)",
                         classes[cls], n, off, truth_in, s.eye[0], s.eye[1], s.eye[2], s.fov,
                         s.near, s.far, s.width, s.height, s.tri[0][0], s.tri[0][1],
                         s.tri[0][2], s.tri[1][0], s.tri[1][1], s.tri[1][2], s.tri[2][0],
                         s.tri[2][1], s.tri[2][2]);
            ras_scene_assets_destroy(assets);
            ras_scene_destroy(scene);
        }
    scene = kept_scene, assets = kept_assets;
    printf("edge-on triangles: %d scenes (%ld with pixels in view), %ld more than 1 px from "
           "the ray cast (worst %ld pixels), %ld where fast != teaching\n",
           4 * per_class, seen, bad, worst, differ);
    if (seen < per_class)
        fail_msg("test setup: only %ld of %d scenes show the triangle", seen, 4 * per_class);
    if (bad || differ)
        fail_msg("%ld of %d edge-on scenes are drawn more than 1 px from a double ray cast, "
                 "and %ld differ between the fast renderer and the teaching pipeline; "
                 "expected none (stage1_vertex.c: the transform in double where the float "
                 "one cancels; stage2_clip.c). First: %s",
                 bad, 4 * per_class, differ, first);
}

/* The fast renderer declines what hw3 refuses (flat, an out-of-range shader)
 * rather than drawing it: -1 hands the frame back to hw3_render, which says
 * why (test_scene_stages' test_flat_shader_refused checks the message). */
static void test_fast_path_declines_flat(void **state) {
    (void)state;
    hw3_render_options opt = hw3_render_defaults();
    fast_img->width = scene->width;
    fast_img->height = scene->height;
    const ras_scene_shader refused[2] = {RAS_SHADER_FLAT, RAS_SHADER_COUNT};
    for (int k = 0; k < 2; k++) {
        opt.shader = refused[k];
        ras_error err = {{0}};
        assert_int_equal(fast_render(scene, assets, &opt, NULL, fast_img, NULL, &err), -1);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fast_path_default_scene),
        cmocka_unit_test(test_fast_path_odd_size_trilinear),
        cmocka_unit_test(test_fast_path_clipping_affine),
        cmocka_unit_test(test_fast_path_clamp_coloured_light_no_light),
        cmocka_unit_test(test_fast_path_rgb8_textures),
        cmocka_unit_test(test_fast_path_extreme_cameras),
        cmocka_unit_test(test_fast_path_far_plane_sweep),
        cmocka_unit_test(test_fast_path_edge_on_raycast),
        cmocka_unit_test(test_fast_path_declines_flat),
    };
    return RAS_RUN_TESTS("fast_path", tests, group_setup, group_teardown);
}
