/* shading.h — hw3: from a covered pixel to its colour.
 *
 * Read all of it: it is the contract of the functions you write in shading.c
 * (what each takes, returns and counts). Leave it as it is: the tests and the
 * grader compile your shading.c against this header as shipped.
 *
 * Implemented twice with the same signatures: shading.c (yours, TODOs) and
 * the reference solution (instructors' edition only). The fragment stage (the
 * core's, common/pipeline/stage5_fragment.c) calls the interpolation functions
 * for every pixel hw2's rasterizer covers; scene.c puts what they give into a
 * fragment_shader_payload and calls one of the fragment shaders below. See
 * docs/hw3.md; the numbered TODO(hw3) hints in shading.c follow its sections.
 *
 * Index
 *   1. interpolation   perspective_correct_barycentric, interpolate_vec3, interpolate_vec2
 *   2. shaders         normal_ (given), phong_, texture_, bump_, displacement_fragment_shader
 *                      with their helpers blinn_phong_lighting and tangent_frame
 *   3. textures        texture_sample_bilinear, texture_sample_trilinear (bonus)
 *
 * Conventions (stated once):
 *   - every position, normal and light in a payload is in VIEW space: the camera
 *     sits at the origin looking down -z, so the direction to the viewer from a
 *     point p is normalize(-p). Light positions are given in view space too, as
 *     in the GAMES101 framework, which uses the numbers (20,20,20) and
 *     (-20,20,0) directly with view-space points (it never multiplies them by
 *     the view matrix);
 *   - colours are floats in [0, 1] (the course works in 0..255 and divides by
 *     255; the results are the same). Shaders may return values above 1: the
 *     image is clamped when it is written;
 *   - screen-space barycentrics λ (from hw2) interpolate depth, which is affine
 *     in screen space; every other attribute needs the 1/w correction, with w
 *     the CLIP-space w of each vertex, kept in ras_triangle.v[i].w (> 0);
 *   - heights (bump, displacement) follow the course: h(u, v) is the length of
 *     the height map's RGB colour in 8-bit units, 255·|rgb| (0 to 441.7), see
 *     height_sample().
 */
#ifndef RAS_HW3_SHADING_H
#define RAS_HW3_SHADING_H

#include "ras_counters.h"
#include "ras_scene.h" /* ras_scene_filter */
#include "ras_texture.h"
#include "ras_triangle.h"

#include <math.h> /* isfinite, fabsf */

/* ---- 1. interpolation --------------------------------------------------- */

/* The barycentrics that interpolate attributes correctly in 3D, from the
 * screen-space ones: b_i = (λ_i / w_i) / Σ_j (λ_j / w_j), summing to 1. */
vec3s perspective_correct_barycentric(const ras_triangle *t, vec3s bary_screen);

/* attr[0..2] interpolated at the fragment with screen barycentrics
 * bary_screen: perspective-correct when `perspective`, else affine
 * (Σ λ_i attr_i — what a w = 1 pipeline silently does). */
vec3s interpolate_vec3(const ras_triangle *t, vec3s bary_screen, const vec3s attr[3],
                       bool perspective);
vec2s interpolate_vec2(const ras_triangle *t, vec3s bary_screen, const vec2s attr[3],
                       bool perspective);

/* ---- 2. fragment shaders ------------------------------------------------ */

/* The texture filter: the core's (ras_scene.h, a scene file's "filter" and
 * --filter), under this header's names. */
typedef ras_scene_filter texture_filter;
#define FILTER_NEAREST RAS_FILTER_NEAREST     /* given: ras_texture_sample_nearest */
#define FILTER_BILINEAR RAS_FILTER_BILINEAR   /* yours: texture_sample_bilinear */
#define FILTER_TRILINEAR RAS_FILTER_TRILINEAR /* bonus: texture_sample_trilinear, mip levels */

typedef struct light {
    vec3s position;  /* view space */
    vec3s intensity; /* I, divided by r² at distance r */
} light;

#define HW3_MAX_LIGHTS 8 /* = RAS_SCENE_MAX_LIGHTS: every scene file fits */

/* Everything a fragment shader may read. The fragment stage fills only the
 * varyings the chosen shader declares (scene.c's hw3_shader_varyings); the
 * others are zero. */
typedef struct fragment_shader_payload {
    /* interpolated at the fragment (perspective-correct) */
    vec3s view_pos; /* the shaded point, view space */
    vec3s normal;   /* unit length (renormalised after interpolation), view space */
    vec2s uv;       /* texture coordinates */
    vec2s duv_dx, duv_dy; /* change of uv per screen pixel in x and y (trilinear only) */
    /* per object */
    vec3s color; /* base colour: kd of phong and displacement */
    const ras_texture *texture;    /* colour map: kd of the texture shader; NULL: none */
    const ras_texture *height_map; /* bump / displacement; NULL: flat */
    texture_filter filter;
    vec3s ka, ks;  /* ambient and specular coefficients */
    float p;       /* specular exponent */
    float kh, kn;  /* bump scale and displacement scale */
    /* per scene */
    light lights[HW3_MAX_LIGHTS];
    int light_count;
    vec3s ambient_intensity; /* I_a: added ONCE, not once per light */
    ras_counters *counters;  /* may be NULL */
} fragment_shader_payload;

typedef vec3s (*fragment_shader_fn)(const fragment_shader_payload *payload);

/* GIVEN (the worked example): the normal as a colour, (n + 1) / 2. */
vec3s normal_fragment_shader(const fragment_shader_payload *payload);

/* Blinn-Phong at `point` with normal `normal` (any length: normalised here —
 * interpolated and perturbed normals are not unit) and diffuse colour kd:
 *   L = ka·I_a + Σ_lights [ kd·(I/r²)·max(0, n·l) + ks·(I/r²)·max(0, n·h)^p ]
 * with l the unit vector to the light, v = normalize(-point) to the viewer,
 * h = normalize(l + v), r the distance to the light (products are per channel). */
vec3s blinn_phong_lighting(const fragment_shader_payload *payload, vec3s kd, vec3s point,
                           vec3s normal);

/* Blinn-Phong with kd = payload->color. */
vec3s phong_fragment_shader(const fragment_shader_payload *payload);

/* Blinn-Phong with kd = the colour map at uv (payload->filter); payload->color
 * when there is no texture. */
vec3s texture_fragment_shader(const fragment_shader_payload *payload);

/* The tangent frame of the course for a unit normal n = (x, y, z):
 *   t = (x·y/√(x²+z²), √(x²+z²), z·y/√(x²+z²)),  b = n × t.
 * t is unit length; it is perpendicular to n only where y = 0 (n·t =
 * 2y√(x²+z²): the course's sign slip, kept so pictures match the course; see
 * docs/hw3.md, bonus). At n = (0, ±1, 0) the formula is 0/0: return any unit t
 * perpendicular to n instead, so nothing is ever NaN. */
void tangent_frame(vec3s n, vec3s *t, vec3s *b);

/* The perturbed normal of bump mapping, TBN · (−dU, −dV, 1) normalised, with
 *   dU = kh·kn·(h(u + 1/W, v) − h(u, v)),  dV = kh·kn·(h(u, v + 1/H) − h(u, v))
 * (W×H the height map's size); the normal itself when there is no height map. */
vec3s bump_normal(const fragment_shader_payload *payload);

/* Bump mapping: the perturbed normal as a colour, (n' + 1) / 2. */
vec3s bump_fragment_shader(const fragment_shader_payload *payload);

/* Displacement mapping: the point moves to p + kn·n·h(u, v), the normal becomes
 * bump_normal(), then Blinn-Phong with kd = payload->color. */
vec3s displacement_fragment_shader(const fragment_shader_payload *payload);

/* ---- 3. texture sampling ------------------------------------------------ */

/* Bilinear filtering of level 0. Texel centres sit at u·W − 0.5 (and v·H − 0.5;
 * v = 0 is the bottom row j = 0, see ras_texture.h); the four neighbours are
 * addressed through the texture's wrap (repeat or clamp-to-edge). Never reads
 * out of bounds, whatever u and v are (NaN reads like 0, ±1e30 is fine). */
vec3s texture_sample_bilinear(const ras_texture *tex, float u, float v);

/* Bonus: trilinear mipmapping. Level L = log2 ρ with ρ the longer screen-pixel
 * footprint in texels, ρ = max(|duv_dx ∘ (W,H)|, |duv_dy ∘ (W,H)|); blends
 * bilinear lookups of levels ⌊L⌋ and ⌊L⌋+1, clamped to the built levels.
 * Without mip levels (level_count 1) it is bilinear. */
vec3s texture_sample_trilinear(const ras_texture *tex, vec2s uv, vec2s duv_dx, vec2s duv_dy);

/* GIVEN: the lookup the shaders use — the payload's filter, and the counters
 * (texels read: 1 nearest, 4 bilinear, 8 trilinear). */
static inline vec3s texture_sample(const fragment_shader_payload *payload,
                                   const ras_texture *tex, vec2s uv) {
    ras_counters *c = payload->counters;
    if (c) c->stages_run |= RAS_STAGE_TEXTURE;
    switch (payload->filter) {
    case FILTER_BILINEAR:
        if (c) c->texels_fetched += 4;
        return texture_sample_bilinear(tex, uv.x, uv.y);
    case FILTER_TRILINEAR:
        if (c) c->texels_fetched += tex->level_count > 1 ? 8 : 4;
        if (c && tex->level_count > 1) c->stages_run |= RAS_STAGE_MIPMAP;
        return texture_sample_trilinear(tex, uv, payload->duv_dx, payload->duv_dy);
    case FILTER_NEAREST: break;
    }
    if (c) c->texels_fetched += 1;
    return ras_texture_sample_nearest(tex, uv.x, uv.y);
}

/* GIVEN: the course's height h(u, v) = |rgb| in 8-bit units (255·|rgb|) of the
 * height map; trilinear reads level 0 bilinearly (a height difference over one
 * texel needs the finest level). 0 without a height map. */
static inline float height_sample(const fragment_shader_payload *payload, float u, float v) {
    const ras_texture *tex = payload->height_map;
    if (!tex) return 0.0f;
    ras_counters *c = payload->counters;
    if (c) c->stages_run |= RAS_STAGE_TEXTURE;
    vec3s rgb;
    if (payload->filter == FILTER_NEAREST) {
        rgb = ras_texture_sample_nearest(tex, u, v);
        if (c) c->texels_fetched += 1;
    } else {
        rgb = texture_sample_bilinear(tex, u, v);
        if (c) c->texels_fetched += 4;
    }
    return 255.0f * glms_vec3_norm(rgb);
}

#endif
