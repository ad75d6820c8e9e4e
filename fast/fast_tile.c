/* fast/fast_tile.c — one screen tile of the fast renderer, from clear to
 * image. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * A worker clears a tile-sized depth buffer (and colour buffer) that stays
 * in cache, draws the tile's bin — its triangles in submission order
 * (fast_rast.c) — shades the fragments still visible (fast_shade.c), and
 * resolves the tile straight into the image with the reference's resolve
 * (hw2's resolve_pixel, or its four-sample copy resolve4). A tile's pixels
 * depend only on its triangles in submission order, so the image is the same
 * for any thread count and any tile schedule.
 */
#include "fast_priv.h"

#include "rasterizer.h" /* hw2: resolve_pixel (the same resolve) */

#include <math.h> /* INFINITY */

/* Writing the image: 700² pixels × 12 bytes is larger than the caches, and an
 * ordinary store first reads the line it writes. Non-temporal stores write
 * whole lines without reading them (the same bytes land in the image); the
 * worker's final sfence orders them before the frame is handed back. Tile rows
 * start 16-byte aligned (64 pixels × 12 bytes = 48 × 16) when the image row
 * does; anything else is copied plainly. */
static void put_row(vec3s *dst, const vec3s *src, int count) {
#if defined(__SSE2__)
    if (((uintptr_t)dst & 15) == 0 && ((uintptr_t)src & 15) == 0 && count % 4 == 0) {
        const float *s = &src[0].x;
        float *d = &dst[0].x;
        for (int i = 0; i < 3 * count; i += 4)
            _mm_stream_ps(d + i, _mm_load_ps(s + i));
        return;
    }
#endif
    memcpy(dst, src, sizeof *dst * (size_t)count);
}

#if defined(__SSE2__)
/* One 16-byte store: non-temporal (stream: the image) or cached (the tile's
 * buffer, read back soon). */
static inline __attribute__((always_inline)) void store4(float *d, __m128 v, const bool stream) {
    if (stream)
        _mm_stream_ps(d, v);
    else
        _mm_store_ps(d, v);
}

/* count copies of c at dst, four pixels as three vectors (rgbr gbrg brgb);
 * count a multiple of 4, dst 16-byte aligned. */
static inline __attribute__((always_inline)) void fill_x4(vec3s *dst, vec3s c, int count,
                                                          const bool stream) {
    __m128 v0 = _mm_setr_ps(c.x, c.y, c.z, c.x), v1 = _mm_setr_ps(c.y, c.z, c.x, c.y),
           v2 = _mm_setr_ps(c.z, c.x, c.y, c.z);
    float *d = &dst[0].x;
    for (int i = 0; i < 3 * count; i += 12) {
        store4(d + i, v0, stream);
        store4(d + i + 4, v1, stream);
        store4(d + i + 8, v2, stream);
    }
}
#endif

/* count copies of c into the image */
static void fill_row(vec3s *dst, vec3s c, int count) {
#if defined(__SSE2__)
    if (((uintptr_t)dst & 15) == 0 && count % 4 == 0) {
        fill_x4(dst, c, count, true);
        return;
    }
#endif
    for (int i = 0; i < count; i++)
        dst[i] = c;
}

/* count copies of c into the tile's colour buffer; count is a multiple of 4
 * and the buffer 16-byte aligned (malloc's). */
static void fill_colour(vec3s *dst, vec3s c, int count) {
#if defined(__SSE2__)
    fill_x4(dst, c, count, false);
#else
    for (int i = 0; i < count; i++)
        dst[i] = c;
#endif
}

/* hw2's resolve_pixel (solution/rasterizer.c) for four samples, in lanes:
 * ((((0 + c0) + c1) + c2) + c3) · (1/4), glms_vec3_add's and _scale's
 * operations lane by lane. Stores 16 bytes at dst (the next pixel's x is
 * rewritten after) and reads 16 at the last sample (the colour buffer has
 * room). */
static inline void resolve4(vec3s *dst, const vec3s *c) {
    vf4 sum = vf4_splat(0.0f);
    for (int s = 0; s < 4; s++)
        sum = sum + vf4_load(&c[s].x);
    sum = sum * vf4_splat(1.0f / (float)4);
    memcpy(dst, &sum, sizeof sum);
}

/* fast_priv.h */
void fast_tile_draw(fast_worker *w, int tile) {
    fast_frame *fr = w->fr;
    const int n = fr->pattern.count;
    int tx = tile % fr->tiles_x, ty = tile / fr->tiles_x;
    int tx0 = tx * TILE, ty0 = ty * TILE;
    int tx1 = tx0 + TILE - 1 < fr->width - 1 ? tx0 + TILE - 1 : fr->width - 1;
    int ty1 = ty0 + TILE - 1 < fr->height - 1 ? ty0 + TILE - 1 : fr->height - 1;
    vec3s clear = fr->scene->clear_color;
    size_t first = fr->bin_start[tile], end = fr->bin_start[tile + 1];
    if (first == end) {
        /* No triangle touches the tile (most of the screen around a model):
         * every pixel resolves like one pixel of clear samples, so resolve
         * that one pixel and fill, without clearing a tile of samples. */
        vec3s c = clear;
        if (n > 1) {
            for (int s = 0; s < n; s++)
                w->color[s] = clear;
            ras_framebuffer one = {
                .width = 1, .height = 1, .samples = n, .color = w->color, .depth = w->depth};
            c = resolve_pixel(&one, 0, 0);
        }
        for (int y = ty0; y <= ty1; y++)
            fill_row(&fr->out->pixels[(size_t)(fr->height - 1 - y) * (size_t)fr->width + tx0], c,
                     tx1 - tx0 + 1);
        return;
    }
    fill_colour(w->color, clear, TILE * TILE * n);
    for (int i = 0; i < TILE * TILE * n; i++)
        w->depth[i] = INFINITY;
    for (size_t j = first; j < end; j++) {
        /* The records are visited in bin order, scattered in memory: fetch
         * the next ones while this one is drawn. */
        if (j + 2 < end) {
            const char *next = (const char *)fr->bin_tri[j + 2];
            __builtin_prefetch(next);
            __builtin_prefetch(next + 64);
            __builtin_prefetch(next + 128);
            __builtin_prefetch(next + 192);
            __builtin_prefetch(next + 256);
        }
        fast_rast_triangle(w, fr->bin_tri[j], tx0, ty0, tx1, ty1);
    }
    if (atomic_load(&fr->failed)) { /* out of memory: the frame is abandoned */
        w->nfrag = 0;
        return;
    }
    fast_shade_tile(w);
    /* Resolve: sample 0 with one sample (ras_resolve_frame), else the hw2
     * reference resolve_pixel on a framebuffer view of this tile. */
    ras_framebuffer view = {
        .width = TILE, .height = TILE, .samples = n, .color = w->color, .depth = w->depth};
    for (int y = ty0; y <= ty1; y++) {
        vec3s *dst = &fr->out->pixels[(size_t)(fr->height - 1 - y) * (size_t)fr->width];
        const vec3s *src = &w->color[(size_t)(y - ty0) * TILE * (size_t)n];
        if (n == 1) {
            put_row(&dst[tx0], src, tx1 - tx0 + 1);
        } else {
            /* resolve_pixel reads screen pixel (x, y) of the view at row
             * TILE-1-y: hand it the mirrored row. */
            _Alignas(16) vec3s row[TILE + 1]; /* + 1: resolve4's last store */
            if (n == 4)
                for (int x = tx0; x <= tx1; x++)
                    resolve4(&row[x - tx0],
                             &w->color[((size_t)(y - ty0) * TILE + (size_t)(x - tx0)) * 4]);
            else
                for (int x = tx0; x <= tx1; x++)
                    row[x - tx0] = resolve_pixel(&view, x - tx0, TILE - 1 - (y - ty0));
            put_row(&dst[tx0], row, tx1 - tx0 + 1);
        }
    }
}
