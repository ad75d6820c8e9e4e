/* ras_compare.h — comparing a rendered image against a reference image.
 *
 * Used by the programs' --compare flag, by the grader and by the tests. One
 * call answers "does it match, and if not, where and how badly"; helpers turn
 * the answer into pictures and text a student can act on.
 *
 * Conventions (stated once, as stb does):
 *   - `expected` is always the reference, `got` the image under test; every
 *     message uses those two words;
 *   - both images are quantised to 8 bits per channel with ras_unit_to_byte
 *     before any metric, so an image compares the same in memory as after a
 *     round trip through PNG (reference images are stored as PNG);
 *   - a pixel's difference is in 8-bit levels (0..255): the largest absolute
 *     difference over R, G and B, so a wrong channel is never averaged away;
 *   - positions are (col, row), row 0 = top row, as in ras_image;
 *   - functions return false / NULL only when they cannot compare (sizes
 *     differ, out of memory) and then fill `err`; whether the images MATCH
 *     is result.pass, not the return value;
 *   - returned images are heap ras_images the caller frees with
 *     ras_image_destroy; nothing here keeps state between calls.
 *
 * Metrics (ras_compare_kind):
 *   EXACT          per-pixel difference as above; for coverage masks, where
 *                  any changed pixel is a bug.
 *   EDGE_TOLERANT  per pixel p, max( min over q in N(p) of |got(p) - expected(q)|,
 *                                    min over q in N(p) of |expected(p) - got(q)| )
 *                  with N(p) the 3x3 neighbourhood of p, clipped at the
 *                  image border. Both directions are needed: the first alone
 *                  forgives a missing one-pixel line, the second alone an
 *                  extra one. A one-pixel shift of an anti-aliased edge costs
 *                  nothing; a missing or extra triangle costs its whole area.
 *   PSNR           10*log10(255^2 / MSE), MSE over all pixels and the three
 *                  channels of the 8-bit values; INFINITY for identical
 *                  images (which passes any threshold).
 *   SSIM           mean SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) on luma
 *                  Y = 0.299 R + 0.587 G + 0.114 B (8-bit scale, unrounded),
 *                  Gaussian 11x11 window with sigma 1.5, C1 = (0.01*255)^2,
 *                  C2 = (0.03*255)^2. Unlike Wang's reference code, which
 *                  drops a 5-pixel border, every pixel gets a window: at the
 *                  border the window is clipped and its weights renormalised,
 *                  so a wrong border still counts and tiny images work.
 * The per-pixel difference of PSNR and SSIM is the plain one of EXACT; their
 * bad-pixel counts and worst pixel are reported for diagnosis.
 */
#ifndef RAS_COMPARE_H
#define RAS_COMPARE_H

#include "ras_error.h"
#include "ras_image.h"

#include <stdbool.h>
#include <stddef.h> /* size_t */

typedef enum ras_compare_kind {
    RAS_COMPARE_EXACT,
    RAS_COMPARE_EDGE_TOLERANT,
    RAS_COMPARE_PSNR,
    RAS_COMPARE_SSIM,
} ras_compare_kind;

/* Short lowercase name for flags and messages: "exact", "edge", "psnr", "ssim". */
const char *ras_compare_kind_name(ras_compare_kind kind);

/* Parses a name from ras_compare_kind_name (also "edge_tolerant"); false and
 * err naming the accepted names when it is none of them. */
bool ras_compare_kind_parse(const char *name, ras_compare_kind *kind, ras_error *err);

/* What counts as a match. The image passes when ALL three checks hold:
 *     bad_pixels <= floor(max_bad_fraction * width * height)
 *     psnr_db    >= min_psnr_db
 *     ssim       >= min_ssim
 * where a bad pixel is one whose difference (of `kind`) exceeds `tolerance`.
 * ras_compare_defaults disables the checks that are not the kind's own
 * (max_bad_fraction = 1, min_psnr_db = min_ssim = -INFINITY); set them to
 * combine, e.g. PSNR >= 30 dB and no more than 1% of pixels off by > 8. */
typedef struct ras_compare_options {
    ras_compare_kind kind;
    int tolerance;           /* 8-bit levels 0..255; "bad" is strictly greater */
    double max_bad_fraction; /* 0..1 of all pixels; 1 disables the check */
    double min_psnr_db;      /* -INFINITY disables the check */
    double min_ssim;         /* -INFINITY disables the check */
} ras_compare_options;

/* Defaults, chosen so a correct renderer passes on any machine and a real bug
 * fails:
 *   EXACT          tolerance 0, max_bad_fraction 0   (no pixel may change)
 *   EDGE_TOLERANT  tolerance 8, max_bad_fraction 0.0005 (245 pixels of a
 *                  700x700 frame, e.g. a missing triangle of 22x22 pixels
 *                  slips through; tighten for tests with small primitives)
 *   PSNR           tolerance 8 (diagnostic), min_psnr_db 35
 *   SSIM           tolerance 8 (diagnostic), min_ssim 0.98 */
ras_compare_options ras_compare_defaults(ras_compare_kind kind);

#define RAS_COMPARE_SUMMARY_SIZE 384

typedef struct ras_compare_result {
    ras_compare_kind kind;
    int width, height;
    double value;        /* the kind's headline: bad_fraction for EXACT and
                            EDGE_TOLERANT, psnr_db for PSNR, ssim for SSIM */
    double psnr_db;      /* always computed; INFINITY when identical */
    double ssim;         /* always computed; 1 when identical */
    long bad_pixels;     /* difference > options.tolerance */
    double bad_fraction; /* bad_pixels / (width * height) */
    int max_diff;        /* largest per-pixel difference, 8-bit levels */
    int worst_col, worst_row; /* first pixel (row-major) with max_diff;
                                 -1, -1 when max_diff is 0 */
    bool pass;
    /* One line, no newline: each enabled check with expected vs got, then
     * the bad pixels and the worst one, e.g.
     * "psnr FAIL: PSNR 27.3 dB < 35.0 dB required; 1204 pixels (0.246%)
     *  differ by more than 8/255, worst at (351,120) by 40/255" */
    char summary[RAS_COMPARE_SUMMARY_SIZE];
} ras_compare_result;

/* Before rendering for a comparison: is the reference `path` (loaded as
 * `expected`) the size of the render (width x height)? false with err
 * "cannot compare: the reference ... is AxB, the render would be CxD; ..."
 * naming the --size that would fit, so the programs refuse up front. */
bool ras_compare_reference_fits(const ras_image *expected, const char *path, int width, int height,
                                ras_error *err);

/* The bytes a comparison of two width x height images holds at its peak
 * (the 8-bit copies and difference map, 7 a pixel, with SSIM's seven
 * double-precision maps, 56 a pixel: 4.2 GB at 8192x8192), so a program can
 * count it in the budget before it draws anything. */
double ras_compare_work_bytes(int width, int height);

/* Compares `got` against `expected` under `opt` and fills `out`. Returns
 * false (err: "expected 700x700 (the reference), got 512x512 ...") when the
 * sizes differ or memory runs out; `out` then has pass false and no
 * measurements (all zero, worst pixel -1, -1). */
bool ras_compare_images(const ras_image *expected, const ras_image *got,
                        const ras_compare_options *opt, ras_compare_result *out,
                        ras_error *err);

/* A picture of the per-pixel difference of `kind` (so EDGE_TOLERANT shows
 * only what it counts): black where the difference is 0, otherwise
 * t = sqrt(diff / 255) through dark blue (t -> 0), cyan (1/3), yellow (2/3)
 * to red (t = 1). The scale is fixed, not normalised per image, so the same
 * difference has the same colour in every run and every image; the sqrt
 * keeps one-level differences visible (dark blue) next to black. */
ras_image *ras_compare_heatmap(const ras_image *expected, const ras_image *got,
                               ras_compare_kind kind, ras_error *err);

/* The worst-region crop: a RAS_COMPARE_CROP_SIDE-square window around
 * (col, row), magnified RAS_COMPARE_CROP_ZOOM times (nearest neighbour), as
 * three panels left to right: expected | got | heatmap of `kind`, separated by
 * RAS_COMPARE_CROP_GAP grey columns. The window is shifted to stay inside the
 * image (so (col, row) is centred only away from the border), and (col, row)
 * itself is clamped into the image, so result.worst_col/row = -1 is fine.
 * The pixel at (col, row) is outlined in white on the heatmap panel. In
 * images smaller than the window, pixels outside the image are a grey
 * checkerboard. Size: RAS_COMPARE_CROP_WIDTH x RAS_COMPARE_CROP_HEIGHT. */
#define RAS_COMPARE_CROP_SIDE 32
#define RAS_COMPARE_CROP_ZOOM 8
#define RAS_COMPARE_CROP_GAP 4
#define RAS_COMPARE_CROP_WIDTH \
    (3 * RAS_COMPARE_CROP_SIDE * RAS_COMPARE_CROP_ZOOM + 2 * RAS_COMPARE_CROP_GAP)
#define RAS_COMPARE_CROP_HEIGHT (RAS_COMPARE_CROP_SIDE * RAS_COMPARE_CROP_ZOOM)
ras_image *ras_compare_crop(const ras_image *expected, const ras_image *got,
                            ras_compare_kind kind, int col, int row, ras_error *err);

/* One comparison, many answers: the 8-bit copies and the difference map of
 * `kind` made once, then the result, the heatmap and the crop read from them
 * (each is what the function above of the same name returns, for a fraction
 * of its cost: the grader asks all three of every picture). opt->kind must be
 * the comparison's kind. NULL / false and err as above. */
typedef struct ras_comparison ras_comparison;
ras_comparison *ras_comparison_create(const ras_image *expected, const ras_image *got,
                                      ras_compare_kind kind, ras_error *err);
bool ras_comparison_result(const ras_comparison *c, const ras_compare_options *opt,
                           ras_compare_result *out, ras_error *err);
ras_image *ras_comparison_heatmap(const ras_comparison *c, ras_error *err);
ras_image *ras_comparison_crop(const ras_comparison *c, int col, int row, ras_error *err);
void ras_comparison_destroy(ras_comparison *c);

/* Coverage masks as text, for failure messages. A pixel is covered when its
 * 8-bit value differs from `background` in any channel. Writes the window of
 * columns col-radius..col+radius and rows row-radius..row+radius, clipped to
 * the image, one line per row, top row first, each line ending in '\n', with
 *   '#' covered in both   '.' covered in neither
 *   '+' covered only in got (extra)   '-' covered only in expected (missing)
 * A full window needs (2*radius+2)*(2*radius+1)+1 bytes of `buf`. Returns
 * false (err says how many bytes) when `size` is too small, or when the sizes
 * differ; `buf` then holds an empty string (if size > 0). */
#define RAS_COMPARE_ASCII_LEGEND \
    "'#' covered in both, '.' in neither, '+' only in got, '-' only in expected"
bool ras_compare_ascii_mask(const ras_image *expected, const ras_image *got,
                            vec3s background, int col, int row, int radius, char *buf,
                            size_t size, ras_error *err);

#endif
