/* ras_image.c — see ras_image.h. */
#include "ras_image.h"

#include "cv_bridge.h"
#include "ras_io.h"

#include <errno.h>    /* errno */
#include <stdio.h>    /* snprintf */
#include <stdlib.h>   /* calloc, free */
#include <string.h>   /* strrchr, strlen, strerror */
#include <strings.h>  /* strcasecmp */
#include <sys/stat.h> /* stat */
#include <unistd.h>   /* access */

static bool ras_image_size_ok(int width, int height, ras_error *err) {
    if (width >= 1 && height >= 1 && width <= RAS_IMAGE_MAX_SIDE && height <= RAS_IMAGE_MAX_SIDE)
        return true;
    return ras_error_set(err, "image size %dx%d is out of range: expected 1..%d on each side",
                         width, height, RAS_IMAGE_MAX_SIDE);
}

ras_image *ras_image_create(int width, int height, ras_error *err) {
    if (!ras_image_size_ok(width, height, err)) return NULL;
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
    if (!known || !cv_bridge_can_write(path))
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
    if (!cv_bridge_decode_size(data, len, &w, &h))
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
    uint8_t *encoded = cv_bridge_encode_rgb8(ext, width, height, rgb, &len, msg, sizeof msg);
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

uint8_t *ras_image_load_rgb8(const char *path, int *width, int *height, ras_error *err) {
    /* The file's bytes first (regular files only: a FIFO fails at once, an
     * unreadable file says "Permission denied"), then the decode from memory. */
    size_t len = 0;
    uint8_t *data = ras_io_read_file(path, "image", RAS_IMAGE_MAX_FILE_BYTES, &len, err);
    if (!data) return NULL;
    char msg[512] = "";
    int w = 0, h = 0;
    uint8_t *rgb = cv_bridge_decode_rgb8(data, len, &w, &h, msg, sizeof msg);
    free(data);
    if (!rgb) {
        ras_error_set(err, "could not read image '%s': %s; check the file", path, msg);
        return NULL;
    }
    if (!ras_image_size_ok(w, h, err)) {
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
