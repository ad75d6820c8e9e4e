/* ras_png.h — PNG files through libpng directly, exactly as OpenCV 4.6 did them.
 *
 * PNG is the format every program reads and writes (textures, -o, the
 * reference images), so it is done here with libpng (0.3 M instructions to
 * load) instead of through OpenCV's imgcodecs, whose Debian build pulls in
 * GDAL and some 140 libraries before main (common/README.md, "What is loaded
 * when"). Every other
 * format goes through the OpenCV bridge (cv_bridge.h), loaded on first use.
 *
 * The encoder makes the same bytes OpenCV 4.6's imencode(".png") made for an
 * 8-bit 3-channel image: zlib level 1 (Z_BEST_SPEED), the Z_RLE strategy, the
 * SUB row filter, no other chunks. The decoder asks libpng for the same
 * transformations as imdecode(IMREAD_COLOR): 16 bits stripped to their high
 * byte, alpha dropped (not blended), palettes and low-bit greys expanded,
 * grey copied into R, G and B, interlacing undone. Both link the same libpng
 * and zlib OpenCV links, so files and pixels are byte-identical.
 *
 * Errors come back as NULL plus a message in `err`; libpng's warnings about a
 * file that still decodes go to stderr as libpng's own handler prints them
 * ("libpng warning: ..."), and are dropped when the decode fails.
 */
#ifndef RAS_PNG_H
#define RAS_PNG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* True when the bytes start with the PNG signature. */
bool ras_png_is_png(const uint8_t *data, size_t len);

/* 8-bit RGB, row-major, top row first → a malloc'ed PNG file image the caller
 * frees; *len its size. */
uint8_t *ras_png_encode_rgb8(int width, int height, const uint8_t *rgb, size_t *len, char *err,
                             int err_size);

/* A PNG file image → a malloc'ed 8-bit RGB buffer the caller frees. Refuses
 * images over OpenCV's decoder limits (OPENCV_IO_MAX_IMAGE_PIXELS, default
 * 2^30 pixels; 2^20 per side), with the bridge's message.
 * A PNG with an eXIf chunk (rare) is left to OpenCV, which turns the picture
 * as its EXIF orientation says: NULL, *exif true, nothing in err and nothing
 * printed; the caller decodes it through cv_bridge_decode_rgb8. */
uint8_t *ras_png_decode_rgb8(const uint8_t *data, size_t len, int *width, int *height, bool *exif,
                             char *err, int err_size);

#endif
