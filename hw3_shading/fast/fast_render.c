/* fast/fast_render.c — the fast renderer (hw3_fast). RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * Draws exactly what hw3_render's teaching loop draws (common/pipeline/ras_pipeline.c →
 * hw2's rasterize_triangle → hw3_shade_fragment → the shader → resolve_pixel),
 * bit for bit, counters included, but organised for speed
 * (docs/performance.md says why each step keeps the result):
 *
 *   1. setup, in submission order, on the calling thread: vertex transform,
 *      clipping, viewport and the fixed-point snap of every triangle — the
 *      same common/ functions and the same integer maths as the reference
 *      rasterizer — into a flat array of triangle records;
 *   2. binning: each record goes into the list of every 64×64 screen tile its
 *      bounding box touches, still in submission order;
 *   3. tiles, on N threads (pthreads; a shared counter hands out tiles): each
 *      worker clears a tile-sized depth buffer (and, with AA, colour
 *      buffer) that stays in cache,
 *      draws the tile's triangles in order — integer edge functions stepped by
 *      one addition per pixel (32-bit vector lanes where the values fit), 8×8
 *      blocks wholly outside an edge skipped — records the fragments that pass
 *      the depth test and, per sample, the last one to pass; then shades only
 *      the fragments that still own a sample (four at a time in vector lanes
 *      for all five shaders; trilinear texturing and unlit shading one at a
 *      time), and resolves the tile straight into the image.
 * A tile's pixels depend only on the tile's triangles in submission order, so
 * the image is the same for any thread count and any tile schedule.
 * No full-screen framebuffer exists: memory is the image plus, per worker,
 * one tile buffer, its sample-owner array and a fragment list that grows to
 * the busiest tile's fragments.
 */
#include "fast_render.h"

#include "rasterizer.h"   /* hw2: resolve_pixel (the same resolve) */
#include "stage2_clip.h"  /* ras_clip_triangle */
#include "stage3_setup.h" /* ras_setup_triangle */

#include "fast_simd.h" /* vf4, v3x4: four fragments at once */

#include <math.h>      /* llround, isfinite */
#include <pthread.h>   /* pthread_create, pthread_join */
#include <sched.h>     /* sched_yield */
#include <stdatomic.h> /* atomic_int */
#include <stddef.h>    /* offsetof */
#include <stdint.h>    /* int64_t, uint64_t */
#include <stdlib.h>    /* malloc, free, getenv, atoi */
#include <string.h>    /* memset */
#include <unistd.h>    /* sysconf */

#define TILE 64         /* pixels per tile side */
#define BLOCK 8         /* pixels per rejection block side */
#define MAX_THREADS 64
/* Objects a frame may have: the per-object payloads and counters are kept in
 * fixed arrays (a worker's); fast_accepts declines larger scenes, which the
 * teaching pipeline draws. */
#define FAST_MAX_OBJECTS 64
#define SUBPIXEL_BITS 8 /* as hw2_rasterize/solution/rasterizer.c */
#define SUBPIXEL_ONE (1 << SUBPIXEL_BITS)
#define FIXED_LIMIT_PX (1 << 20)
_Static_assert(RAS_RASTER_MAX_COORD <= FIXED_LIMIT_PX,
               "the fast path's int64 edge functions must hold the rasterizer's whole range");

/* ---- triangle records ------------------------------------------------------ */

typedef struct fast_tri {
    /* What rasterizing reads first, together (three cache lines; do_tile
     * prefetches them): */
    /* E_k(P) = a[k]·Px + b[k]·Py + c[k] (sub-pixel units) for the edge
     * opposite corner k of the CCW-ordered triangle; covered when
     * E_k >= thr[k] (thr = -bias: 0 on top-left edges, 1 elsewhere). */
    int64_t a[3], b[3], c[3], thr[3], area2;
    double inv_area2; /* RN(1 / area2), for ratio_to_float */
    int order[3]; /* original vertex index of corner k */
    int x0, x1, y0, y1; /* pixel bounding box, clamped, inclusive */
    int object;
    float z[3]; /* t.v[i].z: depth_of's operands */
    /* The batched shaders' inputs, packed so that four fragments are
     * gathered with a few vector loads and transposes (shade_prepare):
     * the corners' clip w (and a 0), and per corner normal xyz, view
     * position xyz and uv — copies of t's floats, in t's vertex order. */
    _Alignas(16) float w3[4];
    _Alignas(16) float attr[3][8];
    /* the rest of ras_triangle: screen x, y (trilinear's gradients) and
     * depth z, clip w; hw3 interpolates no vertex colour */
    vec4s v[3];
} fast_tri;

/* floor(a / 256) for a sub-pixel coordinate (|a| <= 2^28 within the
 * fixed-point limit): shifted while offset to a positive value, where >> is
 * exact floor division (on a negative value C leaves it to the compiler). */
static inline int64_t floor_px(int64_t a) {
    const int64_t offset = (int64_t)1 << 40; /* a multiple of 256 */
    return ((a + offset) >> SUBPIXEL_BITS) - (offset >> SUBPIXEL_BITS);
}

static int clamp_int(int64_t v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : (int)v; }

static bool is_top_left(int64_t dx, int64_t dy) { return dy < 0 || (dy == 0 && dx < 0); }

/* llround(x) for |x| <= 2^28 (a screen coordinate in sub-pixels within the
 * fixed-point limit), inline: the conversion truncates exactly, x − t is
 * exact (both lie within one binade's spacing of each other), and halves go
 * away from zero as llround's do. The library call costs more than the rest
 * of a triangle's snap. */
static inline int64_t round_half_away(double x) {
    int64_t t = (int64_t)x;
    double frac = x - (double)t;
    /* without branches: which way a fraction goes is a coin toss */
    return t + (int64_t)(frac >= 0.5) - (int64_t)(frac <= -0.5);
}

/* The reference rasterizer's setup_fixed, into a record. False: degenerate.
 * An empty (off-screen) box is kept with x1 < x0, as the reference does. */
static bool setup_fixed(fast_tri *r, int width, int height) {
    int64_t X[3], Y[3];
    for (int i = 0; i < 3; i++) {
        X[i] = round_half_away((double)r->v[i].x * SUBPIXEL_ONE);
        Y[i] = round_half_away((double)r->v[i].y * SUBPIXEL_ONE);
    }
    int64_t area2 = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area2 == 0) return false;
    r->order[0] = 0;
    r->order[1] = area2 > 0 ? 1 : 2;
    r->order[2] = area2 > 0 ? 2 : 1;
    r->area2 = area2 > 0 ? area2 : -area2;
    r->inv_area2 = 1.0 / (double)r->area2;
    for (int k = 0; k < 3; k++) {
        int i = r->order[(k + 1) % 3], j = r->order[(k + 2) % 3];
        int64_t dx = X[j] - X[i], dy = Y[j] - Y[i];
        r->a[k] = -dy;
        r->b[k] = dx;
        r->c[k] = dy * X[i] - dx * Y[i];
        r->thr[k] = is_top_left(dx, dy) ? 0 : 1;
    }
    int64_t minx = X[0], maxx = X[0], miny = Y[0], maxy = Y[0];
    for (int i = 1; i < 3; i++) {
        minx = X[i] < minx ? X[i] : minx;
        maxx = X[i] > maxx ? X[i] : maxx;
        miny = Y[i] < miny ? Y[i] : miny;
        maxy = Y[i] > maxy ? Y[i] : maxy;
    }
    r->x0 = clamp_int(floor_px(minx), 0, width - 1);
    r->x1 = clamp_int(floor_px(maxx), 0, width - 1);
    r->y0 = clamp_int(floor_px(miny), 0, height - 1);
    r->y1 = clamp_int(floor_px(maxy), 0, height - 1);
    if (floor_px(maxx) < 0 || floor_px(minx) >= width ||
        floor_px(maxy) < 0 || floor_px(miny) >= height)
        r->x1 = r->x0 - 1;
    return true;
}

typedef struct tri_list {
    fast_tri *tri;
    size_t count, capacity;
} tri_list;

/* ras_pipeline.c's clip_vertex_finite (ras_vec4_finite(p_clip) &&
 * ras_vec3_finite(color) && ...): its fifteen isfinite in one expression,
 * without a call and a branch each. */
static bool clip_vertex_finite(const ras_clip_vertex *v) {
    const vec4s p = v->p_clip;
    const vec3s c = v->color, n = v->normal, q = v->view_pos;
    return isfinite(p.x) & isfinite(p.y) & isfinite(p.z) & isfinite(p.w) & isfinite(c.x) &
           isfinite(c.y) & isfinite(c.z) & isfinite(n.x) & isfinite(n.y) & isfinite(n.z) &
           isfinite(v->uv.x) & isfinite(v->uv.y) & isfinite(q.x) & isfinite(q.y) & isfinite(q.z);
}

/* ras_pipeline_draw_clip_triangle + the reference rasterizer's prologue, with
 * the same counters; records what would be rasterized. */
/* Per vertex, computed once when the vertex is transformed (a vertex is shared
 * by about six triangles): */
enum {
    VERTEX_FINITE = 1, /* clip_vertex_finite */
    SCREEN_FINITE = 2
}; /* ras_viewport's result is finite */

static bool setup_triangle(tri_list *L, const ras_clip_vertex *a, const ras_clip_vertex *b,
                           const ras_clip_vertex *c, const unsigned char flags[3],
                           const unsigned char outcode[3], const vec4s *screen[3], int object,
                           int width, int height, ras_counters *k) {
    k->triangles_in++;
    if (!(flags[0] & flags[1] & flags[2] & VERTEX_FINITE)) {
        k->triangles_rejected_nonfinite++;
        return true;
    }
    ras_clip_vertex poly[RAS_CLIP_MAX_VERTICES];
    int n = 3;
    /* ras_clip_triangle's own classification, from the corners' outcodes
     * (computed once per vertex): only a triangle that straddles a plane is
     * handed to it. */
    ras_clip_result cr = RAS_CLIP_INSIDE;
    if (outcode[0] & outcode[1] & outcode[2])
        cr = RAS_CLIP_OUTSIDE;
    else if (outcode[0] | outcode[1] | outcode[2])
        cr = ras_clip_triangle(a, b, c, poly, &n);
    if (cr == RAS_CLIP_OUTSIDE) {
        k->triangles_clipped_away++;
        return true;
    }
    if (cr == RAS_CLIP_SPLIT) k->triangles_clip_split++;
    k->stages_run |= RAS_STAGE_RASTER | RAS_STAGE_FRAGMENT;
    for (int i = 1; i + 1 < n; i++) {
        if (L->count == L->capacity) {
            size_t cap = L->capacity ? 2 * L->capacity : 1024;
            fast_tri *grown = realloc(L->tri, cap * sizeof *grown);
            if (!grown) return false;
            L->tri = grown;
            L->capacity = cap;
        }
        fast_tri *r = &L->tri[L->count];
        /* the corners' screen position and varyings: poly is a, b, c
         * unless clipped */
        const vec4s *pos[3];
        const ras_clip_vertex *in[3] = {a, b, c};
        ras_triangle t;
        bool set;
        if (cr == RAS_CLIP_INSIDE) {
            /* ras_setup_triangle's viewport per corner, and its finiteness
             * test (the varyings passed VERTEX_FINITE) */
            for (int v = 0; v < 3; v++) pos[v] = screen[v];
            set = flags[0] & flags[1] & flags[2] & SCREEN_FINITE;
        } else {
            set = ras_setup_triangle(&poly[0], &poly[i], &poly[i + 1], width, height, &t);
            in[0] = &poly[0], in[1] = &poly[i], in[2] = &poly[i + 1];
            for (int v = 0; v < 3; v++) pos[v] = &t.v[v];
        }
        if (!set) {
            k->triangles_rejected_nonfinite++;
            continue;
        }
        for (int v = 0; v < 3; v++) r->v[v] = *pos[v];
        /* The rasterizer's range (stage4_raster.h), tested where and as the
         * teaching pipeline tests it (ras_raster_check_range, before the
         * rasterize hook): a triangle beyond it is refused and counted by
         * both, never skipped by one and drawn by the other. The guard band
         * (stage2_clip.h) keeps every corner within 4.5 frames, so no frame
         * the pipeline makes reaches it; the fixed-point arithmetic below
         * holds to FIXED_LIMIT_PX, further still. */
        ras_triangle rt;
        for (int v = 0; v < 3; v++) rt.v[v] = r->v[v];
        if (!ras_raster_in_range(&rt)) {
            k->triangles_rejected_range++;
            continue;
        }
        k->triangles_rasterized++; /* hw3 draws with RAS_CULL_NONE */
        if (!setup_fixed(r, width, height)) {
            k->triangles_degenerate++;
            continue;
        }
        if (r->x1 < r->x0) continue; /* off screen: nothing tested */
        r->object = object;
        for (int v = 0; v < 3; v++) {
            r->w3[v] = r->v[v].w;
            r->z[v] = r->v[v].z;
            /* ras_setup_triangle copies the varyings as they are */
            float *a = r->attr[v];
            const ras_clip_vertex *c = in[v];
            a[0] = c->normal.x, a[1] = c->normal.y, a[2] = c->normal.z;
            a[3] = c->view_pos.x, a[4] = c->view_pos.y, a[5] = c->view_pos.z;
            a[6] = c->uv.x, a[7] = c->uv.y;
        }
        r->w3[3] = 0.0f;
        L->count++;
    }
    return true;
}

/* ---- shading: hw3_shade_fragment, same arithmetic ------------------------ */

typedef struct frame {
    const ras_scene *scene;
    const ras_scene_assets *assets;
    const hw3_fragment_stage *stage;
    int width, height, n; /* samples per pixel */
    bool ssaa;
    ras_sample_pattern pattern;
    int64_t off_x[RAS_MAX_SAMPLES + 1], off_y[RAS_MAX_SAMPLES + 1]; /* [n] = centre */
    /* the box of those offsets (samples and centre): block rejection's corners */
    int64_t omin_x, omax_x, omin_y, omax_y;
    unsigned varyings;
    uint64_t varyings_per_fragment;
    int centre_sample; /* a sample whose position is the pixel centre, or -1 */
    /* per object (each has its own p): powf(x, p) is +0 for 0 <= x <= spec_zero
     * (spec_zero_of) */
    float spec_zero[FAST_MAX_OBJECTS];
    /* bins: tile t holds bin_tri[bin_start[t] .. bin_start[t+1]) */
    int tiles_x, tiles_y;
    size_t *bin_start;
    const fast_tri **bin_tri;
    atomic_int next_tile;
    /* setup, shared out in chunks (setup_chunks) */
    const mat4s *models;
    mat4s view, projection;
    ras_clip_vertex *clip; /* every object's vertices, object o from clip_base[o] */
    vec4s *screen;         /* their ras_viewport */
    unsigned char *vflags; /* VERTEX_FINITE | SCREEN_FINITE */
    unsigned char *voutcode; /* ras_clip_outcode */
    size_t *clip_base;     /* [object_count] */
    size_t *tri_first;     /* [object_count + 1]: object o's first triangle, counted over all */
    int vchunks, tchunks;  /* vertex chunks: (vchunk_obj, vchunk_start) */
    int *vchunk_obj;
    size_t *vchunk_start;
    tri_list *lists; /* [tchunks]: chunk c's records, in submission order */
    atomic_int next_vchunk, vchunks_done, next_tchunk, tchunks_done, binned;
    atomic_bool failed; /* out of memory somewhere */
    double t_setup;     /* when setup ended (ms_vertex) */
    ras_image *out;
    int batch; /* BATCH_*: shade through the queue, four at a time */
    /* One sample per pixel and a batched shader: a fragment that passes the
     * depth test is recorded at its pixel (frags[base]), replacing the one
     * it hides, instead of appended (see shade_deferred). */
    bool per_pixel;
} frame;

/* A visible fragment waiting to be shaded: its colour goes to the tile
 * samples base + k for every bit k of mask. */
typedef struct queued {
    const fast_tri *r;
    vec3s bary;
    float pad; /* 0: bary is loaded as four floats (shade_prepare) */
    int base;
    int object; /* r->object, at hand for queue_fragment */
    uint64_t mask; /* RAS_MAX_SAMPLES is 64 */
} queued;
/* shade_prepare loads bary and pad as one four-float vector */
_Static_assert(offsetof(queued, pad) == offsetof(queued, bary) + 3 * sizeof(float),
               "queued.pad must follow bary");

#define QUEUE 8
#define DEPTH_PAD 8 /* floats past a tile's depth samples (one is used) */

typedef struct worker {
    frame *fr;
    vec3s *color; /* TILE² · n, sample s of tile pixel (lx, ly) at (ly·TILE + lx)·n + s */
    float *depth;
    fragment_shader_payload pay[FAST_MAX_OBJECTS];
    ras_counters k;
    ras_counters ks; /* setup's counters */
    pthread_t thread;
    const queued *q[QUEUE]; /* fragments of frags, queued for shading */
    int qn;
    /* Deferred shading (every shader): the tile's fragments in drawing
     * order, and for every sample the fragment that last passed its depth
     * test (read only where the depth is below +inf). */
    queued *frags;
    size_t nfrag, frag_cap;
    int32_t *owner;
    uint64_t shaded; /* fragments this worker really shaded */
    /* What one fragment of object o adds to the counters when shaded by the
     * scalar shaders (learnt from the first one shaded: a shader's counts
     * depend on the object's material and textures, not on the fragment). */
    ras_counters per_fragment[FAST_MAX_OBJECTS];
    bool per_fragment_known[FAST_MAX_OBJECTS];
    /* Batched shaders: per object, the fragments that passed a depth test
     * but were hidden by the end of their tile, counted as shaded (not
     * shaded) when the worker is done. per_pixel mode adds every pass and
     * takes back the ones still visible. */
    int64_t hidden[FAST_MAX_OBJECTS];
} worker;

/* perspective_correct_barycentric (solution/shading.c), inlined; w: the
 * corners' clip w. */
static inline vec3s persp_bary(const float w[3], vec3s bs) {
    vec3s b = {{bs.x / w[0], bs.y / w[1], bs.z / w[2]}};
    float sum = b.x + b.y + b.z;
    if (!(sum > 0.0f) || !isfinite(sum)) return bs;
    return glms_vec3_scale(b, 1.0f / sum);
}

/* The reference's interpolation of a varying (a0·b.x + a1·b.y + a2·b.z per
 * component, in that order: glms_vec3_scale then two glms_vec3_muladds, or
 * the same sums written out) from the record's packed varyings, float `at`
 * on (0 normal, 3 view position, 6 uv). */
static inline vec3s interp3(vec3s b, const float attr[3][8], int at) {
    vec3s r;
    for (int c = 0; c < 3; c++)
        r.raw[c] = attr[0][at + c] * b.x + attr[1][at + c] * b.y + attr[2][at + c] * b.z;
    return r;
}
static inline vec2s interp2(vec3s b, const float attr[3][8], int at) {
    return (vec2s){{attr[0][at] * b.x + attr[1][at] * b.y + attr[2][at] * b.z,
                    attr[0][at + 1] * b.x + attr[1][at + 1] * b.y + attr[2][at + 1] * b.z}};
}

/* powf(x, p) is +0 for 0 <= x <= spec_zero_of(p): x <= 2^(-151/p) (rounded
 * down) gives x^p <= 2^-151, a quarter of the smallest subnormal float, so the
 * exact power rounds to +0, and powf, whose error is far below a factor of 2,
 * returns +0 too. -1 (never) when p < 1 or p is not finite. The one bound of
 * the scalar and the four-lane Blinn-Phong (frame.spec_zero, per object). */
static float spec_zero_of(float p) {
    if (!(p >= 1.0f) || !isfinite(p)) return -1.0f;
    return nextafterf((float)pow(2.0, -151.0 / p), 0.0f);
}

/* blinn_phong_lighting (solution/shading.c) with the same float operations in
 * the same order, except that powf is not called where its result is certainly
 * +0 (x <= spec_zero: spec_zero_of), and 0·anything added to the colour adds
 * nothing. The plain shader pays powf's slow underflow path on most of the
 * surface (n·h < 0.56 underflows at p = 150). */
static vec3s fast_blinn_phong(const fragment_shader_payload *payload, vec3s kd, vec3s point,
                              vec3s normal, float spec_zero) {
    if (payload->counters && payload->light_count > 0) { /* ambient alone is no lighting work */
        payload->counters->stages_run |= RAS_STAGE_LIGHTING;
        payload->counters->lighting_evaluations += (uint64_t)payload->light_count;
    }
    vec3s n = glms_vec3_normalize(normal);
    vec3s v = glms_vec3_normalize(glms_vec3_negate(point));
    vec3s color = glms_vec3_mul(payload->ka, payload->ambient_intensity);
    for (int i = 0; i < payload->light_count; i++) {
        const light *L = &payload->lights[i];
        vec3s to_light = glms_vec3_sub(L->position, point);
        float r2 = glms_vec3_dot(to_light, to_light);
        vec3s l = glms_vec3_normalize(to_light);
        vec3s h = glms_vec3_normalize(glms_vec3_add(l, v));
        vec3s irradiance = glms_vec3_divs(L->intensity, r2);
        float nl = glms_vec3_dot(n, l), nh = glms_vec3_dot(n, h);
        float diffuse = nl > 0.0f ? nl : 0.0f; /* fmaxf(0, x): NaN gives 0 too */
        float x = nh > 0.0f ? nh : 0.0f;
        float specular = x <= spec_zero ? 0.0f : powf(x, payload->p);
        color = glms_vec3_add(color, glms_vec3_scale(glms_vec3_mul(kd, irradiance), diffuse));
        color = glms_vec3_add(color,
                              glms_vec3_scale(glms_vec3_mul(payload->ks, irradiance), specular));
    }
    return color;
}

static vec3s shade(worker *w, const fast_tri *r, vec3s bary) {
    const frame *fr = w->fr;
    fragment_shader_payload *pay = &w->pay[r->object];
    bool persp = fr->stage->perspective;
    unsigned vary = fr->varyings;
    vec3s b = persp ? persp_bary(r->w3, bary) : bary;
    if (vary & RAS_VARYING_NORMAL) pay->normal = glms_vec3_normalize(interp3(b, r->attr, 0));
    if (vary & RAS_VARYING_VIEW_POS) pay->view_pos = interp3(b, r->attr, 3);
    if (vary & RAS_VARYING_UV) {
        pay->uv = interp2(b, r->attr, 6);
        if (pay->filter == FILTER_TRILINEAR) {
            /* scene.c's bary_gradients and finite difference */
            const vec4s *v = r->v;
            float area2 = (v[1].x - v[0].x) * (v[2].y - v[0].y) -
                          (v[2].x - v[0].x) * (v[1].y - v[0].y); /* ras_triangle_area2 */
            float inv = area2 != 0.0f ? 1.0f / area2 : 0.0f;
            vec3s d_dx = {{-(v[2].y - v[1].y) * inv, -(v[0].y - v[2].y) * inv,
                           -(v[1].y - v[0].y) * inv}};
            vec3s d_dy = {{(v[2].x - v[1].x) * inv, (v[0].x - v[2].x) * inv,
                           (v[1].x - v[0].x) * inv}};
            vec3s bx = glms_vec3_add(bary, d_dx), by = glms_vec3_add(bary, d_dy);
            vec2s uv_x = interp2(persp ? persp_bary(r->w3, bx) : bx, r->attr, 6);
            vec2s uv_y = interp2(persp ? persp_bary(r->w3, by) : by, r->attr, 6);
            pay->duv_dx = glms_vec2_sub(uv_x, pay->uv);
            pay->duv_dy = glms_vec2_sub(uv_y, pay->uv);
        }
    }
    w->k.varyings_interpolated += fr->varyings_per_fragment;
    w->k.fragments_shaded++;
    if (fr->stage->shader == phong_fragment_shader)
        return fast_blinn_phong(pay, pay->color, pay->view_pos, pay->normal,
                                fr->spec_zero[r->object]);
    if (fr->stage->shader == texture_fragment_shader) {
        vec3s kd = pay->texture ? texture_sample(pay, pay->texture, pay->uv) : pay->color;
        return fast_blinn_phong(pay, kd, pay->view_pos, pay->normal, fr->spec_zero[r->object]);
    }
    return fr->stage->shader(pay);
}

/* ---- batched shading: four fragments at a time ----------------------------- */

/* The Normal, Blinn-Phong, texture, bump and displacement shaders are
 * straight-line float arithmetic, so visible fragments are queued (in drawing order) and shaded
 * four at a time by the same operations in vector lanes (fast_simd.h says why
 * that is bit-exact). Colours are written when the queue is flushed; the
 * fragments shade_deferred queues own disjoint samples, so the order of the
 * writes does not matter (depth was tested and written when each fragment
 * was drawn). A queue
 * holds one object's fragments (one material). powf, nearest lookups and the
 * rare lanes with a near-zero vector to normalise (see v3_normalize) are done
 * per lane with the scalar functions. */

enum { BATCH_NONE, BATCH_NORMAL, BATCH_PHONG, BATCH_TEXTURE, BATCH_BUMP, BATCH_DISPLACEMENT };

/* shade() without counting: for a lane redone by the scalar path after the
 * vector path has already counted it. */
static vec3s shade_silent(worker *w, const fast_tri *r, vec3s bary) {
    ras_counters saved = w->k; /* the payloads' counters point at w->k too */
    vec3s c = shade(w, r, bary);
    w->k = saved;
    return c;
}

/* texture_sample_bilinear (solution/shading.c's bilinear_level at level 0)
 * for four lookups, in two halves. bilinear_x4_footprint: the coordinates,
 * floors, weights and wrapped texel indices in vector lanes, giving the four
 * texels each lookup reads (shade_prepare prefetches them). A lane whose
 * texel index falls outside [-1, size - 1] (the reference's range, asserted
 * here rather than assumed) is left to the reference function: bit 1 << i of
 * fallback. bilinear_x4_blend: the texel blends, one lookup per vector (lane =
 * colour channel) with lerp3's operations in its order, so every lane is the
 * reference's float. */
typedef struct footprint {
    const vec3s *px; /* level 0's texels */
    /* per lane, the texel offsets of (i0, j0), (i0+1, j0), (i0, j0+1),
     * (i0+1, j0+1) after wrapping (0 in a fallback lane) */
    vi4 o[4];
    vf4 sx, sy;
    unsigned looked_up, fallback; /* lanes done here / by the reference */
    bool last; /* some offset is the last texel: no 16-byte load there */
} footprint;

static inline const vec3s *footprint_texel(const footprint *F, int lane, int k) {
    return F->px + F->o[k][lane];
}

/* One axis of four lookups (the reference's bilinear_axis_at): safe_coord, x = t·n − 0.5, its
 * floor and fraction, and the two wrapped texel indices times `stride` (1 for
 * columns, the width for rows). bad: lanes whose floor leaves [-1, n - 1]. */
typedef struct axis4 {
    vi4 a, b; /* wrapped index of floor(x), of floor(x) + 1, times stride */
    vf4 s;    /* x - floor(x) */
    vi4 bad;
} axis4;

static inline axis4 axis_x4(vf4 t, int n, int stride, ras_wrap wrap) {
    vf4 zero = vf4_splat(0.0f), one = vf4_splat(1.0f);
    /* safe_coord */
    vi4 finite = (t == t) & ((vf4)((vi4)t & 0x7fffffff) <= vf4_splat(FLT_MAX));
    t = vf4_select(finite, t, zero);
    if (wrap == RAS_WRAP_REPEAT)
        t = t - vf4_floor(t);
    else
        t = vf4_select(t < zero, zero, vf4_select(t > one, one, t));
    vf4 x = t * vf4_splat((float)n) - vf4_splat(0.5f);
    axis4 A;
    /* t is in [0, 1], so x is in [-0.5, n - 0.5] and small enough for the
     * conversion (the range test below still guards): floorf is the
     * truncation, minus one where it went up; x is never -0 (a difference
     * x - 0.5 that is zero is +0), so the sign of a zero floor is +. */
    vi4 bad = ~((x >= vf4_splat(-1.0f)) & (x < vf4_splat((float)n)));
    vf4 xs = vf4_select(bad, zero, x);
    vi4 ti = __builtin_convertvector(xs, vi4);
    vf4 tf = __builtin_convertvector(ti, vf4);
    vi4 up = tf > xs;
    vi4 i0 = ti + up; /* up is -1 where truncation went up */
    vf4 x0f = tf - (vf4)((vi4)one & up);
    A.s = x - x0f;
    vi4 i1 = i0 + 1, N = {n, n, n, n}, z = {0, 0, 0, 0};
    bad |= (i0 < -1) | (i0 > N - 1);
    vi4 ia, ib; /* ras_texture_wrap_index of i0, i0 + 1 */
    if (wrap == RAS_WRAP_REPEAT) {
        ia = i0 + (N & (i0 < z));
        ib = i1 - (N & (i1 >= N));
    } else {
        vi4 in = i1 < N;
        ia = i0 & ~(i0 < z);
        ib = (i1 & in) | ((N - 1) & ~in);
    }
    ia &= ~bad, ib &= ~bad; /* fallback lanes read texel 0 (and are replaced) */
    if (stride != 1) {
        vi4 S = {stride, stride, stride, stride};
        ia *= S, ib *= S;
    }
    A.a = ia, A.b = ib, A.bad = bad;
    return A;
}

/* The footprints of lookups (X, Y): lane i reads column X[i], row Y[i]. */
static void footprint_of(const ras_texture *tex, const axis4 *X, const axis4 *Y, int lanes,
                         footprint *F) {
    const int w = tex->level_width[0], h = tex->level_height[0]; /* as bilinear_level */
    F->px = tex->levels[0] ? tex->levels[0] : tex->texels;
    F->sx = X->s;
    F->sy = Y->s;
    vi4 bad = X->bad | Y->bad;
    F->o[0] = (Y->a + X->a) & ~bad, F->o[1] = (Y->a + X->b) & ~bad;
    F->o[2] = (Y->b + X->a) & ~bad, F->o[3] = (Y->b + X->b) & ~bad;
    int L = w * h - 1;
    vi4 Lv = {L, L, L, L};
    F->last = vi4_any((F->o[0] == Lv) | (F->o[1] == Lv) | (F->o[2] == Lv) | (F->o[3] == Lv));
    unsigned all = (1u << lanes) - 1;
    F->fallback = vi4_sign_bits(bad) & all;
    F->looked_up = all & ~F->fallback;
}

static void bilinear_x4_footprint(const ras_texture *tex, vf4 u, vf4 v, int lanes,
                                  footprint *F) {
    const int w = tex->level_width[0], h = tex->level_height[0];
    axis4 X = axis_x4(u, w, 1, tex->wrap), Y = axis_x4(v, h, w, tex->wrap);
    footprint_of(tex, &X, &Y, lanes, F);
}

/* Every lane's blend (a fallback lane's, of texel 0, is replaced by the
 * caller's; lanes past those looked up are unused). */
static v3x4 bilinear_x4_blend(const footprint *F) {
    vf4 out[4];
    for (int i = 0; i < 4; i++) {
        vf4 a, b, c, d;
        if (__builtin_expect(!F->last, 1)) { /* 16 bytes: the next texel's x too */
            a = vf4_load(&footprint_texel(F, i, 0)->x), b = vf4_load(&footprint_texel(F, i, 1)->x);
            c = vf4_load(&footprint_texel(F, i, 2)->x), d = vf4_load(&footprint_texel(F, i, 3)->x);
        } else {
            a = vf4_load3(&footprint_texel(F, i, 0)->x), b = vf4_load3(&footprint_texel(F, i, 1)->x);
            c = vf4_load3(&footprint_texel(F, i, 2)->x), d = vf4_load3(&footprint_texel(F, i, 3)->x);
        }
        vf4 s = vf4_splat(F->sx[i]), tt = vf4_splat(F->sy[i]);
        vf4 bottom = a + (b - a) * s, top = c + (d - c) * s;
        out[i] = bottom + (top - bottom) * tt;
    }
    vf4_transpose(&out[0], &out[1], &out[2], &out[3]);
    return (v3x4){out[0], out[1], out[2]};
}

/* 255·|rgb| of the bilinear lookups of footprint F (at u, v). */
static inline vf4 height_of(const ras_texture *tex, const footprint *F, vf4 u, vf4 v,
                            int lanes) {
    v3x4 rgb = bilinear_x4_blend(F);
    if (__builtin_expect(F->fallback != 0, 0))
        for (int i = 0; i < lanes; i++) {
            if (!(F->fallback >> i & 1)) continue;
            vec3s c = texture_sample_bilinear(tex, u[i], v[i]);
            rgb.x[i] = c.x, rgb.y[i] = c.y, rgb.z[i] = c.z;
        }
    return vf4_splat(255.0f) * vf4_sqrt(v3_dot(rgb, rgb));
}

/* height_sample (shading.h) for four lookups: |rgb| · 255 of the height map
 * read bilinearly (any filter but nearest) or nearest, lane by lane with the
 * reference's operations (glm_vec3_norm: sqrtf of (x·x + y·y) + z·z). Lanes
 * from `lanes` on are not looked up. Counts nothing (the caller does). */
static vf4 height_x4(const fragment_shader_payload *pay, vf4 u, vf4 v, int lanes) {
    const ras_texture *tex = pay->height_map;
    v3x4 rgb;
    if (pay->filter == FILTER_NEAREST) {
        rgb = v3_splat((vec3s){{0.0f, 0.0f, 0.0f}});
        for (int i = 0; i < lanes; i++) {
            vec3s c = ras_texture_sample_nearest(tex, u[i], v[i]);
            rgb.x[i] = c.x, rgb.y[i] = c.y, rgb.z[i] = c.z;
        }
    } else {
        footprint F;
        bilinear_x4_footprint(tex, u, v, lanes, &F);
        return height_of(tex, &F, u, v, lanes);
    }
    return vf4_splat(255.0f) * vf4_sqrt(v3_dot(rgb, rgb));
}

/* bump_normal (solution/shading.c) for four fragments: n = normalize(normal)
 * (the payload's normal, itself normalised), tangent_frame's t and b, the
 * three height lookups and TBN · (−dU, −dV, 1) normalised — the reference's
 * float operations in its order, lane by lane; a lane whose result is not
 * finite keeps n, as the reference does. *h receives h(u, v) (displacement
 * reuses it: the same lookup gives the same float). */
static v3x4 bump_normal_x4(const fragment_shader_payload *pay, v3x4 normal, vf4 u, vf4 v,
                           int lanes, vi4 *odd, vf4 *h_out) {
    v3x4 n = v3_normalize(normal, odd);
    const ras_texture *hm = pay->height_map;
    if (!hm) {
        *h_out = vf4_splat(0.0f);
        return n;
    }
    /* tangent_frame */
    vf4 zero = vf4_splat(0.0f), one = vf4_splat(1.0f);
    vf4 s = vf4_sqrt(n.x * n.x + n.z * n.z);
    vi4 big = s > vf4_splat(1e-6f);
    v3x4 t = {vf4_select(big, n.x * n.y / s, one), vf4_select(big, s, zero),
              vf4_select(big, n.z * n.y / s, zero)};
    v3x4 b = {n.y * t.z - n.z * t.y, n.z * t.x - n.x * t.z, n.x * t.y - n.y * t.x};
    vf4 u1 = u + vf4_splat(1.0f / (float)hm->width);
    vf4 v1 = v + vf4_splat(1.0f / (float)hm->height);
    vf4 h, hu, hv;
    if (pay->filter == FILTER_NEAREST) {
        h = height_x4(pay, u, v, lanes);
        hu = height_x4(pay, u1, v, lanes);
        hv = height_x4(pay, u, v1, lanes);
    } else {
        /* the three lookups share their columns and rows: u and v1 share u's,
         * v and u1 share v's */
        const int w = hm->level_width[0], hh = hm->level_height[0];
        axis4 X = axis_x4(u, w, 1, hm->wrap), X1 = axis_x4(u1, w, 1, hm->wrap);
        axis4 Y = axis_x4(v, hh, w, hm->wrap), Y1 = axis_x4(v1, hh, w, hm->wrap);
        footprint F;
        footprint_of(hm, &X, &Y, lanes, &F);
        h = height_of(hm, &F, u, v, lanes);
        footprint_of(hm, &X1, &Y, lanes, &F);
        hu = height_of(hm, &F, u1, v, lanes);
        footprint_of(hm, &X, &Y1, lanes, &F);
        hv = height_of(hm, &F, u, v1, lanes);
    }
    vf4 k = vf4_splat(pay->kh * pay->kn);
    vf4 du = k * (hu - h);
    vf4 dv = k * (hv - h);
    v3x4 p = v3_add(v3_scale(t, -du), v3_scale(b, -dv));
    v3x4 bumped = v3_normalize(v3_add(p, n), odd);
    vf4 fmax = vf4_splat(FLT_MAX);
    vi4 fin = (vf4)((vi4)bumped.x & 0x7fffffff) <= fmax;
    fin &= (vf4)((vi4)bumped.y & 0x7fffffff) <= fmax;
    fin &= (vf4)((vi4)bumped.z & 0x7fffffff) <= fmax;
    *h_out = h;
    return (v3x4){vf4_select(fin, bumped.x, n.x), vf4_select(fin, bumped.y, n.y),
                  vf4_select(fin, bumped.z, n.z)};
}

/* What height_sample and bump_normal add to the counters for `count`
 * fragments: `lookups` height lookups each. */
static void count_heights(const fragment_shader_payload *pay, uint64_t lookups, uint64_t count) {
    if (!pay->counters || !pay->height_map) return;
    pay->counters->stages_run |= RAS_STAGE_TEXTURE | RAS_STAGE_BUMP;
    pay->counters->texels_fetched += lookups * (pay->filter == FILTER_NEAREST ? 1 : 4) * count;
}

/* Four fragments between the two halves of their shading. */
typedef struct lanes4 {
    const queued *const *q;
    int lanes;
    vi4 odd;
    v3x4 b, color;
    vf4 u, v; /* texture coordinates (BATCH_TEXTURE) */
    footprint texels; /* their bilinear footprints (BATCH_TEXTURE, a texture) */
    /* per light: I/r², max(0, n·l), the specular power */
    v3x4 irradiance[HW3_MAX_LIGHTS];
    vf4 diffuse[HW3_MAX_LIGHTS], specular[HW3_MAX_LIGHTS];
} lanes4;

/* The gather: four fragments' screen barycentrics and corner w, one record
 * per vector, transposed into one vector per field (unused lanes repeat lane
 * 0, as e[] does), then persp_bary in lanes. */
static inline __attribute__((always_inline)) v3x4 weights_x4(const frame *fr,
                                                             const queued *const e[4]) {
    v3x4 bs, wv;
    vf4 pad;
    bs.x = vf4_load(&e[0]->bary.x), bs.y = vf4_load(&e[1]->bary.x);
    bs.z = vf4_load(&e[2]->bary.x), pad = vf4_load(&e[3]->bary.x);
    vf4_transpose(&bs.x, &bs.y, &bs.z, &pad);
    wv.x = vf4_load(e[0]->r->w3), wv.y = vf4_load(e[1]->r->w3);
    wv.z = vf4_load(e[2]->r->w3), pad = vf4_load(e[3]->r->w3);
    vf4_transpose(&wv.x, &wv.y, &wv.z, &pad);
    if (!fr->stage->perspective) return bs;
    v3x4 p = {bs.x / wv.x, bs.y / wv.y, bs.z / wv.z};
    vf4 sum = p.x + p.y + p.z;
    vi4 ok = (sum > vf4_splat(0.0f)) & (sum <= vf4_splat(FLT_MAX)); /* > 0 and finite */
    v3x4 s = v3_scale(p, vf4_splat(1.0f) / sum);
    return (v3x4){vf4_select(ok, s.x, bs.x), vf4_select(ok, s.y, bs.y), vf4_select(ok, s.z, bs.z)};
}

/* The varyings, one fragment per vector: lane j of lo/hi is varying j
 * (normal xyz, view position x | view position yz, uv), interpolated as
 * a0·b.x + a1·b.y + a2·b.z — interp3's and interp2's operations in their
 * order — then transposed to one vector per varying. hi only with want_hi
 * (the Normal shader reads the normal alone). */
static inline __attribute__((always_inline)) void
varyings_x4(const queued *const e[4], v3x4 b, bool want_hi, vf4 lo[4], vf4 hi[4]) {
    for (int i = 0; i < 4; i++) {
        const float(*a)[8] = e[i]->r->attr;
        vf4 bx = vf4_splat(b.x[i]), by = vf4_splat(b.y[i]), bz = vf4_splat(b.z[i]);
        lo[i] = vf4_load(a[0]) * bx;
        lo[i] = lo[i] + vf4_load(a[1]) * by;
        lo[i] = lo[i] + vf4_load(a[2]) * bz;
        if (want_hi) {
            hi[i] = vf4_load(a[0] + 4) * bx;
            hi[i] = hi[i] + vf4_load(a[1] + 4) * by;
            hi[i] = hi[i] + vf4_load(a[2] + 4) * bz;
        }
    }
    vf4_transpose(&lo[0], &lo[1], &lo[2], &lo[3]);
    if (want_hi) vf4_transpose(&hi[0], &hi[1], &hi[2], &hi[3]);
}

/* fast_blinn_phong up to kd, in lanes: per light, I/r², max(0, n·l) and the
 * specular power (powf lane by lane, only where it can be non-zero). */
static inline __attribute__((always_inline)) void
light_terms_x4(const fragment_shader_payload *pay, float spec_zero, int lanes, v3x4 normal,
               v3x4 point, vi4 *odd, lanes4 *S) {
    if (pay->counters) {
        pay->counters->stages_run |= RAS_STAGE_LIGHTING;
        pay->counters->lighting_evaluations += (uint64_t)pay->light_count * (uint64_t)lanes;
    }
    v3x4 n = v3_normalize(normal, odd);
    v3x4 v = v3_normalize((v3x4){-point.x, -point.y, -point.z}, odd);
    vf4 zero = vf4_splat(0.0f);
    for (int li = 0; li < pay->light_count; li++) {
        const light *L = &pay->lights[li];
        v3x4 to_light = v3_sub(v3_splat(L->position), point);
        vf4 r2 = v3_dot(to_light, to_light);
        v3x4 l = v3_normalize(to_light, odd);
        v3x4 h = v3_normalize(v3_add(l, v), odd);
        if (!memcmp(&L->intensity.x, &L->intensity.y, sizeof(float)) &&
            !memcmp(&L->intensity.x, &L->intensity.z, sizeof(float))) {
            /* a white light (the classic scene's): the three quotients have
             * the same operands, so one division gives all three */
            vf4 q = vf4_splat(L->intensity.x) / r2;
            S->irradiance[li] = (v3x4){q, q, q};
        } else {
            S->irradiance[li] = v3_divs(v3_splat(L->intensity), r2);
        }
        vf4 nl = v3_dot(n, l), nh = v3_dot(n, h);
        S->diffuse[li] = vf4_select(nl > zero, nl, zero);
        vf4 x = vf4_select(nh > zero, nh, zero);
        vf4 specular = zero;
        vi4 lit = x > vf4_splat(spec_zero);
        if (vi4_any(lit))
            for (int i = 0; i < 4; i++)
                if (lit[i]) specular[i] = powf(x[i], pay->p);
        S->specular[li] = specular;
    }
}

/* (n + 1) · 0.5: the Normal and bump shaders' colour */
static inline v3x4 normal_colour_x4(v3x4 n) {
    return v3_scale(v3_add(n, v3_splat((vec3s){{1.0f, 1.0f, 1.0f}})), vf4_splat(0.5f));
}

/* Everything up to the colour map: the weights, the varyings and, per light,
 * the terms that do not involve kd. Then the texels the lookups will read are
 * prefetched, and shade_finish (called after the other half-queue's prepare)
 * finds them in cache. */
static void shade_prepare(worker *w, const queued *const *q, int lanes, lanes4 *S) {
    const frame *fr = w->fr;
    const fragment_shader_payload *pay = &w->pay[q[0]->r->object];
    S->q = q;
    S->lanes = lanes;
    const queued *e[4];
    for (int i = 0; i < 4; i++)
        e[i] = q[i < lanes ? i : 0];
    v3x4 b = weights_x4(fr, e);
    vf4 lo[4], hi[4];
    varyings_x4(e, b, fr->batch != BATCH_NORMAL, lo, hi);
    S->b = b;
    vi4 odd = {0, 0, 0, 0};
    v3x4 normal = v3_normalize((v3x4){lo[0], lo[1], lo[2]}, &odd); /* payload->normal */
    w->k.varyings_interpolated += fr->varyings_per_fragment * (uint64_t)lanes;
    w->k.fragments_shaded += (uint64_t)lanes;
    if (fr->batch == BATCH_NORMAL) {
        /* normal_fragment_shader: (normalize(n) + 1) · 0.5 */
        S->color = normal_colour_x4(v3_normalize(normal, &odd));
        S->odd = odd;
        return;
    }
    v3x4 point = {lo[3], hi[0], hi[1]}; /* payload->view_pos */
    S->u = hi[2];
    S->v = hi[3];
    if (fr->batch == BATCH_BUMP) {
        /* bump_fragment_shader: (bump_normal + 1) · 0.5 */
        vf4 h;
        v3x4 n = bump_normal_x4(pay, normal, S->u, S->v, lanes, &odd, &h);
        count_heights(pay, 3, (uint64_t)lanes);
        S->color = normal_colour_x4(n);
        S->odd = odd;
        return;
    }
    if (fr->batch == BATCH_DISPLACEMENT) {
        /* displacement_fragment_shader: the point p + n·(kn·h), then
         * Blinn-Phong with bump_normal's normal (below) */
        vf4 h;
        v3x4 bumped = bump_normal_x4(pay, normal, S->u, S->v, lanes, &odd, &h);
        count_heights(pay, 3, (uint64_t)lanes); /* h(u, v) once, as the reference */
        v3x4 n = v3_normalize(normal, &odd);
        vf4 s = vf4_splat(pay->kn) * h;
        point = (v3x4){point.x + n.x * s, point.y + n.y * s, point.z + n.z * s};
        normal = bumped;
    }
    light_terms_x4(pay, fr->spec_zero[q[0]->r->object], lanes, normal, point, &odd, S);
    S->odd = odd;
    if (fr->batch == BATCH_TEXTURE && pay->texture) {
        /* the texels the lookups will read (nearest filtering reads one of
         * the four), fetched while the other half-queue is prepared */
        bilinear_x4_footprint(pay->texture, S->u, S->v, lanes, &S->texels);
        for (int i = 0; i < lanes; i++)
            if (S->texels.looked_up >> i & 1)
                for (int k = 0; k < 4; k++) __builtin_prefetch(footprint_texel(&S->texels, i, k));
    }
}


/* Four copies of c at d: three vectors, rgbr gbrg brgb. */
static inline void put4(vec3s *d, vec3s c) {
#if defined(__SSE2__)
    float *f = &d->x;
    _mm_storeu_ps(f, _mm_setr_ps(c.x, c.y, c.z, c.x));
    _mm_storeu_ps(f + 4, _mm_setr_ps(c.y, c.z, c.x, c.y));
    _mm_storeu_ps(f + 8, _mm_setr_ps(c.z, c.x, c.y, c.z));
#else
    d[0] = d[1] = d[2] = d[3] = c;
#endif
}

/* kd (the texture lookups), the sums in fast_blinn_phong's order, and the
 * colours into the tile. */
static void shade_finish(worker *w, lanes4 *S) {
    const frame *fr = w->fr;
    const queued *const *q = S->q;
    int lanes = S->lanes;
    fragment_shader_payload *pay = &w->pay[q[0]->r->object];
    v3x4 color = S->color;
    if (fr->batch != BATCH_NORMAL && fr->batch != BATCH_BUMP) {
        v3x4 kd = v3_splat(pay->color);
        if (fr->batch == BATCH_TEXTURE && pay->texture && pay->filter == FILTER_BILINEAR) {
            kd = bilinear_x4_blend(&S->texels);
            if (pay->counters) { /* texture_sample's counts for the lanes done here */
                pay->counters->stages_run |= RAS_STAGE_TEXTURE;
                unsigned looked_up = (unsigned)__builtin_popcount(S->texels.looked_up);
                pay->counters->texels_fetched += 4u * looked_up;
            }
            for (int i = 0; i < lanes; i++) {
                if (!(S->texels.fallback >> i & 1)) continue;
                vec3s c = texture_sample(pay, pay->texture, (vec2s){{S->u[i], S->v[i]}});
                kd.x[i] = c.x;
                kd.y[i] = c.y;
                kd.z[i] = c.z;
            }
        } else if (fr->batch == BATCH_TEXTURE && pay->texture) {
            for (int i = 0; i < 4; i++) {
                /* lanes past `lanes` copy lane 0: no lookup, no count */
                vec3s c = i < lanes ? texture_sample(pay, pay->texture, (vec2s){{S->u[i], S->v[i]}})
                                    : (vec3s){{kd.x[0], kd.y[0], kd.z[0]}};
                kd.x[i] = c.x;
                kd.y[i] = c.y;
                kd.z[i] = c.z;
            }
        }
        color = v3_splat(glms_vec3_mul(pay->ka, pay->ambient_intensity));
        v3x4 ks = v3_splat(pay->ks);
        for (int li = 0; li < pay->light_count; li++) {
            color = v3_add(color, v3_scale(v3_mul(kd, S->irradiance[li]), S->diffuse[li]));
            color = v3_add(color, v3_scale(v3_mul(ks, S->irradiance[li]), S->specular[li]));
        }
    }
    unsigned odd = vi4_sign_bits(S->odd);
    for (int i = 0; i < lanes; i++) {
        vec3s c = {{color.x[i], color.y[i], color.z[i]}};
        if (__builtin_expect(odd >> i & 1, 0)) c = shade_silent(w, q[i]->r, q[i]->bary);
        vec3s *dst = &w->color[q[i]->base];
        uint64_t mask = q[i]->mask;
        if (mask == 1) { /* one sample: 1x, SSAA */
            *dst = c;
            continue;
        }
        if (mask == 0xF && fr->n == 4) { /* a whole pixel of 4x */
            put4(dst, c);
            continue;
        }
        for (; mask; mask &= mask - 1)
            dst[__builtin_ctzll(mask)] = c;
    }
}

/* Both halves prepared before either is finished: the lighting of one hides
 * the texel fetches of the other. */
static void flush_queue(worker *w) {
    int n = w->qn;
    w->qn = 0;
    lanes4 S[QUEUE / 4];
    int chunks = 0;
    for (int c = 0; c < n; c += 4)
        shade_prepare(w, &w->q[c], n - c < 4 ? n - c : 4, &S[chunks++]);
    for (int c = 0; c < chunks; c++)
        shade_finish(w, &S[c]);
}

/* Queue a fragment for shading: its colour goes to the samples `mask` of
 * tile sample index `base`. */
static inline void queue_fragment(worker *w, const queued *f) {
    /* one object's fragments (one material) per queue */
    if (w->qn == QUEUE || (w->qn && w->q[0]->object != f->object)) flush_queue(w);
    w->q[w->qn++] = f;
    w->shaded++;
}

/* Fragment i owns the samples `mask` of tile sample index base; four
 * samples in a row (a whole pixel of 4x, the common case) are one store. */
static inline void set_owner(worker *w, int base, uint64_t mask, int32_t i) {
    if (mask == 0xF) {
        int32_t four[4] = {i, i, i, i};
        memcpy(&w->owner[base], four, sizeof four);
        return;
    }
    for (uint64_t m = mask; m; m &= m - 1)
        w->owner[base + __builtin_ctzll(m)] = i;
}

/* A fragment that passed the depth test at the samples `mask` (of tile
 * sample index `base`), kept until the tile is drawn: only the samples it
 * still owns then take its colour (shade_deferred). */
static inline void defer_fragment(worker *w, const fast_tri *r, vec3s bary, int base,
                                  uint64_t mask) {
    if (w->nfrag == w->frag_cap) {
        size_t cap = 2 * w->frag_cap;
        /* owner indices are int32: past that (80 GB of fragments) the frame
         * fails like any other allocation */
        queued *grown = cap <= INT32_MAX ? realloc(w->frags, (cap + 1) * sizeof *grown) : NULL;
        if (!grown) { /* the frame fails with "out of memory" */
            atomic_store(&w->fr->failed, true);
            return;
        }
        w->frags = grown;
        w->frag_cap = cap;
    }
    int32_t i = (int32_t)w->nfrag++;
    w->frags[i] = (queued){r, bary, 0.0f, base, r->object, mask};
    set_owner(w, base, mask, i);
}

/* defer_fragment for a pixel's one sample (n = 1; mask 1). In per_pixel mode
 * the fragment is written at its pixel, over the one it hides (shade_pixels
 * fills in the rest), and counted as hidden until shade_pixels finds it. */
static inline void put_pixel(worker *w, const fast_tri *r, vec3s bary, int base) {
    queued *f = &w->frags[base];
    f->r = r;
    f->bary = bary;
    f->pad = 0.0f;
}

static inline void defer_pixel(worker *w, const fast_tri *r, vec3s bary, int base) {
    if (!w->fr->per_pixel) {
        defer_fragment(w, r, bary, base, 1);
        return;
    }
    put_pixel(w, r, bary, base);
    w->hidden[r->object]++;
}

/* What shading `count` fragments of object o adds to the counters
 * (shade_prepare, shade_finish, texture_sample), for fragments
 * shade_deferred need not shade: the counters stay the teaching pipeline's,
 * which shades every fragment that passes a depth test. */
static void count_unshaded(worker *w, int o, uint64_t count) {
    const frame *fr = w->fr;
    const fragment_shader_payload *pay = &w->pay[o];
    w->k.fragments_shaded += count;
    w->k.varyings_interpolated += fr->varyings_per_fragment * count;
    if (fr->batch == BATCH_BUMP) count_heights(pay, 3, count);
    if (fr->batch == BATCH_DISPLACEMENT) count_heights(pay, 3, count);
    if (fr->batch == BATCH_NORMAL || fr->batch == BATCH_BUMP || !pay->counters) return;
    pay->counters->stages_run |= RAS_STAGE_LIGHTING;
    pay->counters->lighting_evaluations += (uint64_t)pay->light_count * count;
    if (fr->batch == BATCH_TEXTURE && pay->texture) {
        pay->counters->stages_run |= RAS_STAGE_TEXTURE;
        pay->counters->texels_fetched += (pay->filter == FILTER_BILINEAR ? 4 : 1) * count;
    }
}

/* What shading one fragment of f's object added to w->k since `before`. */
static void learn_counts(worker *w, const queued *f, const ras_counters *before) {
    ras_counters *d = &w->per_fragment[f->r->object];
    d->stages_run = w->k.stages_run;
    d->fragments_shaded = w->k.fragments_shaded - before->fragments_shaded;
    d->varyings_interpolated = w->k.varyings_interpolated - before->varyings_interpolated;
    d->texels_fetched = w->k.texels_fetched - before->texels_fetched;
    d->lighting_evaluations = w->k.lighting_evaluations - before->lighting_evaluations;
    w->per_fragment_known[f->r->object] = true;
}

/* shade() for a deferred fragment of an unbatched shader, its colour into
 * the samples it owns; the first one of each object teaches what a fragment
 * adds to the counters. */
static void shade_scalar(worker *w, const queued *f) {
    ras_counters before = w->k;
    vec3s c = shade(w, f->r, f->bary);
    w->shaded++;
    if (!w->per_fragment_known[f->r->object]) learn_counts(w, f, &before);
    for (uint64_t m = f->mask; m; m &= m - 1)
        w->color[f->base + __builtin_ctzll(m)] = c;
}

/* An unbatched fragment that owns no sample: what one shaded fragment of its
 * object added to the counters. When none has been shaded yet, this one is
 * shaded as a probe — its colour unused, its counts learnt and then taken
 * back, so that the counters, and the count of fragments really shaded for
 * their colour, do not depend on which worker met which fragment first. */
static void count_unshaded_scalar(worker *w, const queued *f) {
    int o = f->r->object;
    if (!w->per_fragment_known[o]) {
        ras_counters saved = w->k;
        (void)shade(w, f->r, f->bary);
        learn_counts(w, f, &saved);
        w->k = saved;
    }
    const ras_counters *d = &w->per_fragment[o];
    w->k.stages_run |= d->stages_run;
    w->k.fragments_shaded += d->fragments_shaded;
    w->k.varyings_interpolated += d->varyings_interpolated;
    w->k.texels_fetched += d->texels_fetched;
    w->k.lighting_evaluations += d->lighting_evaluations;
}

/* The end of a tile in per_pixel mode: frags[s] is the last fragment that
 * passed the depth test at pixel s (written where the depth is below +inf),
 * the one whose colour the immediate order leaves there. Each is shaded
 * once; shading is a pure function of the fragment, so the order (here the
 * pixels', not the drawing's) changes no colour. The ones they replaced are
 * counted as shaded (hidden[]) when the worker is done. */
static void shade_pixels(worker *w) {
    const vf4 inf = vf4_splat(INFINITY);
    _Static_assert(TILE == 64, "shade_pixels keeps a tile row in a 64-bit mask");
    for (int row = 0; row < TILE * TILE; row += TILE) {
        /* a row's 64 pixels into one mask first: one loop exit per row, not
         * one per four pixels */
        uint64_t drawn = 0;
        for (int x = 0; x < TILE; x += 4)
            drawn |= (uint64_t)vi4_sign_bits(vf4_load(&w->depth[row + x]) == inf) << x;
        for (drawn = ~drawn; drawn; drawn &= drawn - 1) {
            int s = row + __builtin_ctzll(drawn);
            queued *f = &w->frags[s];
            f->base = s;
            f->object = f->r->object;
            f->mask = 1;
            w->hidden[f->object]--;
            queue_fragment(w, f);
        }
    }
    flush_queue(w);
}

/* The end of a tile: a sample's colour is that of the last fragment to pass
 * its depth test (strict <, in drawing order), so each sample's owner gives
 * it. Fragments that own no sample any more (hidden by later ones: about 40 %
 * of the cow's) are counted but not shaded; the others are shaded in
 * drawing order, for exactly the samples they own. Every colour is what the
 * immediate order would have left there, bit for bit. */
static void shade_deferred(worker *w) {
    if (w->fr->per_pixel) {
        shade_pixels(w);
        return;
    }
    const int n = w->fr->n;
    const bool batch = w->fr->batch != BATCH_NONE;
    /* With one sample a fragment (mask 1) still owns its sample when it is
     * the sample's owner: checked in the loop below. Otherwise the owners
     * give each fragment its samples, four samples at a time: none written
     * (most of a tile around a model), or with 4x one pixel's four owned by
     * one fragment. */
    if (n > 1)
        for (size_t i = 0; i < w->nfrag; i++)
            w->frags[i].mask = 0;
    const vf4 inf = vf4_splat(INFINITY);
    for (int s0 = 0; n > 1 && s0 < TILE * TILE * n; s0 += 4) {
        unsigned clear = vi4_sign_bits(vf4_load(&w->depth[s0]) == inf);
        if (clear == 0xF) continue; /* no fragment passed here */
        const int32_t *o = &w->owner[s0];
        if (n == 4 && !clear && o[0] == o[1] && o[0] == o[2] && o[0] == o[3]) {
            queued *f = &w->frags[o[0]];
            f->mask |= (uint64_t)0xF << (s0 - f->base);
            continue;
        }
        for (int k = 0; k < 4; k++) {
            if (clear >> k & 1) continue;
            queued *f = &w->frags[o[k]];
            f->mask |= (uint64_t)1 << (s0 + k - f->base);
        }
    }
    for (size_t i = 0; i < w->nfrag; i++) {
        queued *f = &w->frags[i];
        if (n == 1 && w->owner[f->base] != (int32_t)i) f->mask = 0;
        if (batch && f->mask)
            queue_fragment(w, f);
        else if (batch)
            w->hidden[f->object]++; /* counted when the worker is done */
        else if (f->mask)
            shade_scalar(w, f);
        else
            count_unshaded_scalar(w, f);
    }
    w->nfrag = 0;
    flush_queue(w);
}

static int batch_kind(const ras_scene *scene, const hw3_render_options *opt,
                      const hw3_fragment_stage *stage) {
    unsigned v = stage->varyings;
    bool lit =
        stage->base.light_count > 0 && (v & RAS_VARYING_NORMAL) && (v & RAS_VARYING_VIEW_POS);
    (void)scene;
    if (stage->shader == normal_fragment_shader && (v & RAS_VARYING_NORMAL)) return BATCH_NORMAL;
    if (stage->shader == phong_fragment_shader && lit) return BATCH_PHONG;
    /* trilinear needs each fragment's uv derivatives: the scalar path */
    if (stage->shader == texture_fragment_shader && lit && (v & RAS_VARYING_UV) &&
        opt->filter != FILTER_TRILINEAR)
        return BATCH_TEXTURE;
    /* bump and displacement read no uv derivatives: any filter */
    if (stage->shader == bump_fragment_shader && (v & RAS_VARYING_NORMAL) &&
        (v & RAS_VARYING_UV))
        return BATCH_BUMP;
    if (stage->shader == displacement_fragment_shader && lit && (v & RAS_VARYING_UV))
        return BATCH_DISPLACEMENT;
    return BATCH_NONE;
}

/* ---- rasterizing one triangle into one tile --------------------------------- */

/* The reference's barycentrics of a covered point, in the original vertex
 * order (order is 0,1,2 or 0,2,1: a select, not a scatter through memory). */
/* (float)((double)e / area2), the reference's barycentric, without the
 * division where that is provably the same float. For a covered point
 * 0 <= e <= area2 < 2^53, so (double)e is exact and q = e · RN(1/area2) is
 * within about 3 double ulps of the correctly rounded quotient d (two
 * roundings of 2^-53 each, against d's one). Rounding to float gives the same
 * result for q and d unless a float rounding boundary — a midpoint between
 * two floats, whose 29 bits below float precision read 0x10000000 — lies
 * between them; so when q's 29 low bits are more than 8 from that pattern, q
 * rounds like d, and otherwise (about once in 2^25) divide. q >= 2^-53 is far
 * from float subnormals; e = 0 gives +0 either way. */
static inline float ratio_to_float(int64_t e, const fast_tri *r) {
    double q = (double)e * r->inv_area2;
    uint64_t bits;
    memcpy(&bits, &q, sizeof bits);
    uint32_t low = (uint32_t)(bits & 0x1FFFFFFFu);
    if (__builtin_expect(low - (0x10000000u - 8u) <= 16u, 0))
        return (float)((double)e / (double)r->area2);
    return (float)q;
}

static inline vec3s bary_of(const fast_tri *r, const int64_t e[3]) {
    float l0 = ratio_to_float(e[0], r);
    float l1 = ratio_to_float(e[1], r);
    float l2 = ratio_to_float(e[2], r);
    return r->order[1] == 1 ? (vec3s){{l0, l1, l2}} : (vec3s){{l0, l2, l1}};
}

/* The reference's barycentrics, divided as it does: at 1x the divider
 * runs beside the rest of a pixel's work. */
static inline vec3s bary_div(const fast_tri *r, const int64_t e[3]) {
    double a = (double)r->area2;
    float l0 = (float)((double)e[0] / a);
    float l1 = (float)((double)e[1] / a);
    float l2 = (float)((double)e[2] / a);
    return r->order[1] == 1 ? (vec3s){{l0, l1, l2}} : (vec3s){{l0, l2, l1}};
}

static inline float depth_of(const fast_tri *r, vec3s b) {
    return b.x * r->z[0] + b.y * r->z[1] + b.z * r->z[2];
}

/* Is the whole block [bx0, bx1] × [by0, by1] of pixels outside one edge for
 * every sample position? The edge function is affine, so its largest value
 * over the block's sample points is at a corner of the box spanned by the
 * extreme sample offsets. */
static bool block_outside(const frame *fr, const fast_tri *r, int bx0, int by0, int bx1,
                          int by1, int64_t omin_x, int64_t omax_x, int64_t omin_y,
                          int64_t omax_y) {
    (void)fr;
    for (int i = 0; i < 3; i++) {
        int64_t px = r->a[i] > 0 ? (int64_t)bx1 * SUBPIXEL_ONE + omax_x
                                 : (int64_t)bx0 * SUBPIXEL_ONE + omin_x;
        int64_t py = r->b[i] > 0 ? (int64_t)by1 * SUBPIXEL_ONE + omax_y
                                 : (int64_t)by0 * SUBPIXEL_ONE + omin_y;
        if (r->a[i] * px + r->b[i] * py + r->c[i] < r->thr[i]) return true;
    }
    return false;
}

/* defer_fragment with the barycentrics in lanes 0-2 of bv (lane 3 is 0: the
 * record's pad). */
static inline void defer_fragment_v(worker *w, const fast_tri *r, vf4 bv, int base,
                                    uint64_t mask) {
    if (__builtin_expect(w->nfrag == w->frag_cap, 0)) {
        vec3s b = {{bv[0], bv[1], bv[2]}};
        defer_fragment(w, r, b, base, mask);
        return;
    }
    int32_t i = (int32_t)w->nfrag++;
    queued *f = &w->frags[i];
    f->r = r;
    memcpy(&f->bary, &bv, sizeof bv); /* bary and pad */
    f->base = base;
    f->object = r->object;
    f->mask = mask;
    set_owner(w, base, mask, i);
}

#if defined(__SSE2__)
#define BARY_X4 1
/* ratio_to_float for four points at once: e (int32 lanes, exact: every
 * caller's values fit) to double, times RN(1/area2), to float — the scalar
 * steps lane by lane (cvtdq2pd, mulpd, cvtpd2ps round like cvtsi2sd, mulsd,
 * cvtsd2ss). Returns the lanes (all ones) whose product lies within 8 of a
 * float rounding boundary (ratio_to_float divides there): the caller redoes
 * them. */
static inline vi4 ratios_x4(vi4 e, __m128d inv, vf4 *out) {
    __m128i ei = (__m128i)e;
    __m128d qlo = _mm_mul_pd(_mm_cvtepi32_pd(ei), inv);
    __m128d qhi = _mm_mul_pd(_mm_cvtepi32_pd(_mm_shuffle_epi32(ei, _MM_SHUFFLE(3, 2, 3, 2))), inv);
    *out = (vf4)_mm_movelh_ps(_mm_cvtpd_ps(qlo), _mm_cvtpd_ps(qhi));
    /* the low 32 bits of each double (dwords 0 and 2): low29 − (2^28 − 8) */
    __m128i m = _mm_set1_epi32(0x1FFFFFFF), c = _mm_set1_epi32(0x10000000 - 8);
    __m128i vlo = _mm_sub_epi32(_mm_and_si128(_mm_castpd_si128(qlo), m), c);
    __m128i vhi = _mm_sub_epi32(_mm_and_si128(_mm_castpd_si128(qhi), m), c);
    vi4 v = (vi4)_mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(vlo), _mm_castsi128_ps(vhi),
                                                 _MM_SHUFFLE(2, 0, 2, 0)));
    /* (uint32)(low29 − …) <= 16, as a signed compare with the sign flipped */
    return (v ^ INT32_MIN) < INT32_MIN + 17;
}

/* bary_of and depth_of for four points (lanes) whose edge values E are e[k]:
 * the same floats, lane by lane. Lanes in the returned mask (near a rounding
 * boundary) must be redone with bary_of. */
static inline unsigned bary_depth_x4(const fast_tri *r, const vi4 e[3], v3x4 *b, vf4 *z) {
    __m128d inv = _mm_set1_pd(r->inv_area2);
    vf4 l0, l1, l2;
    vi4 near = ratios_x4(e[0], inv, &l0);
    near |= ratios_x4(e[1], inv, &l1);
    near |= ratios_x4(e[2], inv, &l2);
    *b = r->order[1] == 1 ? (v3x4){l0, l1, l2} : (v3x4){l0, l2, l1};
    *z = b->x * vf4_splat(r->z[0]) + b->y * vf4_splat(r->z[1]) + b->z * vf4_splat(r->z[2]);
    return vi4_sign_bits(near);
}

#else
#define BARY_X4 0
#endif

static inline __attribute__((always_inline)) void
draw_pixel_samples(worker *w, const fast_tri *r, int x, int y, int tx0, int ty0,
                   int64_t e[][3], const int n, uint64_t covered) {
    const frame *fr = w->fr;
    int base = ((y - ty0) * TILE + (x - tx0)) * n;
    vec3s bary[RAS_MAX_SAMPLES];
    float z[RAS_MAX_SAMPLES];
    uint64_t visible = 0;
    for (int k = 0; k < n; k++) {
        /* covered: the caller's coverage bits, or 0 to test here */
        if (covered ? !(covered >> k & 1)
                    : e[k][0] < r->thr[0] || e[k][1] < r->thr[1] || e[k][2] < r->thr[2])
            continue;
        w->k.samples_covered++;
        bary[k] = bary_of(r, e[k]);
        z[k] = depth_of(r, bary[k]);
        if (!(z[k] < w->depth[base + k])) continue;
        w->k.depth_tests_passed++;
        w->depth[base + k] = z[k];
        visible |= (uint64_t)1 << k;
    }
    if (!visible) return;
    if (fr->ssaa) {
        for (int k = 0; k < n; k++) {
            if (!(visible >> k & 1)) continue;
            if (n == 1)
                defer_pixel(w, r, bary[k], base + k);
            else
                defer_fragment(w, r, bary[k], base + k, 1);
        }
        return;
    }
    vec3s bc;
    const int64_t *ec = e[n]; /* the pixel centre */
    if (fr->centre_sample >= 0 && (visible >> fr->centre_sample & 1)) {
        bc = bary[fr->centre_sample]; /* a sample at the centre: the same integers */
    } else if (ec[0] >= r->thr[0] && ec[1] >= r->thr[1] && ec[2] >= r->thr[2]) {
        bc = bary_of(r, ec);
    } else {
        int best = -1;
        float best_d2 = 0;
        for (int k = 0; k < n; k++) {
            if (!(visible >> k & 1)) continue;
            float dx = fr->pattern.offsets[k].x - 0.5f, dy = fr->pattern.offsets[k].y - 0.5f;
            float d2 = dx * dx + dy * dy;
            if (best < 0 || d2 < best_d2) {
                best = k;
                best_d2 = d2;
            }
        }
        bc = bary[best];
    }
    if (n == 1)
        defer_pixel(w, r, bc, base);
    else
        defer_fragment(w, r, bc, base, visible);
}

#if BARY_X4
/* draw_pixel_samples for four samples (MSAA or SSAA 4x) whose E − thr are
 * the lanes of ev[k], covered at the bits of `covered` (not 0), with the
 * pixel centre's edge values ec: the samples' barycentrics and depths in
 * lanes (bary_depth_x4), the depth test and write on the pixel's four
 * depths at once, then draw_pixel_samples' choice of the shading point. */
static inline __attribute__((always_inline)) void
draw_pixel4_v(worker *w, const fast_tri *r, int x, int y, int tx0, int ty0, const vi4 ev[3],
              const vi4 thrv[3], vi4 covv, unsigned covered, const int64_t dcen[3], vi4 *counts) {
    const frame *fr = w->fr;
    int base = ((y - ty0) * TILE + (x - tx0)) * 4;
    vi4 E[3] = {ev[0] + thrv[0], ev[1] + thrv[1], ev[2] + thrv[2]};
    v3x4 b;
    vf4 z;
    unsigned near = bary_depth_x4(r, E, &b, &z) & covered;
    for (; near; near &= near - 1) { /* about once in 2^25 */
        int i = __builtin_ctz(near);
        int64_t ep[3] = {(int64_t)E[0][i], (int64_t)E[1][i], (int64_t)E[2][i]};
        vec3s bb = bary_of(r, ep);
        b.x[i] = bb.x, b.y[i] = bb.y, b.z[i] = bb.z;
        z[i] = depth_of(r, bb);
    }
    float *dp = &w->depth[base];
    vf4 old = vf4_load(dp);
    vi4 pass = (z < old) & covv;
    unsigned visible = vi4_sign_bits(pass);
    counts[0] -= covv; /* samples_covered and depth_tests_passed, per lane */
    if (!visible) return;
    counts[1] -= pass;
    vf4 nz = vf4_select(pass, z, old);
    memcpy(dp, &nz, sizeof nz);
    vf4 bv[4] = {b.x, b.y, b.z, vf4_splat(0.0f)};
    vf4_transpose(&bv[0], &bv[1], &bv[2], &bv[3]);
    if (fr->ssaa) {
        for (unsigned m = visible; m; m &= m - 1) {
            int k = __builtin_ctz(m);
            defer_fragment_v(w, r, bv[k], base + k, 1);
        }
        return;
    }
    if (fr->centre_sample >= 0 && (visible >> fr->centre_sample & 1)) {
        defer_fragment_v(w, r, bv[fr->centre_sample], base, visible);
        return;
    }
    /* the centre's E − thr: sample 0's plus the centre's offset from it */
    int64_t c0 = ev[0][0] + dcen[0], c1 = ev[1][0] + dcen[1], c2 = ev[2][0] + dcen[2];
    if ((c0 | c1 | c2) >= 0) { /* covered (the sign bits, as for the samples) */
        int64_t e3[3] = {c0 + r->thr[0], c1 + r->thr[1], c2 + r->thr[2]};
        defer_fragment(w, r, bary_div(r, e3), base, visible);
    } else {
        int best = -1;
        float best_d2 = 0;
        for (int k = 0; k < 4; k++) {
            if (!(visible >> k & 1)) continue;
            float dx = fr->pattern.offsets[k].x - 0.5f, dy = fr->pattern.offsets[k].y - 0.5f;
            float d2 = dx * dx + dy * dy;
            if (best < 0 || d2 < best_d2) {
                best = k;
                best_d2 = d2;
            }
        }
        defer_fragment_v(w, r, bv[best], base, visible);
    }
}
#endif

/* `n` (samples per pixel) is a constant in each inlined copy: the loops over
 * samples unroll and the edge values stay in registers. */
static inline __attribute__((always_inline)) void
draw_in_tile_n(worker *w, const fast_tri *r, int tx0, int ty0, int x0, int y0, int x1, int y1,
               const int n) {
    const frame *fr = w->fr;
    const int64_t omin_x = fr->omin_x, omax_x = fr->omax_x, omin_y = fr->omin_y,
                  omax_y = fr->omax_y;
    const int64_t step[3] = {r->a[0] * SUBPIXEL_ONE, r->a[1] * SUBPIXEL_ONE,
                             r->a[2] * SUBPIXEL_ONE};
    /* Edge values are kept for the n samples and the pixel centre, except at
     * one sample that is the centre (no AA): draw_pixel_samples reads the
     * centre's values only when no visible sample lies there. */
    const int ne = n == 1 && fr->centre_sample == 0 ? 1 : n + 1;
    bool small = (x1 - x0) < BLOCK && (y1 - y0) < BLOCK;
    for (int by0 = y0; by0 <= y1; by0 += BLOCK) {
        int by1 = by0 + BLOCK - 1 < y1 ? by0 + BLOCK - 1 : y1;
        for (int bx0 = x0; bx0 <= x1; bx0 += BLOCK) {
            int bx1 = bx0 + BLOCK - 1 < x1 ? bx0 + BLOCK - 1 : x1;
            if (!small &&
                block_outside(fr, r, bx0, by0, bx1, by1, omin_x, omax_x, omin_y, omax_y))
                continue;
            for (int y = by0; y <= by1; y++) {
                /* Edge values at (bx0, y) for every sample and the centre,
                 * then one addition per pixel: exact integers, the same
                 * values the reference computes from scratch. */
                int64_t e[RAS_MAX_SAMPLES + 1][3];
                for (int k = 0; k < ne; k++) {
                    int64_t px = (int64_t)bx0 * SUBPIXEL_ONE + fr->off_x[k];
                    int64_t py = (int64_t)y * SUBPIXEL_ONE + fr->off_y[k];
                    for (int i = 0; i < 3; i++) e[k][i] = r->a[i] * px + r->b[i] * py + r->c[i];
                }
                if (n * BLOCK <= 32) {
                    /* Up to 4 samples: the row's coverage as a bit mask
                     * first (n bits per pixel), without a branch per sample
                     * (edges of small triangles are unpredictable), then only
                     * the pixels with a covered sample, their edge values
                     * stepped from the row start (still exact). */
                    /* E >= thr on all three edges <=> every E - thr has
                     * its sign bit clear <=> so has their bitwise or. */
                    uint32_t mask = 0;
                    int64_t ev[RAS_MAX_SAMPLES][3];
                    for (int k = 0; k < n; k++)
                        for (int j = 0; j < 3; j++)
                            ev[k][j] = e[k][j] - r->thr[j];
                    for (int i = 0; i <= bx1 - bx0; i++)
                        for (int k = 0; k < n; k++) {
                            uint64_t any_negative = (uint64_t)(ev[k][0] | ev[k][1] | ev[k][2]);
                            mask |= (uint32_t)(~any_negative >> 63) << (i * n + k);
                            for (int j = 0; j < 3; j++)
                                ev[k][j] += step[j];
                        }
                    while (mask) {
                        int i = __builtin_ctz(mask) / n;
                        mask &= ~((((uint32_t)1 << n) - 1) << (i * n));
                        int64_t ep[RAS_MAX_SAMPLES + 1][3];
                        for (int k = 0; k < ne; k++)
                            for (int j = 0; j < 3; j++)
                                ep[k][j] = e[k][j] + (int64_t)i * step[j];
                        draw_pixel_samples(w, r, bx0 + i, y, tx0, ty0, ep, n, 0);
                    }
                    continue;
                }
                for (int x = bx0; x <= bx1; x++) {
                    draw_pixel_samples(w, r, x, y, tx0, ty0, e, n, 0);
                    for (int k = 0; k < ne; k++)
                        for (int i = 0; i < 3; i++) e[k][i] += step[i];
                }
            }
        }
    }
}

/* Do all three E − thr stay within ±2^30 over the sub-pixel box [px0, px1] ×
 * [py0, py1]? They are affine, so their extremes are at the box's corners;
 * inside that range 32-bit lanes hold them, and a step between two points of
 * the box, exactly. */
static bool edges_fit_31(const fast_tri *r, int64_t px0, int64_t px1, int64_t py0, int64_t py1) {
    const int64_t lim = (int64_t)1 << 30;
    /* -lim < v < lim <=> v + lim - 1 in [0, 2·lim - 2], one unsigned test */
    const uint64_t span = 2 * (uint64_t)lim - 2;
    for (int k = 0; k < 3; k++) {
        /* the corners from one of them and the steps across the box */
        int64_t v00 = r->a[k] * px0 + r->b[k] * py0 + r->c[k] - r->thr[k] + (lim - 1);
        int64_t dx = r->a[k] * (px1 - px0), dy = r->b[k] * (py1 - py0);
        int64_t v10 = v00 + dx, v01 = v00 + dy, v11 = v10 + dy;
        if (((uint64_t)v00 > span) | ((uint64_t)v10 > span) | ((uint64_t)v01 > span) |
            ((uint64_t)v11 > span))
            return false;
    }
    return true;
}

/* Without AA (one sample, at the pixel centre), for a triangle whose edge
 * values over the part of its box in this tile fit in 31 bits (every cow
 * triangle; not a screen-filling one): the coverage of eight pixels of a
 * block row is two 4-lane int32 additions and ors per edge and a sign mask,
 * instead of eight pixels of int64 arithmetic. The values are the same
 * integers (exact arithmetic well inside the range). A covered pixel's
 * barycentrics are the reference's divisions (bary_div), its depth test and
 * fragment draw_pixel_samples' for n = 1; with per_pixel (a constant in each
 * inlined copy) the fragment goes to its pixel, without a branch on the test.
 * False: the values may not fit; draw with draw_in_tile_n. */
static inline __attribute__((always_inline)) bool
draw_in_tile_1x32(worker *w, const fast_tri *r, int tx0, int ty0, int x0, int y0, int x1, int y1,
                  const bool per_pixel) {
    const frame *fr = w->fr;
    const int64_t cx = fr->off_x[0], cy = fr->off_y[0];
    /* x1 + 7: a block row's eight lanes may run past x1; y1 + 1: the
     * lanes are stepped once past the last row */
    if (!edges_fit_31(r, (int64_t)x0 * SUBPIXEL_ONE + cx,
                      (int64_t)(x1 + BLOCK - 1) * SUBPIXEL_ONE + cx,
                      (int64_t)y0 * SUBPIXEL_ONE + cy, (int64_t)(y1 + 1) * SUBPIXEL_ONE + cy))
        return false;
    const int64_t step[3] = {r->a[0] * SUBPIXEL_ONE, r->a[1] * SUBPIXEL_ONE,
                             r->a[2] * SUBPIXEL_ONE};
    /* i · step for lanes i = 0..3 and 4..7, in int32: up to 7 steps is the
     * difference of two values in the checked box, so it fits */
    vi4 ramp_lo[3], ramp_hi[3];
    for (int k = 0; k < 3; k++) {
        int st = (int)step[k];
        vi4 sv = {st, st, st, st};
        ramp_lo[k] = sv * (vi4){0, 1, 2, 3};
        ramp_hi[k] = ramp_lo[k] + (sv << 2);
    }
    vi4 vstepy[3], thrv[3]; /* a row's step, thr */
    for (int k = 0; k < 3; k++) {
        int sy = (int)(r->b[k] * SUBPIXEL_ONE), t = (int)r->thr[k];
        vstepy[k] = (vi4){sy, sy, sy, sy};
        thrv[k] = (vi4){t, t, t, t};
    }
    /* counted here, added once (the stores below could alias w's fields) */
    uint64_t covered_n = 0, passed_n = 0;
    bool small = (x1 - x0) < BLOCK && (y1 - y0) < BLOCK;
    for (int by0 = y0; by0 <= y1; by0 += BLOCK) {
        int by1 = by0 + BLOCK - 1 < y1 ? by0 + BLOCK - 1 : y1;
        for (int bx0 = x0; bx0 <= x1; bx0 += BLOCK) {
            int bx1 = bx0 + BLOCK - 1 < x1 ? bx0 + BLOCK - 1 : x1;
            if (!small && block_outside(fr, r, bx0, by0, bx1, by1, cx, cx, cy, cy)) continue;
            unsigned row_lanes = (1u << (bx1 - bx0 + 1)) - 1;
            int64_t px = (int64_t)bx0 * SUBPIXEL_ONE + cx;
            int64_t py0 = (int64_t)by0 * SUBPIXEL_ONE + cy;
            /* E − thr of the block row's eight pixels, per edge: at the
             * block's first row, then one vector addition per row (exact:
             * every value used lies in the checked box) */
            vi4 elo[3], ehi[3];
            for (int k = 0; k < 3; k++) {
                int start = (int)(r->a[k] * px + r->b[k] * py0 + r->c[k] - r->thr[k]);
                elo[k] = (vi4){start, start, start, start} + ramp_lo[k];
                ehi[k] = (vi4){start, start, start, start} + ramp_hi[k];
            }
            /* The block's coverage first, all its rows without a branch
             * (a row's covered count is unpredictable, and so is whether it
             * has any): eight bits a row in one mask, each row's E (lanes +
             * thr: they fit) stored; then the covered pixels, one loop. */
            int32_t eblk[BLOCK][3][BLOCK];
            uint64_t covered = 0;
            for (int j = 0; j <= by1 - by0; j++) {
                vi4 lo = elo[0] | elo[1] | elo[2], hi = ehi[0] | ehi[1] | ehi[2];
                /* covered: E − thr >= 0 on every edge, so the or is >= 0 */
                unsigned row = ~(vi4_sign_bits(lo) | vi4_sign_bits(hi) << 4) & row_lanes;
                covered |= (uint64_t)row << (BLOCK * j);
                for (int k = 0; k < 3; k++) {
                    vi4 lo_k = elo[k] + thrv[k], hi_k = ehi[k] + thrv[k];
                    memcpy(&eblk[j][k][0], &lo_k, sizeof lo_k);
                    memcpy(&eblk[j][k][4], &hi_k, sizeof hi_k);
                    elo[k] += vstepy[k];
                    ehi[k] += vstepy[k];
                }
            }
            const int base_blk = (by0 - ty0) * TILE + (bx0 - tx0);
            for (; covered; covered &= covered - 1) {
                int bit = __builtin_ctzll(covered), j = bit / BLOCK, i = bit % BLOCK;
                int64_t ep[3] = {eblk[j][0][i], eblk[j][1][i], eblk[j][2][i]};
                int base = base_blk + j * TILE + i;
                covered_n++;
                vec3s bary = bary_div(r, ep);
                float z = depth_of(r, bary);
                if (per_pixel) {
                    /* without a branch on the depth test (it fails for
                     * about one covered pixel in five, unpredictably): a
                     * failing fragment and its depth go to the spare slots
                     * past the tile's pixels, never read */
                    unsigned pass = z < w->depth[base];
                    unsigned keep = 0u - pass; /* all ones when passed */
                    /* pass ? base : TILE * TILE, as masks: GCC turns a
                     * select back into the branch this avoids */
                    int at = (int)(((unsigned)base & keep) | (TILE * TILE & ~keep));
                    passed_n += pass;
                    w->depth[at] = z;
                    put_pixel(w, r, bary, at);
                    continue;
                }
                if (!(z < w->depth[base])) continue;
                passed_n++;
                w->depth[base] = z;
                defer_fragment(w, r, bary, base, 1);
            }
        }
    }
    w->k.samples_covered += covered_n;
    w->k.depth_tests_passed += passed_n;
    if (per_pixel) w->hidden[r->object] += (int64_t)passed_n;
    return true;
}

/* Four samples per pixel (MSAA or SSAA 4x), for a triangle whose edge
 * values over the part of its box in this tile, at every sample position
 * and the pixel centre, fit in 31 bits: one 4-lane int32 vector per edge
 * holds the pixel's four samples, stepped by one addition per pixel, and the
 * coverage is the sign mask of the three or-ed. Covered samples get their
 * exact int64 edge values back (lane + thr) and go through
 * draw_pixel_samples as before. False: the values may not fit. */
static bool draw_in_tile_4x32(worker *w, const fast_tri *r, int tx0, int ty0, int x0, int y0,
                              int x1, int y1) {
    const frame *fr = w->fr;
    const int n = 4;
    const int64_t omin_x = fr->omin_x, omax_x = fr->omax_x, omin_y = fr->omin_y,
                  omax_y = fr->omax_y;
    /* x1 + 1, y1 + 1: the lanes are stepped once past the last pixel and
     * past the last row */
    if (!edges_fit_31(r, (int64_t)x0 * SUBPIXEL_ONE + omin_x,
                      (int64_t)(x1 + 1) * SUBPIXEL_ONE + omax_x,
                      (int64_t)y0 * SUBPIXEL_ONE + omin_y,
                      (int64_t)(y1 + 1) * SUBPIXEL_ONE + omax_y))
        return false;
    const int64_t step[3] = {r->a[0] * SUBPIXEL_ONE, r->a[1] * SUBPIXEL_ONE,
                             r->a[2] * SUBPIXEL_ONE};
    /* offset of sample k (k = n: the centre) from the pixel's corner */
    int64_t off[RAS_MAX_SAMPLES + 1][3];
    for (int k = 0; k <= n; k++)
        for (int i = 0; i < 3; i++) off[k][i] = r->a[i] * fr->off_x[k] + r->b[i] * fr->off_y[k];
    vi4 vstep[3];
    for (int i = 0; i < 3; i++) {
        int st = (int)step[i];
        vstep[i] = (vi4){st, st, st, st};
    }
#if BARY_X4
    /* per edge: the samples' offsets from sample 0 (differences of two
     * values in the box: they fit), a row's step, thr */
    vi4 dlane[3], vstepy[3], thrv[3];
    int64_t dcen[3]; /* the centre's offset from sample 0 */
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < n; k++) dlane[i][k] = (int)(off[k][i] - off[0][i]);
        dcen[i] = off[n][i] - off[0][i];
        int sy = (int)(r->b[i] * SUBPIXEL_ONE), t = (int)r->thr[i];
        vstepy[i] = (vi4){sy, sy, sy, sy};
        thrv[i] = (vi4){t, t, t, t};
    }
    /* samples covered and depth tests passed, counted per lane (a true
     * lane is −1, subtracted) and added to the counters at the end */
    vi4 counts[2] = {{0, 0, 0, 0}, {0, 0, 0, 0}};
#endif
    bool small = (x1 - x0) < BLOCK && (y1 - y0) < BLOCK;
    for (int by0 = y0; by0 <= y1; by0 += BLOCK) {
        int by1 = by0 + BLOCK - 1 < y1 ? by0 + BLOCK - 1 : y1;
        for (int bx0 = x0; bx0 <= x1; bx0 += BLOCK) {
            int bx1 = bx0 + BLOCK - 1 < x1 ? bx0 + BLOCK - 1 : x1;
            if (!small &&
                block_outside(fr, r, bx0, by0, bx1, by1, omin_x, omax_x, omin_y, omax_y))
                continue;
#if BARY_X4
            /* E − thr at the four samples of pixel (bx0, by0), then one
             * vector addition per row and per pixel (exact: every value
             * used lies in the checked box) */
            vi4 evrow[3];
            for (int i = 0; i < 3; i++) {
                int64_t corner = r->a[i] * ((int64_t)bx0 * SUBPIXEL_ONE) +
                                 r->b[i] * ((int64_t)by0 * SUBPIXEL_ONE) + r->c[i];
                int st = (int)(corner + off[0][i] - r->thr[i]);
                evrow[i] = (vi4){st, st, st, st} + dlane[i];
            }
            for (int y = by0; y <= by1; y++) {
                /* the row's coverage first, without a branch per pixel
                 * (whether a pixel has a covered sample is unpredictable):
                 * four bits a pixel, each pixel's E − thr stored; then the
                 * pixels with a covered sample */
                vi4 ev[3] = {evrow[0], evrow[1], evrow[2]};
                vi4 erow[BLOCK][3];
                uint32_t mask = 0;
                for (int i = 0; i <= bx1 - bx0; i++) {
                    /* covered: E − thr >= 0 on all three edges */
                    mask |= (uint32_t)vi4_sign_bits((ev[0] | ev[1] | ev[2]) > -1) << (4 * i);
                    for (int k = 0; k < 3; k++) {
                        erow[i][k] = ev[k];
                        ev[k] += vstep[k];
                    }
                }
                uint32_t any = mask | mask >> 1 | mask >> 2 | mask >> 3;
                for (any &= 0x11111111u; any; any &= any - 1) {
                    int i = __builtin_ctz(any) / 4;
                    const vi4 *e = erow[i];
                    vi4 covv = (e[0] | e[1] | e[2]) > -1;
                    draw_pixel4_v(w, r, bx0 + i, y, tx0, ty0, e, thrv, covv, mask >> (4 * i) & 0xFu,
                                  dcen, counts);
                }
                for (int i = 0; i < 3; i++) evrow[i] += vstepy[i];
            }
            continue;
#endif
            for (int y = by0; y <= by1; y++) {
                int64_t corner[3]; /* E at the corner of pixel (bx0, y) */
                vi4 ev[3] = {{0}};   /* E - thr at the four samples */
                for (int i = 0; i < 3; i++) {
                    corner[i] = r->a[i] * ((int64_t)bx0 * SUBPIXEL_ONE) +
                                r->b[i] * ((int64_t)y * SUBPIXEL_ONE) + r->c[i];
                    for (int k = 0; k < n; k++) ev[i][k] = (int)(corner[i] + off[k][i] - r->thr[i]);
                }
                for (int x = bx0; x <= bx1; x++) {
                    unsigned covered = ~vi4_sign_bits(ev[0] | ev[1] | ev[2]) & 0xFu;
                    if (covered) {
                        int64_t e[RAS_MAX_SAMPLES + 1][3];
                        for (int k = 0; k < n; k++)
                            for (int i = 0; i < 3; i++) e[k][i] = (int64_t)ev[i][k] + r->thr[i];
                        /* the centre (read when no visible sample is there) */
                        int64_t dx = (int64_t)(x - bx0);
                        for (int i = 0; i < 3; i++) e[n][i] = corner[i] + dx * step[i] + off[n][i];
                        draw_pixel_samples(w, r, x, y, tx0, ty0, e, n, covered);
                    }
                    for (int i = 0; i < 3; i++) ev[i] += vstep[i];
                }
            }
        }
    }
#if BARY_X4
    w->k.samples_covered += (uint64_t)(counts[0][0] + counts[0][1] + counts[0][2] + counts[0][3]);
    w->k.depth_tests_passed += (uint64_t)(counts[1][0] + counts[1][1] + counts[1][2] + counts[1][3]);
#endif
    return true;
}

/* The part of r's box inside the tile, drawn by the variant that fits. */
static void draw_in_tile(worker *w, const fast_tri *r, int tx0, int ty0, int tx1, int ty1) {
    int x0 = r->x0 > tx0 ? r->x0 : tx0, x1 = r->x1 < tx1 ? r->x1 : tx1;
    int y0 = r->y0 > ty0 ? r->y0 : ty0, y1 = r->y1 < ty1 ? r->y1 : ty1;
    if (x0 > x1 || y0 > y1) return;
    const int n = w->fr->n;
    /* The reference tests every sample of the bounding box. */
    w->k.samples_tested += (uint64_t)(x1 - x0 + 1) * (uint64_t)(y1 - y0 + 1) * (uint64_t)n;
    switch (n) {
    case 1:
        /* per_pixel a constant in each copy: no test per pixel */
        if (w->fr->centre_sample == 0 &&
            (w->fr->per_pixel ? draw_in_tile_1x32(w, r, tx0, ty0, x0, y0, x1, y1, true)
                              : draw_in_tile_1x32(w, r, tx0, ty0, x0, y0, x1, y1, false)))
            break;
        draw_in_tile_n(w, r, tx0, ty0, x0, y0, x1, y1, 1);
        break;
    case 4:
        if (draw_in_tile_4x32(w, r, tx0, ty0, x0, y0, x1, y1)) break;
        draw_in_tile_n(w, r, tx0, ty0, x0, y0, x1, y1, 4);
        break;
    default: draw_in_tile_n(w, r, tx0, ty0, x0, y0, x1, y1, n); break;
    }
}

/* ---- tiles ----------------------------------------------------------------- */

/* Writing the image: 700² pixels × 12 bytes is larger than the caches, and an
 * ordinary store first reads the line it writes. Non-temporal stores write
 * whole lines without reading them (the same bytes land in the image); the
 * worker's final sfence orders them before the frame is handed back. Tile rows
 * start 16-byte aligned (64 pixels × 12 bytes = 48 × 16) when the image row
 * does; anything else is copied plainly. */
static void put_row(vec3s *dst, const vec3s *src, int count) {
#if defined(__SSE2__)
    if (((uintptr_t)dst & 15) == 0 && ((uintptr_t)src & 15) == 0 && count % 4 == 0) {
        const float *s = &src[0].x;
        float *d = &dst[0].x;
        for (int i = 0; i < 3 * count; i += 4)
            _mm_stream_ps(d + i, _mm_load_ps(s + i));
        return;
    }
#endif
    memcpy(dst, src, sizeof *dst * (size_t)count);
}

/* count copies of c */
static void fill_row(vec3s *dst, vec3s c, int count) {
#if defined(__SSE2__)
    if (((uintptr_t)dst & 15) == 0 && count % 4 == 0) {
        /* four pixels are three vectors: rgbr gbrg brgb */
        __m128 v0 = _mm_setr_ps(c.x, c.y, c.z, c.x), v1 = _mm_setr_ps(c.y, c.z, c.x, c.y),
               v2 = _mm_setr_ps(c.z, c.x, c.y, c.z);
        float *d = &dst[0].x;
        for (int i = 0; i < 3 * count; i += 12) {
            _mm_stream_ps(d + i, v0);
            _mm_stream_ps(d + i + 4, v1);
            _mm_stream_ps(d + i + 8, v2);
        }
        return;
    }
#endif
    for (int i = 0; i < count; i++)
        dst[i] = c;
}

/* count copies of c into the tile's colour buffer (cached: it is read back
 * soon), four samples as three vector stores; count is a multiple of 4 and
 * the buffer 16-byte aligned (malloc's). */
static void fill_colour(vec3s *dst, vec3s c, int count) {
#if defined(__SSE2__)
    __m128 v0 = _mm_setr_ps(c.x, c.y, c.z, c.x), v1 = _mm_setr_ps(c.y, c.z, c.x, c.y),
           v2 = _mm_setr_ps(c.z, c.x, c.y, c.z);
    float *d = &dst[0].x;
    for (int i = 0; i < 3 * count; i += 12) {
        _mm_store_ps(d + i, v0);
        _mm_store_ps(d + i + 4, v1);
        _mm_store_ps(d + i + 8, v2);
    }
#else
    for (int i = 0; i < count; i++)
        dst[i] = c;
#endif
}

/* hw2's resolve_pixel (solution/rasterizer.c) for four samples, in lanes:
 * ((((0 + c0) + c1) + c2) + c3) · (1/4), glms_vec3_add's and _scale's
 * operations lane by lane. Stores 16 bytes at dst (the next pixel's x is
 * rewritten after) and reads 16 at the last sample (the colour buffer has
 * room). */
static inline void resolve4(vec3s *dst, const vec3s *c) {
    vf4 sum = vf4_splat(0.0f);
    for (int s = 0; s < 4; s++) sum = sum + vf4_load(&c[s].x);
    sum = sum * vf4_splat(1.0f / (float)4);
    memcpy(dst, &sum, sizeof sum);
}

static void do_tile(worker *w, int tile) {
    frame *fr = w->fr;
    const int n = fr->n;
    int tx = tile % fr->tiles_x, ty = tile / fr->tiles_x;
    int tx0 = tx * TILE, ty0 = ty * TILE;
    int tx1 = tx0 + TILE - 1 < fr->width - 1 ? tx0 + TILE - 1 : fr->width - 1;
    int ty1 = ty0 + TILE - 1 < fr->height - 1 ? ty0 + TILE - 1 : fr->height - 1;
    vec3s clear = fr->scene->clear_color;
    size_t first = fr->bin_start[tile], end = fr->bin_start[tile + 1];
    if (first == end) {
        /* No triangle touches the tile (most of the screen around a model):
         * every pixel resolves like one pixel of clear samples, so resolve
         * that one pixel and fill, without clearing a tile of samples. */
        vec3s c = clear;
        if (n > 1) {
            for (int s = 0; s < n; s++)
                w->color[s] = clear;
            ras_framebuffer one = {
                .width = 1, .height = 1, .samples = n, .color = w->color, .depth = w->depth};
            c = resolve_pixel(&one, 0, 0);
        }
        for (int y = ty0; y <= ty1; y++)
            fill_row(&fr->out->pixels[(size_t)(fr->height - 1 - y) * (size_t)fr->width + tx0], c,
                     tx1 - tx0 + 1);
        return;
    }
    fill_colour(w->color, clear, TILE * TILE * n);
    for (int i = 0; i < TILE * TILE * n; i++)
        w->depth[i] = INFINITY;
    for (size_t j = first; j < end; j++) {
        /* The records are visited in bin order, scattered in memory: fetch
         * the next ones while this one is drawn. */
        if (j + 2 < end) {
            const char *next = (const char *)fr->bin_tri[j + 2];
            __builtin_prefetch(next);
            __builtin_prefetch(next + 64);
            __builtin_prefetch(next + 128);
            __builtin_prefetch(next + 192);
            __builtin_prefetch(next + 256);
        }
        draw_in_tile(w, fr->bin_tri[j], tx0, ty0, tx1, ty1);
    }
    if (atomic_load(&fr->failed)) { /* out of memory: the frame is abandoned */
        w->nfrag = 0;
        return;
    }
    shade_deferred(w);
    /* Resolve: sample 0 with one sample (ras_resolve_frame), else the hw2
     * reference resolve_pixel on a framebuffer view of this tile. */
    ras_framebuffer view = {.width = TILE, .height = TILE, .samples = n,
                            .color = w->color, .depth = w->depth};
    for (int y = ty0; y <= ty1; y++) {
        vec3s *dst = &fr->out->pixels[(size_t)(fr->height - 1 - y) * (size_t)fr->width];
        const vec3s *src = &w->color[(size_t)(y - ty0) * TILE * (size_t)n];
        if (n == 1) {
            put_row(&dst[tx0], src, tx1 - tx0 + 1);
        } else {
            /* resolve_pixel reads screen pixel (x, y) of the view at row
             * TILE-1-y: hand it the mirrored row. */
            _Alignas(16) vec3s row[TILE + 1]; /* + 1: resolve4's last store */
            if (n == 4)
                for (int x = tx0; x <= tx1; x++)
                    resolve4(&row[x - tx0], &w->color[((size_t)(y - ty0) * TILE + (size_t)(x - tx0)) * 4]);
            else
                for (int x = tx0; x <= tx1; x++)
                    row[x - tx0] = resolve_pixel(&view, x - tx0, TILE - 1 - (y - ty0));
            put_row(&dst[tx0], row, tx1 - tx0 + 1);
        }
    }
}

/* ---- setup in parallel ------------------------------------------------------ */

/* Setup is shared out too (it is about a sixth of a 1x frame): vertex chunks
 * (each vertex is transformed on its own, by the same ras_vertex_transform on
 * a slice of the mesh), then triangle chunks, each into its own record list;
 * the lists in chunk order are the submission order, so binning sees exactly
 * the sequence a single thread would have produced. Chunks are claimed from
 * shared counters, so any number of threads (even one whose siblings failed to
 * start) finishes them; a thread that runs out waits for the stragglers. */
#define VERTEX_CHUNK 1024
#define TRIANGLE_CHUNK 256

static void wait_for(atomic_int *v, int target) {
    while (atomic_load(v) < target)
        sched_yield();
}

static void transform_chunk(frame *fr, int c) {
    int o = fr->vchunk_obj[c];
    const ras_mesh *mesh = fr->assets->meshes[o];
    size_t start = fr->vchunk_start[c];
    ras_mesh part = *mesh;
    part.vertex_count =
        mesh->vertex_count - start < VERTEX_CHUNK ? mesh->vertex_count - start : VERTEX_CHUNK;
    part.positions += start;
    if (part.normals) part.normals += start;
    if (part.uvs) part.uvs += start;
    if (part.colors) part.colors += start;
    size_t first = fr->clip_base[o] + start;
    ras_vertex_transform(&part, fr->models[o], fr->view, fr->projection, fr->stage->varyings,
                         fr->clip + first);
    for (size_t v = first; v < first + part.vertex_count; v++) {
        fr->screen[v] = ras_viewport(fr->clip[v].p_clip, fr->width, fr->height);
        fr->voutcode[v] = (unsigned char)ras_clip_outcode(fr->clip[v].p_clip);
        fr->vflags[v] = (unsigned char)((clip_vertex_finite(&fr->clip[v]) ? VERTEX_FINITE : 0) |
                                        (ras_vec4_finite(fr->screen[v]) ? SCREEN_FINITE : 0));
    }
}

static void setup_chunk(worker *w, int c) {
    frame *fr = w->fr;
    size_t g = (size_t)c * TRIANGLE_CHUNK, end = g + TRIANGLE_CHUNK;
    if (end > fr->tri_first[fr->scene->object_count]) end = fr->tri_first[fr->scene->object_count];
    tri_list *L = &fr->lists[c];
    int o = 0;
    while (fr->tri_first[o + 1] <= g)
        o++;
    for (; g < end; g++) {
        while (fr->tri_first[o + 1] <= g)
            o++;
        const ras_mesh *mesh = fr->assets->meshes[o];
        const unsigned *idx = &mesh->indices[3 * (g - fr->tri_first[o])];
        size_t base = fr->clip_base[o];
        const ras_clip_vertex *clip = fr->clip + base;
        const unsigned char flags[3] = {fr->vflags[base + idx[0]], fr->vflags[base + idx[1]],
                                        fr->vflags[base + idx[2]]};
        const unsigned char outcode[3] = {fr->voutcode[base + idx[0]],
                                          fr->voutcode[base + idx[1]],
                                          fr->voutcode[base + idx[2]]};
        const vec4s *screen[3] = {&fr->screen[base + idx[0]], &fr->screen[base + idx[1]],
                                  &fr->screen[base + idx[2]]};
        if (!setup_triangle(L, &clip[idx[0]], &clip[idx[1]], &clip[idx[2]], flags, outcode,
                            screen, o, fr->width, fr->height, &w->ks)) {
            atomic_store(&fr->failed, true);
            return;
        }
    }
}

/* The chunk lists in order into the tiles' bins (one thread, once). */
static void bin_triangles(frame *fr) {
    int tiles = fr->tiles_x * fr->tiles_y;
    for (int c = 0; c < fr->tchunks; c++)
        for (size_t i = 0; i < fr->lists[c].count; i++) {
            const fast_tri *r = &fr->lists[c].tri[i];
            for (int ty = r->y0 / TILE; ty <= r->y1 / TILE; ty++)
                for (int tx = r->x0 / TILE; tx <= r->x1 / TILE; tx++)
                    fr->bin_start[ty * fr->tiles_x + tx + 1]++;
        }
    for (int t = 0; t < tiles; t++)
        fr->bin_start[t + 1] += fr->bin_start[t];
    fr->bin_tri = malloc((fr->bin_start[tiles] + 1) * sizeof *fr->bin_tri);
    size_t *fill = malloc((size_t)tiles * sizeof *fill);
    if (!fr->bin_tri || !fill) {
        free(fill);
        atomic_store(&fr->failed, true);
        return;
    }
    memcpy(fill, fr->bin_start, (size_t)tiles * sizeof *fill);
    for (int c = 0; c < fr->tchunks; c++)
        for (size_t i = 0; i < fr->lists[c].count; i++) {
            const fast_tri *r = &fr->lists[c].tri[i];
            for (int ty = r->y0 / TILE; ty <= r->y1 / TILE; ty++)
                for (int tx = r->x0 / TILE; tx <= r->x1 / TILE; tx++)
                    fr->bin_tri[fill[ty * fr->tiles_x + tx]++] = r;
        }
    free(fill);
}

static void *worker_main(void *arg) {
    worker *w = arg;
    frame *fr = w->fr;
    for (int c; (c = atomic_fetch_add(&fr->next_vchunk, 1)) < fr->vchunks;) {
        transform_chunk(fr, c);
        atomic_fetch_add(&fr->vchunks_done, 1);
    }
    wait_for(&fr->vchunks_done, fr->vchunks);
    for (int c; (c = atomic_fetch_add(&fr->next_tchunk, 1)) < fr->tchunks;) {
        setup_chunk(w, c);
        /* whoever finishes the last chunk bins */
        if (atomic_fetch_add(&fr->tchunks_done, 1) == fr->tchunks - 1) {
            fr->t_setup = ras_now_ms();
            if (!atomic_load(&fr->failed)) bin_triangles(fr);
            atomic_store(&fr->binned, 1);
        }
    }
    wait_for(&fr->binned, 1);
    int tiles = fr->tiles_x * fr->tiles_y;
    while (!atomic_load(&fr->failed)) {
        int tile = atomic_fetch_add(&fr->next_tile, 1);
        if (tile >= tiles) break;
        do_tile(w, tile);
    }
    for (int o = 0; o < fr->scene->object_count; o++)
        if (w->hidden[o]) count_unshaded(w, o, (uint64_t)w->hidden[o]);
#if defined(__SSE2__)
    _mm_sfence(); /* put_row's and fill_row's streaming stores, before the join */
#endif
    return NULL;
}

/* ---- the frame ------------------------------------------------------------- */

/* What the fast path draws: no culling, z01 depth, at most FAST_MAX_OBJECTS
 * objects. */
static bool fast_accepts(const hw3_renderer *self, const hw3_frame *frame) {
    const hw3_render_options *opt = frame->opt;
    (void)self;
    return opt->cull == RAS_CULL_NONE && opt->depth == RAS_DEPTH_Z01 &&
           frame->scene->object_count <= FAST_MAX_OBJECTS;
}

static int thread_count(const hw3_fast_settings *s) {
    int n = s ? s->threads : 0;
    if (n <= 0) {
        const char *env = getenv("RAS_THREADS");
        n = env ? atoi(env) : 0;
    }
    if (n <= 0) n = (int)sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > MAX_THREADS ? MAX_THREADS : n;
}

/* The frame's sample offsets in sub-pixels (the centre's at [n]), the box
 * they span (block rejection's corners), the sample at the centre if there is
 * one, and what shading needs per frame. */
static void plan_samples(frame *fr, const ras_sample_pattern *pattern) {
    const ras_scene *scene = fr->scene;
    for (int s = 0; s <= fr->n; s++) {
        vec2s o = s < fr->n ? pattern->offsets[s] : (vec2s){{0.5f, 0.5f}};
        fr->off_x[s] = llround((double)o.x * SUBPIXEL_ONE);
        fr->off_y[s] = llround((double)o.y * SUBPIXEL_ONE);
    }
    for (int o = 0; o < scene->object_count; o++)
        fr->spec_zero[o] = spec_zero_of(scene->objects[o].material.p);
    fr->omin_x = fr->omax_x = fr->off_x[0];
    fr->omin_y = fr->omax_y = fr->off_y[0];
    for (int k = 1; k <= fr->n; k++) {
        fr->omin_x = fr->off_x[k] < fr->omin_x ? fr->off_x[k] : fr->omin_x;
        fr->omax_x = fr->off_x[k] > fr->omax_x ? fr->off_x[k] : fr->omax_x;
        fr->omin_y = fr->off_y[k] < fr->omin_y ? fr->off_y[k] : fr->omin_y;
        fr->omax_y = fr->off_y[k] > fr->omax_y ? fr->off_y[k] : fr->omax_y;
    }
    fr->centre_sample = -1;
    for (int s = 0; s < fr->n && fr->centre_sample < 0; s++)
        if (fr->off_x[s] == fr->off_x[fr->n] && fr->off_y[s] == fr->off_y[fr->n])
            fr->centre_sample = s;
    const hw3_fragment_stage *stage = fr->stage;
    fr->varyings_per_fragment = (uint64_t)(!!(stage->varyings & RAS_VARYING_NORMAL) +
                                           !!(stage->varyings & RAS_VARYING_VIEW_POS) +
                                           !!(stage->varyings & RAS_VARYING_UV));
}

/* The setup plan that worker_main runs: where each object's vertices and
 * triangles start, the vertex chunks, and a record list per triangle chunk;
 * the arrays setup fills. The vertex stage is counted here (every vertex is
 * transformed). False: out of memory (what was allocated is freed by
 * free_frame). */
static bool plan_setup(frame *fr, ras_counters *k) {
    const ras_scene *scene = fr->scene;
    int objects = scene->object_count;
    size_t vertices = 0, vchunks = 0;
    for (int o = 0; o < objects; o++) {
        const ras_mesh *mesh = fr->assets->meshes[o];
        vertices += mesh->vertex_count;
        vchunks += (mesh->vertex_count + VERTEX_CHUNK - 1) / VERTEX_CHUNK;
        k->stages_run |= RAS_STAGE_VERTEX;
        k->vertices_transformed += mesh->vertex_count;
        if (mesh->triangle_count) k->stages_run |= RAS_STAGE_CLIP | RAS_STAGE_SETUP;
    }
    fr->clip_base = malloc(((size_t)objects + 1) * sizeof *fr->clip_base);
    fr->tri_first = calloc((size_t)objects + 1, sizeof *fr->tri_first); /* read by the error */
    fr->vchunk_obj = malloc((vchunks + 1) * sizeof *fr->vchunk_obj);
    fr->vchunk_start = malloc((vchunks + 1) * sizeof *fr->vchunk_start);
    fr->clip = malloc((vertices + 1) * sizeof *fr->clip);
    fr->screen = malloc((vertices + 1) * sizeof *fr->screen);
    fr->vflags = malloc(vertices + 1);
    fr->voutcode = malloc(vertices + 1);
    fr->bin_start = calloc((size_t)fr->tiles_x * fr->tiles_y + 1, sizeof *fr->bin_start);
    if (!(fr->clip_base && fr->tri_first && fr->vchunk_obj && fr->vchunk_start && fr->clip &&
          fr->screen && fr->vflags && fr->voutcode && fr->bin_start))
        return false;
    size_t v = 0, t = 0;
    int c = 0;
    for (int o = 0; o < objects; o++) {
        const ras_mesh *mesh = fr->assets->meshes[o];
        fr->clip_base[o] = v;
        fr->tri_first[o] = t;
        for (size_t start = 0; start < mesh->vertex_count; start += VERTEX_CHUNK) {
            fr->vchunk_obj[c] = o;
            fr->vchunk_start[c++] = start;
        }
        v += mesh->vertex_count;
        t += mesh->triangle_count;
    }
    fr->tri_first[objects] = t;
    fr->vchunks = c;
    fr->tchunks = (int)((t + TRIANGLE_CHUNK - 1) / TRIANGLE_CHUNK);
    fr->lists = calloc((size_t)fr->tchunks + 1, sizeof *fr->lists);
    if (!fr->lists) return false;
    for (int i = 0; i < fr->tchunks; i++) {
        /* room for the chunk's triangles and a few clipped pieces */
        fr->lists[i].capacity = TRIANGLE_CHUNK + TRIANGLE_CHUNK / 4;
        fr->lists[i].tri = malloc(fr->lists[i].capacity * sizeof *fr->lists[i].tri);
        if (!fr->lists[i].tri) return false;
    }
    return true;
}

/* One worker's tile buffers, fragment list and sample owners, and its
 * payloads (one per object, counting into the worker's counters). False: out
 * of memory (free_frame frees what was allocated). */
static bool worker_init(worker *w, frame *fr, size_t tile_samples) {
    const ras_scene *scene = fr->scene;
    w->fr = fr;
    w->color = malloc((tile_samples + 2) * sizeof *w->color); /* + 2: resolve4 */
    /* DEPTH_PAD more: the first is draw_in_tile_1x32's spare slot for the
     * depth of a fragment that failed the test (written, never read) */
    w->depth = malloc((tile_samples + DEPTH_PAD) * sizeof *w->depth);
    /* room for a tile's worth of fragments; defer_fragment grows it. One
     * more: per_pixel's spare record for fragments that fail the depth test */
    w->frag_cap = (size_t)TILE * TILE;
    w->frags = malloc((w->frag_cap + 1) * sizeof *w->frags);
    w->owner = malloc(tile_samples * sizeof *w->owner);
    if (!(w->color && w->depth && w->frags && w->owner)) return false;
    for (int i = 0; i < DEPTH_PAD; i++) w->depth[tile_samples + i] = INFINITY;
    for (int o = 0; o < scene->object_count; o++) {
        fragment_shader_payload *p = &w->pay[o];
        *p = fr->stage->base;
        hw3_object_material(scene, fr->assets, o, p);
        p->counters = &w->k;
    }
    return true;
}

/* The calling thread is worker 0; the others get threads of their own
 * (fewer workers, if some fail to start, is only slower). False: the frame
 * failed (out of memory somewhere). */
static bool run_workers(frame *fr, worker *workers, int threads) {
    int started = 1;
    for (; started < threads; started++)
        if (pthread_create(&workers[started].thread, NULL, worker_main, &workers[started]))
            break;
    worker_main(&workers[0]);
    for (int i = 1; i < started; i++) pthread_join(workers[i].thread, NULL);
    return !atomic_load(&fr->failed);
}

/* The workers' counters, setup's and the tiles', added into k, with the
 * buffers they used; *settings->shaded gets the fragments really shaded. */
static void sum_counters(const frame *fr, const worker *workers, int threads,
                         size_t tile_samples, const hw3_fast_settings *settings,
                         ras_counters *k) {
    for (int i = 0; i < threads; i++) {
        const ras_counters *s = &workers[i].ks;
        k->stages_run |= s->stages_run;
        k->triangles_in += s->triangles_in;
        k->triangles_rejected_nonfinite += s->triangles_rejected_nonfinite;
        k->triangles_rejected_range += s->triangles_rejected_range;
        k->triangles_clipped_away += s->triangles_clipped_away;
        k->triangles_clip_split += s->triangles_clip_split;
        k->triangles_rasterized += s->triangles_rasterized;
        k->triangles_degenerate += s->triangles_degenerate;
        const ras_counters *c = &workers[i].k;
        k->stages_run |= c->stages_run;
        k->samples_tested += c->samples_tested;
        k->samples_covered += c->samples_covered;
        k->depth_tests_passed += c->depth_tests_passed;
        k->fragments_shaded += c->fragments_shaded;
        k->varyings_interpolated += c->varyings_interpolated;
        k->texels_fetched += c->texels_fetched;
        k->lighting_evaluations += c->lighting_evaluations;
    }
    if (fr->n > 1) k->stages_run |= RAS_STAGE_RESOLVE;
    k->buffer_bytes = (size_t)threads * tile_samples * (sizeof(vec3s) + sizeof(float));
    uint64_t shaded = 0;
    for (int i = 0; i < threads; i++) {
        shaded += workers[i].shaded;
        k->buffer_bytes += tile_samples * sizeof(int32_t) + workers[i].frag_cap * sizeof(queued);
    }
    if (settings && settings->shaded) *settings->shaded = shaded;
}

/* Everything fast_draw allocated (NULL-safe: a frame that failed halfway). */
static void free_frame(frame *fr, worker *workers, int threads) {
    for (int i = 0; workers && i < threads; i++) {
        free(workers[i].color);
        free(workers[i].depth);
        free(workers[i].frags);
        free(workers[i].owner);
    }
    free(workers);
    for (int i = 0; fr->lists && i < fr->tchunks; i++)
        free(fr->lists[i].tri);
    free(fr->lists);
    free(fr->bin_start);
    free(fr->bin_tri);
    free(fr->clip);
    free(fr->screen);
    free(fr->vflags);
    free(fr->voutcode);
    free(fr->clip_base);
    free(fr->tri_first);
    free(fr->vchunk_obj);
    free(fr->vchunk_start);
}

/* One frame: plan, set up and bin (worker_main, shared out), tiles on the
 * workers, then the counters and times as the teaching pipeline reports them. */
static bool fast_draw(const hw3_renderer *self, const hw3_frame *frame_in, ras_image *out,
                      ras_counters *k, ras_error *err) {
    const hw3_fast_settings *settings = self->user;
    const ras_scene *scene = frame_in->scene;
    const hw3_render_options *opt = frame_in->opt;
    int width = scene->width, height = scene->height;
    if (width < 1 || height < 1 || width > RAS_IMAGE_MAX_SIDE || height > RAS_IMAGE_MAX_SIDE)
        return ras_error_set(err, "frame size %dx%d is out of range", width, height);
    ras_sample_pattern pattern = opt->aa == RAS_AA_NONE ? ras_sample_pattern_center() : opt->pattern;
    if (pattern.count < 1 || pattern.count > RAS_MAX_SAMPLES)
        return ras_error_set(err, "the sample pattern is empty: build it with ras_sample_pattern_make");
    double t0 = ras_now_ms();
    frame fr = {.scene = scene, .assets = frame_in->assets, .stage = frame_in->stage, .width = width, .height = height,
                .n = pattern.count, .ssaa = opt->aa == RAS_AA_SSAA, .pattern = pattern,
                .varyings = frame_in->stage->varyings, .out = out,
                .models = frame_in->models, .view = frame_in->view,
                .projection = frame_in->projection,
                .tiles_x = (width + TILE - 1) / TILE, .tiles_y = (height + TILE - 1) / TILE};
    plan_samples(&fr, &pattern);
    fr.batch = batch_kind(scene, opt, frame_in->stage);
    /* frags holds a tile's pixels from the start (worker_init) */
    fr.per_pixel = fr.n == 1 && fr.batch != BATCH_NONE;
    int tiles = fr.tiles_x * fr.tiles_y;
    int threads = thread_count(settings);
    if (threads > tiles) threads = tiles;
    worker *workers = calloc((size_t)threads, sizeof *workers);
    bool ok = plan_setup(&fr, k) && workers;
    atomic_init(&fr.next_vchunk, 0);
    atomic_init(&fr.vchunks_done, 0);
    atomic_init(&fr.next_tchunk, 0);
    atomic_init(&fr.tchunks_done, 0);
    atomic_init(&fr.binned, fr.tchunks == 0); /* no triangles: the bins are empty */
    atomic_init(&fr.failed, false);
    atomic_init(&fr.next_tile, 0);
    fr.t_setup = t0;
    size_t tile_samples = (size_t)TILE * TILE * (size_t)fr.n;
    for (int i = 0; ok && i < threads; i++) ok = worker_init(&workers[i], &fr, tile_samples);
    if (ok) ok = run_workers(&fr, workers, threads);
    if (ok)
        sum_counters(&fr, workers, threads, tile_samples, settings, k);
    else
        ras_error_set(err, "out of memory drawing %zu triangles",
                      fr.tri_first ? fr.tri_first[scene->object_count] : (size_t)0);
    free_frame(&fr, workers, threads);
    double t1 = fr.t_setup, t2 = ras_now_ms();
    k->ms_vertex += t1 - t0;
    k->ms_raster += t2 - t1;
    k->ms_total += t2 - t0;
    return ok;
}

hw3_renderer hw3_fast_renderer(hw3_fast_settings *settings) {
    return (hw3_renderer){.name = "fast", .accepts = fast_accepts, .draw = fast_draw,
                          .user = settings};
}
