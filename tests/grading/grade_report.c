/* grade_report.c — what raster101-grade hands back (grade_report.h). */
#include "grade_report.h"

#include "grade_base.h"
#include "grade_text.h"
#include "ras_error.h"
#include "ras_io.h"

#include <stdint.h> /* SIZE_MAX */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h> /* strncasecmp */

/* ---------------------------------------------------------------- where to start */

/* The rubric's "where" for an item of assignment `asg`: the first
 * [prefix, text] pair whose prefix starts `name`; NULL when none does. */
static const char *where_of(const cJSON *asg, const char *name) {
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(asg, "where"), *pair;
    cJSON_ArrayForEach(pair, list) {
        const cJSON *prefix = cJSON_GetArrayItem(pair, 0), *text = cJSON_GetArrayItem(pair, 1);
        if (cJSON_IsString(prefix) && cJSON_IsString(text) &&
            !strncmp(name, prefix->valuestring, strlen(prefix->valuestring)))
            return text->valuestring;
    }
    return NULL;
}

/* Each failing item's message opens with where to look (the rubric's file,
 * function and TODO numbers). `from`: the first item of a to mark. */
void mark_where(assignment_result *a, int from, const cJSON *asg, bool integration) {
    for (int k = from; k < a->n_items; k++) {
        item *it = &a->items[k];
        /* an integration item is "hwN image NAME, your whole chain" */
        const char *name = it->name;
        if (integration && strstr(name, " image ")) name = strstr(name, " image ") + 1;
        char bare[300];
        fmt(bare, sizeof bare, "%.*s", (int)strcspn(name, ","), name);
        it->where = where_of(asg, bare);
        if (!it->where || !it->counted || it->score >= it->max_score) continue;
        sbuf o = {0};
        sb_printf(&o, "where: %s\n%s", it->where, it->output ? it->output : "");
        free(it->output);
        it->output = o.s;
    }
}

/* The one-line fix hint of an item: its message's "likely mistake" (either
 * case, as tests and pictures write it), else its reason; at most
 * FIX_CHARS characters, into buf. */
enum { FIX_CHARS = 300 };
static void fix_line(const item *it, char *buf, size_t size) {
    const char *out = it->output ? it->output : "", *p = NULL;
    /* never from a line the student's code printed (student_text marks
     * each with "│ "): a student cannot write their own fix line */
    const char *line = out;
    for (const char *q = out; *q && !p; q++) {
        if (q > out && q[-1] == '\n') line = q;
        if (!strncasecmp(q, "likely mistake: ", 16) && strncmp(line, "\xe2\x94\x82 ", 4))
            p = q + 16;
    }
    if (!p) p = it->reason && *it->reason ? it->reason : "see its message below";
    size_t n = utf8_prefix(p, strcspn(p, "\n"), FIX_CHARS);
    fmt(buf, size, "%.*s%s", (int)n, p, p[n] && p[n] != '\n' ? " …" : "");
}

/* The item a student should start with: the earliest failing item of the
 * earliest assignment that lost points (the report's and the table's
 * opening lines). NULL when nothing lost points. */
static const item *start_here(const assignment_result *as, int n, const char **id) {
    /* an item that failed outright first; one that passed but printed a
     * TODO notice says less */
    for (int i = 0; i < n; i++)
        for (int pass = 0; pass < 2; pass++)
            for (int k = 0; k < as[i].n_items; k++) {
                const item *it = &as[i].items[k];
                if (it->counted && it->score < it->max_score && (pass || !it->passed)) {
                    *id = as[i].id;
                    return it;
                }
            }
    return NULL;
}

/* ---------------------------------------------------------------- Markdown */

/* Writes `text` to a Markdown report as a fenced code block whose fence is
 * longer than any run of backticks inside it, so no text can close it and
 * render as the report's own Markdown. */
static void report_fenced(FILE *f, const char *text) {
    size_t longest = 0, run = 0;
    for (const char *c = text; *c; c++) {
        run = *c == '`' ? run + 1 : 0;
        if (run > longest) longest = run;
    }
    size_t fence = longest < 3 ? 3 : longest + 1;
    fputc('\n', f);
    for (size_t i = 0; i < fence; i++)
        fputc('`', f);
    size_t len = strlen(text);
    fprintf(f, "text\n%s%s", text, len && text[len - 1] == '\n' ? "" : "\n");
    for (size_t i = 0; i < fence; i++)
        fputc('`', f);
    fputc('\n', f);
}

/* Writes `text` into a cell of a Markdown table: Markdown's and HTML's
 * special characters backslash-escaped, line breaks and bidi controls
 * dropped, so a cell is text and stays in its cell. */
static void report_cell(FILE *f, const char *text) {
    for (const unsigned char *c = (const unsigned char *)text; *c; c++) {
        if (*c == '\n' || *c == '\r') {
            fputc(' ', f);
        } else if (*c == 0xE2 && c[1] && c[2] && is_bidi_control(c, 3)) {
            c += 2;
        } else if (*c == '|') {
            fputc('/', f);
        } else {
            if (strchr("\\`*_[]<>!#~&", *c)) fputc('\\', f);
            fputc(*c, f);
        }
    }
}

/* The grader's reports go through the atomic write of common/io/ras_io.h: a
 * full disk or a kill leaves the previous report whole, never half of one. */
static FILE *report_begin(ras_io_report *r) {
    memset(r, 0, sizeof *r);
    return ras_io_report_open(r);
}

static bool report_end(ras_io_report *r, const char *path) {
    ras_error err = {{0}};
    if (ras_io_report_commit(r, path, &err)) return true;
    fprintf(stderr, "raster101-grade: %s\n", err.msg);
    return false;
}

/* ---------------------------------------------------------------- safe text, by construction */

/* RAS_GRADE_STRICT_TEXT=1 (the grader's own tests): a text that reached a
 * report without the sanitizer stops the grading, so the test fails loudly. */
static bool strict_text(void) {
    const char *v = getenv("RAS_GRADE_STRICT_TEXT");
    return v && *v && strcmp(v, "0") != 0;
}

/* The last check on a text a report is about to write (`what` of `whose`):
 * what safe_text writes (grade_text.h) passes; anything else came from the
 * student's side without the sanitizer, a bug of the grader's: said on
 * stderr, and made safe here (under RAS_GRADE_STRICT_TEXT, the grading
 * stops). `markup`: an XML document, its tags allowed. */
static void ensure_safe(char **text, bool markup, const char *what, const char *whose) {
    const char *why = *text ? text_unsafe(*text, markup) : NULL;
    if (!why) return;
    fprintf(stderr,
            "raster101-grade: grader error: the %s of %s holds %s, so it did not pass "
            "through grade_text.h's sanitizer; expected every text from the student's side "
            "to; %s\n",
            what, whose, why,
            strict_text() ? "stopping (RAS_GRADE_STRICT_TEXT is set)" : "made safe here");
    if (strict_text()) abort();
    char *safe = markup ? safe_xml(*text, SIZE_MAX) : safe_text(*text, SIZE_MAX);
    free(*text);
    *text = safe;
}

/* Every text of every item, of every assignment and the notes, checked
 * before any report is written: every report (and the table on stdout)
 * writes only these. */
static void ensure_all_safe(grader *g, assignment_result *as, int n) {
    ensure_safe(&g->notes, false, "notes", "the submission");
    for (int i = 0; i < n; i++) {
        ensure_safe(&as[i].note, false, "note", as[i].id);
        ensure_safe(&as[i].title, false, "title", as[i].id);
        for (int k = 0; k < as[i].n_items; k++) {
            item *it = &as[i].items[k];
            char **plain[] = {&it->name,         &it->status,  &it->reason,   &it->output,
                              &it->img_expected, &it->img_got, &it->img_diff, &it->img_crop,
                              &it->buf_name,     &it->buf_ref, &it->buf_got,  &it->buf_diff};
            static const char *const names[] = {"name",
                                                "status",
                                                "reason",
                                                "output",
                                                "reference picture",
                                                "picture",
                                                "difference",
                                                "worst region",
                                                "buffer name",
                                                "buffer reference",
                                                "buffer picture",
                                                "buffer difference"};
            char whose[400];
            fmt(whose, sizeof whose, "%s %s", as[i].id, it->name ? it->name : "?");
            for (size_t f = 0; f < sizeof plain / sizeof *plain; f++)
                ensure_safe(plain[f], false, names[f], whose);
            ensure_safe(&it->xml, true, "JUnit XML", whose);
        }
    }
}

/* Every string of a JSON tree, checked as above (results.json's summary
 * is put together here, from checked parts). */
static void ensure_json_safe(cJSON *node) {
    for (; node; node = node->next) {
        if (cJSON_IsString(node) && text_unsafe(node->valuestring, false)) {
            char *copy = xstrdup(node->valuestring);
            ensure_safe(&copy, false, node->string ? node->string : "string", "results.json");
            cJSON_SetValuestring(node, copy);
            free(copy);
        }
        ensure_json_safe(node->child);
    }
}

/* ---------------------------------------------------------------- the files */

/* results.json — Gradescope: every counted item with its whole message, as
 * plain text; the summary opens with what tests/grading/grade found in the
 * submission. */
static bool write_results_json(const grader *g, assignment_result *as, int n, double total,
                               double max_total) {
    char path[4096];
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "score", total);
    cJSON_AddNumberToObject(root, "max_score", max_total);
    sbuf summary = {0};
    if (g->notes && *g->notes) sb_printf(&summary, "About your submission:\n%s\n\n", g->notes);
    /* plain text: nothing in an output renders as Markdown or HTML */
    cJSON_AddStringToObject(root, "output_format", "text");
    cJSON_AddStringToObject(root, "test_output_format", "text");
    cJSON *tests = cJSON_AddArrayToObject(root, "tests");
    cJSON *extra = cJSON_AddObjectToObject(root, "extra_data");
    for (int i = 0; i < n; i++) {
        assignment_result *a = &as[i];
        cJSON *ea = cJSON_AddObjectToObject(extra, a->id);
        cJSON_AddBoolToObject(ea, "graded", a->graded);
        cJSON_AddNumberToObject(ea, "score", a->score);
        cJSON_AddNumberToObject(ea, "max_score", a->max_score);
        if (a->note) cJSON_AddStringToObject(ea, "note", a->note);
        if (a->graded)
            sb_printf(&summary, "%s: %g / %g\n", a->id, a->score, a->max_score);
        else
            sb_printf(&summary, "%s: not graded (%s)\n", a->id, a->note ? a->note : "");
        for (int k = 0; k < a->n_items; k++) {
            item *it = &a->items[k];
            if (!it->counted) continue;
            cJSON *t = cJSON_CreateObject();
            char name[400];
            fmt(name, sizeof name, "%s: %s%s", a->id, it->name,
                it->default_weight ? " (default weight)" : "");
            cJSON_AddStringToObject(t, "name", name);
            cJSON_AddNumberToObject(t, "score", it->score);
            cJSON_AddNumberToObject(t, "max_score", it->max_score);
            cJSON_AddStringToObject(t, "status", it->score >= it->max_score ? "passed" : "failed");
            cJSON_AddStringToObject(t, "output", it->output ? it->output : "");
            cJSON_AddStringToObject(t, "visibility", "visible");
            cJSON_AddItemToArray(tests, t);
        }
    }
    cJSON_AddStringToObject(root, "output", sb_str(&summary));
    ensure_json_safe(root);
    char *json = cJSON_Print(root);
    fmt(path, sizeof path, "%s/results.json", g->out);
    ras_io_report rep;
    bool ok = true;
    FILE *f = report_begin(&rep);
    if (f) {
        fprintf(f, "%s\n", json);
        ok &= report_end(&rep, path);
    }
    free(json);
    cJSON_Delete(root);
    free(summary.s);
    return ok;
}

/* scores.csv — one row per item, for tests/grading/grade-all */
static bool write_scores_csv(const grader *g, assignment_result *as, int n, double total,
                             double max_total) {
    char path[4096];
    ras_io_report rep;
    bool ok = true;
    fmt(path, sizeof path, "%s/scores.csv", g->out);
    FILE *f = report_begin(&rep);
    if (f) {
        fprintf(f, "assignment,item,score,max_score,status\n");
        for (int i = 0; i < n; i++) {
            for (int k = 0; k < as[i].n_items; k++) {
                item *it = &as[i].items[k];
                if (it->counted)
                    fprintf(f, "%s,%s,%g,%g,%s\n", as[i].id, it->name, it->score, it->max_score,
                            it->status);
            }
            if (as[i].graded)
                fprintf(f, "%s,total,%g,%g,\n", as[i].id, as[i].score, as[i].max_score);
        }
        fprintf(f, "all,total,%g,%g,\n", total, max_total);
        ok &= report_end(&rep, path);
    }
    return ok;
}

/* failures.txt — every item that lost points, with what it said (for
 * tests/grading/run-mutants and for a quick read) */
static bool write_failures_txt(const grader *g, assignment_result *as, int n) {
    char path[4096];
    ras_io_report rep;
    bool ok = true;
    fmt(path, sizeof path, "%s/failures.txt", g->out);
    FILE *f = report_begin(&rep);
    if (f) {
        for (int i = 0; i < n; i++)
            for (int k = 0; k < as[i].n_items; k++) {
                item *it = &as[i].items[k];
                if (it->counted && it->score < it->max_score)
                    fprintf(f, "== %s: %s (%s)\n%s\n", as[i].id, it->name, it->status,
                            it->output ? it->output : "");
            }
        ok &= report_end(&rep, path);
    }
    return ok;
}

/* hwN/cmocka.xml — JUnit, one suite per assignment */
static bool write_cmocka_xml(const grader *g, assignment_result *as, int n) {
    char path[4096];
    ras_io_report rep;
    bool ok = true;
    for (int i = 0; i < n; i++) {
        if (!as[i].graded) continue;
        fmt(path, sizeof path, "%s/%s/cmocka.xml", g->out, as[i].id);
        FILE *f = report_begin(&rep);
        if (!f) continue;
        int n_tests = 0, n_fail = 0;
        for (int k = 0; k < as[i].n_items; k++)
            if (!as[i].items[k].is_image && as[i].items[k].counted) {
                n_tests++;
                n_fail += !as[i].items[k].passed;
            }
        fprintf(f,
                "<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<testsuites>\n"
                "  <testsuite name=\"%s\" tests=\"%d\" failures=\"%d\" errors=\"0\" "
                "skipped=\"0\">\n",
                as[i].id, n_tests, n_fail);
        for (int k = 0; k < as[i].n_items; k++)
            if (!as[i].items[k].is_image && as[i].items[k].counted && as[i].items[k].xml)
                fputs(as[i].items[k].xml, f);
        fprintf(f, "  </testsuite>\n</testsuites>\n");
        ok &= report_end(&rep, path);
    }
    return ok;
}

/* The points of the items reported but not counted ("SKIP", "not counted"):
 * what a grade elsewhere (the course's, with its reference programs) adds.
 * *no_reference: every one of them lacks only a reference program (the
 * student edition's variant pictures and integration; grade_images.c). */
static double uncounted_points(const assignment_result *as, int n, bool *no_reference) {
    double sum = 0;
    *no_reference = true;
    for (int i = 0; i < n; i++)
        for (int k = 0; as[i].graded && k < as[i].n_items; k++) {
            const item *it = &as[i].items[k];
            if (it->counted) continue;
            sum += it->max_score;
            *no_reference &= it->reason && !strncmp(it->reason, "no reference program", 20);
        }
    return sum;
}

/* What the course's grade counts that this grading did not, in words for
 * the TOTAL lines (empty when nothing): the items marked "not counted", and
 * the integration part when this grading had none (the student edition: no
 * reference code to link the student's with, so no whole-chain runs). */
static void not_counted_here(const grader *g, const assignment_result *as, int n, char *buf,
                             size_t size) {
    bool no_reference, has_integration = false;
    double more = uncounted_points(as, n, &no_reference);
    for (int i = 0; i < n; i++)
        has_integration |= as[i].graded && !strcmp(as[i].id, "integration");
    double per_image = num_or(g->rubric, "integration_points_per_image", 0);
    buf[0] = '\0';
    if (more <= 0 && (has_integration || per_image <= 0)) return;
    int k = snprintf(buf, size, "the course's grade also counts ");
    if (more > 0 && k >= 0 && (size_t)k < size)
        k += snprintf(buf + k, size - (size_t)k,
                      "the %g points of the items marked \"not counted\" (%s)", more,
                      no_reference ? "the variant pictures, which need the reference programs "
                                     "the student edition lacks"
                                   : "each says why");
    /* (the first of the rubric's assignments builds on none) */
    const cJSON *asgs = cJSON_GetObjectItemCaseSensitive(g->rubric, "assignments");
    const char *first = str_or(asgs ? asgs->child : NULL, "id", "the first");
    if (!has_integration && per_image > 0 && k >= 0 && (size_t)k < size)
        snprintf(buf + k, size - (size_t)k,
                 "%san integration part, which this grading does not run (%g point%s for each "
                 "picture with points of the assignments after %s, drawn again by your whole "
                 "chain)",
                 more > 0 ? " and " : "", per_image, per_image == 1 ? "" : "s", first);
}

/* report.md's opening: the notes on the submission, the total, where to
 * start, the table of assignments. */
static void report_md_top(FILE *f, const grader *g, assignment_result *as, int n, double total,
                          double max_total) {
    fprintf(f, "# Raster101 grade report\n\n");
    if (g->notes && *g->notes) {
        fprintf(f, "**About your submission** (what the grader found in it):\n");
        report_fenced(f, g->notes);
        fputc('\n', f);
    }
    fprintf(f, "**Total: %g / %g**", total, max_total);
    if (strcmp(g->variant, "ref") == 0) fprintf(f, " (reference solutions graded as the student)");
    char more[600];
    not_counted_here(g, as, n, more, sizeof more);
    if (*more) fprintf(f, " (the most this grading gives: %s)", more);
    const char *first_id = NULL;
    const item *first = start_here(as, n, &first_id);
    if (first) {
        /* where to start: what the student should fix first, before details */
        fprintf(f, "\n\n**Start here:** %s `%s` (%s)  \n", first_id, first->name, first->status);
        if (first->where) fprintf(f, "**Where:** %s  \n", first->where);
        char fix[1400];
        fix_line(first, fix, sizeof fix);
        fprintf(f, "**Fix:** ");
        report_cell(f, fix); /* the message may quote what the student's code returned */
    }
    fprintf(f, "\n\n| assignment | points |\n|---|---|\n");
    for (int i = 0; i < n; i++) {
        if (as[i].graded)
            fprintf(f, "| %s %s | %g / %g |\n", as[i].id, as[i].title, as[i].score,
                    as[i].max_score);
        else
            fprintf(f, "| %s %s | not graded: %s |\n", as[i].id, as[i].title,
                    as[i].note ? as[i].note : "");
    }
}

/* A picture of report.md that lost points or did not match: the reference,
 * the student's and their difference (words only for a sealed run), the
 * worst region, the first buffer that differs, the message. */
static void report_md_picture(FILE *f, const item *it) {
    fprintf(f, "\n### %s — %s (%g / %g)\n\n", it->name, it->status, it->score, it->max_score);
    if (it->img_got) { /* sealed runs show no picture: words only */
        fprintf(f, "| reference | yours | difference |\n|---|---|---|\n");
        fprintf(f, "| %s%s%s | ![yours](%s) | %s%s%s |\n",
                it->img_expected ? "![reference](" : "(drawn for this grading: not shown)",
                it->img_expected ? it->img_expected : "", it->img_expected ? ")" : "", it->img_got,
                it->img_diff ? "![difference](" : "", it->img_diff ? it->img_diff : "",
                it->img_diff ? ")" : "");
    }
    if (it->img_crop)
        fprintf(f,
                "\nWorst region (reference | yours | difference):\n\n"
                "![worst region](%s)\n",
                it->img_crop);
    if (it->buf_name && (it->buf_ref || it->buf_got)) /* a variant's: no reference */
        fprintf(f,
                "\nThe first buffer that differs, **%s** (reference | yours | "
                "difference):\n\n| %s%s%s | %s%s%s | %s%s%s |\n|---|---|---|"
                "\n",
                it->buf_name, it->buf_ref ? "![reference](" : "(drawn for this grading: not shown)",
                it->buf_ref ? it->buf_ref : "", it->buf_ref ? ")" : "",
                it->buf_got ? "![yours](" : "", it->buf_got ? it->buf_got : "",
                it->buf_got ? ")" : "", it->buf_diff ? "![difference](" : "",
                it->buf_diff ? it->buf_diff : "", it->buf_diff ? ")" : "");
    report_fenced(f, it->output ? it->output : "");
}

/* An assignment's section of report.md: its items, what the failing tests
 * said, its pictures that lost points. */
static void report_md_assignment(FILE *f, const assignment_result *a) {
    fprintf(f, "\n## %s — %s: %g / %g\n\n", a->id, a->title, a->score, a->max_score);
    if (a->note) fprintf(f, "_%s_\n\n", a->note);
    fprintf(f, "| | test | points | why |\n|---|---|---|---|\n");
    for (int k = 0; k < a->n_items; k++) {
        const item *it = &a->items[k];
        fprintf(f, "| %s | `%s`%s | ", it->status, it->name,
                it->default_weight ? " (default weight)" : "");
        if (it->counted)
            fprintf(f, "%g / %g | ", it->score, it->max_score);
        else
            fprintf(f, "not counted | ");
        report_cell(f, it->reason ? it->reason : "");
        fprintf(f, " |\n");
    }
    bool any_fail = false;
    for (int k = 0; k < a->n_items; k++)
        any_fail |= !a->items[k].is_image && a->items[k].score < a->items[k].max_score &&
                    a->items[k].counted;
    if (any_fail) {
        fprintf(f, "\n### What the failing tests said\n");
        for (int k = 0; k < a->n_items; k++) {
            const item *it = &a->items[k];
            if (it->is_image || !it->counted || it->score >= it->max_score) continue;
            fprintf(f, "\n**`%s`** (%s)\n", it->name, it->status);
            report_fenced(f, it->output ? it->output : "");
        }
    }
    for (int k = 0; k < a->n_items; k++) {
        const item *it = &a->items[k];
        /* only the pictures that lost points or did not match: a
         * passing picture is a line of the table; a variant's reference
         * is drawn for this grading and never shown */
        if (it->is_image && (it->img_expected || it->img_diff || it->img_got) &&
            (!it->passed || it->score < it->max_score))
            report_md_picture(f, it);
    }
}

/* report.md — the student's report, with the pictures */
static bool write_report_md(const grader *g, assignment_result *as, int n, double total,
                            double max_total) {
    char path[4096];
    ras_io_report rep;
    fmt(path, sizeof path, "%s/report.md", g->out);
    FILE *f = report_begin(&rep);
    if (!f) return false;
    report_md_top(f, g, as, n, total, max_total);
    for (int i = 0; i < n; i++)
        if (as[i].graded) report_md_assignment(f, &as[i]);
    return report_end(&rep, path);
}

/* Every report, each written whole or not at all; false when one could not
 * be (report_end said why). */
bool write_outputs(grader *g, assignment_result *as, int n, double total, double max_total) {
    ensure_all_safe(g, as, n);
    bool ok = true;
    ok &= write_results_json(g, as, n, total, max_total);
    ok &= write_scores_csv(g, as, n, total, max_total);
    ok &= write_failures_txt(g, as, n);
    ok &= write_cmocka_xml(g, as, n);
    ok &= write_report_md(g, as, n, total, max_total);
    return ok;
}

/* The printed table's "why" column, which starts at `column`: its text
 * wrapped at spaces into lines of at most WHY_CHARS characters, each one
 * after the first indented to the column, so that no word is cut. */
enum { WHY_CHARS = 64 };

static void print_wrapped_why(int column, const char *why) {
    size_t left = strlen(why);
    bool first = true;
    while (left > 0) {
        size_t n = utf8_prefix(why, left, WHY_CHARS);
        if (n < left) { /* break at the last space that fits, if any */
            size_t sp = n;
            while (sp > 0 && why[sp] != ' ') sp--;
            if (sp > 0) n = sp;
        }
        printf("%s%*s%.*s", first ? "" : "\n", first ? 0 : column, "", (int)n, why);
        first = false;
        why += n;
        left -= n;
        while (left > 0 && *why == ' ') why++, left--;
    }
    putchar('\n');
}

void print_table(const grader *g, assignment_result *as, int n, double total, double max_total) {
    bool defaults = false;
    const char *first_id = NULL;
    const item *first = start_here(as, n, &first_id);
    if (first) {
        printf("START HERE: %s %s (%s)\n", first_id, first->name, first->status);
        if (first->where) printf("  where: %s\n", first->where);
        char fix[1400];
        fix_line(first, fix, sizeof fix);
        printf("  fix:   %s\n\n", fix);
    }
    for (int i = 0; i < n; i++) {
        assignment_result *a = &as[i];
        if (!a->graded) {
            printf("%-4s %-48s not graded: %s\n", a->id, a->title, a->note ? a->note : "");
            continue;
        }
        printf("%s  %s\n", a->id, a->title);
        if (a->note) printf("  note: %s\n", a->note);
        for (int k = 0; k < a->n_items; k++) {
            item *it = &a->items[k];
            char name[300];
            fmt(name, sizeof name, "%s%s", it->name, it->default_weight ? " *" : "");
            defaults |= it->default_weight;
            int column =
                it->counted ? printf("  %-7s %-50.50s %5g / %-3g ", it->status, name, it->score,
                                     it->max_score)
                            : printf("  %-7s %-50.50s   (not counted) ", it->status, name);
            print_wrapped_why(column > 0 ? column : 0, it->reason ? it->reason : "");
        }
        printf("  %-58s %5g / %-3g (%.1f s)\n", "total", a->score, a->max_score, a->seconds);
    }
    if (defaults)
        printf("* not in tests/grading/rubric.json: scored with the default weight (%g point%s)\n",
               g->default_points, g->default_points == 1 ? "" : "s");
    printf("TOTAL %g / %g%s\n", total, max_total,
           strcmp(g->variant, "ref") == 0 ? "   (reference solutions graded as the student)" : "");
    char more[600];
    not_counted_here(g, as, n, more, sizeof more);
    if (*more) printf("      %g is the most this grading gives: %s\n", max_total, more);
    printf("report: %s/report.md   Gradescope: %s/results.json\n", g->out, g->out);
}
