/* ras_compare.c — see ras_compare.h. */
#include "ras_compare.h"

#include <assert.h> /* assert */
#include <math.h>   /* INFINITY, log10, sqrt, exp, floor, isinf */
#include <stdint.h> /* uint8_t */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* malloc, free */
#include <string.h> /* strcmp, memset */

/* ---- names -------------------------------------------------------------- */

const char *ras_compare_kind_name(ras_compare_kind kind) {
    switch (kind) {
    case RAS_COMPARE_EXACT: return "exact";
    case RAS_COMPARE_EDGE_TOLERANT: return "edge";
    case RAS_COMPARE_PSNR: return "psnr";
    case RAS_COMPARE_SSIM: return "ssim";
    }
    return "unknown";
}

bool ras_compare_kind_parse(const char *name, ras_compare_kind *kind, ras_error *err) {
    assert(name && kind);
    static const struct {
        const char *name;
        ras_compare_kind kind;
    } names[] = {
        {"exact", RAS_COMPARE_EXACT},
        {"edge", RAS_COMPARE_EDGE_TOLERANT},
        {"edge_tolerant", RAS_COMPARE_EDGE_TOLERANT},
        {"psnr", RAS_COMPARE_PSNR},
        {"ssim", RAS_COMPARE_SSIM},
    };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (strcmp(name, names[i].name) == 0) {
            *kind = names[i].kind;
            return true;
        }
    }
    return ras_error_set(err,
                         "unknown comparison '%s': expected one of exact, edge, psnr, ssim",
                         name);
}

ras_compare_options ras_compare_defaults(ras_compare_kind kind) {
    ras_compare_options o = {
        .kind = kind,
        .tolerance = 8,
        .max_bad_fraction = 1.0,
        .min_psnr_db = -INFINITY,
        .min_ssim = -INFINITY,
    };
    switch (kind) {
    case RAS_COMPARE_EXACT:
        o.tolerance = 0;
        o.max_bad_fraction = 0.0;
        break;
    case RAS_COMPARE_EDGE_TOLERANT: o.max_bad_fraction = 0.0005; break;
    case RAS_COMPARE_PSNR: o.min_psnr_db = 35.0; break;
    case RAS_COMPARE_SSIM: o.min_ssim = 0.98; break;
    }
    return o;
}

/* ---- 8-bit working copies ------------------------------------------------ */

/* Both images as 8-bit RGB plus the per-pixel difference map: everything the
 * metrics and pictures need, computed once per call. */
typedef struct quantised {
    int width, height;
    uint8_t *expected, *got; /* 3 bytes per pixel */
    uint8_t *diff;           /* 1 byte per pixel, 8-bit levels */
} quantised;

static void quantised_free(quantised *q) {
    free(q->expected);
    free(q->got);
    free(q->diff);
}

static int rgb_distance(const uint8_t *a, const uint8_t *b) {
    int d = 0;
    for (int c = 0; c < 3; c++) {
        int dc = a[c] > b[c] ? a[c] - b[c] : b[c] - a[c];
        if (dc > d) d = dc;
    }
    return d;
}

/* min over the clipped 3x3 neighbourhood of (col,row) in `other` of the
 * distance to `px`. */
static int neighbourhood_min(const uint8_t *px, const uint8_t *other, int w, int h, int col,
                             int row) {
    int best = 255;
    /* the clipped window once, not a bounds test per neighbour: the grader
     * measures every differing pixel of every picture this way */
    int r0 = row > 0 ? row - 1 : 0, r1 = row + 1 < h ? row + 1 : h - 1;
    int c0 = col > 0 ? col - 1 : 0, c1 = col + 1 < w ? col + 1 : w - 1;
    for (int r = r0; r <= r1; r++) {
        const uint8_t *q = other + 3 * ((size_t)r * w + c0);
        for (int c = c0; c <= c1; c++, q += 3) {
            int d = rgb_distance(px, q);
            if (d < best) best = d;
        }
        if (best == 0) return 0;
    }
    return best;
}

static void diff_map(quantised *q, ras_compare_kind kind) {
    int w = q->width, h = q->height;
    for (int row = 0; row < h; row++) {
        for (int col = 0; col < w; col++) {
            size_t i = (size_t)row * w + col;
            const uint8_t *e = q->expected + 3 * i, *g = q->got + 3 * i;
            int d = rgb_distance(e, g);
            if (kind == RAS_COMPARE_EDGE_TOLERANT && d > 0) {
                int got_vs_expected = neighbourhood_min(g, q->expected, w, h, col, row);
                int expected_vs_got = neighbourhood_min(e, q->got, w, h, col, row);
                d = got_vs_expected > expected_vs_got ? got_vs_expected : expected_vs_got;
            }
            q->diff[i] = (uint8_t)d;
        }
    }
}

static bool sizes_match(const ras_image *expected, const ras_image *got, ras_error *err) {
    if (expected->width == got->width && expected->height == got->height) return true;
    return ras_error_set(err,
                         "expected %dx%d (the reference), got %dx%d (the image under test): "
                         "render at the reference's size before comparing",
                         expected->width, expected->height, got->width, got->height);
}

static bool quantise(const ras_image *expected, const ras_image *got, ras_compare_kind kind,
                     quantised *q, ras_error *err) {
    memset(q, 0, sizeof *q);
    if (!sizes_match(expected, got, err)) return false;
    q->width = expected->width;
    q->height = expected->height;
    size_t n = (size_t)q->width * (size_t)q->height;
    q->expected = malloc(3 * n);
    q->got = malloc(3 * n);
    q->diff = malloc(n);
    if (!q->expected || !q->got || !q->diff) {
        quantised_free(q);
        return ras_error_set(err, "out of memory comparing two %dx%d images", expected->width,
                             expected->height);
    }
    ras_image_to_rgb8(expected, q->expected);
    ras_image_to_rgb8(got, q->got);
    diff_map(q, kind);
    return true;
}

/* ---- PSNR and SSIM ----------------------------------------------------- */

static double psnr_db(const quantised *q) {
    size_t n = 3 * (size_t)q->width * (size_t)q->height;
    /* Integer sum: exact, so identical images give exactly 0 and INFINITY. */
    unsigned long long sq = 0;
    for (size_t i = 0; i < n; i++) {
        int d = (int)q->expected[i] - (int)q->got[i];
        sq += (unsigned long long)(d * d);
    }
    if (sq == 0) return INFINITY;
    double mse = (double)sq / (double)n;
    return 10.0 * log10(255.0 * 255.0 / mse);
}

#define SSIM_RADIUS 5 /* 11x11 window */
#define SSIM_SIGMA 1.5

/* Horizontal pass of the separable Gaussian for one image row: the five
 * local moments SSIM needs, each normalised by the weights that fell inside
 * the image (clipping a separable window keeps it separable). */
static void ssim_row_moments(const double *x, const double *y, int w, const double *g,
                             double *mx, double *my, double *mxx, double *myy, double *mxy) {
    for (int col = 0; col < w; col++) {
        double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
        for (int k = -SSIM_RADIUS; k <= SSIM_RADIUS; k++) {
            int c = col + k;
            if (c < 0 || c >= w) continue;
            double wk = g[k + SSIM_RADIUS];
            sw += wk;
            sx += wk * x[c];
            sy += wk * y[c];
            sxx += wk * x[c] * x[c];
            syy += wk * y[c] * y[c];
            sxy += wk * x[c] * y[c];
        }
        mx[col] = sx / sw;
        my[col] = sy / sw;
        mxx[col] = sxx / sw;
        myy[col] = syy / sw;
        mxy[col] = sxy / sw;
    }
}

static bool mean_ssim(const quantised *q, double *out) {
    int w = q->width, h = q->height;
    size_t n = (size_t)w * (size_t)h;
    /* Luma of both images, then the five horizontally smoothed moments; the
     * moments must stay consecutive (MX..MXY) for the vertical pass's loop. */
    enum { X, Y, MX, MY, MXX, MYY, MXY, MAPS };
    double *buf = malloc(MAPS * n * sizeof *buf);
    if (!buf) return false;
    double *map[MAPS];
    for (int m = 0; m < MAPS; m++) map[m] = buf + (size_t)m * n;

    for (size_t i = 0; i < n; i++) {
        const uint8_t *e = q->expected + 3 * i, *g = q->got + 3 * i;
        map[X][i] = 0.299 * e[0] + 0.587 * e[1] + 0.114 * e[2];
        map[Y][i] = 0.299 * g[0] + 0.587 * g[1] + 0.114 * g[2];
    }
    double gauss[2 * SSIM_RADIUS + 1];
    for (int k = -SSIM_RADIUS; k <= SSIM_RADIUS; k++)
        gauss[k + SSIM_RADIUS] = exp(-(double)(k * k) / (2.0 * SSIM_SIGMA * SSIM_SIGMA));

    /* Where a pixel's whole window is the same in both images its term is
     * exactly 1: with mx = my and vx = vy = cxy (the same sums of the same
     * values) numerator and denominator are the same products, since 2a and
     * a + a round alike. So a row whose window rows all agree adds 1 per
     * pixel without its sums, and a row no such window needs gets no
     * moments: a picture that matches, or matches in bands, costs little, and
     * the mean is bit for bit the full computation's. */
    unsigned char *same = calloc(3 * (size_t)h, 1);
    if (!same) {
        free(buf);
        return false;
    }
    unsigned char *skip = same + h, *needed = same + 2 * (size_t)h;
    for (int row = 0; row < h; row++)
        same[row] = !memcmp(map[X] + (size_t)row * w, map[Y] + (size_t)row * w, w * sizeof(double));
    for (int row = 0; row < h; row++) {
        skip[row] = 1;
        for (int r = row - SSIM_RADIUS; r <= row + SSIM_RADIUS; r++)
            if (r >= 0 && r < h && !same[r]) skip[row] = 0;
        if (skip[row]) continue;
        for (int r = row - SSIM_RADIUS; r <= row + SSIM_RADIUS; r++)
            if (r >= 0 && r < h) needed[r] = 1;
    }
    for (int row = 0; row < h; row++) {
        if (!needed[row]) continue;
        size_t o = (size_t)row * w;
        ssim_row_moments(map[X] + o, map[Y] + o, w, gauss, map[MX] + o, map[MY] + o,
                         map[MXX] + o, map[MYY] + o, map[MXY] + o);
    }

    const double c1 = (0.01 * 255.0) * (0.01 * 255.0);
    const double c2 = (0.03 * 255.0) * (0.03 * 255.0);
    /* The vertical pass a whole row at a time: each pixel's five sums still
     * add the same terms in the same order (k upwards, from 0), so the value
     * is bit for bit the per-pixel loop's, but the loops over the columns
     * are independent and vectorise (the grader compares every picture). */
    double *acc = malloc(5 * (size_t)w * sizeof *acc);
    if (!acc) {
        free(same);
        free(buf);
        return false;
    }
    double sum = 0.0;
    for (int row = 0; row < h; row++) {
        if (skip[row]) {
            for (int col = 0; col < w; col++) sum += 1.0;
            continue;
        }
        double sw = 0;
        for (size_t i = 0; i < 5 * (size_t)w; i++) acc[i] = 0;
        for (int k = -SSIM_RADIUS; k <= SSIM_RADIUS; k++) {
            int r = row + k;
            if (r < 0 || r >= h) continue;
            double wk = gauss[k + SSIM_RADIUS];
            sw += wk;
            for (int j = 0; j < 5; j++) {
                const double *src = map[MX + j] + (size_t)r * w;
                double *dst = acc + (size_t)j * w;
                for (int col = 0; col < w; col++) dst[col] += wk * src[col];
            }
        }
        for (int col = 0; col < w; col++) {
            double m[5];
            for (int j = 0; j < 5; j++) m[j] = acc[(size_t)j * w + col];
            double mx = m[0] / sw, my = m[1] / sw;
            /* The same expression for both variances and the covariance, so
             * an image against itself gives exactly 1 and swapping the
             * images gives exactly the same value. */
            double vx = m[2] / sw - mx * mx, vy = m[3] / sw - my * my;
            double cxy = m[4] / sw - mx * my;
            sum += ((2.0 * mx * my + c1) * (2.0 * cxy + c2)) /
                   ((mx * mx + my * my + c1) * (vx + vy + c2));
        }
    }
    free(acc);
    free(same);
    free(buf);
    *out = sum / (double)n;
    return true;
}

/* ---- the comparison ------------------------------------------------------ */

static void summarise(ras_compare_result *r, const ras_compare_options *o, long allowed) {
    char *s = r->summary;
    size_t size = sizeof r->summary, len = 0;
#define APPEND(...)                                                                    \
    do {                                                                               \
        if (len < size) {                                                              \
            int k = snprintf(s + len, size - len, __VA_ARGS__);                        \
            if (k > 0) len += (size_t)k;                                               \
        }                                                                              \
    } while (0)

    APPEND("%s %s: ", ras_compare_kind_name(o->kind), r->pass ? "pass" : "FAIL");
    if (o->min_psnr_db > -INFINITY) {
        if (isinf(r->psnr_db))
            APPEND("PSNR inf dB (identical at 8 bits); ");
        else
            APPEND("PSNR %.1f dB %s %.1f dB required; ", r->psnr_db,
                   r->psnr_db >= o->min_psnr_db ? ">=" : "<", o->min_psnr_db);
    }
    if (o->min_ssim > -INFINITY)
        APPEND("SSIM %.4f %s %.4f required; ", r->ssim, r->ssim >= o->min_ssim ? ">=" : "<",
               o->min_ssim);

    if (o->tolerance > 0)
        APPEND("%ld pixels (%.3g%%) differ by more than %d/255", r->bad_pixels,
               100.0 * r->bad_fraction, o->tolerance);
    else
        APPEND("%ld pixels (%.3g%%) differ", r->bad_pixels, 100.0 * r->bad_fraction);
    if (o->kind == RAS_COMPARE_EDGE_TOLERANT) APPEND(" even allowing a 1-pixel shift");
    if (o->max_bad_fraction < 1.0) APPEND(" (at most %ld allowed)", allowed);
    if (r->max_diff > 0)
        APPEND(", worst at (%d,%d) by %d/255", r->worst_col, r->worst_row, r->max_diff);
#undef APPEND
}

bool ras_compare_reference_fits(const ras_image *expected, const char *path, int width, int height,
                                ras_error *err) {
    if (expected->width == width && expected->height == height) return true;
    ras_error_set(err,
                  "cannot compare: the reference %s is %dx%d, the render would be %dx%d; render "
                  "at the reference's size (--size %dx%d) or pass another --reference",
                  path, expected->width, expected->height, width, height, expected->width,
                  expected->height);
    return false;
}

double ras_compare_work_bytes(int width, int height) {
    double n = (double)width * (double)height;
    /* quantise: expected, got (3 bytes each), diff (1); mean_ssim: MAPS
     * doubles and 3 bytes a row. The difference images come after SSIM's
     * maps are freed, and need less (a 12-byte float pixel and its PNG). */
    return 7.0 * n + 7.0 * sizeof(double) * n + 3.0 * height;
}

/* The measurements of `q` under `opt` (opt->kind is the kind q was made for). */
static bool measure(const quantised *q, const ras_compare_options *opt, ras_compare_result *out,
                    ras_error *err) {
    assert(opt->tolerance >= 0 && opt->tolerance <= 255);
    memset(out, 0, sizeof *out);
    out->kind = opt->kind;
    out->worst_col = out->worst_row = -1;
    size_t n = (size_t)q->width * (size_t)q->height;
    out->width = q->width;
    out->height = q->height;

    for (size_t i = 0; i < n; i++) {
        int d = q->diff[i];
        if (d > opt->tolerance) out->bad_pixels++;
        if (d > out->max_diff) {
            out->max_diff = d;
            out->worst_col = (int)(i % (size_t)q->width);
            out->worst_row = (int)(i / (size_t)q->width);
        }
    }
    out->bad_fraction = (double)out->bad_pixels / (double)n;
    out->psnr_db = psnr_db(q);
    if (!mean_ssim(q, &out->ssim)) {
        memset(out, 0, sizeof *out);
        out->kind = opt->kind;
        out->worst_col = out->worst_row = -1;
        return ras_error_set(err, "out of memory computing SSIM of two %dx%d images", q->width,
                             q->height);
    }

    switch (opt->kind) {
    case RAS_COMPARE_EXACT:
    case RAS_COMPARE_EDGE_TOLERANT: out->value = out->bad_fraction; break;
    case RAS_COMPARE_PSNR: out->value = out->psnr_db; break;
    case RAS_COMPARE_SSIM: out->value = out->ssim; break;
    }

    long allowed = (long)floor(opt->max_bad_fraction * (double)n);
    /* INFINITY >= any threshold, so identical images pass PSNR by itself. */
    out->pass = out->bad_pixels <= allowed && out->psnr_db >= opt->min_psnr_db &&
                out->ssim >= opt->min_ssim;
    summarise(out, opt, allowed);
    return true;
}

bool ras_compare_images(const ras_image *expected, const ras_image *got,
                        const ras_compare_options *opt, ras_compare_result *out,
                        ras_error *err) {
    assert(expected && got && opt && out);
    memset(out, 0, sizeof *out);
    out->kind = opt->kind;
    out->worst_col = out->worst_row = -1;
    quantised q;
    if (!quantise(expected, got, opt->kind, &q, err)) return false;
    bool ok = measure(&q, opt, out, err);
    quantised_free(&q);
    return ok;
}

/* ---- pictures ------------------------------------------------------------ */

static vec3s heat_color(int diff) {
    if (diff <= 0) return (vec3s){{0.0f, 0.0f, 0.0f}};
    static const float stops[4][3] = {
        {0.0f, 0.0f, 0.55f}, /* dark blue: still clearly not black at 8 bits */
        {0.0f, 0.8f, 1.0f},  /* cyan */
        {1.0f, 1.0f, 0.0f},  /* yellow */
        {1.0f, 0.0f, 0.0f},  /* red */
    };
    float t = sqrtf((float)diff / 255.0f) * 3.0f;
    int i = t >= 3.0f ? 2 : (int)t;
    float f = t - (float)i;
    vec3s c;
    for (int k = 0; k < 3; k++) c.raw[k] = stops[i][k] + f * (stops[i + 1][k] - stops[i][k]);
    return c;
}

static ras_image *heatmap(const quantised *q, ras_error *err) {
    ras_image *img = ras_image_create(q->width, q->height, err);
    if (img) {
        size_t n = (size_t)q->width * (size_t)q->height;
        for (size_t i = 0; i < n; i++) img->pixels[i] = heat_color(q->diff[i]);
    }
    return img;
}

ras_image *ras_compare_heatmap(const ras_image *expected, const ras_image *got,
                               ras_compare_kind kind, ras_error *err) {
    assert(expected && got);
    quantised q;
    if (!quantise(expected, got, kind, &q, err)) return NULL;
    ras_image *img = heatmap(&q, err);
    quantised_free(&q);
    return img;
}

static int clamp_int(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

static vec3s byte_color(const uint8_t *p) {
    return (vec3s){{p[0] / 255.0f, p[1] / 255.0f, p[2] / 255.0f}};
}

static ras_image *crop(const quantised *qp, int col, int row, ras_error *err) {
    const quantised q = *qp;
    ras_image *img = ras_image_create(RAS_COMPARE_CROP_WIDTH, RAS_COMPARE_CROP_HEIGHT, err);
    if (!img) return NULL;
    ras_image_fill(img, (vec3s){{0.5f, 0.5f, 0.5f}}); /* the gaps */

    const int side = RAS_COMPARE_CROP_SIDE, zoom = RAS_COMPARE_CROP_ZOOM;
    const int panel = side * zoom + RAS_COMPARE_CROP_GAP;
    col = clamp_int(col, 0, q.width - 1);
    row = clamp_int(row, 0, q.height - 1);
    /* Keep the window inside the image when it fits, so no panel area is
     * wasted at the border. */
    int c0 = clamp_int(col - side / 2, 0, q.width > side ? q.width - side : 0);
    int r0 = clamp_int(row - side / 2, 0, q.height > side ? q.height - side : 0);

    for (int wr = 0; wr < side; wr++) {
        for (int wc = 0; wc < side; wc++) {
            int c = c0 + wc, r = r0 + wr;
            vec3s px[3];
            if (c < q.width && r < q.height) {
                size_t i = (size_t)r * q.width + c;
                px[0] = byte_color(q.expected + 3 * i);
                px[1] = byte_color(q.got + 3 * i);
                px[2] = heat_color(q.diff[i]);
            } else {
                float v = ((wc + wr) & 1) ? 0.3f : 0.2f;
                px[0] = px[1] = px[2] = (vec3s){{v, v, v}};
            }
            for (int p = 0; p < 3; p++)
                for (int y = 0; y < zoom; y++)
                    for (int x = 0; x < zoom; x++)
                        ras_image_set(img, p * panel + wc * zoom + x, wr * zoom + y, px[p]);
        }
    }

    /* Outline the pixel of interest on the heatmap panel only, so the
     * expected and got panels show the true colours. */
    const vec3s white = {{1.0f, 1.0f, 1.0f}};
    int x0 = 2 * panel + (col - c0) * zoom, y0 = (row - r0) * zoom;
    for (int k = 0; k < zoom; k++) {
        ras_image_set(img, x0 + k, y0, white);
        ras_image_set(img, x0 + k, y0 + zoom - 1, white);
        ras_image_set(img, x0, y0 + k, white);
        ras_image_set(img, x0 + zoom - 1, y0 + k, white);
    }
    return img;
}

ras_image *ras_compare_crop(const ras_image *expected, const ras_image *got,
                            ras_compare_kind kind, int col, int row, ras_error *err) {
    assert(expected && got);
    quantised q;
    if (!quantise(expected, got, kind, &q, err)) return NULL;
    ras_image *img = crop(&q, col, row, err);
    quantised_free(&q);
    return img;
}

/* ---- one comparison, many answers ---------------------------------------- */

struct ras_comparison {
    quantised q;
    ras_compare_kind kind;
};

ras_comparison *ras_comparison_create(const ras_image *expected, const ras_image *got,
                                      ras_compare_kind kind, ras_error *err) {
    assert(expected && got);
    ras_comparison *c = malloc(sizeof *c);
    if (!c) {
        ras_error_set(err, "out of memory comparing two images");
        return NULL;
    }
    c->kind = kind;
    if (!quantise(expected, got, kind, &c->q, err)) {
        free(c);
        return NULL;
    }
    return c;
}

bool ras_comparison_result(const ras_comparison *c, const ras_compare_options *opt,
                           ras_compare_result *out, ras_error *err) {
    assert(c && opt && out && opt->kind == c->kind);
    return measure(&c->q, opt, out, err);
}

ras_image *ras_comparison_heatmap(const ras_comparison *c, ras_error *err) {
    assert(c);
    return heatmap(&c->q, err);
}

ras_image *ras_comparison_crop(const ras_comparison *c, int col, int row, ras_error *err) {
    assert(c);
    return crop(&c->q, col, row, err);
}

void ras_comparison_destroy(ras_comparison *c) {
    if (!c) return;
    quantised_free(&c->q);
    free(c);
}

/* ---- coverage as text ---------------------------------------------------- */

static bool covered(vec3s px, const uint8_t bg[3]) {
    return ras_unit_to_byte(px.x) != bg[0] || ras_unit_to_byte(px.y) != bg[1] ||
           ras_unit_to_byte(px.z) != bg[2];
}

bool ras_compare_ascii_mask(const ras_image *expected, const ras_image *got,
                            vec3s background, int col, int row, int radius, char *buf,
                            size_t size, ras_error *err) {
    assert(expected && got && buf && radius >= 0);
    if (size > 0) buf[0] = '\0';
    if (!sizes_match(expected, got, err)) return false;

    int c0 = clamp_int(col - radius, 0, expected->width);
    int c1 = clamp_int(col + radius, -1, expected->width - 1);
    int r0 = clamp_int(row - radius, 0, expected->height);
    int r1 = clamp_int(row + radius, -1, expected->height - 1);
    size_t cols = c1 >= c0 ? (size_t)(c1 - c0 + 1) : 0;
    size_t rows = r1 >= r0 ? (size_t)(r1 - r0 + 1) : 0;
    size_t need = cols > 0 ? rows * (cols + 1) + 1 : 1;
    if (need > size)
        return ras_error_set(err,
                             "the coverage window of %zux%zu pixels needs %zu bytes of text, "
                             "got a buffer of %zu",
                             cols, rows, need, size);

    const uint8_t bg[3] = {ras_unit_to_byte(background.x), ras_unit_to_byte(background.y),
                           ras_unit_to_byte(background.z)};
    static const char symbol[2][2] = {
        /* [in expected][in got] */
        {'.', '+'},
        {'-', '#'},
    };
    size_t len = 0;
    for (int r = r0; cols > 0 && r <= r1; r++) {
        for (int c = c0; c <= c1; c++) {
            bool in_expected = covered(ras_image_get(expected, c, r), bg);
            bool in_got = covered(ras_image_get(got, c, r), bg);
            buf[len++] = symbol[in_expected][in_got];
        }
        buf[len++] = '\n';
    }
    buf[len] = '\0';
    return true;
}
