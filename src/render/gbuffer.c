/*
** G-buffer allocation (gbuffer.h). The planes are plain malloc'd arrays;
** running out of memory ends the program (base/mem.h).
*/
#include "gbuffer.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

GBuffer *gbuf_create(int out_width, int out_height, int samples) {
  GBuffer *g = xcalloc(1, sizeof *g);
  g->samples = samples;
  g->width = out_width * samples;
  g->height = out_height * samples;
  size_t n = (size_t)g->width * g->height;
  g->depth = xmalloc(n * sizeof *g->depth);
  g->object = xmalloc(n * sizeof *g->object);
  g->face = xmalloc(n * sizeof *g->face);
  g->bary = xmalloc(n * sizeof *g->bary);
  mem_advise_huge(g->depth, n * sizeof *g->depth);
  mem_advise_huge(g->object, n * sizeof *g->object);
  mem_advise_huge(g->face, n * sizeof *g->face);
  mem_advise_huge(g->bary, n * sizeof *g->bary);
  return g;
}

void gbuf_destroy(GBuffer *g) {
  if (!g) return;
  free(g->depth);
  free(g->object);
  free(g->face);
  free(g->bary);
  free(g->normal);
  free(g->uv);
  free(g->position);
  free(g);
}

void gbuf_clear(GBuffer *g) {
  size_t n = (size_t)g->width * g->height;
  for (size_t i = 0; i < n; i++) g->depth[i] = GBUF_NO_DEPTH;
  memset(g->object, 0xff, n * sizeof *g->object);   /* all bits set: -1 */
  memset(g->face, 0xff, n * sizeof *g->face);
  memset(g->bary, 0, n * sizeof *g->bary);
}

void gbuf_alloc_attributes(GBuffer *g) {
  size_t n = (size_t)g->width * g->height;
  if (!g->normal) g->normal = xcalloc(n, sizeof *g->normal);
  if (!g->uv) g->uv = xcalloc(n, sizeof *g->uv);
  if (!g->position) g->position = xcalloc(n, sizeof *g->position);
  mem_advise_huge(g->normal, n * sizeof *g->normal);
  mem_advise_huge(g->uv, n * sizeof *g->uv);
  mem_advise_huge(g->position, n * sizeof *g->position);
}
