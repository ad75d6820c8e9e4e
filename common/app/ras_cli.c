/* ras_cli.c — see ras_cli.h. */
#include "ras_cli.h"

#include "ras_io.h"     /* ras_io_path_fits */
#include "ras_memory.h" /* ras_memory_set_limit_mb */
#include "ras_names.h"  /* the values --aa, --shader, ... take */
#include "ras_scene.h"  /* RAS_SHADER_NORMAL */

#include <stddef.h> /* offsetof */

#include <getopt.h> /* getopt_long */
#include <math.h>   /* isfinite */
#include <stdio.h>  /* snprintf, sscanf */
#include <stdlib.h> /* strtof, strtol, realpath */
#include <string.h> /* strcmp */
#ifdef __GLIBC__
#include <malloc.h> /* mallopt */
#endif

/* ---- the option table ------------------------------------------------------ */

/* What an option's value is, and so how it is checked and stored. */
typedef enum kind {
    FLAG,     /* no value: sets a bool */
    FILE_ARG, /* a file name: stored as given, checked to fit and to not look like an option */
    NAME,     /* one of a ras_names table's names: stored as the enum value */
    TEXT,     /* any word, stored as given (--renderer: the program checks it) */
    SIZE,     /* WIDTHxHEIGHT */
    ANGLE,    /* a finite number */
    AXIS,     /* X,Y,Z, not all zero */
    SAMPLES,  /* 1 .. RAS_MAX_SAMPLES */
    MEMORY,   /* MiB, handed to ras_memory_set_limit_mb */
    HELP,
    VERSION,
} kind;

#define NO_FIELD ((size_t)-1)
#define F(x) offsetof(ras_cli, x)

typedef struct option_row {
    const char *name; /* long name, without "--" */
    char letter;      /* short option, or 0 */
    unsigned group;   /* RAS_OPT_* bit; 0: every program takes it */
    kind kind;
    size_t field, set_flag; /* where the value goes, and its "_set" bool (NO_FIELD: none) */
    const ras_names *names; /* NAME: the table, from value `first` on */
    int first;
    const char *value; /* what the value looks like: "needs a value: expected ..." */
    const char *arg;   /* its placeholder in --help ("FILE") */
    const char *help;  /* the help text; '\n' starts an indented line; in a NAME
                        * row, %s is the table's names ("none, msaa or ssaa") */
} option_row;

/* One row per option, in --help's order. */
static const option_row options[] = {
    {"output", 'o', 0, FILE_ARG, F(output), NO_FIELD, NULL, 0, "an output FILE such as out.png",
     "FILE", "render once without a window and write FILE (.png; .jpg, .bmp,\n.ppm and .tif "
             "work too)"},
    {"size", 0, 0, SIZE, NO_FIELD, NO_FIELD, NULL, 0, "WIDTHxHEIGHT such as 700x700", "WxH",
     "image size in pixels, 1x1 to 8192x8192 (default: the scene's)"},
    {"angle", 'r', RAS_OPT_ANGLE, ANGLE, F(angle), F(angle_set), NULL, 0,
     "an angle in degrees such as 20", "DEG", "rotation angle in degrees"},
    {"axis", 0, RAS_OPT_ANGLE, AXIS, F(axis), F(axis_set), NULL, 0, "an axis X,Y,Z such as 0,1,0",
     "X,Y,Z", "rotate about this axis (bonus: get_rotation)"},
    {"aa", 0, RAS_OPT_AA, NAME, F(aa), F(aa_set), &ras_names_aa, 0, NULL, "MODE",
     "anti-aliasing: %s"},
    {"samples", 0, RAS_OPT_AA, SAMPLES, F(samples), NO_FIELD, NULL, 0, "a sample count such as 4",
     "N", "samples per pixel (ordered: 4, 16, 64; standard: 2, 4, 8, 16);\nalone, it means "
          "--aa msaa"},
    {"pattern", 0, RAS_OPT_AA, NAME, F(pattern), F(pattern_set), &ras_names_pattern, 0, NULL, "P",
     "sample positions: ordered (grid) or standard (D3D/Vulkan)"},
    {"depth", 0, RAS_OPT_AA, NAME, F(depth), F(depth_set), &ras_names_depth, 0, NULL, "F",
     "depth format: z01 ((1-z)/2, default) or inverse_w\n(-near/w: reversed-z, precise far "
     "away; docs/scenes.md)"},
    {"shader", 0, RAS_OPT_SHADING, NAME, F(shader), F(shader_set), &ras_names_shader,
     RAS_SHADER_NORMAL, NULL, "NAME", "%s"},
    {"filter", 0, RAS_OPT_SHADING, NAME, F(filter), F(filter_set), &ras_names_filter, 0, NULL,
     "NAME", "texture filter: %s"},
    {"model", 0, RAS_OPT_MODEL, FILE_ARG, F(model), NO_FIELD, NULL, 0,
     "a model FILE (OBJ, PLY, STL, glTF, ...)", "FILE", "a model file (OBJ, PLY, STL, glTF, ...)"},
    {"texture", 0, RAS_OPT_MODEL, FILE_ARG, F(texture), NO_FIELD, NULL, 0, "an image FILE",
     "FILE", "colour texture image"},
    {"height", 0, RAS_OPT_MODEL, FILE_ARG, F(height_map), NO_FIELD, NULL, 0, "an image FILE",
     "FILE", "height map for bump / displacement"},
    {"fit", 0, RAS_OPT_MODEL, FLAG, F(fit), NO_FIELD, NULL, 0, NULL, NULL,
     "scale and centre the model to fill the view"},
    {"scene", 0, RAS_OPT_SCENE, FILE_ARG, F(scene), NO_FIELD, NULL, 0, "a scene FILE (JSON)",
     "FILE", "the scene to draw (JSON, docs/scenes.md; default: the built-in\nscene of this "
             "assignment); the options here override it"},
    {"compare", 0, RAS_OPT_COMPARE, FLAG, F(compare), NO_FIELD, NULL, 0, NULL, NULL,
     "render once, compare with the reference for these settings\n(from catalogue.json), "
     "write a difference image"},
    {"reference", 0, RAS_OPT_COMPARE, FILE_ARG, F(reference), NO_FIELD, NULL, 0, "an image FILE",
     "FILE", "with --compare: the reference image to compare with"},
    {"stats", 0, RAS_OPT_STATS, FLAG, F(stats), NO_FIELD, NULL, 0, NULL, NULL,
     "print what each pipeline stage did, as JSON on stdout"},
    {"renderer", 0, RAS_OPT_RENDERER, TEXT, F(renderer), NO_FIELD, NULL, 0,
     "a renderer NAME such as teaching", "NAME",
     "who draws the frames: teaching (default: the pipeline\nstage by stage, as taught), or a "
     "faster renderer the\nprogram offers (the same picture)"},
    {"dump", 0, 0, FILE_ARG, F(dump), NO_FIELD, NULL, 0, "a folder DIR for the buffers", "DIR",
     "with -o: also write the frame's intermediate buffers into DIR\n(created if missing): "
     "coverage, depth, overdraw, normal, uv,\nview_depth, sample_colour (anti-aliased) or hw1's "
     "vertices,\neach as a picture, an exact .pfm and a .json\n(docs/debugging.md)"},
    {"force", 0, 0, FLAG, F(force), NO_FIELD, NULL, 0, NULL, NULL,
     "replace output files even when write-protected (mode 444);\nwithout it they are "
     "refused before any work"},
    {"memory-limit", 0, 0, MEMORY, NO_FIELD, NO_FIELD, NULL, 0, "a number of MiB such as 4096",
     "MB", "refuse inputs estimated to need more memory (default: half\nof physical memory, at "
           "most 2048; also RAS_MEMORY_LIMIT_MB)"},
    {"help", 'h', 0, HELP, NO_FIELD, NO_FIELD, NULL, 0, NULL, NULL, "this help"},
    {"version", 0, 0, VERSION, NO_FIELD, NO_FIELD, NULL, 0, NULL, NULL, "the version"},
};
#define OPTION_COUNT ((int)(sizeof options / sizeof options[0]))

/* getopt_long's view of the table: val is the row's index + 256. */
static struct option g_long_options[OPTION_COUNT + 1];
static char g_short_options[2 * OPTION_COUNT + 2];

static void build_getopt_tables(void) {
    int n = 0;
    g_short_options[n++] = ':'; /* report a missing value as ':' */
    for (int i = 0; i < OPTION_COUNT; i++) {
        bool has_arg = options[i].kind != FLAG && options[i].kind != HELP &&
                       options[i].kind != VERSION;
        g_long_options[i] = (struct option){
            options[i].name, has_arg ? required_argument : no_argument, NULL, 256 + i};
        if (options[i].letter) {
            g_short_options[n++] = options[i].letter;
            if (has_arg) g_short_options[n++] = ':';
        }
    }
    g_long_options[OPTION_COUNT] = (struct option){NULL, 0, NULL, 0};
    g_short_options[n] = '\0';
}

/* The row of getopt's answer (a short letter or 256 + index); NULL if none. */
static const option_row *row_of(int opt) {
    if (opt >= 256 && opt < 256 + OPTION_COUNT) return &options[opt - 256];
    for (int i = 0; i < OPTION_COUNT; i++)
        if (options[i].letter && options[i].letter == opt) return &options[i];
    return NULL;
}

/* What the row's value looks like: its own words, or its table's names. */
static const char *value_of(const option_row *r, char *buf, size_t size) {
    if (!r) return "a value";
    if (r->kind == NAME) return ras_names_list(r->names, r->first, buf, size);
    return r->value ? r->value : "a value";
}

static bool parse_float(const char *s, float *out) {
    char *end = NULL;
    float v = strtof(s, &end);
    if (end == s || *end != '\0' || !isfinite(v)) return false;
    *out = v;
    return true;
}

static bool parse_int(const char *s, long lo, long hi, int *out) {
    char *end = NULL;
    long v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi) return false;
    *out = (int)v;
    return true;
}

/* --size: digits 'x' digits, nothing else (sscanf alone would take
 * "10x10junk", " 10x10" or "+10x10"). */
static bool parse_size(const char *arg, ras_cli *out) {
    size_t w_len = strspn(arg, "0123456789");
    bool shape = w_len > 0 && w_len < 6 && arg[w_len] == 'x';
    if (shape) {
        size_t h_len = strspn(arg + w_len + 1, "0123456789");
        shape = h_len > 0 && h_len < 6 && arg[w_len + 1 + h_len] == '\0';
    }
    return shape && sscanf(arg, "%dx%d", &out->width, &out->height) == 2 && out->width >= 1 &&
           out->height >= 1 && out->width <= 8192 && out->height <= 8192;
}

static bool parse_axis(const char *arg, vec3s *axis) {
    float x, y, z;
    char tail;
    if (sscanf(arg, "%f,%f,%f%c", &x, &y, &z, &tail) != 3 || !isfinite(x) || !isfinite(y) ||
        !isfinite(z) || (x == 0 && y == 0 && z == 0))
        return false;
    *axis = (vec3s){{x, y, z}};
    return true;
}

/* Stores one option's value in `out` (its row says where and how); false
 * with err set when the value is not one the row takes. */
static bool store(const option_row *r, const char *arg, ras_cli *out, ras_error *err) {
    char *base = (char *)out, list[128];
    bool ok = true;
    const char *expects = NULL; /* the "expects ..." message when !ok */
    switch (r->kind) {
    case FLAG: *(bool *)(base + r->field) = true; break;
    case FILE_ARG:
    case TEXT: *(const char **)(base + r->field) = arg; break;
    case NAME: {
        int v = ras_name_find(r->names, arg, r->first);
        ok = v >= 0;
        if (ok) *(int *)(base + r->field) = v;
        expects = value_of(r, list, sizeof list);
        break;
    }
    case SIZE:
        ok = parse_size(arg, out);
        expects = "WIDTHxHEIGHT between 1x1 and 8192x8192, e.g. --size 700x700";
        break;
    case ANGLE:
        ok = parse_float(arg, (float *)(base + r->field));
        expects = "a finite number of degrees, e.g. -r 20";
        break;
    case AXIS:
        ok = parse_axis(arg, (vec3s *)(base + r->field));
        expects = "three numbers X,Y,Z, not all zero, e.g. --axis 0,1,0";
        break;
    case SAMPLES:
        ok = parse_int(arg, 1, RAS_MAX_SAMPLES, (int *)(base + r->field));
        expects = "a whole number of samples per pixel (1, 2, 4, 8, 16 or 64)";
        break;
    case MEMORY: return ras_memory_set_limit_mb(arg, err);
    case HELP:
    case VERSION: break;
    }
    if (!ok)
        return ras_error_set(err, "--%s expects %s; got '%s'", r->name, expects, arg);
    if (r->set_flag != NO_FIELD) *(bool *)(base + r->set_flag) = true;
    return true;
}

/* The long options `word` (after "--", up to any '=') abbreviates; *match is
 * one of them. */
static int prefix_matches(const char *word, const struct option **match) {
    size_t len = strcspn(word, "=");
    int n = 0;
    for (const struct option *o = g_long_options; o->name; o++)
        if (!strncmp(o->name, word, len)) {
            if (strlen(o->name) == len) { /* exact: not ambiguous */
                *match = o;
                return 1;
            }
            *match = o;
            n++;
        }
    return n;
}

/* Whether two names are the same file (or the same name for a file that
 * does not exist yet). */
static bool same_path(const char *a, const char *b) {
    if (!strcmp(a, b)) return true;
    char *ra = realpath(a, NULL), *rb = realpath(b, NULL);
    bool same = ra && rb && !strcmp(ra, rb);
    free(ra);
    free(rb);
    return same;
}

/* getopt's '?' (unknown, ambiguous, or a value given to a flag) and ':' (a
 * value missing) as a message. `word` is the word as typed. */
static bool getopt_error(int opt, const char *word, unsigned accepted, const char *program,
                         ras_error *err) {
    /* An unknown letter inside a cluster ("-xr") leaves optind on its word,
     * so only optopt tells a long option (0, >= 256, or --help=) from a
     * short one there. */
    bool long_word = !strncmp(word, "--", 2);
    if (opt == '?')
        long_word = optopt == 0 || optopt >= 256 || (optopt == 'h' && long_word && strchr(word, '='));
    const struct option *match = NULL;
    int n = long_word ? prefix_matches(word + 2, &match) : 0;
    int len = (int)strcspn(word, "=");
    if (opt == '?' && long_word) {
        if (n == 1 && match->has_arg == no_argument && strchr(word, '='))
            return ras_error_set(err, "option '--%s' takes no value; got '%s'; write it as just "
                                      "'--%s'", match->name, word, match->name);
        if (n > 1)
            return ras_error_set(err, "option '%.*s' is ambiguous: it starts more than one "
                                      "option name; write the option out in full (run '%s "
                                      "--help' for the list)", len, word, program);
        return ras_error_set(err, "unknown option '%.*s'; run '%s --help' for the options it "
                                  "takes", len, word, program);
    }
    char letter = optopt > 32 && optopt < 127 ? (char)optopt : '?';
    if (opt == '?')
        return ras_error_set(err, "unknown option '-%c'; run '%s --help' for the options it takes",
                             letter, program);
    /* ':' — optopt is the short letter or the long option's value. */
    const option_row *r = row_of(long_word && n == 1 ? match->val : optopt);
    char name[64], list[128];
    if (long_word) snprintf(name, sizeof name, "--%s", match ? match->name : word + 2);
    else snprintf(name, sizeof name, "-%c", letter);
    if (r && r->group && !(r->group & accepted))
        return ras_error_set(err, "option '%s' does not apply to this program; run '%s --help' "
                                  "for the options it takes", name, program);
    return ras_error_set(err, "option '%s' needs a value: expected %s after it, got the end of "
                              "the command line", name, value_of(r, list, sizeof list));
}

/* A file option's value that is empty or looks like an option (`-o --size
 * 9x9`: getopt took the option as the file name), or that is too long for
 * the programs' buffers (refused, never cut). */
static bool check_file_value(const option_row *r, const char *name, const char *arg,
                             ras_error *err) {
    if (!arg[0])
        return ras_error_set(err, "option '%s' expects %s, got an empty name", name, r->value);
    if (arg[0] == '-' && arg[1])
        return ras_error_set(err, "option '%s' expects %s, got '%s', which looks like an option; "
                                  "give the file name after %s (a file whose name starts with "
                                  "'-' is written ./%s)", name, r->value, arg, name, arg);
    return ras_io_path_fits(name, arg, err);
}

/* -o must not land on the --reference image, nor on the difference images
 * written beside it (OUT_diff.png, OUT_worst.png): --compare reads the
 * reference before the render overwrites anything. */
static bool check_reference_output(const ras_cli *out, ras_error *err) {
    if (!out->reference || !out->output) return true;
    if (same_path(out->reference, out->output))
        return ras_error_set(err, "-o %s would overwrite the --reference image it is compared "
                                  "with; write the render to another file", out->output);
    static const char *const suffixes[] = {"diff", "worst"};
    for (int k = 0; k < 2; k++) {
        char sibling[RAS_IO_MAX_PATH + 16];
        ras_cli_sibling_path(out->output, NULL, suffixes[k], sibling, sizeof sibling);
        if (same_path(out->reference, sibling))
            return ras_error_set(err, "--compare writes its difference image to %s, which is "
                                      "the --reference image; name -o differently", sibling);
    }
    return true;
}

ras_cli_status ras_cli_parse(int argc, char **argv, unsigned accepted, ras_cli *out,
                             ras_error *err) {
    *out = (ras_cli){.axis = {{0, 0, 1}}};
    const char *program = argc > 0 ? argv[0] : "program";
    if (!g_long_options[0].name) build_getopt_tables();
    optind = 0; /* glibc: 0 re-initialises getopt fully, so parsing twice works */
    opterr = 0; /* we write our own messages */
    int opt;
    while ((opt = getopt_long(argc, argv, g_short_options, g_long_options, NULL)) != -1) {
        /* The word that went wrong, as typed: "--name[=value]" or "-x". */
        const char *word = optind > 0 && optind <= argc ? argv[optind - 1] : "";
        if (opt == '?' || opt == ':') {
            getopt_error(opt, word, accepted, program, err);
            return RAS_CLI_ERROR;
        }
        const option_row *r = row_of(opt);
        char name[64];
        if (opt >= 256) snprintf(name, sizeof name, "--%s", r->name);
        else snprintf(name, sizeof name, "-%c", opt);
        if (r->group && !(r->group & accepted)) {
            ras_error_set(err, "option '%s' does not apply to this program; run '%s --help' for "
                               "the options it takes", name, program);
            return RAS_CLI_ERROR;
        }
        if (r->kind == HELP) return RAS_CLI_HELP;
        if (r->kind == VERSION) return RAS_CLI_VERSION;
        if ((r->kind == FILE_ARG && !check_file_value(r, name, optarg, err)) ||
            !store(r, optarg, out, err))
            return RAS_CLI_ERROR;
    }
    if (!check_reference_output(out, err) || !ras_memory_check_env(err)) return RAS_CLI_ERROR;
    if (out->reference && !out->compare) {
        ras_error_set(err, "--reference FILE goes with --compare (it names the image to compare "
                           "with); add --compare, or drop --reference");
        return RAS_CLI_ERROR;
    }
    for (int i = optind; i < argc; i++) {
        if (out->positional_count == RAS_CLI_MAX_POSITIONAL) {
            ras_error_set(err, "too many arguments ('%s' is one more than %d); run '%s --help'",
                          argv[i], RAS_CLI_MAX_POSITIONAL, program);
            return RAS_CLI_ERROR;
        }
        if (!ras_io_path_fits("a file argument", argv[i], err)) return RAS_CLI_ERROR;
        out->positional[out->positional_count++] = argv[i];
    }
    return RAS_CLI_RUN;
}

void ras_cli_help(unsigned accepted, const char *program, const char *usage, char *buf,
                  int size) {
    int n = snprintf(buf, (size_t)size, "Usage: %s [options]\n%s\nOptions:\n", program, usage);
#define ADD(...)                                                                              \
    do {                                                                                      \
        if (n >= 0 && n < size) n += snprintf(buf + n, (size_t)(size - n), __VA_ARGS__);     \
    } while (0)
    for (int i = 0; i < OPTION_COUNT; i++) {
        const option_row *r = &options[i];
        if (r->group && !(r->group & accepted)) continue;
        char letter[8] = "", words[40];
        if (r->letter) snprintf(letter, sizeof letter, "-%c,", r->letter);
        snprintf(words, sizeof words, "--%s%s%s", r->name, r->arg ? " " : "", r->arg ? r->arg : "");
        ADD("  %-4s%-17s ", letter, words);
        char text[256], list[128];
        if (r->kind == NAME && strstr(r->help, "%s"))
            snprintf(text, sizeof text, r->help, ras_names_list(r->names, r->first, list, sizeof list));
        else
            snprintf(text, sizeof text, "%s", r->help);
        /* The help text, each further line indented under the first. */
        for (const char *line = text; line;) {
            const char *nl = strchr(line, '\n');
            ADD("%.*s\n", nl ? (int)(nl - line) : (int)strlen(line), line);
            line = nl ? nl + 1 : NULL;
            if (line) ADD("%24s", "");
        }
    }
    ADD("Exit status: 0 done, 1 the render or writing failed, 2 bad options or input\n"
        "(nothing is written then).%s\n",
        accepted & RAS_OPT_COMPARE ? " With --compare: 0 the images match, 1 they differ, 2 they could not be compared." : "");
#undef ADD
}

void ras_cli_sibling_path(const char *output, const char *fallback_stem, const char *suffix,
                          char *buf, size_t size) {
    if (!output) {
        snprintf(buf, size, "%s_%s.png", fallback_stem ? fallback_stem : "out", suffix);
        return;
    }
    const char *dot = strrchr(output, '.'), *slash = strrchr(output, '/');
    int stem = (dot && (!slash || dot > slash)) ? (int)(dot - output) : (int)strlen(output);
    snprintf(buf, size, "%.*s_%s.png", stem, output, suffix);
}

void ras_cli_reuse_freed_memory(void) {
#ifdef __GLIBC__
    /* Below 32 MiB (glibc's largest mmap threshold) from the heap, and at
     * most 256 MiB of freed heap kept instead of trimmed. */
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, 256 * 1024 * 1024);
#endif
}
