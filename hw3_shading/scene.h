/* scene.h — hw3: the scene's objects and lights as your shaders see them, and
 * one frame.
 *
 * Not a TODO file: it is the glue between the pipeline (common/) and
 * shading.h, shared by the program (main.c), the tests and the grader. Leave
 * it as it is: they build against it as shipped.
 *
 * The fragment stage is the core's (common/pipeline/stage5_fragment.h): it
 * interpolates the varyings your shader reads with your interpolate_vec3/vec2
 * (hooks of the pipeline's configuration, as rasterize_triangle is), and
 * hands them here (hw3_frame_shade), where they join the object's material
 * and the scene's lights in a fragment_shader_payload for your shader.
 *
 * One frame, for the program, the tests and the grader alike:
 *   hw3_frame_setup    your shader and the varyings it reads, the lights
 *                      moved into view space, the view and projection
 *                      matrices, the mip levels trilinear filtering reads
 *   hw3_frame_config   the pipeline: your hw2 rasterizer, your
 *                      interpolation, your shader (through hw3_frame_shade)
 *   hw3_frame_draw     every object, with its material, through it
 *   hw3_render         the three, with a pipeline of its own, into an image
 *
 * The scene is the core's (ras_scene.h). The shaders get the lights in VIEW
 * space (shading.h); the view matrix is ras_scene_view_matrix's.
 */
#ifndef RAS_HW3_SCENE_H
#define RAS_HW3_SCENE_H

#include "ras_app.h" /* ras_app */
#include "ras_error.h"
#include "ras_pipeline.h"
#include "ras_scene.h"
#include "shading.h"

/* hw3's shaders are the core's (ras_scene.h) from RAS_SHADER_NORMAL to
 * RAS_SHADER_DISPLACEMENT; RAS_SHADER_FLAT (hw2's unlit colour) is none. */
bool hw3_shader_parse(const char *name, ras_scene_shader *out, ras_error *err);
/* The shader's function; NULL for flat. */
fragment_shader_fn hw3_shader_function(ras_scene_shader shader);
/* The RAS_VARYING_* bits the shader reads: normal → NORMAL; phong → NORMAL |
 * VIEW_POS; texture and displacement → NORMAL | VIEW_POS | UV; bump → NORMAL | UV;
 * 0 for flat. */
unsigned hw3_shader_varyings(ras_scene_shader shader);
/* "nearest", "bilinear" or "trilinear". */
bool hw3_filter_parse(const char *name, texture_filter *out, ras_error *err);

/* Object i's material as payload fields: colour (kd when the scene gives
 * kd, else the colour), colour map, height map, ka, ks, p, kh, kn. */
void hw3_object_material(const ras_scene *scene, const ras_scene_assets *assets, int i,
                         fragment_shader_payload *payload);
/* The object's model matrix with the program's turn about y
 * (ras_scene_model_matrix with turn_y_deg = angle_deg). */
mat4s hw3_object_model(const ras_scene_object *object, float angle_deg);

typedef struct hw3_render_options {
    ras_scene_shader shader; /* RAS_SHADER_NORMAL .. RAS_SHADER_DISPLACEMENT */
    texture_filter filter;
    float angle_deg; /* added to every object's spin about y */
    ras_aa_mode aa;
    ras_sample_pattern pattern; /* for MSAA/SSAA */
    bool affine;                /* interpolate without the 1/w correction */
    /* NULL: hw1's get_projection_matrix (the program carries your hw1 forward);
     * the tests pass their own so hw3 is graded on its own. */
    mat4s (*projection)(float fov_deg, float aspect, float z_near, float z_far);
    ras_cull_mode cull;     /* default none */
    ras_depth_format depth; /* default z01 */
    /* hw3_render's --dump DIR: the frame's buffers written there (ras_dump.h:
     * depth, coverage with AA, overdraw, and the fragment stage's normal, uv
     * and view_depth where the shader reads them). NULL: none kept. */
    const char *dump_dir;
} hw3_render_options;

/* Defaults: normal shader, bilinear, angle 0, no AA, perspective-correct. */
hw3_render_options hw3_render_defaults(void);
/* A scene file's shader (flat: the default, normal), filter, anti-aliasing,
 * culling and depth format; the rest the defaults. */
hw3_render_options hw3_render_options_from_ras(const ras_scene *rs);
/* The program's frame: the scene's options with the settings over them
 * (shader, filter, anti-aliasing and pattern, depth, angle, affine). The
 * shell keeps the buffers of --dump and the window's views itself. */
hw3_render_options hw3_app_render_options(const ras_app *app);

/* The varyings a frame interpolates: the shader's, less UV when no object
 * has a map the shader reads, less VIEW_POS when there are no lights. */
unsigned hw3_frame_varyings(const ras_scene *scene, const ras_scene_assets *assets,
                            ras_scene_shader shader);

/* One frame's state; the pipeline's shader_user (so it must outlive the
 * pipeline's frames). */
typedef struct hw3_frame {
    fragment_shader_fn shader;
    unsigned varyings; /* hw3_frame_varyings */
    /* the filter, the lights in view space and the ambient light; each
     * object's material set by hw3_frame_draw; the varyings by hw3_frame_shade */
    fragment_shader_payload payload;
    mat4s view, projection;
    uint64_t mip_levels; /* built by this frame's setup, for the counters */
} hw3_frame;

/* The frame's set-up (see above). False and err for flat, or out of memory. */
bool hw3_frame_setup(const ras_scene *scene, ras_scene_assets *assets,
                     const hw3_render_options *opt, hw3_frame *frame, ras_error *err);
/* The pipeline of the frame: the scene's size and clear colour, the options'
 * anti-aliasing, culling and depth format, your rasterize_triangle,
 * resolve_pixel, interpolate_vec3/vec2 and, through hw3_frame_shade, the
 * frame's shader; dump with opt->dump_dir. */
ras_pipeline_config hw3_frame_config(const ras_scene *scene, const hw3_render_options *opt,
                                     hw3_frame *frame);
/* ras_fragment_shader_fn, user a hw3_frame: the varyings into its payload,
 * then its shader. */
vec3s hw3_frame_shade(const ras_varyings *v, void *frame);
/* Every object into `p` (made from hw3_frame_config, cleared): its material,
 * its model matrix with the turn angle_deg, the frame's view and projection;
 * the mip levels into p's counters. False on out of memory. */
bool hw3_frame_draw(const ras_scene *scene, const ras_scene_assets *assets, float angle_deg,
                    hw3_frame *frame, ras_pipeline *p, ras_error *err);

/* One frame of `scene` (its meshes and textures from `assets`) into `out`
 * (the scene's size): setup, config and draw, with a pipeline of its own,
 * its buffers written into opt->dump_dir when set. Trilinear builds the mip
 * levels of the colour maps the first time (hence the non-const assets).
 * `stats` (may be NULL) receives the counters. False and err on a bad
 * configuration or out of memory. */
bool hw3_render(const ras_scene *scene, ras_scene_assets *assets, const hw3_render_options *opt,
                ras_image *out, ras_counters *stats, ras_error *err);

#endif
