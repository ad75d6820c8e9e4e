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

/* What the buffers say about a picture (buffer_evidence), in pipeline order
 * (DESIGN.md): vertices -> coverage -> depth -> overdraw -> interpolated
 * attributes -> per-sample colour -> resolved colour. */
typedef struct evidence {
    bool ran;          /* both frames were dumped and compared */
    char stage[24];    /* the first buffer that differs; "colour": every buffer
                        * matches and only the colours differ */
    const char *owner; /* the assignment whose code makes that stage */
    bool rasterizer;   /* the stage is the rasterizer's or the resolve's */
    bool blank;        /* the student's frame covered no sample */
    char why_blank[400];
} evidence;

/* ev from the two --dump runs of img (graded: its graded run, for the
 * arguments; own: the own-code link of a sealed run, NULL otherwise), said
 * in o; the buffer's pictures into it->buf_* unless sealed */
void buffer_evidence(const grader *g, item *it, sbuf *o, const cJSON *img, const char *dir,
                     const char *reldir, const job *graded, const char *own, bool ref_raster,
                     evidence *ev);

#endif
