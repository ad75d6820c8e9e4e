/* ras_names.c — see ras_names.h. */
#include "ras_names.h"

#include "ras_pipeline.h"       /* ras_cull_mode */
#include "ras_sample_pattern.h" /* ras_pattern_kind */
#include "ras_scene.h"          /* ras_scene_shader, ras_scene_filter */
#include "ras_texture.h"        /* ras_wrap */
#include "stage3_setup.h"       /* ras_depth_format */
#include "stage4_raster.h"      /* ras_aa_mode */

#include <stdio.h>  /* snprintf */
#include <string.h> /* strcmp */

#define TABLE(id, what_text, ...)                                                              \
    static const char *const id##_list[] = {__VA_ARGS__};                                      \
    const ras_names id = {what_text, (int)(sizeof id##_list / sizeof id##_list[0]), id##_list}

TABLE(ras_names_aa, "an anti-aliasing mode", [RAS_AA_NONE] = "none", [RAS_AA_MSAA] = "msaa",
      [RAS_AA_SSAA] = "ssaa");
TABLE(ras_names_pattern, "a sample pattern", [RAS_PATTERN_ORDERED] = "ordered",
      [RAS_PATTERN_STANDARD] = "standard");
TABLE(ras_names_depth, "a depth format", [RAS_DEPTH_Z01] = "z01", [RAS_DEPTH_INV_W] = "inverse_w");
TABLE(ras_names_shader, "a shader", [RAS_SHADER_FLAT] = "flat", [RAS_SHADER_NORMAL] = "normal",
      [RAS_SHADER_PHONG] = "phong", [RAS_SHADER_TEXTURE] = "texture",
      [RAS_SHADER_BUMP] = "bump", [RAS_SHADER_DISPLACEMENT] = "displacement");
TABLE(ras_names_filter, "a texture filter", [RAS_FILTER_NEAREST] = "nearest",
      [RAS_FILTER_BILINEAR] = "bilinear", [RAS_FILTER_TRILINEAR] = "trilinear");
TABLE(ras_names_wrap, "a wrap mode", [RAS_WRAP_REPEAT] = "repeat", [RAS_WRAP_CLAMP] = "clamp");
TABLE(ras_names_cull, "a cull mode", [RAS_CULL_NONE] = "none", [RAS_CULL_BACK] = "back",
      [RAS_CULL_FRONT] = "front");

/* A table per enum, as long as the enum. */
_Static_assert(sizeof ras_names_shader_list / sizeof ras_names_shader_list[0] == RAS_SHADER_COUNT,
               "ras_names_shader: one name per ras_scene_shader");
_Static_assert(sizeof ras_names_depth_list / sizeof ras_names_depth_list[0] ==
                   RAS_DEPTH_FORMAT_COUNT,
               "ras_names_depth: one name per ras_depth_format");

const char *ras_name_of(const ras_names *t, int value) {
    return value >= 0 && value < t->count ? t->names[value] : "?";
}

int ras_name_find(const ras_names *t, const char *word, int first) {
    for (int i = first; i < t->count; i++)
        if (!strcmp(word, t->names[i])) return i;
    return -1;
}

const char *ras_names_list(const ras_names *t, int first, char *buf, size_t size) {
    size_t n = 0;
    buf[0] = '\0';
    for (int i = first; i < t->count && n < size; i++) {
        const char *sep = i == first ? "" : i == t->count - 1 ? " or " : ", ";
        int w = snprintf(buf + n, size - n, "%s%s", sep, t->names[i]);
        if (w < 0) break;
        n += (size_t)w;
    }
    return buf;
}

/* The name functions of the enums the pipeline's own modules declare
 * (stage3_setup.h, stage4_raster.h, ras_sample_pattern.h) live here, so
 * those modules do not include this one: the names depend on the stages,
 * never the other way. */
const char *ras_depth_format_name(ras_depth_format format) {
    return ras_name_of(&ras_names_depth, (int)format);
}

const char *ras_aa_mode_name(ras_aa_mode aa) { return ras_name_of(&ras_names_aa, (int)aa); }

const char *ras_pattern_kind_name(ras_pattern_kind kind) {
    return ras_name_of(&ras_names_pattern, (int)kind);
}
