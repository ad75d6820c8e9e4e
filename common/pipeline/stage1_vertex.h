/* stage1_vertex.h — stage 1: object space → clip space (model · view · projection).
 *
 * Produces one ras_clip_vertex per mesh vertex. Only the varyings the later
 * stages read are computed (the `varyings` mask): an unlit, untextured scene
 * transforms no normals and copies no UVs.
 */
#ifndef RAS_STAGE1_VERTEX_H
#define RAS_STAGE1_VERTEX_H

#include "ras_mesh.h"

enum {
    RAS_VARYING_COLOR = 1u << 0,
    RAS_VARYING_NORMAL = 1u << 1,
    RAS_VARYING_UV = 1u << 2,
    RAS_VARYING_VIEW_POS = 1u << 3,
};

typedef struct ras_clip_vertex {
    vec4s p_clip;
    vec3s color;
    vec3s normal;   /* view space */
    vec2s uv;
    vec3s view_pos; /* view space */
} ras_clip_vertex;

/* The GAMES101 lecture matrix (n = -zNear) gives w = z_view, which is
 * NEGATIVE in front of the camera; the same matrix times -1 is the same
 * projective map (x/w, y/w, z/w are unchanged) with w > 0 in front. Clipping
 * in homogeneous space needs w > 0 for visible points, so the pipeline flips
 * the sign once here when a point straight ahead of the camera gets w < 0.
 * Either sign a student writes therefore draws the same picture. */
mat4s ras_projection_normalize_w(mat4s projection);

/* View matrix of the GAMES101 framework: a translation by -eye (camera looks
 * down -z, y up). */
mat4s ras_view_matrix_eye(vec3s eye);

/* Transforms every vertex of the mesh. `out` has mesh->vertex_count entries. */
void ras_vertex_transform(const ras_mesh *mesh, mat4s model, mat4s view, mat4s projection,
                          unsigned varyings, ras_clip_vertex *out);

#endif
