/* main.c — hw3_shading: the shaded scene, in a window or as a PNG.
 *
 * Built twice from this file: hw3_shading (your shading.c, with your hw2
 * rasterizer and hw1 projection) and hw3_shading_ref (the reference). The
 * frame (scene.c, hw3_render) is the pipeline: model · view · projection →
 * clip → divide → viewport → rasterize_triangle (hw2) → hw3_shade_fragment
 * (interpolate the varyings the shader reads, perspective-correct) → your
 * fragment shader → resolve_pixel (hw2, with AA) → image.
 *
 *   hw3_shading                               window: 1-5 shader, f filter,
 *                                             p perspective-correct on/off,
 *                                             a/d or the mouse rotate, v: yours /
 *                                             reference / difference, Esc quits
 *   hw3_shading --shader phong -o out.png     render once, headless
 *   hw3_shading out.png phong                 the classic positional form
 *   hw3_shading --model spot.obj --texture spot_texture.png --shader texture -o spot.png
 *   hw3_shading --scene scenes/textured_teapot_trilinear.json -o teapot.png
 *
 * The scene comes from --scene FILE or, without it, from the built-in copy of
 * scenes/hw3_default.json (or, with --model, the classic GAMES101 model
 * scene); --shader, --filter, --aa, --samples, --pattern, --edges and --size
 * override the scene's values.
 */
#include "ras_builtin_scenes.h"
#include "ras_cli.h"
#include "ras_compare.h"
#include "ras_viewer.h"
#include "ras_window.h"
#include "scene.h"

#include <stdio.h>
#include <string.h>

#define ACCEPTED                                                                                   \
    (RAS_OPT_SHADING | RAS_OPT_MODEL | RAS_OPT_AA | RAS_OPT_SCENE | RAS_OPT_STATS |                \
     RAS_OPT_COMPARE | RAS_OPT_RENDERER)
#define PROGRAM "hw3_shading"

static const char usage[] =
    "Shades the hw3 scene with one of the five fragment shaders. With -o it renders\n"
    "once and writes a PNG; without it, a window opens (1-5: shader, f: filter,\n"
    "p: perspective-correct on/off, a/d or mouse: rotate, v: yours/reference/\n"
    "difference, Esc quits).\n"
    "Default scene: scenes/hw3_default.json (built in): a sphere, torus, cube and\n"
    "  teapot on a floor, no files needed; --scene FILE draws another.\n"
    "Classic form: hw3_shading OUTPUT.png [normal|phong|texture|bump|displacement]\n"
    "Classic model scene (GAMES101 numbers): --model spot_triangulated_good.obj\n"
    "  --texture spot_texture.png --shader texture  (bump/displacement read --height,\n"
    "  or the --texture image as the course does with hmap.jpg)\n"
    "--compare (with -o FILE) compares with tests/reference/hw3_<shader>.png and\n"
    "  writes FILE_diff.png beside FILE.\n"
    "--renderer: teaching (default); hw3_shading_ref also offers fast, the same\n"
    "  picture drawn in screen tiles on threads (docs/performance.md).\n";

typedef struct app {
    ras_cli cli;
    ras_scene *file_scene; /* the scene file (or the built-in one); NULL with --model */
    hw3_scene *scene;
    hw3_render_options opt;
    ras_image *image;
    ras_image *expected; /* --compare: the reference, loaded before rendering */
    ras_counters stats;
    const char *argv0;
} app;

/* --aa, --samples and --pattern over the scene's anti-aliasing (`rs`, NULL
 * with --model: none). */
static bool parse_aa(const ras_cli *cli, const ras_scene *rs, hw3_render_options *opt,
                     ras_error *err) {
    if (!cli->aa_set && !cli->samples && !cli->pattern_set) return true; /* the scene's */
    bool scene_aa = rs && rs->aa != RAS_AA_NONE;
    opt->aa = cli->aa_set ? cli->aa : rs ? rs->aa : RAS_AA_NONE;
    if (opt->aa == RAS_AA_NONE) {
        if (cli->samples > 1)
            return ras_error_set(err, "--samples %d needs --aa msaa or --aa ssaa", cli->samples);
        opt->pattern = ras_sample_pattern_center();
        return true;
    }
    ras_pattern_kind kind = cli->pattern_set ? cli->pattern
                            : scene_aa       ? rs->pattern_kind
                                             : RAS_PATTERN_ORDERED;
    int samples = cli->samples ? cli->samples : scene_aa ? rs->samples : 4;
    return ras_sample_pattern_make(kind, samples, &opt->pattern, err);
}

/* The reference image for --compare, loaded before anything is drawn so a
 * missing or mismatched one is a usage error (exit 2) that leaves no output
 * behind. NULL (message printed) when there is none; `path` names it. */
static ras_image *load_reference(const app *a, char *path, size_t size) {
    if (a->cli.reference) {
        snprintf(path, size, "%s", a->cli.reference);
    } else if (a->cli.model || a->cli.scene) {
        fprintf(stderr,
                PROGRAM ": --compare with --%s needs --reference FILE (the "
                        "reference images show the built-in scene)\n",
                a->cli.model ? "model" : "scene");
        return NULL;
    } else {
        snprintf(path, size, "%s/hw3_%s.png", RAS_REFERENCE_DIR,
                 hw3_shader_name(a->opt.shader));
    }
    ras_error err = {{0}};
    ras_image *expected = ras_image_load(path, &err);
    if (!expected) {
        fprintf(stderr, PROGRAM ": %s%s\n", a->cli.reference ? "--reference: " : "", err.msg);
        return NULL;
    }
    if (!ras_compare_reference_fits(expected, path, a->scene->width, a->scene->height, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        ras_image_destroy(expected);
        return NULL;
    }
    return expected;
}

static int compare_with_reference(app *a, const ras_image *expected, const char *ref) {
    ras_error err = {{0}};
    ras_compare_options copt = ras_compare_defaults(RAS_COMPARE_PSNR);
    ras_compare_result res;
    int status = 1;
    if (!ras_compare_images(expected, a->image, &copt, &res, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
    } else {
        printf("compare with %s: %s\n", ref, res.summary);
        status = res.pass ? 0 : 1;
        if (a->cli.output) {
            /* out.png → out_diff.png, as hw2 does */
            char diff[1100];
            const char *dot = strrchr(a->cli.output, '.');
            int stem = dot ? (int)(dot - a->cli.output) : (int)strlen(a->cli.output);
            snprintf(diff, sizeof diff, "%.*s_diff.png", stem, a->cli.output);
            ras_image *heat = ras_compare_heatmap(expected, a->image, RAS_COMPARE_PSNR, &err);
            if (heat && ras_image_save(heat, diff, &err)) printf("difference image: %s\n", diff);
            else
                fprintf(stderr, PROGRAM ": no difference image: %s\n", err.msg);
            ras_image_destroy(heat);
        }
    }
    return status;
}

static void window_status(const app *a, char *buf, size_t size) {
    snprintf(buf, size, "%s  filter %s  %s  angle %.0f\n1-5 shader  f filter  p persp  a/d rotate",
             hw3_shader_name(a->opt.shader), hw3_filter_name(a->opt.filter),
             a->opt.affine ? "AFFINE (w=1 pitfall)" : "persp-correct", a->opt.angle_deg);
}

/* tests/reference/hw3_<shader>.png is the default scene with default options. */
static const char *reference_name(const app *a, char *buf, size_t size) {
    hw3_render_options d = hw3_render_defaults();
    float turns = a->opt.angle_deg / 360.0f;
    if (!(turns > -1e6f && turns < 1e6f)) return NULL; /* (int) of a huge angle is UB */
    if (a->cli.model || a->cli.scene || a->cli.width || a->opt.filter != d.filter ||
        a->opt.aa != d.aa || a->opt.affine || turns != (float)(int)turns)
        return NULL;
    snprintf(buf, size, "hw3_%s", hw3_shader_name(a->opt.shader));
    return buf;
}

static int run_window(app *a) {
    ras_error err = {{0}};
    const char *title = PROGRAM;
    int last_col = -1;
    bool dirty = true, redraw = true;
    ras_viewer viewer;
    ras_viewer_init(&viewer, title, a->argv0, RAS_REFERENCE_DIR, RAS_COMPARE_EXACT);
    for (;;) {
        if (dirty) {
            ras_viewer_frame_begin(&viewer);
            if (!hw3_render(a->scene, &a->opt, a->image, &a->stats, &err)) break;
            ras_viewer_frame_end(&viewer);
            char name[64];
            ras_viewer_set_reference(&viewer, reference_name(a, name, sizeof name),
                                     a->image->width, a->image->height);
            dirty = false;
            redraw = true;
        }
        if (redraw) {
            char status[200];
            window_status(a, status, sizeof status);
            if (!ras_viewer_show(&viewer, a->image, status, &err)) break;
            redraw = false;
        }
        int key = ras_window_wait_key(title, 30);
        if (key == RAS_KEY_ESC || key == 'q' || key == -2) {
            ras_window_close(title);
            ras_viewer_release(&viewer);
            return 0;
        }
        if (ras_viewer_key(&viewer, key)) {
            redraw = true;
            continue;
        }
        if (key >= '1' && key < '1' + HW3_SHADER_COUNT) a->opt.shader = (hw3_shader)(key - '1');
        else if (key == 'f') a->opt.filter = (texture_filter)((a->opt.filter + 1) % 3);
        else if (key == 'p') a->opt.affine = !a->opt.affine;
        else if (key == 'a') a->opt.angle_deg += 10;
        else if (key == 'd') a->opt.angle_deg -= 10;
        if (key >= 0) dirty = true;
        /* The mouse's column turns the model: the full width is one turn. */
        int col, row;
        if (ras_window_mouse(title, &col, &row) && col != last_col) {
            if (last_col >= 0) {
                a->opt.angle_deg += 360.0f * (float)(col - last_col) / (float)a->image->width;
                dirty = true;
            }
            last_col = col;
        }
    }
    ras_viewer_release(&viewer);
    fprintf(stderr, PROGRAM ": %s\n", err.msg);
    return 1;
}

static int run(app *a) {
    ras_error err = {{0}};
    a->opt = hw3_render_defaults();
    if (a->cli.model && a->cli.scene) {
        fprintf(stderr, PROGRAM ": --model and --scene both name the scene; give one (a scene "
                                "file names its models itself)\n");
        return 2;
    }
    /* The scene first: a scene that does not load draws nothing (exit 2).
     * Its effects become the options; the command line overrides them below. */
    if (!a->cli.model) {
        a->file_scene = ras_scene_load_or_builtin(a->cli.scene, "hw3_default", &err);
        if (!a->file_scene) {
            fprintf(stderr, PROGRAM ": %s\n", err.msg);
            return 2;
        }
        a->opt = hw3_render_options_from_ras(a->file_scene);
    }
    /* The classic positional form: OUTPUT.png [SHADER]. */
    int npos = a->cli.positional_count;
    if (npos > 2 || (npos >= 1 && a->cli.output)) {
        fprintf(stderr,
                PROGRAM ": unexpected argument '%s'; expected OUTPUT.png [SHADER] "
                        "(e.g. hw3_shading out.png phong) or -o FILE --shader NAME\n",
                a->cli.positional[npos - 1]);
        return 2;
    }
    if (npos >= 1) a->cli.output = a->cli.positional[0];
    const char *shader = a->cli.shader ? a->cli.shader : npos == 2 ? a->cli.positional[1] : NULL;
    if (npos == 2 && a->cli.shader) {
        fprintf(stderr, PROGRAM ": the shader is given twice ('%s' and --shader %s)\n",
                a->cli.positional[1], a->cli.shader);
        return 2;
    }
    if ((shader && !hw3_shader_parse(shader, &a->opt.shader, &err)) ||
        (a->cli.filter && !hw3_filter_parse(a->cli.filter, &a->opt.filter, &err)) ||
        (a->cli.renderer && !hw3_renderer_parse(a->cli.renderer, &a->opt.renderer, &err)) ||
        !parse_aa(&a->cli, a->file_scene, &a->opt, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        return 2;
    }
    if (a->cli.edges_set) a->opt.edges = a->cli.edges;
    if (a->cli.depth_set) a->opt.depth = a->cli.depth;
    if (!a->cli.model && (a->cli.texture || a->cli.height_map || a->cli.fit)) {
        fprintf(stderr, PROGRAM ": --texture, --height and --fit go with --model FILE\n");
        return 2;
    }
    /* A file that cannot be written is a usage error: say so before any work. */
    if (a->cli.output && !ras_image_check_output(a->cli.output, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        return 2;
    }
    if (a->cli.compare && !a->cli.output) {
        fprintf(stderr, PROGRAM ": --compare needs -o FILE: it renders once, writes FILE and "
                                "its difference image beside it (e.g. hw3_shading --shader "
                                "phong --compare -o phong.png)\n");
        return 2;
    }
    if (!a->cli.output && !ras_window_available()) {
        fprintf(stderr, PROGRAM ": no display to open a window on (DISPLAY is not set); "
                        "render to a file instead, e.g. hw3_shading --shader phong -o out.png\n");
        return 2;
    }
    a->scene = a->cli.model ? hw3_scene_create_model(a->cli.model, a->cli.texture,
                                                     a->cli.height_map, a->cli.fit, &err)
                            : hw3_scene_from_ras(a->file_scene, &err);
    if (!a->scene) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        return 2; /* a model, texture or scene file that does not load is bad input */
    }
    /* Notes only once the scene has loaded: a failing run prints its error alone. */
    if (!shader && a->file_scene && a->file_scene->shader == RAS_SHADER_FLAT)
        fprintf(stderr,
                PROGRAM ": note: the scene's shader \"flat\" is hw2's unlit colour; "
                        "drawing with %s (choose with --shader)\n",
                hw3_shader_name(a->opt.shader));
    if (a->cli.model && !a->scene->objects[0].mesh->has_uv &&
        (a->opt.shader == HW3_SHADER_TEXTURE || a->opt.shader == HW3_SHADER_BUMP ||
         a->opt.shader == HW3_SHADER_DISPLACEMENT))
        fprintf(stderr, PROGRAM ": note: %s has no texture coordinates; the %s shader reads "
                        "one texel everywhere\n", a->cli.model, hw3_shader_name(a->opt.shader));
    if (a->cli.width) a->scene->width = a->cli.width, a->scene->height = a->cli.height;
    /* Too big a frame, or a reference that cannot be compared with, are
     * usage errors too: found before anything is drawn or written. */
    if (!ras_framebuffer_check_size(a->scene->width, a->scene->height,
                                    a->opt.aa != RAS_AA_NONE ? a->opt.pattern.count : 1, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        return 2;
    }
    char reference_path[1024] = "";
    if (a->cli.compare && !(a->expected = load_reference(a, reference_path, sizeof reference_path)))
        return 2;
    a->image = ras_image_create(a->scene->width, a->scene->height, &err);
    if (!a->image) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        return 1;
    }
    if (!a->cli.output) return run_window(a);
    if (!hw3_render(a->scene, &a->opt, a->image, &a->stats, &err) ||
        !ras_image_save(a->image, a->cli.output, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        return 1;
    }
    fprintf(stderr, "wrote %s (%s shader, %s filter)\n", a->cli.output,
            hw3_shader_name(a->opt.shader), hw3_filter_name(a->opt.filter));
    if (a->cli.stats) {
        char json[2048];
        ras_counters_format_json(&a->stats, json, sizeof json);
        puts(json);
    }
    return a->cli.compare ? compare_with_reference(a, a->expected, reference_path) : 0;
}

int main(int argc, char **argv) {
    ras_cli_reuse_freed_memory(); /* fewer page faults: docs/startup.md */
    app a = {0};
    ras_error err = {{0}};
    switch (ras_cli_parse(argc, argv, ACCEPTED, &a.cli, &err)) {
    case RAS_CLI_HELP: {
        char help[4096];
        ras_cli_help(ACCEPTED, PROGRAM, usage, help, sizeof help);
        fputs(help, stdout);
        return 0;
    }
    case RAS_CLI_VERSION: printf(PROGRAM " (Raster101) %s\n", RAS_VERSION); return 0;
    case RAS_CLI_ERROR: fprintf(stderr, PROGRAM ": %s\n", err.msg); return 2;
    case RAS_CLI_RUN: break;
    }
    a.argv0 = argv[0];
    int status = run(&a);
    ras_image_destroy(a.expected);
    ras_image_destroy(a.image);
    hw3_scene_destroy(a.scene);
    ras_scene_destroy(a.file_scene);
    return status;
}
