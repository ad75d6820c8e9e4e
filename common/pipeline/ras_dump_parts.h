/* ras_dump_parts.h — what ras_dump.c and ras_dump_compare.c share, and
 * nothing else includes: ras_dump.h is the module's public face. */
#ifndef RAS_DUMP_PARTS_H
#define RAS_DUMP_PARTS_H

#include "ras_dump.h"
#include "ras_error.h"

#include <cjson/cJSON.h>

/* Range of the finite, non-empty values per channel; counts of empty and
 * non-finite entries. */
typedef struct ras_dump_stats {
    double lo[3], hi[3];
    long empty, nonfinite, entries;
} ras_dump_stats;

ras_dump_stats ras_dump_buffer_stats(const ras_dump_buffer *b);

/* j printed into `path` atomically, ending in a newline; j is freed. */
bool ras_dump_write_json_file(const char *path, const char *what, cJSON *j, ras_error *err);

#endif
