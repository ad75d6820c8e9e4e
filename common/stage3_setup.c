/* stage3_setup.c — see stage3_setup.h. */
#include "stage3_setup.h"

vec4s ras_viewport(vec4s p_clip, int width, int height) {
    float inv_w = 1.0f / p_clip.w;
    /* Clamped to [0, 1] like D3D's viewport depth: a vertex the clipper cut
     * where w is tiny can land a little outside -w <= z <= w (its z and w
     * round separately; tests/fuzz found depth -8.8e-5). NaN passes through
     * (fmaxf/fminf would hide it), so setup still rejects it. */
    float depth = (1.0f - p_clip.z * inv_w) * 0.5f;
    if (depth < 0.0f) depth = 0.0f;
    if (depth > 1.0f) depth = 1.0f;
    return (vec4s){{(p_clip.x * inv_w + 1.0f) * 0.5f * (float)width,
                    (p_clip.y * inv_w + 1.0f) * 0.5f * (float)height, depth, p_clip.w}};
}

bool ras_setup_triangle(const ras_clip_vertex *a, const ras_clip_vertex *b,
                        const ras_clip_vertex *c, int width, int height, ras_triangle *out) {
    const ras_clip_vertex *in[3] = {a, b, c};
    for (int i = 0; i < 3; i++) {
        out->v[i] = ras_viewport(in[i]->p_clip, width, height);
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
