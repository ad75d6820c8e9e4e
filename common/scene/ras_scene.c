/* ras_scene.c — scene files: reading one (ras_scene_load, ras_scene_parse)
 * and what every user of a scene needs (ras_scene_destroy, the model and
 * view matrices).
 *
 * Reading a scene is split by job, one module each:
 *   ras_scene.c          the file: size and kind checks, the text, cJSON
 *   ras_scene_syntax.c   what is wrong with text that is not JSON (line:column)
 *   ras_scene_schema.c   the format: sections, keys, defaults (key paths)
 *   ras_scene_json.c     one value against what a key expects, with a message
 *   ras_scene_assets.c   the meshes and textures a scene names
 * so that the format changes in one place (the schema) and the wording of
 * the messages in two others (ras_scene_json.c, ras_scene_syntax.c).
 *
 * Dependencies: cJSON (libcjson), cglm (struct API).
 */
#include "ras_scene.h"

#include "ras_io.h"           /* ras_io_open_input, ras_io_text_nesting */
#include "ras_scene_json.h"   /* ras_json_ctx, ras_json_fail, ras_json_dup_str */
#include "ras_scene_schema.h" /* ras_scene_schema_defaults, ras_scene_schema_read */
#include "ras_scene_syntax.h" /* ras_scene_syntax_error, ras_scene_syntax_line_col */

#include <cjson/cJSON.h> /* cJSON_ParseWithOpts, cJSON_GetErrorPtr, CJSON_NESTING_LIMIT */
#include <ctype.h>       /* isspace */
#include <errno.h>       /* errno */
#include <math.h>        /* cosf, sinf */
#include <stdio.h>       /* fdopen, fread, snprintf */
#include <stdlib.h>      /* calloc, malloc, free */
#include <string.h>      /* strlen, strerror, strrchr, strcpy, memcpy, memchr */
#include <sys/stat.h>    /* stat, S_ISDIR */
#include <unistd.h>      /* close */

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
    ras_json_ctx c = {.file = name, .dir = dir, .err = err};
    size_t start = 0;
    if (len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3)) start = 3;
    size_t first = start;
    while (first < len && isspace((unsigned char)text[first]))
        first++;
    if (first == len) {
        ras_json_fail(&c, NULL, "expected a JSON object {...}, got %s",
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
        ras_scene_syntax_line_col(text, start + deep_at, &line, &col);
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
        ras_scene_syntax_error(name, text, len, off, err);
        return NULL;
    }
    ras_scene *s = calloc(1, sizeof *s);
    if (!s) {
        cJSON_Delete(root);
        ras_json_fail(&c, NULL, "out of memory");
        return NULL;
    }
    ras_scene_schema_defaults(s);
    bool ok = (s->path = ras_json_dup_str(&c, name)) && (s->dir = ras_json_dup_str(&c, dir)) &&
              ras_scene_schema_read(&c, root, s);
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

/* UTF-16 or UTF-32 (a byte-order mark, or a NUL beside every ASCII
 * character: what Notepad and PowerShell save), and JSON's \u0000 escape
 * inside a string (which would end the string there: "cube\u0000sphere" read
 * as "cube"), refused with what to do; the NUL check after this one then
 * speaks only of binary files. */
static bool scene_text_is_utf8(const char *path, const char *text, size_t len, ras_error *err) {
    const unsigned char *u = (const unsigned char *)text;
    bool bom16 = len >= 2 && ((u[0] == 0xFF && u[1] == 0xFE) || (u[0] == 0xFE && u[1] == 0xFF));
    bool bom32 = len >= 4 && ((u[0] == 0xFF && u[1] == 0xFE && !u[2] && !u[3]) ||
                              (!u[0] && !u[1] && u[2] == 0xFE && u[3] == 0xFF));
    /* without a mark: ASCII in UTF-16 puts a NUL in every other byte */
    size_t pairs = len < 64 ? len / 2 : 32, le = 0, be = 0;
    for (size_t i = 0; i < pairs; i++) {
        le += u[2 * i] && !u[2 * i + 1];
        be += !u[2 * i] && u[2 * i + 1];
    }
    bool wide = pairs >= 2 && (le == pairs || be == pairs);
    if (bom16 || bom32 || wide)
        return ras_error_set(err,
                             "%s: the scene is %s (%s); expected UTF-8 JSON — save it as UTF-8 "
                             "(in Notepad: Save As, Encoding UTF-8)",
                             path, bom32 ? "UTF-32" : "UTF-16",
                             bom16 || bom32 ? "it begins with a byte-order mark"
                                            : "a NUL byte beside every character");
    bool in_string = false;
    for (size_t i = 0; i < len; i++) {
        if (text[i] == '"') in_string = !in_string;
        if (!in_string || text[i] != '\\') continue;
        if (i + 5 < len && text[i + 1] == 'u' && !strncmp(text + i + 2, "0000", 4)) {
            int line, col;
            ras_scene_syntax_line_col(text, i, &line, &col);
            return ras_error_set(err,
                                 "%s:%d:%d: expected a string without NUL characters, got the "
                                 "escape \\u0000 in one (everything after it would be lost: "
                                 "\"cube\\u0000sphere\" reads as \"cube\"); remove it",
                                 path, line, col);
        }
        i++; /* the escaped character, a quote included, is not the string's end */
    }
    return true;
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
    if (!scene_text_is_utf8(path, text, len, err)) {
        free(text);
        return NULL;
    }
    const char *nul = memchr(text, '\0', len);
    if (nul) {
        int line, col;
        ras_scene_syntax_line_col(text, (size_t)(nul - text), &line, &col);
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

/* ---- the model matrix ------------------------------------------------------ */

/* hw3's form turns with its own matrices about +x and +y (its reference
 * images were drawn with them, so they stay), and glms_rotate_make about any
 * other axis (no z matrix written out here: that is hw1's exercise). */
static mat4s rotate_y(float deg) {
    float a = ras_deg_to_rad(deg), c = cosf(a), s = sinf(a);
    return ras_mat4_rows(c, 0, s, 0,
                         0, 1, 0, 0,
                         -s, 0, c, 0,
                         0, 0, 0, 1);
}

static mat4s rotate_x(float deg) {
    float a = ras_deg_to_rad(deg), c = cosf(a), s = sinf(a);
    return ras_mat4_rows(1, 0, 0, 0,
                         0, c, -s, 0,
                         0, s, c, 0,
                         0, 0, 0, 1);
}

static mat4s rotation_about_axis(const ras_scene_rotation *r) {
    return glms_rotate_make(ras_deg_to_rad(r->deg), r->axis);
}

static mat4s rotation_axis_matrices(const ras_scene_rotation *r) {
    vec3s a = r->axis;
    if (a.y == 0 && a.z == 0 && a.x > 0) return rotate_x(r->deg);
    if (a.x == 0 && a.z == 0 && a.y > 0) return rotate_y(r->deg);
    return rotation_about_axis(r);
}

/* A matrix spin: ((T · spin) · (R_{n-1} ⋯ R_0 · I)) · S, every factor. */
static mat4s model_with_matrix(const ras_scene_object *o, mat4s spin) {
    mat4s r = glms_mat4_identity();
    for (int i = 0; i < o->rotation_count; i++)
        r = ras_mat4_mul(rotation_about_axis(&o->rotations[i]), r);
    mat4s m = ras_mat4_mul(glms_translate_make(o->translate), spin);
    return ras_mat4_mul(ras_mat4_mul(m, r), glms_scale_make(o->scale));
}

/* hw3's turn: (T · R_y(yaw + turn)) · orient, a last rotation about ±y taken
 * into the turn as yaw (the turn about y and that rotation commute, so
 * T · spin · R · S is kept). */
static mat4s model_with_turn_y(const ras_scene_object *o, float turn_deg) {
    mat4s place = ras_mat4_rows(1, 0, 0, o->translate.x, 0, 1, 0, o->translate.y, 0, 0, 1,
                                o->translate.z, 0, 0, 0, 1);
    float yaw_deg = 0;
    int n = o->rotation_count;
    const ras_scene_rotation *last = n > 0 ? &o->rotations[n - 1] : NULL;
    if (last && last->axis.x == 0 && last->axis.z == 0 && last->axis.y != 0) {
        yaw_deg = last->axis.y > 0 ? last->deg : -last->deg;
        n--;
    }
    /* orient = R(rotations[n-1]) ⋯ R(rotations[0]) · S, skipping identity
     * factors: the reference images were drawn with exactly these products
     * (a product with the identity can still turn a -0 into +0). */
    mat4s orient = glms_mat4_identity();
    for (int i = 0; i < n; i++)
        orient = i == 0 ? rotation_axis_matrices(&o->rotations[0])
                        : ras_mat4_mul(rotation_axis_matrices(&o->rotations[i]), orient);
    vec3s k = o->scale;
    if (k.x != 1 || k.y != 1 || k.z != 1) orient = ras_mat4_mul(orient, glms_scale_make(k));
    return ras_mat4_mul(ras_mat4_mul(place, rotate_y(yaw_deg + turn_deg)), orient);
}

mat4s ras_scene_model_matrix(const ras_scene_object *object, ras_scene_spin spin) {
    return spin.matrix ? model_with_matrix(object, *spin.matrix)
                       : model_with_turn_y(object, spin.turn_y_deg);
}
