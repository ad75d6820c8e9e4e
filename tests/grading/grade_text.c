/* grade_text.c — what raster101-grade's reports quote (grade_text.h). */
#include "grade_text.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

/* Drops cmocka's banner lines and the "ERROR: " prefix of its XML mode, so
 * what remains is what the test said. */
char *clean_output(const char *raw) {
    sbuf b = {0};
    const char *p = raw;
    while (*p) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        bool banner = n > 0 && p[0] == '[' &&
                      (!strncmp(p, "[==========]", 12) || !strncmp(p, "[ RUN      ]", 12) ||
                       !strncmp(p, "[       OK ]", 12) || !strncmp(p, "[  FAILED  ]", 12) ||
                       !strncmp(p, "[  PASSED  ]", 12) || !strncmp(p, "[  SKIPPED ]", 12));
        bool footer = n > 0 && strstr(p, "FAILED TEST(S)") && strstr(p, "FAILED TEST(S)") < p + n;
        if (!banner && !footer) {
            if (!strncmp(p, "ERROR: ", 7)) p += 7, n -= 7;
            sb_addn(&b, p, n);
            sb_add(&b, "\n");
        }
        p += n + (nl ? 1 : 0);
    }
    /* trim trailing blank lines */
    while (b.len > 0 && (b.s[b.len - 1] == '\n' || b.s[b.len - 1] == ' '))
        b.s[--b.len] = '\0';
    return b.s ? b.s : xstrdup("");
}

bool has_todo_notice(const char *out) { return strstr(out, "is not written yet") != NULL; }

/* A table's "why" column holds this many characters (not bytes: a cut never
 * falls inside a UTF-8 character). */
enum { REASON_CHARS = 110 };

/* The length in bytes of the first `chars` characters of s[0..n) (UTF-8: a
 * continuation byte 10xxxxxx never starts a character). */
size_t utf8_prefix(const char *s, size_t n, size_t chars) {
    size_t i = 0;
    for (size_t c = 0; i < n; c++) {
        if (c == chars) return i;
        i++;
        while (i < n && ((unsigned char)s[i] & 0xC0) == 0x80)
            i++;
    }
    return n;
}

/* The most useful line of a failure: the "likely mistake" if there is one,
 * otherwise the first line that is not a TODO notice. */
char *reason_line(const char *out) {
    const char *todo = strstr(out, "TODO: ");
    if (todo) { /* "TODO: f() is not written yet" is the whole story */
        const char *end = strstr(todo, " is not written yet");
        const char *nl = strchr(todo, '\n');
        if (end && (!nl || end < nl)) {
            size_t n = (size_t)(end - todo) + strlen(" is not written yet");
            char *r = malloc(n + 1);
            if (!r) abort();
            memcpy(r, todo, n);
            r[n] = '\0';
            return r;
        }
    }
    const char *p = strstr(out, "likely mistake");
    if (p && !strncmp(p, "likely mistake: ", 16)) p += 16;
    if (!p) {
        p = out;
        while (*p && (!strncmp(p, "TODO:", 5) || *p == '\n')) {
            const char *nl = strchr(p, '\n');
            if (!nl) break;
            p = nl + 1;
        }
        if (!*p || !strncmp(p, "TODO:", 5)) p = out;
    }
    const char *nl = strchr(p, '\n');
    size_t n = utf8_prefix(p, nl ? (size_t)(nl - p) : strlen(p), REASON_CHARS);
    char *r = malloc(n + 1);
    if (!r) abort();
    memcpy(r, p, n);
    r[n] = '\0';
    return r;
}

void xml_escape(sbuf *b, const char *s) {
    for (; *s; s++) {
        switch (*s) {
        case '<': sb_add(b, "&lt;"); break;
        case '>': sb_add(b, "&gt;"); break;
        case '&': sb_add(b, "&amp;"); break;
        case '"': sb_add(b, "&quot;"); break;
        default: sb_addn(b, s, 1);
        }
    }
}

/* Whether the UTF-8 sequence p[0..n) is a bidirectional control (U+202A-E,
 * U+2066-9, U+200E/F, U+061C): they reorder what a reader sees around them. */
bool is_bidi_control(const unsigned char *p, size_t n) {
    if (n == 3 && p[0] == 0xE2 && p[1] == 0x80 &&
        ((p[2] >= 0xAA && p[2] <= 0xAE) || p[2] == 0x8E || p[2] == 0x8F))
        return true;
    if (n == 3 && p[0] == 0xE2 && p[1] == 0x81 && p[2] >= 0xA6 && p[2] <= 0xA9) return true;
    return n == 2 && p[0] == 0xD8 && p[1] == 0x9C;
}

/* Student output shown in a report: at most `cap` bytes, control
 * characters, bidi controls and invalid UTF-8 replaced by '?', the start of
 * an HTML tag ('<' before a letter, '/', '!' or '?') by U+2039, and every
 * line marked with U+2502 "│ " as the student's, so nothing it prints can
 * forge the report's layout (a heading, a total, a table), its reading
 * order, or its JSON. */
char *student_text(const char *raw, size_t cap) {
    sbuf b = {0};
    const unsigned char *p = (const unsigned char *)raw;
    bool line_start = true;
    while (*p && b.len < cap) {
        unsigned c = *p;
        size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
        bool ok = n > 0;
        for (size_t k = 1; ok && k < n; k++)
            ok = (p[k] & 0xC0) == 0x80;
        if (line_start) sb_add(&b, "\xe2\x94\x82 ");
        line_start = false;
        if (!ok) {
            sb_add(&b, "?");
            p++;
        } else if (n == 1 && ((c < 32 && c != '\n' && c != '\t') || c == 127)) {
            sb_add(&b, "?");
            p++;
        } else if (is_bidi_control(p, n)) {
            sb_add(&b, "?");
            p += n;
        } else if (c == '<' && (isalpha(p[1]) || p[1] == '/' || p[1] == '!' || p[1] == '?')) {
            sb_add(&b, "\xe2\x80\xb9");
            p++;
        } else {
            sb_addn(&b, (const char *)p, n);
            line_start = c == '\n';
            p += n;
        }
    }
    if (*p) sb_add(&b, "\n[... cut ...]");
    return b.s ? b.s : xstrdup("");
}

/* A sealed run's verdict (its process held reference code): the same fixed
 * sentence for every item that did not pass, and another for every item
 * that did. Nothing in it depends on how the run ended: a crash, a failed
 * check, a time-out, an exit status, a TODO notice or the check that
 * failed would each be a bit the student's code chose after reading the
 * reference's memory (issue 36: 23 bits of machine code per grading as
 * CRASH or FAIL). */
char *sealed_text(bool passed) {
    return xstrdup(passed ? "passed on your code linked with the earlier assignments' reference "
                            "(a sealed run: its output is not shown)"
                          : "did not pass on your code linked with the earlier assignments' "
                            "reference (a sealed run: it holds reference code, so how it failed "
                            "is not shown; run this test or program on your own build to see "
                            "it)");
}

/* `text` with every occurrence of the grading's work folder (a random name)
 * written as "WORK": a report says the same for the same files, and names
 * no folder of the grader's. Takes and returns an owned string. */
char *without_work_path(const char *work, char *text) {
    size_t n = work ? strlen(work) : 0;
    if (!text || n < 2 || !strstr(text, work)) return text;
    sbuf b = {0};
    for (const char *p = text, *q; *p; p = q + n) {
        q = strstr(p, work);
        if (!q) {
            sb_add(&b, p);
            break;
        }
        sb_addn(&b, p, (size_t)(q - p));
        sb_add(&b, "WORK");
    }
    free(text);
    return b.s ? b.s : xstrdup("");
}
