/* ras_png.c — see ras_png.h. The libpng calls are the ones OpenCV 4.6's
 * PngEncoder::write and PngDecoder::readHeader/readData make (modules/
 * imgcodecs/src/grfmt_png.cpp), in the same order, minus the BGR swap. */
#include "ras_png.h"

#include <png.h>
#include <zlib.h> /* Z_BEST_SPEED, Z_RLE */

#include <stdio.h>  /* snprintf, fputs */
#include <stdlib.h> /* malloc, realloc, free, getenv, strtoull */
#include <string.h> /* memcpy, memcmp, strcmp */

/* What libpng said: the error that ended the work, and the warnings before. */
typedef struct {
    char error[256];
    char warnings[1024];
    size_t warnings_len;
} png_messages;

static void on_error(png_structp png, png_const_charp msg) {
    png_messages *m = png_get_error_ptr(png);
    snprintf(m->error, sizeof m->error, "%s", msg);
    png_longjmp(png, 1);
}

/* libpng's default handler prints "libpng warning: <msg>" to stderr, which is
 * what OpenCV passed on; kept until the decode is known to succeed. */
static void on_warning(png_structp png, png_const_charp msg) {
    png_messages *m = png_get_error_ptr(png);
    size_t room = sizeof m->warnings - m->warnings_len;
    int n = snprintf(m->warnings + m->warnings_len, room, "libpng warning: %s\n", msg);
    if (n > 0) m->warnings_len += (size_t)n < room ? (size_t)n : room - 1;
}

static void set_err(char *err, int err_size, const char *msg) {
    if (err && err_size > 0) snprintf(err, (size_t)err_size, "%s", msg);
}

bool ras_png_is_png(const uint8_t *data, size_t len) {
    return len >= 8 && !memcmp(data, "\x89PNG\r\n\x1a\n", 8);
}

/* ------------------------------------------------------------------------ */
/* Encoding                                                                  */

typedef struct {
    uint8_t *data;
    size_t len, cap;
    bool failed;
} png_sink;

static void write_to_sink(png_structp png, png_bytep bytes, size_t n) {
    png_sink *s = png_get_io_ptr(png);
    if (s->len + n > s->cap) {
        size_t cap = s->cap ? s->cap : 65536;
        while (cap < s->len + n)
            cap *= 2;
        uint8_t *grown = realloc(s->data, cap);
        if (!grown) {
            s->failed = true;
            png_error(png, "out of memory for the encoded image");
        }
        s->data = grown;
        s->cap = cap;
    }
    memcpy(s->data + s->len, bytes, n);
    s->len += n;
}

static void flush_sink(png_structp png) { (void)png; }

uint8_t *ras_png_encode_rgb8(int width, int height, const uint8_t *rgb, size_t *len, char *err,
                             int err_size) {
    png_messages msgs = {0};
    png_sink sink = {0};
    png_bytep *rows = malloc((size_t)(height > 0 ? height : 1) * sizeof *rows);
    png_structp png =
        rows ? png_create_write_struct(PNG_LIBPNG_VER_STRING, &msgs, on_error, on_warning) : NULL;
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_write_struct(&png, NULL);
        free(rows);
        set_err(err, err_size, "out of memory for the PNG encoder");
        return NULL;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        free(rows);
        free(sink.data);
        char msg[320];
        snprintf(msg, sizeof msg, "the PNG encoder failed: %s", msgs.error);
        set_err(err, err_size, msg);
        return NULL;
    }
    png_set_write_fn(png, &sink, write_to_sink, flush_sink);
    /* OpenCV's defaults when no compression level is asked for: "tune
     * parameters for speed". */
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_compression_level(png, Z_BEST_SPEED);
    png_set_compression_strategy(png, Z_RLE); /* IMWRITE_PNG_STRATEGY_RLE */
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < height; y++)
        rows[y] = (png_bytep)rgb + (size_t)y * (size_t)width * 3;
    png_write_image(png, rows);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    free(rows);
    *len = sink.len;
    return sink.data;
}

/* ------------------------------------------------------------------------ */
/* Decoding                                                                  */

typedef struct {
    const uint8_t *data;
    size_t len, pos;
} png_source;

static void read_from_source(png_structp png, png_bytep out, size_t n) {
    png_source *s = png_get_io_ptr(png);
    if (n > s->len - s->pos) png_error(png, "PNG input buffer is incomplete");
    memcpy(out, s->data + s->pos, n);
    s->pos += n;
}

/* OpenCV's configuration parameter: digits, optionally followed by KB or MB
 * (utils::getConfigurationParameterSizeT); `fallback` when unset or unparsable. */
static unsigned long long size_parameter(const char *name, unsigned long long fallback) {
    const char *v = getenv(name);
    if (!v || *v < '0' || *v > '9') return fallback;
    char *end;
    unsigned long long n = strtoull(v, &end, 10);
    if (!*end) return n;
    if (!strcmp(end, "KB") || !strcmp(end, "Kb") || !strcmp(end, "kb")) return n * 1024;
    if (!strcmp(end, "MB") || !strcmp(end, "Mb") || !strcmp(end, "mb")) return n * 1024 * 1024;
    return fallback;
}

/* The state setjmp must not lose: kept outside the function's registers. */
typedef struct {
    png_structp png;
    png_infop info, end;
    png_bytep *rows;
    uint8_t *rgb;
} png_decode;

static void decode_free(png_decode *d) {
    png_destroy_read_struct(&d->png, &d->info, &d->end);
    free(d->rows);
    free(d->rgb);
}

uint8_t *ras_png_decode_rgb8(const uint8_t *data, size_t len, int *width, int *height, bool *exif,
                             char *err, int err_size) {
    *exif = false;
    png_messages msgs = {0};
    png_source src = {data, len, 0};
    png_decode d = {0};
    d.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &msgs, on_error, on_warning);
    d.info = d.png ? png_create_info_struct(d.png) : NULL;
    d.end = d.info ? png_create_info_struct(d.png) : NULL;
    if (!d.end) {
        decode_free(&d);
        set_err(err, err_size, "out of memory for the PNG decoder");
        return NULL;
    }
    png_decode *volatile dp = &d;
    if (setjmp(png_jmpbuf(d.png))) {
        decode_free(dp);
        char msg[400];
        snprintf(msg, sizeof msg, "not a PNG libpng can decode, or a damaged one (libpng: %s)",
                 msgs.error);
        set_err(err, err_size, msg);
        return NULL;
    }
    png_set_read_fn(d.png, &src, read_from_source);
    png_read_info(d.png, d.info);
    png_uint_32 w = 0, h = 0;
    int bit_depth = 0, color_type = 0;
    png_get_IHDR(d.png, d.info, &w, &h, &bit_depth, &color_type, NULL, NULL, NULL);
    /* imdecode's validateInputImageSize, between the header and the pixels. */
    unsigned long long max_pixels = size_parameter("OPENCV_IO_MAX_IMAGE_PIXELS", 1ull << 30);
    if (w == 0 || h == 0 || w > size_parameter("OPENCV_IO_MAX_IMAGE_WIDTH", 1u << 20) ||
        h > size_parameter("OPENCV_IO_MAX_IMAGE_HEIGHT", 1u << 20) ||
        (unsigned long long)w * h > max_pixels) {
        decode_free(&d);
        const char *limit = getenv("OPENCV_IO_MAX_IMAGE_PIXELS");
        char msg[400];
        snprintf(msg, sizeof msg,
                 "its header announces more pixels than the decoder limit "
                 "(OPENCV_IO_MAX_IMAGE_PIXELS=%s, set from the memory limit); use a smaller "
                 "image or raise the limit with --memory-limit MB",
                 limit ? limit : "?");
        set_err(err, err_size, msg);
        return NULL;
    }
    /* PngDecoder::readData for a 3-channel 8-bit image. */
    if (bit_depth == 16) png_set_strip_16(d.png);
    png_set_strip_alpha(d.png);
    if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(d.png);
    if ((color_type & PNG_COLOR_MASK_COLOR) == 0 && bit_depth < 8)
        png_set_expand_gray_1_2_4_to_8(d.png);
    if ((color_type & PNG_COLOR_MASK_COLOR) == 0) png_set_gray_to_rgb(d.png);
    png_set_interlace_handling(d.png);
    png_read_update_info(d.png, d.info);
    if (png_get_rowbytes(d.png, d.info) != (size_t)w * 3) png_error(d.png, "unexpected row size");
    d.rows = malloc((size_t)h * sizeof *d.rows);
    d.rgb = malloc((size_t)w * (size_t)h * 3);
    if (!d.rows || !d.rgb) png_error(d.png, "out of memory decoding image");
    for (png_uint_32 y = 0; y < h; y++)
        d.rows[y] = d.rgb + (size_t)y * (size_t)w * 3;
    png_read_image(d.png, d.rows);
    png_read_end(d.png, d.end);
    /* imdecode turns the picture by the orientation of an eXIf chunk (before
     * or after the pixels), read with OpenCV's own EXIF parser: such a file
     * goes to OpenCV whole, so what it does with any EXIF is what happens. */
    if (png_get_valid(d.png, d.info, PNG_INFO_eXIf) || png_get_valid(d.png, d.end, PNG_INFO_eXIf)) {
        decode_free(&d);
        *exif = true;
        return NULL;
    }
    if (msgs.warnings_len) fputs(msgs.warnings, stderr);
    uint8_t *rgb = d.rgb;
    d.rgb = NULL;
    decode_free(&d);
    *width = (int)w;
    *height = (int)h;
    return rgb;
}
