/* stage6_resolve.h — stage 6: from the sample buffers to the picture.
 *
 * With one sample per pixel there is nothing to resolve: the colour buffer is
 * copied (with the y-flip already in its layout) and the resolve hook does not
 * run. With several, the hw2 hook (resolve_pixel) turns each pixel's samples
 * into one colour.
 */
#ifndef RAS_STAGE6_RESOLVE_H
#define RAS_STAGE6_RESOLVE_H

#include "ras_image.h"
#include "stage4_raster.h"

/* `out` must have the framebuffer's size. Returns true when the hook ran. */
bool ras_resolve_frame(const ras_framebuffer *fb, ras_resolve_fn resolve, ras_image *out);

#endif
