/* class_view.h — what raster101-class's two files share: class_tool.c (the
 * class view, main) and class_roster.c (the LMS gradebooks). */
#ifndef RAS_GRADING_CLASS_VIEW_H
#define RAS_GRADING_CLASS_VIEW_H

#include <stdbool.h>

/* PATH written whole or not at all (ras_io_write_atomic); false, said on
 * stderr, when it could not be. */
bool class_write_whole(const char *path, const char *text);

/* raster101-class roster OUT ROSTER.csv (class_roster.c): the exit status. */
int roster_main(const char *out, const char *roster_path);

#endif
