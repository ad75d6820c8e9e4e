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

bool ras_catalogue_load(const char *path, ras_catalogue *out, ras_error *err) {
    out->count = 0;
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
    const cJSON *item;
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
