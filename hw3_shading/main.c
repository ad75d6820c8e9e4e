/* main.c — hw3_shading: the shaded scene, in a window or as a PNG.
 *
 * Given code, no TODO: leave it as it is (the grader takes only shading.c).
 * One frame is configure() (the pipeline: your hw2 rasterizer, your
 * interpolate_*, your shader, scene.h) and draw() (every object through it);
 * key(), mouse() and status() are the window's. The shell (common/app/
 * ras_app.h) does the rest: options, the window, --compare, --dump, --stats.
 * Built twice: hw3_shading (your shading.c, hw2 rasterizer, hw1 projection)
 * and hw3_shading_ref (the reference). The scene: --scene FILE, the built-in
 * scenes/hw3_default.json, or --model FILE in scenes/hw3_model.json.
 */
#include "ras_app.h"
#include "scene.h"

#include <stdio.h>  /* fprintf, snprintf */

typedef struct hw3 {
    hw3_render_options opt; /* the settings, as the frame's options */
    hw3_frame frame;        /* your shader, its lights and materials: the pipeline's */
    int last_col;           /* the mouse's column, -1 before it moved */
} hw3;

/* Notes once the scene has loaded. */
static bool prepare(ras_app *app, ras_error *err) {
    const ras_cli *cli = &app->cli;
    if (app->set.shader == RAS_SHADER_FLAT) {
        app->set.shader = RAS_SHADER_NORMAL;
        fprintf(stderr, "hw3_shading: note: the scene's shader \"flat\" is hw2's unlit colour; "
                        "drawing with normal (choose with --shader)\n");
    }
    bool maps = app->set.shader >= RAS_SHADER_TEXTURE;
    if (cli->model && maps && !app->assets->meshes[0]->has_uv)
        fprintf(stderr, "hw3_shading: note: %s has no texture coordinates; the %s shader reads "
                        "one texel everywhere\n", cli->model, ras_scene_shader_name(app->set.shader));
    /* hw3's frame is the scene's size: --size (the settings) replaces the file's. */
    app->scene->width = app->set.width, app->scene->height = app->set.height;
    /* The mip levels trilinear texturing will build, against the budget now:
     * refused as bad input (exit 2) before anything is drawn. */
    if (app->set.filter == RAS_FILTER_TRILINEAR && app->set.shader == RAS_SHADER_TEXTURE)
        return ras_scene_assets_check_mips(app->scene, app->assets, err);
    return true;
}

/* What the frame is drawn with: the pipeline with your rasterizer, your
 * interpolation and your shader (with its lights, in view space). */
static bool configure(ras_app *app, ras_pipeline_config *cfg, ras_error *err) {
    hw3 *h = app->user;
    h->opt = hw3_app_render_options(app);
    if (!hw3_frame_setup(app->scene, app->assets, &h->opt, &h->frame, err)) return false;
    *cfg = hw3_frame_config(app->scene, &h->opt, &h->frame);
    return true;
}

/* What it draws: every object, with its material, through your rasterizer
 * into your shader. */
static bool draw(ras_app *app, ras_pipeline *p, ras_error *err) {
    hw3 *h = app->user;
    return hw3_frame_draw(app->scene, app->assets, h->opt.angle_deg, &h->frame, p, err);
}

/* p: the w = 1 pitfall (affine interpolation) on and off. */
static bool key(ras_app *app, int k) {
    if (k != 'p') return false;
    app->set.affine = !app->set.affine;
    return true;
}

/* The mouse's column turns the model: the full width is one turn. */
static bool mouse(ras_app *app, int col, int row) {
    hw3 *h = app->user;
    (void)row;
    if (app->step.on) { /* in step mode the mouse inspects: it does not turn */
        h->last_col = col;
        return false;
    }
    bool turned = h->last_col >= 0 && col != h->last_col;
    if (turned) app->set.angle += 360.0f * (float)(col - h->last_col) / (float)app->set.width;
    h->last_col = col;
    return turned;
}

static void status(const ras_app *app, char *buf, size_t size) {
    snprintf(buf, size, "%s  filter %s  %s  angle %.0f\n%s",
             ras_scene_shader_name(app->set.shader), ras_scene_filter_name(app->set.filter),
             app->set.affine ? "AFFINE (w=1 pitfall)" : "persp-correct", app->set.angle,
             app->step.on ? "f filter  p persp  a/d rotate  (1-5 shader: after t)"
                          : "1-5 shader  f filter  p persp  a/d rotate  t step  b buffer");
}

int main(int argc, char **argv) {
    static const ras_app_hooks hooks = {
        .program = "hw3_shading", .student_sources = RAS_APP_STUDENT_SOURCES,
        .usage =
            "Shades the hw3 scene with one of the five fragment shaders. With -o it renders\n"
            "once and writes a PNG; without it, a window opens (1-5: shader, f: filter,\n"
            "p: perspective-correct on/off, a/d or mouse: rotate, v: yours/reference/\n"
            "difference, Esc quits).\n"
            "Step view: t steps the frame one triangle at a time (n or space +1, - back,\n"
            "  1-9 +1, 10, 100, ... triangles, 0 none; the digits pick shaders again after\n"
            "  t), b cycles the buffer shown (colour, depth, coverage with AA, overdraw,\n"
            "  normal, uv); in step mode the mouse inspects the pixel (the last triangle's\n"
            "  edge functions, barycentrics and depth) instead of turning the model.\n"
            "Default scene: scenes/hw3_default.json (built in): a sphere, torus, cube and\n"
            "  teapot on a floor, no files needed; --scene FILE draws another.\n"
            "Classic form: hw3_shading OUTPUT.png [normal|phong|texture|bump|displacement]\n"
            "Classic model scene (GAMES101 numbers): --model spot_triangulated_good.obj\n"
            "  --texture spot_texture.png --shader texture  (bump/displacement read --height,\n"
            "  or the --texture image as the course does with hmap.jpg)\n"
            "--compare writes the difference beside -o FILE (FILE_diff.png), or without -o\n"
            "  as <reference>_diff.png in the current folder.\n",
        .options = RAS_OPT_SHADING | RAS_OPT_MODEL | RAS_OPT_AA | RAS_OPT_SCENE | RAS_OPT_STATS |
                   RAS_OPT_COMPARE,
        .scene = "hw3_default", .model_scene = "hw3_model", .compare = RAS_COMPARE_PSNR,
        .features = RAS_APP_LOAD_ASSETS | RAS_APP_POSITIONAL_SHADER | RAS_APP_STEP,
        .example = "--shader phong -o out.png", .reference_dir = RAS_REFERENCE_DIR,
        .keys = RAS_APP_KEYS_ANGLE | RAS_APP_KEYS_SHADING, .prepare = prepare,
        .configure = configure, .draw = draw, .key = key, .mouse = mouse, .status = status};
    hw3 h = {.last_col = -1};
    return ras_app_main(argc, argv, &hooks, &h);
}
