/* bench_accuracy_order.c — section 5b of the accuracy report: whether
 * inverse_w keeps two parallel planes in order at every distance, tilt and
 * relative gap, before and after issue #27's setup change, against the bound
 * of the exact depths of the float input. bench_accuracy.h.
 */
#include "bench_accuracy.h"
#include "rasterizer.h"   /* hw2 reference: rasterize_triangle, resolve_pixel */
#include "stage2_clip.h"  /* ras_clip_triangle */
#include "stage3_setup.h" /* ras_viewport_depth */
#include "transform.h"    /* hw1 reference: get_projection_matrix */

#include <math.h> /* tan, cos, sin, fmin, fmax, INFINITY, NAN */

/* ---- section 5b: inverse_w's order at every distance and tilt -------------------- */

/* Two parallel planes z = -D - y·tan(tilt) in view space (the eye at the
 * origin, fov ACC_FOV_DEG, near ORDER_NEAR, far ORDER_FAR), the second one a
 * relative gap farther (D = d·(1 + gap)) and drawn first, in inverse_w,
 * 64x64 (--quick) or 128x128 pixels.
 * "Before" builds each clipped triangle's depth the way setup did until
 * issue #27 (-near/w of each unsnapped corner: ras_viewport_depth) and
 * hands it to the pipeline's stage 4; "after" is the pipeline as it is
 * (stage3_setup.c carries the rasterizer's snap into depth). The bound is
 * the exact depth, at the sample, of each quad as the pipeline is given it
 * (its float clip-space corners, solved in double), rounded once to float:
 * what no arithmetic after the vertex stage can beat. The two quads are
 * turned differently about the view axis, as two meshes would be: their
 * corners snap differently. Counted: samples both quads cover where the
 * farther wins. */
const double ORDER_DIST[ORDER_D] = {1, 10, 100, 1000};
const double ORDER_TILT[ORDER_T] = {0, 30, 45, 60, 75, 85};
const double ORDER_GAP[ORDER_G] = {1e-7, 1.4e-7, 3e-7, 1e-6, 4e-6};
#define ORDER_NEAR 0.1
#define ORDER_FAR 1e6
static double order_frac[ORDER_KINDS][ORDER_G][ORDER_D][ORDER_T];

double order_fraction(int kind, int gi, int di, int ti) { return order_frac[kind][gi][di][ti]; }

typedef struct order_plane {
    ras_clip_vertex v[4]; /* a quad, drawn as (0,1,2) and (0,2,3) */
} order_plane;

/* The quad of plane z = -D - y·tan(tilt): a square in (x, y), turned by
 * `turn` degrees about the view axis (so that two planes' corners, and
 * their snapping, differ as two meshes' would), large enough to cover the
 * frame up to 4 D ahead (farther, the float corners of a steep plane would
 * no longer describe it to a 1e-7 of its distance). */
static order_plane order_make_plane(mat4s mvp, double D, double tilt_deg, double turn_deg,
                                    vec3s color) {
    double t = tan(ACC_FOV_DEG * RAS_PI / 360.0), tn = tan(tilt_deg * RAS_PI / 180.0);
    double s_top = t * tn < 0.95 ? fmin(D / (1 - t * tn), 4 * D) : 4 * D;
    double y_lo = -t * D / (1 + t * tn), y_hi = tn > 0 ? (s_top - D) / tn : t * D;
    double cx = 0, cy = (y_lo + y_hi) / 2;
    double half = 1.6 * fmax(t * s_top, (y_hi - y_lo) / 2);
    double c = cos(turn_deg * RAS_PI / 180.0), sn = sin(turn_deg * RAS_PI / 180.0);
    const double sq[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    order_plane q;
    for (int i = 0; i < 4; i++) {
        double u = sq[i][0] * half, v = sq[i][1] * half;
        double x = cx + c * u - sn * v, y = cy + sn * u + c * v, z = -D - y * tn;
        vec4s p = {{(float)x, (float)y, (float)z, 1.0f}};
        q.v[i] = (ras_clip_vertex){
            .p_clip = glms_mat4_mulv(mvp, p), .color = color, .normal = {{0, 0, 1}}};
    }
    return q;
}

/* w of the point of clip-space triangle (a, b, c) that projects to NDC
 * (xn, yn), exactly (a 3x3 solve in double on the float corners); 0 when the
 * point is outside the triangle. */
static double order_clip_hit(vec4s a, vec4s b, vec4s c, double xn, double yn) {
    /* λa + μb + νc with λ + μ + ν = 1: x - xn·w = 0 and y - yn·w = 0 */
    const vec4s v[3] = {a, b, c};
    double r0[3], r1[3];
    for (int i = 0; i < 3; i++) {
        r0[i] = (double)v[i].x - xn * v[i].w;
        r1[i] = (double)v[i].y - yn * v[i].w;
    }
    /* rows: r0·λ = 0, r1·λ = 0, (1,1,1)·λ = 1 → λ ∝ r0 × r1 */
    double l[3] = {r0[1] * r1[2] - r0[2] * r1[1], r0[2] * r1[0] - r0[0] * r1[2],
                   r0[0] * r1[1] - r0[1] * r1[0]};
    double sum = l[0] + l[1] + l[2];
    if (sum == 0) return 0;
    for (int i = 0; i < 3; i++) {
        l[i] /= sum;
        if (l[i] < 0) return 0;
    }
    return l[0] * v[0].w + l[1] * v[1].w + l[2] * v[2].w;
}

/* Stage 2 + the old stage 3 (per-corner -near/w) + the pipeline's stage 4. */
static void order_draw_before(ras_pipeline *p, const ras_clip_vertex *a, const ras_clip_vertex *b,
                              const ras_clip_vertex *c) {
    ras_clip_vertex poly[RAS_CLIP_MAX_VERTICES];
    int n = 0;
    if (ras_clip_triangle(a, b, c, poly, &n) == RAS_CLIP_OUTSIDE) return;
    for (int i = 1; i + 1 < n; i++) {
        const ras_clip_vertex *in[3] = {&poly[0], &poly[i], &poly[i + 1]};
        ras_triangle t = {0};
        for (int k = 0; k < 3; k++) {
            t.v[k] = ras_viewport_depth(in[k]->p_clip, p->fb->width, p->fb->height, RAS_DEPTH_INV_W,
                                        (float)ORDER_NEAR);
            t.color[k] = in[k]->color;
        }
        ras_pipeline_draw_screen_triangle(p, &t);
    }
}

static void order_draw(ras_pipeline *p, const order_plane *q, bool before) {
    const ras_clip_vertex *v = q->v;
    if (before) {
        order_draw_before(p, &v[0], &v[1], &v[2]);
        order_draw_before(p, &v[0], &v[2], &v[3]);
    } else {
        ras_pipeline_draw_clip_triangle(p, &v[0], &v[1], &v[2]);
        ras_pipeline_draw_clip_triangle(p, &v[0], &v[2], &v[3]);
    }
}

static ras_pipeline *order_pipeline(int size) {
    ras_pipeline_config cfg = {.width = size,
                               .height = size,
                               .rasterize = rasterize_triangle,
                               .resolve = resolve_pixel,
                               .depth = RAS_DEPTH_INV_W,
                               .z_near = (float)ORDER_NEAR,
                               .varyings = RAS_VARYING_COLOR};
    ras_pipeline *p = ras_pipeline_create(&cfg, NULL);
    acc_die_oom(p);
    return p;
}

/* -near/w of the quad at screen (sx, sy): exact for its clip-space corners
 * (what the pipeline is given), rounded once; NAN when it misses. */
static float order_exact_depth(const order_plane *q, double sx, double sy, int size) {
    double xn = 2 * sx / size - 1, yn = 2 * sy / size - 1;
    const ras_clip_vertex *v = q->v;
    double w = order_clip_hit(v[0].p_clip, v[1].p_clip, v[2].p_clip, xn, yn);
    if (!(w > 0)) w = order_clip_hit(v[0].p_clip, v[2].p_clip, v[3].p_clip, xn, yn);
    return w > 0 ? (float)(-(double)(float)ORDER_NEAR / w) : NAN;
}

void order_run(void) {
    const int size = acc_opt.quick ? 64 : 128;
    mat4s proj = ras_projection_normalize_w(
        get_projection_matrix(ACC_FOV_DEG, 1, (float)ORDER_NEAR, (float)ORDER_FAR));
    mat4s mvp = glms_mat4_mul(proj, ras_view_matrix_eye((vec3s){{0, 0, 0}}));
    ras_pipeline *mask_near = order_pipeline(size), *mask_far = order_pipeline(size);
    ras_pipeline *both[2] = {order_pipeline(size), order_pipeline(size)};
    const vec3s red = {{1, 0, 0}}, blue = {{0, 0, 1}};
    acc_progress("depth order (inverse_w): %d distances x %d tilts x %d gaps", ORDER_D, ORDER_T,
                 ORDER_G);
    for (int gi = 0; gi < ORDER_G; gi++)
        for (int di = 0; di < ORDER_D; di++)
            for (int ti = 0; ti < ORDER_T; ti++) {
                double d = ORDER_DIST[di], D = d * (1 + ORDER_GAP[gi]);
                order_plane nearq = order_make_plane(mvp, d, ORDER_TILT[ti], 0, red);
                order_plane farq = order_make_plane(mvp, D, ORDER_TILT[ti], 37, blue);
                ras_pipeline_begin_frame(mask_near);
                ras_pipeline_begin_frame(mask_far);
                order_draw(mask_near, &nearq, false);
                order_draw(mask_far, &farq, false);
                for (int k = 0; k < 2; k++) {
                    ras_pipeline_begin_frame(both[k]);
                    order_draw(both[k], &farq, k == ORDER_BEFORE);
                    order_draw(both[k], &nearq, k == ORDER_BEFORE);
                }
                long counted = 0, wrong[ORDER_KINDS] = {0};
                for (int y = 0; y < size; y++)
                    for (int x = 0; x < size; x++) {
                        int i = ras_fb_sample_index(mask_near->fb, x, y, 0);
                        if (mask_near->fb->depth[i] == INFINITY ||
                            mask_far->fb->depth[i] == INFINITY)
                            continue;
                        counted++;
                        for (int k = 0; k < 2; k++)
                            wrong[k] += both[k]->fb->color[i].z > 0.5f;
                        float zn = order_exact_depth(&nearq, x + 0.5, y + 0.5, size);
                        float zf = order_exact_depth(&farq, x + 0.5, y + 0.5, size);
                        wrong[ORDER_ROUNDED] += !(zn < zf);
                    }
                for (int k = 0; k < ORDER_KINDS; k++)
                    order_frac[k][gi][di][ti] = counted ? (double)wrong[k] / counted : NAN;
            }
    ras_pipeline_destroy(mask_near);
    ras_pipeline_destroy(mask_far);
    ras_pipeline_destroy(both[0]);
    ras_pipeline_destroy(both[1]);
}

double order_worst(int k, int gi, int *wd, int *wt, int *cells) {
    double worst = 0;
    *wd = *wt = 0;
    *cells = 0;
    for (int di = 0; di < ORDER_D; di++)
        for (int ti = 0; ti < ORDER_T; ti++) {
            double f = order_frac[k][gi][di][ti];
            *cells += f > 0;
            if (f > worst) worst = f, *wd = di, *wt = ti;
        }
    return worst;
}

double order_mean(int k, int gi) {
    double sum = 0;
    for (int di = 0; di < ORDER_D; di++)
        for (int ti = 0; ti < ORDER_T; ti++)
            sum += order_frac[k][gi][di][ti];
    return sum / (ORDER_D * ORDER_T);
}

double order_excess(int k, int gi, int *wd, int *wt, int *cells) {
    double worst = 0;
    *wd = *wt = 0;
    *cells = 0;
    for (int di = 0; di < ORDER_D; di++)
        for (int ti = 0; ti < ORDER_T; ti++) {
            double e = order_frac[k][gi][di][ti] - order_frac[ORDER_ROUNDED][gi][di][ti];
            *cells += e > 0;
            if (e > worst) worst = e, *wd = di, *wt = ti;
        }
    return worst;
}

void order_check(void) {
    /* inverse_w loses order only where its float input already does, at
     * every gap from 1e-6 on, and it never does worse than before. */
    for (int gi = 0; gi < ORDER_G; gi++) {
        int wd, wt, cells;
        double e = order_excess(ORDER_AFTER, gi, &wd, &wt, &cells);
        if (ORDER_GAP[gi] >= 1e-6)
            acc_check(e <= 0.01,
                      "depth order gap %g: inverse_w inverts %.4f more of the samples "
                      "than its input's exact depths at distance %g, tilt %g",
                      ORDER_GAP[gi], e, ORDER_DIST[wd], ORDER_TILT[wt]);
        if (ORDER_GAP[gi] >= 3e-7)
            acc_check(order_mean(ORDER_AFTER, gi) <= order_mean(ORDER_BEFORE, gi),
                      "depth order gap %g: after (%.4f mean) worse than before (%.4f)",
                      ORDER_GAP[gi], order_mean(ORDER_AFTER, gi), order_mean(ORDER_BEFORE, gi));
    }
}
