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
 * Everything else (options, the window, --stats) is the shell's:
 * common/ras_app.h. This is the template of docs/instructors.md, "Add an
 * assignment": replace the scale by the lesson's own step.
 */
#include "ras_app.h"
#include "scale.h"
#include "transform.h" /* hw1: get_projection_matrix */

#include <stdio.h> /* snprintf */

/* The frame: each object scaled about its own origin, then view and
 * projection, drawn as lines in the object's colour. */
static bool render(ras_app *app, ras_error *err) {
    const ras_scene *s = app->scene;
    if (!app->pipeline) {
        ras_pipeline_config cfg = {.width = app->set.width,
                                   .height = app->set.height,
                                   .clear_color = s->clear_color,
                                   .wireframe = true,
                                   .wire_color = {{1, 1, 1}}};
        if (!(app->pipeline = ras_pipeline_create(&cfg, err))) return false;
    }
    ras_pipeline_begin_frame(app->pipeline);
    mat4s projection =
        get_projection_matrix(s->camera.fov_deg, (float)app->set.width / (float)app->set.height,
                              s->camera.z_near, s->camera.z_far);
    mat4s view = ras_scene_view_matrix(s), scale = get_scale_matrix(0.5f);
    for (int i = 0; i < s->object_count; i++) {
        app->pipeline->config.wire_color = s->objects[i].material.color;
        mat4s model = ras_scene_model_matrix(&s->objects[i], scale);
        if (!ras_pipeline_draw_mesh(app->pipeline, app->assets->meshes[i], model, view, projection,
                                    err))
            return false;
    }
    ras_pipeline_end_frame(app->pipeline, app->image);
    app->counters = &app->pipeline->counters;
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
        .load_assets = true,
        .render = render,
        .status = status};
    return ras_app_main(argc, argv, &hooks, NULL);
}
