/* ras_mesh.c — the mesh itself: allocation, the normal repair every mesh
 * gets, bounds and fitting. Where meshes come from is in the other
 * ras_mesh_*.c files (ras_mesh_parts.h says which holds what):
 *   ras_mesh_shapes.c  the built-in shapes and the Utah teapot;
 *   ras_mesh_load.c    model files through assimp (opened on first use);
 *   ras_mesh_check.c   what a model file is checked for before assimp sees it.
 *
 * Normals are generated here rather than by assimp so that
 * has_normals_from_file is exact and a bad normal in a file (zero, NaN) gets
 * the same repair as a missing one.
 */
#include "ras_mesh.h"

#include <assert.h> /* assert */
#include <limits.h> /* UINT_MAX */
#include <math.h>   /* sqrtf, isfinite */
#include <stdint.h> /* SIZE_MAX */
#include <stdlib.h> /* calloc, free */

#include "ras_mesh_parts.h"

/* ------------------------------------------------------------------------ */
/* Allocation                                                                */

/* calloc that treats n * size overflow as failure and never asks for 0 bytes
 * (calloc(0) may return NULL, which would look like OOM). */
void *ras_mesh_calloc(size_t n, size_t size) {
    if (n == 0) n = 1;
    if (n > SIZE_MAX / size) return NULL;
    return calloc(n, size);
}

ras_mesh *ras_mesh_create(size_t vertex_count, size_t triangle_count) {
    /* Indices are unsigned, so every vertex must be addressable by one. */
    if (vertex_count > (size_t)UINT_MAX) return NULL;
    if (triangle_count > SIZE_MAX / 3) return NULL;
    ras_mesh *mesh = calloc(1, sizeof *mesh);
    if (!mesh) return NULL;
    mesh->vertex_count = vertex_count;
    mesh->triangle_count = triangle_count;
    mesh->positions = ras_mesh_calloc(vertex_count, sizeof *mesh->positions);
    mesh->normals = ras_mesh_calloc(vertex_count, sizeof *mesh->normals);
    mesh->uvs = ras_mesh_calloc(vertex_count, sizeof *mesh->uvs);
    mesh->colors = ras_mesh_calloc(vertex_count, sizeof *mesh->colors);
    mesh->indices = ras_mesh_calloc(3 * triangle_count, sizeof *mesh->indices);
    if (!mesh->positions || !mesh->normals || !mesh->uvs || !mesh->colors || !mesh->indices) {
        ras_mesh_destroy(mesh);
        return NULL;
    }
    return mesh;
}

void ras_mesh_destroy(ras_mesh *mesh) {
    if (!mesh) return;
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->uvs);
    free(mesh->colors);
    free(mesh->indices);
    free(mesh);
}


/* ------------------------------------------------------------------------ */
/* Small vector helpers (by value, like cglm's struct API)                   */

/* Unit vector, or `fallback` when v is zero, tiny or not finite: normalising
 * such a vector would give NaN or a direction made of rounding noise. */
vec3s ras_mesh_unit_or(vec3s v, vec3s fallback) {
    float len2 = glms_vec3_dot(v, v);
    if (!(len2 > 1e-30f) || !isfinite(len2)) return fallback;
    return glms_vec3_scale(v, 1.0f / sqrtf(len2));
}

bool ras_mesh_normal_ok(vec3s n) {
    float len2 = glms_vec3_dot(n, n);
    return isfinite(len2) && len2 > 1e-30f;
}

void ras_mesh_fill_color(ras_mesh *mesh, vec3s color) {
    for (size_t i = 0; i < mesh->vertex_count; i++) mesh->colors[i] = color;
}

/* Replaces every normal flagged in `repair` (or every normal, when repair is
 * NULL) by the normalised area-weighted sum of the face normals around it. */
void ras_mesh_smooth_normals(ras_mesh *mesh, const bool *repair) {
    for (size_t v = 0; v < mesh->vertex_count; v++)
        if (!repair || repair[v]) mesh->normals[v] = glms_vec3_zero();
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const unsigned *tri = &mesh->indices[3 * t];
        vec3s n = face_normal_raw(mesh->positions[tri[0]], mesh->positions[tri[1]],
                                           mesh->positions[tri[2]]);
        if (!ras_vec3_finite(n)) continue;
        for (int k = 0; k < 3; k++)
            if (!repair || repair[tri[k]])
                mesh->normals[tri[k]] = glms_vec3_add(mesh->normals[tri[k]], n);
    }
    /* A vertex used by no triangle, or only by zero-area ones, has no face
     * to take a normal from; +y keeps the contract (unit length, finite). */
    for (size_t v = 0; v < mesh->vertex_count; v++)
        if (!repair || repair[v])
            mesh->normals[v] = ras_mesh_unit_or(mesh->normals[v], v3(0, 1, 0));
}


/* ------------------------------------------------------------------------ */
/* Bounds and fitting                                                        */

void ras_mesh_bounds(const ras_mesh *mesh, vec3s *lo, vec3s *hi) {
    assert(mesh && lo && hi);
    if (mesh->vertex_count == 0) {
        *lo = *hi = glms_vec3_zero();
        return;
    }
    vec3s a = mesh->positions[0], b = mesh->positions[0];
    for (size_t i = 1; i < mesh->vertex_count; i++) {
        a = glms_vec3_minv(a, mesh->positions[i]);
        b = glms_vec3_maxv(b, mesh->positions[i]);
    }
    *lo = a;
    *hi = b;
}

mat4s ras_mesh_fit_matrix(const ras_mesh *mesh, float size) {
    vec3s lo, hi;
    ras_mesh_bounds(mesh, &lo, &hi);
    vec3s centre = glms_vec3_scale(glms_vec3_add(lo, hi), 0.5f);
    vec3s extent = glms_vec3_sub(hi, lo);
    float largest = glms_vec3_max(extent);
    /* A single point (or a mesh with a non-finite bound) has no size to
     * scale: only move it. */
    float k = (largest > 0.0f && isfinite(largest)) ? size / largest : 1.0f;
    return ras_mat4_rows(k, 0, 0, -k * centre.x,
                         0, k, 0, -k * centre.y,
                         0, 0, k, -k * centre.z,
                         0, 0, 0, 1);
}
