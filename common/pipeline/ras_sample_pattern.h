/* ras_sample_pattern.h — where the samples of one pixel sit.
 *
 * Offsets are in pixels from the pixel's lower-left corner, so a pixel (x, y)
 * samples at (x + offset.x, y + offset.y); a single centre sample is (0.5, 0.5).
 * Two families:
 *   - ordered grids n×n (2×2, 4×4, 8×8): offsets ((i + 0.5)/n, (j + 0.5)/n);
 *   - the standard patterns of D3D = Vulkan (2x, 4x, 8x, 16x), given in 1/16 px
 *     from the centre: offset = 0.5 + table / 16. D3D measures y downward; we
 *     read the table's y in our y-up screen space as it is, so on screen the
 *     pattern is D3D's mirrored top-to-bottom. Flipping instead would move
 *     16x's (−7, −8) to y = 1.0, onto the next pixel's edge: the tables span
 *     −8..7 and are only half-open the way D3D reads them.
 * Sample order is the order of the tables (it fixes the per-sample buffer layout).
 */
#ifndef RAS_SAMPLE_PATTERN_H
#define RAS_SAMPLE_PATTERN_H

#include "ras_error.h"
#include "ras_math.h"

#define RAS_MAX_SAMPLES 64

typedef enum ras_pattern_kind { RAS_PATTERN_ORDERED, RAS_PATTERN_STANDARD } ras_pattern_kind;

typedef struct ras_sample_pattern {
    ras_pattern_kind kind;
    int count;                        /* samples per pixel: 1, 2, 4, 8, 16, 64 */
    vec2s offsets[RAS_MAX_SAMPLES];   /* from the pixel's lower-left corner, in pixels */
} ras_sample_pattern;

/* One sample at the pixel centre (no anti-aliasing). */
ras_sample_pattern ras_sample_pattern_center(void);

/* ORDERED accepts 1, 4, 16, 64 (1×1, 2×2, 4×4, 8×8); STANDARD accepts 1, 2, 4,
 * 8, 16. Anything else is an error naming the counts that work. */
bool ras_sample_pattern_make(ras_pattern_kind kind, int count, ras_sample_pattern *out,
                             ras_error *err);

const char *ras_pattern_kind_name(ras_pattern_kind kind);

#endif
