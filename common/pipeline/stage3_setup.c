/* stage3_setup.c — see stage3_setup.h. */
#include "stage3_setup.h"

#include <math.h> /* round, fabs, isfinite */

vec4s ras_viewport_depth(vec4s p_clip, int width, int height, ras_depth_format format,
                         float z_near) {
    float inv_w = 1.0f / p_clip.w;
    float depth;
    if (format == RAS_DEPTH_INV_W) {
        /* One correctly rounded division straight from w (not z_near * inv_w,
         * which would round twice). Clamped to [−1, 0] for the same reason as
         * below: a vertex the clipper cut at the near plane can land a
         * rounding error nearer than z_near. */
        depth = -z_near / p_clip.w;
        if (depth < -1.0f) depth = -1.0f;
        if (depth > 0.0f) depth = 0.0f;
    } else {
        /* Clamped to [0, 1] like D3D's viewport depth: a vertex the clipper cut
         * where w is tiny can land a little outside -w <= z <= w (its z and w
         * round separately; tests/fuzz found depth -8.8e-5). */
        depth = (1.0f - p_clip.z * inv_w) * 0.5f;
        if (depth < 0.0f) depth = 0.0f;
        if (depth > 1.0f) depth = 1.0f;
    }
    /* NaN passes through both clamps (fmaxf/fminf would hide it), so setup
     * still rejects it. */
    return (vec4s){{(p_clip.x * inv_w + 1.0f) * 0.5f * (float)width,
                    (p_clip.y * inv_w + 1.0f) * 0.5f * (float)height, depth, p_clip.w}};
}

vec4s ras_viewport(vec4s p_clip, int width, int height) {
    return ras_viewport_depth(p_clip, width, height, RAS_DEPTH_Z01, 0.0f);
}

/* x or y as the rasterizer snaps it: to the nearest 1/RAS_SUBPIXEL_ONE px,
 * half away from zero (the reference rasterizer's snap, stage4_raster.h). */
static double snapped(float v) { return round((double)v * RAS_SUBPIXEL_ONE) / RAS_SUBPIXEL_ONE; }

/* RAS_DEPTH_INV_W: the snap carried into depth. The rasterizer computes
 * coverage AND the barycentrics it interpolates depth with on the snapped
 * corners; with each corner's depth taken at its unsnapped position, the
 * depth plane it interpolates is tilted by up to 1/512 px of slope per
 * corner, differently for two triangles of one surface or of two parallel
 * ones, and that costs -near/w its order at relative gaps of 1e-6. So each
 * corner gets the depth of the triangle's own plane — -near/w
 * is affine in screen space — at its snapped position: the plane through the
 * corners in double (from the clip-space values, before any float rounding
 * of the viewport), evaluated at the snapped x and y, rounded once. A
 * triangle so thin that this moves a corner's depth by more than the
 * triangle's own depth range (its plane is not defined by its corners to
 * that precision) keeps the unsnapped depths. */
static void inv_w_at_snapped_corners(const ras_clip_vertex *const in[3], int width, int height,
                                     float z_near, ras_triangle *out) {
    double x[3], y[3], z[3], lo = 0, hi = -1;
    for (int i = 0; i < 3; i++) {
        vec4s p = in[i]->p_clip;
        double w = p.w;
        x[i] = ((double)p.x / w + 1.0) * 0.5 * width;
        y[i] = ((double)p.y / w + 1.0) * 0.5 * height;
        z[i] = -(double)z_near / w;
        lo = i ? fmin(lo, z[i]) : z[i];
        hi = i ? fmax(hi, z[i]) : z[i];
    }
    double ax = x[1] - x[0], ay = y[1] - y[0], az = z[1] - z[0];
    double bx = x[2] - x[0], by = y[2] - y[0], bz = z[2] - z[0];
    double det = ax * by - ay * bx;
    if (!(det != 0) || !isfinite(det)) return;
    double gx = (az * by - bz * ay) / det, gy = (bz * ax - az * bx) / det;
    float moved[3];
    for (int i = 0; i < 3; i++) {
        double dz = gx * (snapped(out->v[i].x) - x[i]) + gy * (snapped(out->v[i].y) - y[i]);
        if (!isfinite(dz) || fabs(dz) > hi - lo) return;
        double d = z[i] + dz;
        moved[i] = (float)(d < -1 ? -1 : d > 0 ? 0 : d);
    }
    for (int i = 0; i < 3; i++) out->v[i].z = moved[i];
}

bool ras_setup_triangle_depth(const ras_clip_vertex *a, const ras_clip_vertex *b,
                              const ras_clip_vertex *c, int width, int height,
                              ras_depth_format format, float z_near, ras_triangle *out) {
    const ras_clip_vertex *in[3] = {a, b, c};
    for (int i = 0; i < 3; i++) {
        out->v[i] = ras_viewport_depth(in[i]->p_clip, width, height, format, z_near);
        out->color[i] = in[i]->color;
        out->normal[i] = in[i]->normal;
        out->uv[i] = in[i]->uv;
        out->view_pos[i] = in[i]->view_pos;
        if (!ras_vec4_finite(out->v[i]) || !ras_vec3_finite(out->color[i]) ||
            !ras_vec3_finite(out->normal[i]) || !ras_vec2_finite(out->uv[i]) ||
            !ras_vec3_finite(out->view_pos[i]))
            return false;
    }
    if (format == RAS_DEPTH_INV_W) inv_w_at_snapped_corners(in, width, height, z_near, out);
    return true;
}

bool ras_setup_triangle(const ras_clip_vertex *a, const ras_clip_vertex *b,
                        const ras_clip_vertex *c, int width, int height, ras_triangle *out) {
    return ras_setup_triangle_depth(a, b, c, width, height, RAS_DEPTH_Z01, 0.0f, out);
}
