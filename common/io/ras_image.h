/* ras_image.h — a float RGB image, and reading/writing it as PNG.
 *
 * Conventions (stated once, as stb does):
 *   - pixels are vec3s RGB in [0, 1]; 8-bit only at file I/O (rounded, clamped);
 *   - memory is row-major, row 0 is the TOP row of the picture, no padding:
 *     pixel (col, row) is pixels[row * width + col];
 *   - screen space has y growing upward, so screen pixel (x, y) lands in image
 *     row height-1-y (see ras_framebuffer for that mapping);
 *   - files are written atomically (ras_io_write_atomic): encoded in memory,
 *     written to a temporary name beside the target, checked, read back,
 *     decoded, then renamed, so a failed write (disk full, a file-size limit,
 *     a signal) never leaves a half-written file and never harms the old one.
 * Ownership: ras_image_create/ras_image_load return a heap image the caller
 * frees with ras_image_destroy (NULL is allowed and ignored).
 */
#ifndef RAS_IMAGE_H
#define RAS_IMAGE_H

#include "ras_error.h"
#include "ras_math.h"

#include <stddef.h> /* size_t */
#include <stdint.h> /* uint8_t */

typedef struct ras_image {
    int width, height;
    vec3s *pixels; /* width * height, top row first */
} ras_image;

/* Largest side we accept: protects against absurd sizes from flags or files. */
#define RAS_IMAGE_MAX_SIDE 16384
/* Largest image file read (its bytes are held in memory while decoding). */
#define RAS_IMAGE_MAX_FILE_BYTES (512u << 20)

/* A black image, or NULL (and err set) for a size outside 1..RAS_IMAGE_MAX_SIDE. */
ras_image *ras_image_create(int width, int height, ras_error *err);
void ras_image_destroy(ras_image *img);
ras_image *ras_image_clone(const ras_image *img);

static inline vec3s ras_image_get(const ras_image *img, int col, int row) {
    return img->pixels[row * img->width + col];
}
static inline void ras_image_set(ras_image *img, int col, int row, vec3s c) {
    img->pixels[row * img->width + col] = c;
}

void ras_image_fill(ras_image *img, vec3s c);

/* 8-bit RGB, row-major top row first, 3 bytes per pixel; caller owns `rgb`
 * (width*height*3 bytes). */
void ras_image_to_rgb8(const ras_image *img, uint8_t *rgb);

/* One channel value in [0,1] to a byte, rounding to nearest, clamping. */
uint8_t ras_unit_to_byte(float v);

/* Whether ras_image_save could write `path`, checked before any work: the
 * name has an image extension (.png, .jpg/.jpeg, .bmp, .ppm, .tif/.tiff)
 * that this OpenCV can encode, its folder exists, and it is not a folder
 * itself. Otherwise false, and err names the path, what was expected and what
 * to do. Programs call it right after parsing -o, so a bad name costs no
 * render and leaves nothing behind. */
bool ras_image_check_output(const char *path, ras_error *err);

/* Writes a PNG (or another extension ras_image_check_output accepts)
 * atomically: on any failure (err names the file and the reason) the target is
 * left as it was and no temporary file remains. */
bool ras_image_save(const ras_image *img, const char *path, ras_error *err);

/* The same for an 8-bit RGB buffer (see ras_image_to_rgb8's layout). */
bool ras_image_save_rgb8(const uint8_t *rgb, int width, int height, const char *path,
                         ras_error *err);

/* The image formats read, decided by a file's content (never its name):
 * those whose true size a complete header parser (or the decoder's own
 * header call) reads before any pixel is decoded. */
typedef enum ras_image_format {
    RAS_IMAGE_UNKNOWN,
    RAS_IMAGE_PNG,  /* libpng (ras_png.h) */
    RAS_IMAGE_JPEG, /* libjpeg (ras_jpeg.h): baseline and progressive */
    RAS_IMAGE_BMP,  /* OpenCV */
    RAS_IMAGE_PNM,  /* P1..P6, OpenCV */
    RAS_IMAGE_TIFF, /* classic and BigTIFF, OpenCV (libtiff) */
} ras_image_format;
#define RAS_IMAGE_ACCEPTED "PNG, JPEG, BMP, PBM/PGM/PPM or TIFF"

/* Seconds a decode may take (RAS_IMAGE_DECODE_SECONDS overrides). */
#define RAS_IMAGE_DECODE_SECONDS_DEFAULT 20.0

ras_image_format ras_image_sniff(const uint8_t *data, size_t len);
const char *ras_image_format_name(ras_image_format format);

/* A format recognised but refused (Radiance HDR, OpenEXR, WebP, JPEG 2000,
 * PFM, PAM, Sun raster, GIF) as a phrase ("a WebP image"), else NULL. */
const char *ras_image_refused_format(const uint8_t *data, size_t len);

/* Reads an image of an accepted format; returns NULL and sets err when it
 * cannot. The file is read whole (at most RAS_IMAGE_MAX_FILE_BYTES), its
 * format taken from its content, its size from its header and checked against
 * RAS_IMAGE_MAX_SIDE and the memory budget (ras_memory.h) before any pixel is
 * decoded; the decode then runs under RAS_IMAGE_DECODE_SECONDS (a JPEG also
 * under RAS_JPEG_MAX_SCANS). Every refusal names the file and the limit. */
ras_image *ras_image_load(const char *path, ras_error *err);

/* The same file as 8-bit RGB, top row first (see ras_image_to_rgb8), in a
 * malloc'ed buffer the caller frees, for readers that store pixels their own
 * way (ras_texture_load): no float image in between. *width and *height are
 * in 1..RAS_IMAGE_MAX_SIDE; NULL and err as ras_image_load. */
uint8_t *ras_image_load_rgb8(const char *path, int *width, int *height, ras_error *err);
/* The same for a caller that makes `made_per_pixel` more bytes a pixel from
 * the RGB bytes while they are held (ras_image_load: 16, its floats and
 * mips; ras_texture_load: 0, the bytes are the texture): the budget check
 * before decoding counts the decode and that. */
uint8_t *ras_image_load_rgb8_making(const char *path, double made_per_pixel, int *width,
                                    int *height, ras_error *err);

/* The width and height an encoded image's header announces, read without
 * decoding pixels, by the rules its decoder reads them with: PNG (IHDR),
 * JPEG (libjpeg's jpeg_read_header: junk before the frame header is skipped
 * as the decoder skips it), BMP (info and OS/2 core headers), PNM P1..P6,
 * TIFF (classic and BigTIFF, the first directory). False for other data or
 * a header too short to say. */
bool ras_image_peek_size(const uint8_t *data, size_t len, long *width, long *height);

/* The same from the start of a file (regular files only, its first MiB);
 * false when it cannot be opened or its format is not one of those. */
bool ras_image_peek_file(const char *path, long *width, long *height);

/* One byte of a file to a channel value in [0, 1]: the one conversion every
 * reader uses, so a texture and an image of the same file hold the same floats. */
static inline float ras_byte_to_unit(uint8_t b) {
    return b / 255.0f;
}

#endif
