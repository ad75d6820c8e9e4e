/* test_reference_images.c — the committed reference images still match what
 * the reference programs render, and each one passes independent checks.
 *
 * For every row of the table: run build/bin/<program>_ref with the row's
 * arguments and `-o` into a temporary folder, compare with
 * tests/reference/<name>.png by the row's metric (common/app/ras_compare.h), and
 * run the row's sanity check — values worked out by hand or properties that
 * hold whatever the renderer does, so a wrong reference cannot bless itself.
 * Regenerate the references with `make reference-images` when a change to the
 * reference is intended; this test then tells you what changed.
 */
#include "ras_compare.h"
#include "ras_image.h"

#include <math.h>
#include <setjmp.h>
#include <spawn.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

extern char **environ;

typedef void (*sanity_fn)(const ras_image *img);

typedef struct reference_case {
    const char *name;    /* tests/reference/<name>.png */
    const char *program; /* in build/bin */
    const char *args[8]; /* NULL-terminated */
    ras_compare_kind kind;
    sanity_fn sanity;
} reference_case;

static bool is_white(vec3s c) { return c.x > 0.99f && c.y > 0.99f && c.z > 0.99f; }
static bool is_black(vec3s c) { return c.x == 0 && c.y == 0 && c.z == 0; }

/* Screen (x, y) → image (col, row) for a 700×700 frame. */
#define ROW(y) (700 - 1 - (y))

/* Is there a white pixel within 1 px of screen (x, y)? */
static bool white_near(const ras_image *img, float x, float y) {
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            int col = (int)x + dx, row = ROW((int)y + dy);
            if (col >= 0 && col < 700 && row >= 0 && row < 700 &&
                is_white(ras_image_get(img, col, row)))
                return true;
        }
    return false;
}

/* hw1 at 0°: the vertex (2,0,-2) is 7 units ahead: x_ndc = 2·cot(22.5°)/7 =
 * 0.68977, screen x = (1 + 0.68977)·350 = 591.4; the apex (0,2,-2) lands at
 * screen y = 591.4. So the base is the screen row y = 350 (image row 349)
 * from x ≈ 108.6 to 591.4, and the apex pixel is (350, 591) → row 108. */
static void sanity_hw1_r0(const ras_image *img) {
    if (!is_white(ras_image_get(img, 350, ROW(350))))
        fail_msg("hw1 r0: the base of the triangle should cross pixel (350, image row 349)");
    if (!is_white(ras_image_get(img, 591, ROW(350))) || !is_white(ras_image_get(img, 109, ROW(350))))
        fail_msg("hw1 r0: the base should run from x = 109 to x = 591 on image row 349");
    if (!is_black(ras_image_get(img, 592 + 2, ROW(350))) || !is_black(ras_image_get(img, 105, ROW(350))))
        fail_msg("hw1 r0: the base should stop at x = 591 and start at x = 109");
    if (!is_white(ras_image_get(img, 350, ROW(591))))
        fail_msg("hw1 r0: the apex should be at screen (350, 591), image row 108");
    if (!is_black(ras_image_get(img, 350, ROW(400))))
        fail_msg("hw1 r0: a wireframe has a black interior");
    long white = 0;
    for (int i = 0; i < img->width * img->height; i++) white += is_white(img->pixels[i]);
    /* Three Bresenham lines: the base spans x 108..591 (484 pixels), each side
     * runs 241 px across and 241 up (242 pixels), and the 3 corners are shared:
     * 484 + 242 + 242 - 3 = 965, give or take the rounding of the ends. */
    if (white < 960 || white > 970)
        fail_msg("hw1 r0: expected about 965 white pixels (three edges), got %ld", white);
}

/* hw1 at 20°: the triangle is turned counter-clockwise, so its base's right
 * end rises: the rotated (2,0,-2) is (1.879, 0.684, -2) → screen
 * (350 + 350·1.879·k, 350 + 350·0.684·k) with k = cot(22.5°)/7 = 0.34489,
 * i.e. (576.8, 432.6). */
static void sanity_hw1_r20(const ras_image *img) {
    if (!white_near(img, 576.8f, 432.6f))
        fail_msg("hw1 r20: the rotated corner should be near screen (576.8, 432.6)");
    if (!is_black(ras_image_get(img, 591, ROW(350))))
        fail_msg("hw1 r20: the unrotated corner (591, 350) must be empty after rotating");
}

/* 60° about y: (x, y, z) → (x cos + z sin, y, −x sin + z cos). The apex
 * (0, 2, −2) goes to (−1.732, 2, −1), 6 units ahead: screen
 * (350 − 350·1.732·c/6, 350 + 350·2·c/6) with c = cot(22.5°) = 2.41421 →
 * (106.1, 631.6). The corner (2, 0, −2) goes to (−0.732, 0, −2.732) → screen
 * (270.0, 350). The third corner lands off-screen (x ≈ −191): the line to it
 * is clipped at the left border. */
static void sanity_hw1_axis_y60(const ras_image *img) {
    if (!white_near(img, 106.1f, 631.6f))
        fail_msg("hw1 axis y: the apex should land at screen (106.1, 631.6)");
    if (!white_near(img, 270.0f, 350.0f))
        fail_msg("hw1 axis y: the corner (2,0,-2) should land at screen (270.0, 350)");
    bool left_edge = false;
    for (int row = 0; row < 700; row++) left_edge |= is_white(ras_image_get(img, 0, row));
    if (!left_edge) fail_msg("hw1 axis y: the edges to the off-screen corner must reach x = 0");
}

static const reference_case cases[] = {
    {"hw1_r0", "hw1_transform_ref", {"-r", "0", NULL}, RAS_COMPARE_EXACT, sanity_hw1_r0},
    {"hw1_r20", "hw1_transform_ref", {"-r", "20", NULL}, RAS_COMPARE_EXACT, sanity_hw1_r20},
    {"hw1_axis_y60", "hw1_transform_ref", {"--axis", "0,1,0", "-r", "60", NULL},
     RAS_COMPARE_EXACT, sanity_hw1_axis_y60},
};

/* Runs program with args plus `-o out`; returns the exit status (-1 if it could not start). */
static int run_program(const char *program, const char *const *args, const char *out) {
    char path[1024];
    snprintf(path, sizeof path, "%s/bin/%s", RAS_BINARY_DIR, program);
    const char *argv[16] = {path};
    int n = 1;
    for (int i = 0; args[i]; i++) argv[n++] = args[i];
    argv[n++] = "-o";
    argv[n++] = out;
    argv[n] = NULL;
    pid_t pid;
    if (posix_spawn(&pid, path, NULL, NULL, (char *const *)argv, environ) != 0) return -1;
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

static void check_case(const reference_case *c) {
    char dir[] = "/tmp/raster101-ref-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char out[256], ref[1024], diff[300];
    snprintf(out, sizeof out, "%s/%s.png", dir, c->name);
    snprintf(ref, sizeof ref, "%s/tests/reference/%s.png", RAS_SOURCE_DIR, c->name);
    int status = run_program(c->program, c->args, out);
    if (status != 0) fail_msg("%s: %s exited with status %d", c->name, c->program, status);
    ras_error err;
    ras_image *got = ras_image_load(out, &err);
    if (!got) fail_msg("%s: the program wrote no readable image: %s", c->name, err.msg);
    ras_image *expected = ras_image_load(ref, &err);
    if (!expected)
        fail_msg("%s: no reference image (%s); run `make reference-images` and commit it",
                 c->name, err.msg);
    c->sanity(expected); /* the committed reference passes the independent checks */
    ras_compare_options opt = ras_compare_defaults(c->kind);
    ras_compare_result res;
    if (!ras_compare_images(expected, got, &opt, &res, &err)) fail_msg("%s: %s", c->name, err.msg);
    if (!res.pass) {
        ras_image *heat = ras_compare_heatmap(expected, got, c->kind, &err);
        snprintf(diff, sizeof diff, "%s/%s-diff.png", dir, c->name);
        if (heat) ras_image_save(heat, diff, &err);
        ras_image_destroy(heat);
        fail_msg("%s: the reference program no longer renders tests/reference/%s.png: %s "
                 "(difference image: %s). If the change is intended, run `make "
                 "reference-images`.",
                 c->name, c->name, res.summary, diff);
    }
    remove(out);
    rmdir(dir);
    ras_image_destroy(got);
    ras_image_destroy(expected);
}

static void test_reference_image(void **state) { check_case((const reference_case *)*state); }

int main(void) {
    enum { N = sizeof cases / sizeof *cases };
    struct CMUnitTest tests[N];
    for (int i = 0; i < N; i++)
        tests[i] = (struct CMUnitTest){.name = cases[i].name,
                                       .test_func = test_reference_image,
                                       .initial_state = (void *)&cases[i]};
    return cmocka_run_group_tests_name("reference_images", tests, NULL, NULL);
}
