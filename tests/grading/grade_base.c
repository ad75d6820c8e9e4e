/* grade_base.c — raster101-grade's plumbing: strings, files, lists of
 * names, the rubric's lookups, the clock (grade_base.h).
 */
#include "grade_base.h"

#include "ras_io.h" /* ras_io_folder_of */

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* snprintf that cuts silently (paths here are far below the buffer sizes). */
__attribute__((format(printf, 3, 4))) void fmt(char *buf, size_t size, const char *f, ...) {
    va_list ap;
    va_start(ap, f);
    vsnprintf(buf, size, f, ap);
    va_end(ap);
}

/* ---------------------------------------------------------------- strings */

void sb_addn(sbuf *b, const char *s, size_t n) {
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

void sb_add(sbuf *b, const char *s) { sb_addn(b, s, strlen(s)); }

void sb_printf(sbuf *b, const char *fmt, ...) {
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

const char *sb_str(const sbuf *b) { return b->s ? b->s : ""; }

char *xstrdup(const char *s) {
    char *p = strdup(s ? s : "");
    if (!p) abort();
    return p;
}

/* ---------------------------------------------------------------- files */

char *read_file(const char *path, size_t limit) {
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

bool copy_file(const char *from, const char *to) {
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

void mkdirs(const char *path) {
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

bool file_exists(const char *path) { return access(path, F_OK) == 0; }

bool is_dir(const char *path) {
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

void trusted_dir(const char *path) {
    mkdirs(path);
    chmod(path, 0700);
}

bool fresh_trusted_dir(const char *path) {
    if (unlink(path) != 0) remove_tree(path); /* a file or link planted there goes as such */
    struct stat st;
    return mkdir(path, 0700) == 0 && lstat(path, &st) == 0 && S_ISDIR(st.st_mode) &&
           st.st_uid == geteuid();
}

/* Everything under the folder dir_fd (closed here), links removed as links. */
static void remove_under(int dir_fd) {
    DIR *d = fdopendir(dir_fd);
    if (!d) {
        close(dir_fd);
        return;
    }
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        struct stat st;
        if (fstatat(dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
        if (S_ISDIR(st.st_mode)) {
            int sub = openat(dirfd(d), e->d_name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
            if (sub >= 0) remove_under(sub);
            unlinkat(dirfd(d), e->d_name, AT_REMOVEDIR);
        } else
            unlinkat(dirfd(d), e->d_name, 0);
    }
    closedir(d);
}

void remove_tree(const char *path) {
    int fd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd >= 0) remove_under(fd);
    rmdir(path);
}

/* ---------------------------------------------------------------- what the sandbox wrote */

int sandbox_dir(const char *path, char *why, size_t n) {
    int fd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0)
        fmt(why, n, "%s",
            errno == ENOENT ? "the folder does not exist"
            : errno == ELOOP || errno == ENOTDIR
                ? "it is not a folder (a symbolic link or a file stands in its place)"
                : strerror(errno));
    return fd;
}

int sandbox_dir_of(const char *path, const char **name, char *why, size_t n) {
    char dir[4096];
    ras_io_folder_of(path, dir, sizeof dir);
    const char *slash = strrchr(path, '/');
    *name = slash ? slash + 1 : path;
    return sandbox_dir(dir, why, n);
}

int sandbox_open(int dir_fd, const char *name, long long *size, char *why, size_t n) {
    if (!*name || strchr(name, '/') || !strcmp(name, ".") || !strcmp(name, "..")) {
        fmt(why, n, "not a plain file name");
        return -1;
    }
    int fd = openat(dir_fd, name, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        fmt(why, n, "%s",
            errno == ENOENT  ? "it does not exist"
            : errno == ELOOP ? "it is a symbolic link (a file is expected; links are not followed)"
                             : strerror(errno));
        return -1;
    }
    struct stat st;
    const char *bad =
        fstat(fd, &st) != 0 ? "it cannot be examined"
        : !S_ISREG(st.st_mode)
            ? (S_ISDIR(st.st_mode) ? "it is a folder, not a file"
                                   : "it is not a regular file (a FIFO, socket or device)")
        : st.st_nlink != 1 ? "it has more than one name (a hard link)"
                           : NULL;
    if (bad) {
        fmt(why, n, "%s", bad);
        close(fd);
        return -1;
    }
    *size = (long long)st.st_size;
    return fd;
}

int sandbox_check(int dir_fd, const char *name, size_t max_bytes, char *why, size_t n) {
    long long size = 0;
    int in = sandbox_open(dir_fd, name, &size, why, n);
    if (in >= 0 && (unsigned long long)size > max_bytes) {
        fmt(why, n, "it is %lld bytes, over the %zu bytes it may hold", size, max_bytes);
        close(in);
        return -1;
    }
    return in;
}

bool sandbox_take(int dir_fd, const char *name, const char *dest, size_t max_bytes, char *why,
                  size_t n) {
    int in = sandbox_check(dir_fd, name, max_bytes, why, n);
    if (in < 0) return false;
    unlink(dest);
    /* The very inode checked, hard-linked where the folders share a
     * filesystem (a test's record is up to 256 MB; the run is over, so no
     * sandboxed process writes it any more); else copied. */
    char self[64];
    fmt(self, sizeof self, "/proc/self/fd/%d", in);
    if (linkat(AT_FDCWD, self, AT_FDCWD, dest, AT_SYMLINK_FOLLOW) == 0) {
        close(in);
        return true;
    }
    int out = open(dest, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    bool ok = out >= 0;
    size_t copied = 0;
    char buf[65536];
    ssize_t got;
    /* at most max_bytes + 1: a file that grew after fstat is refused too */
    while (ok && (got = read(in, buf, sizeof buf)) > 0) {
        copied += (size_t)got;
        ok = copied <= max_bytes && write(out, buf, (size_t)got) == got;
    }
    close(in);
    if (out >= 0 && close(out) != 0) ok = false;
    if (!ok) {
        fmt(why, n, "%s",
            copied > max_bytes ? "it grew past the size it may hold while it was read"
                               : "it could not be copied to the grader's folder");
        unlink(dest);
    }
    return ok;
}

/* A file the sandbox wrote: only a regular file (no symlink, FIFO or device
 * planted there, nor a link as its folder), at most `limit` bytes of it.
 * NULL when there is none. */
char *read_small_file(const char *path, size_t limit) {
    char why[200];
    const char *name;
    int dfd = sandbox_dir_of(path, &name, why, sizeof why);
    long long size = 0;
    int fd = dfd >= 0 ? sandbox_open(dfd, name, &size, why, sizeof why) : -1;
    if (dfd >= 0) close(dfd);
    if (fd < 0) return NULL;
    sbuf b = {0};
    char chunk[4096];
    ssize_t n;
    while (b.len < limit && (n = read(fd, chunk, sizeof chunk)) > 0)
        sb_addn(&b, chunk, b.len + (size_t)n > limit ? limit - b.len : (size_t)n);
    if ((unsigned long long)size > limit) sb_add(&b, "\n[... output cut ...]\n");
    close(fd);
    return b.s ? b.s : xstrdup("");
}

/* One line of printable text (a fate), "" when there is none. */
void read_small(const char *path, char *buf, size_t n) {
    char *t = read_small_file(path, n - 1);
    size_t k = 0;
    for (const char *p = t ? t : ""; *p && k < n - 1; p++)
        if (*p >= 32 && *p < 127) buf[k++] = *p;
    buf[k] = '\0';
    free(t);
}

/* ---------------------------------------------------------------- lists */

void names_add(name_list *l, const char *s) {
    l->v = realloc(l->v, (size_t)(l->n + 1) * sizeof *l->v);
    if (!l->v) abort();
    l->v[l->n++] = xstrdup(s);
}

void names_free(name_list *l) {
    for (int i = 0; i < l->n; i++)
        free(l->v[i]);
    free(l->v);
    *l = (name_list){0};
}

bool names_has(const name_list *l, const char *s) {
    for (int i = 0; i < l->n; i++)
        if (!strcmp(l->v[i], s)) return true;
    return false;
}

/* ---------------------------------------------------------------- the rubric */

double num_or(const cJSON *obj, const char *key, double fallback) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsNumber(v) ? v->valuedouble : fallback;
}

const char *str_or(const cJSON *obj, const char *key, const char *fallback) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsString(v) ? v->valuestring : fallback;
}

/* ---------------------------------------------------------------- the clock */

double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* RAS_GRADE_PROFILE=1: where a grading's time goes, a line per phase on
 * stderr (docs/feedback.md quotes it). */
void profile(const char *what, const char *id, double since) {
    profile_seconds(what, id, now_s() - since);
}

void profile_seconds(const char *what, const char *id, double seconds) {
    static int on = -1;
    if (on < 0) on = getenv("RAS_GRADE_PROFILE") && *getenv("RAS_GRADE_PROFILE") == '1';
    if (on) fprintf(stderr, "raster101-grade: profile: %-4s %-28s %6.3f s\n", id, what, seconds);
}
