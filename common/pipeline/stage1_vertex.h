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
    /* The position the clipper decides with, when `exact`: the vertex
     * transform's product in double (ras_clip_set_position), a cut corner's
     * before its rounding (stage 2). A float clip coordinate cannot hold a
     * plane that passes 1e-9 from the eye (issue #42, B2). Not exact (a
     * vertex made by hand): the clipper widens p_clip. */
    double p_exact[4];
    bool exact;
    vec3s color;
    vec3s normal; /* view space */
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

/* Whether a float computation of a clip position (chain) lies within 8
 * ulps, relative to its largest coordinate, of the same in double
 * (product). False when either is not finite. */
bool ras_float_chain_accurate(const float chain[4], const double product[4]);

/* Sets v's position: p_exact the product in double, p_clip the float chain
 * (ras_mat4_mulv of the float matrices' product) where that is accurate
 * (ras_float_chain_accurate; it drew the reference pictures), else the
 * product rounded once (the chain cancelled: a vertex near an eye far from
 * the origin). */
void ras_clip_set_position(ras_clip_vertex *v, vec4s float_chain, const double product[4]);

/* Transforms every vertex of the mesh. `out` has mesh->vertex_count entries.
 * The position is also multiplied out in double (model, view and projection
 * from the float matrices, then the vertex: p_exact), which replaces the
 * float chain in p_clip where that chain cancelled (ras_clip_set_position). */
void ras_vertex_transform(const ras_mesh *mesh, mat4s model, mat4s view, mat4s projection,
                          unsigned varyings, ras_clip_vertex *out);

#endif
