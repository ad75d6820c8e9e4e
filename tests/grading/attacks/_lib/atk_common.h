/* ---- atk_common.h: helpers shared by the hostile submissions of tests/grading/attacks/
 * (pasted into each attack's student file by tests/grading/attacks/_lib/assemble when the
 * attacks run, since a submission is one file). libc only, warning-free under -Wall -Wextra.
 *
 * SAFETY. These attacks are meant to be stopped by the grader's sandbox; if the
 * sandbox fails they must not hurt this machine or anyone else's work on it:
 *   - they only write where their own grading run lives: paths named by the
 *     command lines (and working folders) of their ancestors, or of processes
 *     whose command line mentions "raster101-attacks" (the runner's folder), and
 *     /tmp/pwned-RASATK-* marker files; never a search-and-destroy of the disk;
 *   - every process they start is named RASATK_* (prctl) and exits by itself
 *     (forks <= 2000 in total, children and daemons gone after 20-30 s, memory
 *     <= 3 x 1.5 GiB, logs <= ~2 GB);
 *   - they never touch the network.
 * tests/grading/run-attacks restores the instructor files it snapshots if one changes.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define ATK_UNUSED __attribute__((unused))
#define ATK_MAX_DIRS 64
#define ATK_PATH 1024

/* Names this process RASATK_<tag> (15 characters at most, as the kernel keeps them). */
static ATK_UNUSED void atk_name(const char *tag) {
    char comm[16];
    snprintf(comm, sizeof comm, "RASATK_%s", tag);
    prctl(PR_SET_NAME, comm, 0, 0, 0);
}

static ATK_UNUSED void atk_sleep(double s) {
    struct timespec t = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&t, &t) != 0 && errno == EINTR) {}
}

/* Up to max bytes of a file (NUL-terminated), or NULL. */
static ATK_UNUSED char *atk_slurp(const char *path, size_t max, size_t *len) {
    int fd = open(path, O_RDONLY);
    if (fd < 0) return NULL;
    char *buf = malloc(max + 1);
    size_t n = 0;
    if (!buf) {
        close(fd);
        return NULL;
    }
    while (n < max) {
        ssize_t r = read(fd, buf + n, max - n);
        if (r <= 0) break;
        n += (size_t)r;
    }
    close(fd);
    buf[n] = '\0';
    if (len) *len = n;
    return buf;
}

/* How many processes of the machine are named comm... (the floods' and
 * daemons' own limit, so they stay harmless if the sandbox fails). */
static ATK_UNUSED int atk_count_comm(const char *comm) {
    DIR *proc = opendir("/proc");
    struct dirent *e;
    int n = 0;
    while (proc && (e = readdir(proc))) {
        if (atoi(e->d_name) <= 0) continue;
        char p[sizeof e->d_name + 16]; /* "/proc/" NAME "/comm" */
        snprintf(p, sizeof p, "/proc/%s/comm", e->d_name);
        char *t = atk_slurp(p, 31, NULL);
        if (t && !strncmp(t, comm, strlen(comm))) n++;
        free(t);
    }
    if (proc) closedir(proc);
    return n;
}

static ATK_UNUSED int atk_write(const char *path, const void *data, size_t n) {
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0) return -1;
    const char *p = data;
    while (n) {
        ssize_t w = write(fd, p, n);
        if (w <= 0) break;
        p += w;
        n -= (size_t)w;
    }
    close(fd);
    return n ? -1 : 0;
}

/* Replaces path even when it is a running program (write a sibling, rename over). */
static ATK_UNUSED int atk_replace(const char *path, const void *data, size_t n, mode_t mode) {
    char tmp[ATK_PATH + 32];
    snprintf(tmp, sizeof tmp, "%s.RASATK%d", path, (int)getpid());
    if (atk_write(tmp, data, n) == 0) {
        chmod(tmp, mode);
        if (rename(tmp, path) == 0) return 0;
        unlink(tmp);
    }
    return atk_write(path, data, n);
}

static ATK_UNUSED int atk_copy(const char *from, const char *to) {
    size_t n = 0;
    char *d = atk_slurp(from, (size_t)64 << 20, &n);
    if (!d) return -1;
    int r = atk_replace(to, d, n, 0644);
    free(d);
    return r;
}

static ATK_UNUSED int atk_is_dir(const char *p) {
    struct stat st;
    return stat(p, &st) == 0 && S_ISDIR(st.st_mode);
}
static ATK_UNUSED int atk_is_file(const char *p) {
    struct stat st;
    return stat(p, &st) == 0 && S_ISREG(st.st_mode);
}

/* A marker that this attack wrote outside its sandbox (tests/grading/run-attacks looks for it). */
static ATK_UNUSED void atk_pwned(const char *tag, const char *what) {
    char p[256];
    snprintf(p, sizeof p, "/tmp/pwned-RASATK-%s", tag);
    int fd = open(p, O_WRONLY | O_CREAT | O_APPEND, 0666);
    if (fd >= 0) {
        if (write(fd, what, strlen(what)) < 0 || write(fd, "\n", 1) < 0) {}
        close(fd);
    }
}

/* argv of a process: returns argc; argv points into buf. */
static ATK_UNUSED int atk_cmdline(pid_t pid, char *buf, size_t cap, char **argv, int max) {
    char p[64];
    snprintf(p, sizeof p, "/proc/%d/cmdline", (int)pid);
    int fd = open(p, O_RDONLY);
    if (fd < 0) return 0;
    ssize_t n = read(fd, buf, cap - 1);
    close(fd);
    if (n <= 0) return 0;
    buf[n] = '\0';
    int argc = 0;
    for (ssize_t i = 0; i < n && argc < max; i += (ssize_t)strlen(buf + i) + 1)
        argv[argc++] = buf + i;
    return argc;
}

static ATK_UNUSED pid_t atk_parent_of(pid_t pid) {
    char p[64], buf[1024];
    snprintf(p, sizeof p, "/proc/%d/stat", (int)pid);
    int fd = open(p, O_RDONLY);
    if (fd < 0) return 0;
    ssize_t n = read(fd, buf, sizeof buf - 1);
    close(fd);
    if (n <= 0) return 0;
    buf[n] = '\0';
    char *rp = strrchr(buf, ')');
    int ppid = 0;
    char state;
    if (!rp || sscanf(rp + 1, " %c %d", &state, &ppid) != 2) return 0;
    return (pid_t)ppid;
}

/* The value after an option in a process' argv (or NULL). */
static ATK_UNUSED const char *atk_opt(int argc, char **argv, const char *opt) {
    for (int i = 0; i + 1 < argc; i++)
        if (!strcmp(argv[i], opt)) return argv[i + 1];
    return NULL;
}

/* This submission's name: the folder or archive its graders were given
 * (--submission, grade-all's --one), else fallback. */
static ATK_UNUSED void atk_own_name(char *name, size_t cap, const char *fallback) {
    snprintf(name, cap, "%s", fallback);
    for (pid_t p = getppid(); p > 1; p = atk_parent_of(p)) {
        char buf[16384], *argv[256];
        int argc = atk_cmdline(p, buf, sizeof buf, argv, 256);
        const char *s = atk_opt(argc, argv, "--submission");
        if (!s) s = atk_opt(argc, argv, "--one");
        if (s) {
            const char *b = strrchr(s, '/');
            snprintf(name, cap, "%s", b && b[1] ? b + 1 : s);
            return;
        }
    }
}

/* A daemon, started the double-fork way (setsid between): returns 0 in the
 * caller once the middle process is gone, 1 in the daemon, named
 * RASATK_<tag>, its standard streams on /dev/null. */
static ATK_UNUSED int atk_daemonize(const char *tag) {
    pid_t c = fork();
    if (c != 0) {
        if (c > 0) waitpid(c, NULL, 0);
        return 0;
    }
    setsid();
    if (fork() != 0) _exit(0);
    atk_name(tag);
    int devnull = open("/dev/null", O_RDWR);
    if (devnull >= 0) { dup2(devnull, 0); dup2(devnull, 1); dup2(devnull, 2); close(devnull); }
    return 1;
}

/* This process' own -o FILE (image runs), resolved against its cwd. */
static ATK_UNUSED int atk_own_output(char *out, size_t cap) {
    char buf[8192], *argv[64];
    int argc = atk_cmdline(getpid(), buf, sizeof buf, argv, 64);
    const char *o = atk_opt(argc, argv, "-o");
    if (!o) o = atk_opt(argc, argv, "--output");
    if (!o) return 0;
    if (o[0] == '/') {
        snprintf(out, cap, "%s", o);
    } else {
        char cwd[ATK_PATH];
        if (!getcwd(cwd, sizeof cwd)) return 0;
        snprintf(out, cap, "%s/%s", cwd, o);
    }
    return 1;
}

/* Is this a test run (cmocka program) rather than an image run? */
static ATK_UNUSED int atk_own_argv0_has(const char *s) {
    char buf[8192], *argv[64];
    int argc = atk_cmdline(getpid(), buf, sizeof buf, argv, 64);
    return argc > 0 && strstr(argv[0], s) != NULL;
}

/* ---- where the grading run lives: folders named by the command lines and
 * working folders of this process' ancestors and of any process whose command
 * line mentions the runner's folder ("raster101-attacks"). */
typedef struct atk_dirs {
    int n;
    char v[ATK_MAX_DIRS][ATK_PATH];
} atk_dirs;

static ATK_UNUSED void atk_dirs_add(atk_dirs *d, const char *path) {
    if (!path || !*path || d->n >= ATK_MAX_DIRS) return;
    char real[ATK_PATH];
    if (!realpath(path, real)) return;
    if (!atk_is_dir(real)) return;
    if (!strchr(real + 1, '/')) return; /* never a whole top-level folder (/tmp, /work, /root) */
    for (int i = 0; i < d->n; i++)
        if (!strcmp(d->v[i], real)) return;
    snprintf(d->v[d->n++], ATK_PATH, "%s", real);
}

static ATK_UNUSED void atk_dirs_of_process(atk_dirs *d, pid_t pid) {
    char buf[16384], *argv[256], p[64], cwd[ATK_PATH];
    snprintf(p, sizeof p, "/proc/%d/cwd", (int)pid);
    ssize_t n = readlink(p, cwd, sizeof cwd - 1);
    if (n > 0) {
        cwd[n] = '\0';
        atk_dirs_add(d, cwd);
    } else {
        cwd[0] = '\0';
    }
    int argc = atk_cmdline(pid, buf, sizeof buf, argv, 256);
    for (int i = 0; i < argc; i++) {
        char full[ATK_PATH * 2];
        const char *a = argv[i];
        if (a[0] == '-') continue;
        if (a[0] != '/' && cwd[0]) {
            snprintf(full, sizeof full, "%s/%s", cwd, a);
            a = full;
        }
        if (atk_is_dir(a)) {
            atk_dirs_add(d, a);
        } else if (atk_is_file(a)) { /* a script or program: its folder, and its tree */
            char dir[ATK_PATH * 2];
            snprintf(dir, sizeof dir, "%s", a);
            char *slash = strrchr(dir, '/');
            if (slash) {
                *slash = '\0';
                atk_dirs_add(d, dir);
                strncat(dir, "/..", sizeof dir - strlen(dir) - 1);
                atk_dirs_add(d, dir);
            }
        }
    }
}

static ATK_UNUSED void atk_find_dirs(atk_dirs *d) {
    d->n = 0;
    for (pid_t p = getppid(); p > 1; p = atk_parent_of(p))
        atk_dirs_of_process(d, p);
    DIR *proc = opendir("/proc");
    struct dirent *e;
    while (proc && (e = readdir(proc))) {
        int pid = atoi(e->d_name);
        if (pid <= 1 || pid == getpid()) continue;
        char buf[16384], *argv[256];
        int argc = atk_cmdline(pid, buf, sizeof buf, argv, 256);
        for (int i = 0; i < argc; i++)
            if (strstr(argv[i], "raster101-attacks")) {
                atk_dirs_of_process(d, pid);
                break;
            }
    }
    if (proc) closedir(proc);
}

/* May this attack write here? Only inside its own grading run (see SAFETY). */
static ATK_UNUSED int atk_in_scope(const atk_dirs *d, const char *path) {
    if (strstr(path, "raster101-attacks") || strstr(path, "RASATK")) return 1;
    for (int i = 0; i < d->n; i++) {
        size_t k = strlen(d->v[i]);
        if (!strncmp(path, d->v[i], k) && (path[k] == '/' || path[k] == '\0')) return 1;
    }
    return 0;
}
/* ---- finding the reference image of this image run (reading only) ---- */

/* The rubric's image name for this run: from the -o file name (NAME.png,
 * NAME.got.png) or, failing that, from the arguments. */
static ATK_UNUSED int atk_image_name(char *name, size_t cap) {
    char out[ATK_PATH];
    if (atk_own_output(out, sizeof out)) {
        const char *b = strrchr(out, '/');
        b = b ? b + 1 : out;
        if (!strncmp(b, "hw", 2)) {
            snprintf(name, cap, "%s", b);
            char *dot = strchr(name, '.');
            if (dot) *dot = '\0';
            return 1;
        }
    }
    char buf[8192], *argv[64];
    int argc = atk_cmdline(getpid(), buf, sizeof buf, argv, 64);
    if (argc < 1) return 0;
    const char *r = atk_opt(argc, argv, "-r"), *aa = atk_opt(argc, argv, "--aa");
    const char *sh = atk_opt(argc, argv, "--shader"), *pat = atk_opt(argc, argv, "--sample-pattern");
    if (strstr(argv[0], "hw1")) {
        if (atk_opt(argc, argv, "--axis")) snprintf(name, cap, "hw1_axis_y60");
        else snprintf(name, cap, "hw1_r%s", r ? r : "20");
    } else if (strstr(argv[0], "hw2")) {
        if (!aa) snprintf(name, cap, "hw2_1x");
        else snprintf(name, cap, "hw2_%s4%s", aa, pat ? "_standard" : "");
    } else if (strstr(argv[0], "hw3")) {
        snprintf(name, cap, "hw3_%s", sh ? sh : "phong");
    } else {
        return 0;
    }
    return 1;
}

static ATK_UNUSED int atk_try_ref(const char *dir, const char *name, const char *own, char *found,
                                  size_t cap) {
    static const char *pats[] = {"%s/%s.expected.png", "%s/%s.png", "%s/tests/reference/%s.png",
                                 "%s/reference/%s.png", "%s/refs/%s.png"};
    for (size_t i = 0; i < sizeof pats / sizeof pats[0]; i++) {
        char p[ATK_PATH * 2];
        snprintf(p, sizeof p, pats[i], dir, name);
        char real[ATK_PATH];
        if (!atk_is_file(p) || !realpath(p, real)) continue;
        if (own && !strcmp(real, own)) continue;
        snprintf(found, cap, "%s", real);
        return 1;
    }
    return 0;
}

static ATK_UNUSED int atk_try_up(const char *start, const char *name, const char *own, char *found,
                                 size_t cap, int levels) {
    char d[ATK_PATH];
    snprintf(d, sizeof d, "%s", start);
    for (int l = 0; l <= levels && d[0]; l++) {
        if (atk_try_ref(d, name, own, found, cap)) return 1;
        char *s = strrchr(d, '/');
        if (!s || s == d) break;
        *s = '\0';
    }
    return 0;
}

static ATK_UNUSED int atk_scan_tree(const char *dir, const char *name, const char *own, char *found,
                                    size_t cap, int depth) {
    if (atk_try_ref(dir, name, own, found, cap)) return 1;
    if (depth <= 0) return 0;
    DIR *dp = opendir(dir);
    struct dirent *e;
    int ok = 0;
    while (!ok && dp && (e = readdir(dp))) {
        if (e->d_name[0] == '.' || !strcmp(e->d_name, "proc")) continue;
        char sub[ATK_PATH];
        snprintf(sub, sizeof sub, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(sub, &st) == 0 && S_ISDIR(st.st_mode))
            ok = atk_scan_tree(sub, name, own, found, cap, depth - 1);
    }
    if (dp) closedir(dp);
    return ok;
}

/* Looks for the reference of image `name` next to / above the -o file, in the
 * folders of every visible process (cwd, arguments), in environment
 * variables, in /work and /tmp. */
static ATK_UNUSED int atk_find_reference(const char *name, char *found, size_t cap) {
    char out[ATK_PATH], own[ATK_PATH] = "";
    if (atk_own_output(out, sizeof out)) {
        char *s = strrchr(out, '/');
        if (s) *s = '\0';
        if (atk_try_up(out, name, NULL, found, cap, 5)) return 1;
    }
    (void)own;
    static const char *envs[] = {"RAS_SOURCE_DIR", "RAS_REFERENCE_DIR", "RAS_ROOT", "PWD", "OLDPWD",
                                 "HOME", "SRC", "SOURCE_DIR"};
    for (size_t i = 0; i < sizeof envs / sizeof envs[0]; i++) {
        const char *v = getenv(envs[i]);
        if (v && *v && atk_try_up(v, name, NULL, found, cap, 3)) return 1;
    }
    DIR *proc = opendir("/proc");
    struct dirent *e;
    while (proc && (e = readdir(proc))) {
        int pid = atoi(e->d_name);
        if (pid <= 0) continue;
        char p[64], cwd[ATK_PATH];
        snprintf(p, sizeof p, "/proc/%d/cwd", pid);
        ssize_t n = readlink(p, cwd, sizeof cwd - 1);
        if (n > 0) {
            cwd[n] = '\0';
            if (atk_try_up(cwd, name, NULL, found, cap, 3)) {
                closedir(proc);
                return 1;
            }
        }
        char buf[16384], *argv[256];
        int argc = atk_cmdline(pid, buf, sizeof buf, argv, 256);
        for (int i = 0; i < argc; i++) {
            if (argv[i][0] != '/') continue;
            if (atk_try_up(argv[i], name, NULL, found, cap, 3)) {
                closedir(proc);
                return 1;
            }
        }
    }
    if (proc) closedir(proc);
    if (atk_scan_tree("/work", name, NULL, found, cap, 3)) return 1;
    if (atk_scan_tree("/tmp", name, NULL, found, cap, 4)) return 1;
    if (atk_scan_tree("/autograder", name, NULL, found, cap, 3)) return 1;
    return 0;
}

/* dir/rel readable for some dir at most `depth` levels below root? (text) */
static ATK_UNUSED char *atk_scan_for(const char *root, const char *rel, int depth) {
    char p[ATK_PATH * 2];
    snprintf(p, sizeof p, "%s/%s", root, rel);
    char *t = atk_slurp(p, 1 << 20, NULL);
    if (t || depth <= 0) return t;
    DIR *dp = opendir(root);
    struct dirent *e;
    while (!t && dp && (e = readdir(dp))) {
        if (e->d_name[0] == '.' || !strcmp(e->d_name, "proc") || !strcmp(e->d_name, "sys")) continue;
        snprintf(p, sizeof p, "%s/%s", root, e->d_name);
        struct stat st;
        if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode)) t = atk_scan_for(p, rel, depth - 1);
    }
    if (dp) closedir(dp);
    return t;
}

/* Text of the first readable file among the candidates for a solution file
 * `rel` (e.g. "hw1_transform/solution/transform.c"): the usual places, the
 * folders of the processes around, then any copy of the tree within three
 * levels of /tmp, /work, /home, /srv, /opt, /root, /autograder. */
static ATK_UNUSED char *atk_find_solution(const char *rel) {
    char p[ATK_PATH * 2];
    atk_dirs d;
    atk_find_dirs(&d);
    static const char *fixed[] = {"/work/main", "/autograder/source", "..", "../..", "../../.."};
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++) {
        snprintf(p, sizeof p, "%s/%s", fixed[i], rel);
        char *t = atk_slurp(p, 1 << 20, NULL);
        if (t) return t;
    }
    for (int i = 0; i < d.n; i++)
        for (int up = 0; up < 3; up++) {
            snprintf(p, sizeof p, "%s/%s%s", d.v[i], up == 0 ? "" : up == 1 ? "../" : "../../", rel);
            char *t = atk_slurp(p, 1 << 20, NULL);
            if (t) return t;
        }
    static const char *roots[] = {"/tmp", "/work", "/home", "/srv", "/opt", "/root", "/autograder"};
    for (size_t i = 0; i < sizeof roots / sizeof roots[0]; i++) {
        char *t = atk_scan_for(roots[i], rel, 3);
        if (t) return t;
    }
    return NULL;
}
/* ---- faking a passing test run (the worker's output decides nothing) ---- */

/* hw1's tests as the rubric names them. */
static ATK_UNUSED const char *atk_hw1_tests[] = {
    "test_model_matrix_zero_is_identity", "test_model_matrix_90_turns_x_into_y",
    "test_model_matrix_minus_30", "test_model_matrix_360_is_identity",
    "test_projection_matches_hand_worked_matrix", "test_projection_classic_maps_frustum_to_cube",
    "test_projection_respects_aspect", "test_rotation_about_z_matches_model_matrix",
    "test_rotation_normalises_axis", "test_rotation_about_diagonal_cycles_axes",
    "test_rotation_composes"};

/* cmocka's console lines for a passing run of the test filter names (when
 * the grader runs one test), else of all hw1's tests, and the matching JUnit
 * XML at $CMOCKA_XML_FILE. */
static ATK_UNUSED void atk_fake_passing_run(const char *filter) {
    const char *one[1] = {filter};
    const char **names = filter ? one : atk_hw1_tests;
    size_t count = filter ? 1 : sizeof atk_hw1_tests / sizeof atk_hw1_tests[0];
    printf("[==========] hw1: Running %zu test(s).\n", count);
    for (size_t i = 0; i < count; i++) printf("[ RUN      ] %s\n[       OK ] %s\n", names[i], names[i]);
    printf("[==========] hw1: %zu test(s) run.\n[  PASSED  ] %zu test(s).\n", count, count);
    const char *xml = getenv("CMOCKA_XML_FILE");
    if (xml) {
        char x[8192];
        int len = snprintf(x, sizeof x,
                           "<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<testsuites>\n"
                           "  <testsuite name=\"hw1\" time=\"0.000\" tests=\"%zu\" failures=\"0\" "
                           "errors=\"0\" skipped=\"0\" >\n", count);
        for (size_t i = 0; i < count && len < 7000; i++)
            len += snprintf(x + len, sizeof x - (size_t)len,
                            "    <testcase name=\"%s\" time=\"0.001\" >\n    </testcase>\n", names[i]);
        len += snprintf(x + len, sizeof x - (size_t)len, "  </testsuite>\n</testsuites>\n");
        atk_write(xml, x, (size_t)len);
    }
}

/* A JUnit XML file at path that says the one test name passed. */
static ATK_UNUSED void atk_fake_xml_one(const char *path, const char *name) {
    char x[2048];
    int n = snprintf(x, sizeof x,
                     "<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<testsuites>\n"
                     "  <testsuite name=\"hw1\" time=\"0.000\" tests=\"1\" failures=\"0\" "
                     "errors=\"0\" skipped=\"0\" >\n    <testcase name=\"%s\" time=\"0.000\" >\n"
                     "    </testcase>\n  </testsuite>\n</testsuites>\n", name);
    atk_write(path, x, (size_t)n);
}

/* The constructor attacks' move: the reference image of this run's picture
 * (beside or above -o, or anywhere readable) copied over -o, said, then exit 0
 * before main. */
static ATK_UNUSED void atk_copy_reference_and_exit(const char *tag) {
    atk_name(tag);
    char out[ATK_PATH], name[256], ref[ATK_PATH];
    if (atk_own_output(out, sizeof out) && atk_image_name(name, sizeof name) &&
        atk_find_reference(name, ref, sizeof ref)) {
        atk_copy(ref, out);
        printf("copied %s\n", ref);
    }
    fflush(stdout);
    _exit(0);
}
/* ---- end of atk_common.h */
