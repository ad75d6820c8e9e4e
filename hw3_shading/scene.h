/* scene.h — hw3: the fragment stage that feeds your shaders, and one frame.
 *
 * Not a TODO file: it is the glue between the pipeline (common/) and
 * shading.h, shared by the program (main.c) and the tests. Read
 * hw3_fragment_stage and hw3_render_options to see what reaches your shaders
 * and how a frame is set; the rest is the program's. Leave it as it is: the
 * tests and the grader build against it as shipped.
 *
 *   hw3_shade_fragment   the ras_shade_fn the rasterizer calls: interpolates
 *                        exactly the varyings the chosen shader reads
 *                        (perspective-correct, with your interpolate_*),
 *                        fills a fragment_shader_payload, runs the shader
 *   one frame, in three steps (the program's configure and draw hooks
 *   call them; hw3_render, for the tests, runs all three):
 *     hw3_frame_setup    the fragment stage (your shader, the varyings it
 *                        reads, the lights in view space), the view and
 *                        projection matrices, the mip levels
 *     hw3_frame_config   the pipeline that calls it (your hw2 rasterizer),
 *                        and hw3_frame_buffers when the frame keeps its buffers
 *     hw3_frame_draw     every object, with its material, through the pipeline
 *   hw3_render           the three, with a pipeline of its own, into an image
 *
 * The scene is the core's (ras_scene.h): a scene file, or a built-in one from
 * scenes/ (ras_builtin_scenes.h: hw3_default.json, and hw3_model.json for
 * --model), with the meshes and textures ras_scene_load_assets made for it.
 * hw3 keeps no copy of it; what it adds is how the scene reaches the shaders:
 * each object's material as payload fields (hw3_object_material), its model
 * matrix with the program's turn about y (hw3_object_model), and the lights
 * moved into view space (hw3_render).
 *
 * Conventions: view space as in shading.h (lights are given in VIEW space,
 * the camera looks down -z from the view-space origin); the view matrix is
 * ras_scene_view_matrix's (the GAMES101 one, a translation by -eye, unless
 * the scene's camera looks at a point).
 */
#ifndef RAS_HW3_SCENE_H
#define RAS_HW3_SCENE_H

#include "ras_app.h"  /* ras_app_settings */
#include "ras_dump.h" /* ras_dump_buffer */
#include "ras_error.h"
#include "ras_mesh.h"
#include "ras_pipeline.h"
#include "ras_scene.h"
#include "shading.h"

/* hw3's shaders are the core's (ras_scene.h) from RAS_SHADER_NORMAL to
 * RAS_SHADER_DISPLACEMENT, spelt by ras_scene_shader_name; RAS_SHADER_FLAT
 * (hw2's unlit colour) is none of them, and hw3_render refuses it. */

/* A shader hw3 draws by name: "normal", "phong", ... ("flat" is an error). */
bool hw3_shader_parse(const char *name, ras_scene_shader *out, ras_error *err);
/* The shader's function; NULL for a shader hw3 does not draw (flat). */
fragment_shader_fn hw3_shader_function(ras_scene_shader shader);
/* The RAS_VARYING_* bits the shader reads: normal → NORMAL; phong → NORMAL |
 * VIEW_POS; texture and displacement → NORMAL | VIEW_POS | UV; bump → NORMAL | UV;
 * 0 for a shader hw3 does not draw. */
unsigned hw3_shader_varyings(ras_scene_shader shader);

/* A filter by name ("nearest", "bilinear", "trilinear"; spelt back by
 * ras_scene_filter_name). */
bool hw3_filter_parse(const char *name, texture_filter *out, ras_error *err);

/* --dump's buffers of the fragment stage: per pixel, what the last fragment
 * shaded there was given (the visible one: a later fragment passed the
 * depth test, so it is nearer). A NULL array is a buffer this frame does not
 * produce (its shader does not read that varying). Entries nothing was
 * shaded at stay +INF. Row-major, top row first, like the framebuffer. */
typedef struct hw3_gbuffer {
    int width, height;
    float *normal;     /* 3 per pixel: the unit normal the shader got, view space */
    float *uv;         /* 3 per pixel: u, v and 0 */
    float *view_depth; /* 1 per pixel: -view_pos.z, the distance in front of the eye */
} hw3_gbuffer;

/* The fragment stage's state: the pipeline's shade_user. `base` holds the
 * per-scene and per-object fields; hw3_shade_fragment writes the varyings
 * into it in place, fragment by fragment (so one stage serves one thread). */
typedef struct hw3_fragment_stage {
    fragment_shader_fn shader;
    unsigned varyings;
    bool perspective; /* false: affine interpolation (the w = 1 pitfall, for pictures) */
    fragment_shader_payload base;
    hw3_gbuffer *gbuffer; /* --dump only; NULL otherwise */
} hw3_fragment_stage;

/* ras_shade_fn: user is a hw3_fragment_stage. */
vec3s hw3_shade_fragment(const ras_triangle *t, const ras_fragment *f, void *user);

/* Object i's material as payload fields: colour (kd when the scene gives
 * kd, else the colour: the base colour of phong and displacement, and the
 * texel's stand-in for texture), colour map, height map, ka, ks, p, kh, kn.
 * hw3_render sets them through this, per object. */
void hw3_object_material(const ras_scene *scene, const ras_scene_assets *assets, int i,
                         fragment_shader_payload *payload);

/* The object's model matrix with the program's turn about y, T · R_y(angle)
 * · R · S: ras_scene_model_matrix's turn about y (a last rotation about ±y
 * joins the turn; the reference pictures were drawn with that form). */
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
    ras_cull_mode cull;  /* default none */
    ras_depth_format depth; /* default z01 (inverse_w: with the scene's z_near, stage3_setup.h) */
    /* --dump DIR: the frame's buffers are written there (ras_dump.h: depth,
     * coverage with AA, overdraw, and the fragment stage's normal, uv and
     * view_depth where the shader reads them); the teaching pipeline draws
     * such a frame. NULL: nothing is dumped or kept. */
    const char *dump_dir;
    /* The window's step view: only the first step_triangles triangles
     * (ras_pipeline_config.step); the teaching pipeline draws such a frame. */
    bool step;
    long step_triangles;
    /* The window's step and buffer views: the frame keeps its buffers
     * (ras_pipeline_config.dump: overdraw) for the shell to show; the
     * teaching pipeline draws such a frame. */
    bool keep_buffers;
} hw3_render_options;

void hw3_gbuffer_release(hw3_gbuffer *g); /* frees and zeroes; a zeroed one is fine */
/* --dump: the buffers there are, as normal, uv and view_depth in dir (ras_dump.h). */
bool hw3_gbuffer_dump(const hw3_gbuffer *g, const char *dir, ras_error *err);
/* One of the fragment buffers by name, "normal", "uv" or "view_depth" (the
 * window's buffer view shows the first two): what the frame's fragment stage
 * handed each pixel's shader. False for any other name, or a buffer the frame
 * did not make. */
bool hw3_gbuffer_view(const hw3_gbuffer *g, const char *name, ras_dump_buffer *out);

/* Defaults: normal shader, bilinear, angle 0, no AA, perspective-correct. */
hw3_render_options hw3_render_defaults(void);

/* A scene file's effects as options: its shader, filter, anti-aliasing,
 * culling and depth format; the rest from hw3_render_defaults(). "flat"
 * (hw2's unlit colour) has no hw3 shader: it gives the default, normal. */
hw3_render_options hw3_render_options_from_ras(const ras_scene *rs);

/* The program's frame as render options: the scene's
 * (hw3_render_options_from_ras), the settings over them (ras_app.h: shader,
 * filter, anti-aliasing and pattern, depth format, angle, affine), and the
 * shell's --dump, step view and buffer views. The shader is taken as it is:
 * hw3_frame_setup refuses flat (main.c turns it into normal first, with a
 * note). */
hw3_render_options hw3_app_render_options(const ras_app *app);

/* The varyings a frame interpolates: the shader's (hw3_shader_varyings), less
 * those no object of the scene uses — no UVs when no object has a map the
 * shader reads (a colour map for texture, a height map for bump and
 * displacement), no view position when there are no lights to light it with. */
unsigned hw3_frame_varyings(const ras_scene *scene, const ras_scene_assets *assets,
                            ras_scene_shader shader);

/* One frame's set-up, before anything is drawn: the fragment stage (the
 * shader, the varyings it reads, the filter, the lights moved into view
 * space, the ambient light; each object's material is set per object with
 * hw3_object_material), the view and projection matrices, and the mip levels
 * trilinear filtering reads, built the first time (mip_levels: how many this
 * frame built, for the counters). False and err when the shader is not one
 * hw3 draws (flat) or when out of memory. */
typedef struct hw3_frame {
    hw3_fragment_stage stage;
    mat4s view, projection;
    uint64_t mip_levels;
} hw3_frame;
bool hw3_frame_setup(const ras_scene *scene, ras_scene_assets *assets,
                     const hw3_render_options *opt, hw3_frame *frame, ras_error *err);

/* The pipeline of the frame: the scene's size and clear colour, the options'
 * anti-aliasing, culling and depth format, your hw2 rasterize_triangle and
 * resolve_pixel, and `stage` (hw3_frame_setup's, which must outlive the
 * pipeline's frames) as the shade hook's. Its buffers are kept (dump) with
 * opt->dump_dir or opt->keep_buffers. */
ras_pipeline_config hw3_frame_config(const ras_scene *scene, const hw3_render_options *opt,
                                     hw3_fragment_stage *stage);

/* The fragment stage's buffers of a frame that keeps its buffers (cfg->dump,
 * from hw3_frame_config): g is released, then made again at cfg's size for
 * the stage's varyings (every entry +INF) and handed to frame->stage;
 * without cfg->dump it stays empty. False and err on out of memory. */
bool hw3_frame_buffers(hw3_frame *frame, const ras_pipeline_config *cfg, hw3_gbuffer *g,
                       ras_error *err);

/* Draws every object of the scene into `p` (made from hw3_frame_config with
 * frame->stage, and cleared): its material into the stage's payload, its
 * model matrix with the turn angle_deg about y, the frame's view and
 * projection; the frame's mip levels into p's counters. False on out of
 * memory. */
bool hw3_frame_draw(const ras_scene *scene, const ras_scene_assets *assets, float angle_deg,
                    hw3_frame *frame, ras_pipeline *p, ras_error *err);

/* Renders one frame of `scene` into `out` (the scene's size), its meshes and
 * textures from `assets` (ras_scene_load_assets of that scene): setup,
 * config and draw above, with a pipeline of its own, and with opt->dump_dir
 * the pipeline's and the fragment stage's buffers written there. Lights with
 * "space": "world" are moved into view space here. Trilinear builds the mip
 * levels of the scene's colour maps the first time (ras_texture_build_mips,
 * hence the non-const assets). `stats` (may be NULL) receives the counters.
 * False and err on a bad configuration or out of memory. */
bool hw3_render(const ras_scene *scene, ras_scene_assets *assets, const hw3_render_options *opt,
                ras_image *out, ras_counters *stats, ras_error *err);

#endif
