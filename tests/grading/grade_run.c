/* grade_run.c — how raster101-grade runs things (grade_run.h): processes
 * with their limits, the batch of jobs, the sandbox's command lines, the
 * tests' chunks.
 */
#include "grade_run.h"

#include "grade_text.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/personality.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

/* ---------------------------------------------------------------- processes */

/* Runs argv in its own process group with stdout+stderr captured through a
 * pipe (at most OUTPUT_CAP bytes kept, the rest read and dropped, so a flood
 * costs neither disk nor memory) and written to out_path; the
 * NULL-terminated "NAME=value" pairs of env added, a wall-clock limit and an
 * address-space limit (MB, 0 = none). Kills the whole group at the limit. */
#define OUTPUT_CAP (48 * 1024)
run_result run_limited(char *const argv[], const char *const env[], const char *out_path,
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
        /* Without address-space randomisation, as the sandbox runs student
         * code (tests/grading/sandbox): set here, where it costs a system
         * call, the sandbox keeps it and saves a setarch process a run. Only
         * this child: the grader itself, which decodes what student code
         * wrote, keeps its randomisation. */
        int persona = personality(0xffffffff);
        if (persona != -1) personality((unsigned long)persona | ADDR_NO_RANDOMIZE);
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
    bool done = false, pipe_open = true;
    /* The run's end wakes the wait (a pidfd), as its output does: no tick
     * of a clock between a run's end and the next one's start. Without
     * pidfds (Linux < 5.3) a 5 ms poll stands in. */
#ifdef SYS_pidfd_open
    int pidfd = (int)syscall(SYS_pidfd_open, pid, 0);
#else
    int pidfd = -1;
#endif
    for (;;) {
        char chunk[16384];
        ssize_t n = -1;
        while (pipe_open && (n = read(pipefd[0], chunk, sizeof chunk)) > 0) {
            size_t room = kept.len < OUTPUT_CAP ? OUTPUT_CAP - kept.len : 0;
            size_t take = (size_t)n < room ? (size_t)n : room;
            if (take) sb_addn(&kept, chunk, take);
            dropped += (size_t)n - take;
        }
        if (n == 0) pipe_open = false; /* every writer gone: only the end is left to wait for */
        if (done) break;
        pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid) {
            done = true; /* one more read for what is left in the pipe */
            continue;
        }
        if (w < 0 && errno != EINTR) break;
        double left = limit_s - (now_s() - t0);
        if (left <= 0) {
            kill(-pid, SIGKILL);
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            r.kind = RUN_TIMEOUT;
            break;
        }
        struct pollfd pfd[2] = {{pipe_open ? pipefd[0] : -1, POLLIN, 0}, {pidfd, POLLIN, 0}};
        int wait_ms = pidfd >= 0 ? (int)(left * 1000) + 1 : 5;
        poll(pfd, 2, wait_ms);
    }
    if (pidfd >= 0) close(pidfd);
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

/* RAS_GRADE_PROFILE=1: one line per run of a batch, named by its log
 * (a test chunk's worker or replay, a picture's render), with its own
 * clock: where a batch's seconds go (tests/bench/bench-feedback). */
static void profile_job(const job *j) {
    const char *name = strrchr(j->out_path, '/');
    name = name ? name + 1 : j->out_path;
    char what[80];
    fmt(what, sizeof what, "run %s", name);
    profile_seconds(what, "job", j->rr.seconds);
}

/* Runs the jobs, `parallel` at a time, each through run_limited in a child
 * of the grader that hands back its run_result through a pipe. */
void run_jobs(job *jobs, int n, int parallel) {
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
                    if (j->after) j->after(j, j->between_arg);
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
                profile_job(&jobs[i]);
                if (jobs[i].then) {
                    jobs[i].then->rr = (run_result){RUN_NOT_STARTED, 0, 0};
                    if (read(fds[i], &rr, sizeof rr) == (ssize_t)sizeof rr) jobs[i].then->rr = rr;
                    profile_job(jobs[i].then);
                }
                close(fds[i]);
                pids[i] = 0;
                active--;
            }
    }
    free(pids);
    free(fds);
}

const char *signal_text(int sig) {
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

/* How a sandboxed run ended, in words (bwrap reports a signal as 128+N), in
 * the form tests/unit/ras_test_main.h writes a test's fate, so that fate_parse
 * reads both the same way. */
void fate_text(run_result rr, double limit, char *buf, size_t size) {
    int sig = rr.kind == RUN_SIGNALED                                   ? rr.code
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

/* The words of tests/unit/ras_test_main.h's NAME.fate back into a run_result. */
run_result fate_parse(const char *fate) {
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

/* ---------------------------------------------------------------- limits */

/* Time limits (issue 26): a test may use test_time_limit_s of processor time
 * (tests/unit/ras_test_main.h sets it as the test process's RLIMIT_CPU), so a
 * loaded machine, which slows a test down but does not make it compute more,
 * never costs a point. The clock is only a backstop, for a test that waits
 * instead of computing: test_wall_limit_s, by default six times the processor
 * limit and at least a minute. */
double wall_backstop(double cpu_s) { return 6 * cpu_s > 60 ? 6 * cpu_s : 60; }

double test_wall(const grader *g) {
    return num_or(g->rubric, "test_wall_limit_s", wall_backstop(g->test_limit));
}

/* ---------------------------------------------------------------- the sandbox */

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
int sandbox_job(const grader *g, job *j, double limit_s, const char *const env[]) {
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

/* The assignments each graded one builds on, "hw2=1,hw3=12": hwN=K... (the
 * numbers K of its DEPENDS, transitively, earliest first), compiled in by
 * tests/grading/CMakeLists.txt from the assignments' CMake declarations, the
 * same chains its own-code links (raster101_own) are made from. */
#ifndef RAS_GRADE_CHAINS
#define RAS_GRADE_CHAINS ""
#endif

bool own_chain(const char *id, char *digits, size_t size) {
    if (size) digits[0] = '\0';
    size_t n = strlen(id);
    for (const char *c = RAS_GRADE_CHAINS; *c;) {
        const char *end = strchr(c, ',');
        size_t len = end ? (size_t)(end - c) : strlen(c);
        if (len > n && !strncmp(c, id, n) && c[n] == '=') {
            fmt(digits, size, "%.*s", (int)(len - n - 1), c + n + 1);
            return digits[0] != '\0';
        }
        c += len + (end ? 1 : 0);
    }
    return false;
}

bool own_chain_has(const char *id, const char *other) {
    char chain[32];
    int k = 0;
    return own_chain(id, chain, sizeof chain) && other && sscanf(other, "hw%d", &k) == 1 &&
           k >= 1 && k <= 9 && strchr(chain, '0' + k) != NULL;
}

/* Whose code a grade measures (docs/grading.md): hwN is graded on its own
 * code, linked with the reference of the assignments it builds on (its
 * chain, own_chain), when tests/grading/grade could link it (--own). The
 * folder of such a link is OWN/ref followed by their numbers ("ref12" for
 * hw3); `refs` names the assignments taken from the reference ("1", "12";
 * NULL: every one it builds on). False when there is none: then the
 * student's whole chain is graded. */
bool own_dir(const grader *g, const char *id, const char *refs, char *dir, size_t size) {
    char all[32];
    if (size) dir[0] = '\0'; /* "" when there is none: callers print it */
    if (!g->own || !own_chain(id, all, sizeof all)) return false;
    fmt(dir, size, "%s/ref%s", g->own, refs ? refs : all);
    if (is_dir(dir)) return true;
    dir[0] = '\0';
    return false;
}

/* ---------------------------------------------------------------- dealing the tests */

/* How many of the n tests chunk_of gives to `chunk`. */
int chunk_size(int n, const int *chunk_of, int chunk) {
    int size = 0;
    for (int i = 0; i < n; i++)
        size += chunk_of[i] == chunk;
    return size;
}

/* The names of `chunk`, one a line, in the test program's order, into path. */
void write_chunk_list(const char *path, const name_list *names, const int *chunk_of, int chunk) {
    FILE *lf = fopen(path, "w");
    for (int i = 0; i < names->n && lf; i++)
        if (chunk_of[i] == chunk) fprintf(lf, "%s\n", names->v[i]);
    if (lf) fclose(lf);
}

/* The rubric's measured cost of each test of assignment `id` (its
 * "test_costs_ms", tests/grading/measure-test-costs), into cost[0, n); a test
 * it does not name costs the mean of those it does (1 when it names none),
 * so a test added since the last measurement is dealt as a typical one.
 * Every test costs at least 1 ms (its process's start): with nothing to
 * weigh, the chunks still get a test each. */
static void test_costs(const grader *g, const char *id, const name_list *names, double *cost) {
    const cJSON *asgs = cJSON_GetObjectItemCaseSensitive(g->rubric, "assignments"), *costs = NULL;
    for (const cJSON *a = asgs ? asgs->child : NULL; a && !costs; a = a->next)
        if (!strcmp(str_or(a, "id", ""), id))
            costs = cJSON_GetObjectItemCaseSensitive(a, "test_costs_ms");
    double sum = 0;
    int known = 0;
    for (int i = 0; i < names->n; i++) {
        const cJSON *c = cJSON_GetObjectItemCaseSensitive(costs, names->v[i]);
        cost[i] = cJSON_IsNumber(c) && c->valuedouble >= 0 ? c->valuedouble : -1;
        if (cost[i] >= 0 && cost[i] < 1) cost[i] = 1;
        if (cost[i] >= 0) {
            sum += cost[i];
            known++;
        }
    }
    for (int i = 0; i < names->n; i++)
        if (cost[i] < 0) cost[i] = known ? sum / known : 1;
}

/* Deals assignment id's tests (names) to `chunks` chunks, chunk_of[i] the
 * chunk of test i: longest processing time first, the costliest test to the
 * chunk with the least so far, so that no chunk holds most of the whole
 * frames while the others idle. The costs are the rubric's, measured on the
 * reference, never the student's own runs: a student's program cannot steer
 * how its tests are grouped, and a rubric groups them the same way at every
 * grading. Ties go to the earlier test and the lower chunk. */
void deal_tests(const grader *g, const char *id, const name_list *names, int chunks,
                int *chunk_of) {
    int n = names->n;
    double *cost = calloc((size_t)n + 1, sizeof *cost);
    double *load = calloc((size_t)chunks + 1, sizeof *load);
    int *order = calloc((size_t)n + 1, sizeof *order);
    if (!cost || !load || !order) abort();
    test_costs(g, id, names, cost);
    /* costliest first, in the program's order among equals (an insertion sort) */
    for (int i = 0; i < n; i++) {
        int k = i;
        for (; k > 0 && cost[order[k - 1]] < cost[i]; k--)
            order[k] = order[k - 1];
        order[k] = i;
    }
    for (int k = 0; k < n; k++) {
        int least = 0;
        for (int c = 1; c < chunks; c++)
            if (load[c] < load[least]) least = c;
        chunk_of[order[k]] = least;
        load[least] += cost[order[k]];
    }
    free(cost);
    free(load);
    free(order);
}

/* One sandboxed chunk of a test worker (tests/unit/ras_test_main.h, RAS_EACH_*):
 * the names i of `bin` with chunk_of[i] == chunk, each test in a forked child
 * with `per_test` seconds of processor time and `wall` on the clock,
 * recording into the run's own folder, which also gets the list; `own` is
 * bound read-only too ("": none), `extra` adds to the environment (at most 4). */
void worker_job(const grader *g, job *w, const char *bin, const char *own, const name_list *names,
                const int *chunk_of, int chunk, double per_test, double wall,
                const char *const extra[]) {
    char each[5][4300];
    fmt(each[0], sizeof each[0], "RAS_EACH_NAMES=%s/runs/%d/names", g->work, g->runs);
    fmt(each[1], sizeof each[1], "RAS_EACH_OUT=%s/runs/%d", g->work, g->runs);
    fmt(each[2], sizeof each[2], "RAS_EACH_CALLS=%s/runs/%d", g->work, g->runs);
    fmt(each[3], sizeof each[3], "RAS_EACH_LIMIT=%.0f", per_test);
    fmt(each[4], sizeof each[4], "RAS_EACH_WALL=%.0f", wall);
    const char *env[12] = {each[0],
                           each[1],
                           each[2],
                           each[3],
                           each[4],
                           "RAS_EACH_MODE=record",
                           "RAS_RECORD_CAP_MB=256"};
    for (int i = 0; extra && extra[i] && i < 4; i++)
        env[7 + i] = extra[i];
    fmt(w->extra_ro, sizeof w->extra_ro, "%s", own);
    /* the chunk's own backstop: every test at its wall-clock limit */
    int k = sandbox_job(g, w, chunk_size(names->n, chunk_of, chunk) * (wall + 1) + 20, env);
    w->argv[k++] = (char *)bin;
    w->argv[k] = NULL;
    char list_path[4200];
    fmt(list_path, sizeof list_path, "%s/names", w->rw);
    write_chunk_list(list_path, names, chunk_of, chunk);
}

/* The sandboxed run of an image's program: -o into its own run folder.
 * `own`: an own-code link holding the program (then also bound read-only);
 * NULL: the student's build (the whole chain). `tag` names the log. */
void image_job(const grader *g, const cJSON *img, job *j, const char *own, const char *tag) {
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
    /* the log in the work folder, where no sandboxed run writes: a sealed
     * run's output is never handed out, and OUT holds only what the report
     * shows (it quotes what the program printed) */
    char logs[4200];
    fmt(logs, sizeof logs, "%s/logs", g->work);
    trusted_dir(logs);
    fmt(j->out_path, sizeof j->out_path, "%s/%d-%s%s.log", logs, g->runs - 1,
        str_or(img, "name", "image"), tag);
}

/* The trusted reference program, outside the sandbox: `args` as drawn for
 * this grading, -o out_png, and --dump dump_dir unless NULL. */
run_result reference_render(const grader *g, const char *program, const cJSON *args,
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
    /* the clock a backstop, as for the student's renders: a loaded machine
     * slows the reference too, and a reference missing for that would drop
     * the picture or its evidence (issue 42) */
    return run_limited(argv, NULL, log, wall_backstop(g->render_limit), g->mem_mb);
}

void cache_identity(sbuf *key, const char *path) {
    struct stat st;
    if (stat(path, &st) != 0) {
        sb_printf(key, "%s absent\n", path);
        return;
    }
    sb_printf(key, "%s %llu %llu %lld %lld.%09ld %lld.%09ld\n", path, (unsigned long long)st.st_dev,
              (unsigned long long)st.st_ino, (long long)st.st_size, (long long)st.st_mtim.tv_sec,
              st.st_mtim.tv_nsec, (long long)st.st_ctim.tv_sec, st.st_ctim.tv_nsec);
}

void reference_cache_key(const grader *g, const char *kind, const char *program, const cJSON *args,
                         sbuf *key, char *entry, size_t size) {
    char module[4200];
    /* the references' cache keeps its first key text (its entries stay valid) */
    if (!strcmp(kind, "references"))
        sb_add(key, "raster101 reference cache 1\n");
    else
        sb_printf(key, "raster101 reference cache 1 %s\n", kind);
    cache_identity(key, program);
    fmt(module, sizeof module, "%s/bin/libraster101_cv.so", g->build);
    cache_identity(key, module);
    for (const cJSON *v = args ? args->child : NULL; v; v = v->next)
        if (cJSON_IsString(v)) sb_printf(key, "arg %s\n", v->valuestring);
    unsigned long long h = 1469598103934665603ull;
    for (const char *c = sb_str(key); *c; c++)
        h = (h ^ (unsigned char)*c) * 1099511628211ull;
    fmt(entry, size, "%s/grade-cache/%s/%016llx", g->build, kind, h);
}

/* ---------------------------------------------------------------- the tests' chunks */

/* What the trusted replay of a chunk reads comes through sandbox_take: each
 * test's record (NAME.calls) and fate (NAME.fate) copied from the worker's
 * folder into `calls_dir`, a folder of the work folder no sandboxed run can
 * write, which the replay is given (RAS_EACH_CALLS) instead of the worker's.
 * A test whose process never wrote a fate (the whole worker died or was
 * stopped), or wrote one that is refused, gets the worker's own end, there
 * and in the worker's folder (grade_tests.c reads it there through
 * read_small). Run between a chunk's worker and its replay (job.between), in
 * run_jobs' child, when no sandboxed process of the worker is left. */
typedef struct chunk_fates {
    const name_list *names;
    const int *chunk_of; /* test i is the chunk's when chunk_of[i] == chunk */
    int chunk;
    const char *xml_dir;
    char calls_dir[4200];
} chunk_fates;

/* The record cap (RAS_RECORD_CAP_MB) and its header. */
#define RECORD_MAX (((size_t)256 << 20) + 4096)

/* `fate` written new as `name` in the folder dir_fd (never through a link). */
static void write_fate(int dir_fd, const char *name, const char *fate) {
    unlinkat(dir_fd, name, 0);
    int fd = openat(dir_fd, name, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) return;
    ssize_t w = write(fd, fate, strlen(fate)); /* short: a shorter fate, still a failure */
    (void)w;
    close(fd);
}

/* The replay has read them: the copies go (a chunk's records can be hundreds of MB). */
static void records_done(const job *w, void *arg) {
    (void)w;
    remove_tree(((const chunk_fates *)arg)->calls_dir);
}

static void worker_fates(const job *w, void *arg) {
    const chunk_fates *cf = arg;
    char why[300];
    int rw = sandbox_dir(w->rw, why, sizeof why);
    int calls = open(cf->calls_dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    for (int i = 0; i < cf->names->n; i++) {
        if (cf->chunk_of[i] != cf->chunk) continue;
        const char *test = cf->names->v[i];
        char name[4300], dest[8600], fate[300], own_end[200];
        fmt(name, sizeof name, "%s.calls", test);
        fmt(dest, sizeof dest, "%s/%s", cf->calls_dir, name);
        if (rw >= 0) sandbox_take(rw, name, dest, RECORD_MAX, why, sizeof why);
        fmt(name, sizeof name, "%s.fate", test);
        fmt(dest, sizeof dest, "%s/%s", cf->calls_dir, name);
        if (rw < 0 || !sandbox_take(rw, name, dest, 4096, why, sizeof why)) {
            fate_text(w->rr, w->limit, own_end, sizeof own_end);
            fmt(fate, sizeof fate, "(the whole test program) %s", own_end);
            if (rw >= 0) write_fate(rw, name, fate);
            if (calls >= 0) write_fate(calls, name, fate);
        }
        char xml_path[4400];
        fmt(xml_path, sizeof xml_path, "%s/%s.xml", cf->xml_dir, test);
        unlink(xml_path);
    }
    if (rw >= 0) close(rw);
    if (calls >= 0) close(calls);
}

static void tests_jobs(const grader *g, const char *id, test_batch *b);

/* A new batch of a's tests: its verdicts' folder DIR/XML, the trusted
 * replay, and the worker of the student's own build (the whole chain). */
static void batch_begin(const grader *g, const assignment_result *a, const char *dir,
                        const char *xml, test_batch *b) {
    memset(b, 0, sizeof *b);
    fmt(b->xml_dir, sizeof b->xml_dir, "%s/%s", dir, xml);
    mkdirs(b->xml_dir);
    fmt(b->replay_bin, sizeof b->replay_bin, "%s/tests/test_%s_replay", g->build, a->id);
    fmt(b->worker_bin, sizeof b->worker_bin, "%s/tests/test_%s_worker", g->student_build, a->id);
}

bool tests_prepare(const grader *g, assignment_result *a, const char *dir, test_batch *b) {
    batch_begin(g, a, dir, "xml", b);
    char out_path[4096], *replay_bin = b->replay_bin, *worker_bin = b->worker_bin;
    char *own = b->own;
    /* On its own code: the worker linked with the earlier references. It holds
     * reference code, so it is sealed: what it printed is not shown. */
    char own_worker[4200];
    if (own_dir(g, a->id, NULL, own, sizeof b->own)) {
        fmt(own_worker, sizeof own_worker, "%s/tests/test_%s_worker", own, a->id);
        if (file_exists(own_worker)) {
            fmt(worker_bin, sizeof b->worker_bin, "%s", own_worker);
            if (!a->note) {
                sbuf n = {0};
                sb_printf(&n,
                          "graded on your %s code alone, with the reference of the earlier "
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
    run_limited(list_argv, list_env, out_path, wall_backstop(30), g->mem_mb); /* (a backstop) */
    char *listing = read_file(out_path, 1 << 20);
    if (!listing || strncmp(listing, "RAS_TEST_LIST\n", 14) != 0) {
        free(listing);
        free(a->note);
        a->note = xstrdup("grader error: the trusted test program could not list its tests");
        fprintf(stderr,
                "raster101-grade: %s could not list its tests (build it: cmake --build %s "
                "--target test_%s_replay)\n",
                replay_bin, g->build, a->id);
        return false;
    }
    b->listing = listing;
    for (char *line = strtok(listing + 14, "\n"); line; line = strtok(NULL, "\n"))
        if (*line) names_add(&b->names, line);
    tests_jobs(g, a->id, b);
    return true;
}

bool tests_prepare_whole_chain(const grader *g, assignment_result *a, const char *dir,
                               const name_list *names, test_batch *b) {
    batch_begin(g, a, dir, "xml-whole-chain", b);
    if (!file_exists(b->worker_bin) || names->n == 0) return false;
    for (int i = 0; i < names->n; i++)
        names_add(&b->names, names->v[i]);
    tests_jobs(g, a->id, b);
    return true;
}

/* b's jobs for its names (b->names, xml_dir, worker_bin, replay_bin, own set),
 * the tests of assignment `id`. */
static void tests_jobs(const grader *g, const char *id, test_batch *b) {
    const char *replay_bin = b->replay_bin, *worker_bin = b->worker_bin;
    const char *xml_dir = b->xml_dir, *own = b->own;
    name_list *names = &b->names;
    int n = names->n;
    /* The tests in `chunks` groups, one sandbox and one process each (a
     * forked child per test inside: tests/unit/ras_test_main.h, RAS_EACH_*),
     * dealt by their measured costs (deal_tests): dealt round-robin, three
     * of hw3's five whole frames fell into one chunk, which ran 2.5 times as
     * long as the other. */
    int chunks = g->jobs < n ? g->jobs : n;
    if (chunks < 1) chunks = 1;
    job *workers = b->workers = calloc((size_t)chunks, sizeof *workers);
    job *replays = b->replays = calloc((size_t)chunks, sizeof *replays);
    int *chunk_of = b->chunk_of = calloc((size_t)n + 1, sizeof *chunk_of);
    chunk_fates *fates = b->fates = calloc((size_t)chunks, sizeof *fates);
    if (!workers || !replays || !chunk_of || !fates) abort();
    b->n = n;
    b->chunks = chunks;
    deal_tests(g, id, names, chunks, chunk_of);
    for (int c = 0; c < chunks; c++) {
        /* 1. the student's code, in the sandbox: each test records what each
         * call of the student's functions returned */
        job *w = &workers[c];
        int in_chunk = chunk_size(n, chunk_of, c);
        worker_job(g, w, worker_bin, own, names, chunk_of, c, g->test_limit, test_wall(g), NULL);
        fmt(w->out_path, sizeof w->out_path, "%s/worker%d.out", xml_dir, c);
        /* 2. the verdicts: the same tests, trusted, on the recorded outputs
         * (the trusted copy of the list: the worker could rewrite its own) */
        job *r = &replays[c];
        fmt(r->store[0], sizeof r->store[0], "%s/names%d", xml_dir, c);
        write_chunk_list(r->store[0], names, chunk_of, c);
        fmt(r->store[1], sizeof r->store[1], "RAS_EACH_NAMES=%s", r->store[0]);
        fmt(r->store[2], sizeof r->store[2], "RAS_EACH_OUT=%s", xml_dir);
        fates[c] = (chunk_fates){names, chunk_of, c, xml_dir, ""};
        /* beside the run folders (their filesystem: the records are linked,
         * not copied), a folder of the trusted side's own */
        fmt(fates[c].calls_dir, sizeof fates[c].calls_dir, "%s/runs/records-%d", g->work,
            g->runs - 1);
        if (!fresh_trusted_dir(fates[c].calls_dir))
            fprintf(stderr,
                    "raster101-grade: cannot make %s: the replay of chunk %d finds no record\n",
                    fates[c].calls_dir, c);
        fmt(r->store[3], sizeof r->store[3], "RAS_EACH_CALLS=%s", fates[c].calls_dir);
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
        r->argv[0] = (char *)replay_bin;
        r->argv[1] = NULL;
        r->limit = in_chunk * (test_wall(g) + 21) + 20;
        r->mem_mb = g->mem_mb;
        fmt(r->out_path, sizeof r->out_path, "%s/replay%d.out", xml_dir, c);
        /* 3. each chunk's replay as soon as its own worker has ended */
        w->then = r;
        w->between = worker_fates;
        w->between_arg = &fates[c];
        w->after = records_done;
    }
}
