/* ras_counters.c — see ras_counters.h. */
#include "ras_counters.h"

#include <stdio.h> /* snprintf */
#include <time.h>  /* clock_gettime */

static const char *const stage_names[RAS_STAGE_COUNT] = {
    "vertex", "clip",     "setup",  "raster",  "fragment", "texture",
    "lighting", "bump",   "mipmap", "resolve", "wireframe"};

int ras_counters_format_json(const ras_counters *c, char *buf, size_t size) {
    char stages[256] = "";
    int n = 0;
    for (int i = 0; i < RAS_STAGE_COUNT; i++)
        if (c->stages_run & (1u << i))
            n += snprintf(stages + n, sizeof stages - (size_t)n, "%s\"%s\"", n ? ", " : "",
                          stage_names[i]);
#define U(f) (unsigned long long)c->f
    return snprintf(
        buf, size,
        "{\"stages_run\": [%s], \"vertices_transformed\": %llu, \"triangles_in\": %llu, "
        "\"triangles_clipped_away\": %llu, \"triangles_clip_split\": %llu, "
        "\"triangles_culled\": %llu, \"triangles_rejected_nonfinite\": %llu, "
        "\"triangles_rejected_range\": %llu, "
        "\"triangles_degenerate\": %llu, \"triangles_rasterized\": %llu, "
        "\"samples_tested\": %llu, \"samples_covered\": %llu, \"depth_tests_passed\": %llu, "
        "\"fragments_shaded\": %llu, \"varyings_interpolated\": %llu, "
        "\"texels_fetched\": %llu, \"mip_levels_built\": %llu, "
        "\"lighting_evaluations\": %llu, \"lines_drawn\": %llu, \"buffer_bytes\": %llu, "
        "\"ms\": {\"vertex\": %.3f, \"raster\": %.3f, \"resolve\": %.3f, \"total\": %.3f}}",
        stages, U(vertices_transformed), U(triangles_in), U(triangles_clipped_away),
        U(triangles_clip_split), U(triangles_culled), U(triangles_rejected_nonfinite),
        U(triangles_rejected_range),
        U(triangles_degenerate), U(triangles_rasterized), U(samples_tested),
        U(samples_covered), U(depth_tests_passed), U(fragments_shaded),
        U(varyings_interpolated), U(texels_fetched), U(mip_levels_built),
        U(lighting_evaluations), U(lines_drawn), (unsigned long long)c->buffer_bytes,
        c->ms_vertex, c->ms_raster, c->ms_resolve, c->ms_total);
#undef U
}

double ras_now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}
