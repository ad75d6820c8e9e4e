/* shading.c — hw3, a classic GAMES101-style solution (tests/grading/mutants/classic).
 *
 * Written the way a student of the course writes it, independently of
 * hw3_shading/solution/: the course's Blinn-Phong loop, its TBN and bump
 * formulas, plain float math, with the conventions docs/hw3.md states (view
 * space viewer at the origin, colours in [0, 1], the real clip w). The
 * fairness check of `make mutants` grades it and it must get full marks. Not
 * shipped in the handout.
 * RASTER101-SOLUTION: this marker must never appear in a student handout.
 */
#include "shading.h"

#include <math.h>

/* ---- 1. interpolation ---------------------------------------------------- */

vec3s perspective_correct_barycentric(const ras_triangle *t, vec3s bary_screen) {
    float b0 = bary_screen.x / t->v[0].w;
    float b1 = bary_screen.y / t->v[1].w;
    float b2 = bary_screen.z / t->v[2].w;
    float sum = b0 + b1 + b2;
    if (!(sum > 0) || !isfinite(sum)) return bary_screen;
    return (vec3s){{b0 / sum, b1 / sum, b2 / sum}};
}

vec3s interpolate_vec3(const ras_triangle *t, vec3s bary_screen, const vec3s attr[3],
                       bool perspective) {
    vec3s b = perspective ? perspective_correct_barycentric(t, bary_screen) : bary_screen;
    vec3s r;
    r.x = b.x * attr[0].x + b.y * attr[1].x + b.z * attr[2].x;
    r.y = b.x * attr[0].y + b.y * attr[1].y + b.z * attr[2].y;
    r.z = b.x * attr[0].z + b.y * attr[1].z + b.z * attr[2].z;
    return r;
}

vec2s interpolate_vec2(const ras_triangle *t, vec3s bary_screen, const vec2s attr[3],
                       bool perspective) {
    vec3s b = perspective ? perspective_correct_barycentric(t, bary_screen) : bary_screen;
    vec2s r;
    r.x = b.x * attr[0].x + b.y * attr[1].x + b.z * attr[2].x;
    r.y = b.x * attr[0].y + b.y * attr[1].y + b.z * attr[2].y;
    return r;
}

/* ---- 2. fragment shaders -------------------------------------------------- */

vec3s normal_fragment_shader(const fragment_shader_payload *payload) {
    vec3s n = glms_vec3_normalize(payload->normal);
    return glms_vec3_scale(glms_vec3_adds(n, 1.0f), 0.5f);
}

vec3s blinn_phong_lighting(const fragment_shader_payload *payload, vec3s kd, vec3s point,
                           vec3s normal) {
    vec3s ka = payload->ka;
    vec3s ks = payload->ks;
    float p = payload->p;

    vec3s n = glms_vec3_normalize(normal);
    vec3s eye_pos = {{0, 0, 0}}; /* the viewer: the view-space origin */
    vec3s v = glms_vec3_normalize(glms_vec3_sub(eye_pos, point));

    vec3s result_color = glms_vec3_mul(ka, payload->ambient_intensity);
    for (int i = 0; i < payload->light_count; i++) {
        const light *lt = &payload->lights[i];
        vec3s to_light = glms_vec3_sub(lt->position, point);
        float r2 = glms_vec3_dot(to_light, to_light);
        vec3s l = glms_vec3_normalize(to_light);
        vec3s h = glms_vec3_normalize(glms_vec3_add(l, v));
        vec3s intensity = glms_vec3_divs(lt->intensity, r2);

        vec3s diffuse = glms_vec3_scale(glms_vec3_mul(kd, intensity),
                                        fmaxf(0.0f, glms_vec3_dot(n, l)));
        vec3s specular = glms_vec3_scale(glms_vec3_mul(ks, intensity),
                                         powf(fmaxf(0.0f, glms_vec3_dot(n, h)), p));
        result_color = glms_vec3_add(result_color, glms_vec3_add(diffuse, specular));
    }

    if (payload->counters && payload->light_count > 0) {
        payload->counters->stages_run |= RAS_STAGE_LIGHTING;
        payload->counters->lighting_evaluations += (uint64_t)payload->light_count;
    }
    return result_color;
}

vec3s phong_fragment_shader(const fragment_shader_payload *payload) {
    return blinn_phong_lighting(payload, payload->color, payload->view_pos, payload->normal);
}

vec3s texture_fragment_shader(const fragment_shader_payload *payload) {
    vec3s texture_color = payload->color;
    if (payload->texture) texture_color = texture_sample(payload, payload->texture, payload->uv);
    return blinn_phong_lighting(payload, texture_color, payload->view_pos, payload->normal);
}

void tangent_frame(vec3s n, vec3s *t, vec3s *b) {
    float x = n.x, y = n.y, z = n.z;
    float s = sqrtf(x * x + z * z);
    if (s < 1e-6f)
        *t = (vec3s){{1, 0, 0}};
    else
        *t = (vec3s){{x * y / s, s, z * y / s}};
    *b = glms_vec3_cross(n, *t);
}

vec3s bump_normal(const fragment_shader_payload *payload) {
    vec3s n = glms_vec3_normalize(payload->normal);
    if (!payload->height_map) return n;

    vec3s t, b;
    tangent_frame(n, &t, &b);

    float kh = payload->kh, kn = payload->kn;
    float u = payload->uv.x, v = payload->uv.y;
    float w = (float)payload->height_map->width;
    float h = (float)payload->height_map->height;

    float huv = height_sample(payload, u, v);
    float dU = kh * kn * (height_sample(payload, u + 1.0f / w, v) - huv);
    float dV = kh * kn * (height_sample(payload, u, v + 1.0f / h) - huv);

    /* TBN * (-dU, -dV, 1) */
    vec3s ln = {{-dU, -dV, 1.0f}};
    vec3s result;
    result.x = t.x * ln.x + b.x * ln.y + n.x * ln.z;
    result.y = t.y * ln.x + b.y * ln.y + n.y * ln.z;
    result.z = t.z * ln.x + b.z * ln.y + n.z * ln.z;
    return glms_vec3_normalize(result);
}

vec3s bump_fragment_shader(const fragment_shader_payload *payload) {
    return glms_vec3_scale(glms_vec3_adds(bump_normal(payload), 1.0f), 0.5f);
}

vec3s displacement_fragment_shader(const fragment_shader_payload *payload) {
    vec3s n = glms_vec3_normalize(payload->normal);
    float huv = height_sample(payload, payload->uv.x, payload->uv.y);
    vec3s point = glms_vec3_add(payload->view_pos, glms_vec3_scale(n, payload->kn * huv));
    vec3s bumped = bump_normal(payload);
    return blinn_phong_lighting(payload, payload->color, point, bumped);
}

/* ---- 3. texture sampling -------------------------------------------------- */

static vec3s lerp3(vec3s a, vec3s b, float s) {
    return (vec3s){{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)}};
}

static float safe_coord(float u, ras_wrap wrap) {
    if (!isfinite(u)) return 0.0f;
    if (wrap == RAS_WRAP_REPEAT) return u - floorf(u);
    return fminf(fmaxf(u, 0.0f), 1.0f);
}

static vec3s bilinear_level(const ras_texture *tex, int level, float u, float v) {
    u = safe_coord(u, tex->wrap);
    v = safe_coord(v, tex->wrap);
    float x = u * tex->level_width[level] - 0.5f;
    float y = v * tex->level_height[level] - 0.5f;
    float fx = floorf(x), fy = floorf(y);
    int i0 = (int)fx, j0 = (int)fy;
    float s = x - fx, t = y - fy;

    vec3s c00 = ras_texture_texel(tex, level, i0, j0);
    vec3s c10 = ras_texture_texel(tex, level, i0 + 1, j0);
    vec3s c01 = ras_texture_texel(tex, level, i0, j0 + 1);
    vec3s c11 = ras_texture_texel(tex, level, i0 + 1, j0 + 1);
    return lerp3(lerp3(c00, c10, s), lerp3(c01, c11, s), t);
}

vec3s texture_sample_bilinear(const ras_texture *tex, float u, float v) {
    return bilinear_level(tex, 0, u, v);
}

vec3s texture_sample_trilinear(const ras_texture *tex, vec2s uv, vec2s duv_dx, vec2s duv_dy) {
    float w = (float)tex->width, h = (float)tex->height;
    float dx = sqrtf(duv_dx.x * w * duv_dx.x * w + duv_dx.y * h * duv_dx.y * h);
    float dy = sqrtf(duv_dy.x * w * duv_dy.x * w + duv_dy.y * h * duv_dy.y * h);
    float rho = fmaxf(dx, dy);
    float L = (rho > 1.0f) ? log2f(rho) : 0.0f;
    if (!isfinite(L)) L = 0.0f;
    float max_level = (float)(tex->level_count - 1);
    if (L > max_level) L = max_level;

    int l0 = (int)floorf(L);
    int l1 = l0 + 1 < tex->level_count ? l0 + 1 : l0;
    float frac = L - (float)l0;
    vec3s c0 = bilinear_level(tex, l0, uv.x, uv.y);
    vec3s c1 = bilinear_level(tex, l1, uv.x, uv.y);
    return lerp3(c0, c1, frac);
}
