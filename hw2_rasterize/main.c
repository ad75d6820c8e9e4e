/* main.c — hw2_rasterize: the classic two triangles, filled, depth-tested and
 * anti-aliased by your rasterizer.
 *
 * Built twice from this file: hw2_rasterize (your rasterizer.c, and your hw1
 * matrices) and hw2_rasterize_ref (the reference solutions). The frame loop is
 * the pipeline: model (identity) · view · projection → clip → divide →
 * viewport → rasterize_triangle (coverage, depth) → resolve_pixel → image.
 *
 *   hw2_rasterize                          window: m AA mode, s samples,
 *                                          p pattern, e edges; the pixel under
 *                                          the mouse is magnified with its samples;
 *                                          v: yours / reference / difference
 *   hw2_rasterize -o out.png               render once, headless
 *   hw2_rasterize --aa msaa --samples 4 -o out.png
 *   hw2_rasterize --aa msaa --compare      compare with tests/reference/hw2_msaa4.png
 *   hw2_rasterize --stats -o out.png       what each stage did, as JSON on stdout
 *   hw2_rasterize --scene scenes/msaa_thin_triangles.json -o fan.png
 *
 * The scene comes from --scene FILE or, without it, from the built-in copy of
 * scenes/hw2_classic.json; --aa, --samples, --pattern, --edges and --size
 * override its values. hw2 draws flat colours (material × vertex colour):
 * a scene's hw3 shader, textures and lights are not used here.
 */
#include "ras_builtin_scenes.h"
#include "ras_cli.h"
#include "ras_compare.h"
#include "ras_io.h" /* RAS_IO_MAX_PATH */
#include "ras_pipeline.h"
#include "ras_viewer.h"
#include "ras_window.h"
#include "rasterizer.h"
#include "transform.h"

#include <math.h>   /* isinf */
#include <stdio.h>  /* printf, fprintf, snprintf */
#include <string.h> /* strrchr, strlen */

#define ACCEPTED (RAS_OPT_AA | RAS_OPT_COMPARE | RAS_OPT_SCENE | RAS_OPT_STATS)
#define PROGRAM "hw2_rasterize"

/* What the keys change. */
typedef struct settings {
    ras_aa_mode aa;
    int samples; /* used when aa != NONE */
    ras_pattern_kind pattern;
    ras_edge_mode edges;
    ras_depth_format depth;
} settings;

typedef struct app {
    settings set;
    int width, height;
    bool own_scene; /* --scene: the reference images show the built-in scene only */
    ras_scene *scene;
    ras_scene_assets *assets;
    ras_pipeline *pipeline;
    ras_image *image;
} app;

static bool make_pipeline(app *a, ras_error *err) {
    ras_pipeline_config cfg = {.width = a->width,
                               .height = a->height,
                               .clear_color = a->scene->clear_color,
                               .cull = a->scene->cull,
                               .aa = a->set.aa,
                               .edges = a->set.edges,
                               .depth = a->set.depth,
                               .z_near = a->scene->camera.z_near,
                               .varyings = RAS_VARYING_COLOR,
                               .rasterize = rasterize_triangle,
                               .resolve = resolve_pixel};
    cfg.pattern = ras_sample_pattern_center();
    if (a->set.aa != RAS_AA_NONE &&
        !ras_sample_pattern_make(a->set.pattern, a->set.samples, &cfg.pattern, err))
        return false;
    ras_pipeline *p = ras_pipeline_create(&cfg, err);
    if (!p) return false;
    ras_pipeline_destroy(a->pipeline);
    a->pipeline = p;
    return true;
}

/* The scene's model_rotation with hw1's matrices (hw2 has no angle option);
 * 0 degrees is exactly the identity, whatever hw1 returns. */
static mat4s spin_matrix(const ras_scene *s) {
    if (s->model_rotation_deg == 0) return glms_mat4_identity();
    return s->model_rotation_axis_set ? get_rotation(s->model_rotation_axis, s->model_rotation_deg)
                                      : get_model_matrix(s->model_rotation_deg);
}

static bool render(app *a, ras_error *err) {
    const ras_scene *s = a->scene;
    ras_pipeline_begin_frame(a->pipeline);
    mat4s view = ras_scene_view_matrix(s), spin = spin_matrix(s);
    mat4s projection = get_projection_matrix(s->camera.fov_deg, (float)a->width / (float)a->height,
                                             s->camera.z_near, s->camera.z_far);
    for (int i = 0; i < s->object_count; i++)
        if (!ras_pipeline_draw_mesh(a->pipeline, a->assets->meshes[i],
                                    ras_scene_model_matrix(&s->objects[i], spin), view, projection,
                                    err))
            return false;
    ras_pipeline_end_frame(a->pipeline, a->image);
    return true;
}

/* "1x", "msaa4", "ssaa16_standard": names the reference image. The edge
 * mode is not in the name: the scene has no shared edge, so float and fixed
 * edge functions draw it alike (up to samples exactly on an edge). */
static void variant_name(const settings *s, char *buf, size_t size) {
    if (s->aa == RAS_AA_NONE) snprintf(buf, size, "1x");
    else
        snprintf(buf, size, "%s%d%s", ras_aa_mode_name(s->aa), s->samples,
                 s->pattern == RAS_PATTERN_STANDARD ? "_standard" : "");
}

/* out/x.png → out/x_diff.png; no output → hw2_<variant>_diff.png. */
static void sibling_path(const char *output, const char *variant, const char *suffix,
                         char *buf, size_t size) {
    if (!output) {
        snprintf(buf, size, "hw2_%s_%s.png", variant, suffix);
        return;
    }
    const char *dot = strrchr(output, '.'), *slash = strrchr(output, '/');
    int stem = (dot && (!slash || dot > slash)) ? (int)(dot - output) : (int)strlen(output);
    snprintf(buf, size, "%.*s_%s.png", stem, output, suffix);
}

/* The reference image for --compare, loaded before anything is drawn so a
 * missing or mismatched one is a usage error (exit 2) that leaves no output
 * behind. NULL (message printed) when there is none. */
static ras_image *load_reference(const app *a, const char *reference, char *path, size_t size) {
    char variant[64];
    variant_name(&a->set, variant, sizeof variant);
    if (reference)
        snprintf(path, size, "%s", reference);
    else if (a->own_scene) {
        fprintf(stderr, PROGRAM ": --compare with --scene needs --reference FILE (the "
                                "reference images show the built-in scene)\n");
        return NULL;
    } else
        snprintf(path, size, "%s/hw2_%s.png", RAS_REFERENCE_DIR, variant);
    ras_error err = {{0}};
    ras_image *expected = ras_image_load(path, &err);
    if (!expected) {
        if (reference)
            fprintf(stderr, PROGRAM ": --reference: %s\n", err.msg);
        else
            fprintf(stderr,
                    PROGRAM ": no reference image for this variant (%s): %s\n"
                            "  the references are 1x, msaa4, ssaa4 and msaa4_standard at 700x700; "
                            "pass --reference FILE for another\n",
                    variant, err.msg);
        return NULL;
    }
    if (!ras_compare_reference_fits(expected, path, a->width, a->height, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        ras_image_destroy(expected);
        return NULL;
    }
    return expected;
}

/* Returns the exit status: 0 match, 1 mismatch, 2 cannot compare. */
static int compare_with_reference(const app *a, const ras_image *expected, const char *path,
                                  const char *output) {
    char variant[64], diff_path[RAS_IO_MAX_PATH + 16]; /* -o's stem + "_worst.png" */
    variant_name(&a->set, variant, sizeof variant);
    ras_error err = {{0}};
    /* Edge-tolerant: a one-pixel shift along an edge (e.g. another fill rule)
     * is not a bug; a missing or swapped triangle is. With AA, one sample's
     * worth more: a vertex 1/256 px elsewhere (your hw1's rounding, float edge
     * functions) flips single samples along the shallow edges. */
    ras_compare_options opt = ras_compare_defaults(RAS_COMPARE_EDGE_TOLERANT);
    if (a->set.aa != RAS_AA_NONE) opt.tolerance += 255 / a->set.samples;
    ras_compare_result res;
    int status = 2;
    if (!ras_compare_images(expected, a->image, &opt, &res, &err)) {
        fprintf(stderr, PROGRAM ": cannot compare with %s: %s\n", path, err.msg);
    } else {
        printf("compare %s: %s\n", path, res.summary);
        printf("  PSNR %.2f dB, SSIM %.4f, %ld pixels off by more than %d/255\n", res.psnr_db,
               res.ssim, res.bad_pixels, opt.tolerance);
        ras_image *heat = ras_compare_heatmap(expected, a->image, opt.kind, &err);
        sibling_path(output, variant, "diff", diff_path, sizeof diff_path);
        if (heat && ras_image_save(heat, diff_path, &err))
            printf("  difference image: %s (black = same, blue..red = more different)\n",
                   diff_path);
        else
            fprintf(stderr, PROGRAM ": no difference image: %s\n", err.msg);
        ras_image_destroy(heat);
        if (!res.pass) {
            ras_image *crop =
                ras_compare_crop(expected, a->image, opt.kind, res.worst_col, res.worst_row, &err);
            sibling_path(output, variant, "worst", diff_path, sizeof diff_path);
            if (crop && ras_image_save(crop, diff_path, &err))
                printf("  worst region (expected | got | difference): %s\n", diff_path);
            else
                fprintf(stderr, PROGRAM ": no worst-region image: %s\n", err.msg);
            ras_image_destroy(crop);
        }
        status = res.pass ? 0 : 1;
    }
    return status;
}

/* ---- the window and its pixel inspector ---------------------------------- */

#define ZOOM 16     /* magnification of the inspector */
#define RADIUS 5    /* pixels shown on each side of the one under the mouse */
#define MARGIN 8

static void fill_box(ras_image *img, int c0, int r0, int w, int h, vec3s c) {
    for (int r = r0; r < r0 + h; r++)
        for (int col = c0; col < c0 + w; col++)
            if (col >= 0 && r >= 0 && col < img->width && r < img->height)
                ras_image_set(img, col, r, c);
}

static void outline_box(ras_image *img, int c0, int r0, int w, int h, vec3s c) {
    fill_box(img, c0, r0, w, 1, c);
    fill_box(img, c0, r0 + h - 1, w, 1, c);
    fill_box(img, c0, r0, 1, h, c);
    fill_box(img, c0 + w - 1, r0, 1, h, c);
}

/* Magnifies the pixels around screen pixel (x, y) into the top-right corner
 * of `view`, marks the samples of (x, y), and writes their depths to `info`. */
static void draw_inspector(const app *a, ras_image *view, int x, int y, char *info,
                           size_t size) {
    const ras_framebuffer *fb = a->pipeline->fb;
    const ras_sample_pattern *pat = &a->pipeline->config.pattern;
    int side = (2 * RADIUS + 1) * ZOOM;
    int c0 = view->width - side - MARGIN, r0 = MARGIN;
    if (c0 < 0) return; /* frame too small for the inspector */
    outline_box(view, c0 - 1, r0 - 1, side + 2, side + 2, (vec3s){{1, 1, 1}});
    for (int dy = -RADIUS; dy <= RADIUS; dy++)
        for (int dx = -RADIUS; dx <= RADIUS; dx++) {
            int px = x + dx, py = y + dy;
            vec3s c = {{0.25f, 0.25f, 0.25f}}; /* outside the frame */
            if (px >= 0 && py >= 0 && px < a->width && py < a->height)
                c = a->image->pixels[ras_fb_pixel_index(fb, px, py)];
            /* Screen y is up, image rows go down. */
            fill_box(view, c0 + (dx + RADIUS) * ZOOM, r0 + (RADIUS - dy) * ZOOM, ZOOM, ZOOM, c);
        }
    int pc = c0 + RADIUS * ZOOM, pr = r0 + RADIUS * ZOOM;
    outline_box(view, pc, pr, ZOOM, ZOOM, (vec3s){{1, 1, 1}});
    int n = snprintf(info, size, "pixel (%d,%d) depth:", x, y);
    for (int s = 0; s < pat->count; s++) {
        int i = ras_fb_sample_index(fb, x, y, s);
        /* A sample dot: its own colour, ringed red when nothing covers it. */
        int sc = pc + (int)(pat->offsets[s].x * ZOOM), sr = pr + ZOOM - 1 - (int)(pat->offsets[s].y * ZOOM);
        bool empty = isinf(fb->depth[i]);
        fill_box(view, sc - 2, sr - 2, 5, 5, empty ? (vec3s){{1, 0, 0}} : (vec3s){{0, 0, 0}});
        fill_box(view, sc - 1, sr - 1, 3, 3, fb->color[i]);
        if (n > 0 && (size_t)n < size && s < 8)
            n += empty ? snprintf(info + n, size - (size_t)n, " -")
                       : snprintf(info + n, size - (size_t)n, " %.4f", fb->depth[i]);
    }
    if (pat->count > 8 && n > 0 && (size_t)n < size) snprintf(info + n, size - (size_t)n, " ...");
}

static int next_count(ras_pattern_kind kind, int count) {
    static const int ordered[] = {4, 16, 64, 0}, standard[] = {2, 4, 8, 16, 0};
    const int *list = kind == RAS_PATTERN_ORDERED ? ordered : standard;
    for (int i = 0; list[i]; i++)
        if (list[i] == count) return list[i + 1] ? list[i + 1] : list[0];
    return 4; /* every pattern has 4 */
}

static int run_window(app *a, const char *argv0) {
    const char *title = PROGRAM;
    ras_error err = {{0}};
    ras_viewer viewer;
    ras_viewer_init(&viewer, title, argv0, RAS_REFERENCE_DIR, RAS_COMPARE_EDGE_TOLERANT);
    ras_image *view = NULL;
    bool dirty = true, redraw = true;
    int mouse_col = -1, mouse_row = -1;
    for (;;) {
        if (dirty) {
            ras_viewer_frame_begin(&viewer);
            if (!make_pipeline(a, &err) || !render(a, &err)) break;
            ras_viewer_frame_end(&viewer);
            char variant[64], name[80];
            variant_name(&a->set, variant, sizeof variant);
            snprintf(name, sizeof name, "hw2_%s", variant);
            ras_viewer_set_reference(&viewer, a->own_scene ? NULL : name, a->width, a->height);
            dirty = false;
            redraw = true;
        }
        if (redraw) {
            ras_image_destroy(view);
            view = ras_image_clone(a->image);
            if (!view) {
                ras_error_set(&err, "out of memory");
                break;
            }
            char mode[96], info[160] = "move the mouse over the picture to inspect a pixel";
            if (a->set.aa == RAS_AA_NONE) snprintf(mode, sizeof mode, "no AA");
            else
                snprintf(mode, sizeof mode, "%s %dx %s", ras_aa_mode_name(a->set.aa),
                         a->set.samples, ras_pattern_kind_name(a->set.pattern));
            if (mouse_col >= 0 && ras_viewer_showing_program(&viewer))
                draw_inspector(a, view, mouse_col, a->height - 1 - mouse_row, info, sizeof info);
            char status[320];
            snprintf(status, sizeof status, "%s, %s edges\nm aa  s samples  p pattern  e edges  Esc\n%s",
                     mode, a->set.edges == RAS_EDGES_FIXED ? "fixed" : "float", info);
            if (!ras_viewer_show(&viewer, view, status, &err)) break;
            redraw = false;
        }
        int key = ras_window_wait_key(title, 30);
        if (key == RAS_KEY_ESC || key == 'q' || key == -2) {
            ras_window_close(title);
            ras_image_destroy(view);
            ras_viewer_release(&viewer);
            return 0;
        }
        if (ras_viewer_key(&viewer, key)) redraw = true;
        settings *s = &a->set;
        if (key == 'm') {
            s->aa = s->aa == RAS_AA_NONE ? RAS_AA_MSAA : s->aa == RAS_AA_MSAA ? RAS_AA_SSAA : RAS_AA_NONE;
            dirty = true;
        } else if (key == 's') {
            if (s->aa == RAS_AA_NONE) s->aa = RAS_AA_MSAA;
            else s->samples = next_count(s->pattern, s->samples);
            dirty = true;
        } else if (key == 'p') {
            s->pattern = s->pattern == RAS_PATTERN_ORDERED ? RAS_PATTERN_STANDARD : RAS_PATTERN_ORDERED;
            ras_sample_pattern probe;
            if (!ras_sample_pattern_make(s->pattern, s->samples, &probe, NULL)) s->samples = 4;
            dirty = true;
        } else if (key == 'e') {
            s->edges = s->edges == RAS_EDGES_FIXED ? RAS_EDGES_FLOAT : RAS_EDGES_FIXED;
            dirty = true;
        }
        int col, row;
        if (ras_window_mouse(title, &col, &row) && col >= 0 && row >= 0 && col < a->width &&
            row < a->height && (col != mouse_col || row != mouse_row)) {
            mouse_col = col;
            mouse_row = row;
            redraw = true;
        }
    }
    ras_image_destroy(view);
    ras_viewer_release(&viewer);
    fprintf(stderr, PROGRAM ": %s\n", err.msg);
    return 1;
}

/* ---- main ----------------------------------------------------------------- */

int main(int argc, char **argv) {
    ras_cli_reuse_freed_memory(); /* fewer page faults: docs/startup.md */
    ras_cli cli = {0};
    ras_error err = {{0}};
    switch (ras_cli_parse(argc, argv, ACCEPTED, &cli, &err)) {
    case RAS_CLI_HELP: {
        char help[4096];
        ras_cli_help(ACCEPTED, PROGRAM,
                     "Draws the hw2 scene (default: the two classic triangles) with your "
                     "rasterizer\n(coverage, z-buffer, "
                     "anti-aliasing).\nWith -o or --compare it renders once, headless; "
                     "without, a window opens:\n  m AA mode, s sample count, p sample "
                     "pattern, e edge functions,\n  v your picture / the reference / "
                     "the difference, Esc quits;\n  the pixel under the mouse "
                     "is magnified with its samples and their depths.\n"
                     "--compare uses tests/reference/hw2_<1x|msaa4|ssaa4|msaa4_standard>.png\n"
                     "  and writes the difference beside -o FILE (FILE_diff.png), or without\n"
                     "  -o as hw2_<variant>_diff.png in the current folder. --samples N alone\n"
                     "  means --aa msaa.\n",
                     help, sizeof help);
        fputs(help, stdout);
        return 0;
    }
    case RAS_CLI_VERSION: printf(PROGRAM " (Raster101) %s\n", RAS_VERSION); return 0;
    case RAS_CLI_ERROR: fprintf(stderr, PROGRAM ": %s\n", err.msg); return 2;
    case RAS_CLI_RUN: break;
    }
    if (!cli.output && cli.positional_count == 1) cli.output = cli.positional[0];
    else if (cli.positional_count > 0) {
        fprintf(stderr,
                PROGRAM ": unexpected argument '%s'; expected at most one output file "
                        "(e.g. " PROGRAM " --aa msaa -o out.png)\n",
                cli.positional[cli.positional_count - 1]);
        return 2;
    }
    /* A file that cannot be written is a usage error: say so before any work. */
    if (cli.output && !ras_image_check_output(cli.output, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        return 2;
    }
    if (cli.aa_set && cli.aa == RAS_AA_NONE && cli.samples > 1) {
        fprintf(stderr,
                PROGRAM ": --aa none draws one sample per pixel, but --samples %d asks for "
                        "%d; drop --samples or use --aa msaa / --aa ssaa\n",
                cli.samples, cli.samples);
        return 2;
    }
    /* The scene first: a scene that does not load draws nothing (exit 2). */
    app a = {.own_scene = cli.scene != NULL};
    a.scene = ras_scene_load_or_builtin(cli.scene, "hw2_classic", &err);
    a.assets = a.scene ? ras_scene_load_assets(a.scene, &err) : NULL;
    if (!a.assets) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        ras_scene_destroy(a.scene);
        return 2;
    }
    const ras_scene *sc = a.scene;
    if (sc->shader != RAS_SHADER_FLAT)
        fprintf(stderr,
                PROGRAM ": note: hw2 draws flat colours; the scene's \"%s\" shader "
                        "is hw3's (hw3_shading --scene)\n",
                ras_scene_shader_name(sc->shader));
    /* The scene's settings, then the command line over them. */
    a.set = (settings){.aa = sc->aa,
                       .samples = sc->aa != RAS_AA_NONE ? sc->samples : 4,
                       .pattern = sc->pattern_kind,
                       .edges = sc->edges,
                       .depth = sc->depth};
    if (cli.aa_set) a.set.aa = cli.aa;
    if (cli.samples) a.set.samples = cli.samples;
    if (cli.pattern_set) a.set.pattern = cli.pattern;
    if (cli.edges_set) a.set.edges = cli.edges;
    if (cli.depth_set) a.set.depth = cli.depth;
    a.width = cli.width ? cli.width : sc->width;
    a.height = cli.height ? cli.height : sc->height;
    if (cli.samples > 1 && !cli.aa_set && a.set.aa == RAS_AA_NONE)
        a.set.aa = RAS_AA_MSAA; /* --samples N alone means MSAA */
    /* Ordered grids have no 2x or 8x: without --pattern, those counts take
     * the standard pattern. */
    int status = 0;
    ras_sample_pattern probe;
    if (!cli.pattern_set && a.set.aa != RAS_AA_NONE &&
        !ras_sample_pattern_make(RAS_PATTERN_ORDERED, a.set.samples, &probe, NULL))
        a.set.pattern = RAS_PATTERN_STANDARD;
    /* Bad --samples/--pattern pairs are usage errors. */
    if (a.set.aa != RAS_AA_NONE &&
        !ras_sample_pattern_make(a.set.pattern, a.set.samples, &probe, &err)) {
        fprintf(stderr, PROGRAM ": %s (--pattern %s --samples %d)\n", err.msg,
                ras_pattern_kind_name(a.set.pattern), a.set.samples);
        status = 2;
    }
    /* Too big a frame, or a reference that cannot be compared with, are
     * usage errors too: found before anything is drawn or written. */
    if (!status && !ras_framebuffer_check_size(a.width, a.height,
                                               a.set.aa != RAS_AA_NONE ? a.set.samples : 1, &err)) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        status = 2;
    }
    char reference_path[1024] = "";
    ras_image *expected = NULL;
    if (!status && cli.compare &&
        !(expected = load_reference(&a, cli.reference, reference_path, sizeof reference_path)))
        status = 2;
    bool headless = cli.output || cli.compare;
    /* Only ask about a display when a window is wanted: headless runs never
     * touch highgui. */
    if (status) {
        /* nothing to draw */
    } else if (!headless && !ras_window_available()) {
        fprintf(stderr,
                PROGRAM ": no display to open a window on (DISPLAY is not set); "
                        "render to a file instead, e.g. " PROGRAM " --aa msaa -o out.png\n");
        status = 2;
    } else if (!(a.image = ras_image_create(a.width, a.height, &err))) {
        fprintf(stderr, PROGRAM ": %s\n", err.msg);
        status = 1;
    } else if (headless) {
        if (!make_pipeline(&a, &err) || !render(&a, &err) ||
            (cli.output && !ras_image_save(a.image, cli.output, &err))) {
            fprintf(stderr, PROGRAM ": %s\n", err.msg);
            status = 1;
        } else {
            if (cli.output) fprintf(stderr, "wrote %s\n", cli.output);
            if (cli.stats) {
                char json[2048];
                ras_counters_format_json(&a.pipeline->counters, json, sizeof json);
                puts(json);
            }
            if (cli.compare)
                status = compare_with_reference(&a, expected, reference_path, cli.output);
        }
    } else {
        status = run_window(&a, argv[0]);
    }
    ras_image_destroy(expected);
    ras_image_destroy(a.image);
    ras_pipeline_destroy(a.pipeline);
    ras_scene_assets_destroy(a.assets);
    ras_scene_destroy(a.scene);
    return status;
}
