/* ras_test_main.h — the one way a Raster101 test program runs its tests, so
 * the grader (tests/grading/grade) can run each test in its own process.
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
 *
 * For the grader (tests/grading/grade_run.c), one process runs many tests, each in a
 * child forked for it, so the libraries load once and each test still starts
 * from a fresh process image:
 *   RAS_EACH_NAMES=FILE   the tests to run, one name per line;
 *   RAS_EACH_OUT=DIR      per test NAME: NAME.out (its stdout and stderr),
 *                         NAME.xml (cmocka's XML) and NAME.fate (how the
 *                         child ended, in words);
 *   RAS_EACH_CALLS=DIR    NAME.calls, the record of its calls of student
 *                         code: written (RAS_EACH_MODE=record) or replayed
 *                         (RAS_EACH_MODE=replay, with DIR/NAME.fate as what
 *                         happened to the recording process); tests/grading/ras_call.h;
 *   RAS_EACH_LIMIT=S      processor seconds per test (default 10): the child's
 *                         RLIMIT_CPU, so a loaded machine, which slows a test
 *                         down without making it compute more, costs nothing;
 *   RAS_EACH_WALL=S       seconds on the clock per test (default 6 x the limit,
 *                         at least 60): the backstop for a test that waits
 *                         instead of computing. A child over either limit is
 *                         killed with its process group; its fate says which.
 */
#ifndef RAS_TEST_MAIN_H
#define RAS_TEST_MAIN_H

#include <fcntl.h>    /* open */
#include <signal.h>   /* kill */
#include <stdbool.h>  /* bool */
#include <stdio.h>    /* printf, fprintf */
#include <stdlib.h>   /* getenv, setenv */
#include <string.h>   /* strcmp */
#include <sys/resource.h> /* setrlimit, struct rusage */
#include <sys/stat.h> /* stat: a program older than its student files */
#include <sys/wait.h> /* wait4 */
#include <time.h>     /* nanosleep, clock_gettime */
#include <unistd.h>   /* fork, dup2 */

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

static inline const char *ras_test_signal_name(int sig) {
    switch (sig) {
    case SIGSEGV: return "SIGSEGV";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGABRT: return "SIGABRT";
    case SIGKILL: return "SIGKILL";
    case SIGXCPU: return "SIGXCPU";
    case SIGXFSZ: return "SIGXFSZ";
    default: return "a signal";
    }
}

/* cmocka catches a crash inside a test itself ("Test failed with exception:
 * Segmentation fault(11)") and exits 1: the signal, read back from the
 * test's output, or 0. */
static inline int ras_test_caught_signal(const char *out, const char *name) {
    char path[4096], text[8192];
    snprintf(path, sizeof path, "%s/%s.out", out, name);
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    const char *p = strstr(text, "Test failed with exception: ");
    const char *open = p ? strchr(p, '(') : NULL;
    return open ? atoi(open + 1) : 0;
}

/* Reads at most n-1 bytes of printable ASCII of a small file (a fate). */
static inline void ras_test_read_text(const char *path, char *buf, size_t n) {
    buf[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (!f) return;
    size_t got = fread(buf, 1, n - 1, f), k = 0;
    fclose(f);
    for (size_t i = 0; i < got; i++)
        if (buf[i] >= 32 && buf[i] < 127) buf[k++] = buf[i];
    buf[k] = '\0';
}

/* A test child that calls exit() (student code may) ends at once with that
 * status: the libraries' exit handlers, registered in the parent, would wait
 * for threads that do not exist in a forked child, until the time limit. */
static inline void ras_test_child_exit(int status, void *unused) {
    (void)unused;
    fflush(stdout);
    fflush(stderr);
    _exit(status);
}

/* RAS_EACH_*: each listed test in a forked child (see the top of this file). */
static inline int ras_test_each(const char *group_name, const struct CMUnitTest *tests,
                                size_t count, CMFixtureFunction group_setup,
                                CMFixtureFunction group_teardown) {
    const char *names = getenv("RAS_EACH_NAMES"), *out = getenv("RAS_EACH_OUT");
    const char *calls = getenv("RAS_EACH_CALLS"), *mode = getenv("RAS_EACH_MODE");
    const char *limit_s = getenv("RAS_EACH_LIMIT"), *wall_s = getenv("RAS_EACH_WALL");
    double limit = limit_s ? atof(limit_s) : 10;
    if (limit < 1) limit = 1;
    double wall = wall_s ? atof(wall_s) : (6 * limit > 60 ? 6 * limit : 60);
    if (wall < limit) wall = limit;
    bool replay = mode && !strcmp(mode, "replay");
    FILE *list = out ? fopen(names, "r") : NULL;
    if (!list) {
        fprintf(stderr, "%s: RAS_EACH_NAMES and RAS_EACH_OUT must name a list and a folder\n",
                group_name);
        return 3;
    }
    char name[256];
    while (fgets(name, sizeof name, list)) {
        name[strcspn(name, "\r\n")] = '\0';
        size_t which = count;
        for (size_t i = 0; i < count; i++)
            if (!strcmp(tests[i].name, name)) which = i;
        if (which == count) continue; /* not a test of this program */
        char path[4096], fate[256];
        fflush(stdout);
        fflush(stderr);
        pid_t pid = fork();
        if (pid == 0) {
            setpgid(0, 0);
            on_exit(ras_test_child_exit, NULL); /* runs before the parent's handlers */
            /* SIGXCPU after `limit` processor seconds (SIGKILL a second later if
             * it is caught); never above a hard limit the sandbox set. */
            struct rlimit cpu;
            rlim_t want = (rlim_t)(limit + 0.999);
            if (getrlimit(RLIMIT_CPU, &cpu) == 0) {
                if (cpu.rlim_max == RLIM_INFINITY || cpu.rlim_max > want + 1)
                    cpu.rlim_max = want + 1;
                cpu.rlim_cur = want < cpu.rlim_max ? want : cpu.rlim_max;
                setrlimit(RLIMIT_CPU, &cpu);
            }
            snprintf(path, sizeof path, "%s/%s.out", out, name);
            int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
            if (fd >= 0) {
                dup2(fd, 1);
                dup2(fd, 2);
            }
            snprintf(path, sizeof path, "%s/%s.xml", out, name);
            setenv("CMOCKA_XML_FILE", path, 1);
            if (calls) {
                snprintf(path, sizeof path, "%s/%s.calls", calls, name);
                setenv(replay ? "RAS_REPLAY" : "RAS_RECORD", path, 1);
                if (replay) {
                    snprintf(path, sizeof path, "%s/%s.fate", calls, name);
                    ras_test_read_text(path, fate, 120);
                    setenv("RAS_REPLAY_WORKER", *fate ? fate : "did not report how it ended", 1);
                }
            }
            cmocka_set_test_filter(name);
            _exit(_cmocka_run_group_tests(group_name, tests, count, group_setup, group_teardown)
                      ? 1
                      : 0);
        }
        int status = 0, sig;
        bool timed_out = false;
        struct rusage ru = {0};
        struct timespec t0, now, nap = {0, 2000000};
        clock_gettime(CLOCK_MONOTONIC, &t0);
        while (pid > 0 && wait4(pid, &status, WNOHANG, &ru) == 0) {
            clock_gettime(CLOCK_MONOTONIC, &now);
            if ((double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec) >
                wall) {
                kill(-pid, SIGKILL);
                kill(pid, SIGKILL);
                wait4(pid, &status, 0, &ru);
                timed_out = true;
                break;
            }
            nanosleep(&nap, NULL);
        }
        if (pid > 0) kill(-pid, SIGKILL); /* what the test left running in its group */
        double cpu_used = (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                          1e-6 * (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
        bool over_cpu = pid > 0 && !timed_out && WIFSIGNALED(status) &&
                        (WTERMSIG(status) == SIGXCPU ||
                         (WTERMSIG(status) == SIGKILL && cpu_used >= limit));
        /* "was stopped after": the grader's word for a time limit (fate_parse) */
        if (pid < 0)
            snprintf(fate, sizeof fate, "could not be started");
        else if (timed_out)
            snprintf(fate, sizeof fate,
                     "was stopped after %.0f s on the clock (the time limit; it had used %.1f s "
                     "of processor time)",
                     wall, cpu_used);
        else if (over_cpu)
            snprintf(fate, sizeof fate,
                     "was stopped after %.0f s of processor time (the time limit)", limit);
        else if (WIFSIGNALED(status))
            snprintf(fate, sizeof fate, "was killed by signal %d (%s)", WTERMSIG(status),
                     ras_test_signal_name(WTERMSIG(status)));
        else if ((sig = ras_test_caught_signal(out, name)) != 0)
            snprintf(fate, sizeof fate, "was killed by signal %d (%s)", sig,
                     ras_test_signal_name(sig));
        else
            snprintf(fate, sizeof fate, "exited with status %d", WEXITSTATUS(status));
        snprintf(path, sizeof path, "%s/%s.fate", out, name);
        FILE *f = fopen(path, "w");
        if (f) {
            fputs(fate, f);
            fclose(f);
        }
    }
    fclose(list);
    return 0;
}

/* A test program built before the student's last edit tests older code:
 * say so first, in the programs' words (common/app/ras_app.c), since `ctest`
 * and build/tests/test_hwN_student run whatever was built last. Only the
 * student's test programs know their files (RAS_STUDENT_SOURCES, a
 * ':'-separated list from tests/CMakeLists.txt); sources that cannot be read
 * say nothing. */
static inline void ras_test_warn_if_stale(const char *group_name) {
#ifdef RAS_STUDENT_SOURCES
    struct stat exe, src;
    if (stat("/proc/self/exe", &exe) != 0) return;
    for (const char *p = RAS_STUDENT_SOURCES; *p;) {
        size_t n = strcspn(p, ":");
        char path[4096];
        snprintf(path, sizeof path, "%.*s", (int)n, p);
        if (stat(path, &src) == 0 && src.st_mtime > exe.st_mtime) {
            fprintf(stderr,
                    "test_%s_student: note: this test program was built before your last edit "
                    "of %s, so it tests your older code; run `make build` (make grade and make "
                    "test build it too)\n",
                    group_name, path);
            return;
        }
        p += n + (p[n] == ':');
    }
#else
    (void)group_name;
#endif
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
    if (getenv("RAS_EACH_NAMES"))
        return ras_test_each(group_name, tests, count, group_setup, group_teardown);
    ras_test_warn_if_stale(group_name);
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
