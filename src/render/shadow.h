/*
** Cast shadows by shadow maps: for each light with `shadow true`, depth
** images of the scene's triangles seen from the light, made once a frame
** after the objects are in world space, and read by every shading model
** as the share of the light that reaches a surface point (1 lit, 0 in
** shadow).
**
**   sun    one orthographic map across the light's rays, fitted to the
**          box of every object's world vertices (square texels, a margin
**          of the filter's reach around it)
**   spot   one perspective map over its cone (cone <= SHADOW_SPOT_MAX_CONE;
**          a wider spot takes a cube map, as a point light does)
**   point  a cube map: six perspective maps of 90 degrees around the light
**          (each widened by the filter's reach, so a filter near a face's
**          border reads that face alone and no seam shows)
**
** A texel holds the nearest surface's w along the light's rays: w = -z
** (orthographic, z the depth along the rays) or w = 1/z (perspective, z
** along the face's axis). Both are affine over a triangle's image in the
** map, so triangles are filled by their plane, texel centres inside (a
** hair's tolerance on the edges, so that no crack lets light through a
** closed mesh); a texel keeps the largest w of the triangles over it,
** which is the same whatever order they come in.
**
** Reading: the receiver's w is compared with each texel's under a box
** filter shadow_filter texels wide (percentage-closer filtering: the
** box's area over lit texels, weighted by how much of each it covers).
** The receiver is taken as its tangent plane (its normal n), so each
** texel is compared with the plane's own w at that texel's centre, plus
** the bias: shadow_bias texels' worth of depth (a texel's world size at
** the receiver). A plane then never shadows itself whatever the filter's
** width; the plane's slope is followed up to SHADOW_MAX_SLOPE texel depths
** a texel (about 84 degrees from the light), past which the light is
** grazing and its diffuse term near 0 anyway.
**
** Every map depends only on the scene (the triangles in world space and
** the lights), never on the camera's window or the threads: a tile of a
** frame reads the same maps as the whole frame.
*/
#ifndef render_shadow_h
#define render_shadow_h

#include "render.h"

/* Most texels a frame's shadow maps may hold together (4 bytes each:
** 512 MiB): a cube map at shadow_resolution 4096 is 100 M. */
#define SHADOW_MAX_TEXELS (1LL << 27)
/* Widest cone (degrees) a spot's one perspective map covers; past it the
** map's texels would stretch (tan 60 = 1.7 across the axis). */
#define SHADOW_SPOT_MAX_CONE 60.0
/* Steepest receiver slope the comparison follows, in texel depths a texel. */
#define SHADOW_MAX_SLOPE 10.0f

typedef struct ShadowFace {
  float org[3];        /* orthographic: the map's corner; perspective: the light */
  float a[3], b[3];    /* unit axes across the map: s along a, t along b */
  float d[3];          /* unit axis along the rays (away from the light) */
  float rs[4], rt[4], rw[4];   /* orthographic: s, t and w as affine functions of a world
                                  point p: rs . (p, 1) ... */
  float *w;            /* n x n texels, row t of n, column s */
} ShadowFace;

typedef struct ShadowMap {
  int persp;           /* 1: perspective faces; 0: one orthographic face */
  int nfaces;          /* 1, or 6 (a cube: +x, -x, +y, -y, +z, -z) */
  int n;               /* texels a side */
  float texel;         /* orthographic: a texel's world size; perspective: its tan step */
  float centre;        /* perspective: the texel coordinate of the face's axis (n / 2) */
  float znear;         /* perspective: nearest depth drawn */
  float bias;          /* texels */
  float half;          /* half the filter's width, texels */
  ShadowFace face[6];
} ShadowMap;

/* Make the maps of every light of f whose scene light casts shadows (the
** objects in world space; f->lights set) on nthreads workers, into
** f->lights[i].shadow, and with them each object's unit triangle normals
** (RenderObject.wfnrm, the receivers' planes). Returns 1, or 0 after a
** diagnostic (the maps would hold more than SHADOW_MAX_TEXELS).
** shadow_free_all releases the maps (render_frame_free the normals). */
int shadow_prepare(const Scene *s, RenderFrame *f, int nthreads);
void shadow_free_all(RenderFrame *f);

/* The share of the light of map m that reaches world point p whose unit
** normal is nrm (either way round): 1 lit, 0 in shadow, between in the
** filter's penumbra. */
float shadow_visibility(const ShadowMap *m, const float p[3], const float nrm[3]);

/* shadow_visibility for n points (px, py, pz)[j] of object o, each on
** its triangle face[j] (whose plane, o->wfnrm, is the receiver's), into
** vis[j]; where nl[j] <= 0 (the surface faces away from the light: its
** own shadow) vis[j] is 0 and the map is not read. nl may be NULL: every
** point is read. */
void shadow_run(const ShadowMap *m, const RenderObject *o, int n, const int32_t *face, const float *px,
                const float *py, const float *pz, const float *nl, float *vis);

#endif
