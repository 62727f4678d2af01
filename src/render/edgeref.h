/*
** The reference image (001 §2.1.2): every important edge drawn with its own
** id into an edge-id buffer, depth-tested against all meshes. The meshes
** are drawn at their true depth; an edge compares against the nearest
** surface at each pixel pushed away from the camera by a slope-scaled
** offset, as a polygon offset (LINE_DEPTH_OFFSET_BASE + depth_offset
** reference pixels of that surface's depth slope), when the surface is
** turned the same way (toward or away from the viewer) as one of the
** edge's faces, and by only LINE_DEPTH_EPS when it is turned the other
** way. So an edge never loses to the faces it lies on (no stitching), and
** an edge on the far side of an object does not leak out for a pixel or
** two from behind a silhouette or a corner, as one global offset lets it.
** Where edges meet, the nearer wins, and at equal depth one with a face
** toward the viewer. The set of ids that survive is recorded as the edges
** are drawn (per-id pixel counts), so the analysis never scans the image.
**
** Depth here is "nearness", 1 - depth of camera.h (1 at the near plane,
** 0 at the far plane), so a zeroed buffer is empty.
*/
#ifndef render_edgeref_h
#define render_edgeref_h

#include <stdint.h>

#include "edges.h"

/* The polygon-offset factor, in reference pixels of a surface's depth
** slope, before the style's depth_offset (default 0) is added to it: an
** edge pixel's centre lies up to about a pixel off the edge's exact line. */
#define LINE_DEPTH_OFFSET_BASE 1.5
/* Constant part of the mesh offset, in nearness units (a few float ulps at
** depth 1). */
#define LINE_DEPTH_EPS 1e-6f

/* An important edge's line in the reference image: its projected ends,
** clipped to the near plane and the image, ordered from the mesh edge's
** v[0] to v[1]. */
typedef struct LineSpan {
  float x0, y0, x1, y1;        /* reference pixels */
  float n0, n1;                /* nearness at the ends */
  int px0, py0, px1, py1;      /* the pixels of the ends (the walk goes between them) */
  int nsteps;                  /* pixels of the walk; 0 = off screen */
  unsigned char real0, real1;  /* the end is the vertex itself, not a clip point */
} LineSpan;

/* The reference image is stored in tiles of LINE_REF_TILE x LINE_REF_TILE
** pixels, and only in the tiles some edge's walk crosses: depth is only
** ever read where an edge is drawn, and ids only there or a search width
** away (a pixel of a tile without storage reads as empty). So the meshes
** are rasterized into a fraction of the image, and memory and time follow
** the length of the lines, not the resolution. Within those tiles the
** meshes are rasterized only at the pixels of the walks (the only depth
** read); the other pixels stay empty, as surface ids read as 0 anyway. */
#define LINE_REF_TILE_BITS 3
#define LINE_REF_TILE (1 << LINE_REF_TILE_BITS)
#define LINE_REF_TILE_PX (LINE_REF_TILE * LINE_REF_TILE)

typedef struct LineRef {
  int width, height;           /* the reference image */
  int tw, th;                  /* tiles across and down */
  int *tile;                   /* tw * th: storage block of each tile, -1 = none */
  int nblocks;
  float *near;                 /* nblocks * LINE_REF_TILE_PX: nearness of the closest
                                  surface (at walk pixels) or edge, 0 = none */
  uint32_t *id;                /* the same layout: edge id drawn, 0 = none; while
                                  building, LINE_REF_TRI | k marks surface triangle k */
  int nids;                    /* important edges (ids 1..nids) */
  LineSpan *span;              /* per id - 1 */
  int *count;                  /* per id - 1: pixels holding the id after drawing */
  int nvisible;
  int *visible;                /* the ids present in the image, ascending */
} LineRef;

/* Build the reference image of edges (whose vertices are already projected
** into a width x height image) over the meshes of objs, using threads
** workers (>= 1). Free with line_ref_free. */
void line_ref_build(LineRef *ref, const LineEdges *edges, const LineObject *objs, int width,
                    int height, int threads);
void line_ref_free(LineRef *ref);

/* The pixel of step i (0 <= i < s->nsteps) of the walk along s: a
** Bresenham line from (px0, py0) to (px1, py1), stepping one pixel along
** the dominant axis each time. Tracing calls it; drawing steps through the
** same pixels in order without its division (LineSpanWalk below), so both
** visit the same pixels. */
static inline void line_span_step(const LineSpan *s, int i, int *x, int *y) {
  int dx = s->px1 - s->px0, dy = s->py1 - s->py0;
  int ax = dx < 0 ? -dx : dx, ay = dy < 0 ? -dy : dy;
  if (ax >= ay) {   /* x dominant: y moves by round(i * dy / dx) */
    *x = s->px0 + (dx < 0 ? -i : i);
    int off = ax ? (int)((2LL * i * ay + ax) / (2LL * ax)) : 0;
    *y = s->py0 + (dy < 0 ? -off : off);
  } else {
    *y = s->py0 + (dy < 0 ? -i : i);
    int off = (int)((2LL * i * ax + ay) / (2LL * ay));
    *x = s->px0 + (dx < 0 ? -off : off);
  }
}

/* Walking a span: the pixels line_span_step gives for i = 0, 1, ..., one
** after the other, with Bresenham's error term in place of its division.
** The offset along the minor axis at step i is floor((2 i minor + major) /
** (2 major)); err is that numerator less 2 major per unit of offset so far,
** so it stays in [0, 2 major) and a step adds at most one unit.
**
**   LineSpanWalk w;
**   line_span_walk_start(&w, s);
**   for (int i = 0; i < s->nsteps; i++, line_span_walk_next(&w)) ... w.x, w.y ... */
typedef struct LineSpanWalk {
  int x, y, sx, sy;
  int xmajor;           /* x is the dominant axis */
  int major2, minor2;   /* twice the steps along each axis */
  int err;
} LineSpanWalk;

static inline void line_span_walk_start(LineSpanWalk *w, const LineSpan *s) {
  int dx = s->px1 - s->px0, dy = s->py1 - s->py0;
  int ax = dx < 0 ? -dx : dx, ay = dy < 0 ? -dy : dy;
  w->x = s->px0;
  w->y = s->py0;
  w->sx = dx < 0 ? -1 : 1;
  w->sy = dy < 0 ? -1 : 1;
  w->xmajor = ax >= ay;
  w->major2 = 2 * (w->xmajor ? ax : ay);
  w->minor2 = 2 * (w->xmajor ? ay : ax);
  w->err = w->major2 / 2;
}

static inline void line_span_walk_next(LineSpanWalk *w) {
  w->err += w->minor2;
  int up = w->err >= w->major2;
  if (up) w->err -= w->major2;
  if (w->xmajor) {
    w->x += w->sx;
    if (up) w->y += w->sy;
  } else {
    w->y += w->sy;
    if (up) w->x += w->sx;
  }
}

/* Tag of a pixel of LineRef.id that holds a surface triangle, not an edge. */
#define LINE_REF_TRI 0x80000000u

/* Index of pixel (x, y) in ref's near and id, or -1 when it has no storage
** (outside the image or in a tile no edge crosses). */
static inline long line_ref_at(const LineRef *ref, int x, int y) {
  if (x < 0 || y < 0 || x >= ref->width || y >= ref->height) return -1;
  int b = ref->tile[(y >> LINE_REF_TILE_BITS) * ref->tw + (x >> LINE_REF_TILE_BITS)];
  if (b < 0) return -1;
  return (long)b * LINE_REF_TILE_PX + ((y & (LINE_REF_TILE - 1)) << LINE_REF_TILE_BITS) +
         (x & (LINE_REF_TILE - 1));
}

/* The edge id at pixel (x, y) of ref (0 where no edge is). */
static inline uint32_t line_ref_id(const LineRef *ref, int x, int y) {
  long at = line_ref_at(ref, x, y);
  if (at < 0) return 0;
  uint32_t v = ref->id[at];
  return v & LINE_REF_TRI ? 0 : v;
}

/* An empty width x height reference image with storage in every tile and
** no edges (tests fill id through line_ref_at). Free with line_ref_free. */
void line_ref_blank(LineRef *ref, int width, int height);

/* Rasterize the meshes of objs (depth only, no offset) into a width x
** height buffer of object indices (-1 = background), nearest wins; the
** vertices are those of edges (projected at that size). For the SVG's
** filled regions. The caller frees the result. */
int32_t *line_object_ids(const LineEdges *edges, const LineObject *objs, int width, int height,
                         int threads);

#endif
