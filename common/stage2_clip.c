/* stage2_clip.c — see stage2_clip.h. */
#include "stage2_clip.h"

#include <string.h> /* memcpy */

#define PLANE_COUNT 7

/* Signed distance to plane k: >= 0 is inside. */
static inline float plane_distance(int k, vec4s p) {
    switch (k) {
    case 0: return p.w - RAS_CLIP_W_EPSILON;
    case 1: return p.w - p.z; /* z <= w */
    case 2: return p.w + p.z; /* z >= -w */
    case 3: return RAS_CLIP_GUARD * p.w - p.x;
    case 4: return RAS_CLIP_GUARD * p.w + p.x;
    case 5: return RAS_CLIP_GUARD * p.w - p.y;
    default: return RAS_CLIP_GUARD * p.w + p.y;
    }
}

static ras_clip_vertex lerp_vertex(const ras_clip_vertex *a, const ras_clip_vertex *b, float t) {
    ras_clip_vertex o;
    o.p_clip = glms_vec4_lerp(a->p_clip, b->p_clip, t);
    o.color = glms_vec3_lerp(a->color, b->color, t);
    o.normal = glms_vec3_lerp(a->normal, b->normal, t);
    o.uv = glms_vec2_lerp(a->uv, b->uv, t);
    o.view_pos = glms_vec3_lerp(a->view_pos, b->view_pos, t);
    return o;
}

unsigned ras_clip_outcode(vec4s p_clip) {
    unsigned mask = 0;
    for (int k = 0; k < PLANE_COUNT; k++)
        if (!(plane_distance(k, p_clip) >= 0)) mask |= 1u << k;
    return mask;
}

ras_clip_result ras_clip_triangle(const ras_clip_vertex *a, const ras_clip_vertex *b,
                                  const ras_clip_vertex *c,
                                  ras_clip_vertex out[RAS_CLIP_MAX_VERTICES], int *count) {
    const ras_clip_vertex *tri[3] = {a, b, c};
    unsigned outside_all = (1u << PLANE_COUNT) - 1, outside_any = 0;
    for (int i = 0; i < 3; i++) {
        unsigned mask = ras_clip_outcode(tri[i]->p_clip);
        outside_all &= mask;
        outside_any |= mask;
    }
    if (outside_all) { /* every corner outside one plane: trivially rejected */
        *count = 0;
        return RAS_CLIP_OUTSIDE;
    }
    out[0] = *a;
    out[1] = *b;
    out[2] = *c;
    *count = 3;
    if (!outside_any) return RAS_CLIP_INSIDE;

    ras_clip_vertex tmp[RAS_CLIP_MAX_VERTICES];
    int n = 3;
    for (int k = 0; k < PLANE_COUNT && n > 0; k++) {
        if (!(outside_any & (1u << k))) continue;
        int m = 0;
        for (int i = 0; i < n; i++) {
            const ras_clip_vertex *p = &out[i], *q = &out[(i + 1) % n];
            float dp = plane_distance(k, p->p_clip), dq = plane_distance(k, q->p_clip);
            if (dp >= 0) tmp[m++] = *p;
            /* Exactly one of the two inside: the edge crosses the plane. t is
             * in [0, 1] and the denominator cannot be 0 because the signs differ.
             * Always interpolate from the inside corner to the outside one: a
             * neighbour sharing this edge walks it the other way, and only a
             * direction-independent formula gives it the same cut point bit for
             * bit — otherwise the shared edge moves and the mesh cracks on
             * screen (tests/unit/test_hardcases.c, test_watertight_clipped_fan). */
            if ((dp >= 0) != (dq >= 0))
                tmp[m++] = dp >= 0 ? lerp_vertex(p, q, dp / (dp - dq))
                                   : lerp_vertex(q, p, dq / (dq - dp));
        }
        n = m;
        memcpy(out, tmp, (size_t)n * sizeof *out);
    }
    *count = n >= 3 ? n : 0;
    return *count ? RAS_CLIP_SPLIT : RAS_CLIP_OUTSIDE;
}
