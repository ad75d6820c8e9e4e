/* ras_names.h — the one spelling of every option value that has a name.
 *
 * Each enum the programs, scene files, --stats and the docs spell out has
 * exactly one table here, in enum order: the command line (ras_cli.c), the
 * scene loader (ras_scene_schema.c), the viewer's status lines, hw3's shader names
 * and the docs generators all read these, so a new value is added in one
 * place. A table is indexed by the enum's value.
 */
#ifndef RAS_NAMES_H
#define RAS_NAMES_H

#include <stdbool.h>
#include <stddef.h>

typedef struct ras_names {
    const char *what;          /* for messages: "an anti-aliasing mode" */
    int count;                 /* values 0 .. count-1 */
    const char *const *names;  /* names[value] */
} ras_names;

extern const ras_names ras_names_aa;      /* ras_aa_mode: none, msaa, ssaa */
extern const ras_names ras_names_pattern; /* ras_pattern_kind: ordered, standard */
extern const ras_names ras_names_depth;   /* ras_depth_format: z01, inverse_w */
extern const ras_names ras_names_shader;  /* ras_scene_shader: flat, normal, phong, ... */
extern const ras_names ras_names_filter;  /* ras_scene_filter: nearest, ... */
extern const ras_names ras_names_wrap;    /* ras_wrap: repeat, clamp */
extern const ras_names ras_names_cull;    /* ras_cull_mode: none, back, front */

/* The name of `value`; "?" when it is out of range. */
const char *ras_name_of(const ras_names *t, int value);

/* The value spelled `word` among values first .. count-1; -1 when none. */
int ras_name_find(const ras_names *t, const char *word, int first);

/* "a, b or c": the names from `first` on, for messages and help. */
const char *ras_names_list(const ras_names *t, int first, char *buf, size_t size);

#endif
