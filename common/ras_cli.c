/* ras_cli.c — see ras_cli.h. */
#include "ras_cli.h"

#include "ras_io.h"     /* ras_io_path_fits */
#include "ras_memory.h" /* ras_memory_set_limit_mb */

#include <getopt.h> /* getopt_long */
#include <math.h>   /* isfinite */
#include <stdio.h>  /* snprintf, sscanf */
#include <stdlib.h> /* strtof, strtol, realpath */
#include <string.h> /* strcmp */
#ifdef __GLIBC__
#include <malloc.h> /* mallopt */
#endif

enum {
    OPT_AXIS = 256,
    OPT_AA,
    OPT_SAMPLES,
    OPT_PATTERN,
    OPT_EDGES,
    OPT_DEPTH,
    OPT_COMPARE,
    OPT_REFERENCE,
    OPT_SHADER,
    OPT_FILTER,
    OPT_MODEL,
    OPT_TEXTURE,
    OPT_HEIGHT,
    OPT_FIT,
    OPT_SCENE,
    OPT_STATS,
    OPT_RENDERER,
    OPT_SIZE,
    OPT_VERSION,
    OPT_MEMORY_LIMIT,
};

static const struct option long_options[] = {
    {"help", no_argument, NULL, 'h'},         {"version", no_argument, NULL, OPT_VERSION},
    {"output", required_argument, NULL, 'o'}, {"size", required_argument, NULL, OPT_SIZE},
    {"angle", required_argument, NULL, 'r'},  {"axis", required_argument, NULL, OPT_AXIS},
    {"aa", required_argument, NULL, OPT_AA},  {"samples", required_argument, NULL, OPT_SAMPLES},
    {"pattern", required_argument, NULL, OPT_PATTERN},
    {"edges", required_argument, NULL, OPT_EDGES},
    {"depth", required_argument, NULL, OPT_DEPTH},
    {"compare", no_argument, NULL, OPT_COMPARE},
    {"reference", required_argument, NULL, OPT_REFERENCE},
    {"shader", required_argument, NULL, OPT_SHADER},
    {"filter", required_argument, NULL, OPT_FILTER},
    {"model", required_argument, NULL, OPT_MODEL},
    {"texture", required_argument, NULL, OPT_TEXTURE},
    {"height", required_argument, NULL, OPT_HEIGHT},
    {"fit", no_argument, NULL, OPT_FIT},
    {"scene", required_argument, NULL, OPT_SCENE},
    {"stats", no_argument, NULL, OPT_STATS},
    {"renderer", required_argument, NULL, OPT_RENDERER},
    {"memory-limit", required_argument, NULL, OPT_MEMORY_LIMIT},
    {NULL, 0, NULL, 0}};

/* Which group each option belongs to (0: always accepted). */
static unsigned group_of(int opt) {
    switch (opt) {
    case 'r': case OPT_AXIS: return RAS_OPT_ANGLE;
    case OPT_AA: case OPT_SAMPLES: case OPT_PATTERN: case OPT_EDGES: case OPT_DEPTH: return RAS_OPT_AA;
    case OPT_COMPARE: case OPT_REFERENCE: return RAS_OPT_COMPARE;
    case OPT_SHADER: case OPT_FILTER: return RAS_OPT_SHADING;
    case OPT_MODEL: case OPT_TEXTURE: case OPT_HEIGHT: case OPT_FIT: return RAS_OPT_MODEL;
    case OPT_SCENE: return RAS_OPT_SCENE;
    case OPT_STATS: return RAS_OPT_STATS;
    case OPT_RENDERER: return RAS_OPT_RENDERER;
    default: return 0;
    }
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

/* What an option's value looks like, for "needs a value" messages. */
static const char *metavar_of(int opt) {
    switch (opt) {
    case 'o': return "an output FILE such as out.png";
    case OPT_SIZE: return "WIDTHxHEIGHT such as 700x700";
    case 'r': return "an angle in degrees such as 20";
    case OPT_AXIS: return "an axis X,Y,Z such as 0,1,0";
    case OPT_AA: return "none, msaa or ssaa";
    case OPT_SAMPLES: return "a sample count such as 4";
    case OPT_PATTERN: return "ordered or standard";
    case OPT_EDGES: return "fixed or float";
    case OPT_DEPTH: return "z01 or inverse_w";
    case OPT_SHADER: return "normal, phong, texture, bump or displacement";
    case OPT_FILTER: return "nearest, bilinear or trilinear";
    case OPT_REFERENCE: return "an image FILE";
    case OPT_MODEL: return "a model FILE (OBJ, PLY, STL, glTF, ...)";
    case OPT_TEXTURE:
    case OPT_HEIGHT: return "an image FILE";
    case OPT_SCENE: return "a scene FILE (JSON)";
    case OPT_RENDERER: return "a renderer NAME such as teaching";
    case OPT_MEMORY_LIMIT: return "a number of MiB such as 4096";
    default: return "a value";
    }
}

/* The options whose value is a file name. */
static bool takes_file(int opt) {
    return opt == 'o' || opt == OPT_REFERENCE || opt == OPT_MODEL || opt == OPT_TEXTURE ||
           opt == OPT_HEIGHT || opt == OPT_SCENE;
}

/* The long options `word` (after "--", up to any '=') abbreviates; *match is
 * one of them. */
static int prefix_matches(const char *word, const struct option **match) {
    size_t len = strcspn(word, "=");
    int n = 0;
    for (const struct option *o = long_options; o->name; o++)
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

ras_cli_status ras_cli_parse(int argc, char **argv, unsigned accepted, ras_cli *out,
                             ras_error *err) {
    *out = (ras_cli){.axis = {{0, 0, 1}}};
    const char *program = argc > 0 ? argv[0] : "program";
    optind = 0; /* glibc: 0 re-initialises getopt fully, so parsing twice works */
    opterr = 0; /* we write our own messages */
    for (;;) {
        int index = -1;
        int opt = getopt_long(argc, argv, ":ho:r:", long_options, &index);
        if (opt == -1) break;
        const char *arg = optarg;
        /* Name the option as the user typed it: argv[optind - 1] would be its
         * value when the value came as a separate word. */
        /* The word that went wrong, as typed: "--name[=value]" or "-x". An
         * unknown letter inside a cluster ("-xr") leaves optind on its word,
         * so only optopt tells a long option (0 or a value >= 256, or --help=)
         * from a short one there. */
        const char *word = optind > 0 && optind <= argc ? argv[optind - 1] : "";
        bool long_word = !strncmp(word, "--", 2);
        if (opt == '?')
            long_word =
                optopt == 0 || optopt >= 256 || (optopt == 'h' && long_word && strchr(word, '='));
        char name[64];
        if (index >= 0) snprintf(name, sizeof name, "--%s", long_options[index].name);
        else if (opt != '?' && opt != ':') snprintf(name, sizeof name, "-%c", opt);
        else
            snprintf(name, sizeof name, "%s", word);
        if (opt == '?' && long_word) {
            const struct option *match = NULL;
            int n = prefix_matches(word + 2, &match);
            if (n == 1 && match->has_arg == no_argument && strchr(word, '='))
                ras_error_set(err,
                              "option '--%s' takes no value; got '%s'; write it as just "
                              "'--%s'",
                              match->name, word, match->name);
            else if (n > 1)
                ras_error_set(err,
                              "option '%.*s' is ambiguous: it starts more than one option "
                              "name; write the option out in full (run '%s --help' for "
                              "the list)",
                              (int)strcspn(word, "="), word, program);
            else
                ras_error_set(err,
                              "unknown option '%.*s'; run '%s --help' for the options it "
                              "takes",
                              (int)strcspn(word, "="), word, program);
            return RAS_CLI_ERROR;
        }
        if (opt == '?') {
            ras_error_set(err, "unknown option '-%c'; run '%s --help' for the options it takes",
                          optopt > 32 && optopt < 127 ? optopt : '?', program);
            return RAS_CLI_ERROR;
        }
        if (opt == ':') {
            /* optopt is the short letter or the long option's value. */
            int which = optopt;
            if (long_word) {
                const struct option *match = NULL;
                if (prefix_matches(word + 2, &match) == 1) which = match->val;
                snprintf(name, sizeof name, "--%s", match ? match->name : word + 2);
            } else {
                snprintf(name, sizeof name, "-%c", optopt > 32 && optopt < 127 ? optopt : '?');
            }
            unsigned g = group_of(which);
            if (g && !(g & accepted))
                ras_error_set(err,
                              "option '%s' does not apply to this program; run '%s --help' "
                              "for the options it takes",
                              name, program);
            else
                ras_error_set(err,
                              "option '%s' needs a value: expected %s after it, got the "
                              "end of the command line",
                              name, metavar_of(which));
            return RAS_CLI_ERROR;
        }
        unsigned group = group_of(opt);
        if (group && !(group & accepted)) {
            ras_error_set(err,
                          "option '%s' does not apply to this program; run '%s --help' for "
                          "the options it takes",
                          name, program);
            return RAS_CLI_ERROR;
        }
        /* A file option followed by another option (`-o --size 9x9`): getopt
         * takes the option as the file name. Names starting with '-' need ./ */
        if (takes_file(opt) && (!arg[0] || (arg[0] == '-' && arg[1]))) {
            if (!arg[0])
                ras_error_set(err, "option '%s' expects %s, got an empty name", name,
                              metavar_of(opt));
            else
                ras_error_set(err,
                              "option '%s' expects %s, got '%s', which looks like an option; "
                              "give the file name after %s (a file whose name starts with "
                              "'-' is written ./%s)",
                              name, metavar_of(opt), arg, name, arg);
            return RAS_CLI_ERROR;
        }
        /* A file name longer than the programs' buffers is refused, never cut. */
        if (takes_file(opt) && !ras_io_path_fits(name, arg, err)) return RAS_CLI_ERROR;
        switch (opt) {
        case 'h': return RAS_CLI_HELP;
        case OPT_VERSION: return RAS_CLI_VERSION;
        case 'o': out->output = arg; break;
        case OPT_SIZE: {
            /* Digits 'x' digits, nothing else: sscanf alone would take
             * "10x10junk", " 10x10" or "+10x10". */
            size_t w_len = strspn(arg, "0123456789");
            bool shape = w_len > 0 && w_len < 6 && arg[w_len] == 'x';
            if (shape) {
                size_t h_len = strspn(arg + w_len + 1, "0123456789");
                shape = h_len > 0 && h_len < 6 && arg[w_len + 1 + h_len] == '\0';
            }
            if (!shape || sscanf(arg, "%dx%d", &out->width, &out->height) != 2 || out->width < 1 ||
                out->height < 1 || out->width > 8192 || out->height > 8192) {
                ras_error_set(err, "--size expects WIDTHxHEIGHT between 1x1 and 8192x8192, "
                                   "e.g. --size 700x700; got '%s'", arg);
                return RAS_CLI_ERROR;
            }
            break;
        }
        case 'r':
            if (!parse_float(arg, &out->angle)) {
                ras_error_set(err, "--angle expects a finite number of degrees, e.g. -r 20; "
                                   "got '%s'", arg);
                return RAS_CLI_ERROR;
            }
            out->angle_set = true;
            break;
        case OPT_AXIS: {
            float x, y, z;
            char tail;
            if (sscanf(arg, "%f,%f,%f%c", &x, &y, &z, &tail) != 3 || !isfinite(x) ||
                !isfinite(y) || !isfinite(z) || (x == 0 && y == 0 && z == 0)) {
                ras_error_set(err, "--axis expects three numbers X,Y,Z, not all zero, e.g. "
                                   "--axis 0,1,0; got '%s'", arg);
                return RAS_CLI_ERROR;
            }
            out->axis = (vec3s){{x, y, z}};
            out->axis_set = true;
            break;
        }
        case OPT_AA:
            if (!strcmp(arg, "none")) out->aa = RAS_AA_NONE;
            else if (!strcmp(arg, "msaa")) out->aa = RAS_AA_MSAA;
            else if (!strcmp(arg, "ssaa")) out->aa = RAS_AA_SSAA;
            else {
                ras_error_set(err, "--aa expects none, msaa or ssaa; got '%s'", arg);
                return RAS_CLI_ERROR;
            }
            out->aa_set = true;
            break;
        case OPT_SAMPLES:
            if (!parse_int(arg, 1, RAS_MAX_SAMPLES, &out->samples)) {
                ras_error_set(err, "--samples expects a whole number of samples per pixel "
                                   "(1, 2, 4, 8, 16 or 64); got '%s'", arg);
                return RAS_CLI_ERROR;
            }
            break;
        case OPT_PATTERN:
            if (!strcmp(arg, "ordered")) out->pattern = RAS_PATTERN_ORDERED;
            else if (!strcmp(arg, "standard")) out->pattern = RAS_PATTERN_STANDARD;
            else {
                ras_error_set(err, "--pattern expects ordered or standard; got '%s'", arg);
                return RAS_CLI_ERROR;
            }
            out->pattern_set = true;
            break;
        case OPT_EDGES:
            if (!strcmp(arg, "fixed")) out->edges = RAS_EDGES_FIXED;
            else if (!strcmp(arg, "float")) out->edges = RAS_EDGES_FLOAT;
            else {
                ras_error_set(err, "--edges expects fixed or float; got '%s'", arg);
                return RAS_CLI_ERROR;
            }
            out->edges_set = true;
            break;
        case OPT_DEPTH: {
            int f = 0;
            while (f < RAS_DEPTH_FORMAT_COUNT && strcmp(arg, ras_depth_format_names[f]))
                f++;
            if (f == RAS_DEPTH_FORMAT_COUNT) {
                ras_error_set(err, "--depth expects z01 or inverse_w; got '%s'", arg);
                return RAS_CLI_ERROR;
            }
            out->depth = (ras_depth_format)f;
            out->depth_set = true;
            break;
        }
        case OPT_COMPARE: out->compare = true; break;
        case OPT_REFERENCE: out->reference = arg; break;
        case OPT_SHADER: out->shader = arg; break;
        case OPT_FILTER: out->filter = arg; break;
        case OPT_MODEL: out->model = arg; break;
        case OPT_TEXTURE: out->texture = arg; break;
        case OPT_HEIGHT: out->height_map = arg; break;
        case OPT_FIT: out->fit = true; break;
        case OPT_SCENE: out->scene = arg; break;
        case OPT_MEMORY_LIMIT:
            if (!ras_memory_set_limit_mb(arg, err)) return RAS_CLI_ERROR;
            break;
        case OPT_STATS: out->stats = true; break;
        case OPT_RENDERER: out->renderer = arg; break;
        default: break;
        }
    }
    if (out->reference && out->output) {
        /* --compare reads the reference before the render overwrites -o. */
        if (same_path(out->reference, out->output)) {
            ras_error_set(err,
                          "-o %s would overwrite the --reference image it is compared with; "
                          "write the render to another file",
                          out->output);
            return RAS_CLI_ERROR;
        }
        /* Nor may the difference images written beside -o (OUT_diff.png,
         * OUT_worst.png) land on it. */
        static const char *const suffixes[] = {"_diff", "_worst"};
        const char *dot = strrchr(out->output, '.'), *slash = strrchr(out->output, '/');
        int stem = (dot && (!slash || dot > slash)) ? (int)(dot - out->output)
                                                    : (int)strlen(out->output);
        for (int k = 0; k < 2; k++) {
            char sibling[RAS_IO_MAX_PATH + 16];
            snprintf(sibling, sizeof sibling, "%.*s%s.png", stem, out->output, suffixes[k]);
            if (same_path(out->reference, sibling)) {
                ras_error_set(err,
                              "--compare writes its difference image to %s, which is the "
                              "--reference image; name -o differently",
                              sibling);
                return RAS_CLI_ERROR;
            }
        }
    }
    if (!ras_memory_check_env(err)) return RAS_CLI_ERROR;
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
        if (n < size) n += snprintf(buf + n, (size_t)(size - n), __VA_ARGS__);                \
    } while (0)
    ADD("  -o, --output FILE     render once without a window and write FILE (.png; .jpg, .bmp,\n"
        "                        .ppm and .tif work too)\n");
    ADD("      --size WxH        image size in pixels, 1x1 to 8192x8192 (default: the scene's)\n");
    if (accepted & RAS_OPT_ANGLE) {
        ADD("  -r, --angle DEG       rotation angle in degrees\n");
        ADD("      --axis X,Y,Z      rotate about this axis (bonus: get_rotation)\n");
    }
    if (accepted & RAS_OPT_AA) {
        ADD("      --aa MODE         anti-aliasing: none, msaa or ssaa\n");
        ADD("      --samples N       samples per pixel (ordered: 4, 16, 64; standard: 2, 4, "
            "8, 16)\n");
        ADD("      --pattern P       sample positions: ordered (grid) or standard (D3D/Vulkan)\n");
        ADD("      --edges E         reference edge functions: fixed (watertight) or float\n");
        ADD("      --depth F         depth format: z01 ((1-z)/2, default) or inverse_w\n"
            "                        (-near/w: reversed-z, precise far away; docs/accuracy.md)\n");
    }
    if (accepted & RAS_OPT_SHADING) {
        ADD("      --shader NAME     normal, phong, texture, bump or displacement\n");
        ADD("      --filter NAME     texture filter: nearest, bilinear or trilinear\n");
    }
    if (accepted & RAS_OPT_MODEL) {
        ADD("      --model FILE      a model file (OBJ, PLY, STL, glTF, ...)\n");
        ADD("      --texture FILE    colour texture image\n");
        ADD("      --height FILE     height map for bump / displacement\n");
        ADD("      --fit             scale and centre the model to fill the view\n");
    }
    if (accepted & RAS_OPT_SCENE)
        ADD("      --scene FILE      the scene to draw (JSON, docs/scenes.md; default: the "
            "built-in\n                        scene of this assignment); the options here "
            "override it\n");
    if (accepted & RAS_OPT_COMPARE) {
        ADD("      --compare         compare the render with its reference image and write a "
            "difference image\n");
        ADD("      --reference FILE  with --compare: the reference image to compare with\n");
    }
    if (accepted & RAS_OPT_STATS)
        ADD("      --stats           print what each pipeline stage did, as JSON on stdout\n");
    if (accepted & RAS_OPT_RENDERER)
        ADD("      --renderer NAME   who draws the frames: teaching (default: the pipeline\n"
            "                        stage by stage, as taught), or a faster renderer the\n"
            "                        program offers (the same picture)\n");
    ADD("      --memory-limit MB refuse inputs estimated to need more memory (default: half\n"
        "                        of physical memory, at most 2048; also RAS_MEMORY_LIMIT_MB)\n");
    ADD("  -h, --help            this help\n");
    ADD("      --version         the version\n");
    ADD("Exit status: 0 done, 1 the render or writing failed, 2 bad options or input\n"
        "(nothing is written then).%s\n",
        accepted & RAS_OPT_COMPARE ? " With --compare: 0 the images match, 1 they differ." : "");
#undef ADD
}

void ras_cli_reuse_freed_memory(void) {
#ifdef __GLIBC__
    /* Below 32 MiB (glibc's largest mmap threshold) from the heap, and at
     * most 256 MiB of freed heap kept instead of trimmed. */
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, 256 * 1024 * 1024);
#endif
}
