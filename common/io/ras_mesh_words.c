/* ras_mesh_words.c — see ras_mesh_words.h. */
#include "ras_mesh_words.h"

#include "ras_io.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <strings.h> /* strcasecmp, strncasecmp */
#include <unistd.h>  /* read, close */

/* The first bytes of the file (at most size - 1, NUL-terminated); 0 when it
 * cannot be read. */
static size_t first_bytes(const char *path, uint8_t *buf, size_t size) {
    char why[128];
    int fd = ras_io_open_input(path, why, sizeof why);
    if (fd < 0) return 0;
    ssize_t n = read(fd, buf, size - 1);
    close(fd);
    n = n < 0 ? 0 : n;
    buf[n] = '\0';
    return (size_t)n;
}

static const char *extension_of(const char *path) {
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    return dot && (!slash || dot > slash) ? dot + 1 : "";
}

const char *ras_mesh_format_words(const char *path, char *buf, size_t size) {
    uint8_t head[64];
    size_t n = first_bytes(path, head, sizeof head);
    /* a .glb says its version in its header: 1 is glTF 1.0's binary form */
    if (n >= 12 && !memcmp(head, "glTF", 4)) {
        uint32_t version = head[4] | head[5] << 8 | head[6] << 16 | (uint32_t)head[7] << 24;
        snprintf(buf, size, "a binary glTF (.glb) file of version %u", version);
        return buf;
    }
    static const struct { const char *ext, *words; } known[] = {
        {"obj", "an OBJ file"},   {"ply", "a PLY file"},   {"stl", "an STL file"},
        {"gltf", "a glTF file"},  {"glb", "a binary glTF (.glb) file"},
        {"off", "an OFF file"},   {"dae", "a COLLADA file"}, {"fbx", "an FBX file"},
        {"3ds", "a 3DS file"},    {"x3d", "an X3D file"},
    };
    const char *ext = extension_of(path);
    for (size_t k = 0; k < sizeof known / sizeof *known; k++)
        if (!strcasecmp(ext, known[k].ext)) return snprintf(buf, size, "%s", known[k].words), buf;
    if (n >= 4 && !strncmp((const char *)head, "ply", 3) && (head[3] == '\n' || head[3] == '\r'))
        return snprintf(buf, size, "a PLY file (by its first line)"), buf;
    if (n >= 6 && !strncasecmp((const char *)head, "solid ", 6))
        return snprintf(buf, size, "an ASCII STL file (by its first line)"), buf;
    if (n >= 2 && (!strncmp((const char *)head, "v ", 2) || !strncmp((const char *)head, "# ", 2)))
        return NULL; /* OBJ-like text says too little */
    return NULL;
}

/* assimp's words (a piece of its message) and what they mean for the user:
 * what is wrong, then what to do. */
static const struct {
    const char *assimp, *what, *todo;
} g_meanings[] = {
    {"index out of range", "a face names a vertex that does not exist",
     "expected each 'f' index within 1..N (or -1..-N) of the vertices before it; fix the face "
     "lines, or re-export the model"},
    {"Invalid face ind", "a face names a vertex that does not exist (an index of 0, or past the "
                         "vertices)",
     "expected each 'f' index within 1..N (or -1..-N) of the vertices before it; fix the face "
     "lines, or re-export the model"},
    {"STL storage representation", "it is neither an ASCII STL (starting 'solid', then facets) "
                                   "nor a binary STL whose size matches its triangle count",
     "the file is cut short or not an STL; re-export it"},
    {"STL: Invalid number of vertices", "a facet has other than 3 vertices",
     "expected 'outer loop' with three 'vertex' lines per facet; re-export it"},
    {"POINT", "it mixes points (or lines) with faces in a way the importer cannot sort out",
     "expected triangles; export the surface alone"},
    {"LINE", "it mixes lines with faces in a way the importer cannot sort out",
     "expected triangles; export the surface alone"},
};

void ras_mesh_import_failure(ras_error *err, const char *path, const char *assimp_text) {
    const char *said = assimp_text && *assimp_text ? assimp_text : "nothing";
    char format[96];
    const char *is = ras_mesh_format_words(path, format, sizeof format);
    if (is && strstr(is, "glb) file of version") && !strstr(is, "version 2")) {
        ras_error_set(err,
                      "could not read model '%s': it is %s, which the importer does not read "
                      "(binary glTF 1.0); expected glTF 2.0 — re-export it as glTF 2.0 (.glb or "
                      ".gltf) [the importer said: %.300s]",
                      path, is, said);
        return;
    }
    for (size_t k = 0; is && k < sizeof g_meanings / sizeof *g_meanings; k++)
        if (strstr(said, g_meanings[k].assimp)) {
            ras_error_set(err, "could not read model '%s': it is %s, but %s; %s [the importer "
                               "said: %.300s]",
                          path, is, g_meanings[k].what, g_meanings[k].todo, said);
            return;
        }
    if (is)
        ras_error_set(err,
                      "could not read model '%s': it is %s, but not a complete one the importer "
                      "can read — check the file, or re-export it [the importer said: %.300s]",
                      path, is, said);
    else
        ras_error_set(err,
                      "could not read model '%s': it is not a complete mesh file in a format the "
                      "importer knows (expected OBJ, PLY, STL, glTF, OFF, COLLADA, ...) — check "
                      "the file, or re-export it [the importer said: %.300s]",
                      path, said);
}
