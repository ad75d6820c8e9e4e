/* fast/fast_simd.h — four fragments side by side, bit for bit. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * The fast path's batched shading (fast_shade_x4.c) computes four fragments at
 * once with GCC/clang vector extensions. Lane-wise +, -, *, / and sqrt are
 * IEEE operations rounded exactly like their scalar forms (SSE's mulps/divps/
 * sqrtps give the same bits as mulss/divss/sqrtss), and the build's
 * -ffp-contract=off keeps vector multiply-adds unfused as it does scalar
 * ones, so writing each scalar expression of the reference with the same
 * operations in the same order gives the same floats in every lane. No
 * -march flag is needed: SSE2 is the x86-64 baseline; other targets get the
 * same arithmetic lane by lane.
 */
#ifndef RAS_FAST_SIMD_H
#define RAS_FAST_SIMD_H

#include <float.h>  /* FLT_EPSILON, FLT_MAX */
#include <math.h>   /* sqrtf */
#include <stdint.h> /* INT32_MIN */
#include <string.h> /* memcpy */

#if defined(__SSE2__)
#include <emmintrin.h> /* SSE2; includes xmmintrin.h (_MM_TRANSPOSE4_PS) */
#elif defined(__aarch64__) && defined(__ARM_NEON)
#include <arm_neon.h>
#endif

typedef float vf4 __attribute__((vector_size(16)));
typedef int vi4 __attribute__((vector_size(16))); /* masks: -1 true, 0 false */

typedef struct v3x4 {
    vf4 x, y, z;
} v3x4;

static inline vf4 vf4_splat(float x) { return (vf4){x, x, x, x}; }

/* Correctly rounded, as sqrtf is. */
static inline vf4 vf4_sqrt(vf4 x) {
#if defined(__SSE2__)
    return (vf4)_mm_sqrt_ps((__m128)x);
#elif defined(__aarch64__) && defined(__ARM_NEON)
    return (vf4)vsqrtq_f32((float32x4_t)x);
#else
    return (vf4){sqrtf(x[0]), sqrtf(x[1]), sqrtf(x[2]), sqrtf(x[3])};
#endif
}

/* m ? a : b, lane by lane (m from a comparison: all bits or none). */
static inline vf4 vf4_select(vi4 m, vf4 a, vf4 b) { return (vf4)(((vi4)a & m) | ((vi4)b & ~m)); }

static inline int vi4_any(vi4 m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }

/* Four floats from memory (any alignment). */
static inline vf4 vf4_load(const float *p) {
    vf4 v;
    memcpy(&v, p, sizeof v);
    return v;
}

/* Rows a, b, c, d become columns: afterwards a = (a0, b0, c0, d0) and so on.
 * Four fragments' records, loaded one per vector, become one vector per
 * field: moving bits, no arithmetic. */
static inline void vf4_transpose(vf4 *a, vf4 *b, vf4 *c, vf4 *d) {
#if defined(__SSE2__)
    __m128 ra = (__m128)*a, rb = (__m128)*b, rc = (__m128)*c, rd = (__m128)*d;
    _MM_TRANSPOSE4_PS(ra, rb, rc, rd); /* unpacks and moves: any SSE compiler */
    *a = (vf4)ra, *b = (vf4)rb, *c = (vf4)rc, *d = (vf4)rd;
#else
    vf4 r[4] = {*a, *b, *c, *d}, t[4];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            t[i][j] = r[j][i];
    *a = t[0], *b = t[1], *c = t[2], *d = t[3];
#endif
}

/* floorf, lane by lane, for every float (NaN excepted): below 2^23 in
 * magnitude the truncated integer, minus one where truncation went up; from
 * 2^23 on every float is an integer already. A zero result keeps x's sign,
 * as floorf(-0.0f) is -0.0f. */
static inline vf4 vf4_floor(vf4 x) {
    vi4 sign = {INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN};
    vf4 mag = (vf4)((vi4)x & ~sign);
    vi4 small = mag < vf4_splat(8388608.0f);        /* 2^23 */
    vf4 xs = vf4_select(small, x, vf4_splat(0.0f)); /* no out-of-range conversion */
    vf4 t = __builtin_convertvector(__builtin_convertvector(xs, vi4), vf4);
    t = vf4_select(t > xs, t - vf4_splat(1.0f), t);
    t = vf4_select(small, t, x);
    return (vf4)((vi4)t | ((vi4)x & sign & (t == vf4_splat(0.0f))));
}

/* Three floats from memory into lanes 0-2 (lane 3 is 0): a texel. */
static inline vf4 vf4_load3(const float *p) {
    vf4 v = {0.0f, 0.0f, 0.0f, 0.0f};
    memcpy(&v, p, 3 * sizeof(float));
    return v;
}

/* Bit i set where lane i of m is negative (its sign bit). */
static inline unsigned vi4_sign_bits(vi4 m) {
#if defined(__SSE2__)
    return (unsigned)_mm_movemask_ps((__m128)m);
#else
    return (unsigned)(m[0] < 0) | (unsigned)(m[1] < 0) << 1 | (unsigned)(m[2] < 0) << 2 |
           (unsigned)(m[3] < 0) << 3;
#endif
}

static inline v3x4 v3_splat(vec3s v) {
    return (v3x4){vf4_splat(v.x), vf4_splat(v.y), vf4_splat(v.z)};
}
static inline v3x4 v3_add(v3x4 a, v3x4 b) { return (v3x4){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline v3x4 v3_sub(v3x4 a, v3x4 b) { return (v3x4){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline v3x4 v3_mul(v3x4 a, v3x4 b) { return (v3x4){a.x * b.x, a.y * b.y, a.z * b.z}; }
static inline v3x4 v3_scale(v3x4 a, vf4 s) { return (v3x4){a.x * s, a.y * s, a.z * s}; }
static inline v3x4 v3_divs(v3x4 a, vf4 s) { return (v3x4){a.x / s, a.y / s, a.z / s}; }
/* glm_vec3_dot: (x·x' + y·y') + z·z' */
static inline vf4 v3_dot(v3x4 a, v3x4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/* glms_vec3_normalize: v · (1/|v|). Lanes with |v| < FLT_EPSILON are marked
 * in *odd instead of handled here — cglm versions disagree there (0.8 tests
 * |v| == 0, later ones |v| < FLT_EPSILON) — and the caller redoes those
 * fragments with the installed scalar functions. */
static inline v3x4 v3_normalize(v3x4 v, vi4 *odd) {
    vf4 norm = vf4_sqrt(v3_dot(v, v));
    *odd |= norm < FLT_EPSILON;
    vf4 s = vf4_splat(1.0f) / norm;
    return v3_scale(v, s);
}

#endif
