/* stage1_vertex.c — see stage1_vertex.h. */
#include "stage1_vertex.h"

#include <math.h> /* fabs, fmax */

mat4s ras_projection_normalize_w(mat4s projection) {
    vec4s ahead = ras_mat4_mulv(projection, (vec4s){{0, 0, -1, 1}});
    return ahead.w < 0 ? glms_mat4_scale(projection, -1.0f) : projection;
}

mat4s ras_view_matrix_eye(vec3s eye) {
    return ras_mat4_rows(1, 0, 0, -eye.x, 0, 1, 0, -eye.y, 0, 0, 1, -eye.z, 0, 0, 0, 1);
}

/* A 4x4 matrix in double, stored as cglm stores mat4s: m[column][row]. */
typedef struct dmat4 {
    double m[4][4];
} dmat4;

static dmat4 dmat4_of(mat4s a) {
    dmat4 d;
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            d.m[c][r] = a.raw[c][r];
    return d;
}

static dmat4 dmat4_mul(const dmat4 *a, const dmat4 *b) {
    dmat4 d;
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            d.m[c][r] = a->m[0][r] * b->m[c][0] + a->m[1][r] * b->m[c][1] +
                        a->m[2][r] * b->m[c][2] + a->m[3][r] * b->m[c][3];
    return d;
}

/* The products of floats in double: model · view · projection with each
 * product of two float entries exact and only the sums rounded (at 2^-53),
 * where the float chain rounds every product and sum at 2^-24 and loses a
 * translation of 1e6 against an eye at 1e6 to 0.06. */
static dmat4 mvp_exact(mat4s model, mat4s view, mat4s projection) {
    dmat4 m = dmat4_of(model), v = dmat4_of(view),
          p = dmat4_of(ras_projection_normalize_w(projection));
    dmat4 mv = dmat4_mul(&v, &m);
    return dmat4_mul(&p, &mv);
}

static void position_exact(const dmat4 *mvp, vec3s p, double out[4]) {
    for (int r = 0; r < 4; r++)
        out[r] = mvp->m[0][r] * p.x + mvp->m[1][r] * p.y + mvp->m[2][r] * p.z + mvp->m[3][r];
}

/* How far the float chain may stray from the double product, relative to
 * its largest coordinate, and still be kept: 8 ulps. A float product of
 * three matrices and a vertex strays a few ulps; one that cancels (a
 * corner 1e-4 from an eye 10 from the origin) strays by 1e-6, a hundredth
 * of its size, and an edge-on triangle's plane moves by that much. */
#define FLOAT_CHAIN_TOLERANCE 0x1p-21

bool ras_float_chain_accurate(const float chain[4], const double product[4]) {
    double scale = 0, err = 0;
    for (int j = 0; j < 4; j++) {
        scale = fmax(scale, fabs(product[j]));
        err = fmax(err, fabs((double)chain[j] - product[j]));
    }
    return err <= FLOAT_CHAIN_TOLERANCE * scale; /* NaN: false */
}

void ras_clip_set_position(ras_clip_vertex *v, vec4s float_chain, const double product[4]) {
    v->exact = true;
    for (int j = 0; j < 4; j++)
        v->p_exact[j] = product[j];
    /* The float chain is kept where it is accurate: it drew the reference
     * pictures, and moving every vertex by its last bit moves their
     * perspective-correct shading by 1/255 in a few pixels. Not where it
     * cancelled, nor when it is not finite. */
    if (ras_float_chain_accurate(float_chain.raw, product)) {
        v->p_clip = float_chain;
        return;
    }
    for (int j = 0; j < 4; j++)
        v->p_clip.raw[j] = (float)product[j];
}

void ras_vertex_transform(const ras_mesh *mesh, mat4s model, mat4s view, mat4s projection,
                          unsigned varyings, ras_clip_vertex *out) {
    mat4s model_view = ras_mat4_mul(view, model);
    mat4s mvp = ras_mat4_mul(ras_projection_normalize_w(projection), model_view);
    dmat4 mvp_d = mvp_exact(model, view, projection);
    /* Normals transform by the inverse transpose, or non-uniform scales bend them. */
    mat3s normal_matrix = glms_mat3_transpose(glms_mat3_inv(glms_mat4_pick3(model_view)));
    for (size_t i = 0; i < mesh->vertex_count; i++) {
        vec4s p = glms_vec4(mesh->positions[i], 1.0f);
        ras_clip_vertex *o = &out[i];
        double product[4];
        position_exact(&mvp_d, mesh->positions[i], product);
        ras_clip_set_position(o, ras_mat4_mulv(mvp, p), product);
        o->color =
            (varyings & RAS_VARYING_COLOR) && mesh->colors ? mesh->colors[i] : (vec3s){{1, 1, 1}};
        o->normal = (varyings & RAS_VARYING_NORMAL) && mesh->normals
                        ? glms_vec3_normalize(glms_mat3_mulv(normal_matrix, mesh->normals[i]))
                        : (vec3s){{0, 0, 1}};
        o->uv = (varyings & RAS_VARYING_UV) && mesh->uvs ? mesh->uvs[i] : (vec2s){{0, 0}};
        o->view_pos = (varyings & RAS_VARYING_VIEW_POS) ? glms_vec3(ras_mat4_mulv(model_view, p))
                                                        : (vec3s){{0, 0, 0}};
    }
}
