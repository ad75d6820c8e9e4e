/* ras_memory.c — see ras_memory.h. */
#include "ras_memory.h"

#include <stdio.h>        /* snprintf */
#include <stdlib.h>       /* getenv, setenv, strtoull */
#include <sys/resource.h> /* getrlimit, RLIMIT_AS */
#include <unistd.h>       /* sysconf */

#define MIB (1024.0 * 1024.0)
/* Address space the programs need besides the budget: the libraries
 * (OpenCV, assimp, libc: ~250 MiB mapped), thread stacks, small buffers. */
#define RESERVED_ADDRESS_SPACE (320u << 20)

static size_t g_flag_mb;       /* --memory-limit, 0: not given */
static size_t g_limit;         /* cached, 0: not computed yet */
static const char *g_source;

/* A whole number of MiB in range, or 0. */
static size_t parse_mb(const char *text) {
    if (!text || *text < '0' || *text > '9') return 0;
    char *end = NULL;
    unsigned long long v = strtoull(text, &end, 10);
    if (*end != '\0' || v < RAS_MEMORY_MIN_MB || v > RAS_MEMORY_MAX_MB) return 0;
    return (size_t)v;
}

/* The limit for a given --memory-limit (0: none); *source says where it came from. */
static size_t compute_limit(size_t flag_mb, const char **source) {
    size_t limit;
    size_t env_mb = parse_mb(getenv("RAS_MEMORY_LIMIT_MB"));
    if (flag_mb) {
        limit = flag_mb << 20;
        *source = "set by --memory-limit";
    } else if (env_mb) {
        limit = env_mb << 20;
        *source = "set by RAS_MEMORY_LIMIT_MB";
    } else {
        long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        double phys = pages > 0 && page > 0 ? (double)pages * (double)page : 0;
        double cap = (double)RAS_MEMORY_DEFAULT_CAP_MB * MIB;
        limit = (size_t)(phys > 0 && phys / 2 < cap ? phys / 2 : cap);
        *source = "the default: half of physical memory, at most 2 GiB";
    }
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
        double room = (double)rl.rlim_cur > RESERVED_ADDRESS_SPACE
                          ? ((double)rl.rlim_cur - RESERVED_ADDRESS_SPACE) * 0.75
                          : 16 * MIB;
        if (room < (double)limit) {
            limit = (size_t)room;
            *source = "3/4 of what the address-space limit (ulimit -v) leaves after 320 MiB for "
                      "the libraries";
        }
    }
    return limit;
}

size_t ras_memory_limit(void) {
    if (!g_limit) g_limit = compute_limit(g_flag_mb, &g_source);
    return g_limit;
}

const char *ras_memory_limit_source(void) {
    ras_memory_limit();
    return g_source;
}

bool ras_memory_set_limit_mb(const char *text, ras_error *err) {
    size_t mb = parse_mb(text);
    if (!mb)
        return ras_error_set(err,
                             "--memory-limit expects a whole number of MiB, %u..%u, e.g. "
                             "--memory-limit 4096; got '%s'",
                             RAS_MEMORY_MIN_MB, RAS_MEMORY_MAX_MB, text);
    g_flag_mb = mb;
    g_limit = 0;
    return true;
}

bool ras_memory_check_env(ras_error *err) {
    const char *env = getenv("RAS_MEMORY_LIMIT_MB");
    if (!env || !*env || parse_mb(env)) return true;
    return ras_error_set(err,
                         "RAS_MEMORY_LIMIT_MB expects a whole number of MiB, %u..%u, e.g. "
                         "RAS_MEMORY_LIMIT_MB=4096; got '%s'",
                         RAS_MEMORY_MIN_MB, RAS_MEMORY_MAX_MB, env);
}

static double g_committed;

void ras_memory_commit(double bytes) { g_committed += bytes; }

void ras_memory_release(double bytes) {
    g_committed -= bytes;
    if (g_committed < 0) g_committed = 0;
}

bool ras_memory_check(double bytes, const char *what, const char *hint, ras_error *err) {
    size_t limit = ras_memory_limit();
    bytes += g_committed;
    if (bytes <= (double)limit) return true;
    return ras_error_set(err,
                         "%s needs about %.0f MiB, over the memory limit of %.0f MiB (%s); "
                         "%s%sor raise the limit with --memory-limit MB (or RAS_MEMORY_LIMIT_MB)",
                         what, bytes / MIB, (double)limit / MIB, ras_memory_limit_source(),
                         hint ? hint : "", hint ? ", " : "");
}
