/*
** Image threshold textures (002 section 3.1): an image read through
** OpenImageIO, made grey, reduced to a mip pyramid, and equalized by CLAHE
** (clahe.h) at every level of the pyramid, so each level has the
** near-uniform distribution of thresholds a level blurred by the reduction
** alone would lose (the paper's Figure 3). Sampled bilinearly within a
** level and between the two levels nearest the footprint (trilinear).
**
** Grey is Rec. 601 luma (0.299 R + 0.587 G + 0.114 B) of the sRGB codes,
** as OpenCV's cvtColor makes it; alpha is ignored. Level k + 1 is the 2 x 2
** mean of level k's grey (before equalization; an odd side's last row or
** column averages what there is), down to one texel. Each level is cut into
** round(side / window) regions a side (at least one): the window stays the
** same number of texels at every level.
**
** CLAHE makes a level's distribution only near uniform: the bilinear blend
** of four regions' mappings pulls values toward the middle (on skimage's
** photographs, 16-bin histograms within 5-50 % of flat, worse with smaller
** windows and for images of few grey levels), and a constant shade would
** then not cover its own share of the area. So each equalized level (its
** blend kept unrounded) is finally ranked as a whole, ties in scan order,
** and a texel's threshold is its rank's place in [0, 1): exactly uniform,
** with CLAHE's local order, and so its texture, kept.
**
** Preprocessing happens once per image: the textures live in a cache for
** the whole run (every object, style and frame of an animation share
** them), keyed by path, window, clip, and the file's size and
** modification time.
**
** Sampling keeps the distribution: interpolating thresholds would pull
** them toward the middle (a bilinear blend of unrelated neighbours is no
** longer uniform), so the filtered read is percentage-closer: the
** trilinear filter's eight texels (four in each of the two levels) are
** thresholded one by one and their results weighted; the unfiltered read
** is the nearest texel of the nearest level.
*/
#ifndef render_texture_h
#define render_texture_h

#include <stddef.h>
#include <stdint.h>

/* Levels a pyramid may have: 2^25 texels a side is past any readable image. */
#define TEXTURE_MAX_LEVELS 26

typedef struct TextureLevel {
  int w, h;
  uint16_t *texels;            /* thresholds in 65536ths, rows of w */
} TextureLevel;

typedef struct ThresholdTexture {
  int nlevels;                 /* level 0 is the image's size */
  TextureLevel level[TEXTURE_MAX_LEVELS];
} ThresholdTexture;

/* The threshold texture of the image at path with CLAHE window (texels a
** side, >= 1) and clip (OpenCV's units; 0 = none), from the cache or made
** now. NULL, with the reason in err, when the image cannot be read.
** Thread-safe. The texture stays valid until texture_cache_clear. */
const ThresholdTexture *texture_threshold(const char *path, double window, double clip, char *err,
                                          size_t errlen);

/* One level's thresholds from its w x h grey codes: CLAHE with the window
** (regions of about window texels a side), then ranked, into out (w * h).
** texture_build does this for every level. */
void texture_equalize_level(const uint8_t *grey, int w, int h, double window, double clip,
                            uint16_t *out);

/* Make a threshold texture from a w x h 8-bit grey image (the cache's
** worker, public for tests and benchmarks); texture_free releases it. */
ThresholdTexture *texture_build(const uint8_t *grey, int w, int h, double window, double clip);
void texture_free(ThresholdTexture *t);

/* Free every cached texture (at exit, or between tests). */
void texture_cache_clear(void);

/* The four texels of level k around texture coordinates (u, v) and their
** bilinear weights: thresholds q[4] in [0, 1) and weights w[4] summing to
** 1. The image repeats every unit of u and v (u to the right, v up: the
** image's first row is at the top). */
void texture_level_taps(const ThresholdTexture *t, int k, float u, float v, float q[4], float w[4]);

/* The threshold of the texel of level k under (u, v). */
float texture_level_nearest(const ThresholdTexture *t, int k, float u, float v);

/* The level of detail of a footprint that spans rate level-0 texels
** (log2 of it, clamped to the pyramid), split into the two levels around
** it and the weight of the coarser: the trilinear filter's pair. */
void texture_lod(const ThresholdTexture *t, float rate, int *k0, int *k1, float *w1);

#endif
