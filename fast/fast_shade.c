/* fast/fast_shade.c — the fast renderer's shading of a tile. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * While a tile is drawn (fast_rast.c), the fragments that pass a depth test
 * are recorded, with the samples they own (fast_priv.h's fast_defer_*).
 * When it is drawn, a sample's colour is that of the last fragment to pass
 * its depth test, so only the fragments that still own a sample are shaded
 * — four at a time where the shader has a four-lane form (fast_shade_x4.c),
 * else one at a time by shade() below, the core fragment stage's arithmetic (stage5_fragment.c) —
 * and the others are counted as if shaded: the counters stay the teaching
 * pipeline's, which shades every fragment that passes a depth test.
 *
 * Which form a shader has is declared in one table, shader_table.
 */
#include "fast_priv.h"

#include <math.h> /* isfinite, nextafterf, pow, powf */

/* ---- the shaders the fast path knows ------------------------------------- */

/* One row per hw3 shader (scene.h: the core's from normal on; flat has none). The four-lane forms
 * read the varyings of `needs`; the lit ones need a light to light them with (unlit, Blinn-Phong is
 * the ambient term alone: one at a time); the texture shader's trilinear lookups need each
 * fragment's uv derivatives (one at a time). */
static const fast_shader shader_table[RAS_SHADER_COUNT] = {
    [RAS_SHADER_NORMAL] = {.batch = BATCH_NORMAL,
                           .needs = RAS_VARYING_NORMAL,
                           .any_filter = true,
                           .scalar = SCALAR_REFERENCE},
    [RAS_SHADER_PHONG] = {.batch = BATCH_PHONG,
                          .needs = RAS_VARYING_NORMAL | RAS_VARYING_VIEW_POS,
                          .lit = true,
                          .any_filter = true,
                          .scalar = SCALAR_LIT_COLOUR},
    [RAS_SHADER_TEXTURE] = {.batch = BATCH_TEXTURE,
                            .needs = RAS_VARYING_NORMAL | RAS_VARYING_VIEW_POS | RAS_VARYING_UV,
                            .lit = true,
                            .any_filter = false,
                            .scalar = SCALAR_LIT_TEXTURE},
    [RAS_SHADER_BUMP] = {.batch = BATCH_BUMP,
                         .needs = RAS_VARYING_NORMAL | RAS_VARYING_UV,
                         .any_filter = true,
                         .scalar = SCALAR_REFERENCE},
    [RAS_SHADER_DISPLACEMENT] = {.batch = BATCH_DISPLACEMENT,
                                 .needs =
                                     RAS_VARYING_NORMAL | RAS_VARYING_VIEW_POS | RAS_VARYING_UV,
                                 .lit = true,
                                 .any_filter = true,
                                 .scalar = SCALAR_REFERENCE},
};

const fast_shader *fast_shade_find(ras_scene_shader shader) {
    return shader >= RAS_SHADER_NORMAL && shader < RAS_SHADER_COUNT ? &shader_table[shader] : NULL;
}

int fast_shade_batch(const fast_shader *shader, const hw3_render_options *opt,
                     const hw3_frame *setup) {
    if ((setup->varyings & shader->needs) != shader->needs) return BATCH_NONE;
    if (shader->lit && setup->payload.light_count == 0) return BATCH_NONE;
    if (!shader->any_filter && opt->filter == FILTER_TRILINEAR) return BATCH_NONE;
    return shader->batch;
}

/* ---- one fragment at a time: ras_fragment_stage_shade, same arithmetic ---- */

/* perspective_correct_barycentric (solution/shading.c), inlined; w: the
 * corners' clip w. */
static inline vec3s persp_bary(const float w[3], vec3s bs) {
    vec3s b = {{bs.x / w[0], bs.y / w[1], bs.z / w[2]}};
    float sum = b.x + b.y + b.z;
    if (!(sum > 0.0f) || !isfinite(sum)) return bs;
    return glms_vec3_scale(b, 1.0f / sum);
}

/* The reference's interpolation of a varying (a0·b.x + a1·b.y + a2·b.z per
 * component, in that order: glms_vec3_scale then two glms_vec3_muladds, or
 * the same sums written out) from the record's packed varyings, float `at`
 * on (0 normal, 3 view position, 6 uv). */
static inline vec3s interp3(vec3s b, const float attr[3][8], int at) {
    vec3s r;
    for (int c = 0; c < 3; c++)
        r.raw[c] = attr[0][at + c] * b.x + attr[1][at + c] * b.y + attr[2][at + c] * b.z;
    return r;
}
static inline vec2s interp2(vec3s b, const float attr[3][8], int at) {
    return (vec2s){{attr[0][at] * b.x + attr[1][at] * b.y + attr[2][at] * b.z,
                    attr[0][at + 1] * b.x + attr[1][at + 1] * b.y + attr[2][at + 1] * b.z}};
}

/* powf(x, p) is +0 for 0 <= x <= fast_spec_zero(p): x <= 2^(-151/p) (rounded
 * down) gives x^p <= 2^-151, a quarter of the smallest subnormal float, so the
 * exact power rounds to +0, and powf, whose error is far below a factor of 2,
 * returns +0 too. -1 (never) when p < 1 or p is not finite. The one bound of
 * the scalar and the four-lane Blinn-Phong (frame.spec_zero, per object). */
float fast_spec_zero(float p) {
    if (!(p >= 1.0f) || !isfinite(p)) return -1.0f;
    return nextafterf((float)pow(2.0, -151.0 / p), 0.0f);
}

/* blinn_phong_lighting (solution/shading.c) with the same float operations in
 * the same order, except that powf is not called where its result is certainly
 * +0 (x <= spec_zero: fast_spec_zero), and 0·anything added to the colour adds
 * nothing. The plain shader pays powf's slow underflow path on most of the
 * surface (n·h < 0.56 underflows at p = 150). */
static vec3s blinn_phong(const fragment_shader_payload *payload, vec3s kd, vec3s point,
                         vec3s normal, float spec_zero) {
    if (payload->counters && payload->light_count > 0) { /* ambient alone is no lighting work */
        payload->counters->stages_run |= RAS_STAGE_LIGHTING;
        payload->counters->lighting_evaluations += (uint64_t)payload->light_count;
    }
    vec3s n = glms_vec3_normalize(normal);
    vec3s v = glms_vec3_normalize(glms_vec3_negate(point));
    vec3s color = glms_vec3_mul(payload->ka, payload->ambient_intensity);
    for (int i = 0; i < payload->light_count; i++) {
        const light *L = &payload->lights[i];
        vec3s to_light = glms_vec3_sub(L->position, point);
        float r2 = glms_vec3_dot(to_light, to_light);
        vec3s l = glms_vec3_normalize(to_light);
        vec3s h = glms_vec3_normalize(glms_vec3_add(l, v));
        vec3s irradiance = glms_vec3_divs(L->intensity, r2);
        float nl = glms_vec3_dot(n, l), nh = glms_vec3_dot(n, h);
        float diffuse = nl > 0.0f ? nl : 0.0f; /* fmaxf(0, x): NaN gives 0 too */
        float x = nh > 0.0f ? nh : 0.0f;
        float specular = x <= spec_zero ? 0.0f : powf(x, payload->p);
        color = glms_vec3_add(color, glms_vec3_scale(glms_vec3_mul(kd, irradiance), diffuse));
        color =
            glms_vec3_add(color, glms_vec3_scale(glms_vec3_mul(payload->ks, irradiance), specular));
    }
    return color;
}

static vec3s shade(fast_worker *w, const fast_tri *r, vec3s bary) {
    const fast_frame *fr = w->fr;
    fragment_shader_payload *pay = &w->pay[r->object];
    bool persp = fr->perspective;
    unsigned vary = fr->varyings;
    vec3s b = persp ? persp_bary(r->w3, bary) : bary;
    if (vary & RAS_VARYING_NORMAL) pay->normal = glms_vec3_normalize(interp3(b, r->attr, 0));
    if (vary & RAS_VARYING_VIEW_POS) pay->view_pos = interp3(b, r->attr, 3);
    if (vary & RAS_VARYING_UV) {
        pay->uv = interp2(b, r->attr, 6);
        if (pay->filter == FILTER_TRILINEAR) {
            /* scene.c's bary_gradients and finite difference */
            const vec4s *v = r->v;
            float area2 = (v[1].x - v[0].x) * (v[2].y - v[0].y) -
                          (v[2].x - v[0].x) * (v[1].y - v[0].y); /* ras_triangle_area2 */
            float inv = area2 != 0.0f ? 1.0f / area2 : 0.0f;
            vec3s d_dx = {
                {-(v[2].y - v[1].y) * inv, -(v[0].y - v[2].y) * inv, -(v[1].y - v[0].y) * inv}};
            vec3s d_dy = {
                {(v[2].x - v[1].x) * inv, (v[0].x - v[2].x) * inv, (v[1].x - v[0].x) * inv}};
            vec3s bx = glms_vec3_add(bary, d_dx), by = glms_vec3_add(bary, d_dy);
            vec2s uv_x = interp2(persp ? persp_bary(r->w3, bx) : bx, r->attr, 6);
            vec2s uv_y = interp2(persp ? persp_bary(r->w3, by) : by, r->attr, 6);
            pay->duv_dx = glms_vec2_sub(uv_x, pay->uv);
            pay->duv_dy = glms_vec2_sub(uv_y, pay->uv);
        }
    }
    w->k.varyings_interpolated += fr->varyings_per_fragment;
    w->k.fragments_shaded++;
    switch (fr->shader->scalar) {
    case SCALAR_LIT_COLOUR: /* phong_fragment_shader */
        return blinn_phong(pay, pay->color, pay->view_pos, pay->normal, fr->spec_zero[r->object]);
    case SCALAR_LIT_TEXTURE: { /* texture_fragment_shader */
        vec3s kd = pay->texture ? texture_sample(pay, pay->texture, pay->uv) : pay->color;
        return blinn_phong(pay, kd, pay->view_pos, pay->normal, fr->spec_zero[r->object]);
    }
    }
    return fr->setup->shader(pay);
}

/* shade() without counting: for a lane redone by the scalar path after the
 * vector path has already counted it. */
vec3s fast_shade_silent(fast_worker *w, const fast_tri *r, vec3s bary) {
    ras_counters saved = w->k; /* the payloads' counters point at w->k too */
    vec3s c = shade(w, r, bary);
    w->k = saved;
    return c;
}

/* ---- the tile's fragments ------------------------------------------------ */

/* Queue a fragment for shading: its colour goes to the samples `mask` of
 * tile sample index `base`. */
static inline void queue_fragment(fast_worker *w, const fast_queued *f) {
    /* one object's fragments (one material) per queue */
    if (w->qn == QUEUE || (w->qn && w->q[0]->object != f->object)) fast_shade_x4_flush(w);
    w->q[w->qn++] = f;
    w->shaded++;
}

/* What shading `count` fragments of object o adds to the counters
 * (shade_prepare, shade_finish, texture_sample), for fragments
 * fast_shade_tile need not shade: the counters stay the teaching pipeline's,
 * which shades every fragment that passes a depth test. */
static void count_unshaded(fast_worker *w, int o, uint64_t count) {
    const fast_frame *fr = w->fr;
    const fragment_shader_payload *pay = &w->pay[o];
    w->k.fragments_shaded += count;
    w->k.varyings_interpolated += fr->varyings_per_fragment * count;
    if (fr->batch == BATCH_BUMP) fast_count_heights(pay, 3, count);
    if (fr->batch == BATCH_DISPLACEMENT) fast_count_heights(pay, 3, count);
    if (fr->batch == BATCH_NORMAL || fr->batch == BATCH_BUMP || !pay->counters) return;
    pay->counters->stages_run |= RAS_STAGE_LIGHTING;
    pay->counters->lighting_evaluations += (uint64_t)pay->light_count * count;
    if (fr->batch == BATCH_TEXTURE && pay->texture) {
        pay->counters->stages_run |= RAS_STAGE_TEXTURE;
        pay->counters->texels_fetched += (pay->filter == FILTER_BILINEAR ? 4 : 1) * count;
    }
}

/* What shading one fragment of f's object added to w->k since `before`. */
static void learn_counts(fast_worker *w, const fast_queued *f, const ras_counters *before) {
    ras_counters *d = &w->per_fragment[f->r->object];
    d->stages_run = w->k.stages_run;
    d->fragments_shaded = w->k.fragments_shaded - before->fragments_shaded;
    d->varyings_interpolated = w->k.varyings_interpolated - before->varyings_interpolated;
    d->texels_fetched = w->k.texels_fetched - before->texels_fetched;
    d->lighting_evaluations = w->k.lighting_evaluations - before->lighting_evaluations;
    w->per_fragment_known[f->r->object] = true;
}

/* shade() for a deferred fragment of an unbatched shader, its colour into
 * the samples it owns; the first one of each object teaches what a fragment
 * adds to the counters. */
static void shade_scalar(fast_worker *w, const fast_queued *f) {
    ras_counters before = w->k;
    vec3s c = shade(w, f->r, f->bary);
    w->shaded++;
    if (!w->per_fragment_known[f->r->object]) learn_counts(w, f, &before);
    for (uint64_t m = f->mask; m; m &= m - 1)
        w->color[f->base + __builtin_ctzll(m)] = c;
}

/* An unbatched fragment that owns no sample: what one shaded fragment of its
 * object added to the counters. When none has been shaded yet, this one is
 * shaded as a probe — its colour unused, its counts learnt and then taken
 * back, so that the counters, and the count of fragments really shaded for
 * their colour, do not depend on which worker met which fragment first. */
static void count_unshaded_scalar(fast_worker *w, const fast_queued *f) {
    int o = f->r->object;
    if (!w->per_fragment_known[o]) {
        ras_counters saved = w->k;
        (void)shade(w, f->r, f->bary);
        learn_counts(w, f, &saved);
        w->k = saved;
    }
    const ras_counters *d = &w->per_fragment[o];
    w->k.stages_run |= d->stages_run;
    w->k.fragments_shaded += d->fragments_shaded;
    w->k.varyings_interpolated += d->varyings_interpolated;
    w->k.texels_fetched += d->texels_fetched;
    w->k.lighting_evaluations += d->lighting_evaluations;
}

/* The end of a tile in per_pixel mode: frags[s] is the last fragment that
 * passed the depth test at pixel s (written where the depth is below +inf),
 * the one whose colour the immediate order leaves there. Each is shaded
 * once; shading is a pure function of the fragment, so the order (here the
 * pixels', not the drawing's) changes no colour. The ones they replaced are
 * counted as shaded (hidden[]) when the worker is done. */
static void shade_pixels(fast_worker *w) {
    const vf4 inf = vf4_splat(INFINITY);
    _Static_assert(TILE == 64, "shade_pixels keeps a tile row in a 64-bit mask");
    for (int row = 0; row < TILE * TILE; row += TILE) {
        /* a row's 64 pixels into one mask first: one loop exit per row, not
         * one per four pixels */
        uint64_t drawn = 0;
        for (int x = 0; x < TILE; x += 4)
            drawn |= (uint64_t)vi4_sign_bits(vf4_load(&w->depth[row + x]) == inf) << x;
        for (drawn = ~drawn; drawn; drawn &= drawn - 1) {
            int s = row + __builtin_ctzll(drawn);
            fast_queued *f = &w->frags[s];
            f->base = s;
            f->object = f->r->object;
            f->mask = 1;
            w->hidden[f->object]--;
            queue_fragment(w, f);
        }
    }
    fast_shade_x4_flush(w);
}

/* The end of a tile: a sample's colour is that of the last fragment to pass
 * its depth test (strict <, in drawing order), so each sample's owner gives
 * it. Fragments that own no sample any more (hidden by later ones: about 40 %
 * of the cow's) are counted but not shaded; the others are shaded in
 * drawing order, for exactly the samples they own. Every colour is what the
 * immediate order would have left there, bit for bit. */
void fast_shade_tile(fast_worker *w) {
    if (w->fr->per_pixel) {
        shade_pixels(w);
        return;
    }
    const int n = w->fr->pattern.count;
    const bool batch = w->fr->batch != BATCH_NONE;
    /* With one sample a fragment (mask 1) still owns its sample when it is
     * the sample's owner: checked in the loop below. Otherwise the owners
     * give each fragment its samples, four samples at a time: none written
     * (most of a tile around a model), or with 4x one pixel's four owned by
     * one fragment. */
    if (n > 1)
        for (size_t i = 0; i < w->nfrag; i++)
            w->frags[i].mask = 0;
    const vf4 inf = vf4_splat(INFINITY);
    for (int s0 = 0; n > 1 && s0 < TILE * TILE * n; s0 += 4) {
        unsigned clear = vi4_sign_bits(vf4_load(&w->depth[s0]) == inf);
        if (clear == 0xF) continue; /* no fragment passed here */
        const int32_t *o = &w->owner[s0];
        if (n == 4 && !clear && o[0] == o[1] && o[0] == o[2] && o[0] == o[3]) {
            fast_queued *f = &w->frags[o[0]];
            f->mask |= (uint64_t)0xF << (s0 - f->base);
            continue;
        }
        for (int k = 0; k < 4; k++) {
            if (clear >> k & 1) continue;
            fast_queued *f = &w->frags[o[k]];
            f->mask |= (uint64_t)1 << (s0 + k - f->base);
        }
    }
    for (size_t i = 0; i < w->nfrag; i++) {
        fast_queued *f = &w->frags[i];
        if (n == 1 && w->owner[f->base] != (int32_t)i) f->mask = 0;
        if (batch && f->mask)
            queue_fragment(w, f);
        else if (batch)
            w->hidden[f->object]++; /* counted when the worker is done */
        else if (f->mask)
            shade_scalar(w, f);
        else
            count_unshaded_scalar(w, f);
    }
    w->nfrag = 0;
    fast_shade_x4_flush(w);
}

void fast_shade_count_hidden(fast_worker *w) {
    for (int o = 0; o < w->fr->scene->object_count; o++)
        if (w->hidden[o]) count_unshaded(w, o, (uint64_t)w->hidden[o]);
}
