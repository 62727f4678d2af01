/*
** The sheet under the whole image (Yeh ch. 6: "a Xuan paper image ... is
** put on the bottom layer"; `output { sheet ...; }`): procedural xuan paper
** by default, tileable and seeded (pulp mottling, a fine tooth, and
** fibres), or an image that repeats; with no sheet, the background: a
** flat colour, a vertical gradient or an image scaled to the frame. Every texel of the tile that repeats over the image has a colour
** and an absorbency (about 1 on average: where it is higher, ink lands
** darker, so washes show the grain; the diffusion runs further there).
*/
#ifndef render_paper_h
#define render_paper_h

#include <stddef.h>
#include <stdint.h>

#include "../scene/scene.h"

/* Side of the procedural tile at scale 1, in pixels. */
#define PAPER_TILE 384
/* Texels of the flat background's tile (one colour). */
#define PAPER_FLAT_RUN 256
/* Most texels a tile may have (an image sheet at a large scale). */
#define PAPER_MAX_TEXELS (4096LL * 4096LL)

typedef struct Paper {
  int width, height;     /* the tile; pixel (x, y) shows texel (x mod width, y mod height) */
  float *display;        /* 3 a texel: sRGB display values */
  float *linear;         /* 3 a texel: the same in linear light (a sheet's: NULL
                            until paper_fill_linear) */
  uint8_t *code;         /* 3 a texel: the display values as 8-bit codes, rounded */
  float *absorb;         /* 1 a texel; NULL: 1 everywhere (a flat colour) */
  float alpha;           /* 1, or the alpha of a flat background */
} Paper;

/* The paper of sheet sh, or (sh->texture NULL) the flat background.
** An image sheet's path is relative to the folder of the file that names
** it. Returns 1, or 0 with the reason in err (an image that cannot be read,
** a tile over PAPER_MAX_TEXELS). */
int paper_create(const SceneSheet *sh, Color background, Paper *p, char *err, size_t errlen);
/* The paper of output o's gradient or image background (o->nstops >= 2 or
** o->backdrop) for a frame of width x height pixels: a gradient is a
** column of rows from the first stop at the top row to the last at the
** bottom row, interpolated in linear light; an image is scaled to the
** frame, filtered over each pixel's footprint (trilinear, imagemap.h),
** over black. Both are opaque. Returns 1, or 0 with the reason in err (an
** image that cannot be read, a frame over PAPER_MAX_TEXELS for an image). */
int paper_backdrop(const SceneOutput *o, int width, int height, Paper *p, char *err, size_t errlen);
void paper_free(Paper *p);

/* Work out p's linear values, if they are not yet (a sheet's wait for a
** composite that reads them: most frames go from the codes alone). */
void paper_fill_linear(Paper *p);

/* The texel index of pixel (x, y) (x, y >= 0). */
static inline size_t paper_texel(const Paper *p, int x, int y) {
  return (size_t)(y % p->height) * p->width + (size_t)(x % p->width);
}

#endif
