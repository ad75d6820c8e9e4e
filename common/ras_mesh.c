/* ras_mesh.c — triangle meshes: loading through assimp, and built-in shapes.
 *
 * Notes:
 *   - Loading merges every triangle mesh of the file into one indexed list,
 *     with each node's transform applied (an instanced mesh appears once per
 *     node that uses it). Points and lines are dropped: the rasterizer draws
 *     triangles only. Normals are generated here rather than by assimp so that
 *     has_normals_from_file is exact and a bad normal in a file (zero, NaN)
 *     gets the same repair as a missing one.
 *   - Every built-in shape is counter-clockwise seen from outside, has unit
 *     normals and UVs in [0,1]; shapes with a pole (sphere, teapot lid and
 *     bottom) leave out the zero-area triangles the pole would create, so a
 *     face normal can always be computed.
 *   - The teapot is tessellated from Newell's 32 bicubic Bézier patches; the
 *     data is z-up and is turned to the project's y-up world (spout to +x).
 *
 * Dependencies: assimp (C API), cglm (struct API) through ras_math.h.
 * assimp is not linked: it is opened with dlopen when the first model file is
 * read (load_assimp), so programs that draw built-in shapes never load it
 * (docs/startup.md).
 */
#include "ras_mesh.h"

#include <assimp/cfileio.h>     /* aiFileIO, aiFile */
#include <assimp/cimport.h>     /* aiImportFileEx, aiReleaseImport, aiGetErrorString */
#include <assimp/postprocess.h> /* aiProcess_* */
#include <assimp/scene.h>       /* aiScene, aiNode, aiMesh */

#include <assert.h> /* assert */
#include <dlfcn.h>  /* dlopen, dlsym, dlerror: assimp, loaded on first use */
#include <limits.h> /* UINT_MAX, PATH_MAX */
#include <math.h>   /* sqrtf, sinf, cosf, isfinite */
#include <stdint.h> /* SIZE_MAX */
#include <stdio.h>  /* fdopen, fread, fseek, fclose, snprintf */
#include <stdlib.h> /* calloc, malloc, free */
#include <string.h> /* memcpy, memcmp, memchr, strcmp, strrchr, strstr, strchr, strdup */
#include <sys/stat.h> /* fstat */
#include <unistd.h> /* close */

#include "ras_io.h"     /* ras_io_open_input, ras_io_read_file, ras_io_text_nesting */
#include "ras_job.h"    /* ras_job_run: the import on its own thread, with a time limit */
#include "ras_memory.h" /* ras_memory_check, ras_memory_limit */

#include <cjson/cJSON.h> /* cJSON_ParseWithLength: glTF node trees */
#include <pthread.h>     /* pthread_once: assimp opened once */
#ifdef __GLIBC__
#include <malloc.h> /* malloc_trim */
#endif

/* ------------------------------------------------------------------------ */
/* Allocation                                                                */

/* calloc that treats n * size overflow as failure and never asks for 0 bytes
 * (calloc(0) may return NULL, which would look like OOM). */
static void *calloc_checked(size_t n, size_t size) {
    if (n == 0) n = 1;
    if (n > SIZE_MAX / size) return NULL;
    return calloc(n, size);
}

ras_mesh *ras_mesh_create(size_t vertex_count, size_t triangle_count) {
    /* Indices are unsigned, so every vertex must be addressable by one. */
    if (vertex_count > (size_t)UINT_MAX) return NULL;
    if (triangle_count > SIZE_MAX / 3) return NULL;
    ras_mesh *mesh = calloc(1, sizeof *mesh);
    if (!mesh) return NULL;
    mesh->vertex_count = vertex_count;
    mesh->triangle_count = triangle_count;
    mesh->positions = calloc_checked(vertex_count, sizeof *mesh->positions);
    mesh->normals = calloc_checked(vertex_count, sizeof *mesh->normals);
    mesh->uvs = calloc_checked(vertex_count, sizeof *mesh->uvs);
    mesh->colors = calloc_checked(vertex_count, sizeof *mesh->colors);
    mesh->indices = calloc_checked(3 * triangle_count, sizeof *mesh->indices);
    if (!mesh->positions || !mesh->normals || !mesh->uvs || !mesh->colors || !mesh->indices) {
        ras_mesh_destroy(mesh);
        return NULL;
    }
    return mesh;
}

void ras_mesh_destroy(ras_mesh *mesh) {
    if (!mesh) return;
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->uvs);
    free(mesh->colors);
    free(mesh->indices);
    free(mesh);
}

/* ------------------------------------------------------------------------ */
/* Small vector helpers (by value, like cglm's struct API)                   */

static vec3s v3(float x, float y, float z) { return (vec3s){{x, y, z}}; }

static vec3s face_normal_raw(vec3s a, vec3s b, vec3s c) {
    /* Unnormalised: its length is twice the area, which weights the average
     * of face normals at a vertex by area. */
    return glms_vec3_cross(glms_vec3_sub(b, a), glms_vec3_sub(c, a));
}

/* Unit vector, or `fallback` when v is zero, tiny or not finite: normalising
 * such a vector would give NaN or a direction made of rounding noise. */
static vec3s unit_or(vec3s v, vec3s fallback) {
    float len2 = glms_vec3_dot(v, v);
    if (!(len2 > 1e-30f) || !isfinite(len2)) return fallback;
    return glms_vec3_scale(v, 1.0f / sqrtf(len2));
}

static bool normal_ok(vec3s n) {
    float len2 = glms_vec3_dot(n, n);
    return isfinite(len2) && len2 > 1e-30f;
}

static void fill_color(ras_mesh *mesh, vec3s color) {
    for (size_t i = 0; i < mesh->vertex_count; i++) mesh->colors[i] = color;
}

/* Replaces every normal flagged in `repair` (or every normal, when repair is
 * NULL) by the normalised area-weighted sum of the face normals around it. */
static void smooth_normals(ras_mesh *mesh, const bool *repair) {
    for (size_t v = 0; v < mesh->vertex_count; v++)
        if (!repair || repair[v]) mesh->normals[v] = glms_vec3_zero();
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const unsigned *tri = &mesh->indices[3 * t];
        vec3s n = face_normal_raw(mesh->positions[tri[0]], mesh->positions[tri[1]],
                                           mesh->positions[tri[2]]);
        if (!ras_vec3_finite(n)) continue;
        for (int k = 0; k < 3; k++)
            if (!repair || repair[tri[k]])
                mesh->normals[tri[k]] = glms_vec3_add(mesh->normals[tri[k]], n);
    }
    /* A vertex used by no triangle, or only by zero-area ones, has no face
     * to take a normal from; +y keeps the contract (unit length, finite). */
    for (size_t v = 0; v < mesh->vertex_count; v++)
        if (!repair || repair[v])
            mesh->normals[v] = unit_or(mesh->normals[v], v3(0, 1, 0));
}

/* ------------------------------------------------------------------------ */
/* Loading through assimp                                                    */

/* One use of an assimp mesh by a node, with the node's accumulated transform. */
typedef struct ras_mesh_instance {
    const struct aiMesh *mesh;
    struct aiMatrix4x4 transform;
} ras_mesh_instance;

typedef struct ras_mesh_node_item {
    const struct aiNode *node;
    struct aiMatrix4x4 transform;
} ras_mesh_node_item;

/* a * b for assimp's row-major matrices (p' = M p). */
static struct aiMatrix4x4 ai_mul(const struct aiMatrix4x4 *a, const struct aiMatrix4x4 *b) {
    const float *A = &a->a1, *B = &b->a1;
    struct aiMatrix4x4 r;
    float *R = &r.a1;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++) s += A[4 * i + k] * B[4 * k + j];
            R[4 * i + j] = s;
        }
    return r;
}

static struct aiMatrix4x4 ai_identity(void) {
    struct aiMatrix4x4 m;
    memset(&m, 0, sizeof m);
    m.a1 = m.b2 = m.c3 = m.d4 = 1.0f;
    return m;
}

/* Lists every (mesh, transform) pair of the node tree. Iterative, so a file
 * with a very deep hierarchy cannot overflow the C stack. Returns false on
 * OOM; *out is then NULL. */
static bool collect_instances(const struct aiScene *scene, ras_mesh_instance **out,
                                       size_t *out_count) {
    *out = NULL;
    *out_count = 0;
    size_t inst_cap = 16, inst_n = 0, stack_cap = 16, stack_n = 0;
    ras_mesh_instance *inst = malloc(inst_cap * sizeof *inst);
    ras_mesh_node_item *stack = malloc(stack_cap * sizeof *stack);
    if (!inst || !stack) goto oom;
    stack[stack_n++] = (ras_mesh_node_item){scene->mRootNode, ai_identity()};
    while (stack_n > 0) {
        ras_mesh_node_item item = stack[--stack_n];
        const struct aiNode *node = item.node;
        if (!node) continue;
        struct aiMatrix4x4 m = ai_mul(&item.transform, &node->mTransformation);
        for (unsigned i = 0; i < node->mNumMeshes; i++) {
            unsigned mi = node->mMeshes[i];
            if (mi >= scene->mNumMeshes || !scene->mMeshes[mi]) continue;
            if (inst_n == inst_cap) {
                if (inst_cap > SIZE_MAX / 2 / sizeof *inst) goto oom;
                ras_mesh_instance *grown = realloc(inst, 2 * inst_cap * sizeof *inst);
                if (!grown) goto oom;
                inst = grown;
                inst_cap *= 2;
            }
            inst[inst_n++] = (ras_mesh_instance){scene->mMeshes[mi], m};
        }
        for (unsigned c = 0; c < node->mNumChildren; c++) {
            if (stack_n == stack_cap) {
                if (stack_cap > SIZE_MAX / 2 / sizeof *stack) goto oom;
                ras_mesh_node_item *grown = realloc(stack, 2 * stack_cap * sizeof *stack);
                if (!grown) goto oom;
                stack = grown;
                stack_cap *= 2;
            }
            stack[stack_n++] = (ras_mesh_node_item){node->mChildren[c], m};
        }
    }
    free(stack);
    *out = inst;
    *out_count = inst_n;
    return true;
oom:
    free(inst);
    free(stack);
    return false;
}

static size_t ai_triangle_count(const struct aiMesh *m) {
    size_t n = 0;
    for (unsigned f = 0; f < m->mNumFaces; f++)
        if (m->mFaces[f].mNumIndices == 3) n++;
    return n;
}

/* Fills the merged mesh from the instances. Returns false (err set) on an
 * out-of-range index or a non-finite position. `repair` flags the normals
 * to rebuild from faces. */
static bool fill_from_instances(ras_mesh *mesh, bool *repair,
                                         const ras_mesh_instance *inst, size_t inst_count,
                                         const char *path, ras_error *err) {
    size_t vbase = 0, tbase = 0;
    for (size_t k = 0; k < inst_count; k++) {
        const struct aiMesh *am = inst[k].mesh;
        if (ai_triangle_count(am) == 0) continue;
        const struct aiMatrix4x4 *M = &inst[k].transform;
        /* Normals transform by the inverse transpose; the cofactor matrix is
         * det(M) times that, so it needs no division (works for singular M
         * too) and only its sign must be fixed for mirroring transforms. */
        float a = M->a1, b = M->a2, c = M->a3, d = M->b1, e = M->b2, f = M->b3, g = M->c1,
              h = M->c2, i = M->c3;
        float cof[3][3] = {{e * i - f * h, f * g - d * i, d * h - e * g},
                           {c * h - b * i, a * i - c * g, b * g - a * h},
                           {b * f - c * e, c * d - a * f, a * e - b * d}};
        float det = a * cof[0][0] + b * cof[0][1] + c * cof[0][2];
        float nsign = det < 0.0f ? -1.0f : 1.0f;
        /* A mirroring transform turns the winding around; swapping two
         * corners keeps faces counter-clockwise from outside. */
        bool flip = det < 0.0f;

        for (unsigned v = 0; v < am->mNumVertices; v++) {
            struct aiVector3D p = am->mVertices[v];
            vec3s pos = v3(M->a1 * p.x + M->a2 * p.y + M->a3 * p.z + M->a4,
                                    M->b1 * p.x + M->b2 * p.y + M->b3 * p.z + M->b4,
                                    M->c1 * p.x + M->c2 * p.y + M->c3 * p.z + M->c4);
            if (!ras_vec3_finite(pos))
                return ras_error_set(err,
                                     "model '%s': vertex %u of mesh %zu has a position that is not "
                                     "a finite number (%g, %g, %g); expected finite coordinates — "
                                     "repair or re-export the model",
                                     path, v, k, (double)pos.x, (double)pos.y, (double)pos.z);
            size_t dst = vbase + v;
            mesh->positions[dst] = pos;
            repair[dst] = true;
            if (am->mNormals) {
                struct aiVector3D n = am->mNormals[v];
                vec3s nt = v3(cof[0][0] * n.x + cof[0][1] * n.y + cof[0][2] * n.z,
                                       cof[1][0] * n.x + cof[1][1] * n.y + cof[1][2] * n.z,
                                       cof[2][0] * n.x + cof[2][1] * n.y + cof[2][2] * n.z);
                nt = glms_vec3_scale(nt, nsign);
                if (normal_ok(nt)) {
                    mesh->normals[dst] = unit_or(nt, v3(0, 1, 0));
                    repair[dst] = false;
                }
            }
            if (am->mTextureCoords[0]) {
                struct aiVector3D t = am->mTextureCoords[0][v];
                /* A NaN UV would poison every interpolated varying. */
                mesh->uvs[dst] = (vec2s){{isfinite(t.x) ? t.x : 0.0f, isfinite(t.y) ? t.y : 0.0f}};
            }
            vec3s col = v3(1, 1, 1);
            if (am->mColors[0]) {
                struct aiColor4D cc = am->mColors[0][v];
                float ch[3] = {cc.r, cc.g, cc.b};
                for (int q = 0; q < 3; q++)
                    col.raw[q] = isnan(ch[q]) ? 1.0f : ch[q] < 0.0f ? 0.0f : ch[q] > 1.0f ? 1.0f : ch[q];
            }
            mesh->colors[dst] = col;
        }
        for (unsigned fi = 0; fi < am->mNumFaces; fi++) {
            const struct aiFace *face = &am->mFaces[fi];
            if (face->mNumIndices != 3) continue;
            for (int q = 0; q < 3; q++)
                if (face->mIndices[q] >= am->mNumVertices)
                    return ras_error_set(err,
                                         "model '%s': face %u of mesh %zu uses vertex index %u but "
                                         "the mesh has only %u vertices; expected indices below the "
                                         "vertex count — the file is corrupt, re-export it",
                                         path, fi, k, face->mIndices[q], am->mNumVertices);
            unsigned *dst = &mesh->indices[3 * tbase];
            dst[0] = (unsigned)(vbase + face->mIndices[0]);
            dst[1] = (unsigned)(vbase + face->mIndices[flip ? 2 : 1]);
            dst[2] = (unsigned)(vbase + face->mIndices[flip ? 1 : 2]);
            tbase++;
        }
        vbase += am->mNumVertices;
    }
    return true;
}

/* ------------------------------------------------------------------------ */
/* assimp's file access: regular files only                                  */

/* Every file assimp opens (the model, and what it names: an OBJ's .mtl, a
 * glTF's .bin) goes through ras_io_open_input, so a FIFO or a device named by
 * a model fails at once instead of blocking the import forever. */
static size_t io_read(struct aiFile *f, char *buf, size_t size, size_t count) {
    return fread(buf, size, count, (FILE *)f->UserData);
}
static size_t io_write(struct aiFile *f, const char *buf, size_t size, size_t count) {
    (void)f, (void)buf, (void)size, (void)count;
    return 0; /* models are only read */
}
static size_t io_tell(struct aiFile *f) {
    long pos = ftell((FILE *)f->UserData);
    return pos < 0 ? 0 : (size_t)pos;
}
static size_t io_size(struct aiFile *f) {
    struct stat st;
    if (fstat(fileno((FILE *)f->UserData), &st) != 0 || st.st_size < 0) return 0;
    return (size_t)st.st_size;
}
static enum aiReturn io_seek(struct aiFile *f, size_t offset, enum aiOrigin origin) {
    int whence = origin == aiOrigin_CUR ? SEEK_CUR : origin == aiOrigin_END ? SEEK_END : SEEK_SET;
    if (offset > LONG_MAX) return aiReturn_FAILURE;
    return fseek((FILE *)f->UserData, (long)offset, whence) == 0 ? aiReturn_SUCCESS
                                                                : aiReturn_FAILURE;
}
static void io_flush(struct aiFile *f) { (void)f; }

/* The name assimp is given for a file whose content is glTF but whose name
 * does not end in .gltf/.glb (older assimp, 5.0, picks the glTF reader by
 * name alone): the real path plus that suffix, opened as the real path. */
typedef struct io_alias {
    const char *alias, *path;
} io_alias;

static struct aiFile *io_open(struct aiFileIO *io, const char *path, const char *mode) {
    const io_alias *a = (const io_alias *)io->UserData;
    if (a && path && !strcmp(path, a->alias)) path = a->path;
    if (!mode || mode[0] != 'r') return NULL;
    char why[256];
    int fd = ras_io_open_input(path, why, sizeof why);
    if (fd < 0) return NULL;
    FILE *fp = fdopen(fd, "rb");
    struct aiFile *f = fp ? calloc(1, sizeof *f) : NULL;
    if (!f) {
        if (fp) fclose(fp);
        else close(fd);
        return NULL;
    }
    f->ReadProc = io_read;
    f->WriteProc = io_write;
    f->TellProc = io_tell;
    f->FileSizeProc = io_size;
    f->SeekProc = io_seek;
    f->FlushProc = io_flush;
    f->UserData = (aiUserData)fp;
    return f;
}

static void io_close(struct aiFileIO *io, struct aiFile *f) {
    (void)io;
    if (!f) return;
    fclose((FILE *)f->UserData);
    free(f);
}

/* ------------------------------------------------------------------------ */
/* Nesting: checked before assimp, whose importers recurse per level         */

/* The file's extension, lower-cased, in `ext` ("" when none). */
static void file_extension(const char *path, char *ext, size_t size) {
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash + 1 : path, '.');
    size_t n = 0;
    if (dot)
        for (dot++; *dot && n + 1 < size; dot++, n++)
            ext[n] = (char)(*dot >= 'A' && *dot <= 'Z' ? *dot - 'A' + 'a' : *dot);
    ext[n] = '\0';
}

/* glTF 1.0 names its nodes (an object keyed by id, children by id), 2.0
 * numbers them (an array, children by index): both become indices here. */
typedef struct {
    const char *name;
    int index;
} gltf_name;

static int gltf_name_cmp(const void *a, const void *b) {
    return strcmp(((const gltf_name *)a)->name, ((const gltf_name *)b)->name);
}

/* The index of child `kid` (a number, or a glTF 1.0 id), -1 when it names no node. */
static int gltf_child(const cJSON *kid, int n, const gltf_name *names) {
    if (cJSON_IsNumber(kid)) return kid->valuedouble >= 0 && kid->valuedouble < n ? kid->valueint : -1;
    if (!names || !cJSON_IsString(kid)) return -1;
    gltf_name key = {kid->valuestring, 0};
    const gltf_name *hit = bsearch(&key, names, (size_t)n, sizeof *names, gltf_name_cmp);
    return hit ? hit->index : -1;
}

/* The depth of a glTF node tree (1.0 or 2.0), walked without recursion: 0
 * and *bad set when the node graph is not a tree (a cycle, a shared child,
 * a child naming no node) or deeper than RAS_MESH_MAX_NESTING. */
static bool gltf_depth(const cJSON *root, size_t *depth, bool *bad) {
    *depth = 0;
    *bad = false;
    const cJSON *nodes = cJSON_GetObjectItemCaseSensitive(root, "nodes");
    bool named = cJSON_IsObject(nodes);
    int n = cJSON_IsArray(nodes) || named ? cJSON_GetArraySize(nodes) : 0;
    if (n == 0) return true;
    int *parents = calloc((size_t)n, sizeof *parents);
    int *stack = malloc((size_t)n * 2 * sizeof *stack);
    const cJSON **node_at = malloc((size_t)n * sizeof *node_at);
    gltf_name *names = named ? malloc((size_t)n * sizeof *names) : NULL;
    bool ok = parents && stack && node_at && (!named || names);
    const cJSON *node;
    int i = 0;
    if (ok)
        cJSON_ArrayForEach(node, nodes) {
            node_at[i] = node;
            if (named) names[i] = (gltf_name){node->string ? node->string : "", i};
            i++;
        }
    if (ok && named) qsort(names, (size_t)n, sizeof *names, gltf_name_cmp);
    for (i = 0; ok && i < n && !*bad; i++) {
        const cJSON *kids = cJSON_GetObjectItemCaseSensitive(node_at[i], "children"), *kid;
        cJSON_ArrayForEach(kid, kids) {
            int c = gltf_child(kid, n, names);
            if (c < 0 || c == i || ++parents[c] > 1) *bad = true;
        }
    }
    /* Depth from every root (a node without a parent); a cycle has no root
     * and leaves nodes unvisited. */
    int visited = 0;
    for (int r = 0; ok && !*bad && r < n; r++) {
        if (parents[r]) continue;
        int sp = 0;
        stack[sp++] = r;
        stack[sp++] = 1;
        while (sp > 0 && !*bad) {
            int d = stack[--sp], v = stack[--sp];
            visited++;
            if ((size_t)d > *depth) *depth = (size_t)d;
            if ((size_t)d > RAS_MESH_MAX_NESTING) *bad = true;
            const cJSON *kids = cJSON_GetObjectItemCaseSensitive(node_at[v], "children"), *kid;
            cJSON_ArrayForEach(kid, kids) {
                if (sp + 2 > 2 * n) break;
                stack[sp++] = gltf_child(kid, n, names);
                stack[sp++] = d + 1;
            }
        }
    }
    if (ok && !*bad && visited < n) *bad = true; /* a cycle */
    free(parents);
    free(stack);
    free(node_at);
    free(names);
    return ok;
}

/* The folder of `path` ("." when it has none), in `dir`. */
static void folder_of(const char *path, char *dir, size_t size) {
    const char *slash = strrchr(path, '/');
    if (!slash) snprintf(dir, size, ".");
    else if (slash == path) snprintf(dir, size, "/");
    else snprintf(dir, size, "%.*s", (int)(slash - path), path);
}

/* Every external file a glTF names (buffers[].uri, images[].uri; arrays in
 * 2.0, objects in 1.0) must be a regular file inside the model's folder:
 * relative, without "..", no scheme, and still inside once links are
 * followed. Embedded data: URIs are not files. */
static bool check_gltf_uris(const char *path, const cJSON *root, ras_error *err) {
    static const char *const lists[] = {"buffers", "images"};
    char dir[4096], real_dir[PATH_MAX];
    folder_of(path, dir, sizeof dir);
    if (!realpath(dir, real_dir)) return true; /* the model itself was just opened */
    size_t dir_len = strlen(real_dir);
    for (int l = 0; l < 2; l++) {
        const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, lists[l]), *item;
        int k = 0;
        cJSON_ArrayForEach(item, list) {
            const cJSON *uri = cJSON_GetObjectItemCaseSensitive(item, "uri");
            int at = k++;
            if (!cJSON_IsString(uri) || !strncmp(uri->valuestring, "data:", 5)) continue;
            const char *u = uri->valuestring;
            const char *colon = strchr(u, ':'), *first_slash = strchr(u, '/');
            bool outside = u[0] == '/' || u[0] == '\\' || (colon && (!first_slash || colon < first_slash)) ||
                           !strcmp(u, "..") || !strncmp(u, "../", 3) || strstr(u, "/../") ||
                           (strlen(u) >= 3 && !strcmp(u + strlen(u) - 3, "/..")) || strchr(u, '\\') ||
                           strchr(u, '%');
            char file[8192], real_file[PATH_MAX];
            snprintf(file, sizeof file, "%s/%s", dir, u);
            struct stat st;
            bool exists = stat(file, &st) == 0;
            if (!outside && exists)
                outside = !realpath(file, real_file) || strncmp(real_file, real_dir, dir_len) ||
                          (real_file[dir_len] != '/' && dir_len > 1);
            if (outside)
                return ras_error_set(err,
                                     "model '%s': %s[%d].uri '%.200s' points outside the model's "
                                     "folder; expected a file beside the model or in a folder "
                                     "under it (a relative name without '..', '%%' or a scheme)",
                                     path, lists[l], at, u);
            if (exists && !S_ISREG(st.st_mode))
                return ras_error_set(err,
                                     "model '%s': %s[%d].uri '%.200s' is not a regular file; "
                                     "expected the file the model's data is in",
                                     path, lists[l], at, u);
        }
    }
    return true;
}

/* A binary glTF's header and chunk lengths against the file's size: assimp
 * allocates what they say (a 600-byte file whose JSON chunk says 0x7ffffff0
 * took 2 GiB and 39 s). On success *json and *json_len are the JSON chunk. */
static bool check_glb(const char *path, const unsigned char *d, size_t len, const char **json,
                      size_t *json_len, ras_error *err) {
#define LE32(p) ((size_t)(p)[0] | (size_t)(p)[1] << 8 | (size_t)(p)[2] << 16 | (size_t)(p)[3] << 24)
    size_t version = len >= 12 ? LE32(d + 4) : 0, total = len >= 12 ? LE32(d + 8) : 0;
    const char *bad = NULL;
    size_t said = 0, room = 0;
    if (len < 20 || (version != 1 && version != 2)) {
        bad = "its header (expected 'glTF', version 1 or 2, the length, then a chunk)";
    } else if (total > len) {
        bad = "its header's total length", said = total, room = len;
    } else if (version == 1) { /* 20-byte header: contentLength, contentFormat 0 (JSON) */
        size_t content = LE32(d + 12);
        if (content > total - 20) bad = "its JSON content length", said = content, room = total - 20;
        else *json = (const char *)d + 20, *json_len = content;
    } else {
        size_t at = 12;
        bool first = true;
        while (!bad && at < total) {
            if (total - at < 8) {
                bad = "a chunk header (8 bytes)", said = 8, room = total - at;
                break;
            }
            size_t chunk = LE32(d + at);
            if (chunk > total - at - 8) {
                bad = first ? "its JSON chunk's length" : "a binary chunk's length";
                said = chunk, room = total - at - 8;
                break;
            }
            if (first) {
                if (memcmp(d + at + 4, "JSON", 4)) bad = "its first chunk's type (expected JSON)";
                *json = (const char *)d + at + 8, *json_len = chunk;
            }
            first = false;
            at += 8 + ((chunk + 3) & ~(size_t)3);
        }
    }
#undef LE32
    if (!bad) return true;
    if (said)
        return ras_error_set(err,
                             "model '%s': %s says %zu bytes, but the file has only %zu there; "
                             "expected lengths within the file — it is truncated or corrupt",
                             path, bad, said, room);
    return ras_error_set(err, "model '%s': a binary glTF with a damaged header: %s", path, bad);
}

/* cJSON's worst case: a 64-byte node (plus malloc's overhead) per 2-byte "0,". */
#define RAS_MESH_CJSON_BYTES_PER_BYTE 40.0

/* Refuses, before assimp sees it, a model whose content would take assimp
 * past its stack or its memory, whatever the file is called: the format is
 * told by content (a binary glTF by its magic, glTF JSON by its opening
 * brace, any other text by having no NUL byte). Text is scanned for bracket
 * and element depth; glTF (JSON or binary) has its chunk lengths checked,
 * its node tree walked (1.0 and 2.0) and its external files confined to the
 * model's folder. True when the file is fine or not one of those; *suffix
 * is then ".glb" or ".gltf" when the content is glTF, else "". */
static bool check_content(const char *path, const char **suffix, ras_error *err) {
    *suffix = "";
    size_t len = 0;
    ras_error rerr = {{0}};
    char *data = ras_io_read_file(path, "model", RAS_MESH_MAX_SCAN_BYTES, &len, &rerr);
    if (!data) return true; /* too big to scan, or unreadable: assimp says so */
    const unsigned char *u = (const unsigned char *)data;
    const char *text = data;
    size_t text_len = len;
    bool ok = true, glb = len >= 4 && !memcmp(data, "glTF", 4), json = false;
    if (glb) {
        text_len = 0;
        ok = check_glb(path, u, len, &text, &text_len, err);
        json = ok;
        if (ok) *suffix = ".glb";
    } else if (memchr(data, '\0', len)) {
        text_len = 0; /* binary (FBX, 3DS, binary PLY/STL...): the import thread's stack is the guard */
    } else {
        size_t i = len >= 3 && !memcmp(data, "\xEF\xBB\xBF", 3) ? 3 : 0;
        while (i < len && (data[i] == ' ' || data[i] == '\t' || data[i] == '\r' || data[i] == '\n')) i++;
        json = i < len && data[i] == '{';
    }
    size_t at = 0;
    if (ok && text_len &&
        ras_io_text_nesting(text, text_len, RAS_MESH_MAX_NESTING, &at) > RAS_MESH_MAX_NESTING) {
        ok = ras_error_set(err,
                           "model '%s' is nested deeper than %d levels (at byte %zu); expected a "
                           "flatter file — re-export it with the hierarchy flattened",
                           path, RAS_MESH_MAX_NESTING, at + (size_t)(text - data));
    } else if (ok && json && text_len) {
        /* The node tree is walked on cJSON's tree of the whole text, which
         * can take 40 bytes per byte ("0,0,0,..."): refused when that does
         * not fit the budget, since an unchecked tree can overflow any stack. */
        char what[1200];
        snprintf(what, sizeof what, "checking the node tree of model '%s' (%.1f MB of JSON)", path,
                 (double)text_len / 1e6);
        cJSON *root = NULL;
        size_t depth = 0;
        bool bad = false;
        if (!ras_memory_check((double)text_len * RAS_MESH_CJSON_BYTES_PER_BYTE, what,
                              "use a smaller model", err)) {
            ok = false;
        } else if (!(root = cJSON_ParseWithLength(text, text_len))) {
            const char *where = cJSON_GetErrorPtr();
            ok = ras_error_set(err,
                               "model '%s' looks like glTF (JSON) but its JSON does not parse "
                               "(near byte %zu); expected a valid glTF file — check or re-export it",
                               path, where && where >= text && where <= text + text_len
                                         ? (size_t)(where - data) : (size_t)0);
        } else if (!gltf_depth(root, &depth, &bad)) {
            ok = ras_error_set(err, "out of memory checking the node tree of '%s'", path);
        } else if (bad) {
            ok = ras_error_set(err,
                               "model '%s': its node tree is %s; expected a tree at most %d "
                               "levels deep — re-export it with the hierarchy flattened",
                               path,
                               depth > RAS_MESH_MAX_NESTING ? "nested deeper than that"
                                                            : "not a tree (a cycle, a node with "
                                                              "two parents or a child that names "
                                                              "no node)",
                               RAS_MESH_MAX_NESTING);
        } else {
            ok = check_gltf_uris(path, root, err);
            if (ok && !glb && cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(root, "asset")))
                *suffix = ".gltf"; /* every glTF, 1.0 and 2.0, has "asset" */
        }
        cJSON_Delete(root);
    }
    free(data);
#ifdef __GLIBC__
    /* cJSON's tree of a big file was freed in small pieces that assimp's big
     * blocks do not reuse: give them back first (40 MB of glTF numbers peaked
     * at 2.3 GB, the tree plus the import, instead of the larger of the two). */
    if (len > (1u << 20)) malloc_trim(0);
#endif
    return ok;
}

/* ------------------------------------------------------------------------ */
/* Declared counts: checked against the file's size before assimp reserves  */

/* assimp reserves memory for the element counts a PLY or OFF header declares
 * before reading them: a 200-byte PLY declaring 400 M vertices took 4.7 GB
 * and 10 s to be called corrupt. Each element needs some bytes in the file
 * (binary: its fixed-size properties; text: two characters a property), so a
 * count the file cannot hold is refused from the header. */
static bool check_declared_counts(const char *path, double file_bytes, ras_error *err) {
    char why[256];
    int fd = ras_io_open_input(path, why, sizeof why);
    if (fd < 0) return true; /* assimp reports it */
    char head[8192];
    ssize_t n = read(fd, head, sizeof head - 1);
    close(fd);
    if (n <= 0) return true;
    head[n] = '\0';
    /* PLY and OFF by their content, whatever the file is called. */
    const char *lead = head;
    while (*lead == ' ' || *lead == '\t' || *lead == '\r' || *lead == '\n') lead++;
    bool ply = !strncmp(head, "ply", 3) && (head[3] == '\n' || head[3] == '\r'),
         off = !ply && !strncmp(lead, "OFF", 3);
    if (!ply && !off) return true;
    double need = 0, elements = 0;
    if (ply) {
        /* The header is text up to end_header. A NUL in it would end the
         * scan below early, while assimp reads past it and reserves what
         * the rest declares (a 174-byte file asked for 4.8 GB, found by
         * fuzz_mesh): a header with a NUL byte is refused. */
        /* (strstr stops at the first NUL: it finds end_header only before it) */
        if (memchr(head, '\0', (size_t)n) && !strstr(head, "end_header"))
            return ras_error_set(err,
                                 "model '%s': its PLY header has a NUL byte; expected text up to "
                                 "'end_header' — the file is corrupt",
                                 path);
        bool binary = strstr(head, "format binary") != NULL;
        double count = 0, size = 0;
        const char *line = head;
        while (line && *line) {
            char word[32] = "", type[32] = "", type2[32] = "";
            double c = 0;
            if (sscanf(line, "%31s", word) == 1) {
                /* An element line must be `element NAME COUNT`, the name
                 * printable: assimp 5.2's PLY header parser loops forever on
                 * one without a count (found by fuzz_mesh). */
                if (!strcmp(word, "element")) {
                    char name[64] = "";
                    bool printable = true;
                    for (const char *q = line + 7; *q && *q != '\n'; q++)
                        printable &= (*q >= 32 && *q < 127) || *q == '\r' || *q == '\t';
                    if (!printable || sscanf(line, "element %63s %lf", name, &c) != 2 || c < 0)
                        return ras_error_set(err,
                                             "model '%s': a PLY header line 'element ...' is not "
                                             "'element NAME COUNT'; expected a valid PLY file "
                                             "(the header lists each element's name and count)",
                                             path);
                }
                if (!strcmp(word, "element") && sscanf(line, "element %*s %lf", &c) == 1) {
                    need += count * size;
                    elements += count;
                    count = c;
                    size = 0;
                } else if (!strcmp(word, "property") &&
                           sscanf(line, "property %31s %31s", type, type2) >= 1) {
                    const char *t = !strcmp(type, "list") ? type2 : type;
                    int bytes = strstr(t, "char") || strstr(t, "int8")    ? 1
                                : strstr(t, "short") || strstr(t, "int16") ? 2
                                : strstr(t, "double") || strstr(t, "64")   ? 8
                                                                          : 4;
                    size += binary ? bytes : 2;
                } else if (!strcmp(word, "end_header")) {
                    break;
                }
            }
            line = strchr(line, '\n');
            if (line) line++;
        }
        need += count * size;
        elements += count;
    } else {
        const char *p = head;
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') p++;
        if (strncmp(p, "OFF", 3)) return true;
        p = strchr(p, '\n');
        while (p && (p[1] == '#' || p[1] == '\n' || p[1] == '\r')) p = strchr(p + 1, '\n');
        double nv = 0, nf = 0;
        if (!p || sscanf(p + 1, "%lf %lf", &nv, &nf) != 2) return true;
        need = nv * 6 + nf * 8; /* "0 0 0\n", "3 0 1 2\n" */
        elements = nv + nf;
    }
    if (need <= file_bytes) return true;
    return ras_error_set(err,
                         "model '%s' declares %.0f elements (vertices, faces), which need at "
                         "least %.0f bytes, but the file has %.0f; expected counts that match "
                         "the data — the file is truncated or corrupt",
                         path, elements, need, file_bytes);
}

/* Bytes of a PLY scalar type ("uchar", "float32", ...); 0 when unknown. */
static int ply_type_bytes(const char *t) {
    static const struct {
        const char *name;
        int bytes;
    } types[] = {{"char", 1},   {"uchar", 1},  {"int8", 1},    {"uint8", 1},   {"short", 2},
                 {"ushort", 2}, {"int16", 2},  {"uint16", 2},  {"int", 4},     {"uint", 4},
                 {"int32", 4},  {"uint32", 4}, {"float", 4},   {"float32", 4}, {"double", 8},
                 {"float64", 8}};
    for (size_t k = 0; k < sizeof types / sizeof *types; k++)
        if (!strcmp(t, types[k].name)) return types[k].bytes;
    return 0;
}

/* A PLY list count of `bytes` bytes (integer or float type) at p. */
static double ply_read_count(const unsigned char *p, int bytes, bool big, bool is_float) {
    unsigned char b[8];
    for (int k = 0; k < bytes; k++) b[k] = big ? p[bytes - 1 - k] : p[k];
    if (is_float && bytes == 4) {
        float f;
        memcpy(&f, b, 4);
        return f;
    }
    if (is_float && bytes == 8) {
        double f;
        memcpy(&f, b, 8);
        return f;
    }
    uint64_t v = 0;
    for (int k = bytes - 1; k >= 0; k--) v = v << 8 | b[k];
    return (double)v;
}

#define PLY_MAX_PROPS 64
#define PLY_MAX_ELEMENTS 64

/* The list lengths in a PLY's data, each against the bytes left in the file:
 * assimp reserves a face's index count before reading it (a 91-byte ASCII
 * PLY with one face of 10^9 indices reached std::bad_alloc). The data is
 * walked element by element as the header lays it out; a list whose count
 * the rest of the file cannot hold (text: 2 bytes an item, binary: the
 * item's size) is refused, naming the element and the count. */
static bool check_ply_lists(const char *path, ras_error *err) {
    size_t len = 0;
    ras_error rerr = {{0}};
    char *data = ras_io_read_file(path, "model", RAS_MESH_MAX_SCAN_BYTES, &len, &rerr);
    if (!data) return true;
    if (len < 4 || strncmp(data, "ply", 3) || (data[3] != '\n' && data[3] != '\r')) {
        free(data);
        return true;
    }
    struct {
        char name[32];
        double count;
        int props;
        int bytes[PLY_MAX_PROPS], count_bytes[PLY_MAX_PROPS];
        bool list[PLY_MAX_PROPS], count_float[PLY_MAX_PROPS];
    } el[PLY_MAX_ELEMENTS];
    int elements = 0;
    bool ascii = false, big = false, known = true;
    const char *line = data, *body = NULL;
    while (line && line < data + len) {
        char w[32] = "", a[32] = "", b[32] = "", c[32] = "";
        int got = sscanf(line, "%31s %31s %31s %31s", w, a, b, c);
        if (got >= 2 && !strcmp(w, "format")) {
            ascii = !strcmp(a, "ascii");
            big = !strcmp(a, "binary_big_endian");
        } else if (got >= 3 && !strcmp(w, "element")) {
            if (elements == PLY_MAX_ELEMENTS) known = false;
            else {
                snprintf(el[elements].name, sizeof el[elements].name, "%s", a);
                el[elements].count = atof(b);
                el[elements].props = 0;
                elements++;
            }
        } else if (got >= 2 && !strcmp(w, "property") && elements > 0) {
            int e = elements - 1, k = el[e].props;
            if (k == PLY_MAX_PROPS) known = false;
            else if (!strcmp(a, "list") && got >= 4) {
                el[e].list[k] = true;
                el[e].count_bytes[k] = ply_type_bytes(b);
                el[e].count_float[k] = strstr(b, "float") || !strcmp(b, "double");
                el[e].bytes[k] = ply_type_bytes(c);
                known &= el[e].count_bytes[k] && el[e].bytes[k];
                el[e].props++;
            } else {
                el[e].list[k] = false;
                el[e].bytes[k] = ply_type_bytes(a);
                known &= el[e].bytes[k] > 0;
                el[e].props++;
            }
        } else if (got >= 1 && !strcmp(w, "end_header")) {
            body = strchr(line, '\n');
            if (body) body++;
            break;
        }
        line = memchr(line, '\n', (size_t)(data + len - line));
        if (line) line++;
    }
    bool ok = true;
    int bad_e = 0;
    double bad_count = 0;
    /* An unknown type or more than the walk's tables: assimp's own checks. */
    const unsigned char *p = (const unsigned char *)body, *end = (const unsigned char *)data + len;
    for (int e = 0; ok && known && p && e < elements; e++)
        for (double i = 0; ok && i < el[e].count && p < end; i++)
            for (int k = 0; ok && k < el[e].props && p < end; k++) {
                double count = 0;
                if (ascii) { /* a token a scalar; a list: its count, then that many */
                    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) p++;
                    const unsigned char *t = p;
                    while (p < end && !(*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) p++;
                    if (!el[e].list[k]) continue;
                    char num[40];
                    size_t n = (size_t)(p - t) < sizeof num - 1 ? (size_t)(p - t) : sizeof num - 1;
                    memcpy(num, t, n);
                    num[n] = '\0';
                    count = atof(num);
                    if (count > (double)(end - p) / 2 + 1 || count < 0) {
                        ok = false, bad_e = e, bad_count = count;
                        break;
                    }
                    for (double j = 0; j < count && p < end; j++) {
                        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) p++;
                        while (p < end && !(*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) p++;
                    }
                } else if (!el[e].list[k]) {
                    p += (size_t)el[e].bytes[k] <= (size_t)(end - p) ? (size_t)el[e].bytes[k] : (size_t)(end - p);
                } else {
                    if ((size_t)(end - p) < (size_t)el[e].count_bytes[k]) {
                        p = end;
                        break;
                    }
                    count = ply_read_count(p, el[e].count_bytes[k], big, el[e].count_float[k]);
                    p += el[e].count_bytes[k];
                    if (!(count >= 0) || count * el[e].bytes[k] > (double)(end - p)) {
                        ok = false, bad_e = e, bad_count = count;
                        break;
                    }
                    p += (size_t)count * (size_t)el[e].bytes[k];
                }
            }
    if (!ok)
        ras_error_set(err,
                      "model '%s': a list in its PLY element '%s' declares %.0f items, more than "
                      "the rest of the file can hold; expected list lengths that match the data "
                      "— the file is truncated or corrupt",
                      path, el[bad_e].name, bad_count);
    free(data);
    return ok;
}

/* ------------------------------------------------------------------------ */
/* Loading                                                                   */

static ras_mesh *import_mesh(const char *path, const char *suffix, ras_error *err);

/* What the import needs and gives back, owned by whoever holds it last
 * (ras_job.h): the caller, or the import's thread when its time ran out. */
typedef struct import_work {
    char *path;
    ras_error err;
} import_work;

/* The nesting check and the import, on the same thread: the check's cJSON
 * tree and assimp's allocations share one malloc arena, so the peak is the
 * larger of the two, not their sum. */
static void *import_thread(void *arg) {
    import_work *w = arg;
    const char *suffix;
    return check_content(w->path, &suffix, &w->err) ? import_mesh(w->path, suffix, &w->err) : NULL;
}

/* A late import's mesh, which nobody waits for any more. */
static void import_discard(void *mesh, void *arg) {
    import_work *w = arg;
    ras_mesh_destroy(mesh);
    free(w->path);
    free(w);
}

ras_mesh *ras_mesh_load(const char *path, ras_error *err) {
    assert(path);
    /* Checked first because assimp's own message for a missing file does not
     * say why (permissions, no such file, a folder, a FIFO). */
    char why[256];
    int probe = ras_io_open_input(path, why, sizeof why);
    if (probe < 0) {
        ras_error_set(err,
                      "cannot open model file '%s' (%s); expected a readable mesh file such as "
                      "OBJ, PLY or STL — check the path (relative paths start from the current "
                      "directory)",
                      path, why);
        return NULL;
    }
    struct stat st;
    double file_bytes = fstat(probe, &st) == 0 ? (double)st.st_size : 0;
    close(probe);
    char what[1200];
    snprintf(what, sizeof what, "importing model '%s' (%.1f MB)", path, file_bytes / 1e6);
    if (!ras_memory_check(file_bytes * RAS_MESH_IMPORT_BYTES_PER_FILE_BYTE, what,
                          "use a smaller model", err))
        return NULL;
    char ext[16];
    file_extension(path, ext, sizeof ext);
    if (!check_declared_counts(path, file_bytes, err) || !check_ply_lists(path, err))
        return NULL;
    /* assimp's importers, post-processing and node destructors recurse per
     * level of the file's hierarchy: run them on a thread with a large stack
     * (address space only: pages are touched as they are used), sized to fit
     * the memory budget. If no such thread can be made, the import runs here. */
    import_work *work = calloc(1, sizeof *work);
    char *path_copy = work ? strdup(path) : NULL;
    if (!work || !path_copy) {
        free(work);
        ras_error_set(err, "out of memory importing model '%s'", path);
        return NULL;
    }
    work->path = path_copy;
    size_t stack = ras_memory_limit() / 4;
    if (stack > RAS_MESH_IMPORT_STACK) stack = RAS_MESH_IMPORT_STACK;
    if (stack < (16u << 20)) stack = 16u << 20;
    /* At most the import's time limit: assimp has importers that loop
     * forever on some malformed files. */
    double limit = ras_job_seconds("RAS_MESH_IMPORT_SECONDS", RAS_MESH_IMPORT_SECONDS_DEFAULT);
    void *result = NULL;
    if (!ras_job_run(import_thread, work, import_discard, stack, limit, &result))
        return ras_error_set(err,
                             "the importer did not finish '%s' within %g s (assimp is stuck "
                             "on this file, or it is far too big); expected a model that "
                             "imports in time — check the file, or raise "
                             "RAS_MESH_IMPORT_SECONDS",
                             path, limit),
               NULL;
    ras_mesh *mesh = result;
    if (!mesh && err) *err = work->err;
    free(work->path);
    free(work);
#ifdef __GLIBC__
    /* The import's memory was freed in the thread's own malloc arena, where
     * the renderer (on this thread) cannot reuse it: give it back, or the
     * peak is the import plus the render (980 instead of 667 MB measured on
     * a 40 MB OBJ). */
    malloc_trim(0);
#endif
    return mesh;
}

/* ------------------------------------------------------------------------ */
/* assimp, opened on the first import                                        */

/* The library's file name (its SONAME, libassimp.so.5), found by
 * common/CMakeLists.txt from the one this build was compiled against. */
#ifndef RAS_ASSIMP_LIBRARY
#define RAS_ASSIMP_LIBRARY "libassimp.so.5"
#endif

/* The three functions of assimp's C API the loader calls. */
static struct {
    const struct aiScene *(*import_file_ex)(const char *, unsigned int, struct aiFileIO *);
    void (*release_import)(const struct aiScene *);
    const char *(*get_error_string)(void);
    char error[512];
} assimp;
static pthread_once_t assimp_once = PTHREAD_ONCE_INIT;

static void *assimp_symbol(void *lib, const char *name) {
    void *p = dlsym(lib, name);
    if (!p && !assimp.error[0])
        snprintf(assimp.error, sizeof assimp.error, "%s has no %s", RAS_ASSIMP_LIBRARY, name);
    return p;
}

static void open_assimp(void) {
    void *lib = dlopen(RAS_ASSIMP_LIBRARY, RTLD_LAZY | RTLD_LOCAL); /* as at start-up */
    if (!lib) {
        const char *why = dlerror();
        snprintf(assimp.error, sizeof assimp.error, "%s", why ? why : RAS_ASSIMP_LIBRARY);
        return;
    }
    union {
        void *p;
        const struct aiScene *(*import_file_ex)(const char *, unsigned int, struct aiFileIO *);
        void (*release_import)(const struct aiScene *);
        const char *(*get_error_string)(void);
    } f[3] = {{assimp_symbol(lib, "aiImportFileEx")},
              {assimp_symbol(lib, "aiReleaseImport")},
              {assimp_symbol(lib, "aiGetErrorString")}};
    if (!f[0].p || !f[1].p || !f[2].p) return; /* the library stays open: harmless */
    assimp.import_file_ex = f[0].import_file_ex;
    assimp.release_import = f[1].release_import;
    assimp.get_error_string = f[2].get_error_string;
}

/* True when assimp is there; else false and err says why. */
static bool load_assimp(const char *path, ras_error *err) {
    pthread_once(&assimp_once, open_assimp);
    if (assimp.import_file_ex) return true;
    return ras_error_set(err,
                         "cannot read model '%s': the model importer (assimp) could not be "
                         "loaded (%s); install it (scripts/install-deps)",
                         path, assimp.error);
}

static ras_mesh *import_mesh(const char *path, const char *suffix, ras_error *err) {
    if (!load_assimp(path, err)) return NULL;

    /* Triangulate: quads and n-gons become fans the rasterizer can draw.
     * JoinIdenticalVertices: OBJ stores one vertex per face corner; sharing
     * them is what makes smooth generated normals possible.
     * SortByPType: points and lines end up in meshes of their own, dropped below.
     * ValidateDataStructure: assimp rejects inconsistent data (bad indices)
     * with a message instead of handing it over. Normals are made here. */
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                           aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    char ext[16], alias[PATH_MAX + 8];
    file_extension(path, ext, sizeof ext);
    io_alias named = {path, path};
    if (*suffix && strcmp(ext, suffix + 1) && strlen(path) < PATH_MAX) {
        snprintf(alias, sizeof alias, "%s%s", path, suffix);
        named.alias = alias;
    }
    struct aiFileIO io = {io_open, io_close, (aiUserData)&named};
    const struct aiScene *scene = assimp.import_file_ex(named.alias, flags, &io);
    if (!scene) {
        /* assimp's own text names its internals ("OBJ: Invalid face indice",
         * "Unable to open file"): the project's sentence comes first, with
         * the file and what was expected, and assimp's words last, as detail. */
        const char *why = assimp.get_error_string();
        ras_error_set(err,
                      "could not read model '%s': it is not a complete mesh file in a format the "
                      "importer knows (expected OBJ, PLY, STL, glTF, OFF, COLLADA, ...) — check "
                      "the file, or re-export it [the importer said: %.300s]",
                      path, why && *why ? why : "nothing");
        return NULL;
    }
    if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) {
        assimp.release_import(scene);
        ras_error_set(err,
                      "model '%s' is incomplete (an animation or skeleton without geometry); "
                      "expected triangles — export the mesh itself",
                      path);
        return NULL;
    }

    ras_mesh_instance *inst = NULL;
    size_t inst_count = 0;
    if (!collect_instances(scene, &inst, &inst_count)) {
        assimp.release_import(scene);
        ras_error_set(err, "out of memory while reading the node tree of '%s'", path);
        return NULL;
    }

    size_t vcount = 0, tcount = 0;
    bool overflow = false, all_normals = true, any_uv = false;
    for (size_t k = 0; k < inst_count; k++) {
        const struct aiMesh *am = inst[k].mesh;
        size_t t = ai_triangle_count(am);
        if (t == 0) continue;
        if (vcount > SIZE_MAX - am->mNumVertices || tcount > SIZE_MAX - t) overflow = true;
        else {
            vcount += am->mNumVertices;
            tcount += t;
        }
        if (!am->mNormals) all_normals = false;
        if (am->mTextureCoords[0]) any_uv = true;
    }
    ras_mesh *mesh = NULL;
    if (tcount == 0 && !overflow) {
        ras_error_set(err,
                      "model '%s' has no triangles (only points, lines or empty meshes); "
                      "expected at least one face with three or more corners — export the "
                      "model with faces",
                      path);
    } else if (overflow || vcount > (size_t)UINT_MAX ||
               !(mesh = ras_mesh_create(vcount, tcount))) {
        ras_error_set(err,
                      "model '%s' is too big: %zu vertices and %zu triangles do not fit in "
                      "memory or in 32-bit indices; expected at most %u vertices — "
                      "simplify the model",
                      path, vcount, tcount, UINT_MAX);
    } else {
        bool *repair = calloc_checked(vcount, sizeof *repair);
        if (!repair) {
            ras_error_set(err, "out of memory for the %zu vertices of '%s'", vcount, path);
            ras_mesh_destroy(mesh);
            mesh = NULL;
        } else if (!fill_from_instances(mesh, repair, inst, inst_count, path, err)) {
            ras_mesh_destroy(mesh);
            mesh = NULL;
        } else {
            smooth_normals(mesh, repair);
            mesh->has_uv = any_uv; /* meshes without UVs in a mixed file get (0,0) */
            mesh->has_normals_from_file = all_normals;
        }
        free(repair);
    }
    free(inst);
    assimp.release_import(scene);
    return mesh;
}

/* ------------------------------------------------------------------------ */
/* Built-in shapes                                                           */

ras_mesh *ras_mesh_create_triangle(vec3s a, vec3s b, vec3s c, vec3s color) {
    ras_mesh *mesh = ras_mesh_create(3, 1);
    if (!mesh) return NULL;
    mesh->positions[0] = a;
    mesh->positions[1] = b;
    mesh->positions[2] = c;
    /* A degenerate triangle has no plane; +z is what a triangle drawn in the
     * xy plane facing the default camera would have. */
    vec3s n = unit_or(face_normal_raw(a, b, c), v3(0, 0, 1));
    const vec2s uv[3] = {{{0, 0}}, {{1, 0}}, {{0, 1}}};
    for (int i = 0; i < 3; i++) {
        mesh->normals[i] = n;
        mesh->uvs[i] = uv[i];
        mesh->colors[i] = color;
        mesh->indices[i] = (unsigned)i;
    }
    mesh->has_uv = true;
    return mesh;
}

/* Grid sizes come from ints given by the caller; products are formed in
 * size_t and refused when they cannot be indexed. Returns false when a
 * (rows+1) x (cols+1) grid with 2*rows*cols triangles does not fit. */
static bool grid_counts(int rows, int cols, size_t *verts, size_t *tris) {
    size_t r = (size_t)rows, c = (size_t)cols;
    if (r + 1 > SIZE_MAX / (c + 1)) return false;
    *verts = (r + 1) * (c + 1);
    if (r > SIZE_MAX / 2 / (c ? c : 1)) return false;
    *tris = 2 * r * c;
    return *verts <= (size_t)UINT_MAX;
}

ras_mesh *ras_mesh_create_plane(float size, int divisions) {
    if (divisions < 1) divisions = 1;
    size_t nv, nt;
    if (!grid_counts(divisions, divisions, &nv, &nt)) return NULL;
    ras_mesh *mesh = ras_mesh_create(nv, nt);
    if (!mesh) return NULL;
    const size_t d = (size_t)divisions, row = d + 1;
    const float half = 0.5f * size;
    /* Vertex (i, j): i along +x (u), j along -z (v), so the picture's up
     * points away from a camera that looks down -z at the floor. */
    for (size_t j = 0; j <= d; j++)
        for (size_t i = 0; i <= d; i++) {
            float u = (float)i / (float)d, v = (float)j / (float)d;
            size_t k = j * row + i;
            mesh->positions[k] = v3(-half + size * u, 0.0f, half - size * v);
            mesh->normals[k] = v3(0, 1, 0);
            mesh->uvs[k] = (vec2s){{u, v}};
        }
    unsigned *out = mesh->indices;
    for (size_t j = 0; j < d; j++)
        for (size_t i = 0; i < d; i++) {
            unsigned a = (unsigned)(j * row + i), b = a + 1, c = (unsigned)(b + row), e = (unsigned)(a + row);
            /* (+x, then +x-z): the cross product is +y. */
            *out++ = a, *out++ = b, *out++ = c;
            *out++ = a, *out++ = c, *out++ = e;
        }
    fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

ras_mesh *ras_mesh_create_cube(float size) {
    ras_mesh *mesh = ras_mesh_create(24, 12);
    if (!mesh) return NULL;
    /* Each face: outward normal n and in-face axes s (u) and t (v) with
     * s x t = n, so corners listed (-s-t, +s-t, +s+t, -s+t) run counter-
     * clockwise seen from outside and the picture stands upright on the
     * side faces. */
    static const float faces[6][3][3] = {
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
    };
    static const float corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    const float h = 0.5f * size;
    for (int f = 0; f < 6; f++) {
        vec3s n = v3(faces[f][0][0], faces[f][0][1], faces[f][0][2]);
        vec3s s = v3(faces[f][1][0], faces[f][1][1], faces[f][1][2]);
        vec3s t = v3(faces[f][2][0], faces[f][2][1], faces[f][2][2]);
        for (int c = 0; c < 4; c++) {
            int k = 4 * f + c;
            vec3s p = glms_vec3_add(glms_vec3_scale(n, h),
                                    glms_vec3_add(glms_vec3_scale(s, corner[c][0] * h),
                                                  glms_vec3_scale(t, corner[c][1] * h)));
            mesh->positions[k] = p;
            mesh->normals[k] = n;
            mesh->uvs[k] = (vec2s){{0.5f * (corner[c][0] + 1.0f), 0.5f * (corner[c][1] + 1.0f)}};
        }
        unsigned b = (unsigned)(4 * f);
        unsigned *out = &mesh->indices[6 * f];
        out[0] = b, out[1] = b + 1, out[2] = b + 2;
        out[3] = b, out[4] = b + 2, out[5] = b + 3;
    }
    fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

ras_mesh *ras_mesh_create_uv_sphere(float radius, int stacks, int slices) {
    if (stacks < 2) stacks = 2;
    if (slices < 3) slices = 3;
    size_t nv, nt;
    if (!grid_counts(stacks, slices, &nv, &nt)) return NULL;
    /* The first and last stacks are fans around the poles: one of each
     * quad's two triangles has zero area there and is left out. */
    nt -= 2 * (size_t)slices;
    ras_mesh *mesh = ras_mesh_create(nv, nt);
    if (!mesh) return NULL;
    const size_t st = (size_t)stacks, sl = (size_t)slices, row = sl + 1;
    /* theta from the north pole (+y) down, phi from +z towards +x: seen from
     * the front (+z), u grows to the right and v upwards. The seam column is
     * duplicated (u = 0 and u = 1) and so are the poles (one per slice, with
     * u at the middle of the slice) so UVs need no wrap. */
    for (size_t i = 0; i <= st; i++) {
        double theta = RAS_PI * (double)i / (double)st;
        for (size_t j = 0; j <= sl; j++) {
            double phi = 2.0 * RAS_PI * (double)j / (double)sl;
            vec3s n = v3((float)(sin(theta) * sin(phi)), (float)cos(theta),
                                  (float)(sin(theta) * cos(phi)));
            if (i == 0) n = v3(0, 1, 0);   /* exact, not sin(0)*... rounding */
            if (i == st) n = v3(0, -1, 0);
            size_t k = i * row + j;
            float u = (float)j / (float)sl;
            if ((i == 0 || i == st) && j < sl) u = ((float)j + 0.5f) / (float)sl;
            mesh->positions[k] = glms_vec3_scale(n, radius);
            mesh->normals[k] = n;
            mesh->uvs[k] = (vec2s){{u, 1.0f - (float)i / (float)st}};
        }
    }
    unsigned *out = mesh->indices;
    for (size_t i = 0; i < st; i++)
        for (size_t j = 0; j < sl; j++) {
            unsigned a = (unsigned)(i * row + j), d = a + 1, b = (unsigned)(a + row), c = b + 1;
            /* a top-left, b bottom-left, c bottom-right, d top-right seen
             * from outside: (a, b, c) and (a, c, d) run counter-clockwise. */
            if (i != st - 1) *out++ = a, *out++ = b, *out++ = c; /* b, c meet at the south pole */
            if (i != 0) *out++ = a, *out++ = c, *out++ = d;      /* a, d meet at the north pole */
        }
    assert((size_t)(out - mesh->indices) == 3 * nt);
    fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

ras_mesh *ras_mesh_create_torus(float major_radius, float minor_radius, int rings, int sides) {
    if (rings < 3) rings = 3;
    if (sides < 3) sides = 3;
    size_t nv, nt;
    if (!grid_counts(rings, sides, &nv, &nt)) return NULL;
    ras_mesh *mesh = ras_mesh_create(nv, nt);
    if (!mesh) return NULL;
    const size_t nr = (size_t)rings, ns = (size_t)sides, row = ns + 1;
    /* Around the y axis: phi (u) goes round the ring from +z towards +x,
     * theta (v) round the tube starting at the outer equator, going up.
     * d/dphi x d/dtheta points out of the tube, which fixes the winding. */
    for (size_t i = 0; i <= nr; i++) {
        double phi = 2.0 * RAS_PI * (double)i / (double)nr;
        vec3s e = v3((float)sin(phi), 0.0f, (float)cos(phi));
        for (size_t j = 0; j <= ns; j++) {
            double theta = 2.0 * RAS_PI * (double)j / (double)ns;
            vec3s n = glms_vec3_add(glms_vec3_scale(e, (float)cos(theta)),
                                    v3(0.0f, (float)sin(theta), 0.0f));
            size_t k = i * row + j;
            mesh->positions[k] = glms_vec3_add(glms_vec3_scale(e, major_radius),
                                               glms_vec3_scale(n, minor_radius));
            mesh->normals[k] = unit_or(n, e);
            mesh->uvs[k] = (vec2s){{(float)i / (float)nr, (float)j / (float)ns}};
        }
    }
    unsigned *out = mesh->indices;
    for (size_t i = 0; i < nr; i++)
        for (size_t j = 0; j < ns; j++) {
            unsigned a = (unsigned)(i * row + j), b = (unsigned)(a + row), c = b + 1, d = a + 1;
            *out++ = a, *out++ = b, *out++ = c;
            *out++ = a, *out++ = c, *out++ = d;
        }
    fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

/* ------------------------------------------------------------------------ */
/* The Utah teapot                                                           */

/* Newell's teapot (1975, public domain): 32 bicubic Bézier patches over 306
 * control points, z up, as in the classic "teaset" data; indices zero-based.
 * Patches 0-3 rim, 4-11 body, 12-15 handle, 16-19 spout, 20-23 lid knob,
 * 24-27 lid, 28-31 bottom (Frank Crow's addition). Four points (204, 205,
 * 215, 222) are part of the published table but used by no patch. In every
 * patch, d/ds x d/dt (s = row, t = column of the 4x4 grid) points inward. */
static const short teapot_patches[32][16] = {
    {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
    {3, 16, 17, 18, 7, 19, 20, 21, 11, 22, 23, 24, 15, 25, 26, 27},
    {18, 28, 29, 30, 21, 31, 32, 33, 24, 34, 35, 36, 27, 37, 38, 39},
    {30, 40, 41, 0, 33, 42, 43, 4, 36, 44, 45, 8, 39, 46, 47, 12},
    {12, 13, 14, 15, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59},
    {15, 25, 26, 27, 51, 60, 61, 62, 55, 63, 64, 65, 59, 66, 67, 68},
    {27, 37, 38, 39, 62, 69, 70, 71, 65, 72, 73, 74, 68, 75, 76, 77},
    {39, 46, 47, 12, 71, 78, 79, 48, 74, 80, 81, 52, 77, 82, 83, 56},
    {56, 57, 58, 59, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 95},
    {59, 66, 67, 68, 87, 96, 97, 98, 91, 99, 100, 101, 95, 102, 103, 104},
    {68, 75, 76, 77, 98, 105, 106, 107, 101, 108, 109, 110, 104, 111, 112, 113},
    {77, 82, 83, 56, 107, 114, 115, 84, 110, 116, 117, 88, 113, 118, 119, 92},
    {120, 121, 122, 123, 124, 125, 126, 127, 128, 129, 130, 131, 132, 133, 134, 135},
    {123, 136, 137, 120, 127, 138, 139, 124, 131, 140, 141, 128, 135, 142, 143, 132},
    {132, 133, 134, 135, 144, 145, 146, 147, 148, 149, 150, 151, 68, 152, 153, 154},
    {135, 142, 143, 132, 147, 155, 156, 144, 151, 157, 158, 148, 154, 159, 160, 68},
    {161, 162, 163, 164, 165, 166, 167, 168, 169, 170, 171, 172, 173, 174, 175, 176},
    {164, 177, 178, 161, 168, 179, 180, 165, 172, 181, 182, 169, 176, 183, 184, 173},
    {173, 174, 175, 176, 185, 186, 187, 188, 189, 190, 191, 192, 193, 194, 195, 196},
    {176, 183, 184, 173, 188, 197, 198, 185, 192, 199, 200, 189, 196, 201, 202, 193},
    {203, 203, 203, 203, 206, 207, 208, 209, 210, 210, 210, 210, 211, 212, 213, 214},
    {203, 203, 203, 203, 209, 216, 217, 218, 210, 210, 210, 210, 214, 219, 220, 221},
    {203, 203, 203, 203, 218, 223, 224, 225, 210, 210, 210, 210, 221, 226, 227, 228},
    {203, 203, 203, 203, 225, 229, 230, 206, 210, 210, 210, 210, 228, 231, 232, 211},
    {211, 212, 213, 214, 233, 234, 235, 236, 237, 238, 239, 240, 241, 242, 243, 244},
    {214, 219, 220, 221, 236, 245, 246, 247, 240, 248, 249, 250, 244, 251, 252, 253},
    {221, 226, 227, 228, 247, 254, 255, 256, 250, 257, 258, 259, 253, 260, 261, 262},
    {228, 231, 232, 211, 256, 263, 264, 233, 259, 265, 266, 237, 262, 267, 268, 241},
    {269, 269, 269, 269, 278, 279, 280, 281, 274, 275, 276, 277, 270, 271, 272, 273},
    {269, 269, 269, 269, 281, 288, 289, 290, 277, 285, 286, 287, 273, 282, 283, 284},
    {269, 269, 269, 269, 290, 297, 298, 299, 287, 294, 295, 296, 284, 291, 292, 293},
    {269, 269, 269, 269, 299, 304, 305, 278, 296, 302, 303, 274, 293, 300, 301, 270},
};

static const float teapot_points[306][3] = {
    /*   0 */ {1.4, 0.0, 2.4}, {1.4, -0.784, 2.4}, {0.784, -1.4, 2.4}, {0.0, -1.4, 2.4},
    /*   4 */ {1.3375, 0.0, 2.53125}, {1.3375, -0.749, 2.53125}, {0.749, -1.3375, 2.53125}, {0.0, -1.3375, 2.53125},
    /*   8 */ {1.4375, 0.0, 2.53125}, {1.4375, -0.805, 2.53125}, {0.805, -1.4375, 2.53125}, {0.0, -1.4375, 2.53125},
    /*  12 */ {1.5, 0.0, 2.4}, {1.5, -0.84, 2.4}, {0.84, -1.5, 2.4}, {0.0, -1.5, 2.4},
    /*  16 */ {-0.784, -1.4, 2.4}, {-1.4, -0.784, 2.4}, {-1.4, 0.0, 2.4}, {-0.749, -1.3375, 2.53125},
    /*  20 */ {-1.3375, -0.749, 2.53125}, {-1.3375, 0.0, 2.53125}, {-0.805, -1.4375, 2.53125}, {-1.4375, -0.805, 2.53125},
    /*  24 */ {-1.4375, 0.0, 2.53125}, {-0.84, -1.5, 2.4}, {-1.5, -0.84, 2.4}, {-1.5, 0.0, 2.4},
    /*  28 */ {-1.4, 0.784, 2.4}, {-0.784, 1.4, 2.4}, {0.0, 1.4, 2.4}, {-1.3375, 0.749, 2.53125},
    /*  32 */ {-0.749, 1.3375, 2.53125}, {0.0, 1.3375, 2.53125}, {-1.4375, 0.805, 2.53125}, {-0.805, 1.4375, 2.53125},
    /*  36 */ {0.0, 1.4375, 2.53125}, {-1.5, 0.84, 2.4}, {-0.84, 1.5, 2.4}, {0.0, 1.5, 2.4},
    /*  40 */ {0.784, 1.4, 2.4}, {1.4, 0.784, 2.4}, {0.749, 1.3375, 2.53125}, {1.3375, 0.749, 2.53125},
    /*  44 */ {0.805, 1.4375, 2.53125}, {1.4375, 0.805, 2.53125}, {0.84, 1.5, 2.4}, {1.5, 0.84, 2.4},
    /*  48 */ {1.75, 0.0, 1.875}, {1.75, -0.98, 1.875}, {0.98, -1.75, 1.875}, {0.0, -1.75, 1.875},
    /*  52 */ {2.0, 0.0, 1.35}, {2.0, -1.12, 1.35}, {1.12, -2.0, 1.35}, {0.0, -2.0, 1.35},
    /*  56 */ {2.0, 0.0, 0.9}, {2.0, -1.12, 0.9}, {1.12, -2.0, 0.9}, {0.0, -2.0, 0.9},
    /*  60 */ {-0.98, -1.75, 1.875}, {-1.75, -0.98, 1.875}, {-1.75, 0.0, 1.875}, {-1.12, -2.0, 1.35},
    /*  64 */ {-2.0, -1.12, 1.35}, {-2.0, 0.0, 1.35}, {-1.12, -2.0, 0.9}, {-2.0, -1.12, 0.9},
    /*  68 */ {-2.0, 0.0, 0.9}, {-1.75, 0.98, 1.875}, {-0.98, 1.75, 1.875}, {0.0, 1.75, 1.875},
    /*  72 */ {-2.0, 1.12, 1.35}, {-1.12, 2.0, 1.35}, {0.0, 2.0, 1.35}, {-2.0, 1.12, 0.9},
    /*  76 */ {-1.12, 2.0, 0.9}, {0.0, 2.0, 0.9}, {0.98, 1.75, 1.875}, {1.75, 0.98, 1.875},
    /*  80 */ {1.12, 2.0, 1.35}, {2.0, 1.12, 1.35}, {1.12, 2.0, 0.9}, {2.0, 1.12, 0.9},
    /*  84 */ {2.0, 0.0, 0.45}, {2.0, -1.12, 0.45}, {1.12, -2.0, 0.45}, {0.0, -2.0, 0.45},
    /*  88 */ {1.5, 0.0, 0.225}, {1.5, -0.84, 0.225}, {0.84, -1.5, 0.225}, {0.0, -1.5, 0.225},
    /*  92 */ {1.5, 0.0, 0.15}, {1.5, -0.84, 0.15}, {0.84, -1.5, 0.15}, {0.0, -1.5, 0.15},
    /*  96 */ {-1.12, -2.0, 0.45}, {-2.0, -1.12, 0.45}, {-2.0, 0.0, 0.45}, {-0.84, -1.5, 0.225},
    /* 100 */ {-1.5, -0.84, 0.225}, {-1.5, 0.0, 0.225}, {-0.84, -1.5, 0.15}, {-1.5, -0.84, 0.15},
    /* 104 */ {-1.5, 0.0, 0.15}, {-2.0, 1.12, 0.45}, {-1.12, 2.0, 0.45}, {0.0, 2.0, 0.45},
    /* 108 */ {-1.5, 0.84, 0.225}, {-0.84, 1.5, 0.225}, {0.0, 1.5, 0.225}, {-1.5, 0.84, 0.15},
    /* 112 */ {-0.84, 1.5, 0.15}, {0.0, 1.5, 0.15}, {1.12, 2.0, 0.45}, {2.0, 1.12, 0.45},
    /* 116 */ {0.84, 1.5, 0.225}, {1.5, 0.84, 0.225}, {0.84, 1.5, 0.15}, {1.5, 0.84, 0.15},
    /* 120 */ {-1.6, 0.0, 2.025}, {-1.6, -0.3, 2.025}, {-1.5, -0.3, 2.25}, {-1.5, 0.0, 2.25},
    /* 124 */ {-2.3, 0.0, 2.025}, {-2.3, -0.3, 2.025}, {-2.5, -0.3, 2.25}, {-2.5, 0.0, 2.25},
    /* 128 */ {-2.7, 0.0, 2.025}, {-2.7, -0.3, 2.025}, {-3.0, -0.3, 2.25}, {-3.0, 0.0, 2.25},
    /* 132 */ {-2.7, 0.0, 1.8}, {-2.7, -0.3, 1.8}, {-3.0, -0.3, 1.8}, {-3.0, 0.0, 1.8},
    /* 136 */ {-1.5, 0.3, 2.25}, {-1.6, 0.3, 2.025}, {-2.5, 0.3, 2.25}, {-2.3, 0.3, 2.025},
    /* 140 */ {-3.0, 0.3, 2.25}, {-2.7, 0.3, 2.025}, {-3.0, 0.3, 1.8}, {-2.7, 0.3, 1.8},
    /* 144 */ {-2.7, 0.0, 1.575}, {-2.7, -0.3, 1.575}, {-3.0, -0.3, 1.35}, {-3.0, 0.0, 1.35},
    /* 148 */ {-2.5, 0.0, 1.125}, {-2.5, -0.3, 1.125}, {-2.65, -0.3, 0.9375}, {-2.65, 0.0, 0.9375},
    /* 152 */ {-2.0, -0.3, 0.9}, {-1.9, -0.3, 0.6}, {-1.9, 0.0, 0.6}, {-3.0, 0.3, 1.35},
    /* 156 */ {-2.7, 0.3, 1.575}, {-2.65, 0.3, 0.9375}, {-2.5, 0.3, 1.125}, {-1.9, 0.3, 0.6},
    /* 160 */ {-2.0, 0.3, 0.9}, {1.7, 0.0, 1.425}, {1.7, -0.66, 1.425}, {1.7, -0.66, 0.6},
    /* 164 */ {1.7, 0.0, 0.6}, {2.6, 0.0, 1.425}, {2.6, -0.66, 1.425}, {3.1, -0.66, 0.825},
    /* 168 */ {3.1, 0.0, 0.825}, {2.3, 0.0, 2.1}, {2.3, -0.25, 2.1}, {2.4, -0.25, 2.025},
    /* 172 */ {2.4, 0.0, 2.025}, {2.7, 0.0, 2.4}, {2.7, -0.25, 2.4}, {3.3, -0.25, 2.4},
    /* 176 */ {3.3, 0.0, 2.4}, {1.7, 0.66, 0.6}, {1.7, 0.66, 1.425}, {3.1, 0.66, 0.825},
    /* 180 */ {2.6, 0.66, 1.425}, {2.4, 0.25, 2.025}, {2.3, 0.25, 2.1}, {3.3, 0.25, 2.4},
    /* 184 */ {2.7, 0.25, 2.4}, {2.8, 0.0, 2.475}, {2.8, -0.25, 2.475}, {3.525, -0.25, 2.49375},
    /* 188 */ {3.525, 0.0, 2.49375}, {2.9, 0.0, 2.475}, {2.9, -0.15, 2.475}, {3.45, -0.15, 2.5125},
    /* 192 */ {3.45, 0.0, 2.5125}, {2.8, 0.0, 2.4}, {2.8, -0.15, 2.4}, {3.2, -0.15, 2.4},
    /* 196 */ {3.2, 0.0, 2.4}, {3.525, 0.25, 2.49375}, {2.8, 0.25, 2.475}, {3.45, 0.15, 2.5125},
    /* 200 */ {2.9, 0.15, 2.475}, {3.2, 0.15, 2.4}, {2.8, 0.15, 2.4}, {0.0, 0.0, 3.15},
    /* 204 */ {0.0, -0.002, 3.15}, {0.002, 0.0, 3.15}, {0.8, 0.0, 3.15}, {0.8, -0.45, 3.15},
    /* 208 */ {0.45, -0.8, 3.15}, {0.0, -0.8, 3.15}, {0.0, 0.0, 2.85}, {0.2, 0.0, 2.7},
    /* 212 */ {0.2, -0.112, 2.7}, {0.112, -0.2, 2.7}, {0.0, -0.2, 2.7}, {-0.002, 0.0, 3.15},
    /* 216 */ {-0.45, -0.8, 3.15}, {-0.8, -0.45, 3.15}, {-0.8, 0.0, 3.15}, {-0.112, -0.2, 2.7},
    /* 220 */ {-0.2, -0.112, 2.7}, {-0.2, 0.0, 2.7}, {0.0, 0.002, 3.15}, {-0.8, 0.45, 3.15},
    /* 224 */ {-0.45, 0.8, 3.15}, {0.0, 0.8, 3.15}, {-0.2, 0.112, 2.7}, {-0.112, 0.2, 2.7},
    /* 228 */ {0.0, 0.2, 2.7}, {0.45, 0.8, 3.15}, {0.8, 0.45, 3.15}, {0.112, 0.2, 2.7},
    /* 232 */ {0.2, 0.112, 2.7}, {0.4, 0.0, 2.55}, {0.4, -0.224, 2.55}, {0.224, -0.4, 2.55},
    /* 236 */ {0.0, -0.4, 2.55}, {1.3, 0.0, 2.55}, {1.3, -0.728, 2.55}, {0.728, -1.3, 2.55},
    /* 240 */ {0.0, -1.3, 2.55}, {1.3, 0.0, 2.4}, {1.3, -0.728, 2.4}, {0.728, -1.3, 2.4},
    /* 244 */ {0.0, -1.3, 2.4}, {-0.224, -0.4, 2.55}, {-0.4, -0.224, 2.55}, {-0.4, 0.0, 2.55},
    /* 248 */ {-0.728, -1.3, 2.55}, {-1.3, -0.728, 2.55}, {-1.3, 0.0, 2.55}, {-0.728, -1.3, 2.4},
    /* 252 */ {-1.3, -0.728, 2.4}, {-1.3, 0.0, 2.4}, {-0.4, 0.224, 2.55}, {-0.224, 0.4, 2.55},
    /* 256 */ {0.0, 0.4, 2.55}, {-1.3, 0.728, 2.55}, {-0.728, 1.3, 2.55}, {0.0, 1.3, 2.55},
    /* 260 */ {-1.3, 0.728, 2.4}, {-0.728, 1.3, 2.4}, {0.0, 1.3, 2.4}, {0.224, 0.4, 2.55},
    /* 264 */ {0.4, 0.224, 2.55}, {0.728, 1.3, 2.55}, {1.3, 0.728, 2.55}, {0.728, 1.3, 2.4},
    /* 268 */ {1.3, 0.728, 2.4}, {0.0, 0.0, 0.0}, {1.5, 0.0, 0.15}, {1.5, 0.84, 0.15},
    /* 272 */ {0.84, 1.5, 0.15}, {0.0, 1.5, 0.15}, {1.5, 0.0, 0.075}, {1.5, 0.84, 0.075},
    /* 276 */ {0.84, 1.5, 0.075}, {0.0, 1.5, 0.075}, {1.425, 0.0, 0.0}, {1.425, 0.798, 0.0},
    /* 280 */ {0.798, 1.425, 0.0}, {0.0, 1.425, 0.0}, {-0.84, 1.5, 0.15}, {-1.5, 0.84, 0.15},
    /* 284 */ {-1.5, 0.0, 0.15}, {-0.84, 1.5, 0.075}, {-1.5, 0.84, 0.075}, {-1.5, 0.0, 0.075},
    /* 288 */ {-0.798, 1.425, 0.0}, {-1.425, 0.798, 0.0}, {-1.425, 0.0, 0.0}, {-1.5, -0.84, 0.15},
    /* 292 */ {-0.84, -1.5, 0.15}, {0.0, -1.5, 0.15}, {-1.5, -0.84, 0.075}, {-0.84, -1.5, 0.075},
    /* 296 */ {0.0, -1.5, 0.075}, {-1.425, -0.798, 0.0}, {-0.798, -1.425, 0.0}, {0.0, -1.425, 0.0},
    /* 300 */ {0.84, -1.5, 0.15}, {1.5, -0.84, 0.15}, {0.84, -1.5, 0.075}, {1.5, -0.84, 0.075},
    /* 304 */ {0.798, -1.425, 0.0}, {1.425, -0.798, 0.0},
};

/* Cubic Bernstein basis and its derivative at t. */
static void bernstein(float t, float b[4], float db[4]) {
    float s = 1.0f - t;
    b[0] = s * s * s;
    b[1] = 3.0f * t * s * s;
    b[2] = 3.0f * t * t * s;
    b[3] = t * t * t;
    db[0] = -3.0f * s * s;
    db[1] = 3.0f * s * s - 6.0f * t * s;
    db[2] = 6.0f * t * s - 3.0f * t * t;
    db[3] = 3.0f * t * t;
}

/* Point and outward (unnormalised) normal of patch `p` at (s, t), in the
 * y-up frame: (x, y, z)_data -> (x, z, -y), a rotation, so orientation holds.
 * size->x is |dP/ds|^2 + |dP/dt|^2, the scale a degenerate normal is judged by. */
static void teapot_eval(int p, float s, float t, vec3s *pos, vec3s *normal, vec3s *size) {
    float bs[4], dbs[4], bt[4], dbt[4];
    bernstein(s, bs, dbs);
    bernstein(t, bt, dbt);
    vec3s P = glms_vec3_zero(), Ds = glms_vec3_zero(), Dt = glms_vec3_zero();
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            const float *c = teapot_points[teapot_patches[p][4 * i + j]];
            vec3s cp = v3(c[0], c[2], -c[1]);
            P = glms_vec3_add(P, glms_vec3_scale(cp, bs[i] * bt[j]));
            Ds = glms_vec3_add(Ds, glms_vec3_scale(cp, dbs[i] * bt[j]));
            Dt = glms_vec3_add(Dt, glms_vec3_scale(cp, bs[i] * dbt[j]));
        }
    *pos = P;
    *normal = glms_vec3_cross(Dt, Ds);
    *size = v3(glms_vec3_dot(Ds, Ds) + glms_vec3_dot(Dt, Dt), 0.0f, 0.0f);
}

ras_mesh *ras_mesh_create_teapot(int divisions) {
    /* One segment per patch is not a teapot: the spout-tip patches' corners
     * are collinear, so their two triangles would have zero area. */
    if (divisions < 2) divisions = 2;
    size_t nv1, nt1;
    if (!grid_counts(divisions, divisions, &nv1, &nt1)) return NULL;
    if (nv1 > SIZE_MAX / 32 || nt1 > SIZE_MAX / 32 || 32 * nv1 > (size_t)UINT_MAX) return NULL;
    const size_t n = (size_t)divisions, row = n + 1;

    /* Which patch edges collapse to a point (the lid knob's top, the bottom's
     * centre): every control point of that edge is the same one. */
    bool collapsed[32][4]; /* s = 0, s = 1, t = 0, t = 1 */
    size_t degenerate = 0;
    for (int p = 0; p < 32; p++) {
        const short *c = teapot_patches[p];
        collapsed[p][0] = c[0] == c[1] && c[1] == c[2] && c[2] == c[3];
        collapsed[p][1] = c[12] == c[13] && c[13] == c[14] && c[14] == c[15];
        collapsed[p][2] = c[0] == c[4] && c[4] == c[8] && c[8] == c[12];
        collapsed[p][3] = c[3] == c[7] && c[7] == c[11] && c[11] == c[15];
        for (int e = 0; e < 4; e++) degenerate += collapsed[p][e] ? n : 0;
    }
    ras_mesh *mesh = ras_mesh_create(32 * nv1, 32 * nt1 - degenerate);
    if (!mesh) return NULL;

    bool repair_any = false;
    bool *repair = calloc_checked(mesh->vertex_count, sizeof *repair);
    if (!repair) {
        ras_mesh_destroy(mesh);
        return NULL;
    }
    unsigned *out = mesh->indices;
    for (int p = 0; p < 32; p++) {
        size_t base = (size_t)p * nv1;
        for (size_t i = 0; i <= n; i++)
            for (size_t j = 0; j <= n; j++) {
                float s = (float)i / (float)n, t = (float)j / (float)n;
                vec3s pos, nrm, ds_dt;
                teapot_eval(p, s, t, &pos, &nrm, &ds_dt);
                /* On a collapsed edge one derivative vanishes, but only up to
                 * rounding (the basis derivatives sum to ~1e-7, not 0), so
                 * the cross product is tiny noise rather than zero: detect
                 * the edge from the data, and tiny normals relative to the
                 * derivatives elsewhere. */
                bool on_pole = (i == 0 && collapsed[p][0]) || (i == n && collapsed[p][1]) ||
                               (j == 0 && collapsed[p][2]) || (j == n && collapsed[p][3]);
                if (on_pole || !normal_ok(nrm) ||
                    glms_vec3_dot(nrm, nrm) < 1e-10f * ds_dt.x * ds_dt.x) {
                    /* A step into the patch gives the limit direction (the
                     * surface is smooth there, only its parametrisation is not). */
                    const float step = 1e-3f;
                    vec3s dummy, dummy_d;
                    teapot_eval(p, s + (s < 0.5f ? step : -step),
                                         t + (t < 0.5f ? step : -step), &dummy, &nrm, &dummy_d);
                }
                size_t k = base + i * row + j;
                mesh->positions[k] = pos;
                if (normal_ok(nrm)) mesh->normals[k] = unit_or(nrm, v3(0, 1, 0));
                else repair[k] = repair_any = true;
                /* v = 1 at s = 0: the body patches run from the rim down. */
                mesh->uvs[k] = (vec2s){{t, 1.0f - s}};
            }
        for (size_t i = 0; i < n; i++)
            for (size_t j = 0; j < n; j++) {
                unsigned a = (unsigned)(base + i * row + j), b = a + 1, d = (unsigned)(a + row), c = d + 1;
                /* a=(i,j) b=(i,j+1) c=(i+1,j+1) d=(i+1,j): (b-a) x (c-a) ~ Dt x Ds,
                 * outward. A triangle with an edge on a collapsed patch edge
                 * has zero area and is skipped. */
                bool ab_collapsed = (i == 0 && collapsed[p][0]);       /* a, b on s = 0 */
                bool cd_collapsed = (i + 1 == n && collapsed[p][1]);   /* c, d on s = 1 */
                bool ad_collapsed = (j == 0 && collapsed[p][2]);       /* a, d on t = 0 */
                bool bc_collapsed = (j + 1 == n && collapsed[p][3]);   /* b, c on t = 1 */
                if (!ab_collapsed && !bc_collapsed) *out++ = a, *out++ = b, *out++ = c;
                if (!cd_collapsed && !ad_collapsed) *out++ = a, *out++ = c, *out++ = d;
            }
    }
    assert((size_t)(out - mesh->indices) == 3 * mesh->triangle_count);
    if (repair_any) smooth_normals(mesh, repair);
    free(repair);

    /* Centre the bounding box on the origin and scale the longest side
     * (spout to handle) to 2: the teapot then fits the box [-1, 1]^3 like
     * the unit sphere, so a scene can swap one for the other. */
    mat4s fit = ras_mesh_fit_matrix(mesh, 2.0f);
    for (size_t k = 0; k < mesh->vertex_count; k++)
        mesh->positions[k] = ras_mat4_mulv3(fit, mesh->positions[k], 1.0f);
    fill_color(mesh, v3(1, 1, 1));
    mesh->has_uv = true;
    return mesh;
}

/* ------------------------------------------------------------------------ */
/* Bounds and fitting                                                        */

void ras_mesh_bounds(const ras_mesh *mesh, vec3s *lo, vec3s *hi) {
    assert(mesh && lo && hi);
    if (mesh->vertex_count == 0) {
        *lo = *hi = glms_vec3_zero();
        return;
    }
    vec3s a = mesh->positions[0], b = mesh->positions[0];
    for (size_t i = 1; i < mesh->vertex_count; i++) {
        a = glms_vec3_minv(a, mesh->positions[i]);
        b = glms_vec3_maxv(b, mesh->positions[i]);
    }
    *lo = a;
    *hi = b;
}

mat4s ras_mesh_fit_matrix(const ras_mesh *mesh, float size) {
    vec3s lo, hi;
    ras_mesh_bounds(mesh, &lo, &hi);
    vec3s centre = glms_vec3_scale(glms_vec3_add(lo, hi), 0.5f);
    vec3s extent = glms_vec3_sub(hi, lo);
    float largest = glms_vec3_max(extent);
    /* A single point (or a mesh with a non-finite bound) has no size to
     * scale: only move it. */
    float k = (largest > 0.0f && isfinite(largest)) ? size / largest : 1.0f;
    return ras_mat4_rows(k, 0, 0, -k * centre.x,
                         0, k, 0, -k * centre.y,
                         0, 0, k, -k * centre.z,
                         0, 0, 0, 1);
}
