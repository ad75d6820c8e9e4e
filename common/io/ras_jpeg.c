/* ras_jpeg.c — see ras_jpeg.h. The libjpeg calls follow OpenCV 4.6's
 * JpegDecoder::readHeader/readData (modules/imgcodecs/src/grfmt_jpeg.cpp),
 * in the same order, with RGB out instead of BGR, plus the limits. */
#include "ras_jpeg.h"

#include <setjmp.h> /* setjmp, longjmp */
#include <stdio.h>  /* snprintf, fputs; FILE, which jpeglib.h needs first */
#include <stdlib.h> /* malloc, free */
#include <string.h> /* memcmp, memcpy */

#include <jpeglib.h>
#include <jerror.h> /* JWRN_JPEG_EOF */

/* libjpeg's error manager, extended: a longjmp back to the caller instead of
 * exit(), the message that ended the work, the warnings before it, and the
 * limits the progress monitor checks. */
typedef struct {
    struct jpeg_error_mgr pub;
    struct jpeg_progress_mgr progress;
    jmp_buf back;
    char error[320];
    char warnings[512];
    size_t warnings_len;
    const ras_jpeg_limits *limits;
    void (*default_emit)(j_common_ptr, int);
    bool own_words; /* error is a whole sentence of ours, not libjpeg's */
} jpeg_ctx;

static void on_error(j_common_ptr cinfo) {
    jpeg_ctx *c = (jpeg_ctx *)cinfo->err;
    if (!c->error[0]) (*cinfo->err->format_message)(cinfo, c->error);
    longjmp(c->back, 1);
}

/* Warnings (corrupt data that still decodes) are kept, and printed as
 * OpenCV's libjpeg printed them only when the decode succeeds; a file with
 * thousands of them prints the first few. */
static void on_message(j_common_ptr cinfo) {
    jpeg_ctx *c = (jpeg_ctx *)cinfo->err;
    char line[JMSG_LENGTH_MAX];
    (*cinfo->err->format_message)(cinfo, line);
    size_t room = sizeof c->warnings - c->warnings_len;
    int n = snprintf(c->warnings + c->warnings_len, room, "%s\n", line);
    if (n > 0) c->warnings_len += (size_t)n < room ? (size_t)n : room - 1;
}

/* A file cut short is only a warning to libjpeg, which fills the rest of the
 * picture with grey and goes on; a truncated PNG is refused, so this is too:
 * a texture or a reference with half its pixels invented must not pass. */
static void on_emit(j_common_ptr cinfo, int msg_level) {
    jpeg_ctx *c = (jpeg_ctx *)cinfo->err;
    if (msg_level < 0 && cinfo->err->msg_code == JWRN_JPEG_EOF) {
        snprintf(c->error, sizeof c->error,
                 "it is cut short: the file ends before its image data does (libjpeg: "
                 "\"Premature end of JPEG file\"); expected a complete JPEG — copy or export "
                 "the file again");
        c->own_words = true;
        longjmp(c->back, 1);
    }
    c->default_emit(cinfo, msg_level);
}

static bool past(const struct timespec *deadline) {
    if (!deadline->tv_sec && !deadline->tv_nsec) return false;
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return now.tv_sec > deadline->tv_sec ||
           (now.tv_sec == deadline->tv_sec && now.tv_nsec >= deadline->tv_nsec);
}

/* Called by libjpeg every few rows of every scan: where the scan count and
 * the deadline are enforced (djpeg's -maxscans does the same). */
static void on_progress(j_common_ptr cinfo) {
    jpeg_ctx *c = (jpeg_ctx *)cinfo->err;
    j_decompress_ptr d = (j_decompress_ptr)cinfo;
    if (d->input_scan_number > RAS_JPEG_MAX_SCANS) {
        snprintf(c->error, sizeof c->error,
                 "it has more than %d scans (a progressive JPEG with that many is built to "
                 "take minutes to decode); expected at most %d — re-save it as a baseline JPEG "
                 "or a PNG",
                 RAS_JPEG_MAX_SCANS, RAS_JPEG_MAX_SCANS);
        longjmp(c->back, 1);
    }
    if (c->limits && past(&c->limits->deadline)) {
        snprintf(c->error, sizeof c->error,
                 "decoding took longer than the limit of %g s (RAS_IMAGE_DECODE_SECONDS); "
                 "expected an image that decodes in time — use a smaller or simpler image, or "
                 "raise RAS_IMAGE_DECODE_SECONDS",
                 c->limits->seconds);
        longjmp(c->back, 1);
    }
}

bool ras_jpeg_is_jpeg(const uint8_t *data, size_t len) {
    return len >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF;
}

/* The decompressor, set up on the bytes; the caller's setjmp must come first. */
static void start(struct jpeg_decompress_struct *cinfo, jpeg_ctx *c, const uint8_t *data,
                  size_t len) {
    cinfo->err = jpeg_std_error(&c->pub);
    c->pub.error_exit = on_error;
    c->pub.output_message = on_message;
    c->default_emit = c->pub.emit_message;
    c->pub.emit_message = on_emit;
    jpeg_create_decompress(cinfo);
    jpeg_mem_src(cinfo, data, (unsigned long)len);
}

bool ras_jpeg_peek_size(const uint8_t *data, size_t len, long *width, long *height) {
    if (!ras_jpeg_is_jpeg(data, len)) return false;
    struct jpeg_decompress_struct cinfo;
    jpeg_ctx c = {0};
    if (setjmp(c.back)) {
        jpeg_destroy_decompress(&cinfo);
        return false;
    }
    start(&cinfo, &c, data, len);
    bool ok = jpeg_read_header(&cinfo, TRUE) == JPEG_HEADER_OK;
    if (ok) {
        *width = (long)cinfo.image_width;
        *height = (long)cinfo.image_height;
    }
    jpeg_destroy_decompress(&cinfo);
    return ok;
}

/* The orientation (1..8) in the EXIF of the first APP1 marker, read as
 * OpenCV's ExifReader reads it (TIFF header 6 bytes in, IFD0, the first
 * 0x0112 entry); 1 when there is none. */
static int exif_orientation(const struct jpeg_decompress_struct *cinfo) {
    jpeg_saved_marker_ptr m = cinfo->marker_list;
    while (m && m->marker != JPEG_APP0 + 1) m = m->next;
    if (!m || m->data_length < 14) return 1;
    const uint8_t *t = m->data + 6;
    size_t n = m->data_length - 6;
    bool le = t[0] == 'I' && t[1] == 'I';
    if (!le && !(t[0] == 'M' && t[1] == 'M')) return 1;
#define U16(p) (le ? (unsigned)((p)[0] | (p)[1] << 8) : (unsigned)((p)[0] << 8 | (p)[1]))
#define U32(p) (le ? ((uint32_t)(p)[0] | (uint32_t)(p)[1] << 8 | (uint32_t)(p)[2] << 16 | (uint32_t)(p)[3] << 24) \
                   : ((uint32_t)(p)[0] << 24 | (uint32_t)(p)[1] << 16 | (uint32_t)(p)[2] << 8 | (uint32_t)(p)[3]))
    if (U16(t + 2) != 42) return 1;
    uint32_t off = U32(t + 4);
    if ((size_t)off + 2 > n) return 1;
    unsigned count = U16(t + off);
    for (unsigned k = 0; k < count && (size_t)off + 2 + 12 * ((size_t)k + 1) <= n; k++) {
        const uint8_t *e = t + off + 2 + 12 * k;
        if (U16(e) == 0x0112) {
            unsigned v = U16(e + 8);
            return v >= 1 && v <= 8 ? (int)v : 1;
        }
    }
#undef U16
#undef U32
    return 1;
}

/* OpenCV's ApplyExifOrientation: a transpose for 5..8, then flips. */
static uint8_t *orient(uint8_t *rgb, int *width, int *height, int o) {
    if (o == 1) return rgb;
    int w = *width, h = *height;
    bool transpose = o >= 5;
    int ow = transpose ? h : w, oh = transpose ? w : h;
    bool flip_x = o == 2 || o == 3 || o == 6 || o == 7;
    bool flip_y = o == 3 || o == 4 || o == 7 || o == 8;
    uint8_t *out = malloc((size_t)w * (size_t)h * 3);
    if (!out) {
        free(rgb);
        return NULL;
    }
    for (int r = 0; r < oh; r++)
        for (int col = 0; col < ow; col++) {
            int sr = flip_y ? oh - 1 - r : r, sc = flip_x ? ow - 1 - col : col;
            int src_r = transpose ? sc : sr, src_c = transpose ? sr : sc;
            memcpy(out + ((size_t)r * (size_t)ow + (size_t)col) * 3,
                   rgb + ((size_t)src_r * (size_t)w + (size_t)src_c) * 3, 3);
        }
    free(rgb);
    *width = ow;
    *height = oh;
    return out;
}

uint8_t *ras_jpeg_decode_rgb8(const uint8_t *data, size_t len, const ras_jpeg_limits *limits,
                              int *width, int *height, char *err, int err_size) {
    struct jpeg_decompress_struct cinfo;
    jpeg_ctx c = {0};
    c.limits = limits;
    uint8_t *volatile rgb = NULL;
    uint8_t *volatile row = NULL;
    if (setjmp(c.back)) {
        jpeg_destroy_decompress(&cinfo);
        free(rgb);
        free(row);
        if (err && err_size > 0)
            snprintf(err, (size_t)err_size, "%s%s",
                     c.own_words || strstr(c.error, "scans") || strstr(c.error, "limit")
                         ? ""
                         : "not a JPEG libjpeg can decode, or a damaged one: libjpeg says ",
                     c.error);
        return NULL;
    }
    start(&cinfo, &c, data, len);
    if (limits && limits->max_bytes) cinfo.mem->max_memory_to_use = (long)limits->max_bytes;
    c.progress.progress_monitor = on_progress;
    cinfo.progress = &c.progress;
    jpeg_save_markers(&cinfo, JPEG_APP0 + 1, 0xFFFF);
    if (jpeg_read_header(&cinfo, TRUE) != JPEG_HEADER_OK) {
        snprintf(c.error, sizeof c.error, "it has no image (only tables)");
        longjmp(c.back, 1);
    }
    bool cmyk = cinfo.num_components == 4;
    cinfo.out_color_space = cmyk ? JCS_CMYK : JCS_RGB;
    jpeg_start_decompress(&cinfo);
    int w = (int)cinfo.output_width, h = (int)cinfo.output_height;
    rgb = malloc((size_t)w * (size_t)h * 3);
    row = cmyk ? malloc((size_t)w * 4) : NULL;
    if (!rgb || (cmyk && !row)) {
        snprintf(c.error, sizeof c.error, "out of memory for a %dx%d image", w, h);
        longjmp(c.back, 1);
    }
    while (cinfo.output_scanline < cinfo.output_height) {
        uint8_t *dst = rgb + (size_t)cinfo.output_scanline * (size_t)w * 3;
        JSAMPROW line = cmyk ? row : dst;
        jpeg_read_scanlines(&cinfo, &line, 1);
        if (cmyk) /* icvCvt_CMYK2BGR_8u_C4C3R, into RGB order */
            for (int x = 0; x < w; x++) {
                int cc = row[4 * x], m = row[4 * x + 1], y = row[4 * x + 2], k = row[4 * x + 3];
                dst[3 * x] = (uint8_t)(k - ((255 - cc) * k >> 8));
                dst[3 * x + 1] = (uint8_t)(k - ((255 - m) * k >> 8));
                dst[3 * x + 2] = (uint8_t)(k - ((255 - y) * k >> 8));
            }
    }
    int o = exif_orientation(&cinfo); /* before finish, which frees the saved markers */
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    free(row);
    if (c.warnings_len) fputs(c.warnings, stderr);
    uint8_t *out = orient(rgb, &w, &h, o);
    if (!out && err && err_size > 0) snprintf(err, (size_t)err_size, "out of memory decoding image");
    *width = w;
    *height = h;
    return out;
}
