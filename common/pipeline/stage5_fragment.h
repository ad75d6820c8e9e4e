/* stage5_fragment.h — stage 5: from a covered pixel to the shader's inputs.
 *
 * The rasterizer (stage 4, hw2) decides WHERE a triangle is and calls a
 * ras_shade_fn to decide WHAT COLOUR it is there. Two kinds of that hook:
 *   - ras_shade_vertex_color, the pipeline's fallback (hw2's flat
 *     triangles): the vertex colours, interpolated in screen space;
 *   - the fragment stage below (hw3 and every later shading lesson): the
 *     varyings a shader declares, interpolated with the configuration's
 *     interpolation hooks (hw3's interpolate_vec3/vec2, perspective-correct),
 *     the normal renormalised, the uv's change per pixel for trilinear
 *     filtering, handed to the program's shader as a ras_varyings.
 * Barycentrics here are SCREEN-space (λ): they interpolate depth (z/w is affine
 * in screen space) but not attributes — those need the 1/w correction (hw3's
 * interpolate_*).
 *
 * The stage also keeps, when asked (the pipeline's config.dump), what it
 * handed each pixel's shader: the pipeline's named buffers normal, uv and
 * view_depth (ras_pipeline_buffer, --dump, the window's buffer view).
 */
#ifndef RAS_STAGE5_FRAGMENT_H
#define RAS_STAGE5_FRAGMENT_H

#include "ras_counters.h"
#include "ras_math.h"
#include "ras_triangle.h"

typedef struct ras_fragment {
    int x, y;    /* screen pixel */
    vec2s p;     /* screen position shaded: the pixel centre, or the sample (SSAA) */
    vec3s bary;  /* screen-space barycentrics of p, summing to 1 */
    float depth; /* interpolated depth at p */
} ras_fragment;

typedef vec3s (*ras_shade_fn)(const ras_triangle *t, const ras_fragment *f, void *user);

/* Screen-space interpolation of the vertex colours (hw2's flat triangles). */
vec3s ras_shade_vertex_color(const ras_triangle *t, const ras_fragment *f, void *user);

/* The interpolation hooks (hw3's interpolate_vec3 and interpolate_vec2,
 * shading.h): attr at the screen barycentrics, with the 1/w correction
 * unless perspective is false (the w = 1 pitfall). */
typedef vec3s (*ras_interpolate_vec3_fn)(const ras_triangle *t, vec3s bary_screen,
                                         const vec3s attr[3], bool perspective);
typedef vec2s (*ras_interpolate_vec2_fn)(const ras_triangle *t, vec3s bary_screen,
                                         const vec2s attr[3], bool perspective);

/* What the stage hands the shader: the varyings of its mask, the others 0. */
typedef struct ras_varyings {
    vec3s view_pos;       /* RAS_VARYING_VIEW_POS: the shaded point, view space */
    vec3s normal;         /* RAS_VARYING_NORMAL: unit length (renormalised), view space */
    vec2s uv;             /* RAS_VARYING_UV */
    vec2s duv_dx, duv_dy; /* uv's change per pixel in x and y (uv_gradients only) */
} ras_varyings;

/* The program's shader: the colour for those varyings. */
typedef vec3s (*ras_fragment_shader_fn)(const ras_varyings *v, void *user);

/* The stage's state for one frame (the pipeline's; one thread). The
 * buffers are NULL unless kept; when kept, width × height floats (3 per pixel
 * for normal and uv, 1 for view_depth), top row first, +INF where nothing
 * was shaded. */
typedef struct ras_fragment_stage {
    unsigned varyings; /* RAS_VARYING_NORMAL | VIEW_POS | UV: what is interpolated */
    bool perspective;  /* false: affine (the w = 1 pitfall, for pictures) */
    bool uv_gradients; /* also duv_dx, duv_dy (trilinear filtering) */
    ras_interpolate_vec3_fn interpolate_vec3;
    ras_interpolate_vec2_fn interpolate_vec2;
    ras_fragment_shader_fn shader;
    void *shader_user;
    ras_counters *counters; /* varyings_interpolated; may be NULL */
    ras_varyings in;        /* the fragment being shaded */
    int width, height;
    float *normal, *uv, *view_depth; /* the kept buffers, or NULL */
    bool keeping;                    /* any of them */
} ras_fragment_stage;

/* ras_shade_fn: user is a ras_fragment_stage. Interpolates, keeps the
 * buffers, runs the shader. */
vec3s ras_fragment_stage_shade(const ras_triangle *t, const ras_fragment *f, void *user);

/* The kept buffers for the stage's varyings (normal: NORMAL, uv: UV,
 * view_depth: VIEW_POS), width × height, every entry +INF; false on out of
 * memory (none is kept then). ras_fragment_stage_release frees them. */
bool ras_fragment_stage_keep(ras_fragment_stage *s, int width, int height);
void ras_fragment_stage_clear(ras_fragment_stage *s); /* the buffers back to +INF */
void ras_fragment_stage_release(ras_fragment_stage *s);

#endif
