/* test_grade_text — the grader's one sanitizer of text from the student's
 * side (grade_text.h: safe_text, student_text, safe_xml, text_unsafe), one
 * case per class of hostile input with the exact text a report then holds. */
#include "grade_text.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define FFFD "\xef\xbf\xbd"
#define BAR "\xe2\x94\x82 " /* "│ ": the student's line */

/* safe_text(raw) is `want`, and text_unsafe finds nothing in it */
static void expect_safe(const char *raw, const char *want) {
    char *got = safe_text(raw, 4096);
    if (strcmp(got, want) != 0)
        fail_msg("safe_text(\"%s\"): expected \"%s\", got \"%s\"", raw, want, got);
    const char *why = text_unsafe(got, false);
    if (why) fail_msg("safe_text(\"%s\") = \"%s\" still holds %s", raw, got, why);
    free(got);
}

static void test_invalid_utf8_becomes_replacement_characters(void **state) {
    (void)state;
    expect_safe("a\xff\xfe"
                "b",
                "a" FFFD FFFD "b");                       /* FF FE: no UTF-8 byte */
    expect_safe("\xc0\xaf", FFFD FFFD);                   /* overlong '/' */
    expect_safe("\xe0\x80\xaf", FFFD FFFD FFFD);          /* overlong, 3 bytes */
    expect_safe("\xf0\x80\x80\xaf", FFFD FFFD FFFD FFFD); /* overlong, 4 bytes */
    expect_safe("\xed\xa0\x80", FFFD FFFD FFFD);          /* surrogate U+D800 */
    expect_safe("\xf4\x90\x80\x80", FFFD FFFD FFFD FFFD); /* U+110000 */
    expect_safe("\xf5\x80\x80\x80", FFFD FFFD FFFD FFFD); /* F5: above U+10FFFF */
    expect_safe("x\x80y", "x" FFFD "y");                  /* stray continuation */
    expect_safe("end\xe2\x82", "end" FFFD FFFD);          /* cut by the end */
    expect_safe("\xe2\x82"
                "A",
                FFFD FFFD "A"); /* cut by ASCII */
    /* what is valid stays as it is: 2, 3 and 4 bytes, U+FFFD itself */
    expect_safe("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80 " FFFD,
                "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80 " FFFD);
    expect_safe("m\xc3\xb6gen \xe4\xb8\xad\xe6\x96\x87", "m\xc3\xb6gen \xe4\xb8\xad\xe6\x96\x87");
}

static void test_controls_are_shown_not_acted_on(void **state) {
    (void)state;
    expect_safe("a\x1b[31mred\x1b[0m", "a[U+001B][31mred[U+001B][0m"); /* ANSI colours */
    expect_safe("bell\x07", "bell[U+0007]");
    expect_safe("del\x7f", "del[U+007F]");
    expect_safe("nel\xc2\x85"
                "csi\xc2\x9b",
                "nel[U+0085]csi[U+009B]"); /* C1 */
    expect_safe("a\tb", "a    b");
    expect_safe("one\r\ntwo\r\n", "one\ntwo\n"); /* CRLF endings */
    expect_safe("50%\rdone", "50%[U+000D]done"); /* a lone CR would overwrite the line */
    expect_safe("x\x01\x02\x1f", "x[U+0001][U+0002][U+001F]");
}

static void test_bidi_and_invisible_characters_are_shown(void **state) {
    (void)state;
    expect_safe("score \xe2\x80\xae 0 / 24", "score [U+202E] 0 / 24");   /* RLO */
    expect_safe("\xe2\x81\xa6PASS\xe2\x81\xa9", "[U+2066]PASS[U+2069]"); /* isolates */
    expect_safe("\xe2\x80\xaa\xe2\x80\xab\xe2\x80\xac\xe2\x80\xad",
                "[U+202A][U+202B][U+202C][U+202D]"); /* embeddings, PDF */
    expect_safe("\xe2\x80\x8e\xe2\x80\x8f\xd8\x9c", "[U+200E][U+200F][U+061C]"); /* marks */
    expect_safe("zero\xe2\x80\x8bwidth\xe2\x80\x8c\xe2\x80\x8d",
                "zero[U+200B]width[U+200C][U+200D]");
    expect_safe("\xef\xbb\xbf"
                "bom \xe2\x81\xa0",
                "[U+FEFF]bom [U+2060]");
    expect_safe("ls\xe2\x80\xa8ps\xe2\x80\xa9", "ls[U+2028]ps[U+2029]"); /* JS line breaks */
    expect_safe("soft\xc2\xad", "soft[U+00AD]");
    expect_safe("tag\xf3\xa0\x81\x81", "tag[U+E0041]");  /* a Unicode tag character */
    expect_safe("\xef\xbf\xbe", "[U+FFFE]");             /* a noncharacter */
    expect_safe("filler\xe3\x85\xa4", "filler[U+3164]"); /* draws as a blank */
}

static void test_markup_is_inert(void **state) {
    (void)state;
    expect_safe("<script>alert(1)</script>", "\xe2\x80\xb9script>alert(1)\xe2\x80\xb9/script>");
    expect_safe("<img src=x onerror=alert(1)>", "\xe2\x80\xb9img src=x onerror=alert(1)>");
    expect_safe("<!-- c --><?php", "\xe2\x80\xb9!-- c -->\xe2\x80\xb9?php");
    expect_safe("<IMG SRC=x>", "\xe2\x80\xb9IMG SRC=x>");
    expect_safe("a < b && c <= d", "a < b && c <= d"); /* comparisons stay */
    expect_safe("x]]>y", "x]]\xe2\x80\xbay");          /* no CDATA end */
    /* Markdown stays as written: report.md fences it (a fence longer than
     * any run of backticks) and escapes table cells (grade_report.c) */
    expect_safe("```\n# heading", "```\n# heading");
}

static void test_grader_folders_are_hidden(void **state) {
    (void)state;
    text_hide_paths_clear();
    text_hide_path("/tmp/raster101-grade.AbC123", "WORK");
    text_hide_path("/srv/course/build/", "BUILD"); /* a trailing slash is not part of it */
    text_hide_path("/srv/course", "SOURCE");
    text_hide_path("build", "NO"); /* relative: never hidden */
    text_hide_path("/", "NO");     /* the root: never hidden */
    expect_safe("/tmp/raster101-grade.AbC123/tree/hw1_transform/transform.c:5:2: error: x",
                "WORK/tree/hw1_transform/transform.c:5:2: error: x");
    expect_safe("cd /srv/course/build/tests && /srv/course/tests/grading/grade",
                "cd BUILD/tests && SOURCE/tests/grading/grade");
    expect_safe("the build failed", "the build failed");
    /* the folder's name cut by a control is still shown, never joined */
    expect_safe("/tmp/raster101-grade.AbC\x01"
                "123",
                "/tmp/raster101-grade.AbC[U+0001]123");
    char *got = student_text("cwd=/tmp/raster101-grade.AbC123\n", 100);
    assert_string_equal(got, BAR "cwd=WORK\n");
    free(got);
    assert_non_null(text_unsafe("at /tmp/raster101-grade.AbC123/x", false));
    text_hide_paths_clear();
    assert_null(text_unsafe("at /tmp/raster101-grade.AbC123/x", false));
}

static void test_cap_cuts_between_characters(void **state) {
    (void)state;
    char *got = safe_text("a\xc3\xa9", 2); /* é is 2 bytes: it does not fit */
    assert_string_equal(got, "a\n[... cut ...]");
    free(got);
    got = safe_text("ab\xe2\x80\xae", 9); /* "[U+202E]" is 8 bytes: not cut inside */
    assert_string_equal(got, "ab\n[... cut ...]");
    free(got);
    got = safe_text("ab\xe2\x80\xae", 10);
    assert_string_equal(got, "ab[U+202E]");
    free(got);
    got = safe_text("\xf0\x9f\x98\x80\xf0\x9f\x98\x80", 7);
    assert_string_equal(got, "\xf0\x9f\x98\x80\n[... cut ...]");
    free(got);
    got = safe_text("", 0);
    assert_string_equal(got, "");
    free(got);
}

static void test_student_lines_are_marked(void **state) {
    (void)state;
    char *got = student_text("one\n## TOTAL 125 / 125\n\nlast", 200);
    assert_string_equal(got, BAR "one\n" BAR "## TOTAL 125 / 125\n" BAR "\n" BAR "last");
    free(got);
    got = student_text("a\r\nb", 200);
    assert_string_equal(got, BAR "a\n" BAR "b");
    free(got);
}

static void test_xml_keeps_its_markup(void **state) {
    (void)state;
    char *got = safe_xml("<testcase name=\"t\"><failure><![CDATA[got \xff\xe2\x80\xae]]>"
                         "</failure></testcase>",
                         4096);
    assert_string_equal(got, "<testcase name=\"t\"><failure><![CDATA[got " FFFD "[U+202E]]]>"
                             "</failure></testcase>");
    assert_null(text_unsafe(got, true));
    assert_non_null(text_unsafe(got, false)); /* as plain text it holds tags */
    free(got);
}

static void test_text_unsafe_names_each_class(void **state) {
    (void)state;
    assert_string_equal(text_unsafe("a\xff", false), "invalid UTF-8");
    assert_string_equal(text_unsafe("\xc0\xaf", false), "invalid UTF-8");
    assert_string_equal(text_unsafe("a\x1b", false), "a control character");
    assert_string_equal(text_unsafe("a\tb", false), "a control character");
    assert_string_equal(text_unsafe("\xc2\x85", false), "a control character");
    assert_string_equal(text_unsafe("\xe2\x80\xae", false),
                        "a bidi control or an invisible format character");
    assert_string_equal(text_unsafe("<script>", false), "an HTML tag");
    assert_string_equal(text_unsafe("]]>", false), "the end of an XML CDATA section");
    assert_null(text_unsafe("line\nnext \xe2\x94\x82 \xc3\xa9 a < b", false));
}

/* Every byte value in every position of a short string: whatever comes in,
 * what goes out passes text_unsafe. */
static void test_any_bytes_come_out_safe(void **state) {
    (void)state;
    char raw[4];
    for (int a = 1; a < 256; a++)
        for (int b = 1; b < 256; b += 3) {
            raw[0] = (char)a, raw[1] = (char)b, raw[2] = '<', raw[3] = '\0';
            char *got = student_text(raw, 100);
            const char *why = text_unsafe(got, false);
            if (why) fail_msg("bytes %02x %02x: \"%s\" holds %s", a, b, got, why);
            free(got);
        }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_invalid_utf8_becomes_replacement_characters),
        cmocka_unit_test(test_controls_are_shown_not_acted_on),
        cmocka_unit_test(test_bidi_and_invisible_characters_are_shown),
        cmocka_unit_test(test_markup_is_inert),
        cmocka_unit_test(test_grader_folders_are_hidden),
        cmocka_unit_test(test_cap_cuts_between_characters),
        cmocka_unit_test(test_student_lines_are_marked),
        cmocka_unit_test(test_xml_keeps_its_markup),
        cmocka_unit_test(test_text_unsafe_names_each_class),
        cmocka_unit_test(test_any_bytes_come_out_safe),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
