/*
** The G-buffer: what the rasterizer saw at every sample of the frame, in
** plain planes (one array per quantity, row-major, top row first, index
** y * width + x). The shading stage and the line stages read it; nothing in
** it points back into the rasterizer.
**
** Resolution: the G-buffer holds samples, not output pixels: width and
** height are the output size times `samples` (the N of `samples N`), and
** output pixel (i, j) is the box-filtered average of samples
** (N i .. N i + N - 1, N j .. N j + N - 1). camera is set up for the
** sample grid, so camera_to_pixel() gives sample coordinates.
**
** Visibility planes (always present):
**   depth   window depth in [0, 1] (camera.h); GBUF_NO_DEPTH where nothing
**           was drawn (the background).
**   object  index of the object drawn there (RenderFrame.objects, which is
**           Scene.objects in order), GBUF_NO_ID for the background.
**   face    index of the triangle in that object's Mesh (mesh->tri[face]);
**           mesh->tri_face[face] is the source face (patch or polygon).
**   bary    perspective-correct barycentric coordinates (b1, b2) of the
**           sample in that triangle: the surface point is
**           (1 - b1 - b2) v0 + b1 v1 + b2 v2 for the vertices tri[face][0..2].
** Attribute planes (NULL until render_gbuffer_attributes() fills them, for
** AOVs and for stages that want them):
**   normal    world-space unit shading normal, turned toward the viewer on
**             back faces (two-sided shading), (0, 0, 0) on the background;
**   uv        interpolated Mesh.uv (zero where the mesh has none);
**   position  world-space surface point.
*/
#ifndef render_gbuffer_h
#define render_gbuffer_h

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "camera.h"

#define GBUF_NO_DEPTH INFINITY
#define GBUF_NO_ID (-1)

typedef struct GBuffer {
  int width, height;   /* samples */
  int samples;         /* N: an output pixel is N x N samples */
  Camera camera;       /* set up for width x height */
  float *depth;
  int32_t *object;
  int32_t *face;
  float (*bary)[2];
  float (*normal)[3];
  float (*uv)[2];
  float (*position)[3];
} GBuffer;

/* A G-buffer for an output image of out_width x out_height pixels at
** samples x samples a pixel, visibility planes allocated (not cleared:
** the rasterizer clears each tile before drawing it). gbuf_destroy frees
** it and every plane. */
GBuffer *gbuf_create(int out_width, int out_height, int samples);
void gbuf_destroy(GBuffer *g);

/* Set every visibility plane to the background (depth GBUF_NO_DEPTH, ids
** GBUF_NO_ID, bary 0). */
void gbuf_clear(GBuffer *g);

/* Allocate the attribute planes (left as they are when already present). */
void gbuf_alloc_attributes(GBuffer *g);

#endif
