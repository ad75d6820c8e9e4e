/* grade_images.h — raster101-grade's verdict on a picture
 * (tests/grading/grade_*.c): the program's sandboxed run (grade_run.h's
 * image_job) compared with the reference as the rubric says
 * (common/app/ras_compare.h, thresholds from the catalogue), the buffers'
 * evidence first (grade_evidence.h), then what the picture itself shows.
 */
#ifndef RAS_GRADING_GRADE_IMAGES_H
#define RAS_GRADING_GRADE_IMAGES_H

#include "grade_base.h"
#include "grade_priv.h"
#include "ras_compare.h"
#include "ras_error.h"
#include "ras_image.h"

#include <stddef.h>

/* one image run graded as an item of a; whether it matched */
bool grade_image(const grader *g, assignment_result *a, const cJSON *img, const char *dir,
                 const char *reldir, const char *crash_hint, const job *j, bool sealed, bool whole);
/* the comparison the rubric asks of img (the catalogue's thresholds) */
bool image_options(const grader *g, const cJSON *img, ras_compare_kind *kind,
                   ras_compare_options *opt, ras_error *err);
/* the picture a student's program wrote (taken through a trusted copy at
 * `taken`, removed again): a regular PNG of the reference's size, or NULL */
ras_image *load_student_image(const char *path, const char *taken, const char *ref_path,
                              ras_error *err);
/* Which causes a defect's line may name, by what is known of the stages
 * that drew the picture. */
typedef enum defect_voice {
    DEFECT_PATTERN,   /* the pattern only: the buffers acquit the rasterizer, or
                       * the run's rasterizer is the reference's */
    DEFECT_RASTER,    /* the rasterizer or resolve (the student's, not acquitted) */
    DEFECT_SHADING,   /* the buffers up to the rasterizer match: the shader's colours */
    DEFECT_WIREFRAME, /* lines only: no surfaces, no depth test (hw1) */
} defect_voice;
/* a dark seam, a wrong line, speckle: one line each into o; whether any */
bool image_defects(sbuf *o, const ras_image *expected, const ras_image *got, defect_voice voice);
/* whether img is judged as a wireframe (a program with no depth test) */
bool image_is_wireframe(const cJSON *img);
/* the variants' reference renders a batch's pictures need and the cache
 * (BUILD/grade-cache/references) lacks, as jobs for the batch; how many */
int reference_jobs(const grader *g, const cJSON *images, const job *runs, int n_img, job *jobs, int max);
/* after the batch: the renders that succeeded kept in the cache */
void reference_jobs_done(const grader *g, job *jobs, int n);
/* judging ahead (in a child, beside the others): grade_image then gives up
 * rather than start a counted run or remove a sealed run's log */
void images_speculate(bool on);
/* whether the picture judged ahead gave up (judge it again, in order) */
bool images_gave_up(void);
/* true, and the picture given up, when judging ahead: the caller was about
 * to start something counted (the attribution's renders) */
bool images_speculation_stops(void);
/* where a variant's reference, rendered at grading time, is kept */
void variant_reference_path(const grader *g, const char *dir, const char *id, const char *name,
                            char *buf, size_t size);

#endif
