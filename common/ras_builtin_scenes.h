/* ras_builtin_scenes.h — the programs' default scenes, built into the binaries.
 *
 * Each program's default scene is a file in scenes/ (hw1_classic.json,
 * hw2_classic.json, hw3_default.json). CMake copies their text into the
 * binary at build time (common/ras_builtin_scenes.c.in), so a program finds
 * its default without --scene and without the source tree: `make demo` and an
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

#endif
