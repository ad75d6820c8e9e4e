/* grade_tool.c — raster101-grade: grades one build of the assignments against
 * tests/grading/rubric.json. tests/grading/grade builds the student code and then calls this;
 * see docs/grading.md.
 *
 *   raster101-grade --source SRC --build BUILD --out OUT
 *                   [--rubric FILE] [--hw hwN]... [--variant student|ref]
 *                   [--build-failed hwN=LOG]... [--expect full|0|POINTS]
 *
 * For each assignment of the rubric (or only those given with --hw):
 *   1. tests: lists the test program's tests (RAS_TEST_LIST=1, see
 *      tests/unit/ras_test_main.h) and runs each test in its own process
 *      (RAS_TEST_FILTER=name) with cmocka's XML output, a time limit and a
 *      memory limit; a crash or a hang fails that test only. A test program
 *      without ras_test_main.h runs once, whole, and its console output is
 *      split per test.
 *   2. images: runs the program with each graded scene's arguments and
 *      compares the PNG with tests/reference/ (common/app/ras_compare.h), writing
 *      a heatmap and a crop of the worst region.
 * Outputs in OUT: results.json (Gradescope), report.md (with images),
 * scores.csv (one row per item, for tests/grading/grade-all), hwN/cmocka.xml; a table
 * on stdout.
 *
 * Scoring: an item scores its points when it passes and no TODO notice was
 * printed while it ran (passing on a placeholder stub earns nothing). Exit
 * status: 0 graded (whatever the score), 1 --expect not met, 2 grader error.
 */
#include "ras_catalogue.h"
#include "ras_compare.h"
#include "ras_dump.h"
#include "ras_image.h"
#include "ras_io.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h> /* strncasecmp */
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* snprintf that cuts silently (paths here are far below the buffer sizes). */
__attribute__((format(printf, 3, 4))) static void fmt(char *buf, size_t size, const char *f, ...) {
    va_list ap;
    va_start(ap, f);
    vsnprintf(buf, size, f, ap);
    va_end(ap);
}

/* ---------------------------------------------------------------- strings */

typedef struct sbuf {
    char *s;
    size_t len, cap;
} sbuf;

static void sb_addn(sbuf *b, const char *s, size_t n) {
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 256;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *p = realloc(b->s, cap);
        if (!p) abort();
        b->s = p;
        b->cap = cap;
    }
    memcpy(b->s + b->len, s, n);
    b->len += n;
    b->s[b->len] = '\0';
}
static void sb_add(sbuf *b, const char *s) { sb_addn(b, s, strlen(s)); }
static void sb_printf(sbuf *b, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    char tmp[2048];
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n < 0) return;
    if ((size_t)n < sizeof tmp) {
        sb_addn(b, tmp, (size_t)n);
        return;
    }
    char *big = malloc((size_t)n + 1);
    if (!big) abort();
    va_start(ap, fmt);
    vsnprintf(big, (size_t)n + 1, fmt, ap);
    va_end(ap);
    sb_addn(b, big, (size_t)n);
    free(big);
}
static const char *sb_str(const sbuf *b) { return b->s ? b->s : ""; }

static char *xstrdup(const char *s) {
    char *p = strdup(s ? s : "");
    if (!p) abort();
    return p;
}

static char *read_file(const char *path, size_t limit) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    sbuf b = {0};
    char chunk[8192];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (limit && b.len + n > limit) {
            sb_addn(&b, chunk, limit - b.len);
            sb_add(&b, "\n[... output cut ...]\n");
            break;
        }
        sb_addn(&b, chunk, n);
    }
    fclose(f);
    if (!b.s) return xstrdup("");
    return b.s;
}

static bool copy_file(const char *from, const char *to) {
    FILE *in = fopen(from, "rb"), *out = in ? fopen(to, "wb") : NULL;
    bool ok = in && out;
    char buf[65536];
    size_t n;
    while (ok && (n = fread(buf, 1, sizeof buf, in)) > 0)
        ok = fwrite(buf, 1, n, out) == n;
    if (in) fclose(in);
    if (out && fclose(out) != 0) ok = false;
    return ok;
}

static void mkdirs(const char *path) {
    char tmp[4096];
    fmt(tmp, sizeof tmp, "%s", path);
    for (char *p = tmp + 1; *p; p++)
        if (*p == '/') {
            *p = '\0';
            mkdir(tmp, 0755);
            *p = '/';
        }
    mkdir(tmp, 0755);
}

static bool file_exists(const char *path) { return access(path, F_OK) == 0; }

/* Drops cmocka's banner lines and the "ERROR: " prefix of its XML mode, so
 * what remains is what the test said. */
static char *clean_output(const char *raw) {
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

static bool has_todo_notice(const char *out) { return strstr(out, "is not written yet") != NULL; }

/* A table's "why" column holds this many characters (not bytes: a cut never
 * falls inside a UTF-8 character). */
enum { REASON_CHARS = 110 };

/* The length in bytes of the first `chars` characters of s[0..n) (UTF-8: a
 * continuation byte 10xxxxxx never starts a character). */
static size_t utf8_prefix(const char *s, size_t n, size_t chars) {
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
static char *reason_line(const char *out) {
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

static void xml_escape(sbuf *b, const char *s) {
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

/* ---------------------------------------------------------------- processes */

typedef enum run_kind { RUN_EXITED, RUN_SIGNALED, RUN_TIMEOUT, RUN_NOT_STARTED } run_kind;

typedef struct run_result {
    run_kind kind;
    int code; /* exit status or signal number */
    double seconds;
} run_result;

static double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* RAS_GRADE_PROFILE=1: where a grading's time goes, a line per phase on
 * stderr (docs/feedback.md quotes it). */
static void profile(const char *what, const char *id, double since) {
    static int on = -1;
    if (on < 0) on = getenv("RAS_GRADE_PROFILE") && *getenv("RAS_GRADE_PROFILE") == '1';
    if (on) fprintf(stderr, "raster101-grade: profile: %-4s %-28s %6.3f s\n", id, what, now_s() - since);
}

/* Runs argv in its own process group with stdout+stderr captured through a
 * pipe (at most OUTPUT_CAP bytes kept, the rest read and dropped, so a flood
 * costs neither disk nor memory) and written to out_path; the
 * NULL-terminated "NAME=value" pairs of env added, a wall-clock limit and an
 * address-space limit (MB, 0 = none). Kills the whole group at the limit. */
#define OUTPUT_CAP (48 * 1024)
static run_result run_limited(char *const argv[], const char *const env[], const char *out_path,
                              double limit_s, long mem_mb) {
    run_result r = {RUN_NOT_STARTED, 0, 0};
    double t0 = now_s();
    int pipefd[2];
    if (pipe(pipefd) != 0) return r;
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) {
        close(pipefd[0]);
        close(pipefd[1]);
        return r;
    }
    if (pid == 0) {
        setpgid(0, 0);
        dup2(pipefd[1], 1);
        dup2(pipefd[1], 2);
        close(pipefd[0]);
        close(pipefd[1]);
        int devnull = open("/dev/null", O_RDONLY);
        if (devnull >= 0) dup2(devnull, 0);
        for (int i = 0; env && env[i]; i++)
            putenv((char *)env[i]);
        unsetenv("DISPLAY"); /* never open a window while grading */
        struct rlimit core = {0, 0};
        setrlimit(RLIMIT_CORE, &core);
        if (mem_mb > 0) {
            struct rlimit as = {(rlim_t)mem_mb << 20, (rlim_t)mem_mb << 20};
            setrlimit(RLIMIT_AS, &as);
        }
        struct rlimit cpu = {(rlim_t)limit_s + 2, (rlim_t)limit_s + 3};
        setrlimit(RLIMIT_CPU, &cpu);
        execv(argv[0], argv);
        fprintf(stderr, "could not start %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    setpgid(pid, pid);
    close(pipefd[1]);
    fcntl(pipefd[0], F_SETFL, O_NONBLOCK);
    sbuf kept = {0};
    size_t dropped = 0;
    int status = 0;
    bool done = false;
    for (;;) {
        char chunk[16384];
        ssize_t n;
        while ((n = read(pipefd[0], chunk, sizeof chunk)) > 0) {
            size_t room = kept.len < OUTPUT_CAP ? OUTPUT_CAP - kept.len : 0;
            size_t take = (size_t)n < room ? (size_t)n : room;
            if (take) sb_addn(&kept, chunk, take);
            dropped += (size_t)n - take;
        }
        if (done) break;
        pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid) {
            done = true; /* one more read for what is left in the pipe */
            continue;
        }
        if (w < 0 && errno != EINTR) break;
        if (now_s() - t0 > limit_s) {
            kill(-pid, SIGKILL);
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            r.kind = RUN_TIMEOUT;
            break;
        }
        struct pollfd pfd = {pipefd[0], POLLIN, 0};
        poll(&pfd, 1, 5);
    }
    close(pipefd[0]);
    kill(-pid, SIGKILL); /* anything the run left behind in its group */
    if (dropped) sb_printf(&kept, "\n[... %zu more bytes of output dropped ...]\n", dropped);
    int fd = open(out_path, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0) {
        /* a short write only shortens what the report quotes */
        ssize_t w = kept.len ? write(fd, kept.s, kept.len) : 0;
        (void)w;
        close(fd);
    }
    free(kept.s);
    r.seconds = now_s() - t0;
    if (r.kind == RUN_TIMEOUT) return r;
    if (WIFSIGNALED(status)) {
        r.kind = RUN_SIGNALED;
        r.code = WTERMSIG(status);
    } else {
        r.kind = RUN_EXITED;
        r.code = WEXITSTATUS(status);
    }
    return r;
}

/* One process for run_jobs: its command, environment and output file. */
typedef struct job {
    char *argv[120];
    char store[16][4200]; /* strings argv and env point into */
    const char *env[8];
    char out_path[4096];
    char rw[4096];      /* its sandbox's writable folder */
    double limit;
    long mem_mb;
    run_result rr;
    const cJSON *args; /* an image's program arguments, as chosen for this grading */
    char extra_ro[4096]; /* one more read-only folder in its sandbox ("": none) */
    /* A job to run right after this one in the same child of run_jobs (a
     * chunk's trusted replay after its worker), `between` first: so one
     * chunk's replay overlaps the other chunks' workers. */
    struct job *then;
    void (*between)(const struct job *j, void *arg);
    void *between_arg;
} job;

/* Runs the jobs, `parallel` at a time, each through run_limited in a child
 * of the grader that hands back its run_result through a pipe. */
static void run_jobs(job *jobs, int n, int parallel) {
    pid_t *pids = calloc((size_t)n + 1, sizeof *pids);
    int *fds = calloc((size_t)n + 1, sizeof *fds);
    if (!pids || !fds) abort();
    int next = 0, active = 0;
    if (parallel < 1) parallel = 1;
    while (next < n || active > 0) {
        while (active < parallel && next < n) {
            job *j = &jobs[next];
            j->rr = (run_result){RUN_NOT_STARTED, 0, 0};
            int p[2];
            if (pipe(p) != 0) {
                next++;
                continue;
            }
            fflush(stdout);
            fflush(stderr);
            pid_t pid = fork();
            if (pid == 0) {
                close(p[0]);
                run_result rr[2] = {run_limited(j->argv, j->env, j->out_path, j->limit, j->mem_mb),
                                    {RUN_NOT_STARTED, 0, 0}};
                job *t = j->then;
                if (t) {
                    j->rr = rr[0];
                    if (j->between) j->between(j, j->between_arg);
                    rr[1] = run_limited(t->argv, t->env, t->out_path, t->limit, t->mem_mb);
                }
                size_t want = (t ? 2 : 1) * sizeof rr[0];
                ssize_t w = write(p[1], rr, want);
                _exit(w == (ssize_t)want ? 0 : 1);
            }
            close(p[1]);
            pids[next] = pid;
            fds[next] = p[0];
            if (pid > 0) active++;
            next++;
        }
        if (active == 0) continue;
        int status;
        pid_t w = wait(&status);
        if (w < 0) {
            if (errno == EINTR) continue;
            break;
        }
        for (int i = 0; i < next; i++)
            if (pids[i] == w) {
                run_result rr;
                if (read(fds[i], &rr, sizeof rr) == (ssize_t)sizeof rr) jobs[i].rr = rr;
                if (jobs[i].then) {
                    jobs[i].then->rr = (run_result){RUN_NOT_STARTED, 0, 0};
                    if (read(fds[i], &rr, sizeof rr) == (ssize_t)sizeof rr) jobs[i].then->rr = rr;
                }
                close(fds[i]);
                pids[i] = 0;
                active--;
            }
    }
    free(pids);
    free(fds);
}

static const char *signal_text(int sig) {
    switch (sig) {
    case SIGSEGV: return "SIGSEGV, a segmentation fault: memory read or written out of bounds";
    case SIGABRT: return "SIGABRT: an assert failed or memory was corrupted";
    case SIGFPE: return "SIGFPE: an integer division by zero";
    case SIGBUS: return "SIGBUS: a bad memory access";
    case SIGKILL: return "SIGKILL: killed (out of memory or CPU time?)";
    case SIGXCPU: return "SIGXCPU: the CPU time limit ran out (an endless loop?)";
    case SIGILL: return "SIGILL: an illegal instruction (undefined behaviour?)";
    default: return "a signal";
    }
}

/* ---------------------------------------------------------------- results */

typedef struct item {
    char *name; /* test name or "image NAME" */
    bool is_image;
    bool counted; /* false: reported but not in the score */
    bool passed;
    bool default_weight;
    double score, max_score;
    char *status; /* PASS, FAIL, CRASH, TIMEOUT, TODO, BUILD, SKIP */
    char *reason; /* one line for the table */
    char *output; /* everything for the student */
    char *xml;    /* JUnit <testcase> for tests */
    /* images: paths relative to OUT */
    char *img_expected, *img_got, *img_diff, *img_crop;
    /* the first buffer that differs (--dump): its name and pictures */
    char *buf_name, *buf_ref, *buf_got, *buf_diff;
    /* the student file, function and TODO numbers the item checks (the
     * rubric's "where"; points into the rubric); NULL when it names none */
    const char *where;
} item;

typedef struct assignment_result {
    char *id, *title;
    bool graded;
    char *note; /* why not graded, or remarks */
    item *items;
    int n_items, cap_items;
    double score, max_score;
    double seconds;
} assignment_result;

static item *add_item(assignment_result *a) {
    if (a->n_items == a->cap_items) {
        a->cap_items = a->cap_items ? 2 * a->cap_items : 16;
        a->items = realloc(a->items, (size_t)a->cap_items * sizeof *a->items);
        if (!a->items) abort();
    }
    item *it = &a->items[a->n_items++];
    memset(it, 0, sizeof *it);
    it->counted = true;
    return it;
}

static void item_free(item *it) {
    char *owned[] = {it->name,         it->status,  it->reason,   it->output,  it->xml,
                     it->img_expected, it->img_got, it->img_diff, it->img_crop,
                     it->buf_name,     it->buf_ref, it->buf_got,  it->buf_diff};
    for (size_t i = 0; i < sizeof owned / sizeof owned[0]; i++)
        free(owned[i]);
}

static void assignment_results_free(assignment_result *as, int n) {
    for (int k = 0; k < n; k++) {
        for (int i = 0; i < as[k].n_items; i++)
            item_free(&as[k].items[i]);
        free(as[k].items);
        free(as[k].id);
        free(as[k].title);
        free(as[k].note);
    }
    free(as);
}

/* Images given buffer evidence per grading: each costs two more renders. */
enum { EVIDENCE_MAX = 24 };

typedef struct grader {
    const char *source, *build, *out, *variant;
    /* The student's side: the pristine tree and its build, both read-only in
     * the sandbox, and the work folder where each run gets its own writable
     * folder. Nothing of the trusted side (source, build, out) is visible. */
    const char *student_tree, *student_build, *work;
    /* --own: each assignment's programs and test worker linked with the
     * reference of the earlier assignments (tests/grading/grade, step 2b), as
     * OWN/refK.../bin and OWN/refK.../tests; NULL when there are none. */
    const char *own;
    /* --sanitized-build (grade --sanitize): the student's test workers built
     * with AddressSanitizer and UBSan in the sandbox; NULL: no such pass. */
    const char *sanitized;
    long sandbox_uid; /* -1: not root, runs stay this user's */
    int runs;         /* numbers the run folders */
    int evidence_runs; /* images given buffer evidence so far (at most EVIDENCE_MAX) */
    int jobs;         /* sandboxed runs at once */
    cJSON *rubric;
    double default_points, test_limit, render_limit;
    long mem_mb;
    /* --notes: what tests/grading/grade found in the submission (a missing or
     * misnamed file, a link it refused), escaped, shown first; NULL: none */
    char *notes;
    /* --seed: the keyed hash of the submission's files and the course's
     * secret (tests/grading/grade), from which the variants are drawn: the same
     * files always get the same pictures; without it, the kernel's random */
    unsigned long long seed;
    bool has_seed;
    cJSON *drawn; /* the argument lists drawn for this grading (owned) */
    const char *only[8];
    int n_only;
    const char *failed_hw[8], *failed_log[8];
    int n_failed;
} grader;

static double num_or(const cJSON *obj, const char *key, double fallback) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsNumber(v) ? v->valuedouble : fallback;
}
static const char *str_or(const cJSON *obj, const char *key, const char *fallback) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsString(v) ? v->valuestring : fallback;
}

/* Time limits (issue 26): a test may use test_time_limit_s of processor time
 * (tests/unit/ras_test_main.h sets it as the test process's RLIMIT_CPU), so a
 * loaded machine, which slows a test down but does not make it compute more,
 * never costs a point. The clock is only a backstop, for a test that waits
 * instead of computing: test_wall_limit_s, by default six times the processor
 * limit and at least a minute. */
static double wall_backstop(double cpu_s) { return 6 * cpu_s > 60 ? 6 * cpu_s : 60; }
static double test_wall(const grader *g) {
    return num_or(g->rubric, "test_wall_limit_s", wall_backstop(g->test_limit));
}

/* Points for a test from the rubric's "tests" object; *dflt set when the
 * rubric does not name it. */
static double test_points(const grader *g, const cJSON *tests, const char *name, bool *dflt) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(tests, name);
    *dflt = !cJSON_IsNumber(v);
    return cJSON_IsNumber(v) ? v->valuedouble : g->default_points;
}

/* Fills in score and status of a finished test from its run and output. */
static void judge_test(item *it, run_result rr, bool failed_in_output, const char *out,
                       double limit, double wall, const char *crash_hint) {
    sbuf o = {0};
    it->passed = false;
    if (rr.kind == RUN_TIMEOUT && rr.code == 1) { /* fate_parse: stopped by the clock */
        it->status = xstrdup("TIMEOUT");
        sb_printf(&o,
                  "the test was still running after %.0f s on the clock, without having used its "
                  "%.0f s of processor time, and was stopped: it waits for something that never "
                  "comes (an endless loop around sleep or read?)\n",
                  wall, limit);
    } else if (rr.kind == RUN_TIMEOUT) {
        it->status = xstrdup("TIMEOUT");
        sb_printf(&o,
                  "the test used more than %.0f s of processor time and was stopped: an endless "
                  "loop, or far too much work (e.g. a bounding box that is not clamped)\n",
                  limit);
    } else if (rr.kind == RUN_SIGNALED) {
        it->status = xstrdup("CRASH");
        sb_printf(&o, "the test crashed with %s\nlikely mistake: %s\n", signal_text(rr.code),
                  crash_hint);
    } else if (rr.kind == RUN_NOT_STARTED) {
        it->status = xstrdup("ERROR");
        sb_add(&o, "the test program could not be started\n");
    } else if (strstr(out, "Test failed with exception")) {
        /* cmocka caught the signal itself: still a crash of the student code */
        it->status = xstrdup("CRASH");
        sb_printf(&o, "the test crashed (cmocka caught the signal)\nlikely mistake: %s\n",
                  crash_hint);
    } else if (rr.code == 0 && !failed_in_output) {
        it->passed = true;
        it->status = xstrdup(has_todo_notice(out) ? "TODO" : "PASS");
    } else {
        it->status = xstrdup(has_todo_notice(out) ? "TODO" : "FAIL");
    }
    if (*out) sb_printf(&o, "%s%s", o.len ? "output before it stopped:\n" : "", out);
    if (it->passed && has_todo_notice(out))
        sb_add(&o, "\n(passed, but a TODO notice was printed, so no points: either a function it "
                   "calls is still the stub and its placeholder happens to be right, or you wrote "
                   "the function and left its `static bool shown; ras_todo_notice(...)` lines in: "
                   "delete them)");
    it->output = o.s ? o.s : xstrdup("");
    it->score = it->passed && !has_todo_notice(out) ? it->max_score : 0;
    if (it->passed && !has_todo_notice(out))
        it->reason = xstrdup("");
    else if (it->passed)
        it->reason = xstrdup("passes, but a TODO notice was printed (a stub, or notice lines left in)");
    else
        it->reason = reason_line(it->output);
}

static void junit_case(item *it, const char *classname, const char *raw_xml) {
    sbuf x = {0};
    if (raw_xml) {
        sb_add(&x, raw_xml);
    } else {
        sb_add(&x, "    <testcase classname=\"");
        xml_escape(&x, classname);
        sb_add(&x, "\" name=\"");
        xml_escape(&x, it->name);
        sb_add(&x, "\">\n");
        if (!it->passed) {
            sb_add(&x, "      <failure message=\"");
            xml_escape(&x, it->reason ? it->reason : it->status);
            sb_add(&x, "\"><![CDATA[");
            sb_add(&x, it->output ? it->output : "");
            sb_add(&x, "]]></failure>\n");
        }
        sb_add(&x, "    </testcase>\n");
    }
    it->xml = x.s;
}

/* The <testcase> elements of a cmocka XML file, or NULL. */
static char *cmocka_testcases(const char *xml_path, bool *has_failure) {
    char *x = read_file(xml_path, 0);
    if (!x) return NULL;
    char *a = strstr(x, "<testcase"), *b = a ? strstr(a, "</testsuite>") : NULL;
    if (!a || !b) {
        free(x);
        return NULL;
    }
    *b = '\0';
    *has_failure = strstr(a, "<failure") != NULL || strstr(a, "<error") != NULL;
    sbuf s = {0};
    sb_add(&s, "    ");
    sb_add(&s, a);
    free(x);
    while (s.len && (s.s[s.len - 1] == ' ' || s.s[s.len - 1] == '\n'))
        s.s[--s.len] = '\0';
    sb_add(&s, "\n");
    return s.s;
}

/* ------------------------------------------------------------- the tests */

typedef struct name_list {
    char **v;
    int n;
} name_list;

static void names_add(name_list *l, const char *s) {
    l->v = realloc(l->v, (size_t)(l->n + 1) * sizeof *l->v);
    if (!l->v) abort();
    l->v[l->n++] = xstrdup(s);
}
static void names_free(name_list *l) {
    for (int i = 0; i < l->n; i++)
        free(l->v[i]);
    free(l->v);
    *l = (name_list){0};
}
static bool names_has(const name_list *l, const char *s) {
    for (int i = 0; i < l->n; i++)
        if (!strcmp(l->v[i], s)) return true;
    return false;
}

/* Parses the console output of a whole cmocka run (standard output mode)
 * into per-test blocks: used when the test program has no RAS_TEST_FILTER. */
/* Whether the UTF-8 sequence p[0..n) is a bidirectional control (U+202A-E,
 * U+2066-9, U+200E/F, U+061C): they reorder what a reader sees around them. */
static bool is_bidi_control(const unsigned char *p, size_t n) {
    if (n == 3 && p[0] == 0xE2 && p[1] == 0x80 && ((p[2] >= 0xAA && p[2] <= 0xAE) || p[2] == 0x8E ||
                                                    p[2] == 0x8F))
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
static char *student_text(const char *raw, size_t cap) {
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

/* Writes `text` to a Markdown report as a fenced code block whose fence is
 * longer than any run of backticks inside it, so no text can close it and
 * render as the report's own Markdown. */
static void report_fenced(FILE *f, const char *text) {
    size_t longest = 0, run = 0;
    for (const char *c = text; *c; c++) {
        run = *c == '`' ? run + 1 : 0;
        if (run > longest) longest = run;
    }
    size_t fence = longest < 3 ? 3 : longest + 1;
    fputc('\n', f);
    for (size_t i = 0; i < fence; i++)
        fputc('`', f);
    size_t len = strlen(text);
    fprintf(f, "text\n%s%s", text, len && text[len - 1] == '\n' ? "" : "\n");
    for (size_t i = 0; i < fence; i++)
        fputc('`', f);
    fputc('\n', f);
}

/* Writes `text` into a cell of a Markdown table: Markdown's and HTML's
 * special characters backslash-escaped, line breaks and bidi controls
 * dropped, so a cell is text and stays in its cell. */
static void report_cell(FILE *f, const char *text) {
    for (const unsigned char *c = (const unsigned char *)text; *c; c++) {
        if (*c == '\n' || *c == '\r') {
            fputc(' ', f);
        } else if (*c == 0xE2 && c[1] && c[2] && is_bidi_control(c, 3)) {
            c += 2;
        } else if (*c == '|') {
            fputc('/', f);
        } else {
            if (strchr("\\`*_[]<>!#~&", *c)) fputc('\\', f);
            fputc(*c, f);
        }
    }
}

/* A sealed run's failure (its process held reference code): only the
 * verdict and the test's fixed hint go back, never a value the student's
 * code returned (a float can carry bytes of the reference's machine code).
 * The hint is the "Likely mistake:" sentence, with every number that is not
 * a small integer (decimals, exponents, 3+ digits) replaced by "#". */
static char *sealed_text(const char *status, const char *replay_out) {
    sbuf b = {0};
    sb_printf(&b, "%s on your code linked with the earlier assignments' reference; this run "
                  "holds reference code, so the values your code returned are not shown (run "
                  "the test in your own build to see them)",
              status);
    const char *h = strstr(replay_out, "Likely mistake");
    if (!h) h = strstr(replay_out, "likely mistake");
    if (h) {
        sb_add(&b, "\n");
        const char *end = strchr(h, '\n');
        size_t len = end ? (size_t)(end - h) : strlen(h);
        if (len > 400) len = 400;
        for (size_t i = 0; i < len;) {
            if (isdigit((unsigned char)h[i])) {
                size_t j = i, digits = 0;
                bool other = false;
                while (j < len && (isdigit((unsigned char)h[j]) || h[j] == '.' ||
                                   ((h[j] == 'e' || h[j] == 'E') && j + 1 < len &&
                                    (isdigit((unsigned char)h[j + 1]) || h[j + 1] == '-')) ||
                                   (h[j] == '-' && j > i && (h[j - 1] == 'e' || h[j - 1] == 'E')))) {
                    if (isdigit((unsigned char)h[j])) digits++;
                    else if (h[j] != '.' || (j + 1 < len && isdigit((unsigned char)h[j + 1])))
                        other = true;
                    j++;
                }
                /* a TODO's number is the hint's, not a value */
                bool todo = i >= 5 && !strncmp(h + i - 5, "TODO ", 5) && digits < 3;
                if (!todo && (other || digits >= 3)) sb_add(&b, "#");
                else sb_addn(&b, h + i, j - i);
                i = j;
            } else {
                sb_addn(&b, h + i, 1);
                i++;
            }
        }
    }
    return b.s;
}

/* `text` with every occurrence of the grading's work folder (a random name)
 * written as "WORK": a report says the same for the same files, and names
 * no folder of the grader's. Takes and returns an owned string. */
static char *without_work_path(const char *work, char *text) {
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

/* Each sandboxed run its own uid (the grading's base + 1 + run % 90), so
 * runs at the same time never share per-uid limits, and the user isolation's
 * kill-by-uid reaches only its own run. */
static long run_uid(const grader *g, int run) {
    return g->sandbox_uid < 0 ? -1 : g->sandbox_uid + 1 + run % 90;
}

/* A fresh folder for one sandboxed run, writable by that run's user and by
 * nobody else. */
static void run_dir(const grader *g, char *path, size_t size) {
    int run = ((grader *)g)->runs++;
    fmt(path, size, "%s/runs/%d", g->work, run);
    mkdirs(path);
    long uid = run_uid(g, run);
    if (uid >= 0 && chown(path, (uid_t)uid, (gid_t)uid) != 0) chmod(path, 0777);
}

/* Fills j->argv with `tests/grading/sandbox ... --` for a new run folder j->rw: the
 * student's tree and build read-only, j->rw writable, the given environment
 * (the sandbox starts from an empty one); returns the next argv index. */
static int sandbox_job(const grader *g, job *j, double limit_s, const char *const env[]) {
    int n = 0, k = 0;
    run_dir(g, j->rw, sizeof j->rw);
    j->limit = limit_s;
    j->mem_mb = 0; /* the sandbox sets the limits */
    j->env[0] = NULL;
    fmt(j->store[k], sizeof j->store[k], "%s/tests/grading/sandbox", g->source);
    j->argv[n++] = j->store[k++];
    j->argv[n++] = "--ro";
    j->argv[n++] = (char *)g->student_tree;
    j->argv[n++] = "--ro";
    j->argv[n++] = (char *)g->student_build;
    if (j->extra_ro[0]) {
        j->argv[n++] = "--ro";
        j->argv[n++] = j->extra_ro;
    }
    j->argv[n++] = "--rw";
    j->argv[n++] = j->rw;
    j->argv[n++] = "--chdir";
    j->argv[n++] = j->rw;
    j->argv[n++] = "--mem-mb";
    fmt(j->store[k], sizeof j->store[k], "%ld", g->mem_mb > 0 ? g->mem_mb : 65536);
    j->argv[n++] = j->store[k++];
    j->argv[n++] = "--cpu-s";
    fmt(j->store[k], sizeof j->store[k], "%.0f", limit_s + 2);
    j->argv[n++] = j->store[k++];
    if (g->sandbox_uid >= 0) {
        j->argv[n++] = "--uid";
        fmt(j->store[k], sizeof j->store[k], "%ld", run_uid(g, g->runs - 1));
        j->argv[n++] = j->store[k++];
    }
    for (int i = 0; env && env[i] && k < 14; i++) {
        j->argv[n++] = "--env";
        fmt(j->store[k], sizeof j->store[k], "%s", env[i]);
        j->argv[n++] = j->store[k++];
    }
    j->argv[n++] = "--";
    return n;
}

/* How a sandboxed run ended, in words (bwrap reports a signal as 128+N), in
 * the form tests/unit/ras_test_main.h writes a test's fate, so that fate_parse
 * reads both the same way. */
static void fate_text(run_result rr, double limit, char *buf, size_t size) {
    int sig = rr.kind == RUN_SIGNALED                       ? rr.code
              : rr.kind == RUN_EXITED && rr.code > 128 && rr.code < 160 ? rr.code - 128
                                                                        : 0;
    if (rr.kind == RUN_TIMEOUT)
        fmt(buf, size, "was stopped after %.0f s on the clock (the time limit)", limit);
    else if (rr.kind == RUN_NOT_STARTED)
        fmt(buf, size, "could not be started");
    else if (sig)
        fmt(buf, size, "was killed by signal %d (%s)", sig, signal_text(sig));
    else
        fmt(buf, size, "exited with status %d", rr.code);
}

/* A file the sandbox wrote: only a regular file (no symlink, FIFO or device
 * planted there), at most `limit` bytes of it. NULL when there is none. */
static char *read_small_file(const char *path, size_t limit) {
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    struct stat st;
    if (fd < 0) return NULL;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return NULL;
    }
    sbuf b = {0};
    char chunk[4096];
    ssize_t n;
    while (b.len < limit && (n = read(fd, chunk, sizeof chunk)) > 0)
        sb_addn(&b, chunk, b.len + (size_t)n > limit ? limit - b.len : (size_t)n);
    if ((size_t)st.st_size > limit) sb_add(&b, "\n[... output cut ...]\n");
    close(fd);
    return b.s ? b.s : xstrdup("");
}

/* One line of printable text (a fate), "" when there is none. */
static void read_small(const char *path, char *buf, size_t n) {
    char *t = read_small_file(path, n - 1);
    size_t k = 0;
    for (const char *p = t ? t : ""; *p && k < n - 1; p++)
        if (*p >= 32 && *p < 127) buf[k++] = *p;
    buf[k] = '\0';
    free(t);
}

/* The words of tests/unit/ras_test_main.h's NAME.fate back into a run_result. */
static run_result fate_parse(const char *fate) {
    const char *p;
    int v;
    /* code 1: by the clock, 0: by its processor time (ras_test_main.h) */
    if (strstr(fate, "was stopped after"))
        return (run_result){RUN_TIMEOUT, strstr(fate, "on the clock") ? 1 : 0, 0};
    if ((p = strstr(fate, "was killed by signal ")) && sscanf(p + 21, "%d", &v) == 1)
        return (run_result){RUN_SIGNALED, v, 0};
    if ((p = strstr(fate, "exited with status ")) && sscanf(p + 19, "%d", &v) == 1)
        return (run_result){RUN_EXITED, v, 0};
    return (run_result){RUN_EXITED, 1, 0};
}

static bool is_dir(const char *path);

/* Whose code a grade measures (docs/grading.md): hwN is graded on its own
 * code, linked with the reference of hw1 … hwN-1, when tests/grading/grade could link
 * it (--own). The folder of such a link is OWN/ref1…(N-1); `refs` names the
 * assignments taken from the reference ("1", "12"; NULL: every earlier one).
 * False when there is none: then the student's whole chain is graded. */
static bool own_dir(const grader *g, const char *id, const char *refs, char *dir, size_t size) {
    int number = 0;
    if (!g->own || sscanf(id, "hw%d", &number) != 1 || number < 2 || number > 9) return false;
    char all[10] = "";
    for (int k = 1; k < number; k++)
        all[k - 1] = (char)('0' + k);
    fmt(dir, size, "%s/ref%s", g->own, refs ? refs : all);
    if (is_dir(dir)) return true;
    dir[0] = '\0';
    return false;
}

/* The first line of a sanitizer report in `out` and the first frame of it
 * in a student file ("in FUNC .../hw3_shading/shading.c:183"), as one line
 * into buf; false when there is no report. */
static bool sanitizer_finding(const char *out, const cJSON *assignments, char *buf,
                              size_t size) {
    const char *asan = strstr(out, "ERROR: AddressSanitizer: ");
    const char *ub = strstr(out, ": runtime error: ");
    if (!asan && !ub) return false;
    /* every assignment's student files, the names a frame or a path is
     * recognised by */
    const char *files[32];
    int n_files = 0;
    for (const cJSON *as = assignments ? assignments->child : NULL; as; as = as->next) {
        const cJSON *list = cJSON_GetObjectItemCaseSensitive(as, "student_files");
        for (const cJSON *sf = list ? list->child : NULL; sf && n_files < 32; sf = sf->next)
            if (cJSON_IsString(sf) && *sf->valuestring) files[n_files++] = sf->valuestring;
    }
    char kind[200] = "", access[120] = "", where[400] = "";
    if (asan) {
        sscanf(asan + 25, "%199[^ \n]", kind);
        const char *acc = strstr(asan, "\nREAD of size ");
        if (!acc) acc = strstr(asan, "\nWRITE of size ");
        if (acc) sscanf(acc + 1, "%119[^\n]", access);
        char *t = strstr(access, " at 0x");
        if (t) *t = '\0';
        /* the first frame in a student file: "#N 0x... in FUNC PATH/FILE:LINE" */
        for (const char *f = strstr(asan, "    #"); f && !*where; f = strstr(f + 1, "    #")) {
            const char *eol = strchr(f, '\n');
            const char *stop = eol ? eol : f + strlen(f), *in = strstr(f, " in ");
            for (int i = 0; i < n_files && in && in < stop && !*where; i++) {
                const char *hit = strstr(f, files[i]);
                if (!hit || hit >= stop) continue;
                const char *end = hit, *name = in + 4, *name_end = name;
                while (end < stop && *end != ' ')
                    end++;
                while (name_end < hit && *name_end != ' ')
                    name_end++;
                fmt(where, sizeof where, "in %.*s (%.*s)", (int)(name_end - name), name,
                    (int)(end - hit), hit);
            }
        }
        fmt(buf, size, "AddressSanitizer: %s%s%s%s%s", kind, *access ? ", a " : "", access,
            *where ? " " : "", where);
    } else {
        const char *line = ub;
        while (line > out && line[-1] != '\n')
            line--;
        const char *eol = strchr(ub, '\n');
        fmt(buf, size, "UndefinedBehaviorSanitizer: %.*s",
            (int)((eol ? eol : ub + strlen(ub)) - line), line);
    }
    /* the sandbox's paths mean nothing to the student: keep from the
     * assignment folder on */
    for (int i = 0; i < n_files; i++) {
        char *hit = strstr(buf, files[i]), *start = hit;
        while (start && start > buf && start[-1] != '(' && start[-1] != ' ')
            start--;
        if (hit && start < hit) memmove(start, hit, strlen(hit) + 1);
    }
    return true;
}

/* One sandboxed chunk of a test worker (tests/unit/ras_test_main.h, RAS_EACH_*):
 * names[first, last) of `bin`, each test in a forked child with `per_test`
 * seconds of processor time and `wall` on the clock, recording into the run's
 * own folder, which also gets the list; `own` is bound read-only too ("":
 * none), `extra` adds to the environment (at most 4). */
static void worker_job(const grader *g, job *w, const char *bin, const char *own,
                       const name_list *names, int chunk, int chunks, double per_test,
                       double wall, const char *const extra[]) {
    char each[5][4300];
    fmt(each[0], sizeof each[0], "RAS_EACH_NAMES=%s/runs/%d/names", g->work, g->runs);
    fmt(each[1], sizeof each[1], "RAS_EACH_OUT=%s/runs/%d", g->work, g->runs);
    fmt(each[2], sizeof each[2], "RAS_EACH_CALLS=%s/runs/%d", g->work, g->runs);
    fmt(each[3], sizeof each[3], "RAS_EACH_LIMIT=%.0f", per_test);
    fmt(each[4], sizeof each[4], "RAS_EACH_WALL=%.0f", wall);
    const char *env[12] = {each[0], each[1], each[2], each[3], each[4], "RAS_EACH_MODE=record",
                           "RAS_RECORD_CAP_MB=256"};
    for (int i = 0; extra && extra[i] && i < 4; i++)
        env[7 + i] = extra[i];
    fmt(w->extra_ro, sizeof w->extra_ro, "%s", own);
    /* the chunk's own backstop: every test at its wall-clock limit */
    int in_chunk = (names->n - chunk + chunks - 1) / chunks;
    int k = sandbox_job(g, w, in_chunk * (wall + 1) + 20, env);
    w->argv[k++] = (char *)bin;
    w->argv[k] = NULL;
    char list_path[4200];
    fmt(list_path, sizeof list_path, "%s/names", w->rw);
    FILE *lf = fopen(list_path, "w");
    for (int i = chunk; i < names->n && lf; i += chunks)
        fprintf(lf, "%s\n", names->v[i]);
    if (lf) fclose(lf);
}

/* grade --sanitize: the tests once more, on the student's code built with
 * AddressSanitizer and UBSan, only to say where memory or arithmetic goes
 * wrong: the verdicts stay the replay's. The finding is added to its test's
 * output (the first frame in a student file: function, file and line). */
static void sanitizer_pass(const grader *g, assignment_result *a, const cJSON *asg,
                           const name_list *names, int first_item) {
    char worker[4096];
    fmt(worker, sizeof worker, "%s/tests/test_%s_worker", g->sanitized, a->id);
    if (!g->sanitized || !file_exists(worker)) return;
    int n = names->n, chunks = g->jobs < n ? g->jobs : n;
    if (chunks < 1) return;
    job *jobs = calloc((size_t)chunks, sizeof *jobs);
    if (!jobs) abort();
    static const char *const sanitizers[] = {
        "ASAN_OPTIONS=detect_leaks=0:halt_on_error=1:abort_on_error=0",
        "UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1", NULL};
    for (int c = 0; c < chunks; c++) {
        job *w = &jobs[c];
        worker_job(g, w, worker, "", names, c, chunks, 3 * g->test_limit,
                   wall_backstop(3 * g->test_limit), sanitizers);
        w->env[0] = "RAS_SANDBOX_NO_AS=1"; /* ASan reserves terabytes of address space */
        w->env[1] = NULL;
        fmt(w->out_path, sizeof w->out_path, "%s/runs/sanitized-%s-%d.out", g->work, a->id, c);
    }
    run_jobs(jobs, chunks, g->jobs);
    (void)asg;
    const cJSON *files = cJSON_GetObjectItemCaseSensitive(g->rubric, "assignments");
    for (int i = 0; i < n; i++) {
        char path[4400], finding[800];
        fmt(path, sizeof path, "%s/%s.out", jobs[i % chunks].rw, names->v[i]);
        char *out = read_small_file(path, 64 * 1024);
        if (out && sanitizer_finding(out, files, finding, sizeof finding)) {
            char *shown = student_text(finding, 600);
            item *it = &a->items[first_item + i];
            sbuf o = {0};
            sb_printf(&o, "%s\n--- grade --sanitize (your code built with AddressSanitizer "
                          "and UBSan) ---\n%s",
                      it->output ? it->output : "", shown);
            free(it->output);
            it->output = o.s;
            free(shown);
        }
        free(out);
    }
    free(jobs);
}

/* What the sandbox reported for tests whose process never wrote a fate (the
 * whole worker died or was stopped) is the worker's own end; run between a
 * chunk's worker and its replay (job.between), in run_jobs' child. */
typedef struct chunk_fates {
    const name_list *names;
    int chunk, chunks;
    const char *xml_dir;
} chunk_fates;

static void worker_fates(const job *w, void *arg) {
    const chunk_fates *cf = arg;
    for (int i = cf->chunk; i < cf->names->n; i += cf->chunks) {
        char fate_path[4400], fate[200];
        fmt(fate_path, sizeof fate_path, "%s/%s.fate", w->rw, cf->names->v[i]);
        struct stat st;
        if (lstat(fate_path, &st) != 0) {
            fate_text(w->rr, w->limit, fate, sizeof fate);
            FILE *f = fopen(fate_path, "w");
            if (f) {
                fprintf(f, "(the whole test program) %s", fate);
                fclose(f);
            }
        }
        char xml_path[4400];
        fmt(xml_path, sizeof xml_path, "%s/%s.xml", cf->xml_dir, cf->names->v[i]);
        unlink(xml_path);
    }
}

/* An assignment's tests in flight: tests_prepare makes the jobs (a worker per
 * chunk, its replay chained after it), the caller runs them together with
 * the assignment's pictures (so a core a short chunk frees draws a picture),
 * tests_finish reads the verdicts. */
typedef struct test_batch {
    name_list names;
    char *listing;
    int n, chunks;
    job *workers, *replays;
    int *chunk_of;
    chunk_fates *fates;
    /* what the jobs' argv point to, so it lives as long as they do */
    char xml_dir[4096], own[4096], replay_bin[4096], worker_bin[4300];
} test_batch;

static bool tests_prepare(const grader *g, assignment_result *a, const char *dir, test_batch *b) {
    memset(b, 0, sizeof *b);
    char out_path[4096], *replay_bin = b->replay_bin, *worker_bin = b->worker_bin;
    char *xml_dir = b->xml_dir, *own = b->own;
    fmt(xml_dir, sizeof b->xml_dir, "%s/xml", dir);
    mkdirs(xml_dir);
    fmt(replay_bin, sizeof b->replay_bin, "%s/tests/test_%s_replay", g->build, a->id);
    fmt(worker_bin, sizeof b->worker_bin, "%s/tests/test_%s_worker", g->student_build, a->id);
    /* On its own code: the worker linked with the earlier references. It holds
     * reference code, so it is sealed: what it printed is not shown. */
    char own_worker[4200];
    if (own_dir(g, a->id, NULL, own, sizeof b->own)) {
        fmt(own_worker, sizeof own_worker, "%s/tests/test_%s_worker", own, a->id);
        if (file_exists(own_worker)) {
            fmt(worker_bin, sizeof b->worker_bin, "%s", own_worker);
            if (!a->note) {
                sbuf n = {0};
                sb_printf(&n, "graded on your %s code alone, with the reference of the earlier "
                              "assignments (what the test process printed is not shown; run "
                              "ctest to see it)",
                          a->id);
                a->note = n.s;
            }
        } else
            own[0] = '\0';
    }
    /* The list of tests comes from the trusted replay program, never from
     * the student's build. */
    fmt(out_path, sizeof out_path, "%s/list.txt", dir);
    char *list_argv[] = {replay_bin, NULL};
    const char *list_env[] = {"RAS_TEST_LIST=1", NULL};
    run_limited(list_argv, list_env, out_path, 30, g->mem_mb);
    char *listing = read_file(out_path, 1 << 20);
    if (!listing || strncmp(listing, "RAS_TEST_LIST\n", 14) != 0) {
        free(listing);
        free(a->note);
        a->note = xstrdup("grader error: the trusted test program could not list its tests");
        fprintf(stderr, "raster101-grade: %s could not list its tests (build it: cmake --build %s "
                        "--target test_%s_replay)\n",
                replay_bin, g->build, a->id);
        return false;
    }
    b->listing = listing;
    name_list *names = &b->names;
    for (char *line = strtok(listing + 14, "\n"); line; line = strtok(NULL, "\n"))
        if (*line) names_add(names, line);
    int n = names->n;
    /* The tests in `chunks` groups, one sandbox and one process each (a
     * forked child per test inside: tests/unit/ras_test_main.h, RAS_EACH_*),
     * dealt round-robin: the expensive tests (whole frames) come last in a
     * test program, and contiguous groups left one core idle while the other
     * drew them all. */
    int chunks = g->jobs < n ? g->jobs : n;
    if (chunks < 1) chunks = 1;
    job *workers = b->workers = calloc((size_t)chunks, sizeof *workers);
    job *replays = b->replays = calloc((size_t)chunks, sizeof *replays);
    int *chunk_of = b->chunk_of = calloc((size_t)n + 1, sizeof *chunk_of);
    chunk_fates *fates = b->fates = calloc((size_t)chunks, sizeof *fates);
    if (!workers || !replays || !chunk_of || !fates) abort();
    b->n = n;
    b->chunks = chunks;
    for (int c = 0; c < chunks; c++) {
        /* 1. the student's code, in the sandbox: each test records what each
         * call of the student's functions returned */
        job *w = &workers[c];
        int in_chunk = (n - c + chunks - 1) / chunks;
        worker_job(g, w, worker_bin, own, names, c, chunks, g->test_limit, test_wall(g), NULL);
        fmt(w->out_path, sizeof w->out_path, "%s/worker%d.out", xml_dir, c);
        for (int i = c; i < n; i += chunks)
            chunk_of[i] = c;
        /* 2. the verdicts: the same tests, trusted, on the recorded outputs
         * (the trusted copy of the list: the worker could rewrite its own) */
        job *r = &replays[c];
        fmt(r->store[0], sizeof r->store[0], "%s/names%d", xml_dir, c);
        FILE *lf = fopen(r->store[0], "w");
        for (int i = c; i < n; i += chunks)
            if (lf) fprintf(lf, "%s\n", names->v[i]);
        if (lf) fclose(lf);
        fmt(r->store[1], sizeof r->store[1], "RAS_EACH_NAMES=%s", r->store[0]);
        fmt(r->store[2], sizeof r->store[2], "RAS_EACH_OUT=%s", xml_dir);
        fmt(r->store[3], sizeof r->store[3], "RAS_EACH_CALLS=%s", w->rw);
        fmt(r->store[4], sizeof r->store[4], "RAS_EACH_LIMIT=%.0f", g->test_limit + 20);
        fmt(r->store[5], sizeof r->store[5], "RAS_EACH_WALL=%.0f", test_wall(g) + 20);
        r->env[0] = r->store[1];
        r->env[1] = r->store[2];
        r->env[2] = r->store[3];
        r->env[3] = r->store[4];
        r->env[4] = r->store[5];
        r->env[5] = "RAS_EACH_MODE=replay";
        r->env[6] = "CMOCKA_MESSAGE_OUTPUT=xml";
        r->env[7] = NULL;
        r->argv[0] = replay_bin;
        r->argv[1] = NULL;
        r->limit = in_chunk * (test_wall(g) + 21) + 20;
        r->mem_mb = g->mem_mb;
        fmt(r->out_path, sizeof r->out_path, "%s/replay%d.out", xml_dir, c);
        /* 3. each chunk's replay as soon as its own worker has ended */
        fates[c] = (chunk_fates){names, c, chunks, xml_dir};
        w->then = r;
        w->between = worker_fates;
        w->between_arg = &fates[c];
    }
    return true;
}

/* The verdicts of a batch whose jobs have run (b->workers[c].rr and the
 * replays' set); frees the batch. */
static void tests_finish(const grader *g, assignment_result *a, const cJSON *asg, test_batch *b) {
    const cJSON *tests = cJSON_GetObjectItemCaseSensitive(asg, "tests");
    const char *crash_hint = str_or(asg, "crash_hint", "look for an out-of-bounds access");
    const char *xml_dir = b->xml_dir, *own = b->own;
    const name_list names = b->names;
    int n = b->n;
    const job *workers = b->workers;
    const int *chunk_of = b->chunk_of;
    double t_judge = now_s();
    for (int i = 0; i < n; i++) {
        const char *name = names.v[i];
        item *it = add_item(a);
        it->name = xstrdup(name);
        it->max_score = test_points(g, tests, name, &it->default_weight);
        const char *rw = workers[chunk_of[i]].rw;
        char path[4400], fate[200], rfate[200];
        fmt(path, sizeof path, "%s/%s.fate", rw, name);
        read_small(path, fate, sizeof fate);
        fmt(path, sizeof path, "%s/%s.fate", xml_dir, name);
        read_small(path, rfate, sizeof rfate);
        run_result wr = fate_parse(fate), rr = fate_parse(rfate);
        if (!*rfate) rr = (run_result){RUN_NOT_STARTED, 0, 0};
        fmt(path, sizeof path, "%s/%s.out", xml_dir, name);
        char *raw = read_file(path, 64 * 1024);
        char *clean = without_work_path(g->work, clean_output(raw ? raw : ""));
        bool xml_failure = false;
        fmt(path, sizeof path, "%s/%s.xml", xml_dir, name);
        char *cases = rr.kind == RUN_EXITED ? cmocka_testcases(path, &xml_failure) : NULL;
        /* cmocka's XML mode puts assertion texts only into the XML: add them */
        const char *cdata = cases ? strstr(cases, "<failure><![CDATA[") : NULL;
        if (cdata) {
            cdata += strlen("<failure><![CDATA[");
            const char *end = strstr(cdata, "]]>");
            size_t len = end ? (size_t)(end - cdata) : 0;
            char *msg = malloc(len + 1);
            if (!msg) abort();
            memcpy(msg, cdata, len);
            msg[len] = '\0';
            char *first_nl = strchr(msg, '\n');
            if (first_nl) *first_nl = '\0';
            if (len && !strstr(clean, msg) && !strstr(msg, "error: Failure!")) {
                sbuf c = {0};
                sb_printf(&c, "%s%s%.*s", clean, *clean ? "\n" : "", (int)len, cdata);
                free(clean);
                clean = c.s;
            }
            free(msg);
        }
        /* A failure because the worker died is charged to the way it died. */
        run_result verdict = rr;
        bool worker_died = wr.kind == RUN_TIMEOUT || wr.kind == RUN_SIGNALED ||
                           (wr.kind == RUN_EXITED && wr.code > 128 && wr.code < 160);
        if (rr.kind == RUN_EXITED && rr.code != 0 && worker_died) {
            verdict = wr;
            if (wr.kind == RUN_EXITED) verdict = (run_result){RUN_SIGNALED, wr.code - 128, 0};
        } else if (rr.kind != RUN_EXITED) {
            free(clean);
            clean = xstrdup("grader error: the trusted replay of this test did not finish; "
                            "tell your instructor");
            verdict = (run_result){RUN_EXITED, 1, 0};
        }
        /* a test may name its own likely crash (rubric "crash_hints"): a crash
         * says more there than the assignment's generic hint */
        const char *own_crash =
            str_or(cJSON_GetObjectItemCaseSensitive(asg, "crash_hints"), name, crash_hint);
        judge_test(it, verdict, xml_failure, clean, g->test_limit, test_wall(g), own_crash);
        if (own[0] && !it->passed) {
            /* a crash's hint is the rubric's (crash_hints), said before the
             * replay's generic "did not return" */
            char crash_line[1200];
            const char *said = clean;
            if (it->status && !strcmp(it->status, "CRASH")) {
                fmt(crash_line, sizeof crash_line, "Likely mistake: %s", own_crash);
                said = crash_line;
            }
            char *sealed = sealed_text(it->status, said);
            free(it->output);
            it->output = sealed;
            free(it->reason);
            it->reason = reason_line(sealed);
        }
        /* What the student's code printed: theirs, shown as such, capped. */
        fmt(path, sizeof path, "%s/%s.out", rw, name);
        char *wraw = read_small_file(path, 4096);
        char *wclean = wraw && !own[0] ? without_work_path(g->work, clean_output(wraw)) : NULL;
        if (wclean && *wclean) {
            char *shown = student_text(wclean, 1500);
            sbuf o = {0};
            sb_printf(&o, "%s\n--- what the test process printed (your code runs there) ---\n%s",
                      it->output, shown);
            free(it->output);
            it->output = o.s;
            free(shown);
        }
        free(wclean);
        free(wraw);
        if (own[0] && !it->passed) {
            /* sealed: the replay's own XML and console text quote the values
             * returned; the student's folder keeps neither */
            junit_case(it, a->id, NULL);
            fmt(path, sizeof path, "%s/%s.out", xml_dir, name);
            unlink(path);
            fmt(path, sizeof path, "%s/%s.xml", xml_dir, name);
            unlink(path);
        } else {
            junit_case(it, a->id, cases);
        }
        free(cases);
        free(raw);
        free(clean);
    }
    free(b->workers);
    free(b->replays);
    free(b->chunk_of);
    free(b->fates);
    profile("tests: verdicts", a->id, t_judge);
    if (g->sanitized) sanitizer_pass(g, a, asg, &names, a->n_items - n);
    for (const cJSON *t = tests ? tests->child : NULL; t; t = t->next) {
        if (names_has(&names, t->string)) continue;
        item *it = add_item(a);
        it->name = xstrdup(t->string);
        it->counted = false;
        it->max_score = cJSON_IsNumber(t) ? t->valuedouble : g->default_points;
        it->status = xstrdup("MISSING");
        it->output = xstrdup("the rubric names this test but the test program has none by that "
                             "name (not counted; update tests/grading/rubric.json)");
        it->reason = xstrdup("not in the test program (rubric out of date; not counted)");
        junit_case(it, a->id, NULL);
    }
    names_free(&b->names);
    free(b->listing);
}

/* ------------------------------------------------------------- the images */

/* Vertical mirror, to recognise a missing y-flip. */
static ras_image *flip_rows(const ras_image *img) {
    ras_image *f = ras_image_clone(img);
    if (!f) return NULL;
    for (int r = 0; r < img->height; r++)
        for (int c = 0; c < img->width; c++)
            ras_image_set(f, c, img->height - 1 - r, ras_image_get(img, c, r));
    return f;
}

static double mean_luma(const ras_image *img) {
    double s = 0;
    long n = (long)img->width * img->height;
    for (long i = 0; i < n; i++)
        s += 0.299 * img->pixels[i].x + 0.587 * img->pixels[i].y + 0.114 * img->pixels[i].z;
    return n ? s / (double)n : 0;
}

static bool is_flat(const ras_image *img) {
    long n = (long)img->width * img->height;
    for (long i = 1; i < n; i++)
        if (ras_unit_to_byte(img->pixels[i].x) != ras_unit_to_byte(img->pixels[0].x) ||
            ras_unit_to_byte(img->pixels[i].y) != ras_unit_to_byte(img->pixels[0].y) ||
            ras_unit_to_byte(img->pixels[i].z) != ras_unit_to_byte(img->pixels[0].z))
            return false;
    return true;
}

/* Bounding box of the pixels that differ from the top-left (background)
 * pixel; false when there are none. */
static bool content_box(const ras_image *img, int *x0, int *y0, int *x1, int *y1) {
    vec3s bg = ras_image_get(img, 0, 0);
    *x0 = img->width, *y0 = img->height, *x1 = -1, *y1 = -1;
    for (int r = 0; r < img->height; r++)
        for (int c = 0; c < img->width; c++) {
            vec3s p = ras_image_get(img, c, r);
            if (ras_unit_to_byte(p.x) == ras_unit_to_byte(bg.x) &&
                ras_unit_to_byte(p.y) == ras_unit_to_byte(bg.y) &&
                ras_unit_to_byte(p.z) == ras_unit_to_byte(bg.z))
                continue;
            if (c < *x0) *x0 = c;
            if (c > *x1) *x1 = c;
            if (r < *y0) *y0 = r;
            if (r > *y1) *y1 = r;
        }
    return *x1 >= 0;
}

/* What the buffers say about a picture (buffer_evidence), in pipeline order
 * (DESIGN.md): vertices -> coverage -> depth -> overdraw -> interpolated
 * attributes -> per-sample colour -> resolved colour. */
typedef struct evidence {
    bool ran;          /* both frames were dumped and compared */
    char stage[24];    /* the first buffer that differs; "colour": every buffer
                        * matches and only the colours differ */
    const char *owner; /* the assignment whose code makes that stage */
    bool rasterizer;   /* the stage is the rasterizer's or the resolve's */
    bool blank;        /* the student's frame covered no sample */
    char why_blank[400];
} evidence;

/* Likely-mistake lines recognised from the pictures themselves. */
/* Does the image's command line contain `word` (e.g. "msaa")? */
static bool args_have(const cJSON *args, const char *word) {
    for (const cJSON *v = args ? args->child : NULL; v; v = v->next)
        if (cJSON_IsString(v) && strstr(v->valuestring, word)) return true;
    return false;
}

/* Signatures of classic mistakes; a cause is named only where the picture
 * can have it (seams need anti-aliasing, doubled ambient needs lighting). */
/* `ev`: what the buffers said (geometry signatures only where the geometry
 * differs or nothing is known); `raster_causes`: the rasterizer and resolve
 * are the student's and the buffers do not acquit them. */
static void image_signatures(sbuf *o, const ras_image *expected, const ras_image *got,
                             const ras_compare_options *opt, const cJSON *args,
                             const evidence *ev, bool raster_causes) {
    if (is_flat(got) && !is_flat(expected)) return; /* "nothing was drawn" says it */
    bool geometry = !ev->ran || !strcmp(ev->stage, "vertices") ||
                    !strcmp(ev->stage, "coverage") || !strcmp(ev->stage, "depth");
    ras_image *flipped = geometry ? flip_rows(got) : NULL;
    ras_compare_result fr;
    ras_error err;
    if (flipped && ras_compare_images(expected, flipped, opt, &fr, &err) && fr.pass)
        sb_add(o, "likely mistake: your image is the reference upside down: the y-flip is "
                  "missing (image row = height - 1 - y) or the projection flips y\n");
    ras_image_destroy(flipped);
    int ex0, ey0, ex1, ey1, gx0, gy0, gx1, gy1;
    if (geometry && content_box(expected, &ex0, &ey0, &ex1, &ey1) &&
        content_box(got, &gx0, &gy0, &gx1, &gy1)) {
        double cx = (gx0 + gx1 - ex0 - ex1) / 2.0, cy = (gy0 + gy1 - ey0 - ey1) / 2.0;
        double sx = (gx1 - gx0 + 1.0) / (ex1 - ex0 + 1.0),
               sy = (gy1 - gy0 + 1.0) / (ey1 - ey0 + 1.0);
        double cxe = (ex0 + ex1) / 2.0, cye = (ey0 + ey1) / 2.0;
        double ccx = expected->width / 2.0, ccy = expected->height / 2.0;
        /* same centre of projection, different size: the field of view */
        double scale = (sx + sy) / 2;
        if (fabs(sx - sy) < 0.05 && fabs(scale - 1) > 0.05 &&
            fabs((cxe - ccx) * scale - (cxe + cx - ccx)) < 4 &&
            fabs((cye - ccy) * scale - (cye + cy - ccy)) < 4)
            sb_printf(o,
                      "likely mistake: your picture is the reference scaled by %.2f about the "
                      "image centre: the field of view is off (the whole fov used instead of "
                      "half of it, or degrees given to tanf)\n",
                      scale);
        else if (fabs(sx - 1) > 0.05 && fabs(sy - 1) < 0.05)
            sb_printf(o,
                      "likely mistake: your picture is stretched horizontally by %.2f: the "
                      "aspect ratio is applied to the wrong axis\n",
                      sx);
    }
    double le = mean_luma(expected), lg = mean_luma(got);
    bool aa = args_have(args, "msaa") || args_have(args, "ssaa");
    bool lit = args_have(args, "phong") || args_have(args, "texture") ||
               args_have(args, "displacement");
    if (le > 0.02 && lg < 0.97 * le)
        sb_printf(o, "note: your image is darker than the reference on average (mean luma %.4f "
                     "vs %.4f)%s\n",
                  lg, le,
                  aa && raster_causes
                      ? ": dark edges or seams? (resolve in floating point, colour per sample)"
                      : "");
    else if (le > 0.02 && lg > 1.03 * le)
        sb_printf(o, "note: your image is brighter than the reference on average (mean luma "
                     "%.4f vs %.4f)%s\n",
                  lg, le,
                  lit && (!ev->ran || !ev->owner || !strcmp(ev->owner, "hw3"))
                      ? ": light added twice (ambient once per light?)"
                      : "");
}

/* Defects a person sees at once but a global pixel budget can hide: a dark
 * seam, a line of wrong pixels, speckle. Each is a pattern of "bad" pixels
 * (some channel off by more than BAD_BYTES) that a correct image never has,
 * whatever its float style: a seam pixel is darker than everything around it
 * in the reference, speckle sits inside a smooth area of the reference, a
 * line is a row or column whose neighbours match. Appends one "likely
 * mistake" line per defect found; returns whether any was. */
enum { BAD_BYTES = 48, SEAM_MIN = 20, SPECKLE_MIN = 12, LINE_MIN = 24 };

static int byte_diff(vec3s a, vec3s b) {
    int d = 0;
    for (int k = 0; k < 3; k++) {
        int e = abs(ras_unit_to_byte(a.raw[k]) - ras_unit_to_byte(b.raw[k]));
        if (e > d) d = e;
    }
    return d;
}

static double luma(vec3s p) { return 0.299 * p.x + 0.587 * p.y + 0.114 * p.z; }

/* `causes`: name the rasterizer or resolve mistakes that make each defect;
 * false where the buffers acquit those stages (the pattern only). */
static bool image_defects(sbuf *o, const ras_image *expected, const ras_image *got, bool causes) {
    int w = expected->width, h = expected->height;
    if (got->width != w || got->height != h || w < 3 || h < 3) return false;
    unsigned char *bad = calloc((size_t)w * h, 1);
    int *row_bad = calloc((size_t)h, sizeof *row_bad), *col_bad = calloc((size_t)w, sizeof *col_bad);
    if (!bad || !row_bad || !col_bad) abort();
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            if (byte_diff(ras_image_get(expected, x, y), ras_image_get(got, x, y)) > BAD_BYTES) {
                bad[(size_t)y * w + x] = 1;
                row_bad[y]++;
                col_bad[x]++;
            }
    int seams = 0, speckles = 0, sx = -1, sy = -1, px = -1, py = -1;
    for (int y = 1; y < h - 1; y++)
        for (int x = 1; x < w - 1; x++) {
            if (!bad[(size_t)y * w + x]) continue;
            double lo = 1e9, hi = -1e9;
            int bad_around = 0;
            vec3s e0 = ras_image_get(expected, x, y);
            int spread = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    vec3s e = ras_image_get(expected, x + dx, y + dy);
                    double l = luma(e);
                    lo = l < lo ? l : lo;
                    hi = l > hi ? l : hi;
                    int d = byte_diff(e, e0);
                    spread = d > spread ? d : spread;
                    bad_around += (dx || dy) && bad[(size_t)(y + dy) * w + x + dx];
                }
            double lg = luma(ras_image_get(got, x, y));
            /* where two drawn surfaces meet (not against the background),
             * darker than both */
            if (lo > 0.05 && hi - lo > 0.02 && lg < lo - 0.15) {
                if (seams++ == 0) sx = x, sy = y;
            } else if (spread <= 24 && bad_around <= 2) {
                if (speckles++ == 0) px = x, py = y;
            }
        }
    bool found = false;
    if (seams >= SEAM_MIN) {
        sb_printf(o, "%sa dark seam: %d pixels where two surfaces meet are darker than both in "
                     "the reference (first at (%d,%d))%s\n",
                  causes ? "likely mistake: " : "the picture shows ", seams, sx, sy,
                  causes ? ": the background shows through a shared edge (a coverage rule that "
                           "drops edge samples, or a resolve that mixes in uncovered or "
                           "integer-rounded samples)"
                         : "");
        found = true;
    }
    if (speckles >= SPECKLE_MIN) {
        sb_printf(o, "%sspeckle: %d isolated pixels inside smooth areas are wrong (first at "
                     "(%d,%d))%s\n",
                  causes ? "likely mistake: " : "the picture shows ", speckles, px, py,
                  causes ? ": back faces winning the depth test (depth or barycentric precision: "
                           "subtract a vertex before the edge functions; perspective-correct "
                           "depth) or a NaN in some pixels"
                         : "");
        found = true;
    }
    for (int pass = 0; pass < 2; pass++) {
        const int *line = pass ? col_bad : row_bad;
        int n = pass ? w : h;
        for (int i = 0; i < n; i++) {
            int beside = 0;
            if (i > 0 && line[i - 1] > beside) beside = line[i - 1];
            if (i < n - 1 && line[i + 1] > beside) beside = line[i + 1];
            if (line[i] >= LINE_MIN && line[i] >= 4 * (beside + 1)) {
                sb_printf(o, "%s%s %d of the image is wrong along %d pixels while the %ss "
                             "beside it match%s%s%s\n",
                          causes ? "likely mistake: " : "the picture shows: ",
                          pass ? "column" : "row", i, line[i], pass ? "column" : "row",
                          causes ? ": a " : "", causes ? (pass ? "column" : "row") : "",
                          causes ? " skipped or written twice (a loop bound, < against <=, or an "
                                   "index off by one)"
                                 : "");
                found = true;
                break;
            }
        }
    }
    free(bad);
    free(row_bad);
    free(col_bad);
    return found;
}

/* Reads the image a student's program wrote, refusing before any decoding
 * what is not a regular PNG file of the reference's size: a symlink, a FIFO,
 * a huge file or a decompression bomb costs nothing. */
static ras_image *load_student_image(const char *path, const char *ref_path, ras_error *err) {
    unsigned char head[24], rhead[24];
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    struct stat st;
    if (fd < 0) return ras_error_set(err, "no file at -o (%s)", strerror(errno)), NULL;
    bool regular = fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
    ssize_t got = regular ? read(fd, head, sizeof head) : -1;
    close(fd);
    if (!regular) return ras_error_set(err, "the output is not a regular file"), NULL;
    if (st.st_size > (64 << 20))
        return ras_error_set(err, "the output is %lld bytes, over the 64 MiB a PNG of this size "
                                  "needs",
                             (long long)st.st_size),
               NULL;
    FILE *rf = fopen(ref_path, "rb");
    size_t rgot = rf ? fread(rhead, 1, sizeof rhead, rf) : 0;
    if (rf) fclose(rf);
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (got != (ssize_t)sizeof head || memcmp(head, sig, 8) != 0 || memcmp(head + 12, "IHDR", 4))
        return ras_error_set(err, "the output is not a PNG file"), NULL;
    if (rgot == sizeof rhead && memcmp(head + 16, rhead + 16, 8) != 0) {
        unsigned w = (unsigned)head[16] << 24 | head[17] << 16 | head[18] << 8 | head[19];
        unsigned h = (unsigned)head[20] << 24 | head[21] << 16 | head[22] << 8 | head[23];
        unsigned rw = (unsigned)rhead[16] << 24 | rhead[17] << 16 | rhead[18] << 8 | rhead[19];
        unsigned rh = (unsigned)rhead[20] << 24 | rhead[21] << 16 | rhead[22] << 8 | rhead[23];
        return ras_error_set(err, "expected a %ux%u image like the reference, got %ux%u (not "
                                  "decoded)",
                             rw, rh, w, h),
               NULL;
    }
    return ras_image_load(path, err);
}

/* The sandboxed run of an image's program: -o into its own run folder. */
/* `bin_dir` holds the program: the student's build (the whole chain) or an
 * own-code link (then also bound read-only); `tag` names the log. */
static void image_job(const grader *g, const cJSON *img, const char *dir, job *j,
                      const char *own, const char *tag) {
    const cJSON *args = j->args;
    fmt(j->extra_ro, sizeof j->extra_ro, "%s", own ? own : "");
    int n = sandbox_job(g, j, g->render_limit, NULL); /* processor seconds (--cpu-s) */
    j->limit = wall_backstop(g->render_limit);        /* the clock: a backstop */
    fmt(j->store[14], sizeof j->store[14], "%s/bin/%s", own ? own : g->student_build,
        str_or(img, "program", ""));
    j->argv[n++] = j->store[14];
    for (const cJSON *v = args ? args->child : NULL; v && n < 110; v = v->next)
        if (cJSON_IsString(v)) j->argv[n++] = v->valuestring;
    j->argv[n++] = "-o";
    fmt(j->store[15], sizeof j->store[15], "%s/out.png", j->rw);
    j->argv[n++] = j->store[15];
    j->argv[n] = NULL;
    fmt(j->out_path, sizeof j->out_path, "%s/%s%s.log", dir, str_or(img, "name", "image"), tag);
}

/* The comparison the rubric asks of an image; false for an unknown metric. */
/* The rubric names a comparison; its thresholds live only in the
 * catalogue's table (tests/reference/catalogue.json, common/app/ras_catalogue.h),
 * which the students' --compare and raster101-compare read too. */
static bool image_options(const grader *g, const cJSON *img, ras_compare_kind *kind,
                          ras_compare_options *opt, ras_error *err) {
    static ras_catalogue cat;
    static int state; /* 0 not read, 1 read, -1 failed */
    static ras_error failure;
    if (!state) {
        char path[4200];
        fmt(path, sizeof path, "%s/tests/reference/catalogue.json", g->source);
        state = ras_catalogue_load(path, &cat, &failure) ? 1 : -1;
    }
    if (state < 0) return *err = failure, false;
    if (!ras_catalogue_comparison_options(&cat, str_or(img, "comparison", ""), opt, err))
        return false;
    *kind = opt->kind;
    return true;
}

/* The trusted reference program, outside the sandbox: `args` as drawn for
 * this grading, -o out_png, and --dump dump_dir unless NULL. */
static run_result reference_render(const grader *g, const char *program, const cJSON *args,
                                   const char *out_png, const char *dump_dir, const char *log) {
    char *argv[120] = {(char *)program};
    int n = 1;
    for (const cJSON *v = args ? args->child : NULL; v && n < 110; v = v->next)
        if (cJSON_IsString(v)) argv[n++] = v->valuestring;
    argv[n++] = "-o";
    argv[n++] = (char *)out_png;
    if (dump_dir) {
        argv[n++] = "--dump";
        argv[n++] = (char *)dump_dir;
    }
    argv[n] = NULL;
    return run_limited(argv, NULL, log, g->render_limit, g->mem_mb);
}

/* What a buffer's first difference most likely means, by buffer and
 * pattern; "" when nothing specific can be said. */
static const char *buffer_hint(const char *name, const ras_dump_difference *d) {
    const char *pattern = d->pattern;
    bool speckle = !strcmp(pattern, "in speckles"), line = !strncmp(pattern, "along", 5),
         one = !strcmp(pattern, "where only one drew");
    if (!strcmp(name, "depth")) {
        if (speckle)
            return "back faces winning the depth test in scattered pixels: depth or barycentric "
                   "precision (docs/hw2.md: subtract a vertex before the edge functions, "
                   "interpolate v[i].z with the screen barycentrics)";
        if (line) return "a row or column of samples skipped or written twice: the loop bounds";
        if (one)
            return "pixels drawn in one frame and not the other: coverage (the bounding box, "
                   "the inside test, the top-left rule) or the depth test's direction";
        if (d->larger * 10 >= d->pixels_differ * 9)
            return "your depth buffer keeps the FARTHER surface where triangles overlap: the "
                   "depth comparison is reversed (smaller is closer; the buffer starts at +INF)";
        return "depths interpolated differently: v[i].z with the screen barycentrics, nothing "
               "else (not the course's w_reciprocal snippet), or a reversed depth test";
    }
    if (!strcmp(name, "coverage"))
        return line ? "a row or column of samples skipped: the loop bounds"
                    : "samples covered differently: sample positions from ctx->pattern, the "
                      "top-left rule on shared edges";
    if (!strcmp(name, "overdraw"))
        return "fragments shaded a different number of times: shading once per pixel with MSAA, "
               "per sample with SSAA; the depth test before shading";
    if (!strcmp(name, "normal"))
        return "the normals the shader got: interpolate with perspective-correct weights, then "
               "normalise";
    if (!strcmp(name, "uv"))
        return "the texture coordinates the shader got: perspective-correct interpolation (the "
               "1/w weights), not affine";
    if (!strcmp(name, "sample_colour"))
        return "the colours stored per sample: each covered sample that passes the depth test "
               "gets the fragment's colour, the others keep theirs (one colour per pixel "
               "scaled by coverage gives dark seams)";
    if (!strcmp(name, "view_depth"))
        return "the view-space positions: perspective-correct interpolation of view_pos";
    return "";
}

/* Which assignment's code makes `stage` in a run of `program`. `ref_raster`:
 * the run's rasterizer and resolve are the reference (hw3 graded on its own
 * code), so what they produce differently comes from what hw3 feeds them. */
static const char *stage_owner(const char *stage, const char *program, bool ref_raster) {
    bool hw3 = !strncmp(program, "hw3", 3);
    if (!strcmp(stage, "vertices")) return "hw1";
    if (!strcmp(stage, "normal") || !strcmp(stage, "uv") || !strcmp(stage, "view_depth"))
        return "hw3";
    if (!strcmp(stage, "sample_colour") || !strcmp(stage, "colour"))
        return hw3 ? "hw3" : "hw2"; /* the shader's colours; hw2's are the triangles' */
    return ref_raster ? "hw3" : "hw2";
}

/* Why a frame is blank, from the --stats counters it printed (the pipeline
 * counts triangles itself; the student's rasterizer counts samples). */
static void blank_reason(const char *log, char *buf, size_t size) {
    const char *c = log ? strstr(log, "\"triangles_in\"") : NULL;
    unsigned long long in = 0, away = 0, raster = 0, covered = 0, passed = 0;
    buf[0] = '\0';
    if (!c) return;
    const char *q;
    if ((q = strstr(c, "\"triangles_in\":"))) sscanf(q + 15, "%llu", &in);
    if ((q = strstr(c, "\"triangles_clipped_away\":"))) sscanf(q + 25, "%llu", &away);
    if ((q = strstr(c, "\"triangles_rasterized\":"))) sscanf(q + 23, "%llu", &raster);
    if ((q = strstr(c, "\"samples_covered\":"))) sscanf(q + 18, "%llu", &covered);
    if ((q = strstr(c, "\"depth_tests_passed\":"))) sscanf(q + 21, "%llu", &passed);
    if (in > 0 && away == in)
        fmt(buf, size, "no triangle reached the rasterizer: all %llu were clipped away (outside "
                       "the view volume: the projection's n and f signs, or a camera looking away)",
            in);
    else if (raster == 0 && in > 0)
        fmt(buf, size, "no triangle reached the rasterizer (%llu in, %llu clipped away, none "
                       "rasterized: degenerate or non-finite after the vertex stage)",
            in, away);
    else if (covered > 0 && passed == 0)
        fmt(buf, size, "%llu samples were covered but none passed the depth test: the "
                       "comparison never holds (reversed, or against a buffer not cleared to "
                       "+INF)",
            covered);
    else if (raster > 0 && covered == 0)
        fmt(buf, size, "%llu triangles reached your rasterizer and it covered no sample: the "
                       "inside test or the bounding-box loop",
            raster);
}

/* Evidence for a picture (docs/grading.md, "Buffers"): the program renders
 * it again with --dump, in the sandbox, and the trusted reference program
 * with --dump; the first buffer in pipeline order that differs (with its
 * kind's tolerance) is named, with the stage's likely cause and owner.
 * Sealed runs give the words only; others also the buffer's pictures
 * (redrawn here from the exact files, never the sandbox's own pictures).
 * Programs without --dump add nothing (ev->ran stays false). */
static void buffer_evidence(const grader *g, item *it, sbuf *o, const cJSON *img, const char *dir,
                            const char *reldir, const job *graded, const char *own,
                            bool ref_raster, evidence *ev) {
    const char *name = str_or(img, "name", "image");
    const char *program = str_or(img, "program", "");
    memset(ev, 0, sizeof *ev);
    char ref_prog[4200], ref_dir[4300], log[4400];
    const char *rp = str_or(img, "reference_program", NULL);
    if (rp)
        fmt(ref_prog, sizeof ref_prog, "%s/bin/%s", g->build, rp);
    else
        fmt(ref_prog, sizeof ref_prog, "%s/bin/%s_ref", g->build, program);
    if (!file_exists(ref_prog)) return;
    fmt(ref_dir, sizeof ref_dir, "%s/%s%s.buffers-reference", dir, name, own ? ".own" : "");
    mkdirs(ref_dir);
    char ref_png[4400];
    fmt(ref_png, sizeof ref_png, "%s/frame.png", ref_dir);
    fmt(log, sizeof log, "%s/log.txt", ref_dir);
    run_result rr = reference_render(g, ref_prog, graded->args, ref_png, ref_dir, log);
    if (rr.kind != RUN_EXITED || rr.code != 0) return; /* no --dump here */
    /* the student's run, as the graded one but with --dump and --stats */
    job dj;
    memset(&dj, 0, sizeof dj);
    dj.args = graded->args;
    image_job(g, img, dir, &dj, own, own ? ".own-dump" : ".dump");
    int k = 0;
    while (dj.argv[k])
        k++;
    fmt(dj.store[13], sizeof dj.store[13], "%s/dump", dj.rw);
    dj.argv[k++] = "--dump";
    dj.argv[k++] = dj.store[13];
    dj.argv[k++] = "--stats";
    dj.argv[k] = NULL;
    run_jobs(&dj, 1, 1);
    if (dj.rr.kind != RUN_EXITED || dj.rr.code != 0) {
        sb_printf(o, "buffers: your program's --dump run %s, so its buffers cannot be compared\n",
                  dj.rr.kind == RUN_TIMEOUT ? "timed out" : "failed");
        return;
    }
    ev->ran = true;
    /* why a blank frame is blank, from the counters of this run (used only
     * when the picture is one flat colour) */
    char *dlog = read_file(dj.out_path, 64 * 1024);
    blank_reason(dlog, ev->why_blank, sizeof ev->why_blank);
    free(dlog);
    /* blank: the depth buffer holds no sample */
    char dpfm[4400];
    fmt(dpfm, sizeof dpfm, "%s/depth.pfm", dj.store[13]);
    if (file_exists(dpfm)) {
        ras_error derr = {{0}};
        int dw = 0, dh = 0, dc = 0;
        float *depth = ras_dump_read_pfm(dpfm, &dw, &dh, &dc, &derr);
        if (depth) {
            bool any = false;
            for (long i = 0; i < (long)dw * dh * dc && !any; i++)
                any = !(isinf(depth[i]) && depth[i] > 0);
            free(depth);
            if (!any) ev->blank = true;
        }
    }
    /* hw1's frame: its vertices, step by step */
    char rv[4400], gv[4400];
    fmt(rv, sizeof rv, "%s/vertices.json", ref_dir);
    fmt(gv, sizeof gv, "%s/vertices.json", dj.store[13]);
    if (file_exists(rv) && file_exists(gv)) {
        char line[600];
        int r = ras_dump_compare_vertices(rv, gv, line, sizeof line);
        if (r > 0) {
            char *shown = student_text(line, 580);
            sb_printf(o, "buffers: the first that differs is the vertex stage (hw1): %s\n", shown);
            free(shown);
            fmt(ev->stage, sizeof ev->stage, "vertices");
            ev->owner = "hw1";
            return;
        }
    }
    for (int b = 0; ras_dump_buffer_names[b]; b++) {
        const char *buf = ras_dump_buffer_names[b];
        char rf[4400], gf[4400];
        fmt(rf, sizeof rf, "%s/%s.pfm", ref_dir, buf);
        fmt(gf, sizeof gf, "%s/%s.pfm", dj.store[13], buf);
        bool in_ref = file_exists(rf), in_got = file_exists(gf);
        if (!in_ref && !in_got) continue;
        const char *stage = buf;
        if (in_ref != in_got) {
            fmt(ev->stage, sizeof ev->stage, "%s", stage);
            ev->owner = stage_owner(stage, program, ref_raster);
            ev->rasterizer = !ref_raster && strcmp(ev->owner, "hw3");
            sb_printf(o, "buffers: the first that differs is %s (%s's stage): %s\n", buf,
                      ev->owner,
                      in_ref ? "your program wrote none (its frame made no such buffer)"
                             : "the reference's frame makes no such buffer");
            return;
        }
        ras_dump_difference d;
        ras_error err = {{0}};
        if (!ras_dump_compare(ref_dir, dj.store[13], buf, &d, &err)) {
            char *shown = student_text(err.msg, 300);
            sb_printf(o, "buffers: %s could not be compared: %s\n", buf, shown);
            free(shown);
            return;
        }
        if (d.pixels_differ == 0) continue;
        /* at 1x there is no coverage file: depth drawn in one frame only is
         * the coverage */
        if (!strcmp(buf, "depth") && d.drawn_in_one * 2 > d.pixels_differ) stage = "coverage";
        fmt(ev->stage, sizeof ev->stage, "%s", stage);
        ev->owner = stage_owner(stage, program, ref_raster);
        ev->rasterizer = !ref_raster && !strcmp(ev->owner, "hw2");
        char line[600];
        ras_dump_difference_text(buf, &d, line, sizeof line);
        const char *hint = ref_raster && !strcmp(ev->owner, "hw3") &&
                                   (!strcmp(stage, "coverage") || !strcmp(stage, "depth") ||
                                    !strcmp(stage, "overdraw"))
                               ? "the rasterizer here is the reference's, so your hw3 code "
                                 "hands it different triangles or depths"
                               : buffer_hint(buf, &d);
        sb_printf(o, "buffers: the first that differs is %s (%s's stage)%s%s\n", line, ev->owner,
                  *hint ? "; likely: " : "", hint);
        if (own) return; /* sealed: words only */
        /* the pictures, redrawn from the exact files */
        char out_dir[4400];
        fmt(out_dir, sizeof out_dir, "%s/%s.buffers/%s", dir, name, buf);
        mkdirs(out_dir);
        if (ras_dump_compare_pictures(ref_dir, dj.store[13], buf, out_dir, &err)) {
            char rel[4600];
            it->buf_name = xstrdup(buf);
            fmt(rel, sizeof rel, "%s/%s.buffers/%s/reference.png", reldir, name, buf);
            it->buf_ref = xstrdup(rel);
            fmt(rel, sizeof rel, "%s/%s.buffers/%s/yours.png", reldir, name, buf);
            it->buf_got = xstrdup(rel);
            fmt(rel, sizeof rel, "%s/%s.buffers/%s/difference.png", reldir, name, buf);
            it->buf_diff = xstrdup(rel);
        }
        return;
    }
    fmt(ev->stage, sizeof ev->stage, "colour");
    ev->owner = stage_owner("colour", program, ref_raster);
    ev->rasterizer = !ref_raster && !strcmp(ev->owner, "hw2"); /* the resolve */
    sb_printf(o, "buffers: every buffer matches the reference's: the difference is in the "
                 "colours %s computed\n",
              !strcmp(ev->owner, "hw3") ? "your shader" : "your rasterizer wrote");
}

/* Where a variant's reference, rendered at grading time, is kept: in the
 * work folder (never handed out), named by the assignment that owns the
 * image (`id`, not the integration part grading it again) so the whole-chain
 * run and the attribution compare with the picture the own-code run just
 * rendered with the same arguments — and never with one a previous grading
 * left in a reused work folder (--reuse-build). */
static void variant_reference_path(const grader *g, const char *dir, const char *id,
                                   const char *name, char *buf, size_t size) {
    fmt(buf, size, "%s/%s-%s.expected.png", g->work ? g->work : dir, id, name);
}

/* Grades one image run (image_job). `sealed`: the program held reference
 * code (an own-code link), so neither its output nor its picture goes into
 * the report, only the verdict. `whole`: the run of the student's whole
 * chain, for the integration part (its reference was rendered by the own-code
 * run just before, with the same arguments). Returns whether it matched. */
static bool grade_image(const grader *g, assignment_result *a, const cJSON *img, const char *dir,
                        const char *reldir, const char *crash_hint, const job *j, bool sealed,
                        bool whole) {
    const char *name = str_or(img, "name", "image");
    const char *program = str_or(img, "program", "");
    const char *reference = str_or(img, "reference", "");
    const char *hint = str_or(img, "hint", NULL);
    item *it = add_item(a);
    it->is_image = true;
    char label[300];
    fmt(label, sizeof label, whole ? "%s image %s, your whole chain" : "image %s",
        whole ? reldir : name, name);
    it->name = xstrdup(label);
    it->max_score = num_or(img, "points", g->default_points);
    sbuf o = {0};
    char ref_path[4096], prog_path[4096], got_path[4096], log_path[4096];
    fmt(ref_path, sizeof ref_path, "%s/tests/reference/%s", g->source, reference);
    /* A variant (rubric "reference_program"): its reference is rendered now,
     * by the trusted reference program with the arguments chosen for this
     * grading, so no reference image of it exists for a submission to copy or
     * carry. */
    const char *ref_program = str_or(img, "reference_program", NULL);
    if (ref_program) {
        char ref_prog_path[4096], ref_log[4300];
        fmt(ref_prog_path, sizeof ref_prog_path, "%s/bin/%s", g->build, ref_program);
        /* in the work folder: a variant's reference is never handed out,
         * only the difference from it */
        variant_reference_path(g, dir, reldir, name, ref_path, sizeof ref_path);
        fmt(ref_log, sizeof ref_log, "%s/%s.reference.log", dir, name);
        if (whole && file_exists(ref_path)) goto reference_ready;
        unlink(ref_path);
        run_result ref_rr = file_exists(ref_prog_path)
                                ? reference_render(g, ref_prog_path, j->args, ref_path, NULL, ref_log)
                                : (run_result){RUN_NOT_STARTED, 0, 0};
        if (ref_rr.kind != RUN_EXITED || ref_rr.code != 0 || !file_exists(ref_path)) {
            it->counted = false;
            it->status = xstrdup("SKIP");
            it->reason = xstrdup("no reference program here (not counted)");
            sb_printf(&o, "this image is graded against %s, rendered at grading time; this build "
                          "has no working %s (the student edition has none): not counted",
                      ref_program, ref_program);
            it->output = o.s;
            junit_case(it, a->id, NULL);
            return false;
        }
    }
reference_ready:;
    /* The student's program ran in the sandbox (image_job), writing into a
     * folder of its own, never next to the reference. */
    const char *written = j->store[15];
    fmt(prog_path, sizeof prog_path, "%s", j->store[14]);
    fmt(got_path, sizeof got_path, "%s/%s.got.png", dir, name);
    fmt(log_path, sizeof log_path, "%s", j->out_path);
    if (!ref_program && !file_exists(ref_path)) {
        it->counted = false;
        it->status = xstrdup("SKIP");
        it->reason = xstrdup("no reference image yet (not counted)");
        sb_printf(&o, "tests/reference/%s does not exist (make reference-images); not counted",
                  reference);
        it->output = o.s;
        junit_case(it, a->id, NULL);
        return false;
    }
    ras_error err = {{0}};
    ras_compare_kind kind;
    ras_compare_options opt;
    if (!image_options(g, img, &kind, &opt, &err)) {
        it->counted = false;
        it->status = xstrdup("SKIP");
        it->reason = xstrdup("bad metric in the rubric (not counted)");
        it->output = xstrdup(err.msg);
        junit_case(it, a->id, NULL);
        return false;
    }

    /* the copy of the reference that the report shows */
    char exp_copy[4096], rel[4200];
    fmt(exp_copy, sizeof exp_copy, "%s/%s.expected.png", dir, name);
    if (!ref_program) {
        copy_file(ref_path, exp_copy);
        fmt(rel, sizeof rel, "%s/%s.expected.png", reldir, name);
        it->img_expected = xstrdup(rel);
    }

    const cJSON *args = j->args;
    sb_printf(&o, "command: %s", program);
    for (const cJSON *v = args ? args->child : NULL; v; v = v->next)
        if (cJSON_IsString(v)) sb_printf(&o, " %s", v->valuestring);
    sb_printf(&o, " -o %s.png   (comparison %s: metric %s)\n", name,
              str_or(img, "comparison", "?"), ras_compare_kind_name(kind));
    unlink(got_path);
    run_result rr = file_exists(prog_path) ? j->rr : (run_result){RUN_NOT_STARTED, 0, 0};
    if (rr.kind == RUN_EXITED && rr.code > 128 && rr.code < 160) /* bwrap: 128 + signal */
        rr = (run_result){RUN_SIGNALED, rr.code - 128, rr.seconds};
    if (rr.kind == RUN_SIGNALED && rr.code == SIGXCPU) /* its processor time ran out */
        rr = (run_result){RUN_TIMEOUT, 0, rr.seconds};
    char *log = read_file(log_path, 16 * 1024);
    char *clean_raw = without_work_path(g->work, clean_output(log ? log : ""));
    char *clean = student_text(clean_raw, 3000);
    free(clean_raw);
    free(log);
    /* The notice is what the program printed: the student controls it, so it
     * can only cost points, never earn them. */
    bool todo = has_todo_notice(clean);
    ras_image *got = NULL, *expected = NULL;
    if (rr.kind == RUN_NOT_STARTED) {
        it->status = xstrdup("ERROR");
        sb_printf(&o, "the program %s was not built\n", program);
    } else if (rr.kind == RUN_TIMEOUT) {
        it->status = xstrdup("TIMEOUT");
        sb_printf(&o,
                  "the program used more than %.0f s of processor time (or ran %.0f s on the "
                  "clock) and was stopped: an endless loop?\n",
                  g->render_limit, wall_backstop(g->render_limit));
    } else if (rr.kind == RUN_SIGNALED) {
        it->status = xstrdup("CRASH");
        sb_printf(&o, "the program crashed with %s\nlikely mistake: %s\n", signal_text(rr.code),
                  crash_hint);
    } else if (!(got = load_student_image(written, ref_path, &err))) {
        it->status = xstrdup("FAIL");
        sb_printf(&o, "the program exited with status %d and wrote no usable image: %s\n",
                  rr.code, err.msg);
    } else if (!sealed) {
        ras_image_save(got, got_path, &err); /* the report's copy, re-encoded by us */
    }
    if (sealed)
        sb_printf(&o, "(rendered with your %s code and the reference of the earlier assignments; "
                      "this run holds reference code, so its picture and output are not shown%s)\n",
                  a->id, *clean ? ", although it printed some" : "");
    else if (*clean)
        sb_printf(&o, "program output:\n%s\n", clean);
    free(clean);
    /* The verdict follows the evidence (DESIGN.md): the buffers say first
     * where the frame goes wrong; what the picture alone shows may only
     * refine that, and fails a picture within its metric's budget only where
     * the buffers place the defect in the graded assignment's code. */
    bool ref_raster = sealed && !strcmp(a->id, "hw3");
    if (got && (expected = ras_image_load(ref_path, &err)) != NULL) {
        ras_compare_result r;
        fmt(rel, sizeof rel, "%s/%s.got.png", reldir, name);
        if (!sealed) it->img_got = xstrdup(rel);
        /* one comparison for the verdict, the heatmap and the crop */
        ras_comparison *cmp = ras_comparison_create(expected, got, kind, &err);
        if (!cmp || !ras_comparison_result(cmp, &opt, &r, &err)) {
            it->status = xstrdup("FAIL");
            sb_printf(&o, "%s\n", err.msg);
        } else {
            sb_printf(&o, "%s\n", r.summary);
            bool flat = is_flat(got) && !is_flat(expected);
            sbuf defects = {0}, bufs = {0};
            bool defect = !flat && image_defects(&defects, expected, got, true);
            evidence ev;
            memset(&ev, 0, sizeof ev);
            /* (not for a stub's placeholder picture, which says enough; at
             * most EVIDENCE_MAX per grading: each costs two more renders) */
            if ((!r.pass || defect) && rr.kind == RUN_EXITED && !todo &&
                g->evidence_runs < EVIDENCE_MAX && !getenv("RAS_GRADE_NO_BUFFERS")) {
                ((grader *)g)->evidence_runs++;
                buffer_evidence(g, it, &bufs, img, dir, reldir, j, sealed ? j->extra_ro : NULL,
                                ref_raster, &ev);
            }
            bool placed = ev.ran && *ev.stage && strcmp(ev.stage, "colour") &&
                          (whole || (ev.owner && !strcmp(ev.owner, a->id))) &&
                          /* the shader's own colours are judged by the metric alone */
                          !(!strcmp(ev.stage, "sample_colour") && !strcmp(ev.owner, "hw3"));
            if (r.pass && defect) {
                if (placed) {
                    r.pass = false;
                    sb_printf(&o, "(within the metric's budget, but the %s buffer differs from "
                                  "the reference's and the picture shows the defect below: "
                                  "your %s code, not a match)\n",
                              ev.stage, ev.owner);
                } else {
                    sb_printf(&o, "(the picture shows a defect, but %s: within the metric's "
                                  "budget, not charged)\n",
                              !ev.ran ? "no buffer evidence places it"
                              : !strcmp(ev.stage, "colour")
                                  ? "every buffer matches the reference's"
                                  : "the buffers place it outside this assignment's code");
                    free(defects.s);
                    defects = (sbuf){0};
                }
            }
            it->passed = r.pass;
            it->status = xstrdup(r.pass ? (todo ? "TODO" : "PASS") : (todo ? "TODO" : "FAIL"));
            if (!r.pass) {
                /* 1. nothing drawn; 2. the first buffer that differs; 3. what
                 * the picture shows, where the buffers allow that cause */
                if (flat)
                    sb_printf(&o, "likely mistake: nothing was drawn: your image is one flat "
                                  "colour%s%s\n",
                              *ev.why_blank ? ": "
                              : ev.blank    ? ": no sample was covered (your depth buffer is "
                                              "empty)"
                                            : " (are the TODOs written? do the matrices put the "
                                              "scene in front of the camera?)",
                              ev.why_blank);
                else if (ev.ran && *ev.stage && strcmp(ev.stage, "colour")) {
                    const char *line = strstr(sb_str(&bufs), "buffers: the first that differs is ");
                    if (line) {
                        line += strlen("buffers: the first that differs is ");
                        size_t n = strcspn(line, "\n");
                        sb_add(&o, "likely mistake: ");
                        const char *lk = strstr(line, "; likely: ");
                        if (lk && (size_t)(lk - line) < n) {
                            sb_addn(&o, lk + 10, n - (size_t)(lk + 10 - line));
                            sb_printf(&o, " (the first buffer that differs: %s, %s's stage)\n",
                                      ev.stage, ev.owner);
                        } else {
                            sb_addn(&o, line, n);
                            sb_add(&o, "\n");
                        }
                    }
                }
                sb_add(&o, sb_str(&bufs));
                /* rasterizer and resolve causes only where those stages are
                 * the student's and the buffers do not acquit them */
                bool raster_causes = !ref_raster && (!ev.ran || ev.rasterizer);
                if (!flat && raster_causes)
                    sb_add(&o, sb_str(&defects));
                else if (!flat && defects.len) {
                    /* the pattern only: the buffers acquit the rasterizer */
                    sbuf plain = {0};
                    image_defects(&plain, expected, got, false);
                    sb_add(&o, sb_str(&plain));
                    free(plain.s);
                }
                if (!flat)
                    image_signatures(&o, expected, got, &opt, j->args, &ev, raster_causes);
                if (kind == RAS_COMPARE_EXACT || kind == RAS_COMPARE_EDGE_TOLERANT) {
                    char mask[2048];
                    if (ras_compare_ascii_mask(expected, got, (vec3s){{0, 0, 0}}, r.worst_col,
                                               r.worst_row, 8, mask, sizeof mask, &err))
                        sb_printf(&o, "coverage around the worst pixel (%d,%d), %s:\n%s",
                                  r.worst_col, r.worst_row, RAS_COMPARE_ASCII_LEGEND, mask);
                }
                if (hint) sb_printf(&o, "what this image checks: %s\n", hint);
            }
            free(defects.s);
            free(bufs.s);
            ras_image *heat = sealed ? NULL : ras_comparison_heatmap(cmp, &err);
            char p[4096];
            fmt(p, sizeof p, "%s/%s.diff.png", dir, name);
            if (heat && ras_image_save(heat, p, &err)) {
                fmt(rel, sizeof rel, "%s/%s.diff.png", reldir, name);
                it->img_diff = xstrdup(rel);
            }
            ras_image_destroy(heat);
            if (!r.pass && !sealed && !ref_program) { /* a crop shows the reference */
                ras_image *crop = ras_comparison_crop(cmp, r.worst_col, r.worst_row, &err);
                fmt(p, sizeof p, "%s/%s.crop.png", dir, name);
                if (crop && ras_image_save(crop, p, &err)) {
                    fmt(rel, sizeof rel, "%s/%s.crop.png", reldir, name);
                    it->img_crop = xstrdup(rel);
                }
                ras_image_destroy(crop);
            }
        }
        ras_comparison_destroy(cmp);
    } else if (got) {
        it->status = xstrdup("ERROR");
        sb_printf(&o, "could not read the reference: %s\n", err.msg);
    }
    if (it->passed && todo)
        sb_add(&o, "(matches, but the program printed a TODO notice, so no points: a stub it "
                   "calls, or a function you wrote with its notice lines left in: delete them)\n");
    ras_image_destroy(got);
    ras_image_destroy(expected);
    while (o.len && o.s[o.len - 1] == '\n')
        o.s[--o.len] = '\0';
    it->output = o.s;
    it->score = it->passed && !todo ? it->max_score : 0;
    if (it->passed && !todo)
        it->reason = xstrdup("");
    else if (it->passed)
        it->reason = xstrdup("matches, but a TODO notice was printed (a stub, or notice lines left in)");
    else {
        const char *lm = strstr(it->output, "likely mistake");
        const char *summary = strstr(it->output, " FAIL: ");
        if (lm)
            it->reason = reason_line(lm);
        else if (summary) {
            while (summary > it->output && summary[-1] != '\n')
                summary--;
            it->reason = reason_line(summary);
        } else if (rr.kind != RUN_EXITED)
            it->reason = reason_line(strstr(it->output, "\n") + 1);
        else
            it->reason = reason_line(it->output + strcspn(it->output, "\n") + 1);
    }
    junit_case(it, a->id, NULL);
    return it->passed;
}

/* Whether a sealed run (image_job) wrote an image that passes the rubric's
 * comparison with ref_path. */
static bool run_matches(const grader *g, const job *j, const cJSON *img, const char *ref_path) {
    ras_error err = {{0}};
    ras_compare_kind kind;
    ras_compare_options opt;
    if (j->rr.kind != RUN_EXITED || j->rr.code != 0 || !image_options(g, img, &kind, &opt, &err))
        return false;
    ras_image *got = load_student_image(j->store[15], ref_path, &err);
    ras_image *expected = got ? ras_image_load(ref_path, &err) : NULL;
    ras_compare_result r = {0};
    bool pass = expected && ras_compare_images(expected, got, &opt, &r, &err) && r.pass;
    sbuf ignored = {0};
    if (pass && image_defects(&ignored, expected, got, false)) pass = false;
    free(ignored.s);
    ras_image_destroy(got);
    ras_image_destroy(expected);
    return pass;
}

/* The first item of assignment `id` that lost points, as "NAME (reason)"
 * into buf; "" when it lost none or was not graded. */
static void first_loss(const assignment_result *as, int n, const char *id, char *buf, size_t size) {
    buf[0] = '\0';
    for (int i = 0; i < n; i++) {
        if (!as[i].id || strcmp(as[i].id, id)) continue;
        for (int k = 0; k < as[i].n_items; k++) {
            const item *it = &as[i].items[k];
            if (it->counted && it->score < it->max_score) {
                fmt(buf, size, "%s%s%s%s", it->name, it->reason && *it->reason ? " (" : "",
                    it->reason ? it->reason : "", it->reason && *it->reason ? ")" : "");
                return;
            }
        }
    }
}

/* Attribution by substitution (docs/grading.md): the student's whole chain
 * failed an image of hwN. Which assignment's code makes the difference? The
 * own-code run (the references of every earlier assignment) has answered for
 * hwN itself; for each earlier assignment K alone, the image is rendered
 * again, sealed, with only K's reference swapped in. The answer leads the
 * integration item, with the first loss of the assignment it names. */
static void attribute_image(grader *g, item *it, const cJSON *img, const char *dir,
                            const char *id, const job *graded, bool own_passed,
                            const assignment_result *as, int n_as) {
    char ref_path[4096], why[1200] = "", loss[700];
    variant_reference_path(g, dir, id, str_or(img, "name", "image"), ref_path, sizeof ref_path);
    if (!str_or(img, "reference_program", NULL))
        fmt(ref_path, sizeof ref_path, "%s/tests/reference/%s", g->source,
            str_or(img, "reference", ""));
    int number = 0;
    sscanf(id, "hw%d", &number);
    if (!own_passed) {
        fmt(why, sizeof why, "your %s code causes this: it fails this image on its own too, "
                             "with the reference of the earlier assignments (charged in %s)",
            id, id);
    } else if (number == 2) {
        first_loss(as, n_as, "hw1", loss, sizeof loss);
        fmt(why, sizeof why, "your hw1 causes this: with the reference hw1 your hw2 matches this "
                             "image%s%s",
            *loss ? "; hw1's first lost point: " : "", loss);
    } else if (number == 3) {
        /* one sealed render per earlier assignment alone: hw1 then hw2 */
        job subs[2];
        memset(subs, 0, sizeof subs);
        bool ran[2] = {false, false};
        int m = 0;
        for (int k = 0; k < 2; k++) {
            char refs[2] = {(char)('1' + k), '\0'}, own[4096], tag[32], prog[4300];
            if (!own_dir(g, id, refs, own, sizeof own)) continue;
            fmt(prog, sizeof prog, "%s/bin/%s", own, str_or(img, "program", ""));
            if (!file_exists(prog)) continue;
            fmt(tag, sizeof tag, ".ref%s", refs);
            subs[m].args = graded->args;
            image_job(g, img, dir, &subs[m], own, tag);
            ran[k] = true;
            m++;
        }
        run_jobs(subs, m, g->jobs);
        /* matches[k]: the image matches with only hw(k+1)'s reference */
        bool matches[2] = {false, false};
        for (int k = 0, i = 0; k < 2; k++)
            if (ran[k]) matches[k] = run_matches(g, &subs[i++], img, ref_path);
        if (ran[0] && ran[1]) {
            const char *culprit = matches[1] && !matches[0]   ? "hw2"
                                  : matches[0] && !matches[1] ? "hw1"
                                                              : NULL;
            if (culprit) {
                first_loss(as, n_as, culprit, loss, sizeof loss);
                fmt(why, sizeof why, "your %s causes this: with the reference %s this image "
                                     "matches, with your %s it does not%s%s",
                    culprit, culprit, culprit, *loss ? "; its first lost point: " : "", loss);
            } else if (matches[0] && matches[1])
                fmt(why, sizeof why, "one of your hw1 or your hw2 causes this: the image matches "
                                     "with either reference swapped in (most likely hw2, which "
                                     "draws it)");
            else {
                char loss2[700];
                first_loss(as, n_as, "hw1", loss, sizeof loss);
                first_loss(as, n_as, "hw2", loss2, sizeof loss2);
                fmt(why, sizeof why, "both your hw1 and your hw2 cause this: the image matches "
                                     "only with both references swapped in, with neither alone "
                                     "(hw1's first lost point: %s; hw2's: %s)",
                    *loss ? loss : "none", *loss2 ? loss2 : "none");
            }
        }
    }
    if (!*why) return;
    sbuf o = {0};
    sb_printf(&o, "whose code: %s\n%s", why, it->output ? it->output : "");
    free(it->output);
    it->output = o.s;
    free(it->reason);
    it->reason = xstrdup(why);
}

/* ------------------------------------------------------------- outputs */

/* The rubric's "where" for an item of assignment `asg`: the first
 * [prefix, text] pair whose prefix starts `name`; NULL when none does. */
static const char *where_of(const cJSON *asg, const char *name) {
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(asg, "where"), *pair;
    cJSON_ArrayForEach(pair, list) {
        const cJSON *prefix = cJSON_GetArrayItem(pair, 0), *text = cJSON_GetArrayItem(pair, 1);
        if (cJSON_IsString(prefix) && cJSON_IsString(text) &&
            !strncmp(name, prefix->valuestring, strlen(prefix->valuestring)))
            return text->valuestring;
    }
    return NULL;
}

/* Each failing item's message opens with where to look (the rubric's file,
 * function and TODO numbers). `from`: the first item of a to mark. */
static void mark_where(assignment_result *a, int from, const cJSON *asg, bool integration) {
    for (int k = from; k < a->n_items; k++) {
        item *it = &a->items[k];
        /* an integration item is "hwN image NAME, your whole chain" */
        const char *name = it->name;
        if (integration && strstr(name, " image ")) name = strstr(name, " image ") + 1;
        char bare[300];
        fmt(bare, sizeof bare, "%.*s", (int)strcspn(name, ","), name);
        it->where = where_of(asg, bare);
        if (!it->where || !it->counted || it->score >= it->max_score) continue;
        sbuf o = {0};
        sb_printf(&o, "where: %s\n%s", it->where, it->output ? it->output : "");
        free(it->output);
        it->output = o.s;
    }
}

/* The one-line fix hint of an item: its message's "likely mistake" (either
 * case, as tests and pictures write it), else its reason; at most
 * FIX_CHARS characters, into buf. */
enum { FIX_CHARS = 300 };
static void fix_line(const item *it, char *buf, size_t size) {
    const char *out = it->output ? it->output : "", *p = NULL;
    /* never from a line the student's code printed (student_text marks
     * each with "│ "): a student cannot write their own fix line */
    const char *line = out;
    for (const char *q = out; *q && !p; q++) {
        if (q > out && q[-1] == '\n') line = q;
        if (!strncasecmp(q, "likely mistake: ", 16) && strncmp(line, "\xe2\x94\x82 ", 4)) p = q + 16;
    }
    if (!p) p = it->reason && *it->reason ? it->reason : "see its message below";
    size_t n = utf8_prefix(p, strcspn(p, "\n"), FIX_CHARS);
    fmt(buf, size, "%.*s%s", (int)n, p, p[n] && p[n] != '\n' ? " …" : "");
}

/* The item a student should start with: the earliest failing item of the
 * earliest assignment that lost points (the report's and the table's
 * opening lines). NULL when nothing lost points. */
static const item *start_here(const assignment_result *as, int n, const char **id) {
    /* an item that failed outright first; one that passed but printed a
     * TODO notice says less */
    for (int i = 0; i < n; i++)
        for (int pass = 0; pass < 2; pass++)
            for (int k = 0; k < as[i].n_items; k++) {
                const item *it = &as[i].items[k];
                if (it->counted && it->score < it->max_score && (pass || !it->passed)) {
                    *id = as[i].id;
                    return it;
                }
            }
    return NULL;
}

static void mark_build_failed(const grader *g, assignment_result *a, const cJSON *asg,
                              const char *log_path) {
    char *log = read_file(log_path, 0);
    sbuf tail = {0};
    /* the compiler's error lines, at most 30 */
    int lines = 0;
    for (char *line = log ? strtok(log, "\n") : NULL; line && lines < 30; line = strtok(NULL, "\n"))
        if (strstr(line, "error") || strstr(line, "Error")) {
            sb_printf(&tail, "%s\n", line);
            lines++;
        }
    free(log);
    const cJSON *tests = cJSON_GetObjectItemCaseSensitive(asg, "tests");
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(asg, "images");
    for (int pass = 0; pass < 2; pass++)
        for (const cJSON *t = (pass ? images : tests) ? (pass ? images : tests)->child : NULL; t;
             t = t->next) {
            item *it = add_item(a);
            char label[300];
            fmt(label, sizeof label, "%s%s", pass ? "image " : "",
                pass ? str_or(t, "name", "?") : t->string);
            it->name = xstrdup(label);
            it->is_image = pass;
            it->max_score = pass ? num_or(t, "points", g->default_points)
                                 : (cJSON_IsNumber(t) ? t->valuedouble : g->default_points);
            it->status = xstrdup("BUILD");
            it->reason = xstrdup("your code does not compile");
            sbuf o = {0};
            sb_printf(&o, "your code for %s does not compile, so nothing could be tested.\n%s",
                      a->id, sb_str(&tail));
            it->output = o.s;
            junit_case(it, a->id, NULL);
        }
    free(tail.s);
}

/* The grader's reports go through the atomic write of common/io/ras_io.h: a
 * full disk or a kill leaves the previous report whole, never half of one. */
static FILE *report_begin(ras_io_report *r) {
    memset(r, 0, sizeof *r);
    return ras_io_report_open(r);
}

static bool report_end(ras_io_report *r, const char *path) {
    ras_error err = {{0}};
    if (ras_io_report_commit(r, path, &err)) return true;
    fprintf(stderr, "raster101-grade: %s\n", err.msg);
    return false;
}

static bool write_outputs(const grader *g, assignment_result *as, int n, double total,
                          double max_total) {
    char path[4096];
    /* results.json — Gradescope */
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "score", total);
    cJSON_AddNumberToObject(root, "max_score", max_total);
    sbuf summary = {0};
    if (g->notes && *g->notes) sb_printf(&summary, "About your submission:\n%s\n\n", g->notes);
    /* plain text: nothing in an output renders as Markdown or HTML */
    cJSON_AddStringToObject(root, "output_format", "text");
    cJSON_AddStringToObject(root, "test_output_format", "text");
    cJSON *tests = cJSON_AddArrayToObject(root, "tests");
    cJSON *extra = cJSON_AddObjectToObject(root, "extra_data");
    for (int i = 0; i < n; i++) {
        assignment_result *a = &as[i];
        cJSON *ea = cJSON_AddObjectToObject(extra, a->id);
        cJSON_AddBoolToObject(ea, "graded", a->graded);
        cJSON_AddNumberToObject(ea, "score", a->score);
        cJSON_AddNumberToObject(ea, "max_score", a->max_score);
        if (a->note) cJSON_AddStringToObject(ea, "note", a->note);
        if (a->graded)
            sb_printf(&summary, "%s: %g / %g\n", a->id, a->score, a->max_score);
        else
            sb_printf(&summary, "%s: not graded (%s)\n", a->id, a->note ? a->note : "");
        for (int k = 0; k < a->n_items; k++) {
            item *it = &a->items[k];
            if (!it->counted) continue;
            cJSON *t = cJSON_CreateObject();
            char name[400];
            fmt(name, sizeof name, "%s: %s%s", a->id, it->name,
                it->default_weight ? " (default weight)" : "");
            cJSON_AddStringToObject(t, "name", name);
            cJSON_AddNumberToObject(t, "score", it->score);
            cJSON_AddNumberToObject(t, "max_score", it->max_score);
            cJSON_AddStringToObject(t, "status", it->score >= it->max_score ? "passed" : "failed");
            cJSON_AddStringToObject(t, "output", it->output ? it->output : "");
            cJSON_AddStringToObject(t, "visibility", "visible");
            cJSON_AddItemToArray(tests, t);
        }
    }
    cJSON_AddStringToObject(root, "output", sb_str(&summary));
    char *json = cJSON_Print(root);
    fmt(path, sizeof path, "%s/results.json", g->out);
    ras_io_report rep;
    bool ok = true;
    FILE *f = report_begin(&rep);
    if (f) {
        fprintf(f, "%s\n", json);
        ok &= report_end(&rep, path);
    }
    free(json);
    cJSON_Delete(root);
    free(summary.s);

    /* scores.csv — one row per item, for tests/grading/grade-all */
    fmt(path, sizeof path, "%s/scores.csv", g->out);
    f = report_begin(&rep);
    if (f) {
        fprintf(f, "assignment,item,score,max_score,status\n");
        for (int i = 0; i < n; i++) {
            for (int k = 0; k < as[i].n_items; k++) {
                item *it = &as[i].items[k];
                if (it->counted)
                    fprintf(f, "%s,%s,%g,%g,%s\n", as[i].id, it->name, it->score, it->max_score,
                            it->status);
            }
            if (as[i].graded)
                fprintf(f, "%s,total,%g,%g,\n", as[i].id, as[i].score, as[i].max_score);
        }
        fprintf(f, "all,total,%g,%g,\n", total, max_total);
        ok &= report_end(&rep, path);
    }

    /* failures.txt — every item that lost points, with what it said (for
     * tests/grading/run-mutants and for a quick read) */
    fmt(path, sizeof path, "%s/failures.txt", g->out);
    f = report_begin(&rep);
    if (f) {
        for (int i = 0; i < n; i++)
            for (int k = 0; k < as[i].n_items; k++) {
                item *it = &as[i].items[k];
                if (it->counted && it->score < it->max_score)
                    fprintf(f, "== %s: %s (%s)\n%s\n", as[i].id, it->name, it->status,
                            it->output ? it->output : "");
            }
        ok &= report_end(&rep, path);
    }

    /* hwN/cmocka.xml — JUnit, one suite per assignment */
    for (int i = 0; i < n; i++) {
        if (!as[i].graded) continue;
        fmt(path, sizeof path, "%s/%s/cmocka.xml", g->out, as[i].id);
        f = report_begin(&rep);
        if (!f) continue;
        int n_tests = 0, n_fail = 0;
        for (int k = 0; k < as[i].n_items; k++)
            if (!as[i].items[k].is_image && as[i].items[k].counted) {
                n_tests++;
                n_fail += !as[i].items[k].passed;
            }
        fprintf(f,
                "<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<testsuites>\n"
                "  <testsuite name=\"%s\" tests=\"%d\" failures=\"%d\" errors=\"0\" "
                "skipped=\"0\">\n",
                as[i].id, n_tests, n_fail);
        for (int k = 0; k < as[i].n_items; k++)
            if (!as[i].items[k].is_image && as[i].items[k].counted && as[i].items[k].xml)
                fputs(as[i].items[k].xml, f);
        fprintf(f, "  </testsuite>\n</testsuites>\n");
        ok &= report_end(&rep, path);
    }

    /* report.md */
    fmt(path, sizeof path, "%s/report.md", g->out);
    f = report_begin(&rep);
    if (!f) return false;
    fprintf(f, "# Raster101 grade report\n\n");
    if (g->notes && *g->notes) {
        fprintf(f, "**About your submission** (what the grader found in it):\n");
        report_fenced(f, g->notes);
        fputc('\n', f);
    }
    fprintf(f, "**Total: %g / %g**", total, max_total);
    if (strcmp(g->variant, "ref") == 0) fprintf(f, " (reference solutions graded as the student)");
    const char *first_id = NULL;
    const item *first = start_here(as, n, &first_id);
    if (first) {
        /* where to start: what the student should fix first, before details */
        fprintf(f, "\n\n**Start here:** %s `%s` (%s)  \n", first_id, first->name, first->status);
        if (first->where) fprintf(f, "**Where:** %s  \n", first->where);
        char fix[1400];
        fix_line(first, fix, sizeof fix);
        fprintf(f, "**Fix:** ");
        report_cell(f, fix); /* the message may quote what the student's code returned */
    }
    fprintf(f, "\n\n| assignment | points |\n|---|---|\n");
    for (int i = 0; i < n; i++) {
        if (as[i].graded)
            fprintf(f, "| %s %s | %g / %g |\n", as[i].id, as[i].title, as[i].score,
                    as[i].max_score);
        else
            fprintf(f, "| %s %s | not graded: %s |\n", as[i].id, as[i].title,
                    as[i].note ? as[i].note : "");
    }
    for (int i = 0; i < n; i++) {
        assignment_result *a = &as[i];
        if (!a->graded) continue;
        fprintf(f, "\n## %s — %s: %g / %g\n\n", a->id, a->title, a->score, a->max_score);
        if (a->note) fprintf(f, "_%s_\n\n", a->note);
        fprintf(f, "| | test | points | why |\n|---|---|---|---|\n");
        for (int k = 0; k < a->n_items; k++) {
            item *it = &a->items[k];
            fprintf(f, "| %s | `%s`%s | ", it->status, it->name,
                    it->default_weight ? " (default weight)" : "");
            if (it->counted)
                fprintf(f, "%g / %g | ", it->score, it->max_score);
            else
                fprintf(f, "not counted | ");
            report_cell(f, it->reason ? it->reason : "");
            fprintf(f, " |\n");
        }
        bool any_fail = false;
        for (int k = 0; k < a->n_items; k++)
            any_fail |= !a->items[k].is_image && a->items[k].score < a->items[k].max_score &&
                        a->items[k].counted;
        if (any_fail) {
            fprintf(f, "\n### What the failing tests said\n");
            for (int k = 0; k < a->n_items; k++) {
                item *it = &a->items[k];
                if (it->is_image || !it->counted || it->score >= it->max_score) continue;
                fprintf(f, "\n**`%s`** (%s)\n", it->name, it->status);
                report_fenced(f, it->output ? it->output : "");
            }
        }
        for (int k = 0; k < a->n_items; k++) {
            item *it = &a->items[k];
            /* only the pictures that lost points or did not match: a
             * passing picture is a line of the table; a variant's reference
             * is drawn for this grading and never shown */
            if (it->is_image && (it->img_expected || it->img_diff || it->img_got) &&
                (!it->passed || it->score < it->max_score)) {
                fprintf(f, "\n### %s — %s (%g / %g)\n\n", it->name, it->status, it->score,
                        it->max_score);
                if (it->img_got) { /* sealed runs show no picture: words only */
                    fprintf(f, "| reference | yours | difference |\n|---|---|---|\n");
                    fprintf(f, "| %s%s%s | ![yours](%s) | %s%s%s |\n",
                            it->img_expected ? "![reference](" : "(drawn for this grading: not shown)",
                            it->img_expected ? it->img_expected : "", it->img_expected ? ")" : "",
                            it->img_got, it->img_diff ? "![difference](" : "",
                            it->img_diff ? it->img_diff : "", it->img_diff ? ")" : "");
                }
                if (it->img_crop)
                    fprintf(f,
                            "\nWorst region (reference | yours | difference):\n\n"
                            "![worst region](%s)\n",
                            it->img_crop);
                if (it->buf_name && it->buf_ref)
                    fprintf(f,
                            "\nThe first buffer that differs, **%s** (reference | yours | "
                            "difference):\n\n| ![reference](%s) | %s%s%s | %s%s%s |\n|---|---|---|"
                            "\n",
                            it->buf_name, it->buf_ref, it->buf_got ? "![yours](" : "",
                            it->buf_got ? it->buf_got : "", it->buf_got ? ")" : "",
                            it->buf_diff ? "![difference](" : "", it->buf_diff ? it->buf_diff : "",
                            it->buf_diff ? ")" : "");
                report_fenced(f, it->output ? it->output : "");
            }
        }
    }
    ok &= report_end(&rep, path);
    return ok;
}

static void print_table(const grader *g, assignment_result *as, int n, double total,
                        double max_total) {
    bool defaults = false;
    const char *first_id = NULL;
    const item *first = start_here(as, n, &first_id);
    if (first) {
        printf("START HERE: %s %s (%s)\n", first_id, first->name, first->status);
        if (first->where) printf("  where: %s\n", first->where);
        char fix[1400];
        fix_line(first, fix, sizeof fix);
        printf("  fix:   %s\n\n", fix);
    }
    for (int i = 0; i < n; i++) {
        assignment_result *a = &as[i];
        if (!a->graded) {
            printf("%-4s %-48s not graded: %s\n", a->id, a->title, a->note ? a->note : "");
            continue;
        }
        printf("%s  %s\n", a->id, a->title);
        if (a->note) printf("  note: %s\n", a->note);
        for (int k = 0; k < a->n_items; k++) {
            item *it = &a->items[k];
            char name[300];
            fmt(name, sizeof name, "%s%s", it->name, it->default_weight ? " *" : "");
            defaults |= it->default_weight;
            if (it->counted)
                printf("  %-7s %-50.50s %5g / %-3g %s\n", it->status, name, it->score,
                       it->max_score, it->reason ? it->reason : "");
            else
                printf("  %-7s %-50.50s   (not counted) %s\n", it->status, name,
                       it->reason ? it->reason : "");
        }
        printf("  %-58s %5g / %-3g (%.1f s)\n", "total", a->score, a->max_score, a->seconds);
    }
    if (defaults)
        printf("* not in tests/grading/rubric.json: scored with the default weight (%g point%s)\n",
               g->default_points, g->default_points == 1 ? "" : "s");
    printf("TOTAL %g / %g%s\n", total, max_total,
           strcmp(g->variant, "ref") == 0 ? "   (reference solutions graded as the student)" : "");
    printf("report: %s/report.md   Gradescope: %s/results.json\n", g->out, g->out);
}

/* ------------------------------------------------------------- main */

/* A random number from the kernel (the variants a grading draws must not be
 * predictable from the time or the process id). */
static unsigned random_u32(void) {
    unsigned v = 0;
    int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
    if (fd < 0 || read(fd, &v, sizeof v) != (ssize_t)sizeof v) v = (unsigned)time(NULL) ^ (unsigned)getpid();
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
    unsigned long long x = (g->has_seed ? g->seed : ((unsigned long long)random_u32() << 32 | random_u32())) ^
                           h;
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
static const cJSON *variant_args(grader *g, const cJSON *img) {
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

static void usage(FILE *f) {
    fputs("usage: raster101-grade --source SRC --build BUILD --out OUT [--rubric FILE]\n"
          "         [--hw hwN]... [--variant student|ref] [--build-failed hwN=LOG]...\n"
          "         [--expect full|POINTS] [--own OWN]\n"
          "         (tests/grading/grade passes --work, --student-tree, --student-build, --own)\n"
          "       raster101-grade --list RUBRIC   (assignments and their programs)\n",
          f);
}

/* Prints one argument error (what was expected, what came) and the usage. */
__attribute__((format(printf, 1, 2))) static int arg_error(const char *fmt_, ...) {
    va_list ap;
    va_start(ap, fmt_);
    fputs("raster101-grade: ", stderr);
    vfprintf(stderr, fmt_, ap);
    va_end(ap);
    fputc('\n', stderr);
    usage(stderr);
    return 2;
}

static bool is_dir(const char *path) {
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

int main(int argc, char **argv) {
    grader g = {.variant = "student"};
    const char *rubric_path = NULL, *expect = NULL, *list = NULL;
    static const char *const with_value[] = {
        "--source", "--build",        "--out",           "--rubric", "--variant",
        "--expect", "--hw",           "--list",          "--build-failed",
        "--work",   "--student-tree", "--student-build", "--sandbox-uid", "--jobs", "--own", "--sanitized-build",
        "--notes", "--seed"};
    g.sandbox_uid = -1;
    g.jobs = 2;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        }
        bool known = false;
        for (size_t k = 0; k < sizeof with_value / sizeof *with_value; k++)
            known |= !strcmp(a, with_value[k]);
        if (!known)
            return arg_error("unknown argument '%s'%s; expected one of the options below", a,
                             a[0] == '-' ? "" : " (every value follows its option)");
        if (!v || (v[0] == '-' && v[1] == '-'))
            return arg_error("option '%s' needs a value; got %s", a,
                             v ? "another option" : "the end of the command line");
        i++;
        if (!strcmp(a, "--source"))
            g.source = v;
        else if (!strcmp(a, "--build"))
            g.build = v;
        else if (!strcmp(a, "--out"))
            g.out = v;
        else if (!strcmp(a, "--rubric"))
            rubric_path = v;
        else if (!strcmp(a, "--variant")) {
            if (strcmp(v, "student") && strcmp(v, "ref"))
                return arg_error("--variant expects student or ref; got '%s'", v);
            g.variant = v;
        } else if (!strcmp(a, "--expect")) {
            char *end = NULL;
            double points = strtod(v, &end);
            if (strcmp(v, "full") && (end == v || *end || !isfinite(points) || points < 0))
                return arg_error("--expect expects full or a number of points (0 or more); "
                                 "got '%s'",
                                 v);
            expect = v;
        } else if (!strcmp(a, "--hw")) {
            if (g.n_only == 8) return arg_error("at most 8 --hw options; got more (%s)", v);
            g.only[g.n_only++] = v;
        } else if (!strcmp(a, "--list"))
            list = v;
        else if (!strcmp(a, "--work"))
            g.work = v;
        else if (!strcmp(a, "--own"))
            g.own = v;
        else if (!strcmp(a, "--sanitized-build"))
            g.sanitized = v;
        else if (!strcmp(a, "--seed")) {
            char *end = NULL;
            g.seed = strtoull(v, &end, 16);
            if (end == v || *end || strlen(v) > 16)
                return arg_error("--seed expects up to 16 hex digits; got '%s'", v);
            g.has_seed = true;
        }
        else if (!strcmp(a, "--notes")) {
            char *raw = read_small_file(v, 16 * 1024);
            free(g.notes);
            g.notes = raw && *raw ? student_text(raw, 8 * 1024) : NULL;
            free(raw);
        }
        else if (!strcmp(a, "--jobs")) {
            g.jobs = atoi(v);
            if (g.jobs < 1 || g.jobs > 64)
                return arg_error("--jobs expects 1 to 64 runs at once; got '%s'", v);
        }
        else if (!strcmp(a, "--student-tree"))
            g.student_tree = v;
        else if (!strcmp(a, "--student-build"))
            g.student_build = v;
        else if (!strcmp(a, "--sandbox-uid")) {
            char *end = NULL;
            g.sandbox_uid = strtol(v, &end, 10);
            if (end == v || *end || g.sandbox_uid < 1000)
                return arg_error("--sandbox-uid expects a uid of 1000 or more; got '%s'", v);
        }
        else { /* --build-failed */
            if (g.n_failed == 8 || !strchr(v, '=') || v[0] == '=')
                return arg_error("--build-failed expects hwN=LOG (at most 8 of them); got '%s'", v);
            char *hw = xstrdup(v);
            char *eq = strchr(hw, '=');
            *eq = '\0';
            g.failed_hw[g.n_failed] = hw;
            g.failed_log[g.n_failed++] = eq + 1;
        }
    }
    if (list) { /* --list RUBRIC: "hwN program..." per assignment, for tests/grading/grade */
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
    if (!g.source || !g.build || !g.out)
        return arg_error("expected --source, --build and --out; %s is missing",
                         !g.source  ? "--source"
                         : !g.build ? "--build"
                                    : "--out");
    if (!is_dir(g.source))
        return arg_error("--source expects the project folder; '%s' is not a folder", g.source);
    if (!is_dir(g.build))
        return arg_error("--build expects a build folder (cmake -B BUILD); '%s' is not a "
                         "folder",
                         g.build);
    char default_rubric[4096];
    if (!rubric_path) {
        fmt(default_rubric, sizeof default_rubric, "%s/tests/grading/rubric.json", g.source);
        rubric_path = default_rubric;
    }
    char *text = read_file(rubric_path, 0);
    g.rubric = text ? cJSON_Parse(text) : NULL;
    free(text);
    const cJSON *asgs = cJSON_GetObjectItemCaseSensitive(g.rubric, "assignments");
    if (!cJSON_IsArray(asgs)) {
        fprintf(stderr, "raster101-grade: %s: %s\n", rubric_path,
                g.rubric ? "no \"assignments\" array" : "missing or not valid JSON");
        return 2;
    }
    g.default_points = num_or(g.rubric, "default_points", 1);
    g.test_limit = num_or(g.rubric, "test_time_limit_s", 10);
    g.render_limit = num_or(g.rubric, "render_time_limit_s", 60);
    g.mem_mb = (long)num_or(g.rubric, "memory_limit_mb", 4096);
    if (getenv("RAS_GRADE_NO_MEMORY_LIMIT")) g.mem_mb = 0; /* sanitizer builds */
    /* Every --hw must be an assignment of the rubric: a typo would grade
     * nothing and report 0 / 0 as a success. */
    for (int i = 0; i < g.n_only; i++) {
        bool found = false;
        sbuf ids = {0};
        for (const cJSON *asg = asgs->child; asg; asg = asg->next) {
            found |= !strcmp(g.only[i], str_or(asg, "id", ""));
            sb_printf(&ids, "%s%s", ids.len ? ", " : "", str_or(asg, "id", "?"));
        }
        if (!found) {
            fprintf(stderr, "raster101-grade: --hw expects an assignment of %s (%s); got '%s'\n",
                    rubric_path, ids.s ? ids.s : "none", g.only[i]);
            free(ids.s);
            cJSON_Delete(g.rubric);
            return 2;
        }
        free(ids.s);
    }
    mkdirs(g.out);
    if (!is_dir(g.out) || access(g.out, W_OK) != 0) {
        int e = errno;
        fprintf(stderr,
                "raster101-grade: --out expects a folder it can create and write; '%s' is "
                "not (%s): choose another --out\n",
                g.out, file_exists(g.out) && !is_dir(g.out) ? "it is a file" : strerror(e));
        cJSON_Delete(g.rubric);
        return 2;
    }

    /* The student's side: tests/grading/grade makes it (a sandboxed build of a
     * pristine copy); without it there is nothing to grade. */
    if (!g.work || !g.student_tree || !g.student_build) {
        fprintf(stderr,
                "raster101-grade: expected --work, --student-tree and --student-build (the "
                "sandbox's folders, which tests/grading/grade makes); %s is missing: run tests/grading/grade\n",
                !g.work ? "--work" : !g.student_tree ? "--student-tree" : "--student-build");
        cJSON_Delete(g.rubric);
        return 2;
    }
    int n = cJSON_GetArraySize(asgs);
    assignment_result *as = calloc((size_t)n + 1, sizeof *as);
    /* The integration part: the images with points again, rendered by the
     * student's whole chain, each failure attributed (attribute_image). */
    assignment_result integration = {.graded = true};
    integration.id = xstrdup("integration");
    integration.title = xstrdup("Your assignments together: the whole chain");
    double integration_points = num_or(g.rubric, "integration_points_per_image", 0);
    double total = 0, max_total = 0;
    int k = 0;
    for (const cJSON *asg = asgs->child; asg; asg = asg->next) {
        const char *id = str_or(asg, "id", "?");
        bool wanted = g.n_only == 0;
        for (int i = 0; i < g.n_only; i++)
            wanted |= !strcmp(g.only[i], id);
        if (!wanted) continue;
        assignment_result *a = &as[k++];
        int integration_from = integration.n_items;
        a->id = xstrdup(id);
        a->title = xstrdup(str_or(asg, "title", ""));
        double t0 = now_s();
        char dir[4096], test_bin[4096];
        fmt(dir, sizeof dir, "%s/%s", g.out, id);
        fmt(test_bin, sizeof test_bin, "%s/tests/test_%s_worker", g.student_build, id);
        const char *failed_log = NULL;
        for (int i = 0; i < g.n_failed; i++)
            if (!strcmp(g.failed_hw[i], id)) failed_log = g.failed_log[i];
        const cJSON *images = cJSON_GetObjectItemCaseSensitive(asg, "images");
        bool any_program = false;
        for (const cJSON *img = images ? images->child : NULL; img; img = img->next) {
            char p[4096];
            fmt(p, sizeof p, "%s/bin/%s", g.student_build, str_or(img, "program", ""));
            any_program |= file_exists(p);
        }
        mkdirs(dir);
        if (failed_log) {
            a->graded = true;
            a->note = xstrdup("the code does not compile");
            mark_build_failed(&g, a, asg, failed_log);
        } else if (!file_exists(test_bin) && !any_program) {
            a->note = xstrdup("not in this build yet");
        } else {
            a->graded = true;
            test_batch tests;
            bool has_tests = false;
            if (file_exists(test_bin))
                has_tests = tests_prepare(&g, a, dir, &tests);
            else
                a->note = xstrdup("no test program built; images only");
            int n_img = cJSON_GetArraySize(images);
            int n_tests = has_tests ? tests.chunks : 0;
            /* all[0, n_tests): the tests' chunks (each a worker, then its
             * replay), started first; then runs[0, n_img): the graded runs,
             * on the assignment's own code where it could be linked; then the
             * whole-chain runs of the images with points (the integration
             * part), whole_at[i]. One batch, so that no core waits while
             * another finishes a chunk. */
            job *all = calloc((size_t)n_tests + 2 * (size_t)n_img + 1, sizeof *all);
            if (!all) abort();
            for (int c = 0; c < n_tests; c++)
                all[c] = tests.workers[c];
            job *runs = all + n_tests;
            int *whole_at = calloc((size_t)n_img + 1, sizeof *whole_at);
            bool *sealed = calloc((size_t)n_img + 1, sizeof *sealed);
            if (!runs || !whole_at || !sealed) abort();
            char own[4096];
            bool has_own = own_dir(&g, id, NULL, own, sizeof own);
            int i = 0, n_runs = n_img;
            for (const cJSON *img = images ? images->child : NULL; img; img = img->next, i++) {
                /* a variant's arguments, drawn for this grading (variant_args) */
                runs[i].args = variant_args(&g, img);
                char p[4300];
                fmt(p, sizeof p, "%s/bin/%s", own, str_or(img, "program", ""));
                sealed[i] = has_own && file_exists(p);
                image_job(&g, img, dir, &runs[i], sealed[i] ? own : NULL, "");
                whole_at[i] = -1;
                if (sealed[i] && num_or(img, "points", g.default_points) > 0) {
                    whole_at[i] = n_runs;
                    runs[n_runs].args = runs[i].args;
                    image_job(&g, img, dir, &runs[n_runs++], NULL, ".whole");
                }
            }
            double t_runs = now_s();
            run_jobs(all, n_tests + n_runs, g.jobs);
            profile("tests and images: sandboxed runs", id, t_runs);
            if (has_tests) {
                for (int c = 0; c < n_tests; c++)
                    tests.workers[c].rr = all[c].rr; /* (the replays' are set in place) */
                tests_finish(&g, a, asg, &tests);
            }
            double t_judge = now_s();
            i = 0;
            const char *crash_hint = str_or(asg, "crash_hint", "look for an out-of-bounds access");
            for (const cJSON *img = images ? images->child : NULL; img; img = img->next, i++) {
                bool own_passed = grade_image(&g, a, img, dir, id, crash_hint, &runs[i], sealed[i],
                                              false);
                if (whole_at[i] < 0) continue;
                bool whole_passed = grade_image(&g, &integration, img, dir, id,
                                                "a crash in one of your assignments (the "
                                                "attribution below says which)",
                                                &runs[whole_at[i]], false, true);
                item *it = &integration.items[integration.n_items - 1];
                it->score = it->score > 0 ? integration_points : 0;
                it->max_score = integration_points;
                if (!whole_passed || it->score < it->max_score)
                    attribute_image(&g, it, img, dir, id, &runs[i], own_passed, as, k);
            }
            profile("images: judged", id, t_judge);
            free(all);
            free(whole_at);
            free(sealed);
        }
        for (int i = 0; i < a->n_items; i++)
            if (a->items[i].counted) {
                a->score += a->items[i].score;
                a->max_score += a->items[i].max_score;
            }
        mark_where(a, 0, asg, false);
        mark_where(&integration, integration_from, asg, true);
        a->seconds = now_s() - t0;
        total += a->score;
        max_total += a->max_score;
    }
    if (integration.n_items > 0) {
        integration.note = xstrdup("the images with points again, rendered by your whole chain "
                                   "(your hw1 → hw2 → hw3); a failure says whose code causes it");
        for (int i = 0; i < integration.n_items; i++)
            if (integration.items[i].counted) {
                integration.score += integration.items[i].score;
                integration.max_score += integration.items[i].max_score;
            }
        total += integration.score;
        max_total += integration.max_score;
        char idir[4200];
        fmt(idir, sizeof idir, "%s/integration", g.out);
        mkdirs(idir);
        as[k++] = integration;
    } else {
        free(integration.items);
        free(integration.id);
        free(integration.title);
    }
    double t_out = now_s();
    bool written = write_outputs(&g, as, k, total, max_total);
    profile("reports written", "all", t_out);
    print_table(&g, as, k, total, max_total);
    /* Freed although the process ends: the sanitizer CI step runs this tool
     * and counts any leak as a failure. */
    assignment_results_free(as, k);
    cJSON_Delete(g.rubric);
    cJSON_Delete(g.drawn);
    free(g.notes);
    for (int i = 0; i < g.n_failed; i++)
        free((char *)g.failed_hw[i]);
    if (!written) {
        fprintf(stderr, "raster101-grade: the reports in %s could not all be written (see "
                        "above); the grade is not complete\n",
                g.out);
        return 2;
    }
    if (expect) {
        double want = !strcmp(expect, "full") ? max_total : atof(expect);
        if (fabs(total - want) > 1e-9 || max_total <= 0) {
            fprintf(stderr, "raster101-grade: expected %s (%g points), got %g / %g\n", expect, want,
                    total, max_total);
            return 1;
        }
    }
    return 0;
}
