/* fast/fast_rast.c — the fast renderer's rasterizer: one triangle into one
 * tile. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * The reference rasterizer's integer edge functions
 * (hw2_rasterize/solution/rasterizer.c), stepped by one addition per pixel
 * instead of computed from scratch — the same integers — over the part of
 * the triangle's box inside the tile, 8×8 blocks wholly outside an edge
 * skipped; the reference's barycentrics and depth of every covered sample,
 * the depth test against the tile's buffer, and the fragments that pass
 * recorded for shading when the tile is done (fast_shade.c).
 *
 * Three variants draw a triangle, the fastest that fits it: one sample with
 * 32-bit lanes (x1_draw), four samples with 32-bit lanes (x4_draw), and any
 * sample count with int64 values (n_draw, which always fits). Their walk over
 * the box is one template, fast_rast_tile_tmp.h, included once per variant
 * with the variant's state, block and end (as Mesa's lp_rast_tri_tmp.h is
 * included once per plane count).
 */
#include "fast_priv.h"

/* ---- one sample ------------------------------------------------------------ */

/* The reference's barycentrics of a covered point, in the original vertex
 * order (order is 0,1,2 or 0,2,1: a select, not a scatter through memory). */
/* (float)((double)e / area2), the reference's barycentric, without the
 * division where that is provably the same float. For a covered point
 * 0 <= e <= area2 < 2^53, so (double)e is exact and q = e · RN(1/area2) is
 * within about 3 double ulps of the correctly rounded quotient d (two
 * roundings of 2^-53 each, against d's one). Rounding to float gives the same
 * result for q and d unless a float rounding boundary — a midpoint between
 * two floats, whose 29 bits below float precision read 0x10000000 — lies
 * between them; so when q's 29 low bits are more than 8 from that pattern, q
 * rounds like d, and otherwise (about once in 2^25) divide. q >= 2^-53 is far
 * from float subnormals; e = 0 gives +0 either way. */
static inline float ratio_to_float(int64_t e, const fast_tri *r) {
    double q = (double)e * r->inv_area2;
    uint64_t bits;
    memcpy(&bits, &q, sizeof bits);
    uint32_t low = (uint32_t)(bits & 0x1FFFFFFFu);
    if (__builtin_expect(low - (0x10000000u - 8u) <= 16u, 0))
        return (float)((double)e / (double)r->area2);
    return (float)q;
}

static inline vec3s bary_of(const fast_tri *r, const int64_t e[3]) {
    float l0 = ratio_to_float(e[0], r);
    float l1 = ratio_to_float(e[1], r);
    float l2 = ratio_to_float(e[2], r);
    return r->order[1] == 1 ? (vec3s){{l0, l1, l2}} : (vec3s){{l0, l2, l1}};
}

/* The reference's barycentrics, divided as it does: at 1x the divider
 * runs beside the rest of a pixel's work. */
static inline vec3s bary_div(const fast_tri *r, const int64_t e[3]) {
    double a = (double)r->area2;
    float l0 = (float)((double)e[0] / a);
    float l1 = (float)((double)e[1] / a);
    float l2 = (float)((double)e[2] / a);
    return r->order[1] == 1 ? (vec3s){{l0, l1, l2}} : (vec3s){{l0, l2, l1}};
}

static inline float depth_of(const fast_tri *r, vec3s b) {
    return b.x * r->z[0] + b.y * r->z[1] + b.z * r->z[2];
}

/* Is the whole block [bx0, bx1] × [by0, by1] of pixels outside one edge for
 * every sample position? The edge function is affine, so its largest value
 * over the block's sample points is at a corner of the box spanned by the
 * extreme sample offsets. */
static bool block_outside(const fast_tri *r, int bx0, int by0, int bx1, int by1, int64_t omin_x,
                          int64_t omax_x, int64_t omin_y, int64_t omax_y) {
    for (int i = 0; i < 3; i++) {
        int64_t px = r->a[i] > 0 ? (int64_t)bx1 * SUBPIXEL_ONE + omax_x
                                 : (int64_t)bx0 * SUBPIXEL_ONE + omin_x;
        int64_t py = r->b[i] > 0 ? (int64_t)by1 * SUBPIXEL_ONE + omax_y
                                 : (int64_t)by0 * SUBPIXEL_ONE + omin_y;
        if (r->a[i] * px + r->b[i] * py + r->c[i] < r->thr[i]) return true;
    }
    return false;
}

/* fast_defer_fragment with the barycentrics in lanes 0-2 of bv (lane 3 is 0: the
 * record's pad). */
static inline void defer_fragment_v(fast_worker *w, const fast_tri *r, vf4 bv, int base,
                                    uint64_t mask) {
    if (__builtin_expect(w->nfrag == w->frag_cap, 0)) {
        vec3s b = {{bv[0], bv[1], bv[2]}};
        fast_defer_fragment(w, r, b, base, mask);
        return;
    }
    int32_t i = (int32_t)w->nfrag++;
    fast_queued *f = &w->frags[i];
    f->r = r;
    memcpy(&f->bary, &bv, sizeof bv); /* bary and pad */
    f->base = base;
    f->object = r->object;
    f->mask = mask;
    fast_defer_set_owner(w, base, mask, i);
}

#if defined(__SSE2__)
#define BARY_X4 1
/* ratio_to_float for four points at once: e (int32 lanes, exact: every
 * caller's values fit) to double, times RN(1/area2), to float — the scalar
 * steps lane by lane (cvtdq2pd, mulpd, cvtpd2ps round like cvtsi2sd, mulsd,
 * cvtsd2ss). Returns the lanes (all ones) whose product lies within 8 of a
 * float rounding boundary (ratio_to_float divides there): the caller redoes
 * them. */
static inline vi4 ratios_x4(vi4 e, __m128d inv, vf4 *out) {
    __m128i ei = (__m128i)e;
    __m128d qlo = _mm_mul_pd(_mm_cvtepi32_pd(ei), inv);
    __m128d qhi = _mm_mul_pd(_mm_cvtepi32_pd(_mm_shuffle_epi32(ei, _MM_SHUFFLE(3, 2, 3, 2))), inv);
    *out = (vf4)_mm_movelh_ps(_mm_cvtpd_ps(qlo), _mm_cvtpd_ps(qhi));
    /* the low 32 bits of each double (dwords 0 and 2): low29 − (2^28 − 8) */
    __m128i m = _mm_set1_epi32(0x1FFFFFFF), c = _mm_set1_epi32(0x10000000 - 8);
    __m128i vlo = _mm_sub_epi32(_mm_and_si128(_mm_castpd_si128(qlo), m), c);
    __m128i vhi = _mm_sub_epi32(_mm_and_si128(_mm_castpd_si128(qhi), m), c);
    vi4 v = (vi4)_mm_castps_si128(
        _mm_shuffle_ps(_mm_castsi128_ps(vlo), _mm_castsi128_ps(vhi), _MM_SHUFFLE(2, 0, 2, 0)));
    /* (uint32)(low29 − …) <= 16, as a signed compare with the sign flipped */
    return (v ^ INT32_MIN) < INT32_MIN + 17;
}

/* bary_of and depth_of for four points (lanes) whose edge values E are e[k]:
 * the same floats, lane by lane. Lanes in the returned mask (near a rounding
 * boundary) must be redone with bary_of. */
static inline unsigned bary_depth_x4(const fast_tri *r, const vi4 e[3], v3x4 *b, vf4 *z) {
    __m128d inv = _mm_set1_pd(r->inv_area2);
    vf4 l0, l1, l2;
    vi4 near = ratios_x4(e[0], inv, &l0);
    near |= ratios_x4(e[1], inv, &l1);
    near |= ratios_x4(e[2], inv, &l2);
    *b = r->order[1] == 1 ? (v3x4){l0, l1, l2} : (v3x4){l0, l2, l1};
    *z = b->x * vf4_splat(r->z[0]) + b->y * vf4_splat(r->z[1]) + b->z * vf4_splat(r->z[2]);
    return vi4_sign_bits(near);
}

#else
#define BARY_X4 0
#endif

/* The shading point of a pixel whose centre is not covered: the visible
 * sample nearest the centre (the first of equals), as rasterize_triangle
 * chooses it. */
static inline __attribute__((always_inline)) int nearest_visible(const fast_frame *fr,
                                                                 uint64_t visible, const int n) {
    int best = -1;
    float best_d2 = 0;
    for (int k = 0; k < n; k++) {
        if (!(visible >> k & 1)) continue;
        float dx = fr->pattern.offsets[k].x - 0.5f, dy = fr->pattern.offsets[k].y - 0.5f;
        float d2 = dx * dx + dy * dy;
        if (best < 0 || d2 < best_d2) {
            best = k;
            best_d2 = d2;
        }
    }
    return best;
}

static inline __attribute__((always_inline)) void
draw_pixel_samples(fast_worker *w, const fast_tri *r, int x, int y, int tx0, int ty0,
                   int64_t e[][3], const int n, uint64_t covered) {
    const fast_frame *fr = w->fr;
    int base = ((y - ty0) * TILE + (x - tx0)) * n;
    vec3s bary[RAS_MAX_SAMPLES];
    float z[RAS_MAX_SAMPLES];
    uint64_t visible = 0;
    for (int k = 0; k < n; k++) {
        /* covered: the caller's coverage bits, or 0 to test here */
        if (covered ? !(covered >> k & 1)
                    : e[k][0] < r->thr[0] || e[k][1] < r->thr[1] || e[k][2] < r->thr[2])
            continue;
        w->k.samples_covered++;
        bary[k] = bary_of(r, e[k]);
        z[k] = depth_of(r, bary[k]);
        if (!(z[k] < w->depth[base + k])) continue;
        w->k.depth_tests_passed++;
        w->depth[base + k] = z[k];
        visible |= (uint64_t)1 << k;
    }
    if (!visible) return;
    if (fr->ssaa) {
        for (int k = 0; k < n; k++) {
            if (!(visible >> k & 1)) continue;
            if (n == 1)
                fast_defer_pixel(w, r, bary[k], base + k);
            else
                fast_defer_fragment(w, r, bary[k], base + k, 1);
        }
        return;
    }
    vec3s bc;
    const int64_t *ec = e[n]; /* the pixel centre */
    if (fr->centre_sample >= 0 && (visible >> fr->centre_sample & 1)) {
        bc = bary[fr->centre_sample]; /* a sample at the centre: the same integers */
    } else if (ec[0] >= r->thr[0] && ec[1] >= r->thr[1] && ec[2] >= r->thr[2]) {
        bc = bary_of(r, ec);
    } else {
        bc = bary[nearest_visible(fr, visible, n)];
    }
    if (n == 1)
        fast_defer_pixel(w, r, bc, base);
    else
        fast_defer_fragment(w, r, bc, base, visible);
}

#if BARY_X4
/* draw_pixel_samples for four samples (MSAA or SSAA 4x) whose E − thr are
 * the lanes of ev[k], covered at the bits of `covered` (not 0), with the
 * pixel centre's edge values ec: the samples' barycentrics and depths in
 * lanes (bary_depth_x4), the depth test and write on the pixel's four
 * depths at once, then draw_pixel_samples' choice of the shading point. */
static inline __attribute__((always_inline)) void
draw_pixel4_v(fast_worker *w, const fast_tri *r, int x, int y, int tx0, int ty0, const vi4 ev[3],
              const vi4 thrv[3], vi4 covv, unsigned covered, const int64_t dcen[3], vi4 *counts) {
    const fast_frame *fr = w->fr;
    int base = ((y - ty0) * TILE + (x - tx0)) * 4;
    vi4 E[3] = {ev[0] + thrv[0], ev[1] + thrv[1], ev[2] + thrv[2]};
    v3x4 b;
    vf4 z;
    unsigned near = bary_depth_x4(r, E, &b, &z) & covered;
    for (; near; near &= near - 1) { /* about once in 2^25 */
        int i = __builtin_ctz(near);
        int64_t ep[3] = {(int64_t)E[0][i], (int64_t)E[1][i], (int64_t)E[2][i]};
        vec3s bb = bary_of(r, ep);
        b.x[i] = bb.x, b.y[i] = bb.y, b.z[i] = bb.z;
        z[i] = depth_of(r, bb);
    }
    float *dp = &w->depth[base];
    vf4 old = vf4_load(dp);
    vi4 pass = (z < old) & covv;
    unsigned visible = vi4_sign_bits(pass);
    counts[0] -= covv; /* samples_covered and depth_tests_passed, per lane */
    if (!visible) return;
    counts[1] -= pass;
    vf4 nz = vf4_select(pass, z, old);
    memcpy(dp, &nz, sizeof nz);
    vf4 bv[4] = {b.x, b.y, b.z, vf4_splat(0.0f)};
    vf4_transpose(&bv[0], &bv[1], &bv[2], &bv[3]);
    if (fr->ssaa) {
        for (unsigned m = visible; m; m &= m - 1) {
            int k = __builtin_ctz(m);
            defer_fragment_v(w, r, bv[k], base + k, 1);
        }
        return;
    }
    if (fr->centre_sample >= 0 && (visible >> fr->centre_sample & 1)) {
        defer_fragment_v(w, r, bv[fr->centre_sample], base, visible);
        return;
    }
    /* the centre's E − thr: sample 0's plus the centre's offset from it */
    int64_t c0 = ev[0][0] + dcen[0], c1 = ev[1][0] + dcen[1], c2 = ev[2][0] + dcen[2];
    if ((c0 | c1 | c2) >= 0) { /* covered (the sign bits, as for the samples) */
        int64_t e3[3] = {c0 + r->thr[0], c1 + r->thr[1], c2 + r->thr[2]};
        fast_defer_fragment(w, r, bary_div(r, e3), base, visible);
    } else {
        defer_fragment_v(w, r, bv[nearest_visible(fr, visible, 4)], base, visible);
    }
}
#endif

/* ---- the variants, each from fast_rast_tile_tmp.h ------------------------ */

/* What every variant is handed: the tile's corner and the part of the
 * triangle's box inside the tile (pixels, inclusive). */
typedef struct tile_box {
    int tx0, ty0, x0, y0, x1, y1;
} tile_box;

/* Any sample count, int64 edge values. `n` (samples per pixel) is a constant
 * in each inlined copy: the loops over samples unroll and the edge values
 * stay in registers. It draws every triangle (begin never declines). */
typedef struct n_state {
    int64_t reject_x0, reject_x1, reject_y0, reject_y1;
    int64_t step[3]; /* E's change per pixel to the right */
    int ne;          /* edge values kept: the samples' and the centre's */
} n_state;

static inline __attribute__((always_inline)) bool
n_begin(fast_worker *w, const fast_tri *r, const tile_box *box, n_state *s, const int n) {
    const fast_frame *fr = w->fr;
    (void)box;
    s->reject_x0 = fr->omin_x, s->reject_x1 = fr->omax_x;
    s->reject_y0 = fr->omin_y, s->reject_y1 = fr->omax_y;
    for (int i = 0; i < 3; i++)
        s->step[i] = r->a[i] * SUBPIXEL_ONE;
    /* Edge values are kept for the n samples and the pixel centre, except at
     * one sample that is the centre (no AA): draw_pixel_samples reads the
     * centre's values only when no visible sample lies there. */
    s->ne = n == 1 && fr->centre_sample == 0 ? 1 : n + 1;
    return true;
}

/* One row of a block with up to 4 samples: the row's coverage as a bit mask
 * first (n bits per pixel), without a branch per sample (edges of small
 * triangles are unpredictable), then only the pixels with a covered sample,
 * their edge values stepped from the row start (still exact). */
static inline __attribute__((always_inline)) void n_row_masked(fast_worker *w, const fast_tri *r,
                                                               const tile_box *box,
                                                               const n_state *s, int bx0, int bx1,
                                                               int y, int64_t e[][3], const int n) {
    /* E >= thr on all three edges <=> every E - thr has its sign bit clear
     * <=> so has their bitwise or. */
    uint32_t mask = 0;
    int64_t ev[RAS_MAX_SAMPLES][3];
    for (int k = 0; k < n; k++)
        for (int j = 0; j < 3; j++)
            ev[k][j] = e[k][j] - r->thr[j];
    for (int i = 0; i <= bx1 - bx0; i++)
        for (int k = 0; k < n; k++) {
            uint64_t any_negative = (uint64_t)(ev[k][0] | ev[k][1] | ev[k][2]);
            mask |= (uint32_t)(~any_negative >> 63) << (i * n + k);
            for (int j = 0; j < 3; j++)
                ev[k][j] += s->step[j];
        }
    while (mask) {
        int i = __builtin_ctz(mask) / n;
        mask &= ~((((uint32_t)1 << n) - 1) << (i * n));
        int64_t ep[RAS_MAX_SAMPLES + 1][3];
        for (int k = 0; k < s->ne; k++)
            for (int j = 0; j < 3; j++)
                ep[k][j] = e[k][j] + (int64_t)i * s->step[j];
        draw_pixel_samples(w, r, bx0 + i, y, box->tx0, box->ty0, ep, n, 0);
    }
}

static inline __attribute__((always_inline)) void n_block(fast_worker *w, const fast_tri *r,
                                                          const tile_box *box, n_state *s, int bx0,
                                                          int by0, int bx1, int by1, const int n) {
    const fast_frame *fr = w->fr;
    for (int y = by0; y <= by1; y++) {
        /* Edge values at (bx0, y) for every sample and the centre, then one
         * addition per pixel: exact integers, the same values the reference
         * computes from scratch. */
        int64_t e[RAS_MAX_SAMPLES + 1][3];
        for (int k = 0; k < s->ne; k++) {
            int64_t px = (int64_t)bx0 * SUBPIXEL_ONE + fr->off_x[k];
            int64_t py = (int64_t)y * SUBPIXEL_ONE + fr->off_y[k];
            for (int i = 0; i < 3; i++)
                e[k][i] = r->a[i] * px + r->b[i] * py + r->c[i];
        }
        if (n * BLOCK <= 32) {
            n_row_masked(w, r, box, s, bx0, bx1, y, e, n);
            continue;
        }
        for (int x = bx0; x <= bx1; x++) {
            draw_pixel_samples(w, r, x, y, box->tx0, box->ty0, e, n, 0);
            for (int k = 0; k < s->ne; k++)
                for (int i = 0; i < 3; i++)
                    e[k][i] += s->step[i];
        }
    }
}

static inline __attribute__((always_inline)) void n_end(fast_worker *w, const fast_tri *r,
                                                        n_state *s, const int n) {
    (void)w, (void)r, (void)s, (void)n;
}

#define TAG(name) n_##name
#define TILE_ATTR static inline __attribute__((always_inline))
#define TILE_PARAMS , const int n
#define TILE_ARGS , n
#include "fast_rast_tile_tmp.h"

/* Do all three E − thr stay within ±2^30 over the sub-pixel box [px0, px1] ×
 * [py0, py1]? They are affine, so their extremes are at the box's corners;
 * inside that range 32-bit lanes hold them, and a step between two points of
 * the box, exactly. */
static bool edges_fit_31(const fast_tri *r, int64_t px0, int64_t px1, int64_t py0, int64_t py1) {
    const int64_t lim = (int64_t)1 << 30;
    /* -lim < v < lim <=> v + lim - 1 in [0, 2·lim - 2], one unsigned test */
    const uint64_t span = 2 * (uint64_t)lim - 2;
    for (int k = 0; k < 3; k++) {
        /* the corners from one of them and the steps across the box */
        int64_t v00 = r->a[k] * px0 + r->b[k] * py0 + r->c[k] - r->thr[k] + (lim - 1);
        int64_t dx = r->a[k] * (px1 - px0), dy = r->b[k] * (py1 - py0);
        int64_t v10 = v00 + dx, v01 = v00 + dy, v11 = v10 + dy;
        if (((uint64_t)v00 > span) | ((uint64_t)v10 > span) | ((uint64_t)v01 > span) |
            ((uint64_t)v11 > span))
            return false;
    }
    return true;
}

/* Without AA (one sample, at the pixel centre), for a triangle whose edge
 * values over the part of its box in this tile fit in 31 bits (every cow
 * triangle; not a screen-filling one): the coverage of eight pixels of a
 * block row is two 4-lane int32 additions and ors per edge and a sign mask,
 * instead of eight pixels of int64 arithmetic. The values are the same
 * integers (exact arithmetic well inside the range). A covered pixel's
 * barycentrics are the reference's divisions (bary_div), its depth test and
 * fragment draw_pixel_samples' for n = 1; with per_pixel (a constant in each
 * inlined copy) the fragment goes to its pixel, without a branch on the test.
 * Declines when the values may not fit (draw with the n_ variant). */
typedef struct x1_state {
    int64_t reject_x0, reject_x1, reject_y0, reject_y1; /* the centre, cx and cy */
    int64_t cx, cy;
    /* i · step for lanes i = 0..3 and 4..7; a row's step; thr */
    vi4 ramp_lo[3], ramp_hi[3], vstepy[3], thrv[3];
    /* counted here, added once (the stores could alias w's fields) */
    uint64_t covered_n, passed_n;
} x1_state;

static inline __attribute__((always_inline)) bool x1_begin(fast_worker *w, const fast_tri *r,
                                                           const tile_box *box, x1_state *s,
                                                           const bool per_pixel) {
    const fast_frame *fr = w->fr;
    const int64_t cx = fr->off_x[0], cy = fr->off_y[0];
    (void)per_pixel;
    /* x1 + 7: a block row's eight lanes may run past x1; y1 + 1: the
     * lanes are stepped once past the last row */
    if (!edges_fit_31(r, (int64_t)box->x0 * SUBPIXEL_ONE + cx,
                      (int64_t)(box->x1 + BLOCK - 1) * SUBPIXEL_ONE + cx,
                      (int64_t)box->y0 * SUBPIXEL_ONE + cy,
                      (int64_t)(box->y1 + 1) * SUBPIXEL_ONE + cy))
        return false;
    s->reject_x0 = s->reject_x1 = s->cx = cx;
    s->reject_y0 = s->reject_y1 = s->cy = cy;
    /* up to 7 steps is the difference of two values in the checked box, so
     * it fits in int32 */
    for (int k = 0; k < 3; k++) {
        int st = (int)(r->a[k] * SUBPIXEL_ONE);
        vi4 sv = {st, st, st, st};
        s->ramp_lo[k] = sv * (vi4){0, 1, 2, 3};
        s->ramp_hi[k] = s->ramp_lo[k] + (sv << 2);
        int sy = (int)(r->b[k] * SUBPIXEL_ONE), t = (int)r->thr[k];
        s->vstepy[k] = (vi4){sy, sy, sy, sy};
        s->thrv[k] = (vi4){t, t, t, t};
    }
    s->covered_n = s->passed_n = 0;
    return true;
}

/* The block's coverage, all its rows without a branch (a row's covered count
 * is unpredictable, and so is whether it has any): eight bits a row in the
 * mask returned, each row's E (lanes + thr: they fit) into eblk. */
static inline __attribute__((always_inline)) uint64_t x1_coverage(const fast_tri *r,
                                                                  const x1_state *s, int bx0,
                                                                  int by0, int bx1, int by1,
                                                                  int32_t eblk[BLOCK][3][BLOCK]) {
    unsigned row_lanes = (1u << (bx1 - bx0 + 1)) - 1;
    int64_t px = (int64_t)bx0 * SUBPIXEL_ONE + s->cx;
    int64_t py0 = (int64_t)by0 * SUBPIXEL_ONE + s->cy;
    /* E − thr of the block row's eight pixels, per edge: at the block's
     * first row, then one vector addition per row (exact: every value used
     * lies in the checked box) */
    vi4 elo[3], ehi[3];
    for (int k = 0; k < 3; k++) {
        int start = (int)(r->a[k] * px + r->b[k] * py0 + r->c[k] - r->thr[k]);
        elo[k] = (vi4){start, start, start, start} + s->ramp_lo[k];
        ehi[k] = (vi4){start, start, start, start} + s->ramp_hi[k];
    }
    uint64_t covered = 0;
    for (int j = 0; j <= by1 - by0; j++) {
        vi4 lo = elo[0] | elo[1] | elo[2], hi = ehi[0] | ehi[1] | ehi[2];
        /* covered: E − thr >= 0 on every edge, so the or is >= 0 */
        unsigned row = ~(vi4_sign_bits(lo) | vi4_sign_bits(hi) << 4) & row_lanes;
        covered |= (uint64_t)row << (BLOCK * j);
        for (int k = 0; k < 3; k++) {
            vi4 lo_k = elo[k] + s->thrv[k], hi_k = ehi[k] + s->thrv[k];
            memcpy(&eblk[j][k][0], &lo_k, sizeof lo_k);
            memcpy(&eblk[j][k][4], &hi_k, sizeof hi_k);
            elo[k] += s->vstepy[k];
            ehi[k] += s->vstepy[k];
        }
    }
    return covered;
}

/* The block's coverage first, then its covered pixels, one loop. */
static inline __attribute__((always_inline)) void x1_block(fast_worker *w, const fast_tri *r,
                                                           const tile_box *box, x1_state *s,
                                                           int bx0, int by0, int bx1, int by1,
                                                           const bool per_pixel) {
    int32_t eblk[BLOCK][3][BLOCK];
    uint64_t covered = x1_coverage(r, s, bx0, by0, bx1, by1, eblk);
    const int base_blk = (by0 - box->ty0) * TILE + (bx0 - box->tx0);
    for (; covered; covered &= covered - 1) {
        int bit = __builtin_ctzll(covered), j = bit / BLOCK, i = bit % BLOCK;
        int64_t ep[3] = {eblk[j][0][i], eblk[j][1][i], eblk[j][2][i]};
        int base = base_blk + j * TILE + i;
        s->covered_n++;
        vec3s bary = bary_div(r, ep);
        float z = depth_of(r, bary);
        if (per_pixel) {
            /* without a branch on the depth test (it fails for about one
             * covered pixel in five, unpredictably): a failing fragment and
             * its depth go to the spare slots past the tile's pixels, never
             * read */
            unsigned pass = z < w->depth[base];
            unsigned keep = 0u - pass; /* all ones when passed */
            /* pass ? base : TILE * TILE, as masks: GCC turns a select back
             * into the branch this avoids */
            int at = (int)(((unsigned)base & keep) | (TILE * TILE & ~keep));
            s->passed_n += pass;
            w->depth[at] = z;
            fast_defer_put_pixel(w, r, bary, at);
            continue;
        }
        if (!(z < w->depth[base])) continue;
        s->passed_n++;
        w->depth[base] = z;
        fast_defer_fragment(w, r, bary, base, 1);
    }
}

static inline __attribute__((always_inline)) void x1_end(fast_worker *w, const fast_tri *r,
                                                         x1_state *s, const bool per_pixel) {
    w->k.samples_covered += s->covered_n;
    w->k.depth_tests_passed += s->passed_n;
    if (per_pixel) w->hidden[r->object] += (int64_t)s->passed_n;
}

#define TAG(name) x1_##name
#define TILE_ATTR static inline __attribute__((always_inline))
#define TILE_PARAMS , const bool per_pixel
#define TILE_ARGS , per_pixel
#include "fast_rast_tile_tmp.h"

/* Four samples per pixel (MSAA or SSAA 4x), for a triangle whose edge
 * values over the part of its box in this tile, at every sample position
 * and the pixel centre, fit in 31 bits: one 4-lane int32 vector per edge
 * holds the pixel's four samples, stepped by one addition per pixel, and the
 * coverage is the sign mask of the three or-ed. Covered samples go through
 * draw_pixel4_v (or, without SSE2, get their exact int64 edge values back,
 * lane + thr, and go through draw_pixel_samples). Declines when the values
 * may not fit (draw with the n_ variant). */
typedef struct x4_state {
    int64_t reject_x0, reject_x1, reject_y0, reject_y1;
    int64_t step[3];
    /* offset of sample k (k = 4: the centre) from the pixel's corner */
    int64_t off[RAS_MAX_SAMPLES + 1][3];
    vi4 vstep[3];
#if BARY_X4
    /* per edge: the samples' offsets from sample 0 (differences of two
     * values in the box: they fit), a row's step, thr */
    vi4 dlane[3], vstepy[3], thrv[3];
    int64_t dcen[3]; /* the centre's offset from sample 0 */
    /* samples covered and depth tests passed, counted per lane (a true
     * lane is −1, subtracted) and added to the counters at the end */
    vi4 counts[2];
#endif
} x4_state;

static inline __attribute__((always_inline)) bool x4_begin(fast_worker *w, const fast_tri *r,
                                                           const tile_box *box, x4_state *s) {
    const fast_frame *fr = w->fr;
    const int n = 4;
    s->reject_x0 = fr->omin_x, s->reject_x1 = fr->omax_x;
    s->reject_y0 = fr->omin_y, s->reject_y1 = fr->omax_y;
    /* x1 + 1, y1 + 1: the lanes are stepped once past the last pixel and
     * past the last row */
    if (!edges_fit_31(r, (int64_t)box->x0 * SUBPIXEL_ONE + s->reject_x0,
                      (int64_t)(box->x1 + 1) * SUBPIXEL_ONE + s->reject_x1,
                      (int64_t)box->y0 * SUBPIXEL_ONE + s->reject_y0,
                      (int64_t)(box->y1 + 1) * SUBPIXEL_ONE + s->reject_y1))
        return false;
    for (int i = 0; i < 3; i++)
        s->step[i] = r->a[i] * SUBPIXEL_ONE;
    for (int k = 0; k <= n; k++)
        for (int i = 0; i < 3; i++)
            s->off[k][i] = r->a[i] * fr->off_x[k] + r->b[i] * fr->off_y[k];
    for (int i = 0; i < 3; i++) {
        int st = (int)s->step[i];
        s->vstep[i] = (vi4){st, st, st, st};
    }
#if BARY_X4
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < n; k++)
            s->dlane[i][k] = (int)(s->off[k][i] - s->off[0][i]);
        s->dcen[i] = s->off[n][i] - s->off[0][i];
        int sy = (int)(r->b[i] * SUBPIXEL_ONE), t = (int)r->thr[i];
        s->vstepy[i] = (vi4){sy, sy, sy, sy};
        s->thrv[i] = (vi4){t, t, t, t};
    }
    s->counts[0] = s->counts[1] = (vi4){0, 0, 0, 0};
#endif
    return true;
}

#if BARY_X4
static inline __attribute__((always_inline)) void x4_block(fast_worker *w, const fast_tri *r,
                                                           const tile_box *box, x4_state *s,
                                                           int bx0, int by0, int bx1, int by1) {
    /* E − thr at the four samples of pixel (bx0, by0), then one vector
     * addition per row and per pixel (exact: every value used lies in the
     * checked box) */
    vi4 evrow[3];
    for (int i = 0; i < 3; i++) {
        int64_t corner = r->a[i] * ((int64_t)bx0 * SUBPIXEL_ONE) +
                         r->b[i] * ((int64_t)by0 * SUBPIXEL_ONE) + r->c[i];
        int st = (int)(corner + s->off[0][i] - r->thr[i]);
        evrow[i] = (vi4){st, st, st, st} + s->dlane[i];
    }
    for (int y = by0; y <= by1; y++) {
        /* the row's coverage first, without a branch per pixel (whether a
         * pixel has a covered sample is unpredictable): four bits a pixel,
         * each pixel's E − thr stored; then the pixels with a covered
         * sample */
        vi4 ev[3] = {evrow[0], evrow[1], evrow[2]};
        vi4 erow[BLOCK][3];
        uint32_t mask = 0;
        for (int i = 0; i <= bx1 - bx0; i++) {
            /* covered: E − thr >= 0 on all three edges */
            mask |= (uint32_t)vi4_sign_bits((ev[0] | ev[1] | ev[2]) > -1) << (4 * i);
            for (int k = 0; k < 3; k++) {
                erow[i][k] = ev[k];
                ev[k] += s->vstep[k];
            }
        }
        uint32_t any = mask | mask >> 1 | mask >> 2 | mask >> 3;
        for (any &= 0x11111111u; any; any &= any - 1) {
            int i = __builtin_ctz(any) / 4;
            const vi4 *e = erow[i];
            vi4 covv = (e[0] | e[1] | e[2]) > -1;
            draw_pixel4_v(w, r, bx0 + i, y, box->tx0, box->ty0, e, s->thrv, covv,
                          mask >> (4 * i) & 0xFu, s->dcen, s->counts);
        }
        for (int i = 0; i < 3; i++)
            evrow[i] += s->vstepy[i];
    }
}
#else
static inline __attribute__((always_inline)) void x4_block(fast_worker *w, const fast_tri *r,
                                                           const tile_box *box, x4_state *s,
                                                           int bx0, int by0, int bx1, int by1) {
    const int n = 4;
    for (int y = by0; y <= by1; y++) {
        int64_t corner[3]; /* E at the corner of pixel (bx0, y) */
        vi4 ev[3] = {{0}}; /* E - thr at the four samples */
        for (int i = 0; i < 3; i++) {
            corner[i] = r->a[i] * ((int64_t)bx0 * SUBPIXEL_ONE) +
                        r->b[i] * ((int64_t)y * SUBPIXEL_ONE) + r->c[i];
            for (int k = 0; k < n; k++)
                ev[i][k] = (int)(corner[i] + s->off[k][i] - r->thr[i]);
        }
        for (int x = bx0; x <= bx1; x++) {
            unsigned covered = ~vi4_sign_bits(ev[0] | ev[1] | ev[2]) & 0xFu;
            if (covered) {
                int64_t e[RAS_MAX_SAMPLES + 1][3];
                for (int k = 0; k < n; k++)
                    for (int i = 0; i < 3; i++)
                        e[k][i] = (int64_t)ev[i][k] + r->thr[i];
                /* the centre (read when no visible sample is there) */
                int64_t dx = (int64_t)(x - bx0);
                for (int i = 0; i < 3; i++)
                    e[n][i] = corner[i] + dx * s->step[i] + s->off[n][i];
                draw_pixel_samples(w, r, x, y, box->tx0, box->ty0, e, n, covered);
            }
            for (int i = 0; i < 3; i++)
                ev[i] += s->vstep[i];
        }
    }
}
#endif

static inline __attribute__((always_inline)) void x4_end(fast_worker *w, const fast_tri *r,
                                                         x4_state *s) {
    (void)r;
#if BARY_X4
    const vi4 *c = s->counts;
    w->k.samples_covered += (uint64_t)(c[0][0] + c[0][1] + c[0][2] + c[0][3]);
    w->k.depth_tests_passed += (uint64_t)(c[1][0] + c[1][1] + c[1][2] + c[1][3]);
#else
    (void)w, (void)s;
#endif
}

#define TAG(name) x4_##name
#define TILE_ATTR static
#define TILE_PARAMS
#define TILE_ARGS
#include "fast_rast_tile_tmp.h"

/* fast_priv.h: the part of r's box inside the tile, drawn by the variant
 * that fits. */
void fast_rast_triangle(fast_worker *w, const fast_tri *r, int tx0, int ty0, int tx1, int ty1) {
    tile_box box = {.tx0 = tx0, .ty0 = ty0};
    box.x0 = r->x0 > tx0 ? r->x0 : tx0, box.x1 = r->x1 < tx1 ? r->x1 : tx1;
    box.y0 = r->y0 > ty0 ? r->y0 : ty0, box.y1 = r->y1 < ty1 ? r->y1 : ty1;
    if (box.x0 > box.x1 || box.y0 > box.y1) return;
    const int n = w->fr->pattern.count;
    /* The reference tests every sample of the bounding box. */
    w->k.samples_tested +=
        (uint64_t)(box.x1 - box.x0 + 1) * (uint64_t)(box.y1 - box.y0 + 1) * (uint64_t)n;
    switch (n) {
    case 1:
        /* per_pixel a constant in each copy: no test per pixel */
        if (w->fr->centre_sample == 0 &&
            (w->fr->per_pixel ? x1_draw(w, r, &box, true) : x1_draw(w, r, &box, false)))
            break;
        n_draw(w, r, &box, 1);
        break;
    case 4:
        if (x4_draw(w, r, &box)) break;
        n_draw(w, r, &box, 4);
        break;
    default: n_draw(w, r, &box, n); break;
    }
}
