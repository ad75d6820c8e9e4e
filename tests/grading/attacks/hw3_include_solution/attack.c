#include "solution/shading.c"
