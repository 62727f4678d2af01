/*
** Contrast-limited adaptive histogram equalization (CLAHE; Zuiderveld,
** Graphics Gems IV), the preprocessing that turns an image into a threshold
** texture with a near-uniform, locally homogeneous distribution of values
** (002 section 3.1, after Veryovka and Buchanan 2000).
**
** The image is cut into tiles_x x tiles_y contextual regions; each
** region's histogram is clipped at clip times its mean bin count (the
** excess spread over all bins), and its cumulative sum becomes the region's
** mapping; each pixel is mapped by the four nearest regions' mappings,
** blended bilinearly by its distance to their centres. The tiling, the
** clipping (clip in OpenCV's units, 0 = none), the padding of an image the
** tiles do not divide (mirrored, the edge pixel not repeated) and the
** interpolation follow OpenCV's cv::createCLAHE, so the outputs agree (the
** benchmark compares them).
*/
#ifndef render_clahe_h
#define render_clahe_h

#include <stdint.h>

/* Equalize the w x h 8-bit image src (rows of w bytes) into dst (the same
** size; not src). tiles_x, tiles_y >= 1, each at most the side it cuts. */
void clahe_apply(const uint8_t *src, int w, int h, int tiles_x, int tiles_y, double clip,
                 uint8_t *dst);

/* The same, each pixel's blend of the four mappings kept unrounded (0 to
** 255) in dst (w * h floats). */
void clahe_apply_float(const uint8_t *src, int w, int h, int tiles_x, int tiles_y, double clip,
                       float *dst);

#endif
