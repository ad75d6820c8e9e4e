/* ras_cli.h — the one command-line parser the three programs share.
 *
 * One table (ras_cli.c, `options`) holds a row per option: its name, letter,
 * group, the kind of value it takes, the field it fills and its help line.
 * The parser, the "needs a value" and "expects" messages and --help are all
 * read from that table, so an option is added by adding one row.
 * Each program says which option groups it accepts (RAS_OPT_* bits); an
 * option of another group is rejected like an unknown one, with a message
 * that names it and points to --help. Values are checked here (numbers are
 * finite and in range, names are from ras_names.h's tables) so programs only
 * read fields. Parsing never prints: the caller prints err->msg or the help.
 */
#ifndef RAS_CLI_H
#define RAS_CLI_H

#include "ras_error.h"
#include "ras_math.h"
#include "ras_sample_pattern.h"
#include "stage3_setup.h" /* ras_depth_format */
#include "stage4_raster.h"

enum {
    RAS_OPT_ANGLE = 1u << 0,   /* -r/--angle DEG, --axis X,Y,Z */
    RAS_OPT_AA = 1u << 1,      /* --aa, --samples, --pattern, --depth */
    RAS_OPT_COMPARE = 1u << 2, /* --compare [--reference FILE] */
    RAS_OPT_SHADING = 1u << 3, /* --shader, --filter */
    RAS_OPT_MODEL = 1u << 4,   /* --model, --texture, --height, --fit */
    RAS_OPT_SCENE = 1u << 5,   /* --scene FILE */
    RAS_OPT_STATS = 1u << 6,   /* --stats */
    RAS_OPT_RENDERER = 1u << 7, /* --renderer NAME (the program checks the name) */
};

#define RAS_CLI_MAX_POSITIONAL 4

typedef struct ras_cli {
    const char *output; /* -o FILE: headless render */
    int width, height;  /* --size WxH; 0 = the scene's */
    float angle;        /* degrees */
    bool angle_set;
    vec3s axis;
    bool axis_set;
    ras_aa_mode aa;
    bool aa_set;
    int samples; /* 0 = the mode's default */
    ras_pattern_kind pattern;
    bool pattern_set;
    ras_depth_format depth; /* --depth z01|inverse_w */
    bool depth_set;
    bool compare;
    const char *reference; /* --reference FILE for --compare */
    int shader; /* ras_scene_shader (never flat: --shader takes hw3's five) */
    bool shader_set;
    int filter; /* ras_scene_filter */
    bool filter_set;
    const char *model, *texture, *height_map;
    bool fit;
    const char *scene;
    bool stats;
    const char *renderer; /* NULL: the program's default */
    const char *dump;     /* --dump DIR: the frame's buffers go there (ras_dump.h) */
    bool force;           /* --force: replace write-protected output files */
    const char *positional[RAS_CLI_MAX_POSITIONAL];
    int positional_count;
} ras_cli;

typedef enum ras_cli_status {
    RAS_CLI_RUN,     /* parsed: go on */
    RAS_CLI_HELP,    /* --help: print ras_cli_help() and exit 0 */
    RAS_CLI_VERSION, /* --version: print the version and exit 0 */
    RAS_CLI_ERROR,   /* err says why: print it and exit 2 */
} ras_cli_status;

ras_cli_status ras_cli_parse(int argc, char **argv, unsigned accepted, ras_cli *out,
                             ras_error *err);

/* Called first thing in main: big buffers (assimp's 16 MiB OBJ line buffer,
 * textures, frame buffers) come from malloc's heap instead of fresh mmaps,
 * and memory freed stays there for the next one. Every fresh page costs a
 * page fault (about 1 ms per MiB here), so reusing them cuts ~3500 faults
 * off a spot render (measured in the instructors' edition's start-up
 * report). Output is unchanged; the memory goes back to the system at exit.
 * A no-op outside glibc. */
void ras_cli_reuse_freed_memory(void);

/* The file written beside `output` for --compare: out/x.png with suffix
 * "diff" is out/x_diff.png (a dot in a folder name is not an extension);
 * without an output, FALLBACK_STEM_diff.png in the current folder. */
void ras_cli_sibling_path(const char *output, const char *fallback_stem, const char *suffix,
                          char *buf, size_t size);

/* Help for the accepted groups, after a program-specific usage paragraph. */
void ras_cli_help(unsigned accepted, const char *program, const char *usage, char *buf,
                  int size);

#endif
