/* ras_scene_json.c — see ras_scene_json.h.
 *
 * Notes:
 *   - cJSON keeps no source positions, so every message names the key path
 *     (objects[2].material.ks) that ras_json_join builds while descending.
 *   - Numbers: JSON has no NaN or Infinity, but a literal such as 1e400 reads
 *     as infinity, so every number is checked to be finite and in range
 *     before it is narrowed to float or int.
 */
#include "ras_scene_json.h"

#include <ctype.h>   /* tolower */
#include <float.h>   /* FLT_MIN */
#include <math.h>    /* isfinite, floor, fabsf */
#include <stdarg.h>  /* va_list */
#include <stdio.h>   /* snprintf, vsnprintf */
#include <stdlib.h>  /* malloc */
#include <string.h>  /* strcmp, strlen, memcpy */
#include <strings.h> /* strncasecmp */

/* ---- messages ------------------------------------------------------------ */

bool ras_json_fail(ras_json_ctx *c, const char *path, const char *fmt, ...) {
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

bool ras_json_fail_type(ras_json_ctx *c, const char *path, const char *expected, const cJSON *got) {
    char d[160];
    return ras_json_fail(c, path, "expected %s, got %s", expected, describe(got, d, sizeof d));
}

/* parent.key (or key at the top level), cut to RAS_JSON_PATH_LEN - 1 characters. */
void ras_json_join(char *out, const char *parent, const char *key) {
    size_t o = 0;
    for (const char *s = parent; s && *s && o + 1 < RAS_JSON_PATH_LEN; s++)
        out[o++] = *s;
    if (o > 0 && o + 1 < RAS_JSON_PATH_LEN) out[o++] = '.';
    for (const char *s = key; *s && o + 1 < RAS_JSON_PATH_LEN; s++)
        out[o++] = *s;
    out[o] = '\0';
}

/* parent[i] */
void ras_json_join_index(char *out, const char *parent, int i) {
    char index[16];
    snprintf(index, sizeof index, "[%d]", i);
    size_t o = 0;
    for (const char *s = parent; *s && o + 1 < RAS_JSON_PATH_LEN; s++)
        out[o++] = *s;
    for (const char *s = index; *s && o + 1 < RAS_JSON_PATH_LEN; s++)
        out[o++] = *s;
    out[o] = '\0';
}

/* ---- keys: unknown, duplicate, did-you-mean ------------------------------------ */

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

void ras_json_list_names(const char *const *names, int n, char *buf, size_t size) {
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
typedef const char *(*ras_json_other_key_fn)(const char *key, const void *user, char *buf,
                                             size_t size);
bool ras_json_check_keys(ras_json_ctx *c, const cJSON *obj, const char *path,
                         const char *const *known, int n, ras_json_other_key_fn other,
                         const void *user) {
    for (const cJSON *k = obj->child; k; k = k->next) {
        char p[RAS_JSON_PATH_LEN];
        ras_json_join(p, path, k->string);
        for (const cJSON *j = obj->child; j != k; j = j->next)
            if (!strcmp(j->string, k->string))
                return ras_json_fail(c, p, "duplicate key \"%s\": each key may appear once",
                                     k->string);
        bool ok = false;
        for (int i = 0; i < n && !ok; i++)
            ok = !strcmp(k->string, known[i]);
        if (ok) continue;
        char why[300];
        if (other && other(k->string, user, why, sizeof why)) return ras_json_fail(c, p, "%s", why);
        char q[96];
        quote(k->string, q, sizeof q);
        const char *near = closest(k->string, known, n);
        if (near) return ras_json_fail(c, p, "unknown key %s; did you mean \"%s\"?", q, near);
        char list[400];
        ras_json_list_names(known, n, list, sizeof list);
        return ras_json_fail(c, p, "unknown key %s; expected one of %s", q, list);
    }
    return true;
}

const cJSON *ras_json_member(const cJSON *obj, const char *key) {
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

/* ---- values ---------------------------------------------------------------- */

static void describe_range(ras_json_range r, char *buf, size_t size) {
    if (r.integer)
        snprintf(buf, size, "a whole number in %.0f..%.0f", r.lo, r.hi);
    else
        snprintf(buf, size, "a number in %c%g, %g%c", r.lo_open ? '(' : '[', r.lo, r.hi,
                 r.hi_open ? ')' : ']');
}

static bool in_range(double d, ras_json_range r) {
    if (!isfinite(d)) return false;
    if (r.lo_open ? !(d > r.lo) : !(d >= r.lo)) return false;
    if (r.hi_open ? !(d < r.hi) : !(d <= r.hi)) return false;
    return !r.integer || d == floor(d);
}

static bool read_number(ras_json_ctx *c, const cJSON *v, const char *path, ras_json_range r,
                        double *out) {
    char want[96], got[128];
    describe_range(r, want, sizeof want);
    if (!cJSON_IsNumber(v)) return ras_json_fail_type(c, path, want, v);
    if (!in_range(v->valuedouble, r))
        return ras_json_fail(c, path, "expected %s, got %s", want,
                             describe_number(v->valuedouble, got, sizeof got));
    *out = v->valuedouble;
    return true;
}

bool ras_json_read_float(ras_json_ctx *c, const cJSON *v, const char *path, ras_json_range r,
                         float *out) {
    double d = 0; /* set by read_number when it returns true (gcc cannot see that) */
    if (!read_number(c, v, path, r, &d)) return false;
    float f = (float)d;
    /* In range as a number, but a float (what the renderer computes with)
     * holds it only as 0 or a denormal: every product with it is then 0 or
     * loses its digits, and the picture is black with exit 0 (issue #42, B3). */
    if (d != 0 && !(fabsf(f) >= FLT_MIN)) {
        char got[128];
        return ras_json_fail(c, path,
                             "expected a magnitude of at least %g (a float's smallest normal "
                             "number; a float holds this one %s), got %s",
                             (double)FLT_MIN,
                             f == 0 ? "as 0" : "as a denormal, with too few digits",
                             describe_number(d, got, sizeof got));
    }
    *out = f;
    return true;
}

bool ras_json_read_int(ras_json_ctx *c, const cJSON *v, const char *path, int lo, int hi,
                       int *out) {
    double d = 0; /* set by read_number when it returns true (gcc cannot see that) */
    if (!read_number(c, v, path, (ras_json_range){lo, hi, false, false, true}, &d)) return false;
    *out = (int)d;
    return true;
}

/* Optional members: absent leaves *out (the default) as it is. */
static const cJSON *opt_member(const cJSON *obj, const char *path, const char *key,
                               char p[RAS_JSON_PATH_LEN]) {
    ras_json_join(p, path, key);
    return ras_json_member(obj, key);
}

bool ras_json_opt_float(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                        ras_json_range r, float *out) {
    char p[RAS_JSON_PATH_LEN];
    const cJSON *v = opt_member(obj, path, key, p);
    return !v || ras_json_read_float(c, v, p, r, out);
}

bool ras_json_opt_int(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key, int lo,
                      int hi, int *out) {
    char p[RAS_JSON_PATH_LEN];
    const cJSON *v = opt_member(obj, path, key, p);
    return !v || ras_json_read_int(c, v, p, lo, hi, out);
}

bool ras_json_read_vec3(ras_json_ctx *c, const cJSON *v, const char *path, ras_json_range r,
                        vec3s *out) {
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
        return ras_json_fail_type(c, path, "an array of 3 numbers", v);
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        char p[RAS_JSON_PATH_LEN];
        ras_json_join_index(p, path, i);
        if (!ras_json_read_float(c, e, p, r, &out->raw[i])) return false;
    }
    return true;
}

/* A number (the same for x, y and z) or an array of 3. */
bool ras_json_read_vec3_or_scalar(ras_json_ctx *c, const cJSON *v, const char *path,
                                  ras_json_range r, vec3s *out) {
    if (cJSON_IsNumber(v)) {
        float f;
        if (!ras_json_read_float(c, v, path, r, &f)) return false;
        *out = (vec3s){{f, f, f}};
        return true;
    }
    if (!cJSON_IsArray(v))
        return ras_json_fail_type(c, path, "a number or an array of 3 numbers", v);
    return ras_json_read_vec3(c, v, path, r, out);
}

bool ras_json_opt_vec3(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                       ras_json_range r, vec3s *out) {
    char p[RAS_JSON_PATH_LEN];
    const cJSON *v = opt_member(obj, path, key, p);
    return !v || ras_json_read_vec3(c, v, p, r, out);
}

bool ras_json_opt_vec3_or_scalar(ras_json_ctx *c, const cJSON *obj, const char *path,
                                 const char *key, ras_json_range r, vec3s *out) {
    char p[RAS_JSON_PATH_LEN];
    const cJSON *v = opt_member(obj, path, key, p);
    return !v || ras_json_read_vec3_or_scalar(c, v, p, r, out);
}

static int hex_digit(char ch) {
    if (ch >= '0' && ch <= '9') return ch - '0';
    if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
    return -1;
}

/* A colour: [r, g, b] in [0, 1], or "#rrggbb". */
bool ras_json_read_color(ras_json_ctx *c, const cJSON *v, const char *path, vec3s *out) {
    static const char *want = "a colour: an array of 3 numbers in [0, 1] or a \"#rrggbb\" string";
    if (cJSON_IsString(v)) {
        const char *s = v->valuestring;
        bool ok = strlen(s) == 7 && s[0] == '#';
        for (int i = 1; ok && i < 7; i++)
            ok = hex_digit(s[i]) >= 0;
        if (!ok) return ras_json_fail_type(c, path, want, v);
        for (int i = 0; i < 3; i++)
            out->raw[i] = (float)(hex_digit(s[1 + 2 * i]) * 16 + hex_digit(s[2 + 2 * i])) / 255.0f;
        return true;
    }
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
        return ras_json_fail_type(c, path, want, v);
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
        return ras_json_fail(
            c, path,
            "expected colour components in [0, 1], got [%d, %d, %d]; for 8-bit values "
            "write \"#%02x%02x%02x\" (or divide each by 255)",
            b[0], b[1], b[2], b[0], b[1], b[2]);
    }
    return ras_json_read_vec3(c, v, path, RAS_JSON_UNIT, out);
}

bool ras_json_opt_color(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                        vec3s *out) {
    char p[RAS_JSON_PATH_LEN];
    const cJSON *v = opt_member(obj, path, key, p);
    return !v || ras_json_read_color(c, v, p, out);
}

bool ras_json_read_enum(ras_json_ctx *c, const cJSON *v, const char *path, const char *const *names,
                        int n, int *out) {
    char list[300];
    ras_json_list_names(names, n, list, sizeof list);
    char want[340];
    snprintf(want, sizeof want, "one of %s", list);
    if (!cJSON_IsString(v)) return ras_json_fail_type(c, path, want, v);
    for (int i = 0; i < n; i++)
        if (!strcmp(v->valuestring, names[i])) {
            *out = i;
            return true;
        }
    char q[96];
    quote(v->valuestring, q, sizeof q);
    const char *near = closest(v->valuestring, names, n);
    if (near)
        return ras_json_fail(c, path, "expected %s, got %s; did you mean \"%s\"?", want, q, near);
    return ras_json_fail(c, path, "expected %s, got %s", want, q);
}

bool ras_json_opt_enum(ras_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                       const char *const *names, int n, int *out) {
    char p[RAS_JSON_PATH_LEN];
    const cJSON *v = opt_member(obj, path, key, p);
    return !v || ras_json_read_enum(c, v, p, names, n, out);
}

bool ras_json_read_object(ras_json_ctx *c, const cJSON *v, const char *path) {
    return cJSON_IsObject(v) || ras_json_fail_type(c, path, "an object {...}", v);
}

bool ras_json_fail_missing(ras_json_ctx *c, const char *path, const char *key, const char *what) {
    return ras_json_fail(c, path, "missing required key \"%s\" (%s)", key, what);
}

/* A copy of s (NULL on out of memory, with the error set). */
char *ras_json_dup_str(ras_json_ctx *c, const char *s) {
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (!d)
        ras_json_fail(c, NULL, "out of memory");
    else
        memcpy(d, s, n);
    return d;
}

/* dir/rel, or rel itself when it is absolute or dir is ".". */
static char *resolve(ras_json_ctx *c, const char *rel) {
    if (rel[0] == '/' || !strcmp(c->dir, ".")) return ras_json_dup_str(c, rel);
    size_t n = strlen(c->dir) + 1 + strlen(rel) + 1;
    char *d = malloc(n);
    if (!d) {
        ras_json_fail(c, NULL, "out of memory");
        return NULL;
    }
    snprintf(d, n, "%s%s%s", c->dir, c->dir[strlen(c->dir) - 1] == '/' ? "" : "/", rel);
    return d;
}

/* Whether s starts with a URI scheme ("file://", "http://"): such a name
 * joined to the scene's folder would be a file no one meant. */
static bool is_uri(const char *s) {
    if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z'))) return false;
    size_t i = 1;
    while ((s[i] >= 'a' && s[i] <= 'z') || (s[i] >= 'A' && s[i] <= 'Z') ||
           (s[i] >= '0' && s[i] <= '9') || s[i] == '+' || s[i] == '-' || s[i] == '.')
        i++;
    return s[i] == ':' && s[i + 1] == '/' && s[i + 2] == '/';
}

bool ras_json_read_path(ras_json_ctx *c, const cJSON *v, const char *path, const char *what,
                        char **out) {
    if (!cJSON_IsString(v) || !v->valuestring[0]) return ras_json_fail_type(c, path, what, v);
    if (is_uri(v->valuestring)) {
        char q[96];
        quote(v->valuestring, q, sizeof q);
        return ras_json_fail(c, path,
                             "expected %s (relative to the scene's folder, or absolute), got the "
                             "URI %s; write the file's path itself (file:///a/b.png is /a/b.png)",
                             what, q);
    }
    *out = resolve(c, v->valuestring);
    return *out != NULL;
}
