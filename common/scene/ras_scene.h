/* ras_scene.h — scene files: the JSON description a frame is configured from.
 *
 * A scene file says what to draw (objects: a built-in shape or a model file,
 * a transform, a material), from where (camera), under which lights, and
 * which effects the pipeline runs (anti-aliasing, shader, texture filter,
 * culling, depth format). docs/scenes.md documents every key; in short:
 *
 *   {
 *     "image":  {"width": 700, "height": 700},
 *     "camera": {"eye": [0, 0, 5], "fov_deg": 45, "near": 0.1, "far": 50},
 *     "objects": [
 *       {"shape": "triangle", "vertices": [[2, 0, -2], [0, 2, -2], [-2, 0, -2]],
 *        "material": {"color": "#d9eeb9"}}
 *     ]
 *   }
 *
 * Two steps, so that a scene can be checked without touching other files:
 *   1. ras_scene_load / ras_scene_parse read the JSON into a ras_scene: plain
 *      data (numbers, enums, matrices, strings). Paths are resolved against
 *      the scene file's folder but nothing is opened besides the scene file.
 *   2. ras_scene_load_assets creates the meshes and textures it names.
 *
 * Errors (false/NULL and a ras_error, never a partial result) name the file,
 * then either line:column (JSON syntax) or the key path (everything else,
 * since cJSON keeps no positions), what was expected and what came:
 *     scene.json:4:17: JSON syntax error: expected a value after ',', got '}' ...
 *     scene.json: objects[2].material.ks: expected an array of 3 numbers, got a string ("0.7")
 * Unknown keys are errors (with a did-you-mean for a near miss), and so are
 * duplicate keys, wrong types, numbers out of range (JSON has no NaN, but
 * 1e400 parses to infinity: that is out of range too) and missing required keys.
 *
 * Defaults (every key but "objects" is optional):
 *   image 700×700; camera: the GAMES101 fixed view (eye (0,0,5) looking down
 *   −z, y up), fov_deg 45, near 0.1, far 50; model_rotation 0° about z;
 *   transform: identity; material: colour white, no texture, no height map,
 *   ka 0.005, kd = the colour (or texel), ks 0.7937, p 150, kh 0.2, kn 0.1,
 *   uv_scale 1; lights: none; ambient 10; aa none (samples 4, pattern ordered
 *   when a mode is set); shader flat; filter bilinear; cull none;
 *   depth z01; clear_color black; wireframe false.
 *
 * Units and spaces: world units; angles in degrees; colours in [0,1];
 * light positions in VIEW space (the GAMES101 convention) unless the light
 * says "space": "world".
 *
 * Ownership: ras_scene_load/ras_scene_parse return a heap scene freed by
 * ras_scene_destroy; ras_scene_load_assets returns assets freed by
 * ras_scene_assets_destroy (both NULL-safe). The assets do not point into the
 * scene; either may be destroyed first.
 *
 * Dependencies: cJSON (in ras_scene*.c only: the reader, ras_scene.c, is split by
 * job into ras_scene_syntax.c, ras_scene_schema.c, ras_scene_json.c and
 * ras_scene_assets.c), cglm through ras_math.h.
 */
#ifndef RAS_SCENE_H
#define RAS_SCENE_H

#include "ras_error.h"
#include "ras_math.h"
#include "ras_mesh.h"
#include "ras_pipeline.h" /* ras_cull_mode, ras_aa_mode, ras_depth_format */
#include "ras_sample_pattern.h"
#include "ras_texture.h"

#include <stddef.h> /* size_t */

#define RAS_SCENE_MAX_BYTES (16u * 1024u * 1024u) /* larger scene files are refused */
#define RAS_SCENE_MAX_SIZE 8192                   /* image width and height: 1..8192 */
#define RAS_SCENE_MAX_OBJECTS 4096
#define RAS_SCENE_MAX_LIGHTS 8
#define RAS_SCENE_MAX_ROTATIONS 8 /* "rotate" entries per transform */

typedef enum ras_scene_view {
    RAS_SCENE_VIEW_FIXED,   /* GAMES101: a translation by −eye, looking down −z, y up */
    RAS_SCENE_VIEW_LOOK_AT, /* eye, look_at, up */
} ras_scene_view;

typedef struct ras_scene_camera {
    ras_scene_view view;
    vec3s eye, look_at, up; /* look_at and up only for RAS_SCENE_VIEW_LOOK_AT */
    float fov_deg;          /* vertical, in (0, 180) */
    float z_near, z_far;    /* positive distances, 0 < near < far */
} ras_scene_camera;

typedef enum ras_scene_shape {
    RAS_SHAPE_TRIANGLE, /* vertices[3] (object space), material colour */
    RAS_SHAPE_PLANE,    /* size, divisions: ras_mesh_create_plane */
    RAS_SHAPE_CUBE,     /* size */
    RAS_SHAPE_SPHERE,   /* radius, stacks, slices */
    RAS_SHAPE_TORUS,    /* major_radius, minor_radius, rings, sides */
    RAS_SHAPE_TEAPOT,   /* divisions */
    RAS_SHAPE_THIN_FAN, /* count slivers around the origin in the xy plane (facing +z):
                           radius, arc_deg; every inner edge is shared by two triangles */
    RAS_SHAPE_MODEL,    /* model_path (any format assimp reads), fit */
} ras_scene_shape;
#define RAS_SHAPE_COUNT 8

typedef struct ras_scene_shape_params {
    vec3s vertices[3];                /* triangle */
    float size;                       /* plane (side), cube (edge) */
    int divisions;                    /* plane (quads per side), teapot (per patch side) */
    float radius;                     /* sphere, thin_fan */
    int stacks, slices;               /* sphere */
    float major_radius, minor_radius; /* torus */
    int rings, sides;                 /* torus */
    int count;                        /* thin_fan: number of triangles */
    float arc_deg;                    /* thin_fan: the angle they share, in (0, 360] */
    char *model_path;                 /* model: resolved against the scene file's folder */
    float fit;                        /* model: > 0 centres the model and scales its largest
                                         extent to `fit` units (ras_mesh_fit_matrix); 0 = as is */
} ras_scene_shape_params;

typedef enum ras_scene_map_kind {
    RAS_MAP_NONE,
    RAS_MAP_FILE,    /* path */
    RAS_MAP_CHECKER, /* size, squares, colors[2] */
    RAS_MAP_BRICK,   /* size */
    RAS_MAP_BUMPS,   /* size, bumps (a height map) */
} ras_scene_map_kind;

/* A colour texture or a height map: a file or a built-in picture. */
typedef struct ras_scene_map {
    ras_scene_map_kind kind;
    char *path;      /* RAS_MAP_FILE: resolved against the scene file's folder */
    int size;        /* built-ins: texels per side, 1..4096 (default 256) */
    int squares;     /* checker: squares per side (default 8) */
    vec3s colors[2]; /* checker: the two colours */
    int bumps;       /* bumps: bumps per side (default 8) */
    ras_wrap wrap;   /* default RAS_WRAP_REPEAT */
} ras_scene_map;

typedef struct ras_scene_material {
    vec3s color;           /* base colour, [0,1] (default white) */
    ras_scene_map texture; /* colour map (kind NONE: none) */
    ras_scene_map height_map;
    vec3s ka, kd, ks; /* kd is meaningful only when kd_set */
    bool kd_set;      /* false: kd is the colour, or the texel (GAMES101) */
    float p;          /* specular exponent */
    float kh, kn;     /* bump/displacement strengths */
    vec2s uv_scale;   /* multiplies the mesh's UVs (tiling with repeat) */
} ras_scene_material;

typedef struct ras_scene_rotation {
    vec3s axis; /* non-zero, not necessarily unit */
    float deg;
} ras_scene_rotation;

typedef struct ras_scene_object {
    char *name; /* NULL when the file gives none */
    ras_scene_shape shape;
    ras_scene_shape_params params;
    /* transform: model = T(translate) · R(rotations[n-1]) ⋯ R(rotations[0]) · S(scale) */
    vec3s translate;
    ras_scene_rotation rotations[RAS_SCENE_MAX_ROTATIONS];
    int rotation_count;
    vec3s scale;
    mat4s model; /* the product above: ras_scene_model_matrix with the identity */
    ras_scene_material material;
} ras_scene_object;

typedef struct ras_scene_light {
    vec3s position;  /* view space, or world space when in_world */
    vec3s intensity; /* >= 0 per channel */
    bool in_world;
} ras_scene_light;

typedef enum ras_scene_shader {
    RAS_SHADER_FLAT,   /* the material/vertex colour, unlit (hw2) */
    RAS_SHADER_NORMAL, /* hw3 */
    RAS_SHADER_PHONG,
    RAS_SHADER_TEXTURE,
    RAS_SHADER_BUMP,
    RAS_SHADER_DISPLACEMENT,
} ras_scene_shader;
#define RAS_SHADER_COUNT 6

typedef enum ras_scene_filter {
    RAS_FILTER_NEAREST,
    RAS_FILTER_BILINEAR,
    RAS_FILTER_TRILINEAR,
} ras_scene_filter;

typedef struct ras_scene {
    char *path;        /* the file as given (or the name passed to ras_scene_parse) */
    char *dir;         /* the folder relative paths were resolved against */
    char *description; /* NULL when the file gives none */
    int width, height; /* 1..8192 */
    ras_scene_camera camera;
    /* The program's own rotation (hw1: -r ANGLE, the a/d keys): applied to
     * every object about its own origin, see ras_scene_model_matrix. */
    float model_rotation_deg;
    vec3s model_rotation_axis; /* default (0,0,1) */
    bool model_rotation_axis_set;
    ras_scene_object *objects;
    int object_count; /* >= 1 */
    ras_scene_light *lights;
    int light_count; /* 0..RAS_SCENE_MAX_LIGHTS */
    vec3s ambient;
    ras_aa_mode aa;
    ras_pattern_kind pattern_kind; /* as written, also for RAS_AA_NONE */
    /* The samples: pattern_kind's with aa.samples, validated with
     * ras_sample_pattern_make; the centre (count 1) for RAS_AA_NONE. Its
     * count is the scene's sample count: no other field holds it. */
    ras_sample_pattern pattern;
    ras_scene_shader shader;
    ras_scene_filter filter;
    ras_cull_mode cull;
    ras_depth_format depth; /* "depth": "z01" | "inverse_w" (uses camera.z_near) */
    vec3s clear_color;
    bool wireframe;
} ras_scene;

/* Reads and parses a scene file. NULL and err when the file is missing,
 * unreadable, a folder, larger than RAS_SCENE_MAX_BYTES, not valid JSON, or
 * not a valid scene. Relative paths inside resolve against the file's folder. */
ras_scene *ras_scene_load(const char *path, ras_error *err);

/* Parses scene text (NUL-terminated). `name` is used in messages (and kept as
 * scene->path); `base_dir` is the folder relative paths resolve against
 * (NULL: the current folder). */
ras_scene *ras_scene_parse(const char *text, const char *name, const char *base_dir,
                           ras_error *err);

void ras_scene_destroy(ras_scene *scene);

/* The program's own rotation of every object (ras_scene_model_matrix): a
 * matrix (hw1's get_model_matrix or get_rotation, hw2's), or, with `matrix`
 * NULL, hw3's turn of turn_y_deg degrees about +y. */
typedef struct ras_scene_spin {
    const mat4s *matrix;
    float turn_y_deg;
} ras_scene_spin;

/* Every model matrix of the tree: the object's, T · spin · R(rotations[n-1])
 * ⋯ R(rotations[0]) · S, with the program's spin after the object's
 * rotations and before its translation, so each object turns about its own
 * origin. Multiplied out in one of two ways, each bit for bit what reference
 * pictures were drawn with:
 *   - a matrix: ((T · spin) · (R_{n-1} ⋯ R_0 · I)) · S, every factor
 *     multiplied, each R glms_rotate_make's; the identity gives
 *     object->model (hw1, hw2, the scene itself);
 *   - a turn about y (hw3): a last rotation about +y or -y joins the turn
 *     (one R_y of the summed angle: the two commute), rotations about +x and
 *     +y are their cos/sin matrices (any other axis glms_rotate_make's), and
 *     no factor is multiplied for no rotations or a scale of 1:
 *     (T · R_y(turn + yaw)) · (R_{n-1} ⋯ R_0 · S). */
mat4s ras_scene_model_matrix(const ras_scene_object *object, ras_scene_spin spin);

/* The camera's view matrix: ras_view_matrix_eye(eye) for the fixed view,
 * glms_lookat(eye, look_at, up) otherwise. */
mat4s ras_scene_view_matrix(const ras_scene *scene);

/* The meshes and textures a scene names, one entry per object. */
typedef struct ras_scene_assets {
    int object_count;
    ras_mesh **meshes;         /* [object_count], never NULL; fit and uv_scale applied */
    ras_texture **textures;    /* [object_count], NULL when the object has none */
    ras_texture **height_maps; /* [object_count], NULL when the object has none */
    /* Textures are shared between objects that describe the same map; each
     * distinct one is owned once, here. */
    ras_texture **owned_textures;
    int owned_texture_count;
    /* Bytes the meshes, textures and their rendering are estimated to need,
     * committed to the memory budget (ras_memory.h) until destroyed. */
    double memory_estimate;
} ras_scene_assets;

/* Creates every object's mesh (built-in or loaded through assimp) and every
 * texture and height map (built-in or loaded). No mip levels are built (the
 * pipeline builds them when the filter needs them). NULL and err naming the
 * scene file, the object and the path when a file is missing or malformed;
 * nothing is kept on error. */
ras_scene_assets *ras_scene_load_assets(const ras_scene *scene, ras_error *err);
/* The same without textures and height maps (their slots stay NULL), for
 * programs that draw flat colours: a map they never sample is never read,
 * decoded or built (a 404 KB scene's maps took 1.35 GB in hw2 before). */
ras_scene_assets *ras_scene_load_meshes(const ras_scene *scene, ras_error *err);
void ras_scene_assets_destroy(ras_scene_assets *assets);
/* Builds the mip levels of object i's texture (trilinear filtering reads
 * them), once for a texture objects share, after checking their float levels
 * (ras_texture_mip_bytes) against the memory budget and committing them with
 * the assets; adds the levels built to *levels_built. True when there is
 * nothing to build; false and err naming the scene and the object when the
 * budget or memory refuses. */
bool ras_scene_assets_build_mips(const ras_scene *scene, ras_scene_assets *assets, int i,
                                 uint64_t *levels_built, ras_error *err);
/* Whether the mip levels ras_scene_assets_build_mips would build for every
 * colour map fit the memory budget beside what is committed (nothing is
 * built or committed): a program checks before its first frame. False and
 * err naming the scene, the estimate and the limit when they do not. */
bool ras_scene_assets_check_mips(const ras_scene *scene, const ras_scene_assets *assets,
                                 ras_error *err);

/* Names as written in scene files ("triangle", "phong", "trilinear", ...). */
const char *ras_scene_shape_name(ras_scene_shape shape);
const char *ras_scene_shader_name(ras_scene_shader shader);
const char *ras_scene_filter_name(ras_scene_filter filter);
const char *ras_scene_cull_name(ras_cull_mode cull);

#endif
