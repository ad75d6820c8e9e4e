/* solution/rasterizer.c — hw2 reference implementation of rasterizer.h.
 * RASTER101-SOLUTION: this marker must never appear in a student handout.
 *
 * rasterize_triangle has the shape its TODOs give the student: the bounding
 * box, then for each sample inside_triangle, compute_barycentric_2d at the
 * same point, the top-left rule for a sample exactly on an edge, the depth
 * test, the shading. One step comes before the loop and makes that shape
 * exact: the triangle's x and y are snapped to 1/256 px (8 sub-pixel bits,
 * as D3D and llvmpipe), the grid every sample position lies on. With every
 * coordinate a whole number of 1/256 px, the double edge functions of
 * inside_triangle and compute_barycentric_2d come out as exact integers of
 * 1/65536 px² — fixed-point arithmetic that the double unit does without
 * rounding — so "E == 0, exactly on the edge" is a fact, and the top-left
 * rule can give each sample of a shared edge to exactly one triangle.
 *
 * Notes:
 *   - every sample pattern we ship (1/16-pixel standard positions, ordered
 *     grids up to 8x8) lies on the 1/256-pixel grid, so snapping the offsets
 *     moves nothing;
 *   - MSAA shades once per pixel per triangle at the pixel centre when the
 *     triangle covers the centre; otherwise at the covered, visible sample
 *     nearest the centre (a cheap "centroid" rule: the shading point is always
 *     inside the triangle, so attributes are never extrapolated — textures
 *     read no texels outside the triangle's UV range along its silhouette);
 *   - depth is interpolated with screen-space barycentrics (z/w is affine in
 *     screen space), tested per sample with "less than" against a buffer
 *     cleared to +INFINITY.
 * See docs/hw2.md for the maths.
 */
#include "rasterizer.h"

#include <assert.h> /* assert */
#include <math.h>   /* floorf, fminf, fmaxf, isfinite, round */
#include <stdint.h> /* uint64_t */

/* ---- the two tests the handout asks for ---------------------------------- */

/* Twice the signed area of (a, b, p): > 0 when p lies left of the directed
 * edge a→b (y up). Evaluated in double: products of floats are exact there,
 * so only the final rounding remains — and on the snapped coordinates that
 * rasterize_triangle passes, not even that (see "the fixed-point step"). */
static double edge_d(double ax, double ay, double bx, double by, double px, double py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

/* `inline` on these two definitions (still the external ones the header
 * declares) lets the compiler fold them into rasterize_triangle's sample loop,
 * where the area they start with is the same for every sample and is worked
 * out once: calling them per sample then costs no more than the hand-made
 * per-triangle setup the reference had before (callgrind, hw3_shading_ref
 * --shader phong: rasterize_triangle with the shading it calls 466 M
 * instructions then, 454 M now; without `inline`, about 575 M). */
inline bool inside_triangle(float x, float y, const ras_triangle *t) {
    const vec4s *v = t->v;
    double area2 = edge_d(v[0].x, v[0].y, v[1].x, v[1].y, v[2].x, v[2].y);
    /* A zero-area triangle would otherwise "contain" every point of its line:
     * all three edge functions are 0 there. NaN fails `!= 0` too. */
    if (!(area2 != 0) || !isfinite(area2)) return false;
    double e0 = edge_d(v[1].x, v[1].y, v[2].x, v[2].y, x, y);
    double e1 = edge_d(v[2].x, v[2].y, v[0].x, v[0].y, x, y);
    double e2 = edge_d(v[0].x, v[0].y, v[1].x, v[1].y, x, y);
    /* Either winding: inside means all three on the same side as the area. */
    if (area2 < 0) {
        e0 = -e0;
        e1 = -e1;
        e2 = -e2;
    }
    return e0 >= 0 && e1 >= 0 && e2 >= 0;
}

inline bool compute_barycentric_2d(float x, float y, const ras_triangle *t, vec3s *bary) {
    const vec4s *v = t->v;
    *bary = (vec3s){{0, 0, 0}};
    double area2 = edge_d(v[0].x, v[0].y, v[1].x, v[1].y, v[2].x, v[2].y);
    if (!(area2 != 0) || !isfinite(area2)) return false;
    /* Each coordinate is the area of the sub-triangle opposite its vertex,
     * over the whole: the sign carries "outside" for free. */
    double a = edge_d(v[1].x, v[1].y, v[2].x, v[2].y, x, y) / area2;
    double b = edge_d(v[2].x, v[2].y, v[0].x, v[0].y, x, y) / area2;
    double c = edge_d(v[0].x, v[0].y, v[1].x, v[1].y, x, y) / area2;
    *bary = (vec3s){{(float)a, (float)b, (float)c}};
    return true;
}

/* ---- the fixed-point step ------------------------------------------------ */

#define SUBPIXEL_ONE 256.0 /* grid steps per pixel */

/* v rounded to the nearest 1/256 px (half away from zero). Exact in float:
 * below 2^15 px it is a whole number of 1/256 below 2^23, and from 2^15 px on
 * a float is already a multiple of 1/256, so round() gives v back.
 *
 * Why exactness holds after this: within ±2^17 px a difference of two snapped
 * coordinates (or of a snapped vertex and a sample) is a multiple of 2^-8
 * below 2^18 — 26 significant bits, exact in double; the edge function's two
 * products are multiples of 2^-16 below 2^36 (52 bits) and their difference
 * stays below 2^53 units of 2^-16: no rounding anywhere. The pipeline clips
 * to a guard band of 8 viewports (at most 4.5 frames of RAS_IMAGE_MAX_SIDE =
 * 16384 px from the origin, < 2^17 px), so every triangle it draws is in
 * that range. A direct
 * caller who passes larger coordinates gets the same code with double
 * rounding: right away from the edges, not promised exactly-once on them.
 * (Evaluating each shared edge from the same end in both triangles would
 * promise it at any size, but that choice, made per sample, cost a third more
 * instructions in rasterize_triangle for coordinates no frame has.) */
static float snap(float v) { return (float)(round((double)v * SUBPIXEL_ONE) / SUBPIXEL_ONE); }

/* What the loop needs of one triangle, worked out once. */
typedef struct setup {
    ras_triangle g; /* t with x and y snapped: for coverage and barycentrics only */
    /* The D3D top-left rule, per edge opposite vertex i (v[i+1] → v[i+2]). */
    bool top_left[3];
    int x0, x1, y0, y1;             /* pixel bounding box on screen, inclusive both ends */
    vec2s off[RAS_MAX_SAMPLES + 1]; /* snapped sample offsets, then the centre */
    int centre_sample;              /* the first sample at off[centre] (no AA: the one), or -1 */
} setup;

/* False for a triangle that snapped to a line or a point (it covers nothing),
 * or whose area is not finite. */
static bool setup_triangle(setup *s, const ras_triangle *t, const ras_sample_pattern *pat,
                           const ras_framebuffer *fb) {
    s->g = *t;
    for (int i = 0; i < 3; i++) {
        s->g.v[i].x = snap(t->v[i].x);
        s->g.v[i].y = snap(t->v[i].y);
    }
    const vec4s *v = s->g.v;
    double area2 = edge_d(v[0].x, v[0].y, v[1].x, v[1].y, v[2].x, v[2].y);
    if (!(area2 != 0) || !isfinite(area2)) return false;
    for (int i = 0; i < 3; i++) {
        /* Walk the edge counter-clockwise (interior on the left, y up): then a
         * left edge goes down (dy < 0), and a top edge is horizontal with the
         * interior below, i.e. it runs towards -x. */
        vec4s a = v[(i + 1) % 3], b = v[(i + 2) % 3];
        double dx = (double)b.x - a.x, dy = (double)b.y - a.y;
        if (area2 < 0) dx = -dx, dy = -dy;
        s->top_left[i] = dy < 0 || (dy == 0 && dx < 0);
    }
    for (int k = 0; k <= pat->count; k++) {
        vec2s o = k < pat->count ? pat->offsets[k] : (vec2s){{0.5f, 0.5f}};
        s->off[k] = (vec2s){{snap(o.x), snap(o.y)}};
    }
    vec2s centre = s->off[pat->count];
    s->centre_sample = -1;
    for (int k = pat->count - 1; k >= 0; k--)
        if (s->off[k].x == centre.x && s->off[k].y == centre.y) s->centre_sample = k;
    float minx = fminf(fminf(v[0].x, v[1].x), v[2].x), maxx = fmaxf(fmaxf(v[0].x, v[1].x), v[2].x);
    float miny = fminf(fminf(v[0].y, v[1].y), v[2].y), maxy = fmaxf(fmaxf(v[0].y, v[1].y), v[2].y);
    /* A pixel's samples lie in [x, x+1), so pixel floor(min) is the first that
     * can hold a covered sample and floor(max) the last. Clamp in float BEFORE
     * converting: (int)1e30f is undefined behaviour. */
    float w = (float)fb->width, h = (float)fb->height;
    s->x0 = (int)floorf(fminf(fmaxf(minx, 0), w - 1));
    s->x1 = (int)floorf(fminf(fmaxf(maxx, 0), w - 1));
    s->y0 = (int)floorf(fminf(fmaxf(miny, 0), h - 1));
    s->y1 = (int)floorf(fminf(fmaxf(maxy, 0), h - 1));
    if (maxx < 0 || minx >= w || maxy < 0 || miny >= h) s->x1 = s->x0 - 1; /* wholly off one side */
    return true;
}

/* The top-left rule, after inside_triangle said yes: a sample whose
 * barycentric coordinate i is exactly 0 lies on the edge opposite vertex i
 * (bary_i = E_i / area, and E_i is exact), and belongs to this triangle only
 * if that edge is top-left — the neighbour across it then does not take it. */
static bool on_edge_not_ours(const setup *s, vec3s bary) {
    return (bary.x == 0 && !s->top_left[0]) || (bary.y == 0 && !s->top_left[1]) ||
           (bary.z == 0 && !s->top_left[2]);
}

static float depth_at(const ras_triangle *t, vec3s bary) {
    return bary.x * t->v[0].z + bary.y * t->v[1].z + bary.z * t->v[2].z;
}

/* ---- the triangle -------------------------------------------------------- */

/* NONE / MSAA: where the pixel's one fragment is shaded — the centre when the
 * triangle covers it (the same test as a sample), otherwise the covered,
 * visible sample nearest the centre. */
static void shading_point(const setup *s, const ras_sample_pattern *pat, int x, int y,
                          uint64_t visible, const vec3s *bary, ras_fragment *f) {
    int n = pat->count;
    float cx = (float)x + s->off[n].x, cy = (float)y + s->off[n].y;
    /* A visible sample AT the centre (no AA: the one sample) already passed
     * the centre's test, and its barycentrics are the centre's: the same
     * functions at the same point, not worked out twice. */
    int c = s->centre_sample;
    bool centre_visible = c >= 0 && (visible >> c & 1);
    if (centre_visible) f->bary = bary[c];
    if (centre_visible ||
        (inside_triangle(cx, cy, &s->g) && compute_barycentric_2d(cx, cy, &s->g, &f->bary) &&
         !on_edge_not_ours(s, f->bary))) {
        f->p = (vec2s){{(float)x + 0.5f, (float)y + 0.5f}};
        return;
    }
    int best = -1;
    float best_d2 = 0;
    for (int k = 0; k < n; k++) {
        if (!(visible >> k & 1)) continue;
        float dx = pat->offsets[k].x - 0.5f, dy = pat->offsets[k].y - 0.5f;
        float d2 = dx * dx + dy * dy;
        if (best < 0 || d2 < best_d2) {
            best = k;
            best_d2 = d2;
        }
    }
    f->bary = bary[best];
    f->p = (vec2s){{(float)x + pat->offsets[best].x, (float)y + pat->offsets[best].y}};
}

/* What the box loop counts, for ras_counters. */
typedef struct box_counts {
    uint64_t tested, covered, passed, shaded;
} box_counts;

/* Steps 2–6 for every pixel of the box, with n samples a pixel.
 * always_inline: called twice, it would otherwise stay a function, and
 * through the pointer s every store to the depth buffer (a float) might
 * change the snapped triangle (floats too), so nothing could be hoisted. */
__attribute__((always_inline)) static inline void
draw_box(const setup *s, const ras_triangle *t, const ras_raster_ctx *ctx, int n, box_counts *c) {
    ras_framebuffer *fb = ctx->fb;
    const ras_sample_pattern *pat = &ctx->pattern;
    ras_shade_fn shade = ctx->shade ? ctx->shade : ras_shade_vertex_color;
    bool per_sample_shading = ctx->aa == RAS_AA_SSAA;
    uint64_t tested = 0, covered = 0, passed = 0, shaded = 0;

    /* 2. Every sample of every pixel in the box. */
    for (int y = s->y0; y <= s->y1; y++) {
        for (int x = s->x0; x <= s->x1; x++) {
            int base = ras_fb_sample_index(fb, x, y, 0);
            vec3s bary[RAS_MAX_SAMPLES];
            float z[RAS_MAX_SAMPLES];
            uint64_t visible = 0; /* bit k: sample k covered and nearer */
            for (int k = 0; k < n; k++) {
                tested++;
                float px = (float)x + s->off[k].x, py = (float)y + s->off[k].y;
                /* 3. Coverage, on the snapped triangle: exact (see the top). */
                if (!inside_triangle(px, py, &s->g)) continue;
                /* 4. Barycentrics at the same point; they also say whether
                 * the sample lies exactly on an edge, for the top-left rule.
                 * Depth and colour come from the unsnapped triangle t. */
                compute_barycentric_2d(px, py, &s->g, &bary[k]);
                if (on_edge_not_ours(s, bary[k])) continue;
                covered++;
                /* 5. The depth test, per sample. */
                z[k] = depth_at(t, bary[k]);
                if (!(z[k] < fb->depth[base + k])) continue;
                passed++;
                fb->depth[base + k] = z[k];
                visible |= (uint64_t)1 << k;
            }
            if (!visible) continue;
            /* 6. Colour. */
            ras_fragment f = {.x = x, .y = y};
            if (per_sample_shading) {
                /* SSAA: every visible sample is its own fragment. */
                for (int k = 0; k < n; k++) {
                    if (!(visible >> k & 1)) continue;
                    f.p = (vec2s){{(float)x + pat->offsets[k].x, (float)y + pat->offsets[k].y}};
                    f.bary = bary[k];
                    f.depth = z[k];
                    fb->color[base + k] = shade(t, &f, ctx->shade_user);
                    shaded++;
                }
                continue;
            }
            /* NONE / MSAA: one fragment for the pixel, its colour copied to
             * every visible sample — that per-sample copy is what lets the
             * resolve mix two triangles sharing the pixel without a seam. */
            shading_point(s, pat, x, y, visible, bary, &f);
            f.depth = depth_at(t, f.bary);
            vec3s color = shade(t, &f, ctx->shade_user);
            shaded++;
            for (int k = 0; k < n; k++)
                if (visible >> k & 1) fb->color[base + k] = color;
        }
    }
    *c = (box_counts){tested, covered, passed, shaded};
}

void rasterize_triangle(const ras_triangle *t, const ras_raster_ctx *ctx) {
    const ras_sample_pattern *pat = &ctx->pattern;
    assert(pat->count == ctx->fb->samples && pat->count <= RAS_MAX_SAMPLES);
    for (int i = 0; i < 3; i++)
        if (!ras_vec4_finite(t->v[i])) return; /* NaN would pass no test; be explicit */

    /* 1. Snap, the bounding box, the edges' top-left flags. */
    setup s;
    if (!setup_triangle(&s, t, pat, ctx->fb)) {
        if (ctx->counters) ras_count(&ctx->counters->triangles_degenerate, 1);
        return;
    }
    /* 2.–6. The box. The same loop twice: with the sample count a constant
     * 1 (no AA, the common frame) the compiler drops the sample loop and
     * keeps the triangle's edges in registers across the row, which saves
     * about a third of the rasterizer's instructions. */
    box_counts c;
    if (pat->count == 1)
        draw_box(&s, t, ctx, 1, &c);
    else
        draw_box(&s, t, ctx, pat->count, &c);
    /* 7. The counters. */
    if (ctx->counters) {
        ras_count(&ctx->counters->samples_tested, c.tested);
        ras_count(&ctx->counters->samples_covered, c.covered);
        ras_count(&ctx->counters->depth_tests_passed, c.passed);
        ras_count(&ctx->counters->fragments_shaded, c.shaded);
    }
}

vec3s resolve_pixel(const ras_framebuffer *fb, int x, int y) {
    /* Box filter: every sample weighs 1/samples. Sum in float and divide by a
     * float count — `covered / 4` in integers is 0 for any partial pixel. */
    const vec3s *c = &fb->color[ras_fb_sample_index(fb, x, y, 0)];
    vec3s sum = {{0, 0, 0}};
    for (int s = 0; s < fb->samples; s++) sum = glms_vec3_add(sum, c[s]);
    return glms_vec3_scale(sum, 1.0f / (float)fb->samples);
}
