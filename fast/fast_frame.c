/* fast/fast_frame.c — one frame of the fast renderer: the plan, the fast_worker
 * threads, the counters. RASTER101-SOLUTION
 * This marker must never appear in a student handout.
 *
 * fast_render sets the frame up as hw3_render does (hw3_frame_setup, the
 * same function) and draws it on N workers (pthreads; the calling thread is
 * one of them). Each worker takes chunks of setup (fast_setup.c) from shared
 * counters, the last to finish bins the records, and then each takes tiles
 * (fast_tile.c) from a shared counter until none is left. Chunks and tiles
 * are claimed, so any number of threads (even one whose siblings failed to
 * start) finishes them; a thread that runs out waits for the stragglers.
 *
 * No full-screen framebuffer exists: memory is the image plus, per worker,
 * one tile buffer, its sample-owner array and a fragment list that grows to
 * the busiest tile's fragments.
 */
#include "fast_priv.h"

#include <math.h>    /* llround */
#include <pthread.h> /* pthread_create, pthread_join */
#include <stdlib.h>  /* malloc, free, getenv, atoi */
#include <sched.h>   /* sched_yield */
#include <unistd.h>  /* sysconf */

#define MAX_THREADS 64

/* ---- the workers ----------------------------------------------------------- */

static void wait_for(atomic_int *v, int target) {
    while (atomic_load(v) < target)
        sched_yield();
}

static void *worker_main(void *arg) {
    fast_worker *w = arg;
    fast_frame *fr = w->fr;
    for (int c; (c = atomic_fetch_add(&fr->next_vchunk, 1)) < fr->vchunks;) {
        fast_setup_vertices(fr, c);
        atomic_fetch_add(&fr->vchunks_done, 1);
    }
    wait_for(&fr->vchunks_done, fr->vchunks);
    for (int c; (c = atomic_fetch_add(&fr->next_tchunk, 1)) < fr->tchunks;) {
        fast_setup_triangles(w, c);
        /* whoever finishes the last chunk bins */
        if (atomic_fetch_add(&fr->tchunks_done, 1) == fr->tchunks - 1) {
            fr->t_setup = ras_now_ms();
            if (!atomic_load(&fr->failed)) fast_setup_bin(fr);
            atomic_store(&fr->binned, 1);
        }
    }
    wait_for(&fr->binned, 1);
    int tiles = fr->tiles_x * fr->tiles_y;
    while (!atomic_load(&fr->failed)) {
        int tile = atomic_fetch_add(&fr->next_tile, 1);
        if (tile >= tiles) break;
        fast_tile_draw(w, tile);
    }
    fast_shade_count_hidden(w);
#if defined(__SSE2__)
    _mm_sfence(); /* put_row's and fill_row's streaming stores, before the join */
#endif
    return NULL;
}

/* ---- the frame ------------------------------------------------------------- */

/* What the fast path draws: one of hw3's shaders, no culling, z01 depth, at
 * most FAST_MAX_OBJECTS objects, and no frame --dump keeps buffers of (the
 * teaching pipeline's, its fragment stage's among them). */
static bool accepts(const ras_scene *scene, const hw3_render_options *opt) {
    return fast_shade_find(opt->shader) && opt->cull == RAS_CULL_NONE &&
           opt->depth == RAS_DEPTH_Z01 && scene->object_count <= FAST_MAX_OBJECTS && !opt->dump_dir;
}

static int thread_count(const fast_settings *s) {
    int n = s ? s->threads : 0;
    if (n <= 0) {
        const char *env = getenv("RAS_THREADS");
        n = env ? atoi(env) : 0;
    }
    if (n <= 0) n = (int)sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > MAX_THREADS ? MAX_THREADS : n;
}

/* The frame's sample offsets in sub-pixels (the centre's at [n]), the box
 * they span (block rejection's corners), the sample at the centre if there is
 * one, and what shading needs per frame. */
static void plan_samples(fast_frame *fr) {
    const ras_scene *scene = fr->scene;
    const ras_sample_pattern *pattern = &fr->pattern;
    const int n = pattern->count;
    for (int s = 0; s <= n; s++) {
        vec2s o = s < n ? pattern->offsets[s] : (vec2s){{0.5f, 0.5f}};
        fr->off_x[s] = llround((double)o.x * SUBPIXEL_ONE);
        fr->off_y[s] = llround((double)o.y * SUBPIXEL_ONE);
    }
    for (int o = 0; o < scene->object_count; o++)
        fr->spec_zero[o] = fast_spec_zero(scene->objects[o].material.p);
    fr->omin_x = fr->omax_x = fr->off_x[0];
    fr->omin_y = fr->omax_y = fr->off_y[0];
    for (int k = 1; k <= n; k++) {
        fr->omin_x = fr->off_x[k] < fr->omin_x ? fr->off_x[k] : fr->omin_x;
        fr->omax_x = fr->off_x[k] > fr->omax_x ? fr->off_x[k] : fr->omax_x;
        fr->omin_y = fr->off_y[k] < fr->omin_y ? fr->off_y[k] : fr->omin_y;
        fr->omax_y = fr->off_y[k] > fr->omax_y ? fr->off_y[k] : fr->omax_y;
    }
    fr->centre_sample = -1;
    for (int s = 0; s < n && fr->centre_sample < 0; s++)
        if (fr->off_x[s] == fr->off_x[n] && fr->off_y[s] == fr->off_y[n]) fr->centre_sample = s;
    unsigned v = fr->setup->varyings;
    fr->varyings_per_fragment = (uint64_t)(!!(v & RAS_VARYING_NORMAL) +
                                           !!(v & RAS_VARYING_VIEW_POS) + !!(v & RAS_VARYING_UV));
}

/* One worker's tile buffers, fragment list and sample owners, and its
 * payloads (one per object, counting into the worker's counters). False: out
 * of memory (free_frame frees what was allocated). */
static bool worker_init(fast_worker *w, fast_frame *fr, size_t tile_samples) {
    const ras_scene *scene = fr->scene;
    w->fr = fr;
    w->color = malloc((tile_samples + 2) * sizeof *w->color); /* + 2: resolve4 */
    /* DEPTH_PAD more: the first is x1_draw's spare slot for the
     * depth of a fragment that failed the test (written, never read) */
    w->depth = malloc((tile_samples + DEPTH_PAD) * sizeof *w->depth);
    /* room for a tile's worth of fragments; fast_defer_fragment grows it. One
     * more: per_pixel's spare record for fragments that fail the depth test */
    w->frag_cap = (size_t)TILE * TILE;
    w->frags = malloc((w->frag_cap + 1) * sizeof *w->frags);
    w->owner = malloc(tile_samples * sizeof *w->owner);
    if (!(w->color && w->depth && w->frags && w->owner)) return false;
    for (int i = 0; i < DEPTH_PAD; i++)
        w->depth[tile_samples + i] = INFINITY;
    for (int o = 0; o < scene->object_count; o++) {
        fragment_shader_payload *p = &w->pay[o];
        *p = fr->setup->payload;
        hw3_object_material(scene, fr->assets, o, p);
        p->counters = &w->k;
    }
    return true;
}

/* The calling thread is worker 0; the others get threads of their own
 * (fewer workers, if some fail to start, is only slower). False: the fast_frame
 * failed (out of memory somewhere). */
static bool run_workers(fast_frame *fr, fast_worker *workers, int threads) {
    int started = 1;
    for (; started < threads; started++)
        if (pthread_create(&workers[started].thread, NULL, worker_main, &workers[started])) break;
    worker_main(&workers[0]);
    for (int i = 1; i < started; i++)
        pthread_join(workers[i].thread, NULL);
    return !atomic_load(&fr->failed);
}

/* A worker's counts added into k: setup's (ks: the triangles) or the
 * tiles' (k: samples, fragments, shading); each leaves the other's zero. */
static void add_work(ras_counters *k, const ras_counters *s) {
    k->stages_run |= s->stages_run;
    k->triangles_in += s->triangles_in;
    k->triangles_rejected_nonfinite += s->triangles_rejected_nonfinite;
    k->triangles_rejected_range += s->triangles_rejected_range;
    k->triangles_clipped_away += s->triangles_clipped_away;
    k->triangles_clip_split += s->triangles_clip_split;
    k->triangles_rasterized += s->triangles_rasterized;
    k->triangles_degenerate += s->triangles_degenerate;
    k->samples_tested += s->samples_tested;
    k->samples_covered += s->samples_covered;
    k->depth_tests_passed += s->depth_tests_passed;
    k->fragments_shaded += s->fragments_shaded;
    k->varyings_interpolated += s->varyings_interpolated;
    k->texels_fetched += s->texels_fetched;
    k->lighting_evaluations += s->lighting_evaluations;
}

/* The workers' counters, setup's and the tiles', added into k, with the
 * buffers they used; *settings->shaded gets the fragments really shaded. */
static void sum_counters(const fast_frame *fr, const fast_worker *workers, int threads,
                         size_t tile_samples, const fast_settings *settings, ras_counters *k) {
    for (int i = 0; i < threads; i++) {
        add_work(k, &workers[i].ks);
        add_work(k, &workers[i].k);
    }
    if (fr->pattern.count > 1) k->stages_run |= RAS_STAGE_RESOLVE;
    k->buffer_bytes = (size_t)threads * tile_samples * (sizeof(vec3s) + sizeof(float));
    uint64_t shaded = 0;
    for (int i = 0; i < threads; i++) {
        shaded += workers[i].shaded;
        k->buffer_bytes +=
            tile_samples * sizeof(int32_t) + workers[i].frag_cap * sizeof(fast_queued);
    }
    if (settings && settings->shaded) *settings->shaded = shaded;
}

/* Everything draw_frame allocated (NULL-safe: a frame that failed halfway). */
static void free_frame(fast_frame *fr, fast_worker *workers, int threads) {
    for (int i = 0; workers && i < threads; i++) {
        free(workers[i].color);
        free(workers[i].depth);
        free(workers[i].frags);
        free(workers[i].owner);
    }
    free(workers);
    for (int i = 0; fr->lists && i < fr->tchunks; i++)
        free(fr->lists[i].tri);
    free(fr->lists);
    free(fr->bin_start);
    free(fr->bin_tri);
    free(fr->clip);
    free(fr->screen);
    free(fr->vflags);
    free(fr->voutcode);
    free(fr->clip_base);
    free(fr->tri_first);
    free(fr->vchunk_obj);
    free(fr->vchunk_start);
}

/* One frame: plan, set up and bin (worker_main, shared out), tiles on the
 * workers, then the counters and times as the teaching pipeline reports them. */
static bool draw_frame(fast_frame *fr, const hw3_render_options *opt, const fast_settings *settings,
                       ras_counters *k, ras_error *err) {
    const ras_scene *scene = fr->scene;
    int width = scene->width, height = scene->height;
    if (width < 1 || height < 1 || width > RAS_IMAGE_MAX_SIDE || height > RAS_IMAGE_MAX_SIDE)
        return ras_error_set(err, "frame size %dx%d is out of range", width, height);
    ras_sample_pattern pattern =
        opt->aa == RAS_AA_NONE ? ras_sample_pattern_center() : opt->pattern;
    if (pattern.count < 1 || pattern.count > RAS_MAX_SAMPLES)
        return ras_error_set(err,
                             "the sample pattern is empty: build it with ras_sample_pattern_make");
    double t0 = ras_now_ms();
    fr->width = width, fr->height = height;
    fr->ssaa = opt->aa == RAS_AA_SSAA, fr->pattern = pattern;
    fr->varyings = fr->setup->varyings;
    fr->tiles_x = (width + TILE - 1) / TILE, fr->tiles_y = (height + TILE - 1) / TILE;
    plan_samples(fr);
    fr->shader = fast_shade_find(opt->shader);
    fr->batch = fast_shade_batch(fr->shader, opt, fr->setup);
    /* frags holds a tile's pixels from the start (worker_init) */
    fr->per_pixel = fr->pattern.count == 1 && fr->batch != BATCH_NONE;
    int tiles = fr->tiles_x * fr->tiles_y;
    int threads = thread_count(settings);
    if (threads > tiles) threads = tiles;
    fast_worker *workers = calloc((size_t)threads, sizeof *workers);
    bool ok = fast_setup_plan(fr, k) && workers;
    atomic_init(&fr->next_vchunk, 0);
    atomic_init(&fr->vchunks_done, 0);
    atomic_init(&fr->next_tchunk, 0);
    atomic_init(&fr->tchunks_done, 0);
    atomic_init(&fr->binned, fr->tchunks == 0); /* no triangles: the bins are empty */
    atomic_init(&fr->failed, false);
    atomic_init(&fr->next_tile, 0);
    fr->t_setup = t0;
    size_t tile_samples = (size_t)TILE * TILE * (size_t)fr->pattern.count;
    for (int i = 0; ok && i < threads; i++)
        ok = worker_init(&workers[i], fr, tile_samples);
    if (ok) ok = run_workers(fr, workers, threads);
    if (ok)
        sum_counters(fr, workers, threads, tile_samples, settings, k);
    else
        ras_error_set(err, "out of memory drawing %zu triangles",
                      fr->tri_first ? fr->tri_first[scene->object_count] : (size_t)0);
    free_frame(fr, workers, threads);
    double t1 = fr->t_setup, t2 = ras_now_ms();
    k->ms_vertex += t1 - t0;
    k->ms_raster += t2 - t1;
    k->ms_total += t2 - t0;
    return ok;
}

int fast_render(const ras_scene *scene, ras_scene_assets *assets, const hw3_render_options *opt,
                const fast_settings *settings, ras_image *out, ras_counters *stats,
                ras_error *err) {
    if (!accepts(scene, opt)) return -1;
    /* every object's model matrix, hw3_render's (the frame's turn about y included) */
    mat4s *models = malloc((size_t)scene->object_count * sizeof *models);
    if (!models) return -1;
    for (int i = 0; i < scene->object_count; i++)
        models[i] = ras_scene_model_matrix(&scene->objects[i],
                                           (ras_scene_spin){.turn_y_deg = opt->angle_deg});
    /* the same set-up as the teaching frame's: the mip levels, the fragment
     * stage, the view and the projection */
    hw3_frame setup;
    if (!hw3_frame_setup(scene, assets, opt, &setup, err)) {
        free(models);
        return 0;
    }
    fast_frame fr = {.scene = scene,
                     .assets = assets,
                     .setup = &setup,
                     .perspective = !opt->affine,
                     .out = out,
                     .models = models,
                     .view = setup.view,
                     .projection = setup.projection};
    ras_counters k = {.mip_levels_built = setup.mip_levels,
                      .stages_run = setup.mip_levels ? RAS_STAGE_MIPMAP : 0u};
    bool ok = draw_frame(&fr, opt, settings, &k, err);
    if (stats) *stats = k;
    free(models);
    return ok;
}
