/* ras_scene_syntax.c — see ras_scene_syntax.h.
 *
 * Notes: cJSON reports only where it stopped (cJSON_GetErrorPtr). The hints
 * here look at the characters around that point and at which brackets and
 * strings are still open; they describe the likely mistake, they do not parse
 * (a second parser would be a second place for JSON's rules to be wrong).
 */
#include "ras_scene_syntax.h"

#include <ctype.h>  /* isalnum, isalpha, isspace */
#include <stdio.h>  /* snprintf */
#include <string.h> /* strlen, strncmp */

static bool is_word_char(char ch) {
    return isalnum((unsigned char)ch) || ch == '_' || ch == '-' || ch == '+' || ch == '.';
}

void ras_scene_syntax_line_col(const char *text, size_t off, int *line, int *col) {
    *line = 1;
    *col = 1;
    for (size_t i = 0; i < off; i++) {
        if (text[i] == '\n') {
            ++*line;
            *col = 1;
        } else if (((unsigned char)text[i] & 0xC0) != 0x80) {
            ++*col; /* count characters, not UTF-8 continuation bytes */
        }
    }
}

/* The position of the innermost '{', '[' or '"' still open at `len` (the
 * end of the text, or the error), or (size_t)-1 when everything is closed. */
static size_t unclosed_at(const char *text, size_t len, char *what) {
    size_t stack[64];
    char kinds[64];
    int depth = 0;
    for (size_t i = 0; i < len; i++) {
        char ch = text[i];
        if (ch == '"') {
            size_t start = i++;
            while (i < len && text[i] != '"')
                i += text[i] == '\\' ? 2 : 1;
            if (i >= len) {
                *what = '"';
                return start;
            }
        } else if (ch == '{' || ch == '[') {
            if (depth < 64) {
                stack[depth] = i;
                kinds[depth] = ch;
            }
            depth++;
        } else if ((ch == '}' || ch == ']') && depth > 0) {
            depth--;
        }
    }
    if (depth == 0) return (size_t)-1;
    int top = depth <= 64 ? depth - 1 : 63;
    *what = kinds[top];
    return stack[top];
}

bool ras_scene_syntax_error(const char *file, const char *text, size_t len, size_t off,
                            ras_error *err) {
    if (off > len) off = len;
    /* cJSON stops one character into a comment. */
    if (off > 0 && off < len && text[off - 1] == '/' && (text[off] == '/' || text[off] == '*'))
        off--;
    /* ... and one character into a word (an unquoted key, a bad literal). */
    while (off > 0 && off < len && is_word_char(text[off]) && is_word_char(text[off - 1]))
        off--;
    int line, col;
    ras_scene_syntax_line_col(text, off, &line, &col);
    char where[224]; /* file:line:col; a very long file name is cut */
    snprintf(where, sizeof where, "%s:%d:%d", file, line, col);
    /* The token at the error, and the last significant character before it. */
    size_t end = off;
    while (end < len && is_word_char(text[end]))
        end++;
    size_t rest = end == off ? off + 1 : end;
    while (rest < len && isspace((unsigned char)text[rest]))
        rest++;
    size_t b = off;
    while (b > 0 && isspace((unsigned char)text[b - 1]))
        b--;
    char prev = b > 0 ? text[b - 1] : '\0';
    char ch = off < len ? text[off] : '\0';
    char got[64];
    if (off >= len)
        snprintf(got, sizeof got, "the end of the text");
    else if (end > off)
        snprintf(got, sizeof got, "'%.*s'", (int)(end - off > 20 ? 20 : end - off), text + off);
    else if ((unsigned char)ch < 0x20)
        snprintf(got, sizeof got, "a control character (0x%02x)", (unsigned char)ch);
    else
        snprintf(got, sizeof got, "'%c'", ch);

    char what;
    size_t open = unclosed_at(text, len, &what);
    if (open != (size_t)-1 && rest >= len) {
        int ol, oc;
        ras_scene_syntax_line_col(text, open, &ol, &oc);
        const char *closer = what == '"' ? "'\"'" : what == '{' ? "'}'" : "']'";
        return ras_error_set(err,
                             "%s: JSON syntax error: expected %s to close the '%c' at %d:%d, got "
                             "the end of the text",
                             where, closer, what, ol, oc);
    }
    char top;
    if (unclosed_at(text, off, &top) == (size_t)-1 && b > 0)
        return ras_error_set(err,
                             "%s: JSON syntax error: expected the end of the text after the "
                             "top-level object, got %s",
                             where, got);
    if ((ch == '}' || ch == ']') && prev == ',')
        return ras_error_set(err,
                             "%s: JSON syntax error: expected a value after ',', got '%c' (JSON "
                             "allows no trailing comma: remove the ',')",
                             where, ch);
    if (ch == '/' && off + 1 < len && (text[off + 1] == '/' || text[off + 1] == '*'))
        return ras_error_set(err,
                             "%s: JSON syntax error: expected a value or ',', got a comment "
                             "('%c%c'); JSON has no comments (use a \"description\" key)",
                             where, ch, text[off + 1]);
    if (ch == '\'' || prev == '\'')
        return ras_error_set(err,
                             "%s: JSON syntax error: expected a string in double quotes, got a "
                             "single quote (JSON strings and keys take \"...\")",
                             where);
    if (end > off) {
        static const char *const special[] = {"NaN", "nan", "Infinity", "-Infinity", "inf", "-inf"};
        for (size_t i = 0; i < sizeof special / sizeof special[0]; i++)
            if (end - off == strlen(special[i]) && !strncmp(text + off, special[i], end - off))
                return ras_error_set(err,
                                     "%s: JSON syntax error: expected a number, got %s (JSON has "
                                     "no NaN or Infinity: write a finite number)",
                                     where, got);
    }
    if (ch == ':' || ((prev == '{' || prev == ',') && isalpha((unsigned char)ch)))
        return ras_error_set(err,
                             "%s: JSON syntax error: expected a key in double quotes, got %s "
                             "(write \"key\": value)",
                             where, ch == ':' ? "an unquoted key before ':'" : got);
    bool prev_ends_value =
        prev == '"' || prev == '}' || prev == ']' || isalnum((unsigned char)prev);
    bool starts_value =
        ch == '"' || ch == '{' || ch == '[' || ch == '-' || isalnum((unsigned char)ch);
    if (b < off && prev_ends_value && starts_value)
        return ras_error_set(err,
                             "%s: JSON syntax error: expected ',' or a closing bracket, got %s "
                             "(a ',' is missing between two values)",
                             where, got);
    if (ch == ',')
        return ras_error_set(err, "%s: JSON syntax error: expected a value after '%c', got ','",
                             where, prev ? prev : '{');
    if (isalpha((unsigned char)ch))
        return ras_error_set(err,
                             "%s: JSON syntax error: expected a value (a number, a string in "
                             "double quotes, true, false, null, an object or an array), got %s",
                             where, got);
    return ras_error_set(err, "%s: JSON syntax error: unexpected %s", where, got);
}
