/* bump_lookups_test.c — the reference's bump and displacement shaders share
 * their texture lookups (issue 28: h(u, v) looked up once, the three bilinear
 * heights sharing two axes); they must give, bit for bit, what shading.h's
 * formulas give with one height_sample per height. RASTER101-SOLUTION: the
 * expected values below are those formulas written out, so this file never
 * ships in a handout (tests/bench/ is left out of it).
 *
 * Each case: a 7×5 texture of distinct colours (W ≠ H, so an axis that took
 * the other's size shows), wrap repeat and clamp, filters nearest, bilinear
 * and trilinear (which reads heights bilinearly), and uv on texel centres and
 * edges, at 0 and 1, just below 1 (u + 1/W wraps), negative, huge, NaN and
 * ±Inf. Counters must match too (texels fetched, stages run), but for the
 * height lookup displacement no longer repeats. Exit 0: all
 * equal; 1: the first case that differs, named.
 */
#include "shading.h"

#include <math.h>   /* NAN, INFINITY */
#include <stdio.h>  /* printf, fprintf */
#include <string.h> /* memcmp */

/* bump_normal as shading.h states it: one height_sample per height. */
static vec3s formula_bump_normal(const fragment_shader_payload *p) {
    vec3s n = glms_vec3_normalize(p->normal);
    if (!p->height_map) return n;
    if (p->counters) p->counters->stages_run |= RAS_STAGE_BUMP;
    vec3s t, b;
    tangent_frame(n, &t, &b);
    float u = p->uv.x, v = p->uv.y;
    float h = height_sample(p, u, v);
    float k = p->kh * p->kn;
    float du = k * (height_sample(p, u + 1.0f / (float)p->height_map->width, v) - h);
    float dv = k * (height_sample(p, u, v + 1.0f / (float)p->height_map->height) - h);
    vec3s q = glms_vec3_add(glms_vec3_scale(t, -du), glms_vec3_scale(b, -dv));
    vec3s bumped = glms_vec3_normalize(glms_vec3_add(q, n));
    return ras_vec3_finite(bumped) ? bumped : n;
}

/* displacement_fragment_shader as shading.h states it. */
static vec3s formula_displacement(const fragment_shader_payload *p) {
    vec3s n = glms_vec3_normalize(p->normal);
    float h = height_sample(p, p->uv.x, p->uv.y);
    vec3s point = glms_vec3_muladds(n, p->kn * h, p->view_pos);
    return blinn_phong_lighting(p, p->color, point, formula_bump_normal(p));
}

static ras_texture *distinct_texture(ras_wrap wrap) {
    ras_image *img = ras_image_create(7, 5, NULL);
    if (!img) return NULL;
    for (int r = 0; r < 5; r++)
        for (int c = 0; c < 7; c++)
            ras_image_set(
                img, c, r,
                (vec3s){{0.1f + 0.11f * c, 0.9f - 0.13f * r, 0.05f * (float)((c * 3 + r) % 7)}});
    ras_texture *tex = ras_texture_from_image(img, wrap, NULL);
    ras_image_destroy(img);
    return tex;
}

static bool same_counters(const ras_counters *a, const ras_counters *b) {
    return a->texels_fetched == b->texels_fetched && a->stages_run == b->stages_run;
}

int main(void) {
    const float coords[] = {0.0f,  1.0f / 14,  1.0f / 7, 0.5f,     0.3f,     1.0f - 1.0f / 7,
                            0.99f, 0.9999999f, 1.0f,     -0.3f,    -1e-8f,   2.75f,
                            1e30f, -1e30f,     NAN,      INFINITY, -INFINITY};
    const int nc = (int)(sizeof coords / sizeof coords[0]);
    const texture_filter filters[] = {FILTER_NEAREST, FILTER_BILINEAR, FILTER_TRILINEAR};
    const ras_wrap wraps[] = {RAS_WRAP_REPEAT, RAS_WRAP_CLAMP};
    int cases = 0;
    for (int w = 0; w < 2; w++) {
        ras_texture *hm = distinct_texture(wraps[w]);
        if (!hm) {
            fprintf(stderr, "bump_lookups_test: out of memory for a 7x5 texture\n");
            return 1;
        }
        for (int f = 0; f < 3; f++)
            for (int i = 0; i < nc; i++)
                for (int j = 0; j < nc; j++) {
                    fragment_shader_payload p = {0};
                    p.view_pos = (vec3s){{0.3f, -0.2f, -10.0f}};
                    p.normal = (vec3s){{0.36f, 0.48f, 0.8f}};
                    p.color = (vec3s){{0.5f, 0.6f, 0.7f}};
                    p.ka = (vec3s){{0.005f, 0.005f, 0.005f}};
                    p.ambient_intensity = (vec3s){{10, 10, 10}};
                    p.ks = (vec3s){{0.3f, 0.3f, 0.3f}};
                    p.p = 150;
                    p.kh = 0.2f;
                    p.kn = 0.1f;
                    p.filter = filters[f];
                    p.height_map = hm;
                    p.lights[0] = (light){{{20, 20, 20}}, {{500, 500, 500}}};
                    p.light_count = 1;
                    p.uv = (vec2s){{coords[i], coords[j]}};
                    /* bump: the same counts; displacement: one height lookup fewer */
                    ras_counters got_k = {0}, want_k = {0}, got_dk = {0}, want_dk = {0};
                    p.counters = &got_k;
                    vec3s got_n = bump_normal(&p);
                    p.counters = &got_dk;
                    vec3s got_c = displacement_fragment_shader(&p);
                    p.counters = &want_k;
                    vec3s want_n = formula_bump_normal(&p);
                    p.counters = &want_dk;
                    vec3s want_c = formula_displacement(&p);
                    want_dk.texels_fetched -= filters[f] == FILTER_NEAREST ? 1 : 4;
                    cases++;
                    if (memcmp(&got_n, &want_n, sizeof got_n) ||
                        memcmp(&got_c, &want_c, sizeof got_c) || !same_counters(&got_k, &want_k) ||
                        !same_counters(&got_dk, &want_dk)) {
                        fprintf(
                            stderr,
                            "bump_lookups_test: wrap %s, filter %d, uv (%g, %g): expected the "
                            "formula's normal (%.9g, %.9g, %.9g) and colour (%.9g, %.9g, %.9g), "
                            "texels %llu and %llu (bump, displacement); the reference gave "
                            "(%.9g, %.9g, %.9g), (%.9g, %.9g, %.9g), texels %llu and %llu. "
                            "The shared lookups in "
                            "hw3_shading/solution/shading.c (bump_heights, bumped_normal) no "
                            "longer compute what height_sample does\n",
                            w ? "clamp" : "repeat", (int)filters[f], coords[i], coords[j], want_n.x,
                            want_n.y, want_n.z, want_c.x, want_c.y, want_c.z,
                            (unsigned long long)want_k.texels_fetched,
                            (unsigned long long)want_dk.texels_fetched, got_n.x, got_n.y, got_n.z,
                            got_c.x, got_c.y, got_c.z, (unsigned long long)got_k.texels_fetched,
                            (unsigned long long)got_dk.texels_fetched);
                        ras_texture_destroy(hm);
                        return 1;
                    }
                }
        ras_texture_destroy(hm);
    }
    printf("bump_lookups_test: %d cases, bump_normal and displacement bit-identical to "
           "shading.h's formulas\n",
           cases);
    return 0;
}
