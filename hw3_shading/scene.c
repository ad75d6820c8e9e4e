/* scene.c — see scene.h.
 *
 * Given code, no TODO. Worth reading: hw3_frame_setup (the lights your
 * shaders get), hw3_frame_config (the pipeline: your rasterizer, your
 * interpolation, your shader) and hw3_frame_draw (one frame, object by
 * object); how the varyings are interpolated is the core's
 * (common/pipeline/stage5_fragment.c). Leave it as it is: the grader takes
 * only shading.c from a submission.
 */
#include "scene.h"

#include "rasterizer.h" /* hw2: rasterize_triangle, resolve_pixel */
#include "transform.h"  /* hw1: get_projection_matrix */

#include "ras_names.h" /* the shader and filter spellings */

/* ---- the shaders ------------------------------------------------------------ */

/* hw3's shaders, the core's from normal on (flat has none): the function and
 * the varyings it reads. The spellings are ras_names.h's. */
enum { VN = RAS_VARYING_NORMAL, VP = RAS_VARYING_VIEW_POS, VUV = RAS_VARYING_UV };
static const struct {
    fragment_shader_fn fn;
    unsigned varyings;
} shader_table[RAS_SHADER_COUNT] = {
    [RAS_SHADER_NORMAL] = {normal_fragment_shader, VN},
    [RAS_SHADER_PHONG] = {phong_fragment_shader, VN | VP},
    [RAS_SHADER_TEXTURE] = {texture_fragment_shader, VN | VP | VUV},
    [RAS_SHADER_BUMP] = {bump_fragment_shader, VN | VUV},
    [RAS_SHADER_DISPLACEMENT] = {displacement_fragment_shader, VN | VP | VUV},
};

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
    return (unsigned)shader < RAS_SHADER_COUNT ? shader_table[shader].fn : NULL;
}

unsigned hw3_shader_varyings(ras_scene_shader shader) {
    return (unsigned)shader < RAS_SHADER_COUNT ? shader_table[shader].varyings : 0;
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

/* ---- the scene's objects, as the shaders see them -------------------------- */

mat4s hw3_object_model(const ras_scene_object *so, float angle_deg) {
    return ras_scene_model_matrix(so, (ras_scene_spin){.turn_y_deg = angle_deg});
}

void hw3_object_material(const ras_scene *scene, const ras_scene_assets *assets, int i,
                         fragment_shader_payload *payload) {
    const ras_scene_material *m = &scene->objects[i].material;
    payload->color = m->kd_set ? m->kd : m->color;
    payload->texture = assets->textures[i], payload->height_map = assets->height_maps[i];
    payload->kh = m->kh, payload->kn = m->kn;
    payload->ka = m->ka, payload->ks = m->ks, payload->p = m->p;
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
    opt.filter = rs->filter, opt.cull = rs->cull, opt.depth = rs->depth;
    opt.aa = rs->aa;
    opt.pattern = rs->aa == RAS_AA_NONE ? ras_sample_pattern_center() : rs->pattern;
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

hw3_render_options hw3_app_render_options(const ras_app *app) {
    const ras_app_settings *s = &app->set;
    hw3_render_options opt = hw3_render_options_from_ras(app->scene);
    opt.shader = s->shader, opt.filter = s->filter;
    opt.aa = s->aa, opt.pattern = ras_app_settings_pattern(s), opt.depth = s->depth;
    opt.angle_deg = s->angle, opt.affine = s->affine;
    return opt;
}

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
    if (opt->filter == FILTER_TRILINEAR && opt->shader == RAS_SHADER_TEXTURE) {
        for (int i = 0; i < scene->object_count; i++)
            if (!ras_scene_assets_build_mips(scene, assets, i, &mip_levels, err)) return false;
    }
    *frame = (hw3_frame){.shader = shader,
                         .varyings = hw3_frame_varyings(scene, assets, opt->shader),
                         .mip_levels = mip_levels};
    fragment_shader_payload *b = &frame->payload;
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
                                     hw3_frame *frame) {
    return (ras_pipeline_config){.width = scene->width,
                                 .height = scene->height,
                                 .clear_color = scene->clear_color,
                                 .aa = opt->aa,
                                 .pattern = opt->pattern,
                                 .cull = opt->cull,
                                 .depth = opt->depth,
                                 .z_near = scene->camera.z_near,
                                 .z_far = scene->camera.z_far,
                                 .varyings = frame->varyings,
                                 .rasterize = rasterize_triangle,
                                 .resolve = resolve_pixel,
                                 .interpolate_vec3 = interpolate_vec3,
                                 .interpolate_vec2 = interpolate_vec2,
                                 .affine = opt->affine,
                                 .uv_gradients = opt->filter == FILTER_TRILINEAR,
                                 .shader = hw3_frame_shade,
                                 .shader_user = frame,
                                 .dump = opt->dump_dir != NULL};
}

vec3s hw3_frame_shade(const ras_varyings *v, void *user) {
    /* Into the frame's own payload, in place: copying the whole payload (its
     * lights included) for every fragment cost more than the normal shader. */
    hw3_frame *frame = user;
    fragment_shader_payload *payload = &frame->payload;
    payload->view_pos = v->view_pos, payload->normal = v->normal, payload->uv = v->uv;
    payload->duv_dx = v->duv_dx, payload->duv_dy = v->duv_dy;
    return frame->shader(payload);
}

bool hw3_frame_draw(const ras_scene *scene, const ras_scene_assets *assets, float angle_deg,
                    hw3_frame *frame, ras_pipeline *p, ras_error *err) {
    fragment_shader_payload *b = &frame->payload;
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
    ras_pipeline_config cfg = hw3_frame_config(scene, opt, &frame);
    ras_pipeline *p = ras_pipeline_create(&cfg, err);
    bool ok = p && hw3_frame_draw(scene, assets, opt->angle_deg, &frame, p, err);
    if (ok) ras_pipeline_end_frame(p, out);
    if (ok && opt->dump_dir) ok = ras_pipeline_dump(p, opt->dump_dir, NULL, err);
    if (p && stats) *stats = p->counters;
    ras_pipeline_destroy(p);
    return ok;
}
