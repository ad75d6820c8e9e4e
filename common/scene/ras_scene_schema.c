/* ras_scene_schema.c — see ras_scene_schema.h.
 *
 * Notes:
 *   - One function a section of the format (parse_camera, parse_object,
 *     parse_map, ...): each lists the keys its object may have, so an unknown
 *     or misplaced key is reported where it is (ras_json_check_keys), then
 *     reads the values with ras_json_read_* / ras_json_opt_*.
 *   - Every function that fills the scene returns false after setting the
 *     error; the caller unwinds and ras_scene_destroy frees whatever was
 *     filled in (the scene starts zeroed, so that is always safe).
 *   - Defaults are set before a section is read (ras_scene_schema_defaults,
 *     material_defaults, the shape parameters' in parse_shape_params), so an
 *     absent key keeps its documented default.
 */
#include "ras_scene_schema.h"

#include "ras_names.h" /* the option values' spellings */

#include <float.h>  /* FLT_MIN */
#include <math.h>   /* tanf */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* calloc */
#include <string.h> /* strcmp */

/* ---- names --------------------------------------------------------------- */

static const char *const shape_names[RAS_SHAPE_COUNT] = {"triangle", "plane",  "cube",     "sphere",
                                                         "torus",    "teapot", "thin_fan", "model"};
/* Option values are spelled by ras_names.h's tables; NAMES(t) passes one
 * to ras_json_read_enum. */
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
const char *ras_scene_cull_name(ras_cull_mode c) { return ras_name_of(&ras_names_cull, (int)c); }

/* ---- sections ------------------------------------------------------------ */

static bool parse_image(ras_json_ctx *c, const cJSON *v, ras_scene *s) {
    static const char *const keys[] = {"width", "height"};
    if (!ras_json_read_object(c, v, "image") ||
        !ras_json_check_keys(c, v, "image", keys, COUNT(keys), NULL, NULL))
        return false;
    return ras_json_opt_int(c, v, "image", "width", 1, RAS_SCENE_MAX_SIZE, &s->width) &&
           ras_json_opt_int(c, v, "image", "height", 1, RAS_SCENE_MAX_SIZE, &s->height);
}

/* The projection (hw1's get_projection_matrix) computes in float with
 * tan(fov / 2), the frustum's half height at the near plane near ·
 * tan(fov / 2) and its half width (that times the aspect, as narrow as
 * 1 / RAS_SCENE_MAX_SIZE with --size), their reciprocals, and near · far.
 * Each value is legal alone; one of these products of them that is 0 or a
 * denormal in float makes the matrix 0 or infinite and the picture black,
 * with exit 0 (issue #42, B3). */
static bool projection_in_float(ras_json_ctx *c, const ras_scene_camera *cam) {
    float tan_half = tanf(ras_deg_to_rad(cam->fov_deg) * 0.5f);
    if (!(tan_half >= FLT_MIN))
        return ras_json_fail(c, "camera.fov_deg",
                             "expected a field of view whose half angle's tangent a float holds "
                             "(tan(fov/2) at least %g), got %g degrees (tan(fov/2) = %g in "
                             "float); use a wider field of view",
                             (double)FLT_MIN, (double)cam->fov_deg, (double)tan_half);
    float half_width = cam->z_near * tan_half / (float)RAS_SCENE_MAX_SIZE;
    if (!(half_width >= FLT_MIN))
        return ras_json_fail(c, "camera.near",
                             "expected a near distance whose frustum half width near * "
                             "tan(fov/2) / %d a float holds (at least %g), got near %g with "
                             "fov %g degrees (%g); use a larger near or field of view",
                             RAS_SCENE_MAX_SIZE, (double)FLT_MIN, (double)cam->z_near,
                             (double)cam->fov_deg, (double)half_width);
    float near_far = cam->z_near * cam->z_far;
    if (!(near_far >= FLT_MIN))
        return ras_json_fail(c, "camera.near",
                             "expected near * far to be at least %g (a float's smallest normal "
                             "number; the projection's depth row is made of it), got near %g * "
                             "far %g = %g; use a larger near",
                             (double)FLT_MIN, (double)cam->z_near, (double)cam->z_far,
                             (double)near_far);
    return true;
}

static bool parse_camera(ras_json_ctx *c, const cJSON *v, ras_scene_camera *cam) {
    static const char *const keys[] = {"eye", "look_at", "up", "fov_deg", "near", "far"};
    if (!ras_json_read_object(c, v, "camera") ||
        !ras_json_check_keys(c, v, "camera", keys, COUNT(keys), NULL, NULL))
        return false;
    if (!ras_json_opt_vec3(c, v, "camera", "eye", RAS_JSON_ANY, &cam->eye) ||
        !ras_json_opt_vec3(c, v, "camera", "look_at", RAS_JSON_ANY, &cam->look_at) ||
        !ras_json_opt_vec3(c, v, "camera", "up", RAS_JSON_ANY, &cam->up) ||
        !ras_json_opt_float(c, v, "camera", "fov_deg", (ras_json_range){0, 180, true, true, false},
                            &cam->fov_deg) ||
        !ras_json_opt_float(c, v, "camera", "near", RAS_JSON_POS, &cam->z_near) ||
        !ras_json_opt_float(c, v, "camera", "far", RAS_JSON_POS, &cam->z_far))
        return false;
    if (ras_json_member(v, "up") && !ras_json_member(v, "look_at"))
        return ras_json_fail(
            c, "camera.up",
            "\"up\" is used only with \"look_at\"; the fixed view (no \"look_at\") "
            "always has y up");
    if (ras_json_member(v, "look_at")) {
        cam->view = RAS_SCENE_VIEW_LOOK_AT;
        vec3s dir = glms_vec3_sub(cam->look_at, cam->eye);
        if (glms_vec3_norm(dir) < 1e-6f)
            return ras_json_fail(
                c, "camera.look_at",
                "expected a point other than the eye (%g, %g, %g), got the eye itself", cam->eye.x,
                cam->eye.y, cam->eye.z);
        vec3s side = glms_vec3_cross(glms_vec3_normalize(dir), cam->up);
        if (glms_vec3_norm(side) < 1e-6f * (glms_vec3_norm(cam->up) + 1e-30f) ||
            glms_vec3_norm(cam->up) < 1e-12f)
            return ras_json_fail(
                c, "camera.up",
                "expected a direction not parallel to the view direction (look_at - "
                "eye), got (%g, %g, %g)",
                cam->up.x, cam->up.y, cam->up.z);
    }
    if (!(cam->z_near < cam->z_far))
        return ras_json_fail(c, "camera.far", "expected far > near (%g), got %g", cam->z_near,
                             cam->z_far);
    return projection_in_float(c, cam);
}

static bool read_axis(ras_json_ctx *c, const cJSON *v, const char *path, vec3s *axis) {
    if (!ras_json_read_vec3(c, v, path, RAS_JSON_ANY, axis)) return false;
    if (glms_vec3_norm(*axis) < 1e-12f)
        return ras_json_fail(c, path, "expected a non-zero axis, got (0, 0, 0)");
    return true;
}

static bool parse_model_rotation(ras_json_ctx *c, const cJSON *v, ras_scene *s) {
    static const char *const keys[] = {"angle_deg", "axis"};
    const char *path = "model_rotation";
    if (!ras_json_read_object(c, v, path) ||
        !ras_json_check_keys(c, v, path, keys, COUNT(keys), NULL, NULL))
        return false;
    if (!ras_json_opt_float(c, v, path, "angle_deg", RAS_JSON_ANY, &s->model_rotation_deg))
        return false;
    const cJSON *axis = ras_json_member(v, "axis");
    if (axis) {
        if (!read_axis(c, axis, "model_rotation.axis", &s->model_rotation_axis)) return false;
        s->model_rotation_axis_set = true;
    }
    return true;
}

/* ---- objects ------------------------------------------------------------- */

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
                ras_json_list_names(own, own_n, list, sizeof list);
                snprintf(buf, size,
                         "shape \"%s\" takes no \"%s\" (a parameter of %s); its "
                         "parameters are %s",
                         shape_names[shape], key, shape_names[s], list);
                return buf;
            }
    }
    return NULL;
}

static bool parse_shape_params(ras_json_ctx *c, const cJSON *v, const char *path,
                               ras_scene_object *o) {
    ras_scene_shape_params *sp = &o->params;
    switch (o->shape) {
    case RAS_SHAPE_TRIANGLE: {
        const cJSON *vs = ras_json_member(v, "vertices");
        char p[RAS_JSON_PATH_LEN];
        ras_json_join(p, path, "vertices");
        if (!vs)
            return ras_json_fail_missing(c, path, "vertices", "an array of 3 points [x, y, z]");
        if (!cJSON_IsArray(vs) || cJSON_GetArraySize(vs) != 3)
            return ras_json_fail_type(c, p, "an array of 3 points [x, y, z]", vs);
        int i = 0;
        for (const cJSON *e = vs->child; e; e = e->next, i++) {
            char pi[RAS_JSON_PATH_LEN];
            ras_json_join_index(pi, p, i);
            if (!ras_json_read_vec3(c, e, pi, RAS_JSON_ANY, &sp->vertices[i])) return false;
        }
        return true;
    }
    case RAS_SHAPE_PLANE:
        sp->size = 2;
        sp->divisions = 1;
        return ras_json_opt_float(c, v, path, "size", RAS_JSON_POS, &sp->size) &&
               ras_json_opt_int(c, v, path, "divisions", 1, 1024, &sp->divisions);
    case RAS_SHAPE_CUBE:
        sp->size = 1;
        return ras_json_opt_float(c, v, path, "size", RAS_JSON_POS, &sp->size);
    case RAS_SHAPE_SPHERE:
        sp->radius = 1;
        sp->stacks = 32;
        sp->slices = 64;
        return ras_json_opt_float(c, v, path, "radius", RAS_JSON_POS, &sp->radius) &&
               ras_json_opt_int(c, v, path, "stacks", 2, 1024, &sp->stacks) &&
               ras_json_opt_int(c, v, path, "slices", 3, 1024, &sp->slices);
    case RAS_SHAPE_TORUS:
        sp->major_radius = 1;
        sp->minor_radius = 0.4f;
        sp->rings = 64;
        sp->sides = 32;
        return ras_json_opt_float(c, v, path, "major_radius", RAS_JSON_POS, &sp->major_radius) &&
               ras_json_opt_float(c, v, path, "minor_radius", RAS_JSON_POS, &sp->minor_radius) &&
               ras_json_opt_int(c, v, path, "rings", 3, 1024, &sp->rings) &&
               ras_json_opt_int(c, v, path, "sides", 3, 1024, &sp->sides);
    case RAS_SHAPE_TEAPOT:
        sp->divisions = 8;
        return ras_json_opt_int(c, v, path, "divisions", 1, 64, &sp->divisions);
    case RAS_SHAPE_THIN_FAN:
        sp->count = 200;
        sp->radius = 1;
        sp->arc_deg = 360;
        return ras_json_opt_int(c, v, path, "count", 1, 100000, &sp->count) &&
               ras_json_opt_float(c, v, path, "radius", RAS_JSON_POS, &sp->radius) &&
               ras_json_opt_float(c, v, path, "arc_deg",
                                  (ras_json_range){0, 360, true, false, false}, &sp->arc_deg);
    case RAS_SHAPE_MODEL: {
        char p[RAS_JSON_PATH_LEN];
        ras_json_join(p, path, "model");
        return ras_json_read_path(c, ras_json_member(v, "model"), p,
                                  "a model file path (a non-empty string)", &sp->model_path) &&
               ras_json_opt_float(c, v, path, "fit", RAS_JSON_POS, &sp->fit);
    }
    }
    return false;
}

static bool read_scale(ras_json_ctx *c, const cJSON *v, const char *path, vec3s *out) {
    if (!ras_json_read_vec3_or_scalar(c, v, path, RAS_JSON_ANY, out)) return false;
    for (int i = 0; i < 3; i++)
        if (out->raw[i] == 0)
            return ras_json_fail(c, path, "expected a non-zero scale, got 0%s",
                                 cJSON_IsArray(v) ? " in one component" : "");
    return true;
}

static bool read_rotation(ras_json_ctx *c, const cJSON *v, const char *path,
                          ras_scene_rotation *r) {
    static const char *const keys[] = {"axis", "deg"};
    if (!cJSON_IsObject(v))
        return ras_json_fail_type(c, path, "a rotation {\"axis\": [x, y, z], \"deg\": angle}", v);
    if (!ras_json_check_keys(c, v, path, keys, COUNT(keys), NULL, NULL)) return false;
    const cJSON *axis = ras_json_member(v, "axis"), *deg = ras_json_member(v, "deg");
    if (!axis) return ras_json_fail_missing(c, path, "axis", "an array of 3 numbers, not all zero");
    if (!deg) return ras_json_fail_missing(c, path, "deg", "the angle in degrees");
    char pa[RAS_JSON_PATH_LEN], pd[RAS_JSON_PATH_LEN];
    ras_json_join(pa, path, "axis");
    ras_json_join(pd, path, "deg");
    return read_axis(c, axis, pa, &r->axis) &&
           ras_json_read_float(c, deg, pd, RAS_JSON_ANY, &r->deg);
}

static bool parse_transform(ras_json_ctx *c, const cJSON *v, const char *path,
                            ras_scene_object *o) {
    static const char *const keys[] = {"translate", "rotate", "scale"};
    if (!ras_json_read_object(c, v, path) ||
        !ras_json_check_keys(c, v, path, keys, COUNT(keys), NULL, NULL))
        return false;
    if (!ras_json_opt_vec3(c, v, path, "translate", RAS_JSON_ANY, &o->translate)) return false;
    char p[RAS_JSON_PATH_LEN];
    const cJSON *scale = ras_json_member(v, "scale");
    ras_json_join(p, path, "scale");
    if (scale && !read_scale(c, scale, p, &o->scale)) return false;
    const cJSON *rot = ras_json_member(v, "rotate");
    ras_json_join(p, path, "rotate");
    if (rot && cJSON_IsArray(rot)) {
        int n = cJSON_GetArraySize(rot);
        if (n > RAS_SCENE_MAX_ROTATIONS)
            return ras_json_fail(c, p, "expected at most %d rotations, got %d",
                                 RAS_SCENE_MAX_ROTATIONS, n);
        int i = 0;
        for (const cJSON *e = rot->child; e; e = e->next, i++) {
            char pi[RAS_JSON_PATH_LEN];
            ras_json_join_index(pi, p, i);
            if (!read_rotation(c, e, pi, &o->rotations[i])) return false;
        }
        o->rotation_count = n;
    } else if (rot) {
        if (!cJSON_IsObject(rot))
            return ras_json_fail_type(
                c, p,
                "a rotation {\"axis\": [x, y, z], \"deg\": angle} or an array of "
                "them",
                rot);
        if (!read_rotation(c, rot, p, &o->rotations[0])) return false;
        o->rotation_count = 1;
    }
    return true;
}

static bool parse_map(ras_json_ctx *c, const cJSON *v, const char *path, ras_scene_map *m) {
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
                return ras_json_fail(
                    c, path,
                    "expected a file path or an object, got \"%s\", which reads as a "
                    "file name; for the built-in picture write {\"builtin\": \"%s\"}",
                    v->valuestring, v->valuestring);
        m->kind = RAS_MAP_FILE;
        return ras_json_read_path(c, v, path, "a file path", &m->path);
    }
    if (!cJSON_IsObject(v))
        return ras_json_fail_type(c, path,
                                  "a file path (a string) or an object {\"file\": ...} or "
                                  "{\"builtin\": \"checker\" | \"brick\" | \"bumps\", ...}",
                                  v);
    const cJSON *file = ras_json_member(v, "file"), *builtin = ras_json_member(v, "builtin");
    if (file && builtin)
        return ras_json_fail(c, path, "expected either \"file\" or \"builtin\", got both");
    if (!file && !builtin)
        return ras_json_fail_missing(c, path, "file\" or \"builtin",
                                     "a file path, or one of checker, brick, bumps");
    /* Which keys go with which kind. */
    const char *keys[4];
    int n = 0;
    keys[n++] = file ? "file" : "builtin";
    keys[n++] = "wrap";
    char p[RAS_JSON_PATH_LEN];
    if (file) {
        m->kind = RAS_MAP_FILE;
        ras_json_join(p, path, "file");
        if (!ras_json_read_path(c, file, p, "a file path (a non-empty string)", &m->path))
            return false;
    } else {
        int kind = 0; /* gcc -O2 cannot see ras_json_read_enum sets it on success */
        ras_json_join(p, path, "builtin");
        if (!ras_json_read_enum(c, builtin, p, builtin_map_names, COUNT(builtin_map_names), &kind))
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
            ras_json_join(p, path, k->string);
            return ras_json_fail(c, p, "\"%s\" does not apply to %s", k->string,
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
    if (!ras_json_check_keys(c, v, path, known, kn, NULL, NULL)) return false;
    int wrap = 0;
    if (!ras_json_opt_enum(c, v, path, "wrap", NAMES(ras_names_wrap), &wrap)) return false;
    m->wrap = wrap == 0 ? RAS_WRAP_REPEAT : RAS_WRAP_CLAMP;
    if (!ras_json_opt_int(c, v, path, "size", 1, 4096, &m->size) ||
        !ras_json_opt_int(c, v, path, "squares", 1, 4096, &m->squares) ||
        !ras_json_opt_int(c, v, path, "bumps", 1, 256, &m->bumps))
        return false;
    if (m->kind == RAS_MAP_CHECKER && m->squares > m->size)
        return ras_json_fail(c, path, "expected squares <= size (%d), got %d squares", m->size,
                             m->squares);
    const cJSON *colors = ras_json_member(v, "colors");
    if (colors) {
        ras_json_join(p, path, "colors");
        if (!cJSON_IsArray(colors) || cJSON_GetArraySize(colors) != 2)
            return ras_json_fail_type(c, p, "an array of 2 colours", colors);
        int i = 0;
        for (const cJSON *e = colors->child; e; e = e->next, i++) {
            char pi[RAS_JSON_PATH_LEN];
            ras_json_join_index(pi, p, i);
            if (!ras_json_read_color(c, e, pi, &m->colors[i])) return false;
        }
    }
    return true;
}

static bool parse_material(ras_json_ctx *c, const cJSON *v, const char *path,
                           ras_scene_material *m) {
    static const char *const keys[] = {"color", "texture", "height_map", "ka", "kd",
                                       "ks",    "p",       "kh",         "kn", "uv_scale"};
    /* "colour" is within distance 2 of "color", so the did-you-mean covers it. */
    if (!ras_json_read_object(c, v, path) ||
        !ras_json_check_keys(c, v, path, keys, COUNT(keys), NULL, NULL))
        return false;
    if (!ras_json_opt_color(c, v, path, "color", &m->color) ||
        !ras_json_opt_vec3_or_scalar(c, v, path, "ka", RAS_JSON_NONNEG, &m->ka) ||
        !ras_json_opt_vec3_or_scalar(c, v, path, "kd", RAS_JSON_NONNEG, &m->kd) ||
        !ras_json_opt_vec3_or_scalar(c, v, path, "ks", RAS_JSON_NONNEG, &m->ks) ||
        !ras_json_opt_float(c, v, path, "p", (ras_json_range){0, 10000, false, false, false},
                            &m->p) ||
        !ras_json_opt_float(c, v, path, "kh", RAS_JSON_ANY, &m->kh) ||
        !ras_json_opt_float(c, v, path, "kn", RAS_JSON_ANY, &m->kn))
        return false;
    m->kd_set = ras_json_member(v, "kd") != NULL;
    const cJSON *uv = ras_json_member(v, "uv_scale");
    if (uv) {
        char p[RAS_JSON_PATH_LEN];
        ras_json_join(p, path, "uv_scale");
        if (cJSON_IsNumber(uv)) {
            float f;
            if (!ras_json_read_float(c, uv, p, RAS_JSON_POS, &f)) return false;
            m->uv_scale = (vec2s){{f, f}};
        } else if (cJSON_IsArray(uv) && cJSON_GetArraySize(uv) == 2) {
            int i = 0;
            for (const cJSON *e = uv->child; e; e = e->next, i++) {
                char pi[RAS_JSON_PATH_LEN];
                ras_json_join_index(pi, p, i);
                if (!ras_json_read_float(c, e, pi, RAS_JSON_POS, &m->uv_scale.raw[i])) return false;
            }
        } else {
            return ras_json_fail_type(c, p, "a number or an array of 2 numbers [u, v]", uv);
        }
    }
    char p[RAS_JSON_PATH_LEN];
    const cJSON *tex = ras_json_member(v, "texture"), *height = ras_json_member(v, "height_map");
    ras_json_join(p, path, "texture");
    if (tex && !parse_map(c, tex, p, &m->texture)) return false;
    ras_json_join(p, path, "height_map");
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

static bool parse_object(ras_json_ctx *c, const cJSON *v, const char *path, ras_scene_object *o) {
    if (!ras_json_read_object(c, v, path)) return false;
    o->scale = (vec3s){{1, 1, 1}};
    material_defaults(&o->material);
    const cJSON *shape = ras_json_member(v, "shape"), *model = ras_json_member(v, "model");
    char p[RAS_JSON_PATH_LEN];
    if (shape && model)
        return ras_json_fail(c, path,
                             "expected either \"shape\" (a built-in) or \"model\" (a file), got "
                             "both");
    if (!shape && !model) {
        char list[200];
        ras_json_list_names(shape_names, RAS_SHAPE_COUNT - 1, list, sizeof list);
        return ras_json_fail(
            c, path, "missing required key \"shape\" (%s) or \"model\" (a file path)", list);
    }
    if (shape) {
        int k = 0;
        ras_json_join(p, path, "shape");
        if (cJSON_IsString(shape) && !strcmp(shape->valuestring, "model"))
            return ras_json_fail(c, p,
                                 "a model file is given as \"model\": \"path/to/file.obj\", not as "
                                 "a shape");
        if (!ras_json_read_enum(c, shape, p, shape_names, RAS_SHAPE_COUNT - 1, &k)) return false;
        o->shape = (ras_scene_shape)k;
    } else {
        o->shape = RAS_SHAPE_MODEL;
    }
    const char *keys[16] = {"name", "shape", "transform", "material"};
    int n = 4, pn;
    const char *const *params = shape_keys(o->shape, &pn);
    for (int i = 0; i < pn; i++)
        keys[n++] = params[i];
    if (!ras_json_check_keys(c, v, path, keys, n, other_shape_key, &o->shape)) return false;
    const cJSON *name = ras_json_member(v, "name");
    if (name) {
        ras_json_join(p, path, "name");
        if (!cJSON_IsString(name)) return ras_json_fail_type(c, p, "a string", name);
        if (!(o->name = ras_json_dup_str(c, name->valuestring))) return false;
    }
    if (!parse_shape_params(c, v, path, o)) return false;
    const cJSON *tr = ras_json_member(v, "transform"), *mat = ras_json_member(v, "material");
    ras_json_join(p, path, "transform");
    if (tr && !parse_transform(c, tr, p, o)) return false;
    ras_json_join(p, path, "material");
    if (mat && !parse_material(c, mat, p, &o->material)) return false;
    mat4s identity = glms_mat4_identity();
    o->model = ras_scene_model_matrix(o, (ras_scene_spin){.matrix = &identity});
    return true;
}

static bool parse_objects(ras_json_ctx *c, const cJSON *v, ras_scene *s) {
    if (!v) return ras_json_fail_missing(c, NULL, "objects", "an array of 1 or more objects");
    if (!cJSON_IsArray(v))
        return ras_json_fail_type(c, "objects", "an array of 1 or more objects", v);
    int n = cJSON_GetArraySize(v);
    if (n == 0)
        return ras_json_fail(c, "objects",
                             "expected 1 or more objects, got an empty array: there is "
                             "nothing to draw");
    if (n > RAS_SCENE_MAX_OBJECTS)
        return ras_json_fail(c, "objects", "expected at most %d objects, got %d",
                             RAS_SCENE_MAX_OBJECTS, n);
    s->objects = calloc((size_t)n, sizeof *s->objects);
    if (!s->objects) return ras_json_fail(c, NULL, "out of memory for %d objects", n);
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        char p[RAS_JSON_PATH_LEN];
        ras_json_join_index(p, "objects", i);
        s->object_count = i + 1; /* so that destroy frees what this object got */
        if (!parse_object(c, e, p, &s->objects[i])) return false;
    }
    return true;
}

static bool parse_light(ras_json_ctx *c, const cJSON *v, const char *path, ras_scene_light *l) {
    static const char *const keys[] = {"position", "intensity", "space"};
    if (!ras_json_read_object(c, v, path) ||
        !ras_json_check_keys(c, v, path, keys, COUNT(keys), NULL, NULL))
        return false;
    const cJSON *pos = ras_json_member(v, "position");
    if (!pos) return ras_json_fail_missing(c, path, "position", "an array of 3 numbers");
    char p[RAS_JSON_PATH_LEN];
    ras_json_join(p, path, "position");
    l->intensity = (vec3s){{500, 500, 500}};
    int space = 0;
    if (!ras_json_read_vec3(c, pos, p, RAS_JSON_ANY, &l->position) ||
        !ras_json_opt_vec3_or_scalar(c, v, path, "intensity", RAS_JSON_NONNEG, &l->intensity) ||
        !ras_json_opt_enum(c, v, path, "space", space_names, COUNT(space_names), &space))
        return false;
    l->in_world = space == 1;
    return true;
}

static bool parse_lights(ras_json_ctx *c, const cJSON *v, ras_scene *s) {
    if (!cJSON_IsArray(v)) return ras_json_fail_type(c, "lights", "an array of lights", v);
    int n = cJSON_GetArraySize(v);
    if (n > RAS_SCENE_MAX_LIGHTS)
        return ras_json_fail(c, "lights", "expected at most %d lights, got %d",
                             RAS_SCENE_MAX_LIGHTS, n);
    if (n == 0) return true;
    s->lights = calloc((size_t)n, sizeof *s->lights);
    if (!s->lights) return ras_json_fail(c, NULL, "out of memory");
    s->light_count = n;
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        char p[RAS_JSON_PATH_LEN];
        ras_json_join_index(p, "lights", i);
        if (!parse_light(c, e, p, &s->lights[i])) return false;
    }
    return true;
}

static bool parse_aa(ras_json_ctx *c, const cJSON *v, ras_scene *s) {
    static const char *const keys[] = {"mode", "samples", "pattern"};
    if (!ras_json_read_object(c, v, "aa") ||
        !ras_json_check_keys(c, v, "aa", keys, COUNT(keys), NULL, NULL))
        return false;
    int mode = 0, pattern = 0, samples = 4;
    if (!ras_json_opt_enum(c, v, "aa", "mode", NAMES(ras_names_aa), &mode) ||
        !ras_json_opt_enum(c, v, "aa", "pattern", NAMES(ras_names_pattern), &pattern) ||
        !ras_json_opt_int(c, v, "aa", "samples", 1, RAS_MAX_SAMPLES, &samples))
        return false;
    s->aa = (ras_aa_mode)mode;
    s->pattern_kind = (ras_pattern_kind)pattern;
    if (s->aa == RAS_AA_NONE) {
        if (ras_json_member(v, "samples") && samples != 1)
            return ras_json_fail(c, "aa.samples",
                                 "expected 1 (or no \"samples\") with mode \"none\", got %d; set "
                                 "\"mode\": \"msaa\" or \"ssaa\" to use %d samples",
                                 samples, samples);
        s->pattern = ras_sample_pattern_center();
        return true;
    }
    ras_error inner;
    if (!ras_sample_pattern_make(s->pattern_kind, samples, &s->pattern, &inner))
        return ras_json_fail(c, "aa.samples", "%s (pattern \"%s\")", inner.msg,
                             ras_name_of(&ras_names_pattern, (int)s->pattern_kind));
    return true;
}

bool ras_scene_schema_read(ras_json_ctx *c, const cJSON *root, ras_scene *s) {
    static const char *const keys[] = {
        "description", "image",  "camera", "model_rotation", "objects", "lights",      "ambient",
        "aa",          "shader", "filter", "cull",           "depth",   "clear_color", "wireframe"};
    if (!cJSON_IsObject(root))
        return ras_json_fail_type(c, "the top level", "an object {...}", root);
    if (!ras_json_check_keys(c, root, "", keys, COUNT(keys), NULL, NULL)) return false;
    const cJSON *v;
    if ((v = ras_json_member(root, "description"))) {
        if (!cJSON_IsString(v)) return ras_json_fail_type(c, "description", "a string", v);
        if (!(s->description = ras_json_dup_str(c, v->valuestring))) return false;
    }
    if ((v = ras_json_member(root, "image")) && !parse_image(c, v, s)) return false;
    if ((v = ras_json_member(root, "camera")) && !parse_camera(c, v, &s->camera)) return false;
    if ((v = ras_json_member(root, "model_rotation")) && !parse_model_rotation(c, v, s))
        return false;
    if (!parse_objects(c, ras_json_member(root, "objects"), s)) return false;
    if ((v = ras_json_member(root, "lights")) && !parse_lights(c, v, s)) return false;
    if (!ras_json_opt_vec3_or_scalar(c, root, "", "ambient", RAS_JSON_NONNEG, &s->ambient))
        return false;
    if ((v = ras_json_member(root, "aa")) && !parse_aa(c, v, s)) return false;
    int shader = 0, filter = RAS_FILTER_BILINEAR, cull = 0, depth = 0;
    if (!ras_json_opt_enum(c, root, "", "shader", NAMES(ras_names_shader), &shader) ||
        !ras_json_opt_enum(c, root, "", "filter", NAMES(ras_names_filter), &filter) ||
        !ras_json_opt_enum(c, root, "", "cull", NAMES(ras_names_cull), &cull) ||
        !ras_json_opt_enum(c, root, "", "depth", NAMES(ras_names_depth), &depth) ||
        !ras_json_opt_color(c, root, "", "clear_color", &s->clear_color))
        return false;
    s->shader = (ras_scene_shader)shader;
    s->filter = (ras_scene_filter)filter;
    s->cull = (ras_cull_mode)cull;
    s->depth = (ras_depth_format)depth;
    if ((v = ras_json_member(root, "wireframe"))) {
        if (!cJSON_IsBool(v)) return ras_json_fail_type(c, "wireframe", "true or false", v);
        s->wireframe = cJSON_IsTrue(v);
    }
    return true;
}

void ras_scene_schema_defaults(ras_scene *s) {
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
    s->pattern_kind = RAS_PATTERN_ORDERED;
    s->pattern = ras_sample_pattern_center();
    s->shader = RAS_SHADER_FLAT;
    s->filter = RAS_FILTER_BILINEAR;
    s->cull = RAS_CULL_NONE;
    s->depth = RAS_DEPTH_Z01;
}
