/* bench_accuracy_depth.c — section 5 of the accuracy report: two planes δ
 * apart near the far plane, the fraction of pixels where the farther wins,
 * in the pipeline with each depth format (timed) and, as what-ifs from the
 * exact depths, for encodings the pipeline has no mode for. bench_accuracy.h.
 */
#include "bench_accuracy.h"
#include "rasterizer.h" /* hw2 reference: rasterize_triangle */
#include "transform.h"  /* hw1 reference: get_projection_matrix */

#include <math.h>   /* tan, llround, INFINITY, NAN */
#include <stdio.h>  /* snprintf, fprintf */
#include <stdlib.h> /* exit */

/* ---- section 5: depth precision -------------------------------------------------- */

const double DEPTH_DELTAS[DEPTH_DELTA_COUNT] = {0.0001, 0.0003, 0.001, 0.003, 0.01, 0.1};
/* The two pipeline formats (stage3_setup.h) first, rendered and timed; then
 * what-ifs for storage the pipeline has no mode for. Float view depth w is
 * not among them: w is not affine on screen, so a rasterizer can only get it
 * as 1/(interpolated 1/w), which orders exactly as inverse_w does. */
const char *const DEPTH_ENCODINGS[DEPTH_ENCODING_COUNT] = {
    "pipeline z01: (1−z_ndc)/2, 0 = near",          "pipeline inverse_w: −near/w, −1 = near",
    "what-if: float z01, exact depth rounded once", "what-if: 24-bit unorm z01",
    "what-if: 24-bit unorm near/w (reversed-z)",
};
static const ras_depth_format DEPTH_FORMATS[DEPTH_PIPELINE_COUNT] = {RAS_DEPTH_Z01,
                                                                     RAS_DEPTH_INV_W};

/* The pipeline's depth of view distance d: (1 − z_ndc)/2 of the GAMES101
 * projection, i.e. f(d − n) / (d (f − n)). */
static double depth01(double d) {
    return DEPTH_FAR * (d - ACC_Z_NEAR) / (d * (DEPTH_FAR - ACC_Z_NEAR));
}

/* A plane tilted away from the camera: view depth 30 at the bottom of the
 * screen to 49 at the top, overscanned; `shift` moves it farther along -z. */
static acc_quad depth_plane(double shift) {
    double t = tan(ACC_FOV_DEG * RAS_PI / 360.0), d0 = 30, d1 = 49, o = 1.1;
    acc_quad q = {.p = {{-o * d0 * t, -o * d0 * t, -d0 - shift},
                        {o * d0 * t, -o * d0 * t, -d0 - shift},
                        {o * d1 * t, o * d1 * t, -d1 - shift},
                        {-o * d1 * t, o * d1 * t, -d1 - shift}}};
    return q;
}

void depth_precision(void) {
    const int size = acc_opt.quick ? 96 : 256;
    mat4s proj = get_projection_matrix(ACC_FOV_DEG, 1, ACC_Z_NEAR, (float)DEPTH_FAR);
    ras_image *img[DEPTH_PIPELINE_COUNT];
    for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++) {
        img[e] = ras_image_create(size, size, NULL);
        acc_die_oom(img[e]);
    }
    for (int di = 0; di < DEPTH_DELTA_COUNT; di++) {
        double delta = DEPTH_DELTAS[di];
        char scene[40];
        snprintf(scene, sizeof scene, "delta = %g", delta);
        acc_quad qa = depth_plane(0), qb = depth_plane(delta);
        ras_mesh *near = truth_quad_mesh(&qa), *far = truth_quad_mesh(&qb);
        for (int i = 0; i < 4; i++) {
            near->colors[i] = (vec3s){{1, 0, 0}};
            far->colors[i] = (vec3s){{0, 0, 1}};
        }
        /* The farther plane first: on a tie the nearer one (drawn second)
         * fails the "less than" test — the case that shows the precision. */
        ras_mesh *order[2] = {far, near};
        acc_progress("depth / %s", scene);
        /* Both formats timed in one group (interleaved frame by frame), so
         * their time ratio survives load on the machine. */
        acc_timed t[DEPTH_PIPELINE_COUNT];
        for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++) {
            ras_pipeline *p = acc_make_pipeline(size, size, RAS_AA_NONE, RAS_PATTERN_ORDERED, 1,
                                                rasterize_triangle, RAS_VARYING_COLOR, NULL, NULL,
                                                (vec3s){{0, 0, 0}});
            /* acc_make_pipeline builds z01; the format is a field of the config
             * that ras_pipeline_create copies, so rebuild with it set. */
            if (DEPTH_FORMATS[e] != RAS_DEPTH_Z01) {
                ras_pipeline_config cfg = p->config;
                cfg.depth = DEPTH_FORMATS[e];
                cfg.z_near = ACC_Z_NEAR;
                ras_pipeline_destroy(p);
                ras_error err = {{0}};
                p = ras_pipeline_create(&cfg, &err);
                if (!p) {
                    fprintf(stderr, "bench_accuracy: %s\n", err.msg);
                    exit(2);
                }
            }
            t[e].f = (acc_mesh_frame){.p = p,
                                      .meshes = order,
                                      .mesh_count = 2,
                                      .view = *acc_identity(),
                                      .projection = proj,
                                      .img = img[e]};
            t[e].r = acc_new_row("depth", scene, DEPTH_ENCODINGS[e]);
        }
        acc_time_group(t, DEPTH_PIPELINE_COUNT);
        for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++)
            acc_draw_mesh_frame(&t[e].f);
        long wrong_e[DEPTH_ENCODING_COUNT] = {0}, n = 0;
        for (int y = 0; y < size; y++)
            for (int x = 0; x < size; x++) {
                double d[3], da, db, uv[2];
                truth_pixel_ray(x, y, 0.5, 0.5, size, d);
                if (!truth_quad_hit(&qa, d, &da, uv) || !truth_quad_hit(&qb, d, &db, uv)) continue;
                n++;
                for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++) {
                    vec3s c = img[e]->pixels[(size - 1 - y) * size + x];
                    wrong_e[e] += c.z > c.x;
                }
                /* What-ifs from the exact depths: the nearer must be strictly
                 * better after storage rounding (ties go to the first drawn). */
                float za = (float)depth01(da), zb = (float)depth01(db);
                wrong_e[2] += !(za < zb);
                double qa24 = llround(depth01(da) * 16777215.0),
                       qb24 = llround(depth01(db) * 16777215.0);
                wrong_e[3] += !(qa24 < qb24);
                double ra24 = llround(ACC_Z_NEAR / da * 16777215.0),
                       rb24 = llround(ACC_Z_NEAR / db * 16777215.0);
                wrong_e[4] += !(ra24 > rb24);
            }
        for (int e = 0; e < DEPTH_ENCODING_COUNT; e++) {
            acc_row *re =
                e < DEPTH_PIPELINE_COUNT ? t[e].r : acc_new_row("depth", scene, DEPTH_ENCODINGS[e]);
            re->wrong = n ? (double)wrong_e[e] / n : NAN;
        }
        for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++)
            ras_pipeline_destroy(t[e].f.p);
        ras_mesh_destroy(near), ras_mesh_destroy(far);
    }
    for (int e = 0; e < DEPTH_PIPELINE_COUNT; e++)
        ras_image_destroy(img[e]);
}

void depth_check(void) {
    double prev = INFINITY;
    for (int di = 0; di < DEPTH_DELTA_COUNT; di++) {
        char scene[40];
        snprintf(scene, sizeof scene, "delta = %g", DEPTH_DELTAS[di]);
        acc_row *p = acc_find_row("depth", scene, DEPTH_ENCODINGS[0]);
        acc_row *inv = acc_find_row("depth", scene, DEPTH_ENCODINGS[1]);
        acc_check(p->wrong <= prev + 0.02,
                  "depth %s: wrong fraction %.4f does not grow with the gap", scene, p->wrong);
        acc_check(inv->wrong <= p->wrong,
                  "depth %s: pipeline inverse_w wrong fraction (%.4f) <= pipeline z01 (%.4f)",
                  scene, inv->wrong, p->wrong);
        prev = p->wrong;
    }
    /* The point of inverse_w: the smallest gap resolves where z01 fails. */
    acc_row *z_small = acc_find_row("depth", "delta = 0.0001", DEPTH_ENCODINGS[0]);
    acc_row *i_small = acc_find_row("depth", "delta = 0.0001", DEPTH_ENCODINGS[1]);
    acc_check(i_small->wrong < 0.01 && z_small->wrong > 0.5,
              "depth delta = 0.0001: inverse_w resolves (%.4f wrong), z01 does not (%.4f wrong)",
              i_small->wrong, z_small->wrong);
    acc_row *big = acc_find_row("depth", "delta = 0.1", DEPTH_ENCODINGS[0]);
    acc_check(big->wrong < 0.01, "depth delta = 0.1: the pipeline resolves (%.4f wrong)",
              big->wrong);
}
