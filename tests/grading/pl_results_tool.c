/* pl_results_tool.c — raster101-pl-results: the grader's output folder as
 * PrairieLearn's external-grading results.json (the PrairieLearn package,
 * tests/grading/make-prairielearn; docs/instructors.md "PrairieLearn").
 *
 *   raster101-pl-results --from OUT --hw hwN -o RESULTS.json [--limit BYTES]
 *       OUT is tests/grading/grade's --out folder (its results.json, in
 *       Gradescope's format, and report.md, whose picture sections name the
 *       pictures of each item that lost points). Writes PrairieLearn's
 *       format: score in [0, 1] (hwN's points over its maximum), message,
 *       output, tests[] {name, points, max_points, message, output,
 *       images[] {label, url: a PNG data URI}}. A hwN that does not compile
 *       gives gradable: false with the compiler's lines in format_errors
 *       (PrairieLearn charges no attempt for it).
 *       Pictures: the reference (the public ones only: the grader never
 *       writes a variant's), the student's and the difference, each read
 *       from OUT without following a link, checked to be a PNG, in the
 *       order of the items; the whole file stays within --limit (PrairieLearn
 *       takes 1 MB; default 1000000 bytes): a picture that does not fit is
 *       downscaled (halved, up to three times) and else left out, and the
 *       test's message says which.
 *   raster101-pl-results --not-gradable -o RESULTS.json MESSAGE...
 *       gradable: false with each MESSAGE a format error (the entrypoint's
 *       own: no file submitted, the grader could not run).
 *   raster101-pl-results --student-id DATA.json
 *       prints "prairielearn:SEED" for the variant_seed of PrairieLearn's
 *       /grade/data/data.json (letters and digits only), or nothing.
 *
 * Exit status: 0 written, 2 bad arguments or an unreadable OUT.
 */
#include "ras_io.h"  /* ras_io_read_file, ras_io_write_atomic */
#include "ras_png.h" /* ras_png_is_png, ras_png_decode_rgb8, ras_png_encode_rgb8 */

#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define DEFAULT_LIMIT 1000000
#define MAX_PICTURE_BYTES (16u << 20)
#define MAX_REPORT_BYTES (64u << 20)
#define PNG_URI_PREFIX "data:image/png;base64,"
/* what a test's text may keep when the texts alone would not fit */
#define OUTPUT_CUT 4000

static void *xmalloc(size_t n) {
    void *p = malloc(n ? n : 1);
    if (!p) {
        fprintf(stderr, "raster101-pl-results: out of memory\n");
        exit(2);
    }
    return p;
}

static char *xstrndup(const char *s, size_t n) {
    char *d = xmalloc(n + 1);
    memcpy(d, s, n);
    d[n] = '\0';
    return d;
}

/* ------------------------------------------------------------ reading OUT */

/* A path the grader wrote into report.md, relative to OUT: only letters,
 * digits and ._-/, no empty or dot-dot component, not absolute. Anything
 * else is not the grader's and is not read. */
static bool plain_relative_path(const char *p) {
    if (!*p || *p == '/' || strlen(p) > 1000) return false;
    for (const char *c = p; *c; c++)
        if (!isalnum((unsigned char)*c) && !strchr("._-/", *c)) return false;
    for (const char *c = p; *c;) {
        size_t n = strcspn(c, "/");
        if (n == 0 || (n == 1 && c[0] == '.') || (n == 2 && c[0] == '.' && c[1] == '.'))
            return false;
        c += n;
        if (*c == '/') c++;
    }
    return true;
}

/* Opens OUT/rel for reading, no component a symbolic link (O_NOFOLLOW at
 * each step), a regular file; -1 otherwise. */
static int open_beneath(int dir, const char *rel) {
    char *copy = xstrndup(rel, strlen(rel));
    int fd = dup(dir);
    char *part = copy;
    while (fd >= 0) {
        char *slash = strchr(part, '/');
        if (slash) *slash = '\0';
        int flags = O_RDONLY | O_NOFOLLOW | O_CLOEXEC | (slash ? O_DIRECTORY : O_NONBLOCK);
        int next = openat(fd, part, flags);
        close(fd);
        fd = next;
        if (!slash) break;
        part = slash + 1;
    }
    free(copy);
    struct stat st;
    if (fd >= 0 && (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))) {
        close(fd);
        fd = -1;
    }
    return fd;
}

/* The whole of OUT/rel (at most max bytes), or NULL. */
static uint8_t *read_beneath(int dir, const char *rel, size_t max, size_t *len) {
    int fd = open_beneath(dir, rel);
    if (fd < 0) return NULL;
    struct stat st;
    if (fstat(fd, &st) != 0 || st.st_size < 0 || (size_t)st.st_size > max) {
        close(fd);
        return NULL;
    }
    uint8_t *buf = xmalloc((size_t)st.st_size + 1);
    size_t got = 0;
    while (got < (size_t)st.st_size) {
        ssize_t n = read(fd, buf + got, (size_t)st.st_size - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        got += (size_t)n;
    }
    close(fd);
    buf[got] = '\0';
    *len = got;
    return buf;
}

/* --------------------------------------------------------- the pictures */

typedef struct {
    char *label; /* reference, yours, difference, worst region, buffer: ... */
    char *path;  /* relative to OUT */
} picture_ref;

typedef struct {
    char *item;   /* "hwN: NAME", as results.json names the test */
    char *status; /* the grader's (PASS, FAIL, TODO, BUILD, ...): the table's */
    char *why;    /* the table's one-line reason */
    picture_ref *pics;
    int n_pics;
} item_pictures;

typedef struct {
    item_pictures *items;
    int n;
} report_pictures;

static item_pictures *item_add(report_pictures *r, const char *hw, const char *name, size_t len) {
    for (int i = 0; i < r->n; i++) {
        const char *it = r->items[i].item;
        size_t h = strlen(hw);
        if (!strncmp(it, hw, h) && !strncmp(it + h, ": ", 2) && strlen(it + h + 2) == len &&
            !strncmp(it + h + 2, name, len))
            return &r->items[i];
    }
    r->items = realloc(r->items, (size_t)(r->n + 1) * sizeof *r->items);
    if (!r->items) abort();
    item_pictures *it = &r->items[r->n++];
    memset(it, 0, sizeof *it);
    it->item = xmalloc(strlen(hw) + len + 3);
    sprintf(it->item, "%s: %.*s", hw, (int)len, name);
    return it;
}

/* Each ![label](path) of one line of an item's section. */
static void pictures_of_line(item_pictures *it, const char *line, size_t len, bool buffer) {
    const char *end = line + len;
    for (const char *c = line; c < end;) {
        const char *open = strstr(c, "![");
        if (!open || open >= end) break;
        const char *close = strstr(open, "](");
        const char *stop = close ? memchr(close + 2, ')', (size_t)(end - close - 2)) : NULL;
        if (!close || close >= end || !stop) break;
        char *path = xstrndup(close + 2, (size_t)(stop - close - 2));
        if (plain_relative_path(path)) {
            it->pics = realloc(it->pics, (size_t)(it->n_pics + 1) * sizeof *it->pics);
            if (!it->pics) abort();
            size_t ln = (size_t)(close - open - 2);
            char *label = xmalloc(ln + 9);
            sprintf(label, "%s%.*s", buffer ? "buffer: " : "", (int)ln, open + 2);
            it->pics[it->n_pics++] = (picture_ref){label, path};
        } else {
            free(path);
        }
        c = stop + 1;
    }
}

/* A cell of report.md's table as text: the grader's escapes undone. */
static char *cell_text(const char *c, size_t n) {
    while (n && *c == ' ') c++, n--;
    while (n && c[n - 1] == ' ') n--;
    char *out = xmalloc(n + 1), *o = out;
    for (size_t i = 0; i < n; i++) {
        if (c[i] == '\\' && i + 1 < n && strchr("\\`*_[]<>!#~&", c[i + 1])) i++;
        *o++ = c[i];
    }
    *o = '\0';
    return out;
}

/* "| STATUS | `NAME` | POINTS | WHY |": an item's status and reason. */
static void table_row(report_pictures *r, const char *hw, const char *line, size_t len) {
    const char *cells[6];
    int n = 0;
    for (const char *c = line; c < line + len && n < 6; c++)
        if (*c == '|') cells[n++] = c;
    if (n != 5) return;
    const char *tick = memchr(cells[1], '`', (size_t)(cells[2] - cells[1]));
    const char *end = tick ? memchr(tick + 1, '`', (size_t)(cells[2] - tick - 1)) : NULL;
    if (!end) return;
    item_pictures *it = item_add(r, hw, tick + 1, (size_t)(end - tick - 1));
    free(it->status);
    free(it->why);
    it->status = cell_text(cells[0] + 1, (size_t)(cells[1] - cells[0] - 1));
    it->why = cell_text(cells[3] + 1, (size_t)(cells[4] - cells[3] - 1));
}

/* report.md's picture sections: "## hwN — ..." opens an assignment,
 * "### NAME — STATUS (s / m)" an item that lost points; its image links
 * follow until the next heading. */
static report_pictures parse_report(const char *md) {
    report_pictures r = {0};
    char hw[64] = "";
    item_pictures *cur = NULL;
    bool buffer = false;
    for (const char *line = md; *line;) {
        size_t len = strcspn(line, "\n");
        const char *dash = NULL;
        for (const char *c = line; c + 4 < line + len && !dash; c++)
            if (!strncmp(c, " \xE2\x80\x94 ", 5)) dash = c; /* " — " */
        if (!strncmp(line, "## ", 3) && dash && (size_t)(dash - line - 3) < sizeof hw) {
            snprintf(hw, sizeof hw, "%.*s", (int)(dash - line - 3), line + 3);
            cur = NULL;
        } else if (!strncmp(line, "### ", 4) && dash && *hw) {
            cur = item_add(&r, hw, line + 4, (size_t)(dash - line - 4));
            buffer = false;
        } else if (!strncmp(line, "#", 1)) {
            cur = NULL;
        } else if (!cur && *hw && !strncmp(line, "| ", 2)) {
            table_row(&r, hw, line, len);
        } else if (cur) {
            if (!strncmp(line, "The first buffer that differs", 29)) buffer = true;
            pictures_of_line(cur, line, len, buffer);
        }
        line += len + (line[len] == '\n');
    }
    return r;
}

static const item_pictures *pictures_for(const report_pictures *r, const char *test_name) {
    for (int i = 0; i < r->n; i++) {
        size_t n = strlen(r->items[i].item);
        /* results.json may add " (default weight)" after the name */
        if (!strncmp(test_name, r->items[i].item, n) &&
            (!test_name[n] || !strcmp(test_name + n, " (default weight)")))
            return &r->items[i];
    }
    return NULL;
}

static char *base64_uri(const uint8_t *data, size_t len) {
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t pre = strlen(PNG_URI_PREFIX);
    char *out = xmalloc(pre + 4 * ((len + 2) / 3) + 1);
    memcpy(out, PNG_URI_PREFIX, pre);
    char *o = out + pre;
    for (size_t i = 0; i < len; i += 3) {
        uint32_t v = (uint32_t)data[i] << 16;
        if (i + 1 < len) v |= (uint32_t)data[i + 1] << 8;
        if (i + 2 < len) v |= data[i + 2];
        *o++ = tab[(v >> 18) & 63];
        *o++ = tab[(v >> 12) & 63];
        *o++ = i + 1 < len ? tab[(v >> 6) & 63] : '=';
        *o++ = i + 2 < len ? tab[v & 63] : '=';
    }
    *o = '\0';
    return out;
}

static size_t uri_size(size_t png_len) {
    return strlen(PNG_URI_PREFIX) + 4 * ((png_len + 2) / 3);
}

/* The PNG at half its size (2x2 boxes), or NULL. */
static uint8_t *png_half(const uint8_t *png, size_t len, size_t *out_len, int *w2, int *h2) {
    int w, h;
    bool exif = false;
    char err[256];
    uint8_t *rgb = ras_png_decode_rgb8(png, len, &w, &h, &exif, err, sizeof err);
    if (!rgb) return NULL;
    *w2 = w / 2;
    *h2 = h / 2;
    if (*w2 < 16 || *h2 < 16) {
        free(rgb);
        return NULL;
    }
    uint8_t *half = xmalloc((size_t)*w2 * (size_t)*h2 * 3);
    for (int y = 0; y < *h2; y++)
        for (int x = 0; x < *w2; x++)
            for (int c = 0; c < 3; c++) {
                const uint8_t *p = rgb + ((size_t)(2 * y) * (size_t)w + (size_t)(2 * x)) * 3 + c;
                unsigned s = p[0] + p[3] + p[(size_t)w * 3] + p[(size_t)w * 3 + 3];
                half[((size_t)y * (size_t)*w2 + (size_t)x) * 3 + c] = (uint8_t)((s + 2) / 4);
            }
    free(rgb);
    uint8_t *out = ras_png_encode_rgb8(*w2, *h2, half, out_len, err, sizeof err);
    free(half);
    return out;
}

/* Adds one picture to a test's images if it fits in *room (bytes of the
 * file still free), halving it up to three times; false if left out. */
static bool add_picture(cJSON *images, int out_dir, const picture_ref *p, size_t *room,
                        bool *downscaled) {
    size_t len = 0;
    uint8_t *png = read_beneath(out_dir, p->path, MAX_PICTURE_BYTES, &len);
    if (!png || !ras_png_is_png(png, len)) {
        free(png);
        return false;
    }
    char label[400];
    snprintf(label, sizeof label, "%s", p->label);
    size_t overhead = strlen(label) + 80; /* the object, indented as written */
    for (int halvings = 0; uri_size(len) + overhead > *room; halvings++) {
        size_t n2 = 0;
        int w2 = 0, h2 = 0;
        uint8_t *smaller = halvings < 3 ? png_half(png, len, &n2, &w2, &h2) : NULL;
        free(png);
        if (!smaller) return false;
        png = smaller;
        len = n2;
        snprintf(label, sizeof label, "%s (downscaled to %dx%d: PrairieLearn's 1 MB limit)",
                 p->label, w2, h2);
        overhead = strlen(label) + 80;
    }
    *downscaled |= strcmp(label, p->label) != 0;
    char *uri = base64_uri(png, len);
    free(png);
    cJSON *img = cJSON_CreateObject();
    cJSON_AddStringToObject(img, "label", label);
    cJSON_AddStringToObject(img, "url", uri);
    cJSON_AddItemToArray(images, img);
    *room -= uri_size(len) + overhead;
    free(uri);
    return true;
}

/* ------------------------------------------------------ results.json */

/* the size of the file as written (write_json) */
static size_t json_size(const cJSON *root) {
    char *s = cJSON_Print(root);
    size_t n = s ? strlen(s) : SIZE_MAX;
    free(s);
    return n;
}

static const char *json_str(const cJSON *o, const char *key, const char *dflt) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : dflt;
}

static double json_num(const cJSON *o, const char *key) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : 0;
}

static bool write_json(const cJSON *root, const char *path) {
    char *s = cJSON_Print(root);
    if (!s) return false;
    ras_error err;
    bool ok = ras_io_write_atomic(path, "results", s, strlen(s), NULL, NULL, &err);
    if (!ok) fprintf(stderr, "raster101-pl-results: %s\n", err.msg);
    free(s);
    return ok;
}

/* The file PrairieLearn reads when there is nothing to grade. */
static cJSON *not_gradable(const char *const *errors, int n) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddBoolToObject(root, "gradable", false);
    cJSON_AddNumberToObject(root, "score", 0);
    cJSON *fe = cJSON_AddArrayToObject(root, "format_errors");
    for (int i = 0; i < n; i++)
        cJSON_AddItemToArray(fe, cJSON_CreateString(errors[i]));
    cJSON_AddStringToObject(root, "message", n ? errors[0] : "not gradable");
    return root;
}

/* hwN did not compile: the compiler's lines, as the grader quoted them in
 * every item of hwN. */
static cJSON *compile_error(const cJSON *gs, const char *hw) {
    char prefix[80];
    snprintf(prefix, sizeof prefix, "%s: ", hw);
    const char *said = NULL;
    const cJSON *t;
    cJSON_ArrayForEach(t, cJSON_GetObjectItemCaseSensitive(gs, "tests")) {
        if (!strncmp(json_str(t, "name", ""), prefix, strlen(prefix))) {
            said = json_str(t, "output", NULL);
            break;
        }
    }
    char first[200];
    snprintf(first, sizeof first,
             "Your %s code does not compile, so nothing could be tested: fix the compiler's "
             "errors below and submit again (this attempt is not counted).",
             hw);
    const char *errors[2] = {first, said ? said : "(the compiler's lines were not found)"};
    return not_gradable(errors, 2);
}

/* The estimate above is close, not exact: the last pictures go until the
 * whole file fits, each test that lost one saying so. */
static int drop_past_limit(cJSON *tests, size_t limit, const cJSON *root) {
    int dropped = 0;
    while (json_size(root) > limit) {
        cJSON *last = NULL, *t;
        cJSON_ArrayForEach(t, tests) {
            if (cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(t, "images")) > 0) last = t;
        }
        if (!last) break;
        cJSON *images = cJSON_GetObjectItemCaseSensitive(last, "images");
        cJSON_DeleteItemFromArray(images, cJSON_GetArraySize(images) - 1);
        const char *m = json_str(last, "message", "");
        if (!strstr(m, "left out")) {
            char note[800];
            snprintf(note, sizeof note, "%.600s (pictures left out: PrairieLearn's 1 MB limit)", m);
            cJSON_ReplaceItemInObjectCaseSensitive(last, "message", cJSON_CreateString(note));
        }
        dropped++;
    }
    return dropped;
}

/* Each test of hwN with its pictures, as long as they fit in the limit. */
static cJSON *graded(const cJSON *gs, const char *hw, int out_dir, const report_pictures *pics,
                     size_t limit) {
    const cJSON *ea =
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(gs, "extra_data"), hw);
    double got = json_num(ea, "score"), max = json_num(ea, "max_score");
    double score = max > 0 ? got / max : 0;
    score = score < 0 ? 0 : score > 1 ? 1 : score;
    char msg[300];
    snprintf(msg, sizeof msg, "%s: %g / %g points", hw, got, max);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddBoolToObject(root, "gradable", true);
    cJSON_AddNumberToObject(root, "score", score);
    cJSON_AddStringToObject(root, "message", msg);
    cJSON_AddStringToObject(root, "output", json_str(gs, "output", ""));
    cJSON *tests = cJSON_AddArrayToObject(root, "tests");
    char prefix[80];
    snprintf(prefix, sizeof prefix, "%s: ", hw);
    const cJSON *t;
    cJSON_ArrayForEach(t, cJSON_GetObjectItemCaseSensitive(gs, "tests")) {
        const char *name = json_str(t, "name", "");
        if (strncmp(name, prefix, strlen(prefix))) continue;
        cJSON *nt = cJSON_CreateObject();
        cJSON_AddStringToObject(nt, "name", name);
        cJSON_AddNumberToObject(nt, "points", json_num(t, "score"));
        cJSON_AddNumberToObject(nt, "max_points", json_num(t, "max_score"));
        const item_pictures *ip = pictures_for(pics, name);
        char said[600];
        if (ip && ip->status)
            snprintf(said, sizeof said, "%s%s%.500s", ip->status, *ip->why ? ": " : "", ip->why);
        else
            snprintf(said, sizeof said, "%s", json_str(t, "status", ""));
        cJSON_AddStringToObject(nt, "message", said);
        cJSON_AddStringToObject(nt, "output", json_str(t, "output", ""));
        cJSON_AddItemToArray(tests, nt);
    }
    /* the texts alone past the limit (they should never be): each cut */
    cJSON *pt;
    if (json_size(root) + 200 > limit) {
        cJSON_ArrayForEach(pt, tests) {
            const char *o = json_str(pt, "output", "");
            if (strlen(o) <= OUTPUT_CUT) continue;
            char *cut = xmalloc(OUTPUT_CUT + 100);
            snprintf(cut, OUTPUT_CUT + 100, "%.*s\n[cut here: PrairieLearn's 1 MB limit]",
                     OUTPUT_CUT, o);
            cJSON_ReplaceItemInObjectCaseSensitive(pt, "output", cJSON_CreateString(cut));
            free(cut);
        }
    }
    size_t used = json_size(root) + 200;
    size_t room = used < limit ? limit - used : 0;
    int left_out_total = 0;
    /* the pictures of the items that lost points first, then the others' */
    for (int lost_first = 1; lost_first >= 0; lost_first--) cJSON_ArrayForEach(pt, tests) {
        const item_pictures *ip = pictures_for(pics, json_str(pt, "name", ""));
        if (!ip || !ip->n_pics) continue;
        bool lost = json_num(pt, "points") < json_num(pt, "max_points");
        if (lost != (lost_first == 1)) continue;
        cJSON *images = cJSON_AddArrayToObject(pt, "images");
        int left_out = 0;
        bool downscaled = false;
        for (int i = 0; i < ip->n_pics; i++)
            left_out += !add_picture(images, out_dir, &ip->pics[i], &room, &downscaled);
        if (left_out || downscaled) {
            char note[800];
            snprintf(note, sizeof note, "%s (%s%s%s)", json_str(pt, "message", ""),
                     downscaled ? "pictures downscaled" : "", downscaled && left_out ? "; " : "",
                     left_out ? "pictures left out: PrairieLearn's 1 MB limit on results" : "");
            cJSON_ReplaceItemInObjectCaseSensitive(pt, "message", cJSON_CreateString(note));
            room = room > 200 ? room - 200 : 0;
        }
        left_out_total += left_out;
    }
    left_out_total += drop_past_limit(tests, limit, root);
    if (left_out_total) {
        snprintf(msg, sizeof msg, "%s: %g / %g points (%d pictures left out: PrairieLearn's 1 MB limit)",
                 hw, got, max, left_out_total);
        cJSON_ReplaceItemInObjectCaseSensitive(root, "message", cJSON_CreateString(msg));
    }
    return root;
}

static int convert(const char *from, const char *hw, const char *out_path, size_t limit) {
    int dir = open(from, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir < 0) {
        fprintf(stderr, "raster101-pl-results: cannot open the grader's output folder '%s': %s\n",
                from, strerror(errno));
        return 2;
    }
    size_t len = 0, md_len = 0;
    char *js = (char *)read_beneath(dir, "results.json", MAX_REPORT_BYTES, &len);
    cJSON *gs = js ? cJSON_Parse(js) : NULL;
    free(js);
    const cJSON *ea =
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(gs, "extra_data"), hw);
    if (!gs || !cJSON_IsObject(ea)) {
        fprintf(stderr,
                "raster101-pl-results: expected %s/results.json (tests/grading/grade's) with "
                "extra_data.%s; %s: was %s graded?\n",
                from, hw, gs ? "it has no such assignment" : "it is missing or not JSON", hw);
        cJSON_Delete(gs);
        close(dir);
        return 2;
    }
    cJSON *root;
    if (!strcmp(json_str(ea, "note", ""), "the code does not compile")) {
        root = compile_error(gs, hw);
    } else {
        char *md = (char *)read_beneath(dir, "report.md", MAX_REPORT_BYTES, &md_len);
        report_pictures pics = parse_report(md ? md : "");
        free(md);
        root = graded(gs, hw, dir, &pics, limit);
        for (int i = 0; i < pics.n; i++) {
            for (int k = 0; k < pics.items[i].n_pics; k++) {
                free(pics.items[i].pics[k].label);
                free(pics.items[i].pics[k].path);
            }
            free(pics.items[i].pics);
            free(pics.items[i].item);
            free(pics.items[i].status);
            free(pics.items[i].why);
        }
        free(pics.items);
    }
    size_t size = json_size(root);
    int rc = write_json(root, out_path) ? 0 : 2;
    if (!rc)
        printf("raster101-pl-results: %s (%zu bytes, limit %zu)\n", out_path, size,
               limit);
    cJSON_Delete(root);
    cJSON_Delete(gs);
    close(dir);
    return rc;
}

/* prairielearn:SEED from data.json's variant_seed (a number or a string),
 * letters and digits only. */
static int student_id(const char *data_path) {
    ras_error err;
    size_t len;
    char *s = ras_io_read_file(data_path, "data.json", 4u << 20, &len, &err);
    cJSON *d = s ? cJSON_Parse(s) : NULL;
    free(s);
    const cJSON *seed = cJSON_GetObjectItemCaseSensitive(d, "variant_seed");
    char buf[64] = "";
    if (cJSON_IsNumber(seed))
        snprintf(buf, sizeof buf, "%.0f", seed->valuedouble);
    else if (cJSON_IsString(seed))
        snprintf(buf, sizeof buf, "%s", seed->valuestring);
    bool ok = *buf;
    for (char *c = buf; *c; c++)
        ok &= isalnum((unsigned char)*c) != 0;
    if (ok) printf("prairielearn:%s\n", buf);
    cJSON_Delete(d);
    return 0;
}

static int usage(const char *why) {
    fprintf(stderr,
            "raster101-pl-results: %s\nusage: raster101-pl-results --from OUT --hw hwN -o "
            "RESULTS.json [--limit BYTES]\n       raster101-pl-results --not-gradable -o "
            "RESULTS.json MESSAGE...\n       raster101-pl-results --student-id DATA.json\n",
            why);
    return 2;
}

int main(int argc, char **argv) {
    const char *from = NULL, *hw = NULL, *out = NULL;
    size_t limit = DEFAULT_LIMIT;
    bool refuse = false;
    int i = 1;
    for (; i < argc; i++) {
        bool has = i + 1 < argc;
        if (!strcmp(argv[i], "--from") && has) {
            from = argv[++i];
        } else if (!strcmp(argv[i], "--hw") && has) {
            hw = argv[++i];
        } else if (!strcmp(argv[i], "-o") && has) {
            out = argv[++i];
        } else if (!strcmp(argv[i], "--limit") && has) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 10000) return usage("--limit expects a number of bytes >= 10000");
            limit = (size_t)v;
        } else if (!strcmp(argv[i], "--not-gradable")) {
            refuse = true;
        } else if (!strcmp(argv[i], "--student-id") && has) {
            return student_id(argv[i + 1]);
        } else if (refuse && argv[i][0] != '-') {
            break;
        } else {
            char why[300];
            snprintf(why, sizeof why, "unknown or incomplete argument '%.200s'", argv[i]);
            return usage(why);
        }
    }
    if (!out) return usage("-o RESULTS.json is required");
    if (refuse) {
        cJSON *root = not_gradable((const char *const *)argv + i, argc - i);
        int rc = write_json(root, out) ? 0 : 2;
        cJSON_Delete(root);
        return rc;
    }
    if (!from || !hw) return usage("--from OUT and --hw hwN are required");
    return convert(from, hw, out, limit);
}
