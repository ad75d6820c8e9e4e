/* ras_scene_schema.h — the scene format: which keys a scene file has, their
 * defaults and their rules (private to ras_scene*.c).
 *
 * ras_scene.h documents the format for its users (and docs/scenes.md every
 * key); this is where it is checked. The reader (ras_scene.c) parses the text
 * with cJSON, then hands the tree to ras_scene_schema_read, which walks it
 * section by section (image, camera, objects with their shape, transform and
 * material, lights, aa, the effects) and fills a ras_scene. Value checks and
 * messages are ras_scene_json.h's.
 *
 * Dependencies: cJSON, ras_scene_json.h.
 */
#ifndef RAS_SCENE_SCHEMA_H
#define RAS_SCENE_SCHEMA_H

#include "ras_scene.h"
#include "ras_scene_json.h"

/* The defaults of every key outside "objects" (ras_scene.h lists them). */
void ras_scene_schema_defaults(ras_scene *s);

/* Fills s from the parsed document `root`, over the defaults. False and
 * c->err (naming the key path) at the first key that breaks the format;
 * whatever was filled in is for ras_scene_destroy. */
bool ras_scene_schema_read(ras_json_ctx *c, const cJSON *root, ras_scene *s);

#endif
