/* stage3_setup.c — see stage3_setup.h. */
#include "stage3_setup.h"

#include "ras_names.h"

const char *ras_depth_format_name(ras_depth_format format) {
    return ras_name_of(&ras_names_depth, (int)format);
}

vec4s ras_viewport_depth(vec4s p_clip, int width, int height, ras_depth_format format,
                         float z_near) {
    float inv_w = 1.0f / p_clip.w;
    float depth;
    if (format == RAS_DEPTH_INV_W) {
        /* One correctly rounded division straight from w (not z_near * inv_w,
         * which would round twice). Clamped to [−1, 0] for the same reason as
         * below: a vertex the clipper cut at the near plane can land a
         * rounding error nearer than z_near. */
        depth = -z_near / p_clip.w;
        if (depth < -1.0f) depth = -1.0f;
        if (depth > 0.0f) depth = 0.0f;
    } else {
        /* Clamped to [0, 1] like D3D's viewport depth: a vertex the clipper cut
         * where w is tiny can land a little outside -w <= z <= w (its z and w
         * round separately; tests/fuzz found depth -8.8e-5). */
        depth = (1.0f - p_clip.z * inv_w) * 0.5f;
        if (depth < 0.0f) depth = 0.0f;
        if (depth > 1.0f) depth = 1.0f;
    }
    /* NaN passes through both clamps (fmaxf/fminf would hide it), so setup
     * still rejects it. */
    return (vec4s){{(p_clip.x * inv_w + 1.0f) * 0.5f * (float)width,
                    (p_clip.y * inv_w + 1.0f) * 0.5f * (float)height, depth, p_clip.w}};
}

vec4s ras_viewport(vec4s p_clip, int width, int height) {
    return ras_viewport_depth(p_clip, width, height, RAS_DEPTH_Z01, 0.0f);
}

bool ras_setup_triangle_depth(const ras_clip_vertex *a, const ras_clip_vertex *b,
                              const ras_clip_vertex *c, int width, int height,
                              ras_depth_format format, float z_near, ras_triangle *out) {
    const ras_clip_vertex *in[3] = {a, b, c};
    for (int i = 0; i < 3; i++) {
        out->v[i] = ras_viewport_depth(in[i]->p_clip, width, height, format, z_near);
        out->color[i] = in[i]->color;
        out->normal[i] = in[i]->normal;
        out->uv[i] = in[i]->uv;
        out->view_pos[i] = in[i]->view_pos;
        if (!ras_vec4_finite(out->v[i]) || !ras_vec3_finite(out->color[i]) ||
            !ras_vec3_finite(out->normal[i]) || !ras_vec2_finite(out->uv[i]) ||
            !ras_vec3_finite(out->view_pos[i]))
            return false;
    }
    return true;
}

bool ras_setup_triangle(const ras_clip_vertex *a, const ras_clip_vertex *b,
                        const ras_clip_vertex *c, int width, int height, ras_triangle *out) {
    return ras_setup_triangle_depth(a, b, c, width, height, RAS_DEPTH_Z01, 0.0f, out);
}
