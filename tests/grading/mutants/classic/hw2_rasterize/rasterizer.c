/* rasterizer.c — hw2, a classic GAMES101-style solution (tests/grading/mutants/classic).
 *
 * Written the way a student of the course writes it, independently of
 * hw2_rasterize/solution/: float edge functions (the handout's form, a vertex
 * subtracted first), the course's loops over the bounding box, the top-left
 * rule in float as docs/hw2.md 3.3 states it. The fairness check of
 * `make mutants` grades it and it must get full marks. Not shipped in the
 * handout.
 * RASTER101-SOLUTION: this marker must never appear in a student handout.
 */
#include "rasterizer.h"

#include <math.h>

/* E_ab(p): > 0 when p is left of a->b (y up). */
static float edge_function(float ax, float ay, float bx, float by, float px, float py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

bool inside_triangle(float x, float y, const ras_triangle *t) {
    const vec4s *v = t->v;
    float area = ras_triangle_area2(t);
    if (area == 0 || !isfinite(area)) return false;

    float e01 = edge_function(v[0].x, v[0].y, v[1].x, v[1].y, x, y);
    float e12 = edge_function(v[1].x, v[1].y, v[2].x, v[2].y, x, y);
    float e20 = edge_function(v[2].x, v[2].y, v[0].x, v[0].y, x, y);

    if (area > 0) return e01 >= 0 && e12 >= 0 && e20 >= 0;
    return e01 <= 0 && e12 <= 0 && e20 <= 0;
}

bool compute_barycentric_2d(float x, float y, const ras_triangle *t, vec3s *bary) {
    const vec4s *v = t->v;
    *bary = (vec3s){{0, 0, 0}};
    float area = ras_triangle_area2(t);
    if (area == 0 || !isfinite(area)) return false;

    float alpha = edge_function(v[1].x, v[1].y, v[2].x, v[2].y, x, y) / area;
    float beta = edge_function(v[2].x, v[2].y, v[0].x, v[0].y, x, y) / area;
    float gamma = edge_function(v[0].x, v[0].y, v[1].x, v[1].y, x, y) / area;
    *bary = (vec3s){{alpha, beta, gamma}};
    return true;
}

/* Top-left rule for edge a->b of a counter-clockwise triangle (y up). */
static bool is_top_left(float ax, float ay, float bx, float by) {
    float dx = bx - ax, dy = by - ay;
    return dy < 0 || (dy == 0 && dx < 0);
}

static bool edge_covers(float e, bool top_left) { return e > 0 || (e == 0 && top_left); }

/* Coverage with the top-left rule: the triangle a, b, c taken counter-clockwise. */
static bool covered(const vec4s *a, const vec4s *b, const vec4s *c, float x, float y) {
    float e0 = edge_function(a->x, a->y, b->x, b->y, x, y);
    float e1 = edge_function(b->x, b->y, c->x, c->y, x, y);
    float e2 = edge_function(c->x, c->y, a->x, a->y, x, y);
    return edge_covers(e0, is_top_left(a->x, a->y, b->x, b->y)) &&
           edge_covers(e1, is_top_left(b->x, b->y, c->x, c->y)) &&
           edge_covers(e2, is_top_left(c->x, c->y, a->x, a->y));
}

static vec3s shade(const ras_triangle *t, const ras_raster_ctx *ctx, int x, int y, float px,
                   float py) {
    ras_fragment frag;
    frag.x = x;
    frag.y = y;
    frag.p = (vec2s){{px, py}};
    compute_barycentric_2d(px, py, t, &frag.bary);
    frag.depth = frag.bary.x * t->v[0].z + frag.bary.y * t->v[1].z + frag.bary.z * t->v[2].z;
    if (ctx->counters) ctx->counters->fragments_shaded++;
    if (ctx->shade) return ctx->shade(t, &frag, ctx->shade_user);
    return ras_shade_vertex_color(t, &frag, NULL);
}

void rasterize_triangle(const ras_triangle *t, const ras_raster_ctx *ctx) {
    ras_framebuffer *fb = ctx->fb;
    const vec4s *v = t->v;
    for (int i = 0; i < 3; i++)
        if (!isfinite(v[i].x) || !isfinite(v[i].y) || !isfinite(v[i].z)) return;
    float area = ras_triangle_area2(t);
    if (area == 0 || !isfinite(area)) return;

    /* counter-clockwise order for the top-left rule */
    const vec4s *a = &v[0], *b = &v[1], *c = &v[2];
    if (area < 0) {
        b = &v[2];
        c = &v[1];
    }

    /* bounding box, clamped to the screen before converting to int */
    float min_x = fminf(v[0].x, fminf(v[1].x, v[2].x));
    float max_x = fmaxf(v[0].x, fmaxf(v[1].x, v[2].x));
    float min_y = fminf(v[0].y, fminf(v[1].y, v[2].y));
    float max_y = fmaxf(v[0].y, fmaxf(v[1].y, v[2].y));
    float w1 = (float)(fb->width - 1), h1 = (float)(fb->height - 1);
    min_x = fminf(fmaxf(min_x, 0.0f), w1);
    max_x = fminf(fmaxf(max_x, 0.0f), w1);
    min_y = fminf(fmaxf(min_y, 0.0f), h1);
    max_y = fminf(fmaxf(max_y, 0.0f), h1);
    int x_min = (int)floorf(min_x), x_max = (int)floorf(max_x);
    int y_min = (int)floorf(min_y), y_max = (int)floorf(max_y);

    int n = ctx->pattern.count;
    for (int x = x_min; x <= x_max; x++) {
        for (int y = y_min; y <= y_max; y++) {
            bool passed[RAS_MAX_SAMPLES];
            bool any = false;
            for (int s = 0; s < n; s++) {
                passed[s] = false;
                float sx = x + ctx->pattern.offsets[s].x;
                float sy = y + ctx->pattern.offsets[s].y;
                if (ctx->counters) ctx->counters->samples_tested++;
                if (!covered(a, b, c, sx, sy)) continue;
                if (ctx->counters) ctx->counters->samples_covered++;

                vec3s bary;
                compute_barycentric_2d(sx, sy, t, &bary);
                float z = bary.x * v[0].z + bary.y * v[1].z + bary.z * v[2].z;
                int idx = ras_fb_sample_index(fb, x, y, s);
                if (z < fb->depth[idx]) {
                    fb->depth[idx] = z;
                    passed[s] = true;
                    any = true;
                    if (ctx->counters) ctx->counters->depth_tests_passed++;
                    if (ctx->aa == RAS_AA_SSAA) fb->color[idx] = shade(t, ctx, x, y, sx, sy);
                }
            }
            if (!any || ctx->aa == RAS_AA_SSAA) continue;
            /* no AA and MSAA: shade once per pixel, at its centre */
            vec3s color = shade(t, ctx, x, y, x + 0.5f, y + 0.5f);
            for (int s = 0; s < n; s++)
                if (passed[s]) fb->color[ras_fb_sample_index(fb, x, y, s)] = color;
        }
    }
}

vec3s resolve_pixel(const ras_framebuffer *fb, int x, int y) {
    vec3s sum = {{0, 0, 0}};
    for (int s = 0; s < fb->samples; s++) {
        vec3s c = fb->color[ras_fb_sample_index(fb, x, y, s)];
        sum.x += c.x;
        sum.y += c.y;
        sum.z += c.z;
    }
    float n = (float)fb->samples;
    return (vec3s){{sum.x / n, sum.y / n, sum.z / n}};
}
