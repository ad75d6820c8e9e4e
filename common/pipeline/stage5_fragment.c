/* stage5_fragment.c — see stage5_fragment.h. */
#include "stage5_fragment.h"

#include "stage1_vertex.h" /* RAS_VARYING_* */

#include <math.h>   /* INFINITY */
#include <stdlib.h> /* malloc, free */

vec3s ras_shade_vertex_color(const ras_triangle *t, const ras_fragment *f, void *user) {
    (void)user;
    vec3s c = glms_vec3_scale(t->color[0], f->bary.x);
    c = glms_vec3_muladds(t->color[1], f->bary.y, c);
    return glms_vec3_muladds(t->color[2], f->bary.z, c);
}

/* Screen barycentrics are affine in (x, y): their change per pixel step is
 * constant over the triangle. λ0 = E(v1, v2, p) / area2, and so on, with
 * E(a, b, p) = (b.x − a.x)(p.y − a.y) − (b.y − a.y)(p.x − a.x). */
static void bary_gradients(const ras_triangle *t, vec3s *d_dx, vec3s *d_dy) {
    float area2 = ras_triangle_area2(t);
    float inv = area2 != 0.0f ? 1.0f / area2 : 0.0f;
    const vec4s *v = t->v;
    *d_dx = (vec3s){{-(v[2].y - v[1].y) * inv, -(v[0].y - v[2].y) * inv, -(v[1].y - v[0].y) * inv}};
    *d_dy = (vec3s){{(v[2].x - v[1].x) * inv, (v[0].x - v[2].x) * inv, (v[1].x - v[0].x) * inv}};
}

/* What the shader was handed at pixel (x, y), into the kept buffers. */
static void keep(ras_fragment_stage *s, int x, int y) {
    if (x < 0 || x >= s->width || y < 0 || y >= s->height) return;
    size_t i = (size_t)(s->height - 1 - y) * (size_t)s->width + (size_t)x;
    if (s->normal)
        for (int k = 0; k < 3; k++)
            s->normal[3 * i + k] = s->in.normal.raw[k];
    if (s->uv) {
        s->uv[3 * i] = s->in.uv.x;
        s->uv[3 * i + 1] = s->in.uv.y;
        s->uv[3 * i + 2] = 0.0f;
    }
    if (s->view_depth) s->view_depth[i] = -s->in.view_pos.z;
}

vec3s ras_fragment_stage_shade(const ras_triangle *t, const ras_fragment *f, void *user) {
    /* The varyings are written into the stage's own ras_varyings, in place:
     * those outside the mask stay 0 from frame to frame. */
    ras_fragment_stage *s = user;
    ras_varyings *in = &s->in;
    bool persp = s->perspective;
    uint64_t interpolated = 0;
    if (s->varyings & RAS_VARYING_NORMAL) {
        /* Interpolated unit normals are shorter than 1 between the vertices. */
        in->normal = glms_vec3_normalize(s->interpolate_vec3(t, f->bary, t->normal, persp));
        interpolated++;
    }
    if (s->varyings & RAS_VARYING_VIEW_POS) {
        in->view_pos = s->interpolate_vec3(t, f->bary, t->view_pos, persp);
        interpolated++;
    }
    if (s->varyings & RAS_VARYING_UV) {
        in->uv = s->interpolate_vec2(t, f->bary, t->uv, persp);
        interpolated++;
        if (s->uv_gradients) {
            /* The UV one pixel to the right and one pixel up, from the same
             * triangle's (extrapolated) barycentrics: a finite difference of
             * the perspective-correct UV, like a GPU's 2×2 quad. */
            vec3s d_dx, d_dy;
            bary_gradients(t, &d_dx, &d_dy);
            vec2s uv_x = s->interpolate_vec2(t, glms_vec3_add(f->bary, d_dx), t->uv, persp);
            vec2s uv_y = s->interpolate_vec2(t, glms_vec3_add(f->bary, d_dy), t->uv, persp);
            in->duv_dx = glms_vec2_sub(uv_x, in->uv);
            in->duv_dy = glms_vec2_sub(uv_y, in->uv);
        }
    }
    if (s->counters) s->counters->varyings_interpolated += interpolated;
    if (s->keeping) keep(s, f->x, f->y);
    return s->shader(in, s->shader_user);
}

/* The kept buffers, in the order of their arrays below: the varying each
 * keeps, and its floats per pixel. */
static const unsigned kept_varying[3] = {RAS_VARYING_NORMAL, RAS_VARYING_UV, RAS_VARYING_VIEW_POS};
static const size_t kept_channels[3] = {3, 3, 1};

void ras_fragment_stage_clear(ras_fragment_stage *s) {
    size_t n = (size_t)s->width * (size_t)s->height;
    float *arrays[3] = {s->normal, s->uv, s->view_depth};
    for (int k = 0; k < 3; k++)
        for (size_t i = 0; arrays[k] && i < n * kept_channels[k]; i++)
            arrays[k][i] = INFINITY;
}

bool ras_fragment_stage_keep(ras_fragment_stage *s, int width, int height) {
    ras_fragment_stage_release(s);
    size_t n = (size_t)width * (size_t)height;
    float **arrays[3] = {&s->normal, &s->uv, &s->view_depth};
    for (int k = 0; k < 3; k++) {
        if (!(s->varyings & kept_varying[k])) continue;
        if (!(*arrays[k] = malloc(n * kept_channels[k] * sizeof(float)))) {
            ras_fragment_stage_release(s);
            return false;
        }
    }
    s->width = width, s->height = height;
    s->keeping = s->normal || s->uv || s->view_depth;
    ras_fragment_stage_clear(s);
    return true;
}

void ras_fragment_stage_release(ras_fragment_stage *s) {
    free(s->normal);
    free(s->uv);
    free(s->view_depth);
    s->normal = s->uv = s->view_depth = NULL;
    s->keeping = false;
}
