/* ras_image.c — see ras_image.h. */
#include "ras_image.h"

#include "cv_bridge.h"
#include "ras_io.h"
#include "ras_job.h"
#include "ras_jpeg.h"
#include "ras_memory.h"
#include "ras_png.h"

#include <errno.h>    /* errno */
#include <limits.h>   /* NAME_MAX */
#include <stdio.h>    /* snprintf */
#include <stdlib.h>   /* calloc, free */
#include <string.h>   /* strrchr, strlen, strerror */
#include <strings.h>  /* strcasecmp */
#include <sys/stat.h> /* stat */
#include <time.h>     /* clock_gettime */
#include <unistd.h>   /* access, read, close */

static bool size_ok(int width, int height, ras_error *err) {
    if (width >= 1 && height >= 1 && width <= RAS_IMAGE_MAX_SIDE && height <= RAS_IMAGE_MAX_SIDE)
        return true;
    return ras_error_set(err, "image size %dx%d is out of range: expected 1..%d on each side",
                         width, height, RAS_IMAGE_MAX_SIDE);
}

ras_image *ras_image_create(int width, int height, ras_error *err) {
    if (!size_ok(width, height, err)) return NULL;
    ras_image *img = calloc(1, sizeof *img);
    if (!img) {
        ras_error_set(err, "out of memory for a %dx%d image", width, height);
        return NULL;
    }
    img->width = width;
    img->height = height;
    img->pixels = calloc((size_t)width * (size_t)height, sizeof *img->pixels);
    if (!img->pixels) {
        free(img);
        ras_error_set(err, "out of memory for a %dx%d image", width, height);
        return NULL;
    }
    return img;
}

void ras_image_destroy(ras_image *img) {
    if (!img) return;
    free(img->pixels);
    free(img);
}

ras_image *ras_image_clone(const ras_image *img) {
    ras_image *copy = ras_image_create(img->width, img->height, NULL);
    if (copy)
        memcpy(copy->pixels, img->pixels,
               (size_t)img->width * (size_t)img->height * sizeof *img->pixels);
    return copy;
}

void ras_image_fill(ras_image *img, vec3s c) {
    size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++) img->pixels[i] = c;
}

uint8_t ras_unit_to_byte(float v) {
    if (!(v > 0.0f)) return 0; /* also NaN → 0 */
    if (v >= 1.0f) return 255;
    return (uint8_t)(v * 255.0f + 0.5f);
}

void ras_image_to_rgb8(const ras_image *img, uint8_t *rgb) {
    size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++) {
        rgb[3 * i + 0] = ras_unit_to_byte(img->pixels[i].x);
        rgb[3 * i + 1] = ras_unit_to_byte(img->pixels[i].y);
        rgb[3 * i + 2] = ras_unit_to_byte(img->pixels[i].z);
    }
}

bool ras_image_check_output(const char *path, ras_error *err) {
    static const char *const formats[] = {".png", ".jpg", ".jpeg", ".bmp", ".ppm", ".tif", ".tiff"};
    if (!path || !*path)
        return ras_error_set(err, "expected an output file name such as out.png, got an "
                                  "empty name");
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *ext = strrchr(base, '.');
    if (!*base || !ext || ext == base) {
        return ras_error_set(err,
                             "cannot write '%s': expected a file name with an image extension "
                             "(e.g. '%s%s'), got %s",
                             path, path, *base ? ".png" : "out.png",
                             *base ? "a name without one" : "a folder name");
    }
    bool known = false;
    for (size_t i = 0; i < sizeof formats / sizeof *formats; i++)
        known |= strcasecmp(ext, formats[i]) == 0;
    /* PNG is written here (ras_png.h); other formats ask OpenCV, which is
     * loaded for it (cv_bridge.h). */
    if (known && strcasecmp(ext, ".png") != 0 && !cv_bridge_can_write(path) &&
        *cv_bridge_load_error())
        return ras_error_set(err,
                             "cannot write '%s': %s needs OpenCV, which could not be "
                             "loaded (%s); write a .png instead",
                             path, ext, cv_bridge_load_error());
    if (!known || (strcasecmp(ext, ".png") != 0 && !cv_bridge_can_write(path)))
        return ras_error_set(err,
                             "cannot write '%s': expected an image extension (.png, .jpg, "
                             ".bmp, .ppm or .tif), got '%s'; name the file e.g. '%.*s.png'",
                             path, ext, (int)(ext - path), path);
    /* Found now, not after the frame is drawn: a name the file system
     * cannot hold, and a link to nothing (the write would refuse it). */
    for (const char *part = path; *part;) {
        size_t n = strcspn(part, "/");
        if (n > NAME_MAX)
            return ras_error_set(err,
                                 "cannot write '%.60s...': its name has a part of %zu bytes; "
                                 "expected at most %d bytes between slashes — choose a "
                                 "shorter name",
                                 path, n, NAME_MAX);
        part += n + (part[n] == '/');
    }
    struct stat st;
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode) && stat(path, &st) != 0)
        return ras_error_set(err,
                             "cannot write '%s': it is a symbolic link to a file that does "
                             "not exist (%s); expected a regular file or a new name — "
                             "remove the link or write elsewhere",
                             path, strerror(errno));
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
        return ras_error_set(err,
                             "cannot write '%s': it is a folder; expected a file name "
                             "such as '%s/out.png'",
                             path, path);
    /* A FIFO or a device would be replaced by the rename (or, written into,
     * block): refused before any work. */
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return ras_error_set(err,
                             "cannot write '%s': it is %s; expected a regular file or a new "
                             "name",
                             path,
                             S_ISFIFO(st.st_mode)  ? "a FIFO"
                             : S_ISCHR(st.st_mode) ? "a character device"
                             : S_ISBLK(st.st_mode) ? "a block device"
                                                   : "not a regular file");
    if (!ras_io_check_replace(path, "image", err)) return false;
    /* The folder the file goes into. */
    char dir[4096];
    ras_io_folder_of(path, dir, sizeof dir);
    if (stat(dir, &st) != 0)
        return ras_error_set(err,
                             "cannot write '%s': the folder '%s' does not exist; create it "
                             "first (mkdir -p '%s') or write elsewhere",
                             path, dir, dir);
    if (!S_ISDIR(st.st_mode))
        return ras_error_set(err, "cannot write '%s': '%s' is a file, not a folder", path, dir);
    if (access(dir, W_OK) != 0)
        return ras_error_set(err,
                             "cannot write '%s': the folder '%s' is not writable (%s); write "
                             "the image somewhere else",
                             path, dir, strerror(errno));
    return true;
}

/* ras_io_write_atomic's check of the file read back: it decodes, at the size
 * that was encoded. */
static bool verify_decodes(const void *data, size_t len, void *ctx, ras_error *err) {
    const int *size = ctx;
    int w = 0, h = 0;
    bool exif = false;
    if (ras_png_is_png(data, len)) {
        char msg[512];
        uint8_t *rgb = ras_png_decode_rgb8(data, len, &w, &h, &exif, msg, sizeof msg);
        if (!rgb && !exif) return ras_error_set(err, "libpng cannot decode it (%s)", msg);
        free(rgb);
    }
    if ((!ras_png_is_png(data, len) || exif) && !cv_bridge_decode_size(data, len, &w, &h))
        return ras_error_set(err, "OpenCV cannot decode it");
    if (w != size[0] || h != size[1])
        return ras_error_set(err, "it decodes as %dx%d, expected %dx%d", w, h, size[0], size[1]);
    return true;
}

bool ras_image_save_rgb8(const uint8_t *rgb, int width, int height, const char *path,
                         ras_error *err) {
    if (!ras_image_check_output(path, err)) return false;
    /* Encoded in memory, the codec following the extension, then written
     * through ras_io_write_atomic: a temporary file beside the target, every
     * write checked, fsync, read back and decoded, renamed over the target. */
    const char *ext = strrchr(path, '.');
    char msg[512] = "";
    size_t len = 0;
    uint8_t *encoded = strcasecmp(ext, ".png") == 0
                           ? ras_png_encode_rgb8(width, height, rgb, &len, msg, sizeof msg)
                           : cv_bridge_encode_rgb8(ext, width, height, rgb, &len, msg, sizeof msg);
    if (!encoded) return ras_error_set(err, "could not write '%s': %s", path, msg);
    int size[2] = {width, height};
    bool ok = ras_io_write_atomic(path, "image", encoded, len, verify_decodes, size, err);
    free(encoded);
    return ok;
}

bool ras_image_save(const ras_image *img, const char *path, ras_error *err) {
    if (!ras_image_check_output(path, err)) return false;
    size_t bytes = (size_t)img->width * (size_t)img->height * 3;
    uint8_t *rgb = malloc(bytes);
    if (!rgb) return ras_error_set(err, "out of memory writing '%s'", path);
    ras_image_to_rgb8(img, rgb);
    bool ok = ras_image_save_rgb8(rgb, img->width, img->height, path, err);
    free(rgb);
    return ok;
}

/* Big-endian and little-endian reads from a byte buffer. */
static uint32_t be32(const uint8_t *p) {
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}
static uint32_t le32(const uint8_t *p) {
    return (uint32_t)p[3] << 24 | (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
}

ras_image_format ras_image_sniff(const uint8_t *d, size_t len) {
    if (ras_png_is_png(d, len)) return RAS_IMAGE_PNG;
    if (ras_jpeg_is_jpeg(d, len)) return RAS_IMAGE_JPEG;
    if (len >= 2 && d[0] == 'B' && d[1] == 'M') return RAS_IMAGE_BMP;
    if (len >= 3 && d[0] == 'P' && d[1] >= '1' && d[1] <= '6' &&
        (d[2] == ' ' || d[2] == '\t' || d[2] == '\r' || d[2] == '\n'))
        return RAS_IMAGE_PNM;
    if (len >= 4 && (!memcmp(d, "II*\0", 4) || !memcmp(d, "MM\0*", 4) || !memcmp(d, "II+\0", 4) ||
                     !memcmp(d, "MM\0+", 4)))
        return RAS_IMAGE_TIFF;
    return RAS_IMAGE_UNKNOWN;
}

const char *ras_image_refused_format(const uint8_t *d, size_t len) {
    if (len >= 2 && d[0] == 'P' && (d[1] == 'f' || d[1] == 'F')) return "a PFM (float) image";
    if (len >= 2 && d[0] == 'P' && d[1] == '7') return "a PAM image";
    if (len >= 6 && (!memcmp(d, "#?RADIANCE", len < 10 ? len : 10) || !memcmp(d, "#?RGBE", 6)))
        return "a Radiance HDR image";
    if (len >= 4 && le32(d) == 0x01312f76u) return "an OpenEXR image";
    if (len >= 12 && !memcmp(d, "RIFF", 4) && !memcmp(d + 8, "WEBP", 4)) return "a WebP image";
    if ((len >= 4 && d[0] == 0xFF && d[1] == 0x4F && d[2] == 0xFF && d[3] == 0x51) ||
        (len >= 12 && !memcmp(d, "\0\0\0\x0cjP  \r\n\x87\n", 12)))
        return "a JPEG 2000 image";
    if (len >= 4 && be32(d) == 0x59a66a95u) return "a Sun raster image";
    if (len >= 6 && (!memcmp(d, "GIF87a", 6) || !memcmp(d, "GIF89a", 6))) return "a GIF image";
    return NULL;
}

/* PNM (P1..P6): the magic, then width and height as decimal text, with '#'
 * comments between (OpenCV's PxMDecoder::readHeader, ReadNumber). */
static bool pnm_size(const uint8_t *d, size_t len, long *w, long *h) {
    size_t i = 2;
    long v[2];
    for (int k = 0; k < 2; k++) {
        for (;;) {
            while (i < len && (d[i] == ' ' || d[i] == '\t' || d[i] == '\r' || d[i] == '\n')) i++;
            if (i < len && d[i] == '#')
                while (i < len && d[i] != '\n' && d[i] != '\r') i++;
            else
                break;
        }
        if (i >= len || d[i] < '0' || d[i] > '9') return false;
        v[k] = 0;
        while (i < len && d[i] >= '0' && d[i] <= '9') {
            if (v[k] < 100000000) v[k] = v[k] * 10 + (d[i] - '0');
            i++;
        }
    }
    *w = v[0];
    *h = v[1];
    return true;
}

/* BMP (OpenCV's BmpDecoder::readHeader): after the 14-byte file header, an
 * info header of 40+ bytes (32-bit sizes, height negative for top-down) or
 * an OS/2 core header of 12 (16-bit sizes). */
static bool bmp_size(const uint8_t *d, size_t len, long *w, long *h) {
    if (len < 26) return false;
    uint32_t size = le32(d + 14);
    if (size >= 36) {
        int32_t bw = (int32_t)le32(d + 18), bh = (int32_t)le32(d + 22);
        *w = bw < 0 ? -(long)bw : bw;
        *h = bh < 0 ? -(long)bh : bh;
        return true;
    }
    if (size == 12) {
        *w = d[18] | d[19] << 8;
        *h = d[20] | d[21] << 8;
        return true;
    }
    return false;
}

/* TIFF, classic and BigTIFF (what libtiff, OpenCV's decoder, reads): the
 * first directory's ImageWidth (256) and ImageLength (257). A tag given twice
 * counts with its larger value, so a duplicate cannot hide a size. */
static bool tiff_size(const uint8_t *d, size_t len, long *w, long *h) {
    if (len < 8) return false;
    bool le = d[0] == 'I', big = d[2] == '+' || d[3] == '+';
#define U16(p) (le ? (uint64_t)((p)[0] | (p)[1] << 8) : (uint64_t)((p)[0] << 8 | (p)[1]))
#define U32(p) (le ? (uint64_t)le32(p) : (uint64_t)be32(p))
#define U64(p) (le ? (U32((p) + 4) << 32 | U32(p)) : (U32(p) << 32 | U32((p) + 4)))
    uint64_t off, n;
    size_t entry, head;
    if (big) {
        if (len < 16 || U16(d + 4) != 8) return false;
        off = U64(d + 8);
        entry = 20, head = 8;
        if (off > len || len - off < head) return false;
        n = U64(d + off);
    } else {
        off = U32(d + 4);
        entry = 12, head = 2;
        if (off > len || len - off < head) return false;
        n = U16(d + off);
    }
    long got[2] = {-1, -1};
    for (uint64_t k = 0; k < n && (len - off - head) / entry > k; k++) {
        const uint8_t *e = d + off + head + entry * k;
        uint64_t tag = U16(e), type = U16(e + 2);
        if (tag != 256 && tag != 257) continue;
        const uint8_t *val = e + (big ? 12 : 8);
        uint64_t v = type == 3 ? U16(val) : type == 4 || type == 9 ? U32(val)
                   : (type == 16 || type == 17) && big ? U64(val)
                                                      : UINT64_MAX;
        long lv = v > 100000000 ? 100000000 : (long)v;
        if (lv > got[tag - 256]) got[tag - 256] = lv;
    }
#undef U16
#undef U32
#undef U64
    if (got[0] < 0 || got[1] < 0) return false;
    *w = got[0];
    *h = got[1];
    return true;
}

bool ras_image_peek_size(const uint8_t *d, size_t len, long *w, long *h) {
    switch (ras_image_sniff(d, len)) {
    case RAS_IMAGE_PNG: /* IHDR must come first (libpng refuses anything else) */
        if (len < 24 || memcmp(d + 12, "IHDR", 4)) return false;
        *w = (long)be32(d + 16);
        *h = (long)be32(d + 20);
        return true;
    case RAS_IMAGE_JPEG: return ras_jpeg_peek_size(d, len, w, h);
    case RAS_IMAGE_BMP: return bmp_size(d, len, w, h);
    case RAS_IMAGE_PNM: return pnm_size(d, len, w, h);
    case RAS_IMAGE_TIFF: return tiff_size(d, len, w, h);
    case RAS_IMAGE_UNKNOWN: break;
    }
    return false;
}

bool ras_image_peek_file(const char *path, long *width, long *height) {
    char why[256];
    int fd = ras_io_open_input(path, why, sizeof why);
    if (fd < 0) return false;
    /* A JPEG's size may follow EXIF and ICC segments, a TIFF's directory
     * may sit anywhere: read enough, and the whole file when it is small.
     * A header further in is found by ras_image_load, which reads it all. */
    size_t cap = 1024 * 1024, len = 0;
    uint8_t *buf = malloc(cap);
    while (buf && len < cap) {
        ssize_t r = read(fd, buf + len, cap - len);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;
        len += (size_t)r;
    }
    close(fd);
    bool ok = buf && ras_image_peek_size(buf, len, width, height);
    free(buf);
    return ok;
}

/* One decode, run under the time limit (ras_job.h): it owns the file's bytes,
 * so a decode that outlives the limit frees them itself. */
typedef struct decode_job {
    uint8_t *data;
    size_t len;
    ras_image_format format;
    ras_jpeg_limits limits;
    uint8_t *rgb;
    int width, height;
    char msg[512];
} decode_job;

static void *decode_run(void *arg) {
    decode_job *j = arg;
    /* PNG by its signature through libpng (ras_png.h), JPEG through libjpeg
     * (ras_jpeg.h); BMP, PNM, TIFF, and a PNG with EXIF, through OpenCV. */
    bool exif = false;
    if (j->format == RAS_IMAGE_PNG)
        j->rgb = ras_png_decode_rgb8(j->data, j->len, &j->width, &j->height, &exif, j->msg,
                                     sizeof j->msg);
    else if (j->format == RAS_IMAGE_JPEG)
        j->rgb = ras_jpeg_decode_rgb8(j->data, j->len, &j->limits, &j->width, &j->height, j->msg,
                                      sizeof j->msg);
    if ((j->format != RAS_IMAGE_PNG && j->format != RAS_IMAGE_JPEG) || exif)
        j->rgb = cv_bridge_decode_rgb8(j->data, j->len, &j->width, &j->height, j->msg,
                                       sizeof j->msg);
    return j;
}

static void decode_discard(void *result, void *arg) {
    (void)result;
    decode_job *j = arg;
    free(j->rgb);
    free(j->data);
    free(j);
}

uint8_t *ras_image_load_rgb8(const char *path, int *width, int *height, ras_error *err) {
    return ras_image_load_rgb8_making(
        path, RAS_MEMORY_BYTES_PER_LOADED_PIXEL - RAS_MEMORY_DECODE_BYTES_PER_PIXEL, width, height,
        err);
}

uint8_t *ras_image_load_rgb8_making(const char *path, double made_per_pixel, int *width,
                                    int *height, ras_error *err) {
    /* The file's bytes first (regular files only: a FIFO fails at once, an
     * unreadable file says "Permission denied"), then its format from its
     * content (never its name), then the size from its header read by the
     * decoder's own rules, checked against RAS_IMAGE_MAX_SIDE and the memory
     * budget before a single pixel is decoded, then the decode from memory
     * under the time limit. */
    struct stat st;
    char what[1200];
    snprintf(what, sizeof what, "reading image '%s'", path);
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_size <= RAS_IMAGE_MAX_FILE_BYTES &&
        !ras_memory_check((double)st.st_size, what, "use a smaller image", err))
        return NULL;
    size_t len = 0;
    uint8_t *data = ras_io_read_file(path, "image", RAS_IMAGE_MAX_FILE_BYTES, &len, err);
    if (!data) return NULL;
    ras_image_format format = ras_image_sniff(data, len);
    const char *refused = ras_image_refused_format(data, len);
    if (format == RAS_IMAGE_UNKNOWN) {
        if (refused)
            ras_error_set(err,
                          "could not read image '%s': it is %s, a format not accepted here (its "
                          "size cannot be bounded before decoding); expected %s — convert it to "
                          "PNG",
                          path, refused, RAS_IMAGE_ACCEPTED);
        else
            ras_error_set(err,
                          "could not read image '%s': its content is not an image format "
                          "accepted here (whatever its name); expected %s — check the file",
                          path, RAS_IMAGE_ACCEPTED);
        free(data);
        return NULL;
    }
    long hw = 0, hh = 0;
    if (!ras_image_peek_size(data, len, &hw, &hh)) {
        ras_error_set(err,
                      "could not read image '%s': it starts like %s but its header does not say "
                      "its size (truncated or damaged); expected a complete image file — check "
                      "the file",
                      path, ras_image_format_name(format));
        free(data);
        return NULL;
    }
    snprintf(what, sizeof what, "image '%s' (%ldx%ld pixels)", path, hw, hh);
    if (hw < 1 || hh < 1 || hw > RAS_IMAGE_MAX_SIDE || hh > RAS_IMAGE_MAX_SIDE) {
        ras_error_set(err,
                      "could not read image '%s': its header says %ldx%ld pixels; expected "
                      "1..%d on each side — use a smaller image",
                      path, hw, hh, RAS_IMAGE_MAX_SIDE);
        free(data);
        return NULL;
    }
    double pixels = (double)hw * (double)hh;
    double decode = format == RAS_IMAGE_JPEG ? RAS_MEMORY_JPEG_DECODE_BYTES_PER_PIXEL
                                             : RAS_MEMORY_DECODE_BYTES_PER_PIXEL;
    double need = pixels * (decode + made_per_pixel) + (double)len;
    if (!ras_memory_check(need, what, "use a smaller image", err)) {
        free(data);
        return NULL;
    }
    decode_job *job = calloc(1, sizeof *job);
    if (!job) {
        free(data);
        ras_error_set(err, "out of memory reading image '%s'", path);
        return NULL;
    }
    double seconds = ras_job_seconds("RAS_IMAGE_DECODE_SECONDS", RAS_IMAGE_DECODE_SECONDS_DEFAULT);
    job->data = data;
    job->len = len;
    job->format = format;
    /* libjpeg's working memory (a progressive file's coefficients) within
     * what the check above allowed for the whole load. */
    double decoder = need - 3.0 * pixels; /* beside its RGB output */
    job->limits.max_bytes = (size_t)(decoder > 64e6 ? decoder : 64e6);
    job->limits.seconds = seconds;
    clock_gettime(CLOCK_MONOTONIC, &job->limits.deadline);
    job->limits.deadline.tv_sec += (time_t)seconds + 1; /* the job's wait ends first */
    void *done = NULL;
    if (!ras_job_run(decode_run, job, decode_discard, 0, seconds, &done))
        return ras_error_set(err,
                             "could not read image '%s': decoding it took longer than the limit "
                             "of %g s (RAS_IMAGE_DECODE_SECONDS); expected an image that "
                             "decodes in time — use a smaller or simpler image, or raise "
                             "RAS_IMAGE_DECODE_SECONDS",
                             path, seconds),
               NULL;
    uint8_t *rgb = job->rgb;
    int w = job->width, h = job->height;
    if (!rgb)
        ras_error_set(err, "could not read image '%s': %s; check the file", path, job->msg);
    free(job->data);
    free(job);
    if (!rgb) return NULL;
    /* The decoders read the header this check read; a disagreement would be
     * a bug in the check, refused rather than trusted. */
    if (!size_ok(w, h, err) || (long)w * h != hw * hh) {
        if (rgb && (long)w * h != hw * hh)
            ras_error_set(err,
                          "could not read image '%s': it decoded as %dx%d but its header says "
                          "%ldx%ld; expected the two to agree — the file is damaged",
                          path, w, h, hw, hh);
        free(rgb);
        return NULL;
    }
    *width = w;
    *height = h;
    return rgb;
}

const char *ras_image_format_name(ras_image_format format) {
    switch (format) {
    case RAS_IMAGE_PNG: return "a PNG";
    case RAS_IMAGE_JPEG: return "a JPEG";
    case RAS_IMAGE_BMP: return "a BMP";
    case RAS_IMAGE_PNM: return "a PNM (PBM/PGM/PPM)";
    case RAS_IMAGE_TIFF: return "a TIFF";
    case RAS_IMAGE_UNKNOWN: break;
    }
    return "an unknown format";
}

ras_image *ras_image_load(const char *path, ras_error *err) {
    int w = 0, h = 0;
    uint8_t *rgb = ras_image_load_rgb8(path, &w, &h, err);
    if (!rgb) return NULL;
    ras_image *img = ras_image_create(w, h, err);
    if (img) {
        size_t n = (size_t)w * (size_t)h;
        for (size_t i = 0; i < n; i++)
            img->pixels[i] = (vec3s){{ras_byte_to_unit(rgb[3 * i]), ras_byte_to_unit(rgb[3 * i + 1]),
                                      ras_byte_to_unit(rgb[3 * i + 2])}};
    }
    free(rgb);
    return img;
}
