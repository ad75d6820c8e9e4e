/* class_tool.c — raster101-class: the class view and the LMS gradebooks of a
 * graded class (tests/grading/grade-all's output folder; docs/instructors.md,
 * "The class view" and "LMS gradebooks").
 *
 *   raster101-class view OUT
 *       reads OUT/students/NAME/ (results.json, scores.csv, missing.txt and
 *       grade-all's status) and writes OUT/class.json and OUT/class.html
 *   raster101-class html CLASS.json HTML
 *       renders a class.json as the page alone (the 500-student benchmark)
 *   raster101-class roster OUT ROSTER.csv
 *       OUT/class.json's scores keyed by the roster (CSV: name,id,email;
 *       a student's name is their submission's name, exactly): writes
 *       OUT/canvas.csv, OUT/moodle.csv and OUT/roster-problems.txt (the
 *       roster's names without a submission and the submissions without a
 *       roster row; never guessed)
 *
 * Everything in a student's folder came from a grading of hostile code: it
 * is read without following links (grade_base.h's read_small_file), every
 * text through grade_text.h's safe_text and then HTML-escaped, every link
 * built here from the folder's name, percent-encoded.
 *
 * Exit status: 0 done (roster: problems are listed, not failed), 2 bad
 * arguments or a file that cannot be read or written.
 */
#include "class_view.h"
#include "grade_base.h"
#include "grade_text.h"
#include "ras_io.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

enum {
    TEXT_CAP = 400, /* bytes of one quoted line */
    /* bytes of a likely-mistake line: the grader's diagnoses run to ~600,
     * and a mistake is grouped by its whole text */
    MISTAKE_CAP = 2000,
    RESULTS_LIMIT = 8 << 20,  /* a results.json larger than this is cut (and then unreadable) */
    SMALL_LIMIT = 64 << 10,   /* scores.csv, missing.txt, status */
    BINS = 10,                /* a histogram's bars */
    MISTAKE_NAMES_SHOWN = 40, /* names listed in a mistake's row before "and N more" */
};

/* ---------------------------------------------------------------- text */

/* text from a student's folder, made safe (grade_text.h) and at most TEXT_CAP bytes (owned) */
static char *shown(const char *raw) { return safe_text(raw ? raw : "", TEXT_CAP); }

static void html(sbuf *b, const char *s) {
    for (; s && *s; s++) {
        switch (*s) {
        case '&': sb_add(b, "&amp;"); break;
        case '<': sb_add(b, "&lt;"); break;
        case '>': sb_add(b, "&gt;"); break;
        case '"': sb_add(b, "&quot;"); break;
        case '\'': sb_add(b, "&#39;"); break;
        default: sb_addn(b, s, 1);
        }
    }
}

/* A folder's name as one URL path segment: every byte but letters, digits
 * and "-._~" percent-encoded, so no name can leave its folder or open a
 * scheme ("javascript:") or a query. */
static void url_segment(sbuf *b, const char *s) {
    for (const unsigned char *c = (const unsigned char *)s; *c; c++) {
        if (isalnum(*c) || strchr("-._~", *c))
            sb_addn(b, (const char *)c, 1);
        else
            sb_printf(b, "%%%02X", *c);
    }
}

/* Whether a link read back from class.json is one this tool writes:
 * students/SEGMENT/... of URL-safe characters, no "..", nothing else. */
static bool link_ok(const char *l) {
    if (!l || strncmp(l, "students/", 9) || strstr(l, "..")) return false;
    for (const char *c = l; *c; c++)
        if (!isalnum((unsigned char)*c) && !strchr("-._~%/", *c)) return false;
    return true;
}

/* A mistake's key: its line with every number written "#" (a number: digits,
 * with a sign and a decimal part, not part of a word such as "hw3"), runs of
 * spaces as one. */
static char *mistake_key(const char *line) {
    sbuf b = {0};
    const char *p = line;
    while (*p == ' ')
        p++;
    for (; *p; p++) {
        bool word_before = p > line && (isalnum((unsigned char)p[-1]) || p[-1] == '_');
        bool sign = (*p == '-' || *p == '+') && isdigit((unsigned char)p[1]) && !word_before;
        if ((isdigit((unsigned char)*p) && !word_before) || sign) {
            p += sign;
            while (isdigit((unsigned char)p[1]) ||
                   ((p[1] == '.' || p[1] == ',') && isdigit((unsigned char)p[2])))
                p++;
            sb_add(&b, "#");
        } else if (*p == ' ' && b.len && b.s[b.len - 1] == ' ') {
            continue;
        } else {
            sb_addn(&b, p, 1);
        }
    }
    while (b.len && b.s[b.len - 1] == ' ')
        b.s[--b.len] = '\0';
    return b.s ? b.s : xstrdup("");
}

/* The "likely mistake: " line of a failing item's message, as report.md's
 * fix line finds it (grade_report.c, fix_line): the first, in either case,
 * on a line the grader wrote — never on one the student's code printed,
 * which the grader marks "│ ". NULL when there is none (owned). */
static char *likely_mistake(const char *out) {
    const char *line = out;
    for (const char *q = out; q && *q; q++) {
        if (q > out && q[-1] == '\n') line = q;
        if (!strncasecmp(q, "likely mistake: ", 16) && strncmp(line, "\xe2\x94\x82 ", 4)) {
            q += 16;
            char *raw = strndup(q, strcspn(q, "\n"));
            char *safe = safe_text(raw, MISTAKE_CAP);
            free(raw);
            return safe;
        }
    }
    return NULL;
}

/* ---------------------------------------------------------------- one student's folder */

static char *student_file(const char *out, const char *name, const char *file, size_t limit) {
    char path[8192];
    fmt(path, sizeof path, "%s/students/%s/%s", out, name, file);
    return read_small_file(path, limit);
}

/* Whether students/NAME/REL is a regular file (not a link), REL of
 * [A-Za-z0-9_./] only: a picture the page may show. */
static bool student_picture(const char *out, const char *name, const char *rel) {
    for (const char *c = rel; *c; c++)
        if (!isalnum((unsigned char)*c) && !strchr("_./", *c)) return false;
    if (strstr(rel, "..")) return false;
    char path[8192], why[200];
    const char *file;
    fmt(path, sizeof path, "%s/students/%s/%s", out, name, rel);
    int dfd = sandbox_dir_of(path, &file, why, sizeof why);
    long long size = 0;
    int fd = dfd >= 0 ? sandbox_open(dfd, file, &size, why, sizeof why) : -1;
    if (dfd >= 0) close(dfd);
    if (fd >= 0) close(fd);
    return fd >= 0;
}

/* A link to a student's file: students/NAME/REL, NAME percent-encoded (owned) */
static char *student_link(const char *name, const char *rel) {
    sbuf b = {0};
    sb_add(&b, "students/");
    url_segment(&b, name);
    sb_printf(&b, "/%s", rel);
    return b.s;
}

/* The pictures of a failing picture item "ASG: ... image NAME ...": the
 * reference (only when OUT holds it: never a variant's, which it does not),
 * the student's and the difference, as links; NULL when OUT has no picture
 * of the student's for it (a sealed run shows none). */
static cJSON *picture_of(const char *out, const char *student, const char *item) {
    const char *img = strstr(item, "image ");
    size_t asg_len = strcspn(item, ":");
    if (!img || item[asg_len] != ':' || asg_len == 0 || asg_len > 40) return NULL;
    /* a whole-chain item "integration: hw2 image NAME, your whole chain"
     * keeps its pictures in its assignment's folder (hw2/) */
    const char *folder = item;
    if (item[asg_len + 1] == ' ' && img > item + asg_len + 2 && img[-1] == ' ') {
        const char *w = item + asg_len + 2;
        size_t wl = strspn(w, "abcdefghijklmnopqrstuvwxyz0123456789");
        if (wl && w + wl + 1 == img) folder = w, asg_len = wl;
    }
    img += 6;
    size_t n = strspn(img, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_");
    if (n == 0 || n > 100) return NULL;
    static const char *const kinds[] = {"expected", "got", "diff"};
    static const char *const keys[] = {"reference", "yours", "difference"};
    cJSON *pic = cJSON_CreateObject();
    for (int k = 0; k < 3; k++) {
        char rel[300];
        fmt(rel, sizeof rel, "%.*s/%.*s.%s.png", (int)asg_len, folder, (int)n, img, kinds[k]);
        if (student_picture(out, student, rel)) {
            char *l = student_link(student, rel);
            cJSON_AddStringToObject(pic, keys[k], l);
            free(l);
        } else if (k > 0) {
            cJSON_Delete(pic);
            return NULL;
        }
    }
    return pic;
}

/* scores.csv's rows "assignment,item,score,max_score,status" (an item's
 * name may hold commas: the status is the last field, the assignment the
 * first): each assignment's count of BUILD, CRASH and TIMEOUT items. */
static void attention_from_scores(const char *csv, cJSON *reasons) {
    cJSON *counts = cJSON_CreateObject();
    const char *line = csv;
    while (line && *line) {
        size_t len = strcspn(line, "\n");
        const char *comma = memchr(line, ',', len), *last = line + len;
        while (last > line && last[-1] != ',')
            last--;
        if (comma && last > comma) {
            char asg[64], status[16];
            fmt(asg, sizeof asg, "%.*s", (int)(comma - line), line);
            fmt(status, sizeof status, "%.*s", (int)(line + len - last), last);
            if (!strcmp(status, "BUILD") || !strcmp(status, "CRASH") ||
                !strcmp(status, "TIMEOUT")) {
                char key[100];
                fmt(key, sizeof key, "%s %s", asg, status);
                cJSON *c = cJSON_GetObjectItemCaseSensitive(counts, key);
                if (c)
                    cJSON_SetNumberValue(c, c->valuedouble + 1);
                else
                    cJSON_AddNumberToObject(counts, key, 1);
            }
        }
        line += len + (line[len] == '\n');
    }
    cJSON *c;
    cJSON_ArrayForEach(c, counts) {
        char asg[64], status[16], text[200];
        sscanf(c->string, "%63s %15s", asg, status);
        char *a = shown(asg);
        if (!strcmp(status, "BUILD"))
            fmt(text, sizeof text, "%s: does not compile", a);
        else
            fmt(text, sizeof text, "%s: %g %s %s", a, c->valuedouble,
                c->valuedouble == 1 ? "item" : "items",
                !strcmp(status, "CRASH") ? "crashed" : "timed out");
        cJSON_AddItemToArray(reasons, cJSON_CreateString(text));
        free(a);
    }
    cJSON_Delete(counts);
}

/* Why a student needs a TA's attention: no results at all, a file missing
 * (graded as the stub), an assignment that does not compile, items that
 * crashed or timed out, a grading stopped (grade-all's status). */
static cJSON *attention_of(const char *out, const char *name, bool graded) {
    cJSON *reasons = cJSON_CreateArray();
    char *status = student_file(out, name, "status", SMALL_LIMIT);
    if (status) status[strcspn(status, "\n")] = '\0';
    if (!graded) {
        char *s = shown(status && *status ? status : "no results.json: see grade.log");
        char text[600];
        fmt(text, sizeof text, "not graded: %s", s);
        cJSON_AddItemToArray(reasons, cJSON_CreateString(text));
        free(s);
    }
    char *missing = student_file(out, name, "missing.txt", SMALL_LIMIT);
    if (missing && *missing) {
        for (char *c = missing; *c; c++)
            if (*c == '\n') *c = ' ';
        char *m = shown(missing), text[600];
        fmt(text, sizeof text, "missing %s(graded as the stub)", m);
        cJSON_AddItemToArray(reasons, cJSON_CreateString(text));
        free(m);
    }
    if (graded && status && strstr(status, "took longer"))
        cJSON_AddItemToArray(reasons, cJSON_CreateString("grading timed out and was stopped"));
    char *scores = student_file(out, name, "scores.csv", SMALL_LIMIT);
    attention_from_scores(scores, reasons);
    free(scores);
    free(missing);
    free(status);
    return reasons;
}

/* ---------------------------------------------------------------- the class */

typedef struct klass {
    const char *out;
    cJSON *students, *assignments, *items, *mistakes, *attention;
} klass;

static cJSON *find_by(cJSON *array, const char *key, const char *value) {
    cJSON *e;
    cJSON_ArrayForEach(e, array) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(e, key);
        if (cJSON_IsString(v) && !strcmp(v->valuestring, value)) return e;
    }
    return NULL;
}

static cJSON *add_name(cJSON *to, const char *name, const char *link) {
    cJSON *n = cJSON_CreateObject();
    cJSON_AddStringToObject(n, "name", name);
    cJSON_AddStringToObject(n, "link", link);
    cJSON_AddItemToArray(to, n);
    return n;
}

static void add_unique_string(cJSON *array, const char *s) {
    cJSON *e;
    cJSON_ArrayForEach(e, array) if (!strcmp(e->valuestring, s)) return;
    cJSON_AddItemToArray(array, cJSON_CreateString(s));
}

/* The object of `array` whose `key` is `value`; *made when it is new (added
 * with that key only, for the caller to fill in). */
static cJSON *find_or_add(cJSON *array, const char *key, const char *value, bool *made) {
    cJSON *o = find_by(array, key, value);
    *made = !o;
    if (o) return o;
    o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, key, value);
    cJSON_AddItemToArray(array, o);
    return o;
}

/* Adds one to the number `key` of `o`. */
static void count_one(cJSON *o, const char *key) {
    cJSON *n = cJSON_GetObjectItemCaseSensitive(o, key);
    cJSON_SetNumberValue(n, n->valuedouble + 1);
}

/* One assignment's score of one student, into the assignment's tally. */
static void tally_assignment(klass *k, const char *id, double score, double max) {
    bool made;
    cJSON *a = find_or_add(k->assignments, "id", id, &made);
    if (made) {
        cJSON_AddNumberToObject(a, "max", max);
        cJSON_AddNumberToObject(a, "graded", 0);
        cJSON *h = cJSON_AddArrayToObject(a, "histogram");
        for (int i = 0; i < BINS; i++)
            cJSON_AddItemToArray(h, cJSON_CreateNumber(0));
    }
    count_one(a, "graded");
    cJSON *m = cJSON_GetObjectItemCaseSensitive(a, "max");
    if (max > m->valuedouble) cJSON_SetNumberValue(m, max);
    /* by the fraction of the points: a full score is the last bar */
    int bin = max > 0 ? (int)(score / max * BINS) : BINS - 1;
    bin = bin < 0 ? 0 : bin >= BINS ? BINS - 1 : bin;
    cJSON *bar = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(a, "histogram"), bin);
    cJSON_SetNumberValue(bar, bar->valuedouble + 1);
}

static void tally_item(klass *k, const char *name, double max, bool passed) {
    bool made;
    cJSON *it = find_or_add(k->items, "item", name, &made);
    if (made) {
        cJSON_AddNumberToObject(it, "max", max);
        cJSON_AddNumberToObject(it, "graded", 0);
        cJSON_AddNumberToObject(it, "passed", 0);
    }
    count_one(it, "graded");
    if (passed) count_one(it, "passed");
}

/* A failing item's named mistake, counted once per student (a student who
 * makes it in three items counts once; the items are listed). */
static void tally_mistake(klass *k, const char *raw_name, const char *name, const char *link,
                          const char *item, const char *line) {
    char *key = mistake_key(line);
    bool made;
    cJSON *m = find_or_add(k->mistakes, "mistake", key, &made);
    if (made) {
        cJSON_AddStringToObject(m, "example", line);
        cJSON_AddNumberToObject(m, "students", 0);
        cJSON_AddArrayToObject(m, "who");
        cJSON_AddArrayToObject(m, "items");
    }
    free(key);
    cJSON *who = cJSON_GetObjectItemCaseSensitive(m, "who");
    if (!find_by(who, "name", name)) {
        add_name(who, name, link);
        count_one(m, "students");
    }
    add_unique_string(cJSON_GetObjectItemCaseSensitive(m, "items"), item);
    /* one picture: the first student's, or a later one's that has its
     * reference (the first's was a variant's, drawn for that grading) */
    cJSON *had = cJSON_GetObjectItemCaseSensitive(m, "picture");
    if ((!had || !cJSON_GetObjectItemCaseSensitive(had, "reference")) && strstr(item, "image ")) {
        cJSON *pic = picture_of(k->out, raw_name, item);
        if (pic && (!had || cJSON_GetObjectItemCaseSensitive(pic, "reference"))) {
            cJSON_AddStringToObject(pic, "student", name);
            cJSON_AddStringToObject(pic, "item", item);
            if (had)
                cJSON_ReplaceItemInObjectCaseSensitive(m, "picture", pic);
            else
                cJSON_AddItemToObject(m, "picture", pic);
        } else {
            cJSON_Delete(pic);
        }
    }
}

/* results.json's tests: each item's pass and its named mistake. */
static void read_results(klass *k, const cJSON *results, const char *raw_name, const char *name,
                         const char *link, cJSON *student) {
    const cJSON *t;
    cJSON_ArrayForEach(t, cJSON_GetObjectItemCaseSensitive(results, "tests")) {
        double score = num_or(t, "score", 0), max = num_or(t, "max_score", 0);
        if (max <= 0) continue; /* not part of any score */
        char *item = shown(str_or(t, "name", "?"));
        tally_item(k, item, max, score >= max);
        if (score < max) {
            char *line = likely_mistake(str_or(t, "output", ""));
            if (line && *line) tally_mistake(k, raw_name, name, link, item, line);
            free(line);
        }
        free(item);
    }
    cJSON *asgs = cJSON_AddObjectToObject(student, "assignments");
    const cJSON *a;
    cJSON_ArrayForEach(a, cJSON_GetObjectItemCaseSensitive(results, "extra_data")) {
        if (!cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(a, "graded"))) continue;
        char *id = shown(a->string);
        double score = num_or(a, "score", 0), max = num_or(a, "max_score", 0);
        cJSON *sa = cJSON_AddObjectToObject(asgs, id);
        cJSON_AddNumberToObject(sa, "score", score);
        cJSON_AddNumberToObject(sa, "max", max);
        tally_assignment(k, id, score, max);
        free(id);
    }
}

static void read_student(klass *k, const char *raw_name) {
    char *name = shown(raw_name), *link = student_link(raw_name, "report.md");
    cJSON *s = cJSON_CreateObject();
    cJSON_AddStringToObject(s, "name", name);
    cJSON_AddStringToObject(s, "link", link);
    char *text = student_file(k->out, raw_name, "results.json", RESULTS_LIMIT);
    cJSON *results = text ? cJSON_Parse(text) : NULL;
    bool graded = cJSON_IsObject(results);
    cJSON_AddBoolToObject(s, "graded", graded);
    if (graded) {
        cJSON_AddNumberToObject(s, "total", num_or(results, "score", 0));
        cJSON_AddNumberToObject(s, "max", num_or(results, "max_score", 0));
        read_results(k, results, raw_name, name, link, s);
    }
    cJSON *reasons = attention_of(k->out, raw_name, graded);
    if (cJSON_GetArraySize(reasons)) {
        cJSON *a = add_name(k->attention, name, link);
        cJSON_AddItemReferenceToObject(a, "reasons", reasons);
    }
    cJSON_AddItemToObject(s, "attention", reasons);
    cJSON_AddItemToArray(k->students, s);
    cJSON_Delete(results);
    free(text);
    free(name);
    free(link);
}

static int by_name(const void *a, const void *b) {
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int by_students(const void *a, const void *b) {
    const cJSON *x = *(cJSON *const *)a, *y = *(cJSON *const *)b;
    double nx = num_or(x, "students", 0), ny = num_or(y, "students", 0);
    if (nx != ny) return nx < ny ? 1 : -1;
    return strcmp(str_or(x, "mistake", ""), str_or(y, "mistake", ""));
}

/* The mistakes, most students first (ties by text, so the page is the same
 * at every run). */
static void rank_mistakes(cJSON *mistakes) {
    int n = cJSON_GetArraySize(mistakes);
    cJSON **v = calloc((size_t)n + 1, sizeof *v);
    for (int i = n - 1; i >= 0; i--)
        v[i] = cJSON_DetachItemFromArray(mistakes, i);
    qsort(v, (size_t)n, sizeof *v, by_students);
    for (int i = 0; i < n; i++)
        cJSON_AddItemToArray(mistakes, v[i]);
    free(v);
}

/* OUT/students/'s folders (never a link), by name. */
static bool list_students(const char *out, name_list *names) {
    char path[8192], why[200];
    fmt(path, sizeof path, "%s/students", out);
    int dfd = sandbox_dir(path, why, sizeof why);
    DIR *d = dfd >= 0 ? fdopendir(dfd) : NULL;
    if (!d) {
        fprintf(stderr, "raster101-class: expected the folder %s (grade-all's students), got %s\n",
                path, dfd < 0 ? why : "an unreadable folder");
        if (dfd >= 0) close(dfd);
        return false;
    }
    struct dirent *e;
    while ((e = readdir(d))) {
        struct stat st;
        if (e->d_name[0] == '.' || fstatat(dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) ||
            !S_ISDIR(st.st_mode))
            continue;
        names_add(names, e->d_name);
    }
    closedir(d);
    qsort(names->v, (size_t)names->n, sizeof *names->v, by_name);
    return true;
}

static cJSON *read_class(const char *out) {
    name_list names = {0};
    if (!list_students(out, &names)) return NULL;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", "raster101-class 1");
    klass k = {.out = out,
               .students = cJSON_AddArrayToObject(root, "students"),
               .assignments = cJSON_AddArrayToObject(root, "assignments"),
               .items = cJSON_AddArrayToObject(root, "items"),
               .mistakes = cJSON_AddArrayToObject(root, "mistakes"),
               .attention = cJSON_AddArrayToObject(root, "attention")};
    for (int i = 0; i < names.n; i++)
        read_student(&k, names.v[i]);
    rank_mistakes(k.mistakes);
    names_free(&names);
    return root;
}

/* ---------------------------------------------------------------- the page */

static const char *page_style =
    "body{font:15px/1.4 system-ui,sans-serif;margin:1.5em auto;max-width:72em;padding:0 1em;"
    "color:#111;background:#fff}"
    "table{border-collapse:collapse;margin:.5em 0 1.5em}"
    "td,th{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}"
    "th{background:#f0f0f0}td.n{text-align:right}"
    ".bar{background:#4a7;height:.8em;display:inline-block}"
    ".warn{background:#fff3e0}img{image-rendering:pixelated;width:160px;border:1px solid #999}"
    "figure{display:inline-block;margin:0 .5em 0 0;vertical-align:top}figcaption{font-size:.85em}"
    ".none{display:inline-flex;width:160px;height:160px;border:1px dashed #999;align-items:center;"
    "text-align:center;font-size:.85em}"
    "svg text{font:11px sans-serif}";

static void link_to(sbuf *b, const cJSON *who) {
    const char *l = str_or(who, "link", NULL), *n = str_or(who, "name", "?");
    if (link_ok(l)) {
        sb_add(b, "<a href=\"");
        html(b, l);
        sb_add(b, "\">");
        html(b, n);
        sb_add(b, "</a>");
    } else {
        html(b, n);
    }
}

static void page_attention(sbuf *b, const cJSON *root) {
    const cJSON *att = cJSON_GetObjectItemCaseSensitive(root, "attention"), *a, *r;
    sb_printf(b, "<h2 id=\"attention\">Students needing attention (%d)</h2>\n",
              cJSON_GetArraySize(att));
    if (!cJSON_GetArraySize(att)) {
        sb_add(b, "<p>None: every submission compiled, ran and had all its files.</p>\n");
        return;
    }
    sb_add(b, "<table class=\"warn\"><tr><th>student</th><th>why</th></tr>\n");
    cJSON_ArrayForEach(a, att) {
        sb_add(b, "<tr><td>");
        link_to(b, a);
        sb_add(b, "</td><td>");
        cJSON_ArrayForEach(r, cJSON_GetObjectItemCaseSensitive(a, "reasons")) {
            html(b, cJSON_IsString(r) ? r->valuestring : "");
            sb_add(b, r->next ? "<br>" : "");
        }
        sb_add(b, "</td></tr>\n");
    }
    sb_add(b, "</table>\n");
}

static void page_picture(sbuf *b, const cJSON *pic) {
    static const char *const keys[] = {"reference", "yours", "difference"};
    static const char *const captions[] = {"reference", "the student's", "difference"};
    sb_add(b, "<div>");
    for (int k = 0; k < 3; k++) {
        const char *l = str_or(pic, keys[k], NULL);
        sb_add(b, "<figure>");
        if (link_ok(l)) {
            sb_add(b, "<img alt=\"");
            html(b, captions[k]);
            sb_add(b, "\" src=\"");
            html(b, l);
            sb_add(b, "\">");
        } else {
            sb_add(b, "<span class=\"none\">drawn for this grading: not shown</span>");
        }
        sb_printf(b, "<figcaption>%s</figcaption></figure>", captions[k]);
    }
    sb_add(b, "<br><small>");
    html(b, str_or(pic, "student", "?"));
    sb_add(b, ", ");
    html(b, str_or(pic, "item", "?"));
    sb_add(b, "</small></div>");
}

static void page_mistakes(sbuf *b, const cJSON *root) {
    const cJSON *ms = cJSON_GetObjectItemCaseSensitive(root, "mistakes"), *m, *e;
    sb_printf(b, "<h2 id=\"mistakes\">Named mistakes, most students first (%d)</h2>\n",
              cJSON_GetArraySize(ms));
    sb_add(b, "<p>Each failing item's “likely mistake” line, numbers written #, counted once "
              "per student.</p>\n<table id=\"mistake-table\"><tr><th>#</th><th>students</th>"
              "<th>likely mistake</th><th>in items</th><th>who</th></tr>\n");
    int rank = 0;
    cJSON_ArrayForEach(m, ms) {
        sb_printf(b, "<tr class=\"mistake\"><td class=\"n\">%d</td><td class=\"n\">%g</td><td>",
                  ++rank, num_or(m, "students", 0));
        html(b, str_or(m, "mistake", ""));
        sb_add(b, "</td><td>");
        cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(m, "items")) {
            html(b, cJSON_IsString(e) ? e->valuestring : "");
            sb_add(b, e->next ? "<br>" : "");
        }
        sb_add(b, "</td><td>");
        int shown_names = 0, all = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(m, "who"));
        cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(m, "who")) {
            if (shown_names == MISTAKE_NAMES_SHOWN) {
                sb_printf(b, " and %d more (the table of students below)", all - shown_names);
                break;
            }
            sb_add(b, shown_names++ ? ", " : "");
            link_to(b, e);
        }
        sb_add(b, "</td></tr>\n");
        /* its picture on a row of its own, the three side by side */
        const cJSON *pic = cJSON_GetObjectItemCaseSensitive(m, "picture");
        if (pic) {
            sb_add(b, "<tr class=\"picture\"><td></td><td></td><td colspan=\"3\">");
            page_picture(b, pic);
            sb_add(b, "</td></tr>\n");
        }
    }
    sb_add(b, "</table>\n");
}

/* One assignment's histogram: BINS bars of 10 % of the points each, as an
 * inline SVG (no script, no network). */
static void page_histogram(sbuf *b, const cJSON *a) {
    const cJSON *h = cJSON_GetObjectItemCaseSensitive(a, "histogram"), *bar;
    double top = 1, max = num_or(a, "max", 0);
    cJSON_ArrayForEach(bar, h) if (bar->valuedouble > top) top = bar->valuedouble;
    const int W = 36, H = 120;
    sb_printf(b, "<figure><svg width=\"%d\" height=\"%d\" role=\"img\"><title>", BINS * W + 10,
              H + 40);
    html(b, str_or(a, "id", "?"));
    sb_add(b, ": students by score</title>");
    int i = 0;
    cJSON_ArrayForEach(bar, h) {
        int height = (int)(bar->valuedouble / top * H + 0.5);
        sb_printf(b,
                  "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"#4a7\"/>"
                  "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">%g</text>"
                  "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">%g</text>",
                  5 + i * W, 12 + H - height, W - 4, height, 5 + i * W + W / 2 - 2, 10 + H - height,
                  bar->valuedouble, 5 + i * W + W / 2 - 2, H + 26, max * (i + 1) / BINS);
        i++;
    }
    sb_add(b, "</svg><figcaption>");
    html(b, str_or(a, "id", "?"));
    sb_printf(b,
              ": %g students graded; bars: students scoring up to the points below each "
              "(of %g)</figcaption></figure>\n",
              num_or(a, "graded", 0), max);
}

static void page_items(sbuf *b, const cJSON *root) {
    const cJSON *it;
    sb_add(b, "<h2 id=\"items\">Rubric items: pass rate</h2>\n<table><tr><th>item</th>"
              "<th>points</th><th>passed</th><th>rate</th></tr>\n");
    cJSON_ArrayForEach(it, cJSON_GetObjectItemCaseSensitive(root, "items")) {
        double g = num_or(it, "graded", 0), p = num_or(it, "passed", 0);
        double rate = g > 0 ? 100 * p / g : 0;
        sb_add(b, "<tr><td>");
        html(b, str_or(it, "item", "?"));
        sb_printf(b,
                  "</td><td class=\"n\">%g</td><td class=\"n\">%g / %g</td><td>"
                  "<span class=\"bar\" style=\"width:%.0fpx\"></span> %.0f%%</td></tr>\n",
                  num_or(it, "max", 0), p, g, rate, rate);
    }
    sb_add(b, "</table>\n");
}

static void page_students(sbuf *b, const cJSON *root) {
    const cJSON *asgs = cJSON_GetObjectItemCaseSensitive(root, "assignments"), *a, *s;
    sb_add(b, "<h2 id=\"students\">Students</h2>\n<table><tr><th>student</th><th>total</th>");
    cJSON_ArrayForEach(a, asgs) {
        sb_add(b, "<th>");
        html(b, str_or(a, "id", "?"));
        sb_add(b, "</th>");
    }
    sb_add(b, "</tr>\n");
    cJSON_ArrayForEach(s, cJSON_GetObjectItemCaseSensitive(root, "students")) {
        sb_add(b, "<tr><td>");
        link_to(b, s);
        if (cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(s, "graded")))
            sb_printf(b, "</td><td class=\"n\">%g / %g</td>", num_or(s, "total", 0),
                      num_or(s, "max", 0));
        else
            sb_add(b, "</td><td>not graded</td>");
        const cJSON *mine = cJSON_GetObjectItemCaseSensitive(s, "assignments");
        cJSON_ArrayForEach(a, asgs) {
            const cJSON *sa = cJSON_GetObjectItemCaseSensitive(mine, str_or(a, "id", ""));
            if (sa)
                sb_printf(b, "<td class=\"n\">%g</td>", num_or(sa, "score", 0));
            else
                sb_add(b, "<td>—</td>");
        }
        sb_add(b, "</tr>\n");
    }
    sb_add(b, "</table>\n");
}

static char *render_page(const cJSON *root) {
    sbuf b = {0};
    const cJSON *a;
    int n = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "students"));
    sb_printf(&b,
              "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
              "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
              "img-src 'self'; style-src 'unsafe-inline'\">"
              "<title>Raster101 class view</title><style>%s</style></head><body>\n"
              "<h1>Raster101 class view: %d students</h1>\n"
              "<p><a href=\"#attention\">needing attention</a> · <a href=\"#mistakes\">named "
              "mistakes</a> · <a href=\"#scores\">scores</a> · <a href=\"#items\">rubric "
              "items</a> · <a href=\"#students\">students</a> · <a "
              "href=\"gradebook.csv\">gradebook.csv</a></p>\n",
              page_style, n);
    page_attention(&b, root);
    page_mistakes(&b, root);
    sb_add(&b, "<h2 id=\"scores\">Score distribution</h2>\n");
    cJSON_ArrayForEach(a, cJSON_GetObjectItemCaseSensitive(root, "assignments"))
        page_histogram(&b, a);
    page_items(&b, root);
    page_students(&b, root);
    sb_add(&b, "</body></html>\n");
    return b.s;
}

/* ---------------------------------------------------------------- files */

bool class_write_whole(const char *path, const char *text) {
    ras_error err = {{0}};
    if (ras_io_write_atomic(path, "class view file", text, strlen(text), NULL, NULL, &err))
        return true;
    fprintf(stderr, "raster101-class: %s\n", err.msg);
    return false;
}

static cJSON *read_json(const char *path) {
    char *text = read_file(path, 0);
    cJSON *j = text ? cJSON_Parse(text) : NULL;
    free(text);
    if (!cJSON_IsObject(j))
        fprintf(stderr,
                "raster101-class: expected a class.json (raster101-class view) at %s, "
                "got %s\n",
                path, text ? "something that is not a JSON object" : "no readable file");
    return j;
}

static int cmd_html(const char *json_path, const char *html_path) {
    cJSON *root = read_json(json_path);
    if (!root) return 2;
    char *page = render_page(root);
    bool ok = class_write_whole(html_path, page);
    free(page);
    cJSON_Delete(root);
    return ok ? 0 : 2;
}

static int cmd_view(const char *out) {
    cJSON *root = read_class(out);
    if (!root) return 2;
    char path[8192];
    char *json = cJSON_Print(root), *page = render_page(root);
    fmt(path, sizeof path, "%s/class.json", out);
    bool ok = class_write_whole(path, json);
    fmt(path, sizeof path, "%s/class.html", out);
    ok = class_write_whole(path, page) && ok;
    printf("raster101-class: %d students, %d named mistakes, %d needing attention: %s\n",
           cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "students")),
           cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "mistakes")),
           cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "attention")), path);
    free(json);
    free(page);
    cJSON_Delete(root);
    return ok ? 0 : 2;
}

int main(int argc, char **argv) {
    if (argc == 3 && !strcmp(argv[1], "view")) return cmd_view(argv[2]);
    if (argc == 4 && !strcmp(argv[1], "html")) return cmd_html(argv[2], argv[3]);
    if (argc == 4 && !strcmp(argv[1], "roster")) return roster_main(argv[2], argv[3]);
    fprintf(stderr, "usage: raster101-class view OUT | html CLASS.json HTML | roster OUT "
                    "ROSTER.csv\n");
    return 2;
}
