/* grade_tests.c — raster101-grade's verdicts on an assignment's tests
 * (grade_tests.h). A verdict is the trusted replay's; the worker (the
 * student's code, sandboxed) only says how it ended, and what it printed is
 * shown as the student's.
 */
#include "grade_tests.h"

#include "grade_base.h"
#include "grade_results.h"
#include "grade_text.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Points for a test from the rubric's "tests" object; *dflt set when the
 * rubric does not name it. */
static double test_points(const grader *g, const cJSON *tests, const char *name, bool *dflt) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(tests, name);
    *dflt = !cJSON_IsNumber(v);
    return cJSON_IsNumber(v) ? v->valuedouble : g->default_points;
}

/* Fills in score and status of a finished test from its run and output. */
static void judge_test(item *it, run_result rr, bool failed_in_output, const char *out,
                       double limit, double wall, const char *crash_hint) {
    sbuf o = {0};
    it->passed = false;
    if (rr.kind == RUN_TIMEOUT && rr.code == 1) { /* fate_parse: stopped by the clock */
        it->status = xstrdup("TIMEOUT");
        sb_printf(&o,
                  "the test was still running after %.0f s on the clock, without having used its "
                  "%.0f s of processor time, and was stopped: it waits for something that never "
                  "comes (an endless loop around sleep or read?)\n",
                  wall, limit);
    } else if (rr.kind == RUN_TIMEOUT) {
        it->status = xstrdup("TIMEOUT");
        sb_printf(&o,
                  "the test used more than %.0f s of processor time and was stopped: an endless "
                  "loop, or far too much work (e.g. a bounding box that is not clamped)\n",
                  limit);
    } else if (rr.kind == RUN_SIGNALED) {
        it->status = xstrdup("CRASH");
        sb_printf(&o, "the test crashed with %s\nlikely mistake: %s\n", signal_text(rr.code),
                  crash_hint);
    } else if (rr.kind == RUN_NOT_STARTED) {
        it->status = xstrdup("ERROR");
        sb_add(&o, "the test program could not be started\n");
    } else if (strstr(out, "Test failed with exception")) {
        /* cmocka caught the signal itself: still a crash of the student code */
        it->status = xstrdup("CRASH");
        sb_printf(&o, "the test crashed (cmocka caught the signal)\nlikely mistake: %s\n",
                  crash_hint);
    } else if (rr.code == 0 && !failed_in_output) {
        it->passed = true;
        it->status = xstrdup(has_todo_notice(out) ? "TODO" : "PASS");
    } else {
        it->status = xstrdup(has_todo_notice(out) ? "TODO" : "FAIL");
    }
    if (*out) sb_printf(&o, "%s%s", o.len ? "output before it stopped:\n" : "", out);
    if (it->passed && has_todo_notice(out))
        sb_add(&o, "\n(passed, but a TODO notice was printed, so no points: either a function it "
                   "calls is still the stub and its placeholder happens to be right, or you wrote "
                   "the function and left its `static bool shown; ras_todo_notice(...)` lines in: "
                   "delete them)");
    it->output = o.s ? o.s : xstrdup("");
    it->score = it->passed && !has_todo_notice(out) ? it->max_score : 0;
    if (it->passed && !has_todo_notice(out))
        it->reason = xstrdup("");
    else if (it->passed)
        it->reason =
            xstrdup("passes, but a TODO notice was printed (a stub, or notice lines left in)");
    else
        it->reason = reason_line(it->output);
}

/* The <testcase> elements of a cmocka XML file, or NULL. */
static char *cmocka_testcases(const char *xml_path, bool *has_failure) {
    char *x = read_file(xml_path, 0);
    if (!x) return NULL;
    char *a = strstr(x, "<testcase"), *b = a ? strstr(a, "</testsuite>") : NULL;
    if (!a || !b) {
        free(x);
        return NULL;
    }
    *b = '\0';
    *has_failure = strstr(a, "<failure") != NULL || strstr(a, "<error") != NULL;
    sbuf s = {0};
    sb_add(&s, "    ");
    char *safe = safe_xml(a, 256 * 1024); /* its CDATA quotes the values returned */
    sb_add(&s, safe);
    free(safe);
    free(x);
    while (s.len && (s.s[s.len - 1] == ' ' || s.s[s.len - 1] == '\n'))
        s.s[--s.len] = '\0';
    sb_add(&s, "\n");
    return s.s;
}

/* The first line of a sanitizer report in `out` and the first frame of it
 * in a student file ("in FUNC .../hw3_shading/shading.c:183"), as one line
 * into buf; false when there is no report. */
static bool sanitizer_finding(const char *out, const cJSON *assignments, char *buf, size_t size) {
    const char *asan = strstr(out, "ERROR: AddressSanitizer: ");
    const char *ub = strstr(out, ": runtime error: ");
    if (!asan && !ub) return false;
    /* every assignment's student files, the names a frame or a path is
     * recognised by */
    const char *files[32];
    int n_files = 0;
    for (const cJSON *as = assignments ? assignments->child : NULL; as; as = as->next) {
        const cJSON *list = cJSON_GetObjectItemCaseSensitive(as, "student_files");
        for (const cJSON *sf = list ? list->child : NULL; sf && n_files < 32; sf = sf->next)
            if (cJSON_IsString(sf) && *sf->valuestring) files[n_files++] = sf->valuestring;
    }
    char kind[200] = "", access[120] = "", where[400] = "";
    if (asan) {
        sscanf(asan + 25, "%199[^ \n]", kind);
        const char *acc = strstr(asan, "\nREAD of size ");
        if (!acc) acc = strstr(asan, "\nWRITE of size ");
        if (acc) sscanf(acc + 1, "%119[^\n]", access);
        char *t = strstr(access, " at 0x");
        if (t) *t = '\0';
        /* the first frame in a student file: "#N 0x... in FUNC PATH/FILE:LINE" */
        for (const char *f = strstr(asan, "    #"); f && !*where; f = strstr(f + 1, "    #")) {
            const char *eol = strchr(f, '\n');
            const char *stop = eol ? eol : f + strlen(f), *in = strstr(f, " in ");
            for (int i = 0; i < n_files && in && in < stop && !*where; i++) {
                const char *hit = strstr(f, files[i]);
                if (!hit || hit >= stop) continue;
                const char *end = hit, *name = in + 4, *name_end = name;
                while (end < stop && *end != ' ')
                    end++;
                while (name_end < hit && *name_end != ' ')
                    name_end++;
                fmt(where, sizeof where, "in %.*s (%.*s)", (int)(name_end - name), name,
                    (int)(end - hit), hit);
            }
        }
        fmt(buf, size, "AddressSanitizer: %s%s%s%s%s", kind, *access ? ", a " : "", access,
            *where ? " " : "", where);
    } else {
        const char *line = ub;
        while (line > out && line[-1] != '\n')
            line--;
        const char *eol = strchr(ub, '\n');
        fmt(buf, size, "UndefinedBehaviorSanitizer: %.*s",
            (int)((eol ? eol : ub + strlen(ub)) - line), line);
    }
    /* the sandbox's paths mean nothing to the student: keep from the
     * assignment folder on */
    for (int i = 0; i < n_files; i++) {
        char *hit = strstr(buf, files[i]), *start = hit;
        while (start && start > buf && start[-1] != '(' && start[-1] != ' ')
            start--;
        if (hit && start < hit) memmove(start, hit, strlen(hit) + 1);
    }
    return true;
}

/* grade --sanitize: the tests once more, on the student's code built with
 * AddressSanitizer and UBSan, only to say where memory or arithmetic goes
 * wrong: the verdicts stay the replay's. The finding is added to its test's
 * output (the first frame in a student file: function, file and line). */
static void sanitizer_pass(const grader *g, assignment_result *a, const name_list *names,
                           int first_item) {
    if (!g->sanitized) return;
    char worker[4096];
    fmt(worker, sizeof worker, "%s/tests/test_%s_worker", g->sanitized, a->id);
    if (!file_exists(worker)) return;
    int n = names->n, chunks = g->jobs < n ? g->jobs : n;
    if (chunks < 1) return;
    job *jobs = calloc((size_t)chunks, sizeof *jobs);
    int *chunk_of = calloc((size_t)n + 1, sizeof *chunk_of);
    if (!jobs || !chunk_of) abort();
    deal_tests(g, a->id, names, chunks, chunk_of);
    static const char *const sanitizers[] = {
        "ASAN_OPTIONS=detect_leaks=0:halt_on_error=1:abort_on_error=0",
        "UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1", NULL};
    for (int c = 0; c < chunks; c++) {
        job *w = &jobs[c];
        worker_job(g, w, worker, "", names, chunk_of, c, 3 * g->test_limit,
                   wall_backstop(3 * g->test_limit), sanitizers);
        w->env[0] = "RAS_SANDBOX_NO_AS=1"; /* ASan reserves terabytes of address space */
        w->env[1] = NULL;
        fmt(w->out_path, sizeof w->out_path, "%s/runs/sanitized-%s-%d.out", g->work, a->id, c);
    }
    run_jobs(jobs, chunks, g->jobs);
    const cJSON *files = cJSON_GetObjectItemCaseSensitive(g->rubric, "assignments");
    for (int i = 0; i < n; i++) {
        char path[4400], finding[800];
        fmt(path, sizeof path, "%s/%s.out", jobs[chunk_of[i]].rw, names->v[i]);
        char *out = read_small_file(path, 64 * 1024);
        if (out && sanitizer_finding(out, files, finding, sizeof finding)) {
            char *shown = student_text(finding, 600);
            item *it = &a->items[first_item + i];
            sbuf o = {0};
            sb_printf(&o,
                      "%s\n--- grade --sanitize (your code built with AddressSanitizer "
                      "and UBSan) ---\n%s",
                      it->output ? it->output : "", shown);
            free(it->output);
            it->output = o.s;
            free(shown);
        }
        free(out);
    }
    free(jobs);
    free(chunk_of);
}

/* What the replay of test `name` said: its console text without the banners
 * and the work folder, with the assertion text cmocka's XML mode puts only
 * into the XML (*cases: the XML's <testcase> elements, owned; NULL when the
 * replay did not exit). */
static char *replay_said(const grader *g, const char *xml_dir, const char *name, run_result rr,
                         char **cases, bool *xml_failure) {
    char path[4400];
    fmt(path, sizeof path, "%s/%s.out", xml_dir, name);
    char *raw = read_file(path, 64 * 1024);
    char *clean = without_work_path(g->work, clean_output(raw ? raw : ""));
    free(raw);
    fmt(path, sizeof path, "%s/%s.xml", xml_dir, name);
    *cases = rr.kind == RUN_EXITED ? cmocka_testcases(path, xml_failure) : NULL;
    /* cmocka's XML mode puts assertion texts only into the XML: add them */
    const char *cdata = *cases ? strstr(*cases, "<failure><![CDATA[") : NULL;
    if (cdata) {
        cdata += strlen("<failure><![CDATA[");
        const char *end = strstr(cdata, "]]>");
        size_t len = end ? (size_t)(end - cdata) : 0;
        char *msg = malloc(len + 1);
        if (!msg) abort();
        memcpy(msg, cdata, len);
        msg[len] = '\0';
        char *first_nl = strchr(msg, '\n');
        if (first_nl) *first_nl = '\0';
        if (len && !strstr(clean, msg) && !strstr(msg, "error: Failure!")) {
            sbuf c = {0};
            sb_printf(&c, "%s%s%.*s", clean, *clean ? "\n" : "", (int)len, cdata);
            free(clean);
            clean = c.s;
        }
        free(msg);
    }
    /* the trusted replay's words, but they quote what the student's code
     * returned (and its assertion texts): made safe, not marked as theirs */
    char *safe = safe_text(clean, 96 * 1024);
    free(clean);
    return safe;
}

/* The run a test's verdict is charged to: the replay's (rr), but a failure
 * because the worker died is charged to the way it died (wr), and a replay
 * that did not finish is the grader's error (*clean replaced). */
static run_result charged_run(run_result wr, run_result rr, char **clean) {
    run_result verdict = rr;
    bool worker_died = wr.kind == RUN_TIMEOUT || wr.kind == RUN_SIGNALED ||
                       (wr.kind == RUN_EXITED && wr.code > 128 && wr.code < 160);
    if (rr.kind == RUN_EXITED && rr.code != 0 && worker_died) {
        verdict = wr;
        if (wr.kind == RUN_EXITED) verdict = (run_result){RUN_SIGNALED, wr.code - 128, 0};
    } else if (rr.kind != RUN_EXITED) {
        free(*clean);
        *clean = xstrdup("grader error: the trusted replay of this test did not finish; "
                         "tell your instructor");
        verdict = (run_result){RUN_EXITED, 1, 0};
    }
    return verdict;
}

/* A sealed verdict (a run that held reference code: own code linked with
 * the earlier references): pass or not, and nothing else. `earned`: the
 * item passed and earned its points (no TODO notice). Every other end -
 * a failed check, a crash, a time-out, an exit status, a TODO notice, a
 * replay that did not finish - becomes the same status and the same text
 * (sealed_text), since each distinction would be a bit the student's code
 * chose after reading the reference. An image keeps its first line, the
 * grader's own "command: ..." (the arguments drawn for this grading).
 * The grader's self-test (--variant ref: the course's own reference graded
 * as the student, trusted code) keeps what the run said below that text,
 * so that a failure of the self-test in CI can be read from its log. */
void seal_verdict(const grader *g, item *it, bool earned) {
    sbuf o = {0};
    const char *out = it->output ? it->output : "";
    if (it->is_image && !strncmp(out, "command: ", 9))
        sb_printf(&o, "%.*s\n", (int)strcspn(out, "\n"), out);
    char *said = sealed_text(earned);
    sb_add(&o, said);
    if (!earned && !strcmp(g->variant, "ref"))
        sb_printf(&o, "\n(self-test: the reference graded as the student; the sealed run ended %s "
                      "and said:)\n%s",
                  it->status ? it->status : "?", out);
    free(it->output);
    it->output = o.s;
    free(it->status);
    it->status = xstrdup(earned ? "PASS" : "FAIL");
    free(it->reason);
    it->reason = earned ? xstrdup("") : reason_line(said);
    free(said);
    it->passed = earned;
    it->score = earned ? it->max_score : 0;
}

/* What the student's code printed (the worker's NAME.out in its run folder
 * rw), added to the item: theirs, shown as such, capped; nothing from a
 * sealed run. */
static void add_worker_output(item *it, const char *rw, const char *name, bool sealed) {
    char path[4400];
    fmt(path, sizeof path, "%s/%s.out", rw, name);
    char *wraw = read_small_file(path, 4096);
    char *wclean = wraw && !sealed ? clean_output(wraw) : NULL;
    if (wclean && *wclean) {
        char *shown = student_text(wclean, 1500);
        sbuf o = {0};
        sb_printf(&o, "%s\n--- what the test process printed (your code runs there) ---\n%s",
                  it->output, shown);
        free(it->output);
        it->output = o.s;
        free(shown);
    }
    free(wclean);
    free(wraw);
}

/* The test's item, judged: the fates of its worker (in the chunk's run
 * folder) and of its replay, what the replay said, the rubric's hints. */
static void test_verdict(const grader *g, assignment_result *a, const cJSON *asg,
                         const test_batch *b, int i) {
    const cJSON *tests = cJSON_GetObjectItemCaseSensitive(asg, "tests");
    const char *crash_hint = str_or(asg, "crash_hint", "look for an out-of-bounds access");
    const char *xml_dir = b->xml_dir, *own = b->own;
    const char *name = b->names.v[i];
    item *it = add_item(a);
    it->name = xstrdup(name);
    it->max_score = test_points(g, tests, name, &it->default_weight);
    const char *rw = b->workers[b->chunk_of[i]].rw;
    char path[4400], fate[200], rfate[200];
    fmt(path, sizeof path, "%s/%s.fate", rw, name);
    read_small(path, fate, sizeof fate);
    fmt(path, sizeof path, "%s/%s.fate", xml_dir, name);
    read_small(path, rfate, sizeof rfate);
    run_result wr = fate_parse(fate), rr = fate_parse(rfate);
    if (!*rfate) rr = (run_result){RUN_NOT_STARTED, 0, 0};
    bool xml_failure = false;
    char *cases = NULL;
    char *clean = replay_said(g, xml_dir, name, rr, &cases, &xml_failure);
    run_result verdict = charged_run(wr, rr, &clean);
    /* a test may name its own likely crash (rubric "crash_hints"): a crash
     * says more there than the assignment's generic hint */
    const char *own_crash =
        str_or(cJSON_GetObjectItemCaseSensitive(asg, "crash_hints"), name, crash_hint);
    judge_test(it, verdict, xml_failure, clean, g->test_limit, test_wall(g), own_crash);
    if (own[0]) seal_verdict(g, it, it->passed && !has_todo_notice(clean));
    add_worker_output(it, rw, name, own[0]);
    if (own[0]) {
        /* sealed: the replay's own XML and console text quote the values
         * returned (and its times), its fate says how it ended; the
         * student's folder keeps none of them */
        junit_case(it, a->id, NULL);
        static const char *const kept[] = {"out", "xml", "fate"};
        for (int k = 0; k < 3; k++) {
            fmt(path, sizeof path, "%s/%s.%s", xml_dir, name, kept[k]);
            unlink(path);
        }
    } else {
        junit_case(it, a->id, cases);
    }
    free(cases);
    free(clean);
}

/* The tests the rubric names that the test program does not have: reported,
 * not counted. */
static void rubric_only_tests(const grader *g, assignment_result *a, const cJSON *tests,
                              const name_list *names) {
    for (const cJSON *t = tests ? tests->child : NULL; t; t = t->next) {
        if (names_has(names, t->string)) continue;
        item *it = add_item(a);
        it->name = xstrdup(t->string);
        it->counted = false;
        it->max_score = cJSON_IsNumber(t) ? t->valuedouble : g->default_points;
        it->status = xstrdup("MISSING");
        it->output = xstrdup("the rubric names this test but the test program has none by that "
                             "name (not counted; update tests/grading/rubric.json)");
        it->reason = xstrdup("not in the test program (rubric out of date; not counted)");
        junit_case(it, a->id, NULL);
    }
}

/* What a batch holds (tests_prepare, tests_prepare_whole_chain). */
static void test_batch_free(test_batch *b) {
    free(b->workers);
    free(b->replays);
    free(b->chunk_of);
    free(b->fates);
    names_free(&b->names);
    free(b->listing);
}

/* The verdicts of a batch whose jobs have run (b->workers[c].rr and the
 * replays' set); frees the batch. */
void tests_finish(const grader *g, assignment_result *a, const cJSON *asg, test_batch *b) {
    const cJSON *tests = cJSON_GetObjectItemCaseSensitive(asg, "tests");
    int n = b->n;
    double t_judge = now_s();
    for (int i = 0; i < n; i++)
        test_verdict(g, a, asg, b, i);
    /* a sealed batch's consoles go with its tests' files: the workers'
     * (what the student's code printed beside reference code) and the
     * replays' */
    for (int c = 0; b->own[0] && c < b->chunks && b->replays; c++) {
        unlink(b->workers[c].out_path);
        unlink(b->replays[c].out_path);
    }
    profile("tests: verdicts", a->id, t_judge);
    if (g->sanitized) sanitizer_pass(g, a, &b->names, a->n_items - n);
    rubric_only_tests(g, a, tests, &b->names);
    test_batch_free(b);
}

/* The whole-chain run of a sealed failure, said after the sealed verdict
 * (this line opens it: run-attacks' sealed_uniform compares the texts
 * before it). */
#define WHOLE_CHAIN_HEADING "--- the same test on your whole chain ---"

/* A sealed test that failed says only that (seal_verdict): what it did
 * would be a value computed beside reference code. So each one runs once
 * more on the student's whole chain (their own build, their code of every
 * assignment and nothing else), where what happened can be shown, and its
 * message is added to the sealed item: the student learns what is wrong
 * without the sealed run saying anything but "not passed". Only the
 * failures run again: what passes costs nothing. */
void tests_explain_sealed(const grader *g, assignment_result *a, const cJSON *asg, const char *dir,
                          int from) {
    name_list failed = {0};
    for (int i = from; i < a->n_items; i++) {
        const item *it = &a->items[i];
        if (!it->is_image && it->counted && !it->passed) names_add(&failed, it->name);
    }
    test_batch b;
    if (!tests_prepare_whole_chain(g, a, dir, &failed, &b)) {
        names_free(&failed);
        return;
    }
    double t0 = now_s();
    run_jobs(b.workers, b.chunks, g->jobs);
    assignment_result twin = {.id = a->id};
    for (int i = 0; i < b.n; i++)
        test_verdict(g, &twin, asg, &b, i);
    for (int i = 0; i < twin.n_items; i++) {
        item *t = &twin.items[i];
        for (int k = from; k < a->n_items; k++) {
            item *s = &a->items[k];
            if (s->is_image || strcmp(s->name, t->name)) continue;
            sbuf o = {0};
            sb_printf(&o, "%s\n" WHOLE_CHAIN_HEADING "\n", s->output ? s->output : "");
            if (t->passed)
                sb_printf(&o,
                          "it passes on your whole chain (your own code of every assignment, no "
                          "reference code): it fails only with the earlier assignments' "
                          "reference, so your %s code depends on something your earlier code "
                          "does differently from the reference (a helper, a convention, a "
                          "global)",
                          a->id);
            else {
                sb_printf(&o,
                          "on your whole chain (your own code of every assignment, no reference "
                          "code) it fails too, and there it can be shown:\n%s",
                          t->output ? t->output : "");
                free(s->reason);
                s->reason = xstrdup(t->reason);
            }
            free(s->output);
            s->output = o.s;
        }
        item_free(t);
    }
    free(twin.items);
    test_batch_free(&b);
    names_free(&failed);
    profile("tests: sealed failures on the whole chain", a->id, t0);
}

/* A linker's complaint: it names a clash or a missing function on a line
 * without "error". */
static bool link_complaint(const char *line) {
    return strstr(line, "multiple definition") || strstr(line, "undefined reference");
}
static bool error_line(const char *line) { return strstr(line, "error") || strstr(line, "Error"); }

/* The compiler's error lines in a failed build's log (at most 30), as
 * the student's text: the compiler echoes their #error and #include lines
 * byte for byte, and names the sandbox's folders (owned); the linker's
 * complaints too. */
static char *compiler_error_lines(const char *log_path) {
    /* the log is written by tests/grading/grade, its text by the build in
     * the sandbox: read as a regular file, the first 8 MiB */
    char *log = read_small_file(log_path, 8u << 20);
    sbuf lines = {0};
    int n = 0;
    for (char *line = log ? strtok(log, "\n") : NULL; line && n < 30; line = strtok(NULL, "\n"))
        if (error_line(line) || link_complaint(line)) {
            sb_printf(&lines, "%s\n", line);
            n++;
        }
    free(log);
    char *shown = student_text(sb_str(&lines), 6000);
    free(lines.s);
    return shown;
}

char *first_link_error(const char *log_path) {
    char *log = read_small_file(log_path, 8u << 20);
    const char *found = NULL;
    for (char *line = log ? strtok(log, "\n") : NULL; line; line = strtok(NULL, "\n"))
        if (link_complaint(line)) {
            found = line;
            break;
        } else if (!found && error_line(line))
            found = line;
    /* the line names the student's file and symbol: their bytes */
    char *shown = student_text(found ? found : "", 300);
    free(log);
    return shown;
}

/* A build that failed: every test and image of the assignment lost to it,
 * each quoting the compiler's error lines (compiler_error_lines). */
void mark_build_failed(const grader *g, assignment_result *a, const cJSON *asg,
                       const char *log_path, bool linked) {
    const char *why = linked ? "your code compiles, but does not link with your earlier files"
                             : "your code does not compile";
    char *said = compiler_error_lines(log_path);
    const cJSON *tests = cJSON_GetObjectItemCaseSensitive(asg, "tests");
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(asg, "images");
    for (int pass = 0; pass < 2; pass++)
        for (const cJSON *t = (pass ? images : tests) ? (pass ? images : tests)->child : NULL; t;
             t = t->next) {
            item *it = add_item(a);
            char label[300];
            fmt(label, sizeof label, "%s%s", pass ? "image " : "",
                pass ? str_or(t, "name", "?") : t->string);
            it->name = xstrdup(label);
            it->is_image = pass;
            it->max_score = pass ? num_or(t, "points", g->default_points)
                                 : (cJSON_IsNumber(t) ? t->valuedouble : g->default_points);
            it->status = xstrdup("BUILD");
            it->reason = xstrdup(why);
            sbuf o = {0};
            sb_printf(&o, "your code for %s %s, so nothing could be tested.\n", a->id,
                      linked ? "compiles, but does not link with your earlier files"
                             : "does not compile");
            if (*said) sb_printf(&o, "--- the compiler's error lines (at most 30) ---\n%s\n", said);
            it->output = o.s;
            junit_case(it, a->id, NULL);
        }
    free(said);
}
