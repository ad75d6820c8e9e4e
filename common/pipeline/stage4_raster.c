/* stage4_raster.c — the range every rasterizer may be handed (the
 * rasterizers themselves are the hw2 student's and the reference's; see
 * stage4_raster.h). */
#include "stage4_raster.h"

bool ras_raster_check_range(const ras_triangle *t, ras_error *err) {
    if (ras_raster_in_range(t)) return true;
    for (int i = 0; i < 3; i++) {
        float x = t->v[i].x, y = t->v[i].y;
        if (x >= -RAS_RASTER_MAX_COORD && x <= RAS_RASTER_MAX_COORD &&
            y >= -RAS_RASTER_MAX_COORD && y <= RAS_RASTER_MAX_COORD)
            continue;
        return ras_error_set(err,
                             "triangle corner %d at screen (%.9g, %.9g) px is outside the "
                             "rasterizer's exact range of +-%.0f px in x and y "
                             "(stage4_raster.h): the triangle is refused, not drawn. Clip it "
                             "first (ras_clip_triangle keeps corners within the guard band)",
                             i, (double)x, (double)y, (double)RAS_RASTER_MAX_COORD);
    }
    return false;
}
