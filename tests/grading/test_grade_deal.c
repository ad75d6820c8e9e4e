/* test_grade_deal — how a grading's tests are dealt to its chunks
 * (grade_run.h: deal_tests, chunk_size, write_chunk_list): by the rubric's
 * measured costs (test_costs_ms), the costliest first to the least loaded
 * chunk, a test without a cost as its assignment's mean, and without any
 * costs round-robin as before. */
#include "grade_run.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

/* A grader whose rubric has one assignment "hw9" with the given
 * test_costs_ms (JSON text; NULL: none), and the tests t0..t(n-1). */
static grader with_costs(const char *costs_json, name_list *names, int n) {
    grader g = {0};
    char text[2048];
    snprintf(text, sizeof text, "{\"assignments\": [{\"id\": \"hw1\"}, {\"id\": \"hw9\"%s%s}]}",
             costs_json ? ", \"test_costs_ms\": " : "", costs_json ? costs_json : "");
    g.rubric = cJSON_Parse(text);
    if (!g.rubric) fail_msg("the test's own rubric does not parse: %s", text);
    for (int i = 0; i < n; i++) {
        char name[16];
        snprintf(name, sizeof name, "t%d", i);
        names_add(names, name);
    }
    return g;
}

/* chunk_of is `want` (n entries), said with both when not */
static void expect_chunks(const int *chunk_of, const int *want, int n, const char *what) {
    for (int i = 0; i < n; i++)
        if (chunk_of[i] != want[i]) {
            char got_s[200] = "", want_s[200] = "";
            for (int k = 0; k < n; k++) {
                size_t g = strlen(got_s), w = strlen(want_s);
                snprintf(got_s + g, sizeof got_s - g, "%d ", chunk_of[k]);
                snprintf(want_s + w, sizeof want_s - w, "%d ", want[k]);
            }
            fail_msg("%s: expected chunks %s, got %s", what, want_s, got_s);
        }
}

static void test_without_costs_round_robin(void **state) {
    (void)state;
    for (int chunks = 2; chunks <= 3; chunks++) {
        name_list names = {0};
        grader g = with_costs(NULL, &names, 7);
        int chunk_of[7], want[7];
        deal_tests(&g, "hw9", &names, chunks, chunk_of);
        for (int i = 0; i < 7; i++)
            want[i] = i % chunks;
        expect_chunks(chunk_of, want, 7, "no test_costs_ms (every test alike)");
        names_free(&names);
        cJSON_Delete(g.rubric);
    }
}

/* costs 10 1 1 1 7 3: 10 and 7 apart, then each to the lighter chunk
 * (ties to chunk 0): loads 12 and 10, where round-robin gives 18 and 5 */
static void test_costliest_first_to_the_least_loaded(void **state) {
    (void)state;
    name_list names = {0};
    grader g = with_costs("{\"t0\": 10, \"t1\": 1, \"t2\": 1, \"t3\": 1, \"t4\": 7, \"t5\": 3}",
                          &names, 6);
    int chunk_of[6];
    deal_tests(&g, "hw9", &names, 2, chunk_of);
    expect_chunks(chunk_of, (const int[]){0, 0, 1, 0, 1, 1}, 6, "costs 10 1 1 1 7 3");
    assert_int_equal(chunk_size(6, chunk_of, 0), 3);
    assert_int_equal(chunk_size(6, chunk_of, 1), 3);
    names_free(&names);
    cJSON_Delete(g.rubric);
}

/* t1 has no cost, t4's is not a number, t5's is negative: each counts as
 * the mean of the tests' known costs (100 50 50 -> 66.7; t_gone, no test of
 * the program, not among them), so they go before t2 and t3 */
static void test_missing_cost_counts_as_the_mean(void **state) {
    (void)state;
    name_list names = {0};
    grader g = with_costs("{\"t0\": 100, \"t2\": 50, \"t3\": 50, \"t4\": \"x\", \"t5\": -4, "
                          "\"t_gone\": 9999}",
                          &names, 6);
    int chunk_of[6];
    deal_tests(&g, "hw9", &names, 2, chunk_of);
    /* t0 100 -> 0; t1 66.7 -> 1; t4 -> 1 (66.7 < 100); t5 -> 0 (100 < 133.3);
     * t2 50 -> 1 (133.3 < 166.7); t3 -> 0 (166.7 < 183.3) */
    expect_chunks(chunk_of, (const int[]){0, 1, 1, 0, 1, 0}, 6, "t1, t4, t5 without a cost");
    names_free(&names);
    cJSON_Delete(g.rubric);
}

/* another assignment's costs are not this one's */
static void test_costs_are_the_assignments_own(void **state) {
    (void)state;
    name_list names = {0};
    grader g = {0};
    g.rubric = cJSON_Parse("{\"assignments\": [{\"id\": \"hw1\", \"test_costs_ms\": {\"t0\": "
                           "1, \"t1\": 1, \"t2\": 500}}, {\"id\": \"hw9\"}]}");
    for (int i = 0; i < 3; i++) {
        char name[8];
        snprintf(name, sizeof name, "t%d", i);
        names_add(&names, name);
    }
    int chunk_of[3];
    deal_tests(&g, "hw9", &names, 2, chunk_of);
    expect_chunks(chunk_of, (const int[]){0, 1, 0}, 3, "hw9 without costs beside hw1's");
    deal_tests(&g, "hw1", &names, 2, chunk_of);
    expect_chunks(chunk_of, (const int[]){1, 1, 0}, 3, "hw1 by its costs 1 1 500");
    names_free(&names);
    cJSON_Delete(g.rubric);
}

/* a chunk's list: its tests one a line, in the program's order */
static void test_chunk_list_in_program_order(void **state) {
    (void)state;
    name_list names = {0};
    grader g = with_costs(NULL, &names, 5);
    int chunk_of[5] = {1, 0, 1, 1, 0};
    char path[] = "/tmp/test_grade_deal.XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    write_chunk_list(path, &names, chunk_of, 1);
    char *text = read_file(path, 4096);
    unlink(path);
    assert_non_null(text);
    assert_string_equal(text, "t0\nt2\nt3\n");
    free(text);
    names_free(&names);
    cJSON_Delete(g.rubric);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_without_costs_round_robin),
        cmocka_unit_test(test_costliest_first_to_the_least_loaded),
        cmocka_unit_test(test_missing_cost_counts_as_the_mean),
        cmocka_unit_test(test_costs_are_the_assignments_own),
        cmocka_unit_test(test_chunk_list_in_program_order),
    };
    return cmocka_run_group_tests_name("grade_deal", tests, NULL, NULL);
}
