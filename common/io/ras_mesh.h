/* ras_mesh.h — triangle meshes: loaded through assimp, or built in.
 *
 * A mesh is an indexed triangle list. Every vertex has a position, a normal
 * (unit length; generated when the file has none) and a texture coordinate
 * (0,0 when the file has none; has_uv says which). Faces with more than three
 * corners are triangulated on load. Built-in shapes need no file and carry
 * UVs and normals, so every scene, test and reference image of the project
 * works on a machine with no downloaded data.
 *
 * Ownership: ras_mesh_load / ras_mesh_create_* return a heap mesh that the
 * caller frees with ras_mesh_destroy (NULL is allowed and ignored).
 */
#ifndef RAS_MESH_H
#define RAS_MESH_H

#include "ras_error.h"
#include "ras_math.h"

#include <stddef.h> /* size_t */

typedef struct ras_mesh {
    size_t vertex_count;
    vec3s *positions; /* object space */
    vec3s *normals;   /* object space, unit length */
    vec2s *uvs;       /* [0,1] for the built-in shapes; files may go outside */
    vec3s *colors;    /* per-vertex colour in [0,1]; white when the file has none */
    size_t triangle_count;
    unsigned *indices; /* 3 * triangle_count, counter-clockwise seen from outside */
    bool has_uv;
    bool has_normals_from_file;
} ras_mesh;

/* Limits of ras_mesh_load (docs/robustness.md), each applied by the file's
 * content, whatever its name:
 * - nesting: a glTF node tree (1.0 or 2.0, JSON or binary), or the
 *   brackets/elements of any text file (COLLADA, X, FBX ASCII, ...), deeper
 *   than RAS_MESH_MAX_NESTING levels is refused before assimp sees it
 *   (scanned up to RAS_MESH_MAX_SCAN_BYTES);
 * - structure: a binary glTF's chunk lengths and a PLY's element counts and
 *   list lengths must fit in the file; a glTF's buffer and image files must
 *   be regular files inside the model's folder;
 * - the import runs on a thread with a stack of up to RAS_MESH_IMPORT_STACK
 *   (a quarter of the memory budget, at least 16 MiB), for formats whose
 *   nesting is not scanned;
 * - memory: the file's size times RAS_MESH_IMPORT_BYTES_PER_FILE_BYTE, plus
 *   an OBJ's .mtl files (their size the same way, and each material's
 *   import) and its objects, material switches and groups (each their
 *   import), must fit the memory budget (ras_memory.h) before the import
 *   starts; so must the glTF node walk (a cJSON tree, up to 40 bytes a
 *   byte), or the file is refused. The import's process is held to the
 *   budget as well (RLIMIT_AS: its address space so far plus the budget);
 * - side files: every file the importer opens besides the model (an OBJ's
 *   mtllib, a glTF's URIs) must be a regular file inside the model's folder;
 *   an OBJ's mtllib outside it is refused with its line;
 * - OBJ: a face's vt/vn index beyond what the file defines is refused (with
 *   its line); at most RAS_MESH_MAX_OBJ_PARTS 'o' and 'usemtl' lines;
 * - PLY: the header must be complete text ('end_header' within 64 KiB) of
 *   the lines the format has, or the file is refused at once. */
#define RAS_MESH_MAX_NESTING 10000
#define RAS_MESH_MAX_SCAN_BYTES (256u << 20)
#define RAS_MESH_IMPORT_STACK (256u << 20)
/* Seconds an import may take before it is an error (assimp has importers
 * that loop forever on some malformed files); RAS_MESH_IMPORT_SECONDS
 * overrides it. The import runs in a child process, so that an importer
 * that crashes on a file fails the load instead of the program. */
#define RAS_MESH_IMPORT_SECONDS_DEFAULT 60
/* measured: 14 (a 40.8 MB OBJ: 570 MB), 19 (a 40 MB glTF of numbers: 761 MB) */
#define RAS_MESH_IMPORT_BYTES_PER_FILE_BYTE 20.0
/* Seconds all imports of one scene may take together (a batch:
 * ras_mesh_imports_begin); RAS_MESH_IMPORT_TOTAL_SECONDS overrides it. A
 * model named by several objects is imported once in the batch (by device,
 * inode, size and times). */
#define RAS_MESH_IMPORT_TOTAL_SECONDS_DEFAULT 120
/* The most 'o' lines, and the most 'usemtl' lines, an OBJ may have: assimp's
 * OBJ reader takes time quadratic in each (measured: 20,000 'o' 2 s, 100,000
 * about a minute; 20,000 'usemtl' 4.5 s). */
#define RAS_MESH_MAX_OBJ_PARTS 20000

/* Loads any format assimp reads (OBJ, PLY, STL, glTF, ...), all meshes of the
 * file merged into one. Returns NULL and sets err for a missing file, a file
 * assimp cannot parse, out-of-range indices, or a file with no triangles. */
ras_mesh *ras_mesh_load(const char *path, ras_error *err);

/* A batch of loads (a scene's objects), between begin and end: a file named
 * again is imported once (a copy of the first import is returned), and all
 * the batch's imports together have RAS_MESH_IMPORT_TOTAL_SECONDS. Outside
 * a batch each load is on its own (the fuzzer, the unit tests). begin also
 * ends a batch left open; end frees the kept copies. */
void ras_mesh_imports_begin(void);
void ras_mesh_imports_end(void);

/* An empty mesh with room for the given counts (zeroed); NULL on overflow/OOM. */
ras_mesh *ras_mesh_create(size_t vertex_count, size_t triangle_count);
void ras_mesh_destroy(ras_mesh *mesh);

/* Built-in shapes, centred on the origin. */
ras_mesh *ras_mesh_create_triangle(vec3s a, vec3s b, vec3s c, vec3s color);
ras_mesh *ras_mesh_create_plane(float size, int divisions);   /* in the xz plane, normal +y, uv over [0,1]² */
ras_mesh *ras_mesh_create_cube(float size);                   /* 24 vertices, flat normals, uv per face */
ras_mesh *ras_mesh_create_uv_sphere(float radius, int stacks, int slices);
ras_mesh *ras_mesh_create_torus(float major_radius, float minor_radius, int rings, int sides);
ras_mesh *ras_mesh_create_teapot(int divisions);              /* Utah teapot from its 32 Bézier patches; fits in a unit-ish box */

/* Axis-aligned bounds of the positions. */
void ras_mesh_bounds(const ras_mesh *mesh, vec3s *lo, vec3s *hi);

/* Model matrix that moves the mesh's bounding-box centre to the origin and
 * scales its largest extent to `size` (what --fit uses). */
mat4s ras_mesh_fit_matrix(const ras_mesh *mesh, float size);

#endif
