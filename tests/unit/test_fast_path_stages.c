/* test_fast_path_stages.c — test_scene_stages' frames drawn again by the fast
 * renderer, which must report the same work. Not in the handout (it has no
 * fast renderer: tests/grading/manifest).
 *
 * test_scene_stages.c is shipped (it tests the teaching pipeline's counters,
 * with the student's code in the handout) and names no fast renderer. In the
 * instructors' build (tests/unit/CMakeLists.txt, when the library fast
 * exists) it is linked with this file and -Wl,--wrap=hw3_render, so that
 * every frame it draws with counters is drawn a second time by fast_render
 * on 2 threads, from its own copy of the scene's assets (the mip levels a
 * frame builds are counted: the second frame must build them too), and the
 * two frames' work counters must agree. A frame the fast renderer declines
 * (inverse_w, culling, kept buffers) is the teaching pipeline's alone.
 */
#include <setjmp.h> /* cmocka needs these three first */
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "fast_render.h"
#include "test_fast_path_work.h"

bool __real_hw3_render(const ras_scene *scene, ras_scene_assets *assets,
                       const hw3_render_options *opt, ras_image *out, ras_counters *stats,
                       ras_error *err);
bool __wrap_hw3_render(const ras_scene *scene, ras_scene_assets *assets,
                       const hw3_render_options *opt, ras_image *out, ras_counters *stats,
                       ras_error *err);

bool __wrap_hw3_render(const ras_scene *scene, ras_scene_assets *assets,
                       const hw3_render_options *opt, ras_image *out, ras_counters *stats,
                       ras_error *err) {
    if (!__real_hw3_render(scene, assets, opt, out, stats, err)) return false;
    if (!stats) return true; /* nothing to compare */
    ras_error fast_err = {{0}};
    ras_scene_assets *fresh = ras_scene_load_assets(scene, &fast_err);
    if (!fresh) fail_msg("ras_scene_load_assets (for the fast renderer): %s", fast_err.msg);
    ras_image *image = ras_image_create(out->width, out->height, &fast_err);
    assert_non_null(image);
    ras_counters k = {0};
    fast_settings settings = {.threads = 2};
    int drawn = fast_render(scene, fresh, opt, &settings, image, &k, &fast_err);
    if (drawn == 0) fail_msg("fast_render: %s", fast_err.msg);
    if (drawn > 0) fast_path_same_work(stats, &k, "test_scene_stages' frame drawn again by fast_render");
    ras_image_destroy(image);
    ras_scene_assets_destroy(fresh);
    return true;
}
