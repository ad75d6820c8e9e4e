/* rasterizer.c — hw2: YOUR implementation of rasterizer.h.
 *
 * Each function returns a placeholder (false, zero, black; rasterize_triangle
 * draws nothing) and prints a one-time notice until you write it. Read
 * docs/hw2.md first; run the tests with `make grade HW=2` or
 * `(cd build && ctest -L hw2)`. Useful helpers: ras_triangle_area2()
 * (ras_triangle.h), ras_fb_sample_index() (ras_framebuffer.h),
 * ras_shade_vertex_color() (stage5_fragment.h), ras_count() (ras_counters.h).
 */
/* When you write a function, DELETE its two notice lines (`static bool shown;`
 * and `ras_todo_notice(...)`): the grader gives no points to a test during
 * which a notice was printed, however right the result. */
#include "rasterizer.h"

#include "ras_todo.h"

#include <math.h> /* floorf, fminf, fmaxf, isfinite */

bool inside_triangle(float x, float y, const ras_triangle *t) {
    static bool shown;
    ras_todo_notice(&shown, "inside_triangle", "docs/hw2.md, section 1 (inside test)");
    /* TODO(hw2) 1. For each directed edge a→b (v0→v1, v1→v2, v2→v0) compute
     *              the edge function E = (b.x-a.x)*(y-a.y) - (b.y-a.y)*(x-a.x):
     *              the 2D cross product, > 0 when (x, y) is left of a→b.
     * TODO(hw2) 2. Inside means all three have the SAME sign as the triangle's
     *              area (ras_triangle_area2): that handles both windings. A
     *              point exactly on an edge or a vertex (E == 0) is inside.
     * TODO(hw2) 3. A zero-area triangle contains nothing: return false first,
     *              or every point on its line would pass (all E are 0 there). */
    (void)x;
    (void)y;
    (void)t;
    return false;
}

bool compute_barycentric_2d(float x, float y, const ras_triangle *t, vec3s *bary) {
    static bool shown;
    ras_todo_notice(&shown, "compute_barycentric_2d", "docs/hw2.md, section 2 (barycentrics)");
    /* TODO(hw2) 1. Set *bary to (0, 0, 0) and compute the area A = area2 of t;
     *              if it is 0 (or not finite) return false — no division.
     * TODO(hw2) 2. α = E_12(x, y) / A, β = E_20(x, y) / A, γ = E_01(x, y) / A:
     *              each is the area of the sub-triangle opposite its vertex
     *              over the whole (the same edge functions as section 1).
     * TODO(hw2) 3. Check: at v0 you get (1, 0, 0); α + β + γ = 1; outside the
     *              triangle one coordinate is negative. Return true. */
    (void)x;
    (void)y;
    (void)t;
    *bary = (vec3s){{0, 0, 0}};
    return false;
}

void rasterize_triangle(const ras_triangle *t, const ras_raster_ctx *ctx) {
    static bool shown;
    ras_todo_notice(&shown, "rasterize_triangle", "docs/hw2.md, section 3 (rasterize)");
    /* TODO(hw2) 1. Bounding box: min/max of the three screen x and y, CLAMPED
     *              to 0..width-1 and 0..height-1 (clamp the floats before
     *              casting to int). A triangle partly off-screen must not
     *              write outside the buffers. Skip NaN vertices.
     * TODO(hw2) 2. Loop over integer pixels (x, y) in the box, and over the
     *              samples s < ctx->pattern.count: the sample sits at
     *              (x + offsets[s].x, y + offsets[s].y). With no AA that is the
     *              pixel CENTRE (x + 0.5, y + 0.5), not the corner (x, y).
     * TODO(hw2) 3. Coverage: inside_triangle(), plus the top-left rule for a
     *              sample exactly on an edge (docs/hw2.md, 3.3): on a shared
     *              edge it must belong to exactly one of the two triangles.
     * TODO(hw2) 4. Barycentrics at THAT SAME sample point; depth
     *              z = α·v0.z + β·v1.z + γ·v2.z.
     * TODO(hw2) 5. Depth test per sample: i = ras_fb_sample_index(fb, x, y, s);
     *              draw only if z < fb->depth[i] (smaller is closer, cleared
     *              to +INFINITY); then store z in fb->depth[i].
     * TODO(hw2) 6. Colour: ctx->shade (or ras_shade_vertex_color when NULL)
     *              with a ras_fragment {x, y, p, bary, depth}. RAS_AA_SSAA:
     *              shade every sample that passed. RAS_AA_NONE / MSAA: shade
     *              ONCE per pixel (at the centre) and store that colour in
     *              every sample that passed — per sample, not per pixel.
     * TODO(hw2) 7. If ctx->counters is not NULL, add to samples_tested,
     *              samples_covered, depth_tests_passed, fragments_shaded. */
    (void)t;
    (void)ctx;
}

vec3s resolve_pixel(const ras_framebuffer *fb, int x, int y) {
    static bool shown;
    ras_todo_notice(&shown, "resolve_pixel", "docs/hw2.md, section 4 (resolve)");
    /* TODO(hw2) 1. Sum the colours of the fb->samples samples of pixel (x, y)
     *              (ras_fb_sample_index(fb, x, y, s)); do not hard-code 4.
     * TODO(hw2) 2. Divide by the sample count IN FLOAT: with ints, 2 / 4 is 0
     *              and every edge pixel turns black. */
    (void)fb;
    (void)x;
    (void)y;
    return (vec3s){{0, 0, 0}};
}
