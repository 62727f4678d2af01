/*
** shade ink, its shading half (Yeh ch. 5.2; ink.h): the style's
** parameters, the high-contrast Gouraud grey at each vertex, and the
** quantisation the canvas applies to it per pixel. In the tile pass an ink
** object's samples stay transparent (RenderStyle.alpha 0): the canvas
** (canvas.c) paints them, with the diffusion and the box filter, once the
** whole frame is known.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../lang/diag.h"
#include "../lang/value.h"
#include "ink.h"
#include "shade.h"

/* ORDER InkStrength. How far ink runs: the loss sets how many hops a
** difference of ink survives rule 3 inside a wash (more hops across a
** larger difference, as ch. 5.2 says), the water how far the light level
** runs onto dry paper; the passes bound both. */
const InkStrengthRow ink_strengths[3] = {
  {"small", 0.60f, 2, 16},
  {"medium", 0.40f, 4, 32},
  {"large", 0.25f, 8, 64},
};

/* A linear colour channel as a display value (sRGB), in [0, 1]. */
static float display_of(float c) {
  return (float)val_linear_to_srgb(c < 0 ? 0 : c > 1 ? 1 : c);
}

void ink_style_init(InkStyle *k, const SceneShade *sh) {
  const ShadeInk *src = &sh->ink;
  const InkStrengthRow *row = &ink_strengths[src->diffusion];
  memset(k, 0, sizeof *k);
  k->ambient = (float)sh->toon.ambient;
  k->diffuse = (float)src->diffuse;
  k->specular = (float)sh->toon.specular;
  k->shininess = sh->toon.shininess > 0 ? (float)sh->toon.shininess : 1;
  k->ntones = src->nlevels + 1;
  for (int i = 0; i < src->nlevels; i++) k->levels[i] = (float)src->levels[i];
  for (int i = 0; i < k->ntones; i++) {   /* by default each range becomes its upper end */
    double tone = src->ntones ? src->tones[i] : i < src->nlevels ? src->levels[i] : 1.0;
    k->tones[i] = (float)tone;
    k->ink[k->ntones - 1 - i] = (float)(255.0 * (1.0 - tone));   /* in double: 255 (1 - 0.9) is 25.5 in float */
  }
  k->ink_loss = row->ink_loss;
  k->water = row->water;
  k->paper_cost = INK_PAPER_COST;
  k->passes = src->passes > 0 ? src->passes : row->passes;
  k->ink_threshold = (float)src->ink_threshold;
  k->water_threshold = (float)src->water_threshold;
  k->roughness = (float)src->roughness;
  k->box = src->box_filter;
  k->stage = src->stage;
  k->color[0] = display_of(src->color.r);
  k->color[1] = display_of(src->color.g);
  k->color[2] = display_of(src->color.b);
}

int shade_ink_prepare(RenderFrame *f) {
  int ok = 1;
  for (int i = 0; i < f->nstyles; i++) {
    RenderStyle *rs = &f->styles[i];
    if (rs->kind != SHADE_INK) continue;
    rs->ink = xcalloc(1, sizeof *rs->ink);
    ink_style_init(rs->ink, &rs->src->shade);
    const ShadeInk *src = &rs->src->shade.ink;
    if (!src->nlights) continue;   /* all of the frame's lights */
    rs->ink->lights = xmalloc((size_t)src->nlights * sizeof *rs->ink->lights);
    rs->ink->nlights = src->nlights;
    for (int j = 0; j < src->nlights; j++) {   /* the scene has lights: the frame's are those, in order */
      int li = src->light_index ? src->light_index[j] : -1;
      if (li < 0 || li >= f->nlights) {
        diag_error(src->lights_loc, "`lights` in `shade ink`: no light is named `%s`", src->lights[j]);
        ok = 0;
        li = 0;
      }
      rs->ink->lights[j] = li;
    }
  }
  return ok;
}

void shade_ink_free(RenderFrame *f) {
  for (int i = 0; i < f->nstyles; i++) {
    if (!f->styles[i].ink) continue;
    free(f->styles[i].ink->lights);
    free(f->styles[i].ink);
    f->styles[i].ink = NULL;
  }
}

static inline float dot3(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Light j of k's list: its index in f->lights. */
static int ink_light(const InkStyle *k, int j) { return k->nlights ? k->lights[j] : j; }

/* Layers of an ink object's vertex greys: 1, and with shadows one more for
** each of its lights that casts them. */
static int ink_layers(const RenderFrame *f, const RenderObject *o, const InkStyle *k) {
  int n = 1, nl = k->nlights ? k->nlights : f->nlights;
  if (!o->wfnrm) return 1;
  for (int j = 0; j < nl; j++) n += f->lights[ink_light(k, j)].shadow != NULL;
  return n;
}

/* The Gouraud grey at world point p with unit normal n (toward the viewer
** v): the thesis's lighting with its weights, clamped as a frame buffer
** clamps (layer < 0). With shadows, unclamped parts: the ambient and the
** lights that cast none (layer 0), or the layer-th light that casts them
** alone. */
static float ink_grey(const RenderFrame *f, const InkStyle *k, const float p[3], const float n[3],
                      const float v[3], int layer) {
  float g = layer <= 0 ? k->ambient : 0;
  int nl = k->nlights ? k->nlights : f->nlights;
  for (int j = 0, shadowed = 0; j < nl; j++) {
    int i = ink_light(k, j);
    shadowed += f->lights[i].shadow != NULL;
    if (layer >= 0 && (f->lights[i].shadow ? shadowed != layer : layer != 0)) continue;
    float l[3], col[3];
    shade_light(f, i, p, l, col);
    float lum = 0.2126f * col[0] + 0.7152f * col[1] + 0.0722f * col[2];
    float fs = k->specular > 0 ? k->specular * shade_specular(n, l, v, k->shininess) : 0;
    g += lum * (k->diffuse * shade_diffuse(n, l) + fs);
  }
  if (layer >= 0) return g;
  return g > 0 ? (g < 1 ? g : 1) : 0;   /* NaN to 0 */
}

/* The grey at world point p with normal nrm turned toward the viewer. */
static float grey_at(const RenderFrame *f, const InkStyle *k, const float p[3], const float nrm[3], int layer) {
  Vec3 vd = camera_view_dir(&f->camera, v3(p[0], p[1], p[2]));
  float v[3] = {(float)vd.x, (float)vd.y, (float)vd.z};
  float n[3] = {nrm[0], nrm[1], nrm[2]};
  if (dot3(n, v) < 0) { n[0] = -n[0]; n[1] = -n[1]; n[2] = -n[2]; }
  return ink_grey(f, k, p, n, v, layer);
}

void shade_ink_vertex_values(const RenderFrame *f, RenderObject *o) {
  const InkStyle *k = o->style->ink;
  const Mesh *m = o->mesh;
  int layers = ink_layers(f, o, k);
  size_t count = o->wcnrm ? 3 * (size_t)m->ntris : (size_t)m->nverts;
  o->vink = xmalloc((size_t)layers * count * sizeof *o->vink + 1);
  for (int layer = 0; layer < layers; layer++) {
    float *vi = o->vink + layer * count;
    int which = layers > 1 ? layer : -1;
    if (o->wcnrm) {   /* hard edges: a grey per triangle corner, with that corner's normal */
      for (int t = 0; t < m->ntris; t++)
        for (int c = 0; c < 3; c++) vi[3 * t + c] = grey_at(f, k, o->wpos[m->tri[t][c]], o->wcnrm[t][c], which);
    } else {
      for (int i = 0; i < m->nverts; i++) vi[i] = grey_at(f, k, o->wpos[i], o->wnrm[i], which);
    }
  }
}

int shade_ink_corners(const RenderFrame *f, const RenderObject *o, int face, float v[3]) {
  if (ink_layers(f, o, o->style->ink) != 1) return 0;
  const int *t = o->mesh->tri[face];
  if (o->wcnrm) {   /* a grey per corner */
    const float *c = o->vink + 3 * (size_t)face;
    v[0] = c[0]; v[1] = c[1]; v[2] = c[2];
  } else {
    v[0] = o->vink[t[0]]; v[1] = o->vink[t[1]]; v[2] = o->vink[t[2]];
  }
  return 1;
}

float shade_ink_grey(const RenderFrame *f, const RenderObject *o, int face, const float b[2]) {
  float b1 = b[0], b2 = b[1], b0 = 1 - b1 - b2;
  const int *t = o->mesh->tri[face];
  size_t i0 = t[0], i1 = t[1], i2 = t[2], count = (size_t)o->mesh->nverts;
  if (o->wcnrm) {   /* a grey per corner */
    i0 = 3 * (size_t)face; i1 = i0 + 1; i2 = i0 + 2; count = 3 * (size_t)o->mesh->ntris;
  }
  const float *v = o->vink;
  float g = b0 * v[i0] + b1 * v[i1] + b2 * v[i2];
  const InkStyle *k = o->style->ink;
  if (ink_layers(f, o, k) == 1) return g;
  const float *p0 = o->wpos[t[0]], *p1 = o->wpos[t[1]], *p2 = o->wpos[t[2]];
  float p[3];   /* the sample's point, as shade_surface_at makes it */
  for (int c = 0; c < 3; c++) p[c] = b0 * p0[c] + b1 * p1[c] + b2 * p2[c];
  int nl = k->nlights ? k->nlights : f->nlights;
  for (int j = 0; j < nl; j++) {
    int i = ink_light(k, j);
    if (!f->lights[i].shadow) continue;
    v += count;   /* the next layer: light i's */
    float part = b0 * v[i0] + b1 * v[i1] + b2 * v[i2];
    if (part > 0) g += part * shade_reach(f, i, o, face, p);
  }
  return g > 0 ? (g < 1 ? g : 1) : 0;   /* NaN to 0 */
}

void shade_ink_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb, int stride) {
  (void)r;
  (void)o;
  for (int k = k0; k < k1; k++) rgb[(size_t)k * stride] = rgb[(size_t)k * stride + 1] = rgb[(size_t)k * stride + 2] = 0;
}

void shade_ink(const ShadeSample *s, float rgb[3]) {
  (void)s;
  rgb[0] = rgb[1] = rgb[2] = 0;   /* premultiplied by its alpha 0 */
}
