/* ras_catalogue.c — see ras_catalogue.h. */
#include "ras_catalogue.h"

#include "ras_io.h" /* ras_io_read_file */

#include <cjson/cJSON.h>
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* free */
#include <string.h> /* strlen */

/* Copies the string member `key` of `item` into buf; false when it is not a
 * string that fits (missing is fine when `optional`). */
static bool copy_member(const cJSON *item, const char *key, bool optional, char *buf, size_t size) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(item, key);
    if (!v && optional) return buf[0] = '\0', true;
    if (!cJSON_IsString(v) || strlen(v->valuestring) >= size) return false;
    snprintf(buf, size, "%s", v->valuestring);
    return true;
}

static bool read_entry(const cJSON *item, ras_catalogue_entry *e) {
    const cJSON *args = cJSON_GetObjectItemCaseSensitive(item, "args");
    if (!cJSON_IsObject(item) || !copy_member(item, "reference", false, e->reference, sizeof e->reference) ||
        !copy_member(item, "program", false, e->program, sizeof e->program) ||
        !copy_member(item, "demo", true, e->demo, sizeof e->demo) ||
        (args && (!cJSON_IsArray(args) || cJSON_GetArraySize(args) > RAS_CATALOGUE_MAX_ARGS)))
        return false;
    e->argc = 0;
    const cJSON *a;
    cJSON_ArrayForEach(a, args) {
        if (!cJSON_IsString(a) || strlen(a->valuestring) >= RAS_CATALOGUE_NAME) return false;
        snprintf(e->args[e->argc++], RAS_CATALOGUE_NAME, "%s", a->valuestring);
    }
    return true;
}

/* One comparison of the table: {"metric": KIND, "tolerance": N, "max_bad":
 * F, "min_psnr": DB, "min_ssim": S} (all but metric optional: the kind's
 * defaults, ras_compare_defaults). */
static bool read_comparison(const cJSON *item, ras_catalogue_comparison *c, ras_error *err) {
    const cJSON *metric = cJSON_GetObjectItemCaseSensitive(item, "metric");
    ras_compare_kind kind;
    if (!cJSON_IsObject(item) || !cJSON_IsString(metric) ||
        !ras_compare_kind_parse(metric->valuestring, &kind, err) ||
        strlen(item->string) >= sizeof c->name)
        return false;
    snprintf(c->name, sizeof c->name, "%s", item->string);
    c->options = ras_compare_defaults(kind);
    static const char *const keys[] = {"tolerance", "max_bad", "min_psnr", "min_ssim"};
    for (int k = 0; k < 4; k++) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(item, keys[k]);
        if (!v) continue;
        if (!cJSON_IsNumber(v)) return false;
        double x = v->valuedouble;
        bool in_range = k == 0 ? x >= 0 && x <= 255 && x == (int)x
                        : k == 1 ? x >= 0 && x <= 1
                        : k == 2 ? x >= 0
                                 : x >= -1 && x <= 1;
        if (!in_range) return false;
        if (k == 0) c->options.tolerance = (int)x;
        if (k == 1) c->options.max_bad_fraction = x;
        if (k == 2) c->options.min_psnr_db = x;
        if (k == 3) c->options.min_ssim = x;
    }
    return true;
}

bool ras_catalogue_comparison_options(const ras_catalogue *cat, const char *name,
                                      ras_compare_options *opt, ras_error *err) {
    char names[512] = "";
    size_t n = 0;
    for (int i = 0; i < cat->comparison_count; i++) {
        if (!strcmp(cat->comparisons[i].name, name)) {
            *opt = cat->comparisons[i].options;
            return true;
        }
        int w = snprintf(names + n, sizeof names - n, "%s%s", i ? ", " : "",
                         cat->comparisons[i].name);
        if (w > 0 && (size_t)w < sizeof names - n) n += (size_t)w;
    }
    return ras_error_set(err, "no comparison '%s' in the catalogue; expected one of: %s", name,
                         *names ? names : "(the table is empty)");
}

const ras_catalogue_entry *ras_catalogue_find(const ras_catalogue *cat, const char *reference) {
    size_t n = strlen(reference);
    if (n > 4 && !strcmp(reference + n - 4, ".png")) n -= 4;
    for (int i = 0; i < cat->count; i++)
        if (strlen(cat->entries[i].reference) == n &&
            !strncmp(cat->entries[i].reference, reference, n))
            return &cat->entries[i];
    return NULL;
}

bool ras_catalogue_load(const char *path, ras_catalogue *out, ras_error *err) {
    out->count = 0;
    out->comparison_count = 0;
    size_t size = 0;
    char *text = ras_io_read_file(path, "the reference catalogue", 1 << 20, &size, err);
    if (!text) return false;
    cJSON *root = cJSON_Parse(text);
    free(text);
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(root, "images");
    bool ok = cJSON_IsArray(images) && cJSON_GetArraySize(images) <= RAS_CATALOGUE_MAX_ENTRIES;
    if (!ok)
        ras_error_set(err, "%s: expected a JSON object with an \"images\" array of at most %d "
                           "entries; fix the file",
                      path, RAS_CATALOGUE_MAX_ENTRIES);
    const cJSON *comparisons = cJSON_GetObjectItemCaseSensitive(root, "comparisons");
    const cJSON *item;
    if (ok && (!cJSON_IsObject(comparisons) ||
               cJSON_GetArraySize(comparisons) > RAS_CATALOGUE_MAX_COMPARISONS)) {
        ras_error_set(err, "%s: expected a \"comparisons\" object of at most %d entries "
                           "(NAME: {\"metric\": ...}); fix the file",
                      path, RAS_CATALOGUE_MAX_COMPARISONS);
        ok = false;
    }
    const cJSON *table = ok ? comparisons : NULL;
    cJSON_ArrayForEach(item, table) {
        ras_error why = {{0}};
        if (!read_comparison(item, &out->comparisons[out->comparison_count], &why)) {
            ras_error_set(err, "%s: comparisons.%s: expected {\"metric\": exact|edge|psnr|ssim, "
                               "\"tolerance\": 0..255, \"max_bad\": 0..1, \"min_psnr\": dB, "
                               "\"min_ssim\": -1..1}%s%s; fix that entry",
                          path, item->string, *why.msg ? ": " : "", why.msg);
            ok = false;
            break;
        }
        out->comparison_count++;
    }
    const cJSON *list = ok ? images : NULL;
    cJSON_ArrayForEach(item, list) {
        if (!read_entry(item, &out->entries[out->count])) {
            ras_error_set(err, "%s: images[%d]: expected {\"reference\": NAME, \"program\": NAME, "
                               "\"args\": [at most %d strings], \"demo\": NAME (optional)}, "
                               "each string shorter than %d bytes; fix that entry",
                          path, out->count, RAS_CATALOGUE_MAX_ARGS, RAS_CATALOGUE_NAME);
            ok = false;
            break;
        }
        ras_catalogue_entry *e = &out->entries[out->count];
        const cJSON *c = cJSON_GetObjectItemCaseSensitive(item, "comparison");
        ras_error why = {{0}};
        if (!cJSON_IsString(c) || strlen(c->valuestring) >= sizeof e->comparison ||
            !ras_catalogue_comparison_options(out, c->valuestring, &e->compare, &why)) {
            ras_error_set(err, "%s: images[%d] (%s): expected \"comparison\": a name from "
                               "\"comparisons\"%s%s; fix that entry",
                          path, out->count, e->reference, *why.msg ? ": " : "", why.msg);
            ok = false;
            break;
        }
        snprintf(e->comparison, sizeof e->comparison, "%s", c->valuestring);
        out->count++;
    }
    cJSON_Delete(root);
    return ok;
}

void ras_catalogue_args_text(const ras_catalogue_entry *e, char *buf, int size) {
    int n = snprintf(buf, (size_t)size, "%s", e->argc ? "" : "no options");
    for (int i = 0; i < e->argc && n >= 0 && n < size; i++)
        n += snprintf(buf + n, (size_t)(size - n), "%s%s", i ? " " : "", e->args[i]);
}
