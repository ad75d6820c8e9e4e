/* ras_dump.c — see ras_dump.h: buffers painted, written, read and staged.
 * Comparing two dumps is in ras_dump_compare.c. */
#include "ras_dump.h"

#include "cv_bridge.h"
#include "ras_image.h"
#include "ras_io.h"
#include "ras_mesh.h"
#include "ras_dump_parts.h"
#include "stage3_setup.h" /* ras_viewport */

#include <cjson/cJSON.h>
#include <dirent.h> /* opendir: the staged dump folder */
#include <fcntl.h>  /* open, renameat */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h> /* close */
#include <zlib.h>   /* the reference buffers ship as .pfm.gz */

/* Rows under the picture for the legend. */
enum { LEGEND_ROWS = 34 };

/* Google's "turbo" colour map as Anton Mikhailov's polynomial fit (Apache
 * 2.0): perceptually ordered blue → green → red, readable by colour-blind
 * people better than a rainbow, and never black, which stays "empty". */
static void turbo(double x, uint8_t rgb[3]) {
    x = x < 0 ? 0 : x > 1 ? 1 : x;
    double x2 = x * x, x3 = x2 * x, x4 = x2 * x2, x5 = x4 * x;
    double r = 0.13572138 + 4.61539260 * x - 42.66032258 * x2 + 132.13108234 * x3 -
               152.94239396 * x4 + 59.28637943 * x5;
    double g = 0.09140261 + 2.19418839 * x + 4.84296658 * x2 - 14.18503333 * x3 + 4.27729857 * x4 +
               2.82956604 * x5;
    double b = 0.10667330 + 12.64194608 * x - 60.58204836 * x2 + 110.36276771 * x3 -
               89.90310912 * x4 + 27.34824973 * x5;
    double c[3] = {r, g, b};
    for (int k = 0; k < 3; k++)
        rgb[k] = (uint8_t)lround(255.0 * (c[k] < 0 ? 0 : c[k] > 1 ? 1 : c[k]));
}

/* The part of turbo a value range is drawn with: its ends are near black
 * (the darkest blue, the darkest red), and black means "empty" here. */
static void scalar_colour(double t, uint8_t rgb[3]) { turbo(0.1 + 0.85 * t, rgb); }

static bool is_empty(const ras_dump_buffer *b, const float *v) {
    if (!b->has_empty) return false;
    for (int k = 0; k < b->channels; k++)
        if (memcmp(&v[k], &b->empty, sizeof(float)) != 0) return false;
    return true;
}

ras_dump_stats ras_dump_buffer_stats(const ras_dump_buffer *b) {
    ras_dump_stats s = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}, 0, 0, 0};
    s.entries = (long)b->width * b->height * b->samples;
    for (long i = 0; i < s.entries; i++) {
        const float *v = b->data + i * b->channels;
        if (is_empty(b, v)) {
            s.empty++;
            continue;
        }
        bool finite = true;
        for (int k = 0; k < b->channels; k++)
            finite = finite && isfinite(v[k]);
        if (!finite) {
            s.nonfinite++;
            continue;
        }
        for (int k = 0; k < b->channels; k++) {
            if (v[k] < s.lo[k]) s.lo[k] = v[k];
            if (v[k] > s.hi[k]) s.hi[k] = v[k];
        }
    }
    return s;
}

/* The picture: each pixel's mean over its non-empty finite samples, in the
 * buffer's style; black where every sample is empty, magenta where only
 * non-finite values are (a NaN is a mistake worth seeing). */
/* The range a scalar is drawn over: its own, or the one it is given. */
static ras_dump_stats drawn_range(const ras_dump_buffer *b, ras_dump_stats s) {
    if (b->range && b->style == RAS_DUMP_SCALAR) s.lo[0] = b->range[0], s.hi[0] = b->range[1];
    return s;
}

static void paint(const ras_dump_buffer *b, const ras_dump_stats *s_own, uint8_t *rgb) {
    ras_dump_stats drawn = drawn_range(b, *s_own);
    const ras_dump_stats *s = &drawn;
    int spp = b->samples, ch = b->channels;
    for (int row = 0; row < b->height; row++)
        for (int x = 0; x < b->width; x++) {
            double sum[3] = {0, 0, 0};
            int n = 0, bad = 0;
            for (int k = 0; k < spp; k++) {
                const float *v = b->data + (((long)row * b->width + x) * spp + k) * ch;
                if (is_empty(b, v)) continue;
                bool finite = true;
                for (int c = 0; c < ch; c++)
                    finite = finite && isfinite(v[c]);
                if (!finite) {
                    bad++;
                    continue;
                }
                for (int c = 0; c < ch; c++)
                    sum[c] += v[c];
                n++;
            }
            uint8_t *p = rgb + ((size_t)row * b->width + x) * 3;
            if (n == 0) {
                p[0] = bad ? 255 : 0, p[1] = 0, p[2] = bad ? 255 : 0;
                continue;
            }
            if (b->style == RAS_DUMP_SCALAR) {
                double span = s->hi[0] - s->lo[0];
                scalar_colour(span > 0 ? (sum[0] / n - s->lo[0]) / span : 0.5, p);
            } else {
                for (int c = 0; c < 3; c++) {
                    double v = c < ch ? sum[c] / n : 0;
                    if (b->style == RAS_DUMP_VECTOR)
                        v = 0.5 + 0.5 * v;
                    else if (v < 0 || v > 1) /* repeating coordinates: the fraction */
                        v -= floor(v);
                    p[c] = ras_unit_to_byte((float)v);
                }
            }
        }
}

static void legend_text(const ras_dump_buffer *b, const ras_dump_stats *s_own, char *text, size_t size) {
    ras_dump_stats drawn = drawn_range(b, *s_own);
    const ras_dump_stats *s = &drawn;
    /* one value has no range to colour: a "1 (blue) .. 1 (red)" scale
     * would promise two colours the picture cannot show */
    if (b->style == RAS_DUMP_SCALAR && s->lo[0] == s->hi[0])
        snprintf(text, size, "%s: %.6g wherever drawn (one value, one colour); black: empty",
                 b->name, s->lo[0]);
    else if (b->style == RAS_DUMP_SCALAR && s->lo[0] < s->hi[0])
        snprintf(text, size, "%s: %.6g (blue) .. %.6g (red); black: empty", b->name, s->lo[0],
                 s->hi[0]);
    else if (b->style == RAS_DUMP_SCALAR)
        snprintf(text, size, "%s: every entry empty", b->name);
    else if (b->style == RAS_DUMP_VECTOR)
        snprintf(text, size, "%s: x y z as red green blue (0.5 + 0.5 v); black: empty", b->name);
    else
        snprintf(text, size, "%s: u v as red green (outside 0..1: the fraction); black: empty",
                 b->name);
}

static void legend(const ras_dump_buffer *b, const ras_dump_stats *s, uint8_t *rgb) {
    int w = b->width, h = b->height + LEGEND_ROWS;
    memset(rgb + (size_t)b->height * w * 3, 40, (size_t)LEGEND_ROWS * w * 3);
    char text[160];
    if (b->style == RAS_DUMP_SCALAR)
        for (int x = 4; x < w - 4; x++)
            for (int y = b->height + 3; y < b->height + 11; y++)
                scalar_colour((double)(x - 4) / (w > 9 ? w - 9 : 1), rgb + ((size_t)y * w + x) * 3);
    legend_text(b, s, text, sizeof text);
    cv_bridge_draw_text(rgb, w, h, 4, b->height + 28, text, 0.4);
}

void ras_dump_paint(const ras_dump_buffer *b, uint8_t *rgb, char *text, size_t size) {
    ras_dump_stats s = ras_dump_buffer_stats(b);
    paint(b, &s, rgb);
    if (text && size) legend_text(b, &s, text, size);
}

/* A PFM file image (what --dump writes: "PF" RGB or "Pf" grey, width and
 * height, the scale ±1 whose sign is the byte order, then the rows bottom
 * first) → malloc'd floats, top row first, RGB order: read here rather than
 * by OpenCV, whose PFM decoder goes through a temporary file in /tmp that
 * its errors leave behind. The header's size is checked against the bytes
 * that follow it, so no header can ask for more than the file holds. */
static float *pfm_decode(const uint8_t *d, size_t len, int *width, int *height, int *channels,
                         char *msg, size_t msg_size) {
    if (len < 3 || d[0] != 'P' || (d[1] != 'F' && d[1] != 'f')) {
        snprintf(msg, msg_size, "not a PFM file (expected 'PF' or 'Pf' first, as --dump writes)");
        return NULL;
    }
    int ch = d[1] == 'F' ? 3 : 1;
    size_t i = 2;
    double v[3];
    for (int k = 0; k < 3; k++) {
        while (i < len && (d[i] == ' ' || d[i] == '\t' || d[i] == '\r' || d[i] == '\n')) i++;
        char num[40];
        size_t n = 0;
        while (i < len && n + 1 < sizeof num && d[i] > ' ' && d[i] < 127) num[n++] = (char)d[i++];
        num[n] = '\0';
        char *end = NULL;
        v[k] = n ? strtod(num, &end) : NAN;
        if (!n || *end || !isfinite(v[k]) || (k < 2 && (v[k] < 1 || v[k] > 1 << 20 || v[k] != floor(v[k])))) {
            snprintf(msg, msg_size, "its PFM header is damaged (expected WIDTH HEIGHT SCALE, whole "
                                    "sizes 1..%d and a finite scale)", 1 << 20);
            return NULL;
        }
    }
    if (i >= len || (d[i] != '\n' && d[i] != ' ' && d[i] != '\r' && d[i] != '\t') ||
        fabs(v[2]) != 1.0) {
        snprintf(msg, msg_size, "its PFM header is not one --dump writes (expected the scale "
                                "-1 or 1 and one whitespace byte before the data)");
        return NULL;
    }
    i++;
    size_t w = (size_t)v[0], h = (size_t)v[1], row = w * (size_t)ch;
    if ((len - i) / sizeof(float) / h < row) {
        snprintf(msg, msg_size, "its header says %zux%zu with %d channel%s, more than the %zu "
                 "bytes that follow it hold; the file is truncated",
                 w, h, ch, ch > 1 ? "s" : "", len - i);
        return NULL;
    }
    float *out = malloc(w * h * (size_t)ch * sizeof *out);
    if (!out) {
        snprintf(msg, msg_size, "out of memory for a %zux%zu buffer", w, h);
        return NULL;
    }
    const uint16_t one = 1;
    bool swap = (v[2] < 0) != (*(const uint8_t *)&one == 1); /* the file's order is not ours */
    for (size_t r = 0; r < h; r++) {
        const uint8_t *src = d + i + (h - 1 - r) * row * sizeof(float);
        for (size_t k = 0; k < row; k++) {
            uint8_t b[4];
            memcpy(b, src + 4 * k, 4);
            if (swap) {
                uint8_t t = b[0]; b[0] = b[3]; b[3] = t;
                t = b[1]; b[1] = b[2]; b[2] = t;
            }
            memcpy(&out[r * row + k], b, 4);
        }
    }
    *width = (int)w;
    *height = (int)h;
    *channels = ch;
    return out;
}

uint8_t *ras_dump_encode_pfm(int width, int height, int channels, const float *data, size_t *len) {
    char head[64];
    int n = snprintf(head, sizeof head, "%s\n%d %d\n-1\n", channels == 3 ? "PF" : "Pf", width,
                     height);
    size_t row = (size_t)width * (size_t)channels, body = row * (size_t)height * sizeof(float);
    uint8_t *out = malloc((size_t)n + body);
    if (!out) return NULL;
    memcpy(out, head, (size_t)n);
    const uint16_t one = 1;
    bool host_le = *(const uint8_t *)&one == 1;
    uint8_t *dst = out + n;
    for (int r = height - 1; r >= 0; r--) /* bottom row first */
        for (size_t k = 0; k < row; k++, dst += 4) {
            uint8_t b[4];
            memcpy(b, &data[(size_t)r * row + k], 4);
            for (int i = 0; i < 4; i++) dst[i] = host_le ? b[i] : b[3 - i]; /* little-endian */
        }
    *len = (size_t)n + body;
    return out;
}

static bool same_floats(const void *data, size_t len, void *ctx, ras_error *err) {
    const ras_dump_buffer *b = ctx;
    char msg[256] = "";
    int w = 0, h = 0, ch = 0;
    float *back = pfm_decode(data, len, &w, &h, &ch, msg, sizeof msg);
    size_t n = (size_t)b->width * b->samples * b->height * b->channels;
    bool ok = back && w == b->width * b->samples && h == b->height && ch == b->channels &&
              memcmp(back, b->data, n * sizeof(float)) == 0;
    free(back);
    if (!ok)
        return ras_error_set(err, "the buffer file does not read back bit for bit%s%s",
                             *msg ? ": " : "", msg);
    return true;
}

/* j printed into `path` atomically, ending in a newline; j is freed. */
bool ras_dump_write_json_file(const char *path, const char *what, cJSON *j, ras_error *err) {
    char *text = cJSON_Print(j);
    cJSON_Delete(j);
    if (!text) return ras_error_set(err, "out of memory writing '%s'", path);
    size_t len = strlen(text);
    text[len] = '\n'; /* cJSON's terminator becomes the last newline */
    bool ok = ras_io_write_atomic(path, what, text, len + 1, NULL, NULL, err);
    free(text);
    return ok;
}

static bool write_json(const char *path, const ras_dump_buffer *b, const ras_dump_stats *s, ras_error *err) {
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "buffer", b->name);
    cJSON_AddStringToObject(j, "what", b->what);
    cJSON_AddStringToObject(j, "units", b->units);
    cJSON_AddNumberToObject(j, "width", b->width);
    cJSON_AddNumberToObject(j, "height", b->height);
    cJSON_AddNumberToObject(j, "samples", b->samples);
    cJSON_AddNumberToObject(j, "channels", b->channels);
    cJSON_AddStringToObject(j, "layout",
                            b->samples > 1
                                ? "row-major, top row first; sample s of pixel x at column "
                                  "x*samples+s (the PFM is width*samples wide)"
                                : "row-major, top row first");
    char file[300];
    snprintf(file, sizeof file, "%s.pfm", b->name);
    cJSON_AddStringToObject(j, "exact", file);
    snprintf(file, sizeof file, "%s.png", b->name);
    cJSON_AddStringToObject(j, "picture", file);
    cJSON *range = cJSON_AddArrayToObject(j, "range");
    for (int k = 0; k < b->channels; k++) {
        cJSON *r = cJSON_CreateArray();
        if (s->lo[k] <= s->hi[k]) {
            cJSON_AddItemToArray(r, cJSON_CreateNumber(s->lo[k]));
            cJSON_AddItemToArray(r, cJSON_CreateNumber(s->hi[k]));
        }
        cJSON_AddItemToArray(range, r);
    }
    if (b->has_empty) {
        char e[32];
        snprintf(e, sizeof e, "%g", (double)b->empty);
        cJSON_AddStringToObject(j, "empty_value", e);
    }
    cJSON_AddNumberToObject(j, "entries", (double)s->entries);
    cJSON_AddNumberToObject(j, "empty_entries", (double)s->empty);
    cJSON_AddNumberToObject(j, "non_finite_entries", (double)s->nonfinite);
    return ras_dump_write_json_file(path, "buffer description", j, err);
}

bool ras_dump_write(const char *dir, const ras_dump_buffer *b, ras_error *err) {
    if (b->channels != 1 && b->channels != 3)
        return ras_error_set(err, "buffer '%s': 1 or 3 channels, not %d", b->name, b->channels);
    ras_dump_stats s = ras_dump_buffer_stats(b);
    char path[RAS_IO_MAX_PATH + 64];
    /* the exact file first: the picture and the sidecar describe it */
    size_t len = 0;
    char msg[256] = "";
    uint8_t *pfm = ras_dump_encode_pfm(b->width * b->samples, b->height, b->channels, b->data,
                                       &len);
    if (!pfm) snprintf(msg, sizeof msg, "out of memory");
    if (!pfm) return ras_error_set(err, "could not encode the %s buffer: %s", b->name, msg);
    snprintf(path, sizeof path, "%s/%s.pfm", dir, b->name);
    bool ok = ras_io_write_atomic(path, "buffer", pfm, len, same_floats, (void *)b, err);
    free(pfm);
    if (!ok) return false;
    size_t bytes = (size_t)b->width * (b->height + LEGEND_ROWS) * 3;
    uint8_t *rgb = malloc(bytes);
    if (!rgb) return ras_error_set(err, "out of memory drawing the %s buffer", b->name);
    paint(b, &s, rgb);
    legend(b, &s, rgb);
    snprintf(path, sizeof path, "%s/%s.png", dir, b->name);
    ok = ras_image_save_rgb8(rgb, b->width, b->height + LEGEND_ROWS, path, err);
    free(rgb);
    if (!ok) return false;
    snprintf(path, sizeof path, "%s/%s.json", dir, b->name);
    return write_json(path, b, &s, err);
}

/* A .pfm.gz whole into memory, at most `limit` bytes once inflated (a
 * decompression bomb stops there); NULL with err set. */
static uint8_t *gunzip_file(const char *path, size_t limit, size_t *len, ras_error *err) {
    char why[256];
    int fd = ras_io_open_input(path, why, sizeof why);
    if (fd < 0) return ras_error_set(err, "cannot read the buffer file '%s': %s", path, why), NULL;
    gzFile gz = gzdopen(fd, "rb");
    if (!gz) {
        close(fd);
        return ras_error_set(err, "cannot read the buffer file '%s': out of memory", path), NULL;
    }
    size_t cap = 1 << 20, n = 0;
    uint8_t *buf = malloc(cap);
    int got = 0;
    while (buf && (got = gzread(gz, buf + n, (unsigned)(cap - n))) > 0) {
        n += (size_t)got;
        if (n < cap) continue;
        if (cap >= limit) {
            free(buf);
            gzclose(gz);
            return ras_error_set(err, "the buffer file '%s' inflates to more than %zu MiB", path,
                                 limit >> 20),
                   NULL;
        }
        size_t grow = cap * 2 > limit ? limit : cap * 2;
        uint8_t *grown = realloc(buf, grow);
        if (!grown) free(buf);
        buf = grown;
        cap = grow;
    }
    bool bad = got < 0;
    gzclose(gz);
    if (!buf) return ras_error_set(err, "out of memory reading '%s'", path), NULL;
    if (bad) {
        free(buf);
        return ras_error_set(err, "the buffer file '%s' is not a whole gzip file", path), NULL;
    }
    *len = n;
    return buf;
}

static bool ends_with(const char *s, const char *tail) {
    size_t a = strlen(s), b = strlen(tail);
    return a >= b && !strcmp(s + a - b, tail);
}

float *ras_dump_read_pfm(const char *path, int *width, int *height, int *channels, ras_error *err) {
    size_t len = 0;
    /* PFM is uncompressed: the file's size bounds what decoding allocates */
    uint8_t *data = ends_with(path, ".gz")
                        ? gunzip_file(path, (size_t)256 << 20, &len, err)
                        : ras_io_read_file(path, "buffer file", (size_t)1 << 30, &len, err);
    if (!data) return NULL;
    char msg[256] = "";
    float *f = pfm_decode(data, len, width, height, channels, msg, sizeof msg);
    free(data);
    if (!f) ras_error_set(err, "could not read the buffer file '%s': %s", path, msg);
    return f;
}

bool ras_dump_check_input_dir(const char *dir, ras_error *err) {
    struct stat st;
    if (stat(dir, &st) != 0)
        return ras_error_set(err,
                             "--buffers: cannot open the folder '%s' (%s); expected the folder "
                             "of a --dump run — check the path",
                             dir, strerror(errno));
    if (!S_ISDIR(st.st_mode))
        return ras_error_set(err,
                             "--buffers: '%s' is not a folder; expected the folder of a --dump "
                             "run",
                             dir);
    return true;
}

bool ras_dump_prepare_dir(const char *dir, ras_error *err) {
    struct stat st;
    if (!ras_io_path_fits("--dump", dir, err)) return false;
    if (stat(dir, &st) == 0) {
        if (S_ISDIR(st.st_mode)) return true;
        return ras_error_set(err,
                             "--dump expects a folder; '%s' exists and is not one: choose "
                             "another path",
                             dir);
    }
    if (errno == ENOENT && mkdir(dir, 0777) == 0) return true;
    return ras_error_set(err,
                         "--dump could not create the folder '%s' (%s): create it, or "
                         "choose a folder you can write",
                         dir, strerror(errno));
}

/* Staging folders of this DIR (".BASE-XXXXXX") that a kill -9 left, from
 * before this run began: their buffer files and then the folder removed
 * (a folder holding anything else is left alone). */
static void remove_stale_stages(const char *parent, const char *base) {
    time_t start = ras_io_process_start();
    DIR *d = start ? opendir(parent) : NULL;
    struct dirent *e;
    size_t bl = strlen(base);
    while (d && (e = readdir(d)) != NULL) {
        const char *n = e->d_name;
        size_t nl = strlen(n);
        if (nl != bl + 8 || n[0] != '.' || strncmp(n + 1, base, bl) || n[bl + 1] != '-') continue;
        struct stat sb;
        if (fstatat(dirfd(d), n, &sb, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISDIR(sb.st_mode) ||
            sb.st_uid != geteuid() || sb.st_mtime >= start - 1)
            continue;
        int fd = openat(dirfd(d), n, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        DIR *in = fd >= 0 ? fdopendir(fd) : NULL;
        struct dirent *f;
        while (in && (f = readdir(in)) != NULL) {
            size_t fl = strlen(f->d_name);
            bool ours = (fl > 4 && (!strcmp(f->d_name + fl - 4, ".pfm") ||
                                    !strcmp(f->d_name + fl - 4, ".png"))) ||
                        (fl > 5 && !strcmp(f->d_name + fl - 5, ".json"));
            if (ours) unlinkat(dirfd(in), f->d_name, 0);
        }
        if (in) closedir(in);
        else if (fd >= 0) close(fd);
        unlinkat(dirfd(d), n, AT_REMOVEDIR); /* fails, harmlessly, when not empty */
    }
    if (d) closedir(d);
}

bool ras_dump_stage_begin(ras_dump_stage *st, const char *dir, ras_error *err) {
    memset(st, 0, sizeof *st);
    if (!ras_io_path_fits("--dump", dir, err)) return false;
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/') n--; /* "out/" is the folder "out" */
    snprintf(st->target, sizeof st->target, "%.*s", (int)n, dir);
    struct stat sb;
    st->existed = stat(st->target, &sb) == 0;
    if (st->existed && !S_ISDIR(sb.st_mode))
        return ras_error_set(err,
                             "--dump expects a folder; '%s' exists and is not one: choose "
                             "another path",
                             dir);
    if (st->existed && ((sb.st_mode & 0222) == 0 || access(st->target, W_OK | X_OK) != 0))
        return ras_error_set(err,
                             "--dump: the folder '%s' is not writable (mode %04o); expected a "
                             "folder this run may write into — choose another, or change its "
                             "mode (checked before rendering)",
                             dir, (unsigned)(sb.st_mode & 07777));
    const char *slash = strrchr(st->target, '/');
    const char *base = slash ? slash + 1 : st->target;
    char parent[1100];
    if (!slash) snprintf(parent, sizeof parent, ".");
    else if (slash == st->target) snprintf(parent, sizeof parent, "/");
    else snprintf(parent, sizeof parent, "%.*s", (int)(slash - st->target), st->target);
    remove_stale_stages(parent, base);
    (void)snprintf(st->temp, sizeof st->temp, "%s/.%.200s-XXXXXX", parent, base);
    if (!mkdtemp(st->temp))
        return ras_error_set(err,
                             "--dump could not create the folder '%s' (%s creating a temporary "
                             "folder in '%s'): create it, or choose a folder you can write",
                             dir, strerror(errno), parent);
    st->active = true;
    return true;
}

/* Every entry of folder `from` renamed into `to` (same file system). */
static bool move_entries(const char *from, const char *to, ras_error *err) {
    DIR *d = opendir(from);
    int tfd = open(to, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    bool ok = d && tfd >= 0;
    struct dirent *e;
    while (ok && (e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        if (renameat(dirfd(d), e->d_name, tfd, e->d_name) != 0)
            ok = ras_error_set(err, "--dump: could not move '%s' into '%s' (%s)", e->d_name, to,
                               strerror(errno));
    }
    if (!d || tfd < 0) ras_error_set(err, "--dump: could not open '%s' (%s)", d ? to : from,
                                     strerror(errno));
    if (tfd >= 0) {
        fsync(tfd);
        close(tfd);
    }
    if (d) closedir(d);
    return ok;
}

bool ras_dump_stage_commit(ras_dump_stage *st, ras_error *err) {
    if (!st->active) return true;
    bool ok;
    if (!st->existed && rename(st->temp, st->target) == 0) {
        ok = true;
    } else {
        if (!st->existed && mkdir(st->target, 0777) != 0 && errno != EEXIST) {
            ras_error_set(err, "--dump could not create the folder '%s' (%s)", st->target,
                          strerror(errno));
            ras_dump_stage_abort(st);
            return false;
        }
        ok = move_entries(st->temp, st->target, err);
        ras_dump_stage_abort(st); /* what is left of the temporary folder */
        return ok;
    }
    st->active = false;
    return ok;
}

void ras_dump_stage_abort(ras_dump_stage *st) {
    if (!st->active) return;
    DIR *d = opendir(st->temp);
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) unlinkat(dirfd(d), e->d_name, 0);
    if (d) closedir(d);
    rmdir(st->temp);
    st->active = false;
}

/* Pipeline order (DESIGN.md, "a verdict follows the evidence"): which
 * samples are covered, which survive the depth test, how often each pixel
 * is shaded, what the shader was given, what it wrote per sample. */
const char *const ras_dump_buffer_names[] = {"coverage", "depth",      "overdraw",      "normal",
                                             "uv",       "view_depth", "sample_colour", NULL};
