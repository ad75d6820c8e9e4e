/* bench_float_edges.c — the float-edge rasterizer of bench_float_edges.h.
 * RASTER101-SOLUTION: a working rasterizer; never in a student handout.
 *
 * The float path the reference carried until its coverage became one exact
 * fixed-point path (hw2_rasterize/solution/rasterizer.c), kept here operation
 * for operation so the benchmark's crack and double-hit counts and the fan
 * figure stay what they were: the triangle made counter-clockwise, each edge
 * function evaluated in float with its start vertex subtracted first,
 * covered when all three are >= 0.
 */
#include "bench_float_edges.h"

#include <math.h>   /* floorf, fminf, fmaxf, isfinite */
#include <stdint.h> /* uint64_t */

void bench_rasterize_float_edges(const ras_triangle *t, const ras_raster_ctx *ctx) {
    ras_framebuffer *fb = ctx->fb;
    const ras_sample_pattern *pat = &ctx->pattern;
    const vec4s *v = t->v;
    for (int i = 0; i < 3; i++)
        if (!ras_vec4_finite(v[i])) return;
    float area2 = ras_triangle_area2(t);
    if (!(area2 != 0) || !isfinite(area2)) {
        if (ctx->counters) ras_count(&ctx->counters->triangles_degenerate, 1);
        return;
    }
    /* Corner k of the counter-clockwise order is original vertex order[k]. */
    int order[3] = {0, area2 > 0 ? 1 : 2, area2 > 0 ? 2 : 1};
    float area = area2 > 0 ? area2 : -area2, vx[3], vy[3];
    for (int k = 0; k < 3; k++) {
        vx[k] = v[order[k]].x;
        vy[k] = v[order[k]].y;
    }
    float minx = fminf(fminf(v[0].x, v[1].x), v[2].x), maxx = fmaxf(fmaxf(v[0].x, v[1].x), v[2].x);
    float miny = fminf(fminf(v[0].y, v[1].y), v[2].y), maxy = fmaxf(fmaxf(v[0].y, v[1].y), v[2].y);
    float w = (float)fb->width, h = (float)fb->height;
    if (maxx < 0 || minx >= w || maxy < 0 || miny >= h) return; /* wholly off one side */
    int x0 = (int)floorf(fminf(fmaxf(minx, 0), w - 1));
    int x1 = (int)floorf(fminf(fmaxf(maxx, 0), w - 1));
    int y0 = (int)floorf(fminf(fmaxf(miny, 0), h - 1));
    int y1 = (int)floorf(fminf(fmaxf(maxy, 0), h - 1));

    ras_shade_fn shade = ctx->shade ? ctx->shade : ras_shade_vertex_color;
    uint64_t tested = 0, covered = 0, passed = 0, shaded = 0;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            for (int k = 0; k < pat->count; k++) {
                tested++;
                float px = (float)x + pat->offsets[k].x, py = (float)y + pat->offsets[k].y;
                float e[3];
                bool in = true;
                for (int i = 0; i < 3 && in; i++) {
                    int a = (i + 1) % 3, b = (i + 2) % 3; /* the edge opposite corner i */
                    e[i] = (vx[b] - vx[a]) * (py - vy[a]) - (vy[b] - vy[a]) * (px - vx[a]);
                    in = e[i] >= 0;
                }
                if (!in) continue;
                covered++;
                float l[3];
                for (int i = 0; i < 3; i++) l[order[i]] = e[i] / area;
                ras_fragment f = {.x = x, .y = y, .p = {{px, py}}, .bary = {{l[0], l[1], l[2]}}};
                f.depth = l[0] * v[0].z + l[1] * v[1].z + l[2] * v[2].z;
                int i = ras_fb_sample_index(fb, x, y, k);
                if (!(f.depth < fb->depth[i])) continue;
                passed++;
                fb->depth[i] = f.depth;
                fb->color[i] = shade(t, &f, ctx->shade_user);
                shaded++;
            }
    if (ctx->counters) {
        ras_count(&ctx->counters->samples_tested, tested);
        ras_count(&ctx->counters->samples_covered, covered);
        ras_count(&ctx->counters->depth_tests_passed, passed);
        ras_count(&ctx->counters->fragments_shaded, shaded);
    }
}
