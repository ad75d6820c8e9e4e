/* fast/fast_hw3.c — hw3_shading_ref's --renderer option. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * hw3's main.c and scene.c are the student's given code, and the handout has
 * no fast renderer, so they name none: main.c calls ras_app_main and
 * hw3_render, nothing else. The reference program alone is linked with this
 * file and with the linker's --wrap for those two functions (fast/
 * CMakeLists.txt), so that in hw3_shading_ref
 *   - ras_app_main takes --renderer NAME as well (teaching, the default, or
 *     fast), checked once the options are parsed;
 *   - hw3_render draws with fast_render when fast was chosen and it accepts
 *     the frame, else as always.
 * The student build never sees this: same main.c, same scene.c, no hook.
 */
#include "fast_render.h"

#include "ras_app.h"

#include <string.h> /* strcmp */

int __real_ras_app_main(int argc, char **argv, const ras_app_hooks *hooks, void *user);
int __wrap_ras_app_main(int argc, char **argv, const ras_app_hooks *hooks, void *user);
bool __real_hw3_render(const ras_scene *scene, ras_scene_assets *assets,
                       const hw3_render_options *opt, ras_image *out, ras_counters *stats,
                       ras_error *err);
bool __wrap_hw3_render(const ras_scene *scene, ras_scene_assets *assets,
                       const hw3_render_options *opt, ras_image *out, ras_counters *stats,
                       ras_error *err);

static bool (*g_program_prepare)(ras_app *app, ras_error *err);
static bool g_use_fast; /* --renderer fast */

/* --renderer's name, then the program's own prepare. */
static bool prepare(ras_app *app, ras_error *err) {
    const char *name = app->cli.renderer;
    if (name && strcmp(name, "teaching") && strcmp(name, "fast"))
        return ras_error_set(err, "unknown renderer '%s'; this program has: teaching, fast", name);
    g_use_fast = name && !strcmp(name, "fast");
    return g_program_prepare ? g_program_prepare(app, err) : true;
}

int __wrap_ras_app_main(int argc, char **argv, const ras_app_hooks *hooks, void *user) {
    ras_app_hooks with_renderer = *hooks;
    with_renderer.options |= RAS_OPT_RENDERER;
    g_program_prepare = hooks->prepare;
    with_renderer.prepare = prepare;
    return __real_ras_app_main(argc, argv, &with_renderer, user);
}

bool __wrap_hw3_render(const ras_scene *scene, ras_scene_assets *assets,
                       const hw3_render_options *opt, ras_image *out, ras_counters *stats,
                       ras_error *err) {
    if (g_use_fast) {
        /* threads: $RAS_THREADS or one per CPU */
        int drawn = fast_render(scene, assets, opt, NULL, out, stats, err);
        if (drawn >= 0) return drawn;
    }
    return __real_hw3_render(scene, assets, opt, out, stats, err);
}
