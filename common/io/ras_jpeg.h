/* ras_jpeg.h — JPEG files read through libjpeg directly, bounded before and
 * while they decode.
 *
 * A JPEG's true size is what libjpeg's own jpeg_read_header finds (it skips
 * junk bytes before the frame header that a hand-written marker walk gives up
 * on), so the size is read with that call, checked, and only then are pixels
 * decoded. A progressive JPEG may carry any number of scans, each a pass over
 * every block: 2,000 empty ones took 17 CPU seconds on an 8192² frame. The
 * decode counts scans (RAS_JPEG_MAX_SCANS), watches a deadline, and holds
 * libjpeg's own allocations under a byte cap; past any of them it stops with
 * a message naming the limit.
 *
 * Pixels are those OpenCV 4.6's imdecode(IMREAD_COLOR) gives (the same libjpeg,
 * the same default settings: islow DCT, fancy upsampling; grey copied to R, G
 * and B; Adobe CMYK converted as OpenCV converts it; the EXIF orientation of
 * the first APP1 applied as OpenCV applies it): 8-bit RGB, row-major, top row
 * first, 3 bytes a pixel. Errors come back as NULL plus a message in `err`.
 */
#ifndef RAS_JPEG_H
#define RAS_JPEG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h> /* struct timespec */

/* More scans than any encoder writes (libjpeg's own progressive script has
 * 10, an optimised one a few dozen); a file with more is refused. */
#define RAS_JPEG_MAX_SCANS 256

/* True when the bytes start like a JPEG file (SOI and a marker: FF D8 FF),
 * the signature OpenCV's decoder uses. */
bool ras_jpeg_is_jpeg(const uint8_t *data, size_t len);

/* The size in the frame header, as libjpeg reads it (no pixel decoded).
 * False when libjpeg finds no frame header. */
bool ras_jpeg_peek_size(const uint8_t *data, size_t len, long *width, long *height);

/* What a decode may use. max_bytes bounds libjpeg's own working memory
 * (coefficient buffers of a progressive file); deadline is CLOCK_MONOTONIC
 * ({0, 0}: none). */
typedef struct ras_jpeg_limits {
    size_t max_bytes;
    struct timespec deadline;
    double seconds; /* the limit the deadline came from, for the message */
} ras_jpeg_limits;

/* A JPEG file image → a malloc'ed 8-bit RGB buffer the caller frees. */
uint8_t *ras_jpeg_decode_rgb8(const uint8_t *data, size_t len, const ras_jpeg_limits *limits,
                              int *width, int *height, char *err, int err_size);

#endif
