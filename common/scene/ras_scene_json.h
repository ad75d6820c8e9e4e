/* ras_scene_json.h — checking JSON values, for the scene reader (private to
 * ras_scene*.c).
 *
 * cJSON parses; these functions check what it built against what the scene
 * format expects, one value at a time, and say what is wrong in one sentence
 * that names the file and the key path, what was expected and what came:
 *     scene.json: objects[2].material.ks: expected an array of 3 numbers, got a string ("0.7")
 * The schema (ras_scene_schema.c) says which keys exist; this module knows
 * the value types: numbers in a range, vectors, colours, enums, file paths,
 * and objects whose keys must be known (with a did-you-mean for a near miss)
 * and appear once.
 *
 * Conventions: every ras_json_read_* and ras_json_opt_* returns false after
 * setting c->err and leaves *out alone on failure; ras_json_opt_* leave *out
 * (the default) as it is when the key is absent. `path` is the key path of
 * the value (built with ras_json_join / ras_json_join_index, at most
 * RAS_JSON_PATH_LEN - 1 characters; "" at the top level).
 *
 * Dependencies: cJSON, ras_error, cglm through ras_math.h.
 */
#ifndef RAS_SCENE_JSON_H
#define RAS_SCENE_JSON_H

#include "ras_error.h"
#include "ras_math.h"

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stddef.h> /* size_t */

#define RAS_JSON_BIG 1e6      /* coordinates, strengths and scales are limited to ±1e6 */
#define RAS_JSON_PATH_LEN 192 /* a key path's buffer */

/* Where messages come from, and where relative paths lead. */
typedef struct ras_json_ctx {
    const char *file; /* for messages */
    const char *dir;  /* relative paths resolve against it */
    ras_error *err;
} ras_json_ctx;

/* The numbers a key accepts: [lo, hi], either end open, whole numbers only. */
typedef struct ras_json_range {
    double lo, hi;
    bool lo_open, hi_open;
    bool integer;
} ras_json_range;

#define RAS_JSON_ANY ((ras_json_range){-RAS_JSON_BIG, RAS_JSON_BIG, false, false, false})
#define RAS_JSON_NONNEG ((ras_json_range){0, RAS_JSON_BIG, false, false, false})
#define RAS_JSON_POS ((ras_json_range){0, RAS_JSON_BIG, true, false, false})
#define RAS_JSON_UNIT ((ras_json_range){0, 1, false, false, false})

/* ---- messages ---- */

/* Sets "<file>: <path>: <message>" (no path: "<file>: <message>"); false. */
bool ras_json_fail(ras_json_ctx *c, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* "expected <expected>, got <what got is>"; false. */
bool ras_json_fail_type(ras_json_ctx *c, const char *path, const char *expected, const cJSON *got);
/* "missing required key \"<key>\" (<what>)"; false. */
bool ras_json_fail_missing(ras_json_ctx *c, const char *path, const char *key, const char *what);
/* out = parent.key (or key at the top level), cut to RAS_JSON_PATH_LEN - 1. */
void ras_json_join(char *out, const char *parent, const char *key);
/* out = parent[i]. */
void ras_json_join_index(char *out, const char *parent, int i);
/* "a, b or c" into buf. */
void ras_json_list_names(const char *const *names, int n, char *buf, size_t size);

/* ---- objects and keys ---- */

/* A message for `key`, which is known elsewhere but not here (buf), or NULL. */
typedef const char *(*ras_json_other_key_fn)(const char *key, const void *user, char *buf,
                                             size_t size);
/* Every key of obj must be in `known` and appear once. `other` (may be NULL)
 * explains keys that are known elsewhere but not here. */
bool ras_json_check_keys(ras_json_ctx *c, const cJSON *obj, const char *path,
                         const char *const *known, int n, ras_json_other_key_fn other,
                         const void *user);
/* obj's member `key` (case-sensitive), or NULL. */
const cJSON *ras_json_member(const cJSON *obj, const char *key);
bool ras_json_read_object(ras_json_ctx *c, const cJSON *v, const char *path);

/* ---- values ---- */

bool ras_json_read_float(ras_json_ctx *c, const cJSON *v, const char *path, ras_json_range r,
                         float *out);
bool ras_json_read_int(ras_json_ctx *c, const cJSON *v, const char *path, int lo, int hi, int *out);
bool ras_json_opt_float(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                        ras_json_range r, float *out);
bool ras_json_opt_int(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key, int lo,
                      int hi, int *out);
/* [x, y, z], each in r. */
bool ras_json_read_vec3(ras_json_ctx *c, const cJSON *v, const char *path, ras_json_range r,
                        vec3s *out);
/* A number (the same for x, y and z) or an array of 3. */
bool ras_json_read_vec3_or_scalar(ras_json_ctx *c, const cJSON *v, const char *path,
                                  ras_json_range r, vec3s *out);
bool ras_json_opt_vec3(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                       ras_json_range r, vec3s *out);
bool ras_json_opt_vec3_or_scalar(ras_json_ctx *c, const cJSON *obj, const char *path,
                                 const char *key, ras_json_range r, vec3s *out);
/* A colour: [r, g, b] in [0, 1], or "#rrggbb" (8-bit triples get a hint). */
bool ras_json_read_color(ras_json_ctx *c, const cJSON *v, const char *path, vec3s *out);
bool ras_json_opt_color(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                        vec3s *out);
/* One of names[0..n) (a did-you-mean for a near miss); *out is its index. */
bool ras_json_read_enum(ras_json_ctx *c, const cJSON *v, const char *path, const char *const *names,
                        int n, int *out);
bool ras_json_opt_enum(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                       const char *const *names, int n, int *out);
/* A non-empty string, resolved against c->dir into a heap copy (*out). */
bool ras_json_read_path(ras_json_ctx *c, const cJSON *v, const char *path, const char *what,
                        char **out);
/* A heap copy of s; NULL (and the error set) on out of memory. */
char *ras_json_dup_str(ras_json_ctx *c, const char *s);

#endif
