/* ras_call.c — record (in the sandboxed worker) and replay (in the trusted
 * grader) of the calls a test makes into student code; see ras_call.h.
 *
 * Built with RAS_CALL_HW=N (the assignment: its functions and those of the
 * assignments before it are wrapped) and one of RAS_CALL_RECORD or
 * RAS_CALL_REPLAY. The functions are the rows of ras_call_table.h; each
 * row's __wrap_NAME is generated at the end of this file. The link adds
 * -Wl,--wrap=NAME for each row, so a call to NAME from any other object lands
 * in __wrap_NAME; the recorder forwards it to __real_NAME (the student's code).
 *
 * The record file ($RAS_RECORD, written through a shared mapping so that a
 * crash keeps every finished record) is:
 *   "RASCALL1", u64 bytes used after this header, then records
 *   u32 tag, u32 length, payload:
 *     BEGIN  u32 function, u64 hash of the inputs
 *     END    u32 function, u32 regions; per region u64 size, u32 runs, then
 *            runs of (u64 offset, u32 length, bytes): what the call changed
 *            in each memory region the test can see (the return value, the
 *            out-parameters, the framebuffer, the counters)
 *     SHADE  ras_triangle, ras_fragment: rasterize_triangle called ctx->shade
 *     TODO   u16 length, function name, u16 length, handout section
 * The replayer trusts nothing in it: every length is checked against the
 * file and against the regions the trusted test itself passes in, and any
 * disagreement fails the test with a message that says what happened.
 */
#include <setjmp.h> /* cmocka needs these before cmocka.h */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ras_call.h"
#include "ras_call_table.h"
#include "ras_counters.h"
#include "ras_error.h"
#include "ras_framebuffer.h"
#include "ras_math.h"
#include "ras_todo.h"
#include "ras_triangle.h"
#include "stage4_raster.h"
#include "stage5_fragment.h"
/* The assignments' headers: each row of the table is checked against them. */
#include "transform.h"
#if RAS_CALL_HW >= 2
#include "rasterizer.h"
#endif
#if RAS_CALL_HW >= 3
#include "scene.h"
#include "shading.h"
#endif

#include <fcntl.h>    /* open */
#include <stdio.h>    /* fprintf */
#include <stdlib.h>   /* getenv, malloc */
#include <string.h>   /* memcpy, memcmp */
#include <sys/mman.h> /* mmap */
#include <sys/stat.h> /* fstat */
#include <unistd.h>   /* ftruncate, close */

#if !defined(RAS_CALL_RECORD) && !defined(RAS_CALL_REPLAY)
#error "build ras_call.c with RAS_CALL_RECORD or RAS_CALL_REPLAY"
#endif

enum { TAG_BEGIN = 1, TAG_END = 2, TAG_SHADE = 3, TAG_TODO = 4 };
#define MAGIC "RASCALL1"
#define HEADER 16

/* The functions, by number (their rows in ras_call_table.h); the names are
 * for messages. */
#define AS_ENUM(hw, name, ...) FN_##name,
#define AS_NAME(hw, name, ...) #name,
enum { RAS_CALL_TABLE(AS_ENUM, AS_ENUM, AS_ENUM) FN_COUNT };
static const char *const fn_names[FN_COUNT] = {RAS_CALL_TABLE(AS_NAME, AS_NAME, AS_NAME)};

__attribute__((unused)) static const char *fn_name(uint32_t fn) { return fn < FN_COUNT ? fn_names[fn] : "(unknown)"; }

/* A memory region the test can see that a call may change. */
typedef struct region {
    void *p;
    size_t n;
    bool diff; /* record only the bytes that changed: for big buffers the test
                * itself initialised (a framebuffer); everything else whole,
                * since an out-parameter's bytes before the call are garbage
                * that differs between the two processes */
    bool text; /* a message: its last byte is set to 0 after the call, since the
                * replayed bytes come from the untrusted record */
} region;

/* ---- the inputs' fingerprint (FNV-1a): catches a record made for other calls */

typedef struct hash {
    uint64_t h;
} hash;

static hash hash_start(uint32_t fn) {
    hash h = {1469598103934665603ull ^ fn};
    return h;
}

static void hash_bytes(hash *h, const void *p, size_t n) {
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++) h->h = (h->h ^ b[i]) * 1099511628211ull;
}
#define HASH(h, v) hash_bytes(&(h), &(v), sizeof(v))

__attribute__((unused)) static void hash_triangle(hash *h, const ras_triangle *t) {
    if (!t) return; /* field by field: the struct's tail padding holds garbage */
    hash_bytes(h, t->v, sizeof t->v);
    hash_bytes(h, t->color, sizeof t->color);
    hash_bytes(h, t->normal, sizeof t->normal);
    hash_bytes(h, t->uv, sizeof t->uv);
    hash_bytes(h, t->view_pos, sizeof t->view_pos);
}

/* ---- the regions a test asked to watch (guarded framebuffers) ---------- */

#define MAX_WATCH 8
static region watched[MAX_WATCH];
static int watched_count;

void ras_call_watch_impl(void *p, size_t n) {
    if (!p) {
        watched_count = 0;
        return;
    }
    if (watched_count < MAX_WATCH) watched[watched_count++] = (region){.p = p, .n = n, .diff = true};
}

#ifdef RAS_CALL_RECORD
/* ======================================================== record (worker) */

static unsigned char *rec_map;
static size_t rec_cap, rec_used; /* rec_used includes the header */
static int rec_state;            /* 0 not opened, 1 open, -1 off or failed or full */
static int depth;                /* > 0: inside a recorded call, do not record */

/* The record lies between two inaccessible zones. The student's buffers
 * (hw3_render's frame, a test's framebuffer) are mappings of their own that
 * the kernel may place right below or above the record; without the zones a
 * write past their end lands in the record and the replay can only say the
 * record is malformed. With them it stops the process at the first such
 * write, and the test says what it is: a crash, an access out of bounds. A
 * zone is larger than a few hundred rows of a big sample buffer, since an
 * unclamped box writes row by row, not byte by byte. */
#define GUARD_BYTES ((size_t)32 << 20)

static void *map_between_guards(int fd, size_t n) {
    size_t total = GUARD_BYTES + n + GUARD_BYTES;
    unsigned char *zone =
        mmap(NULL, total, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (zone == MAP_FAILED) /* a tight address-space limit: the record alone */
        return mmap(NULL, n, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    void *m = mmap(zone + GUARD_BYTES, n, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_FIXED, fd, 0);
    if (m == MAP_FAILED) munmap(zone, total);
    return m;
}

static void rec_open(void) {
    if (rec_state) return;
    rec_state = -1;
    const char *path = getenv("RAS_RECORD");
    if (!path || !*path) return;
    const char *cap_mb = getenv("RAS_RECORD_CAP_MB");
    rec_cap = (size_t)(cap_mb ? atol(cap_mb) : 256) << 20;
    if (rec_cap < 4096) rec_cap = 4096;
    int fd = open(path, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0 || ftruncate(fd, (off_t)rec_cap) != 0) {
        fprintf(stderr, "ras_call: cannot write the record %s\n", path);
        if (fd >= 0) close(fd);
        return;
    }
    void *m = map_between_guards(fd, rec_cap);
    close(fd);
    if (m == MAP_FAILED) return;
    rec_map = m;
    memcpy(rec_map, MAGIC, 8);
    rec_used = HEADER;
    rec_state = 1;
}

/* Appends one record; the header's length is updated last, so a record is
 * either wholly there or not at all. */
static void rec_put(uint32_t tag, const void *a, size_t na, const void *b, size_t nb) {
    rec_open();
    if (rec_state != 1) return;
    size_t need = 8 + na + nb;
    if (need > rec_cap - rec_used) {
        rec_state = -1; /* full: the replay says the record ended early */
        return;
    }
    uint32_t len = (uint32_t)(na + nb);
    memcpy(rec_map + rec_used, &tag, 4);
    memcpy(rec_map + rec_used + 4, &len, 4);
    if (na) memcpy(rec_map + rec_used + 8, a, na);
    if (nb) memcpy(rec_map + rec_used + 8 + na, b, nb);
    rec_used += need;
    uint64_t used = rec_used - HEADER;
    __atomic_store_n((uint64_t *)(void *)(rec_map + 8), used, __ATOMIC_RELEASE);
}

/* Growable scratch buffer for an END record. */
typedef struct buf {
    unsigned char *p;
    size_t n, cap;
} buf;

__attribute__((noinline)) static void buf_grow(buf *b, size_t n) {
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->n + n) cap *= 2;
    unsigned char *q = realloc(b->p, cap);
    if (!q) abort();
    b->p = q;
    b->cap = cap;
}

/* Inline, so that the fixed-size fields of a record are stores, not calls. */
static inline __attribute__((always_inline)) void buf_add(buf *b, const void *p, size_t n) {
    if (b->n + n > b->cap) buf_grow(b, n);
    memcpy(b->p + b->n, p, n);
    b->n += n;
}

typedef struct call {
    uint32_t fn;
    region regs[4 + MAX_WATCH];
    unsigned char *before[4 + MAX_WATCH];
    int n;
    bool active;
} call;

/* Scratch kept from call to call: a frame records about a million calls
 * (resolve_pixel per pixel), and a malloc, realloc and free for each made
 * recording cost 4x the student's own work. Calls do not nest (depth) and the
 * pipeline calls the student's functions from one thread, so one set does. */
static buf end_scratch;
static buf before_scratch[4 + MAX_WATCH];

static unsigned char *scratch_copy(buf *b, const void *p, size_t n) {
    static const unsigned char none = 0;
    b->n = 0;
    if (n) buf_add(b, p, n);
    else buf_add(b, &none, 1);
    return b->p;
}

/* Starts a call: false when it is nested in another recorded call (then the
 * caller just runs the student's function). */
static bool call_begin(call *c, uint32_t fn, hash h) {
    c->active = false;
    if (depth > 0) return false;
    rec_open();
    c->fn = fn;
    unsigned char payload[12];
    memcpy(payload, &fn, 4);
    memcpy(payload + 4, &h.h, 8);
    rec_put(TAG_BEGIN, payload, sizeof payload, NULL, 0);
    for (int i = 0; i < c->n; i++) {
        c->before[i] = NULL;
        if (!c->regs[i].diff) continue;
        c->before[i] = scratch_copy(&before_scratch[i], c->regs[i].p, c->regs[i].n);
    }
    depth++;
    c->active = true;
    return true;
}

static void call_end(call *c) {
    if (!c->active) return;
    depth--;
    buf b = end_scratch;
    b.n = 0;
    buf_add(&b, &c->fn, 4);
    uint32_t nreg = (uint32_t)c->n;
    buf_add(&b, &nreg, 4);
    for (int i = 0; i < c->n; i++) {
        const unsigned char *now = c->regs[i].p, *was = c->before[i];
        uint64_t size = c->regs[i].n;
        buf_add(&b, &size, 8);
        size_t count_at = b.n;
        uint32_t runs = 0;
        buf_add(&b, &runs, 4);
        size_t k = 0;
        if (!c->regs[i].diff && size) { /* one run: the whole region */
            uint64_t off = 0;
            uint32_t len = (uint32_t)size;
            buf_add(&b, &off, 8);
            buf_add(&b, &len, 4);
            buf_add(&b, now, size);
            runs = 1;
            k = size;
        }
        while (k < size) {
            if (now[k] == was[k]) {
                size_t skip = 64 - (k & 63);
                if (k + skip <= size && memcmp(now + k, was + k, skip) == 0) {
                    k += skip;
                    continue;
                }
                k++;
                continue;
            }
            size_t start = k, same = 0;
            while (k < size && same < 16) {
                same = now[k] == was[k] ? same + 1 : 0;
                k++;
            }
            size_t end = k - same;
            uint64_t off = start;
            uint32_t len = (uint32_t)(end - start);
            buf_add(&b, &off, 8);
            buf_add(&b, &len, 4);
            buf_add(&b, now + start, len);
            runs++;
        }
        memcpy(b.p + count_at, &runs, 4);
    }
    rec_put(TAG_END, b.p, b.n, NULL, 0);
    end_scratch = b;
}

/* The stubs' notice, recorded so the replay can tell a placeholder pass. */
void __real_ras_todo_notice(bool *shown, const char *function, const char *handout_section);
void __wrap_ras_todo_notice(bool *shown, const char *function, const char *handout_section) {
    if (!*shown && function && handout_section) {
        uint16_t n1 = (uint16_t)strnlen(function, 120), n2 = (uint16_t)strnlen(handout_section, 200);
        buf b = {0};
        buf_add(&b, &n1, 2);
        buf_add(&b, function, n1);
        buf_add(&b, &n2, 2);
        buf_add(&b, handout_section, n2);
        rec_put(TAG_TODO, b.p, b.n, NULL, 0);
        free(b.p);
    }
    __real_ras_todo_notice(shown, function, handout_section);
}

/* ctx->shade seen through rasterize_triangle: record each call's inputs. */
static ras_shade_fn shade_original;
static void *shade_user;
__attribute__((unused)) static vec3s shade_recorded(const ras_triangle *t, const ras_fragment *f, void *user) {
    (void)user;
    rec_put(TAG_SHADE, t, sizeof *t, f, sizeof *f);
    return shade_original(t, f, shade_user);
}

#define CALL(fn, h, real_call)                                                                     \
    do {                                                                                           \
        if (call_begin(&c, FN_##fn, h)) {                                                          \
            real_call;                                                                             \
            call_end(&c);                                                                          \
        } else {                                                                                   \
            real_call;                                                                             \
        }                                                                                          \
    } while (0)
#define REAL(name) __real_##name

#else
/* ======================================================= replay (trusted) */

static const unsigned char *rp_map;
static size_t rp_len, rp_pos; /* rp_pos: offset of the next record */
static int rp_state;          /* 0 not opened, 1 open */
static unsigned long rp_calls;
static int rp_todos;

/* How the sandboxed worker ended, as the grader saw it. */
static const char *worker_fate(void) {
    const char *w = getenv("RAS_REPLAY_WORKER");
    return w && *w ? w : "ended";
}

/* What a record that the recorder could not have written means. Only the
 * recorder and the student's code run in the sandboxed process, and the
 * record lies between inaccessible zones (map_between_guards), so a write
 * running off the end of a buffer stops the process there; what still
 * reaches the record is a write far out of bounds. Nothing here proves a
 * deliberate change, so none is claimed. */
#define OVERWRITTEN_BY_CODE                                                                        \
    "likely mistake: memory written out of bounds: your code wrote far past the end of a buffer " \
    "(an index outside the sample or frame buffers: a bounding box not clamped to the screen, a " \
    "row or sample index not checked) and hit the record the grader keeps of its calls; grade " \
    "with --sanitize (docs/grading.md) to see the line that writes out of bounds"

/* The worker was stopped by an access to memory it may not touch. */
static bool out_of_bounds_fate(void) {
    const char *w = worker_fate();
    return strstr(w, "(SIGSEGV)") || strstr(w, "(SIGBUS)");
}

static void rp_open(void) {
    if (rp_state) return;
    const char *path = getenv("RAS_REPLAY");
    if (!path || !*path) fail_msg("grader error: test_*_replay needs RAS_REPLAY=record file");
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size < HEADER) {
        if (fd >= 0) close(fd);
        fail_msg("the sandboxed test process %s without recording any call of your code (it "
                 "never reached the test: code that runs before main, or the process ended "
                 "at once)",
                 worker_fate());
    }
    void *m = mmap(NULL, (size_t)st.st_size, PROT_READ, MAP_PRIVATE, fd, 0);
    close(fd);
    if (m == MAP_FAILED) fail_msg("grader error: cannot map the record %s", path);
    rp_map = m;
    uint64_t used;
    memcpy(&used, rp_map + 8, 8);
    if (memcmp(rp_map, MAGIC, 8) != 0 || used > (uint64_t)st.st_size - HEADER)
        fail_msg("the record of your code's calls was overwritten while your code ran (its "
                 "header is not the one the grader wrote; the sandboxed test process %s); %s",
                 worker_fate(), OVERWRITTEN_BY_CODE);
    rp_len = HEADER + (size_t)used;
    rp_pos = HEADER;
    rp_state = 1;
}

/* The next record; handles TODO notices on the way. Fails the test at the end. */
static const unsigned char *rp_next(uint32_t *tag, uint32_t *len, uint32_t want_fn,
                                    bool inside) {
    for (;;) {
        if (rp_len - rp_pos < 8) {
            if (inside && want_fn == FN_hw3_render && out_of_bounds_fate())
                fail_msg("hw3_render() did not return: the sandboxed test process %s while it "
                         "drew the frame (call %lu of this test); likely mistake: memory "
                         "accessed out of bounds in one of YOUR functions it runs: your "
                         "rasterizer (hw2: a bounding box not clamped to the screen writes past "
                         "the sample and frame buffers), your texture lookups (hw3: u, v outside "
                         "[0, 1]); the hw2 tests say whether the rasterizer passes, and grading "
                         "with --sanitize (docs/grading.md) shows the line",
                         worker_fate(), rp_calls);
            if (inside && want_fn == FN_hw3_render)
                fail_msg("hw3_render() did not return: the sandboxed test process %s while it "
                         "drew the frame (call %lu of this test); likely mistake: a crash, an "
                         "endless loop or exit() in one of YOUR functions it runs: your shaders "
                         "and texture lookups (hw3), or your rasterizer (hw2) and matrices "
                         "(hw1), which hw3 draws with; the hw2 and hw1 tests say whether those "
                         "pass",
                         worker_fate(), rp_calls);
            if (inside && out_of_bounds_fate())
                fail_msg("%s() did not return: the sandboxed test process %s while it ran "
                         "(call %lu of this test); likely mistake: memory accessed out of "
                         "bounds in your %s (or in a function of yours that it calls): an index "
                         "outside a buffer (the sample or frame buffers: a bounding box not "
                         "clamped to the screen?); grading with --sanitize (docs/grading.md) "
                         "shows the line",
                         fn_name(want_fn), worker_fate(), rp_calls, fn_name(want_fn));
            if (inside)
                fail_msg("%s() did not return: the sandboxed test process %s while it ran "
                         "(call %lu of this test); likely mistake: a crash, an endless loop or "
                         "exit() in your %s (or in a function of yours that it calls)",
                         fn_name(want_fn), worker_fate(), rp_calls, fn_name(want_fn));
            fail_msg("the sandboxed test process %s before the test called %s() (call %lu); "
                     "a function must return its result, never exit or stop the process",
                     worker_fate(), fn_name(want_fn), rp_calls + 1);
        }
        memcpy(tag, rp_map + rp_pos, 4);
        memcpy(len, rp_map + rp_pos + 4, 4);
        if (*len > rp_len - rp_pos - 8)
            fail_msg("the record of your code's calls was overwritten while your code ran (at "
                     "byte %zu a record claims more bytes than follow); %s",
                     rp_pos, OVERWRITTEN_BY_CODE);
        const unsigned char *p = rp_map + rp_pos + 8;
        rp_pos += 8 + (size_t)*len;
        if (*tag != TAG_TODO) return p;
        /* A stub's notice: printed again here, where the grader reads it. */
        uint16_t n1, n2;
        if (*len < 4) continue;
        memcpy(&n1, p, 2);
        if ((size_t)n1 + 4 > *len) continue;
        memcpy(&n2, p + 2 + n1, 2);
        if ((size_t)n1 + n2 + 4 > *len || rp_todos >= 32) continue;
        char name[128], section[208];
        size_t k = 0;
        for (size_t i = 0; i < n1 && k < sizeof name - 1; i++)
            if (p[2 + i] >= 32 && p[2 + i] < 127) name[k++] = (char)p[2 + i];
        name[k] = '\0';
        k = 0;
        for (size_t i = 0; i < n2 && k < sizeof section - 1; i++)
            if (p[4 + n1 + i] >= 32 && p[4 + n1 + i] < 127) section[k++] = (char)p[4 + n1 + i];
        section[k] = '\0';
        bool shown = false;
        ras_todo_notice(&shown, name, section);
        rp_todos++;
    }
}

typedef void (*shade_replay_fn)(const ras_triangle *t, const ras_fragment *f, void *user);

/* Answers one call from the record: checks that it is the call the test
 * makes, replays ctx->shade calls through `shade`, then writes what the
 * student's call changed into the test's regions. */
static void replay(uint32_t fn, hash h, region *regs, int nregs, const ras_raster_ctx *ctx) {
    rp_open();
    uint32_t tag, len;
    const unsigned char *p = rp_next(&tag, &len, fn, false);
    rp_calls++;
    uint32_t got_fn;
    uint64_t got_h;
    if (tag != TAG_BEGIN || len != 12)
        fail_msg("the record of your code's calls was overwritten while your code ran (call "
                 "%lu does not start as the grader wrote it); %s",
                 rp_calls, OVERWRITTEN_BY_CODE);
    memcpy(&got_fn, p, 4);
    memcpy(&got_h, p + 4, 8);
    if (got_fn != fn || got_h != h.h)
        fail_msg("call %lu of this test is %s() with the test's inputs, but in the sandboxed "
                 "process the test called %s()%s: the test's own data had changed there before "
                 "this call; likely mistake: your code changed memory it was not given to "
                 "write: past the end of a buffer (an index outside the sample or frame "
                 "buffers: a bounding box not clamped to the screen?), or an input it should "
                 "only read; grade with --sanitize (docs/grading.md) to see the line",
                 rp_calls, fn_name(fn), fn_name(got_fn),
                 got_fn == fn ? " with other inputs" : "");
    for (;;) {
        p = rp_next(&tag, &len, fn, true);
        if (tag == TAG_SHADE) {
            if (len != sizeof(ras_triangle) + sizeof(ras_fragment))
                fail_msg("the record of your code's calls was overwritten while your code "
                         "ran (a shade call of the wrong size); %s",
                         OVERWRITTEN_BY_CODE);
            if (ctx && ctx->shade) {
                ras_triangle t;
                ras_fragment f;
                memcpy(&t, p, sizeof t);
                memcpy(&f, p + sizeof t, sizeof f);
                ctx->shade(&t, &f, ctx->shade_user);
            }
            continue;
        }
        if (tag == TAG_END) break;
        fail_msg("%s() did not return: the sandboxed test process %s while it ran (call %lu)",
                 fn_name(fn), worker_fate(), rp_calls);
    }
    const unsigned char *end = p + len;
    uint32_t nreg;
    if (len < 8)
        fail_msg("the record of your code's calls was overwritten while your code ran (an end "
                 "of call too short); %s",
                 OVERWRITTEN_BY_CODE);
    memcpy(&got_fn, p, 4);
    memcpy(&nreg, p + 4, 4);
    p += 8;
    if (got_fn != fn || nreg != (uint32_t)nregs)
        fail_msg("the record of %s() (call %lu) does not match the call: it was overwritten "
                 "while your code ran; %s",
                 fn_name(fn), rp_calls, OVERWRITTEN_BY_CODE);
    for (int i = 0; i < nregs; i++) {
        uint64_t size;
        uint32_t runs;
        if (end - p < 12) fail_msg("the record of %s() is cut short: it was overwritten while your code ran; %s",
                                    fn_name(fn), OVERWRITTEN_BY_CODE);
        memcpy(&size, p, 8);
        memcpy(&runs, p + 8, 4);
        p += 12;
        if (size != regs[i].n)
            fail_msg("the record of %s() (call %lu) has a region of %llu bytes where the test "
                     "has %zu: the test's own data, or the record, was overwritten while your "
                     "code ran; %s",
                     fn_name(fn), rp_calls, (unsigned long long)size, regs[i].n,
                     OVERWRITTEN_BY_CODE);
        for (uint32_t r = 0; r < runs; r++) {
            uint64_t off;
            uint32_t n;
            if (end - p < 12) fail_msg("the record of %s() is cut short: it was overwritten while your code ran; %s",
                                    fn_name(fn), OVERWRITTEN_BY_CODE);
            memcpy(&off, p, 8);
            memcpy(&n, p + 8, 4);
            p += 12;
            if (off > size || n > size - off || (size_t)(end - p) < n)
                fail_msg("the record of %s() claims a change outside the memory the test gave it: "
                         "it was overwritten while your code ran; %s",
                         fn_name(fn), OVERWRITTEN_BY_CODE);
            memcpy((unsigned char *)regs[i].p + off, p, n);
            p += n;
        }
    }
}

/* The student's function is not here: real_call stays unevaluated (inside
 * sizeof, so nothing links to it), which also keeps the wrapper's parameters
 * used when the call's inputs do not hash them all (hw3_render's scene). */
#define CALL(fn, h, real_call)                                                                     \
    do {                                                                                           \
        replay(FN_##fn, h, c.regs, c.n, NULL);                                                     \
        (void)sizeof((real_call), 0);                                                              \
    } while (0)
#define REAL(name) name

typedef struct call {
    region regs[4 + MAX_WATCH];
    int n;
} call;
#endif

/* ================================================ the wrapped functions */

/* A message's last byte is 0 after the call, in both processes. */
static void call_finish(call *c) {
    for (int i = 0; i < c->n; i++)
        if (c->regs[i].text && c->regs[i].n) ((char *)c->regs[i].p)[c->regs[i].n - 1] = '\0';
}

#ifdef RAS_CALL_RECORD
#define WRAP(ret, name, params)                                                                    \
    ret __real_##name params;                                                                      \
    ret __wrap_##name params
#else
#define WRAP(ret, name, params) ret __wrap_##name params
#endif

/* The regions of a call: its returned value r, and what else it writes. */
/* Only the count: the regions are written as they are named, and zeroing
 * the whole struct (400 bytes) cost a frame's 490,000 resolve_pixel calls as
 * much as the student's own code. */
#define CALL_START(c)                                                                              \
    call c;                                                                                        \
    c.n = 0
#define RESULT(r) (c.regs[c.n++] = (region){.p = &(r), .n = sizeof(r)})
#define REGION(ptr, size)                                                                          \
    do {                                                                                           \
        if (ptr) c.regs[c.n++] = (region){.p = (void *)(ptr), .n = (size)};                        \
    } while (0)
#define REGION_DIFF(ptr, size)                                                                     \
    do {                                                                                           \
        if (ptr) c.regs[c.n++] = (region){.p = (void *)(ptr), .n = (size), .diff = true};          \
    } while (0)

/* The (inputs) and (outputs) of a row (ras_call_table.h): statements on the
 * wrapper's hash h and call c. */
#define IN(v) HASH(h, v);
#define IN_ARRAY(ptr, count)                                                                       \
    if (ptr) hash_bytes(&h, (ptr), (count) * sizeof *(ptr));
#define IN_TRIANGLE(t) hash_triangle(&h, (t));
#define IN_FB_SIZE(fb)                                                                             \
    if (fb) {                                                                                      \
        HASH(h, (fb)->width);                                                                      \
        HASH(h, (fb)->height);                                                                     \
        HASH(h, (fb)->samples);                                                                    \
    }
#define IN_PAYLOAD(p) hash_payload(&h, (p));
#define IN_TEXTURE(tex) hash_texture(&h, (tex));
#define IN_RENDER_OPTIONS(o)                                                                       \
    if (o) {                                                                                       \
        HASH(h, (o)->shader);                                                                      \
        HASH(h, (o)->filter);                                                                      \
        HASH(h, (o)->angle_deg);                                                                   \
    }
#define IN_IMAGE_SIZE(img)                                                                         \
    if (img) {                                                                                     \
        HASH(h, (img)->width);                                                                     \
        HASH(h, (img)->height);                                                                    \
    }
#define OUT(ptr) REGION(ptr, sizeof *(ptr));
#define OUT_COUNTERS(p)                                                                            \
    if (p) REGION((p)->counters, sizeof *(p)->counters);
#define OUT_IMAGE(img)                                                                             \
    if (img)                                                                                       \
        REGION((img)->pixels,                                                                      \
               (size_t)(img)->width * (size_t)(img)->height * sizeof *(img)->pixels);
#define OUT_ERROR(err)                                                                             \
    if (err) c.regs[c.n++] = (region){.p = (err), .n = sizeof *(err), .text = true};

#if RAS_CALL_HW >= 3
/* What a shader's result depends on, without the pointers (which differ
 * between the two processes). */
static void hash_payload(hash *h, const fragment_shader_payload *p) {
    if (!p) return;
    HASH(*h, p->view_pos);
    HASH(*h, p->normal);
    HASH(*h, p->uv);
    HASH(*h, p->color);
    HASH(*h, p->filter);
    HASH(*h, p->light_count);
    HASH(*h, p->p);
    HASH(*h, p->kh);
    HASH(*h, p->kn);
}

static void hash_texture(hash *h, const ras_texture *tex) {
    if (!tex) return;
    HASH(*h, tex->width);
    HASH(*h, tex->height);
    HASH(*h, tex->level_count);
}
#endif

/* FOR_HW(hw, code...): the code only in a build for assignment hw or a later
 * one (RAS_CALL_HW), whose headers declare what it names. A new assignment N
 * adds its FOR_HW_N (and includes its header above). */
#define FOR_HW(hw, ...) FOR_HW_##hw(__VA_ARGS__)
#define FOR_HW_1(...) __VA_ARGS__
#if RAS_CALL_HW >= 2
#define FOR_HW_2(...) __VA_ARGS__
#else
#define FOR_HW_2(...)
#endif
#if RAS_CALL_HW >= 3
#define FOR_HW_3(...) __VA_ARGS__
#else
#define FOR_HW_3(...)
#endif

#define LIST(...) __VA_ARGS__
/* A row's signature is the header's: a wrapper with other parameters would
 * hand the student's code, or the test, the wrong bytes. */
#define SAME_SIGNATURE(name, ret, params)                                                          \
    _Static_assert(__builtin_types_compatible_p(__typeof__(&name), ret(*) params),                 \
                   "ras_call_table.h: the row of " #name " differs from its declaration in the "   \
                   "assignment's header; copy the header's parameters into the row");

/* The generated wrappers: hash the inputs, name the regions, then record the
 * student's call (worker) or answer it from the record (replay). */
/* clang-format off */
#define WRAP_FN(hw, name, ret, params, args, inputs, outputs)                                      \
    FOR_HW(hw, SAME_SIGNATURE(name, ret, params)                                                   \
    WRAP(ret, name, params) {                                                                      \
        hash h = hash_start(FN_##name);                                                            \
        LIST inputs                                                                                \
        ret r = {0};                                                                               \
        CALL_START(c);                                                                             \
        RESULT(r);                                                                                 \
        LIST outputs                                                                               \
        CALL(name, h, r = REAL(name) args);                                                        \
        call_finish(&c);                                                                           \
        return r;                                                                                  \
    })
#define WRAP_FN_VOID(hw, name, params, args, inputs, outputs)                                      \
    FOR_HW(hw, SAME_SIGNATURE(name, void, params)                                                  \
    WRAP(void, name, params) {                                                                     \
        hash h = hash_start(FN_##name);                                                            \
        LIST inputs                                                                                \
        CALL_START(c);                                                                             \
        LIST outputs                                                                               \
        CALL(name, h, REAL(name) args);                                                            \
        call_finish(&c);                                                                           \
    })
/* clang-format on */
/* A hand-written wrapper below: its signature checked all the same. */
#define WRAP_FN_CUSTOM(hw, name, ret, params)                                                      \
    FOR_HW(hw, SAME_SIGNATURE(name, ret, params) ret __wrap_##name params;)

RAS_CALL_TABLE(WRAP_FN, WRAP_FN_VOID, WRAP_FN_CUSTOM)

#if RAS_CALL_HW >= 2
/* The framebuffer, the counters and any watched canaries; ctx->shade is seen
 * through the record, and called again in the replay. */
WRAP(void, rasterize_triangle, (const ras_triangle *t, const ras_raster_ctx *ctx)) {
    hash h = hash_start(FN_rasterize_triangle);
    hash_triangle(&h, t);
    CALL_START(c);
    if (ctx) {
        HASH(h, ctx->aa);
        HASH(h, ctx->pattern.count);
        if (ctx->fb) {
            const ras_framebuffer *fb = ctx->fb;
            HASH(h, fb->width);
            HASH(h, fb->height);
            HASH(h, fb->samples);
            size_t n = (size_t)fb->width * (size_t)fb->height * (size_t)fb->samples;
            REGION_DIFF(fb->color, n * sizeof *fb->color);
            REGION_DIFF(fb->depth, n * sizeof *fb->depth);
        }
        REGION(ctx->counters, sizeof *ctx->counters);
    }
    for (int i = 0; i < watched_count; i++) REGION_DIFF(watched[i].p, watched[i].n);
#ifdef RAS_CALL_RECORD
    if (ctx && ctx->shade && depth == 0) {
        ras_raster_ctx seen = *ctx;
        shade_original = ctx->shade;
        shade_user = ctx->shade_user;
        seen.shade = shade_recorded;
        CALL(rasterize_triangle, h, REAL(rasterize_triangle)(t, &seen));
    } else {
        CALL(rasterize_triangle, h, REAL(rasterize_triangle)(t, ctx));
    }
#else
    replay(FN_rasterize_triangle, h, c.regs, c.n, ctx);
#endif
}
#endif
