/* class_roster.c — raster101-class roster: a graded class's scores as the
 * gradebooks Canvas and Moodle import (class_tool.c; docs/instructors.md,
 * "LMS gradebooks").
 *
 * The roster (CSV: name,id,email; a first row "name,..." is a header) is the
 * instructor's; a student's name is their submission's name as grade-all
 * graded it (students/NAME), and the two must be equal byte for byte. A
 * name the roster lacks, a roster row without a submission, a name twice,
 * a submission that came out as NAME~2 beside NAME, a student not graded:
 * each is listed (stderr and OUT/roster-problems.txt) and left out of the
 * gradebooks, never matched by a guess.
 */
#include "class_view.h"
#include "grade_base.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct row {
    char *field[3]; /* name, id, email */
    int line;
} row;

/* One CSV record of `p` (RFC 4180: quoted fields, "" inside quotes, CRLF or
 * LF) into fields (at most max, each owned); *n the count of fields of the
 * record. Returns where the next record starts. */
static const char *csv_record(const char *p, char **fields, int max, int *n) {
    *n = 0;
    for (;;) {
        sbuf f = {0};
        if (*p == '"') {
            for (p++; *p; p++) {
                if (*p == '"' && p[1] == '"') {
                    sb_add(&f, "\"");
                    p++;
                } else if (*p == '"') {
                    p++;
                    break;
                } else {
                    sb_addn(&f, p, 1);
                }
            }
        }
        size_t len = strcspn(p, ",\r\n");
        sb_addn(&f, p, len);
        p += len;
        if (*n < max)
            fields[*n] = f.s ? f.s : xstrdup("");
        else
            free(f.s);
        (*n)++;
        if (*p != ',') break;
        p++;
    }
    if (*p == '\r') p++;
    if (*p == '\n') p++;
    return p;
}

/* The roster's rows; problems with a row itself go to `problems`. */
static row *read_roster(const char *text, int *count, sbuf *problems) {
    row *rows = NULL;
    int n = 0, line = 0;
    const char *p = text;
    if (!strncmp(p, "\xef\xbb\xbf", 3)) p += 3; /* a spreadsheet's BOM */
    while (*p) {
        char *f[3] = {0};
        int nf;
        line++;
        p = csv_record(p, f, 3, &nf);
        bool blank = nf == 1 && !*f[0];
        bool header = line == 1 && f[0] && !strcasecmp(f[0], "name");
        if (!blank && !header && (nf != 3 || !*f[0])) {
            sb_printf(problems,
                      "roster line %d: expected name,id,email with a name, got %d field%s%s; "
                      "left out: fix the roster's line\n",
                      line, nf, nf == 1 ? "" : "s", nf >= 1 && !*f[0] ? " and no name" : "");
        } else if (!blank && !header) {
            rows = realloc(rows, (size_t)(n + 1) * sizeof *rows);
            if (!rows) abort();
            rows[n++] = (row){{f[0], f[1], f[2]}, line};
            continue;
        }
        for (int i = 0; i < 3 && i < nf; i++)
            free(f[i]);
    }
    *count = n;
    return rows;
}

static const cJSON *find_student(const cJSON *students, const char *name) {
    const cJSON *s;
    cJSON_ArrayForEach(s, students) if (!strcmp(str_or(s, "name", ""), name)) return s;
    return NULL;
}

static int roster_index(const row *rows, int n, const char *name) {
    for (int i = 0; i < n; i++)
        if (!strcmp(rows[i].field[0], name)) return i;
    return -1;
}

/* A CSV field, always quoted: a name with a comma or a quote stays one field. */
static void csv_field(sbuf *b, const char *s) {
    sb_add(b, "\"");
    for (; *s; s++)
        sb_add(b, *s == '"' ? "\"\"" : (char[]){*s, 0});
    sb_add(b, "\"");
}

static void score_cells(sbuf *b, const cJSON *student, const cJSON *asgs) {
    const cJSON *a;
    const cJSON *mine = cJSON_GetObjectItemCaseSensitive(student, "assignments");
    cJSON_ArrayForEach(a, asgs) {
        const cJSON *sa = cJSON_GetObjectItemCaseSensitive(mine, str_or(a, "id", ""));
        if (sa)
            sb_printf(b, ",%g", num_or(sa, "score", 0));
        else
            sb_add(b, ","); /* not graded in this one: left for the LMS as it is */
    }
    sb_add(b, "\n");
}

/* Whether the student `s` of the class may be written:
 * graded, and no other submission came out as "NAME~k" beside it. */
static bool writable(const cJSON *students, const cJSON *s, const char *name, sbuf *problems) {
    const cJSON *o;
    size_t len = strlen(name);
    cJSON_ArrayForEach(o, students) {
        const char *other = str_or(o, "name", "");
        if (!strncmp(other, name, len) && other[len] == '~') {
            sb_printf(problems,
                      "%s: two submissions, graded as '%s' and '%s'; neither written: keep "
                      "one submission of that name and grade again\n",
                      name, name, other);
            return false;
        }
    }
    if (!cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(s, "graded"))) {
        sb_printf(problems, "%s: not graded (class.html says why); not written\n", name);
        return false;
    }
    return true;
}

/* OUT/FILE, written whole or not at all */
static bool write_text(const char *out, const char *file, const char *text) {
    char path[8192];
    fmt(path, sizeof path, "%s/%s", out, file);
    return class_write_whole(path, text);
}

static void gradebook_headers(sbuf *canvas, sbuf *moodle, const cJSON *asgs) {
    const cJSON *a;
    sb_add(canvas, "Student,ID,SIS User ID,SIS Login ID,Section");
    sb_add(moodle, "Full name,ID number,Email address");
    cJSON_ArrayForEach(a, asgs) {
        sb_add(canvas, ",");
        csv_field(canvas, str_or(a, "id", "?"));
        sb_add(moodle, ",");
        csv_field(moodle, str_or(a, "id", "?"));
    }
    sb_add(canvas, "\n");
    sb_add(moodle, "\n");
}

int roster_main(const char *out, const char *roster_path) {
    char path[8192];
    fmt(path, sizeof path, "%s/class.json", out);
    char *class_text = read_file(path, 0), *roster_text = read_file(roster_path, 4 << 20);
    cJSON *root = class_text ? cJSON_Parse(class_text) : NULL;
    if (!cJSON_IsObject(root) || !roster_text) {
        fprintf(stderr,
                "raster101-class: expected %s (raster101-class view) and the roster %s "
                "(CSV: name,id,email), got %s\n",
                path, roster_path, !roster_text ? "no readable roster" : "no readable class.json");
        cJSON_Delete(root);
        free(class_text);
        free(roster_text);
        return 2;
    }
    sbuf problems = {0}, canvas = {0}, moodle = {0};
    int n = 0, written = 0;
    row *rows = read_roster(roster_text, &n, &problems);
    const cJSON *students = cJSON_GetObjectItemCaseSensitive(root, "students");
    const cJSON *asgs = cJSON_GetObjectItemCaseSensitive(root, "assignments"), *s;
    gradebook_headers(&canvas, &moodle, asgs);
    bool *twice = calloc((size_t)n + 1, 1);
    for (int i = 0; i < n; i++)
        if (roster_index(rows, n, rows[i].field[0]) != i) {
            int first = roster_index(rows, n, rows[i].field[0]);
            twice[i] = twice[first] = true;
            sb_printf(&problems, "%s: on roster lines %d and %d; neither written\n",
                      rows[i].field[0], rows[first].line, rows[i].line);
        }
    cJSON_ArrayForEach(s, students) {
        const char *name = str_or(s, "name", "");
        int r = roster_index(rows, n, name);
        if (r < 0) {
            sb_printf(&problems,
                      "%s: a submission the roster does not name (the roster's name must be "
                      "the submission's name exactly); not written\n",
                      name);
            continue;
        }
        if (twice[r] || !writable(students, s, name, &problems)) continue;
        const row *w = &rows[r];
        csv_field(&canvas, w->field[0]);
        sb_add(&canvas, ",");
        csv_field(&canvas, w->field[1]);
        sb_add(&canvas, ",,");
        csv_field(&canvas, w->field[2]);
        sb_add(&canvas, ",");
        score_cells(&canvas, s, asgs);
        csv_field(&moodle, w->field[0]);
        sb_add(&moodle, ",");
        csv_field(&moodle, w->field[1]);
        sb_add(&moodle, ",");
        csv_field(&moodle, w->field[2]);
        score_cells(&moodle, s, asgs);
        written++;
    }
    for (int i = 0; i < n; i++)
        if (!twice[i] && !find_student(students, rows[i].field[0]))
            sb_printf(&problems, "%s: on the roster (line %d), no submission; not written\n",
                      rows[i].field[0], rows[i].line);
    bool ok = write_text(out, "canvas.csv", sb_str(&canvas));
    ok = write_text(out, "moodle.csv", sb_str(&moodle)) && ok;
    ok = write_text(out, "roster-problems.txt", sb_str(&problems)) && ok;
    fputs(sb_str(&problems), stderr);
    printf("raster101-class: %d of %d roster students written to %s/canvas.csv and moodle.csv"
           "%s\n",
           written, n, out, problems.len ? "; problems listed in roster-problems.txt" : "");
    for (int i = 0; i < n; i++)
        for (int f = 0; f < 3; f++)
            free(rows[i].field[f]);
    free(rows);
    free(twice);
    free(problems.s);
    free(canvas.s);
    free(moodle.s);
    cJSON_Delete(root);
    free(class_text);
    free(roster_text);
    return ok ? 0 : 2;
}
