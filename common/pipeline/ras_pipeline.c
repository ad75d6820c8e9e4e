/* ras_pipeline.c — see ras_pipeline.h. */
#include "ras_pipeline.h"

#include "ras_draw.h"
#include "ras_dump.h"
#include "stage2_clip.h"
#include "stage3_setup.h"
#include "stage6_resolve.h"

#include <math.h>   /* isfinite */
#include <stdlib.h> /* calloc, realloc, free */
#include <string.h> /* memcmp, strcmp */

/* --dump's overdraw count: every fragment the rasterizer hands over is
 * counted at its pixel, then shaded by the real shader (or the vertex
 * colour, as the rasterizer would have). Installed only with config.dump,
 * so a frame that is not dumped pays nothing. */
static vec3s shade_counting(const ras_triangle *t, const ras_fragment *f, void *user) {
    ras_pipeline *p = user;
    if (f->x >= 0 && f->x < p->fb->width && f->y >= 0 && f->y < p->fb->height)
        p->overdraw[ras_fb_pixel_index(p->fb, f->x, f->y)] += 1;
    ras_shade_fn shade = p->shade ? p->shade : ras_shade_vertex_color;
    return shade(t, f, p->shade_user);
}

/* Everything of ras_pipeline_begin_frame but the clear. */
static void reset_frame_state(ras_pipeline *p) {
    p->counters = (ras_counters){.buffer_bytes = p->fb->bytes};
    p->step_reached = 0;
    p->has_last = false;
    p->has_refused = false;
    if (p->overdraw)
        for (long i = 0, n = (long)p->fb->width * p->fb->height; i < n; i++)
            p->overdraw[i] = 0;
    ras_fragment_stage_clear(&p->fragment);
    p->fragment.in = (ras_varyings){0};
}

/* Stage 5 from the configuration: the fragment stage with its hooks, or the
 * configuration's shade hook. False and err when a hook it needs is missing
 * or the kept buffers do not fit. */
static bool fragment_setup(ras_pipeline *p, ras_error *err) {
    const ras_pipeline_config *c = &p->config;
    p->shade = c->shade, p->shade_user = c->shade_user;
    if (!c->shader || c->wireframe) return true;
    unsigned v = c->varyings & (RAS_VARYING_NORMAL | RAS_VARYING_VIEW_POS | RAS_VARYING_UV);
    if ((v & (RAS_VARYING_NORMAL | RAS_VARYING_VIEW_POS)) && !c->interpolate_vec3)
        return ras_error_set(err, "no interpolate_vec3 hook for the normal or view position");
    if ((v & RAS_VARYING_UV) && !c->interpolate_vec2)
        return ras_error_set(err, "no interpolate_vec2 hook for the texture coordinates");
    p->fragment = (ras_fragment_stage){.varyings = v,
                                       .perspective = !c->affine,
                                       .uv_gradients = c->uv_gradients,
                                       .interpolate_vec3 = c->interpolate_vec3,
                                       .interpolate_vec2 = c->interpolate_vec2,
                                       .shader = c->shader,
                                       .shader_user = c->shader_user,
                                       .counters = &p->counters};
    p->shade = ras_fragment_stage_shade, p->shade_user = &p->fragment;
    if (c->dump && !ras_fragment_stage_keep(&p->fragment, c->width, c->height))
        return ras_error_set(err, "out of memory for the buffers of --dump");
    return true;
}

ras_pipeline *ras_pipeline_create(const ras_pipeline_config *config, ras_error *err) {
    ras_pipeline_config cfg = *config;
    if (cfg.wireframe || cfg.aa == RAS_AA_NONE) cfg.pattern = ras_sample_pattern_center();
    if (cfg.pattern.count < 1) {
        ras_error_set(err, "the sample pattern is empty: build it with ras_sample_pattern_make");
        return NULL;
    }
    if (!cfg.wireframe && !cfg.rasterize) {
        ras_error_set(err, "no rasterizer hook: a filled pipeline needs config.rasterize");
        return NULL;
    }
    if (cfg.pattern.count > 1 && !cfg.resolve) {
        ras_error_set(err, "%d samples per pixel but no resolve hook: set config.resolve",
                      cfg.pattern.count);
        return NULL;
    }
    if ((unsigned)cfg.depth >= RAS_DEPTH_FORMAT_COUNT) {
        ras_error_set(err, "unknown depth format %d", (int)cfg.depth);
        return NULL;
    }
    /* Not !(z_near > 0) alone: an infinite z_near would make every depth -1
     * (after the clamp), i.e. no depth test at all. */
    if (cfg.depth == RAS_DEPTH_INV_W && !(cfg.z_near > 0 && isfinite(cfg.z_near))) {
        ras_error_set(err,
                      "depth format inverse_w needs config.z_near, the projection's near "
                      "distance (> 0, finite), got %g",
                      (double)cfg.z_near);
        return NULL;
    }
    if (!(cfg.z_far >= 0 && isfinite(cfg.z_far))) {
        ras_error_set(err,
                      "config.z_far is the camera's far distance (> 0, finite) or 0 for "
                      "none, got %g",
                      (double)cfg.z_far);
        return NULL;
    }
    ras_pipeline *p = calloc(1, sizeof *p);
    if (!p) {
        ras_error_set(err, "out of memory creating the pipeline");
        return NULL;
    }
    p->config = cfg;
    p->fb = ras_framebuffer_create(cfg.width, cfg.height, cfg.pattern.count, err);
    if (!p->fb) {
        free(p);
        return NULL;
    }
    if (!fragment_setup(p, err)) {
        ras_pipeline_destroy(p);
        return NULL;
    }
    p->raster = (ras_raster_ctx){.fb = p->fb,
                                 .aa = cfg.aa,
                                 .pattern = cfg.pattern,
                                 .shade = p->shade,
                                 .shade_user = p->shade_user,
                                 .counters = &p->counters};
    if (cfg.dump && !cfg.wireframe) {
        p->overdraw = calloc((size_t)cfg.width * (size_t)cfg.height, sizeof *p->overdraw);
        if (!p->overdraw) {
            ras_error_set(err, "out of memory for the overdraw buffer of --dump");
            ras_pipeline_destroy(p);
            return NULL;
        }
        p->raster.shade = shade_counting;
        p->raster.shade_user = p;
    }
    /* ras_framebuffer_create cleared to black: a second pass over the
     * whole buffer (a program makes one pipeline per frame) only for another
     * clear colour. */
    static const vec3s black = {{0, 0, 0}};
    if (memcmp(&cfg.clear_color, &black, sizeof black) != 0) /* -0.0f too: bits, not values */
        ras_framebuffer_clear(p->fb, cfg.clear_color);
    reset_frame_state(p);
    return p;
}

static bool same_bits(const void *a, const void *b, size_t n) { return !memcmp(a, b, n); }

bool ras_pipeline_config_equal(const ras_pipeline_config *a, const ras_pipeline_config *b) {
    /* Field by field, not memcmp of the structs: their padding is unset. */
    const ras_sample_pattern *pa = &a->pattern, *pb = &b->pattern;
    bool pattern = pa->kind == pb->kind && pa->count == pb->count &&
                   (pa->count < 1 || pa->count > RAS_MAX_SAMPLES ||
                    same_bits(pa->offsets, pb->offsets, (size_t)pa->count * sizeof pa->offsets[0]));
    return a->width == b->width && a->height == b->height &&
           same_bits(&a->clear_color, &b->clear_color, sizeof a->clear_color) &&
           a->wireframe == b->wireframe &&
           same_bits(&a->wire_color, &b->wire_color, sizeof a->wire_color) && a->aa == b->aa &&
           pattern && a->cull == b->cull && a->depth == b->depth &&
           same_bits(&a->z_near, &b->z_near, sizeof a->z_near) &&
           same_bits(&a->z_far, &b->z_far, sizeof a->z_far) && a->varyings == b->varyings &&
           a->rasterize == b->rasterize && a->resolve == b->resolve &&
           a->interpolate_vec3 == b->interpolate_vec3 &&
           a->interpolate_vec2 == b->interpolate_vec2 && a->affine == b->affine &&
           a->uv_gradients == b->uv_gradients && a->shader == b->shader &&
           a->shader_user == b->shader_user && a->shade == b->shade &&
           a->shade_user == b->shade_user && a->dump == b->dump && a->step == b->step &&
           a->step_triangles == b->step_triangles;
}

void ras_pipeline_destroy(ras_pipeline *p) {
    if (!p) return;
    ras_framebuffer_destroy(p->fb);
    free(p->clip_vertices);
    free(p->overdraw);
    ras_fragment_stage_release(&p->fragment);
    free(p);
}

void ras_pipeline_begin_frame(ras_pipeline *p) {
    ras_framebuffer_clear(p->fb, p->config.clear_color);
    reset_frame_state(p);
}

static void draw_wire_polygon(ras_pipeline *p, const ras_clip_vertex *poly, int n) {
    for (int i = 0; i < n; i++) {
        vec4s a = ras_viewport(poly[i].p_clip, p->fb->width, p->fb->height);
        vec4s b = ras_viewport(poly[(i + 1) % n].p_clip, p->fb->width, p->fb->height);
        ras_draw_line(p->fb, (vec2s){{a.x, a.y}}, (vec2s){{b.x, b.y}}, p->config.wire_color);
        p->counters.lines_drawn++;
    }
}

void ras_pipeline_draw_screen_triangle(ras_pipeline *p, const ras_triangle *t) {
    /* Beyond the rasterizer's exact range: refused, counted and located
     * (stage4_raster.h), never drawn approximately. */
    if (!ras_raster_check_range(t, p->has_refused ? NULL : &p->refused)) {
        p->has_refused = true;
        p->counters.triangles_rejected_range++;
        return;
    }
    float area2 = ras_triangle_area2(t);
    if ((p->config.cull == RAS_CULL_BACK && area2 < 0) ||
        (p->config.cull == RAS_CULL_FRONT && area2 > 0)) {
        p->counters.triangles_culled++;
        return;
    }
    if (p->config.step) { /* the step view: the first step_triangles only */
        if (p->step_reached++ >= p->config.step_triangles) return;
        p->last_triangle = *t;
        p->has_last = true;
    }
    p->counters.triangles_rasterized++;
    p->config.rasterize(t, &p->raster);
}

static void raster_one(ras_pipeline *p, const ras_clip_vertex *a, const ras_clip_vertex *b,
                       const ras_clip_vertex *c) {
    ras_triangle t;
    if (!ras_setup_triangle_depth(a, b, c, p->fb->width, p->fb->height, p->config.depth,
                                  p->config.z_near, &t)) {
        p->counters.triangles_rejected_nonfinite++;
        return;
    }
    ras_pipeline_draw_screen_triangle(p, &t);
}

static bool clip_vertex_finite(const ras_clip_vertex *v) {
    return ras_vec4_finite(v->p_clip) && ras_vec3_finite(v->color) &&
           ras_vec3_finite(v->normal) && ras_vec2_finite(v->uv) && ras_vec3_finite(v->view_pos);
}

void ras_pipeline_draw_clip_triangle(ras_pipeline *p, const ras_clip_vertex *a,
                                     const ras_clip_vertex *b, const ras_clip_vertex *c) {
    ras_counters *k = &p->counters;
    k->triangles_in++;
    k->stages_run |= RAS_STAGE_CLIP | RAS_STAGE_SETUP;
    /* NaN positions would slip through every plane test (comparisons with NaN
     * are false both ways), so reject them before clipping; non-finite
     * varyings too, so a triangle the clipper splits is rejected (and
     * counted) once, not once per piece. */
    if (!clip_vertex_finite(a) || !clip_vertex_finite(b) || !clip_vertex_finite(c)) {
        k->triangles_rejected_nonfinite++;
        return;
    }
    ras_clip_vertex poly[RAS_CLIP_MAX_VERTICES];
    int n = 0;
    ras_clip_result r = ras_clip_triangle_far(a, b, c, p->config.z_far, poly, &n);
    if (r == RAS_CLIP_OUTSIDE) {
        k->triangles_clipped_away++;
        return;
    }
    if (r == RAS_CLIP_SPLIT) k->triangles_clip_split++;
    if (p->config.wireframe) {
        k->stages_run |= RAS_STAGE_WIREFRAME;
        draw_wire_polygon(p, poly, n);
        return;
    }
    k->stages_run |= RAS_STAGE_RASTER;
    if (p->config.shade || p->config.shader) k->stages_run |= RAS_STAGE_FRAGMENT;
    /* The clipped polygon is convex: a fan from its first corner covers it
     * exactly, and the fan's inner edges are shared, so watertight coverage
     * draws each sample once. */
    for (int i = 1; i + 1 < n; i++) raster_one(p, &poly[0], &poly[i], &poly[i + 1]);
}

bool ras_pipeline_draw_mesh(ras_pipeline *p, const ras_mesh *mesh, mat4s model, mat4s view,
                            mat4s projection, ras_error *err) {
    if (mesh->vertex_count > p->clip_capacity) {
        ras_clip_vertex *grown =
            realloc(p->clip_vertices, mesh->vertex_count * sizeof *p->clip_vertices);
        if (!grown)
            return ras_error_set(err, "out of memory transforming %zu vertices",
                                 mesh->vertex_count);
        p->clip_vertices = grown;
        p->clip_capacity = mesh->vertex_count;
    }
    double t0 = ras_now_ms();
    ras_vertex_transform(mesh, model, view, projection, p->config.varyings, p->clip_vertices);
    p->counters.stages_run |= RAS_STAGE_VERTEX;
    p->counters.vertices_transformed += mesh->vertex_count;
    double t1 = ras_now_ms();
    for (size_t i = 0; i < mesh->triangle_count; i++) {
        const unsigned *idx = &mesh->indices[3 * i];
        ras_pipeline_draw_clip_triangle(p, &p->clip_vertices[idx[0]],
                                        &p->clip_vertices[idx[1]], &p->clip_vertices[idx[2]]);
    }
    double t2 = ras_now_ms();
    p->counters.ms_vertex += t1 - t0;
    p->counters.ms_raster += t2 - t1;
    p->counters.ms_total += t2 - t0;
    return true;
}

void ras_pipeline_end_frame(ras_pipeline *p, ras_image *out) {
    double t0 = ras_now_ms();
    if (ras_resolve_frame(p->fb, p->config.resolve, out))
        p->counters.stages_run |= RAS_STAGE_RESOLVE;
    double dt = ras_now_ms() - t0;
    p->counters.ms_resolve += dt;
    p->counters.ms_total += dt;
}

/* The frame's buffers, in the words of their --dump sidecars and in the
 * order --dump writes them; the frame gives the sizes and the data
 * (ras_pipeline_buffer), and depth its words for the sample count and the
 * depth format. */
enum {
    BUFFER_DEPTH,
    BUFFER_COVERAGE,
    BUFFER_OVERDRAW,
    BUFFER_SAMPLE_COLOUR,
    BUFFER_NORMAL, /* the fragment stage's (stage5_fragment.h) */
    BUFFER_UV,
    BUFFER_VIEW_DEPTH,
    BUFFER_COUNT
};
static const ras_dump_buffer pipeline_buffers[BUFFER_COUNT] = {
    [BUFFER_DEPTH] = {.name = "depth",
                      .channels = 1,
                      .style = RAS_DUMP_SCALAR,
                      .empty = INFINITY,
                      .has_empty = true},
    [BUFFER_COVERAGE] = {.name = "coverage",
                         .what = "which samples some triangle covered (1) or none did (0); the "
                                 "picture shows the covered fraction of each pixel",
                         .units = "1 covered, 0 not",
                         .channels = 1,
                         .style = RAS_DUMP_SCALAR},
    [BUFFER_OVERDRAW] = {.name = "overdraw",
                         .what = "how many fragments were shaded at each pixel (every triangle "
                                 "that passed the depth test there, in drawing order, counts "
                                 "once; per sample with SSAA)",
                         .units = "fragments",
                         .channels = 1,
                         .style = RAS_DUMP_SCALAR,
                         .empty = 0.0f,
                         .has_empty = true},
    /* what the resolve averages: without it an MSAA colour mistake (one
     * colour per pixel scaled by coverage) shows in no buffer */
    [BUFFER_SAMPLE_COLOUR] = {.name = "sample_colour",
                              .what = "the colour each sample holds before the resolve averages "
                                      "them (the picture shows each pixel's mean)",
                              .units = "linear RGB in [0, 1]",
                              .channels = 3,
                              .style = RAS_DUMP_UNIT},
    [BUFFER_NORMAL] = {.name = "normal",
                       .what = "the unit normal each pixel's shader got (interpolated, "
                               "normalised), view space",
                       .units = "unit vector: x right, y up, z towards the eye",
                       .channels = 3,
                       .style = RAS_DUMP_VECTOR,
                       .empty = INFINITY,
                       .has_empty = true},
    [BUFFER_UV] = {.name = "uv",
                   .what = "the texture coordinates each pixel's shader got (perspective-correct "
                           "unless --affine); the third channel is 0",
                   .units = "u, v in texture space (1 = the texture's width, height)",
                   .channels = 3,
                   .style = RAS_DUMP_UNIT,
                   .empty = INFINITY,
                   .has_empty = true},
    [BUFFER_VIEW_DEPTH] = {.name = "view_depth",
                           .what = "how far in front of the eye each pixel's shaded point is: "
                                   "-z of its interpolated view-space position",
                           .units = "scene units",
                           .channels = 1,
                           .style = RAS_DUMP_SCALAR,
                           .empty = INFINITY,
                           .has_empty = true},
};

static const char *const depth_units[] = {
    [RAS_DEPTH_Z01] = "depth format z01: 0 at the near plane, 1 at the far plane; smaller is "
                      "closer",
    [RAS_DEPTH_INV_W] = "depth format inverse_w: -near/w, -1 at the near plane towards 0 far "
                        "away; smaller is closer",
};

bool ras_pipeline_buffer(const ras_pipeline *p, const char *name, ras_dump_buffer *out,
                         float **owned) {
    *owned = NULL;
    if (p->config.wireframe) return false; /* lines only: no depth, no coverage */
    int k = 0;
    while (k < BUFFER_COUNT && strcmp(name, pipeline_buffers[k].name)) k++;
    const ras_framebuffer *fb = p->fb;
    bool samples = fb->samples > 1;
    ras_dump_buffer b = k < BUFFER_COUNT ? pipeline_buffers[k] : (ras_dump_buffer){0};
    b.width = fb->width;
    b.height = fb->height;
    b.samples = fb->samples;
    switch (k) {
    case BUFFER_DEPTH:
        b.what = samples ? "the depth buffer, one value per sample: what the depth test "
                           "compared against at the end of the frame"
                         : "the depth buffer: what the depth test compared against at the end "
                           "of the frame";
        b.units = (unsigned)p->config.depth < RAS_DEPTH_FORMAT_COUNT ? depth_units[p->config.depth]
                                                                    : "depth";
        b.data = fb->depth;
        break;
    case BUFFER_COVERAGE: {
        if (!samples) return false;
        /* covered = a fragment was stored there: its depth is no longer the
         * cleared +INF */
        size_t n = (size_t)fb->width * fb->height * fb->samples;
        float *cov = malloc(n * sizeof *cov);
        if (!cov) return false;
        for (size_t i = 0; i < n; i++)
            cov[i] = fb->depth[i] != INFINITY ? 1.0f : 0.0f;
        *owned = cov;
        b.data = cov;
        break;
    }
    case BUFFER_SAMPLE_COLOUR:
        if (!samples) return false;
        b.data = (const float *)fb->color;
        break;
    case BUFFER_OVERDRAW:
        if (!p->overdraw) return false;
        b.samples = 1;
        b.data = p->overdraw;
        break;
    case BUFFER_NORMAL:
    case BUFFER_UV:
    case BUFFER_VIEW_DEPTH: {
        const ras_fragment_stage *s = &p->fragment;
        const float *data[] = {s->normal, s->uv, s->view_depth};
        if (!(b.data = data[k - BUFFER_NORMAL])) return false;
        b.samples = 1;
        break;
    }
    default: return false; /* no such buffer */
    }
    *out = b;
    return true;
}

bool ras_pipeline_dump(const ras_pipeline *p, const char *dir, int *written, ras_error *err) {
    if (written) *written = 0;
    for (int k = 0; k < BUFFER_COUNT; k++) {
        ras_dump_buffer b;
        float *owned = NULL;
        if (!ras_pipeline_buffer(p, pipeline_buffers[k].name, &b, &owned)) {
            if (k == BUFFER_COVERAGE && !p->config.wireframe && p->fb->samples > 1)
                return ras_error_set(err, "out of memory for the coverage buffer of --dump");
            continue;
        }
        bool ok = ras_dump_write(dir, &b, err);
        free(owned);
        if (!ok) return false;
        if (written) (*written)++;
    }
    return true;
}
