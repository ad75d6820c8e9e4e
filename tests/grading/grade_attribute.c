/* grade_attribute.c — whose code a failure of the whole chain is
 * (grade_attribute.h).
 */
#include "grade_attribute.h"

#include "grade_base.h"
#include "grade_images.h"
#include "grade_run.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h> /* unlink */

/* Whether a sealed run (image_job) wrote an image that passes the rubric's
 * comparison with ref_path. */
static bool run_matches(const grader *g, const job *j, const cJSON *img, const char *ref_path) {
    ras_error err = {{0}};
    ras_compare_kind kind;
    ras_compare_options opt;
    if (j->rr.kind != RUN_EXITED || j->rr.code != 0 || !image_options(g, img, &kind, &opt, &err))
        return false;
    char taken[4200];
    fmt(taken, sizeof taken, "%s.taken.png", j->out_path); /* trusted: the work folder */
    ras_image *got = load_student_image(j->store[15], taken, ref_path, &err);
    ras_image *expected = got ? ras_image_load(ref_path, &err) : NULL;
    ras_compare_result r = {0};
    bool pass = expected && ras_compare_images(expected, got, &opt, &r, &err) && r.pass;
    sbuf ignored = {0};
    if (pass && image_defects(&ignored, expected, got,
                              image_is_wireframe(img) ? DEFECT_WIREFRAME : DEFECT_PATTERN))
        pass = false;
    free(ignored.s);
    ras_image_destroy(got);
    ras_image_destroy(expected);
    return pass;
}

/* The first item of assignment `id` that lost points, as "NAME (reason)"
 * into buf; "" when it lost none or was not graded. */
static void first_loss(const assignment_result *as, int n, const char *id, char *buf, size_t size) {
    buf[0] = '\0';
    for (int i = 0; i < n; i++) {
        if (!as[i].id || strcmp(as[i].id, id)) continue;
        for (int k = 0; k < as[i].n_items; k++) {
            const item *it = &as[i].items[k];
            if (it->counted && it->score < it->max_score) {
                fmt(buf, size, "%s%s%s%s", it->name, it->reason && *it->reason ? " (" : "",
                    it->reason ? it->reason : "", it->reason && *it->reason ? ")" : "");
                return;
            }
        }
    }
}

/* Attribution by substitution (docs/grading.md): the student's whole chain
 * failed an image of hwN. Which assignment's code makes the difference? The
 * own-code run (the references of every earlier assignment) has answered for
 * hwN itself; for each earlier assignment K alone, the image is rendered
 * again, sealed, with only K's reference swapped in. The answer leads the
 * integration item, with the first loss of the assignment it names. */
void attribute_image(grader *g, item *it, const cJSON *img, const char *dir, const char *id,
                     const job *graded, const job *whole, bool own_passed,
                     const assignment_result *as, int n_as) {
    char ref_path[4096], why[1200] = "", loss[700];
    variant_reference_path(g, dir, id, str_or(img, "name", "image"), ref_path, sizeof ref_path);
    if (!str_or(img, "reference_program", NULL))
        fmt(ref_path, sizeof ref_path, "%s/tests/reference/%s", g->source,
            str_or(img, "reference", ""));
    /* the assignments it builds on, earliest first: hw3's "12" */
    char chain[32];
    own_chain(id, chain, sizeof chain);
    size_t n_chain = strlen(chain);
    char earlier[2][16] = {"", ""};
    for (size_t k = 0; k < n_chain && k < 2; k++)
        fmt(earlier[k], sizeof earlier[k], "hw%c", chain[k]);
    /* Each earlier assignment's code builds (it lost no point, or a swap with
     * it built), the own-code run passed, yet the whole chain's program was
     * not built: the student's files do not link together. */
    bool whole_unbuilt = !file_exists(whole->store[14]);
    char not_linked[400];
    fmt(not_linked, sizeof not_linked,
        "your files do not link together (often a function two of them both "
        "define: make it static in each, or rename one; build.log names it): your "
        "whole chain, %s to %s, was not built, yet each file builds, and with the "
        "reference of an earlier assignment in its place this image matches",
        earlier[0], id);
    if (!own_passed) {
        fmt(why, sizeof why,
            "your %s code causes this: it fails this image on its own too, "
            "with the reference of the earlier assignments (charged in %s)",
            id, id);
    } else if (n_chain == 1) {
        first_loss(as, n_as, earlier[0], loss, sizeof loss);
        if (!*loss && whole_unbuilt)
            fmt(why, sizeof why, "%s", not_linked);
        else
            fmt(why, sizeof why,
                "your %s causes this: with the reference %s your %s matches this "
                "image%s%s%s%s",
                earlier[0], earlier[0], id, *loss ? "; " : "", *loss ? earlier[0] : "",
                *loss ? "'s first lost point: " : "", loss);
    } else if (n_chain == 2) {
        /* one sealed render per earlier assignment alone: the first then the second */
        job subs[2];
        memset(subs, 0, sizeof subs);
        bool ran[2] = {false, false};
        int m = 0;
        for (int k = 0; k < 2; k++) {
            char refs[2] = {chain[k], '\0'}, own[4096], tag[32], prog[4300];
            if (!own_dir(g, id, refs, own, sizeof own)) continue;
            fmt(prog, sizeof prog, "%s/bin/%s", own, str_or(img, "program", ""));
            if (!file_exists(prog)) continue;
            fmt(tag, sizeof tag, ".ref%s", refs);
            subs[m].args = graded->args;
            image_job(g, img, &subs[m], own, tag);
            ran[k] = true;
            m++;
        }
        run_jobs(subs, m, g->jobs);
        /* matches[k]: the image matches with only earlier[k]'s reference */
        bool matches[2] = {false, false};
        for (int k = 0, i = 0; k < 2; k++)
            if (ran[k]) matches[k] = run_matches(g, &subs[i++], img, ref_path);
        /* sealed runs: what they printed beside reference code leaves OUT */
        for (int i = 0; i < m; i++)
            unlink(subs[i].out_path);
        if (ran[0] && ran[1]) {
            const char *culprit = matches[1] && !matches[0]   ? earlier[1]
                                  : matches[0] && !matches[1] ? earlier[0]
                                                              : NULL;
            if (culprit) {
                first_loss(as, n_as, culprit, loss, sizeof loss);
                fmt(why, sizeof why,
                    "your %s causes this: with the reference %s this image "
                    "matches, with your %s it does not%s%s",
                    culprit, culprit, culprit, *loss ? "; its first lost point: " : "", loss);
            } else if (matches[0] && matches[1] && whole_unbuilt)
                fmt(why, sizeof why, "%s", not_linked);
            else if (matches[0] && matches[1])
                fmt(why, sizeof why,
                    "one of your %s or your %s causes this: the image matches "
                    "with either reference swapped in (most likely %s, which "
                    "draws it)",
                    earlier[0], earlier[1], earlier[1]);
            else {
                char loss2[700];
                first_loss(as, n_as, earlier[0], loss, sizeof loss);
                first_loss(as, n_as, earlier[1], loss2, sizeof loss2);
                fmt(why, sizeof why,
                    "both your %s and your %s cause this: the image matches "
                    "only with both references swapped in, with neither alone "
                    "(%s's first lost point: %s; %s's: %s)",
                    earlier[0], earlier[1], earlier[0], *loss ? loss : "none", earlier[1],
                    *loss2 ? loss2 : "none");
            }
        }
    }
    if (!*why) return;
    sbuf o = {0};
    sb_printf(&o, "whose code: %s\n%s", why, it->output ? it->output : "");
    free(it->output);
    it->output = o.s;
    free(it->reason);
    it->reason = xstrdup(why);
}
