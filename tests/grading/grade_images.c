/* grade_images.c — raster101-grade's verdict on a picture (grade_images.h).
 * The verdict follows the evidence (DESIGN.md): the buffers say first where
 * the frame goes wrong; what the picture alone shows may only refine that.
 */
#include "grade_images.h"

#include "grade_evidence.h"
#include "grade_results.h"
#include "grade_run.h"
#include "grade_tests.h"
#include "grade_text.h"
#include "ras_catalogue.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---------------------------------------------------------------- what a picture shows */

/* Vertical mirror, to recognise a missing y-flip. */
static ras_image *flip_rows(const ras_image *img) {
    ras_image *f = ras_image_clone(img);
    if (!f) return NULL;
    for (int r = 0; r < img->height; r++)
        for (int c = 0; c < img->width; c++)
            ras_image_set(f, c, img->height - 1 - r, ras_image_get(img, c, r));
    return f;
}

static double mean_luma(const ras_image *img) {
    double s = 0;
    long n = (long)img->width * img->height;
    for (long i = 0; i < n; i++)
        s += 0.299 * img->pixels[i].x + 0.587 * img->pixels[i].y + 0.114 * img->pixels[i].z;
    return n ? s / (double)n : 0;
}

static bool is_flat(const ras_image *img) {
    long n = (long)img->width * img->height;
    for (long i = 1; i < n; i++)
        if (ras_unit_to_byte(img->pixels[i].x) != ras_unit_to_byte(img->pixels[0].x) ||
            ras_unit_to_byte(img->pixels[i].y) != ras_unit_to_byte(img->pixels[0].y) ||
            ras_unit_to_byte(img->pixels[i].z) != ras_unit_to_byte(img->pixels[0].z))
            return false;
    return true;
}

/* Bounding box of the pixels that differ from the top-left (background)
 * pixel; false when there are none. */
static bool content_box(const ras_image *img, int *x0, int *y0, int *x1, int *y1) {
    vec3s bg = ras_image_get(img, 0, 0);
    *x0 = img->width, *y0 = img->height, *x1 = -1, *y1 = -1;
    for (int r = 0; r < img->height; r++)
        for (int c = 0; c < img->width; c++) {
            vec3s p = ras_image_get(img, c, r);
            if (ras_unit_to_byte(p.x) == ras_unit_to_byte(bg.x) &&
                ras_unit_to_byte(p.y) == ras_unit_to_byte(bg.y) &&
                ras_unit_to_byte(p.z) == ras_unit_to_byte(bg.z))
                continue;
            if (c < *x0) *x0 = c;
            if (c > *x1) *x1 = c;
            if (r < *y0) *y0 = r;
            if (r > *y1) *y1 = r;
        }
    return *x1 >= 0;
}

/* Does the image's command line contain `word` (e.g. "msaa")? */
static bool args_have(const cJSON *args, const char *word) {
    for (const cJSON *v = args ? args->child : NULL; v; v = v->next)
        if (cJSON_IsString(v) && strstr(v->valuestring, word)) return true;
    return false;
}

/* Signatures of classic mistakes; a cause is named only where the picture
 * can have it (seams need anti-aliasing, doubled ambient needs lighting). */
/* `ev`: what the buffers said (geometry signatures only where the geometry
 * differs or nothing is known); `raster_causes`: the rasterizer and resolve
 * are the student's and the buffers do not acquit them. */
/* `whole` gets the findings that explain the whole picture (upside down,
 * scaled, stretched), `o` the notes on its brightness. */
static void image_signatures(sbuf *whole, sbuf *o, const ras_image *expected, const ras_image *got,
                             const ras_compare_options *opt, const cJSON *args, const evidence *ev,
                             bool raster_causes) {
    if (is_flat(got) && !is_flat(expected)) return; /* "nothing was drawn" says it */
    bool geometry = !evidence_ran(ev) || !strcmp(ev->stage, "vertices") ||
                    !strcmp(ev->stage, "coverage") || !strcmp(ev->stage, "depth");
    ras_image *flipped = geometry ? flip_rows(got) : NULL;
    ras_compare_result fr;
    ras_error err;
    if (flipped && ras_compare_images(expected, flipped, opt, &fr, &err) && fr.pass)
        sb_add(whole, "likely mistake: your image is the reference upside down: the y-flip is "
                      "missing (image row = height - 1 - y) or the projection flips y\n");
    ras_image_destroy(flipped);
    int ex0, ey0, ex1, ey1, gx0, gy0, gx1, gy1;
    if (geometry && content_box(expected, &ex0, &ey0, &ex1, &ey1) &&
        content_box(got, &gx0, &gy0, &gx1, &gy1)) {
        double cx = (gx0 + gx1 - ex0 - ex1) / 2.0, cy = (gy0 + gy1 - ey0 - ey1) / 2.0;
        double sx = (gx1 - gx0 + 1.0) / (ex1 - ex0 + 1.0),
               sy = (gy1 - gy0 + 1.0) / (ey1 - ey0 + 1.0);
        double cxe = (ex0 + ex1) / 2.0, cye = (ey0 + ey1) / 2.0;
        double ccx = expected->width / 2.0, ccy = expected->height / 2.0;
        /* same centre of projection, different size: the field of view */
        double scale = (sx + sy) / 2;
        if (fabs(sx - sy) < 0.05 && fabs(scale - 1) > 0.05 &&
            fabs((cxe - ccx) * scale - (cxe + cx - ccx)) < 4 &&
            fabs((cye - ccy) * scale - (cye + cy - ccy)) < 4)
            sb_printf(whole,
                      "likely mistake: your picture is the reference scaled by %.2f about the "
                      "image centre: the field of view is off (the whole fov used instead of "
                      "half of it, or degrees given to tanf)\n",
                      scale);
        else if (fabs(sx - 1) > 0.05 && fabs(sy - 1) < 0.05)
            sb_printf(whole,
                      "likely mistake: your picture is stretched horizontally by %.2f: the "
                      "aspect ratio is applied to the wrong axis\n",
                      sx);
    }
    double le = mean_luma(expected), lg = mean_luma(got);
    bool aa = args_have(args, "msaa") || args_have(args, "ssaa");
    bool lit =
        args_have(args, "phong") || args_have(args, "texture") || args_have(args, "displacement");
    if (le > 0.02 && lg < 0.97 * le)
        sb_printf(o,
                  "note: your image is darker than the reference on average (mean luma %.4f "
                  "vs %.4f)%s\n",
                  lg, le,
                  aa && raster_causes
                      ? ": dark edges or seams? (resolve in floating point, colour per sample)"
                      : "");
    else if (le > 0.02 && lg > 1.03 * le)
        sb_printf(o,
                  "note: your image is brighter than the reference on average (mean luma "
                  "%.4f vs %.4f)%s\n",
                  lg, le,
                  lit && (!evidence_ran(ev) || !ev->owner ||
                          stage_owner_is(ev->owner, RAS_GRADE_SHADING_OWNER))
                      ? ": light added twice (ambient once per light?)"
                      : "");
}

/* Defects a person sees at once but a global pixel budget can hide: a dark
 * seam, a line of wrong pixels, speckle. Each is a pattern of "bad" pixels
 * (some channel off by more than BAD_BYTES) that a correct image never has,
 * whatever its float style: a seam pixel is darker than everything around it
 * in the reference, speckle sits inside a smooth area of the reference, a
 * line is a row or column whose neighbours match. Appends one "likely
 * mistake" line per defect found; returns whether any was. */
enum { BAD_BYTES = 48, SEAM_MIN = 20, SPECKLE_MIN = 12, LINE_MIN = 24 };

static int byte_diff(vec3s a, vec3s b) {
    int d = 0;
    for (int k = 0; k < 3; k++) {
        int e = abs(ras_unit_to_byte(a.raw[k]) - ras_unit_to_byte(b.raw[k]));
        if (e > d) d = e;
    }
    return d;
}

static double luma(vec3s p) { return 0.299 * p.x + 0.587 * p.y + 0.114 * p.z; }

/* What a defect's line may say it comes from (defect_voice in
 * grade_images.h). */
static const char *seam_cause(defect_voice v) {
    switch (v) {
    case DEFECT_RASTER:
        return ": the background shows through a shared edge (a coverage rule that drops edge "
               "samples, or a resolve that mixes in uncovered or integer-rounded samples)";
    case DEFECT_SHADING:
        return ": the buffers up to the rasterizer match the reference's, so it is the colour "
               "your shader returned there (shading), not coverage";
    default: return "";
    }
}

static const char *speckle_cause(defect_voice v) {
    switch (v) {
    case DEFECT_RASTER:
        return ": back faces winning the depth test (depth or barycentric precision: subtract a "
               "vertex before the edge functions; perspective-correct depth) or a NaN in some "
               "pixels";
    case DEFECT_SHADING:
        return ": the buffers up to the rasterizer match the reference's, so it is the colour "
               "your shader returned in those pixels (a NaN, or a term that jumps: a missing "
               "max(0, ...), a vector not normalised)";
    default: return "";
    }
}

static const char *line_cause(defect_voice v, bool column) {
    switch (v) {
    case DEFECT_RASTER:
        return column ? ": a column skipped or written twice (a loop bound, < against <=, or an "
                        "index off by one)"
                      : ": a row skipped or written twice (a loop bound, < against <=, or an "
                        "index off by one)";
    case DEFECT_SHADING:
        return ": the buffers up to the rasterizer match the reference's, so it is the colour "
               "your shader returned along it";
    case DEFECT_WIREFRAME:
        return ": an edge of the wireframe runs along it in one picture and not in the other "
               "(the vertices land elsewhere: the matrices)";
    default: return "";
    }
}

/* `voice`: which causes each defect's line may name (grade_images.h). A
 * wireframe is lines on a background: it has no surfaces to meet in a seam,
 * no smooth area for speckle and no depth test, so only a wrong row or
 * column is looked for. */
bool image_defects(sbuf *o, const ras_image *expected, const ras_image *got, defect_voice voice) {
    int w = expected->width, h = expected->height;
    if (got->width != w || got->height != h || w < 3 || h < 3) return false;
    bool surfaces = voice != DEFECT_WIREFRAME;
    const char *lead = voice == DEFECT_RASTER ? "likely mistake: " : "the picture shows ";
    unsigned char *bad = calloc((size_t)w * h, 1);
    int *row_bad = calloc((size_t)h, sizeof *row_bad),
        *col_bad = calloc((size_t)w, sizeof *col_bad);
    if (!bad || !row_bad || !col_bad) abort();
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            if (byte_diff(ras_image_get(expected, x, y), ras_image_get(got, x, y)) > BAD_BYTES) {
                bad[(size_t)y * w + x] = 1;
                row_bad[y]++;
                col_bad[x]++;
            }
    int seams = 0, speckles = 0, sx = -1, sy = -1, px = -1, py = -1;
    for (int y = 1; y < h - 1 && surfaces; y++)
        for (int x = 1; x < w - 1; x++) {
            if (!bad[(size_t)y * w + x]) continue;
            double lo = 1e9, hi = -1e9;
            int bad_around = 0;
            vec3s e0 = ras_image_get(expected, x, y);
            int spread = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    vec3s e = ras_image_get(expected, x + dx, y + dy);
                    double l = luma(e);
                    lo = l < lo ? l : lo;
                    hi = l > hi ? l : hi;
                    int d = byte_diff(e, e0);
                    spread = d > spread ? d : spread;
                    bad_around += (dx || dy) && bad[(size_t)(y + dy) * w + x + dx];
                }
            double lg = luma(ras_image_get(got, x, y));
            /* where two drawn surfaces meet (not against the background),
             * darker than both */
            if (lo > 0.05 && hi - lo > 0.02 && lg < lo - 0.15) {
                if (seams++ == 0) sx = x, sy = y;
            } else if (spread <= 24 && bad_around <= 2) {
                if (speckles++ == 0) px = x, py = y;
            }
        }
    bool found = false;
    if (seams >= SEAM_MIN) {
        /* "seam" names a coverage or resolve mistake: only where those can be */
        sb_printf(o,
                  voice == DEFECT_SHADING
                      ? "%s%d pixels where two surfaces meet are darker than both in the "
                        "reference (first at (%d,%d))%s\n"
                      : "%sa dark seam: %d pixels where two surfaces meet are darker than both in "
                        "the reference (first at (%d,%d))%s\n",
                  lead, seams, sx, sy, seam_cause(voice));
        found = true;
    }
    if (speckles >= SPECKLE_MIN) {
        sb_printf(o,
                  "%sspeckle: %d isolated pixels inside smooth areas are wrong (first at "
                  "(%d,%d))%s\n",
                  lead, speckles, px, py, speckle_cause(voice));
        found = true;
    }
    for (int pass = 0; pass < 2; pass++) {
        const int *line = pass ? col_bad : row_bad;
        int n = pass ? w : h;
        for (int i = 0; i < n; i++) {
            int beside = 0;
            if (i > 0 && line[i - 1] > beside) beside = line[i - 1];
            if (i < n - 1 && line[i + 1] > beside) beside = line[i + 1];
            if (line[i] >= LINE_MIN && line[i] >= 4 * (beside + 1)) {
                sb_printf(
                    o,
                    "%s%s %d of the image is wrong along %d pixels while the %ss "
                    "beside it match%s\n",
                    voice == DEFECT_RASTER ? lead : "the picture shows: ", pass ? "column" : "row",
                    i, line[i], pass ? "column" : "row", line_cause(voice, pass));
                found = true;
                break;
            }
        }
    }
    free(bad);
    free(row_bad);
    free(col_bad);
    return found;
}

bool image_is_wireframe(const cJSON *img) {
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(img, "comparison");
    return cJSON_IsString(c) && !strcmp(c->valuestring, "wireframe");
}

/* ---------------------------------------------------------------- the picture and its reference */

/* A PNG as taken from the sandbox: its header checked against the
 * reference's size before any decoding. */
static ras_image *decode_taken(const char *path, const char *ref_path, ras_error *err) {
    unsigned char head[24], rhead[24];
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    ssize_t got = fd >= 0 ? read(fd, head, sizeof head) : -1;
    if (fd >= 0) close(fd);
    FILE *rf = fopen(ref_path, "rb");
    size_t rgot = rf ? fread(rhead, 1, sizeof rhead, rf) : 0;
    if (rf) fclose(rf);
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (got != (ssize_t)sizeof head || memcmp(head, sig, 8) != 0 || memcmp(head + 12, "IHDR", 4))
        return ras_error_set(err, "the output is not a PNG file"), NULL;
    if (rgot == sizeof rhead && memcmp(head + 16, rhead + 16, 8) != 0) {
        unsigned w = (unsigned)head[16] << 24 | head[17] << 16 | head[18] << 8 | head[19];
        unsigned h = (unsigned)head[20] << 24 | head[21] << 16 | head[22] << 8 | head[23];
        unsigned rw = (unsigned)rhead[16] << 24 | rhead[17] << 16 | rhead[18] << 8 | rhead[19];
        unsigned rh = (unsigned)rhead[20] << 24 | rhead[21] << 16 | rhead[22] << 8 | rhead[23];
        return ras_error_set(err,
                             "expected a %ux%u image like the reference, got %ux%u (not "
                             "decoded)",
                             rw, rh, w, h),
               NULL;
    }
    return ras_image_load(path, err);
}

/* The image a student's program wrote, taken (sandbox_take) into `taken` (a
 * trusted path, removed again) and read from there: refused before any
 * decoding when it is not a regular PNG file of the reference's size: a
 * symlink, a FIFO, a huge file or a decompression bomb costs nothing. */
ras_image *load_student_image(const char *path, const char *taken, const char *ref_path,
                              ras_error *err) {
    char why[300];
    const char *name;
    int dfd = sandbox_dir_of(path, &name, why, sizeof why);
    bool took = dfd >= 0 && sandbox_take(dfd, name, taken, 64 << 20, why, sizeof why);
    if (dfd >= 0) close(dfd);
    if (!took) {
        if (!strcmp(why, "it does not exist"))
            return ras_error_set(err, "no file at -o (%s)", why), NULL;
        return ras_error_set(err, "the output was refused: %s", why), NULL;
    }
    ras_image *img = decode_taken(taken, ref_path, err);
    unlink(taken);
    return img;
}

/* The comparison the rubric asks of an image; false for an unknown metric.
 * The rubric names a comparison; its thresholds live only in the
 * catalogue's table (tests/reference/catalogue.json, common/app/ras_catalogue.h),
 * which the students' --compare and raster101-compare read too. */
bool image_options(const grader *g, const cJSON *img, ras_compare_kind *kind,
                   ras_compare_options *opt, ras_error *err) {
    static ras_catalogue cat;
    static int state; /* 0 not read, 1 read, -1 failed */
    static ras_error failure;
    if (!state) {
        char path[4200];
        fmt(path, sizeof path, "%s/tests/reference/catalogue.json", g->source);
        state = ras_catalogue_load(path, &cat, &failure) ? 1 : -1;
    }
    if (state < 0) return *err = failure, false;
    if (!ras_catalogue_comparison_options(&cat, str_or(img, "comparison", ""), opt, err))
        return false;
    *kind = opt->kind;
    return true;
}

/* The folder of what the grader renders or keeps beside reference code (a
 * variant's reference, a sealed run's passed picture): the work folder's
 * refs/, root's alone once made with trusted_dir. The work folder is 0711, so
 * a sandboxed run that is not in a mount namespace of its own (the
 * separate-uid isolation) could open a file of a known name in it, and with
 * a template the work folder is a known path. */
static void refs_dir(const grader *g, const char *dir, char *buf, size_t size) {
    fmt(buf, size, "%s/refs", g->work ? g->work : dir);
}

/* Where a variant's reference, rendered at grading time, is kept: in the
 * work folder (never handed out), named by the assignment that owns the
 * image (`id`, not the integration part grading it again) so the whole-chain
 * run and the attribution compare with the picture the own-code run just
 * rendered with the same arguments — and never with one a previous grading
 * left in a reused work folder (--reuse-build). In refs_dir. */
void variant_reference_path(const grader *g, const char *dir, const char *id, const char *name,
                            char *buf, size_t size) {
    char refs[4096];
    refs_dir(g, dir, refs, sizeof refs);
    fmt(buf, size, "%s/%s-%s.expected.png", refs, id, name);
}

/* ---------------------------------------------------------------- speculation */

/* A picture judged ahead, in a child of judge_pictures beside the others
 * (images_speculate): it may compare, write its files and say its verdict,
 * but not start anything the grading counts or numbers (the buffers'
 * evidence, a blank picture's counters, the attribution's renders) nor
 * remove what a judging done again would need (a sealed run's log): there it
 * gives up, and the picture is judged again in order, in the grader itself. */
static bool speculating, gave_up;

void images_speculate(bool on) {
    speculating = on;
    gave_up = false;
}

bool images_gave_up(void) { return gave_up; }

bool images_speculation_stops(void) {
    if (speculating) gave_up = true;
    return speculating;
}

/* ---------------------------------------------------------------- grading a picture */

/* One picture being graded: what grade_image's steps share. */
typedef struct picture {
    const grader *g;
    assignment_result *a;
    const cJSON *img;
    const char *dir, *reldir, *name, *program;
    const char *ref_program; /* a variant's (rubric "reference_program"), else NULL */
    const job *j;            /* the graded run (image_job) */
    bool sealed, whole;      /* as grade_image's */
    item *it;
    sbuf o;              /* the item's message */
    char ref_path[4096]; /* the reference picture */
    ras_error err;       /* the last error of any step, as one function had it */
    ras_compare_kind kind;
    ras_compare_options opt;
    run_result rr; /* how the graded run ended, a signal through bwrap decoded */
    bool todo;     /* the program printed a TODO notice */
} picture;

/* The item as not counted: `reason` for the table, `output` (owned) its
 * message. Returns false, grade_image's answer. */
static bool picture_skip(picture *p, const char *reason, char *output) {
    p->it->counted = false;
    p->it->status = xstrdup("SKIP");
    p->it->reason = xstrdup(reason);
    p->it->output = output;
    junit_case(p->it, p->a->id, NULL);
    return false;
}

/* ---------------------------------------------------------------- the references' cache */

/* A variant's reference depends only on the trusted reference program and
 * the arguments drawn for it, so it is kept, per program and arguments, in
 * the trusted build's folder (BUILD/grade-cache/references, 0700): never
 * bound into a sandbox, never in OUT or the work folder, so no student
 * program can read or plant one. A grading then renders only what no
 * earlier grading of this build rendered (a regrade, the same student's
 * next grading, a class's gradings with the course's draws). Its key, served
 * only on a byte-for-byte match: reference_cache_key (grade_run.h). */
enum { REFERENCE_CACHE_MAX = 4096 }; /* entries; past it nothing more is kept */

/* A regular file of the cache (never through a link), its contents. */
static char *cache_read(const char *path, size_t cap) {
    struct stat st;
    if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode)) return NULL;
    return read_small_file(path, cap);
}

/* The cached reference for `key` copied to `to`; false on a miss. */
static bool reference_from_cache(const char *entry, const char *key, const char *to) {
    char path[4300];
    fmt(path, sizeof path, "%s.key", entry);
    char *held = cache_read(path, 64 * 1024);
    bool same = held && !strcmp(held, key);
    free(held);
    fmt(path, sizeof path, "%s.png", entry);
    struct stat st;
    if (!same || lstat(path, &st) != 0 || !S_ISREG(st.st_mode)) return false;
    if (copy_file(path, to)) return true;
    unlink(to);
    return false;
}

static bool cache_full(const char *dir) {
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d)) != NULL && n < 2 * REFERENCE_CACHE_MAX;)
        n++;
    if (d) closedir(d);
    return n >= 2 * REFERENCE_CACHE_MAX; /* a .png and a .key an entry */
}

/* `png` kept as the entry for `key`: each file written beside and renamed
 * in, the picture first, so a key present names a whole picture (gradings
 * of one build running at once write the same bytes). */
static void reference_to_cache(const grader *g, const char *entry, const char *key,
                               const char *png) {
    char dir[4200], tmp[4400], path[4300];
    fmt(dir, sizeof dir, "%s/grade-cache", g->build);
    trusted_dir(dir);
    fmt(dir, sizeof dir, "%s/grade-cache/references", g->build);
    trusted_dir(dir);
    if (cache_full(dir)) return;
    fmt(tmp, sizeof tmp, "%s.png.%ld.tmp", entry, (long)getpid());
    fmt(path, sizeof path, "%s.png", entry);
    if (!copy_file(png, tmp) || rename(tmp, path) != 0) {
        unlink(tmp);
        return;
    }
    fmt(tmp, sizeof tmp, "%s.key.%ld.tmp", entry, (long)getpid());
    fmt(path, sizeof path, "%s.key", entry);
    FILE *f = fopen(tmp, "wb");
    bool ok = f && fputs(key, f) >= 0;
    if (f && fclose(f) != 0) ok = false;
    if (!ok || rename(tmp, path) != 0) unlink(tmp);
}

/* The reference render for a variant, from the cache or rendered now (and
 * then kept); whether `out_png` holds it. */
static bool cached_reference_render(const grader *g, const char *program, const cJSON *args,
                                    const char *out_png, const char *log) {
    sbuf key = {0};
    char entry[4200];
    reference_cache_key(g, "references", program, args, &key, entry, sizeof entry);
    bool ok = reference_from_cache(entry, sb_str(&key), out_png);
    if (!ok) {
        run_result rr = reference_render(g, program, args, out_png, NULL, log);
        ok = rr.kind == RUN_EXITED && rr.code == 0 && file_exists(out_png);
        if (ok) reference_to_cache(g, entry, sb_str(&key), out_png);
    }
    free(key.s);
    return ok;
}

/* The reference renders that a batch's pictures will ask for and the cache
 * lacks, each once, as jobs run beside the batch's sandboxed runs (trusted
 * programs, run as reference_render runs them): the renders then share the
 * cores with the student's runs instead of following one another while the
 * pictures are judged. Each writes into the trusted work folder (logs/). */
int reference_jobs(const grader *g, const cJSON *images, const job *runs, int n_img, job *jobs,
                   int max) {
    int n = 0, i = 0;
    for (const cJSON *img = images ? images->child : NULL; img && i < n_img && n < max;
         img = img->next, i++) {
        const char *ref_program = str_or(img, "reference_program", NULL);
        if (!ref_program) continue;
        job *j = &jobs[n];
        memset(j, 0, sizeof *j);
        fmt(j->store[0], sizeof j->store[0], "%s/bin/%s", g->build, ref_program);
        if (!file_exists(j->store[0])) continue;
        sbuf key = {0};
        reference_cache_key(g, "references", j->store[0], runs[i].args, &key, j->store[1],
                            sizeof j->store[1]);
        char png[4300];
        fmt(png, sizeof png, "%s.png", j->store[1]);
        bool cached = false, twice = false;
        struct stat st;
        cached = lstat(png, &st) == 0 && S_ISREG(st.st_mode);
        if (cached) {
            char keyf[4300];
            fmt(keyf, sizeof keyf, "%s.key", j->store[1]);
            char *held = cache_read(keyf, 64 * 1024);
            cached = held && !strcmp(held, sb_str(&key));
            free(held);
        }
        for (int k = 0; k < n && !twice; k++)
            twice = !strcmp(jobs[k].store[1], j->store[1]);
        free(key.s);
        if (cached || twice) continue;
        char logs[4200];
        fmt(logs, sizeof logs, "%s/logs", g->work ? g->work : g->out);
        trusted_dir(logs);
        /* named by the image, not numbered as the runs are: the run numbers
         * (folders, uids) stay those of a grading without the cache */
        const char *name = str_or(img, "name", "image");
        fmt(j->store[2], sizeof j->store[2], "%s/reference-%s.png", logs, name);
        fmt(j->out_path, sizeof j->out_path, "%s/reference-%s.log", logs, name);
        int a = 0;
        j->argv[a++] = j->store[0];
        for (const cJSON *v = runs[i].args ? runs[i].args->child : NULL; v && a < 110; v = v->next)
            if (cJSON_IsString(v)) j->argv[a++] = v->valuestring;
        j->argv[a++] = "-o";
        j->argv[a++] = j->store[2];
        j->argv[a] = NULL;
        j->args = runs[i].args;
        j->limit = wall_backstop(g->render_limit); /* as reference_render's */
        j->mem_mb = g->mem_mb;
        n++;
    }
    return n;
}

/* The batch's reference renders that succeeded, kept in the cache (from
 * where the pictures' judging copies them); their files removed. */
void reference_jobs_done(const grader *g, job *jobs, int n) {
    for (int i = 0; i < n; i++) {
        job *j = &jobs[i];
        if (j->rr.kind == RUN_EXITED && j->rr.code == 0 && file_exists(j->store[2])) {
            sbuf key = {0};
            char entry[4200];
            reference_cache_key(g, "references", j->store[0], j->args, &key, entry, sizeof entry);
            reference_to_cache(g, entry, sb_str(&key), j->store[2]);
            free(key.s);
        }
        unlink(j->store[2]);
        unlink(j->out_path);
    }
}

/* A variant's reference, rendered now by the trusted reference program with
 * the arguments chosen for this grading (or kept from an earlier grading's
 * same render, above), so no reference image of it exists for a submission
 * to copy or carry; false when it could not be. */
static bool variant_reference(picture *p) {
    char ref_prog_path[4096], ref_log[4300];
    fmt(ref_prog_path, sizeof ref_prog_path, "%s/bin/%s", p->g->build, p->ref_program);
    /* in the work folder: a variant's reference is never handed out,
     * only the difference from it */
    variant_reference_path(p->g, p->dir, p->reldir, p->name, p->ref_path, sizeof p->ref_path);
    char refs[4096];
    refs_dir(p->g, p->dir, refs, sizeof refs);
    trusted_dir(refs);
    fmt(ref_log, sizeof ref_log, "%s.log", p->ref_path); /* the work folder's too */
    if (p->whole && file_exists(p->ref_path)) return true;
    unlink(p->ref_path);
    return file_exists(ref_prog_path) &&
           cached_reference_render(p->g, ref_prog_path, p->j->args, p->ref_path, ref_log);
}

/* p->ref_path, p->kind and p->opt: the reference and the comparison; false
 * (the item skipped, not counted) when either is missing. */
static bool picture_reference(picture *p) {
    const char *reference = str_or(p->img, "reference", "");
    fmt(p->ref_path, sizeof p->ref_path, "%s/tests/reference/%s", p->g->source, reference);
    if (p->ref_program && !variant_reference(p)) {
        sb_printf(&p->o,
                  "this image is graded against %s, rendered at grading time; this build "
                  "has no working %s (the student edition has none): not counted",
                  p->ref_program, p->ref_program);
        return picture_skip(p, "no reference program here (not counted)", p->o.s);
    }
    if (!p->ref_program && !file_exists(p->ref_path)) {
        sb_printf(&p->o, "tests/reference/%s does not exist (make reference-images); not counted",
                  reference);
        return picture_skip(p, "no reference image yet (not counted)", p->o.s);
    }
    if (!image_options(p->g, p->img, &p->kind, &p->opt, &p->err))
        return picture_skip(p, "bad metric in the rubric (not counted)", xstrdup(p->err.msg));
    return true;
}

/* The copy of the reference that the report shows (none of a variant's),
 * and the command line the message opens with. */
static void picture_intro(picture *p) {
    char exp_copy[4096], rel[4200];
    fmt(exp_copy, sizeof exp_copy, "%s/%s.expected.png", p->dir, p->name);
    if (!p->ref_program) {
        copy_file(p->ref_path, exp_copy);
        fmt(rel, sizeof rel, "%s/%s.expected.png", p->reldir, p->name);
        p->it->img_expected = xstrdup(rel);
    }
    const cJSON *args = p->j->args;
    sb_printf(&p->o, "command: %s", p->program);
    for (const cJSON *v = args ? args->child : NULL; v; v = v->next)
        if (cJSON_IsString(v)) sb_printf(&p->o, " %s", v->valuestring);
    sb_printf(&p->o, " -o %s.png   (comparison %s: metric %s)\n", p->name,
              str_or(p->img, "comparison", "?"), ras_compare_kind_name(p->kind));
}

/* How the graded run ended (p->rr, p->todo, the status when it wrote no
 * usable picture) and what it printed; the student's picture, or NULL. */
static ras_image *picture_run(picture *p, const char *crash_hint) {
    const grader *g = p->g;
    item *it = p->it;
    char prog_path[4096], got_path[4096], log_path[4096];
    /* The student's program ran in the sandbox (image_job), writing into a
     * folder of its own, never next to the reference. */
    const char *written = p->j->store[15];
    fmt(prog_path, sizeof prog_path, "%s", p->j->store[14]);
    fmt(got_path, sizeof got_path, "%s/%s.got.png", p->dir, p->name);
    fmt(log_path, sizeof log_path, "%s", p->j->out_path);
    char taken[4200];
    fmt(taken, sizeof taken, "%s.taken.png", p->j->out_path); /* trusted: the work folder */
    unlink(got_path);
    run_result rr = file_exists(prog_path) ? p->j->rr : (run_result){RUN_NOT_STARTED, 0, 0};
    if (rr.kind == RUN_EXITED && rr.code > 128 && rr.code < 160) /* bwrap: 128 + signal */
        rr = (run_result){RUN_SIGNALED, rr.code - 128, rr.seconds};
    if (rr.kind == RUN_SIGNALED && rr.code == SIGXCPU) /* its processor time ran out */
        rr = (run_result){RUN_TIMEOUT, 0, rr.seconds};
    p->rr = rr;
    char *log = read_small_file(log_path, 16 * 1024);
    /* what a sealed run printed is never kept (a judging ahead leaves it to
     * the grader, which may judge the picture again) */
    if (p->sealed && !speculating) unlink(log_path);
    /* (student_text writes the grader's folders as WORK, ...) */
    char *clean_raw = clean_output(log ? log : "");
    char *clean = student_text(clean_raw, 3000);
    free(clean_raw);
    free(log);
    /* The notice is what the program printed: the student controls it, so it
     * can only cost points, never earn them. */
    p->todo = has_todo_notice(clean);
    ras_image *got = NULL;
    if (rr.kind == RUN_NOT_STARTED) {
        it->status = xstrdup("ERROR");
        sb_printf(&p->o, "the program %s was not built\n", p->program);
    } else if (rr.kind == RUN_TIMEOUT) {
        it->status = xstrdup("TIMEOUT");
        sb_printf(&p->o,
                  "the program used more than %.0f s of processor time (or ran %.0f s on the "
                  "clock) and was stopped: an endless loop?\n",
                  g->render_limit, wall_backstop(g->render_limit));
    } else if (rr.kind == RUN_SIGNALED) {
        it->status = xstrdup("CRASH");
        sb_printf(&p->o, "the program crashed with %s\nlikely mistake: %s\n", signal_text(rr.code),
                  crash_hint);
    } else if (!(got = load_student_image(written, taken, p->ref_path, &p->err))) {
        it->status = xstrdup("FAIL");
        sb_printf(&p->o, "the program exited with status %d and wrote no usable image: %s\n",
                  rr.code, p->err.msg);
    } else if (!p->sealed) {
        ras_image_save(got, got_path, &p->err); /* the report's copy, re-encoded by us */
    }
    /* sealed: whether it printed anything is a bit it chose too; its
     * verdict is made pass-or-not at the end (seal_verdict) */
    if (p->sealed)
        sb_printf(&p->o,
                  "(rendered with your %s code and the reference of the earlier assignments; "
                  "this run holds reference code, so its picture and output are not shown)\n",
                  p->a->id);
    else if (*clean)
        sb_printf(&p->o, "program output:\n%s\n", clean);
    free(clean);
    return got;
}

/* What a comparison found beyond its metric. */
typedef struct findings {
    bool flat;    /* the student's picture is one flat colour, the reference's not */
    sbuf defects; /* what the picture shows (image_defects, causes named) */
    sbuf bufs;    /* what the buffers say (buffer_evidence) */
    evidence ev;
    /* a whole-chain run: its picture is, up to the rubric's comparison, the
     * one the assignment's own-code run drew and passed (same_as_own_picture) */
    bool as_own;
} findings;

/* Where a passed own-code run's picture is kept for the whole-chain run of
 * the same image, graded right after it (judge_pictures): in the work
 * folder's refs/, which no sandboxed run can write or read (a sealed run's
 * picture, drawn beside reference code); "" without one. `id`: the
 * assignment that owns the image. */
static void own_picture_path(const grader *g, const char *id, const char *name, char *buf,
                             size_t size) {
    buf[0] = '\0';
    if (!g->work) return;
    char refs[4096];
    refs_dir(g, NULL, refs, sizeof refs);
    fmt(buf, size, "%s/%s-%s.own-passed.png", refs, id, name);
}

/* A sealed run's picture: kept when it passed, removed otherwise (so that a
 * whole-chain run never meets one a previous image or grading left). */
static void keep_own_picture(const picture *p, const ras_image *got, bool passed) {
    char path[4400];
    own_picture_path(p->g, p->reldir, p->name, path, sizeof path);
    if (!*path) return;
    char refs[4096];
    refs_dir(p->g, NULL, refs, sizeof refs);
    trusted_dir(refs);
    unlink(path);
    ras_error err = {{0}};
    if (passed && got) ras_image_save(got, path, &err);
}

/* Whether a whole-chain picture is the own-code run's passed picture up to
 * what the rubric's comparison allows, with no defect between them: then
 * the earlier assignments' code changed nothing that shows (a float style's
 * few pixels aside), and what differs from the reference is the
 * assignment's own code, judged (and passed) on its own-code run. */
static bool same_as_own_picture(const picture *p, const ras_image *got) {
    char path[4400];
    own_picture_path(p->g, p->reldir, p->name, path, sizeof path);
    if (!p->whole || !*path || !file_exists(path)) return false;
    ras_error err = {{0}};
    ras_image *own = ras_image_load(path, &err);
    ras_compare_result r;
    bool same = own && own->width == got->width && own->height == got->height &&
                ras_compare_images(own, got, &p->opt, &r, &err) && r.pass;
    sbuf ignored = {0};
    if (same && image_defects(&ignored, own, got, DEFECT_PATTERN)) same = false;
    free(ignored.s);
    ras_image_destroy(own);
    return same;
}

/* The buffers' evidence (not for a stub's placeholder picture, which says
 * enough; at most EVIDENCE_MAX per grading: each costs two more renders),
 * and a defect within the metric's budget: evidence or nothing. Only
 * evidence that ran fully and acquits (every buffer matches, or the
 * difference is in a stage this assignment's code does not make) keeps such
 * a picture passing; withheld evidence fails it, and where none can be had
 * (the budget spent, a reference without --dump) the picture decides. */
static void picture_findings(picture *p, ras_compare_result *r, const ras_image *got,
                             const ras_image *expected, bool ref_raster, findings *f) {
    const grader *g = p->g;
    f->flat = is_flat(got) && !is_flat(expected);
    bool defect =
        !f->flat && image_defects(&f->defects, expected, got,
                                  image_is_wireframe(p->img) ? DEFECT_WIREFRAME : DEFECT_RASTER);
    f->as_own = same_as_own_picture(p, got);
    memset(&f->ev, 0, sizeof f->ev);
    if ((!r->pass || defect) && p->rr.kind == RUN_EXITED && !p->todo) {
        if (g->evidence_runs >= EVIDENCE_MAX || getenv("RAS_GRADE_NO_BUFFERS")) {
            f->ev.kind = EVIDENCE_BUDGET;
        } else if (images_speculation_stops()) {
            return;
        } else {
            ((grader *)g)->evidence_runs++;
            buffer_evidence(g, p->it, &f->bufs, p->img, p->dir, p->reldir, p->j,
                            p->sealed ? p->j->extra_ro : NULL, ref_raster, f->flat, &f->ev);
        }
    }
    /* a blank picture without buffers still says why from its counters
     * (one more render, within the same budget) */
    if (f->flat && (f->ev.kind == EVIDENCE_BUDGET || f->ev.kind == EVIDENCE_NO_REFERENCE) &&
        g->evidence_runs < EVIDENCE_MAX) {
        if (images_speculation_stops()) return;
        ((grader *)g)->evidence_runs++;
        blank_counters(g, p->img, p->j, p->sealed ? p->j->extra_ro : NULL, &f->ev);
    }
    const evidence *ev = &f->ev;
    if (ev->kind == EVIDENCE_WITHHELD && r->pass) {
        r->pass = false;
        sb_add(&p->o, "(within the metric's budget, but the buffers that would clear it were "
                      "not given: charged)\n");
        return;
    }
    if (!(r->pass && defect)) return;
    if (f->as_own) {
        /* already judged: the own-code run drew this very picture and its
         * evidence cleared it (or it showed nothing); the integration item
         * measures what the earlier assignments' code adds, here nothing */
        sb_printf(&p->o,
                  "(the picture shows a defect, but your whole chain draws the picture your %s "
                  "code drew with the reference of the earlier assignments, which passed (the "
                  "two match as this image's comparison asks, with no defect between them): "
                  "your earlier assignments add nothing that shows, and what differs is your "
                  "%s code's, judged in %s: within the metric's budget, not charged)\n",
                  p->reldir, p->reldir, p->reldir);
        free(f->defects.s);
        f->defects = (sbuf){0};
        return;
    }
    bool placed = evidence_ran(ev) && *ev->stage && strcmp(ev->stage, "colour") &&
                  (p->whole || (ev->owner && !strcmp(ev->owner, p->a->id))) &&
                  /* the shader's own colours are judged by the metric alone */
                  !(!strcmp(ev->stage, "sample_colour") &&
                    stage_owner_is(ev->owner, RAS_GRADE_SHADING_OWNER));
    /* a sealed run's earlier stages are the reference's code: a difference
     * placed there did not come from it, so it clears nothing */
    bool impossible = evidence_ran(ev) && p->sealed && !p->whole && !placed && *ev->stage &&
                      strcmp(ev->stage, "colour") && ev->owner && strcmp(ev->owner, p->a->id);
    if (placed) {
        r->pass = false;
        sb_printf(&p->o,
                  "(within the metric's budget, but the %s buffer differs from "
                  "the reference's and the picture shows the defect below: "
                  "your %s code, not a match)\n",
                  ev->stage, ev->owner);
    } else if (!evidence_ran(ev) || impossible) {
        r->pass = false;
        sb_printf(&p->o,
                  "(within the metric's budget, but the picture shows the defect below and "
                  "%s: decided by the picture, charged)\n",
                  impossible ? "the buffers place it in a stage this run takes from the "
                               "reference, which cannot make it"
                  : ev->kind == EVIDENCE_BUDGET
                      ? "this grading's buffer comparisons are spent"
                      : "the reference program here has no buffers to compare");
    } else {
        sb_printf(&p->o,
                  "(the picture shows a defect, but %s: within the metric's "
                  "budget, not charged)\n",
                  !strcmp(ev->stage, "colour") ? "every buffer matches the reference's"
                                               : "the buffers place it outside this "
                                                 "assignment's code");
        free(f->defects.s);
        f->defects = (sbuf){0};
    }
}

/* A failed picture's first likely mistake: nothing drawn, or the first
 * buffer that differs; whether it said one. */
static bool picture_first_cause(picture *p, const findings *f) {
    const evidence *ev = &f->ev;
    size_t before = p->o.len;
    if (f->flat)
        sb_printf(&p->o, "likely mistake: nothing was drawn: your image is one flat colour%s%s\n",
                  *ev->why_blank ? ": "
                  : ev->blank    ? ": no sample was covered (your depth buffer is empty)"
                                 : " (are the TODOs written? do the matrices put the "
                                   "scene in front of the camera?)",
                  ev->why_blank);
    else if (evidence_ran(ev) && *ev->stage && strcmp(ev->stage, "colour")) {
        const char *line = strstr(sb_str(&f->bufs), "buffers: the first that differs is ");
        if (line) {
            line += strlen("buffers: the first that differs is ");
            size_t n = strcspn(line, "\n");
            sb_add(&p->o, "likely mistake: ");
            const char *lk = strstr(line, "; likely: ");
            if (lk && (size_t)(lk - line) < n) {
                sb_addn(&p->o, lk + 10, n - (size_t)(lk + 10 - line));
                sb_printf(&p->o, " (the first buffer that differs: %s, %s's stage)\n", ev->stage,
                          ev->owner);
            } else {
                sb_addn(&p->o, line, n);
                sb_add(&p->o, "\n");
            }
        }
    }
    return p->o.len > before;
}

/* Which causes the picture's defects may name: none of a stage the program
 * lacks (a wireframe has no surfaces and no depth test), the rasterizer's
 * only where that is the student's and the buffers do not acquit it, the
 * shader's where the buffers up to the rasterizer match the reference's. */
static defect_voice picture_voice(const picture *p, const findings *f, bool ref_raster) {
    const evidence *ev = &f->ev;
    if (image_is_wireframe(p->img)) return DEFECT_WIREFRAME;
    if (!ref_raster && (!evidence_ran(ev) || ev->rasterizer)) return DEFECT_RASTER;
    bool before_shading = !strcmp(ev->stage, "vertices") || !strcmp(ev->stage, "coverage") ||
                          !strcmp(ev->stage, "depth") || !strcmp(ev->stage, "overdraw");
    if (evidence_ran(ev) && stage_owner_is(ev->owner, RAS_GRADE_SHADING_OWNER) && !before_shading)
        return DEFECT_SHADING;
    return DEFECT_PATTERN;
}

/* A failed picture's message: 1. nothing drawn; 2. the first buffer that
 * differs; 3. a finding that explains the whole picture (upside down,
 * scaled, stretched) — and then not the local defects it makes; else what
 * the picture shows, with the causes its stages allow; then its
 * brightness, the coverage around the worst pixel and what the image
 * checks. */
static void picture_failure(picture *p, const ras_compare_result *r, const ras_image *got,
                            const ras_image *expected, bool ref_raster, const findings *f) {
    bool told = picture_first_cause(p, f);
    sb_add(&p->o, sb_str(&f->bufs));
    defect_voice voice = picture_voice(p, f, ref_raster);
    if (!f->flat) {
        sbuf whole = {0}, notes = {0};
        image_signatures(&whole, &notes, expected, got, &p->opt, p->j->args, &f->ev,
                         voice == DEFECT_RASTER);
        /* a wireframe is its vertices joined by lines: what else can move them */
        if (!told && !whole.len && voice == DEFECT_WIREFRAME)
            sb_add(&p->o, "likely mistake: the lines are drawn elsewhere than the reference's: "
                          "your vertices land in other places, so one of your matrices is off "
                          "(the model matrix's rotation, its direction or its axis; the "
                          "projection): the failing tests above say which\n");
        if (whole.len)
            sb_add(&p->o, sb_str(&whole));
        else if (f->defects.len && voice == DEFECT_RASTER)
            sb_add(&p->o, sb_str(&f->defects));
        else if (f->defects.len) {
            sbuf told = {0};
            image_defects(&told, expected, got, voice);
            sb_add(&p->o, sb_str(&told));
            free(told.s);
        }
        sb_add(&p->o, sb_str(&notes));
        free(whole.s);
        free(notes.s);
    }
    if (p->kind == RAS_COMPARE_EXACT || p->kind == RAS_COMPARE_EDGE_TOLERANT) {
        char mask[2048];
        if (ras_compare_ascii_mask(expected, got, (vec3s){{0, 0, 0}}, r->worst_col, r->worst_row, 8,
                                   mask, sizeof mask, &p->err))
            sb_printf(&p->o, "coverage around the worst pixel (%d,%d), %s:\n%s", r->worst_col,
                      r->worst_row, RAS_COMPARE_ASCII_LEGEND, mask);
    }
    const char *hint = str_or(p->img, "hint", NULL);
    if (hint) sb_printf(&p->o, "what this image checks: %s\n", hint);
}

/* The report's heatmap and, for a failure, the crop of the worst region
 * (a crop shows the reference: none of a variant's); none for a sealed run. */
static void picture_maps(picture *p, ras_comparison *cmp, const ras_compare_result *r) {
    char path[4096], rel[4200];
    ras_image *heat = p->sealed ? NULL : ras_comparison_heatmap(cmp, &p->err);
    fmt(path, sizeof path, "%s/%s.diff.png", p->dir, p->name);
    if (heat && ras_image_save(heat, path, &p->err)) {
        fmt(rel, sizeof rel, "%s/%s.diff.png", p->reldir, p->name);
        p->it->img_diff = xstrdup(rel);
    }
    ras_image_destroy(heat);
    if (!r->pass && !p->sealed && !p->ref_program) {
        ras_image *crop = ras_comparison_crop(cmp, r->worst_col, r->worst_row, &p->err);
        fmt(path, sizeof path, "%s/%s.crop.png", p->dir, p->name);
        if (crop && ras_image_save(crop, path, &p->err)) {
            fmt(rel, sizeof rel, "%s/%s.crop.png", p->reldir, p->name);
            p->it->img_crop = xstrdup(rel);
        }
        ras_image_destroy(crop);
    }
}

/* The picture against its reference: one comparison for the verdict, the
 * heatmap and the crop. */
static void picture_compare(picture *p, const ras_image *got, const ras_image *expected,
                            bool ref_raster) {
    item *it = p->it;
    ras_compare_result r;
    char rel[4200];
    fmt(rel, sizeof rel, "%s/%s.got.png", p->reldir, p->name);
    if (!p->sealed) it->img_got = xstrdup(rel);
    ras_comparison *cmp = ras_comparison_create(expected, got, p->kind, &p->err);
    if (!cmp || !ras_comparison_result(cmp, &p->opt, &r, &p->err)) {
        it->status = xstrdup("FAIL");
        sb_printf(&p->o, "%s\n", p->err.msg);
    } else {
        sb_printf(&p->o, "%s\n", r.summary);
        findings f = {0};
        picture_findings(p, &r, got, expected, ref_raster, &f);
        it->passed = r.pass;
        it->status = xstrdup(r.pass ? (p->todo ? "TODO" : "PASS") : (p->todo ? "TODO" : "FAIL"));
        if (!r.pass) picture_failure(p, &r, got, expected, ref_raster, &f);
        free(f.defects.s);
        free(f.bufs.s);
        picture_maps(p, cmp, &r);
    }
    ras_comparison_destroy(cmp);
}

/* The item's score and the one line for the table. */
static void picture_score(picture *p) {
    item *it = p->it;
    it->score = it->passed && !p->todo ? it->max_score : 0;
    if (it->passed && !p->todo)
        it->reason = xstrdup("");
    else if (it->passed)
        it->reason =
            xstrdup("matches, but a TODO notice was printed (a stub, or notice lines left in)");
    else {
        const char *lm = strstr(it->output, "likely mistake");
        const char *summary = strstr(it->output, " FAIL: ");
        if (lm)
            it->reason = reason_line(lm);
        else if (summary) {
            while (summary > it->output && summary[-1] != '\n')
                summary--;
            it->reason = reason_line(summary);
        } else {
            /* the line after the first (the run's own heading), or nothing
             * when the output is one line: never past its end */
            const char *nl = strchr(it->output, '\n');
            it->reason = reason_line(nl ? nl + 1 : "");
        }
    }
}

/* Grades one image run (image_job). `sealed`: the program held reference
 * code (an own-code link), so neither its output nor its picture goes into
 * the report, only the verdict. `whole`: the run of the student's whole
 * chain, for the integration part (its reference was rendered by the own-code
 * run just before, with the same arguments). Returns whether it matched. */
bool grade_image(const grader *g, assignment_result *a, const cJSON *img, const char *dir,
                 const char *reldir, const char *crash_hint, const job *j, bool sealed,
                 bool whole) {
    picture p = {.g = g,
                 .a = a,
                 .img = img,
                 .dir = dir,
                 .reldir = reldir,
                 .j = j,
                 .sealed = sealed,
                 .whole = whole};
    p.name = str_or(img, "name", "image");
    p.program = str_or(img, "program", "");
    p.ref_program = str_or(img, "reference_program", NULL);
    item *it = p.it = add_item(a);
    it->is_image = true;
    char label[300];
    fmt(label, sizeof label, whole ? "%s image %s, your whole chain" : "image %s",
        whole ? reldir : p.name, p.name);
    it->name = xstrdup(label);
    it->max_score = num_or(img, "points", g->default_points);
    if (sealed) keep_own_picture(&p, NULL, false); /* none from an earlier grading */
    if (!picture_reference(&p)) return false;
    picture_intro(&p);
    ras_image *got = picture_run(&p, crash_hint), *expected = NULL;
    /* the rasterizer and resolve of a sealed run of an assignment that builds
     * on the raster's (hw3) are the reference's */
    bool ref_raster = sealed && own_chain_has(a->id, RAS_GRADE_RASTER_OWNER);
    if (got && (expected = ras_image_load(p.ref_path, &p.err)) != NULL) {
        picture_compare(&p, got, expected, ref_raster);
    } else if (got) {
        it->status = xstrdup("ERROR");
        sb_printf(&p.o, "could not read the reference: %s\n", p.err.msg);
    }
    if (sealed) keep_own_picture(&p, got, it->passed && !p.todo);
    if (it->passed && p.todo)
        sb_add(&p.o,
               "(matches, but the program printed a TODO notice, so no points: a stub it "
               "calls, or a function you wrote with its notice lines left in: delete them)\n");
    ras_image_destroy(got);
    ras_image_destroy(expected);
    while (p.o.len && p.o.s[p.o.len - 1] == '\n')
        p.o.s[--p.o.len] = '\0';
    it->output = p.o.s;
    picture_score(&p);
    bool matched = it->passed; /* the attribution's answer, sealed or not */
    if (sealed) {
        seal_verdict(g, it, it->passed && !p.todo);
        /* the --dump re-render of a sealed run (buffer_evidence's ".own-dump"
         * job) printed beside reference code too: its log leaves OUT */
        char dump_log[4400];
        fmt(dump_log, sizeof dump_log, "%s/%s.own-dump.log", dir, p.name);
        unlink(dump_log);
    }
    junit_case(it, a->id, NULL);
    return matched;
}
