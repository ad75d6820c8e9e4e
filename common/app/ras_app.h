/* ras_app.h — the program shell the three assignments share.
 *
 * Each main.c fills a ras_app_hooks (its name, options, built-in scene and
 * the frame it draws) and calls ras_app_main, which does the rest the same
 * way for every program. A frame is the shell's (ras_app_draw_frame), with
 * the program's two hooks inside it:
 *
 *   hooks.configure   what the frame is drawn with: the pipeline's
 *                     configuration for the current settings
 *   (the shell)       sets its own state in it (--dump and the window's
 *                     views keep the buffers, the step view's prefix), makes
 *                     the pipeline from it (keeps the last one while the
 *                     configuration is equal) and clears it
 *   hooks.draw        what the frame draws: the scene's objects into it
 *   (the shell)       resolves it into app->image, and writes: -o, --dump
 *                     (the pipeline's buffers, its fragment stage's too), --stats
 *
 * The shell owns the pipeline from the first frame to the end of the
 * program; a program reads it (app->pipeline) and never frees or replaces
 * it. The steps of ras_app_main:
 *
 *   1. parse the command line (ras_cli.h; --help, --version; exit 2 on a
 *      bad option), the classic positional form (OUTPUT [SHADER]);
 *   2. check -o and the option pairs, and that a window can open when one
 *      is wanted (exit 2 before any work);
 *   3. load the scene (--scene FILE, the built-in one, or with --model the
 *      built-in model scene around that file) and apply the flags over it
 *      with one set of rules (ras_app_resolve below);
 *   4. hooks.prepare (the program's own state), the frame-size budget, and
 *      with --compare the reference image (exit 2 when there is none);
 *   5. headless (-o or --compare): one frame, write -o, --stats as JSON on
 *      stdout, --compare; or the window (ras_viewer.h): a frame on every
 *      change, keys, the reference and difference views.
 *
 * The reference image for the current settings is the catalogue entry
 * (ras_catalogue.h) of this program whose arguments give the same settings
 * on the built-in scene; --compare and the window's reference view use it.
 * Exit status: 0 done (--compare: the images match), 1 the render or
 * writing failed (--compare: they differ), 2 bad options or input.
 */
#ifndef RAS_APP_H
#define RAS_APP_H

#include "ras_cli.h"
#include "ras_compare.h"
#include "ras_counters.h"
#include "ras_image.h"
#include "ras_pipeline.h"
#include "ras_scene.h"

/* The settings a frame is drawn with: the scene's, with the flags over them
 * (ras_app_resolve); the window's keys change them. */
typedef struct ras_app_settings {
    int width, height;
    float angle;   /* the program's rotation in degrees (-r) */
    bool axis_set; /* rotate about `axis` (get_rotation) instead of z */
    vec3s axis;
    ras_aa_mode aa;
    /* The samples per pixel and their positions with AA: the pattern is
     * ras_app_settings_pattern's, made from these two (kept while aa is NONE:
     * the window's m turns AA back on with them). */
    int samples;
    ras_pattern_kind pattern_kind;
    ras_depth_format depth;
    ras_cull_mode cull;
    ras_scene_shader shader;
    ras_scene_filter filter;
    bool affine;        /* hw3's w = 1 pitfall (window key p) */
    bool builtin_scene; /* no --scene, no --model: the scene the references show */
} ras_app_settings;

typedef struct ras_app ras_app;

/* The window's step view and buffer view (RAS_APP_STEP; docs/hw2.md "Step
 * through a frame"). Keys: t step mode on/off; n or space one triangle more,
 * - (minus) one less (not N: OpenCV's Qt window reports shift+n as n); in
 * step mode 1-9 forward 1, 10, 100, ... (10^(k-1)) triangles and 0 back to
 * none; b the buffer shown: colour -> depth -> coverage (AA
 * only) -> overdraw -> normal -> uv (hw3, when the shader reads them),
 * skipping what the frame does not produce. The shell sets `on` and `limit`
 * as the pipeline's config.step and step_triangles, and config.dump while
 * ras_app_capturing (ras_app_draw_frame). */
typedef enum ras_app_buffer {
    RAS_APP_BUFFER_COLOUR,
    RAS_APP_BUFFER_DEPTH,
    RAS_APP_BUFFER_COVERAGE,
    RAS_APP_BUFFER_OVERDRAW,
    RAS_APP_BUFFER_NORMAL,
    RAS_APP_BUFFER_UV,
    RAS_APP_BUFFER_COUNT
} ras_app_buffer;

typedef struct ras_app_step {
    bool on;               /* draw only the first `limit` triangles */
    long limit;            /* triangles drawn in step mode */
    long total;            /* triangles the whole frame rasterizes (after clipping, culling) */
    ras_app_buffer buffer; /* what the window shows */
} ras_app_step;

/* Window keys the shell handles for a program (ras_app_hooks.keys). */
enum {
    RAS_APP_KEYS_ANGLE = 1u << 0,   /* a/d: angle ±10° */
    RAS_APP_KEYS_SHADING = 1u << 1, /* 1-5: shader, f: filter */
    RAS_APP_KEYS_AA = 1u << 2,      /* m: AA mode, s: samples, p: pattern */
};

/* What the shell does for a program (ras_app_hooks.features). */
enum {
    RAS_APP_LOAD_ASSETS = 1u << 0,       /* load the scene's meshes and textures */
    RAS_APP_WITHOUT_MAPS = 1u << 1,      /* ... but no textures or height maps: the program draws
                                          * flat colours (ras_scene_load_meshes) */
    RAS_APP_SPIN_FROM_SCENE = 1u << 2,   /* the scene's model_rotation is the starting angle */
    RAS_APP_POSITIONAL_SHADER = 1u << 3, /* OUTPUT [SHADER]: the classic form takes a shader */
    RAS_APP_INSPECTOR = 1u << 4,         /* the window magnifies the pixel under the mouse */
    RAS_APP_STEP = 1u << 5,              /* the step and buffer views (ras_app_step; the inspector
                                          * is on in step mode) */
};

/* For a main.c's hooks: the student files it is built from, or NULL for
 * the reference build (the build defines RAS_STUDENT_SOURCES for the
 * student's programs only). */
#ifdef RAS_STUDENT_SOURCES
#define RAS_APP_STUDENT_SOURCES RAS_STUDENT_SOURCES
#else
#define RAS_APP_STUDENT_SOURCES NULL
#endif

typedef struct ras_app_hooks {
    const char *program; /* "hw2_rasterize": messages, window title, catalogue */
    /* the student build's own source files, "a.c:b.c" (RAS_STUDENT_SOURCES,
     * set by the build); NULL for the reference. A program older than one
     * of them says, before anything else, that it runs older code. */
    const char *student_sources;
    const char *usage;         /* --help's paragraph */
    unsigned options;          /* RAS_OPT_* the program takes */
    const char *scene;         /* the built-in scene: "hw2_classic" */
    const char *model_scene;   /* with RAS_OPT_MODEL: the built-in scene --model FILE puts
                                * the file into (ras_builtin_scene_with_model) */
    const char *example;       /* a headless example for messages: "--aa msaa -o out.png" */
    const char *reference_dir; /* the reference images and catalogue.json: RAS_REFERENCE_DIR,
                                * which the build gives each program (common names no tests/) */
    ras_compare_kind compare;  /* --compare's metric and the difference view's */
    unsigned keys;             /* RAS_APP_KEYS_* */
    unsigned features;         /* RAS_APP_LOAD_ASSETS, RAS_APP_STEP, ... */
    /* The program's own state, once the settings are known. false: bad
     * input, err says why (exit 2). */
    bool (*prepare)(ras_app *app, ras_error *err);
    /* What the frame is drawn with: the pipeline's configuration for
     * app->set (zeroed before the call). Called before every frame; its
     * dump, step and step_triangles are the shell's (set after it). false:
     * the frame cannot be drawn, err says why. */
    bool (*configure)(ras_app *app, ras_pipeline_config *config, ras_error *err);
    /* What the frame draws: the scene's objects into the shell's pipeline,
     * cleared (ras_pipeline_begin_frame); the shell resolves it after. false:
     * the frame failed (out of memory). */
    bool (*draw)(ras_app *app, ras_pipeline *pipeline, ras_error *err);
    /* A frame drawn another way than the core's pipeline (hw3_shading_ref's
     * --renderer fast): into app->image, with app->counters set; it calls
     * ras_app_draw_frame for a frame it does not draw, and for every frame
     * while ras_app_capturing (the window then reads app->pipeline, which
     * otherwise keeps the last frame the shell drew). NULL (every
     * assignment): the shell's frame. */
    bool (*render)(ras_app *app, ras_error *err);
    /* A window key the shell does not handle: true when it changed the frame. */
    bool (*key)(ras_app *app, int key);
    /* The mouse moved to (col, row): true when it changed the frame. */
    bool (*mouse)(ras_app *app, int col, int row);
    /* The status line under the viewer's: what is drawn and the keys. */
    void (*status)(const ras_app *app, char *buf, size_t size);
} ras_app_hooks;

struct ras_app {
    const ras_app_hooks *hooks;
    const char *argv0;
    ras_cli cli;
    ras_scene *scene;         /* the scene drawn (--scene, --model or the built-in one) */
    ras_scene_assets *assets; /* with RAS_APP_LOAD_ASSETS */
    ras_app_settings set;
    ras_image *image;
    const ras_counters *counters; /* the last frame's, for --stats */
    /* The shell's: made by ras_app_draw_frame from hooks.configure, kept
     * while the configuration stays equal, freed at the end. The last frame's
     * samples, depths and counters: the inspector, the buffer view and --dump
     * read them. NULL before the first frame. */
    ras_pipeline *pipeline;
    ras_pipeline_config pipeline_config; /* what hooks.configure gave for it */
    void *user;                          /* the program's */
    ras_app_step step;                   /* the window's step and buffer views */
};

/* Whether the frame must keep its buffers for the window (step mode, or a
 * buffer other than colour shown): the render draws with config.step and
 * config.dump then. Never during a headless frame. */
bool ras_app_capturing(const ras_app *app);

/* One frame through the shell's pipeline: hooks.configure, the pipeline made
 * (again when the configuration changed) or cleared, hooks.draw, resolved into
 * app->image; app->counters are the pipeline's. false and err when a hook
 * failed or the pipeline could not be made. */
bool ras_app_draw_frame(ras_app *app, ras_error *err);

/* The whole program: returns main's exit status. */
int ras_app_main(int argc, char **argv, const ras_app_hooks *hooks, void *user);

/* The one set of rules that turns a scene and a command line into settings:
 *   - every flag overrides the scene's value (--size, -r, --axis, --aa,
 *     --samples, --pattern, --depth, --shader, --filter);
 *   - --samples N (N > 1) alone means --aa msaa; --aa none with --samples
 *     N > 1 is an error;
 *   - without --pattern, a count the ordered grid lacks (2, 8) takes the
 *     standard pattern;
 *   - a count the pattern lacks is an error.
 * `scene` may be NULL (the defaults). */
bool ras_app_resolve(const ras_app_hooks *hooks, const ras_cli *cli, const ras_scene *scene,
                     ras_app_settings *set, ras_error *err);

/* The sample pattern the settings draw with: pattern_kind's with `samples`
 * (ras_app_resolve and the window's keys keep that pair valid), the pixel
 * centre without AA. */
ras_sample_pattern ras_app_settings_pattern(const ras_app_settings *set);

/* The catalogue's reference image for the current settings: its name
 * ("hw2_msaa4") in buf, or false when none (another scene, size, ...). */
bool ras_app_reference_name(const ras_app *app, char *buf, size_t size);

#endif
