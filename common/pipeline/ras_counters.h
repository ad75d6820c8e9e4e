/* ras_counters.h — what each pipeline stage did in one frame (--stats).
 *
 * The counters prove the third promise of Raster101: a stage the scene does not
 * call for does not run. A stage that ran sets its bit in `stages_run`; work
 * is counted where it happens. Rasterizers and shaders given a NULL counters
 * pointer count nothing (ras_count() is NULL-safe).
 */
#ifndef RAS_COUNTERS_H
#define RAS_COUNTERS_H

#include <stddef.h> /* size_t */
#include <stdint.h> /* uint64_t */

enum {
    RAS_STAGE_VERTEX = 1u << 0,
    RAS_STAGE_CLIP = 1u << 1,
    RAS_STAGE_SETUP = 1u << 2,
    RAS_STAGE_RASTER = 1u << 3,
    RAS_STAGE_FRAGMENT = 1u << 4,
    RAS_STAGE_TEXTURE = 1u << 5,
    RAS_STAGE_LIGHTING = 1u << 6,
    RAS_STAGE_BUMP = 1u << 7,
    RAS_STAGE_MIPMAP = 1u << 8,
    RAS_STAGE_RESOLVE = 1u << 9,
    RAS_STAGE_WIREFRAME = 1u << 10,
};
#define RAS_STAGE_COUNT 11

typedef struct ras_counters {
    unsigned stages_run; /* RAS_STAGE_* bits */
    uint64_t vertices_transformed;
    uint64_t triangles_in;
    uint64_t triangles_clipped_away;  /* wholly outside the clip volume */
    uint64_t triangles_clip_split;    /* crossed a plane and were cut */
    uint64_t triangles_culled;
    uint64_t triangles_rejected_nonfinite; /* NaN/Inf in positions or varyings */
    uint64_t triangles_rejected_range; /* a corner beyond RAS_RASTER_MAX_COORD (stage4_raster.h) */
    uint64_t triangles_degenerate;    /* zero area after snapping */
    uint64_t triangles_rasterized;
    uint64_t samples_tested;
    uint64_t samples_covered;
    uint64_t depth_tests_passed;
    uint64_t fragments_shaded;
    uint64_t varyings_interpolated;   /* one per varying per shaded fragment */
    uint64_t texels_fetched;
    uint64_t mip_levels_built;
    uint64_t lighting_evaluations;
    uint64_t lines_drawn;
    size_t buffer_bytes;              /* framebuffer memory */
    double ms_vertex, ms_raster, ms_resolve, ms_total;
} ras_counters;

static inline void ras_count(uint64_t *counter_field_or_null, uint64_t n) {
    if (counter_field_or_null) *counter_field_or_null += n;
}

/* The counters as one JSON object (no trailing newline). Returns the length
 * that was needed, like snprintf. */
int ras_counters_format_json(const ras_counters *c, char *buf, size_t size);

/* Milliseconds from a monotonic clock, for stage timings. */
double ras_now_ms(void);

#endif
