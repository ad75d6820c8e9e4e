/* fast/fast_shade_x4.c — the fast renderer's four-lane shaders. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * The Normal, Blinn-Phong, texture, bump and displacement shaders are
 * straight-line float arithmetic, so visible fragments are queued (in drawing order) and shaded
 * four at a time by the same operations in vector lanes (fast_simd.h says why
 * that is bit-exact). Colours are written when the queue is flushed; the
 * fragments fast_shade_tile queues own disjoint samples, so the order of the
 * writes does not matter (depth was tested and written when each fragment
 * was drawn). A queue
 * holds one object's fragments (one material). powf, nearest lookups and the
 * rare lanes with a near-zero vector to normalise (see v3_normalize) are done
 * per lane with the scalar functions.
 */
#include "fast_priv.h"

#include <math.h> /* powf */

/* texture_sample_bilinear (solution/shading.c's bilinear_level at level 0)
 * for four lookups, in two halves. bilinear_x4_footprint: the coordinates,
 * floors, weights and wrapped texel indices in vector lanes, giving the four
 * texels each lookup reads (shade_prepare prefetches them). A lane whose
 * texel index falls outside [-1, size - 1] (the reference's range, asserted
 * here rather than assumed) is left to the reference function: bit 1 << i of
 * fallback. bilinear_x4_blend: the texel blends, one lookup per vector (lane =
 * colour channel) with lerp3's operations in its order, so every lane is the
 * reference's float. */
typedef struct footprint {
    const vec3s *px;   /* level 0's texels when they are floats, else NULL */
    const uint8_t *px8; /* level 0's bytes (3 a texel) when it is RGB8, else NULL */
    const char *base;   /* px8 or px, */
    size_t texel_bytes; /* and 3 or 12: a texel's address without a branch */
    /* per lane, the texel offsets of (i0, j0), (i0+1, j0), (i0, j0+1),
     * (i0+1, j0+1) after wrapping (0 in a fallback lane) */
    vi4 o[4];
    vf4 sx, sy;
    unsigned looked_up, fallback; /* lanes done here / by the reference */
    bool last;                    /* some offset is the last texel: no 16-byte load there */
} footprint;

static inline const vec3s *footprint_texel(const footprint *F, int lane, int k) {
    return F->px + F->o[k][lane];
}

static inline const uint8_t *footprint_texel8(const footprint *F, int lane, int k) {
    return F->px8 + 3 * (size_t)F->o[k][lane];
}

/* Where lookup `lane`'s texel k is, whatever the format: for prefetching. */
static inline const void *footprint_address(const footprint *F, int lane, int k) {
    return F->base + F->texel_bytes * (size_t)F->o[k][lane];
}

/* An RGB8 texel as the vector (r, g, b, 0) of the floats the reference
 * reads (ras_texel_unit: the same as a float texture's). */
static inline vf4 texel8_x4(const uint8_t *p) {
    return (vf4){ras_texel_unit[p[0]], ras_texel_unit[p[1]], ras_texel_unit[p[2]], 0.0f};
}

/* The same from a 4-byte load (lane 3 is the next texel's red, unused, as
 * the float path's 16-byte load): widened and converted in the vector, then
 * divided by 255 — the float division ras_byte_to_unit does, correctly
 * rounded in each lane as in the scalar unit, so the same floats as the table
 * in half the instructions of its six loads. Not for the last texel. */
static inline vf4 texel8_x4_wide(const uint8_t *p) {
#if defined(__SSE2__)
    uint32_t bytes;
    memcpy(&bytes, p, sizeof bytes);
    __m128i zero = _mm_setzero_si128();
    __m128i x = _mm_unpacklo_epi8(_mm_cvtsi32_si128((int)bytes), zero);
    x = _mm_unpacklo_epi16(x, zero);
    return (vf4)_mm_div_ps(_mm_cvtepi32_ps(x), _mm_set1_ps(255.0f));
#else
    return texel8_x4(p);
#endif
}

/* One axis of four lookups (the reference's bilinear_axis_at): safe_coord, x = t·n − 0.5, its
 * floor and fraction, and the two wrapped texel indices times `stride` (1 for
 * columns, the width for rows). bad: lanes whose floor leaves [-1, n - 1]. */
typedef struct axis4 {
    vi4 a, b; /* wrapped index of floor(x), of floor(x) + 1, times stride */
    vf4 s;    /* x - floor(x) */
    vi4 bad;
} axis4;

static inline axis4 axis_x4(vf4 t, int n, int stride, ras_wrap wrap) {
    vf4 zero = vf4_splat(0.0f), one = vf4_splat(1.0f);
    /* safe_coord */
    vi4 finite = (t == t) & ((vf4)((vi4)t & 0x7fffffff) <= vf4_splat(FLT_MAX));
    t = vf4_select(finite, t, zero);
    if (wrap == RAS_WRAP_REPEAT)
        t = t - vf4_floor(t);
    else
        t = vf4_select(t < zero, zero, vf4_select(t > one, one, t));
    vf4 x = t * vf4_splat((float)n) - vf4_splat(0.5f);
    axis4 A;
    /* t is in [0, 1], so x is in [-0.5, n - 0.5] and small enough for the
     * conversion (the range test below still guards): floorf is the
     * truncation, minus one where it went up; x is never -0 (a difference
     * x - 0.5 that is zero is +0), so the sign of a zero floor is +. */
    vi4 bad = ~((x >= vf4_splat(-1.0f)) & (x < vf4_splat((float)n)));
    vf4 xs = vf4_select(bad, zero, x);
    vi4 ti = __builtin_convertvector(xs, vi4);
    vf4 tf = __builtin_convertvector(ti, vf4);
    vi4 up = tf > xs;
    vi4 i0 = ti + up; /* up is -1 where truncation went up */
    vf4 x0f = tf - (vf4)((vi4)one & up);
    A.s = x - x0f;
    vi4 i1 = i0 + 1, N = {n, n, n, n}, z = {0, 0, 0, 0};
    bad |= (i0 < -1) | (i0 > N - 1);
    vi4 ia, ib; /* ras_texture_wrap_index of i0, i0 + 1 */
    if (wrap == RAS_WRAP_REPEAT) {
        ia = i0 + (N & (i0 < z));
        ib = i1 - (N & (i1 >= N));
    } else {
        vi4 in = i1 < N;
        ia = i0 & ~(i0 < z);
        ib = (i1 & in) | ((N - 1) & ~in);
    }
    ia &= ~bad, ib &= ~bad; /* fallback lanes read texel 0 (and are replaced) */
    if (stride != 1) {
        vi4 S = {stride, stride, stride, stride};
        ia *= S, ib *= S;
    }
    A.a = ia, A.b = ib, A.bad = bad;
    return A;
}

/* The footprints of lookups (X, Y): lane i reads column X[i], row Y[i]. */
static void footprint_of(const ras_texture *tex, const axis4 *X, const axis4 *Y, int lanes,
                         footprint *F) {
    const int w = tex->level_width[0], h = tex->level_height[0]; /* as bilinear_level */
    F->px8 = ras_texture_level0_rgb8(tex);
    F->px = F->px8 ? NULL : tex->levels[0] ? tex->levels[0] : tex->texels;
    F->base = F->px8 ? (const char *)F->px8 : (const char *)F->px;
    F->texel_bytes = F->px8 ? 3 : sizeof *F->px;
    F->sx = X->s;
    F->sy = Y->s;
    vi4 bad = X->bad | Y->bad;
    F->o[0] = (Y->a + X->a) & ~bad, F->o[1] = (Y->a + X->b) & ~bad;
    F->o[2] = (Y->b + X->a) & ~bad, F->o[3] = (Y->b + X->b) & ~bad;
    int L = w * h - 1;
    vi4 Lv = {L, L, L, L};
    F->last = vi4_any((F->o[0] == Lv) | (F->o[1] == Lv) | (F->o[2] == Lv) | (F->o[3] == Lv));
    unsigned all = (1u << lanes) - 1;
    F->fallback = vi4_sign_bits(bad) & all;
    F->looked_up = all & ~F->fallback;
}

static void bilinear_x4_footprint(const ras_texture *tex, vf4 u, vf4 v, int lanes, footprint *F) {
    const int w = tex->level_width[0], h = tex->level_height[0];
    axis4 X = axis_x4(u, w, 1, tex->wrap), Y = axis_x4(v, h, w, tex->wrap);
    footprint_of(tex, &X, &Y, lanes, F);
}

/* Lane i's bilinear blend of its four texels (one vector each, lane =
 * channel): lerp3's operations in its order. */
static inline vf4 blend_lane(const footprint *F, int i, vf4 a, vf4 b, vf4 c, vf4 d) {
    vf4 s = vf4_splat(F->sx[i]), tt = vf4_splat(F->sy[i]);
    vf4 bottom = a + (b - a) * s, top = c + (d - c) * s;
    return bottom + (top - bottom) * tt;
}

/* Every lane's blend (a fallback lane's, of texel 0, is replaced by the
 * caller's; lanes past those looked up are unused). */
static v3x4 bilinear_x4_blend(const footprint *F) {
    vf4 out[4];
    if (F->px8) { /* bytes (a loaded texture): decided once for the four lanes */
        for (int i = 0; i < 4; i++) {
            vf4 a, b, c, d;
            if (__builtin_expect(!F->last, 1)) { /* 4 bytes: the next texel's red too */
                a = texel8_x4_wide(footprint_texel8(F, i, 0));
                b = texel8_x4_wide(footprint_texel8(F, i, 1));
                c = texel8_x4_wide(footprint_texel8(F, i, 2));
                d = texel8_x4_wide(footprint_texel8(F, i, 3));
            } else { /* the last texel among them: no over-read */
                a = texel8_x4(footprint_texel8(F, i, 0)), b = texel8_x4(footprint_texel8(F, i, 1));
                c = texel8_x4(footprint_texel8(F, i, 2)), d = texel8_x4(footprint_texel8(F, i, 3));
            }
            out[i] = blend_lane(F, i, a, b, c, d);
        }
    } else {
        for (int i = 0; i < 4; i++) {
            vf4 a, b, c, d;
            if (__builtin_expect(!F->last, 1)) { /* 16 bytes: the next texel's x too */
                a = vf4_load(&footprint_texel(F, i, 0)->x), b = vf4_load(&footprint_texel(F, i, 1)->x);
                c = vf4_load(&footprint_texel(F, i, 2)->x), d = vf4_load(&footprint_texel(F, i, 3)->x);
            } else {
                a = vf4_load3(&footprint_texel(F, i, 0)->x),
                b = vf4_load3(&footprint_texel(F, i, 1)->x);
                c = vf4_load3(&footprint_texel(F, i, 2)->x),
                d = vf4_load3(&footprint_texel(F, i, 3)->x);
            }
            out[i] = blend_lane(F, i, a, b, c, d);
        }
    }
    vf4_transpose(&out[0], &out[1], &out[2], &out[3]);
    return (v3x4){out[0], out[1], out[2]};
}

/* 255·|rgb| of the bilinear lookups of footprint F (at u, v). */
static inline vf4 height_of(const ras_texture *tex, const footprint *F, vf4 u, vf4 v, int lanes) {
    v3x4 rgb = bilinear_x4_blend(F);
    if (__builtin_expect(F->fallback != 0, 0))
        for (int i = 0; i < lanes; i++) {
            if (!(F->fallback >> i & 1)) continue;
            vec3s c = texture_sample_bilinear(tex, u[i], v[i]);
            rgb.x[i] = c.x, rgb.y[i] = c.y, rgb.z[i] = c.z;
        }
    return vf4_splat(255.0f) * vf4_sqrt(v3_dot(rgb, rgb));
}

/* height_sample (shading.h) for four lookups: |rgb| · 255 of the height map
 * read bilinearly (any filter but nearest) or nearest, lane by lane with the
 * reference's operations (glm_vec3_norm: sqrtf of (x·x + y·y) + z·z). Lanes
 * from `lanes` on are not looked up. Counts nothing (the caller does). */
static vf4 height_x4(const fragment_shader_payload *pay, vf4 u, vf4 v, int lanes) {
    const ras_texture *tex = pay->height_map;
    v3x4 rgb;
    if (pay->filter == FILTER_NEAREST) {
        rgb = v3_splat((vec3s){{0.0f, 0.0f, 0.0f}});
        for (int i = 0; i < lanes; i++) {
            vec3s c = ras_texture_sample_nearest(tex, u[i], v[i]);
            rgb.x[i] = c.x, rgb.y[i] = c.y, rgb.z[i] = c.z;
        }
    } else {
        footprint F;
        bilinear_x4_footprint(tex, u, v, lanes, &F);
        return height_of(tex, &F, u, v, lanes);
    }
    return vf4_splat(255.0f) * vf4_sqrt(v3_dot(rgb, rgb));
}

/* bump_normal (solution/shading.c) for four fragments: n = normalize(normal)
 * (the payload's normal, itself normalised), tangent_frame's t and b, the
 * three height lookups and TBN · (−dU, −dV, 1) normalised — the reference's
 * float operations in its order, lane by lane; a lane whose result is not
 * finite keeps n, as the reference does. *h receives h(u, v) (displacement
 * reuses it: the same lookup gives the same float). */
static v3x4 bump_normal_x4(const fragment_shader_payload *pay, v3x4 normal, vf4 u, vf4 v, int lanes,
                           vi4 *odd, vf4 *h_out) {
    v3x4 n = v3_normalize(normal, odd);
    const ras_texture *hm = pay->height_map;
    if (!hm) {
        *h_out = vf4_splat(0.0f);
        return n;
    }
    /* tangent_frame */
    vf4 zero = vf4_splat(0.0f), one = vf4_splat(1.0f);
    vf4 s = vf4_sqrt(n.x * n.x + n.z * n.z);
    vi4 big = s > vf4_splat(1e-6f);
    v3x4 t = {vf4_select(big, n.x * n.y / s, one), vf4_select(big, s, zero),
              vf4_select(big, n.z * n.y / s, zero)};
    v3x4 b = {n.y * t.z - n.z * t.y, n.z * t.x - n.x * t.z, n.x * t.y - n.y * t.x};
    vf4 u1 = u + vf4_splat(1.0f / (float)hm->width);
    vf4 v1 = v + vf4_splat(1.0f / (float)hm->height);
    vf4 h, hu, hv;
    if (pay->filter == FILTER_NEAREST) {
        h = height_x4(pay, u, v, lanes);
        hu = height_x4(pay, u1, v, lanes);
        hv = height_x4(pay, u, v1, lanes);
    } else {
        /* the three lookups share their columns and rows: u and v1 share u's,
         * v and u1 share v's */
        const int w = hm->level_width[0], hh = hm->level_height[0];
        axis4 X = axis_x4(u, w, 1, hm->wrap), X1 = axis_x4(u1, w, 1, hm->wrap);
        axis4 Y = axis_x4(v, hh, w, hm->wrap), Y1 = axis_x4(v1, hh, w, hm->wrap);
        footprint F;
        footprint_of(hm, &X, &Y, lanes, &F);
        h = height_of(hm, &F, u, v, lanes);
        footprint_of(hm, &X1, &Y, lanes, &F);
        hu = height_of(hm, &F, u1, v, lanes);
        footprint_of(hm, &X, &Y1, lanes, &F);
        hv = height_of(hm, &F, u, v1, lanes);
    }
    vf4 k = vf4_splat(pay->kh * pay->kn);
    vf4 du = k * (hu - h);
    vf4 dv = k * (hv - h);
    v3x4 p = v3_add(v3_scale(t, -du), v3_scale(b, -dv));
    v3x4 bumped = v3_normalize(v3_add(p, n), odd);
    vf4 fmax = vf4_splat(FLT_MAX);
    vi4 fin = (vf4)((vi4)bumped.x & 0x7fffffff) <= fmax;
    fin &= (vf4)((vi4)bumped.y & 0x7fffffff) <= fmax;
    fin &= (vf4)((vi4)bumped.z & 0x7fffffff) <= fmax;
    *h_out = h;
    return (v3x4){vf4_select(fin, bumped.x, n.x), vf4_select(fin, bumped.y, n.y),
                  vf4_select(fin, bumped.z, n.z)};
}

/* Four fragments between the two halves of their shading. */
typedef struct lanes4 {
    const fast_queued *const *q;
    int lanes;
    vi4 odd;
    v3x4 b, color;
    vf4 u, v;         /* texture coordinates (BATCH_TEXTURE) */
    footprint texels; /* their bilinear footprints (BATCH_TEXTURE, a texture) */
    /* per light: I/r², max(0, n·l), the specular power */
    v3x4 irradiance[HW3_MAX_LIGHTS];
    vf4 diffuse[HW3_MAX_LIGHTS], specular[HW3_MAX_LIGHTS];
} lanes4;

/* The gather: four fragments' screen barycentrics and corner w, one record
 * per vector, transposed into one vector per field (unused lanes repeat lane
 * 0, as e[] does), then persp_bary in lanes. */
static inline __attribute__((always_inline)) v3x4 weights_x4(const fast_frame *fr,
                                                             const fast_queued *const e[4]) {
    v3x4 bs, wv;
    vf4 pad;
    bs.x = vf4_load(&e[0]->bary.x), bs.y = vf4_load(&e[1]->bary.x);
    bs.z = vf4_load(&e[2]->bary.x), pad = vf4_load(&e[3]->bary.x);
    vf4_transpose(&bs.x, &bs.y, &bs.z, &pad);
    wv.x = vf4_load(e[0]->r->w3), wv.y = vf4_load(e[1]->r->w3);
    wv.z = vf4_load(e[2]->r->w3), pad = vf4_load(e[3]->r->w3);
    vf4_transpose(&wv.x, &wv.y, &wv.z, &pad);
    if (!fr->perspective) return bs;
    v3x4 p = {bs.x / wv.x, bs.y / wv.y, bs.z / wv.z};
    vf4 sum = p.x + p.y + p.z;
    vi4 ok = (sum > vf4_splat(0.0f)) & (sum <= vf4_splat(FLT_MAX)); /* > 0 and finite */
    v3x4 s = v3_scale(p, vf4_splat(1.0f) / sum);
    return (v3x4){vf4_select(ok, s.x, bs.x), vf4_select(ok, s.y, bs.y), vf4_select(ok, s.z, bs.z)};
}

/* The varyings, one fragment per vector: lane j of lo/hi is varying j
 * (normal xyz, view position x | view position yz, uv), interpolated as
 * a0·b.x + a1·b.y + a2·b.z — interp3's and interp2's operations in their
 * order — then transposed to one vector per varying. hi only with want_hi
 * (the Normal shader reads the normal alone). */
static inline __attribute__((always_inline)) void varyings_x4(const fast_queued *const e[4], v3x4 b,
                                                              bool want_hi, vf4 lo[4], vf4 hi[4]) {
    for (int i = 0; i < 4; i++) {
        const float(*a)[8] = e[i]->r->attr;
        vf4 bx = vf4_splat(b.x[i]), by = vf4_splat(b.y[i]), bz = vf4_splat(b.z[i]);
        lo[i] = vf4_load(a[0]) * bx;
        lo[i] = lo[i] + vf4_load(a[1]) * by;
        lo[i] = lo[i] + vf4_load(a[2]) * bz;
        if (want_hi) {
            hi[i] = vf4_load(a[0] + 4) * bx;
            hi[i] = hi[i] + vf4_load(a[1] + 4) * by;
            hi[i] = hi[i] + vf4_load(a[2] + 4) * bz;
        }
    }
    vf4_transpose(&lo[0], &lo[1], &lo[2], &lo[3]);
    if (want_hi) vf4_transpose(&hi[0], &hi[1], &hi[2], &hi[3]);
}

/* blinn_phong up to kd, in lanes: per light, I/r², max(0, n·l) and the
 * specular power (powf lane by lane, only where it can be non-zero). */
static inline __attribute__((always_inline)) void light_terms_x4(const fragment_shader_payload *pay,
                                                                 float spec_zero, int lanes,
                                                                 v3x4 normal, v3x4 point, vi4 *odd,
                                                                 lanes4 *S) {
    if (pay->counters) {
        pay->counters->stages_run |= RAS_STAGE_LIGHTING;
        pay->counters->lighting_evaluations += (uint64_t)pay->light_count * (uint64_t)lanes;
    }
    v3x4 n = v3_normalize(normal, odd);
    v3x4 v = v3_normalize((v3x4){-point.x, -point.y, -point.z}, odd);
    vf4 zero = vf4_splat(0.0f);
    for (int li = 0; li < pay->light_count; li++) {
        const light *L = &pay->lights[li];
        v3x4 to_light = v3_sub(v3_splat(L->position), point);
        vf4 r2 = v3_dot(to_light, to_light);
        v3x4 l = v3_normalize(to_light, odd);
        v3x4 h = v3_normalize(v3_add(l, v), odd);
        if (!memcmp(&L->intensity.x, &L->intensity.y, sizeof(float)) &&
            !memcmp(&L->intensity.x, &L->intensity.z, sizeof(float))) {
            /* a white light (the classic scene's): the three quotients have
             * the same operands, so one division gives all three */
            vf4 q = vf4_splat(L->intensity.x) / r2;
            S->irradiance[li] = (v3x4){q, q, q};
        } else {
            S->irradiance[li] = v3_divs(v3_splat(L->intensity), r2);
        }
        vf4 nl = v3_dot(n, l), nh = v3_dot(n, h);
        S->diffuse[li] = vf4_select(nl > zero, nl, zero);
        vf4 x = vf4_select(nh > zero, nh, zero);
        vf4 specular = zero;
        vi4 lit = x > vf4_splat(spec_zero);
        if (vi4_any(lit))
            for (int i = 0; i < 4; i++)
                if (lit[i]) specular[i] = powf(x[i], pay->p);
        S->specular[li] = specular;
    }
}

/* (n + 1) · 0.5: the Normal and bump shaders' colour */
static inline v3x4 normal_colour_x4(v3x4 n) {
    return v3_scale(v3_add(n, v3_splat((vec3s){{1.0f, 1.0f, 1.0f}})), vf4_splat(0.5f));
}

/* Everything up to the colour map: the weights, the varyings and, per light,
 * the terms that do not involve kd. Then the texels the lookups will read are
 * prefetched, and shade_finish (called after the other half-queue's prepare)
 * finds them in cache. */
static void shade_prepare(fast_worker *w, const fast_queued *const *q, int lanes, lanes4 *S) {
    const fast_frame *fr = w->fr;
    const fragment_shader_payload *pay = &w->pay[q[0]->r->object];
    S->q = q;
    S->lanes = lanes;
    const fast_queued *e[4];
    for (int i = 0; i < 4; i++)
        e[i] = q[i < lanes ? i : 0];
    v3x4 b = weights_x4(fr, e);
    vf4 lo[4], hi[4];
    varyings_x4(e, b, fr->batch != BATCH_NORMAL, lo, hi);
    S->b = b;
    vi4 odd = {0, 0, 0, 0};
    v3x4 normal = v3_normalize((v3x4){lo[0], lo[1], lo[2]}, &odd); /* payload->normal */
    w->k.varyings_interpolated += fr->varyings_per_fragment * (uint64_t)lanes;
    w->k.fragments_shaded += (uint64_t)lanes;
    if (fr->batch == BATCH_NORMAL) {
        /* normal_fragment_shader: (normalize(n) + 1) · 0.5 */
        S->color = normal_colour_x4(v3_normalize(normal, &odd));
        S->odd = odd;
        return;
    }
    v3x4 point = {lo[3], hi[0], hi[1]}; /* payload->view_pos */
    S->u = hi[2];
    S->v = hi[3];
    if (fr->batch == BATCH_BUMP) {
        /* bump_fragment_shader: (bump_normal + 1) · 0.5 */
        vf4 h;
        v3x4 n = bump_normal_x4(pay, normal, S->u, S->v, lanes, &odd, &h);
        fast_count_heights(pay, 3, (uint64_t)lanes);
        S->color = normal_colour_x4(n);
        S->odd = odd;
        return;
    }
    if (fr->batch == BATCH_DISPLACEMENT) {
        /* displacement_fragment_shader: the point p + n·(kn·h), then
         * Blinn-Phong with bump_normal's normal (below) */
        vf4 h;
        v3x4 bumped = bump_normal_x4(pay, normal, S->u, S->v, lanes, &odd, &h);
        fast_count_heights(pay, 3, (uint64_t)lanes); /* h(u, v) once, as the reference */
        v3x4 n = v3_normalize(normal, &odd);
        vf4 s = vf4_splat(pay->kn) * h;
        point = (v3x4){point.x + n.x * s, point.y + n.y * s, point.z + n.z * s};
        normal = bumped;
    }
    light_terms_x4(pay, fr->spec_zero[q[0]->r->object], lanes, normal, point, &odd, S);
    S->odd = odd;
    if (fr->batch == BATCH_TEXTURE && pay->texture) {
        /* the texels the lookups will read (nearest filtering reads one of
         * the four), fetched while the other half-queue is prepared */
        bilinear_x4_footprint(pay->texture, S->u, S->v, lanes, &S->texels);
        for (int i = 0; i < lanes; i++)
            if (S->texels.looked_up >> i & 1)
                for (int k = 0; k < 4; k++)
                    __builtin_prefetch(footprint_address(&S->texels, i, k));
    }
}

/* Four copies of c at d: three vectors, rgbr gbrg brgb. */
static inline void put4(vec3s *d, vec3s c) {
#if defined(__SSE2__)
    float *f = &d->x;
    _mm_storeu_ps(f, _mm_setr_ps(c.x, c.y, c.z, c.x));
    _mm_storeu_ps(f + 4, _mm_setr_ps(c.y, c.z, c.x, c.y));
    _mm_storeu_ps(f + 8, _mm_setr_ps(c.z, c.x, c.y, c.z));
#else
    d[0] = d[1] = d[2] = d[3] = c;
#endif
}

/* kd (the texture lookups), the sums in blinn_phong's order, and the
 * colours into the tile. */
static void shade_finish(fast_worker *w, lanes4 *S) {
    const fast_frame *fr = w->fr;
    const fast_queued *const *q = S->q;
    int lanes = S->lanes;
    fragment_shader_payload *pay = &w->pay[q[0]->r->object];
    v3x4 color = S->color;
    if (fr->batch != BATCH_NORMAL && fr->batch != BATCH_BUMP) {
        v3x4 kd = v3_splat(pay->color);
        if (fr->batch == BATCH_TEXTURE && pay->texture && pay->filter == FILTER_BILINEAR) {
            kd = bilinear_x4_blend(&S->texels);
            if (pay->counters) { /* texture_sample's counts for the lanes done here */
                pay->counters->stages_run |= RAS_STAGE_TEXTURE;
                unsigned looked_up = (unsigned)__builtin_popcount(S->texels.looked_up);
                pay->counters->texels_fetched += 4u * looked_up;
            }
            for (int i = 0; i < lanes; i++) {
                if (!(S->texels.fallback >> i & 1)) continue;
                vec3s c = texture_sample(pay, pay->texture, (vec2s){{S->u[i], S->v[i]}});
                kd.x[i] = c.x;
                kd.y[i] = c.y;
                kd.z[i] = c.z;
            }
        } else if (fr->batch == BATCH_TEXTURE && pay->texture) {
            for (int i = 0; i < 4; i++) {
                /* lanes past `lanes` copy lane 0: no lookup, no count */
                vec3s c = i < lanes ? texture_sample(pay, pay->texture, (vec2s){{S->u[i], S->v[i]}})
                                    : (vec3s){{kd.x[0], kd.y[0], kd.z[0]}};
                kd.x[i] = c.x;
                kd.y[i] = c.y;
                kd.z[i] = c.z;
            }
        }
        color = v3_splat(glms_vec3_mul(pay->ka, pay->ambient_intensity));
        v3x4 ks = v3_splat(pay->ks);
        for (int li = 0; li < pay->light_count; li++) {
            color = v3_add(color, v3_scale(v3_mul(kd, S->irradiance[li]), S->diffuse[li]));
            color = v3_add(color, v3_scale(v3_mul(ks, S->irradiance[li]), S->specular[li]));
        }
    }
    unsigned odd = vi4_sign_bits(S->odd);
    for (int i = 0; i < lanes; i++) {
        vec3s c = {{color.x[i], color.y[i], color.z[i]}};
        if (__builtin_expect(odd >> i & 1, 0)) c = fast_shade_silent(w, q[i]->r, q[i]->bary);
        vec3s *dst = &w->color[q[i]->base];
        uint64_t mask = q[i]->mask;
        if (mask == 1) { /* one sample: 1x, SSAA */
            *dst = c;
            continue;
        }
        if (mask == 0xF && fr->pattern.count == 4) { /* a whole pixel of 4x */
            put4(dst, c);
            continue;
        }
        for (; mask; mask &= mask - 1)
            dst[__builtin_ctzll(mask)] = c;
    }
}

/* Both halves prepared before either is finished: the lighting of one hides
 * the texel fetches of the other. */
void fast_shade_x4_flush(fast_worker *w) {
    int n = w->qn;
    w->qn = 0;
    lanes4 S[QUEUE / 4];
    int chunks = 0;
    for (int c = 0; c < n; c += 4)
        shade_prepare(w, &w->q[c], n - c < 4 ? n - c : 4, &S[chunks++]);
    for (int c = 0; c < chunks; c++)
        shade_finish(w, &S[c]);
}
