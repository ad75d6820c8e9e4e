/* fuzz_scene.c — the scene-file parser (ras_scene_parse, cJSON underneath).
 * Input: the JSON text (a NUL is appended). Parsing must either fail with a
 * message or give a scene whose sizes are in range; it never opens a file. */
#include "fuzz_target.h"

#include "ras_scene.h"

#include <stdlib.h> /* malloc, free */
#include <string.h> /* memcpy */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    ras_error err;
    ras_scene *s = ras_scene_parse(text, "fuzz.json", NULL, &err);
    free(text);
    if (!s) {
        fuzz_check(err.msg[0] != '\0', "a failed parse must say why");
        return 0;
    }
    ras_scene_destroy(s);
    return 0;
}
