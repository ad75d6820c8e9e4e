/* scene.c — see scene.h.
 *
 * Given code, no TODO. Worth reading: hw3_shade_fragment (what your shaders
 * are handed: which varyings, interpolated with your interpolate_*, and the
 * trilinear footprint) and hw3_render (one frame, object by object). The
 * names, the options and the window's buffers you can skip. Leave it as it
 * is: the grader takes only shading.c from a submission.
 */
#include "scene.h"

#include "ras_dump.h"

#include "rasterizer.h" /* hw2: rasterize_triangle, resolve_pixel */
#include "transform.h"  /* hw1: get_projection_matrix */

#include "ras_names.h" /* the shader and filter spellings */

#include <math.h>   /* INFINITY */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* calloc, free */
#include <string.h> /* strcmp */

/* ---- names --------------------------------------------------------------- */

/* The spellings are ras_names.h's; hw3's shaders are the core's from normal on. */

bool hw3_shader_parse(const char *name, ras_scene_shader *out, ras_error *err) {
    int i = ras_name_find(&ras_names_shader, name, RAS_SHADER_NORMAL);
    if (i >= 0) {
        *out = (ras_scene_shader)i;
        return true;
    }
    char list[96];
    return ras_error_set(err, "--shader expects %s; got '%s'",
                         ras_names_list(&ras_names_shader, RAS_SHADER_NORMAL, list, sizeof list),
                         name);
}

fragment_shader_fn hw3_shader_function(ras_scene_shader shader) {
    switch (shader) {
    case RAS_SHADER_NORMAL: return normal_fragment_shader;
    case RAS_SHADER_PHONG: return phong_fragment_shader;
    case RAS_SHADER_TEXTURE: return texture_fragment_shader;
    case RAS_SHADER_BUMP: return bump_fragment_shader;
    case RAS_SHADER_DISPLACEMENT: return displacement_fragment_shader;
    case RAS_SHADER_FLAT: break;
    }
    return NULL;
}

unsigned hw3_shader_varyings(ras_scene_shader shader) {
    switch (shader) {
    case RAS_SHADER_NORMAL: return RAS_VARYING_NORMAL;
    case RAS_SHADER_PHONG: return RAS_VARYING_NORMAL | RAS_VARYING_VIEW_POS;
    case RAS_SHADER_TEXTURE:
    case RAS_SHADER_DISPLACEMENT: return RAS_VARYING_NORMAL | RAS_VARYING_VIEW_POS | RAS_VARYING_UV;
    case RAS_SHADER_BUMP: return RAS_VARYING_NORMAL | RAS_VARYING_UV;
    case RAS_SHADER_FLAT: break;
    }
    return 0;
}

bool hw3_filter_parse(const char *name, texture_filter *out, ras_error *err) {
    int i = ras_name_find(&ras_names_filter, name, 0);
    if (i >= 0) {
        *out = (texture_filter)i;
        return true;
    }
    char list[96];
    return ras_error_set(err, "--filter expects %s; got '%s'",
                         ras_names_list(&ras_names_filter, 0, list, sizeof list), name);
}

/* ---- the fragment stage --------------------------------------------------- */

/* Screen barycentrics are affine in (x, y): their change per pixel step is
 * constant over the triangle. λ0 = E(v1, v2, p) / area2, and so on, with
 * E(a, b, p) = (b.x − a.x)(p.y − a.y) − (b.y − a.y)(p.x − a.x). */
static void bary_gradients(const ras_triangle *t, vec3s *d_dx, vec3s *d_dy) {
    float area2 = ras_triangle_area2(t);
    float inv = area2 != 0.0f ? 1.0f / area2 : 0.0f;
    const vec4s *v = t->v;
    *d_dx = (vec3s){{-(v[2].y - v[1].y) * inv, -(v[0].y - v[2].y) * inv,
                     -(v[1].y - v[0].y) * inv}};
    *d_dy = (vec3s){{(v[2].x - v[1].x) * inv, (v[0].x - v[2].x) * inv,
                     (v[1].x - v[0].x) * inv}};
}

vec3s hw3_shade_fragment(const ras_triangle *t, const ras_fragment *f, void *user) {
    /* The varyings are written into the stage's own payload, in place: the
     * per-object fields around them stay as set, and copying the whole
     * payload (its lights included) for every fragment cost more than the
     * normal shader itself. */
    hw3_fragment_stage *stage = user;
    fragment_shader_payload *payload = &stage->base;
    bool persp = stage->perspective;
    uint64_t interpolated = 0;
    if (stage->varyings & RAS_VARYING_NORMAL) {
        /* Interpolated unit normals are shorter than 1 between the vertices. */
        payload->normal = glms_vec3_normalize(interpolate_vec3(t, f->bary, t->normal, persp));
        interpolated++;
    }
    if (stage->varyings & RAS_VARYING_VIEW_POS) {
        payload->view_pos = interpolate_vec3(t, f->bary, t->view_pos, persp);
        interpolated++;
    }
    if (stage->varyings & RAS_VARYING_UV) {
        payload->uv = interpolate_vec2(t, f->bary, t->uv, persp);
        interpolated++;
        if (payload->filter == FILTER_TRILINEAR) {
            /* The UV one pixel to the right and one pixel up, from the same
             * triangle's (extrapolated) barycentrics: a finite difference of
             * the perspective-correct UV, like a GPU's 2×2 quad. */
            vec3s d_dx, d_dy;
            bary_gradients(t, &d_dx, &d_dy);
            vec2s uv_x = interpolate_vec2(t, glms_vec3_add(f->bary, d_dx), t->uv, persp);
            vec2s uv_y = interpolate_vec2(t, glms_vec3_add(f->bary, d_dy), t->uv, persp);
            payload->duv_dx = glms_vec2_sub(uv_x, payload->uv);
            payload->duv_dy = glms_vec2_sub(uv_y, payload->uv);
        }
    }
    if (payload->counters) payload->counters->varyings_interpolated += interpolated;
    hw3_gbuffer *g = stage->gbuffer;
    if (g && f->x >= 0 && f->x < g->width && f->y >= 0 && f->y < g->height) {
        size_t i = (size_t)(g->height - 1 - f->y) * (size_t)g->width + (size_t)f->x;
        if (g->normal)
            for (int k = 0; k < 3; k++)
                g->normal[3 * i + k] = payload->normal.raw[k];
        if (g->uv) {
            g->uv[3 * i] = payload->uv.x;
            g->uv[3 * i + 1] = payload->uv.y;
            g->uv[3 * i + 2] = 0.0f;
        }
        if (g->view_depth) g->view_depth[i] = -payload->view_pos.z;
    }
    return stage->shader(payload);
}

/* ---- the scene's objects, as the shaders see them -------------------------- */

mat4s hw3_object_model(const ras_scene_object *so, float angle_deg) {
    return ras_scene_model_matrix(so, (ras_scene_spin){.turn_y_deg = angle_deg});
}

void hw3_object_material(const ras_scene *scene, const ras_scene_assets *assets, int i,
                         fragment_shader_payload *payload) {
    const ras_scene_material *m = &scene->objects[i].material;
    payload->color = m->kd_set ? m->kd : m->color;
    payload->texture = assets->textures[i];
    payload->height_map = assets->height_maps[i];
    payload->kh = m->kh;
    payload->kn = m->kn;
    payload->ka = m->ka;
    payload->ks = m->ks;
    payload->p = m->p;
}

/* ---- one frame -------------------------------------------------------------- */

hw3_render_options hw3_render_defaults(void) {
    return (hw3_render_options){.shader = RAS_SHADER_NORMAL,
                                .filter = FILTER_BILINEAR,
                                .aa = RAS_AA_NONE,
                                .pattern = ras_sample_pattern_center(),
                                .cull = RAS_CULL_NONE,
                                .depth = RAS_DEPTH_Z01};
}

hw3_render_options hw3_render_options_from_ras(const ras_scene *rs) {
    hw3_render_options opt = hw3_render_defaults();
    if (hw3_shader_function(rs->shader)) opt.shader = rs->shader; /* flat: the default */
    opt.filter = rs->filter;
    opt.aa = rs->aa;
    opt.pattern = rs->aa == RAS_AA_NONE ? ras_sample_pattern_center() : rs->pattern;
    opt.cull = rs->cull;
    opt.depth = rs->depth;
    return opt;
}

unsigned hw3_frame_varyings(const ras_scene *scene, const ras_scene_assets *assets,
                            ras_scene_shader shader) {
    unsigned v = hw3_shader_varyings(shader);
    bool maps = false; /* does any object have a map this shader reads? */
    for (int i = 0; i < scene->object_count; i++)
        maps |= shader == RAS_SHADER_TEXTURE ? assets->textures[i] != NULL
                                             : assets->height_maps[i] != NULL;
    if (!maps) v &= ~(unsigned)RAS_VARYING_UV;
    /* The view position only places the shaded point relative to the lights
     * (with none, Blinn-Phong is the ambient term alone). */
    if (scene->light_count == 0) v &= ~(unsigned)RAS_VARYING_VIEW_POS;
    return v;
}

/* The buffers for `varyings`, every entry +INF; false on out of memory
 * (what was made is freed). */
static bool gbuffer_create(hw3_gbuffer *g, int width, int height, unsigned varyings) {
    size_t n = (size_t)width * (size_t)height;
    *g = (hw3_gbuffer){.width = width, .height = height};
    float **arrays[3] = {&g->normal, &g->uv, &g->view_depth};
    const unsigned need[3] = {RAS_VARYING_NORMAL, RAS_VARYING_UV, RAS_VARYING_VIEW_POS};
    const size_t channels[3] = {3, 3, 1};
    for (int k = 0; k < 3; k++) {
        if (!(varyings & need[k])) continue;
        float *a = malloc(n * channels[k] * sizeof *a);
        if (!a) {
            hw3_gbuffer_release(g);
            return false;
        }
        for (size_t i = 0; i < n * channels[k]; i++)
            a[i] = INFINITY;
        *arrays[k] = a;
    }
    return true;
}

void hw3_gbuffer_release(hw3_gbuffer *g) {
    free(g->normal);
    free(g->uv);
    free(g->view_depth);
    *g = (hw3_gbuffer){0};
}

hw3_render_options hw3_app_render_options(const ras_app *app) {
    const ras_app_settings *s = &app->set;
    hw3_render_options opt = hw3_render_options_from_ras(app->scene);
    opt.shader = s->shader;
    opt.filter = s->filter;
    opt.aa = s->aa;
    opt.pattern = ras_app_settings_pattern(s);
    opt.depth = s->depth;
    opt.angle_deg = s->angle;
    opt.affine = s->affine;
    opt.dump_dir = app->cli.dump;
    opt.step = app->step.on;
    opt.step_triangles = app->step.limit;
    opt.keep_buffers = ras_app_capturing(app);
    return opt;
}

/* The fragment stage's buffers, in the words of their --dump sidecars. */
static const ras_dump_buffer gbuffer_kinds[3] = {
    {.name = "normal",
     .what = "the unit normal each pixel's shader got (interpolated, normalised), view space",
     .units = "unit vector: x right, y up, z towards the eye",
     .channels = 3,
     .style = RAS_DUMP_VECTOR},
    {.name = "uv",
     .what = "the texture coordinates each pixel's shader got (perspective-correct unless "
             "--affine); the third channel is 0",
     .units = "u, v in texture space (1 = the texture's width, height)",
     .channels = 3,
     .style = RAS_DUMP_UNIT},
    {.name = "view_depth",
     .what = "how far in front of the eye each pixel's shaded point is: -z of its "
             "interpolated view-space position",
     .units = "scene units",
     .channels = 1,
     .style = RAS_DUMP_SCALAR},
};

/* Buffer k of the table with g's data; false when the frame made none. */
static bool gbuffer_entry(const hw3_gbuffer *g, int k, ras_dump_buffer *out) {
    const float *data[3] = {g->normal, g->uv, g->view_depth};
    if (!data[k]) return false;
    *out = gbuffer_kinds[k];
    out->width = g->width, out->height = g->height, out->samples = 1;
    out->data = data[k];
    out->empty = INFINITY, out->has_empty = true; /* nothing shaded there */
    return true;
}

bool hw3_gbuffer_view(const hw3_gbuffer *g, const char *name, ras_dump_buffer *out) {
    for (int k = 0; k < 3; k++)
        if (!strcmp(name, gbuffer_kinds[k].name)) return gbuffer_entry(g, k, out);
    return false;
}

bool hw3_gbuffer_dump(const hw3_gbuffer *g, const char *dir, ras_error *err) {
    ras_dump_buffer b;
    for (int k = 0; k < 3; k++)
        if (gbuffer_entry(g, k, &b) && !ras_dump_write(dir, &b, err)) return false;
    return true;
}

static bool shader_reads_texture(ras_scene_shader shader) { return shader == RAS_SHADER_TEXTURE; }

bool hw3_frame_setup(const ras_scene *scene, ras_scene_assets *assets,
                     const hw3_render_options *opt, hw3_frame *frame, ras_error *err) {
    fragment_shader_fn shader = hw3_shader_function(opt->shader);
    if (!shader) {
        char list[96];
        return ras_error_set(
            err, "hw3 has no shader \"%s\"%s: expected %s (--shader, or the scene's \"shader\")",
            ras_scene_shader_name(opt->shader),
            opt->shader == RAS_SHADER_FLAT ? " (hw2's unlit colour)" : "",
            ras_names_list(&ras_names_shader, RAS_SHADER_NORMAL, list, sizeof list));
    }
    uint64_t mip_levels = 0;
    /* Mip levels only when trilinear filtering reads a colour map, once. */
    if (opt->filter == FILTER_TRILINEAR && shader_reads_texture(opt->shader)) {
        for (int i = 0; i < scene->object_count; i++)
            if (!ras_scene_assets_build_mips(scene, assets, i, &mip_levels, err)) return false;
    }
    *frame = (hw3_frame){.mip_levels = mip_levels};
    hw3_fragment_stage *stage = &frame->stage;
    *stage = (hw3_fragment_stage){.shader = shader,
                                  .varyings = hw3_frame_varyings(scene, assets, opt->shader),
                                  .perspective = !opt->affine};
    fragment_shader_payload *b = &stage->base;
    b->filter = opt->filter; /* the material (ka, ks, p, ...) is set per object */
    mat4s view = ras_scene_view_matrix(scene);
    /* Every scene file's lights fit (RAS_SCENE_MAX_LIGHTS). */
    _Static_assert(HW3_MAX_LIGHTS >= RAS_SCENE_MAX_LIGHTS, "hw3 must take every scene's lights");
    b->light_count = scene->light_count;
    for (int i = 0; i < scene->light_count; i++) {
        const ras_scene_light *l = &scene->lights[i];
        /* The shaders work in view space (shading.h): world lights move there. */
        vec3s pos = l->in_world ? ras_mat4_mulv3(view, l->position, 1.0f) : l->position;
        b->lights[i] = (light){pos, l->intensity};
    }
    b->ambient_intensity = scene->ambient;
    const ras_scene_camera *cam = &scene->camera;
    frame->view = view;
    frame->projection = (opt->projection ? opt->projection : get_projection_matrix)(
        cam->fov_deg, (float)scene->width / (float)scene->height, cam->z_near, cam->z_far);
    return true;
}

ras_pipeline_config hw3_frame_config(const ras_scene *scene, const hw3_render_options *opt,
                                     hw3_fragment_stage *stage) {
    return (ras_pipeline_config){.width = scene->width,
                                 .height = scene->height,
                                 .clear_color = scene->clear_color,
                                 .aa = opt->aa,
                                 .pattern = opt->pattern,
                                 .cull = opt->cull,
                                 .depth = opt->depth,
                                 .z_near = scene->camera.z_near,
                                 .z_far = scene->camera.z_far,
                                 .varyings = stage->varyings,
                                 .rasterize = rasterize_triangle,
                                 .resolve = resolve_pixel,
                                 .shade = hw3_shade_fragment,
                                 .shade_user = stage,
                                 .dump = opt->dump_dir != NULL || opt->keep_buffers,
                                 .step = opt->step,
                                 .step_triangles = opt->step_triangles};
}

bool hw3_frame_buffers(hw3_frame *frame, const ras_pipeline_config *cfg, hw3_gbuffer *g,
                       ras_error *err) {
    hw3_gbuffer_release(g); /* no stale buffers when nothing is kept */
    if (!cfg->dump) return true;
    if (!gbuffer_create(g, cfg->width, cfg->height, frame->stage.varyings))
        return ras_error_set(err, "out of memory for the buffers of --dump");
    frame->stage.gbuffer = g;
    return true;
}

bool hw3_frame_draw(const ras_scene *scene, const ras_scene_assets *assets, float angle_deg,
                    hw3_frame *frame, ras_pipeline *p, ras_error *err) {
    fragment_shader_payload *b = &frame->stage.base;
    b->counters = &p->counters; /* the shaders count texels and lighting there */
    p->counters.mip_levels_built = frame->mip_levels;
    if (frame->mip_levels) p->counters.stages_run |= RAS_STAGE_MIPMAP;
    for (int i = 0; i < scene->object_count; i++) {
        hw3_object_material(scene, assets, i, b);
        if (!ras_pipeline_draw_mesh(p, assets->meshes[i],
                                    hw3_object_model(&scene->objects[i], angle_deg), frame->view,
                                    frame->projection, err))
            return false;
    }
    return true;
}

bool hw3_render(const ras_scene *scene, ras_scene_assets *assets, const hw3_render_options *opt,
                ras_image *out, ras_counters *stats, ras_error *err) {
    hw3_frame frame;
    if (!hw3_frame_setup(scene, assets, opt, &frame, err)) return false;
    ras_pipeline_config cfg = hw3_frame_config(scene, opt, &frame.stage);
    hw3_gbuffer gbuffer = {0};
    if (!hw3_frame_buffers(&frame, &cfg, &gbuffer, err)) return false;
    ras_pipeline *p = ras_pipeline_create(&cfg, err);
    bool ok = p && hw3_frame_draw(scene, assets, opt->angle_deg, &frame, p, err);
    if (ok) ras_pipeline_end_frame(p, out);
    if (ok && opt->dump_dir)
        ok = ras_pipeline_dump(p, opt->dump_dir, NULL, err) &&
             hw3_gbuffer_dump(&gbuffer, opt->dump_dir, err);
    if (p && stats) *stats = p->counters;
    ras_pipeline_destroy(p);
    hw3_gbuffer_release(&gbuffer);
    return ok;
}
