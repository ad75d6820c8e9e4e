/* fuzz_pipeline.c — the triangle pipeline fed arbitrary floats.
 *
 * Input: byte 0 = configuration (bits 0-1 anti-aliasing none/MSAA/SSAA,
 * bit 2 ordered/standard pattern, bits 3-4 culling, bit 5 unused (it chose
 * float edge functions, which the reference no longer offers),
 * bit 6 a perspective-correct hw3 shader instead of vertex colours, bit 7
 * the inverse_w depth format instead of z01); then
 * triangles of 3 clip-space vertices, each 15 raw floats: p_clip (4), colour
 * (3), normal (3), uv (2), view_pos (3). Drawn through the reference
 * pipeline (clip, setup, hw2's rasterizer and resolve) into 12x10 pixels.
 * Invariants: no crash or undefined behaviour; every triangle is counted in;
 * every stored depth is +Inf (untouched) or in [0, 1] (vertex depths are
 * clamped there; interpolation adds at most a rounding error above 1). */
#include "fuzz_target.h"

#include "ras_pipeline.h"
#include "rasterizer.h"
#include "shading.h"

#include <math.h>   /* isinf */
#include <string.h> /* memcpy */

#define FLOATS_PER_VERTEX 15
#define W 12
#define H 10

static vec3s fuzz_shade(const ras_triangle *t, const ras_fragment *f, void *user) {
    (void)user;
    fragment_shader_payload p = {0};
    p.normal = glms_vec3_normalize(interpolate_vec3(t, f->bary, t->normal, true));
    p.uv = interpolate_vec2(t, f->bary, t->uv, true);
    p.view_pos = interpolate_vec3(t, f->bary, t->view_pos, true);
    return normal_fragment_shader(&p);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    unsigned cfg_bits = data[0];
    data++, size--;
    ras_pipeline_config cfg = {
        .width = W,
        .height = H,
        .aa = (ras_aa_mode)((cfg_bits & 3) % 3),
        .cull = (ras_cull_mode)(((cfg_bits >> 3) & 3) % 3),
        .varyings = RAS_VARYING_COLOR | RAS_VARYING_NORMAL | RAS_VARYING_UV,
        .rasterize = rasterize_triangle,
        .resolve = resolve_pixel,
        .shade = (cfg_bits & 64) ? fuzz_shade : NULL,
        .depth = (cfg_bits & 128) ? RAS_DEPTH_INV_W : RAS_DEPTH_Z01,
        .z_near = 0.1f, /* inverse_w stores -z_near / w */
    };
    if (cfg.aa != RAS_AA_NONE &&
        !ras_sample_pattern_make((cfg_bits & 4) ? RAS_PATTERN_STANDARD : RAS_PATTERN_ORDERED, 4,
                                 &cfg.pattern, NULL))
        return 0;
    ras_pipeline *p = ras_pipeline_create(&cfg, NULL);
    fuzz_check(p != NULL, "a valid configuration was refused");
    size_t vertex_bytes = FLOATS_PER_VERTEX * sizeof(float);
    size_t tris = size / (3 * vertex_bytes);
    if (tris > 64) tris = 64;
    for (size_t i = 0; i < tris; i++) {
        ras_clip_vertex v[3] = {0};
        for (int k = 0; k < 3; k++) {
            float f[FLOATS_PER_VERTEX];
            memcpy(f, data + (3 * i + (size_t)k) * vertex_bytes, vertex_bytes);
            v[k].p_clip = (vec4s){{f[0], f[1], f[2], f[3]}};
            /* Both ways a position reaches the clipper: the float one alone,
             * or with its double product (stage1_vertex.h), here the float
             * widened, as a vertex whose float chain was accurate. */
            v[k].exact = (cfg_bits & 32) != 0;
            for (int j = 0; j < 4; j++)
                v[k].p_exact[j] = f[j];
            v[k].color = (vec3s){{f[4], f[5], f[6]}};
            v[k].normal = (vec3s){{f[7], f[8], f[9]}};
            v[k].uv = (vec2s){{f[10], f[11]}};
            v[k].view_pos = (vec3s){{f[12], f[13], f[14]}};
        }
        ras_pipeline_draw_clip_triangle(p, &v[0], &v[1], &v[2]);
    }
    const ras_counters *c = &p->counters;
    fuzz_check(c->triangles_in == tris, "%llu triangles counted in, %zu drawn",
               (unsigned long long)c->triangles_in, tris);
    const ras_framebuffer *fb = p->fb;
    for (size_t i = 0; i < (size_t)fb->width * fb->height * fb->samples; i++) {
        float z = fb->depth[i];
        /* Each format's range (stage3_setup.h), or the +inf of a cleared
         * sample. Vertices are clamped to the range; a sample's depth is their
         * barycentric mix. The reference's edge functions are exact (fixed
         * point: vertices snapped to 1/256 px), so the barycentrics are exact
         * ratios rounded to float and sum to 1 within a few ulp: 1e-6 slack
         * at the ends (fuzz_pipeline found -1.00000012 with inverse_w). */
        float lo = cfg.depth == RAS_DEPTH_INV_W ? -1.0f - 1e-6f : 0.0f;
        float hi = cfg.depth == RAS_DEPTH_INV_W ? 0.0f : 1.0f + 1e-6f;
        fuzz_check((isinf(z) && z > 0) || (z >= lo && z <= hi), "depth %.9g stored at %zu (%s)",
                   (double)z, i, ras_depth_format_name(cfg.depth));
    }
    ras_image *img = ras_image_create(W, H, NULL);
    if (img) {
        ras_pipeline_end_frame(p, img);
        ras_image_destroy(img);
    }
    ras_pipeline_destroy(p);
    return 0;
}
