/* ras_memory.h — the memory budget: large allocations are estimated and
 * checked before they are made.
 *
 * A small file can ask for a lot of memory: a 1 MB PNG of 32768² grey pixels
 * decodes to 3 GiB, a 3 KB scene of subdivided teapots to gigabytes of
 * triangles. Every large allocation (an image decode, read from the file's
 * header first; a texture and its mip chain; a mesh after subdivision and the
 * renderer's per-triangle data; per-sample frame buffers; the compare tool's
 * images) is estimated up front and refused when the estimate is over the
 * limit, with a message naming what was asked, the estimate and the limit.
 *
 * The limit, in order of precedence:
 *   - --memory-limit MB on the command line (ras_memory_set_limit_mb);
 *   - the environment variable RAS_MEMORY_LIMIT_MB;
 *   - the default: half of physical memory, at most 2 GiB.
 * Never above what the process's address-space limit (RLIMIT_AS, ulimit -v)
 * leaves after the libraries: 3/4 of (RLIMIT_AS - 320 MiB).
 *
 * OpenCV's own decoder limit, OPENCV_IO_MAX_IMAGE_PIXELS, is read once when
 * libopencv_imgcodecs loads; OpenCV is a module opened on first use
 * (cv_bridge_load.c), which sets it first to the budget's worth of pixels
 * (at most 2^28) unless the user exported another. ras_image reads the size
 * from the header of every format it accepts, by its decoder's rules
 * (ras_image_peek_size), before any pixel is decoded.
 */
#ifndef RAS_MEMORY_H
#define RAS_MEMORY_H

#include "ras_error.h"

#include <stddef.h> /* size_t */

#define RAS_MEMORY_DEFAULT_CAP_MB 2048u /* the default is at most 2 GiB */
#define RAS_MEMORY_MIN_MB 16u           /* smaller limits are refused */
#define RAS_MEMORY_MAX_MB (1u << 24)    /* 16 TiB: larger is a typo */

/* Estimated bytes per pixel of decoding an image: OpenCV's BGR decode (3)
 * and the RGB copy (3) (libpng writes the RGB bytes directly, but a PNG
 * with EXIF goes to OpenCV). A JPEG: the RGB output (3) and libjpeg's own
 * memory, bounded by what is left (7): a progressive file keeps every
 * coefficient, 2 bytes each, 3 components at 4:4:4 (6), and its buffers. */
#define RAS_MEMORY_DECODE_BYTES_PER_PIXEL 6.0
#define RAS_MEMORY_JPEG_DECODE_BYTES_PER_PIXEL 10.0
/* Estimated bytes per pixel of an image being loaded as floats
 * (ras_image_load): the decode (6), and the caller's float copy with mips
 * (16). A texture keeps the decoder's RGB bytes instead (ras_texture.h): its
 * load needs the decode alone, and it then holds 3 bytes a pixel, and 4 more
 * once trilinear filtering builds its float mips. */
#define RAS_MEMORY_BYTES_PER_LOADED_PIXEL 22.0
/* Estimated bytes the renderers (teaching pipeline and fast path) hold per
 * triangle and per vertex of a mesh, beyond the mesh itself: measured peak
 * RSS / triangle count on 2.1 M-triangle spheres and 1 M-triangle teapots is
 * 530-600 bytes (docs/robustness.md). */
#define RAS_MEMORY_RENDER_BYTES_PER_TRIANGLE 600.0
/* per vertex: the clip vertex (96 bytes since it carries its position in
 * double, stage1_vertex.h) and the fast path's screen position and codes */
#define RAS_MEMORY_RENDER_BYTES_PER_VERTEX 112.0

/* Estimated bytes per pixel of writing the frame's picture: OpenCV's BGR
 * copy of the 8-bit image (3) and the encoder's output (at most about 3).
 * Measured peak RSS of hw2 at 2048² and 4096² is 33.4-33.9 bytes per pixel
 * against the 31 the frame's buffers alone were counted at. */
#define RAS_MEMORY_ENCODE_BYTES_PER_PIXEL 6.0
/* --dump: the buffers built and encoded beside the frame (sample colour,
 * depth and coverage per sample, their pictures, the per-pixel ones).
 * Measured: hw3 at 1024² with 16 samples peaks 668 MB above the same frame
 * without --dump, 39.8 bytes per sample. */
#define RAS_MEMORY_DUMP_BYTES_PER_SAMPLE 44.0
#define RAS_MEMORY_DUMP_BYTES_PER_PIXEL 32.0

/* The limit in bytes, and a few words saying where it comes from
 * ("the default, half of physical memory capped at 2 GiB", "--memory-limit",
 * "RAS_MEMORY_LIMIT_MB", "the address-space limit (ulimit -v)"). */
size_t ras_memory_limit(void);
const char *ras_memory_limit_source(void);

/* --memory-limit MB: a whole number of MiB, RAS_MEMORY_MIN_MB..MAX_MB.
 * False and err for anything else. */
bool ras_memory_set_limit_mb(const char *text, ras_error *err);

/* Checks the environment variable RAS_MEMORY_LIMIT_MB (programs call it
 * once, so a bad value is an error rather than silently ignored). */
bool ras_memory_check_env(ras_error *err);

/* Estimated bytes held by long-lived objects (a scene's meshes and
 * textures): ras_memory_check counts them against the limit too, so a texture
 * loaded after a million triangles sees what is left. */
void ras_memory_commit(double bytes);
void ras_memory_release(double bytes);

/* True when `bytes` (an estimate) plus what is committed fits the limit. Otherwise false and err:
 * "WHAT needs about N MiB, over the memory limit of L MiB (SOURCE); HINT, or
 * raise the limit with --memory-limit MB (or RAS_MEMORY_LIMIT_MB)". */
bool ras_memory_check(double bytes, const char *what, const char *hint, ras_error *err);

#endif
