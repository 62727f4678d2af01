/*
** The ukiyo-e colour layer (001 sections 2.2.1 and 2.2.2): a style's
** `pattern { }` and `noise { }` laid over whatever its shading model gave,
** per object, in screen space. A sample at output pixel position x (y
** alike) reads texel
**   u = (x - x_centre) * wpp / texel + u_0
** where x_centre is the object's centre on screen and wpp the scene units
** a pixel spans at the centre's depth: the texture moves with the centre
** (no shower door) and keeps its size against the object as it comes
** closer or goes away, but does not turn with it (printed flat, as the
** paper intends). texel is the scene units one texel covers (the style's
** `scale` over the tile's width); u_0 puts the pattern's middle on the
** centre and gives each object's noise its own seeded place in the tile.
** The pattern goes first (over or multiplied, its opacity and the image's
** alpha), then the noise is added on top, in a display-like space (the
** square root of linear light, close to sRGB) so a grain shows as much on a
** dark colour as on a light one.
*/
#ifndef render_screentex_h
#define render_screentex_h

#include "noise.h"
#include "shade.h"

/* The procedural noise's tile: texels a side, and lattice cells a side at
** its first octave (SCENE_MAX_NOISE_OCTAVES octaves fit it). */
#define SCREENTEX_NOISE_SIZE 256
#define SCREENTEX_NOISE_CELLS 8

/* A style's layer, set up once a frame. */
typedef struct ScreenTex {
  int has_noise, has_pattern;
  NoiseTile noise;
  float noise_gain;            /* 2 * amount: texel - mean of +-0.5 moves a channel +-amount */
  float noise_texel;           /* scene units a noise texel covers */
  NoiseTile pattern;
  float pattern_texel;
  float opacity;
  int blend;                   /* PatternBlend */
  int nramp;
  float ramp[SCENE_MAX_PATTERN_COLORS][3];           /* colour mapping: grey 0..1 across these, linear */
} ScreenTex;

/* One object's mapping: texel (u, v) of sample (sx, sy) of the sample grid
** is (u0 + k sx, v0 + k sy), read from the given level. */
typedef struct ScreenTexMap {
  float u0, v0, k;
  int level;
} ScreenTexMap;

typedef struct ScreenTexObject {
  ScreenTexMap noise, pattern;
} ScreenTexObject;

typedef struct ScreenTexFrame {
  ScreenTex *styles;           /* per frame style */
  ScreenTexObject *objects;    /* per frame object */
} ScreenTexFrame;

/* Set up the layers of f's styles (reading pattern and noise images, baking
** procedural noise) and every object's mapping (its centre must be set:
** shade_centre_init); styles without noise or pattern get none. Returns 1,
** or 0 after a diagnostic at the image's property (unreadable, empty). */
int screentex_prepare(RenderFrame *f);
void screentex_free(RenderFrame *f);

/* Lay o's layer over samples k0..k1-1 of r, colours at rgb[k * stride]
** (linear). o->tex must be set. */
void screentex_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb, int stride);

#endif
