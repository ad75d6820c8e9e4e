/* ras_viewer.h — the window the three programs share: your picture, the
 * reference picture, or their difference, with a status line.
 *
 * A program renders a frame between ras_viewer_frame_begin/end (the status
 * line shows how long it took), names the reference image for its current
 * settings (ras_viewer_set_reference: "hw2_msaa4" → hw2_msaa4.png in the
 * reference folder the program names; NULL when no reference exists for
 * these settings — the shell, ras_app.c, finds the name in the reference
 * catalogue, ras_catalogue.h), and shows the frame with ras_viewer_show. The key `v` (ras_viewer_key) cycles
 * what the window shows:
 *
 *   program     what this program rendered (your code, or the reference
 *               solution in a *_ref build)
 *   reference   the committed reference image for the same settings
 *   difference  ras_compare_heatmap(reference, program): black = same,
 *               blue → red = more different (fixed scale, see ras_compare.h)
 *
 * Without a reference for the current settings the program's picture stays
 * on screen and the status line says "no reference for these settings".
 * Status lines: the viewer's own line (view, frame time, key) first, then
 * the program's status, one screen line per '\n'.
 *
 * Only for windows: callers check ras_window_available() first, and headless
 * paths never create a viewer (highgui aborts without a display).
 * Ownership: ras_viewer_init / ras_viewer_release (NULL-safe); the viewer
 * owns the loaded reference image, nothing else.
 */
#ifndef RAS_VIEWER_H
#define RAS_VIEWER_H

#include "ras_compare.h" /* ras_compare_kind */
#include "ras_error.h"
#include "ras_image.h"

#include <stdbool.h>

typedef enum ras_view {
    RAS_VIEW_PROGRAM,
    RAS_VIEW_REFERENCE,
    RAS_VIEW_DIFFERENCE,
} ras_view;
#define RAS_VIEW_COUNT 3

/* The key that cycles the views. */
#define RAS_VIEWER_KEY_VIEW 'v'

typedef struct ras_viewer {
    const char *title;          /* window title, not owned (a string literal) */
    char program[64];           /* basename of argv[0], for the status line */
    ras_compare_kind diff_kind; /* metric of the difference view */
    ras_view view;
    double frame_ms;    /* duration of the last ras_viewer_frame_begin..end */
    double frame_start; /* seconds, monotonic clock */
    const char *reference_dir; /* the reference images' folder, not owned; NULL: none */
    char reference_name[64]; /* "" when there is none for these settings */
    ras_image *reference;    /* loaded reference, NULL when missing */
    /* the catalogue's comparison for the reference (the grader's): the
     * difference view shows its verdict; "" when the catalogue has none */
    char comparison[64];
    ras_compare_options compare;
} ras_viewer;

/* argv0 names the program in the status line; reference_dir is the folder
 * of the reference images (the build tells each program where it is:
 * RAS_REFERENCE_DIR; NULL: no reference view); diff_kind is the metric the
 * difference view shows (EDGE_TOLERANT for line and edge pictures, EXACT for
 * shading). */
void ras_viewer_init(ras_viewer *v, const char *title, const char *argv0,
                     const char *reference_dir, ras_compare_kind diff_kind);

/* Frees the reference image. NULL-safe. */
void ras_viewer_release(ras_viewer *v);

/* Time one frame: call around the render. */
void ras_viewer_frame_begin(ras_viewer *v);
void ras_viewer_frame_end(ras_viewer *v);

/* The reference for the current settings, by name (no directory, no ".png"):
 * loads <reference_dir>/<name>.png when the name changed. NULL, a missing
 * file, or a size different from `width` x `height` mean "no reference". */
void ras_viewer_set_reference(ras_viewer *v, const char *name, int width, int height);

/* Handles the view key; true when it was one (the window needs a redraw). */
bool ras_viewer_key(ras_viewer *v, int key);

/* True when the window shows the program's own picture (overlays such as
 * hw2's pixel inspector belong only on that view). */
bool ras_viewer_showing_program(const ras_viewer *v);

/* The pixel inspector (hw2's window): magnifies the pixels around screen
 * pixel (x, y) of `image` into the top-right corner of `view`, marks the
 * samples of (x, y) from the frame buffer `fb` (pattern `pattern`), each a
 * dot of its colour, ringed red when nothing covers it, and writes their
 * depths to `info`. Draw it only on the program's view. */
struct ras_framebuffer;
struct ras_sample_pattern;
void ras_viewer_inspect(ras_image *view, const ras_image *image, const struct ras_framebuffer *fb,
                        const struct ras_sample_pattern *pattern, int x, int y, char *info,
                        size_t size);

/* The step view's inspector: what the current (last drawn) triangle `t`
 * gives at the centre (x + 0.5, y + 0.5) of screen pixel (x, y) (y up):
 * its three edge functions E01, E12, E20 (docs/hw2.md section 1), the
 * barycentrics alpha = E12/A, beta = E20/A, gamma = E01/A (A = E01(v2),
 * twice the area), the depth alpha z0 + beta z1 + gamma z2, and whether the
 * centre is inside (all three of the area's sign; exactly 0: on an edge,
 * the top-left rule decides). Two lines into info. */
struct ras_triangle;
void ras_viewer_inspect_triangle(const struct ras_triangle *t, int x, int y, char *info,
                                 size_t size);

/* Shows the current view of `img` (the program's frame) with the status
 * lines. False and err when the window cannot be shown or memory runs out. */
bool ras_viewer_show(ras_viewer *v, const ras_image *img, const char *status, ras_error *err);

#endif
