/* grade_text.c — what raster101-grade's reports quote (grade_text.h). */
#include "grade_text.h"

#include <ctype.h>
#include <stdio.h>
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

/* A table's "why" column holds the whole line, which the tables wrap; only a
 * line longer than this many characters (not bytes: a cut never falls inside
 * a UTF-8 character) is cut, at a space, and ends in "…". */
enum { REASON_CHARS = 600 };

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
    size_t whole = nl ? (size_t)(nl - p) : strlen(p);
    size_t n = utf8_prefix(p, whole, REASON_CHARS);
    bool cut = n < whole;
    if (cut) { /* at the last space, so that no word is cut */
        size_t sp = n;
        while (sp > 0 && p[sp] != ' ') sp--;
        if (sp > n / 2) n = sp;
    }
    char *r = malloc(n + sizeof " …");
    if (!r) abort();
    memcpy(r, p, n);
    strcpy(r + n, cut ? " …" : "");
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

/* ---------------------------------------------------------------- safe text */

/* The code point at p (strict UTF-8: no overlong form, no surrogate, nothing
 * above U+10FFFF, no stray continuation byte) and its length in *len; -1
 * with *len 1 for a byte that starts no valid sequence. p is NUL-terminated,
 * and NUL is no continuation byte, so a sequence cut by the end stops there. */
static long utf8_decode(const unsigned char *p, size_t *len) {
    unsigned c = p[0], lo = 0x80, hi = 0xBF;
    size_t n;
    long cp;
    *len = 1;
    if (c < 0x80) return (long)c;
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2, cp = c & 0x1F;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3, cp = c & 0x0F;
        if (c == 0xE0) lo = 0xA0; /* overlong below U+0800 */
        if (c == 0xED) hi = 0x9F; /* surrogates U+D800-DFFF */
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4, cp = c & 0x07;
        if (c == 0xF0) lo = 0x90; /* overlong below U+10000 */
        if (c == 0xF4) hi = 0x8F; /* above U+10FFFF */
    } else {
        return -1; /* C0, C1 (overlong ASCII), F5-FF, a stray continuation */
    }
    for (size_t k = 1; k < n; k++) {
        unsigned b = p[k];
        if (b < (k == 1 ? lo : 0x80) || b > (k == 1 ? hi : 0xBF)) return -1;
        cp = cp << 6 | (long)(b & 0x3F);
    }
    *len = n;
    return cp;
}

/* Characters that draw nothing yet change what a reader sees or what a
 * program parses: the bidi controls (U+202A-E, U+2066-9, U+200E/F, U+061C),
 * zero-width and joining characters, the other format characters (Cf), the
 * line and paragraph separators (a line break in JavaScript), fillers that
 * draw as blanks, interlinear annotations, tags and noncharacters. */
static bool is_hidden_char(long cp) {
    static const long ranges[][2] = {
        {0x00AD, 0x00AD},   {0x034F, 0x034F},   {0x0600, 0x0605},   {0x061C, 0x061C},
        {0x06DD, 0x06DD},   {0x070F, 0x070F},   {0x0890, 0x0891},   {0x08E2, 0x08E2},
        {0x115F, 0x1160},   {0x17B4, 0x17B5},   {0x180B, 0x180F},   {0x200B, 0x200F},
        {0x2028, 0x202E},   {0x2060, 0x206F},   {0x3164, 0x3164},   {0xFDD0, 0xFDEF},
        {0xFEFF, 0xFEFF},   {0xFFA0, 0xFFA0},   {0xFFF0, 0xFFFC},   {0x110BD, 0x110BD},
        {0x110CD, 0x110CD}, {0x13430, 0x1343F}, {0x1BCA0, 0x1BCA3}, {0x1D173, 0x1D17A},
        {0xE0000, 0xE007F},
    };
    if ((cp & 0xFFFE) == 0xFFFE) return true; /* U+nFFFE, U+nFFFF: noncharacters */
    for (size_t i = 0; i < sizeof ranges / sizeof *ranges; i++)
        if (cp >= ranges[i][0] && cp <= ranges[i][1]) return true;
    return false;
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

/* The grader's folders (text_hide_path), longest first: a folder inside
 * another is hidden whole, by its own word. */
enum { HIDDEN_MAX = 24 };
static struct {
    char *path;
    const char *token;
} g_hidden[HIDDEN_MAX];
static int g_n_hidden;

static void hide_one(const char *path, const char *token) {
    size_t n = strlen(path);
    while (n > 1 && path[n - 1] == '/')
        n--;
    /* only absolute folders below the root ("/tmp/x", not "build" or "/") */
    if (path[0] != '/' || n < 5 || g_n_hidden == HIDDEN_MAX) return;
    for (int i = 0; i < g_n_hidden; i++)
        if (strlen(g_hidden[i].path) == n && !strncmp(g_hidden[i].path, path, n)) return;
    char *copy = malloc(n + 1);
    if (!copy) abort();
    memcpy(copy, path, n);
    copy[n] = '\0';
    int at = g_n_hidden++;
    while (at > 0 && strlen(g_hidden[at - 1].path) < n) {
        g_hidden[at] = g_hidden[at - 1];
        at--;
    }
    g_hidden[at].path = copy;
    g_hidden[at].token = token;
}

void text_hide_path(const char *path, const char *token) {
    if (!path || !token) return;
    hide_one(path, token);
    /* the same folder as a program finds it (getcwd, /proc/self/cwd): the
     * real path, when a link such as /tmp -> /private/tmp leads there */
    char *real = realpath(path, NULL);
    if (real) hide_one(real, token);
    free(real);
}

void text_hide_paths_clear(void) {
    for (int i = 0; i < g_n_hidden; i++)
        free(g_hidden[i].path);
    g_n_hidden = 0;
}

/* The hidden folder that starts at p, or -1. */
static int hidden_at(const char *p) {
    for (int i = 0; i < g_n_hidden; i++)
        if (!strncmp(p, g_hidden[i].path, strlen(g_hidden[i].path))) return i;
    return -1;
}

/* raw with each of the grader's folders written as its token (owned), in
 * one pass: a token is never read again, so no replacement can join the
 * text around it into another folder's name. */
static char *hide_paths(const char *raw) {
    sbuf b = {0};
    for (const char *p = raw; *p;) {
        int h = *p == '/' ? hidden_at(p) : -1;
        if (h >= 0) {
            sb_add(&b, g_hidden[h].token);
            p += strlen(g_hidden[h].path);
        } else {
            sb_addn(&b, p, 1);
            p++;
        }
    }
    return b.s ? b.s : xstrdup("");
}

/* Whether the '<' at p would open an HTML tag (a letter, '/', '!' or '?' follows). */
static bool opens_tag(const unsigned char *p) {
    return *p == '<' && (isalpha(p[1]) || p[1] == '/' || p[1] == '!' || p[1] == '?');
}

/* Whether the '>' at p (text from start) ends "]]>", which would close an XML CDATA section. */
static bool closes_cdata(const unsigned char *start, const unsigned char *p) {
    return *p == '>' && p - start >= 2 && p[-1] == ']' && p[-2] == ']';
}

enum text_style {
    TEXT_PLAIN,   /* the grader's text that quotes the student's */
    TEXT_STUDENT, /* the student's: each line marked "│ " */
    TEXT_XML      /* an XML document: its markup kept, its text made safe */
};

/* What one character of raw (at p, len bytes, code point cp: -1 invalid)
 * becomes in safe text, into out (at most 16 bytes); *skip: bytes taken. */
static void safe_char(const unsigned char *start, const unsigned char *p, long cp, size_t len,
                      enum text_style style, char *out, size_t *skip) {
    *skip = len;
    if (cp < 0) {
        strcpy(out, "\xef\xbf\xbd"); /* U+FFFD, one for each byte of no character */
    } else if (cp == '\r' && p[1] == '\n') {
        out[0] = '\0'; /* CRLF: the line break that follows is enough */
    } else if (cp == '\t') {
        strcpy(out, "    ");
    } else if (cp == '\n') {
        strcpy(out, "\n");
    } else if (cp < 0x20 || (cp >= 0x7F && cp <= 0x9F) || is_hidden_char(cp)) {
        snprintf(out, 16, "[U+%04X]", (unsigned)cp); /* shown, never acted on */
    } else if (style != TEXT_XML && opens_tag(p)) {
        strcpy(out, "\xe2\x80\xb9"); /* U+2039: no HTML tag can open */
    } else if (style != TEXT_XML && closes_cdata(start, p)) {
        strcpy(out, "\xe2\x80\xba"); /* U+203A: no "]]>" ends an XML CDATA section */
    } else {
        memcpy(out, p, len);
        out[len] = '\0';
    }
}

/* The one sanitizer of text from the student's side (grade_text.h). */
static char *text_made_safe(const char *raw, size_t cap, enum text_style style) {
    char *hidden = hide_paths(raw ? raw : "");
    const unsigned char *start = (const unsigned char *)hidden, *p = start;
    sbuf b = {0};
    bool line_start = true, cut = false;
    while (*p) {
        size_t len, skip;
        long cp = utf8_decode(p, &len);
        char out[16];
        safe_char(start, p, cp, len, style, out, &skip);
        const char *mark = style == TEXT_STUDENT && line_start && *out ? "\xe2\x94\x82 " : "";
        size_t add = strlen(mark) + strlen(out);
        if (b.len + add > cap) { /* whole characters only */
            cut = true;
            break;
        }
        sb_add(&b, mark);
        sb_add(&b, out);
        if (*out) line_start = cp == '\n';
        p += skip;
    }
    if (cut) sb_add(&b, style == TEXT_XML ? "\n[... cut ...]\n" : "\n[... cut ...]");
    free(hidden);
    return b.s ? b.s : xstrdup("");
}

char *safe_text(const char *raw, size_t cap) { return text_made_safe(raw, cap, TEXT_PLAIN); }

char *student_text(const char *raw, size_t cap) { return text_made_safe(raw, cap, TEXT_STUDENT); }

char *safe_xml(const char *raw, size_t cap) { return text_made_safe(raw, cap, TEXT_XML); }

const char *text_unsafe(const char *s, bool markup) {
    const unsigned char *start = (const unsigned char *)s;
    for (const unsigned char *p = start; *p;) {
        size_t len;
        long cp = utf8_decode(p, &len);
        if (cp < 0) return "invalid UTF-8";
        if ((cp < 0x20 && cp != '\n') || (cp >= 0x7F && cp <= 0x9F)) return "a control character";
        if (is_hidden_char(cp)) return "a bidi control or an invisible format character";
        if (*p == '/' && hidden_at((const char *)p) >= 0) return "a folder of the grader's";
        if (!markup && opens_tag(p)) return "an HTML tag";
        if (!markup && closes_cdata(start, p)) return "the end of an XML CDATA section";
        p += len;
    }
    return NULL;
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
