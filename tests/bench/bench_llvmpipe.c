/* bench_llvmpipe.c — the classic hw3 scene through Mesa llvmpipe (OSMesa), to
 * time the project's renderers against a real software GPU (issue 18, item 1).
 *
 * The scene is hw3_shading --model's (scenes/hw3_model.json around the model
 * file, ras_builtin_scene_with_model), read by the project's own loaders:
 * the same mesh (indexed: one VBO per attribute, glDrawElements), model, view
 * and projection matrices (the projection's z row negated, so near is −1 as
 * OpenGL expects — the project's depth runs the other way), the same lights,
 * material and colour / height maps (RGBA8 from the same texels, bilinear,
 * the same wrap). The five fragment shaders are GLSL ports of
 * hw3_shading/solution/shading.c, formula for formula and with its constants
 * (below); the vertex stage is ras_vertex_transform's (view-space position,
 * normal matrix = inverse transpose, normal normalised per vertex and again
 * per fragment). A frame is glClear, one glDrawElements, for MSAA 4x the
 * resolve (glBlitFramebuffer into a one-sample framebuffer), and glFinish.
 *
 *   bench_llvmpipe --serve --model OBJ [--texture PNG]
 *       bench_perf's side process (protocol in bench_llvmpipe.h); llvmpipe's
 *       thread count is LP_NUM_THREADS, read once per process
 *   bench_llvmpipe --check [--model OBJ [--texture PNG]] [--wrong] [--save DIR]
 *       renders every shader at 1x and MSAA 4x here and with hw3_render, and
 *       compares them (llvmpipe_compare's tolerances); without --model the
 *       built-in teapot of bench_perf. A shader's port passes when its 1x and
 *       its MSAA image both pass; exit 0 when every port passes. With --wrong
 *       each shader is ported with a plausible mistake (WRONG below) and
 *       exit 0 means every wrong port failed: the check catches it.
 *       --save DIR writes both images of every pair as PNG.
 *   bench_llvmpipe --count --model OBJ [--texture PNG]
 *       under `valgrind --tool=callgrind`, for every shader at 1x and MSAA
 *       4x: two warm-up frames, then the counters zeroed, one frame, and a
 *       dump named SHADER_none or SHADER_msaa (bench_perf --instructions
 *       reads them: the instructions of one frame, all threads)
 *
 * RASTER101-SOLUTION: the GLSL below ports the reference shaders; this file
 * must never appear in a student handout (tests/grading/make-handout leaves it out).
 */
#define GL_GLEXT_PROTOTYPES 1
#include "bench_llvmpipe.h"
#include "ras_builtin_scenes.h" /* ras_builtin_scene_with_model */
#include "ras_counters.h"  /* ras_now_ms */
#include "stage1_vertex.h" /* ras_view_matrix_eye, ras_projection_normalize_w */
#include "transform.h"     /* hw1: get_projection_matrix, as hw3_render uses */

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h> /* CALLGRIND_ZERO_STATS, CALLGRIND_DUMP_STATS_AT */
#else /* no valgrind headers (make test does not install them): the requests do nothing */
#define CALLGRIND_ZERO_STATS
#define CALLGRIND_DUMP_STATS_AT(name) ((void)(name))
#endif

#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <stdio.h>  /* printf, fprintf, fgets */
#include <stdlib.h> /* malloc, free */
#include <string.h> /* strcmp */
#include <time.h>   /* clock_gettime */
#include <unistd.h> /* getpid */

/* ---- the shaders ----------------------------------------------------------- */

static const char *vertex_src = /* after "#version 330 core" */
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "uniform mat4 u_mv, u_proj;\n"
    "uniform mat3 u_nmat;\n"
    "centroid out vec3 v_view, v_normal;\n"
    "centroid out vec2 v_uv;\n"
    "void main() {\n"
    "    vec4 p = u_mv * vec4(a_pos, 1.0);\n"
    "    v_view = p.xyz;\n"
    "#ifdef WRONG_NORMAL\n"
    "    v_normal = a_normal; /* wrong: the object-space normal */\n"
    "#else\n"
    "    v_normal = normalize(u_nmat * a_normal);\n"
    "#endif\n"
    "    v_uv = a_uv;\n"
    "    gl_Position = u_proj * p;\n"
    "}\n";

/* shading.c's formulas. SHADER: 0 normal, 1 phong, 2 texture, 3 bump,
 * 4 displacement (ras_scene_shader's order, from RAS_SHADER_NORMAL). */
static const char *fragment_src =
    "centroid in vec3 v_view, v_normal;\n"
    "centroid in vec2 v_uv;\n"
    "out vec4 frag;\n"
    "uniform vec3 u_kd, u_ka, u_ks, u_ambient;\n"
    "uniform float u_p, u_kh, u_kn;\n"
    "uniform vec3 u_light_pos[LIGHTS + 1], u_light_int[LIGHTS + 1];\n"
    "uniform sampler2D u_tex, u_hmap;\n"
    "uniform vec2 u_hmap_size;\n"

    /* L = ka·Ia + Σ kd·(I/r²)·max(0, n·l) + ks·(I/r²)·max(0, n·h)^p */
    "vec3 blinn_phong(vec3 kd, vec3 point, vec3 normal) {\n"
    "    vec3 n = normalize(normal);\n"
    "    vec3 v = normalize(-point);\n"
    "#ifdef WRONG_VIEW\n"
    "    v = normalize(point); /* wrong: the direction from the eye */\n"
    "#endif\n"
    "    vec3 color = u_ka * u_ambient;\n"
    "    for (int i = 0; i < LIGHTS; i++) {\n"
    "        vec3 to_light = u_light_pos[i] - point;\n"
    "        float r2 = dot(to_light, to_light);\n"
    "        vec3 l = normalize(to_light);\n"
    "        vec3 h = normalize(l + v);\n"
    "        vec3 irradiance = u_light_int[i] / r2;\n"
    "        float diffuse = max(0.0, dot(n, l));\n"
    "        float specular = pow(max(0.0, dot(n, h)), u_p);\n"
    "        color += kd * irradiance * diffuse;\n"
    "        color += u_ks * irradiance * specular;\n"
    "    }\n"
    "    return color;\n"
    "}\n"
    /* the course's height: 255·|rgb| of the bilinear lookup */
    "#if HAS_HMAP\n"
    "float height(vec2 uv) { return 255.0 * length(textureLod(u_hmap, uv, 0.0).rgb); }\n"
    "#else\n"
    "float height(vec2 uv) { return 0.0; }\n"
    "#endif\n"
    "vec3 bump_normal(vec3 normal, vec2 uv) {\n"
    "    vec3 n = normalize(normal);\n"
    "#if !HAS_HMAP\n"
    "    return n;\n"
    "#endif\n"
    "    float s = sqrt(n.x * n.x + n.z * n.z);\n" /* tangent_frame, the course's t */
    "    vec3 t = s > 1e-6 ? vec3(n.x * n.y / s, s, n.z * n.y / s) : vec3(1.0, 0.0, 0.0);\n"
    "    vec3 b = cross(n, t);\n"
    "    float h = height(uv);\n"
    "    float k = u_kh * u_kn;\n"
    "#ifdef WRONG_BUMP\n"
    "    k = u_kn; /* wrong: kh forgotten */\n"
    "#endif\n"
    "    float du = k * (height(uv + vec2(1.0 / u_hmap_size.x, 0.0)) - h);\n"
    "    float dv = k * (height(uv + vec2(0.0, 1.0 / u_hmap_size.y)) - h);\n"
    "    vec3 bumped = normalize(-du * t - dv * b + n);\n"
    "    return any(isnan(bumped)) || any(isinf(bumped)) ? n : bumped;\n"
    "}\n"
    "void main() {\n"
    "    vec3 n = normalize(v_normal);\n" /* the fragment stage renormalises */
    "    vec3 c;\n"
    "#if SHADER == 0\n"
    "    c = (normalize(n) + 1.0) * 0.5;\n"
    "#elif SHADER == 1\n"
    "    c = blinn_phong(u_kd, v_view, n);\n"
    "#elif SHADER == 2\n"
    "#ifdef WRONG_UV\n"
    "    vec2 uv = vec2(v_uv.x, 1.0 - v_uv.y); /* wrong: v flipped */\n"
    "#else\n"
    "    vec2 uv = v_uv;\n"
    "#endif\n"
    "#if HAS_TEX\n"
    "    c = blinn_phong(textureLod(u_tex, uv, 0.0).rgb, v_view, n);\n"
    "#else\n"
    "    c = blinn_phong(u_kd, v_view, n);\n"
    "#endif\n"
    "#elif SHADER == 3\n"
    "    c = (bump_normal(n, v_uv) + 1.0) * 0.5;\n"
    "#else\n"
    "    float h = height(v_uv);\n"
    "#ifdef WRONG_DISPLACE\n"
    "    vec3 point = v_view; /* wrong: the point is not moved */\n"
    "#else\n"
    "    vec3 point = v_view + n * (u_kn * h);\n"
    "#endif\n"
    "    c = blinn_phong(u_kd, point, bump_normal(n, v_uv));\n"
    "#endif\n"
    "    frag = vec4(c, 1.0);\n"
    "}\n";

/* One GL program per hw3 shader: program k draws RAS_SHADER_NORMAL + k. */
#define GL_SHADERS (RAS_SHADER_COUNT - RAS_SHADER_NORMAL)

/* The plausible mistake of --wrong, per shader. */
static const char *const wrong_define[GL_SHADERS] = {
    "#define WRONG_NORMAL\n", "#define WRONG_VIEW\n", "#define WRONG_UV\n", "#define WRONG_BUMP\n",
    "#define WRONG_DISPLACE\n"};

/* ---- OpenGL state ---------------------------------------------------------- */

typedef struct gl_scene {
    int width, height;
    vec3s clear;
    GLuint program[GL_SHADERS];
    GLuint vao;
    GLsizei index_count;
    GLuint fbo[2], color_rb[2], depth_rb[2]; /* 0: one sample (the resolved image); 1: MSAA 4x */
} gl_scene;

static bool compile(GLuint shader, const char *const *parts, int count) {
    glShaderSource(shader, count, parts, NULL);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetShaderInfoLog(shader, sizeof log, NULL, log);
        fprintf(stderr, "bench_llvmpipe: GLSL: %s\n", log);
    }
    return ok;
}

/* The light count and which maps exist are constants of each program, as a
 * GL application would compile them: the light loop unrolls and its arrays
 * are indexed by constants (a loop bound by a uniform indexes them per lane,
 * which made llvmpipe's Blinn-Phong frame about 2.5x slower), and no lookup
 * sits in a branch. Lookups are textureLod(…, 0): level 0, as shading.c's
 * bilinear filter reads, with no derivatives to compute. */
static GLuint make_program(int shader, bool wrong, int lights, bool tex, bool hmap) {
    char define[160];
    snprintf(define, sizeof define,
             "#version 330 core\n#define SHADER %d\n#define LIGHTS %d\n#define HAS_TEX %d\n"
             "#define HAS_HMAP %d\n",
             shader, lights, tex, hmap);
    const char *fs_parts[3] = {define, wrong ? wrong_define[shader] : "", fragment_src};
    const char *vs_parts[3] = {"#version 330 core\n",
                               wrong && shader == 0 ? wrong_define[shader] : "",
                               vertex_src};
    GLuint vs = glCreateShader(GL_VERTEX_SHADER), fs = glCreateShader(GL_FRAGMENT_SHADER);
    if (!compile(vs, vs_parts, 3) || !compile(fs, fs_parts, 3)) return 0;
    GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    return ok ? p : 0;
}

static GLuint upload_texture(const ras_texture *tex, GLenum unit) {
    size_t n = (size_t)tex->width * (size_t)tex->height;
    uint8_t *rgba = malloc(4 * n);
    if (!rgba) return 0;
    for (size_t i = 0; i < n; i++) { /* row 0 is v = 0 in both */
        vec3s c = ras_texture_texel0(tex, i); /* floats or bytes */
        rgba[4 * i] = ras_unit_to_byte(c.x);
        rgba[4 * i + 1] = ras_unit_to_byte(c.y);
        rgba[4 * i + 2] = ras_unit_to_byte(c.z);
        rgba[4 * i + 3] = 255;
    }
    GLuint t;
    glGenTextures(1, &t);
    glActiveTexture(unit);
    glBindTexture(GL_TEXTURE_2D, t);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, tex->width, tex->height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 rgba);
    free(rgba);
    /* Bilinear on level 0, no mip levels: shading.c's texture_sample_bilinear. */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    GLint wrap = tex->wrap == RAS_WRAP_REPEAT ? GL_REPEAT : GL_CLAMP_TO_EDGE;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
    return t;
}

/* o: the object's material and the scene's lights (view space), as hw3_render
 * hands them to the shaders. */
static void set_uniforms(GLuint p, const fragment_shader_payload *o, mat4s mv, mat4s proj) {
    glUseProgram(p);
    mat3s nmat =
        glms_mat3_transpose(glms_mat3_inv(glms_mat4_pick3(mv))); /* ras_vertex_transform's */
    glUniformMatrix4fv(glGetUniformLocation(p, "u_mv"), 1, GL_FALSE, &mv.raw[0][0]);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_proj"), 1, GL_FALSE, &proj.raw[0][0]);
    glUniformMatrix3fv(glGetUniformLocation(p, "u_nmat"), 1, GL_FALSE, &nmat.raw[0][0]);
    glUniform3fv(glGetUniformLocation(p, "u_kd"), 1, o->color.raw);
    glUniform3fv(glGetUniformLocation(p, "u_ka"), 1, o->ka.raw);
    glUniform3fv(glGetUniformLocation(p, "u_ks"), 1, o->ks.raw);
    glUniform3fv(glGetUniformLocation(p, "u_ambient"), 1, o->ambient_intensity.raw);
    glUniform1f(glGetUniformLocation(p, "u_p"), o->p);
    glUniform1f(glGetUniformLocation(p, "u_kh"), o->kh);
    glUniform1f(glGetUniformLocation(p, "u_kn"), o->kn);
    for (int i = 0; i < o->light_count; i++) {
        char name[32];
        snprintf(name, sizeof name, "u_light_pos[%d]", i);
        glUniform3fv(glGetUniformLocation(p, name), 1, o->lights[i].position.raw);
        snprintf(name, sizeof name, "u_light_int[%d]", i);
        glUniform3fv(glGetUniformLocation(p, name), 1, o->lights[i].intensity.raw);
    }
    glUniform1i(glGetUniformLocation(p, "u_tex"), 0);
    glUniform1i(glGetUniformLocation(p, "u_hmap"), 1);
    if (o->height_map)
        glUniform2f(glGetUniformLocation(p, "u_hmap_size"), (float)o->height_map->width,
                    (float)o->height_map->height);
}

static GLuint buffer(GLenum target, size_t bytes, const void *data) {
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    glBufferData(target, (GLsizeiptr)bytes, data, GL_STATIC_DRAW);
    return b;
}

/* The GL objects for the scene's one object (the classic model scene). */
static bool gl_scene_init(gl_scene *g, const ras_scene *s, const ras_scene_assets *a,
                          bool wrong) {
    if (s->object_count != 1) {
        fprintf(stderr, "bench_llvmpipe: the classic model scene has one object\n");
        return false;
    }
    fragment_shader_payload material = {.ambient_intensity = s->ambient,
                                        .light_count = s->light_count};
    const fragment_shader_payload *o = &material;
    hw3_object_material(s, a, 0, &material);
    const ras_mesh *m = a->meshes[0];
    g->width = s->width;
    g->height = s->height;
    g->clear = s->clear_color;
    mat4s model = hw3_object_model(&s->objects[0], 0);
    mat4s view = ras_scene_view_matrix(s);
    for (int i = 0; i < s->light_count; i++) { /* into view space, as hw3_render */
        const ras_scene_light *l = &s->lights[i];
        material.lights[i] = (light){
            l->in_world ? glms_mat4_mulv3(view, l->position, 1.0f) : l->position, l->intensity};
    }
    mat4s mv = glms_mat4_mul(view, model);
    const ras_scene_camera *cam = &s->camera;
    mat4s proj = ras_projection_normalize_w(get_projection_matrix(
        cam->fov_deg, (float)s->width / (float)s->height, cam->z_near, cam->z_far));
    /* The project's depth (1 − z/w)/2 puts near at 0 from z/w = +1; OpenGL's
     * window depth is (z/w + 1)/2: negate the z row, and near is −1 → 0 too. */
    for (int c = 0; c < 4; c++)
        proj.raw[c][2] = -proj.raw[c][2];

    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    buffer(GL_ARRAY_BUFFER, m->vertex_count * sizeof(vec3s), m->positions);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(vec3s), NULL);
    glEnableVertexAttribArray(0);
    buffer(GL_ARRAY_BUFFER, m->vertex_count * sizeof(vec3s), m->normals);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(vec3s), NULL);
    glEnableVertexAttribArray(1);
    buffer(GL_ARRAY_BUFFER, m->vertex_count * sizeof(vec2s), m->uvs);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(vec2s), NULL);
    glEnableVertexAttribArray(2);
    buffer(GL_ELEMENT_ARRAY_BUFFER, m->triangle_count * 3 * sizeof(unsigned), m->indices);
    g->index_count = (GLsizei)(m->triangle_count * 3);

    if (o->texture && !upload_texture(o->texture, GL_TEXTURE0)) return false;
    if (o->height_map && !upload_texture(o->height_map, GL_TEXTURE1)) return false;
    for (int sh = 0; sh < GL_SHADERS; sh++) {
        g->program[sh] =
            make_program(sh, wrong, o->light_count, o->texture != NULL, o->height_map != NULL);
        if (!g->program[sh]) return false;
        set_uniforms(g->program[sh], o, mv, proj);
    }

    glGenFramebuffers(2, g->fbo);
    glGenRenderbuffers(2, g->color_rb);
    glGenRenderbuffers(2, g->depth_rb);
    for (int i = 0; i < 2; i++) {
        int samples = i ? 4 : 0;
        glBindRenderbuffer(GL_RENDERBUFFER, g->color_rb[i]);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, g->width, g->height);
        glBindRenderbuffer(GL_RENDERBUFFER, g->depth_rb[i]);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, g->width,
                                         g->height);
        glBindFramebuffer(GL_FRAMEBUFFER, g->fbo[i]);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  g->color_rb[i]);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                  g->depth_rb[i]);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            fprintf(stderr, "bench_llvmpipe: framebuffer %d incomplete\n", i);
            return false;
        }
    }
    glViewport(0, 0, g->width, g->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);                                   /* the project's strict < */
    glDisable(GL_CULL_FACE);                                /* the classic scene culls nothing */
    glClearColor(g->clear.x, g->clear.y, g->clear.z, 0.0f); /* alpha 0: not covered */
    glClearDepth(1.0);
    return glGetError() == GL_NO_ERROR;
}

/* One frame: clear, draw, resolve, finish. */
static void gl_frame(const gl_scene *g, int shader, bool msaa) {
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo[msaa]);
    if (msaa) glEnable(GL_MULTISAMPLE);
    glUseProgram(g->program[shader]);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawElements(GL_TRIANGLES, g->index_count, GL_UNSIGNED_INT, NULL);
    if (msaa) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo[1]);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, g->fbo[0]);
        glBlitFramebuffer(0, 0, g->width, g->height, 0, 0, g->width, g->height, GL_COLOR_BUFFER_BIT,
                          GL_NEAREST);
    }
    glFinish();
}

/* The resolved frame as RGBA, top row first. */
static void gl_read(const gl_scene *g, uint8_t *rgba) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo[0]);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    size_t row = (size_t)g->width * 4;
    uint8_t *tmp = malloc(row * (size_t)g->height);
    if (!tmp) return;
    glReadPixels(0, 0, g->width, g->height, GL_RGBA, GL_UNSIGNED_BYTE, tmp);
    for (int y = 0; y < g->height; y++) /* OpenGL's row 0 is the bottom */
        memcpy(rgba + row * (size_t)y, tmp + row * (size_t)(g->height - 1 - y), row);
    free(tmp);
}

static double cpu_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* ---- modes ------------------------------------------------------------------ */

static int serve(const gl_scene *g) {
    char line[256], verb[32], shader_name[32], aa[32];
    size_t bytes = (size_t)g->width * (size_t)g->height * 4;
    uint8_t *rgba = malloc(bytes);
    if (!rgba) return 1;
    printf("ready %s\n", (const char *)glGetString(GL_RENDERER));
    fflush(stdout);
    while (fgets(line, sizeof line, stdin)) {
        if (!strncmp(line, "quit", 4)) break;
        ras_scene_shader sh;
        ras_error err = {{0}};
        if (sscanf(line, "%31s %31s %31s", verb, shader_name, aa) != 3 ||
            !hw3_shader_parse(shader_name, &sh, &err)) {
            fprintf(stderr, "bench_llvmpipe: bad request '%s'\n", line);
            return 2;
        }
        bool msaa = !strcmp(aa, "msaa");
        double c0 = cpu_ms(), t0 = ras_now_ms();
        gl_frame(g, (int)sh - RAS_SHADER_NORMAL, msaa);
        double ms = ras_now_ms() - t0, cpu = cpu_ms() - c0;
        if (!strcmp(verb, "frame")) {
            printf("%.6f %.6f\n", ms, cpu);
        } else {
            gl_read(g, rgba);
            printf("image %d %d\n", g->width, g->height);
            fwrite(rgba, 1, bytes, stdout);
        }
        fflush(stdout);
    }
    free(rgba);
    return 0;
}

static bool save_rgba(const uint8_t *rgba, int w, int h, const char *path) {
    uint8_t *rgb = malloc((size_t)w * (size_t)h * 3);
    if (!rgb) return false;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
        memcpy(rgb + 3 * i, rgba + 4 * i, 3);
    ras_error err = {{0}};
    bool ok = ras_image_save_rgb8(rgb, w, h, path, &err);
    if (!ok) fprintf(stderr, "bench_llvmpipe: %s\n", err.msg);
    free(rgb);
    return ok;
}

static int check(const gl_scene *g, const ras_scene *scene, ras_scene_assets *assets, bool wrong,
                 const char *save_dir) {
    size_t bytes = (size_t)g->width * (size_t)g->height * 4;
    uint8_t *rgba = malloc(bytes);
    ras_error err = {{0}};
    ras_image *ours = ras_image_create(g->width, g->height, &err);
    if (!rgba || !ours) return 1;
    int as_expected = 0; /* shaders: correct ports passed, or wrong ports caught */
    printf("%-12s %-7s %9s %9s %7s %6s %7s %4s  %s\n", "shader", "AA", "covered", "llvmpipe",
           "cover", "mean", ">8", "max", wrong ? "wrong port (must fail)" : "result");
    for (int sh = 0; sh < GL_SHADERS; sh++) {
        bool port_ok = true; /* both checks of this shader pass */
        for (int msaa = 0; msaa < 2; msaa++) {
            hw3_render_options opt = hw3_render_defaults();
            opt.shader = (ras_scene_shader)(RAS_SHADER_NORMAL + sh);
            if (msaa) {
                opt.aa = RAS_AA_MSAA;
                if (!ras_sample_pattern_make(RAS_PATTERN_STANDARD, 4, &opt.pattern, &err)) return 1;
            }
            if (!hw3_render(scene, assets, &opt, ours, NULL, &err)) {
                fprintf(stderr, "bench_llvmpipe: %s\n", err.msg);
                return 1;
            }
            gl_frame(g, sh, msaa);
            gl_read(g, rgba);
            llvmpipe_check c;
            llvmpipe_compare(ours, g->clear, rgba, msaa, &c);
            port_ok = port_ok && c.pass;
            printf("%-12s %-7s %9ld %9ld %6.2f%% %6.3f %6.2f%% %4d  %s\n",
                   ras_scene_shader_name(opt.shader), msaa ? "MSAA 4x" : "1x", c.covered_ours,
                   c.covered_llvmpipe, 100 * c.coverage_diff, c.mean_diff, 100 * c.bad_fraction,
                   c.max_diff, c.pass ? "within tolerance" : "OUTSIDE tolerance");
            if (save_dir) {
                char path[1024];
                snprintf(path, sizeof path, "%s/%s_%s_ours.png", save_dir,
                         ras_scene_shader_name(opt.shader), msaa ? "msaa" : "1x");
                if (!ras_image_save(ours, path, &err)) fprintf(stderr, "%s\n", err.msg);
                snprintf(path, sizeof path, "%s/%s_%s_llvmpipe.png", save_dir,
                         ras_scene_shader_name(opt.shader), msaa ? "msaa" : "1x");
                save_rgba(rgba, g->width, g->height, path);
            }
        }
        as_expected += port_ok != wrong;
    }
    printf("%s: %d of %d shaders %s\n", wrong ? "wrong ports caught" : "ports within tolerance",
           as_expected, GL_SHADERS, as_expected == GL_SHADERS ? "(all)" : "(NOT all)");
    free(rgba);
    ras_image_destroy(ours);
    return as_expected == GL_SHADERS ? 0 : 1;
}

/* One frame's instructions per shader and AA under callgrind (outside
 * valgrind the requests do nothing and this only renders 30 frames). */
static int count(const gl_scene *g) {
    for (int sh = 0; sh < GL_SHADERS; sh++)
        for (int msaa = 0; msaa < 2; msaa++) {
            for (int i = 0; i < 2; i++)
                gl_frame(g, sh, msaa); /* llvmpipe compiles its variants */
            char name[64];
            snprintf(name, sizeof name, "%s_%s", ras_scene_shader_name(RAS_SHADER_NORMAL + sh),
                     msaa ? "msaa" : "none");
            CALLGRIND_ZERO_STATS;
            gl_frame(g, sh, msaa);
            CALLGRIND_DUMP_STATS_AT(name);
        }
    return 0;
}

int main(int argc, char **argv) {
    const char *model = NULL, *texture = NULL, *save_dir = NULL;
    bool do_serve = false, do_check = false, wrong = false, do_count = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--count"))
            do_count = true;
        else if (!strcmp(argv[i], "--serve"))
            do_serve = true;
        else if (!strcmp(argv[i], "--check"))
            do_check = true;
        else if (!strcmp(argv[i], "--wrong"))
            wrong = true;
        else if (!strcmp(argv[i], "--model") && i + 1 < argc)
            model = argv[++i];
        else if (!strcmp(argv[i], "--texture") && i + 1 < argc)
            texture = argv[++i];
        else if (!strcmp(argv[i], "--save") && i + 1 < argc)
            save_dir = argv[++i];
        else {
            do_serve = do_check = false;
            break;
        }
    }
    if (do_count) do_serve = true; /* the same: a model is needed */
    if (do_serve == do_check || (do_serve && !model)) {
        fprintf(stderr, "usage: bench_llvmpipe --serve --model OBJ [--texture PNG]\n"
                        "       bench_llvmpipe --check [--model OBJ [--texture PNG]] [--wrong] "
                        "[--save DIR]\n"
                        "       bench_llvmpipe --count --model OBJ [--texture PNG]\n");
        return 2;
    }
    char tmp_obj[256] = "";
    if (!model) {
        snprintf(tmp_obj, sizeof tmp_obj, "/tmp/raster101_llvmpipe_teapot_%d.obj", (int)getpid());
        if (!bench_write_teapot_obj(tmp_obj)) {
            fprintf(stderr, "bench_llvmpipe: cannot write %s\n", tmp_obj);
            return 1;
        }
        model = tmp_obj;
    }
    ras_error err = {{0}};
    ras_scene *scene =
        ras_builtin_scene_with_model("hw3_model", model, texture, NULL, false, &err);
    ras_scene_assets *assets = scene ? ras_scene_load_assets(scene, &err) : NULL;
    if (tmp_obj[0]) remove(tmp_obj);
    if (!assets) {
        ras_scene_destroy(scene);
        fprintf(stderr, "bench_llvmpipe: %s\n", err.msg);
        return 1;
    }
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           0,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
    static uint8_t dummy[4 * 16 * 16]; /* the window-system buffer; frames go to FBOs */
    if (!ctx || !OSMesaMakeCurrent(ctx, dummy, GL_UNSIGNED_BYTE, 16, 16)) {
        fprintf(stderr, "bench_llvmpipe: no OpenGL 3.3 core context from OSMesa\n");
        return 1;
    }
    gl_scene g = {0};
    if (!gl_scene_init(&g, scene, assets, wrong)) {
        fprintf(stderr, "bench_llvmpipe: OpenGL setup failed\n");
        return 1;
    }
    int rc = do_count  ? count(&g)
             : do_serve ? serve(&g)
                        : check(&g, scene, assets, wrong, save_dir);
    OSMesaDestroyContext(ctx);
    ras_scene_assets_destroy(assets);
    ras_scene_destroy(scene);
    return rc;
}
