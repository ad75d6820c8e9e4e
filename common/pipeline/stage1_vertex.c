/* stage1_vertex.c — see stage1_vertex.h. */
#include "stage1_vertex.h"

mat4s ras_projection_normalize_w(mat4s projection) {
    vec4s ahead = ras_mat4_mulv(projection, (vec4s){{0, 0, -1, 1}});
    return ahead.w < 0 ? glms_mat4_scale(projection, -1.0f) : projection;
}

mat4s ras_view_matrix_eye(vec3s eye) {
    return ras_mat4_rows(1, 0, 0, -eye.x, 0, 1, 0, -eye.y, 0, 0, 1, -eye.z, 0, 0, 0, 1);
}

void ras_vertex_transform(const ras_mesh *mesh, mat4s model, mat4s view, mat4s projection,
                          unsigned varyings, ras_clip_vertex *out) {
    mat4s model_view = ras_mat4_mul(view, model);
    mat4s mvp = ras_mat4_mul(ras_projection_normalize_w(projection), model_view);
    /* Normals transform by the inverse transpose, or non-uniform scales bend them. */
    mat3s normal_matrix = glms_mat3_transpose(glms_mat3_inv(glms_mat4_pick3(model_view)));
    for (size_t i = 0; i < mesh->vertex_count; i++) {
        vec4s p = glms_vec4(mesh->positions[i], 1.0f);
        ras_clip_vertex *o = &out[i];
        o->p_clip = ras_mat4_mulv(mvp, p);
        o->color = (varyings & RAS_VARYING_COLOR) && mesh->colors ? mesh->colors[i]
                                                                  : (vec3s){{1, 1, 1}};
        o->normal = (varyings & RAS_VARYING_NORMAL) && mesh->normals
                        ? glms_vec3_normalize(glms_mat3_mulv(normal_matrix, mesh->normals[i]))
                        : (vec3s){{0, 0, 1}};
        o->uv = (varyings & RAS_VARYING_UV) && mesh->uvs ? mesh->uvs[i] : (vec2s){{0, 0}};
        o->view_pos = (varyings & RAS_VARYING_VIEW_POS)
                          ? glms_vec3(ras_mat4_mulv(model_view, p))
                          : (vec3s){{0, 0, 0}};
    }
}
