/* isoterra — embedded 6x8 bitmap font (printable ASCII), drawn for this
 * project: 5x7 glyphs in 6x8 cells. */
#ifndef ISOTERRA_FONT_H
#define ISOTERRA_FONT_H

#include <stdint.h>

#define FONT_W 6
#define FONT_H 8
#define FONT_FIRST 32
#define FONT_COUNT 95 /* ' ' .. '~' */

/* Row bitmaps, top row first; bit 4 is the leftmost of the 5 glyph columns
 * (column 5 of the cell is spacing).  Characters outside ' '..'~' map to '?'. */
const uint8_t *font_glyph(int c);

#endif
