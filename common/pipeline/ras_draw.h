/* ras_draw.h — lines into a framebuffer (hw1's wireframe; given, not a TODO).
 *
 * Bresenham between screen points (rounded to the nearest pixel), clipped to
 * the screen so any endpoints are safe (off-screen, huge, NaN: nothing bad).
 * Writes sample 0 of each pixel it touches; no depth test.
 */
#ifndef RAS_DRAW_H
#define RAS_DRAW_H

#include "ras_framebuffer.h"

/* Returns the number of pixels written. */
long ras_draw_line(ras_framebuffer *fb, vec2s a, vec2s b, vec3s color);

#endif
