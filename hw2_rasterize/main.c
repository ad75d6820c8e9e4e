/* main.c — hw2_rasterize: the classic two triangles, filled, depth-tested and
 * anti-aliased by your rasterizer.
 *
 * Built twice from this file: hw2_rasterize (your rasterizer.c, and your hw1
 * matrices) and hw2_rasterize_ref (the reference solutions). The frame loop is
 * the pipeline: model (identity) · view · projection → clip → divide →
 * viewport → rasterize_triangle (coverage, depth) → resolve_pixel → image.
 *
 *   hw2_rasterize                          window: m AA mode, s samples, p pattern,
 *                                          v yours / reference / difference, t step
 *                                          (n, 1-9), b buffer; the pixel under the
 *                                          mouse magnified with its samples
 *   hw2_rasterize -o out.png               render once, headless
 *   hw2_rasterize --aa msaa --samples 4 -o out.png
 *   hw2_rasterize --aa msaa --compare      compare with tests/reference/hw2_msaa4.png
 *   hw2_rasterize --stats -o out.png       what each stage did, as JSON on stdout
 *   hw2_rasterize --scene scenes/msaa_thin_triangles.json -o fan.png
 *
 * The scene: --scene FILE or the built-in scenes/hw2_classic.json; the
 * options override it. hw2 draws flat colours (material × vertex colour).
 * One frame is configure() and draw(); the rest (options, the window and its
 * inspector, --compare, --dump, --stats, the frame around the two) is the
 * shell's: common/app/ras_app.h.
 */
#include "ras_app.h"
#include "rasterizer.h"
#include "transform.h"

#include <stdio.h> /* fprintf, snprintf */

static bool prepare(ras_app *app, ras_error *err) {
    (void)err;
    if (app->scene->shader != RAS_SHADER_FLAT)
        fprintf(stderr, "hw2_rasterize: note: hw2 draws flat colours; the scene's \"%s\" shader "
                        "is hw3's (hw3_shading --scene)\n",
                ras_scene_shader_name(app->scene->shader));
    return true;
}

/* The scene's model_rotation with hw1's matrices (hw2 has no angle option);
 * 0 degrees is exactly the identity, whatever hw1 returns. */
static mat4s spin_matrix(const ras_app_settings *s) {
    if (s->angle == 0) return glms_mat4_identity();
    return s->axis_set ? get_rotation(s->axis, s->angle) : get_model_matrix(s->angle);
}

/* What the frame is drawn with: your rasterizer and resolve, the AA
 * settings (the shell adds --dump's and the step view's own). */
static bool configure(ras_app *app, ras_pipeline_config *cfg, ras_error *err) {
    (void)err;
    const ras_scene *s = app->scene;
    const ras_app_settings *set = &app->set;
    *cfg = (ras_pipeline_config){.width = set->width,
                                 .height = set->height,
                                 .clear_color = s->clear_color,
                                 .cull = s->cull,
                                 .aa = set->aa,
                                 .pattern = ras_app_settings_pattern(set),
                                 .depth = set->depth,
                                 .z_near = s->camera.z_near,
                                 .z_far = s->camera.z_far,
                                 .varyings = RAS_VARYING_COLOR,
                                 .rasterize = rasterize_triangle,
                                 .resolve = resolve_pixel};
    return true;
}

/* What it draws: each object's model · view · projection through
 * rasterize_triangle (the shell resolves the samples with resolve_pixel). */
static bool draw(ras_app *app, ras_pipeline *p, ras_error *err) {
    const ras_scene *s = app->scene;
    const ras_app_settings *set = &app->set;
    mat4s view = ras_scene_view_matrix(s), spin = spin_matrix(set);
    float aspect = (float)set->width / (float)set->height;
    mat4s projection =
        get_projection_matrix(s->camera.fov_deg, aspect, s->camera.z_near, s->camera.z_far);
    for (int i = 0; i < s->object_count; i++)
        if (!ras_pipeline_draw_mesh(
                p, app->assets->meshes[i],
                ras_scene_model_matrix(&s->objects[i], (ras_scene_spin){.matrix = &spin}), view,
                projection, err))
            return false;
    return true;
}

static void status(const ras_app *app, char *buf, size_t size) {
    const ras_app_settings *s = &app->set;
    char mode[96] = "no AA";
    if (s->aa != RAS_AA_NONE)
        snprintf(mode, sizeof mode, "%s %dx %s", ras_aa_mode_name(s->aa), s->samples,
                 ras_pattern_kind_name(s->pattern_kind));
    snprintf(buf, size, "%s\nm aa  s samples  p pattern  t step  b buffer  Esc", mode);
}

int main(int argc, char **argv) {
    static const ras_app_hooks hooks = {
        .program = "hw2_rasterize",
        .student_sources = RAS_APP_STUDENT_SOURCES,
        .usage = "Draws the hw2 scene (default: the two classic triangles) with your "
                 "rasterizer\n(coverage, z-buffer, anti-aliasing).\nWith -o or --compare it "
                 "renders once, headless; without, a window opens:\n  m AA mode, s sample "
                 "count, p sample pattern,\n  v your picture / the reference "
                 "/ the difference, Esc quits;\n  the pixel under the mouse is magnified with "
                 "its samples and their depths.\nStep view: t steps the frame one triangle at a "
                 "time (n or space +1, - one back,\n  1-9 +1, 10, 100, ... triangles, 0 none), b "
                 "cycles the buffer shown (colour,\n  depth, coverage with AA, overdraw); the "
                 "inspector then also shows the last\n  triangle's edge functions, barycentrics "
                 "and depth at the pixel.\n--compare writes the difference beside -o "
                 "FILE (FILE_diff.png), or without\n  -o as <reference>_diff.png in the current "
                 "folder.\n",
        .options = RAS_OPT_AA | RAS_OPT_COMPARE | RAS_OPT_SCENE | RAS_OPT_STATS,
        .keys = RAS_APP_KEYS_AA, .compare = RAS_COMPARE_EDGE_TOLERANT, .scene = "hw2_classic",
        .features = RAS_APP_LOAD_ASSETS | RAS_APP_WITHOUT_MAPS | RAS_APP_SPIN_FROM_SCENE |
                    RAS_APP_INSPECTOR | RAS_APP_STEP,
        .example = "--aa msaa -o out.png", .reference_dir = RAS_REFERENCE_DIR,
        .prepare = prepare, .configure = configure, .draw = draw, .status = status,
    };
    return ras_app_main(argc, argv, &hooks, NULL);
}
