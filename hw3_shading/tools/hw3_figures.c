/* hw3_figures.c — renders the pictures of docs/hw3.md with the reference
 * solution, so no figure is drawn by hand:
 *
 *   hw3_<shader>.png     the default scene with each of the five shaders, 350×350
 *   hw3_w1_pitfall.png   the textured floor: perspective-correct | affine (what
 *                        a pipeline that forces w = 1 draws)
 *   hw3_half_texel.png   a 4×4 checker magnified to 240×240 px: nearest |
 *                        bilinear with texel centres at u·W − 0.5 | bilinear
 *                        without the −0.5 (the picture moves half a texel)
 *   hw3_filters.png      the far floor with a fine checker, magnified 2×:
 *                        nearest | bilinear | trilinear
 *
 * Usage: hw3_figures [OUTPUT_DIR]   (default docs/img)
 */
#include "ras_builtin_scenes.h" /* the default scene, scenes/hw3_default.json */
#include "scene.h"

#include <math.h>   /* floorf */
#include <stdio.h>  /* printf, fprintf, snprintf */
#include <stdlib.h> /* EXIT_FAILURE */

static const vec3s GAP = {{0.5f, 0.5f, 0.5f}};

static ras_image *render(const ras_scene *s, ras_scene_assets *assets, hw3_render_options opt) {
    ras_error err = {{0}};
    ras_image *img = ras_image_create(s->width, s->height, &err);
    if (!img || !hw3_render(s, assets, &opt, img, NULL, &err)) {
        fprintf(stderr, "hw3_figures: %s\n", err.msg);
        exit(EXIT_FAILURE);
    }
    return img;
}

/* Copies the w×h window at (c0, r0) of src, magnified `zoom` times, to dst at (dc, dr). */
static void blit(ras_image *dst, int dc, int dr, const ras_image *src, int c0, int r0, int w,
                 int h, int zoom) {
    for (int r = 0; r < h * zoom; r++)
        for (int c = 0; c < w * zoom; c++)
            ras_image_set(dst, dc + c, dr + r, ras_image_get(src, c0 + c / zoom, r0 + r / zoom));
}

static void save(ras_image *img, const char *dir, const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    ras_error err = {{0}};
    if (!ras_image_save(img, path, &err)) {
        fprintf(stderr, "hw3_figures: %s\n", err.msg);
        exit(EXIT_FAILURE);
    }
    printf("wrote %s\n", path);
    ras_image_destroy(img);
}

/* Panels side by side with a 4-pixel grey gap. */
static ras_image *row_of(int n, int w, int h) {
    ras_image *img = ras_image_create(n * w + (n - 1) * 4, h, NULL);
    if (!img) exit(EXIT_FAILURE);
    ras_image_fill(img, GAP);
    return img;
}

/* Bilinear WITHOUT the half-texel shift (the mistake), clamp-to-edge. */
static vec3s bilinear_no_shift(const ras_texture *tex, float u, float v) {
    float x = u * (float)tex->width, y = v * (float)tex->height;
    float x0 = floorf(x), y0 = floorf(y), sx = x - x0, sy = y - y0;
    int i = (int)x0, j = (int)y0;
    vec3s a = ras_texture_texel(tex, 0, i, j), b = ras_texture_texel(tex, 0, i + 1, j);
    vec3s c = ras_texture_texel(tex, 0, i, j + 1), d = ras_texture_texel(tex, 0, i + 1, j + 1);
    vec3s bottom = glms_vec3_lerp(a, b, sx), top = glms_vec3_lerp(c, d, sx);
    return glms_vec3_lerp(bottom, top, sy);
}

static void half_texel(const char *dir) {
    ras_texture *tex = ras_texture_create_checker(4, 4, (vec3s){{0.95f, 0.85f, 0.3f}},
                                                  (vec3s){{0.15f, 0.2f, 0.45f}});
    if (!tex) exit(EXIT_FAILURE);
    tex->wrap = RAS_WRAP_CLAMP;
    const int side = 240;
    ras_image *img = row_of(3, side, side);
    for (int r = 0; r < side; r++)
        for (int c = 0; c < side; c++) {
            /* pixel centre → uv; image row 0 is the top, v = 1 */
            float u = ((float)c + 0.5f) / side, v = 1.0f - ((float)r + 0.5f) / side;
            ras_image_set(img, c, r, ras_texture_sample_nearest(tex, u, v));
            ras_image_set(img, side + 4 + c, r, texture_sample_bilinear(tex, u, v));
            ras_image_set(img, 2 * (side + 4) + c, r, bilinear_no_shift(tex, u, v));
        }
    /* texel centres of the 4×4 texture: small black dots on every panel */
    for (int p = 0; p < 3; p++)
        for (int j = 0; j < 4; j++)
            for (int i = 0; i < 4; i++) {
                int cc = p * (side + 4) + (2 * i + 1) * side / 8, rr = (2 * j + 1) * side / 8;
                for (int dr = -1; dr <= 1; dr++)
                    for (int dc = -1; dc <= 1; dc++)
                        ras_image_set(img, cc + dc, rr + dr, (vec3s){{0, 0, 0}});
            }
    ras_texture_destroy(tex);
    save(img, dir, "hw3_half_texel.png");
}

int main(int argc, char **argv) {
    const char *dir = argc > 1 ? argv[1] : "docs/img";
    ras_error err = {{0}};
    ras_scene *scene = ras_builtin_scene_load("hw3_default", &err);
    ras_scene_assets *assets = scene ? ras_scene_load_assets(scene, &err) : NULL;
    if (!assets) {
        fprintf(stderr, "hw3_figures: %s\n", err.msg);
        return EXIT_FAILURE;
    }
    hw3_render_options opt = hw3_render_defaults();

    /* the five shaders, half size */
    scene->width = scene->height = 350;
    for (int s = RAS_SHADER_NORMAL; s < RAS_SHADER_COUNT; s++) {
        opt.shader = (ras_scene_shader)s;
        char name[64];
        snprintf(name, sizeof name, "hw3_%s.png", ras_scene_shader_name(opt.shader));
        save(render(scene, assets, opt), dir, name);
    }
    scene->width = scene->height = 700;

    /* the w = 1 pitfall: the bottom half (the floor), correct | affine */
    opt.shader = RAS_SHADER_TEXTURE;
    ras_image *correct = render(scene, assets, opt);
    opt.affine = true;
    ras_image *affine = render(scene, assets, opt);
    opt.affine = false;
    ras_image *pit = row_of(2, 700, 300);
    blit(pit, 0, 0, correct, 0, 400, 700, 300, 1);
    blit(pit, 704, 0, affine, 0, 400, 700, 300, 1);
    save(pit, dir, "hw3_w1_pitfall.png");

    ras_image_destroy(correct);
    ras_image_destroy(affine);

    /* filters on the far floor (minified), magnified 2×; the lights are made
     * six times brighter so the distant floor is not too dark to see */
    for (int i = 0; i < scene->light_count; i++)
        scene->lights[i].intensity = glms_vec3_scale(scene->lights[i].intensity, 6);
    /* a fine checker (4 texels a square) on the floor: far away, many texels
     * fall into one pixel, which is where the three filters differ */
    ras_texture *fine = ras_texture_create_checker(256, 64, (vec3s){{0.9f, 0.9f, 0.9f}},
                                                   (vec3s){{0.1f, 0.15f, 0.3f}});
    if (!fine) return EXIT_FAILURE;
    fine->wrap = RAS_WRAP_REPEAT;
    assets->textures[scene->object_count - 1] = fine; /* the floor's */
    ras_image *filters = row_of(3, 300, 150);
    const texture_filter fs[3] = {FILTER_NEAREST, FILTER_BILINEAR, FILTER_TRILINEAR};
    for (int k = 0; k < 3; k++) {
        opt.filter = fs[k];
        ras_image *img = render(scene, assets, opt);
        blit(filters, k * 304, 0, img, 200, 412, 150, 75, 2);
        ras_image_destroy(img);
    }
    save(filters, dir, "hw3_filters.png");
    ras_texture_destroy(fine);
    half_texel(dir);
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(scene);
    return 0;
}
