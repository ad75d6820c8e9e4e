/* ras_mesh_words.h — what a failed model import tells the user.
 *
 * assimp's messages name its internals ("OBJ: Invalid face index.",
 * "Failed to determine STL storage representation for m.stl."): the
 * project's sentence names the format the file is (by its extension, else
 * its first bytes) and what is wrong with it in the user's terms, and keeps
 * assimp's words last, as detail.
 */
#ifndef RAS_MESH_WORDS_H
#define RAS_MESH_WORDS_H

#include "ras_error.h"

/* err set to "could not read model PATH: it is FORMAT, but WHAT — DO
 * [the importer said: ASSIMP]"; `assimp_text` may be NULL or empty. */
void ras_mesh_import_failure(ras_error *err, const char *path, const char *assimp_text);

/* The format `path` is, in words ("an OBJ file", "a binary glTF (.glb)
 * version 1 file"), from its extension or, without one the project knows,
 * its first bytes; NULL when neither says. */
const char *ras_mesh_format_words(const char *path, char *buf, size_t size);

#endif
