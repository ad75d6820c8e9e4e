/* ras_image.c — see ras_image.h. */
#include "ras_image.h"

#include "cv_bridge.h"
#include "ras_io.h"
#include "ras_memory.h"
#include "ras_png.h"

#include <errno.h>    /* errno */
#include <stdio.h>    /* snprintf */
#include <stdlib.h>   /* calloc, free */
#include <string.h>   /* strrchr, strlen, strerror */
#include <strings.h>  /* strcasecmp */
#include <sys/stat.h> /* stat */
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
    struct stat st;
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
    /* The folder the file goes into. */
    char dir[4096];
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (slash == path)
        snprintf(dir, sizeof dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
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

/* PNM (P1..P6, Pf/PF): the magic, then width and height as decimal text,
 * with '#' comments between. */
static bool pnm_size(const uint8_t *d, size_t len, long *w, long *h) {
    size_t i = 2;
    long v[2];
    for (int k = 0; k < 2; k++) {
        for (;;) {
            while (i < len && (d[i] == ' ' || d[i] == '\t' || d[i] == '\r' || d[i] == '\n')) i++;
            if (i < len && d[i] == '#')
                while (i < len && d[i] != '\n') i++;
            else
                break;
        }
        if (i >= len || d[i] < '0' || d[i] > '9') return false;
        v[k] = 0;
        while (i < len && d[i] >= '0' && d[i] <= '9' && v[k] < 100000000) v[k] = v[k] * 10 + (d[i++] - '0');
    }
    *w = v[0];
    *h = v[1];
    return true;
}

/* A decimal number after `key` in a text header (PAM's "WIDTH 640"). */
static bool text_field(const uint8_t *d, size_t len, const char *key, long *out) {
    size_t k = strlen(key), end = len < 4096 ? len : 4096;
    for (size_t i = 0; i + k < end; i++)
        if (!memcmp(d + i, key, k)) {
            long v = 0;
            size_t j = i + k;
            while (j < end && d[j] == ' ') j++;
            if (j >= end || d[j] < '0' || d[j] > '9') return false;
            while (j < end && d[j] >= '0' && d[j] <= '9' && v < 100000000) v = v * 10 + (d[j++] - '0');
            *out = v;
            return true;
        }
    return false;
}

/* Radiance HDR: after the header's blank line, "-Y H +X W" (or a variant). */
static bool radiance_size(const uint8_t *d, size_t len, long *w, long *h) {
    const uint8_t *end = d + (len < 65536 ? len : 65536);
    for (const uint8_t *q = d; q + 2 < end; q++)
        if (q[0] == '\n' && q[1] == '\n') {
            char line[64];
            size_t n = 0;
            for (q += 2; q < end && *q != '\n' && n + 1 < sizeof line; q++) line[n++] = (char)*q;
            line[n] = '\0';
            char a[3], b[3];
            long v1, v2;
            if (sscanf(line, "%2s %ld %2s %ld", a, &v1, b, &v2) != 4) return false;
            bool y_first = a[1] == 'Y';
            *h = y_first ? v1 : v2;
            *w = y_first ? v2 : v1;
            return true;
        }
    return false;
}

/* OpenEXR: the dataWindow attribute (a box, inclusive corners). */
static bool exr_size(const uint8_t *d, size_t len, long *w, long *h) {
    static const char key[] = "dataWindow\0box2i\0";
    for (size_t i = 8; i + sizeof key - 1 + 20 <= len && i < 65536; i++)
        if (!memcmp(d + i, key, sizeof key - 1)) {
            const uint8_t *b = d + i + sizeof key - 1 + 4; /* after the size */
            *w = (long)(int32_t)le32(b + 8) - (long)(int32_t)le32(b) + 1;
            *h = (long)(int32_t)le32(b + 12) - (long)(int32_t)le32(b + 4) + 1;
            return true;
        }
    return false;
}

/* WebP: the size sits in a different place in each of the three chunk kinds. */
static bool webp_size(const uint8_t *d, long *w, long *h) {
    if (!memcmp(d + 12, "VP8 ", 4)) {
        *w = (d[26] | d[27] << 8) & 0x3fff;
        *h = (d[28] | d[29] << 8) & 0x3fff;
        return true;
    }
    if (!memcmp(d + 12, "VP8L", 4)) {
        uint32_t b = le32(d + 21);
        *w = (long)(b & 0x3fff) + 1;
        *h = (long)((b >> 14) & 0x3fff) + 1;
        return true;
    }
    if (!memcmp(d + 12, "VP8X", 4)) {
        *w = (long)(d[24] | d[25] << 8 | d[26] << 16) + 1;
        *h = (long)(d[27] | d[28] << 8 | d[29] << 16) + 1;
        return true;
    }
    return false;
}

/* TIFF: tags 256 (width) and 257 (height) of the first IFD, in the file's
 * byte order. */
static bool tiff_size(const uint8_t *d, size_t len, long *w, long *h) {
    bool le = d[0] == 'I';
    uint32_t off = le ? le32(d + 4) : be32(d + 4);
    if ((size_t)off + 2 > len) return false;
    unsigned n = le ? (unsigned)(d[off] | d[off + 1] << 8) : (unsigned)(d[off] << 8 | d[off + 1]);
    long got[2] = {-1, -1};
    for (unsigned k = 0; k < n && (size_t)off + 2 + 12 * (k + 1) <= len; k++) {
        const uint8_t *e = d + off + 2 + 12 * k;
        unsigned tag = le ? (unsigned)(e[0] | e[1] << 8) : (unsigned)(e[0] << 8 | e[1]);
        unsigned type = le ? (unsigned)(e[2] | e[3] << 8) : (unsigned)(e[2] << 8 | e[3]);
        if (tag != 256 && tag != 257) continue;
        long v = type == 3 ? (le ? (long)(e[8] | e[9] << 8) : (long)(e[8] << 8 | e[9]))
                           : (long)(le ? le32(e + 8) : be32(e + 8));
        got[tag - 256] = v;
    }
    if (got[0] < 0 || got[1] < 0) return false;
    *w = got[0];
    *h = got[1];
    return true;
}

/* JPEG 2000 file format: the ihdr box (height first). */
static bool jp2_size(const uint8_t *d, size_t len, long *w, long *h) {
    for (size_t i = 12; i + 16 <= len && i < 4096; i++)
        if (!memcmp(d + i, "ihdr", 4)) {
            *h = (long)be32(d + i + 4);
            *w = (long)be32(d + i + 8);
            return true;
        }
    return false;
}

/* JPEG: walk the markers to a SOFn (start of frame) segment. */
static bool jpeg_size(const uint8_t *d, size_t len, long *w, long *h) {
    size_t i = 2;
    while (i + 4 <= len) {
        if (d[i] != 0xFF) return false;
        uint8_t m = d[i + 1];
        if (m == 0xFF) { i++; continue; }
        if (m == 0x01 || (m >= 0xD0 && m <= 0xD7)) { i += 2; continue; }
        size_t seg = (size_t)(d[i + 2] << 8 | d[i + 3]);
        if (m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC) {
            if (i + 9 > len) return false;
            *h = d[i + 5] << 8 | d[i + 6];
            *w = d[i + 7] << 8 | d[i + 8];
            return true;
        }
        if (seg < 2) return false;
        i += 2 + seg;
    }
    return false;
}

bool ras_image_peek_size(const uint8_t *d, size_t len, long *w, long *h) {
    if (len >= 24 && !memcmp(d, "\x89PNG\r\n\x1a\n", 8) && !memcmp(d + 12, "IHDR", 4)) {
        *w = (long)be32(d + 16);
        *h = (long)be32(d + 20);
        return true;
    }
    if (len >= 26 && d[0] == 'B' && d[1] == 'M') {
        int32_t bw = (int32_t)le32(d + 18), bh = (int32_t)le32(d + 22);
        *w = bw < 0 ? -(long)bw : bw;
        *h = bh < 0 ? -(long)bh : bh;
        return true;
    }
    if (len >= 3 && d[0] == 'P' && ((d[1] >= '1' && d[1] <= '6') || d[1] == 'f' || d[1] == 'F'))
        return pnm_size(d, len, w, h);
    if (len >= 3 && d[0] == 'P' && d[1] == '7') /* PAM: WIDTH and HEIGHT lines */
        return text_field(d, len, "\nWIDTH ", w) && text_field(d, len, "\nHEIGHT ", h);
    if (len >= 10 && (!memcmp(d, "#?RADIANCE", 10) || !memcmp(d, "#?RGBE", 6)))
        return radiance_size(d, len, w, h);
    if (len >= 24 && d[0] == 0xFF && d[1] == 0x4F && d[2] == 0xFF && d[3] == 0x51) {
        /* JPEG 2000 codestream: the SIZ segment, image size minus its offset. */
        *w = (long)be32(d + 8) - (long)be32(d + 16);
        *h = (long)be32(d + 12) - (long)be32(d + 20);
        return true;
    }
    if (len >= 8 && le32(d) == 0x01312f76u) return exr_size(d, len, w, h);
    if (len >= 30 && !memcmp(d, "RIFF", 4) && !memcmp(d + 8, "WEBP", 4)) return webp_size(d, w, h);
    if (len >= 8 && (!memcmp(d, "II*\0", 4) || !memcmp(d, "MM\0*", 4))) /* TIFF */
        return tiff_size(d, len, w, h);
    if (len >= 12 && be32(d) == 0x59a66a95u) { /* Sun raster */
        *w = (long)be32(d + 4);
        *h = (long)be32(d + 8);
        return true;
    }
    if (len >= 48 && !memcmp(d, "\0\0\0\x0cjP  \r\n\x87\n", 12)) return jp2_size(d, len, w, h);
    if (len >= 4 && d[0] == 0xFF && d[1] == 0xD8) return jpeg_size(d, len, w, h);
    return false;
}

bool ras_image_peek_file(const char *path, long *width, long *height) {
    char why[256];
    int fd = ras_io_open_input(path, why, sizeof why);
    if (fd < 0) return false;
    /* A JPEG's size may follow EXIF and ICC segments: read enough of them. */
    size_t cap = 256 * 1024, len = 0;
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

uint8_t *ras_image_load_rgb8(const char *path, int *width, int *height, ras_error *err) {
    /* The file's bytes first (regular files only: a FIFO fails at once, an
     * unreadable file says "Permission denied"), then the size from its
     * header, checked against RAS_IMAGE_MAX_SIDE and the memory budget before
     * a single pixel is decoded, then the decode from memory. */
    struct stat st;
    char what[1200];
    snprintf(what, sizeof what, "reading image '%s'", path);
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_size <= RAS_IMAGE_MAX_FILE_BYTES &&
        !ras_memory_check((double)st.st_size, what, "use a smaller image", err))
        return NULL;
    size_t len = 0;
    uint8_t *data = ras_io_read_file(path, "image", RAS_IMAGE_MAX_FILE_BYTES, &len, err);
    if (!data) return NULL;
    long hw = 0, hh = 0;
    if (ras_image_peek_size(data, len, &hw, &hh)) {
        snprintf(what, sizeof what, "image '%s' (%ldx%ld pixels)", path, hw, hh);
        if (hw < 1 || hh < 1 || hw > RAS_IMAGE_MAX_SIDE || hh > RAS_IMAGE_MAX_SIDE) {
            ras_error_set(err,
                          "could not read image '%s': its header says %ldx%ld pixels; expected "
                          "1..%d on each side — use a smaller image",
                          path, hw, hh, RAS_IMAGE_MAX_SIDE);
            free(data);
            return NULL;
        }
        if (!ras_memory_check((double)hw * (double)hh * RAS_MEMORY_BYTES_PER_LOADED_PIXEL + (double)len,
                              what, "use a smaller image", err)) {
            free(data);
            return NULL;
        }
    }
    char msg[512] = "";
    int w = 0, h = 0;
    /* PNG by its signature through libpng (ras_png.h); anything else, and a
     * PNG with EXIF, through OpenCV. */
    bool exif = false;
    bool png = ras_png_is_png(data, len);
    uint8_t *rgb = png ? ras_png_decode_rgb8(data, len, &w, &h, &exif, msg, sizeof msg) : NULL;
    if (!png || exif) rgb = cv_bridge_decode_rgb8(data, len, &w, &h, msg, sizeof msg);
    free(data);
    if (!rgb) {
        ras_error_set(err, "could not read image '%s': %s; check the file", path, msg);
        return NULL;
    }
    if (!size_ok(w, h, err)) {
        free(rgb);
        return NULL;
    }
    *width = w;
    *height = h;
    return rgb;
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
