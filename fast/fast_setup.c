/* fast/fast_setup.c — the fast renderer's setup and binning. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * In submission order, as the teaching pipeline (common/pipeline/ras_pipeline.c) does
 * it and with its counters: every vertex transformed (ras_vertex_transform,
 * the reference's), every triangle clipped (ras_clip_triangle), put on
 * screen (ras_viewport, ras_setup_triangle) and snapped to the reference
 * rasterizer's fixed point (setup_fixed, a copy of
 * hw2_rasterize/solution/rasterizer.c's) into a fast_tri record; then each
 * record into the bin of every tile its bounding box touches.
 *
 * Setup is shared out too (it is about a sixth of a 1x frame): vertex chunks
 * (each vertex is transformed on its own, by the same ras_vertex_transform on
 * a slice of the mesh), then triangle chunks, each into its own record list;
 * the lists in chunk order are the submission order, so binning sees exactly
 * the sequence a single thread would have produced (fast_frame.c's
 * worker_main hands the chunks out).
 */
#include "fast_priv.h"

#include "stage2_clip.h"  /* ras_clip_triangle_far, ras_clip_vertex_outcode */
#include "stage3_setup.h" /* ras_setup_triangle, ras_viewport */

#include <math.h> /* isfinite */

#define VERTEX_CHUNK 1024
#define TRIANGLE_CHUNK 256

/* ---- one triangle ---------------------------------------------------------- */

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
    if (floor_px(maxx) < 0 || floor_px(minx) >= width || floor_px(maxy) < 0 ||
        floor_px(miny) >= height)
        r->x1 = r->x0 - 1;
    return true;
}

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
static bool setup_triangle(fast_tri_list *L, const ras_clip_vertex *a, const ras_clip_vertex *b,
                           const ras_clip_vertex *c, const unsigned char flags[3],
                           const unsigned char outcode[3], const vec4s *screen[3], int object,
                           int width, int height, double z_far, ras_counters *k) {
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
        cr = ras_clip_triangle_far(a, b, c, z_far, poly, &n);
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
            for (int v = 0; v < 3; v++)
                pos[v] = screen[v];
            set = flags[0] & flags[1] & flags[2] & SCREEN_FINITE;
        } else {
            set = ras_setup_triangle(&poly[0], &poly[i], &poly[i + 1], width, height, &t);
            in[0] = &poly[0], in[1] = &poly[i], in[2] = &poly[i + 1];
            for (int v = 0; v < 3; v++)
                pos[v] = &t.v[v];
        }
        if (!set) {
            k->triangles_rejected_nonfinite++;
            continue;
        }
        for (int v = 0; v < 3; v++)
            r->v[v] = *pos[v];
        /* The rasterizer's range (stage4_raster.h), tested where and as the
         * teaching pipeline tests it (ras_raster_check_range, before the
         * rasterize hook): a triangle beyond it is refused and counted by
         * both, never skipped by one and drawn by the other. The guard band
         * (stage2_clip.h) keeps every corner within 4.5 frames, so no fast_frame
         * the pipeline makes reaches it; the fixed-point arithmetic below
         * holds to FIXED_LIMIT_PX, further still. */
        ras_triangle rt;
        for (int v = 0; v < 3; v++)
            rt.v[v] = r->v[v];
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

/* ---- in chunks ------------------------------------------------------------- */

void fast_setup_vertices(fast_frame *fr, int c) {
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
    ras_vertex_transform(&part, fr->models[o], fr->view, fr->projection, fr->setup->varyings,
                         fr->clip + first);
    for (size_t v = first; v < first + part.vertex_count; v++) {
        fr->screen[v] = ras_viewport(fr->clip[v].p_clip, fr->width, fr->height);
        fr->voutcode[v] =
            (unsigned char)ras_clip_vertex_outcode(&fr->clip[v], fr->scene->camera.z_far);
        fr->vflags[v] = (unsigned char)((clip_vertex_finite(&fr->clip[v]) ? VERTEX_FINITE : 0) |
                                        (ras_vec4_finite(fr->screen[v]) ? SCREEN_FINITE : 0));
    }
}

void fast_setup_triangles(fast_worker *w, int c) {
    fast_frame *fr = w->fr;
    size_t g = (size_t)c * TRIANGLE_CHUNK, end = g + TRIANGLE_CHUNK;
    if (end > fr->tri_first[fr->scene->object_count]) end = fr->tri_first[fr->scene->object_count];
    fast_tri_list *L = &fr->lists[c];
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
        const unsigned char outcode[3] = {fr->voutcode[base + idx[0]], fr->voutcode[base + idx[1]],
                                          fr->voutcode[base + idx[2]]};
        const vec4s *screen[3] = {&fr->screen[base + idx[0]], &fr->screen[base + idx[1]],
                                  &fr->screen[base + idx[2]]};
        if (!setup_triangle(L, &clip[idx[0]], &clip[idx[1]], &clip[idx[2]], flags, outcode, screen,
                            o, fr->width, fr->height, fr->scene->camera.z_far, &w->ks)) {
            atomic_store(&fr->failed, true);
            return;
        }
    }
}

/* fast_priv.h */
void fast_setup_bin(fast_frame *fr) {
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

/* The setup plan that worker_main runs: where each object's vertices and
 * triangles start, the vertex chunks, and a record list per triangle chunk;
 * the arrays setup fills. The vertex stage is counted here (every vertex is
 * transformed). False: out of memory (what was allocated is freed by
 * free_frame). */
bool fast_setup_plan(fast_frame *fr, ras_counters *k) {
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
