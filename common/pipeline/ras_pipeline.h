/* ras_pipeline.h — one frame through the stages, assembled from what the scene asks for.
 *
 *   mesh ─▶ stage1_vertex ─▶ stage2_clip ─▶ stage3_setup ─▶ (cull)
 *        ─▶ stage4 rasterize hook (hw2) ─▶ stage5 fragment stage: the
 *           varyings, interpolated with the hooks (hw3), into the shader hook
 *        ─▶ stage6_resolve (hw2 hook, only with AA) ─▶ ras_image
 *
 * The configuration decides what exists: sample buffers only with AA, the
 * resolve hook only with more than one sample, varyings only those in the
 * mask, no rasterizer at all for a wireframe. Counters record what ran.
 * Ownership: ras_pipeline_create/ras_pipeline_destroy (NULL-safe).
 */
#ifndef RAS_PIPELINE_H
#define RAS_PIPELINE_H

#include "ras_counters.h"
#include "ras_image.h"
#include "ras_mesh.h"
#include "stage1_vertex.h"
#include "stage3_setup.h" /* ras_depth_format */
#include "stage4_raster.h"

typedef enum ras_cull_mode { RAS_CULL_NONE, RAS_CULL_BACK, RAS_CULL_FRONT } ras_cull_mode;

typedef struct ras_pipeline_config {
    int width, height;
    vec3s clear_color;
    bool wireframe; /* hw1: draw triangle edges as lines instead of filling */
    vec3s wire_color;
    ras_aa_mode aa;
    ras_sample_pattern pattern; /* ignored for RAS_AA_NONE (one centre sample) */
    ras_cull_mode cull; /* front faces are counter-clockwise on screen */
    /* What the depth buffer holds (stage3_setup.h): the rasterizer compares
     * "smaller is closer" either way. RAS_DEPTH_INV_W needs z_near, the
     * projection's near distance (> 0); RAS_DEPTH_Z01 ignores it. */
    ras_depth_format depth;
    float z_near;
    /* The camera's far distance: > 0 clips the far plane at view depth
     * w <= z_far, decided in double (stage2_clip.h); 0: at the projection's
     * z >= -w, which a float matrix holds only while near / far is well
     * above 1e-7. */
    float z_far;
    unsigned varyings;  /* RAS_VARYING_* the shader reads */
    ras_rasterize_fn rasterize; /* required unless wireframe */
    ras_resolve_fn resolve;     /* required when the pattern has > 1 sample */
    /* Stage 5 (stage5_fragment.h). With `shader` set, the fragment stage:
     * the varyings of the mask (NORMAL, VIEW_POS, UV) interpolated with the
     * two hooks (required for the varyings they serve: hw3's
     * interpolate_vec3/vec2, wired as rasterize is), affine instead of
     * perspective-correct with `affine`, the uv's change per pixel with
     * uv_gradients, handed to shader(varyings, shader_user). Else `shade`
     * colours the fragment itself (NULL: interpolated vertex colour). */
    ras_interpolate_vec3_fn interpolate_vec3;
    ras_interpolate_vec2_fn interpolate_vec2;
    bool affine;
    bool uv_gradients;
    ras_fragment_shader_fn shader;
    void *shader_user;
    ras_shade_fn shade;
    void *shade_user;
    /* --dump (and the window's buffer view): also count the fragments shaded
     * at each pixel (the overdraw buffer of ras_pipeline_dump) and keep what
     * the fragment stage handed each pixel's shader (normal, uv, view_depth).
     * Off, nothing is counted, kept or allocated. The shell (ras_app.h) sets
     * it and the step view's two fields below for its frames. */
    bool dump;
    /* The window's step view: rasterize only the first step_triangles
     * triangles of the frame, counted as triangles_rasterized counts them
     * (after clipping — each piece of the fan is one — and culling), and keep
     * the last one drawn (ras_pipeline.last_triangle). Off (false), the frame
     * is drawn whole and nothing is kept: one compare per triangle. */
    bool step;
    long step_triangles;
    /* A new field goes into ras_pipeline_config_equal too. */
} ras_pipeline_config;

typedef struct ras_pipeline {
    ras_pipeline_config config;
    ras_framebuffer *fb;
    ras_counters counters;
    ras_raster_ctx raster; /* handed to the rasterize hook */
    ras_clip_vertex *clip_vertices; /* scratch, grows to the largest mesh */
    size_t clip_capacity;
    float *overdraw; /* config.dump: fragments shaded per pixel, else NULL */
    /* config.shader: stage 5's state, its buffers kept with config.dump */
    ras_fragment_stage fragment;
    ras_shade_fn shade; /* what colours a fragment (under the overdraw count) */
    void *shade_user;
    /* config.step: the triangles that reached the rasterizer this frame, drawn
     * or not (the whole frame's count), and the last one drawn (the step
     * view's "current triangle"; has_last false before the first). */
    long step_reached;
    bool has_last;
    ras_triangle last_triangle;
    /* The first triangle of the frame refused for its range (stage4_raster.h:
     * counters.triangles_rejected_range > 0), with which corner was where;
     * has_refused false when none was. */
    bool has_refused;
    ras_error refused;
} ras_pipeline;

/* Checks the configuration (hooks present, sizes, sample counts) and
 * allocates exactly the buffers it needs. */
ras_pipeline *ras_pipeline_create(const ras_pipeline_config *config, ras_error *err);
void ras_pipeline_destroy(ras_pipeline *p);

/* Whether a pipeline made from `a` draws as one made from `b`: the same
 * values field by field (bits for the floats, so -0 is not 0; the sample
 * offsets only as far as the count). The shell (ras_app.h) keeps its
 * pipeline from frame to frame while the program's configuration is equal. */
bool ras_pipeline_config_equal(const ras_pipeline_config *a, const ras_pipeline_config *b);

/* Clears the buffers to the clear colour and zeroes the counters. */
void ras_pipeline_begin_frame(ras_pipeline *p);

/* Runs stages 1–5 on every triangle of the mesh. False only on out of memory. */
bool ras_pipeline_draw_mesh(ras_pipeline *p, const ras_mesh *mesh, mat4s model, mat4s view,
                            mat4s projection, ras_error *err);

/* Stages 3–5 for a triangle already in clip space (tests, benchmarks). */
void ras_pipeline_draw_clip_triangle(ras_pipeline *p, const ras_clip_vertex *a,
                                     const ras_clip_vertex *b, const ras_clip_vertex *c);

/* Stage 4–5 for a triangle already in screen space, as every clipped and set
 * up triangle goes (tests, direct callers): the rasterizer's range check
 * (stage4_raster.h: refused, counted in triangles_rejected_range, the first
 * refusal kept in p->refused), culling, the step view, the rasterize hook. */
void ras_pipeline_draw_screen_triangle(ras_pipeline *p, const ras_triangle *t);

/* Stage 6 into `out` (same size as the frame). */
void ras_pipeline_end_frame(ras_pipeline *p, ras_image *out);

/* --dump: writes the frame's buffers into dir (ras_dump.h): depth (per
 * sample), coverage and sample_colour (per sample, only with anti-aliasing),
 * overdraw (only with config.dump), and the fragment stage's normal, uv and
 * view_depth (with config.dump, those of its varyings). A wireframe frame has
 * none of them: it writes nothing.
 * `written` (may be NULL) gets how many buffers were written. */
bool ras_pipeline_dump(const ras_pipeline *p, const char *dir, int *written, ras_error *err);

/* One of the frame's buffers as ras_dump_write and ras_dump_paint take it:
 * "depth", "coverage" and "sample_colour" (only with more than one sample),
 * "overdraw", "normal", "uv" or "view_depth" (only with config.dump; the last
 * three only with the fragment stage, for the varyings it interpolates).
 * False when the frame has no such buffer (a wireframe has none). Coverage is computed: *owned gets the array to free (NULL for
 * the others); false with *owned NULL also when memory runs out. */
struct ras_dump_buffer;
bool ras_pipeline_buffer(const ras_pipeline *p, const char *name, struct ras_dump_buffer *out,
                         float **owned);

#endif
