/* main.c — hw3_shading: the shaded scene, in a window or as a PNG.
 *
 * Given code, no TODO. Read configure() and draw() (one frame: what it is
 * drawn with, what it draws) and key()/status() (the window's keys) if you
 * want to know what the program does with your shaders; the rest is the
 * shell's plumbing. Leave it as it is: your work is shading.c, the one hw3
 * file the grader takes from a submission, so a change here is not graded.
 *
 * Built twice from this file: hw3_shading (your shading.c, with your hw2
 * rasterizer and hw1 projection) and hw3_shading_ref (the reference; the
 * student edition has none, only its pictures in tests/reference/). The
 * frame is the pipeline: model · view · projection → clip → divide →
 * viewport → rasterize_triangle (hw2) → hw3_shade_fragment (scene.c:
 * interpolate the varyings the shader reads, perspective-correct) → your
 * fragment shader → resolve_pixel (hw2, with AA) → image.
 *
 * The scene comes from --scene FILE, the built-in scenes/hw3_default.json, or
 * --model FILE (put into the built-in scenes/hw3_model.json, the classic
 * GAMES101 scene); the options override it. The shell (common/app/ras_app.h)
 * loads it and its meshes and textures, and does the rest (options, the
 * window, --compare, --stats, and the frame around configure() and draw():
 * the pipeline made, cleared, resolved into the PNG).
 * Examples: docs/hw3.md, or hw3_shading --help.
 */
#include "ras_app.h"
#include "scene.h"

#include <stdio.h>  /* fprintf, snprintf */

typedef struct hw3 {
    hw3_render_options opt; /* the settings, as the frame's options */
    hw3_frame frame;        /* its fragment stage: the pipeline's shade hook calls it */
    hw3_gbuffer gbuffer;    /* what the stage handed each pixel (--dump, the buffer view) */
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
    /* hw3's frame is the scene's size (hw3_frame_setup's aspect,
     * hw3_frame_config's pipeline): --size (the settings) replaces the
     * file's. The settings were resolved already, so this changes no rule. */
    app->scene->width = app->set.width;
    app->scene->height = app->set.height;
    /* The mip levels trilinear texturing will build, against the budget now:
     * a run that cannot hold them is refused as bad input (exit 2) before
     * anything is drawn. (The first frame builds them.) */
    if (app->set.filter == RAS_FILTER_TRILINEAR && app->set.shader == RAS_SHADER_TEXTURE)
        return ras_scene_assets_check_mips(app->scene, app->assets, err);
    return true;
}

/* What the frame is drawn with: the settings as render options, the
 * fragment stage (your shader, the varyings it reads, the lights in view
 * space), the pipeline that calls it, and the stage's buffers when the frame
 * keeps them (--dump, the window's step and buffer views). */
static bool configure(ras_app *app, ras_pipeline_config *cfg, ras_error *err) {
    hw3 *h = app->user;
    h->opt = hw3_app_render_options(app);
    if (!hw3_frame_setup(app->scene, app->assets, &h->opt, &h->frame, err)) return false;
    *cfg = hw3_frame_config(app->scene, &h->opt, &h->frame.stage);
    return hw3_frame_buffers(&h->frame, cfg, &h->gbuffer, err);
}

/* What it draws: every object, with its material, through your rasterizer
 * into your shader. */
static bool draw(ras_app *app, ras_pipeline *p, ras_error *err) {
    hw3 *h = app->user;
    return hw3_frame_draw(app->scene, app->assets, h->opt.angle_deg, &h->frame, p, err);
}

/* --dump: the fragment stage's buffers, after the pipeline's. */
static bool dump(const ras_app *app, const char *dir, ras_error *err) {
    return hw3_gbuffer_dump(&((const hw3 *)app->user)->gbuffer, dir, err);
}

/* The buffer view's normal and uv: the last frame's fragment buffers. */
static bool buffer(const ras_app *app, const char *name, ras_dump_buffer *out) {
    return hw3_gbuffer_view(&((const hw3 *)app->user)->gbuffer, name, out);
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

static void release(ras_app *app) {
    hw3 *h = app->user;
    hw3_gbuffer_release(&h->gbuffer);
}

int main(int argc, char **argv) {
    static const ras_app_hooks hooks = {
        .program = "hw3_shading",
        .student_sources = RAS_APP_STUDENT_SOURCES,
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
        .scene = "hw3_default", .model_scene = "hw3_model", .load_assets = true,
        .positional_shader = true, .compare = RAS_COMPARE_PSNR,
        .example = "--shader phong -o out.png", .reference_dir = RAS_REFERENCE_DIR,
        .keys = RAS_APP_KEYS_ANGLE | RAS_APP_KEYS_SHADING,
        .step = true,
        .prepare = prepare, .configure = configure, .draw = draw, .dump = dump, .key = key,
        .mouse = mouse, .status = status, .release = release, .buffer = buffer};
    hw3 h = {.last_col = -1};
    return ras_app_main(argc, argv, &hooks, &h);
}
