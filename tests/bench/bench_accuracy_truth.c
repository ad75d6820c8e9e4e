/* bench_accuracy_truth.c — the accuracy report's ground truths, computed
 * outside the pipeline: exact areas of polygons clipped to pixel squares
 * (sections 1-2) and rays against planes (sections 3-5). bench_accuracy.h.
 */
#include "bench_accuracy.h"

#include <math.h>   /* llround, floor, fmin, fmax, tan */
#include <string.h> /* memcpy */

/* Keeps the part of polygon `in` left of the directed line a→b. */
static int clip_half(const acc_pt *in, int n, acc_pt a, acc_pt b, acc_pt *out) {
    int m = 0;
    for (int i = 0; i < n; i++) {
        acc_pt p = in[i], q = in[(i + 1) % n];
        double dp = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        double dq = (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
        if (dp >= 0) out[m++] = p;
        if ((dp >= 0) != (dq >= 0)) {
            double t = dp / (dp - dq);
            out[m++] = (acc_pt){p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
        }
        if (m >= ACC_POLY_MAX - 2) break;
    }
    return m;
}

int truth_clip_convex(const acc_pt *poly, int n, const acc_pt *clip, int m, acc_pt *out) {
    acc_pt a[ACC_POLY_MAX], b[ACC_POLY_MAX];
    memcpy(a, poly, (size_t)n * sizeof *a);
    for (int i = 0; i < m && n > 0; i++) {
        n = clip_half(a, n, clip[i], clip[(i + 1) % m], b);
        memcpy(a, b, (size_t)n * sizeof *a);
    }
    memcpy(out, a, (size_t)n * sizeof *a);
    return n;
}

double truth_poly_area(const acc_pt *p, int n) {
    double s = 0;
    for (int i = 0; i < n; i++)
        s += p[i].x * p[(i + 1) % n].y - p[(i + 1) % n].x * p[i].y;
    return 0.5 * s;
}

static double pixel_area(const acc_pt *poly, int n, int x, int y) {
    acc_pt sq[4] = {{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}}, out[ACC_POLY_MAX];
    int m = truth_clip_convex(poly, n, sq, 4, out);
    return m >= 3 ? truth_poly_area(out, m) : 0;
}

void truth_snapped_ccw(const vec4s v[3], acc_pt out[3]) {
    for (int i = 0; i < 3; i++)
        out[i] =
            (acc_pt){llround((double)v[i].x * 256) / 256.0, llround((double)v[i].y * 256) / 256.0};
    if (truth_poly_area(out, 3) < 0) {
        acc_pt t = out[1];
        out[1] = out[2];
        out[2] = t;
    }
}

void truth_add_coverage(double *cov, int w, int h, const acc_pt *poly, int n, double weight) {
    double x0 = poly[0].x, x1 = x0, y0 = poly[0].y, y1 = y0;
    for (int i = 1; i < n; i++) {
        x0 = fmin(x0, poly[i].x), x1 = fmax(x1, poly[i].x);
        y0 = fmin(y0, poly[i].y), y1 = fmax(y1, poly[i].y);
    }
    for (int y = (int)fmax(0, floor(y0)); y <= (int)fmin(h - 1, floor(y1)); y++)
        for (int x = (int)fmax(0, floor(x0)); x <= (int)fmin(w - 1, floor(x1)); x++)
            cov[(h - 1 - y) * w + x] += weight * pixel_area(poly, n, x, y);
}

void truth_pixel_ray(int x, int y, double sx, double sy, int size, double d[3]) {
    double t = tan(ACC_FOV_DEG * RAS_PI / 360.0);
    d[0] = (2 * (x + sx) / size - 1) * t;
    d[1] = (2 * (y + sy) / size - 1) * t;
    d[2] = -1;
}

ras_mesh *truth_quad_mesh(const acc_quad *q) {
    ras_mesh *m = ras_mesh_create(4, 2);
    acc_die_oom(m);
    for (int i = 0; i < 4; i++) {
        m->positions[i] = (vec3s){{(float)q->p[i][0], (float)q->p[i][1], (float)q->p[i][2]}};
        m->uvs[i] = (vec2s){{(float)q->uv[i][0], (float)q->uv[i][1]}};
        m->colors[i] = (vec3s){{1, 1, 1}};
        m->normals[i] = (vec3s){{0, 0, 1}};
    }
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    memcpy(m->indices, idx, sizeof idx);
    m->has_uv = true;
    return m;
}

bool truth_quad_hit(const acc_quad *q, const double d[3], double *depth, double uv[2]) {
    double e1[3], e2[3], n[3];
    for (int i = 0; i < 3; i++)
        e1[i] = q->p[1][i] - q->p[0][i], e2[i] = q->p[3][i] - q->p[0][i];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double nd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    if (nd == 0) return false;
    double s = (n[0] * q->p[0][0] + n[1] * q->p[0][1] + n[2] * q->p[0][2]) / nd;
    if (!(s > 0)) return false;
    double r[3] = {s * d[0] - q->p[0][0], s * d[1] - q->p[0][1], s * d[2] - q->p[0][2]};
    /* Solve r = a e1 + b e2 by least squares (exact: r lies in the plane). */
    double e11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    double e22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    double e12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    double r1 = r[0] * e1[0] + r[1] * e1[1] + r[2] * e1[2];
    double r2 = r[0] * e2[0] + r[1] * e2[1] + r[2] * e2[2];
    double det = e11 * e22 - e12 * e12;
    double a = (r1 * e22 - r2 * e12) / det, b = (r2 * e11 - r1 * e12) / det;
    *depth = s;
    for (int k = 0; k < 2; k++)
        uv[k] = q->uv[0][k] + a * (q->uv[1][k] - q->uv[0][k]) + b * (q->uv[3][k] - q->uv[0][k]);
    return a >= 0 && a <= 1 && b >= 0 && b <= 1;
}
