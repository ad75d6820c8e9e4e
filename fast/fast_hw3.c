/* fast/fast_hw3.c — hw3_shading_ref's --renderer option. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * hw3's main.c and scene.c are the student's given code, and the handout has
 * no fast renderer, so they name none: main.c calls ras_app_main with its
 * configure and draw hooks, nothing else. The reference program alone is
 * linked with this file and with the linker's --wrap for ras_app_main (fast/
 * CMakeLists.txt), so that in hw3_shading_ref
 *   - ras_app_main takes --renderer NAME as well (teaching, the default, or
 *     fast), checked once the options are parsed;
 *   - each frame is drawn by fast_render when fast was chosen and it accepts
 *     the frame (hooks.render), else by the shell's pipeline as always
 *     (ras_app_draw_frame, with main.c's hooks).
 * The student build never sees this: same main.c, same scene.c, no hook.
 */
#include "fast_render.h"

#include "ras_app.h"

#include <string.h> /* strcmp */

int __real_ras_app_main(int argc, char **argv, const ras_app_hooks *hooks, void *user);
int __wrap_ras_app_main(int argc, char **argv, const ras_app_hooks *hooks, void *user);

static bool (*g_program_prepare)(ras_app *app, ras_error *err);
static bool g_use_fast;              /* --renderer fast */
static ras_counters g_fast_counters; /* the last frame fast_render drew */

/* --renderer's name, then the program's own prepare. */
static bool prepare(ras_app *app, ras_error *err) {
    const char *name = app->cli.renderer;
    if (name && strcmp(name, "teaching") && strcmp(name, "fast"))
        return ras_error_set(err, "unknown renderer '%s'; this program has: teaching, fast", name);
    g_use_fast = name && !strcmp(name, "fast");
    return g_program_prepare ? g_program_prepare(app, err) : true;
}

/* The frame: fast_render's when chosen and accepted, else the shell's: so
 * always for the frames whose buffers --dump or the window's views keep (the
 * shell's pipeline holds them). */
static bool render(ras_app *app, ras_error *err) {
    if (g_use_fast && !app->cli.dump && !ras_app_capturing(app)) {
        hw3_render_options opt = hw3_app_render_options(app);
        /* threads: $RAS_THREADS or one per CPU */
        int drawn =
            fast_render(app->scene, app->assets, &opt, NULL, app->image, &g_fast_counters, err);
        if (drawn >= 0) {
            app->counters = &g_fast_counters;
            return drawn;
        }
    }
    return ras_app_draw_frame(app, err);
}

int __wrap_ras_app_main(int argc, char **argv, const ras_app_hooks *hooks, void *user) {
    ras_app_hooks with_renderer = *hooks;
    with_renderer.options |= RAS_OPT_RENDERER;
    g_program_prepare = hooks->prepare;
    with_renderer.prepare = prepare;
    with_renderer.render = render;
    return __real_ras_app_main(argc, argv, &with_renderer, user);
}
