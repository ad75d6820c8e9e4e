/* ras_viewer.c — see ras_viewer.h. */
#include "ras_viewer.h"

#include "cv_bridge.h" /* Required for: cv_bridge_draw_text, cv_bridge_window_show */
#include "ras_catalogue.h"      /* the comparison the grader uses */
#include "ras_framebuffer.h"    /* the inspector reads the samples */
#include "ras_sample_pattern.h"
#include "ras_triangle.h"      /* the step view's current triangle */

#include <math.h>   /* isinf */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* malloc, free */
#include <string.h> /* strrchr, strcmp, strchr */
#include <time.h>   /* clock_gettime */

static const char *const view_names[RAS_VIEW_COUNT] = {"program", "reference", "difference"};

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

void ras_viewer_init(ras_viewer *v, const char *title, const char *argv0,
                     const char *reference_dir, ras_compare_kind diff_kind) {
    *v = (ras_viewer){.title = title,
                      .diff_kind = diff_kind,
                      .view = RAS_VIEW_PROGRAM,
                      .reference_dir = reference_dir};
    const char *slash = argv0 ? strrchr(argv0, '/') : NULL;
    snprintf(v->program, sizeof v->program, "%s", slash ? slash + 1 : argv0 ? argv0 : title);
}

void ras_viewer_release(ras_viewer *v) {
    if (!v) return;
    ras_image_destroy(v->reference);
    v->reference = NULL;
    v->reference_name[0] = '\0';
}

void ras_viewer_frame_begin(ras_viewer *v) { v->frame_start = now_seconds(); }

void ras_viewer_frame_end(ras_viewer *v) {
    v->frame_ms = (now_seconds() - v->frame_start) * 1000.0;
}

void ras_viewer_set_reference(ras_viewer *v, const char *name, int width, int height) {
    if (!name) name = "";
    if (strcmp(name, v->reference_name) == 0 &&
        (!v->reference || (v->reference->width == width && v->reference->height == height)))
        return; /* unchanged */
    ras_image_destroy(v->reference);
    v->reference = NULL;
    snprintf(v->reference_name, sizeof v->reference_name, "%s", name);
    if (!name[0] || !v->reference_dir) return;
    char path[1200];
    snprintf(path, sizeof path, "%s/%s.png", v->reference_dir, name);
    ras_error err = {{0}};
    ras_image *ref = ras_image_load(path, &err); /* missing: no reference, not an error */
    v->comparison[0] = '\0';
    ras_catalogue *cat = malloc(sizeof *cat);
    snprintf(path, sizeof path, "%s/catalogue.json", v->reference_dir);
    const ras_catalogue_entry *e =
        cat && ras_catalogue_load(path, cat, &err) ? ras_catalogue_find(cat, name) : NULL;
    if (e) {
        snprintf(v->comparison, sizeof v->comparison, "%s", e->comparison);
        v->compare = e->compare;
    }
    free(cat);
    if (ref && (ref->width != width || ref->height != height)) {
        ras_image_destroy(ref);
        ref = NULL;
    }
    v->reference = ref;
}

bool ras_viewer_key(ras_viewer *v, int key) {
    if (key != RAS_VIEWER_KEY_VIEW) return false;
    v->view = (ras_view)((v->view + 1) % RAS_VIEW_COUNT);
    return true;
}

bool ras_viewer_showing_program(const ras_viewer *v) {
    return v->view == RAS_VIEW_PROGRAM || !v->reference;
}

/* The viewer's own status line: what is shown, the frame time, the key.
 *   "program: hw2_rasterize  12.3 ms   v: reference"
 *   "reference: hw2_msaa4.png  12.3 ms   v: difference"
 *   "difference: vs hw2_msaa4.png (black = same; rasterized: pass)  12.3 ms   v: program"
 *   "reference: none for these settings  12.3 ms   v: difference" */
static void viewer_line(const ras_viewer *v, const char *verdict, char *buf, size_t size) {
    char what[200];
    if (v->view == RAS_VIEW_PROGRAM) snprintf(what, sizeof what, "%s", v->program);
    else if (!v->reference) snprintf(what, sizeof what, "none for these settings");
    else if (v->view == RAS_VIEW_REFERENCE) snprintf(what, sizeof what, "%s.png", v->reference_name);
    else snprintf(what, sizeof what, "vs %s.png (black = same%s%s)", v->reference_name,
                  *verdict ? "; " : "", verdict);
    snprintf(buf, size, "%s: %s  %.1f ms   v: %s", view_names[v->view], what, v->frame_ms,
             view_names[(v->view + 1) % RAS_VIEW_COUNT]);
}

bool ras_viewer_show(ras_viewer *v, const ras_image *img, const char *status, ras_error *err) {
    const ras_image *shown = img;
    ras_image *heat = NULL;
    if (v->reference && v->view == RAS_VIEW_REFERENCE) shown = v->reference;
    if (v->reference && v->view == RAS_VIEW_DIFFERENCE) {
        heat = ras_compare_heatmap(v->reference, img,
                                   v->comparison[0] ? v->compare.kind : v->diff_kind, err);
        if (!heat) return false;
        shown = heat;
    }
    int width = shown->width, height = shown->height;
    uint8_t *rgb = malloc((size_t)width * (size_t)height * 3);
    if (rgb) ras_image_to_rgb8(shown, rgb);
    ras_image_destroy(heat);
    if (!rgb) return ras_error_set(err, "out of memory showing the window");
    /* Status: the viewer's line, then the program's lines, 18 px apart. */
    /* the grader's verdict on this picture, in the status line (--compare
     * prints the same in full) */
    char verdict_text[96] = "";
    ras_compare_result verdict;
    ras_error ignored = {{0}};
    if (v->reference && v->view == RAS_VIEW_DIFFERENCE && v->comparison[0] &&
        ras_compare_images(v->reference, img, &v->compare, &verdict, &ignored))
        snprintf(verdict_text, sizeof verdict_text, "%s: %s", v->comparison,
                 verdict.pass ? "pass" : "FAIL");
    char line[512];
    viewer_line(v, verdict_text, line, sizeof line);
    int row = 20;
    cv_bridge_draw_text(rgb, width, height, 8, row, line, 0.5);
    for (const char *s = status; s && *s;) {
        const char *end = strchr(s, '\n');
        int len = end ? (int)(end - s) : (int)strlen(s);
        snprintf(line, sizeof line, "%.*s", len, s);
        row += 18;
        cv_bridge_draw_text(rgb, width, height, 8, row, line, 0.5);
        s = end ? end + 1 : s + len;
    }
    char msg[512] = "";
    bool ok = cv_bridge_window_show(v->title, width, height, rgb, msg, sizeof msg);
    free(rgb);
    if (!ok) return ras_error_set(err, "%s", msg);
    return true;
}

/* ---- the pixel inspector ----------------------------------------------------- */

#define ZOOM 16  /* magnification of the inspector */
#define RADIUS 5 /* pixels shown on each side of the one under the mouse */
#define MARGIN 8

static void fill_box(ras_image *img, int c0, int r0, int w, int h, vec3s c) {
    for (int r = r0; r < r0 + h; r++)
        for (int col = c0; col < c0 + w; col++)
            if (col >= 0 && r >= 0 && col < img->width && r < img->height)
                ras_image_set(img, col, r, c);
}

static void outline_box(ras_image *img, int c0, int r0, int w, int h, vec3s c) {
    fill_box(img, c0, r0, w, 1, c);
    fill_box(img, c0, r0 + h - 1, w, 1, c);
    fill_box(img, c0, r0, 1, h, c);
    fill_box(img, c0 + w - 1, r0, 1, h, c);
}

void ras_viewer_inspect(ras_image *view, const ras_image *image, const ras_framebuffer *fb,
                        const ras_sample_pattern *pat, int x, int y, char *info, size_t size) {
    int side = (2 * RADIUS + 1) * ZOOM;
    int c0 = view->width - side - MARGIN, r0 = MARGIN;
    if (c0 < 0) return; /* frame too small for the inspector */
    outline_box(view, c0 - 1, r0 - 1, side + 2, side + 2, (vec3s){{1, 1, 1}});
    for (int dy = -RADIUS; dy <= RADIUS; dy++)
        for (int dx = -RADIUS; dx <= RADIUS; dx++) {
            int px = x + dx, py = y + dy;
            vec3s c = {{0.25f, 0.25f, 0.25f}}; /* outside the frame */
            if (px >= 0 && py >= 0 && px < image->width && py < image->height)
                c = image->pixels[ras_fb_pixel_index(fb, px, py)];
            /* Screen y is up, image rows go down. */
            fill_box(view, c0 + (dx + RADIUS) * ZOOM, r0 + (RADIUS - dy) * ZOOM, ZOOM, ZOOM, c);
        }
    int pc = c0 + RADIUS * ZOOM, pr = r0 + RADIUS * ZOOM;
    outline_box(view, pc, pr, ZOOM, ZOOM, (vec3s){{1, 1, 1}});
    int n = snprintf(info, size, "pixel (%d,%d) depth:", x, y);
    for (int s = 0; s < pat->count; s++) {
        int i = ras_fb_sample_index(fb, x, y, s);
        int sc = pc + (int)(pat->offsets[s].x * ZOOM);
        int sr = pr + ZOOM - 1 - (int)(pat->offsets[s].y * ZOOM);
        bool empty = isinf(fb->depth[i]);
        fill_box(view, sc - 2, sr - 2, 5, 5, empty ? (vec3s){{1, 0, 0}} : (vec3s){{0, 0, 0}});
        fill_box(view, sc - 1, sr - 1, 3, 3, fb->color[i]);
        if (n > 0 && (size_t)n < size && s < 8)
            n += empty ? snprintf(info + n, size - (size_t)n, " -")
                       : snprintf(info + n, size - (size_t)n, " %.4f", fb->depth[i]);
    }
    if (pat->count > 8 && n > 0 && (size_t)n < size) snprintf(info + n, size - (size_t)n, " ...");
}

void ras_viewer_inspect_triangle(const ras_triangle *t, int x, int y, char *info, size_t size) {
    double px = x + 0.5, py = y + 0.5;
    const vec4s *v = t->v;
    /* E_ab(p) = (b.x - a.x)(p.y - a.y) - (b.y - a.y)(p.x - a.x), in double:
     * the numbers a float rasterizer should come close to */
#define EDGE(a, b)                                                                        \
    (((double)v[b].x - v[a].x) * (py - v[a].y) - ((double)v[b].y - v[a].y) * (px - v[a].x))
    double e01 = EDGE(0, 1), e12 = EDGE(1, 2), e20 = EDGE(2, 0);
    double area2 = ((double)v[1].x - v[0].x) * ((double)v[2].y - v[0].y) -
                   ((double)v[2].x - v[0].x) * ((double)v[1].y - v[0].y);
#undef EDGE
    int n = snprintf(info, size, "last triangle (%.1f,%.1f) (%.1f,%.1f) (%.1f,%.1f) A %.1f\n"
                                 "at (%.1f,%.1f): E01 %.1f  E12 %.1f  E20 %.1f",
                     v[0].x, v[0].y, v[1].x, v[1].y, v[2].x, v[2].y, area2, px, py, e01, e12,
                     e20);
    if (n < 0 || (size_t)n >= size) return;
    if (area2 == 0) {
        snprintf(info + n, size - (size_t)n, "\ndegenerate (A = 0): no barycentrics, covers nothing");
        return;
    }
    double a = e12 / area2, b = e20 / area2, c = e01 / area2;
    double depth = a * v[0].z + b * v[1].z + c * v[2].z;
    const char *where = a < 0 || b < 0 || c < 0    ? "OUTSIDE"
                        : a == 0 || b == 0 || c == 0 ? "on an edge (top-left rule)"
                                                     : "inside";
    snprintf(info + n, size - (size_t)n, "\nbary %.4f %.4f %.4f  depth %.5f  %s", a, b, c,
             depth, where);
}
