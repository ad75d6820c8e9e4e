/* ras_mesh_parts.h — what the ras_mesh*.c files share, and nothing else
 * includes: ras_mesh.h is the module's public face. The files:
 *   ras_mesh.c         allocation, normal repair, bounds and fitting;
 *   ras_mesh_shapes.c  the built-in shapes and the Utah teapot;
 *   ras_mesh_load.c    model files through assimp;
 *   ras_mesh_check.c   the checks a model file passes before assimp sees it.
 */
#ifndef RAS_MESH_PARTS_H
#define RAS_MESH_PARTS_H

#include "ras_mesh.h"

static inline vec3s v3(float x, float y, float z) { return (vec3s){{x, y, z}}; }

static inline vec3s face_normal_raw(vec3s a, vec3s b, vec3s c) {
    /* Unnormalised: its length is twice the area, which weights the average
     * of face normals at a vertex by area. */
    return glms_vec3_cross(glms_vec3_sub(b, a), glms_vec3_sub(c, a));
}

/* calloc that treats n * size overflow as failure and never asks for 0 bytes. */
void *ras_mesh_calloc(size_t n, size_t size);

/* Unit vector, or `fallback` when v is zero, tiny or not finite. */
vec3s ras_mesh_unit_or(vec3s v, vec3s fallback);
/* Finite and not (nearly) zero: a normal that needs no repair. */
bool ras_mesh_normal_ok(vec3s n);
void ras_mesh_fill_color(ras_mesh *mesh, vec3s color);
/* Every normal flagged in `repair` (all of them when NULL) becomes the
 * normalised area-weighted sum of the face normals around it. */
void ras_mesh_smooth_normals(ras_mesh *mesh, const bool *repair);

/* The file's extension, lower-cased, in `ext` ("" when none). */
void ras_mesh_file_extension(const char *path, char *ext, size_t size);
/* The checks of ras_mesh_check.c: true when the file may go to assimp, else
 * false with err saying why. ras_mesh_check_content also tells glTF by content:
 * *suffix is ".glb" or ".gltf" then, else "". */
bool ras_mesh_check_content(const char *path, const char **suffix, ras_error *err);
bool ras_mesh_check_declared_counts(const char *path, double file_bytes, ras_error *err);
bool ras_mesh_check_ply_lists(const char *path, ras_error *err);
/* A PLY's header complete and made of known lines (true for any other file). */
bool ras_mesh_check_ply_header(const char *path, ras_error *err);
/* An OBJ (by name or content; true for any other file): its vt/vn indices,
 * its 'o'/'usemtl' counts, its mtllib files inside the model's folder.
 * *side_bytes is the estimated import cost of those material files. */
bool ras_mesh_check_obj(const char *path, double *side_bytes, ras_error *err);

#endif
