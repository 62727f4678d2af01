/*
** Antialiasing of the edges between surfaces, by coverage, at one sample
** a pixel (render.h's tile pass; toon's bands are filtered in the shader,
** shade_step_aa).
**
** Where two neighbouring samples show different surfaces (an object
** against the background or against another object, one part of an
** object in front of another, a hard edge, the border of a flat-shaded
** facet, two objects passing through each other), the boundary between
** them is found in the meshes themselves: a walk from the front sample's
** triangle toward the other sample, across the triangles of its mesh,
** stops at the first edge where the surface ends (a boundary edge, an
** edge between a front and a back face: the outline) or where its shading
** jumps (a hard edge); where the surfaces pass through each other, the
** boundary is where their depth planes meet. Its crossing between the two
** sample centres and its slope give, for a straight boundary, the exact
** share of each sample's square on the other side, and that share of the
** other sample's colour is blended in. A boundary steeper than 45 degrees
** is taken by the horizontal neighbours, a flatter one by the vertical
** ones, so each is counted once.
**
** The tile pass rasterizes each tile with a one-sample apron (so the
** neighbours of its border samples are there) and shades an apron sample
** only when a blend needs its colour; the result depends only on the
** scene, never on the tiling or the threads.
*/
#ifndef render_antialias_h
#define render_antialias_h

#include <stdint.h>

#include "raster.h"
#include "render.h"
#include "shade.h"

/* Triangles a walk crosses at most before it gives up (a boundary
** between two neighbouring samples lies within a few triangles of them). */
#define AA_MAX_STEPS 16

/* What the walk needs of one object. */
typedef struct AaObject {
  const int (*tri)[3];
  const RastVert *rv;      /* per vertex, as the rasterizer projected it (aa_vertex) */
  const int32_t (*nb)[3];  /* per triangle, edge k (corners k, k + 1): the triangle across
                              it, or -1 where the surface ends or its shading jumps */
  const unsigned char *back;   /* per triangle: it faces away (RenderObject.backfacing) */
  unsigned char *away;     /* per vertex: the sides of the window it lies beyond, or NULL
                              when none does (a triangle beyond one is walked no further) */
  int32_t (*own)[3];       /* nb when made for this frame alone, or NULL */
  int clear;               /* its samples are transparent (shade ink: the canvas paints it
                              later), as the background is: between such, nothing to blend */
} AaObject;

typedef struct AaFrame {
  const RenderFrame *f;
  int nobjects;
  AaObject *objects;
} AaFrame;

/* One blend: sample at (a plane index of the tile) takes share a of the
** colour of sample from. */
typedef struct AaBlend {
  int32_t at, from;
  float a;
} AaBlend;

/* Prepare the walk's data for frame f, whose vertices the rasterizer
** projected into verts (per object, for the sample grid), for the tiles of
** f's window with an apron of apron samples: a triangle wholly away from
** them is never walked (a walk crosses one sample's step), so it gets no
** neighbours, and a tile of a big frame does not pay for the whole mesh.
** On up to nthreads threads; the same tables at any count. */
void aa_frame_init(AaFrame *af, const RenderFrame *f, RastVert *const *verts, int apron, int nthreads);
void aa_frame_free(AaFrame *af);

/* Where the shading steps at each sample of a tile: the level keys
** (ShadeRow.step_key, indexed like the tile's G-buffer planes), and the
** camera that rebuilds a sample's surface for shade_step_value. */
typedef struct AaSteps {
  const uint32_t *key;
  const ShadeView *view;
  /* the values worked out so far this tile (a sample's term is asked for
  ** by up to six pairs): value t of sample i at memo[i * SHADE_STEP_TERMS
  ** + t], valid where seen[] there is stamp (the caller's, one a tile) */
  float *memo;
  uint32_t *seen, stamp;
} AaSteps;

/* The blends of the samples of [x0, x1) x [y0, y1) (a tile) of rt, whose
** planes also hold the samples one step around it (where they are inside
** rt's rectangle, its apron), with st the steps of the shading at all of
** them (NULL: edges between surfaces only). Writes them to out (room for
** 4 (x1 - x0 + 2) (y1 - y0 + 2)), in an order that depends only on the
** tile, and returns how many. */
int aa_tile(const AaFrame *af, const RastTarget *rt, const AaSteps *st, int x0, int y0, int x1,
            int y1, AaBlend *out);

/* Where aa_apply gathers each sample's blends: planes indexed like the
** tile's (zero between calls), and room for a list of samples. */
typedef struct AaScratch {
  float *sum;        /* the shares a sample takes */
  float *acc;        /* 4 a sample: the colours they bring, weighted */
  int *touched;
} AaScratch;

/* Apply blends b[0..n-1] to colours col (nc floats a sample, indexed
** like the planes): each sample at becomes its colour less the shares,
** plus each share of its from's colour (the shares are scaled down to add
** up to 1 at most), all read before any is written. With unassociated
** (nc == 4, alpha not premultiplied), the colours mix by their alpha. */
void aa_apply(const AaBlend *b, int n, float *col, int nc, int unassociated, AaScratch *sc);

#endif
