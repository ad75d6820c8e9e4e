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

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

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
    /* then refs[0, n_refs): the variants' reference renders the cache lacks */
    job *refs;
    int n_refs;
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
    /* the tests' chunks, two runs an image, and an image's reference render */
    job *all = b->all = calloc((size_t)n_tests + 3 * (size_t)n_img + 1, sizeof *all);
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
    b->refs = runs + n_runs;
    b->n_refs = reference_jobs(g, images, runs, n_img, b->refs, n_img);
}

/* What every picture's judging shares. */
typedef struct judging {
    grader *g;
    grading *gr;
    assignment_result *a;
    const char *dir, *crash_hint, *why;
    const batch *b;
} judging;

/* Image i's verdict, and of its whole-chain run, attributed when it loses
 * points. */
static void judge_one(const judging *J, const cJSON *img, int i) {
    grader *g = J->g;
    grading *gr = J->gr;
    assignment_result *a = J->a;
    const batch *b = J->b;
    const char *id = a->id;
    double t_img = now_s();
    bool own_passed =
        grade_image(g, a, img, J->dir, id, J->crash_hint, &b->runs[i], b->sealed[i], false);
    profile(str_or(img, "name", "image"), "pic", t_img);
    if (b->has_own && !b->sealed[i]) {
        integration_not_run(g, gr, img, id, "FAIL", J->why);
        if (!a->note || !strstr(a->note, "could not be linked")) {
            free(a->note);
            sbuf n = {0};
            sb_printf(&n,
                      "%s: its pictures ran on your whole chain, and their "
                      "whole-chain points score 0",
                      J->why);
            a->note = n.s;
        }
    }
    if (b->whole_at[i] < 0) return;
    double t_whole = now_s();
    bool whole_passed = grade_image(g, &gr->integration, img, J->dir, id,
                                    "a crash in one of your assignments (the "
                                    "attribution below says which)",
                                    &b->runs[b->whole_at[i]], false, true);
    profile(str_or(img, "name", "image"), "pic+", t_whole);
    item *it = &gr->integration.items[gr->integration.n_items - 1];
    it->score = it->score > 0 ? gr->integration_points : 0;
    it->max_score = gr->integration_points;
    if ((!whole_passed || it->score < it->max_score) && !images_speculation_stops())
        attribute_image(g, it, img, J->dir, id, &b->runs[i], &b->runs[b->whole_at[i]], own_passed,
                        gr->as, gr->n);
}

/* ---------------------------------------------------------------- judging ahead */

/* The pictures are judged ahead, up to --jobs at once, each in a child that
 * writes its items to a file of the trusted work folder (logs/, 0700); the
 * grader then takes them in the images' order, so the items, and every
 * report made of them, are those of a judging one after another. A picture
 * whose judging would start something the grading counts or numbers (the
 * buffers' evidence, the attribution: a failure's) gives up ahead and is
 * judged again there, in order, in the grader: a working submission's
 * pictures, which need none, cost a share of the cores each. */
static void put_str(FILE *f, const char *s) {
    long long n = s ? (long long)strlen(s) : -1;
    fwrite(&n, sizeof n, 1, f);
    if (s) fwrite(s, 1, (size_t)n, f);
}

/* a string put_str wrote (NULL for none), *ok false on a short read */
static char *get_str(FILE *f, bool *ok) {
    long long n;
    if (fread(&n, sizeof n, 1, f) != 1 || n < -1 || n > (64ll << 20)) return *ok = false, NULL;
    if (n < 0) return NULL;
    char *s = malloc((size_t)n + 1);
    if (!s) abort();
    if (fread(s, 1, (size_t)n, f) != (size_t)n) {
        free(s);
        return *ok = false, NULL;
    }
    s[n] = '\0';
    return s;
}

static void put_item(FILE *f, const item *it) {
    int flags[4] = {it->is_image, it->counted, it->passed, it->default_weight};
    double sc[2] = {it->score, it->max_score};
    fwrite(flags, sizeof flags, 1, f);
    fwrite(sc, sizeof sc, 1, f);
    fwrite(&it->where, sizeof it->where, 1, f); /* the rubric's, at the same address */
    const char *strs[] = {it->name,     it->status,       it->reason,  it->output,   it->xml,
                          it->img_expected, it->img_got, it->img_diff, it->img_crop,
                          it->buf_name, it->buf_ref,      it->buf_got, it->buf_diff};
    for (size_t k = 0; k < sizeof strs / sizeof *strs; k++)
        put_str(f, strs[k]);
}

static bool get_item(FILE *f, item *it) {
    int flags[4];
    double sc[2];
    memset(it, 0, sizeof *it);
    if (fread(flags, sizeof flags, 1, f) != 1 || fread(sc, sizeof sc, 1, f) != 1 ||
        fread(&it->where, sizeof it->where, 1, f) != 1)
        return false;
    it->is_image = flags[0], it->counted = flags[1], it->passed = flags[2];
    it->default_weight = flags[3];
    it->score = sc[0], it->max_score = sc[1];
    bool ok = true;
    char **strs[] = {&it->name,     &it->status,       &it->reason,  &it->output,   &it->xml,
                     &it->img_expected, &it->img_got, &it->img_diff, &it->img_crop,
                     &it->buf_name, &it->buf_ref,      &it->buf_got, &it->buf_diff};
    for (size_t k = 0; k < sizeof strs / sizeof *strs; k++)
        *strs[k] = get_str(f, &ok);
    if (!ok) item_free(it);
    return ok;
}

static void ahead_path(const judging *J, int i, char *buf, size_t size) {
    fmt(buf, size, "%s/logs/ahead-%s-%d.items", J->g->work, J->a->id, i);
}

/* In the child: image i judged ahead, its items (and the note, when it set
 * one) written for the grader; nothing written when it gave up. */
static void judge_ahead(const judging *J, const cJSON *img, int i) {
    int from_a = J->a->n_items, from_int = J->gr->integration.n_items;
    const char *note = J->a->note;
    images_speculate(true);
    judge_one(J, img, i);
    if (images_gave_up()) return;
    char path[4400], tmp[4500];
    ahead_path(J, i, path, sizeof path);
    fmt(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "wb");
    if (!f) return;
    int counts[2] = {J->a->n_items - from_a, J->gr->integration.n_items - from_int};
    fwrite(counts, sizeof counts, 1, f);
    for (int k = from_a; k < J->a->n_items; k++)
        put_item(f, &J->a->items[k]);
    for (int k = from_int; k < J->gr->integration.n_items; k++)
        put_item(f, &J->gr->integration.items[k]);
    put_str(f, J->a->note != note ? J->a->note : NULL);
    if (fclose(f) == 0) rename(tmp, path); /* whole, or not there */
    unlink(tmp);
}

/* In the grader: image i's items as judged ahead, appended; false (nothing
 * taken) when there are none to take. */
static bool take_ahead(const judging *J, int i) {
    char path[4400];
    ahead_path(J, i, path, sizeof path);
    FILE *f = fopen(path, "rb");
    unlink(path);
    if (!f) return false;
    int counts[2];
    bool ok = fread(counts, sizeof counts, 1, f) == 1 && counts[0] >= 0 && counts[0] <= 4 &&
              counts[1] >= 0 && counts[1] <= 4;
    item got[8];
    int n = 0;
    while (ok && n < counts[0] + counts[1])
        if (get_item(f, &got[n]))
            n++;
        else
            ok = false;
    char *note = ok ? get_str(f, &ok) : NULL;
    fclose(f);
    if (!ok) {
        for (int k = 0; k < n; k++)
            item_free(&got[k]);
        free(note);
        return false;
    }
    for (int k = 0; k < n; k++)
        *add_item(k < counts[0] ? J->a : &J->gr->integration) = got[k];
    if (note) {
        free(J->a->note);
        J->a->note = note;
    }
    /* what the child left for a judging again: a sealed run's log goes now */
    if (J->b->sealed[i]) unlink(J->b->runs[i].out_path);
    return true;
}

/* Each picture judged ahead, --jobs at once (fork, wait). */
static void judge_all_ahead(const judging *J, const cJSON *images, int n) {
    pid_t *pids = calloc((size_t)n + 1, sizeof *pids);
    if (!pids) abort();
    int active = 0, i = 0;
    for (const cJSON *img = images->child; img; img = img->next, i++) {
        while (active >= J->g->jobs && wait(NULL) > 0)
            active--;
        fflush(stdout);
        fflush(stderr);
        pid_t pid = fork();
        if (pid == 0) {
            judge_ahead(J, img, i);
            fflush(stderr);
            _exit(0);
        }
        if (pid > 0) active++;
        pids[i] = pid;
    }
    for (int k = 0; k < n; k++)
        if (pids[k] > 0) waitpid(pids[k], NULL, 0);
    free(pids);
}

/* Each picture's verdict, and of its whole-chain run, attributed when it
 * loses points: judged ahead where it can be, taken in order. */
static void judge_pictures(grader *g, grading *gr, assignment_result *a, const cJSON *asg,
                           const char *dir, const batch *b) {
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(asg, "images");
    char why[300];
    fmt(why, sizeof why,
        "your %s code could not be linked with the reference of the earlier assignments "
        "(the first lines of this report say why and what to do)",
        a->id);
    judging J = {g, gr, a, dir, str_or(asg, "crash_hint", "look for an out-of-bounds access"), why,
                 b};
    int n = cJSON_GetArraySize(images);
    bool ahead = g->jobs > 1 && n > 1 && g->work && !getenv("RAS_GRADE_NO_AHEAD");
    if (ahead) {
        char logs[4200];
        fmt(logs, sizeof logs, "%s/logs", g->work);
        trusted_dir(logs);
        judge_all_ahead(&J, images, n);
    }
    int i = 0;
    for (const cJSON *img = images ? images->child : NULL; img; img = img->next, i++)
        if (!(ahead && take_ahead(&J, i))) judge_one(&J, img, i);
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
    run_jobs(b.all, n_tests + b.n_runs + b.n_refs, g->jobs);
    reference_jobs_done(g, b.refs, b.n_refs);
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
    bool chain_unlinked = false;
    for (int i = 0; i < g->n_failed; i++)
        if (!strcmp(g->failed_hw[i], id))
            failed_log = g->failed_log[i], chain_unlinked = g->chain_unlinked[i];
    bool built_program = any_program(g, asg);
    mkdirs(dir);
    /* Its own file compiled; only its link with the student's earlier files
     * failed (a helper two of them define): graded on its own code, linked
     * with the earlier references, where that link was made; the whole
     * chain's pictures then find no program, and the attribution says why. */
    char own[4096], own_worker[4300] = "";
    if (chain_unlinked && own_dir(g, id, NULL, own, sizeof own))
        fmt(own_worker, sizeof own_worker, "%s/tests/test_%s_worker", own, id);
    bool on_own = *own_worker && file_exists(own_worker);
    if (!on_own && (failed_log || (!file_exists(test_bin) && !built_program))) {
        /* nothing of it runs: neither do its images' whole-chain checks */
        char why[200];
        fmt(why, sizeof why, "your %s code %s", id,
            chain_unlinked ? "does not link with your earlier files"
            : failed_log   ? "does not compile"
                           : "was not built");
        const cJSON *images = cJSON_GetObjectItemCaseSensitive(asg, "images");
        if (own_dir(g, id, NULL, own, sizeof own))
            for (const cJSON *img = images ? images->child : NULL; img; img = img->next)
                integration_not_run(g, gr, img, id, failed_log ? "BUILD" : "FAIL", why);
    }
    if (on_own) {
        /* an earlier assignment that does not compile, or else the link */
        const char *broken = NULL;
        int number = 0, earlier = 0;
        sscanf(id, "hw%d", &number);
        for (int i = 0; i < g->n_failed && !broken; i++)
            if (!g->chain_unlinked[i] && sscanf(g->failed_hw[i], "hw%d", &earlier) == 1 &&
                earlier < number)
                broken = g->failed_hw[i];
        char *said = broken ? xstrdup("") : first_link_error(failed_log);
        sbuf n = {0};
        if (broken)
            sb_printf(&n, "your %s code compiles, but your %s does not (charged there), so ", id,
                      broken);
        else
            sb_printf(&n, "your %s code compiles, but your files do not link together%s%s%s, so ",
                      id, *said ? " (" : "", said, *said ? ")" : "");
        sb_printf(&n,
                  "%s is graded on your %s code alone, with the reference of the earlier "
                  "assignments, and its pictures' whole-chain points score 0",
                  id, id);
        free(said);
        a->note = n.s;
        run_and_judge(g, gr, a, asg, dir, own_worker);
    } else if (failed_log) {
        a->graded = true;
        a->note = xstrdup(chain_unlinked ? "the code compiles, but does not link with your "
                                           "earlier files (build.log says why)"
                                         : "the code does not compile");
        mark_build_failed(g, a, asg, failed_log, chain_unlinked);
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
        /* the chain: the rubric's assignments, in its order */
        sbuf chain = {0};
        const cJSON *asgs = cJSON_GetObjectItemCaseSensitive(g->rubric, "assignments");
        for (const cJSON *x = asgs ? asgs->child : NULL; x; x = x->next)
            sb_printf(&chain, "%s%s", chain.s ? " → " : "", str_or(x, "id", "?"));
        sbuf note = {0};
        sb_printf(&note,
                  "the images with points again, rendered by your whole chain (your %s); a "
                  "failure says whose code causes it",
                  chain.s ? chain.s : "");
        free(chain.s);
        integration->note = note.s;
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
