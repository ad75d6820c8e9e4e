/* ras_io.c — see ras_io.h. */
#include "ras_io.h"

#include <dirent.h>   /* opendir, readdir: stale temporaries */
#include <errno.h>    /* errno, EINTR */
#include <fcntl.h>    /* open, fcntl, O_* */
#include <limits.h>   /* PATH_MAX */
#include <pthread.h>  /* pthread_mutex_t: one write at a time */
#include <signal.h>   /* sigaction, sigprocmask, raise */
#include <stdio.h>    /* snprintf, rename */
#include <stdlib.h>   /* malloc, free, mkstemp, realpath */
#include <string.h>   /* strerror, strrchr, memcmp */
#include <strings.h>  /* strncasecmp */
#include <time.h>     /* time_t */
#include <sys/stat.h> /* fstat, lstat, umask, fchmod */
#include <sys/syscall.h> /* SYS_getdents64: a folder listed inside a handler */
#include <sys/vfs.h>  /* fstatfs: is the file in memory */
#include <unistd.h>   /* read, write, close, fsync, unlink */

/* statfs's f_type of the filesystems that live in memory (linux/magic.h) */
#define RAS_IO_TMPFS_MAGIC 0x01021994
#define RAS_IO_RAMFS_MAGIC 0x858458f6

static const char *file_type_name(mode_t mode) {
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

int ras_io_open_input(const char *path, char *why, size_t why_size) {
    /* O_NONBLOCK: opening a FIFO (or a tty, a tape) must not wait. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        snprintf(why, why_size, "%s", strerror(errno));
        return -1;
    }
    struct stat st;
    if (fstat(fd, &st) != 0) {
        snprintf(why, why_size, "%s", strerror(errno));
        close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        snprintf(why, why_size, "expected a regular file, got %s", file_type_name(st.st_mode));
        close(fd);
        return -1;
    }
    int flags = fcntl(fd, F_GETFL);
    if (flags >= 0) fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    return fd;
}

/* Reads exactly n bytes unless the file ends first; returns the count, or -1. */
static ssize_t read_full(int fd, void *buf, size_t n) {
    size_t got = 0;
    while (got < n) {
        ssize_t r = read(fd, (char *)buf + got, n - got);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) return -1;
        if (r == 0) break;
        got += (size_t)r;
    }
    return (ssize_t)got;
}

void *ras_io_read_file(const char *path, const char *what, size_t max_bytes, size_t *len,
                       ras_error *err) {
    char why[256];
    int fd = ras_io_open_input(path, why, sizeof why);
    if (fd < 0) {
        ras_error_set(err, "could not read %s '%s': %s; check the path", what, path, why);
        return NULL;
    }
    struct stat st;
    if (fstat(fd, &st) != 0 || st.st_size < 0) {
        ras_error_set(err, "could not read %s '%s': %s", what, path, strerror(errno));
        close(fd);
        return NULL;
    }
    if ((unsigned long long)st.st_size > max_bytes) {
        ras_error_set(err,
                      "could not read %s '%s': expected at most %zu bytes, got %lld; is this the "
                      "right file?",
                      what, path, max_bytes, (long long)st.st_size);
        close(fd);
        return NULL;
    }
    size_t size = (size_t)st.st_size;
    char *buf = malloc(size + 2);
    if (!buf) {
        ras_error_set(err, "could not read %s '%s': out of memory for %zu bytes", what, path,
                      size);
        close(fd);
        return NULL;
    }
    /* One byte past the size: the file may have grown since fstat. */
    ssize_t got = read_full(fd, buf, size + 1);
    int e = errno;
    close(fd);
    if (got < 0) {
        ras_error_set(err, "could not read %s '%s': %s", what, path, strerror(e));
        free(buf);
        return NULL;
    }
    if ((size_t)got > size) {
        ras_error_set(err, "could not read %s '%s': the file grew while it was being read", what,
                      path);
        free(buf);
        return NULL;
    }
    buf[got] = '\0';
    *len = (size_t)got;
    return buf;
}

bool ras_io_path_fits(const char *option, const char *path, ras_error *err) {
    size_t n = strlen(path);
    if (n <= RAS_IO_MAX_PATH) return true;
    return ras_error_set(err,
                         "%s expects a file name of at most %d bytes; got one of %zu bytes "
                         "('%.40s...'); use a shorter (e.g. relative) path",
                         option, RAS_IO_MAX_PATH, n, path);
}

/* ---- atomic writes ---------------------------------------------------- */

/* The temporary file being written, for the signal handler; writes are
 * serialised by g_write_lock, so there is one at a time. */
static char g_tmp[PATH_MAX];
static volatile sig_atomic_t g_tmp_live;
static pthread_mutex_t g_write_lock = PTHREAD_MUTEX_INITIALIZER;
/* The temporary folder a --dump is staged in, for the same handler: a
 * SIGTERM mid-dump must not leave it behind (ras_io_temp_folder_create). */
static char g_tmp_dir[PATH_MAX];
static volatile sig_atomic_t g_tmp_dir_live;

static const int cleanup_signals[] = {SIGINT, SIGTERM, SIGHUP};
#define N_CLEANUP_SIGNALS (sizeof cleanup_signals / sizeof *cleanup_signals)

/* The entries of the flat folder `dir`, then the folder, removed with
 * system calls only (opendir and readdir may allocate: not in a handler). */
static void remove_flat_folder_signal_safe(const char *dir) {
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd >= 0) {
        char buf[4096] __attribute__((aligned(8)));
        long n;
        while ((n = syscall(SYS_getdents64, fd, buf, sizeof buf)) > 0)
            for (long at = 0; at < n;) {
                const struct getdents_entry {
                    unsigned long long ino;
                    long long off;
                    unsigned short reclen;
                    unsigned char type;
                    char name[];
                } *e = (const void *)(buf + at);
                if (strcmp(e->name, ".") && strcmp(e->name, ".."))
                    unlinkat(fd, e->name, 0);
                at += e->reclen;
            }
        close(fd);
    }
    rmdir(dir);
}

static void on_fatal_signal(int sig) {
    if (g_tmp_live) unlink(g_tmp); /* async-signal-safe */
    if (g_tmp_dir_live) remove_flat_folder_signal_safe(g_tmp_dir);
    signal(sig, SIG_DFL);
    raise(sig); /* die as we would have, with the signal's exit status */
}

typedef struct saved_signals {
    struct sigaction old[N_CLEANUP_SIGNALS];
    struct sigaction old_xfsz;
} saved_signals;

static void signals_install(saved_signals *s) {
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_fatal_signal;
    sigemptyset(&sa.sa_mask);
    for (size_t i = 0; i < N_CLEANUP_SIGNALS; i++) {
        sigaction(cleanup_signals[i], NULL, &s->old[i]);
        /* A signal the caller ignores (nohup, a shell's background job)
         * stays ignored. */
        if (s->old[i].sa_handler != SIG_IGN) sigaction(cleanup_signals[i], &sa, NULL);
    }
    sa.sa_handler = SIG_IGN; /* past RLIMIT_FSIZE: EFBIG from write, not a kill */
    sigaction(SIGXFSZ, &sa, &s->old_xfsz);
}

static void signals_restore(const saved_signals *s) {
    for (size_t i = 0; i < N_CLEANUP_SIGNALS; i++)
        sigaction(cleanup_signals[i], &s->old[i], NULL);
    sigaction(SIGXFSZ, &s->old_xfsz, NULL);
}

/* The handlers installed while a temporary folder is held: outside any one
 * write, which installs (and then restores) the same handler over them. */
static saved_signals g_folder_saved;

bool ras_io_temp_folder_create(char *templ) {
    if (g_tmp_dir_live || strlen(templ) >= sizeof g_tmp_dir) {
        errno = EBUSY;
        return false;
    }
    signals_install(&g_folder_saved);
    sigset_t all, old_mask;
    sigfillset(&all);
    /* Blocked while the folder is made and marked live, as for a file. */
    sigprocmask(SIG_BLOCK, &all, &old_mask);
    bool made = mkdtemp(templ) != NULL;
    int e = errno;
    if (made) {
        memcpy(g_tmp_dir, templ, strlen(templ) + 1);
        g_tmp_dir_live = 1;
    }
    sigprocmask(SIG_SETMASK, &old_mask, NULL);
    if (!made) signals_restore(&g_folder_saved);
    errno = e;
    return made;
}

void ras_io_temp_folder_release(void) {
    if (!g_tmp_dir_live) return;
    g_tmp_dir_live = 0;
    signals_restore(&g_folder_saved);
}

void ras_io_cleanup_signals_block(sigset_t *old) {
    sigset_t set;
    sigemptyset(&set);
    for (size_t i = 0; i < N_CLEANUP_SIGNALS; i++) sigaddset(&set, cleanup_signals[i]);
    sigprocmask(SIG_BLOCK, &set, old);
}

static bool write_full(int fd, const void *data, size_t len) {
    size_t done = 0;
    while (done < len) {
        ssize_t w = write(fd, (const char *)data + done, len - done);
        if (w < 0 && errno == EINTR) continue;
        if (w < 0) return false;
        if (w == 0) {
            errno = ENOSPC;
            return false;
        }
        done += (size_t)w;
    }
    return true;
}

/* The temporary name beside `target`: DIR/.NAME-XXXXXX, NAME cut to keep the
 * last component within 255 bytes. False when it does not fit `size`. */
static bool temp_name(const char *target, char *out, size_t size) {
    const char *slash = strrchr(target, '/');
    const char *base = slash ? slash + 1 : target;
    int dir_len = (int)(base - target);
    size_t base_len = strlen(base);
    const size_t max_base = 255 - 1 - 7; /* "." + NAME + "-XXXXXX" */
    if (base_len > max_base) base_len = max_base;
    int n = snprintf(out, size, "%.*s.%.*s-XXXXXX", dir_len, target, (int)base_len, base);
    return n > 0 && (size_t)n < size;
}

/* Reads the file back and compares it with what was meant to be there. */
static bool read_back_matches(const char *tmp, const void *data, size_t len, void **copy) {
    int fd = open(tmp, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    char *buf = malloc(len + 1);
    ssize_t got = buf ? read_full(fd, buf, len + 1) : -1;
    int e = errno;
    close(fd);
    if (got < 0 || (size_t)got != len || memcmp(buf, data, len) != 0) {
        free(buf);
        errno = got < 0 ? e : EIO;
        return false;
    }
    *copy = buf;
    return true;
}

/* ---- write-protected targets, stale temporaries -------------------------- */

static bool g_force; /* --force: replace write-protected files */

void ras_io_set_force(bool force) { g_force = force; }

bool ras_io_check_replace(const char *path, const char *what, ras_error *err) {
    struct stat st;
    if (g_force || stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return true;
    /* No write bit at all (mode 444) means "keep this", even for root, whom
     * access() lets write anything. */
    if ((st.st_mode & 0222) == 0 || access(path, W_OK) != 0)
        return ras_error_set(err,
                             "cannot write %s '%s': it is write-protected (mode %04o); expected "
                             "a file you may replace — pass --force to replace it anyway, or "
                             "write elsewhere",
                             what, path, (unsigned)(st.st_mode & 07777));
    return true;
}

/* When this process started (seconds since the epoch, rounded down), from
 * /proc: a temporary file older than that cannot be one this run, or any
 * writer started after it, is still writing. 0 when unknown. */
time_t ras_io_process_start(void) {
    static time_t start = -1;
    if (start >= 0) return start;
    start = 0;
    FILE *f = fopen("/proc/self/stat", "r");
    char buf[1024];
    size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
    if (f) fclose(f);
    buf[n] = '\0';
    const char *p = strrchr(buf, ')'); /* the name may hold spaces */
    unsigned long long ticks = 0;
    if (p && sscanf(p + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %*u %*u %*d %*d %*d %*d "
                           "%*d %*d %llu", &ticks) == 1) {
        f = fopen("/proc/stat", "r");
        char line[256];
        long long btime = 0;
        while (f && fgets(line, sizeof line, f))
            if (sscanf(line, "btime %lld", &btime) == 1) break;
        if (f) fclose(f);
        long hz = sysconf(_SC_CLK_TCK);
        if (btime > 0 && hz > 0) start = (time_t)(btime + (long long)(ticks / (unsigned long long)hz));
    }
    return start;
}

void ras_io_folder_of(const char *path, char *dir, size_t size) {
    const char *slash = strrchr(path, '/');
    if (!slash) snprintf(dir, size, ".");
    else if (slash == path) snprintf(dir, size, "/");
    else snprintf(dir, size, "%.*s", (int)(slash - path), path);
}

/* Whether `name` is one of ras_io_write_atomic's temporaries: ".NAME-XXXXXX"
 * (six characters mkstemp chooses), NAME ending in an extension the programs
 * write, so no other dotfile ever matches. */
static bool is_our_temporary(const char *name) {
    static const char *const exts[] = {".png", ".jpg", ".jpeg", ".bmp", ".ppm", ".tif", ".tiff",
                                       ".pfm", ".json", ".csv", ".md", ".txt", ".xml", ".html"};
    size_t n = strlen(name);
    if (n < 1 + 2 + 7 || name[0] != '.' || name[n - 7] != '-') return false;
    for (size_t k = n - 6; k < n; k++)
        if (!((name[k] >= 'a' && name[k] <= 'z') || (name[k] >= 'A' && name[k] <= 'Z') ||
              (name[k] >= '0' && name[k] <= '9')))
            return false;
    size_t stem = n - 7; /* ".NAME" */
    for (size_t e = 0; e < sizeof exts / sizeof *exts; e++) {
        size_t el = strlen(exts[e]);
        if (stem > el && !strncasecmp(name + stem - el, exts[e], el)) return true;
    }
    return false;
}

int ras_io_remove_stale_temporaries(const char *dir) {
    time_t start = ras_io_process_start();
    if (!start) return 0;
    DIR *d = opendir(dir);
    if (!d) return 0;
    int removed = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!is_our_temporary(e->d_name)) continue;
        struct stat st;
        /* regular files of ours only, last written before this run began
         * (with a second's margin for the clock's rounding) */
        if (fstatat(dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(st.st_mode) ||
            st.st_uid != geteuid() || st.st_mtime >= start - 1)
            continue;
        if (unlinkat(dirfd(d), e->d_name, 0) == 0) removed++;
    }
    closedir(d);
    return removed;
}

static bool write_atomic_locked(const char *path, const char *what, const void *data,
                                size_t len, ras_io_verify_fn verify, void *ctx, ras_error *err);

bool ras_io_write_atomic(const char *path, const char *what, const void *data, size_t len,
                         ras_io_verify_fn verify, void *ctx, ras_error *err) {
    pthread_mutex_lock(&g_write_lock);
    bool ok = write_atomic_locked(path, what, data, len, verify, ctx, err);
    pthread_mutex_unlock(&g_write_lock);
    return ok;
}

static bool write_atomic_locked(const char *path, const char *what, const void *data,
                                size_t len, ras_io_verify_fn verify, void *ctx, ras_error *err) {
    /* A symbolic link stays a link: write over the file it points to. */
    char resolved[PATH_MAX];
    const char *target = path;
    struct stat lst;
    if (lstat(path, &lst) == 0 && S_ISLNK(lst.st_mode) && realpath(path, resolved))
        target = resolved;
    bool exists = lstat(target, &lst) == 0;
    if (exists && !S_ISREG(lst.st_mode))
        return ras_error_set(err,
                             "could not write %s '%s': expected a regular file or a new name, "
                             "got %s; choose another name",
                             what, path, file_type_name(lst.st_mode));
    if (!ras_io_check_replace(target, what, err)) return false;
    {
        /* Temporaries a kill -9 left in this folder (nothing could remove
         * them then): the next writer does. */
        char folder[PATH_MAX];
        ras_io_folder_of(target, folder, sizeof folder);
        ras_io_remove_stale_temporaries(folder);
    }

    saved_signals saved;
    signals_install(&saved);
    sigset_t all, old_mask;
    sigfillset(&all);
    /* Blocked while the name is made and marked live: a signal in between
     * would otherwise leave the new file behind. */
    sigprocmask(SIG_BLOCK, &all, &old_mask);
    int fd = -1;
    bool named = temp_name(target, g_tmp, sizeof g_tmp);
    if (named) fd = mkstemp(g_tmp);
    int e = errno;
    if (fd >= 0) g_tmp_live = 1;
    sigprocmask(SIG_SETMASK, &old_mask, NULL);
    if (fd < 0) {
        signals_restore(&saved);
        return ras_error_set(err,
                             "could not write %s '%s': %s a temporary file beside it (%s); "
                             "check that the folder exists and is writable",
                             what, path, named ? "cannot create" : "the name is too long for",
                             named ? strerror(e) : "PATH_MAX");
    }
    const char *step = "writing";
    bool ok = false;
    void *copy = NULL;
    /* The replaced file's permissions, or a new file's usual ones. */
    mode_t mask = umask(0);
    umask(mask);
    mode_t mode = exists ? (lst.st_mode & 07777) : (0666 & ~mask);
    if (fchmod(fd, mode) != 0) step = "setting the mode of";
    else if (!write_full(fd, data, len)) step = "writing";
    else if (fsync(fd) != 0 && errno != EINVAL) step = "flushing (fsync)";
    else ok = true;
    e = errno;
    /* A file in memory (tmpfs, ramfs) would read back the very pages just
     * written: the check cannot fail there, and for a 150 MB dump it is a
     * third of the work. */
    struct statfs fs;
    bool in_memory = fstatfs(fd, &fs) == 0 && (fs.f_type == RAS_IO_TMPFS_MAGIC ||
                                                fs.f_type == RAS_IO_RAMFS_MAGIC);
    if (close(fd) != 0 && ok) {
        ok = false;
        e = errno;
        step = "closing";
    }
    if (ok && !in_memory && !read_back_matches(g_tmp, data, len, &copy)) {
        ok = false;
        e = errno;
        step = "reading back";
    }
    if (ok && verify) {
        ras_error verr = {{0}};
        if (!verify(copy ? copy : data, len, ctx, &verr)) {
            free(copy);
            unlink(g_tmp);
            g_tmp_live = 0;
            signals_restore(&saved);
            return ras_error_set(err,
                                 "could not write %s '%s': the file written does not decode "
                                 "(%s); '%s' was left as it was",
                                 what, path, verr.msg, path);
        }
    }
    free(copy);
    if (ok && rename(g_tmp, target) != 0) {
        ok = false;
        e = errno;
        step = "renaming";
    }
    if (!ok) {
        unlink(g_tmp);
        g_tmp_live = 0;
        signals_restore(&saved);
        return ras_error_set(err,
                             "could not write %s '%s': %s (while %s the temporary file); '%s' "
                             "was left as it was — free some space or write elsewhere",
                             what, path, strerror(e), step, path);
    }
    g_tmp_live = 0;
    signals_restore(&saved);
    /* The rename itself reaches the disk when the folder is synced. */
    char dir[PATH_MAX];
    ras_io_folder_of(target, dir, sizeof dir);
    int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
    return true;
}

/* ---- reports -------------------------------------------------------------- */

FILE *ras_io_report_open(ras_io_report *r) {
    r->buf = NULL;
    r->len = 0;
    r->f = open_memstream(&r->buf, &r->len);
    return r->f;
}

bool ras_io_report_commit(ras_io_report *r, const char *path, ras_error *err) {
    bool ok = r->f != NULL;
    if (r->f && (ferror(r->f) || fclose(r->f) != 0)) ok = false;
    r->f = NULL;
    if (!ok && path) ras_error_set(err, "could not write report '%s': out of memory", path);
    else if (path) ok = ras_io_write_atomic(path, "report", r->buf, r->len, NULL, NULL, err);
    free(r->buf);
    r->buf = NULL;
    return ok;
}

/* ---- nesting -------------------------------------------------------------- */

size_t ras_io_text_nesting(const char *text, size_t len, size_t stop, size_t *at) {
    size_t depth = 0, max = 0;
    for (size_t i = 0; i < len; i++) {
        char ch = text[i];
        if (ch == '"') { /* a string: skip it, escapes included */
            for (i++; i < len && text[i] != '"'; i++)
                if (text[i] == '\\') i++;
        } else if (ch == '{' || ch == '[') {
            depth++;
        } else if (ch == '}' || ch == ']') {
            if (depth) depth--;
        } else if (ch == '<' && i + 1 < len) {
            char next = text[i + 1];
            bool open = (next >= 'A' && next <= 'Z') || (next >= 'a' && next <= 'z') ||
                        next == '_' || next == ':';
            if (next == '/' && depth) depth--;
            if (!open) continue;
            /* To the tag's end: <a/> opens and closes. */
            size_t j = i + 1;
            while (j < len && text[j] != '>') j++;
            if (!(j < len && text[j - 1] == '/')) depth++;
            i = j;
        }
        if (depth > max) {
            max = depth;
            if (max > stop) {
                if (at) *at = i;
                return stop + 1;
            }
        }
    }
    return max;
}
