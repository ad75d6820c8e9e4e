/* main.c — hw1_transform: a triangle, rotated and projected, as a wireframe.
 *
 * Built twice from this file: hw1_transform (your transform.c) and
 * hw1_transform_ref (the reference solution). The frame loop is the pipeline:
 * model (get_model_matrix or get_rotation) · view · projection → clip →
 * divide → viewport → lines.
 *
 *   hw1_transform                  window: a/d rotate by ±10°, v: yours /
 *                                  reference / difference, Esc quits
 *   hw1_transform -r 20 -o out.png render once, headless
 *   hw1_transform -r 20 out.png    the classic positional form
 *   hw1_transform --axis 0,1,0 -r 30 -o out.png   bonus: rotation about any axis
 *   hw1_transform --scene scenes/hw1_classic.json -o out.png
 *
 * The scene (camera, objects, size, starting angle) comes from --scene FILE or,
 * without it, from the built-in copy of scenes/hw1_classic.json; -r, --axis
 * and --size override it. hw1 has no rasterizer yet: every scene is drawn as
 * a wireframe, each object in its material colour. Everything else (options,
 * the window, --stats, and the frame around configure() and draw(): the
 * pipeline made, cleared, resolved into the PNG) is the shell's:
 * common/app/ras_app.h.
 */
#include "ras_app.h"
#include "ras_dump.h"
#include "transform.h"

#include <stdio.h> /* snprintf */

/* The program's rotation: get_model_matrix (about z) or, with an axis, the
 * bonus get_rotation. The scene inserts it after each object's own rotations
 * (ras_scene_model_matrix), so each object turns about its own origin. */
static mat4s spin_matrix(const ras_app_settings *s) {
    return s->axis_set ? get_rotation(s->axis, s->angle) : get_model_matrix(s->angle);
}

/* What the frame is drawn with: lines only (hw1 has no rasterizer yet). */
static bool configure(ras_app *app, ras_pipeline_config *cfg, ras_error *err) {
    (void)err;
    *cfg = (ras_pipeline_config){.width = app->set.width,
                                 .height = app->set.height,
                                 .clear_color = app->scene->clear_color,
                                 .z_far = app->scene->camera.z_far,
                                 .wireframe = true,
                                 .wire_color = {{1, 1, 1}}};
    return true;
}

/* What it draws: each object's model · view · projection, as lines in the
 * object's colour. */
static bool draw(ras_app *app, ras_pipeline *p, ras_error *err) {
    const ras_scene *s = app->scene;
    mat4s projection = get_projection_matrix(
        s->camera.fov_deg, (float)app->set.width / (float)app->set.height, s->camera.z_near,
        s->camera.z_far);
    mat4s view = ras_scene_view_matrix(s), spin = spin_matrix(&app->set);
    for (int i = 0; i < s->object_count; i++) {
        p->config.wire_color = s->objects[i].material.color;
        mat4s model = ras_scene_model_matrix(&s->objects[i], (ras_scene_spin){.matrix = &spin});
        if (!ras_pipeline_draw_mesh(p, app->assets->meshes[i], model, view, projection, err))
            return false;
        /* --dump: hw1's buffer is its vertices, at every step of the transform */
        char stem[32];
        snprintf(stem, sizeof stem, i ? "vertices_%d" : "vertices", i);
        if (app->cli.dump && !ras_dump_vertices(app->cli.dump, stem, app->assets->meshes[i], model,
                                                view, projection, app->set.width,
                                                app->set.height, err))
            return false;
    }
    return true;
}

static void status(const ras_app *app, char *buf, size_t size) {
    snprintf(buf, size, "angle %.0f deg   a/d: rotate   Esc: quit", app->set.angle);
}

int main(int argc, char **argv) {
    static const ras_app_hooks hooks = {
        .program = "hw1_transform", .student_sources = RAS_APP_STUDENT_SOURCES,
        .scene = "hw1_classic", .reference_dir = RAS_REFERENCE_DIR,
        .options = RAS_OPT_ANGLE | RAS_OPT_SCENE | RAS_OPT_STATS, .keys = RAS_APP_KEYS_ANGLE,
        .usage = "Draws the hw1 scene (default: the classic triangle) as a wireframe. With -o "
                 "it\nrenders once and writes a PNG; without it, a window opens (a/d rotate by "
                 "10\ndegrees, v: yours/reference/difference, Esc quits).\n"
                 "Classic form: hw1_transform -r ANGLE FILE.png\n",
        .example = "-r 20 -o out.png", .compare = RAS_COMPARE_EDGE_TOLERANT,
        .features = RAS_APP_LOAD_ASSETS | RAS_APP_WITHOUT_MAPS | RAS_APP_SPIN_FROM_SCENE,
        .configure = configure, .draw = draw, .status = status};
    return ras_app_main(argc, argv, &hooks, NULL);
}
