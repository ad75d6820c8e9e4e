/* ras_catalogue.h — the catalogue of reference images: which program, with
 * which arguments, draws each one.
 *
 * One file (catalogue.json in the reference folder the build names,
 * RAS_REFERENCE_DIR) lists every reference image once:
 *
 *   {"images": [{"reference": "hw2_msaa4", "program": "hw2_rasterize",
 *                "args": ["--aa", "msaa", "--samples", "4"],
 *                "demo": "hw2_rasterize_msaa4"}, ...]}
 *
 * and, in "comparisons", how a picture is judged against its reference:
 *
 *   "comparisons": {"textured": {"metric": "psnr", "min_psnr": 33}, ...}
 *
 * each image naming one ("comparison": "textured"). That table is the only
 * place thresholds live: the grader (the rubric names a comparison per
 * image), the programs' --compare and window, and raster101-compare --as
 * NAME all read it, so one pair of pictures gets one verdict everywhere.
 *
 * scripts/reference-images renders each entry with the program's *_ref
 * build, scripts/demo the entries that have a "demo" name, the programs'
 * --compare and window (ras_app.c) find the reference for their settings
 * here, and tests read it (raster101-catalogue prints it for shell scripts).
 */
#ifndef RAS_CATALOGUE_H
#define RAS_CATALOGUE_H

#include "ras_compare.h"
#include "ras_error.h"

#include <stdbool.h>

#define RAS_CATALOGUE_MAX_ENTRIES 64
#define RAS_CATALOGUE_MAX_ARGS 12
#define RAS_CATALOGUE_NAME 64
#define RAS_CATALOGUE_MAX_COMPARISONS 16

typedef struct ras_catalogue_comparison {
    char name[RAS_CATALOGUE_NAME];
    ras_compare_options options;
} ras_catalogue_comparison;

typedef struct ras_catalogue_entry {
    char reference[RAS_CATALOGUE_NAME]; /* the image: <reference>.png beside the catalogue */
    char program[RAS_CATALOGUE_NAME];   /* "hw2_rasterize" (its *_ref build draws it) */
    char demo[RAS_CATALOGUE_NAME];      /* scripts/demo's out/<demo>.png; "" when not in the demo */
    int argc;
    char args[RAS_CATALOGUE_MAX_ARGS][RAS_CATALOGUE_NAME];
    char comparison[RAS_CATALOGUE_NAME]; /* a name in the comparisons table */
    ras_compare_options compare;         /* that comparison's options */
} ras_catalogue_entry;

typedef struct ras_catalogue {
    int count;
    ras_catalogue_entry entries[RAS_CATALOGUE_MAX_ENTRIES];
    int comparison_count;
    ras_catalogue_comparison comparisons[RAS_CATALOGUE_MAX_COMPARISONS];
} ras_catalogue;

/* The options of comparison `name`; false and err listing the names when
 * the table has none of that name. */
bool ras_catalogue_comparison_options(const ras_catalogue *cat, const char *name,
                                      ras_compare_options *opt, ras_error *err);

/* The entry whose reference image is `reference` (with or without ".png");
 * NULL when there is none. */
const ras_catalogue_entry *ras_catalogue_find(const ras_catalogue *cat, const char *reference);

/* Reads `path`; false and err naming the file and the entry that is wrong. */
bool ras_catalogue_load(const char *path, ras_catalogue *out, ras_error *err);

/* "--aa msaa --samples 4" (or "no options"), for messages and listings. */
void ras_catalogue_args_text(const ras_catalogue_entry *e, char *buf, int size);

#endif
