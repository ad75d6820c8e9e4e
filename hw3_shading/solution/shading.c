/* solution/shading.c — hw3 reference implementation of shading.h. RASTER101-SOLUTION
 * This marker must never appear in a student handout. */
#include "shading.h"

#include <float.h> /* FLT_MAX */
#include <math.h>  /* floorf, log2f, powf, sqrtf, isfinite */

/* ---- 1. interpolation --------------------------------------------------- */

/* perspective_correct_barycentric, inline in the interpolators (two or three
 * calls a fragment). */
static inline vec3s perspective_weights(const ras_triangle *t, vec3s bary_screen) {
    /* 1/w is affine in screen space, and so is attr/w: interpolate both with
     * λ and divide. b_i = (λ_i / w_i) / Σ (λ_j / w_j). */
    vec3s b = {{bary_screen.x / t->v[0].w, bary_screen.y / t->v[1].w,
                bary_screen.z / t->v[2].w}};
    float sum = b.x + b.y + b.z;
    /* w > 0 after clipping, so sum > 0 inside the triangle; a degenerate
     * input keeps the screen barycentrics rather than producing NaN. (0 <
     * sum <= FLT_MAX is "positive and finite" in two comparisons; NaN fails.) */
    if (!(sum > 0.0f && sum <= FLT_MAX)) return bary_screen;
    return glms_vec3_scale(b, 1.0f / sum);
}

vec3s perspective_correct_barycentric(const ras_triangle *t, vec3s bary_screen) {
    return perspective_weights(t, bary_screen);
}

vec3s interpolate_vec3(const ras_triangle *t, vec3s bary_screen, const vec3s attr[3],
                       bool perspective) {
    vec3s b = perspective ? perspective_weights(t, bary_screen) : bary_screen;
    vec3s r = glms_vec3_scale(attr[0], b.x);
    r = glms_vec3_muladds(attr[1], b.y, r);
    return glms_vec3_muladds(attr[2], b.z, r);
}

vec2s interpolate_vec2(const ras_triangle *t, vec3s bary_screen, const vec2s attr[3],
                       bool perspective) {
    vec3s b = perspective ? perspective_weights(t, bary_screen) : bary_screen;
    return (vec2s){{attr[0].x * b.x + attr[1].x * b.y + attr[2].x * b.z,
                    attr[0].y * b.x + attr[1].y * b.y + attr[2].y * b.z}};
}

/* ---- 2. fragment shaders ------------------------------------------------ */

vec3s normal_fragment_shader(const fragment_shader_payload *payload) {
    vec3s n = glms_vec3_normalize(payload->normal);
    return glms_vec3_scale(glms_vec3_adds(n, 1.0f), 0.5f);
}

/* fmaxf(0, x) — NaN gives 0 too — without fmaxf's library call: GCC
 * cannot inline fmaxf at -O2, and Blinn-Phong takes two a light. */
static inline float max0(float x) { return x > 0.0f ? x : 0.0f; }

vec3s blinn_phong_lighting(const fragment_shader_payload *payload, vec3s kd, vec3s point,
                           vec3s normal) {
    if (payload->counters && payload->light_count > 0) { /* ambient alone is no lighting work */
        payload->counters->stages_run |= RAS_STAGE_LIGHTING;
        payload->counters->lighting_evaluations += (uint64_t)payload->light_count;
    }
    vec3s n = glms_vec3_normalize(normal);
    vec3s v = glms_vec3_normalize(glms_vec3_negate(point)); /* the eye is the view-space origin */
    /* Ambient light does not come from any light: once, outside the loop. */
    vec3s color = glms_vec3_mul(payload->ka, payload->ambient_intensity);
    for (int i = 0; i < payload->light_count; i++) {
        const light *L = &payload->lights[i];
        vec3s to_light = glms_vec3_sub(L->position, point);
        float r2 = glms_vec3_dot(to_light, to_light);
        vec3s l = glms_vec3_normalize(to_light);
        vec3s h = glms_vec3_normalize(glms_vec3_add(l, v));
        vec3s irradiance = glms_vec3_divs(L->intensity, r2); /* I / r² */
        float diffuse = max0(glms_vec3_dot(n, l));
        float specular = powf(max0(glms_vec3_dot(n, h)), payload->p);
        color = glms_vec3_add(color, glms_vec3_scale(glms_vec3_mul(kd, irradiance), diffuse));
        color = glms_vec3_add(color,
                              glms_vec3_scale(glms_vec3_mul(payload->ks, irradiance), specular));
    }
    return color;
}

vec3s phong_fragment_shader(const fragment_shader_payload *payload) {
    return blinn_phong_lighting(payload, payload->color, payload->view_pos, payload->normal);
}

vec3s texture_fragment_shader(const fragment_shader_payload *payload) {
    vec3s kd = payload->texture ? texture_sample(payload, payload->texture, payload->uv)
                                : payload->color;
    return blinn_phong_lighting(payload, kd, payload->view_pos, payload->normal);
}

/* tangent_frame, inline in bump mapping. */
static inline void tangent_frame_inline(vec3s n, vec3s *t, vec3s *b) {
    float s = sqrtf(n.x * n.x + n.z * n.z);
    if (s > 1e-6f) {
        *t = (vec3s){{n.x * n.y / s, s, n.z * n.y / s}};
    } else {
        /* n = (0, ±1, 0): the formula is 0/0. Any perpendicular unit vector
         * will do; x keeps the frame continuous with the formula's limit
         * along the x axis. */
        *t = (vec3s){{1.0f, 0.0f, 0.0f}};
    }
    *b = glms_vec3_cross(n, *t);
}

void tangent_frame(vec3s n, vec3s *t, vec3s *b) { tangent_frame_inline(n, t, b); }

/* h(u, v), h(u + 1/W, v) and h(u, v + 1/H) (section 3, beside the lookups). */
static inline void bump_heights(const fragment_shader_payload *payload, float heights[3]);

/* bump_normal of the unit normal n = normalize(payload->normal) with a height
 * map; *h receives h(u, v), by which the displacement shader moves the point. */
static inline vec3s bumped_normal(const fragment_shader_payload *payload, vec3s n, float *h) {
    if (payload->counters) payload->counters->stages_run |= RAS_STAGE_BUMP;
    vec3s t, b;
    tangent_frame_inline(n, &t, &b);
    float heights[3];
    bump_heights(payload, heights);
    *h = heights[0];
    float k = payload->kh * payload->kn;
    float du = k * (heights[1] - heights[0]);
    float dv = k * (heights[2] - heights[0]);
    /* TBN · (−dU, −dV, 1) = −dU·t − dV·b + n */
    vec3s p = glms_vec3_add(glms_vec3_scale(t, -du), glms_vec3_scale(b, -dv));
    vec3s bumped = glms_vec3_normalize(glms_vec3_add(p, n));
    return ras_vec3_finite(bumped) ? bumped : n;
}

vec3s bump_normal(const fragment_shader_payload *payload) {
    vec3s n = glms_vec3_normalize(payload->normal);
    float h;
    return payload->height_map ? bumped_normal(payload, n, &h) : n;
}

vec3s bump_fragment_shader(const fragment_shader_payload *payload) {
    return glms_vec3_scale(glms_vec3_adds(bump_normal(payload), 1.0f), 0.5f);
}

/* bump_normal's heights give the point's h(u, v) too. */
vec3s displacement_fragment_shader(const fragment_shader_payload *payload) {
    vec3s n = glms_vec3_normalize(payload->normal);
    float h = 0.0f; /* height_sample's h without a height map */
    vec3s normal = payload->height_map ? bumped_normal(payload, n, &h) : n;
    vec3s point = glms_vec3_muladds(n, payload->kn * h, payload->view_pos);
    return blinn_phong_lighting(payload, payload->color, point, normal);
}

/* ---- 3. texture sampling ------------------------------------------------ */

/* floorf(x) as an int, for |x| < 2^31: truncate, then step down where
 * truncation went up (negative non-integers). The same value as floorf —
 * which without SSE4.1 is a call-free but 20-instruction sequence, run four
 * times a lookup. */
static inline int floor_small(float x) {
    int i = (int)x;
    return (float)i > x ? i - 1 : i;
}

/* A texture coordinate made safe for integer conversion: NaN/±Inf read like
 * 0; repeat keeps the fraction; clamp keeps [0, 1] (clamp-to-edge). */
static inline float safe_coord(float u, ras_wrap wrap) {
    if (wrap == RAS_WRAP_REPEAT) {
        /* From 2^23 on every float is a whole number: its fraction is 0
         * (1e30 → 0; NaN and ±Inf fail the test too), and below that
         * floor_small may be used. */
        if (!(fabsf(u) < 0x1p23f)) return 0.0f;
        return u - (float)floor_small(u); /* [0, 1] */
    }
    if (!isfinite(u)) return 0.0f;
    return fminf(fmaxf(u, 0.0f), 1.0f);
}

static vec3s lerp3(vec3s a, vec3s b, float s) {
    return glms_vec3_add(a, glms_vec3_scale(glms_vec3_sub(b, a), s));
}

/* One axis of a bilinear lookup: the texels either side of the coordinate,
 * wrapped, and the weight of the second. */
typedef struct bilinear_axis {
    int a, b; /* texel indices, in [0, n) */
    float s;  /* weight of b, in [0, 1) */
} bilinear_axis;

static inline bilinear_axis bilinear_axis_at(float u, int n, ras_wrap wrap) {
    /* Texel i's centre is at u_img = i: shift by half a texel. */
    float x = safe_coord(u, wrap) * (float)n - 0.5f;
    int i0 = floor_small(x); /* x in [-0.5, 2^14): i0 in [-1, n-1] */
    return (bilinear_axis){ras_texture_wrap_index(wrap, i0, n),
                           ras_texture_wrap_index(wrap, i0 + 1, n), x - (float)i0};
}

/* The four texels of axes x and y (of a level w texels wide), blended. */
static inline vec3s bilinear_blend(const vec3s *px, int w, bilinear_axis x, bilinear_axis y) {
    vec3s bottom = lerp3(px[y.a * w + x.a], px[y.a * w + x.b], x.s);
    vec3s top = lerp3(px[y.b * w + x.a], px[y.b * w + x.b], x.s);
    return lerp3(bottom, top, y.s);
}

/* A byte texel (level 0 of a loaded texture) as the float the float texture held. */
static inline vec3s byte_texel(const uint8_t *px, int k) { return ras_texel_rgb8(px + 3 * (size_t)k); }

/* bilinear_blend of byte texels: the same floats, the same operations. */
static inline vec3s bilinear_blend8(const uint8_t *px, int w, bilinear_axis x, bilinear_axis y) {
    vec3s bottom = lerp3(byte_texel(px, y.a * w + x.a), byte_texel(px, y.a * w + x.b), x.s);
    vec3s top = lerp3(byte_texel(px, y.b * w + x.a), byte_texel(px, y.b * w + x.b), x.s);
    return lerp3(bottom, top, y.s);
}

/* Bilinear lookup in one mip level (v = 0 is row j = 0, the bottom). */
static inline vec3s bilinear_level(const ras_texture *tex, int level, float u, float v) {
    int w = tex->level_width[level], h = tex->level_height[level];
    bilinear_axis x = bilinear_axis_at(u, w, tex->wrap), y = bilinear_axis_at(v, h, tex->wrap);
    const uint8_t *bytes = level == 0 ? ras_texture_level0_rgb8(tex) : NULL;
    if (bytes) return bilinear_blend8(bytes, w, x, y);
    const vec3s *px = tex->levels[level] ? tex->levels[level] : tex->texels;
    return bilinear_blend(px, w, x, y);
}

/* The three heights of bump mapping, h(u, v), h(u + 1/W, v) and h(u, v + 1/H),
 * each the float height_sample gives (and counted as it counts them). With
 * bilinear lookups the two at u share that axis's texels and weight, and the
 * two at v theirs: four axes instead of six. */
static inline void bump_heights(const fragment_shader_payload *payload, float heights[3]) {
    const ras_texture *hm = payload->height_map;
    float u = payload->uv.x, v = payload->uv.y;
    float u1 = u + 1.0f / (float)hm->width, v1 = v + 1.0f / (float)hm->height;
    if (payload->filter == FILTER_NEAREST) { /* one texel each: nothing to share */
        /* one call site, not three: GCC then inlines height_sample */
        const float us[3] = {u, u1, u}, vs[3] = {v, v, v1};
        for (int i = 0; i < 3; i++)
            heights[i] = height_sample(payload, us[i], vs[i]);
        return;
    }
    ras_counters *c = payload->counters;
    if (c) {
        c->stages_run |= RAS_STAGE_TEXTURE;
        c->texels_fetched += 3 * 4;
    }
    int w = hm->level_width[0], h = hm->level_height[0];
    bilinear_axis x = bilinear_axis_at(u, w, hm->wrap), x1 = bilinear_axis_at(u1, w, hm->wrap);
    bilinear_axis y = bilinear_axis_at(v, h, hm->wrap), y1 = bilinear_axis_at(v1, h, hm->wrap);
    const uint8_t *bytes = ras_texture_level0_rgb8(hm); /* a loaded height map */
    if (bytes) {
        heights[0] = 255.0f * glms_vec3_norm(bilinear_blend8(bytes, w, x, y));
        heights[1] = 255.0f * glms_vec3_norm(bilinear_blend8(bytes, w, x1, y));
        heights[2] = 255.0f * glms_vec3_norm(bilinear_blend8(bytes, w, x, y1));
        return;
    }
    const vec3s *px = hm->levels[0] ? hm->levels[0] : hm->texels;
    heights[0] = 255.0f * glms_vec3_norm(bilinear_blend(px, w, x, y));
    heights[1] = 255.0f * glms_vec3_norm(bilinear_blend(px, w, x1, y));
    heights[2] = 255.0f * glms_vec3_norm(bilinear_blend(px, w, x, y1));
}

vec3s texture_sample_bilinear(const ras_texture *tex, float u, float v) {
    return bilinear_level(tex, 0, u, v);
}

vec3s texture_sample_trilinear(const ras_texture *tex, vec2s uv, vec2s duv_dx, vec2s duv_dy) {
    if (tex->level_count <= 1) return bilinear_level(tex, 0, uv.x, uv.y);
    float W = (float)tex->width, H = (float)tex->height;
    float lx = hypotf(duv_dx.x * W, duv_dx.y * H); /* texels per pixel step in x */
    float ly = hypotf(duv_dy.x * W, duv_dy.y * H);
    float rho = fmaxf(lx, ly);
    float L = rho > 1.0f && isfinite(rho) ? log2f(rho) : 0.0f; /* magnified: level 0 */
    float top = (float)(tex->level_count - 1);
    if (L >= top) return bilinear_level(tex, tex->level_count - 1, uv.x, uv.y);
    int l0 = (int)floorf(L);
    float s = L - (float)l0;
    vec3s a = bilinear_level(tex, l0, uv.x, uv.y);
    if (s <= 0.0f) return a;
    return lerp3(a, bilinear_level(tex, l0 + 1, uv.x, uv.y), s);
}
