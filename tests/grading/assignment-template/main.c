/* main.c — hwX_template: hw1's scene drawn at half size, as a wireframe.
 *
 * Built twice from this file: hwX_template (your scale.c) and
 * hwX_template_ref (the reference solution). The frame loop is the pipeline:
 * model (each object's own, with get_scale_matrix inside it) · view ·
 * projection (hw1) → clip → divide → viewport → lines.
 *
 *   hwX_template -o out.png            render once, headless
 *   hwX_template --compare -o out.png  and compare with the reference image
 *
 * Everything else (options, the window, --stats, and the frame around
 * configure() and draw(): the pipeline made, cleared, resolved into the PNG)
 * is the shell's: common/app/ras_app.h. This is the template of docs/instructors.md, "Add an
 * assignment": replace the scale by the lesson's own step.
 */
#include "ras_app.h"
#include "scale.h"
#include "transform.h" /* hw1: get_projection_matrix */

#include <stdio.h> /* snprintf */

/* What the frame is drawn with: lines only (no rasterizer here). */
static bool configure(ras_app *app, ras_pipeline_config *cfg, ras_error *err) {
    (void)err;
    *cfg = (ras_pipeline_config){.width = app->set.width,
                                 .height = app->set.height,
                                 .clear_color = app->scene->clear_color,
                                 .wireframe = true};
    return true;
}

/* What it draws: each object scaled about its own origin, then view and
 * projection (hw1), as lines in the object's colour. */
static bool draw(ras_app *app, ras_pipeline *p, ras_error *err) {
    const ras_scene *s = app->scene;
    float aspect = (float)app->set.width / (float)app->set.height;
    mat4s scale = get_scale_matrix(0.5f), view = ras_scene_view_matrix(s);
    mat4s projection =
        get_projection_matrix(s->camera.fov_deg, aspect, s->camera.z_near, s->camera.z_far);
    for (int i = 0; i < s->object_count; i++) {
        p->config.wire_color = s->objects[i].material.color;
        mat4s model = ras_scene_model_matrix(&s->objects[i], (ras_scene_spin){.matrix = &scale});
        if (!ras_pipeline_draw_mesh(p, app->assets->meshes[i], model, view, projection, err))
            return false;
    }
    return true;
}

static void status(const ras_app *app, char *buf, size_t size) {
    (void)app;
    snprintf(buf, size, "half size   Esc: quit");
}

int main(int argc, char **argv) {
    static const ras_app_hooks hooks = {
        .program = "hwX_template",
        .scene = "hw1_classic",
        .reference_dir = RAS_REFERENCE_DIR,
        .options = RAS_OPT_COMPARE | RAS_OPT_SCENE | RAS_OPT_STATS,
        .usage = "Draws the hw1 scene at half size as a wireframe. With -o it renders once and\n"
                 "writes a PNG; without it, a window opens (v: yours/reference/difference, Esc\n"
                 "quits).\n",
        .example = "-o out.png",
        .compare = RAS_COMPARE_EDGE_TOLERANT,
        .features = RAS_APP_LOAD_ASSETS,
        .configure = configure,
        .draw = draw,
        .status = status};
    return ras_app_main(argc, argv, &hooks, NULL);
}
