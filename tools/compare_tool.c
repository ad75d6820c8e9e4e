/* compare_tool.c — raster101-compare: compares two images from the command
 * line with the metrics of common/app/ras_compare.h.
 *
 *   raster101-compare --metric exact|edge|psnr|ssim EXPECTED.png GOT.png
 *                     [--tolerance N] [--max-bad F] [--min-psnr DB] [--min-ssim S]
 *                     [--diff HEATMAP.png] [--crop CROP.png] [--mask]
 *   raster101-compare --as NAME [--catalogue FILE] EXPECTED.png GOT.png [...]
 *   raster101-compare --buffers REFERENCE_DIR GOT_DIR [--pictures OUT_DIR]
 *
 * --as NAME judges with comparison NAME of the catalogue's table
 * (tests/reference/catalogue.json, "comparisons"; e.g. textured, bumped):
 * the grader's and the programs' --compare thresholds, so the verdict and
 * the numbers are the grade's. With --as, --metric and the threshold flags
 * are refused (the table decides).
 *
 * --buffers compares two --dump folders buffer by buffer, in the order a frame
 * makes them (vertices, coverage, depth, overdraw, normal, uv, view_depth,
 * sample_colour), each with
 * its kind's tolerance (common/pipeline/ras_dump.h), and names the first that differs:
 * where a picture is wrong, the first wrong buffer says which stage made it.
 * --pictures OUT_DIR draws that buffer for both, on the reference's range,
 * and their difference (reference.png, yours.png, difference.png).
 *
 * Prints the one-line summary of ras_compare_result (and, with --mask, the
 * ASCII coverage window around the worst pixel, background black). Exit
 * status: 0 the images match, 1 they do not, 2 error (bad arguments,
 * unreadable image, sizes differ). The grader (tests/grading/grade) uses the same
 * module in-process; this tool is for students and scripts.
 */
#include "ras_catalogue.h"
#include "ras_compare.h"
#include "ras_dump.h"
#include "ras_image.h"
#include "ras_memory.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void usage(FILE *out) {
    fputs("usage: raster101-compare --metric exact|edge|psnr|ssim EXPECTED GOT\n"
          "         [--tolerance N] [--max-bad FRACTION] [--min-psnr DB] [--min-ssim S]\n"
          "         [--diff OUT.png] [--crop OUT.png] [--mask] [--memory-limit MB]\n"
          "       raster101-compare --as NAME [--catalogue FILE] EXPECTED GOT [--diff ...]\n"
          "judges with comparison NAME of the catalogue (the grader's thresholds).\n"
          "Compares GOT (the image under test) with EXPECTED (the reference).\n"
          "--memory-limit MB (or RAS_MEMORY_LIMIT_MB): refuse images estimated to need\n"
          "more (default: half of physical memory, at most 2048).\n"
          "       raster101-compare --buffers REFERENCE_DIR GOT_DIR [--pictures OUT_DIR]\n"
          "Compares two --dump folders buffer by buffer and names the first that differs.\n"
          "Exit status: 0 match, 1 mismatch, 2 error.\n",
          out);
}

static bool parse_double(const char *s, double *v) {
    char *end;
    *v = strtod(s, &end);
    return end != s && *end == '\0' && !isnan(*v);
}

/* Each number option's range, checked before any image is read: out of range
 * the comparison would assert (tolerance) or never fail (a negative --max-bad). */
static bool number_in_range(const char *option, const char *text, double v, double lo, double hi,
                            bool whole, const char *what) {
    if (v >= lo && v <= hi && (!whole || v == (double)(long)v)) return true;
    fprintf(stderr, "raster101-compare: %s expects %s; got '%s'\n", option, what, text);
    return false;
}

/* --diff and --crop are written after the comparison: check their names first. */
static bool output_ok(const char *option, const char *path) {
    ras_error err = {{0}};
    if (!path || ras_image_check_output(path, &err)) return true;
    fprintf(stderr, "raster101-compare: %s: %s\n", option, err.msg);
    return false;
}

/* Estimated bytes per pixel of each image compared: measured 43 (decode,
 * float image, the metric's buffers) on two 6000x6000 TIFFs. */
#define COMPARE_BYTES_PER_PIXEL 48.0

/* Whether two names are the same existing file (hard links and ./a.png too). */
static bool same_file(const char *a, const char *b) {
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

/* A buffer the shipped reference keeps as its picture only (NAME.png):
 * GOT's own NAME.png, painted by the same code from its exact floats, is
 * compared with it pixel by pixel above the legend strip. Normals and UVs
 * are painted without a range (0.5 + 0.5 n; u, v as they are), so equal
 * floats give equal pictures: one 8-bit level is allowed for rounding, and
 * the w = 1 mistake (UVs off by hundredths) shows in thousands of pixels.
 * Returns the pixels that differ by more (first one in *col, *row), or -1
 * with `why` set when the pictures cannot be compared. */
static long compare_buffer_pictures(const char *ref_dir, const char *got_dir, const char *name,
                                    int *col, int *row, int *worst, char *why, size_t size) {
    char rp[4200], gp[4200], gpfm[4200];
    snprintf(rp, sizeof rp, "%s/%s.png", ref_dir, name);
    snprintf(gp, sizeof gp, "%s/%s.png", got_dir, name);
    snprintf(gpfm, sizeof gpfm, "%s/%s.pfm", got_dir, name);
    ras_error err = {{0}};
    int w = 0, h = 0, ch = 0;
    float *exact = ras_dump_read_pfm(gpfm, &w, &h, &ch, &err);
    free(exact);
    ras_image *a = exact ? ras_image_load(rp, &err) : NULL;
    ras_image *b = a ? ras_image_load(gp, &err) : NULL;
    long differ = -1;
    if (!b)
        snprintf(why, size, "%s", err.msg);
    else if (a->width != b->width || a->height != b->height || a->width != w || a->height < h)
        snprintf(why, size, "the pictures are %dx%d and %dx%d; expected the frame's %dx%d above "
                 "the legend in both", a->width, a->height, b->width, b->height, w, h);
    else {
        differ = 0;
        *worst = 0, *col = -1, *row = -1;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                vec3s p = ras_image_get(a, x, y), q = ras_image_get(b, x, y);
                int d = 0;
                for (int k = 0; k < 3; k++) {
                    int e = abs(ras_unit_to_byte(p.raw[k]) - ras_unit_to_byte(q.raw[k]));
                    d = e > d ? e : d;
                }
                if (d > *worst) *worst = d;
                if (d > 1 && differ++ == 0) *col = x, *row = y;
            }
    }
    ras_image_destroy(a);
    ras_image_destroy(b);
    return differ;
}

/* --buffers: each buffer of the reference's dump against the same of GOT. */
static int compare_buffers(const char *ref_dir, const char *got_dir, const char *pictures) {
    int differing = 0, compared = 0;
    ras_error derr = {{0}};
    if (!ras_dump_check_input_dir(ref_dir, &derr) || !ras_dump_check_input_dir(got_dir, &derr)) {
        fprintf(stderr, "raster101-compare: %s\n", derr.msg);
        return 2;
    }
    /* hw1's buffer: its vertices, step by step */
    char rv[4200], gv[4200];
    snprintf(rv, sizeof rv, "%s/vertices.json", ref_dir);
    snprintf(gv, sizeof gv, "%s/vertices.json", got_dir);
    if (access(rv, F_OK) == 0 || access(gv, F_OK) == 0) {
        char line[600];
        int r = ras_dump_compare_vertices(rv, gv, line, sizeof line);
        if (r < 0) {
            fprintf(stderr, "raster101-compare: %s\n", line);
            return 2;
        }
        printf("%s\n", line);
        compared++;
        if (r && differing++ == 0) printf("first differing buffer: vertices\n");
    }
    for (int i = 0; ras_dump_buffer_names[i]; i++) {
        const char *name = ras_dump_buffer_names[i];
        char ref_desc[4200], got_pfm[4200];
        snprintf(ref_desc, sizeof ref_desc, "%s/%s.json", ref_dir, name);
        snprintf(got_pfm, sizeof got_pfm, "%s/%s.pfm", got_dir, name); /* a dump: uncompressed */
        bool in_ref = ras_dump_has_exact(ref_dir, name), in_got = access(got_pfm, F_OK) == 0;
        if (!in_ref && in_got && access(ref_desc, F_OK) == 0) {
            /* the shipped references keep some buffers as pictures only */
            compared++;
            if (strcmp(name, "normal") && strcmp(name, "uv")) {
                printf("%s: the reference has its picture only (%s/%s.png), painted on its own "
                       "range: compare by eye\n",
                       name, ref_dir, name);
                continue;
            }
            int col, row, worst;
            char why[1200];
            long differ = compare_buffer_pictures(ref_dir, got_dir, name, &col, &row, &worst, why,
                                                  sizeof why);
            if (differ < 0) {
                fprintf(stderr, "raster101-compare: %s: %s\n", name, why);
                return 2;
            }
            if (differ == 0)
                printf("%s: the same as the reference's picture (within one 8-bit level; the "
                       "reference keeps no exact file)\n",
                       name);
            else
                printf("%s differs in %ld pixels of its picture (largest difference %d/255), the "
                       "first at (%d, %d) (the reference keeps its picture only)\n",
                       name, differ, worst, col, row);
            if (differ && differing++ == 0) printf("first differing buffer: %s\n", name);
            continue;
        }
        if (!in_ref && !in_got) continue;
        if (!in_ref && !strcmp(name, "sample_colour") && access(ref_desc, F_OK) != 0) {
            /* the shipped reference buffers keep no per-sample colour (the
             * grader dumps both frames afresh and compares it) */
            printf("%s: not in the reference folder: not compared\n", name);
            continue;
        }
        compared++;
        if (in_ref != in_got) {
            printf("%s: only in %s (the other frame %s it)\n", name,
                   in_ref ? "the reference" : "yours",
                   in_ref ? "did not make" : "made no such buffer: the reference does not have");
            if (differing++ == 0) printf("first differing buffer: %s\n", name);
            continue;
        }
        ras_dump_difference d;
        ras_error err = {{0}};
        if (!ras_dump_compare(ref_dir, got_dir, name, &d, &err)) {
            fprintf(stderr, "raster101-compare: %s\n", err.msg);
            return 2;
        }
        char line[512];
        ras_dump_difference_text(name, &d, line, sizeof line);
        printf("%s\n", line);
        if (d.pixels_differ && differing++ == 0) {
            printf("first differing buffer: %s\n", name);
            if (pictures && !(ras_dump_prepare_dir(pictures, &err) &&
                              ras_dump_compare_pictures(ref_dir, got_dir, name, pictures, &err))) {
                fprintf(stderr, "raster101-compare: --pictures: %s\n", err.msg);
                return 2;
            }
            if (pictures) printf("wrote %s/reference.png, yours.png, difference.png\n", pictures);
        }
    }
    if (compared == 0) {
        fprintf(stderr,
                "raster101-compare: --buffers found no buffer files in '%s' or '%s' "
                "(expected the folders of two --dump runs)\n",
                ref_dir, got_dir);
        return 2;
    }
    return differing ? 1 : 0;
}

/* What the command line asked for; NaN thresholds were not given. */
typedef struct compare_args {
    const char *metric, *diff_path, *crop_path, *as, *catalogue_path;
    double tol, max_bad, min_psnr, min_ssim;
    bool mask;
    int first_image; /* argv index of EXPECTED (optind) */
} compare_args;

/* Parses the options of the image comparison into a; -1 to go on, else the
 * exit status (0 after --help, 2 on a bad option, said on stderr). */
static int parse_args(int argc, char **argv, compare_args *a) {
    enum { OPT_TOL = 256, OPT_MAXBAD, OPT_PSNR, OPT_SSIM, OPT_MASK, OPT_MEMORY, OPT_AS, OPT_CAT };
    static const struct option longopts[] = {{"metric", required_argument, NULL, 'm'},
                                             {"diff", required_argument, NULL, 'd'},
                                             {"crop", required_argument, NULL, 'c'},
                                             {"tolerance", required_argument, NULL, OPT_TOL},
                                             {"max-bad", required_argument, NULL, OPT_MAXBAD},
                                             {"min-psnr", required_argument, NULL, OPT_PSNR},
                                             {"min-ssim", required_argument, NULL, OPT_SSIM},
                                             {"mask", no_argument, NULL, OPT_MASK},
                                             {"help", no_argument, NULL, 'h'},
                                             {"memory-limit", required_argument, NULL, OPT_MEMORY},
                                             {"as", required_argument, NULL, OPT_AS},
                                             {"catalogue", required_argument, NULL, OPT_CAT},
                                             {NULL, 0, NULL, 0}};
    *a = (compare_args){.catalogue_path = RAS_REFERENCE_DIR "/catalogue.json",
                        .tol = NAN, .max_bad = NAN, .min_psnr = NAN, .min_ssim = NAN};
    int c;
    while ((c = getopt_long(argc, argv, "m:d:c:h", longopts, NULL)) != -1) {
        double *target = NULL;
        const char *option = "";
        switch (c) {
        case 'm': a->metric = optarg; break;
        case 'd': a->diff_path = optarg; break;
        case 'c': a->crop_path = optarg; break;
        case OPT_TOL: target = &a->tol, option = "--tolerance"; break;
        case OPT_MAXBAD: target = &a->max_bad, option = "--max-bad"; break;
        case OPT_PSNR: target = &a->min_psnr, option = "--min-psnr"; break;
        case OPT_SSIM: target = &a->min_ssim, option = "--min-ssim"; break;
        case OPT_MASK: a->mask = true; break;
        case OPT_AS: a->as = optarg; break;
        case OPT_CAT: a->catalogue_path = optarg; break;
        case OPT_MEMORY: {
            ras_error merr = {{0}};
            if (!ras_memory_set_limit_mb(optarg, &merr)) {
                fprintf(stderr, "raster101-compare: %s\n", merr.msg);
                return 2;
            }
            break;
        }
        case 'h': usage(stdout); return 0;
        default: usage(stderr); return 2; /* getopt named the option */
        }
        if (target && !parse_double(optarg, target)) {
            fprintf(stderr, "raster101-compare: %s expects a number; got '%s'\n", option, optarg);
            return 2;
        }
        if ((target == &a->tol &&
             !number_in_range("--tolerance", optarg, a->tol, 0, 255, true, "a whole number 0..255")) ||
            (target == &a->max_bad && !number_in_range("--max-bad", optarg, a->max_bad, 0, 1, false,
                                                       "a fraction of the pixels, 0..1")) ||
            (target == &a->min_psnr &&
             !number_in_range("--min-psnr", optarg, a->min_psnr, 0, INFINITY, false,
                              "decibels, 0 or more (inf: identical)")) ||
            (target == &a->min_ssim &&
             !number_in_range("--min-ssim", optarg, a->min_ssim, -1, 1, false, "a value -1..1")))
            return 2;
    }
    a->first_image = optind;
    return -1;
}

/* The comparison the arguments name: --as's row of the catalogue, or
 * --metric's defaults with the thresholds given over them. False (said on
 * stderr) when they name none, or both. */
static bool comparison_options(int argc, const compare_args *a, ras_compare_options *opt,
                               ras_compare_kind *kind) {
    const char *metric = a->metric;
    if (a->as && (metric || !isnan(a->tol) || !isnan(a->max_bad) || !isnan(a->min_psnr) ||
                  !isnan(a->min_ssim))) {
        fprintf(stderr, "raster101-compare: --as %s takes its metric and thresholds from the "
                        "catalogue; expected no --metric, --tolerance, --max-bad, --min-psnr or "
                        "--min-ssim with it\n",
                a->as);
        return false;
    }
    ras_compare_options table_opt;
    if (a->as) {
        ras_catalogue *cat = malloc(sizeof *cat);
        ras_error cerr = {{0}};
        bool found = cat && ras_catalogue_load(a->catalogue_path, cat, &cerr) &&
                     ras_catalogue_comparison_options(cat, a->as, &table_opt, &cerr);
        free(cat);
        if (!found) {
            fprintf(stderr, "raster101-compare: --as %s: %s\n", a->as,
                    cerr.msg[0] ? cerr.msg : "out of memory");
            return false;
        }
        metric = ras_compare_kind_name(table_opt.kind);
    }
    if (!metric) {
        fprintf(stderr, "raster101-compare: expected --metric exact|edge|psnr|ssim or --as NAME; "
                        "got none\n");
        usage(stderr);
        return false;
    }
    int images = argc - a->first_image;
    if (images != 2) {
        fprintf(stderr,
                "raster101-compare: expected two images, EXPECTED and GOT; got %d argument%s\n",
                images, images == 1 ? "" : "s");
        usage(stderr);
        return false;
    }
    if (!output_ok("--diff", a->diff_path) || !output_ok("--crop", a->crop_path)) return false;
    ras_error err = {{0}};
    if (!ras_compare_kind_parse(metric, kind, &err)) {
        fprintf(stderr, "raster101-compare: %s\n", err.msg);
        return false;
    }
    *opt = a->as ? table_opt : ras_compare_defaults(*kind);
    if (!isnan(a->tol)) opt->tolerance = (int)a->tol;
    if (!isnan(a->max_bad)) opt->max_bad_fraction = a->max_bad;
    if (!isnan(a->min_psnr)) opt->min_psnr_db = a->min_psnr;
    if (!isnan(a->min_ssim)) opt->min_ssim = a->min_ssim;
    return true;
}

/* Before anything is decoded: the memory budget, and no output over an
 * input. False (said on stderr) when the comparison must not start. */
static bool inputs_ok(const compare_args *a, const char *expected_path, const char *got_path) {
    ras_error err = {{0}};
    if (!ras_memory_check_env(&err)) {
        fprintf(stderr, "raster101-compare: %s\n", err.msg);
        return false;
    }
    /* --diff or --crop over one of the inputs would destroy it. */
    const char *outputs[2][2] = {{"--diff", a->diff_path}, {"--crop", a->crop_path}};
    for (int k = 0; k < 2; k++)
        if (outputs[k][1] &&
            (same_file(outputs[k][1], expected_path) || same_file(outputs[k][1], got_path))) {
            fprintf(stderr,
                    "raster101-compare: %s '%s' would overwrite one of the images being "
                    "compared; expected a new file name, e.g. diff.png\n",
                    outputs[k][0], outputs[k][1]);
            return false;
        }
    /* Both images, the comparison's own buffers and the heat map, estimated
     * from the files' headers before either is decoded. */
    long ew = 0, eh = 0, gw = 0, gh = 0;
    if (ras_image_peek_file(expected_path, &ew, &eh) && ras_image_peek_file(got_path, &gw, &gh)) {
        char what[2400];
        snprintf(what, sizeof what, "comparing '%s' (%ldx%ld) with '%s' (%ldx%ld)", expected_path,
                 ew, eh, got_path, gw, gh);
        if (!ras_memory_check(((double)ew * (double)eh + (double)gw * (double)gh) *
                                  COMPARE_BYTES_PER_PIXEL,
                              what, "compare smaller images", &err)) {
            fprintf(stderr, "raster101-compare: %s\n", err.msg);
            return false;
        }
    }
    return true;
}

/* The summary line, then what was asked besides (--mask, --diff, --crop);
 * the exit status: 0 match, 1 differ, 2 an error. */
static int report(const compare_args *a, const ras_image *expected, const ras_image *got,
                  const ras_compare_options *opt, ras_compare_kind kind) {
    ras_error err = {{0}};
    ras_compare_result r;
    ras_comparison *cmp = ras_comparison_create(expected, got, kind, &err);
    if (!cmp || !ras_comparison_result(cmp, opt, &r, &err)) {
        fprintf(stderr, "raster101-compare: %s\n", err.msg);
        ras_comparison_destroy(cmp);
        return 2;
    }
    printf("%s\n", r.summary);
    int status = r.pass ? 0 : 1;
    if (a->mask) {
        char buf[4096];
        if (ras_compare_ascii_mask(expected, got, (vec3s){{0, 0, 0}},
                                   r.worst_col < 0 ? 0 : r.worst_col,
                                   r.worst_row < 0 ? 0 : r.worst_row, 12, buf, sizeof buf, &err))
            printf("coverage around (%d,%d), %s:\n%s", r.worst_col, r.worst_row,
                   RAS_COMPARE_ASCII_LEGEND, buf);
    }
    if (a->diff_path) {
        ras_image *heat = ras_comparison_heatmap(cmp, &err);
        if (!heat || !ras_image_save(heat, a->diff_path, &err)) {
            fprintf(stderr, "raster101-compare: --diff: %s\n", err.msg);
            status = 2;
        }
        ras_image_destroy(heat);
    }
    if (a->crop_path) {
        ras_image *crop = ras_comparison_crop(cmp, r.worst_col, r.worst_row, &err);
        if (!crop || !ras_image_save(crop, a->crop_path, &err)) {
            fprintf(stderr, "raster101-compare: --crop: %s\n", err.msg);
            status = 2;
        }
        ras_image_destroy(crop);
    }
    ras_comparison_destroy(cmp);
    return status;
}

int main(int argc, char **argv) {
    if (argc >= 2 && !strcmp(argv[1], "--buffers")) {
        bool with_pictures = argc == 6 && !strcmp(argv[4], "--pictures");
        if (argc != 4 && !with_pictures) {
            fprintf(stderr,
                    "raster101-compare: --buffers expects two folders (the reference's "
                    "--dump, then yours), then optionally --pictures OUT_DIR; got %d "
                    "argument(s)\n",
                    argc - 2);
            usage(stderr);
            return 2;
        }
        return compare_buffers(argv[2], argv[3], with_pictures ? argv[5] : NULL);
    }
    compare_args a;
    int status = parse_args(argc, argv, &a);
    if (status >= 0) return status;
    ras_compare_options opt;
    ras_compare_kind kind;
    if (!comparison_options(argc, &a, &opt, &kind)) return 2;
    const char *expected_path = argv[a.first_image], *got_path = argv[a.first_image + 1];
    if (!inputs_ok(&a, expected_path, got_path)) return 2;
    ras_error err = {{0}};
    ras_image *expected = ras_image_load(expected_path, &err);
    if (!expected) {
        fprintf(stderr, "raster101-compare: expected image: %s\n", err.msg);
        return 2;
    }
    ras_image *got = ras_image_load(got_path, &err);
    if (!got) {
        fprintf(stderr, "raster101-compare: got image: %s\n", err.msg);
        ras_image_destroy(expected);
        return 2;
    }
    status = report(&a, expected, got, &opt, kind);
    ras_image_destroy(expected);
    ras_image_destroy(got);
    return status;
}
