/* ras_dump.c — see ras_dump.h. */
#include "ras_dump.h"

#include "cv_bridge.h"
#include "ras_image.h"
#include "ras_io.h"
#include "ras_mesh.h"
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

/* Range of the finite, non-empty values per channel; counts of empty and
 * non-finite entries. */
typedef struct stats {
    double lo[3], hi[3];
    long empty, nonfinite, entries;
} stats;

static stats buffer_stats(const ras_dump_buffer *b) {
    stats s = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}, 0, 0, 0};
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
static stats drawn_range(const ras_dump_buffer *b, stats s) {
    if (b->range && b->style == RAS_DUMP_SCALAR) s.lo[0] = b->range[0], s.hi[0] = b->range[1];
    return s;
}

static void paint(const ras_dump_buffer *b, const stats *s_own, uint8_t *rgb) {
    stats drawn = drawn_range(b, *s_own);
    const stats *s = &drawn;
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

static void legend_text(const ras_dump_buffer *b, const stats *s_own, char *text, size_t size) {
    stats drawn = drawn_range(b, *s_own);
    const stats *s = &drawn;
    if (b->style == RAS_DUMP_SCALAR && s->lo[0] <= s->hi[0])
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

static void legend(const ras_dump_buffer *b, const stats *s, uint8_t *rgb) {
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
    stats s = buffer_stats(b);
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
static bool write_json_file(const char *path, const char *what, cJSON *j, ras_error *err) {
    char *text = cJSON_Print(j);
    cJSON_Delete(j);
    if (!text) return ras_error_set(err, "out of memory writing '%s'", path);
    size_t len = strlen(text);
    text[len] = '\n'; /* cJSON's terminator becomes the last newline */
    bool ok = ras_io_write_atomic(path, what, text, len + 1, NULL, NULL, err);
    free(text);
    return ok;
}

static bool write_json(const char *path, const ras_dump_buffer *b, const stats *s, ras_error *err) {
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
    return write_json_file(path, "buffer description", j, err);
}

bool ras_dump_write(const char *dir, const ras_dump_buffer *b, ras_error *err) {
    if (b->channels != 1 && b->channels != 3)
        return ras_error_set(err, "buffer '%s': 1 or 3 channels, not %d", b->name, b->channels);
    stats s = buffer_stats(b);
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

/* The tolerance of a buffer kind, and whether it is relative to the value. */
static double tolerance_of(const char *name, bool *relative) {
    *relative = !strcmp(name, "depth") || !strcmp(name, "view_depth");
    if (*relative) return 1e-5;
    if (!strcmp(name, "normal")) return 1e-3;
    if (!strcmp(name, "uv")) return 1e-4;
    /* half an 8-bit level: a float-style difference never shows, a wrong
     * sample colour always does */
    if (!strcmp(name, "sample_colour")) return 0.5 / 255;
    return 0; /* coverage, overdraw: counts */
}

/* The exact file of buffer `name` in dir: NAME.pfm, or NAME.pfm.gz (the
 * shipped reference buffers are compressed); false, with path the .pfm,
 * when there is neither. */
static bool exact_path(const char *dir, const char *name, char *path, size_t size) {
    struct stat st;
    snprintf(path, size, "%s/%s.pfm", dir, name);
    if (lstat(path, &st) == 0) return true;
    snprintf(path, size, "%s/%s.pfm.gz", dir, name);
    if (lstat(path, &st) == 0) return true;
    snprintf(path, size, "%s/%s.pfm", dir, name);
    return false;
}

bool ras_dump_has_exact(const char *dir, const char *name) {
    char path[RAS_IO_MAX_PATH + 64];
    return exact_path(dir, name, path, sizeof path);
}

/* max_bytes < 0: a reference, which may be compressed; else the file must
 * be an uncompressed .pfm of at most max_bytes. */
static float *read_dump(const char *dir, const char *name, long max_bytes, int *w, int *h, int *ch,
                        ras_error *err) {
    char path[RAS_IO_MAX_PATH + 64];
    struct stat st;
    if (max_bytes < 0)
        exact_path(dir, name, path, sizeof path);
    else
        snprintf(path, sizeof path, "%s/%s.pfm", dir, name);
    if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return ras_error_set(err, "%s: no buffer file (expected a regular file)", path), NULL;
    if (max_bytes >= 0 && st.st_size > max_bytes)
        return ras_error_set(err, "%s: %lld bytes, more than the reference's %ld", path,
                             (long long)st.st_size, max_bytes),
               NULL;
    return ras_dump_read_pfm(path, w, h, ch, err);
}

/* A JSON file (`what`, at most `limit` bytes) parsed; NULL with the reason
 * in text. */
static cJSON *read_json(const char *path, const char *what, size_t limit, char *text, size_t size) {
    ras_error err = {{0}};
    size_t len = 0;
    char *data = ras_io_read_file(path, what, limit, &len, &err);
    if (!data) {
        snprintf(text, size, "%s", err.msg);
        return NULL;
    }
    cJSON *j = cJSON_ParseWithLength(data, len);
    free(data);
    if (!j) snprintf(text, size, "%s is not JSON", path);
    return j;
}

/* The samples per pixel a dump's sidecar gives buffer `name` (1 when it
 * says nothing usable: the buffers a frame makes are width*samples wide,
 * and only depth and coverage have more than one). */
static int sidecar_samples(const char *dir, const char *name, int pfm_width) {
    char path[RAS_IO_MAX_PATH + 64], why[256];
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    cJSON *j = read_json(path, "buffer description", 1u << 20, why, sizeof why);
    const cJSON *s = cJSON_GetObjectItemCaseSensitive(j, "samples");
    int samples =
        cJSON_IsNumber(s) && s->valueint >= 1 && pfm_width % s->valueint == 0 ? s->valueint : 1;
    cJSON_Delete(j);
    return samples;
}

/* Buffer `name` of two dumps, read to be compared: the reference's (a
 * shipped one may be .pfm.gz), then the other's, read only if no larger
 * than the reference's decoded size and then required to have its size;
 * `w` is the files' width (pixels times samples), `samples` the
 * reference's. Both malloc'd; false with err set (nothing to free). */
static bool load_pair(const char *ref_dir, const char *got_dir, const char *name, float **ref,
                      float **got, int *w, int *h, int *ch, int *samples, ras_error *err) {
    int gw, gh, gc;
    *got = NULL;
    *ref = read_dump(ref_dir, name, -1, w, h, ch, err);
    if (!*ref) return false;
    long limit = (long)*w * *h * *ch * (long)sizeof(float) + 4096;
    *got = read_dump(got_dir, name, limit, &gw, &gh, &gc, err);
    if (*got && (gw != *w || gh != *h || gc != *ch))
        ras_error_set(err,
                      "%s: expected %dx%d with %d channel(s) like the reference, got %dx%d "
                      "with %d",
                      name, *w, *h, *ch, gw, gh, gc);
    if (!*got || gw != *w || gh != *h || gc != *ch) {
        free(*ref);
        free(*got);
        *ref = *got = NULL;
        return false;
    }
    *samples = sidecar_samples(ref_dir, name, *w);
    return true;
}

/* The pattern of the differing pixels (`bad`, w x h): isolated pixels, a
 * row or column wrong while its neighbours are not, pixels only one side
 * drew, or regions. False when out of memory. */
static bool classify(ras_dump_difference *d, const unsigned char *bad, int w, int h) {
    int *rows = calloc((size_t)h, sizeof *rows), *cols = calloc((size_t)w, sizeof *cols);
    if (!rows || !cols) {
        free(rows), free(cols);
        return false;
    }
    for (int row = 0; row < h; row++)
        for (int x = 0; x < w; x++) {
            if (!bad[(size_t)row * w + x]) continue;
            rows[row]++, cols[x]++;
            int around = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++)
                    if ((dx || dy) && row + dy >= 0 && row + dy < h && x + dx >= 0 && x + dx < w)
                        around += bad[(size_t)(row + dy) * w + x + dx];
            d->isolated += around <= 2;
        }
    for (int pass = 0; pass < 2 && d->line < 0; pass++) {
        const int *line = pass ? cols : rows;
        int n = pass ? w : h;
        for (int i = 0; i < n; i++) {
            int beside = 0;
            if (i > 0 && line[i - 1] > beside) beside = line[i - 1];
            if (i < n - 1 && line[i + 1] > beside) beside = line[i + 1];
            if (line[i] >= 24 && line[i] >= 4 * (beside + 1) && line[i] * 2 >= d->pixels_differ) {
                d->line = i, d->line_is_column = pass == 1;
                break;
            }
        }
    }
    free(rows), free(cols);
    if (d->pixels_differ == 0)
        d->pattern = "";
    else if (d->line >= 0)
        d->pattern = d->line_is_column ? "along a column" : "along a row";
    else if (d->isolated * 2 >= d->pixels_differ)
        d->pattern = "in speckles";
    else if (d->drawn_in_one * 2 >= d->pixels_differ)
        d->pattern = "where only one drew";
    else
        d->pattern = "in regions";
    return true;
}

bool ras_dump_compare(const char *ref_dir, const char *got_dir, const char *name,
                      ras_dump_difference *d, ras_error *err) {
    *d = (ras_dump_difference){.line = -1, .first_col = -1, .first_row = -1, .pattern = ""};
    int rw, rh, rc, samples;
    float *ref, *got;
    if (!load_pair(ref_dir, got_dir, name, &ref, &got, &rw, &rh, &rc, &samples, err)) return false;
    int w = rw / samples, h = rh, per = samples * rc;
    bool relative;
    double tol = tolerance_of(name, &relative);
    unsigned char *bad = calloc((size_t)w * h, 1);
    if (!bad) {
        free(ref);
        free(got);
        return ras_error_set(err, "out of memory comparing the %s buffers", name);
    }
    d->entries = (long)rw * rh * rc;
    for (int row = 0; row < h; row++)
        for (int x = 0; x < w; x++) {
            const float *a = ref + ((size_t)row * w + x) * per,
                        *b = got + ((size_t)row * w + x) * per;
            bool differs = false, one_empty = false, larger = false, signed_once = false;
            for (int k = 0; k < per; k++) {
                bool ea = isinf(a[k]) && a[k] > 0, eb = isinf(b[k]) && b[k] > 0;
                if (ea != eb) {
                    one_empty = differs = true;
                    continue;
                }
                if (ea) continue;
                if (isnan(a[k]) != isnan(b[k])) {
                    differs = true;
                    continue;
                }
                if (isnan(a[k])) continue;
                double diff = fabs((double)a[k] - b[k]);
                double limit = relative ? tol * fmax(1.0, fabs((double)a[k])) : tol;
                if (diff > d->max_abs && isfinite(diff)) d->max_abs = diff;
                if (diff > limit || !isfinite(diff)) {
                    differs = true;
                    if (!signed_once) larger = b[k] > a[k], signed_once = true;
                }
            }
            if (!differs) continue;
            bad[(size_t)row * w + x] = 1;
            d->pixels_differ++;
            d->drawn_in_one += one_empty;
            d->larger += larger;
            if (d->first_col < 0) d->first_col = x, d->first_row = row;
        }
    free(ref);
    free(got);
    bool classified = classify(d, bad, w, h);
    free(bad);
    if (!classified) return ras_error_set(err, "out of memory comparing the %s buffers", name);
    return true;
}

void ras_dump_difference_text(const char *name, const ras_dump_difference *d, char *buf,
                              size_t size) {
    if (d->pixels_differ == 0) {
        snprintf(buf, size, "%s: the same (within its tolerance)", name);
        return;
    }
    char where[80] = "";
    if (d->line >= 0)
        snprintf(where, sizeof where, " %d", d->line);
    else if (!strcmp(d->pattern, "in speckles"))
        snprintf(where, sizeof where, ": %ld isolated", d->isolated);
    snprintf(buf, size,
             "%s differs in %ld pixels (largest difference %.3g), %s%s; the first at (%d, %d)%s",
             name, d->pixels_differ, d->max_abs, d->pattern, where, d->first_col, d->first_row,
             d->drawn_in_one ? "" : "");
}

static cJSON *numbers(const float *v, int n) {
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; k < n; k++)
        cJSON_AddItemToArray(a, isfinite(v[k]) ? cJSON_CreateNumber(v[k]) : cJSON_CreateNull());
    return a;
}

bool ras_dump_vertices(const char *dir, const char *stem, const ras_mesh *mesh, mat4s model,
                       mat4s view, mat4s projection, int width, int height, ras_error *err) {
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "buffer", "vertices");
    cJSON_AddStringToObject(
        j, "what",
        "each vertex at every step of the vertex stage: object -> world (model) -> eye (view) "
        "-> clip (projection) -> NDC (divided by w) -> screen (viewport: x right, y up, pixel "
        "(x, y) covers [x, x+1) x [y, y+1)); null where a value is not finite");
    cJSON_AddNumberToObject(j, "width", width);
    cJSON_AddNumberToObject(j, "height", height);
    cJSON_AddItemToObject(j, "model", numbers((const float *)model.raw, 16));
    cJSON_AddItemToObject(j, "view", numbers((const float *)view.raw, 16));
    cJSON_AddItemToObject(j, "projection", numbers((const float *)projection.raw, 16));
    cJSON_AddStringToObject(j, "matrix_layout", "column-major (cglm): m[column][row]");
    cJSON *vs = cJSON_AddArrayToObject(j, "vertices");
    size_t n = mesh->vertex_count < 4096 ? mesh->vertex_count : 4096;
    for (size_t i = 0; i < n; i++) {
        vec4s object = glms_vec4(mesh->positions[i], 1.0f);
        vec4s world = ras_mat4_mulv(model, object);
        vec4s eye = ras_mat4_mulv(view, world);
        vec4s clip = ras_mat4_mulv(projection, eye);
        vec4s ndc = glms_vec4_scale(clip, 1.0f / clip.w);
        vec4s screen = ras_viewport(clip, width, height);
        cJSON *v = cJSON_CreateObject();
        cJSON_AddItemToObject(v, "object", numbers(object.raw, 3));
        cJSON_AddItemToObject(v, "world", numbers(world.raw, 3));
        cJSON_AddItemToObject(v, "eye", numbers(eye.raw, 3));
        cJSON_AddItemToObject(v, "clip", numbers(clip.raw, 4));
        cJSON_AddItemToObject(v, "ndc", numbers(ndc.raw, 3));
        cJSON_AddItemToObject(v, "screen", numbers(screen.raw, 3));
        cJSON_AddItemToArray(vs, v);
    }
    if (n < mesh->vertex_count)
        cJSON_AddNumberToObject(j, "vertices_left_out", (double)(mesh->vertex_count - n));
    char path[RAS_IO_MAX_PATH + 64];
    snprintf(path, sizeof path, "%s/%s.json", dir, stem);
    return write_json_file(path, "vertex dump", j, err);
}

int ras_dump_compare_vertices(const char *ref_path, const char *got_path, char *text, size_t size) {
    cJSON *a = read_json(ref_path, "vertex dump", 16u << 20, text, size),
          *b = a ? read_json(got_path, "vertex dump", 16u << 20, text, size) : NULL;
    const cJSON *va = cJSON_GetObjectItemCaseSensitive(a, "vertices");
    const cJSON *vb = cJSON_GetObjectItemCaseSensitive(b, "vertices");
    int result = -1;
    if (a && b && (!cJSON_IsArray(va) || !cJSON_IsArray(vb)))
        snprintf(text, size, "not a vertex dump (no \"vertices\" list)");
    else if (a && b && cJSON_GetArraySize(va) != cJSON_GetArraySize(vb))
        snprintf(text, size, "vertices: %d in the reference, %d here", cJSON_GetArraySize(va),
                 cJSON_GetArraySize(vb));
    else if (a && b) {
        static const char *const steps[] = {"object", "world", "eye", "clip", "ndc", "screen"};
        result = 0;
        snprintf(text, size, "vertices: the same at every step");
        for (int i = 0; i < cJSON_GetArraySize(va) && !result; i++)
            for (int s = 0; s < 6 && !result; s++) {
                const cJSON *x =
                    cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(va, i), steps[s]);
                const cJSON *y =
                    cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(vb, i), steps[s]);
                int n = cJSON_GetArraySize(x);
                bool same = cJSON_GetArraySize(y) == n;
                for (int k = 0; k < n && same; k++) {
                    const cJSON *p = cJSON_GetArrayItem(x, k), *q = cJSON_GetArrayItem(y, k);
                    if (cJSON_IsNull(p) || cJSON_IsNull(q)) {
                        same = cJSON_IsNull(p) == cJSON_IsNull(q);
                        continue;
                    }
                    double u = p->valuedouble, v = q->valuedouble;
                    same = fabs(u - v) <= 1e-5 * fmax(1.0, fabs(u));
                }
                if (same) continue;
                result = 1;
                char want[160] = "", got[160] = "";
                for (int k = 0; k < n; k++) {
                    const cJSON *p = cJSON_GetArrayItem(x, k), *q = cJSON_GetArrayItem(y, k);
                    size_t lw = strlen(want), lg = strlen(got);
                    snprintf(want + lw, sizeof want - lw, "%s%.4g", k ? ", " : "",
                             cJSON_IsNumber(p) ? p->valuedouble : NAN);
                    snprintf(got + lg, sizeof got - lg, "%s%.4g", k ? ", " : "",
                             cJSON_IsNumber(q) ? q->valuedouble : NAN);
                }
                static const char *const matrix[] = {"the mesh itself", "the model matrix",
                                                     "the view matrix", "the projection matrix",
                                                     "the divide by w", "the viewport"};
                snprintf(text, size,
                         "vertices differ first at vertex %d, step %s: expected (%s), got (%s); "
                         "look at %s",
                         i, steps[s], want, got, matrix[s]);
            }
    }
    cJSON_Delete(a);
    cJSON_Delete(b);
    return result;
}

bool ras_dump_compare_pictures(const char *ref_dir, const char *got_dir, const char *name,
                               const char *out_dir, ras_error *err) {
    int w, h, ch, samples;
    float *ref, *got;
    if (!load_pair(ref_dir, got_dir, name, &ref, &got, &w, &h, &ch, &samples, err)) return false;
    size_t n = (size_t)w * h;
    float *diff = malloc(n * sizeof *diff);
    if (!diff) {
        free(ref);
        free(got);
        return ras_error_set(err, "out of memory drawing the %s buffers", name);
    }
    for (size_t i = 0; i < n; i++) {
        double m = 0;
        for (int c = 0; c < ch; c++) {
            float a = ref[i * ch + c], b = got[i * ch + c];
            double e = (isinf(a) && isinf(b) && a == b) ? 0 : fabs((double)a - b);
            m = fmax(m, isfinite(e) ? e : 1);
        }
        diff[i] = (float)m;
    }
    ras_dump_buffer ref_b = {.name = "reference",
                             .what = name,
                             .units = "",
                             .width = w / samples,
                             .height = h,
                             .samples = samples,
                             .channels = ch,
                             .data = ref,
                             .empty = INFINITY,
                             .has_empty = true};
    ref_b.style = ch == 1                   ? RAS_DUMP_SCALAR
                  : !strcmp(name, "normal") ? RAS_DUMP_VECTOR
                                            : RAS_DUMP_UNIT;
    stats rs = buffer_stats(&ref_b);
    double range[2] = {rs.lo[0], rs.hi[0]};
    ras_dump_buffer got_b = ref_b;
    got_b.name = "yours", got_b.data = got;
    if (ch == 1 && rs.lo[0] <= rs.hi[0]) got_b.range = range;
    ras_dump_buffer diff_b = ref_b;
    diff_b.name = "difference", diff_b.units = "|reference - yours|", diff_b.channels = 1;
    diff_b.data = diff, diff_b.style = RAS_DUMP_SCALAR, diff_b.empty = 0.0f;
    bool ok = ras_dump_write(out_dir, &ref_b, err) && ras_dump_write(out_dir, &got_b, err) &&
              ras_dump_write(out_dir, &diff_b, err);
    free(ref);
    free(got);
    free(diff);
    return ok;
}
