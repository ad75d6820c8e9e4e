/* ras_dump_compare.c — see ras_dump.h: two dumps compared buffer by buffer,
 * in pipeline order, with the first difference located and classified. */
#include "ras_dump.h"
#include "cv_bridge.h"
#include "ras_image.h"
#include "ras_io.h"
#include "ras_mesh.h"
#include "ras_dump_parts.h"
#include "stage3_setup.h" /* ras_viewport */
#include <cjson/cJSON.h>
#include <dirent.h> /* opendir: the staged dump folder */
#include <fcntl.h>  /* open, renameat */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h> /* close */
#include <zlib.h>   /* the reference buffers ship as .pfm.gz */


/* The tolerance of a buffer kind, and whether it is relative to the value. */
static double tolerance_of(const char *name, bool *relative) {
    *relative = !strcmp(name, "depth") || !strcmp(name, "view_depth");
    if (*relative) return 1e-5;
    if (!strcmp(name, "normal")) return 1e-3;
    if (!strcmp(name, "uv")) return 1e-4;
    /* half an 8-bit level: a float-style difference never shows, a wrong
     * sample colour always does */
    if (!strcmp(name, "sample_colour")) return 0.5 / 255;
    return 0; /* coverage, overdraw: counts */
}

/* The exact file of buffer `name` in dir: NAME.pfm, or NAME.pfm.gz (the
 * shipped reference buffers are compressed); false, with path the .pfm,
 * when there is neither. */
static bool exact_path(const char *dir, const char *name, char *path, size_t size) {
    struct stat st;
    snprintf(path, size, "%s/%s.pfm", dir, name);
    if (lstat(path, &st) == 0) return true;
    snprintf(path, size, "%s/%s.pfm.gz", dir, name);
    if (lstat(path, &st) == 0) return true;
    snprintf(path, size, "%s/%s.pfm", dir, name);
    return false;
}

bool ras_dump_has_exact(const char *dir, const char *name) {
    char path[RAS_IO_MAX_PATH + 64];
    return exact_path(dir, name, path, sizeof path);
}

/* max_bytes < 0: a reference, which may be compressed; else the file must
 * be an uncompressed .pfm of at most max_bytes. */
static float *read_dump(const char *dir, const char *name, long max_bytes, int *w, int *h, int *ch,
                        ras_error *err) {
    char path[RAS_IO_MAX_PATH + 64];
    struct stat st;
    if (max_bytes < 0)
        exact_path(dir, name, path, sizeof path);
    else
        snprintf(path, sizeof path, "%s/%s.pfm", dir, name);
    if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return ras_error_set(err, "%s: no buffer file (expected a regular file)", path), NULL;
    if (max_bytes >= 0 && st.st_size > max_bytes)
        return ras_error_set(err, "%s: %lld bytes, more than the reference's %ld", path,
                             (long long)st.st_size, max_bytes),
               NULL;
    return ras_dump_read_pfm(path, w, h, ch, err);
}

/* A JSON file (`what`, at most `limit` bytes) parsed; NULL with the reason
 * in text. */
static cJSON *read_json(const char *path, const char *what, size_t limit, char *text, size_t size) {
    ras_error err = {{0}};
    size_t len = 0;
    char *data = ras_io_read_file(path, what, limit, &len, &err);
    if (!data) {
        snprintf(text, size, "%s", err.msg);
        return NULL;
    }
    cJSON *j = cJSON_ParseWithLength(data, len);
    free(data);
    if (!j) snprintf(text, size, "%s is not JSON", path);
    return j;
}

/* The samples per pixel a dump's sidecar gives buffer `name` (1 when it
 * says nothing usable: the buffers a frame makes are width*samples wide,
 * and only depth and coverage have more than one). */
static int sidecar_samples(const char *dir, const char *name, int pfm_width) {
    char path[RAS_IO_MAX_PATH + 64], why[256];
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    cJSON *j = read_json(path, "buffer description", 1u << 20, why, sizeof why);
    const cJSON *s = cJSON_GetObjectItemCaseSensitive(j, "samples");
    int samples =
        cJSON_IsNumber(s) && s->valueint >= 1 && pfm_width % s->valueint == 0 ? s->valueint : 1;
    cJSON_Delete(j);
    return samples;
}

/* Buffer `name` of two dumps, read to be compared: the reference's (a
 * shipped one may be .pfm.gz), then the other's, read only if no larger
 * than the reference's decoded size and then required to have its size;
 * `w` is the files' width (pixels times samples), `samples` the
 * reference's. Both malloc'd; false with err set (nothing to free). */
static bool load_pair(const char *ref_dir, const char *got_dir, const char *name, float **ref,
                      float **got, int *w, int *h, int *ch, int *samples, ras_error *err) {
    int gw, gh, gc;
    *got = NULL;
    *ref = read_dump(ref_dir, name, -1, w, h, ch, err);
    if (!*ref) return false;
    long limit = (long)*w * *h * *ch * (long)sizeof(float) + 4096;
    *got = read_dump(got_dir, name, limit, &gw, &gh, &gc, err);
    if (*got && (gw != *w || gh != *h || gc != *ch))
        ras_error_set(err,
                      "%s: expected %dx%d with %d channel(s) like the reference, got %dx%d "
                      "with %d",
                      name, *w, *h, *ch, gw, gh, gc);
    if (!*got || gw != *w || gh != *h || gc != *ch) {
        free(*ref);
        free(*got);
        *ref = *got = NULL;
        return false;
    }
    *samples = sidecar_samples(ref_dir, name, *w);
    return true;
}

/* The pattern of the differing pixels (`bad`, w x h): isolated pixels, a
 * row or column wrong while its neighbours are not, pixels only one side
 * drew, or regions. False when out of memory. */
static bool classify(ras_dump_difference *d, const unsigned char *bad, int w, int h) {
    int *rows = calloc((size_t)h, sizeof *rows), *cols = calloc((size_t)w, sizeof *cols);
    if (!rows || !cols) {
        free(rows), free(cols);
        return false;
    }
    for (int row = 0; row < h; row++)
        for (int x = 0; x < w; x++) {
            if (!bad[(size_t)row * w + x]) continue;
            rows[row]++, cols[x]++;
            int around = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++)
                    if ((dx || dy) && row + dy >= 0 && row + dy < h && x + dx >= 0 && x + dx < w)
                        around += bad[(size_t)(row + dy) * w + x + dx];
            d->isolated += around <= 2;
        }
    for (int pass = 0; pass < 2 && d->line < 0; pass++) {
        const int *line = pass ? cols : rows;
        int n = pass ? w : h;
        for (int i = 0; i < n; i++) {
            int beside = 0;
            if (i > 0 && line[i - 1] > beside) beside = line[i - 1];
            if (i < n - 1 && line[i + 1] > beside) beside = line[i + 1];
            if (line[i] >= 24 && line[i] >= 4 * (beside + 1) && line[i] * 2 >= d->pixels_differ) {
                d->line = i, d->line_is_column = pass == 1;
                break;
            }
        }
    }
    free(rows), free(cols);
    if (d->pixels_differ == 0)
        d->pattern = "";
    else if (d->line >= 0)
        d->pattern = d->line_is_column ? "along a column" : "along a row";
    else if (d->isolated * 2 >= d->pixels_differ)
        d->pattern = "in speckles";
    else if (d->drawn_in_one * 2 >= d->pixels_differ)
        d->pattern = "where only one drew";
    else
        d->pattern = "in regions";
    return true;
}

bool ras_dump_compare(const char *ref_dir, const char *got_dir, const char *name,
                      ras_dump_difference *d, ras_error *err) {
    *d = (ras_dump_difference){.line = -1, .first_col = -1, .first_row = -1, .pattern = ""};
    int rw, rh, rc, samples;
    float *ref, *got;
    if (!load_pair(ref_dir, got_dir, name, &ref, &got, &rw, &rh, &rc, &samples, err)) return false;
    int w = rw / samples, h = rh, per = samples * rc;
    bool relative;
    double tol = tolerance_of(name, &relative);
    unsigned char *bad = calloc((size_t)w * h, 1);
    if (!bad) {
        free(ref);
        free(got);
        return ras_error_set(err, "out of memory comparing the %s buffers", name);
    }
    d->entries = (long)rw * rh * rc;
    for (int row = 0; row < h; row++)
        for (int x = 0; x < w; x++) {
            const float *a = ref + ((size_t)row * w + x) * per,
                        *b = got + ((size_t)row * w + x) * per;
            bool differs = false, one_empty = false, larger = false, signed_once = false;
            for (int k = 0; k < per; k++) {
                /* Counted apart: a NaN or inf has no difference to report. */
                bool same = a[k] == b[k] || (isnan(a[k]) && isnan(b[k]));
                d->nonfinite_got += !same && !isfinite(b[k]);
                d->nonfinite_ref += !same && !isfinite(a[k]) && isfinite(b[k]);
                bool ea = isinf(a[k]) && a[k] > 0, eb = isinf(b[k]) && b[k] > 0;
                if (ea != eb) {
                    one_empty = differs = true;
                    continue;
                }
                if (ea) continue;
                if (isnan(a[k]) != isnan(b[k])) {
                    differs = true;
                    continue;
                }
                if (isnan(a[k])) continue;
                double diff = fabs((double)a[k] - b[k]);
                double limit = relative ? tol * fmax(1.0, fabs((double)a[k])) : tol;
                if (diff > d->max_abs && isfinite(diff)) d->max_abs = diff;
                if (diff > limit || !isfinite(diff)) {
                    differs = true;
                    d->finite_differ += isfinite(a[k]) && isfinite(b[k]);
                    if (!signed_once) larger = b[k] > a[k], signed_once = true;
                }
            }
            if (!differs) continue;
            bad[(size_t)row * w + x] = 1;
            d->pixels_differ++;
            d->drawn_in_one += one_empty;
            d->larger += larger;
            if (d->first_col < 0) d->first_col = x, d->first_row = row;
        }
    free(ref);
    free(got);
    bool classified = classify(d, bad, w, h);
    free(bad);
    if (!classified) return ras_error_set(err, "out of memory comparing the %s buffers", name);
    return true;
}

void ras_dump_difference_text(const char *name, const ras_dump_difference *d, char *buf,
                              size_t size) {
    if (d->pixels_differ == 0) {
        snprintf(buf, size, "%s: the same (within its tolerance)", name);
        return;
    }
    char where[80] = "";
    if (d->line >= 0)
        snprintf(where, sizeof where, " %d", d->line);
    else if (!strcmp(d->pattern, "in speckles"))
        snprintf(where, sizeof where, ": %ld isolated", d->isolated);
    /* "largest difference 0" would hide what differs when it is NaN or inf
     * (an all-NaN buffer): those are named, with their file. */
    char how[200] = "", largest[48] = "";
    if (d->nonfinite_got || d->nonfinite_ref)
        snprintf(how, sizeof how, ": %ld non-finite values (NaN/inf) in %s%s.pfm where %s holds "
                                  "other values%s",
                 d->nonfinite_got ? d->nonfinite_got : d->nonfinite_ref,
                 d->nonfinite_got ? "" : "the reference's ", name,
                 d->nonfinite_got ? "the reference" : "the dump",
                 d->nonfinite_got && d->nonfinite_ref ? " (and some the other way round)" : "");
    if (d->finite_differ)
        snprintf(largest, sizeof largest, " (largest difference %.3g)", d->max_abs);
    snprintf(buf, size, "%s differs in %ld pixels%s%s, %s%s; the first at (%d, %d)", name,
             d->pixels_differ, largest, how, d->pattern, where, d->first_col, d->first_row);
}

static cJSON *numbers(const float *v, int n) {
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; k < n; k++)
        cJSON_AddItemToArray(a, isfinite(v[k]) ? cJSON_CreateNumber(v[k]) : cJSON_CreateNull());
    return a;
}

bool ras_dump_vertices(const char *dir, const char *stem, const ras_mesh *mesh, mat4s model,
                       mat4s view, mat4s projection, int width, int height, ras_error *err) {
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "buffer", "vertices");
    cJSON_AddStringToObject(j, "frame", ras_dump_frame_id());
    cJSON_AddStringToObject(
        j, "what",
        "each vertex at every step of the vertex stage: object -> world (model) -> eye (view) "
        "-> clip (projection) -> NDC (divided by w) -> screen (viewport: x right, y up, pixel "
        "(x, y) covers [x, x+1) x [y, y+1)); null where a value is not finite");
    cJSON_AddNumberToObject(j, "width", width);
    cJSON_AddNumberToObject(j, "height", height);
    cJSON_AddItemToObject(j, "model", numbers((const float *)model.raw, 16));
    cJSON_AddItemToObject(j, "view", numbers((const float *)view.raw, 16));
    cJSON_AddItemToObject(j, "projection", numbers((const float *)projection.raw, 16));
    cJSON_AddStringToObject(j, "matrix_layout", "column-major (cglm): m[column][row]");
    cJSON *vs = cJSON_AddArrayToObject(j, "vertices");
    size_t n = mesh->vertex_count < 4096 ? mesh->vertex_count : 4096;
    for (size_t i = 0; i < n; i++) {
        vec4s object = glms_vec4(mesh->positions[i], 1.0f);
        vec4s world = ras_mat4_mulv(model, object);
        vec4s eye = ras_mat4_mulv(view, world);
        vec4s clip = ras_mat4_mulv(projection, eye);
        vec4s ndc = glms_vec4_scale(clip, 1.0f / clip.w);
        vec4s screen = ras_viewport(clip, width, height);
        cJSON *v = cJSON_CreateObject();
        cJSON_AddItemToObject(v, "object", numbers(object.raw, 3));
        cJSON_AddItemToObject(v, "world", numbers(world.raw, 3));
        cJSON_AddItemToObject(v, "eye", numbers(eye.raw, 3));
        cJSON_AddItemToObject(v, "clip", numbers(clip.raw, 4));
        cJSON_AddItemToObject(v, "ndc", numbers(ndc.raw, 3));
        cJSON_AddItemToObject(v, "screen", numbers(screen.raw, 3));
        cJSON_AddItemToArray(vs, v);
    }
    if (n < mesh->vertex_count)
        cJSON_AddNumberToObject(j, "vertices_left_out", (double)(mesh->vertex_count - n));
    char path[RAS_IO_MAX_PATH + 64];
    snprintf(path, sizeof path, "%s/%s.json", dir, stem);
    return ras_dump_write_json_file(path, "vertex dump", j, err);
}

int ras_dump_compare_vertices(const char *ref_path, const char *got_path, char *text, size_t size) {
    cJSON *a = read_json(ref_path, "vertex dump", 16u << 20, text, size),
          *b = a ? read_json(got_path, "vertex dump", 16u << 20, text, size) : NULL;
    const cJSON *va = cJSON_GetObjectItemCaseSensitive(a, "vertices");
    const cJSON *vb = cJSON_GetObjectItemCaseSensitive(b, "vertices");
    int result = -1;
    if (a && b && (!cJSON_IsArray(va) || !cJSON_IsArray(vb)))
        snprintf(text, size, "not a vertex dump (no \"vertices\" list)");
    else if (a && b && cJSON_GetArraySize(va) != cJSON_GetArraySize(vb))
        snprintf(text, size, "vertices: %d in the reference, %d here", cJSON_GetArraySize(va),
                 cJSON_GetArraySize(vb));
    else if (a && b) {
        static const char *const steps[] = {"object", "world", "eye", "clip", "ndc", "screen"};
        result = 0;
        snprintf(text, size, "vertices: the same at every step");
        for (int i = 0; i < cJSON_GetArraySize(va) && !result; i++)
            for (int s = 0; s < 6 && !result; s++) {
                const cJSON *x =
                    cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(va, i), steps[s]);
                const cJSON *y =
                    cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(vb, i), steps[s]);
                int n = cJSON_GetArraySize(x);
                bool same = cJSON_GetArraySize(y) == n;
                for (int k = 0; k < n && same; k++) {
                    const cJSON *p = cJSON_GetArrayItem(x, k), *q = cJSON_GetArrayItem(y, k);
                    if (cJSON_IsNull(p) || cJSON_IsNull(q)) {
                        same = cJSON_IsNull(p) == cJSON_IsNull(q);
                        continue;
                    }
                    double u = p->valuedouble, v = q->valuedouble;
                    same = fabs(u - v) <= 1e-5 * fmax(1.0, fabs(u));
                }
                if (same) continue;
                result = 1;
                char want[160] = "", got[160] = "";
                for (int k = 0; k < n; k++) {
                    const cJSON *p = cJSON_GetArrayItem(x, k), *q = cJSON_GetArrayItem(y, k);
                    size_t lw = strlen(want), lg = strlen(got);
                    snprintf(want + lw, sizeof want - lw, "%s%.4g", k ? ", " : "",
                             cJSON_IsNumber(p) ? p->valuedouble : NAN);
                    snprintf(got + lg, sizeof got - lg, "%s%.4g", k ? ", " : "",
                             cJSON_IsNumber(q) ? q->valuedouble : NAN);
                }
                static const char *const matrix[] = {"the mesh itself", "the model matrix",
                                                     "the view matrix", "the projection matrix",
                                                     "the divide by w", "the viewport"};
                snprintf(text, size,
                         "vertices differ first at vertex %d, step %s: expected (%s), got (%s); "
                         "look at %s",
                         i, steps[s], want, got, matrix[s]);
            }
    }
    cJSON_Delete(a);
    cJSON_Delete(b);
    return result;
}

bool ras_dump_compare_pictures(const char *ref_dir, const char *got_dir, const char *name,
                               const char *out_dir, ras_error *err) {
    int w, h, ch, samples;
    float *ref, *got;
    if (!load_pair(ref_dir, got_dir, name, &ref, &got, &w, &h, &ch, &samples, err)) return false;
    size_t n = (size_t)w * h;
    float *diff = malloc(n * sizeof *diff);
    if (!diff) {
        free(ref);
        free(got);
        return ras_error_set(err, "out of memory drawing the %s buffers", name);
    }
    for (size_t i = 0; i < n; i++) {
        double m = 0;
        for (int c = 0; c < ch; c++) {
            float a = ref[i * ch + c], b = got[i * ch + c];
            double e = (isinf(a) && isinf(b) && a == b) ? 0 : fabs((double)a - b);
            m = fmax(m, isfinite(e) ? e : 1);
        }
        diff[i] = (float)m;
    }
    ras_dump_buffer ref_b = {.name = "reference",
                             .what = name,
                             .units = "",
                             .width = w / samples,
                             .height = h,
                             .samples = samples,
                             .channels = ch,
                             .data = ref,
                             .empty = INFINITY,
                             .has_empty = true};
    ref_b.style = ch == 1                   ? RAS_DUMP_SCALAR
                  : !strcmp(name, "normal") ? RAS_DUMP_VECTOR
                                            : RAS_DUMP_UNIT;
    ras_dump_stats rs = ras_dump_buffer_stats(&ref_b);
    double range[2] = {rs.lo[0], rs.hi[0]};
    ras_dump_buffer got_b = ref_b;
    got_b.name = "yours", got_b.data = got;
    if (ch == 1 && rs.lo[0] <= rs.hi[0]) got_b.range = range;
    ras_dump_buffer diff_b = ref_b;
    diff_b.name = "difference", diff_b.units = "|reference - yours|", diff_b.channels = 1;
    diff_b.data = diff, diff_b.style = RAS_DUMP_SCALAR, diff_b.empty = 0.0f;
    bool ok = ras_dump_write(out_dir, &ref_b, err) && ras_dump_write(out_dir, &got_b, err) &&
              ras_dump_write(out_dir, &diff_b, err);
    free(ref);
    free(got);
    free(diff);
    return ok;
}
