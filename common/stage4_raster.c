/* stage4_raster.c — names for the stage-4 options (the rasterizers themselves
 * are the hw2 student's and the reference's; see stage4_raster.h). */
#include "stage4_raster.h"

#include "ras_names.h"

const char *ras_aa_mode_name(ras_aa_mode aa) { return ras_name_of(&ras_names_aa, (int)aa); }
