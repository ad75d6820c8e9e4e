/* ras_scene_assets.c — a scene's meshes and textures (ras_scene.h:
 * ras_scene_load_assets, ras_scene_assets_destroy).
 *
 * Notes:
 *   - The second step of loading a scene: the scene itself is plain data
 *     checked without opening any other file; here the built-in shapes are
 *     built and the model and image files loaded, so errors name the object
 *     and the file.
 *   - Memory: a few bytes of JSON can ask for millions of triangles or a
 *     4096² texture, so each built-in shape and texture is estimated and
 *     checked against the memory budget (ras_memory.h) before it is built,
 *     and a loaded file once its size is known.
 *   - Objects that describe the same map share one texture (same_map).
 *
 * Dependencies: ras_mesh (assimp for model files), ras_texture, ras_memory.
 */
#include "ras_scene.h"

#include "ras_memory.h" /* ras_memory_check, ras_memory_commit, ras_memory_release */

#include <math.h>   /* cosf, sinf */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* calloc, free */
#include <string.h> /* strcmp, memcmp */

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
        /* built-ins are floats; their mips are counted when built */
        double bytes = ras_texture_level0_bytes(RAS_TEXELS_FLOAT, m->size, m->size);
        if (!budget_add(s, a, i, what, bytes, err)) return NULL;
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
        /* a file is held as its bytes (ras_texture_load checked its decode) */
        double bytes = ras_texture_level0_bytes(t->format, t->width, t->height);
        if (!budget_add(s, a, i, what, bytes, err)) return NULL;
    }
    return t;
}

bool ras_scene_assets_check_mips(const ras_scene *s, const ras_scene_assets *a, ras_error *err) {
    double bytes = 0;
    int textures = 0;
    for (int k = 0; k < a->owned_texture_count; k++) {
        const ras_texture *t = a->owned_textures[k];
        bool colour_map = false; /* height maps get no mips */
        for (int i = 0; i < s->object_count && !colour_map; i++)
            colour_map = a->textures[i] == t;
        if (!colour_map || t->level_count > 1) continue;
        bytes += ras_texture_mip_bytes(t->width, t->height);
        textures++;
    }
    char what[512];
    snprintf(what, sizeof what, "%s: building the mip levels of %d texture%s for trilinear filtering", s->path,
             textures, textures == 1 ? "" : "s");
    return ras_memory_check(bytes, what, "use smaller textures or another --filter", err);
}

bool ras_scene_assets_build_mips(const ras_scene *s, ras_scene_assets *a, int i,
                                 uint64_t *levels_built, ras_error *err) {
    ras_texture *t = a->textures[i];
    if (!t || t->level_count > 1) return true; /* none, or built (maps are shared) */
    char what[96];
    snprintf(what, sizeof what, "the mip levels of a %dx%d texture", t->width, t->height);
    if (!budget_add(s, a, i, what, ras_texture_mip_bytes(t->width, t->height), err)) return false;
    if (!ras_texture_build_mips(t))
        return ras_error_set(err, "%s: objects[%d]: out of memory building %s", s->path, i, what);
    *levels_built += (uint64_t)(t->level_count - 1);
    return true;
}

static ras_scene_assets *load_assets(const ras_scene *s, bool maps, ras_error *err) {
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
            snprintf(what, sizeof what, "a %s of %.0f triangles", ras_scene_shape_name(o->shape),
                     nt);
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
                              ras_scene_shape_name(o->shape));
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
                mesh->positions[v] = ras_mat4_mulv3(fit, mesh->positions[v], 1.0f);
        }
        const ras_scene_material *mat = &o->material;
        for (size_t v = 0; v < mesh->vertex_count; v++) {
            mesh->colors[v] = glms_vec3_mul(mesh->colors[v], mat->color);
            mesh->uvs[v] = glms_vec2_mul(mesh->uvs[v], mat->uv_scale);
        }
        if (!maps) continue;
        if ((mat->texture.kind != RAS_MAP_NONE && !(a->textures[i] = get_map(s, a, i, 0, err))) ||
            (mat->height_map.kind != RAS_MAP_NONE &&
             !(a->height_maps[i] = get_map(s, a, i, 1, err)))) {
            ras_scene_assets_destroy(a);
            return NULL;
        }
    }
    return a;
}

/* The scene's models as one batch: each file imported once, all of them
 * within one time limit (ras_mesh.h). */
static ras_scene_assets *load_assets_batch(const ras_scene *s, bool maps, ras_error *err) {
    ras_mesh_imports_begin();
    ras_scene_assets *a = load_assets(s, maps, err);
    ras_mesh_imports_end();
    return a;
}

ras_scene_assets *ras_scene_load_assets(const ras_scene *s, ras_error *err) {
    return load_assets_batch(s, true, err);
}

ras_scene_assets *ras_scene_load_meshes(const ras_scene *s, ras_error *err) {
    return load_assets_batch(s, false, err);
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
