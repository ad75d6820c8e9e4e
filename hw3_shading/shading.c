/* shading.c — hw3: YOUR implementation of shading.h.
 *
 * Each function returns a placeholder and prints a one-time notice until you
 * write it: interpolation is affine, lighting is the unlit base colour,
 * bilinear is nearest, the bump normal is the plain normal. The program runs
 * from the start; the pictures get right as the TODOs get done. Read
 * docs/hw3.md first; run the tests with `make grade HW=3` or
 * `(cd build && ctest -L hw3)`.
 *
 * Given complete: normal_fragment_shader (the worked example), and the small
 * shaders that only combine your helpers (phong, bump).
 */
/* When you write a function, DELETE its two notice lines (`static bool shown;`
 * and `ras_todo_notice(...)`): the grader gives no points to a test during
 * which a notice was printed, however right the result. */
#include "shading.h"

#include "ras_todo.h"

#include <math.h> /* floorf, powf, sqrtf, fmaxf, isfinite */

/* ---- 1. interpolation (docs/hw3.md, section 1) --------------------------- */

vec3s perspective_correct_barycentric(const ras_triangle *t, vec3s bary_screen) {
    static bool shown;
    ras_todo_notice(&shown, "perspective_correct_barycentric",
                    "docs/hw3.md, section 1 (perspective-correct interpolation)");
    /* TODO(hw3) 1.1 Divide each screen barycentric by its vertex's CLIP w:
     *               b_i = λ_i / t->v[i].w. Use the real w kept in t->v[i].w —
     *               a vertex converted with w forced to 1 makes this silently
     *               affine (the "w = 1 pitfall", docs/hw3.md figure 2).
     * TODO(hw3) 1.2 Normalise: b_i / (b_0 + b_1 + b_2), so they sum to 1.
     * TODO(hw3) 1.3 Guard: if the sum is not > 0 (or not finite), return the
     *               screen barycentrics unchanged instead of dividing by it. */
    (void)t;
    return bary_screen; /* placeholder: affine */
}

vec3s interpolate_vec3(const ras_triangle *t, vec3s bary_screen, const vec3s attr[3],
                       bool perspective) {
    static bool shown;
    ras_todo_notice(&shown, "interpolate_vec3",
                    "docs/hw3.md, section 1 (perspective-correct interpolation)");
    /* TODO(hw3) 1.4 Choose the weights: perspective ?
     *               perspective_correct_barycentric(t, bary_screen) : bary_screen,
     *               then return Σ b_i · attr[i] (the affine sum below is the
     *               placeholder; it ignores `perspective`). */
    (void)t;
    (void)perspective;
    vec3s r = glms_vec3_scale(attr[0], bary_screen.x);
    r = glms_vec3_muladds(attr[1], bary_screen.y, r);
    return glms_vec3_muladds(attr[2], bary_screen.z, r);
}

vec2s interpolate_vec2(const ras_triangle *t, vec3s bary_screen, const vec2s attr[3],
                       bool perspective) {
    static bool shown;
    ras_todo_notice(&shown, "interpolate_vec2",
                    "docs/hw3.md, section 1 (perspective-correct interpolation)");
    /* TODO(hw3) 1.5 The same as 1.4 for two components (texture coordinates:
     *               the checkerboard on the floor bends when this is affine). */
    (void)t;
    (void)perspective;
    return (vec2s){{attr[0].x * bary_screen.x + attr[1].x * bary_screen.y +
                        attr[2].x * bary_screen.z,
                    attr[0].y * bary_screen.x + attr[1].y * bary_screen.y +
                        attr[2].y * bary_screen.z}};
}

/* ---- 2. fragment shaders (docs/hw3.md, sections 2, 3, 5, 6) ------------- */

/* GIVEN — the worked example: a unit normal's components are in [-1, 1];
 * (n + 1) / 2 maps them to colours in [0, 1]. Facing the camera (0, 0, 1)
 * gives (0.5, 0.5, 1), the familiar lavender blue. */
vec3s normal_fragment_shader(const fragment_shader_payload *payload) {
    vec3s n = glms_vec3_normalize(payload->normal);
    return glms_vec3_scale(glms_vec3_adds(n, 1.0f), 0.5f);
}

vec3s blinn_phong_lighting(const fragment_shader_payload *payload, vec3s kd, vec3s point,
                           vec3s normal) {
    static bool shown;
    ras_todo_notice(&shown, "blinn_phong_lighting", "docs/hw3.md, section 2 (Blinn-Phong)");
    /* TODO(hw3) 2.1 Normalise the normal n; the viewer is at the view-space
     *               origin, so v = normalize(-point).
     * TODO(hw3) 2.2 Start from the ambient term ka * I_a (payload->ka,
     *               payload->ambient_intensity; glms_vec3_mul is per channel).
     *               ONCE — not inside the loop: ambient light comes from no
     *               light, and adding it per light doubles it with two lights.
     * TODO(hw3) 2.3 For each of payload->light_count lights: l = normalize(
     *               light.position - point), r² = |light.position - point|²,
     *               h = normalize(l + v).
     * TODO(hw3) 2.4 Add the diffuse term kd * (I / r²) * max(0, n·l) and the
     *               specular term ks * (I / r²) * max(0, n·h)^p (powf;
     *               payload->ks, payload->p).
     * TODO(hw3) 2.5 Count your work for --stats (a test checks it): when
     *               payload->counters is not NULL and light_count > 0, set
     *               RAS_STAGE_LIGHTING in counters->stages_run and add
     *               light_count to counters->lighting_evaluations. */
    (void)payload;
    (void)point;
    (void)normal;
    return kd; /* placeholder: unlit */
}

/* GIVEN: Blinn-Phong with the object's base colour as kd. */
vec3s phong_fragment_shader(const fragment_shader_payload *payload) {
    return blinn_phong_lighting(payload, payload->color, payload->view_pos, payload->normal);
}

vec3s texture_fragment_shader(const fragment_shader_payload *payload) {
    static bool shown;
    ras_todo_notice(&shown, "texture_fragment_shader",
                    "docs/hw3.md, section 3 (texture as kd)");
    /* TODO(hw3) 3.1 kd = texture_sample(payload, payload->texture, payload->uv)
     *               when payload->texture is not NULL, else payload->color.
     * TODO(hw3) 3.2 Return blinn_phong_lighting with that kd at
     *               payload->view_pos and payload->normal. */
    return blinn_phong_lighting(payload, payload->color, payload->view_pos,
                                payload->normal); /* placeholder: ignores the texture */
}

void tangent_frame(vec3s n, vec3s *t, vec3s *b) {
    static bool shown;
    ras_todo_notice(&shown, "tangent_frame", "docs/hw3.md, section 5 (bump mapping)");
    /* TODO(hw3) 5.1 s = sqrt(x² + z²); t = (x·y/s, s, z·y/s).
     * TODO(hw3) 5.2 When s is (almost) 0 — n = (0, ±1, 0), the top of every
     *               sphere — the formula is 0/0 = NaN: use t = (1, 0, 0)
     *               (any unit vector perpendicular to n) instead.
     * TODO(hw3) 5.3 b = n × t (glms_vec3_cross). */
    (void)n;
    *t = (vec3s){{1.0f, 0.0f, 0.0f}}; /* placeholder */
    *b = (vec3s){{0.0f, 0.0f, 1.0f}};
}

vec3s bump_normal(const fragment_shader_payload *payload) {
    static bool shown;
    ras_todo_notice(&shown, "bump_normal", "docs/hw3.md, section 5 (bump mapping)");
    /* TODO(hw3) 5.4 Without a height map (payload->height_map == NULL) return
     *               the normalised normal.
     * TODO(hw3) 5.5 Get t and b from tangent_frame(n, &t, &b).
     * TODO(hw3) 5.6 With h = height_sample(payload, u, v), W×H the height
     *               map's size and k = kh·kn:
     *               dU = k·(h(u + 1/W, v) − h(u, v)), dV = k·(h(u, v + 1/H) − h(u, v)).
     * TODO(hw3) 5.7 Return normalize(−dU·t − dV·b + n) (that is TBN·(−dU, −dV, 1)). */
    return glms_vec3_normalize(payload->normal); /* placeholder: no bumps */
}

/* GIVEN: the bumped normal as a colour, like the normal shader. */
vec3s bump_fragment_shader(const fragment_shader_payload *payload) {
    return glms_vec3_scale(glms_vec3_adds(bump_normal(payload), 1.0f), 0.5f);
}

vec3s displacement_fragment_shader(const fragment_shader_payload *payload) {
    static bool shown;
    ras_todo_notice(&shown, "displacement_fragment_shader",
                    "docs/hw3.md, section 6 (displacement mapping)");
    /* TODO(hw3) 6.1 Move the point along the ORIGINAL unit normal n:
     *               p' = view_pos + kn · h(u, v) · n.
     * TODO(hw3) 6.2 Light p' with the bumped normal bump_normal(payload) and
     *               kd = payload->color (blinn_phong_lighting). */
    return phong_fragment_shader(payload); /* placeholder: no displacement */
}

/* ---- 3. texture sampling (docs/hw3.md, sections 4 and 7) ---------------- */

vec3s texture_sample_bilinear(const ras_texture *tex, float u, float v) {
    static bool shown;
    ras_todo_notice(&shown, "texture_sample_bilinear",
                    "docs/hw3.md, section 4 (bilinear filtering)");
    /* TODO(hw3) 4.1 Make u, v safe first: NaN or ±Inf → 0; for
     *               RAS_WRAP_REPEAT keep the fraction u − floorf(u); for
     *               RAS_WRAP_CLAMP clamp to [0, 1]. Then even u = 1e30 can be
     *               converted to int without overflow.
     * TODO(hw3) 4.2 Continuous texel coordinates with the half-texel shift:
     *               x = u·W − 0.5, y = v·H − 0.5 (texel i's centre is at x = i;
     *               v = 0 is row j = 0, the bottom — the texture has already
     *               flipped the image, do not flip again).
     * TODO(hw3) 4.3 i0 = floor(x), sx = x − i0 (same for y); the four texels
     *               (i0, j0), (i0+1, j0), (i0, j0+1), (i0+1, j0+1) through
     *               ras_texture_texel(tex, 0, i, j), which wraps or clamps.
     * TODO(hw3) 4.4 Blend: lerp along x on both rows, then along y. */
    return ras_texture_sample_nearest(tex, u, v); /* placeholder: nearest */
}

vec3s texture_sample_trilinear(const ras_texture *tex, vec2s uv, vec2s duv_dx, vec2s duv_dy) {
    static bool shown;
    ras_todo_notice(&shown, "texture_sample_trilinear",
                    "docs/hw3.md, section 7 (bonus: trilinear mipmapping)");
    /* TODO(hw3, bonus) 7.1 ρ = max(|duv_dx ∘ (W, H)|, |duv_dy ∘ (W, H)|): how
     *                      many texels one screen pixel spans.
     * TODO(hw3, bonus) 7.2 L = log2(ρ), 0 when ρ <= 1; clamp to
     *                      tex->level_count − 1.
     * TODO(hw3, bonus) 7.3 Bilinear in levels ⌊L⌋ and ⌊L⌋+1 (sizes
     *                      tex->level_width/height[l], texels
     *                      ras_texture_texel(tex, l, i, j)), blended by L − ⌊L⌋. */
    (void)duv_dx;
    (void)duv_dy;
    return texture_sample_bilinear(tex, uv.x, uv.y); /* placeholder: bilinear */
}
