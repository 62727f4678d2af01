/*
** Display (sRGB-encoded) values and linear light, as floats in [0, 1].
** Where a paper gives its constants and formulas for display values (the
** ink quantities of Yeh's ch. 5.2, Mitani's colours), sumi mixes in display
** space and goes back to linear with these.
*/
#ifndef render_display_h
#define render_display_h

/* The sRGB curve, exact: linear -> display (clamped to [0, 1]; NaN -> 0). */
float display_from_linear(float c);
/* Display -> linear through a table (4096 steps over [0, 1], linear in
** between): a powf per channel per pixel was most of a frame. Values above
** 1 follow the curve exactly; NaN and values below 0 give 0. */
float display_to_linear(float c);

#endif
