/* test_fast_path_work.h — the one list of work counters the fast renderer
 * must report as the teaching pipeline does (test_fast_path.c, and
 * test_fast_path_stages.c for test_scene_stages' frames). Not the timings or
 * the buffer memory: the fast path draws into tiles, on threads. Not in the
 * handout, with the fast renderer (tests/grading/manifest). Include after
 * cmocka.h. */
#ifndef RAS_UNIT_TEST_FAST_PATH_WORK_H
#define RAS_UNIT_TEST_FAST_PATH_WORK_H

#include "ras_counters.h"

/* Fails the test, naming `what` and the first counter that differs. */
static inline void fast_path_same_work(const ras_counters *a, const ras_counters *b,
                                       const char *what) {
#define SAME(f)                                                                                    \
    if (a->f != b->f)                                                                              \
    fail_msg("%s: counter " #f " differs: teaching %llu, fast %llu", what,                         \
             (unsigned long long)a->f, (unsigned long long)b->f)
    SAME(stages_run);
    SAME(vertices_transformed);
    SAME(triangles_in);
    SAME(triangles_clipped_away);
    SAME(triangles_clip_split);
    SAME(triangles_culled);
    SAME(triangles_rejected_nonfinite);
    SAME(triangles_rejected_range);
    SAME(triangles_degenerate);
    SAME(triangles_rasterized);
    SAME(samples_tested);
    SAME(samples_covered);
    SAME(depth_tests_passed);
    SAME(fragments_shaded);
    SAME(varyings_interpolated);
    SAME(texels_fetched);
    SAME(mip_levels_built);
    SAME(lighting_evaluations);
#undef SAME
}

#endif
