/* ras_mesh_check.c — what a model file is checked for before assimp sees it.
 *
 * assimp's importers recurse per level of a file's hierarchy, reserve what a
 * header declares and follow a glTF's URIs: each check here reads the file's
 * own bytes first and refuses, with a sentence, what would take assimp past
 * its stack, its memory or the model's folder (docs/robustness.md).
 */
#include "ras_mesh.h"

#include <limits.h> /* PATH_MAX */
#include <math.h>   /* isfinite */
#include <stdint.h> /* SIZE_MAX */
#include <stdio.h>  /* snprintf */
#include <stdlib.h> /* malloc, free, qsort */
#include <string.h> /* memcpy, memcmp, memchr, strcmp, strrchr, strstr, strchr */
#include <sys/stat.h> /* stat: a glTF's external files */
#include <unistd.h> /* read, close */

#include "ras_io.h"     /* ras_io_read_file, ras_io_text_nesting, ras_io_folder_of */
#include "ras_memory.h" /* ras_memory_check */
#include "ras_mesh_parts.h"

#include <cjson/cJSON.h> /* cJSON_ParseWithLength: glTF node trees */
#ifdef __GLIBC__
#include <malloc.h> /* malloc_trim */
#endif

/* ------------------------------------------------------------------------ */
/* Nesting: checked before assimp, whose importers recurse per level         */

/* The file's extension, lower-cased, in `ext` ("" when none). */
void ras_mesh_file_extension(const char *path, char *ext, size_t size) {
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

/* Whether `name`, a file a model names (a glTF URI, an OBJ's mtllib), stays
 * inside the model's folder `dir` (real_dir once links are resolved): a
 * relative name without "..", '\\', '%' or a scheme, still inside once links
 * are followed. *exists and *st say whether it is there and what it is. */
static bool side_file_inside(const char *dir, const char *real_dir, const char *name,
                             bool *exists, struct stat *st) {
    size_t dir_len = strlen(real_dir), n = strlen(name);
    const char *colon = strchr(name, ':'), *first_slash = strchr(name, '/');
    bool outside = name[0] == '/' || name[0] == '\\' || (colon && (!first_slash || colon < first_slash)) ||
                   !strcmp(name, "..") || !strncmp(name, "../", 3) || strstr(name, "/../") ||
                   (n >= 3 && !strcmp(name + n - 3, "/..")) || strchr(name, '\\') ||
                   strchr(name, '%');
    char file[8192], real_file[PATH_MAX];
    snprintf(file, sizeof file, "%s/%s", dir, name);
    *exists = stat(file, st) == 0;
    if (!outside && *exists)
        outside = !realpath(file, real_file) || strncmp(real_file, real_dir, dir_len) ||
                  (real_file[dir_len] != '/' && dir_len > 1);
    return !outside;
}

/* Every external file a glTF names (buffers[].uri, images[].uri; arrays in
 * 2.0, objects in 1.0) must be a regular file inside the model's folder
 * (side_file_inside). Embedded data: URIs are not files. */
static bool check_gltf_uris(const char *path, const cJSON *root, ras_error *err) {
    static const char *const lists[] = {"buffers", "images"};
    char dir[4096], real_dir[PATH_MAX];
    ras_io_folder_of(path, dir, sizeof dir);
    if (!realpath(dir, real_dir)) return true; /* the model itself was just opened */
    for (int l = 0; l < 2; l++) {
        const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, lists[l]), *item;
        int k = 0;
        cJSON_ArrayForEach(item, list) {
            const cJSON *uri = cJSON_GetObjectItemCaseSensitive(item, "uri");
            int at = k++;
            if (!cJSON_IsString(uri) || !strncmp(uri->valuestring, "data:", 5)) continue;
            const char *u = uri->valuestring;
            struct stat st;
            bool exists;
            if (!side_file_inside(dir, real_dir, u, &exists, &st))
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
bool ras_mesh_check_content(const char *path, const char **suffix, ras_error *err) {
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
bool ras_mesh_check_declared_counts(const char *path, double file_bytes, ras_error *err) {
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
bool ras_mesh_check_ply_lists(const char *path, ras_error *err) {
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
/* A PLY's header: every line known, end_header present                      */

/* The longest PLY header read: real ones are a few hundred bytes. */
#define PLY_MAX_HEADER_BYTES (64u << 10)

/* Whether a PLY header line (NUL-terminated, without its newline) is one of
 * the kinds the format has, with a known type for a property. */
static bool ply_header_line_known(const char *line) {
    char w[32] = "", a[32] = "", b[32] = "", c[32] = "", d[32] = "";
    int got = sscanf(line, "%31s %31s %31s %31s %31s", w, a, b, c, d);
    if (got < 1) return true; /* a blank line */
    if (!strcmp(w, "comment") || !strcmp(w, "obj_info")) return true;
    if (!strcmp(w, "format"))
        return got == 3 && (!strcmp(a, "ascii") || !strcmp(a, "binary_little_endian") ||
                            !strcmp(a, "binary_big_endian"));
    if (!strcmp(w, "element")) return got == 3;
    if (!strcmp(w, "property") && !strcmp(a, "list"))
        return got == 5 && ply_type_bytes(b) && ply_type_bytes(c);
    if (!strcmp(w, "property")) return got == 3 && ply_type_bytes(a);
    return !strcmp(w, "end_header") && got == 1;
}

/* assimp's PLY reader waits out the whole import limit (60 s) on a header
 * cut short or with end_header misspelt: the header is read here first, and
 * refused at once, naming the line, unless it is `ply`, a format line, then
 * only the lines the format has, up to `end_header`. */
bool ras_mesh_check_ply_header(const char *path, ras_error *err) {
    char why[256];
    int fd = ras_io_open_input(path, why, sizeof why);
    if (fd < 0) return true; /* assimp reports it */
    char *head = malloc(PLY_MAX_HEADER_BYTES + 1);
    size_t n = 0;
    while (head && n < PLY_MAX_HEADER_BYTES) {
        ssize_t got = read(fd, head + n, PLY_MAX_HEADER_BYTES - n);
        if (got <= 0) break;
        n += (size_t)got;
    }
    close(fd);
    if (!head) return ras_error_set(err, "out of memory reading the header of model '%s'", path);
    bool ply = n >= 4 && !memcmp(head, "ply", 3) && (head[3] == '\n' || head[3] == '\r');
    bool ok = true;
    int line_no = 0;
    for (size_t at = 0; ply && ok;) {
        char *nl = memchr(head + at, '\n', n - at);
        line_no++;
        if (!nl) {
            ok = ras_error_set(err,
                               "model '%s': its PLY header ends at line %d without 'end_header' "
                               "(within the first %u KiB); expected a complete header — the "
                               "file is cut short or not a PLY file",
                               path, line_no, PLY_MAX_HEADER_BYTES >> 10);
            break;
        }
        *nl = '\0';
        if (nl > head + at && nl[-1] == '\r') nl[-1] = '\0';
        const char *line = head + at;
        at = (size_t)(nl - head) + 1;
        if (line_no == 1) continue; /* "ply" */
        bool is_text = !memchr(line, '\0', (size_t)(nl - line)) || strlen(line) == 0;
        for (const char *q = line; is_text && *q; q++) is_text = (*q >= 32 && *q < 127) || *q == '\t';
        if (!is_text || !ply_header_line_known(line))
            ok = ras_error_set(err,
                               "model '%s': line %d of its PLY header, '%.60s', is not one of "
                               "'format', 'element NAME COUNT', 'property TYPE NAME', 'property "
                               "list TYPE TYPE NAME', 'comment', 'obj_info' or 'end_header'; "
                               "expected a valid PLY header — the file is corrupt",
                               path, line_no, is_text ? line : "(binary bytes)");
        else if (line_no == 2 && strncmp(line, "format", 6))
            ok = ras_error_set(err,
                               "model '%s': line 2 of its PLY header is '%.60s'; expected "
                               "'format ascii 1.0' (or binary_little_endian/binary_big_endian) "
                               "— the file is corrupt",
                               path, line);
        else if (!strncmp(line, "end_header", 10))
            break;
    }
    free(head);
    return ok;
}

/* ------------------------------------------------------------------------ */
/* OBJ: its parts, its indices and its material files                         */

/* The OBJ keywords whose count assimp's reader pays for quadratically. */
typedef struct obj_counts {
    double vertices, uvs, normals, objects, material_switches, groups;
} obj_counts;

/* Whether the text is an OBJ: by its name, or (whatever the name, as assimp
 * tells it) by its first keyword. */
static bool looks_like_obj(const char *path, const char *data, size_t len) {
    char ext[16];
    ras_mesh_file_extension(path, ext, sizeof ext);
    if (!strcmp(ext, "obj")) return true;
    if (memchr(data, '\0', len)) return false;
    static const char *const first[] = {"v", "vt", "vn", "o", "g", "f", "s", "mtllib", "usemtl"};
    for (size_t at = 0; at < len;) {
        const char *line = data + at, *nl = memchr(line, '\n', len - at);
        size_t n = nl ? (size_t)(nl - line) : len - at;
        at += n + 1;
        while (n && (*line == ' ' || *line == '\t' || *line == '\r')) line++, n--;
        if (!n || *line == '#') continue;
        for (size_t k = 0; k < sizeof first / sizeof *first; k++) {
            size_t w = strlen(first[k]);
            if (n > w && !strncmp(line, first[k], w) && (line[w] == ' ' || line[w] == '\t'))
                return true;
        }
        return false;
    }
    return false;
}

/* An OBJ index (1-based, or negative: counted back from the last one so
 * far) against the `have` elements defined before it: true when it names one. */
static bool obj_index_ok(long index, double have) {
    return index > 0 ? (double)index <= have : index < 0 && -(double)index <= have;
}

/* The corners of one `f` line: each v[/vt][/vn], the vt and vn checked
 * against what the file has defined so far (assimp drops a bad one
 * silently, and the face loses its texture coordinate or normal). The v
 * index is assimp's to check. */
static bool obj_face_ok(const char *path, const char *line, size_t n, int line_no,
                        const obj_counts *c, ras_error *err) {
    static const char *const kinds[] = {"vertex", "texture coordinate (vt)", "normal (vn)"};
    const char *p = line + 1, *end = line + n;
    while (p < end) {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) p++;
        for (int slot = 0; p < end && !(*p == ' ' || *p == '\t' || *p == '\r'); slot++) {
            char num[24];
            size_t k = 0;
            while (p < end && *p != '/' && !(*p == ' ' || *p == '\t' || *p == '\r')) {
                if (k + 1 < sizeof num) num[k++] = *p;
                p++;
            }
            num[k] = '\0';
            if (p < end && *p == '/') p++;
            if (slot == 0 || slot > 2 || k == 0) continue;
            double have = slot == 1 ? c->uvs : c->normals;
            long index = strtol(num, NULL, 10);
            if (!obj_index_ok(index, have) && have == 0)
                return ras_error_set(err,
                                     "model '%s': line %d: a face uses %s index %s, but the "
                                     "file defines none before it; expected a face without "
                                     "one, or the %s lines first — the file is corrupt, "
                                     "re-export it",
                                     path, line_no, kinds[slot], num, slot == 1 ? "vt" : "vn");
            if (!obj_index_ok(index, have))
                return ras_error_set(err,
                                     "model '%s': line %d: a face uses %s index %s, but the "
                                     "file defines only %.0f before it; expected an index from "
                                     "1 to %.0f (or -1 to -%.0f) — the file is corrupt, "
                                     "re-export it",
                                     path, line_no, kinds[slot], num, have, have, have);
        }
    }
    return true;
}

/* Bytes of assimp's import per material of an OBJ's .mtl (measured: 100,000
 * materials, 3.5 GB): each holds a dozen 1 KB texture names. */
#define RAS_MESH_IMPORT_BYTES_PER_MATERIAL 36000.0

/* Bytes of assimp's import per `g` group line of an OBJ (measured: 100,000
 * groups of one face each, 1.7 MB, took 342 MB; 200,000 groups with a face of
 * their own 488 MB above the same faces without them, 2.5 KB each; 100,000
 * without faces 1.4 KB each). Unlike objects, groups cost time linearly
 * (200,000: 1.1 s), so they are counted, not limited. */
#define RAS_MESH_IMPORT_BYTES_PER_GROUP 3400.0

/* One `mtllib` line: the file it names (the rest of the line, as assimp
 * reads it) inside the model's folder, and its cost (its size and its
 * materials) added to *side_bytes. */
static bool obj_material_file(const char *path, const char *dir, const char *real_dir,
                              const char *names, int line_no, double *side_bytes,
                              ras_error *err) {
    while (*names == ' ' || *names == '\t') names++;
    char name_buf[1024];
    size_t k = strlen(names);
    while (k && (names[k - 1] == ' ' || names[k - 1] == '\t' || names[k - 1] == '\r')) k--;
    if (k == 0 || k >= sizeof name_buf) return true; /* assimp ignores it, or cannot open it */
    memcpy(name_buf, names, k);
    name_buf[k] = '\0';
    const char *name = name_buf;
    struct stat st;
    bool exists;
    if (!side_file_inside(dir, real_dir, name, &exists, &st))
        return ras_error_set(err,
                             "model '%s': line %d: mtllib '%.200s' points outside the "
                             "model's folder; expected a material file beside the model or "
                             "in a folder under it (a relative name without '..', '%%' or a "
                             "scheme)",
                             path, line_no, name);
    /* Missing, or not a regular file (which the importer's file access
     * refuses to open): assimp warns and uses its default material. */
    if (!exists || !S_ISREG(st.st_mode)) return true;
    char file[8192];
    snprintf(file, sizeof file, "%s/%s", dir, name);
    size_t len = 0;
    ras_error rerr = {{0}};
    char *mtl = ras_io_read_file(file, "material file", RAS_MESH_MAX_SCAN_BYTES, &len, &rerr);
    double materials = 0;
    for (size_t at = 0; mtl && at < len;) {
        const char *l = mtl + at, *nl = memchr(l, '\n', len - at);
        at = nl ? (size_t)(nl - mtl) + 1 : len;
        while (l < mtl + len && (*l == ' ' || *l == '\t')) l++;
        if ((size_t)(mtl + len - l) > 7 && !strncmp(l, "newmtl", 6) && (l[6] == ' ' || l[6] == '\t'))
            materials++;
    }
    free(mtl);
    *side_bytes += (double)st.st_size * RAS_MESH_IMPORT_BYTES_PER_FILE_BYTE +
                   materials * RAS_MESH_IMPORT_BYTES_PER_MATERIAL;
    return true;
}

/* The counts of one OBJ line's keyword, and the checks of an `f` or `mtllib` line. */
static bool obj_line(const char *path, const char *line, size_t n, int line_no,
                     const char *dir, const char *real_dir, obj_counts *c, double *side_bytes,
                     ras_error *err) {
    while (n && (*line == ' ' || *line == '\t')) line++, n--;
    size_t w = 0;
    while (w < n && !(line[w] == ' ' || line[w] == '\t' || line[w] == '\r')) w++;
    if (w == 1 && line[0] == 'v') c->vertices++;
    else if (w == 2 && !strncmp(line, "vt", 2)) c->uvs++;
    else if (w == 2 && !strncmp(line, "vn", 2)) c->normals++;
    else if (w == 1 && line[0] == 'o') c->objects++;
    else if (w == 1 && line[0] == 'g') c->groups++;
    else if (w == 6 && !strncmp(line, "usemtl", 6)) c->material_switches++;
    else if (w == 1 && line[0] == 'f') return obj_face_ok(path, line, n, line_no, c, err);
    else if (w == 6 && !strncmp(line, "mtllib", 6)) {
        char names[1024];
        size_t k = n - w < sizeof names - 1 ? n - w : sizeof names - 1;
        memcpy(names, line + w, k);
        names[k] = '\0';
        return obj_material_file(path, dir, real_dir, names, line_no, side_bytes, err);
    }
    return true;
}

bool ras_mesh_check_obj(const char *path, double *side_bytes, ras_error *err) {
    *side_bytes = 0;
    size_t len = 0;
    ras_error rerr = {{0}};
    char *data = ras_io_read_file(path, "model", RAS_MESH_MAX_SCAN_BYTES, &len, &rerr);
    if (!data) return true; /* too big to scan (the estimate refuses it), or unreadable */
    if (!looks_like_obj(path, data, len)) {
        free(data);
        return true;
    }
    char dir[4096], real_dir[PATH_MAX];
    ras_io_folder_of(path, dir, sizeof dir);
    if (!realpath(dir, real_dir)) snprintf(real_dir, sizeof real_dir, "%s", dir);
    obj_counts c = {0};
    bool ok = true;
    int line_no = 0;
    for (size_t at = 0; ok && at < len;) {
        const char *line = data + at, *nl = memchr(line, '\n', len - at);
        size_t n = nl ? (size_t)(nl - line) : len - at;
        at += n + 1;
        line_no++;
        ok = obj_line(path, line, n, line_no, dir, real_dir, &c, side_bytes, err);
    }
    free(data);
    /* Each object and each material switch is a mesh of its own in assimp,
     * as costly as a material (20,000 'usemtl' lines: 729 MB). */
    *side_bytes += (c.objects + c.material_switches) * RAS_MESH_IMPORT_BYTES_PER_MATERIAL +
                   c.groups * RAS_MESH_IMPORT_BYTES_PER_GROUP;
    if (ok && (c.objects > RAS_MESH_MAX_OBJ_PARTS || c.material_switches > RAS_MESH_MAX_OBJ_PARTS))
        ok = ras_error_set(err,
                           "model '%s' has %.0f objects ('o' lines) and %.0f material switches "
                           "('usemtl' lines); expected at most %d of each: the importer's time "
                           "grows with the square of their number (100,000 take minutes) — "
                           "merge the objects or materials, or convert the model to PLY or glTF",
                           path, c.objects, c.material_switches, RAS_MESH_MAX_OBJ_PARTS);
    return ok;
}
