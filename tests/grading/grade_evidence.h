/* grade_evidence.h — the buffers' evidence for a picture that differs
 * (tests/grading/grade_*.c; docs/grading.md, "Buffers"): the student's
 * program and the trusted reference program draw it again with --dump, and
 * the first buffer in pipeline order that differs names the stage, the
 * assignment whose code makes it and the likely cause. grade_images.c
 * judges with it: what the picture alone shows may only refine it.
 */
#ifndef RAS_GRADING_GRADE_EVIDENCE_H
#define RAS_GRADING_GRADE_EVIDENCE_H

#include "grade_base.h"
#include "grade_priv.h"

#include <string.h> /* strcmp */

/* The assignments whose code makes the stages of the course's pipeline: the
 * vertices (the matrices: get_model_matrix), the raster (rasterize_triangle
 * and the resolve) and the shading (the fragment shaders): the owners of
 * those functions' rows in ras_call_table.h, compiled in by
 * tests/grading/CMakeLists.txt; "" when no row names the function. */
#ifndef RAS_GRADE_VERTICES_OWNER
#define RAS_GRADE_VERTICES_OWNER ""
#endif
#ifndef RAS_GRADE_RASTER_OWNER
#define RAS_GRADE_RASTER_OWNER ""
#endif
#ifndef RAS_GRADE_SHADING_OWNER
#define RAS_GRADE_SHADING_OWNER ""
#endif
/* whether owner (one of the three) is set and is id */
static inline bool stage_owner_is(const char *owner, const char *id) {
    return owner && id && *owner && !strcmp(owner, id);
}
/* whether program is one of assignment owner's ("hw3_shading", "hw3_shading_ref") */
static inline bool program_of(const char *program, const char *owner) {
    size_t n = strlen(owner);
    return n && !strncmp(program, owner, n) && program[n] == '_';
}

/* Where the evidence stands. Only EVIDENCE_RAN can clear a picture; what the
 * student's program withholds or spoils fails the item (docs/grading.md,
 * "Buffers"), and where no evidence can be had the picture decides alone. */
typedef enum evidence_kind {
    EVIDENCE_NOT_ASKED,    /* the picture needs none (it matches and shows no defect) */
    EVIDENCE_BUDGET,       /* EVIDENCE_MAX renders spent: the picture decides */
    EVIDENCE_NO_REFERENCE, /* the trusted side has no --dump here: the picture decides */
    EVIDENCE_WITHHELD,     /* the student's --dump run failed, or its files were
                            * missing, extra, malformed or too big: the item fails */
    EVIDENCE_RAN,          /* both frames were dumped and compared */
} evidence_kind;

/* What the buffers say about a picture (buffer_evidence), in pipeline order
 * (DESIGN.md): vertices -> coverage -> depth -> overdraw -> interpolated
 * attributes -> per-sample colour -> resolved colour. */
typedef struct evidence {
    evidence_kind kind;
    char withheld[600]; /* EVIDENCE_WITHHELD: why, in a sentence for the student */
    char stage[24];     /* the first buffer that differs; "colour": every buffer
                         * matches and only the colours differ */
    const char *owner;  /* the assignment whose code makes that stage */
    bool rasterizer;    /* the stage is the rasterizer's or the resolve's */
    bool blank;         /* the student's frame covered no sample */
    char why_blank[400];
} evidence;

/* whether both frames were dumped and compared (only such evidence can clear a picture) */
static inline bool evidence_ran(const evidence *ev) { return ev->kind == EVIDENCE_RAN; }

/* ev from the two --dump runs of img (graded: its graded run, for the
 * arguments; own: the own-code link of a sealed run, NULL otherwise; flat:
 * the picture is one flat colour, so why it is blank is asked too), said
 * in o; the reference's dump from the trusted build's cache (or made now
 * and kept there), the student's in the work folder only while it is
 * compared (its files taken through sandbox_take, a buffer's when it is
 * compared); the buffer's pictures into it->buf_* unless sealed (for a
 * variant only yours and the difference: a variant's reference never
 * reaches OUT) */
void buffer_evidence(const grader *g, item *it, sbuf *o, const cJSON *img, const char *dir,
                     const char *reldir, const job *graded, const char *own, bool ref_raster,
                     bool flat, evidence *ev);

/* ev->why_blank from the counters of one more sandboxed run of img with
 * --stats (graded, own: as buffer_evidence's), for a blank picture that
 * got no buffers; left "" when the run fails or prints none */
void blank_counters(const grader *g, const cJSON *img, const job *graded, const char *own,
                    evidence *ev);

#endif
