/* grade_assignment.c — one assignment graded (grade_assignment.h). */
#include "grade_assignment.h"

#include "grade_attribute.h"
#include "grade_base.h"
#include "grade_images.h"
#include "grade_intake.h"
#include "grade_report.h"
#include "grade_results.h"
#include "grade_run.h"
#include "grade_tests.h"

#include <stdlib.h>
#include <string.h>

void grading_begin(grading *gr, const grader *g, int n_assignments) {
    memset(gr, 0, sizeof *gr);
    gr->as = calloc((size_t)n_assignments + 1, sizeof *gr->as);
    gr->integration.graded = true;
    gr->integration.id = xstrdup("integration");
    gr->integration.title = xstrdup("Your assignments together: the whole chain");
    gr->integration_points = num_or(g->rubric, "integration_points_per_image", 0);
}

bool grading_wants(const grader *g, const char *id) {
    bool wanted = g->n_only == 0;
    for (int i = 0; i < g->n_only; i++)
        wanted |= !strcmp(g->only[i], id);
    return wanted;
}

/* An assignment's sandboxed runs in one batch: all[0, n_tests) the tests'
 * chunks (each a worker, then its replay), started first; then
 * runs[0, n_img) the graded runs, on the assignment's own code where it
 * could be linked (sealed[i]); then the whole-chain runs of the images with
 * points (the integration part), whole_at[i] (-1: none). One batch, so that
 * no core waits while another finishes a chunk. */
typedef struct batch {
    job *all, *runs;
    int n_tests, n_runs;
    int *whole_at;
    bool *sealed;
    bool
        has_own; /* an own-code link was made for the assignment: each image with points needs it */
} batch;

/* The integration item of an image with points whose whole-chain check
 * could not be made (`why`, e.g. "your hw2 code does not compile"): it
 * scores 0 and stays in the total, which never shrinks silently. */
static void integration_not_run(const grader *g, grading *gr, const cJSON *img, const char *id,
                                const char *status, const char *why) {
    if (num_or(img, "points", g->default_points) <= 0) return;
    item *it = add_item(&gr->integration);
    char label[300];
    fmt(label, sizeof label, "%s image %s, your whole chain", id, str_or(img, "name", "image"));
    it->name = xstrdup(label);
    it->is_image = true;
    it->max_score = gr->integration_points;
    it->status = xstrdup(status);
    sbuf r = {0}, o = {0};
    sb_printf(&r, "not run: %s", why);
    sb_printf(&o,
              "0 of %g: this point is for this image rendered by your whole chain, given when "
              "your %s code also renders it with the reference of the earlier assignments; %s, "
              "so that check could not be run",
              gr->integration_points, id, why);
    it->reason = r.s;
    it->output = o.s;
    junit_case(it, gr->integration.id, NULL);
}

/* The batch's jobs: the tests' chunks (tests, n_tests of them), then each
 * image's runs, its variant's arguments drawn for this grading. */
static void batch_make(grader *g, const char *id, const cJSON *images, const test_batch *tests,
                       int n_tests, batch *b) {
    int n_img = cJSON_GetArraySize(images);
    b->n_tests = n_tests;
    job *all = b->all = calloc((size_t)n_tests + 2 * (size_t)n_img + 1, sizeof *all);
    if (!all) abort();
    for (int c = 0; c < n_tests; c++)
        all[c] = tests->workers[c];
    job *runs = b->runs = all + n_tests;
    int *whole_at = b->whole_at = calloc((size_t)n_img + 1, sizeof *whole_at);
    bool *sealed = b->sealed = calloc((size_t)n_img + 1, sizeof *sealed);
    if (!runs || !whole_at || !sealed) abort();
    char own[4096] = "";
    bool has_own = b->has_own = own_dir(g, id, NULL, own, sizeof own);
    int i = 0, n_runs = n_img;
    for (const cJSON *img = images ? images->child : NULL; img; img = img->next, i++) {
        /* a variant's arguments, drawn for this grading (variant_args) */
        runs[i].args = variant_args(g, img);
        char p[4300];
        fmt(p, sizeof p, "%s/bin/%s", own, str_or(img, "program", ""));
        sealed[i] = has_own && file_exists(p);
        image_job(g, img, &runs[i], sealed[i] ? own : NULL, "");
        whole_at[i] = -1;
        if (sealed[i] && num_or(img, "points", g->default_points) > 0) {
            whole_at[i] = n_runs;
            runs[n_runs].args = runs[i].args;
            image_job(g, img, &runs[n_runs++], NULL, ".whole");
        }
    }
    b->n_runs = n_runs;
}

/* Each picture's verdict, and of its whole-chain run, attributed when it
 * loses points. */
static void judge_pictures(grader *g, grading *gr, assignment_result *a, const cJSON *asg,
                           const char *dir, const batch *b) {
    const char *id = a->id;
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(asg, "images");
    const char *crash_hint = str_or(asg, "crash_hint", "look for an out-of-bounds access");
    char why[300];
    fmt(why, sizeof why,
        "your %s code could not be linked with the reference of the earlier assignments "
        "(the first lines of this report say why and what to do)",
        id);
    int i = 0;
    for (const cJSON *img = images ? images->child : NULL; img; img = img->next, i++) {
        double t_img = now_s();
        bool own_passed =
            grade_image(g, a, img, dir, id, crash_hint, &b->runs[i], b->sealed[i], false);
        profile(str_or(img, "name", "image"), "pic", t_img);
        if (b->has_own && !b->sealed[i]) {
            integration_not_run(g, gr, img, id, "FAIL", why);
            if (!a->note || !strstr(a->note, "could not be linked")) {
                free(a->note);
                sbuf n = {0};
                sb_printf(&n,
                          "%s: its pictures ran on your whole chain, and their "
                          "whole-chain points score 0",
                          why);
                a->note = n.s;
            }
        }
        if (b->whole_at[i] < 0) continue;
        double t_whole = now_s();
        bool whole_passed = grade_image(g, &gr->integration, img, dir, id,
                                        "a crash in one of your assignments (the "
                                        "attribution below says which)",
                                        &b->runs[b->whole_at[i]], false, true);
        profile(str_or(img, "name", "image"), "pic+", t_whole);
        item *it = &gr->integration.items[gr->integration.n_items - 1];
        it->score = it->score > 0 ? gr->integration_points : 0;
        it->max_score = gr->integration_points;
        if (!whole_passed || it->score < it->max_score)
            attribute_image(g, it, img, dir, id, &b->runs[i], own_passed, gr->as, gr->n);
    }
}

/* An assignment that is built: its tests and pictures run in one batch, then
 * judged. */
static void run_and_judge(grader *g, grading *gr, assignment_result *a, const cJSON *asg,
                          const char *dir, const char *test_bin) {
    const char *id = a->id;
    a->graded = true;
    test_batch tests;
    bool has_tests = false;
    if (file_exists(test_bin))
        has_tests = tests_prepare(g, a, dir, &tests);
    else
        a->note = xstrdup("no test program built; images only");
    int n_tests = has_tests ? tests.chunks : 0;
    batch b;
    batch_make(g, id, cJSON_GetObjectItemCaseSensitive(asg, "images"), &tests, n_tests, &b);
    double t_runs = now_s();
    run_jobs(b.all, n_tests + b.n_runs, g->jobs);
    profile("tests and images: sandboxed runs", id, t_runs);
    if (has_tests) {
        for (int c = 0; c < n_tests; c++)
            tests.workers[c].rr = b.all[c].rr; /* (the replays' are set in place) */
        int from = a->n_items;
        bool sealed = tests.own[0] != '\0';
        tests_finish(g, a, asg, &tests);
        if (sealed) tests_explain_sealed(g, a, asg, dir, from);
    }
    double t_judge = now_s();
    judge_pictures(g, gr, a, asg, dir, &b);
    profile("images: judged", id, t_judge);
    free(b.all);
    free(b.whole_at);
    free(b.sealed);
}

/* Whether the student's build has a program of one of asg's images. */
static bool any_program(const grader *g, const cJSON *asg) {
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(asg, "images");
    bool any = false;
    for (const cJSON *img = images ? images->child : NULL; img; img = img->next) {
        char p[4096];
        fmt(p, sizeof p, "%s/bin/%s", g->student_build, str_or(img, "program", ""));
        any |= file_exists(p);
    }
    return any;
}

/* An assignment graded: lost to the build (--build-failed), not in this
 * build yet, or run and judged; then its score and where to look. */
void grade_assignment(grader *g, grading *gr, const cJSON *asg) {
    const char *id = str_or(asg, "id", "?");
    assignment_result *a = &gr->as[gr->n++];
    int integration_from = gr->integration.n_items;
    a->id = xstrdup(id);
    a->title = xstrdup(str_or(asg, "title", ""));
    double t0 = now_s();
    char dir[4096], test_bin[4096];
    fmt(dir, sizeof dir, "%s/%s", g->out, id);
    fmt(test_bin, sizeof test_bin, "%s/tests/test_%s_worker", g->student_build, id);
    const char *failed_log = NULL;
    for (int i = 0; i < g->n_failed; i++)
        if (!strcmp(g->failed_hw[i], id)) failed_log = g->failed_log[i];
    bool built_program = any_program(g, asg);
    mkdirs(dir);
    if (failed_log || (!file_exists(test_bin) && !built_program)) {
        /* nothing of it runs: neither do its images' whole-chain checks */
        char own[4096], why[200];
        fmt(why, sizeof why, "your %s code %s", id,
            failed_log ? "does not compile" : "was not built");
        const cJSON *images = cJSON_GetObjectItemCaseSensitive(asg, "images");
        if (own_dir(g, id, NULL, own, sizeof own))
            for (const cJSON *img = images ? images->child : NULL; img; img = img->next)
                integration_not_run(g, gr, img, id, failed_log ? "BUILD" : "FAIL", why);
    }
    if (failed_log) {
        a->graded = true;
        a->note = xstrdup("the code does not compile");
        mark_build_failed(g, a, asg, failed_log);
    } else if (!file_exists(test_bin) && !built_program) {
        a->note = xstrdup("not in this build yet");
    } else {
        run_and_judge(g, gr, a, asg, dir, test_bin);
    }
    add_up(a);
    mark_where(a, 0, asg, false);
    mark_where(&gr->integration, integration_from, asg, true);
    a->seconds = now_s() - t0;
    gr->total += a->score;
    gr->max_total += a->max_score;
}

void grading_end(const grader *g, grading *gr) {
    assignment_result *integration = &gr->integration;
    if (integration->n_items > 0) {
        integration->note = xstrdup("the images with points again, rendered by your whole chain "
                                    "(your hw1 → hw2 → hw3); a failure says whose code causes it");
        add_up(integration);
        gr->total += integration->score;
        gr->max_total += integration->max_score;
        char idir[4200];
        fmt(idir, sizeof idir, "%s/integration", g->out);
        mkdirs(idir);
        gr->as[gr->n++] = *integration;
    } else {
        free(integration->items);
        free(integration->id);
        free(integration->title);
    }
}
