/* ras_test_main.h — the one way a Raster101 test program runs its tests, so
 * the grader (tests/grade) can run each test in its own process.
 *
 * Use it in place of cmocka_run_group_tests_name at the bottom of a test file:
 *
 *     #include "ras_test_main.h"   // after cmocka.h
 *     int main(void) {
 *         const struct CMUnitTest tests[] = { cmocka_unit_test(test_a), ... };
 *         return RAS_RUN_TESTS("hw2", tests, group_setup, group_teardown);
 *     }
 *
 * Environment (both optional; without them the program behaves exactly as
 * cmocka_run_group_tests_name would):
 *   RAS_TEST_LIST=1       print "RAS_TEST_LIST" and then one test name per line
 *                         to stdout, run nothing, exit 0;
 *   RAS_TEST_FILTER=NAME  run only the test called NAME (cmocka's test filter:
 *                         '*' and '?' are wildcards); exit 3 with a message
 *                         when no test matches, so a typo is not a silent pass.
 * Group setup and teardown still run, once, around the selected test.
 */
#ifndef RAS_TEST_MAIN_H
#define RAS_TEST_MAIN_H

#include <stdio.h>  /* printf, fprintf */
#include <stdlib.h> /* getenv */
#include <string.h> /* strcmp */

#define RAS_RUN_TESTS(group_name, tests, group_setup, group_teardown)                         \
    ras_test_run((group_name), (tests), sizeof(tests) / sizeof((tests)[0]), (group_setup),  \
                 (group_teardown))

/* '*' and '?' glob match, the subset cmocka's filter understands. */
static inline int ras_test_glob(const char *pat, const char *s) {
    if (*pat == '\0') return *s == '\0';
    if (*pat == '*') return ras_test_glob(pat + 1, s) || (*s && ras_test_glob(pat, s + 1));
    if (*s && (*pat == '?' || *pat == *s)) return ras_test_glob(pat + 1, s + 1);
    return 0;
}

static inline int ras_test_run(const char *group_name, const struct CMUnitTest *tests,
                               size_t count, CMFixtureFunction group_setup,
                               CMFixtureFunction group_teardown) {
    const char *list = getenv("RAS_TEST_LIST");
    if (list && *list && strcmp(list, "0") != 0) {
        printf("RAS_TEST_LIST\n");
        for (size_t i = 0; i < count; i++) printf("%s\n", tests[i].name);
        return 0;
    }
    const char *filter = getenv("RAS_TEST_FILTER");
    if (filter && *filter) {
        size_t matches = 0;
        for (size_t i = 0; i < count; i++) matches += (size_t)ras_test_glob(filter, tests[i].name);
        if (matches == 0) {
            fprintf(stderr, "%s: no test matches RAS_TEST_FILTER='%s' (RAS_TEST_LIST=1 lists them)\n",
                    group_name, filter);
            return 3;
        }
        cmocka_set_test_filter(filter);
    }
    return _cmocka_run_group_tests(group_name, tests, count, group_setup, group_teardown);
}

#endif
