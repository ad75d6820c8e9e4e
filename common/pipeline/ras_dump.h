/* ras_dump.h — a frame's intermediate buffers as files (--dump DIR).
 *
 * The colour picture hides most rasterizer mistakes; the buffers behind it
 * show them: back faces speckling through the depth buffer, samples never
 * covered, a triangle shaded twice, normals or UVs that jump. Each buffer is
 * written as three files in DIR:
 *   NAME.png   a picture a person can read: false colour (turbo: blue is the
 *              smallest value, red the largest) or the vector as RGB, with a
 *              legend strip below saying what the colours mean;
 *   NAME.pfm   the exact floats (OpenCV's PFM, read back bit for bit, ±Inf
 *              included), one or three channels;
 *   NAME.json  what it is, its units, its size and layout, and the range of
 *              its values (the --stats style).
 * Only buffers the frame produced exist: without anti-aliasing there is no
 * coverage file, without a texture no UV file. Files are written atomically
 * (ras_io.h): a failure leaves no half-written file.
 *
 * Layout of `data`: row-major, TOP image row first (like ras_image and the
 * framebuffer), `channels` floats per entry. With `samples` > 1 each pixel
 * owns `samples` consecutive entries (sample s of pixel x at column
 * x*samples + s), exactly as the framebuffer stores them: the PFM is then
 * (width*samples) x height, and the picture shows each pixel's mean over
 * its non-empty samples.
 */
#ifndef RAS_DUMP_H
#define RAS_DUMP_H

#include "ras_error.h"
#include "ras_math.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum ras_dump_style {
    RAS_DUMP_SCALAR, /* one channel, false colour over its finite range */
    RAS_DUMP_VECTOR, /* three channels in [-1, 1] (a normal), shown as 0.5 + 0.5 v */
    RAS_DUMP_UNIT,   /* two or three channels in [0, 1] (u, v); outside it the fraction is shown */
} ras_dump_style;

typedef struct ras_dump_buffer {
    const char *name;  /* the file stem: depth, coverage, overdraw, normal, uv, view_depth */
    const char *what;  /* one sentence for the sidecar */
    const char *units; /* e.g. "depth format z01: 0 at near, 1 at far" */
    int width, height, samples, channels;
    const float *data;
    ras_dump_style style;
    /* entries equal to `empty` (compared bitwise after NaN checks: +INF for
     * a cleared depth) mean "nothing here": black in the picture, left out of
     * the range, counted in the sidecar */
    float empty;
    bool has_empty;
    /* a scalar's colours over [range[0], range[1]] instead of its own range
     * (two buffers drawn comparably); NULL: its own */
    const double *range;
} ras_dump_buffer;

/* Writes NAME.png, NAME.pfm and NAME.json into dir (which must exist). */
bool ras_dump_write(const char *dir, const ras_dump_buffer *b, ras_error *err);

/* The buffer's picture without the legend, as NAME.png draws it: width x
 * height 8-bit RGB, top row first (the window's buffer view). `legend`
 * (may be NULL) gets the legend's sentence, e.g. "depth: 0.41 (blue) ..
 * 0.93 (red); black: empty". */
void ras_dump_paint(const ras_dump_buffer *b, uint8_t *rgb, char *legend, size_t size);

/* Reads an exact float file back: malloc'd floats (free them), its size and
 * channels. A path ending in .gz is gunzipped first (the reference buffers
 * ship compressed), at most 256 MiB of it. The PFM is decoded here, its
 * header's size checked against the bytes that follow (OpenCV is not used:
 * its PFM decoder leaves /tmp/__opencv_temp.* files when it fails). */
float *ras_dump_read_pfm(const char *path, int *width, int *height, int *channels, ras_error *err);

/* Floats (1 or 3 channels, top row first) as a PFM file image, the bytes
 * OpenCV's encoder wrote ("PF"/"Pf", the size, scale -1: little-endian,
 * rows bottom first), made here: OpenCV's encoder goes through a temporary
 * file in /tmp, which a file-size limit or a kill leaves behind. malloc'd;
 * NULL when out of memory. */
uint8_t *ras_dump_encode_pfm(int width, int height, int channels, const float *data, size_t *len);

/* A folder given to raster101-compare --buffers exists, is a folder, and
 * holds one frame's files (every sidecar names the same frame, every
 * buffer file has its sidecar's size): false and err naming it otherwise
 * (an error, not a mismatch). */
bool ras_dump_check_input_dir(const char *dir, ras_error *err);

/* The buffers a dump may hold, in the order a frame makes them (NULL-ended):
 * the first one that differs from the reference is where to look first. */
extern const char *const ras_dump_buffer_names[];

/* Whether a dump in dir holds buffer `name` exactly (NAME.pfm, or the
 * shipped references' NAME.pfm.gz): what ras_dump_compare can read. */
bool ras_dump_has_exact(const char *dir, const char *name);

/* How buffer NAME of one dump differs from another's (ras_dump_compare). */
typedef struct ras_dump_difference {
    long entries;       /* floats compared (all channels and samples) */
    long pixels_differ; /* pixels with any entry beyond the tolerance */
    long drawn_in_one;  /* pixels empty in one dump and not in the other */
    long isolated;      /* differing pixels with at most 2 differing neighbours */
    long larger;        /* differing pixels where got's first differing value is the larger */
    int line;           /* a row (or column) wrong along it while its neighbours are
                         * not: its index; -1 when there is none */
    bool line_is_column;
    double max_abs;           /* largest difference where both have a value */
    long finite_differ;       /* entries beyond the tolerance where both are finite */
    long nonfinite_got;       /* entries NaN or inf in got, the reference's other */
    long nonfinite_ref;       /* entries NaN or inf in the reference where got is finite */
    int first_col, first_row; /* first differing pixel (image col, row) */
    const char *pattern;      /* "in speckles", "along a row", "along a column",
                               * "where only one drew", "in regions" */
} ras_dump_difference;

/* Compares buffer `name` of the dumps in ref_dir and got_dir with the
 * tolerance of its kind (depth and view_depth 1e-5 relative, normal 1e-3, uv
 * 1e-4, coverage and overdraw exact). d->pixels_differ == 0: the same.
 * got_dir's file may be hostile: it is read only if no larger than the
 * reference's (plus its header) and must have the reference's size. False
 * with err when a file is missing or unreadable. */
bool ras_dump_compare(const char *ref_dir, const char *got_dir, const char *name,
                      ras_dump_difference *d, ras_error *err);

/* One line for a difference: "depth differs in 3112 of 490000 pixels (max
 * 0.0021), in speckles: 2900 isolated, the first at (120, 340)". */
void ras_dump_difference_text(const char *name, const ras_dump_difference *d, char *buf,
                              size_t size);

/* hw1's buffer is its vertices: vertices.json holds, for each vertex of the
 * mesh (at most the first 4096), its position at every step of the vertex
 * stage (into STEM.json: "vertices", or "vertices_1" for a scene's second
 * object) — object, world (model), eye (view), clip (projection), NDC (the
 * divide by w) and screen (the viewport, y up, pixel centres at +0.5) — so
 * a wrong matrix shows at the step where the numbers go wrong. */
struct ras_mesh;
bool ras_dump_vertices(const char *dir, const char *stem, const struct ras_mesh *mesh,
                       mat4s model, mat4s view, mat4s projection, int width, int height,
                       ras_error *err);

/* The pictures of one buffer of two dumps, drawn to be compared, into
 * out_dir: reference.png and yours.png (a scalar on the reference's range),
 * difference.png (the largest difference of each pixel's entries; 1 where
 * one is empty and the other not), each with its .pfm and .json. got_dir's
 * file is read under ras_dump_compare's rules. */
bool ras_dump_compare_pictures(const char *ref_dir, const char *got_dir, const char *name,
                               const char *out_dir, ras_error *err);

/* Compares two vertices.json (ras_dump_vertices) step by step: 0 the same
 * (within 1e-5, relative above 1), 1 they differ — `text` says at which
 * vertex and step first ("vertex 0: world differs: expected (1.88, 0.68,
 * -2), got ...": the matrix of that step is the one to look at) — and -1
 * when a file is missing or not a vertex dump (text says why). */
int ras_dump_compare_vertices(const char *ref_path, const char *got_path, char *text,
                              size_t size);

/* The folder for --dump: created if missing (one level), refused when it is
 * a file; false with err set. */
bool ras_dump_prepare_dir(const char *dir, ras_error *err);

/* --dump all or nothing: the buffers are written into a temporary folder
 * beside the target (DIR's folder/.NAME-XXXXXX), and moved into place only
 * when every one is written (ras_dump_stage_commit): a new DIR is the
 * temporary folder renamed (mode 0777 & ~umask, as mkdir makes it); into
 * an existing DIR the older frame's dump files (buffer and vertex files of
 * the known names) the new frame lacks are removed and each new file is
 * renamed over its old copy (other files there are left alone). Commits
 * into one parent folder take turns under a flock on it; a stage is locked
 * by its owner while live, so the next dump there removes a stage whose
 * lock it can take (its owner died, kill -9 included). SIGINT, SIGTERM and
 * SIGHUP remove the stage before the process dies of them. A failure
 * removes the temporary folder and leaves DIR as it was. ras_dump_stage_begin checks,
 * before any work, that DIR is (or can be) a folder this run may write. */
typedef struct ras_dump_stage {
    char target[1100];
    char temp[1400]; /* where the buffers go until the commit */
    bool active, existed, begun;
    int parent_fd, temp_fd; /* the parent's lock; the stage's own, held while live */
} ras_dump_stage;
/* The frame's name every sidecar records ("frame"): a new one for each
 * ras_dump_stage_begin. ras_dump_check_input_dir (what --buffers reads
 * first) refuses a folder whose sidecars name two frames, or whose buffer
 * files are not the size their sidecar says. */
const char *ras_dump_frame_id(void);
bool ras_dump_stage_begin(ras_dump_stage *stage, const char *dir, ras_error *err);
bool ras_dump_stage_commit(ras_dump_stage *stage, ras_error *err);
/* Removes the temporary folder and what is in it (nothing when committed). */
void ras_dump_stage_abort(ras_dump_stage *stage);

#endif
