/*
** Image maps: a style's `texture "file"` laid on an object's (u, v), its
** colour taking the place of the style's `base` in every shading model
** that has one (docs/language.md, Styles).
**
** The image is read through the image reader (any format OpenImageIO
** reads; 8- and 16-bit codes are sRGB and become linear, float images are
** linear already), made RGBA (grey and grey-alpha spread to the colour
** channels; no alpha is 1), and reduced to a mip pyramid in linear light:
** level k + 1 is the 2 x 2 mean of level k (an odd side's last row or
** column averages what there is), down to one texel. A sample is
** bilinear within a level and linear between the two levels around its
** footprint (trilinear): the footprint is the longer of the texture
** coordinates' steps for one output pixel along x and along y, in level-0
** texels, and its level of detail log2 of that. The image repeats every
** unit of u and v; u runs to the right and v up (the image's first row is
** at the top, at v = 1). Alpha lays the image over the base colour: the
** colour is base (1 - a) + texel a (the texel's colour unassociated).
*/
#ifndef render_imagemap_h
#define render_imagemap_h

#include <stddef.h>

/* Levels a pyramid may have: 2^25 texels a side is past any readable image. */
#define IMAGEMAP_MAX_LEVELS 26

typedef struct ImageMapLevel {
  int w, h;
  float *rgba;                 /* w x h texels, rows top first, linear RGBA */
} ImageMapLevel;

typedef struct ImageMap {
  int nlevels;                 /* level 0 is the image's size */
  ImageMapLevel level[IMAGEMAP_MAX_LEVELS];
} ImageMap;

/* The map of the image at path, or NULL with the reason in err. Free with
** imagemap_free. */
ImageMap *imagemap_load(const char *path, char *err, size_t errlen);

/* A map from w x h linear RGBA texels (copied), for tests. */
ImageMap *imagemap_from_rgba(const float *rgba, int w, int h);
void imagemap_free(ImageMap *m);

/* The filtered colour at (u, v) whose steps for one output pixel are
** (dudx, dvdx) along x and (dudy, dvdy) along y, into rgba. */
void imagemap_sample(const ImageMap *m, float u, float v, float dudx, float dvdx, float dudy, float dvdy,
                     float rgba[4]);

/* Level k alone, bilinear, at (u, v). */
void imagemap_bilinear(const ImageMap *m, int k, float u, float v, float rgba[4]);

#endif
