/* fast/fast_priv.h — what the fast renderer's stages share. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * The fast renderer (fast_render.h) is built like Mesa's llvmpipe, one file
 * per stage, each reading and writing the records below:
 *
 *   fast_setup.c          setup and binning: vertex transform, clipping,
 *                         viewport and the fixed-point snap of every triangle
 *                         into a fast_tri record, in submission order, then
 *                         each record into the bin of every 64×64 screen tile
 *                         its box touches (lp_setup_tri.c, lp_setup.c)
 *   fast_rast.c           one triangle into one tile: coverage, barycentrics,
 *                         the depth test; the fragments that pass are
 *                         recorded (fast_defer_*) — its tile loops are made
 *                         from one template, fast_rast_tile_tmp.h
 *                         (lp_rast_tri.c, lp_rast_tri_tmp.h)
 *   fast_shade.c          the tile's fragments shaded once drawn: those that
 *                         still own a sample, through the four-lane queue or
 *                         one at a time, and the counters of the others
 *   fast_shade_x4.c       the four-lane shaders (fast_simd.h)
 *   fast_tile.c           one tile from start to end: clear, rasterize its
 *                         bin, shade, resolve into the image (lp_rast.c)
 *   fast_frame.c          the frame: planning, the worker threads, the
 *                         counters; fast_render (lp_scene.c, lp_rast.c's
 *                         threads)
 *
 * Every private copy of a reference function is listed, with the test that
 * holds it equal, in fast/README.md.
 */
#ifndef RAS_FAST_PRIV_H
#define RAS_FAST_PRIV_H

#include "fast_render.h"

#include "fast_simd.h" /* vf4, v3x4: four fragments at once */

#include <pthread.h>   /* pthread_t */
#include <stdatomic.h> /* atomic_int */
#include <stddef.h>    /* offsetof */
#include <stdint.h>    /* int64_t, uint64_t */
#include <stdlib.h>    /* realloc */
#include <string.h>    /* memcpy */

#define TILE 64 /* pixels per tile side */
#define BLOCK 8 /* pixels per rejection block side */
/* Objects a frame may have: the per-object payloads and counters are kept in
 * fixed arrays (a worker's); fast_render declines larger scenes, which the
 * teaching pipeline draws. */
#define FAST_MAX_OBJECTS 64
#define SUBPIXEL_BITS 8 /* as hw2_rasterize/solution/rasterizer.c */
#define SUBPIXEL_ONE (1 << SUBPIXEL_BITS)
#define FIXED_LIMIT_PX (1 << 20)
_Static_assert(RAS_RASTER_MAX_COORD <= FIXED_LIMIT_PX,
               "the fast path's int64 edge functions must hold the rasterizer's whole range");

/* ---- triangle records ------------------------------------------------------ */

typedef struct fast_tri {
    /* What rasterizing reads first, together (three cache lines; fast_tile_draw
     * prefetches them): */
    /* E_k(P) = a[k]·Px + b[k]·Py + c[k] (sub-pixel units) for the edge
     * opposite corner k of the CCW-ordered triangle; covered when
     * E_k >= thr[k] (thr = -bias: 0 on top-left edges, 1 elsewhere). */
    int64_t a[3], b[3], c[3], thr[3], area2;
    double inv_area2;   /* RN(1 / area2), for ratio_to_float */
    int order[3];       /* original vertex index of corner k */
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

typedef struct fast_tri_list {
    fast_tri *tri;
    size_t count, capacity;
} fast_tri_list;

/* Per vertex, computed once when the vertex is transformed (a vertex is shared
 * by about six triangles): */
enum {
    VERTEX_FINITE = 1, /* fast_setup's clip_vertex_finite */
    SCREEN_FINITE = 2  /* ras_viewport's result is finite */
};

/* The four-lane form of a shader (fast_shade_x4.c), or none. */
enum { BATCH_NONE, BATCH_NORMAL, BATCH_PHONG, BATCH_TEXTURE, BATCH_BUMP, BATCH_DISPLACEMENT };

/* How the one-at-a-time path (fast_shade.c's shade) colours a fragment of
 * a shader: the shader itself (the reference function), or Blinn-Phong with
 * the material's colour or with the colour map's texel as kd
 * (blinn_phong, which skips powf where it is certainly +0). */
enum { SCALAR_REFERENCE, SCALAR_LIT_COLOUR, SCALAR_LIT_TEXTURE };

/* What the fast path knows of one of hw3's shaders, declared in one table
 * (fast_shade.c's shader_table, one row per hw3 shader): it is found by the
 * shader's name in the render options, never by its function's address. */
typedef struct fast_shader {
    int batch;       /* BATCH_*: its four-lane form */
    unsigned needs;  /* RAS_VARYING_*: what the four-lane form reads */
    bool lit;        /* the four-lane form needs a light (else one at a time) */
    bool any_filter; /* false: trilinear (per-fragment uv derivatives) is
                      * shaded one at a time */
    int scalar;      /* SCALAR_*: the one-at-a-time path */
} fast_shader;

typedef struct fast_frame {
    const ras_scene *scene;
    const ras_scene_assets *assets;
    const hw3_frame *setup; /* hw3_frame_setup's: the shader, varyings, payload */
    bool perspective;       /* !opt->affine */
    int width, height;
    bool ssaa;
    ras_sample_pattern pattern; /* its count is the samples per pixel, n below */
    int64_t off_x[RAS_MAX_SAMPLES + 1], off_y[RAS_MAX_SAMPLES + 1]; /* [n] = centre */
    /* the box of those offsets (samples and centre): block rejection's corners */
    int64_t omin_x, omax_x, omin_y, omax_y;
    unsigned varyings;
    uint64_t varyings_per_fragment;
    int centre_sample; /* a sample whose position is the pixel centre, or -1 */
    /* per object (each has its own p): powf(x, p) is +0 for 0 <= x <= spec_zero
     * (fast_spec_zero) */
    float spec_zero[FAST_MAX_OBJECTS];
    /* bins: tile t holds bin_tri[bin_start[t] .. bin_start[t+1]) */
    int tiles_x, tiles_y;
    size_t *bin_start;
    const fast_tri **bin_tri;
    atomic_int next_tile;
    /* setup, shared out in chunks (fast_setup_triangles) */
    const mat4s *models;
    mat4s view, projection;
    ras_clip_vertex *clip;   /* every object's vertices, object o from clip_base[o] */
    vec4s *screen;           /* their ras_viewport */
    unsigned char *vflags;   /* VERTEX_FINITE | SCREEN_FINITE */
    unsigned char *voutcode; /* ras_clip_outcode */
    size_t *clip_base;       /* [object_count] */
    size_t *tri_first;       /* [object_count + 1]: object o's first triangle, counted over all */
    int vchunks, tchunks;    /* vertex chunks: (vchunk_obj, vchunk_start) */
    int *vchunk_obj;
    size_t *vchunk_start;
    fast_tri_list *lists; /* [tchunks]: chunk c's records, in submission order */
    atomic_int next_vchunk, vchunks_done, next_tchunk, tchunks_done, binned;
    atomic_bool failed; /* out of memory somewhere */
    double t_setup;     /* when setup ended (ms_vertex) */
    ras_image *out;
    const fast_shader *shader; /* the frame's shader, as shader_table declares it */
    int batch;                 /* BATCH_*: shade through the queue, four at a time */
    /* One sample per pixel and a batched shader: a fragment that passes the
     * depth test is recorded at its pixel (frags[base]), replacing the one
     * it hides, instead of appended (see fast_shade_tile). */
    bool per_pixel;
} fast_frame;

/* A visible fragment waiting to be shaded: its colour goes to the tile
 * samples base + k for every bit k of mask. */
typedef struct fast_queued {
    const fast_tri *r;
    vec3s bary;
    float pad; /* 0: bary is loaded as four floats (shade_prepare) */
    int base;
    int object;    /* r->object, at hand for queue_fragment */
    uint64_t mask; /* RAS_MAX_SAMPLES is 64 */
} fast_queued;
/* shade_prepare loads bary and pad as one four-float vector */
_Static_assert(offsetof(fast_queued, pad) == offsetof(fast_queued, bary) + 3 * sizeof(float),
               "fast_queued.pad must follow bary");

#define QUEUE 8
#define DEPTH_PAD 8 /* floats past a tile's depth samples (one is used) */

typedef struct fast_worker {
    fast_frame *fr;
    vec3s *color; /* TILE² · n, sample s of tile pixel (lx, ly) at (ly·TILE + lx)·n + s */
    float *depth;
    fragment_shader_payload pay[FAST_MAX_OBJECTS];
    ras_counters k;
    ras_counters ks; /* setup's counters */
    pthread_t thread;
    const fast_queued *q[QUEUE]; /* fragments of frags, queued for shading */
    int qn;
    /* Deferred shading (every shader): the tile's fragments in drawing
     * order, and for every sample the fragment that last passed its depth
     * test (read only where the depth is below +inf). */
    fast_queued *frags;
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
} fast_worker;

/* Fragment i owns the samples `mask` of tile sample index base; four
 * samples in a row (a whole pixel of 4x, the common case) are one store. */
static inline void fast_defer_set_owner(fast_worker *w, int base, uint64_t mask, int32_t i) {
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
 * still owns then take its colour (fast_shade_tile). */
static inline void fast_defer_fragment(fast_worker *w, const fast_tri *r, vec3s bary, int base,
                                       uint64_t mask) {
    if (w->nfrag == w->frag_cap) {
        size_t cap = 2 * w->frag_cap;
        /* owner indices are int32: past that (80 GB of fragments) the fast_frame
         * fails like any other allocation */
        fast_queued *grown = cap <= INT32_MAX ? realloc(w->frags, (cap + 1) * sizeof *grown) : NULL;
        if (!grown) { /* the frame fails with "out of memory" */
            atomic_store(&w->fr->failed, true);
            return;
        }
        w->frags = grown;
        w->frag_cap = cap;
    }
    int32_t i = (int32_t)w->nfrag++;
    w->frags[i] = (fast_queued){r, bary, 0.0f, base, r->object, mask};
    fast_defer_set_owner(w, base, mask, i);
}

/* fast_defer_fragment for a pixel's one sample (n = 1; mask 1). In per_pixel mode
 * the fragment is written at its pixel, over the one it hides (shade_pixels
 * fills in the rest), and counted as hidden until shade_pixels finds it. */
static inline void fast_defer_put_pixel(fast_worker *w, const fast_tri *r, vec3s bary, int base) {
    fast_queued *f = &w->frags[base];
    f->r = r;
    f->bary = bary;
    f->pad = 0.0f;
}

static inline void fast_defer_pixel(fast_worker *w, const fast_tri *r, vec3s bary, int base) {
    if (!w->fr->per_pixel) {
        fast_defer_fragment(w, r, bary, base, 1);
        return;
    }
    fast_defer_put_pixel(w, r, bary, base);
    w->hidden[r->object]++;
}

/* What height_sample and bump_normal add to the counters for `count`
 * fragments: `lookups` height lookups each. */
static inline void fast_count_heights(const fragment_shader_payload *pay, uint64_t lookups,
                                      uint64_t count) {
    if (!pay->counters || !pay->height_map) return;
    pay->counters->stages_run |= RAS_STAGE_TEXTURE | RAS_STAGE_BUMP;
    pay->counters->texels_fetched += lookups * (pay->filter == FILTER_NEAREST ? 1 : 4) * count;
}

/* ---- the stages (each file's top comment says more) ---------------------- */

/* fast_setup.c. fast_setup_plan: where each object's vertices and triangles
 * start, the vertex and triangle chunks the workers share out, the arrays
 * setup fills; the vertex stage counted into k. False: out of memory (what
 * was allocated is freed by fast_frame.c's free_frame). */
bool fast_setup_plan(fast_frame *fr, ras_counters *k);
/* Vertex chunk c: transformed, viewport, outcodes, finiteness. */
void fast_setup_vertices(fast_frame *fr, int c);
/* Triangle chunk c into its record list, counted into w->ks. */
void fast_setup_triangles(fast_worker *w, int c);
/* The chunk lists in order into the tiles' bins (one thread, once). */
void fast_setup_bin(fast_frame *fr);

/* fast_rast.c: the part of r's box inside the tile [tx0, tx1] × [ty0, ty1],
 * rasterized, depth-tested and its fragments recorded. */
void fast_rast_triangle(fast_worker *w, const fast_tri *r, int tx0, int ty0, int tx1, int ty1);

/* fast_shade.c. The frame's shader as shader_table declares it (NULL: not
 * one of hw3's); the four-lane form the frame can use (BATCH_NONE: one at a
 * time). */
const fast_shader *fast_shade_find(ras_scene_shader shader);
int fast_shade_batch(const fast_shader *shader, const hw3_render_options *opt,
                     const hw3_frame *setup);
/* powf(x, p) is +0 for 0 <= x <= fast_spec_zero(p) (-1: never). */
float fast_spec_zero(float p);
/* The end of a tile: its recorded fragments shaded, or counted. */
void fast_shade_tile(fast_worker *w);
/* The end of a worker: the fragments it counted as hidden, into its
 * counters. */
void fast_shade_count_hidden(fast_worker *w);
/* One fragment one at a time, without counting (a lane the four-lane path
 * has already counted). */
vec3s fast_shade_silent(fast_worker *w, const fast_tri *r, vec3s bary);

/* fast_shade_x4.c: the queued fragments, shaded four at a time. */
void fast_shade_x4_flush(fast_worker *w);

/* fast_tile.c: tile number `tile` of the frame, from clear to image. */
void fast_tile_draw(fast_worker *w, int tile);

#endif
