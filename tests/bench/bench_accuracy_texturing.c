/* bench_accuracy_texturing.c — sections 3 and 4 of the accuracy report:
 * affine vs perspective-correct interpolation on a receding plane (against
 * the analytic ray–plane UV) and nearest / bilinear / trilinear texture
 * filtering on a receding floor (against supersampled level 0).
 * bench_accuracy.h.
 */
#include "bench_accuracy.h"
#include "ras_texture.h"
#include "rasterizer.h" /* hw2 reference: rasterize_triangle */
#include "scene.h"      /* hw3: hw3_frame, hw3_frame_shade */
#include "shading.h"    /* hw3 reference: texture_sample_bilinear, ... */
#include "transform.h"  /* hw1 reference: get_projection_matrix */

#include <math.h>   /* sqrt, fabs, tan, isinf */
#include <stdlib.h> /* malloc, free */

/* Section 3's error pass: the interpolated UV itself as the colour. */
static vec3s shader_uv(const fragment_shader_payload *payload) {
    return (vec3s){{payload->uv.x, payload->uv.y, 0}};
}

/* The timed frames of sections 3 and 4: one texture lookup, no lighting. */
static vec3s shader_unlit_texture(const fragment_shader_payload *payload) {
    return texture_sample(payload, payload->texture, payload->uv);
}

/* ---- section 3: interpolation ------------------------------------------------- */

/* A rectangle receding from view depth w0 = 1 (bottom of the screen) to
 * w1 = k (top), its sides along the view's x: v runs near → far, u across.
 * Along its long edges v changes from 0 to 1 while w goes from w0 to w1, the
 * case of the formula (√k − 1)/(√k + 1). */
static acc_quad receding_rect(double k) {
    double t = tan(ACC_FOV_DEG * RAS_PI / 360.0), w0 = 1, w1 = k, a = 0.9 * w0 * t;
    double y0 = -0.9 * w0 * t, y1 = 0.9 * w1 * t;
    acc_quad q = {.p = {{-a, y0, -w0}, {a, y0, -w0}, {a, y1, -w1}, {-a, y1, -w1}},
                  .uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    return q;
}

/* The textured plane's pipeline: one sample, hw2's rasterizer, the core's
 * fragment stage with hw3's interpolation (affine unless persp) handing the
 * UVs to `frame`'s shader, on black. */
static ras_pipeline *plane_pipeline(int size, hw3_frame *frame, bool persp) {
    ras_error err = {{0}};
    ras_pipeline_config cfg = {.width = size,
                               .height = size,
                               .pattern = ras_sample_pattern_center(),
                               .varyings = frame->varyings,
                               .rasterize = rasterize_triangle,
                               .resolve = resolve_pixel,
                               .interpolate_vec3 = interpolate_vec3,
                               .interpolate_vec2 = interpolate_vec2,
                               .affine = !persp,
                               .uv_gradients = frame->payload.filter == FILTER_TRILINEAR,
                               .shader = hw3_frame_shade,
                               .shader_user = frame};
    ras_pipeline *p = ras_pipeline_create(&cfg, &err);
    if (!p) {
        fprintf(stderr, "bench_accuracy: %s\n", err.msg);
        exit(2);
    }
    return p;
}

/* A frame of the one plane mesh *m, in view space already, through `proj`. */
static acc_mesh_frame plane_frame(int size, hw3_frame *frame, bool persp, ras_mesh *const *m,
                                  mat4s proj, ras_image *img) {
    return (acc_mesh_frame){.p = plane_pipeline(size, frame, persp),
                            .meshes = m,
                            .mesh_count = 1,
                            .view = *acc_identity(),
                            .projection = proj,
                            .img = img};
}

void texturing_interpolation(void) {
    static const double ks[4] = {1.1, 2, 4, 8};
    const int size = acc_opt.quick ? 128 : 512, texels = 256;
    ras_texture *tex = ras_texture_create_checker(texels, 8, (vec3s){{0.9f, 0.9f, 0.9f}},
                                                  (vec3s){{0.1f, 0.1f, 0.1f}});
    ras_image *img = ras_image_create(size, size, NULL);
    acc_die_oom(tex), acc_die_oom(img);
    mat4s proj = get_projection_matrix(ACC_FOV_DEG, 1, ACC_Z_NEAR, 100);
    for (int ki = 0; ki < 4; ki++) {
        double k = ks[ki];
        acc_quad q = receding_rect(k);
        ras_mesh *m = truth_quad_mesh(&q);
        char scene[40];
        snprintf(scene, sizeof scene, "w1/w0 = %g", k);
        /* Time: the plane with an unlit bilinear texture, both modes in turn. */
        hw3_frame ts[2];
        acc_timed t[2];
        for (int persp = 0; persp < 2; persp++) {
            ts[persp] = (hw3_frame){.shader = shader_unlit_texture,
                                    .varyings = RAS_VARYING_UV,
                                    .payload = {.texture = tex, .filter = FILTER_BILINEAR}};
            t[persp].f = plane_frame(size, &ts[persp], persp, &m, proj, img);
            t[persp].r = acc_new_row("interp", scene,
                                     persp ? "perspective-correct" : "affine (screen-space)");
        }
        acc_progress("interp / %s: timing", scene);
        acc_time_group(t, 2);
        for (int persp = 0; persp < 2; persp++) {
            ras_pipeline_destroy(t[persp].f.p);
            acc_row *r = t[persp].r;
            acc_mesh_frame f = t[persp].f;
            /* Error: the interpolated UV itself, against the ray-plane hit. */
            hw3_frame us = {.shader = shader_uv, .varyings = RAS_VARYING_UV};
            f.p = plane_pipeline(size, &us, persp);
            acc_draw_mesh_frame(&f);
            double v_max = 0, uv_max = 0, sum2 = 0;
            long n = 0;
            for (int y = 0; y < size; y++)
                for (int x = 0; x < size; x++) {
                    double d[3], depth, uv[2];
                    int i = ras_fb_pixel_index(f.p->fb, x, y);
                    if (isinf(f.p->fb->depth[i])) continue;
                    truth_pixel_ray(x, y, 0.5, 0.5, size, d);
                    if (!truth_quad_hit(&q, d, &depth, uv)) continue;
                    vec3s got = f.p->fb->color[i];
                    double du = got.x - uv[0], dv = got.y - uv[1];
                    v_max = fmax(v_max, fabs(dv));
                    uv_max = fmax(uv_max, sqrt(du * du + dv * dv));
                    sum2 += du * du + dv * dv;
                    n++;
                }
            r->v_max = v_max;
            r->formula = (sqrt(k) - 1) / (sqrt(k) + 1);
            r->uv_max_texels = uv_max * texels;
            r->uv_rms_texels = n ? sqrt(sum2 / n) * texels : NAN;
            ras_pipeline_destroy(f.p);
            if (persp)
                acc_check(r->uv_max_texels < 0.05,
                          "interp %s: perspective-correct UV error %.4f texels < 0.05", scene,
                          r->uv_max_texels);
            else
                acc_check(v_max > 0.9 * r->formula && v_max < 1.02 * r->formula + 1e-4,
                          "interp %s: affine worst v error %.4f within [0.9, 1.02] x formula %.4f",
                          scene, v_max, r->formula);
        }
        ras_mesh_destroy(m);
    }
    ras_image_destroy(img);
    ras_texture_destroy(tex);
}

/* ---- section 4: texture filtering ---------------------------------------------- */

void texturing_filtering(void) {
    const int size = acc_opt.quick ? 128 : 512, ss = acc_opt.quick ? 8 : 16;
    ras_texture *tx[2] = {ras_texture_create_checker(256, 8, (vec3s){{0.92f, 0.9f, 0.85f}},
                                                     (vec3s){{0.12f, 0.14f, 0.2f}}),
                          ras_texture_create_brick(256)};
    static const char *tex_names[2] = {"checker", "brick"};
    ras_image *img = ras_image_create(size, size, NULL);
    vec3s *truth = malloc((size_t)size * size * sizeof *truth);
    bool *valid = malloc((size_t)size * size * sizeof *valid);
    acc_die_oom(tx[0]), acc_die_oom(tx[1]), acc_die_oom(img), acc_die_oom(truth),
        acc_die_oom(valid);
    /* The floor y = -1 from depth 1 to 40, 40 wide; one texture tile per 8 units. */
    const double tile = 8, zf = 40;
    acc_quad q = {
        .p = {{-20, -1, -1}, {20, -1, -1}, {20, -1, -zf}, {-20, -1, -zf}},
        .uv = {{0, 0}, {40 / tile, 0}, {40 / tile, (zf - 1) / tile}, {0, (zf - 1) / tile}}};
    ras_mesh *m = truth_quad_mesh(&q);
    mat4s proj = get_projection_matrix(ACC_FOV_DEG, 1, ACC_Z_NEAR, 100);
    for (int ti = 0; ti < 2; ti++) {
        ras_texture *tex = tx[ti];
        tex->wrap = RAS_WRAP_REPEAT;
        char scene[40];
        snprintf(scene, sizeof scene, "floor, %s %d", tex_names[ti], tex->width);
        acc_progress("filter / %s: ground truth (%dx%d bilinear samples per pixel)", scene, ss, ss);
        long nvalid = 0;
        for (int y = 0; y < size; y++)
            for (int x = 0; x < size; x++) {
                int i = (size - 1 - y) * size + x;
                vec3s sum = {{0, 0, 0}};
                bool all = true;
                for (int sy = 0; sy < ss && all; sy++)
                    for (int sx = 0; sx < ss && all; sx++) {
                        double d[3], depth, uv[2];
                        truth_pixel_ray(x, y, (sx + 0.5) / ss, (sy + 0.5) / ss, size, d);
                        all = truth_quad_hit(&q, d, &depth, uv);
                        if (all)
                            sum = glms_vec3_add(
                                sum, texture_sample_bilinear(tex, (float)uv[0], (float)uv[1]));
                    }
                valid[i] = all;
                nvalid += all;
                truth[i] = glms_vec3_scale(sum, 1.0f / (float)(ss * ss));
            }
        ras_texture_build_mips(tex);
        static const texture_filter filters[3] = {FILTER_NEAREST, FILTER_BILINEAR,
                                                  FILTER_TRILINEAR};
        hw3_frame st[3];
        acc_timed t[3];
        for (int fi = 0; fi < 3; fi++) {
            st[fi] = (hw3_frame){.shader = shader_unlit_texture,
                                 .varyings = RAS_VARYING_UV,
                                 .payload = {.texture = tex, .filter = filters[fi]}};
            t[fi].f = plane_frame(size, &st[fi], true, &m, proj, img);
            t[fi].r = acc_new_row("filter", scene, ras_scene_filter_name(filters[fi]));
        }
        acc_progress("filter / %s: timing nearest, bilinear, trilinear", scene);
        acc_time_group(t, 3);
        for (int fi = 0; fi < 3; fi++) {
            acc_row *r = t[fi].r;
            acc_draw_mesh_frame(&t[fi].f);
            ras_pipeline_destroy(t[fi].f.p);
            double s2 = 0;
            for (int i = 0; i < size * size; i++) {
                if (!valid[i]) continue;
                for (int c = 0; c < 3; c++) {
                    double dd = (double)img->pixels[i].raw[c] - truth[i].raw[c];
                    s2 += dd * dd / 3;
                }
            }
            r->rmse_all = nvalid ? sqrt(s2 / nvalid) : NAN;
            r->psnr_all = acc_psnr(r->rmse_all);
        }
        acc_row *rn = acc_find_row("filter", scene, "nearest"),
                *rb = acc_find_row("filter", scene, "bilinear");
        acc_row *rt = acc_find_row("filter", scene, "trilinear");
        acc_check(rt->rmse_all < rn->rmse_all && rt->rmse_all < rb->rmse_all,
                  "filter %s: trilinear RMSE %.4f < bilinear %.4f and nearest %.4f", scene,
                  rt->rmse_all, rb->rmse_all, rn->rmse_all);
    }
    ras_mesh_destroy(m);
    free(truth), free(valid);
    ras_image_destroy(img);
    ras_texture_destroy(tx[0]), ras_texture_destroy(tx[1]);
}
