/* ras_builtin_scenes.h — the programs' default scenes, built into the binaries.
 *
 * Each program's default scene is a file in scenes/ (hw1_classic.json,
 * hw2_classic.json, hw3_default.json). CMake copies their text into the
 * binary at build time (common/scene/ras_builtin_scenes.c.in), so a program finds
 * its default without --scene and without the source tree: scripts/demo and an
 * installed binary need nothing else. Editing a scene file re-runs CMake's
 * configure step and rebuilds the embedded copy.
 */
#ifndef RAS_BUILTIN_SCENES_H
#define RAS_BUILTIN_SCENES_H

#include "ras_scene.h"

/* The JSON text of scenes/<name>.json ("hw1_classic", ...), NUL-terminated;
 * NULL for a name that is not built in. */
const char *ras_builtin_scene_text(const char *name);

/* Parses the built-in scene `name`; messages call it
 * "scenes/<name>.json (built in)". NULL and err when the name is unknown or
 * the text does not parse (a test keeps the latter from happening). */
ras_scene *ras_builtin_scene_load(const char *name, ras_error *err);

/* The scene a program draws: the file `path` when given (--scene), else the
 * built-in `builtin`. */
ras_scene *ras_scene_load_or_builtin(const char *path, const char *builtin, ras_error *err);

/* What --fit makes of a model: centred, its largest extent this many units. */
#define RAS_BUILTIN_MODEL_FIT 5.0f

/* The built-in scene `name` with a model file in place of its first object
 * (--model FILE; scenes/hw3_model.json is the classic GAMES101 one):
 *   model_path     the object's mesh (any format assimp reads)
 *   texture_path   its colour map; NULL: the scene's own (a built-in one)
 *   height_path    its height map; NULL: texture_path, as the course loads
 *                  hmap.jpg as "the texture"; both NULL: the scene's own
 *   fit            centre the model and scale it to RAS_BUILTIN_MODEL_FIT
 *                  units instead of the object's scale (its rotations and
 *                  translation stay)
 * Paths are used as given (relative to the current folder); nothing is
 * opened here, ras_scene_load_assets loads them. Messages call the scene
 * "scenes/<name>.json (built in, with --model)". NULL and err when the name
 * is unknown or out of memory. */
ras_scene *ras_builtin_scene_with_model(const char *name, const char *model_path,
                                        const char *texture_path, const char *height_path,
                                        bool fit, ras_error *err);

#endif
