/*
** Tileable noise and wrapping texture tiles, for grain laid over a picture
** in screen space (ukiyo-e's pseudo-uniform colour, 001 section 2.2.1; a
** paper sheet's fibres):
**   NoiseFbm   fractal gradient noise, periodic over the unit square: at
**              each octave a lattice of cells * 2^k cells a side whose unit
**              gradients are drawn from the seeded generator (rng.h), so the
**              same seed gives the same noise on every machine
**   NoiseTile  a w x h texture of 1 or 3 channels (baked from a NoiseFbm, or
**              an image) read with wrap-around: bilinear, from a chain of
**              box-filtered levels so a far object reads a prefiltered one
** Texture coordinates are in level-0 texels; a tile repeats every w x h.
*/
#ifndef render_noise_h
#define render_noise_h

#include <stdint.h>

#include "../io/image.h"

/* Most octaves a NoiseFbm adds (its finest lattice has cells * 2^(n-1) cells). */
#define NOISE_MAX_OCTAVES 8
/* Most levels of a tile's chain (a 2^15 texel side halves down to 1). */
#define NOISE_MAX_LEVELS 16

typedef struct NoiseFbm {
  int cells;                   /* lattice cells a side at the first octave (>= 1) */
  int octaves;                 /* 1 .. NOISE_MAX_OCTAVES */
  float gain;                  /* amplitude of each octave over the one before */
  float *grad[NOISE_MAX_OCTAVES];   /* per octave: (cells 2^k)^2 unit gradients, x then y */
} NoiseFbm;

/* Draw n's lattices from seed. gain is usually 0.5. Free with noise_fbm_free. */
void noise_fbm_init(NoiseFbm *n, int cells, int octaves, float gain, uint64_t seed);
void noise_fbm_free(NoiseFbm *n);

/* The noise at (x, y) of the unit square (periodic: x and x + 1 give the
** same value), about -1 .. 1, mean about 0. */
float noise_fbm_eval(const NoiseFbm *n, float x, float y);

/* A coordinate's place on a lattice: its cell's sides and how far across
** the cell it lies. A grid of points (a frame's pixels) takes each
** column's and each row's once, then the noise at each point from them. */
typedef struct NoiseAxis { int i0, i1; float t, fade; } NoiseAxis;

/* Coordinate v of the unit square on n's first lattice. */
void noise_axis(const NoiseFbm *n, float v, NoiseAxis *a);
/* n's first octave at the point of axes ax and ay: for n of one octave,
** noise_fbm_eval there, to the bit. */
float noise_fbm_axes(const NoiseFbm *n, const NoiseAxis *ax, const NoiseAxis *ay);

typedef struct NoiseTile {
  int channels;                /* 1 (grey) or 3 (RGB); a 4th, alpha, when has_alpha */
  int has_alpha;
  int levels;                  /* at least 1 */
  int w[NOISE_MAX_LEVELS], h[NOISE_MAX_LEVELS];
  float *texel[NOISE_MAX_LEVELS];   /* level k: w[k] * h[k] * (channels + has_alpha) */
  float mean[4];               /* level 0's mean of each channel */
} NoiseTile;

/* A size x size single-channel tile of n, scaled so its values fill
** [0, 1] around a mean of 0.5 (the same for every seed's spread). */
void noise_tile_bake(NoiseTile *t, const NoiseFbm *n, int size);

/* A tile of img's texels (linear values): grey images give 1 channel,
** colour images 3, and a 2nd or 4th channel is kept as alpha. */
void noise_tile_from_image(NoiseTile *t, const Image *img);
void noise_tile_free(NoiseTile *t);

/* The level to read when a sample spans texels_per_sample level-0 texels:
** the finest whose texels are at least that large (0 when magnified). */
int noise_tile_level(const NoiseTile *t, float texels_per_sample);

/* Bilinear value of level at (u, v) in level-0 texels, wrapping, into out
** (channels + has_alpha floats). Texel (i, j) is centred at (i + 0.5, j + 0.5). */
void noise_tile_sample(const NoiseTile *t, int level, float u, float v, float *out);

/* n bilinear reads of a one-channel tile along a row: out[k] is
** noise_tile_sample at (u0 + k du, v), du >= 0, up to rounding. */
void noise_tile_row(const NoiseTile *t, int level, float u0, float du, float v, int n, float *out);

#endif
