/* grade_intake.c — what a grading is given (grade_intake.h). */
#include "grade_intake.h"

#include "grade_base.h"
#include "grade_text.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* --list RUBRIC: "hwN program..." per assignment, for tests/grading/grade */
int intake_list(const char *list) {
    char *t = read_file(list, 0);
    cJSON *r = t ? cJSON_Parse(t) : NULL;
    free(t);
    const cJSON *as = cJSON_GetObjectItemCaseSensitive(r, "assignments");
    if (!cJSON_IsArray(as)) {
        fprintf(stderr, "raster101-grade: %s: missing, not JSON or no \"assignments\"\n", list);
        return 2;
    }
    for (const cJSON *a = as->child; a; a = a->next) {
        printf("%s", str_or(a, "id", "?"));
        name_list progs = {0};
        const cJSON *imgs = cJSON_GetObjectItemCaseSensitive(a, "images");
        for (const cJSON *i = imgs ? imgs->child : NULL; i; i = i->next)
            if (!names_has(&progs, str_or(i, "program", ""))) {
                names_add(&progs, str_or(i, "program", ""));
                printf(" %s", str_or(i, "program", ""));
            }
        printf("\n");
        names_free(&progs);
    }
    cJSON_Delete(r);
    return 0;
}

/* The rubric with its defaults and limits. */
const cJSON *intake_rubric(grader *g, const char *rubric_path) {
    char *text = read_file(rubric_path, 0);
    g->rubric = text ? cJSON_Parse(text) : NULL;
    free(text);
    const cJSON *asgs = cJSON_GetObjectItemCaseSensitive(g->rubric, "assignments");
    if (!cJSON_IsArray(asgs)) {
        fprintf(stderr, "raster101-grade: %s: %s\n", rubric_path,
                g->rubric ? "no \"assignments\" array" : "missing or not valid JSON");
        return NULL;
    }
    g->default_points = num_or(g->rubric, "default_points", 1);
    g->test_limit = num_or(g->rubric, "test_time_limit_s", 10);
    g->render_limit = num_or(g->rubric, "render_time_limit_s", 60);
    g->mem_mb = (long)num_or(g->rubric, "memory_limit_mb", 4096);
    if (getenv("RAS_GRADE_NO_MEMORY_LIMIT")) g->mem_mb = 0; /* sanitizer builds */
    return asgs;
}

/* Every --hw must be an assignment of the rubric: a typo would grade
 * nothing and report 0 / 0 as a success. */
bool intake_only(const grader *g, const cJSON *asgs, const char *rubric_path) {
    for (int i = 0; i < g->n_only; i++) {
        bool found = false;
        sbuf ids = {0};
        for (const cJSON *asg = asgs->child; asg; asg = asg->next) {
            found |= !strcmp(g->only[i], str_or(asg, "id", ""));
            sb_printf(&ids, "%s%s", ids.len ? ", " : "", str_or(asg, "id", "?"));
        }
        if (!found) {
            fprintf(stderr, "raster101-grade: --hw expects an assignment of %s (%s); got '%s'\n",
                    rubric_path, ids.s ? ids.s : "none", g->only[i]);
            free(ids.s);
            return false;
        }
        free(ids.s);
    }
    return true;
}

bool intake_out(const grader *g) {
    mkdirs(g->out);
    if (!is_dir(g->out) || access(g->out, W_OK) != 0) {
        int e = errno;
        fprintf(stderr,
                "raster101-grade: --out expects a folder it can create and write; '%s' is "
                "not (%s): choose another --out\n",
                g->out, file_exists(g->out) && !is_dir(g->out) ? "it is a file" : strerror(e));
        return false;
    }
    return true;
}

/* The grader's folders, as no report names them: the work folder (the
 * student's tree, build and runs are inside it) and the trusted side's. */
static void hide_grader_folders(const grader *g) {
    text_hide_path(g->work, "WORK");
    text_hide_path(g->student_tree, "WORK/tree");
    text_hide_path(g->student_build, "WORK/build");
    text_hide_path(g->own, "WORK/own");
    text_hide_path(g->sanitized, "WORK/sanitized");
    text_hide_path(g->source, "SOURCE");
    text_hide_path(g->build, "BUILD");
    text_hide_path(g->out, "OUT");
}

/* The student's side: tests/grading/grade makes it (a sandboxed build of a
 * pristine copy); without it there is nothing to grade. Once it is known,
 * the submission's notes become the student's text with its folders hidden. */
bool intake_student_side(grader *g) {
    if (!g->work || !g->student_tree || !g->student_build) {
        fprintf(stderr,
                "raster101-grade: expected --work, --student-tree and --student-build (the "
                "sandbox's folders, which tests/grading/grade makes); %s is missing: run "
                "tests/grading/grade\n",
                !g->work           ? "--work"
                : !g->student_tree ? "--student-tree"
                                   : "--student-build");
        return false;
    }
    hide_grader_folders(g);
    if (g->notes) {
        char *raw = g->notes;
        g->notes = *raw ? student_text(raw, 8 * 1024) : NULL;
        free(raw);
    }
    return true;
}

/* The file's first 16 KiB, kept as it is until intake_student_side makes
 * it the student's text (8 KiB shown); a later --notes replaces an earlier
 * one. */
void intake_notes(grader *g, const char *path) {
    free(g->notes);
    g->notes = read_small_file(path, 16 * 1024);
}

/* A random number from the kernel (the variants a grading draws must not be
 * predictable from the time or the process id). */
static unsigned random_u32(void) {
    unsigned v = 0;
    int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
    if (fd < 0 || read(fd, &v, sizeof v) != (ssize_t)sizeof v)
        v = (unsigned)time(NULL) ^ (unsigned)getpid();
    if (fd >= 0) close(fd);
    return v;
}

/* The k-th 64-bit draw for the image `name`: splitmix64 over the grading's
 * seed and the name, so each image's draws are independent of the order of
 * the rubric and the same for the same seed. */
static unsigned long long variant_draw(const grader *g, const char *name, unsigned k) {
    unsigned long long h = 1469598103934665603ULL; /* FNV-1a of the name */
    for (const char *c = name; *c; c++)
        h = (h ^ (unsigned char)*c) * 1099511628211ULL;
    unsigned long long x =
        (g->has_seed ? g->seed : ((unsigned long long)random_u32() << 32 | random_u32())) ^ h;
    x += 0x9E3779B97F4A7C15ULL * (k + 1);
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
}

/* The arguments of a variant image for this grading: "draw_args" is a list
 * of strings in which {int:A:B} is any integer in [A, B], {real:A:B} any
 * number in [A, B] and {pm:A:B} any of either sign whose magnitude is in
 * [A, B] (two decimals), drawn from the seed; else one list of
 * "choose_args", drawn the same way; else "args". The lists made live in
 * g->drawn. */
const cJSON *variant_args(grader *g, const cJSON *img) {
    const char *name = str_or(img, "name", "");
    const cJSON *draw = cJSON_GetObjectItemCaseSensitive(img, "draw_args");
    if (cJSON_IsArray(draw)) {
        if (!g->drawn) g->drawn = cJSON_CreateArray();
        cJSON *list = cJSON_CreateArray();
        unsigned k = 0;
        for (const cJSON *v = draw->child; v; v = v->next) {
            const char *t = cJSON_IsString(v) ? v->valuestring : "";
            sbuf b = {0};
            while (*t) {
                double lo, hi;
                int used = 0;
                char kind[8] = "";
                if (*t == '{' && sscanf(t, "{%7[a-z]:%lf:%lf}%n", kind, &lo, &hi, &used) == 3 &&
                    used > 0 && hi >= lo) {
                    double u = (double)(variant_draw(g, name, k++) >> 11) / 9007199254740992.0;
                    if (!strcmp(kind, "int")) {
                        sb_printf(&b, "%lld", (long long)floor(lo + u * (hi - lo + 1)));
                    } else if (!strcmp(kind, "pm")) { /* either sign: a magnitude in [lo, hi] */
                        bool minus = variant_draw(g, name, k++) & 1;
                        sb_printf(&b, "%.2f", (minus ? -1 : 1) * (lo + u * (hi - lo)));
                    } else {
                        sb_printf(&b, "%.2f", lo + u * (hi - lo));
                    }
                    t += used;
                } else {
                    sb_addn(&b, t, 1);
                    t++;
                }
            }
            cJSON_AddItemToArray(list, cJSON_CreateString(b.s ? b.s : ""));
            free(b.s);
        }
        cJSON_AddItemToArray(g->drawn, list);
        return list;
    }
    const cJSON *choose = cJSON_GetObjectItemCaseSensitive(img, "choose_args");
    int nc = cJSON_IsArray(choose) ? cJSON_GetArraySize(choose) : 0;
    if (nc > 0) return cJSON_GetArrayItem(choose, (int)(variant_draw(g, name, 0) % (unsigned)nc));
    return cJSON_GetObjectItemCaseSensitive(img, "args");
}
