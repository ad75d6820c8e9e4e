/* grade_base.h — raster101-grade's plumbing (tests/grading/grade_*.c): a
 * growing string (sbuf), files read and written the simple way, lists of
 * names, the rubric's lookups and the clock. Knows nothing of a grading.
 */
#ifndef RAS_GRADING_GRADE_BASE_H
#define RAS_GRADING_GRADE_BASE_H

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stddef.h>

/* snprintf that cuts silently (paths here are far below the buffer sizes). */
__attribute__((format(printf, 3, 4))) void fmt(char *buf, size_t size, const char *f, ...);

/* ---------------------------------------------------------------- strings */

/* A growing string; {0} is the empty one, and its s is owned (free(b.s)). */
typedef struct sbuf {
    char *s;
    size_t len, cap;
} sbuf;

void sb_addn(sbuf *b, const char *s, size_t n);
void sb_add(sbuf *b, const char *s);
__attribute__((format(printf, 2, 3))) void sb_printf(sbuf *b, const char *fmt, ...);
/* b's text, "" while it has none */
const char *sb_str(const sbuf *b);
/* strdup that aborts when out of memory; NULL is taken as "" */
char *xstrdup(const char *s);

/* ---------------------------------------------------------------- files */

/* The whole file (at most `limit` bytes, then a cut mark; 0: no limit), or NULL. */
char *read_file(const char *path, size_t limit);
bool copy_file(const char *from, const char *to);
/* mkdir -p */
void mkdirs(const char *path);
bool file_exists(const char *path);
bool is_dir(const char *path);
/* A folder made 0700: what the trusted side keeps where no sandboxed run can write. */
void trusted_dir(const char *path);
/* A new 0700 folder at path (whatever stood there removed, never followed),
 * in a folder that may not be the trusted side's alone; false when it cannot be. */
bool fresh_trusted_dir(const char *path);
/* The folder at path and everything in it, never following a link. */
void remove_tree(const char *path);

/* ---------------------------------------------------------------- what the sandbox wrote */

/* Every read of a file a sandboxed run wrote goes through sandbox_open: a
 * folder opened O_DIRECTORY|O_NOFOLLOW, the file by openat with
 * O_NOFOLLOW|O_NONBLOCK, fstat on the open descriptor: a regular file with
 * one link, else refused with the reason in why. */

/* A folder the sandbox wrote (its last component no link): its descriptor, or -1 and why. */
int sandbox_dir(const char *path, char *why, size_t n);
/* The folder of path, as sandbox_dir, and *name its last component (in path). */
int sandbox_dir_of(const char *path, const char **name, char *why, size_t n);
/* File `name` (one component) of that folder: its descriptor and *size, or -1 and why. */
int sandbox_open(int dir_fd, const char *name, long long *size, char *why, size_t n);
/* File `name` (sandbox_open) no larger than max_bytes: its descriptor, or -1
 * and why. */
int sandbox_check(int dir_fd, const char *name, size_t max_bytes, char *why, size_t n);
/* File `name` of the folder dir_fd taken to dest (a trusted folder): the
 * checked inode hard-linked where both share a filesystem, else copied (new,
 * 0600); refused, with why, when it is missing, not a regular file or over
 * max_bytes. Only once the run that wrote it is over. What the trusted side
 * then reads is dest. */
bool sandbox_take(int dir_fd, const char *name, const char *dest, size_t max_bytes, char *why,
                  size_t n);
/* A file the sandbox wrote, by path (sandbox_open on its folder and name):
 * at most `limit` bytes of it, then a cut mark; NULL when it is refused or missing. */
char *read_small_file(const char *path, size_t limit);
/* One line of printable text of a small file (a fate) into buf, "" when none. */
void read_small(const char *path, char *buf, size_t n);

/* ---------------------------------------------------------------- lists */

typedef struct name_list {
    char **v;
    int n;
} name_list;

void names_add(name_list *l, const char *s);
void names_free(name_list *l);
bool names_has(const name_list *l, const char *s);

/* ---------------------------------------------------------------- the rubric */

/* obj's number or string `key`, else the fallback */
double num_or(const cJSON *obj, const char *key, double fallback);
const char *str_or(const cJSON *obj, const char *key, const char *fallback);

/* ---------------------------------------------------------------- the clock */

/* seconds on the monotonic clock */
double now_s(void);
/* RAS_GRADE_PROFILE=1: one line on stderr for a phase that began at `since` */
void profile(const char *what, const char *id, double since);
/* the same for a span measured elsewhere (a sandboxed run's own clock) */
void profile_seconds(const char *what, const char *id, double seconds);

#endif
