/* ras_error.c — see ras_error.h. */
#include "ras_error.h"

#include <stdarg.h> /* va_list */
#include <stdio.h>  /* vsnprintf */
#include <stdlib.h> /* malloc, free */
#include <string.h> /* memmove, strlen */

/* The shortest a shortened word keeps: its head and tail still say which
 * file it was. */
enum { KEEP_AT_LEAST = 48 };

static bool word_char(char c) { return c != ' ' && c != '\'' && c != '"' && c != '\0'; }

/* The longest word (a run of characters between spaces and quotes: a path,
 * in practice) of text: its start and length. */
static size_t longest_word(const char *text, size_t *start) {
    size_t best = 0, at = 0;
    for (size_t i = 0; text[i];) {
        if (!word_char(text[i])) {
            i++;
            continue;
        }
        size_t j = i;
        while (word_char(text[j])) j++;
        if (j - i > best) best = j - i, at = i;
        i = j;
    }
    *start = at;
    return best;
}

size_t ras_error_shorten(char *text, size_t cap) {
    static const char mark[] = "[...]";
    const size_t mark_len = sizeof mark - 1;
    size_t len = strlen(text);
    while (len + 1 > cap) {
        size_t at, word = longest_word(text, &at);
        if (word <= KEEP_AT_LEAST + mark_len) break;
        size_t excess = len + 1 - cap;
        size_t keep = word > excess + mark_len + KEEP_AT_LEAST ? word - excess - mark_len
                                                               : KEEP_AT_LEAST;
        size_t head = keep / 2, tail = keep - head;
        /* WORD = HEAD ... TAIL becomes HEAD [...] TAIL */
        memcpy(text + at + head, mark, mark_len);
        memmove(text + at + head + mark_len, text + at + word - tail, len - (at + word - tail) + 1);
        len = strlen(text);
    }
    if (len + 1 > cap && cap > 0) { /* no long word left: the end goes */
        text[cap - 1] = '\0';
        len = cap - 1;
    }
    return len;
}

bool ras_error_set(ras_error *err, const char *fmt, ...) {
    if (!err) return false;
    va_list ap, again;
    va_start(ap, fmt);
    va_copy(again, ap);
    int need = vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    /* Longer than the message holds: the whole text formatted, then its
     * longest words (paths) cut in the middle, so that the reason and the
     * key after a long path are never the part that is lost. */
    char *whole = need >= (int)sizeof err->msg ? malloc((size_t)need + 1) : NULL;
    if (whole) {
        vsnprintf(whole, (size_t)need + 1, fmt, again);
        ras_error_shorten(whole, sizeof err->msg);
        memcpy(err->msg, whole, strlen(whole) + 1);
        free(whole);
    }
    va_end(again);
    return false;
}
