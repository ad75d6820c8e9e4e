/* ras_mesh_load.c — model files through assimp.
 *
 * Loading merges every triangle mesh of the file into one indexed list, with
 * each node's transform applied (an instanced mesh appears once per node that
 * uses it). Points and lines are dropped: the rasterizer draws triangles
 * only. The file is checked first (ras_mesh_check.c), then imported on a
 * thread of its own with a time limit (ras_job.h).
 *
 * assimp is not linked: it is opened with dlopen when the first model file is
 * read (load_assimp), so programs that draw built-in shapes never load it
 * (common/README.md, "What is loaded when"). Every file assimp opens goes through this file's
 * aiFileIO, which reads regular files only.
 */
#include "ras_mesh.h"
#include "ras_mesh_words.h" /* the import failure in the project's words */

#include <assimp/cfileio.h>     /* aiFileIO, aiFile */
#include <assimp/cimport.h>     /* aiImportFileEx, aiReleaseImport, aiGetErrorString */
#include <assimp/postprocess.h> /* aiProcess_* */
#include <assimp/scene.h>       /* aiScene, aiNode, aiMesh */

#include <assert.h> /* assert */
#include <errno.h>  /* errno, EINTR */
#include <dlfcn.h>  /* dlopen, dlsym, dlerror: assimp, loaded on first use */
#include <limits.h> /* UINT_MAX, PATH_MAX */
#include <math.h>   /* isfinite */
#include <stdint.h> /* SIZE_MAX */
#include <stdio.h>  /* fdopen, fread, fseek, fclose, snprintf */
#include <stdlib.h> /* calloc, malloc, free */
#include <string.h> /* memcpy, strcmp, strrchr, strdup, strsignal */
#include <signal.h>   /* SIGKILL */
#include <sys/prctl.h> /* prctl, PR_SET_PDEATHSIG: the import's child ends with its parent */
#include <sys/resource.h> /* setrlimit, RLIMIT_AS: the import's child held to the budget */
#include <sys/stat.h> /* fstat */
#include <time.h>   /* clock_gettime: a scene's total import time */
#include <unistd.h> /* close, write, getppid, sysconf */

#include "ras_io.h"     /* ras_io_open_input */
#include "ras_job.h"    /* the import in a child process, or on its own thread, with a time limit */
#include "ras_memory.h" /* ras_memory_check, ras_memory_limit */
#include "ras_mesh_parts.h"

#include <pthread.h> /* pthread_once: assimp opened once */
#ifdef __GLIBC__
#include <malloc.h> /* malloc_trim */
#endif

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

/* `array` of *cap elements of `size` bytes, reallocated to twice as many
 * (*cap doubled); NULL, and the array and *cap as they were, on overflow or
 * out of memory. */
static void *grown_twice(void *array, size_t *cap, size_t size) {
    if (*cap > SIZE_MAX / 2 / size) return NULL;
    void *grown = realloc(array, 2 * *cap * size);
    if (grown) *cap *= 2;
    return grown;
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
                ras_mesh_instance *grown = grown_twice(inst, &inst_cap, sizeof *inst);
                if (!grown) goto oom;
                inst = grown;
            }
            inst[inst_n++] = (ras_mesh_instance){scene->mMeshes[mi], m};
        }
        for (unsigned c = 0; c < node->mNumChildren; c++) {
            if (stack_n == stack_cap) {
                ras_mesh_node_item *grown = grown_twice(stack, &stack_cap, sizeof *stack);
                if (!grown) goto oom;
                stack = grown;
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
                if (ras_mesh_normal_ok(nt)) {
                    mesh->normals[dst] = ras_mesh_unit_or(nt, v3(0, 1, 0));
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
    char real_dir[PATH_MAX]; /* the model's folder, links resolved ("" when unknown) */
} io_alias;

/* Whether a file assimp asks for besides the model lies in the model's
 * folder once links are resolved: ras_mesh_check.c refuses an OBJ's mtllib
 * or a glTF's URI outside it with a sentence; this holds every other
 * format's side files (and whatever name assimp builds) to the same. */
static bool io_inside_model_folder(const io_alias *a, const char *path) {
    char real[PATH_MAX];
    if (!a->real_dir[0] || !realpath(path, real)) return false;
    size_t n = strlen(a->real_dir);
    return !strncmp(real, a->real_dir, n) && (real[n] == '/' || (n == 1 && real[0] == '/'));
}

static struct aiFile *io_open(struct aiFileIO *io, const char *path, const char *mode) {
    const io_alias *a = (const io_alias *)io->UserData;
    if (!path || !mode || mode[0] != 'r') return NULL;
    if (!strcmp(path, a->alias)) path = a->path;
    else if (strcmp(path, a->path) && !io_inside_model_folder(a, path)) return NULL;
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
/* Loading                                                                   */

static ras_mesh *import_mesh(const char *path, const char *suffix, ras_error *err);
static bool load_assimp(const char *path, ras_error *err);

/* What the import needs and gives back, owned by whoever holds it last
 * (ras_job.h): the caller, or the import's thread when its time ran out. */
typedef struct import_work {
    char *path;
    ras_error err;
    pid_t parent; /* the process that forks the import's child */
} import_work;

/* The nesting check and the import, on the same thread: the check's cJSON
 * tree and assimp's allocations share one malloc arena, so the peak is the
 * larger of the two, not their sum. */
static void *import_thread(void *arg) {
    import_work *w = arg;
    const char *suffix;
    return ras_mesh_check_content(w->path, &suffix, &w->err) ? import_mesh(w->path, suffix, &w->err) : NULL;
}

/* A late import's mesh, which nobody waits for any more. */
static void import_discard(void *mesh, void *arg) {
    import_work *w = arg;
    ras_mesh_destroy(mesh);
    free(w->path);
    free(w);
}

/* assimp's importers, post-processing and node destructors recurse per
 * level of the file's hierarchy: they run on a thread with a large stack
 * (address space only: pages are touched as they are used), sized to fit
 * the memory budget. If no such thread can be made, the import runs here. */
static size_t import_stack(void) {
    size_t stack = ras_memory_limit() / 4;
    if (stack > RAS_MESH_IMPORT_STACK) stack = RAS_MESH_IMPORT_STACK;
    if (stack < (16u << 20)) stack = 16u << 20;
    return stack;
}

/* The import in this process, on a thread waited for at most `limit`
 * seconds. When the time ran out, the thread owns `work` from then on and
 * work->path is cleared here so the caller does not free it. */
static ras_mesh *import_in_process(import_work *work, double limit, ras_error *err) {
    void *result = NULL;
    if (!ras_job_run(import_thread, work, import_discard, import_stack(), limit, &result)) {
        ras_error_set(err,
                      "the importer did not finish '%s' within %g s (assimp is stuck on this "
                      "file, or it is far too big); expected a model that imports in time — "
                      "check the file, or raise RAS_MESH_IMPORT_SECONDS",
                      work->path, limit);
        work->path = NULL;
        return NULL;
    }
    if (!result && err) *err = work->err;
    return result;
}

/* The mesh as the child writes it to the parent: a header, then the five
 * arrays as they lie in memory (the same process image, so the same layout). */
typedef struct import_header {
    char tag; /* 'M': a mesh follows; 'E': the error's text follows */
    bool has_uv, has_normals_from_file;
    uint64_t vertex_count, triangle_count;
} import_header;

static bool write_all(int fd, const void *data, size_t n) {
    const unsigned char *p = data;
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

#if defined(__SANITIZE_ADDRESS__)
#define RAS_MESH_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RAS_MESH_UNDER_ASAN 1
#endif
#endif

/* Address space the child may add to what it has at the fork besides the
 * budget and the import thread's stack: small mappings (the pipe's stdio,
 * the locale). */
#define IMPORT_SLACK (16.0 * 1024 * 1024)

/* The child's address space held to what it has now (the parent's image)
 * plus the import thread's stack and the memory budget: assimp reserves
 * what a file asks (a .mtl of 100,000 materials took 3.5 GB) and its
 * std::bad_alloc then fails the import instead of the machine. Not under
 * AddressSanitizer, whose shadow memory is terabytes of address space. */
static void import_hold_to_budget(void) {
#ifndef RAS_MESH_UNDER_ASAN
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long pages = 0;
    bool known = f && fscanf(f, "%lu", &pages) == 1;
    if (f) fclose(f);
    if (!known) return; /* no /proc: the up-front estimate alone holds it */
    double now = (double)pages * (double)sysconf(_SC_PAGESIZE);
#ifdef __GLIBC__
    /* One malloc arena: a thread's own arena reserves 64 MiB of address
     * space (128 MiB while it is aligned), which would count against the
     * budget without holding anything. */
    mallopt(M_ARENA_MAX, 1);
#endif
    double cap = now + (double)import_stack() + IMPORT_SLACK + (double)ras_memory_limit();
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && (rl.rlim_max == RLIM_INFINITY || cap < (double)rl.rlim_max) &&
        (rl.rlim_cur == RLIM_INFINITY || cap < (double)rl.rlim_cur)) {
        rl.rlim_cur = (rlim_t)cap;
        setrlimit(RLIMIT_AS, &rl);
    }
#endif
}

/* assimp's words for running out of memory, in the project's: the budget
 * (RLIMIT_AS in this child) was reached. */
static void import_say_out_of_memory(import_work *work) {
    if (!strstr(work->err.msg, "bad_alloc") && !strstr(work->err.msg, "out of memory")) return;
    ras_error_set(&work->err,
                  "model '%s' needs more memory than the budget (%zu MiB, %s) while it is "
                  "imported; expected a model that fits — use a smaller model, or raise the "
                  "limit with --memory-limit MB (or RAS_MEMORY_LIMIT_MB)",
                  work->path, ras_memory_limit() >> 20, ras_memory_limit_source());
}

/* In the child: held to the budget, ended with its parent whatever ends the
 * parent (kill PID from an IDE or a grader: SIGKILL has no handler to
 * clean up from), then the import (on its large-stack thread; the parent
 * keeps the time), then its mesh or its error down the pipe. */
static int import_child(void *arg, int fd) {
    import_work *work = arg;
    /* getppid after the prctl: a parent that died before it would leave
     * this child re-parented, and the death signal never sent. */
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != work->parent) return 3;
    import_hold_to_budget();
    void *result = NULL;
    ras_job_run(import_thread, work, import_discard, import_stack(), 1e9, &result);
    ras_mesh *m = result;
    if (!m) import_say_out_of_memory(work);
    import_header h = {m ? 'M' : 'E', m && m->has_uv, m && m->has_normals_from_file,
                       m ? m->vertex_count : 0, m ? m->triangle_count : 0};
    bool ok = write_all(fd, &h, sizeof h);
    if (m) {
        size_t v = m->vertex_count;
        ok = ok && write_all(fd, m->positions, v * sizeof *m->positions) &&
             write_all(fd, m->normals, v * sizeof *m->normals) &&
             write_all(fd, m->uvs, v * sizeof *m->uvs) &&
             write_all(fd, m->colors, v * sizeof *m->colors) &&
             write_all(fd, m->indices, 3 * m->triangle_count * sizeof *m->indices);
    } else {
        ok = ok && write_all(fd, work->err.msg, strlen(work->err.msg));
    }
    return ok ? 0 : 1;
}

/* The child's bytes back into a mesh; NULL with err set when they are not
 * what import_child writes. */
static ras_mesh *import_decode(const unsigned char *bytes, size_t len, const char *path,
                               ras_error *err) {
    import_header h;
    if (len < sizeof h) goto broken;
    memcpy(&h, bytes, sizeof h);
    const unsigned char *p = bytes + sizeof h;
    size_t rest = len - sizeof h;
    if (h.tag == 'E') {
        ras_error_set(err, "%.*s", (int)(rest < sizeof err->msg - 1 ? rest : sizeof err->msg - 1),
                      (const char *)p);
        return NULL;
    }
    size_t per_vertex = sizeof(vec3s) * 3 + sizeof(vec2s);
    if (h.tag != 'M' || h.vertex_count > UINT_MAX || h.triangle_count > SIZE_MAX / 12 ||
        rest != h.vertex_count * per_vertex + h.triangle_count * 3 * sizeof(unsigned))
        goto broken;
    ras_mesh *m = ras_mesh_create(h.vertex_count, h.triangle_count);
    if (!m) {
        ras_error_set(err, "out of memory importing model '%s'", path);
        return NULL;
    }
    size_t v = m->vertex_count;
    memcpy(m->positions, p, v * sizeof *m->positions), p += v * sizeof *m->positions;
    memcpy(m->normals, p, v * sizeof *m->normals), p += v * sizeof *m->normals;
    memcpy(m->uvs, p, v * sizeof *m->uvs), p += v * sizeof *m->uvs;
    memcpy(m->colors, p, v * sizeof *m->colors), p += v * sizeof *m->colors;
    memcpy(m->indices, p, 3 * m->triangle_count * sizeof *m->indices);
    m->has_uv = h.has_uv;
    m->has_normals_from_file = h.has_normals_from_file;
    return m;
broken:
    ras_error_set(err, "could not read model '%s': the importer's process sent back %zu bytes "
                       "that are not a mesh (an internal error: please report it)",
                  path, len);
    return NULL;
}

/* The import in a child process: assimp is not built with the sanitizers
 * and some of its importers crash on malformed files (stack-protector
 * aborts, segfaults) instead of failing; a crash or a stuck importer then
 * ends only the child. *isolated is false when no child could be made. */
static ras_mesh *import_isolated(import_work *work, double limit, bool *isolated,
                                 ras_error *err) {
    unsigned char *bytes;
    size_t len;
    int code, sig;
    ras_job_child_status st =
        ras_job_run_child(import_child, work, limit, ras_memory_limit(), &bytes, &len, &code, &sig);
    *isolated = st != RAS_JOB_CHILD_NO_PROCESS;
    const char *path = work->path;
    switch (st) {
    case RAS_JOB_CHILD_NO_PROCESS: return NULL;
    case RAS_JOB_CHILD_LATE:
        return ras_error_set(err,
                             "the importer did not finish '%s' within %g s (assimp is stuck "
                             "on this file, or it is far too big); expected a model that "
                             "imports in time — check the file, or raise "
                             "RAS_MESH_IMPORT_SECONDS",
                             path, limit),
               NULL;
    case RAS_JOB_CHILD_TOO_BIG:
        return ras_error_set(err,
                             "model '%s' is too big for the memory budget (%zu MB) once "
                             "imported; use a smaller model or raise the budget (RAS_MEMORY_LIMIT_MB)",
                             path, ras_memory_limit() >> 20),
               NULL;
    case RAS_JOB_CHILD_CRASHED:
        return ras_error_set(err,
                             "could not read model '%s': the model importer (assimp) crashed "
                             "on it (signal %d, %s; its process is held to the memory budget "
                             "of %zu MiB, which it may have reached); expected a well-formed "
                             "mesh file that fits — check the file, re-export it, or raise "
                             "--memory-limit",
                             path, sig, strsignal(sig), ras_memory_limit() >> 20),
               NULL;
    case RAS_JOB_CHILD_DONE: break;
    }
    ras_mesh *mesh = code == 0 ? import_decode(bytes, len, path, err) : NULL;
    if (code != 0)
        ras_error_set(err, "could not read model '%s': the importer's process failed (exit %d)",
                      path, code);
    free(bytes);
    return mesh;
}

/* ------------------------------------------------------------------------ */
/* A scene's imports: each file once, all of them within a total time      */

/* A model already imported in this batch (a scene's objects), by the file's
 * identity: a scene that names one model in 4,096 objects imported it 4,096
 * times, each in its own child (minutes). The copy kept here is counted in
 * the memory budget until the batch ends. */
typedef struct import_cached {
    dev_t dev;
    ino_t ino;
    off_t size;
    struct timespec mtime, ctime;
    ras_mesh *mesh;
} import_cached;

static struct {
    pthread_mutex_t lock;
    bool active; /* between ras_mesh_imports_begin and _end */
    import_cached *items;
    size_t count, cap;
    double seconds_used; /* wall-clock seconds the batch's imports took so far */
} g_imports = {PTHREAD_MUTEX_INITIALIZER, false, NULL, 0, 0, 0};

static double mesh_bytes(const ras_mesh *m) {
    return (double)m->vertex_count * (3 * sizeof(vec3s) + sizeof(vec2s)) +
           (double)m->triangle_count * 3 * sizeof(unsigned);
}

/* A new mesh equal to `m` (NULL when out of memory). */
static ras_mesh *mesh_copy(const ras_mesh *m) {
    ras_mesh *c = ras_mesh_create(m->vertex_count, m->triangle_count);
    if (!c) return NULL;
    size_t v = m->vertex_count;
    memcpy(c->positions, m->positions, v * sizeof *m->positions);
    memcpy(c->normals, m->normals, v * sizeof *m->normals);
    memcpy(c->uvs, m->uvs, v * sizeof *m->uvs);
    memcpy(c->colors, m->colors, v * sizeof *m->colors);
    memcpy(c->indices, m->indices, 3 * m->triangle_count * sizeof *m->indices);
    c->has_uv = m->has_uv;
    c->has_normals_from_file = m->has_normals_from_file;
    return c;
}

static bool same_time(struct timespec a, struct timespec b) {
    return a.tv_sec == b.tv_sec && a.tv_nsec == b.tv_nsec;
}

static bool same_file(const import_cached *c, const struct stat *st) {
    return c->dev == st->st_dev && c->ino == st->st_ino && c->size == st->st_size &&
           same_time(c->mtime, st->st_mtim) && same_time(c->ctime, st->st_ctim);
}

/* Drops every kept import and its share of the budget, and restarts the
 * batch's clock. Called with the lock held. */
static void imports_reset(bool active) {
    for (size_t i = 0; i < g_imports.count; i++) {
        ras_memory_release(mesh_bytes(g_imports.items[i].mesh));
        ras_mesh_destroy(g_imports.items[i].mesh);
    }
    free(g_imports.items);
    g_imports.items = NULL;
    g_imports.count = g_imports.cap = 0;
    g_imports.seconds_used = 0;
    g_imports.active = active;
}

void ras_mesh_imports_begin(void) {
    pthread_mutex_lock(&g_imports.lock);
    imports_reset(true);
    pthread_mutex_unlock(&g_imports.lock);
}

void ras_mesh_imports_end(void) {
    pthread_mutex_lock(&g_imports.lock);
    imports_reset(false);
    pthread_mutex_unlock(&g_imports.lock);
}

/* A copy of the batch's earlier import of this file, or NULL. */
static ras_mesh *cached_import(const struct stat *st) {
    ras_mesh *copy = NULL;
    pthread_mutex_lock(&g_imports.lock);
    for (size_t i = 0; g_imports.active && i < g_imports.count && !copy; i++)
        if (same_file(&g_imports.items[i], st)) copy = mesh_copy(g_imports.items[i].mesh);
    pthread_mutex_unlock(&g_imports.lock);
    return copy;
}

/* Keeps a copy of `mesh` for the run's later uses of the same file, when the
 * budget has room for it (else the file is imported again if named again). */
static void remember_import(const struct stat *st, const ras_mesh *mesh) {
    ras_error ignored = {{0}};
    if (!ras_memory_check(mesh_bytes(mesh), "keeping an imported model", NULL, &ignored)) return;
    pthread_mutex_lock(&g_imports.lock);
    if (g_imports.active && g_imports.count == g_imports.cap) {
        size_t cap = g_imports.cap ? 2 * g_imports.cap : 8;
        import_cached *grown = realloc(g_imports.items, cap * sizeof *grown);
        if (grown) g_imports.items = grown, g_imports.cap = cap;
    }
    ras_mesh *copy = g_imports.active && g_imports.count < g_imports.cap ? mesh_copy(mesh) : NULL;
    if (copy) {
        g_imports.items[g_imports.count++] =
            (import_cached){st->st_dev, st->st_ino, st->st_size, st->st_mtim, st->st_ctim, copy};
        ras_memory_commit(mesh_bytes(copy));
    }
    pthread_mutex_unlock(&g_imports.lock);
}

static double seconds_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* The checks before assimp, with the memory estimate of the model and its
 * side files; true when the file may be imported. */
static bool import_allowed(const char *path, double file_bytes, ras_error *err) {
    double side_bytes = 0;
    if (!ras_mesh_check_declared_counts(path, file_bytes, err) || !ras_mesh_check_ply_lists(path, err) ||
        !ras_mesh_check_ply_header(path, err) || !ras_mesh_check_obj(path, &side_bytes, err))
        return false;
    char what[1200];
    if (side_bytes > 0)
        snprintf(what, sizeof what, "importing model '%s' (%.1f MB) with its materials, objects and groups",
                 path, file_bytes / 1e6);
    else
        snprintf(what, sizeof what, "importing model '%s' (%.1f MB)", path, file_bytes / 1e6);
    return ras_memory_check(file_bytes * RAS_MESH_IMPORT_BYTES_PER_FILE_BYTE + side_bytes, what,
                            "use a smaller model", err);
}

/* The import proper, in a child process when one can be made, with at most
 * `limit` seconds. */
static ras_mesh *import_with_limit(const char *path, double limit, ras_error *err) {
    if (!load_assimp(path, err)) return NULL; /* opened here: the child must not dlopen */
    import_work *work = calloc(1, sizeof *work);
    char *path_copy = work ? strdup(path) : NULL;
    if (!work || !path_copy) {
        free(work);
        ras_error_set(err, "out of memory importing model '%s'", path);
        return NULL;
    }
    work->path = path_copy;
    work->parent = getpid();
    bool isolated = false;
    ras_mesh *mesh = import_isolated(work, limit, &isolated, err);
    if (!isolated) { /* no child process could be made: the import runs in this one */
        mesh = import_in_process(work, limit, err);
        if (!work->path) return mesh; /* still running: its thread owns the work now */
    }
    free(work->path);
    free(work);
#ifdef __GLIBC__
    /* The import's memory was freed in the thread's own malloc arena, where
     * the renderer (on this thread) cannot reuse it: give it back, or the
     * peak is the import plus the render (980 instead of 667 MB measured on
     * a 40 MB OBJ). */
    if (!isolated) malloc_trim(0);
#endif
    return mesh;
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
    bool known = fstat(probe, &st) == 0;
    close(probe);
    double file_bytes = known ? (double)st.st_size : 0;
    ras_mesh *mesh = known ? cached_import(&st) : NULL;
    if (mesh) return mesh;
    if (!import_allowed(path, file_bytes, err)) return NULL;
    /* Each import at most its own limit (assimp has importers that loop
     * forever on some malformed files), and all of a run's together at most
     * the total: a scene naming many slow models ends, naming the one it
     * was on. */
    double limit = ras_job_seconds("RAS_MESH_IMPORT_SECONDS", RAS_MESH_IMPORT_SECONDS_DEFAULT);
    double total = ras_job_seconds("RAS_MESH_IMPORT_TOTAL_SECONDS", RAS_MESH_IMPORT_TOTAL_SECONDS_DEFAULT);
    pthread_mutex_lock(&g_imports.lock);
    bool batch = g_imports.active;
    double used = g_imports.seconds_used;
    pthread_mutex_unlock(&g_imports.lock);
    double left = batch ? total - used : limit;
    if (left < 0.001)
        return ras_error_set(err,
                             "the scene's model imports took %.1f s together, the limit on all "
                             "of them (%g s), before '%s' could start; expected fewer or "
                             "smaller models — or raise RAS_MESH_IMPORT_TOTAL_SECONDS",
                             used, total, path),
               NULL;
    bool total_binds = left < limit; /* the batch's remainder, not the file's own limit */
    if (total_binds) limit = left;
    double start = seconds_now();
    ras_error inner = {{0}};
    mesh = import_with_limit(path, limit, &inner);
    double took = seconds_now() - start;
    pthread_mutex_lock(&g_imports.lock);
    g_imports.seconds_used += took;
    pthread_mutex_unlock(&g_imports.lock);
    if (!mesh && total_binds && took >= limit && strstr(inner.msg, "did not finish"))
        ras_error_set(err,
                      "importing '%s' ran past the limit on all of the scene's model imports "
                      "(%g s; the earlier imports took %.1f s of it); expected fewer or smaller "
                      "models — or raise RAS_MESH_IMPORT_TOTAL_SECONDS",
                      path, total, used);
    else if (!mesh && err)
        *err = inner;
    if (mesh && known && batch) remember_import(&st, mesh);
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
} g_assimp;
static pthread_once_t g_assimp_once = PTHREAD_ONCE_INIT;

static void *assimp_symbol(void *lib, const char *name) {
    void *p = dlsym(lib, name);
    if (!p && !g_assimp.error[0])
        snprintf(g_assimp.error, sizeof g_assimp.error, "%s has no %s", RAS_ASSIMP_LIBRARY, name);
    return p;
}

static void open_assimp(void) {
    void *lib = dlopen(RAS_ASSIMP_LIBRARY, RTLD_LAZY | RTLD_LOCAL); /* as at start-up */
    if (!lib) {
        const char *why = dlerror();
        snprintf(g_assimp.error, sizeof g_assimp.error, "%s", why ? why : RAS_ASSIMP_LIBRARY);
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
    g_assimp.import_file_ex = f[0].import_file_ex;
    g_assimp.release_import = f[1].release_import;
    g_assimp.get_error_string = f[2].get_error_string;
}

/* True when assimp is there; else false and err says why. */
static bool load_assimp(const char *path, ras_error *err) {
    pthread_once(&g_assimp_once, open_assimp);
    if (g_assimp.import_file_ex) return true;
    return ras_error_set(err,
                         "cannot read model '%s': the model importer (assimp) could not be "
                         "loaded (%s); install it (scripts/install-deps)",
                         path, g_assimp.error);
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
    ras_mesh_file_extension(path, ext, sizeof ext);
    io_alias named = {path, path, ""};
    char dir[4096];
    ras_io_folder_of(path, dir, sizeof dir);
    if (!realpath(dir, named.real_dir)) named.real_dir[0] = '\0';
    if (*suffix && strcmp(ext, suffix + 1) && strlen(path) < PATH_MAX) {
        snprintf(alias, sizeof alias, "%s%s", path, suffix);
        named.alias = alias;
    }
    struct aiFileIO io = {io_open, io_close, (aiUserData)&named};
    const struct aiScene *scene = g_assimp.import_file_ex(named.alias, flags, &io);
    if (!scene) {
        /* assimp's own text names its internals ("OBJ: Invalid face indice",
         * "Unable to open file"): the project's sentence comes first, with
         * the file and what was expected, and assimp's words last, as detail. */
        ras_mesh_import_failure(err, path, g_assimp.get_error_string());
        return NULL;
    }
    if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) {
        g_assimp.release_import(scene);
        ras_error_set(err,
                      "model '%s' is incomplete (an animation or skeleton without geometry); "
                      "expected triangles — export the mesh itself",
                      path);
        return NULL;
    }

    ras_mesh_instance *inst = NULL;
    size_t inst_count = 0;
    if (!collect_instances(scene, &inst, &inst_count)) {
        g_assimp.release_import(scene);
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
        bool *repair = ras_mesh_calloc(vcount, sizeof *repair);
        if (!repair) {
            ras_error_set(err, "out of memory for the %zu vertices of '%s'", vcount, path);
            ras_mesh_destroy(mesh);
            mesh = NULL;
        } else if (!fill_from_instances(mesh, repair, inst, inst_count, path, err)) {
            ras_mesh_destroy(mesh);
            mesh = NULL;
        } else {
            ras_mesh_smooth_normals(mesh, repair);
            mesh->has_uv = any_uv; /* meshes without UVs in a mixed file get (0,0) */
            mesh->has_normals_from_file = all_normals;
        }
        free(repair);
    }
    free(inst);
    g_assimp.release_import(scene);
    return mesh;
}

