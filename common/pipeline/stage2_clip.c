/* stage2_clip.c — see stage2_clip.h. */
#include "stage2_clip.h"

#include <string.h> /* memcpy */

#define PLANE_COUNT 7

/* Signed distance to plane k: >= 0 is inside. In float its sign is exact
 * (a rounded sum or difference of two floats is 0 only when they are equal,
 * and G = 8 scales exactly), which is all a plane test needs. */
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

/* The same in double, on the exact position (stage1_vertex.h), which is
 * what a vertex is inside or outside of: the distance of a far corner
 * (w ~ 1e6) is then not rounded to float's 0.06 before it decides where a
 * near-plane cut at w ~ 0.01 lands, and a plane 1e-9 from the eye is where
 * it is. Plane 2 with a far distance (z_far > 0) is w <= z_far, the far
 * test on the view depth itself: z >= -w says the same for the exact
 * projection, but the float matrix's z row rounds (f + n) / (f - n) to
 * 1 + 2^-23 at near / far = 1e-7, which moves its far plane by half its
 * distance (issue #42, B1). */
static inline double plane_distance_d(int k, const double p[4], double z_far) {
    double gw = (double)RAS_CLIP_GUARD * p[3];
    switch (k) {
    case 0: return p[3] - (double)RAS_CLIP_W_EPSILON;
    case 1: return p[3] - p[2];
    case 2: return z_far > 0 ? z_far - p[3] : p[3] + p[2];
    case 3: return gw - p[0];
    case 4: return gw + p[0];
    case 5: return gw - p[1];
    default: return gw + p[1];
    }
}

/* The vertex's exact position, from p_clip when it was made by hand. */
static void make_exact(ras_clip_vertex *v) {
    if (v->exact) return;
    v->p_exact[0] = v->p_clip.x, v->p_exact[1] = v->p_clip.y;
    v->p_exact[2] = v->p_clip.z, v->p_exact[3] = v->p_clip.w;
    v->exact = true;
}

static inline bool inside_d(int k, const ras_clip_vertex *v, double z_far) {
    return plane_distance_d(k, v->p_exact, z_far) >= 0;
}

/* t and the point at t on the edge a → b where it crosses plane k (a
 * inside, b outside), in double; false when the distances do not straddle
 * the plane (only the float chain's can fail to). */
static bool cut_at(int k, const double a[4], const double b[4], double z_far, double *t,
                   double d[4]) {
    double da = plane_distance_d(k, a, z_far), db = plane_distance_d(k, b, z_far);
    if (!(da >= 0 && db < 0)) return false;
    *t = da / (da - db); /* in [0, 1) */
    for (int j = 0; j < 4; j++) d[j] = a[j] + *t * (b[j] - a[j]);
    return true;
}

/* d put exactly on plane k: the coordinate the plane constrains set from
 * the others (w = ε or z_far, z = ±w, x or y = ±G·w). */
static void onto_plane_d(int k, double d[4], double z_far) {
    double G = RAS_CLIP_GUARD;
    switch (k) {
    case 0: d[3] = RAS_CLIP_W_EPSILON; break;
    case 1: d[2] = d[3]; break;
    case 2:
        if (z_far > 0) d[3] = z_far;
        else d[2] = -d[3];
        break;
    case 3: d[0] = G * d[3]; break;
    case 4: d[0] = -G * d[3]; break;
    case 5: d[1] = G * d[3]; break;
    default: d[1] = -G * d[3]; break;
    }
}

/* The same in float: through the double one, exact there too (a copy of
 * a float, and G·w with G a power of two, round back to the float the
 * float arithmetic gives; ε and z_far are floats). */
static void onto_plane_f(int k, float p[4], double z_far) {
    double d[4] = {p[0], p[1], p[2], p[3]};
    onto_plane_d(k, d, z_far);
    for (int j = 0; j < 4; j++) p[j] = (float)d[j];
}

/* The point where the edge from `in` (inside plane k) to `out` (outside)
 * crosses plane k. Decided on the exact positions in double and kept exact
 * for the later planes. Its float position is the cut of the corners'
 * float positions (in double, as before the exact ones existed: it drew
 * the reference pictures) where that lies within 8 ulps of the exact cut,
 * else the exact cut rounded: a far corner's float rounding moves an
 * edge-on triangle's cut near the eye by its whole size. Either is then
 * put exactly on the plane. Both depend only on the edge, not on the
 * direction it is walked, so a neighbour's shared edge is cut bit for bit
 * alike. The attributes are interpolated in float (exact in clip space up
 * to rounding; nothing downstream depends on them being on a plane), with
 * the t of the position kept. */
static ras_clip_vertex cut_vertex(const ras_clip_vertex *in, const ras_clip_vertex *out, int k,
                                  double z_far) {
    ras_clip_vertex o;
    double t = 0;
    /* The caller's tests make the exact distances straddle the plane; were
     * one NaN, the corner stays where `in` is. */
    if (!cut_at(k, in->p_exact, out->p_exact, z_far, &t, o.p_exact))
        memcpy(o.p_exact, in->p_exact, sizeof o.p_exact);
    onto_plane_d(k, o.p_exact, z_far);
    o.exact = true;
    const double a[4] = {in->p_clip.x, in->p_clip.y, in->p_clip.z, in->p_clip.w};
    const double b[4] = {out->p_clip.x, out->p_clip.y, out->p_clip.z, out->p_clip.w};
    double tc, dc[4];
    float p[4], chain[4];
    bool keep = cut_at(k, a, b, z_far, &tc, dc);
    if (keep) {
        for (int j = 0; j < 4; j++) chain[j] = (float)dc[j];
        onto_plane_f(k, chain, z_far);
        keep = ras_float_chain_accurate(chain, o.p_exact);
    }
    for (int j = 0; j < 4; j++) p[j] = keep ? chain[j] : (float)o.p_exact[j];
    if (!keep) onto_plane_f(k, p, z_far);
    float tf = (float)(keep ? tc : t); /* the t of the position kept */
    o.p_clip = (vec4s){{p[0], p[1], p[2], p[3]}};
    o.color = glms_vec3_lerp(in->color, out->color, tf);
    o.normal = glms_vec3_lerp(in->normal, out->normal, tf);
    o.uv = glms_vec2_lerp(in->uv, out->uv, tf);
    o.view_pos = glms_vec3_lerp(in->view_pos, out->view_pos, tf);
    return o;
}

static inline float clampf(float v, float lo, float hi) { return v < lo ? lo : v > hi ? hi : v; }

/* A corner cut by a later plane is a convex combination of corners inside
 * every earlier plane, so it is inside them too — up to the last rounding
 * of its coordinates (an ulp). That ulp is taken back here, so every corner
 * keeps the promise of the header exactly. With a far distance, z is also
 * clamped into -w <= z <= w: between the float matrix's far plane and the
 * true one it is outside (its depth is the far plane's, 1). */
static void into_volume(vec4s *p, double z_far) {
    if (!(p->w >= RAS_CLIP_W_EPSILON)) p->w = RAS_CLIP_W_EPSILON;
    if (z_far > 0 && p->w > (float)z_far) p->w = (float)z_far;
    float g = RAS_CLIP_GUARD * p->w;
    p->z = clampf(p->z, -p->w, p->w);
    p->x = clampf(p->x, -g, g);
    p->y = clampf(p->y, -g, g);
}

unsigned ras_clip_outcode(vec4s p_clip) {
    unsigned mask = 0;
    for (int k = 0; k < PLANE_COUNT; k++)
        if (!(plane_distance(k, p_clip) >= 0)) mask |= 1u << k;
    return mask;
}

unsigned ras_clip_vertex_outcode(const ras_clip_vertex *v, double z_far) {
    const double widened[4] = {v->p_clip.x, v->p_clip.y, v->p_clip.z, v->p_clip.w};
    const double *p = v->exact ? v->p_exact : widened;
    unsigned mask = 0;
    for (int k = 0; k < PLANE_COUNT; k++)
        if (!(plane_distance_d(k, p, z_far) >= 0)) mask |= 1u << k;
    return mask;
}

ras_clip_result ras_clip_triangle(const ras_clip_vertex *a, const ras_clip_vertex *b,
                                  const ras_clip_vertex *c,
                                  ras_clip_vertex out[RAS_CLIP_MAX_VERTICES], int *count) {
    return ras_clip_triangle_far(a, b, c, 0.0, out, count);
}

ras_clip_result ras_clip_triangle_far(const ras_clip_vertex *a, const ras_clip_vertex *b,
                                      const ras_clip_vertex *c, double z_far,
                                      ras_clip_vertex out[RAS_CLIP_MAX_VERTICES], int *count) {
    const ras_clip_vertex *tri[3] = {a, b, c};
    unsigned outside_all = (1u << PLANE_COUNT) - 1, outside_any = 0;
    for (int i = 0; i < 3; i++) {
        unsigned mask = ras_clip_vertex_outcode(tri[i], z_far);
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
    for (int i = 0; i < n; i++) make_exact(&out[i]);
    for (int k = 0; k < PLANE_COUNT && n > 0; k++) {
        /* The planes the polygon as it is NOW crosses, not those the
         * original corners crossed: a corner cut against an earlier plane
         * is tested against this one like any other. */
        bool crosses = false;
        for (int i = 0; i < n && !crosses; i++) crosses = !inside_d(k, &out[i], z_far);
        if (!crosses) continue;
        int m = 0;
        for (int i = 0; i < n; i++) {
            const ras_clip_vertex *p = &out[i], *q = &out[(i + 1) % n];
            bool p_in = inside_d(k, p, z_far), q_in = inside_d(k, q, z_far);
            /* At most 3 + 7 corners for a convex polygon; the bound also
             * holds the array should rounding make one not quite convex. */
            if (p_in && m < RAS_CLIP_MAX_VERTICES) tmp[m++] = *p;
            /* Exactly one of the two inside: the edge crosses the plane.
             * Always interpolate from the inside corner to the outside one: a
             * neighbour sharing this edge walks it the other way, and only a
             * direction-independent formula gives it the same cut point bit for
             * bit — otherwise the shared edge moves and the mesh cracks on
             * screen (tests/unit/test_hardcases.c, test_watertight_clipped_fan). */
            if (p_in != q_in && m < RAS_CLIP_MAX_VERTICES)
                tmp[m++] = p_in ? cut_vertex(p, q, k, z_far) : cut_vertex(q, p, k, z_far);
        }
        n = m;
        memcpy(out, tmp, (size_t)n * sizeof *out);
    }
    for (int i = 0; i < n; i++) into_volume(&out[i].p_clip, z_far);
    *count = n >= 3 ? n : 0;
    return *count ? RAS_CLIP_SPLIT : RAS_CLIP_OUTSIDE;
}
