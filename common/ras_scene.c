/* ras_scene.c — scene files: JSON (through cJSON) → ras_scene → meshes and textures.
 *
 * Notes:
 *   - cJSON does the parsing; this file only checks what cJSON built, key by
 *     key, against the format documented in ras_scene.h and docs/scenes.md.
 *     cJSON keeps no source positions, so semantic errors name the key path
 *     (objects[2].material.ks) and only syntax errors name line:column,
 *     computed from cJSON_GetErrorPtr(). The syntax hints (trailing comma,
 *     comments, single quotes, ...) look at the characters around that point;
 *     they describe the error, they do not parse.
 *   - Every function that fills the scene returns false after setting the
 *     error; the caller unwinds and ras_scene_destroy frees whatever was
 *     filled in (the scene starts zeroed, so that is always safe).
 *   - Numbers: JSON has no NaN or Infinity, but a literal such as 1e400 reads
 *     as infinity, so every number is checked to be finite and in range
 *     before it is narrowed to float or int.
 *
 * Dependencies: cJSON (libcjson), cglm (struct API), ras_mesh, ras_texture.
 */
#include "ras_scene.h"

#include <cjson/cJSON.h> /* cJSON_ParseWithOpts, cJSON_GetErrorPtr, cJSON_* */

#include <ctype.h>    /* isalnum, isspace, tolower */
#include <errno.h>    /* errno */
#include <math.h>     /* isfinite, floor, cosf, sinf */
#include <stdarg.h>   /* va_list */
#include <stdio.h>    /* fdopen, fread, snprintf */
#include <stdlib.h>   /* calloc, malloc, free */
#include <string.h>   /* strcmp, strlen, strerror, memcpy */
#include <strings.h>  /* strncasecmp */
#include <sys/stat.h> /* stat, S_ISDIR */
#include <unistd.h>   /* close */

#include "ras_io.h"     /* ras_io_open_input */
#include "ras_memory.h" /* ras_memory_check, ras_memory_commit */
#include "ras_names.h"  /* the option values' spellings */

#define BIG 1e6 /* coordinates, strengths and scales are limited to ±1e6 */
#define PATH_LEN 192

/* ------------------------------------------------------------------------ */
/* Names                                                                     */

static const char *const shape_names[RAS_SHAPE_COUNT] = {"triangle", "plane",  "cube",     "sphere",
                                                         "torus",    "teapot", "thin_fan", "model"};
/* Option values are spelled by ras_names.h's tables; NAMES(t) passes one
 * to read_enum. */
#define NAMES(t) (t).names, (t).count
static const char *const space_names[] = {"view", "world"};
static const char *const builtin_map_names[] = {"checker", "brick", "bumps"};
#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

const char *ras_scene_shape_name(ras_scene_shape s) {
    return (unsigned)s < RAS_SHAPE_COUNT ? shape_names[s] : "?";
}
const char *ras_scene_shader_name(ras_scene_shader s) {
    return ras_name_of(&ras_names_shader, (int)s);
}
const char *ras_scene_filter_name(ras_scene_filter f) {
    return ras_name_of(&ras_names_filter, (int)f);
}
const char *ras_scene_cull_name(ras_cull_mode c) {
    return ras_name_of(&ras_names_cull, (int)c);
}

/* ------------------------------------------------------------------------ */
/* Messages                                                                  */

typedef struct ctx {
    const char *file; /* for messages */
    const char *dir;  /* relative paths resolve against it */
    ras_error *err;
} ctx;

/* "<file>: <path>: <message>" (no path: "<file>: <message>"). */
static bool fail(ctx *c, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bool fail(ctx *c, const char *path, const char *fmt, ...) {
    char msg[900];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (path && *path) return ras_error_set(c->err, "%s: %s: %s", c->file, path, msg);
    return ras_error_set(c->err, "%s: %s", c->file, msg);
}

/* A short quoted copy of s: at most 40 characters, quotes and control
 * characters escaped. */
static void quote(const char *s, char *buf, size_t size) {
    size_t o = 0;
    buf[o++] = '"';
    for (size_t i = 0; s[i] && o + 8 < size; i++) {
        if (i == 40) {
            memcpy(buf + o, "...", 3);
            o += 3;
            break;
        }
        unsigned char ch = (unsigned char)s[i];
        if (ch == '"' || ch == '\\') {
            buf[o++] = '\\';
            buf[o++] = (char)ch;
        } else if (ch < 0x20) {
            o += (size_t)snprintf(buf + o, size - o, "\\u%04x", ch);
        } else {
            buf[o++] = (char)ch;
        }
    }
    buf[o++] = '"';
    buf[o] = '\0';
}

static const char *describe_number(double d, char *buf, size_t size) {
    if (isfinite(d))
        snprintf(buf, size, "%.9g", d);
    else
        snprintf(buf, size, "a number too large to represent (it reads as %sinfinity)",
                 d < 0 ? "minus " : "");
    return buf;
}

/* What a JSON value is, for "got ..." (a type mismatch). */
static const char *describe(const cJSON *v, char *buf, size_t size) {
    char tmp[96];
    if (!v)
        snprintf(buf, size, "nothing");
    else if (cJSON_IsString(v)) {
        quote(v->valuestring, tmp, sizeof tmp);
        snprintf(buf, size, "a string (%s)", tmp);
    } else if (cJSON_IsNumber(v)) {
        if (isfinite(v->valuedouble))
            snprintf(buf, size, "a number (%.9g)", v->valuedouble);
        else
            describe_number(v->valuedouble, buf, size);
    } else if (cJSON_IsArray(v)) {
        int n = cJSON_GetArraySize(v);
        if (n == 0)
            snprintf(buf, size, "an empty array");
        else
            snprintf(buf, size, "an array of %d item%s", n, n == 1 ? "" : "s");
    } else if (cJSON_IsObject(v))
        snprintf(buf, size, "an object");
    else if (cJSON_IsTrue(v))
        snprintf(buf, size, "true");
    else if (cJSON_IsFalse(v))
        snprintf(buf, size, "false");
    else if (cJSON_IsNull(v))
        snprintf(buf, size, "null");
    else
        snprintf(buf, size, "an unknown value");
    return buf;
}

static bool fail_type(ctx *c, const char *path, const char *expected, const cJSON *got) {
    char d[160];
    return fail(c, path, "expected %s, got %s", expected, describe(got, d, sizeof d));
}

/* parent.key (or key at the top level), cut to PATH_LEN - 1 characters. */
static void join(char *out, const char *parent, const char *key) {
    size_t o = 0;
    for (const char *s = parent; s && *s && o + 1 < PATH_LEN; s++)
        out[o++] = *s;
    if (o > 0 && o + 1 < PATH_LEN) out[o++] = '.';
    for (const char *s = key; *s && o + 1 < PATH_LEN; s++)
        out[o++] = *s;
    out[o] = '\0';
}

/* parent[i] */
static void join_index(char *out, const char *parent, int i) {
    char index[16];
    snprintf(index, sizeof index, "[%d]", i);
    size_t o = 0;
    for (const char *s = parent; *s && o + 1 < PATH_LEN; s++)
        out[o++] = *s;
    for (const char *s = index; *s && o + 1 < PATH_LEN; s++)
        out[o++] = *s;
    out[o] = '\0';
}

/* ------------------------------------------------------------------------ */
/* Keys: unknown, duplicate, did-you-mean                                    */

/* Case-insensitive Levenshtein distance, or a large number for long strings. */
static int edit_distance(const char *a, const char *b) {
    size_t la = strlen(a), lb = strlen(b);
    if (la > 40 || lb > 40) return 99;
    int row[41];
    for (size_t j = 0; j <= lb; j++)
        row[j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        int diag = row[0];
        row[0] = (int)i;
        for (size_t j = 1; j <= lb; j++) {
            int up = row[j];
            int cost = tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]);
            int best = diag + cost;
            if (up + 1 < best) best = up + 1;
            if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[lb];
}

/* The name word abbreviates ("fov" → "fov_deg"), else the one within edit
 * distance 2 (closest first), or NULL. */
static const char *closest(const char *word, const char *const *names, int n) {
    size_t len = strlen(word);
    for (int i = 0; i < n && len >= 3; i++)
        if (strlen(names[i]) > len && !strncasecmp(word, names[i], len)) return names[i];
    const char *best = NULL;
    int best_d = 3;
    for (int i = 0; i < n; i++) {
        int d = edit_distance(word, names[i]);
        if (d < best_d) {
            best_d = d;
            best = names[i];
        }
    }
    return best;
}

static void list_names(const char *const *names, int n, char *buf, size_t size) {
    size_t o = 0;
    buf[0] = '\0';
    for (int i = 0; i < n && o < size; i++)
        o += (size_t)snprintf(buf + o, size - o, "%s%s",
                              i == 0       ? ""
                              : i == n - 1 ? " or "
                                           : ", ",
                              names[i]);
}

/* Every key of obj must be in `known` and appear once. `other` (may be NULL)
 * explains keys that are known elsewhere but not here: it returns a message
 * for such a key, or NULL. */
typedef const char *(*other_key_fn)(const char *key, const void *user, char *buf, size_t size);
static bool check_keys(ctx *c, const cJSON *obj, const char *path, const char *const *known, int n,
                       other_key_fn other, const void *user) {
    for (const cJSON *k = obj->child; k; k = k->next) {
        char p[PATH_LEN];
        join(p, path, k->string);
        for (const cJSON *j = obj->child; j != k; j = j->next)
            if (!strcmp(j->string, k->string))
                return fail(c, p, "duplicate key \"%s\": each key may appear once", k->string);
        bool ok = false;
        for (int i = 0; i < n && !ok; i++)
            ok = !strcmp(k->string, known[i]);
        if (ok) continue;
        char why[300];
        if (other && other(k->string, user, why, sizeof why)) return fail(c, p, "%s", why);
        char q[96];
        quote(k->string, q, sizeof q);
        const char *near = closest(k->string, known, n);
        if (near) return fail(c, p, "unknown key %s; did you mean \"%s\"?", q, near);
        char list[400];
        list_names(known, n, list, sizeof list);
        return fail(c, p, "unknown key %s; expected one of %s", q, list);
    }
    return true;
}

static const cJSON *member(const cJSON *obj, const char *key) {
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

/* ------------------------------------------------------------------------ */
/* Values                                                                    */

typedef struct range {
    double lo, hi;
    bool lo_open, hi_open;
    bool integer;
} range;

static const range R_ANY = {-BIG, BIG, false, false, false};
static const range R_NONNEG = {0, BIG, false, false, false};
static const range R_POS = {0, BIG, true, false, false};
static const range R_UNIT = {0, 1, false, false, false};

static void describe_range(range r, char *buf, size_t size) {
    if (r.integer)
        snprintf(buf, size, "a whole number in %.0f..%.0f", r.lo, r.hi);
    else
        snprintf(buf, size, "a number in %c%g, %g%c", r.lo_open ? '(' : '[', r.lo, r.hi,
                 r.hi_open ? ')' : ']');
}

static bool in_range(double d, range r) {
    if (!isfinite(d)) return false;
    if (r.lo_open ? !(d > r.lo) : !(d >= r.lo)) return false;
    if (r.hi_open ? !(d < r.hi) : !(d <= r.hi)) return false;
    return !r.integer || d == floor(d);
}

static bool read_number(ctx *c, const cJSON *v, const char *path, range r, double *out) {
    char want[96], got[128];
    describe_range(r, want, sizeof want);
    if (!cJSON_IsNumber(v)) return fail_type(c, path, want, v);
    if (!in_range(v->valuedouble, r))
        return fail(c, path, "expected %s, got %s", want,
                    describe_number(v->valuedouble, got, sizeof got));
    *out = v->valuedouble;
    return true;
}

static bool read_float(ctx *c, const cJSON *v, const char *path, range r, float *out) {
    double d;
    if (!read_number(c, v, path, r, &d)) return false;
    *out = (float)d;
    return true;
}

static bool read_int(ctx *c, const cJSON *v, const char *path, int lo, int hi, int *out) {
    double d;
    if (!read_number(c, v, path, (range){lo, hi, false, false, true}, &d)) return false;
    *out = (int)d;
    return true;
}

/* Optional members: absent leaves *out (the default) as it is. */
static bool opt_float(ctx *c, const cJSON *obj, const char *path, const char *key, range r,
                      float *out) {
    const cJSON *v = member(obj, key);
    char p[PATH_LEN];
    join(p, path, key);
    return !v || read_float(c, v, p, r, out);
}

static bool opt_int(ctx *c, const cJSON *obj, const char *path, const char *key, int lo, int hi,
                    int *out) {
    const cJSON *v = member(obj, key);
    char p[PATH_LEN];
    join(p, path, key);
    return !v || read_int(c, v, p, lo, hi, out);
}

static bool read_vec3(ctx *c, const cJSON *v, const char *path, range r, vec3s *out) {
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
        return fail_type(c, path, "an array of 3 numbers", v);
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        char p[PATH_LEN];
        join_index(p, path, i);
        if (!read_float(c, e, p, r, &out->raw[i])) return false;
    }
    return true;
}

/* A number (the same for x, y and z) or an array of 3. */
static bool read_vec3_or_scalar(ctx *c, const cJSON *v, const char *path, range r, vec3s *out) {
    if (cJSON_IsNumber(v)) {
        float f;
        if (!read_float(c, v, path, r, &f)) return false;
        *out = (vec3s){{f, f, f}};
        return true;
    }
    if (!cJSON_IsArray(v)) return fail_type(c, path, "a number or an array of 3 numbers", v);
    return read_vec3(c, v, path, r, out);
}

static bool opt_vec3(ctx *c, const cJSON *obj, const char *path, const char *key, range r,
                     vec3s *out) {
    const cJSON *v = member(obj, key);
    char p[PATH_LEN];
    join(p, path, key);
    return !v || read_vec3(c, v, p, r, out);
}

static bool opt_vec3_or_scalar(ctx *c, const cJSON *obj, const char *path, const char *key, range r,
                               vec3s *out) {
    const cJSON *v = member(obj, key);
    char p[PATH_LEN];
    join(p, path, key);
    return !v || read_vec3_or_scalar(c, v, p, r, out);
}

static int hex_digit(char ch) {
    if (ch >= '0' && ch <= '9') return ch - '0';
    if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
    return -1;
}

/* A colour: [r, g, b] in [0, 1], or "#rrggbb". */
static bool read_color(ctx *c, const cJSON *v, const char *path, vec3s *out) {
    static const char *want = "a colour: an array of 3 numbers in [0, 1] or a \"#rrggbb\" string";
    if (cJSON_IsString(v)) {
        const char *s = v->valuestring;
        bool ok = strlen(s) == 7 && s[0] == '#';
        for (int i = 1; ok && i < 7; i++)
            ok = hex_digit(s[i]) >= 0;
        if (!ok) return fail_type(c, path, want, v);
        for (int i = 0; i < 3; i++)
            out->raw[i] = (float)(hex_digit(s[1 + 2 * i]) * 16 + hex_digit(s[2 + 2 * i])) / 255.0f;
        return true;
    }
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3) return fail_type(c, path, want, v);
    /* 8-bit values are the classic slip: say how to write them. */
    bool bytes = true, over = false;
    for (const cJSON *e = v->child; e; e = e->next) {
        if (!cJSON_IsNumber(e)) {
            bytes = false;
            continue;
        }
        double d = e->valuedouble;
        if (!(d >= 0 && d <= 255 && d == floor(d))) bytes = false;
        if (d > 1) over = true;
    }
    if (bytes && over) {
        int b[3], i = 0;
        for (const cJSON *e = v->child; e; e = e->next)
            b[i++] = (int)e->valuedouble;
        return fail(c, path,
                    "expected colour components in [0, 1], got [%d, %d, %d]; for 8-bit values "
                    "write \"#%02x%02x%02x\" (or divide each by 255)",
                    b[0], b[1], b[2], b[0], b[1], b[2]);
    }
    return read_vec3(c, v, path, R_UNIT, out);
}

static bool opt_color(ctx *c, const cJSON *obj, const char *path, const char *key, vec3s *out) {
    const cJSON *v = member(obj, key);
    char p[PATH_LEN];
    join(p, path, key);
    return !v || read_color(c, v, p, out);
}

static bool read_enum(ctx *c, const cJSON *v, const char *path, const char *const *names, int n,
                      int *out) {
    char list[300];
    list_names(names, n, list, sizeof list);
    char want[340];
    snprintf(want, sizeof want, "one of %s", list);
    if (!cJSON_IsString(v)) return fail_type(c, path, want, v);
    for (int i = 0; i < n; i++)
        if (!strcmp(v->valuestring, names[i])) {
            *out = i;
            return true;
        }
    char q[96];
    quote(v->valuestring, q, sizeof q);
    const char *near = closest(v->valuestring, names, n);
    if (near) return fail(c, path, "expected %s, got %s; did you mean \"%s\"?", want, q, near);
    return fail(c, path, "expected %s, got %s", want, q);
}

static bool opt_enum(ctx *c, const cJSON *obj, const char *path, const char *key,
                     const char *const *names, int n, int *out) {
    const cJSON *v = member(obj, key);
    char p[PATH_LEN];
    join(p, path, key);
    return !v || read_enum(c, v, p, names, n, out);
}

static bool read_object(ctx *c, const cJSON *v, const char *path) {
    return cJSON_IsObject(v) || fail_type(c, path, "an object {...}", v);
}

static bool fail_missing(ctx *c, const char *path, const char *key, const char *what) {
    return fail(c, path, "missing required key \"%s\" (%s)", key, what);
}

/* A copy of s (NULL on out of memory, with the error set). */
static char *dup_str(ctx *c, const char *s) {
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (!d)
        fail(c, NULL, "out of memory");
    else
        memcpy(d, s, n);
    return d;
}

/* dir/rel, or rel itself when it is absolute or dir is ".". */
static char *resolve(ctx *c, const char *rel) {
    if (rel[0] == '/' || !strcmp(c->dir, ".")) return dup_str(c, rel);
    size_t n = strlen(c->dir) + 1 + strlen(rel) + 1;
    char *d = malloc(n);
    if (!d) {
        fail(c, NULL, "out of memory");
        return NULL;
    }
    snprintf(d, n, "%s%s%s", c->dir, c->dir[strlen(c->dir) - 1] == '/' ? "" : "/", rel);
    return d;
}

static bool read_path(ctx *c, const cJSON *v, const char *path, const char *what, char **out) {
    if (!cJSON_IsString(v) || !v->valuestring[0]) return fail_type(c, path, what, v);
    *out = resolve(c, v->valuestring);
    return *out != NULL;
}

/* ------------------------------------------------------------------------ */
/* Sections                                                                  */

static bool parse_image(ctx *c, const cJSON *v, ras_scene *s) {
    static const char *const keys[] = {"width", "height"};
    if (!read_object(c, v, "image") || !check_keys(c, v, "image", keys, COUNT(keys), NULL, NULL))
        return false;
    return opt_int(c, v, "image", "width", 1, RAS_SCENE_MAX_SIZE, &s->width) &&
           opt_int(c, v, "image", "height", 1, RAS_SCENE_MAX_SIZE, &s->height);
}

static bool parse_camera(ctx *c, const cJSON *v, ras_scene_camera *cam) {
    static const char *const keys[] = {"eye", "look_at", "up", "fov_deg", "near", "far"};
    if (!read_object(c, v, "camera") || !check_keys(c, v, "camera", keys, COUNT(keys), NULL, NULL))
        return false;
    if (!opt_vec3(c, v, "camera", "eye", R_ANY, &cam->eye) ||
        !opt_vec3(c, v, "camera", "look_at", R_ANY, &cam->look_at) ||
        !opt_vec3(c, v, "camera", "up", R_ANY, &cam->up) ||
        !opt_float(c, v, "camera", "fov_deg", (range){0, 180, true, true, false}, &cam->fov_deg) ||
        !opt_float(c, v, "camera", "near", R_POS, &cam->z_near) ||
        !opt_float(c, v, "camera", "far", R_POS, &cam->z_far))
        return false;
    if (member(v, "up") && !member(v, "look_at"))
        return fail(c, "camera.up",
                    "\"up\" is used only with \"look_at\"; the fixed view (no \"look_at\") "
                    "always has y up");
    if (member(v, "look_at")) {
        cam->view = RAS_SCENE_VIEW_LOOK_AT;
        vec3s dir = glms_vec3_sub(cam->look_at, cam->eye);
        if (glms_vec3_norm(dir) < 1e-6f)
            return fail(c, "camera.look_at",
                        "expected a point other than the eye (%g, %g, %g), got the eye itself",
                        cam->eye.x, cam->eye.y, cam->eye.z);
        vec3s side = glms_vec3_cross(glms_vec3_normalize(dir), cam->up);
        if (glms_vec3_norm(side) < 1e-6f * (glms_vec3_norm(cam->up) + 1e-30f) ||
            glms_vec3_norm(cam->up) < 1e-12f)
            return fail(c, "camera.up",
                        "expected a direction not parallel to the view direction (look_at - "
                        "eye), got (%g, %g, %g)",
                        cam->up.x, cam->up.y, cam->up.z);
    }
    if (!(cam->z_near < cam->z_far))
        return fail(c, "camera.far", "expected far > near (%g), got %g", cam->z_near, cam->z_far);
    return true;
}

static bool read_axis(ctx *c, const cJSON *v, const char *path, vec3s *axis) {
    if (!read_vec3(c, v, path, R_ANY, axis)) return false;
    if (glms_vec3_norm(*axis) < 1e-12f)
        return fail(c, path, "expected a non-zero axis, got (0, 0, 0)");
    return true;
}

static bool parse_model_rotation(ctx *c, const cJSON *v, ras_scene *s) {
    static const char *const keys[] = {"angle_deg", "axis"};
    const char *path = "model_rotation";
    if (!read_object(c, v, path) || !check_keys(c, v, path, keys, COUNT(keys), NULL, NULL))
        return false;
    if (!opt_float(c, v, path, "angle_deg", R_ANY, &s->model_rotation_deg)) return false;
    const cJSON *axis = member(v, "axis");
    if (axis) {
        if (!read_axis(c, axis, "model_rotation.axis", &s->model_rotation_axis)) return false;
        s->model_rotation_axis_set = true;
    }
    return true;
}

/* --- objects --------------------------------------------------------------- */

/* The parameter keys of each shape (model's are "model" and "fit"). */
static const char *const *shape_keys(ras_scene_shape shape, int *n) {
    static const char *const triangle[] = {"vertices"};
    static const char *const plane[] = {"size", "divisions"};
    static const char *const cube[] = {"size"};
    static const char *const sphere[] = {"radius", "stacks", "slices"};
    static const char *const torus[] = {"major_radius", "minor_radius", "rings", "sides"};
    static const char *const teapot[] = {"divisions"};
    static const char *const fan[] = {"count", "radius", "arc_deg"};
    static const char *const model[] = {"model", "fit"};
    switch (shape) {
    case RAS_SHAPE_TRIANGLE: *n = COUNT(triangle); return triangle;
    case RAS_SHAPE_PLANE: *n = COUNT(plane); return plane;
    case RAS_SHAPE_CUBE: *n = COUNT(cube); return cube;
    case RAS_SHAPE_SPHERE: *n = COUNT(sphere); return sphere;
    case RAS_SHAPE_TORUS: *n = COUNT(torus); return torus;
    case RAS_SHAPE_TEAPOT: *n = COUNT(teapot); return teapot;
    case RAS_SHAPE_THIN_FAN: *n = COUNT(fan); return fan;
    case RAS_SHAPE_MODEL: *n = COUNT(model); return model;
    }
    *n = 0;
    return NULL;
}

/* A key that is some other shape's parameter: say whose it is. */
static const char *other_shape_key(const char *key, const void *user, char *buf, size_t size) {
    ras_scene_shape shape = *(const ras_scene_shape *)user;
    for (int s = 0; s < RAS_SHAPE_COUNT; s++) {
        int n;
        const char *const *keys = shape_keys((ras_scene_shape)s, &n);
        for (int i = 0; i < n; i++)
            if (!strcmp(keys[i], key)) {
                int own_n;
                const char *const *own = shape_keys(shape, &own_n);
                char list[200];
                list_names(own, own_n, list, sizeof list);
                snprintf(buf, size,
                         "shape \"%s\" takes no \"%s\" (a parameter of %s); its "
                         "parameters are %s",
                         shape_names[shape], key, shape_names[s], list);
                return buf;
            }
    }
    return NULL;
}

static bool parse_shape_params(ctx *c, const cJSON *v, const char *path, ras_scene_object *o) {
    ras_scene_shape_params *sp = &o->params;
    switch (o->shape) {
    case RAS_SHAPE_TRIANGLE: {
        const cJSON *vs = member(v, "vertices");
        char p[PATH_LEN];
        join(p, path, "vertices");
        if (!vs) return fail_missing(c, path, "vertices", "an array of 3 points [x, y, z]");
        if (!cJSON_IsArray(vs) || cJSON_GetArraySize(vs) != 3)
            return fail_type(c, p, "an array of 3 points [x, y, z]", vs);
        int i = 0;
        for (const cJSON *e = vs->child; e; e = e->next, i++) {
            char pi[PATH_LEN];
            join_index(pi, p, i);
            if (!read_vec3(c, e, pi, R_ANY, &sp->vertices[i])) return false;
        }
        return true;
    }
    case RAS_SHAPE_PLANE:
        sp->size = 2;
        sp->divisions = 1;
        return opt_float(c, v, path, "size", R_POS, &sp->size) &&
               opt_int(c, v, path, "divisions", 1, 1024, &sp->divisions);
    case RAS_SHAPE_CUBE: sp->size = 1; return opt_float(c, v, path, "size", R_POS, &sp->size);
    case RAS_SHAPE_SPHERE:
        sp->radius = 1;
        sp->stacks = 32;
        sp->slices = 64;
        return opt_float(c, v, path, "radius", R_POS, &sp->radius) &&
               opt_int(c, v, path, "stacks", 2, 1024, &sp->stacks) &&
               opt_int(c, v, path, "slices", 3, 1024, &sp->slices);
    case RAS_SHAPE_TORUS:
        sp->major_radius = 1;
        sp->minor_radius = 0.4f;
        sp->rings = 64;
        sp->sides = 32;
        return opt_float(c, v, path, "major_radius", R_POS, &sp->major_radius) &&
               opt_float(c, v, path, "minor_radius", R_POS, &sp->minor_radius) &&
               opt_int(c, v, path, "rings", 3, 1024, &sp->rings) &&
               opt_int(c, v, path, "sides", 3, 1024, &sp->sides);
    case RAS_SHAPE_TEAPOT:
        sp->divisions = 8;
        return opt_int(c, v, path, "divisions", 1, 64, &sp->divisions);
    case RAS_SHAPE_THIN_FAN:
        sp->count = 200;
        sp->radius = 1;
        sp->arc_deg = 360;
        return opt_int(c, v, path, "count", 1, 100000, &sp->count) &&
               opt_float(c, v, path, "radius", R_POS, &sp->radius) &&
               opt_float(c, v, path, "arc_deg", (range){0, 360, true, false, false}, &sp->arc_deg);
    case RAS_SHAPE_MODEL: {
        char p[PATH_LEN];
        join(p, path, "model");
        return read_path(c, member(v, "model"), p, "a model file path (a non-empty string)",
                         &sp->model_path) &&
               opt_float(c, v, path, "fit", R_POS, &sp->fit);
    }
    }
    return false;
}

static bool read_scale(ctx *c, const cJSON *v, const char *path, vec3s *out) {
    if (!read_vec3_or_scalar(c, v, path, R_ANY, out)) return false;
    for (int i = 0; i < 3; i++)
        if (out->raw[i] == 0)
            return fail(c, path, "expected a non-zero scale, got 0%s",
                        cJSON_IsArray(v) ? " in one component" : "");
    return true;
}

static bool read_rotation(ctx *c, const cJSON *v, const char *path, ras_scene_rotation *r) {
    static const char *const keys[] = {"axis", "deg"};
    if (!cJSON_IsObject(v))
        return fail_type(c, path, "a rotation {\"axis\": [x, y, z], \"deg\": angle}", v);
    if (!check_keys(c, v, path, keys, COUNT(keys), NULL, NULL)) return false;
    const cJSON *axis = member(v, "axis"), *deg = member(v, "deg");
    if (!axis) return fail_missing(c, path, "axis", "an array of 3 numbers, not all zero");
    if (!deg) return fail_missing(c, path, "deg", "the angle in degrees");
    char pa[PATH_LEN], pd[PATH_LEN];
    join(pa, path, "axis");
    join(pd, path, "deg");
    return read_axis(c, axis, pa, &r->axis) && read_float(c, deg, pd, R_ANY, &r->deg);
}

static bool parse_transform(ctx *c, const cJSON *v, const char *path, ras_scene_object *o) {
    static const char *const keys[] = {"translate", "rotate", "scale"};
    if (!read_object(c, v, path) || !check_keys(c, v, path, keys, COUNT(keys), NULL, NULL))
        return false;
    if (!opt_vec3(c, v, path, "translate", R_ANY, &o->translate)) return false;
    char p[PATH_LEN];
    const cJSON *scale = member(v, "scale");
    join(p, path, "scale");
    if (scale && !read_scale(c, scale, p, &o->scale)) return false;
    const cJSON *rot = member(v, "rotate");
    join(p, path, "rotate");
    if (rot && cJSON_IsArray(rot)) {
        int n = cJSON_GetArraySize(rot);
        if (n > RAS_SCENE_MAX_ROTATIONS)
            return fail(c, p, "expected at most %d rotations, got %d", RAS_SCENE_MAX_ROTATIONS, n);
        int i = 0;
        for (const cJSON *e = rot->child; e; e = e->next, i++) {
            char pi[PATH_LEN];
            join_index(pi, p, i);
            if (!read_rotation(c, e, pi, &o->rotations[i])) return false;
        }
        o->rotation_count = n;
    } else if (rot) {
        if (!cJSON_IsObject(rot))
            return fail_type(c, p,
                             "a rotation {\"axis\": [x, y, z], \"deg\": angle} or an array of "
                             "them",
                             rot);
        if (!read_rotation(c, rot, p, &o->rotations[0])) return false;
        o->rotation_count = 1;
    }
    return true;
}

static bool parse_map(ctx *c, const cJSON *v, const char *path, ras_scene_map *m) {
    static const char *const all_keys[] = {"file",   "builtin", "size", "squares",
                                           "colors", "bumps",   "wrap"};
    m->wrap = RAS_WRAP_REPEAT;
    m->size = 256;
    m->squares = 8;
    m->bumps = 8;
    m->colors[0] = (vec3s){{0.92f, 0.9f, 0.85f}};
    m->colors[1] = (vec3s){{0.75f, 0.22f, 0.16f}};
    if (cJSON_IsString(v)) {
        for (int i = 0; i < COUNT(builtin_map_names); i++)
            if (!strcmp(v->valuestring, builtin_map_names[i]))
                return fail(c, path,
                            "expected a file path or an object, got \"%s\", which reads as a "
                            "file name; for the built-in picture write {\"builtin\": \"%s\"}",
                            v->valuestring, v->valuestring);
        m->kind = RAS_MAP_FILE;
        return read_path(c, v, path, "a file path", &m->path);
    }
    if (!cJSON_IsObject(v))
        return fail_type(c, path,
                         "a file path (a string) or an object {\"file\": ...} or "
                         "{\"builtin\": \"checker\" | \"brick\" | \"bumps\", ...}",
                         v);
    const cJSON *file = member(v, "file"), *builtin = member(v, "builtin");
    if (file && builtin) return fail(c, path, "expected either \"file\" or \"builtin\", got both");
    if (!file && !builtin)
        return fail_missing(c, path, "file\" or \"builtin",
                            "a file path, or one of checker, brick, bumps");
    /* Which keys go with which kind. */
    const char *keys[4];
    int n = 0;
    keys[n++] = file ? "file" : "builtin";
    keys[n++] = "wrap";
    char p[PATH_LEN];
    if (file) {
        m->kind = RAS_MAP_FILE;
        join(p, path, "file");
        if (!read_path(c, file, p, "a file path (a non-empty string)", &m->path)) return false;
    } else {
        int kind = 0; /* gcc -O2 cannot see read_enum sets it on success */
        join(p, path, "builtin");
        if (!read_enum(c, builtin, p, builtin_map_names, COUNT(builtin_map_names), &kind))
            return false;
        m->kind = kind == 0 ? RAS_MAP_CHECKER : kind == 1 ? RAS_MAP_BRICK : RAS_MAP_BUMPS;
        keys[n++] = "size";
        if (m->kind == RAS_MAP_CHECKER) keys[n++] = "squares";
        if (m->kind == RAS_MAP_BUMPS) keys[n++] = "bumps";
    }
    /* colors is a checker key (checked separately: it would make the list 5 long). */
    for (const cJSON *k = v->child; k; k = k->next) {
        bool own = false;
        for (int i = 0; i < n && !own; i++)
            own = !strcmp(k->string, keys[i]);
        if (own || (m->kind == RAS_MAP_CHECKER && !strcmp(k->string, "colors"))) continue;
        bool known = false;
        for (int i = 0; i < COUNT(all_keys) && !known; i++)
            known = !strcmp(k->string, all_keys[i]);
        if (known) {
            join(p, path, k->string);
            return fail(c, p, "\"%s\" does not apply to %s", k->string,
                        file                         ? "a texture file"
                        : m->kind == RAS_MAP_CHECKER ? "the checker"
                        : m->kind == RAS_MAP_BRICK   ? "the brick texture"
                                                     : "the bumps");
        }
    }
    const char *known[8];
    int kn = 0;
    for (int i = 0; i < n; i++)
        known[kn++] = keys[i];
    if (m->kind == RAS_MAP_CHECKER) known[kn++] = "colors";
    if (!check_keys(c, v, path, known, kn, NULL, NULL)) return false;
    int wrap = 0;
    if (!opt_enum(c, v, path, "wrap", NAMES(ras_names_wrap), &wrap)) return false;
    m->wrap = wrap == 0 ? RAS_WRAP_REPEAT : RAS_WRAP_CLAMP;
    if (!opt_int(c, v, path, "size", 1, 4096, &m->size) ||
        !opt_int(c, v, path, "squares", 1, 4096, &m->squares) ||
        !opt_int(c, v, path, "bumps", 1, 256, &m->bumps))
        return false;
    if (m->kind == RAS_MAP_CHECKER && m->squares > m->size)
        return fail(c, path, "expected squares <= size (%d), got %d squares", m->size, m->squares);
    const cJSON *colors = member(v, "colors");
    if (colors) {
        join(p, path, "colors");
        if (!cJSON_IsArray(colors) || cJSON_GetArraySize(colors) != 2)
            return fail_type(c, p, "an array of 2 colours", colors);
        int i = 0;
        for (const cJSON *e = colors->child; e; e = e->next, i++) {
            char pi[PATH_LEN];
            join_index(pi, p, i);
            if (!read_color(c, e, pi, &m->colors[i])) return false;
        }
    }
    return true;
}

static bool parse_material(ctx *c, const cJSON *v, const char *path, ras_scene_material *m) {
    static const char *const keys[] = {"color", "texture", "height_map", "ka", "kd",
                                       "ks",    "p",       "kh",         "kn", "uv_scale"};
    /* "colour" is within distance 2 of "color", so the did-you-mean covers it. */
    if (!read_object(c, v, path) || !check_keys(c, v, path, keys, COUNT(keys), NULL, NULL))
        return false;
    if (!opt_color(c, v, path, "color", &m->color) ||
        !opt_vec3_or_scalar(c, v, path, "ka", R_NONNEG, &m->ka) ||
        !opt_vec3_or_scalar(c, v, path, "kd", R_NONNEG, &m->kd) ||
        !opt_vec3_or_scalar(c, v, path, "ks", R_NONNEG, &m->ks) ||
        !opt_float(c, v, path, "p", (range){0, 10000, false, false, false}, &m->p) ||
        !opt_float(c, v, path, "kh", R_ANY, &m->kh) || !opt_float(c, v, path, "kn", R_ANY, &m->kn))
        return false;
    m->kd_set = member(v, "kd") != NULL;
    const cJSON *uv = member(v, "uv_scale");
    if (uv) {
        char p[PATH_LEN];
        join(p, path, "uv_scale");
        if (cJSON_IsNumber(uv)) {
            float f;
            if (!read_float(c, uv, p, R_POS, &f)) return false;
            m->uv_scale = (vec2s){{f, f}};
        } else if (cJSON_IsArray(uv) && cJSON_GetArraySize(uv) == 2) {
            int i = 0;
            for (const cJSON *e = uv->child; e; e = e->next, i++) {
                char pi[PATH_LEN];
                join_index(pi, p, i);
                if (!read_float(c, e, pi, R_POS, &m->uv_scale.raw[i])) return false;
            }
        } else {
            return fail_type(c, p, "a number or an array of 2 numbers [u, v]", uv);
        }
    }
    char p[PATH_LEN];
    const cJSON *tex = member(v, "texture"), *height = member(v, "height_map");
    join(p, path, "texture");
    if (tex && !parse_map(c, tex, p, &m->texture)) return false;
    join(p, path, "height_map");
    if (height && !parse_map(c, height, p, &m->height_map)) return false;
    return true;
}

static void material_defaults(ras_scene_material *m) {
    *m = (ras_scene_material){.color = {{1, 1, 1}},
                              .ka = {{0.005f, 0.005f, 0.005f}},
                              .kd = {{1, 1, 1}},
                              .ks = {{0.7937f, 0.7937f, 0.7937f}},
                              .p = 150,
                              .kh = 0.2f,
                              .kn = 0.1f,
                              .uv_scale = {{1, 1}}};
}

static mat4s object_matrix(const ras_scene_object *o, mat4s spin) {
    mat4s r = glms_mat4_identity();
    for (int i = 0; i < o->rotation_count; i++)
        r = glms_mat4_mul(
            glms_rotate_make(ras_deg_to_rad(o->rotations[i].deg), o->rotations[i].axis), r);
    mat4s m = glms_mat4_mul(glms_translate_make(o->translate), spin);
    return glms_mat4_mul(glms_mat4_mul(m, r), glms_scale_make(o->scale));
}

mat4s ras_scene_model_matrix(const ras_scene_object *object, mat4s spin) {
    return object_matrix(object, spin);
}

static bool parse_object(ctx *c, const cJSON *v, const char *path, ras_scene_object *o) {
    if (!read_object(c, v, path)) return false;
    o->scale = (vec3s){{1, 1, 1}};
    material_defaults(&o->material);
    const cJSON *shape = member(v, "shape"), *model = member(v, "model");
    char p[PATH_LEN];
    if (shape && model)
        return fail(c, path,
                    "expected either \"shape\" (a built-in) or \"model\" (a file), got "
                    "both");
    if (!shape && !model) {
        char list[200];
        list_names(shape_names, RAS_SHAPE_COUNT - 1, list, sizeof list);
        return fail(c, path, "missing required key \"shape\" (%s) or \"model\" (a file path)",
                    list);
    }
    if (shape) {
        int k = 0;
        join(p, path, "shape");
        if (cJSON_IsString(shape) && !strcmp(shape->valuestring, "model"))
            return fail(c, p,
                        "a model file is given as \"model\": \"path/to/file.obj\", not as "
                        "a shape");
        if (!read_enum(c, shape, p, shape_names, RAS_SHAPE_COUNT - 1, &k)) return false;
        o->shape = (ras_scene_shape)k;
    } else {
        o->shape = RAS_SHAPE_MODEL;
    }
    const char *keys[16] = {"name", "shape", "transform", "material"};
    int n = 4, pn;
    const char *const *params = shape_keys(o->shape, &pn);
    for (int i = 0; i < pn; i++)
        keys[n++] = params[i];
    if (!check_keys(c, v, path, keys, n, other_shape_key, &o->shape)) return false;
    const cJSON *name = member(v, "name");
    if (name) {
        join(p, path, "name");
        if (!cJSON_IsString(name)) return fail_type(c, p, "a string", name);
        if (!(o->name = dup_str(c, name->valuestring))) return false;
    }
    if (!parse_shape_params(c, v, path, o)) return false;
    const cJSON *tr = member(v, "transform"), *mat = member(v, "material");
    join(p, path, "transform");
    if (tr && !parse_transform(c, tr, p, o)) return false;
    join(p, path, "material");
    if (mat && !parse_material(c, mat, p, &o->material)) return false;
    o->model = object_matrix(o, glms_mat4_identity());
    return true;
}

static bool parse_objects(ctx *c, const cJSON *v, ras_scene *s) {
    if (!v) return fail_missing(c, NULL, "objects", "an array of 1 or more objects");
    if (!cJSON_IsArray(v)) return fail_type(c, "objects", "an array of 1 or more objects", v);
    int n = cJSON_GetArraySize(v);
    if (n == 0)
        return fail(c, "objects",
                    "expected 1 or more objects, got an empty array: there is "
                    "nothing to draw");
    if (n > RAS_SCENE_MAX_OBJECTS)
        return fail(c, "objects", "expected at most %d objects, got %d", RAS_SCENE_MAX_OBJECTS, n);
    s->objects = calloc((size_t)n, sizeof *s->objects);
    if (!s->objects) return fail(c, NULL, "out of memory for %d objects", n);
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        char p[PATH_LEN];
        join_index(p, "objects", i);
        s->object_count = i + 1; /* so that destroy frees what this object got */
        if (!parse_object(c, e, p, &s->objects[i])) return false;
    }
    return true;
}

static bool parse_light(ctx *c, const cJSON *v, const char *path, ras_scene_light *l) {
    static const char *const keys[] = {"position", "intensity", "space"};
    if (!read_object(c, v, path) || !check_keys(c, v, path, keys, COUNT(keys), NULL, NULL))
        return false;
    const cJSON *pos = member(v, "position");
    if (!pos) return fail_missing(c, path, "position", "an array of 3 numbers");
    char p[PATH_LEN];
    join(p, path, "position");
    l->intensity = (vec3s){{500, 500, 500}};
    int space = 0;
    if (!read_vec3(c, pos, p, R_ANY, &l->position) ||
        !opt_vec3_or_scalar(c, v, path, "intensity", R_NONNEG, &l->intensity) ||
        !opt_enum(c, v, path, "space", space_names, COUNT(space_names), &space))
        return false;
    l->in_world = space == 1;
    return true;
}

static bool parse_lights(ctx *c, const cJSON *v, ras_scene *s) {
    if (!cJSON_IsArray(v)) return fail_type(c, "lights", "an array of lights", v);
    int n = cJSON_GetArraySize(v);
    if (n > RAS_SCENE_MAX_LIGHTS)
        return fail(c, "lights", "expected at most %d lights, got %d", RAS_SCENE_MAX_LIGHTS, n);
    if (n == 0) return true;
    s->lights = calloc((size_t)n, sizeof *s->lights);
    if (!s->lights) return fail(c, NULL, "out of memory");
    s->light_count = n;
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        char p[PATH_LEN];
        join_index(p, "lights", i);
        if (!parse_light(c, e, p, &s->lights[i])) return false;
    }
    return true;
}

static bool parse_aa(ctx *c, const cJSON *v, ras_scene *s) {
    static const char *const keys[] = {"mode", "samples", "pattern"};
    if (!read_object(c, v, "aa") || !check_keys(c, v, "aa", keys, COUNT(keys), NULL, NULL))
        return false;
    int mode = 0, pattern = 0, samples = 4;
    if (!opt_enum(c, v, "aa", "mode", NAMES(ras_names_aa), &mode) ||
        !opt_enum(c, v, "aa", "pattern", NAMES(ras_names_pattern), &pattern) ||
        !opt_int(c, v, "aa", "samples", 1, RAS_MAX_SAMPLES, &samples))
        return false;
    s->aa = (ras_aa_mode)mode;
    s->pattern_kind = (ras_pattern_kind)pattern;
    if (s->aa == RAS_AA_NONE) {
        if (member(v, "samples") && samples != 1)
            return fail(c, "aa.samples",
                        "expected 1 (or no \"samples\") with mode \"none\", got %d; set "
                        "\"mode\": \"msaa\" or \"ssaa\" to use %d samples",
                        samples, samples);
        s->samples = 1;
        s->pattern = ras_sample_pattern_center();
        return true;
    }
    s->samples = samples;
    ras_error inner;
    if (!ras_sample_pattern_make(s->pattern_kind, samples, &s->pattern, &inner))
        return fail(c, "aa.samples", "%s (pattern \"%s\")", inner.msg,
                    ras_name_of(&ras_names_pattern, (int)s->pattern_kind));
    return true;
}

static bool parse_root(ctx *c, const cJSON *root, ras_scene *s) {
    static const char *const keys[] = {"description", "image",       "camera",   "model_rotation",
                                       "objects",     "lights",      "ambient",  "aa",
                                       "shader",      "filter",      "cull",     "depth",
                                       "clear_color", "wireframe"};
    if (!cJSON_IsObject(root)) return fail_type(c, "the top level", "an object {...}", root);
    if (!check_keys(c, root, "", keys, COUNT(keys), NULL, NULL)) return false;
    const cJSON *v;
    if ((v = member(root, "description"))) {
        if (!cJSON_IsString(v)) return fail_type(c, "description", "a string", v);
        if (!(s->description = dup_str(c, v->valuestring))) return false;
    }
    if ((v = member(root, "image")) && !parse_image(c, v, s)) return false;
    if ((v = member(root, "camera")) && !parse_camera(c, v, &s->camera)) return false;
    if ((v = member(root, "model_rotation")) && !parse_model_rotation(c, v, s)) return false;
    if (!parse_objects(c, member(root, "objects"), s)) return false;
    if ((v = member(root, "lights")) && !parse_lights(c, v, s)) return false;
    if (!opt_vec3_or_scalar(c, root, "", "ambient", R_NONNEG, &s->ambient)) return false;
    if ((v = member(root, "aa")) && !parse_aa(c, v, s)) return false;
    int shader = 0, filter = RAS_FILTER_BILINEAR, cull = 0, depth = 0;
    if (!opt_enum(c, root, "", "shader", NAMES(ras_names_shader), &shader) ||
        !opt_enum(c, root, "", "filter", NAMES(ras_names_filter), &filter) ||
        !opt_enum(c, root, "", "cull", NAMES(ras_names_cull), &cull) ||
        !opt_enum(c, root, "", "depth", NAMES(ras_names_depth), &depth) ||
        !opt_color(c, root, "", "clear_color", &s->clear_color))
        return false;
    s->shader = (ras_scene_shader)shader;
    s->filter = (ras_scene_filter)filter;
    s->cull = (ras_cull_mode)cull;
    s->depth = (ras_depth_format)depth;
    if ((v = member(root, "wireframe"))) {
        if (!cJSON_IsBool(v)) return fail_type(c, "wireframe", "true or false", v);
        s->wireframe = cJSON_IsTrue(v);
    }
    return true;
}

static void scene_defaults(ras_scene *s) {
    s->width = s->height = 700;
    s->camera = (ras_scene_camera){.view = RAS_SCENE_VIEW_FIXED,
                                   .eye = {{0, 0, 5}},
                                   .look_at = {{0, 0, 0}},
                                   .up = {{0, 1, 0}},
                                   .fov_deg = 45,
                                   .z_near = 0.1f,
                                   .z_far = 50};
    s->model_rotation_axis = (vec3s){{0, 0, 1}};
    s->ambient = (vec3s){{10, 10, 10}};
    s->aa = RAS_AA_NONE;
    s->samples = 1;
    s->pattern_kind = RAS_PATTERN_ORDERED;
    s->pattern = ras_sample_pattern_center();
    s->shader = RAS_SHADER_FLAT;
    s->filter = RAS_FILTER_BILINEAR;
    s->cull = RAS_CULL_NONE;
    s->depth = RAS_DEPTH_Z01;
}

/* ------------------------------------------------------------------------ */
/* JSON syntax errors                                                        */

static bool is_word_char(char ch) {
    return isalnum((unsigned char)ch) || ch == '_' || ch == '-' || ch == '+' || ch == '.';
}

static void line_col(const char *text, size_t off, int *line, int *col) {
    *line = 1;
    *col = 1;
    for (size_t i = 0; i < off; i++) {
        if (text[i] == '\n') {
            ++*line;
            *col = 1;
        } else if (((unsigned char)text[i] & 0xC0) != 0x80) {
            ++*col; /* count characters, not UTF-8 continuation bytes */
        }
    }
}

/* The position of the innermost '{', '[' or '"' still open at `len` (the
 * end of the text, or the error), or (size_t)-1 when everything is closed. */
static size_t unclosed_at(const char *text, size_t len, char *what) {
    size_t stack[64];
    char kinds[64];
    int depth = 0;
    for (size_t i = 0; i < len; i++) {
        char ch = text[i];
        if (ch == '"') {
            size_t start = i++;
            while (i < len && text[i] != '"')
                i += text[i] == '\\' ? 2 : 1;
            if (i >= len) {
                *what = '"';
                return start;
            }
        } else if (ch == '{' || ch == '[') {
            if (depth < 64) {
                stack[depth] = i;
                kinds[depth] = ch;
            }
            depth++;
        } else if ((ch == '}' || ch == ']') && depth > 0) {
            depth--;
        }
    }
    if (depth == 0) return (size_t)-1;
    int top = depth <= 64 ? depth - 1 : 63;
    *what = kinds[top];
    return stack[top];
}

static bool syntax_error(ctx *c, const char *text, size_t len, size_t off) {
    if (off > len) off = len;
    /* cJSON stops one character into a comment. */
    if (off > 0 && off < len && text[off - 1] == '/' && (text[off] == '/' || text[off] == '*'))
        off--;
    /* ... and one character into a word (an unquoted key, a bad literal). */
    while (off > 0 && off < len && is_word_char(text[off]) && is_word_char(text[off - 1]))
        off--;
    int line, col;
    line_col(text, off, &line, &col);
    char where[PATH_LEN + 32];
    snprintf(where, sizeof where, "%s:%d:%d", c->file, line, col);
    /* The token at the error, and the last significant character before it. */
    size_t end = off;
    while (end < len && is_word_char(text[end]))
        end++;
    size_t rest = end == off ? off + 1 : end;
    while (rest < len && isspace((unsigned char)text[rest]))
        rest++;
    size_t b = off;
    while (b > 0 && isspace((unsigned char)text[b - 1]))
        b--;
    char prev = b > 0 ? text[b - 1] : '\0';
    char ch = off < len ? text[off] : '\0';
    char got[64];
    if (off >= len)
        snprintf(got, sizeof got, "the end of the text");
    else if (end > off)
        snprintf(got, sizeof got, "'%.*s'", (int)(end - off > 20 ? 20 : end - off), text + off);
    else if ((unsigned char)ch < 0x20)
        snprintf(got, sizeof got, "a control character (0x%02x)", (unsigned char)ch);
    else
        snprintf(got, sizeof got, "'%c'", ch);

    char what;
    size_t open = unclosed_at(text, len, &what);
    if (open != (size_t)-1 && rest >= len) {
        int ol, oc;
        line_col(text, open, &ol, &oc);
        const char *closer = what == '"' ? "'\"'" : what == '{' ? "'}'" : "']'";
        return ras_error_set(c->err,
                             "%s: JSON syntax error: expected %s to close the '%c' at %d:%d, got "
                             "the end of the text",
                             where, closer, what, ol, oc);
    }
    char top;
    if (unclosed_at(text, off, &top) == (size_t)-1 && b > 0)
        return ras_error_set(c->err,
                             "%s: JSON syntax error: expected the end of the text after the "
                             "top-level object, got %s",
                             where, got);
    if ((ch == '}' || ch == ']') && prev == ',')
        return ras_error_set(c->err,
                             "%s: JSON syntax error: expected a value after ',', got '%c' (JSON "
                             "allows no trailing comma: remove the ',')",
                             where, ch);
    if (ch == '/' && off + 1 < len && (text[off + 1] == '/' || text[off + 1] == '*'))
        return ras_error_set(c->err,
                             "%s: JSON syntax error: expected a value or ',', got a comment "
                             "('%c%c'); JSON has no comments (use a \"description\" key)",
                             where, ch, text[off + 1]);
    if (ch == '\'' || prev == '\'')
        return ras_error_set(c->err,
                             "%s: JSON syntax error: expected a string in double quotes, got a "
                             "single quote (JSON strings and keys take \"...\")",
                             where);
    if (end > off) {
        static const char *const special[] = {"NaN", "nan", "Infinity", "-Infinity", "inf", "-inf"};
        for (int i = 0; i < COUNT(special); i++)
            if (end - off == strlen(special[i]) && !strncmp(text + off, special[i], end - off))
                return ras_error_set(c->err,
                                     "%s: JSON syntax error: expected a number, got %s (JSON has "
                                     "no NaN or Infinity: write a finite number)",
                                     where, got);
    }
    if (ch == ':' || ((prev == '{' || prev == ',') && isalpha((unsigned char)ch)))
        return ras_error_set(c->err,
                             "%s: JSON syntax error: expected a key in double quotes, got %s "
                             "(write \"key\": value)",
                             where, ch == ':' ? "an unquoted key before ':'" : got);
    bool prev_ends_value =
        prev == '"' || prev == '}' || prev == ']' || isalnum((unsigned char)prev);
    bool starts_value =
        ch == '"' || ch == '{' || ch == '[' || ch == '-' || isalnum((unsigned char)ch);
    if (b < off && prev_ends_value && starts_value)
        return ras_error_set(c->err,
                             "%s: JSON syntax error: expected ',' or a closing bracket, got %s "
                             "(a ',' is missing between two values)",
                             where, got);
    if (ch == ',')
        return ras_error_set(c->err, "%s: JSON syntax error: expected a value after '%c', got ','",
                             where, prev ? prev : '{');
    if (isalpha((unsigned char)ch))
        return ras_error_set(c->err,
                             "%s: JSON syntax error: expected a value (a number, a string in "
                             "double quotes, true, false, null, an object or an array), got %s",
                             where, got);
    return ras_error_set(c->err, "%s: JSON syntax error: unexpected %s", where, got);
}

/* ------------------------------------------------------------------------ */
/* Entry points                                                              */

void ras_scene_destroy(ras_scene *s) {
    if (!s) return;
    for (int i = 0; i < s->object_count; i++) {
        ras_scene_object *o = &s->objects[i];
        free(o->name);
        free(o->params.model_path);
        free(o->material.texture.path);
        free(o->material.height_map.path);
    }
    free(s->objects);
    free(s->lights);
    free(s->description);
    free(s->path);
    free(s->dir);
    free(s);
}

/* text[len] must be '\0'; text may start with a UTF-8 byte order mark. */
static ras_scene *parse_text(const char *text, size_t len, const char *name, const char *dir,
                             ras_error *err) {
    ctx c = {.file = name, .dir = dir, .err = err};
    size_t start = 0;
    if (len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3)) start = 3;
    size_t first = start;
    while (first < len && isspace((unsigned char)text[first]))
        first++;
    if (first == len) {
        fail(&c, NULL, "expected a JSON object {...}, got %s",
             len == 0 ? "an empty file" : "only white space");
        return NULL;
    }
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text + start, &end, 1);
    size_t deep_at = 0;
    if (!root && ras_io_text_nesting(text + start, len - start, CJSON_NESTING_LIMIT, &deep_at) >
                     CJSON_NESTING_LIMIT) {
        /* cJSON stops at its nesting limit with a plain syntax error: say why. */
        int line, col;
        line_col(text, start + deep_at, &line, &col);
        ras_error_set(err,
                      "%s:%d:%d: expected JSON nested at most %d levels deep, got deeper (a "
                      "scene needs about 5); is this really a scene?",
                      name, line, col, CJSON_NESTING_LIMIT);
        return NULL;
    }
    if (!root) {
        const char *at = cJSON_GetErrorPtr();
        size_t off = at && at >= text && at <= text + len ? (size_t)(at - text) : len;
        if (!at && end && end >= text && end <= text + len) off = (size_t)(end - text);
        syntax_error(&c, text, len, off);
        return NULL;
    }
    ras_scene *s = calloc(1, sizeof *s);
    if (!s) {
        cJSON_Delete(root);
        fail(&c, NULL, "out of memory");
        return NULL;
    }
    scene_defaults(s);
    bool ok =
        (s->path = dup_str(&c, name)) && (s->dir = dup_str(&c, dir)) && parse_root(&c, root, s);
    cJSON_Delete(root);
    if (!ok) {
        ras_scene_destroy(s);
        return NULL;
    }
    return s;
}

ras_scene *ras_scene_parse(const char *text, const char *name, const char *base_dir,
                           ras_error *err) {
    return parse_text(text, strlen(text), name ? name : "(scene)", base_dir ? base_dir : ".", err);
}

ras_scene *ras_scene_load(const char *path, ras_error *err) {
    struct stat st;
    if (stat(path, &st) != 0)
        return ras_error_set(err, "%s: cannot open the scene file: %s", path, strerror(errno)),
               NULL;
    if (S_ISDIR(st.st_mode))
        return ras_error_set(err, "%s: expected a scene file, got a folder", path), NULL;
    if ((unsigned long long)st.st_size > RAS_SCENE_MAX_BYTES)
        return ras_error_set(err,
                             "%s: expected a scene file of at most %u MiB (%u bytes), got %lld "
                             "bytes; is this really a scene?",
                             path, RAS_SCENE_MAX_BYTES >> 20, RAS_SCENE_MAX_BYTES,
                             (long long)st.st_size),
               NULL;
    /* Regular files only: a FIFO would block the read forever. */
    char why[256];
    int fd = ras_io_open_input(path, why, sizeof why);
    FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        if (fd >= 0) {
            snprintf(why, sizeof why, "%s", strerror(errno));
            close(fd);
        }
        return ras_error_set(err, "%s: cannot open the scene file: %s", path, why), NULL;
    }
    /* Read up to one byte past the cap: the file may have grown since stat. */
    char *text = malloc(RAS_SCENE_MAX_BYTES + 2);
    if (!text) {
        fclose(f);
        return ras_error_set(err, "%s: out of memory reading the scene file", path), NULL;
    }
    size_t len = fread(text, 1, RAS_SCENE_MAX_BYTES + 1, f);
    bool bad = ferror(f);
    int e = errno;
    fclose(f);
    if (bad) {
        free(text);
        return ras_error_set(err, "%s: cannot read the scene file: %s", path, strerror(e)), NULL;
    }
    if (len > RAS_SCENE_MAX_BYTES) {
        free(text);
        return ras_error_set(err, "%s: expected a scene file of at most %u MiB, got more", path,
                             RAS_SCENE_MAX_BYTES >> 20),
               NULL;
    }
    text[len] = '\0';
    const char *nul = memchr(text, '\0', len);
    if (nul) {
        int line, col;
        line_col(text, (size_t)(nul - text), &line, &col);
        ras_error_set(err, "%s:%d:%d: expected JSON text, got a NUL byte (is this a binary file?)",
                      path, line, col);
        free(text);
        return NULL;
    }
    /* The folder of the file: "a/b/s.json" → "a/b", "s.json" → ".", "/s.json" → "/". */
    const char *slash = strrchr(path, '/');
    size_t dir_len = slash ? (slash == path ? 1 : (size_t)(slash - path)) : 0;
    char *dir = malloc(dir_len + 2);
    if (!dir) {
        free(text);
        return ras_error_set(err, "%s: out of memory", path), NULL;
    }
    if (slash) {
        memcpy(dir, path, dir_len);
        dir[dir_len] = '\0';
    } else {
        strcpy(dir, ".");
    }
    ras_scene *s = parse_text(text, len, path, dir, err);
    free(dir);
    free(text);
    return s;
}

mat4s ras_scene_view_matrix(const ras_scene *scene) {
    const ras_scene_camera *cam = &scene->camera;
    if (cam->view == RAS_SCENE_VIEW_LOOK_AT) return glms_lookat(cam->eye, cam->look_at, cam->up);
    return ras_view_matrix_eye(cam->eye);
}

/* ------------------------------------------------------------------------ */
/* Assets                                                                    */

/* count slivers around the origin in the xy plane, facing +z; with a full
 * circle the last triangle closes on the first rim vertex, so every inner
 * edge is shared by exactly two triangles with bit-identical end points. */
static ras_mesh *create_thin_fan(int count, float radius, float arc_deg) {
    bool closed = arc_deg >= 360.0f;
    size_t rim = closed ? (size_t)count : (size_t)count + 1;
    ras_mesh *m = ras_mesh_create(rim + 1, (size_t)count);
    if (!m) return NULL;
    m->positions[0] = (vec3s){{0, 0, 0}};
    m->uvs[0] = (vec2s){{0.5f, 0.5f}};
    for (size_t k = 0; k < rim; k++) {
        float a = ras_deg_to_rad(arc_deg * (float)k / (float)count);
        float x = cosf(a), y = sinf(a);
        m->positions[k + 1] = (vec3s){{radius * x, radius * y, 0}};
        m->uvs[k + 1] = (vec2s){{0.5f + 0.5f * x, 0.5f + 0.5f * y}};
    }
    for (size_t v = 0; v < m->vertex_count; v++) {
        m->normals[v] = (vec3s){{0, 0, 1}};
        m->colors[v] = (vec3s){{1, 1, 1}};
    }
    for (size_t t = 0; t < (size_t)count; t++) {
        m->indices[3 * t] = 0;
        m->indices[3 * t + 1] = (unsigned)(t + 1);
        m->indices[3 * t + 2] = (unsigned)(closed ? (t + 1) % rim + 1 : t + 2);
    }
    m->has_uv = true;
    return m;
}

static ras_mesh *create_mesh(const ras_scene_object *o, ras_error *inner) {
    const ras_scene_shape_params *sp = &o->params;
    switch (o->shape) {
    case RAS_SHAPE_TRIANGLE:
        return ras_mesh_create_triangle(sp->vertices[0], sp->vertices[1], sp->vertices[2],
                                        (vec3s){{1, 1, 1}});
    case RAS_SHAPE_PLANE: return ras_mesh_create_plane(sp->size, sp->divisions);
    case RAS_SHAPE_CUBE: return ras_mesh_create_cube(sp->size);
    case RAS_SHAPE_SPHERE: return ras_mesh_create_uv_sphere(sp->radius, sp->stacks, sp->slices);
    case RAS_SHAPE_TORUS:
        return ras_mesh_create_torus(sp->major_radius, sp->minor_radius, sp->rings, sp->sides);
    case RAS_SHAPE_TEAPOT: return ras_mesh_create_teapot(sp->divisions);
    case RAS_SHAPE_THIN_FAN: return create_thin_fan(sp->count, sp->radius, sp->arc_deg);
    case RAS_SHAPE_MODEL: return ras_mesh_load(sp->model_path, inner);
    }
    return NULL;
}

/* The vertex and triangle counts of a built-in shape, from its parameters,
 * before it is built (an upper bound; the pole triangles a sphere drops are
 * counted). False for a model file: its counts are known once it is loaded. */
static bool shape_counts(const ras_scene_object *o, double *v, double *t) {
    const ras_scene_shape_params *sp = &o->params;
    double a = 0, b = 0;
    switch (o->shape) {
    case RAS_SHAPE_TRIANGLE: *v = 3, *t = 1; return true;
    case RAS_SHAPE_CUBE: *v = 24, *t = 12; return true;
    case RAS_SHAPE_PLANE: a = b = sp->divisions; break;
    case RAS_SHAPE_SPHERE: a = sp->stacks, b = sp->slices; break;
    case RAS_SHAPE_TORUS: a = sp->rings, b = sp->sides; break;
    case RAS_SHAPE_TEAPOT: /* 32 bicubic patches, divisions x divisions quads each */
        *v = 32.0 * (sp->divisions + 1) * (sp->divisions + 1);
        *t = 64.0 * sp->divisions * sp->divisions;
        return true;
    case RAS_SHAPE_THIN_FAN: *v = sp->count + 2.0, *t = sp->count; return true;
    case RAS_SHAPE_MODEL: return false;
    }
    *v = (a + 1) * (b + 1);
    *t = 2 * a * b;
    return true;
}

/* What a mesh of v vertices and t triangles costs: the mesh (position,
 * normal, uv, colour; three indices a triangle) and the renderers' data. */
static double mesh_bytes(double v, double t) {
    return v * (3 * sizeof(vec3s) + sizeof(vec2s) + RAS_MEMORY_RENDER_BYTES_PER_VERTEX) +
           t * (3 * sizeof(unsigned) + RAS_MEMORY_RENDER_BYTES_PER_TRIANGLE);
}

/* A texture of w x h texels with its mip chain (a third more). */
static double texture_bytes(double w, double h) { return w * h * sizeof(vec3s) * 4.0 / 3.0; }

/* Adds `bytes` to the assets' estimate and checks the total against the
 * memory budget; false and err (naming the scene, the object, the estimate
 * and the limit) when it is over. */
static bool budget_add(const ras_scene *s, ras_scene_assets *a, int i, const char *what,
                       double bytes, ras_error *err) {
    ras_memory_release(a->memory_estimate);
    a->memory_estimate += bytes;
    ras_memory_commit(a->memory_estimate);
    char label[512];
    if (i == 0)
        snprintf(label, sizeof label, "%s: objects[0] (%s)", s->path, what);
    else
        snprintf(label, sizeof label, "%s: objects[%d] (%s), with the %d object%s before it,",
                 s->path, i, what, i, i == 1 ? "" : "s");
    ras_error inner = {{0}};
    if (ras_memory_check(0, label, "use fewer or coarser objects or smaller textures", &inner))
        return true;
    ras_error_set(err, "%s", inner.msg);
    return false;
}

static bool same_map(const ras_scene_map *a, const ras_scene_map *b) {
    if (a->kind != b->kind || a->wrap != b->wrap) return false;
    switch (a->kind) {
    case RAS_MAP_NONE: return true;
    case RAS_MAP_FILE: return !strcmp(a->path, b->path);
    case RAS_MAP_CHECKER:
        return a->size == b->size && a->squares == b->squares &&
               !memcmp(a->colors, b->colors, sizeof a->colors);
    case RAS_MAP_BRICK: return a->size == b->size;
    case RAS_MAP_BUMPS: return a->size == b->size && a->bumps == b->bumps;
    }
    return false;
}

/* The texture for map m of object i (which = 0: texture, 1: height map),
 * shared with an earlier identical one. NULL and err on failure. */
static ras_texture *get_map(const ras_scene *s, ras_scene_assets *a, int i, int which,
                            ras_error *err) {
    const ras_scene_map *m =
        which ? &s->objects[i].material.height_map : &s->objects[i].material.texture;
    for (int j = 0; j <= i; j++)
        for (int w = 0; w < 2; w++) {
            if (j == i && w >= which) break;
            const ras_scene_map *o =
                w ? &s->objects[j].material.height_map : &s->objects[j].material.texture;
            ras_texture *t = w ? a->height_maps[j] : a->textures[j];
            if (t && same_map(m, o)) return t;
        }
    ras_error inner = {{0}};
    ras_texture *t = NULL;
    const char *key = which ? "height_map" : "texture";
    if (m->kind != RAS_MAP_NONE && m->kind != RAS_MAP_FILE) {
        char what[96];
        snprintf(what, sizeof what, "a %dx%d %s", m->size, m->size, key);
        if (!budget_add(s, a, i, what, texture_bytes(m->size, m->size), err)) return NULL;
    }
    switch (m->kind) {
    case RAS_MAP_NONE: return NULL;
    case RAS_MAP_FILE: t = ras_texture_load(m->path, m->wrap, &inner); break;
    case RAS_MAP_CHECKER:
        t = ras_texture_create_checker(m->size, m->squares, m->colors[0], m->colors[1]);
        break;
    case RAS_MAP_BRICK: t = ras_texture_create_brick(m->size); break;
    case RAS_MAP_BUMPS: t = ras_texture_create_bumps(m->size, m->bumps); break;
    }
    if (!t) {
        if (m->kind == RAS_MAP_FILE)
            ras_error_set(err, "%s: objects[%d].material.%s: cannot load \"%s\": %s", s->path, i,
                          key, m->path, inner.msg);
        else
            ras_error_set(err, "%s: objects[%d].material.%s: out of memory", s->path, i, key);
        return NULL;
    }
    t->wrap = m->wrap;
    a->owned_textures[a->owned_texture_count++] = t;
    if (m->kind == RAS_MAP_FILE) {
        char what[96];
        snprintf(what, sizeof what, "a %dx%d %s", t->width, t->height, key);
        if (!budget_add(s, a, i, what, texture_bytes(t->width, t->height), err)) return NULL;
    }
    return t;
}

ras_scene_assets *ras_scene_load_assets(const ras_scene *s, ras_error *err) {
    ras_scene_assets *a = calloc(1, sizeof *a);
    size_t n = (size_t)s->object_count;
    if (!a || !(a->meshes = calloc(n, sizeof *a->meshes)) ||
        !(a->textures = calloc(n, sizeof *a->textures)) ||
        !(a->height_maps = calloc(n, sizeof *a->height_maps)) ||
        !(a->owned_textures = calloc(2 * n, sizeof *a->owned_textures))) {
        ras_scene_assets_destroy(a);
        ras_error_set(err, "%s: out of memory for the scene's assets", s->path);
        return NULL;
    }
    a->object_count = s->object_count;
    for (int i = 0; i < s->object_count; i++) {
        const ras_scene_object *o = &s->objects[i];
        ras_error inner = {{0}};
        /* Estimated before a built-in shape is built: a few bytes of JSON
         * can ask for millions of triangles. */
        double nv, nt;
        char what[96];
        if (shape_counts(o, &nv, &nt)) {
            snprintf(what, sizeof what, "a %s of %.0f triangles", shape_names[o->shape], nt);
            if (!budget_add(s, a, i, what, mesh_bytes(nv, nt), err)) {
                ras_scene_assets_destroy(a);
                return NULL;
            }
        }
        ras_mesh *mesh = a->meshes[i] = create_mesh(o, &inner);
        if (!mesh) {
            if (o->shape == RAS_SHAPE_MODEL)
                ras_error_set(err, "%s: objects[%d].model: cannot load \"%s\": %s", s->path, i,
                              o->params.model_path, inner.msg);
            else
                ras_error_set(err, "%s: objects[%d]: out of memory building the %s", s->path, i,
                              shape_names[o->shape]);
            ras_scene_assets_destroy(a);
            return NULL;
        }
        if (o->shape == RAS_SHAPE_MODEL) {
            snprintf(what, sizeof what, "a model of %zu triangles", mesh->triangle_count);
            if (!budget_add(s, a, i, what,
                            mesh_bytes((double)mesh->vertex_count, (double)mesh->triangle_count),
                            err)) {
                ras_scene_assets_destroy(a);
                return NULL;
            }
        }
        if (o->params.fit > 0) {
            /* Translation and uniform scale: normals keep their direction. */
            mat4s fit = ras_mesh_fit_matrix(mesh, o->params.fit);
            for (size_t v = 0; v < mesh->vertex_count; v++)
                mesh->positions[v] = glms_mat4_mulv3(fit, mesh->positions[v], 1.0f);
        }
        const ras_scene_material *mat = &o->material;
        for (size_t v = 0; v < mesh->vertex_count; v++) {
            mesh->colors[v] = glms_vec3_mul(mesh->colors[v], mat->color);
            mesh->uvs[v] = glms_vec2_mul(mesh->uvs[v], mat->uv_scale);
        }
        if ((mat->texture.kind != RAS_MAP_NONE && !(a->textures[i] = get_map(s, a, i, 0, err))) ||
            (mat->height_map.kind != RAS_MAP_NONE &&
             !(a->height_maps[i] = get_map(s, a, i, 1, err)))) {
            ras_scene_assets_destroy(a);
            return NULL;
        }
    }
    return a;
}

void ras_scene_assets_destroy(ras_scene_assets *a) {
    if (!a) return;
    ras_memory_release(a->memory_estimate);
    if (a->meshes)
        for (int i = 0; i < a->object_count; i++)
            ras_mesh_destroy(a->meshes[i]);
    for (int i = 0; i < a->owned_texture_count; i++)
        ras_texture_destroy(a->owned_textures[i]);
    free(a->meshes);
    free(a->textures);
    free(a->height_maps);
    free(a->owned_textures);
    free(a);
}
