/*
** The Chinese-painting front end of the line stage (Yeh, 003 ch. 2.5 and
** 3.3), the alternative to the reference image, tracing and graph linking
** of 001 (`lines { visibility endpoints; }`, the default for brush
** strokes):
**
**   culling  each important edge's two projected ends are tested against
**            the meshes' depth (the reference test of edgeref.h, which
**            decides every point of the edge's walk; culling reads only
**            the ends and the bisection's points): both pass, it is kept
**            whole; neither, it is dropped; one, the edge is bisected
**            toward its visible end, at most cull_steps times (or until
**            the boundary is bracketed within half a pixel), and the part
**            from the visible end to the last point that passed is kept.
**   linking  per object, a stroke starts from the first unused piece (in
**            edge id order) and grows at its end, then at its start, by
**            an unused piece with an end within link_distance pixels of
**            the stroke's end, adding that piece's other end; each piece
**            is used once. Of several that close, the one that turns the
**            stroke least wins (ties: the nearer, then the lower id). A finished
**            stroke runs so that, weighted by length, its pieces' front
**            faces lie mostly on its left as seen on the screen: the
**            object's outline is drawn counter-clockwise.
**
** Output is the same LinePolys the graph linker makes, so every stroke
** kind draws it.
*/
#ifndef render_silhouette_h
#define render_silhouette_h

#include "edgeref.h"
#include "link.h"

/* A visible piece of an important edge, in reference pixels, ordered so
** that the face that decides its side (the front face of a silhouette,
** the one face of a boundary) is on its left; side = 0 when no face does
** (a crease between two front faces), and then it runs v[0] -> v[1]. */
typedef struct SilPiece {
  float x0, y0, x1, y1;
  int obj;
  int side;
} SilPiece;

typedef struct SilPieces {
  int n, cap;
  SilPiece *p;             /* in edge id order */
  int tested, whole, cut, dropped;   /* edges tested, kept whole, bisected, hidden */
} SilPieces;

/* Which part of edge id's span in ref passes the endpoint test: returns 0
** (hidden: neither end passes, or the span is off screen), 1 (both ends
** pass: [0, 1]) or 2 (bisected: [*t0, *t1] along the span, the visible end
** first). steps bounds the bisection (0 drops a half-hidden edge). */
int sil_cull_span(const LineRef *ref, int id, int steps, float *t0, float *t1);

/* The visible pieces of the important edges of edges (their spans and
** visibility in ref, made by line_ref_build), each object's cull_steps
** from its lines. Free with sil_pieces_free. */
void sil_cull(SilPieces *out, const LineRef *ref, const LineEdges *edges);
void sil_pieces_free(SilPieces *p);

/* Link pieces into strokes (appended to out, objects in order, strokes in
** the order of their first piece); an object's link distance is its
** lines' link_distance times px_scale (output to reference pixels). */
void sil_link(LinePolys *out, const SilPieces *pieces, const LineEdges *edges, double px_scale);

#endif
