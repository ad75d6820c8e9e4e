/* fast/fast_rast_tile_tmp.h — the tile loop of fast_rast.c, one copy per
 * variant. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * fast_rast.c includes this once per rasterizing variant, as Mesa's
 * lp_rast_tri.c includes lp_rast_tri_tmp.h once per plane count: the walk
 * over a triangle's box is written here once, and each variant supplies
 * only what differs — its lanes and how a block's coverage is found. Define
 * before including:
 *
 *   TAG(name)    the variant's names: its prefix and name (x1_ ## name)
 *   TILE_ATTR    the generated function's storage and inlining
 *   TILE_PARAMS  the variant's constant parameters after a comma (or
 *                nothing), TILE_ARGS their names the same way: a constant
 *                in each inlined copy, so its tests fold away
 *
 * and, above the include, the variant's parts:
 *
 *   TAG(state)   what the variant computes once per triangle, with
 *                reject_x0/x1/y0/y1: the extreme sample offsets, in
 *                sub-pixels (block_outside's corners)
 *   bool TAG(begin)(fast_worker *, const fast_tri *, const tile_box *,
 *                   TAG(state) * TILE_PARAMS)
 *                false when the variant cannot draw this triangle (its edge
 *                values would leave its lanes' range)
 *   void TAG(block)(fast_worker *, const fast_tri *, const tile_box *,
 *                   TAG(state) *, int bx0, int by0, int bx1, int by1 TILE_PARAMS)
 *                one block of pixels [bx0, bx1] × [by0, by1] that is not
 *                wholly outside an edge
 *   void TAG(end)(fast_worker *, const fast_tri *, TAG(state) * TILE_PARAMS)
 *                after the last block (the counts kept in the state)
 *
 * It defines TAG(draw): the triangle's box within the tile, in BLOCK × BLOCK
 * blocks row by row (the order fragments are recorded in, which the
 * shading keeps), each skipped when it lies wholly outside one edge at every
 * sample position — unless the whole box is one block, where the test costs
 * more than it saves. False: TAG(begin) declined (draw with another variant).
 */

TILE_ATTR bool TAG(draw)(fast_worker *w, const fast_tri *r, const tile_box *box TILE_PARAMS) {
    TAG(state) s;
    if (!TAG(begin)(w, r, box, &s TILE_ARGS)) return false;
    const int x0 = box->x0, y0 = box->y0, x1 = box->x1, y1 = box->y1;
    bool small = (x1 - x0) < BLOCK && (y1 - y0) < BLOCK;
    for (int by0 = y0; by0 <= y1; by0 += BLOCK) {
        int by1 = by0 + BLOCK - 1 < y1 ? by0 + BLOCK - 1 : y1;
        for (int bx0 = x0; bx0 <= x1; bx0 += BLOCK) {
            int bx1 = bx0 + BLOCK - 1 < x1 ? bx0 + BLOCK - 1 : x1;
            if (!small && block_outside(r, bx0, by0, bx1, by1, s.reject_x0, s.reject_x1,
                                        s.reject_y0, s.reject_y1))
                continue;
            TAG(block)(w, r, box, &s, bx0, by0, bx1, by1 TILE_ARGS);
        }
    }
    TAG(end)(w, r, &s TILE_ARGS);
    return true;
}

#undef TAG
#undef TILE_ATTR
#undef TILE_PARAMS
#undef TILE_ARGS
