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
 * a wireframe, each object in its material colour.
 */
#include "ras_builtin_scenes.h"
#include "ras_cli.h"
#include "ras_pipeline.h"
#include "ras_viewer.h"
#include "ras_window.h"
#include "transform.h"

#include <stdio.h>
#include <stdlib.h>

#define ACCEPTED (RAS_OPT_ANGLE | RAS_OPT_SCENE | RAS_OPT_STATS)
#define PROGRAM "hw1_transform"

typedef struct app {
    ras_cli cli;
    ras_scene *scene;
    ras_scene_assets *assets;
    bool axis_set; /* --axis, or the scene's model_rotation.axis */
    vec3s axis;
    ras_pipeline *pipeline;
    ras_image *image;
} app;

/* The program's rotation: get_model_matrix (about z) or, with an axis, the
 * bonus get_rotation. The scene inserts it after each object's own rotations
 * (ras_scene_model_matrix), so each object turns about its own origin. */
static mat4s spin_matrix(const app *a, float angle) {
    return a->axis_set ? get_rotation(a->axis, angle) : get_model_matrix(angle);
}

static bool render(app *a, float angle, ras_error *err) {
    const ras_scene *s = a->scene;
    ras_pipeline_begin_frame(a->pipeline);
    mat4s projection =
        get_projection_matrix(s->camera.fov_deg, (float)a->image->width / (float)a->image->height,
                              s->camera.z_near, s->camera.z_far);
    mat4s view = ras_scene_view_matrix(s), spin = spin_matrix(a, angle);
    for (int i = 0; i < s->object_count; i++) {
        a->pipeline->config.wire_color = s->objects[i].material.color;
        if (!ras_pipeline_draw_mesh(a->pipeline, a->assets->meshes[i],
                                    ras_scene_model_matrix(&s->objects[i], spin), view, projection,
                                    err))
            return false;
    }
    ras_pipeline_end_frame(a->pipeline, a->image);
    return true;
}

/* The reference image for these settings: hw1_r<angle>, or hw1_axis_y<angle>
 * for the y axis (tests/reference/, scripts/reference-images). */
static const char *reference_name(const app *a, float angle, char *buf, size_t size) {
    if (!(angle > -1e6f && angle < 1e6f)) return NULL; /* (int) of a huge angle is UB */
    int deg = (int)angle;
    if ((float)deg != angle) return NULL;
    if (a->cli.scene) return NULL; /* the references show the classic scene */
    if (!a->axis_set)
        snprintf(buf, size, "hw1_r%d", deg);
    else if (a->axis.x == 0 && a->axis.y > 0 && a->axis.z == 0)
        snprintf(buf, size, "hw1_axis_y%d", deg);
    else return NULL;
    return buf;
}

static int run_window(app *a, float angle, const char *argv0) {
    ras_error err;
    const char *title = "hw1_transform";
    ras_viewer viewer;
    ras_viewer_init(&viewer, title, argv0, RAS_REFERENCE_DIR, RAS_COMPARE_EDGE_TOLERANT);
    bool dirty = true;
    for (;;) {
        if (dirty) {
            ras_viewer_frame_begin(&viewer);
            if (!render(a, angle, &err)) break;
            ras_viewer_frame_end(&viewer);
            char name[64];
            ras_viewer_set_reference(&viewer, reference_name(a, angle, name, sizeof name),
                                     a->image->width, a->image->height);
        }
        char status[128];
        snprintf(status, sizeof status, "angle %.0f deg   a/d: rotate   Esc: quit", angle);
        if (!ras_viewer_show(&viewer, a->image, status, &err)) break;
        int key = ras_window_wait_key(title, 0);
        if (key == RAS_KEY_ESC || key == 'q' || key == -2) {
            ras_window_close(title);
            ras_viewer_release(&viewer);
            return 0;
        }
        dirty = key == 'a' || key == 'd';
        if (key == 'a') angle += 10;
        if (key == 'd') angle -= 10;
        ras_viewer_key(&viewer, key);
    }
    ras_viewer_release(&viewer);
    fprintf(stderr, "hw1_transform: %s\n", err.msg);
    return 1;
}

int main(int argc, char **argv) {
    ras_cli_reuse_freed_memory(); /* fewer page faults: docs/startup.md */
    app a = {0};
    ras_error err = {{0}};
    switch (ras_cli_parse(argc, argv, ACCEPTED, &a.cli, &err)) {
    case RAS_CLI_HELP: {
        char help[4096];
        ras_cli_help(
            ACCEPTED, "hw1_transform",
            "Draws the hw1 scene (default: the classic triangle) as a wireframe. With -o it\n"
            "renders once and writes a PNG; without it, a window opens (a/d rotate by 10\n"
            "degrees, v: yours/reference/difference, Esc quits).\n"
            "Classic form: hw1_transform -r ANGLE FILE.png\n",
            help, sizeof help);
        fputs(help, stdout);
        return 0;
    }
    case RAS_CLI_VERSION: printf("hw1_transform (Raster101) %s\n", RAS_VERSION); return 0;
    case RAS_CLI_ERROR: fprintf(stderr, "hw1_transform: %s\n", err.msg); return 2;
    case RAS_CLI_RUN: break;
    }
    /* The classic positional form: `-r ANGLE FILE.png`. */
    if (!a.cli.output && a.cli.positional_count == 1) a.cli.output = a.cli.positional[0];
    else if (a.cli.positional_count > 0) {
        fprintf(stderr,
                "hw1_transform: unexpected argument '%s'; expected at most one output file "
                "(e.g. hw1_transform -r 20 out.png)\n",
                a.cli.positional[a.cli.positional_count - 1]);
        return 2;
    }
    /* A file that cannot be written is a usage error: say so before any work. */
    if (a.cli.output && !ras_image_check_output(a.cli.output, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        return 2;
    }
    if (!a.cli.output && !ras_window_available()) {
        fprintf(stderr, "hw1_transform: no display to open a window on (DISPLAY is not set); "
                        "render to a file instead, e.g. hw1_transform -r 20 -o out.png\n");
        return 2;
    }
    /* The scene first: a scene that does not load draws nothing (exit 2). */
    a.scene = ras_scene_load_or_builtin(a.cli.scene, "hw1_classic", &err);
    a.assets = a.scene ? ras_scene_load_assets(a.scene, &err) : NULL;
    if (!a.assets) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        ras_scene_destroy(a.scene);
        return 2;
    }
    /* Command-line flags override the scene. */
    float angle = a.cli.angle_set ? a.cli.angle : a.scene->model_rotation_deg;
    a.axis_set = a.cli.axis_set || a.scene->model_rotation_axis_set;
    a.axis = a.cli.axis_set ? a.cli.axis : a.scene->model_rotation_axis;
    int width = a.cli.width ? a.cli.width : a.scene->width;
    int height = a.cli.height ? a.cli.height : a.scene->height;
    ras_pipeline_config cfg = {.width = width,
                               .height = height,
                               .clear_color = a.scene->clear_color,
                               .wireframe = true,
                               .wire_color = {{1, 1, 1}}};
    /* Too big a frame for the memory budget is a usage error (exit 2), as in
     * hw2 and hw3; running out of memory anyway is a failed render (1). */
    bool fits = ras_framebuffer_check_size(width, height, 1, &err);
    a.pipeline = fits ? ras_pipeline_create(&cfg, &err) : NULL;
    a.image = a.pipeline ? ras_image_create(width, height, &err) : NULL;
    int status = 0;
    if (!a.pipeline || !a.image) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        status = fits ? 1 : 2;
    } else if (a.cli.output) {
        if (!render(&a, angle, &err) || !ras_image_save(a.image, a.cli.output, &err)) {
            fprintf(stderr, "hw1_transform: %s\n", err.msg);
            status = 1;
        } else {
            if (a.cli.stats) {
                char json[2048];
                ras_counters_format_json(&a.pipeline->counters, json, sizeof json);
                puts(json);
            }
            fprintf(stderr, "wrote %s\n", a.cli.output);
        }
    } else {
        status = run_window(&a, angle, argv[0]);
    }
    ras_image_destroy(a.image);
    ras_pipeline_destroy(a.pipeline);
    ras_scene_assets_destroy(a.assets);
    ras_scene_destroy(a.scene);
    return status;
}
