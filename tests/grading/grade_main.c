/* grade_main.c — raster101-grade: grades one build of the assignments against
 * tests/grading/rubric.json. tests/grading/grade takes the submission in,
 * builds it in the sandbox and then calls this; see docs/grading.md.
 *
 *   raster101-grade --source SRC --build BUILD --out OUT
 *                   [--rubric FILE] [--hw hwN]... [--variant student|ref]
 *                   [--build-failed hwN=LOG]... [--chain-unlinked hwN=LOG]...
 *                   [--expect full|0|POINTS]
 *                   (and from tests/grading/grade: --work, --student-tree,
 *                   --student-build, --own, --sanitized-build, --sandbox-uid,
 *                   --jobs, --notes, --seed)
 *   raster101-grade --list RUBRIC
 *
 * The story of a grading, one phase after another (the modules are listed in
 * grade_priv.h):
 *   1. what it is given: the command line, the rubric, the sandbox's
 *      folders, the notes on the submission (grade_intake.c);
 *   2. for each assignment of the rubric (or only those given with --hw), in
 *      one batch of sandboxed runs (grade_assignment.c, grade_run.c):
 *      the tests in chunks, each chunk's worker recording what the student's
 *      functions return and its trusted replay deciding (grade_tests.c);
 *      each graded picture's program, compared with the reference, the
 *      buffers' evidence first (grade_images.c, grade_evidence.c); the
 *      pictures with points again by the student's whole chain, a failure
 *      attributed to the assignment whose code causes it (grade_attribute.c);
 *   3. the reports (grade_report.c): results.json (Gradescope), report.md
 *      (with images), scores.csv (one row per item, for
 *      tests/grading/grade-all), failures.txt, hwN/cmocka.xml in OUT; a table
 *      on stdout.
 *
 * Scoring: an item scores its points when it passes and no TODO notice was
 * printed while it ran (passing on a placeholder stub earns nothing). Exit
 * status: 0 graded (whatever the score), 1 --expect not met, 2 grader error.
 */
#include "grade_assignment.h"
#include "grade_base.h"
#include "grade_intake.h"
#include "grade_priv.h"
#include "grade_report.h"
#include "grade_results.h"
#include "grade_text.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* What the command line asks beyond the grader's own fields. */
typedef struct options {
    const char *rubric_path, *expect, *list;
} options;

static void usage(FILE *f) {
    fputs("usage: raster101-grade --source SRC --build BUILD --out OUT [--rubric FILE]\n"
          "         [--hw hwN]... [--variant student|ref] [--build-failed hwN=LOG]...\n"
          "         [--chain-unlinked hwN=LOG]...\n"
          "         [--expect full|POINTS] [--own OWN]\n"
          "         (tests/grading/grade passes --work, --student-tree, --student-build, --own)\n"
          "       raster101-grade --list RUBRIC   (assignments and their programs)\n",
          f);
}

/* Prints one argument error (what was expected, what came) and the usage. */
__attribute__((format(printf, 1, 2))) static int arg_error(const char *fmt_, ...) {
    va_list ap;
    va_start(ap, fmt_);
    fputs("raster101-grade: ", stderr);
    vfprintf(stderr, fmt_, ap);
    va_end(ap);
    fputc('\n', stderr);
    usage(stderr);
    return 2;
}

/* One option `a` with its value v into g or o; -1 when taken, else the exit
 * status (the error said). */
static int set_option(grader *g, options *o, const char *a, const char *v) {
    if (!strcmp(a, "--source"))
        g->source = v;
    else if (!strcmp(a, "--build"))
        g->build = v;
    else if (!strcmp(a, "--out"))
        g->out = v;
    else if (!strcmp(a, "--rubric"))
        o->rubric_path = v;
    else if (!strcmp(a, "--variant")) {
        if (strcmp(v, "student") && strcmp(v, "ref"))
            return arg_error("--variant expects student or ref; got '%s'", v);
        g->variant = v;
    } else if (!strcmp(a, "--expect")) {
        char *end = NULL;
        double points = strtod(v, &end);
        if (strcmp(v, "full") && (end == v || *end || !isfinite(points) || points < 0))
            return arg_error("--expect expects full or a number of points (0 or more); "
                             "got '%s'",
                             v);
        o->expect = v;
    } else if (!strcmp(a, "--hw")) {
        if (g->n_only == 8) return arg_error("at most 8 --hw options; got more (%s)", v);
        g->only[g->n_only++] = v;
    } else if (!strcmp(a, "--list"))
        o->list = v;
    else if (!strcmp(a, "--work"))
        g->work = v;
    else if (!strcmp(a, "--own"))
        g->own = v;
    else if (!strcmp(a, "--sanitized-build"))
        g->sanitized = v;
    else if (!strcmp(a, "--seed")) {
        char *end = NULL;
        g->seed = strtoull(v, &end, 16);
        if (end == v || *end || strlen(v) > 16)
            return arg_error("--seed expects up to 16 hex digits; got '%s'", v);
        g->has_seed = true;
    } else if (!strcmp(a, "--notes"))
        intake_notes(g, v);
    else if (!strcmp(a, "--jobs")) {
        g->jobs = atoi(v);
        if (g->jobs < 1 || g->jobs > 64)
            return arg_error("--jobs expects 1 to 64 runs at once; got '%s'", v);
    } else if (!strcmp(a, "--student-tree"))
        g->student_tree = v;
    else if (!strcmp(a, "--student-build"))
        g->student_build = v;
    else if (!strcmp(a, "--sandbox-uid")) {
        char *end = NULL;
        g->sandbox_uid = strtol(v, &end, 10);
        if (end == v || *end || g->sandbox_uid < 1000)
            return arg_error("--sandbox-uid expects a uid of 1000 or more; got '%s'", v);
    } else { /* --build-failed, --chain-unlinked */
        if (g->n_failed == 8 || !strchr(v, '=') || v[0] == '=')
            return arg_error("%s expects hwN=LOG (at most 8 of them); got '%s'", a, v);
        char *hw = xstrdup(v);
        char *eq = strchr(hw, '=');
        *eq = '\0';
        g->chain_unlinked[g->n_failed] = !strcmp(a, "--chain-unlinked");
        g->failed_hw[g->n_failed] = hw;
        g->failed_log[g->n_failed++] = eq + 1;
    }
    return -1;
}

/* The command line into g and o: every option takes a value. -1 when it is
 * all taken, else the exit status (--help: 0; an error, said: 2). */
static int parse_args(grader *g, options *o, int argc, char **argv) {
    static const char *const with_value[] = {
        "--source",       "--build",  "--out",          "--rubric",
        "--variant",      "--expect", "--hw",           "--list",
        "--build-failed", "--work",   "--student-tree", "--student-build", "--chain-unlinked",
        "--sandbox-uid",  "--jobs",   "--own",          "--sanitized-build",
        "--notes",        "--seed"};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        }
        bool known = false;
        for (size_t k = 0; k < sizeof with_value / sizeof *with_value; k++)
            known |= !strcmp(a, with_value[k]);
        if (!known)
            return arg_error("unknown argument '%s'%s; expected one of the options below", a,
                             a[0] == '-' ? "" : " (every value follows its option)");
        if (!v || (v[0] == '-' && v[1] == '-'))
            return arg_error("option '%s' needs a value; got %s", a,
                             v ? "another option" : "the end of the command line");
        i++;
        int status = set_option(g, o, a, v);
        if (status >= 0) return status;
    }
    return -1;
}

/* The trusted side's folders: -1 when they are there, else the exit status. */
static int check_folders(const grader *g) {
    if (!g->source || !g->build || !g->out)
        return arg_error("expected --source, --build and --out; %s is missing",
                         !g->source  ? "--source"
                         : !g->build ? "--build"
                                     : "--out");
    if (!is_dir(g->source))
        return arg_error("--source expects the project folder; '%s' is not a folder", g->source);
    if (!is_dir(g->build))
        return arg_error("--build expects a build folder (cmake -B BUILD); '%s' is not a "
                         "folder",
                         g->build);
    return -1;
}

/* The exit status for --expect (NULL: none asked). A self-test that
 * misses it prints the items that lost points (OUT/failures.txt, its first
 * 200 lines): a CI log then says why, with the output folder long gone. */
static int expect_status(const char *expect, double total, double max_total, const char *out) {
    if (expect) {
        double want = !strcmp(expect, "full") ? max_total : atof(expect);
        if (fabs(total - want) > 1e-9 || max_total <= 0) {
            fprintf(stderr, "raster101-grade: expected %s (%g points), got %g / %g\n", expect, want,
                    total, max_total);
            char path[4200];
            fmt(path, sizeof path, "%s/failures.txt", out);
            FILE *f = fopen(path, "r");
            char line[1024];
            for (int n = 0; f && n < 200 && fgets(line, sizeof line, f); n++) {
                if (!n) fprintf(stderr, "raster101-grade: what lost points (%s):\n", path);
                fputs(line, stderr);
            }
            if (f) fclose(f);
            return 1;
        }
    }
    return 0;
}

/* The build logs the grade script leaves in OUT (the sandbox's configure and
 * build, the own-code links, --sanitize's build): the compiler echoes the
 * student's #error and #include lines byte for byte and names the grader's
 * folders, and OUT is what a student may be handed. So each is rewritten
 * as safe text (grade_text.h), its first 8 MiB; the reports have quoted
 * from them already. */
static void rewrite_as_safe_text(const char *path) {
    char *raw = read_small_file(path, 8u << 20);
    if (!raw) return;
    char *safe = safe_text(raw, 8u << 20);
    free(raw);
    char tmp[4500];
    fmt(tmp, sizeof tmp, "%s.safe", path);
    FILE *f = fopen(tmp, "wb");
    bool ok = f && fputs(safe, f) >= 0;
    if (f && fclose(f) != 0) ok = false;
    if (!ok || rename(tmp, path) != 0) {
        unlink(tmp);
        unlink(path); /* never left as the compiler wrote it */
    }
    free(safe);
}

static void safe_build_logs(const grader *g, const assignment_result *as, int n) {
    static const char *const top[] = {"build.log", "build-all.log", "build-own.log",
                                      "build-sanitized.log"};
    char path[4400];
    for (size_t i = 0; i < sizeof top / sizeof *top; i++) {
        fmt(path, sizeof path, "%s/%s", g->out, top[i]);
        rewrite_as_safe_text(path);
    }
    for (int i = 0; i < n; i++) {
        fmt(path, sizeof path, "%s/%s/build.log", g->out, as[i].id);
        rewrite_as_safe_text(path);
    }
}

int main(int argc, char **argv) {
    grader g = {.variant = "student"};
    g.sandbox_uid = -1;
    g.jobs = 2;
    options o = {0};
    int status = parse_args(&g, &o, argc, argv);
    if (status >= 0) return status;
    if (o.list) return intake_list(o.list);
    if ((status = check_folders(&g)) >= 0) return status;
    char default_rubric[4096];
    if (!o.rubric_path) {
        fmt(default_rubric, sizeof default_rubric, "%s/tests/grading/rubric.json", g.source);
        o.rubric_path = default_rubric;
    }
    const cJSON *asgs = intake_rubric(&g, o.rubric_path);
    if (!asgs) return 2;
    if (!intake_only(&g, asgs, o.rubric_path) || !intake_out(&g) || !intake_student_side(&g)) {
        cJSON_Delete(g.rubric);
        return 2;
    }

    grading gr;
    grading_begin(&gr, &g, cJSON_GetArraySize(asgs));
    for (const cJSON *asg = asgs->child; asg; asg = asg->next)
        if (grading_wants(&g, str_or(asg, "id", "?"))) grade_assignment(&g, &gr, asg);
    grading_end(&g, &gr);

    double t_out = now_s();
    bool written = write_outputs(&g, gr.as, gr.n, gr.total, gr.max_total);
    safe_build_logs(&g, gr.as, gr.n);
    profile("reports written", "all", t_out);
    print_table(&g, gr.as, gr.n, gr.total, gr.max_total);
    /* Freed although the process ends: the sanitizer CI step runs this tool
     * and counts any leak as a failure. */
    assignment_results_free(gr.as, gr.n);
    cJSON_Delete(g.rubric);
    cJSON_Delete(g.drawn);
    free(g.notes);
    for (int i = 0; i < g.n_failed; i++)
        free((char *)g.failed_hw[i]);
    if (!written) {
        fprintf(stderr,
                "raster101-grade: the reports in %s could not all be written (see "
                "above); the grade is not complete\n",
                g.out);
        return 2;
    }
    return expect_status(o.expect, gr.total, gr.max_total, g.out);
}
