/*
** `sumi eval FILE --scene`: the evaluated scene as stable text, one
** property a line, `path value` (numbers as echo prints them, colours as
** sRGB #rrggbbaa). Tests diff it, so the order and spelling are fixed:
** output, camera, lights, styles, objects, origami, clock.
*/
#include <stdlib.h>
#include <string.h>

#include "eval.h"
#include "value.h"

static void put_num(FILE *out, double x) {
  char b[32];
  val_format_number(b, sizeof b, x);
  fputs(b, out);
}

static void put_vec3(FILE *out, Vec3 v) {
  fputc('[', out);
  put_num(out, v.x); fputs(", ", out);
  put_num(out, v.y); fputs(", ", out);
  put_num(out, v.z);
  fputc(']', out);
}

static void put_color(FILE *out, Color c) {
  Value v;
  v.kind = V_COLOR;
  v.u.c = &c;
  val_print(out, &v, 0);
}

static void put_mat(FILE *out, const Mat4 *m) {
  Value v;
  v.kind = V_XFORM;
  v.u.m = (Mat4 *)m;
  val_print(out, &v, 0);
}

static void line_num(FILE *out, const char *pre, const char *key, double x) {
  fprintf(out, "%s%s ", pre, key);
  put_num(out, x);
  fputc('\n', out);
}

static void line_color(FILE *out, const char *pre, const char *key, Color c) {
  fprintf(out, "%s%s ", pre, key);
  put_color(out, c);
  fputc('\n', out);
}

static void print_output(const SceneOutput *o, FILE *out) {
  if (o->width) fprintf(out, "output.size %d %d\n", o->width, o->height);
  else fputs("output.size default\n", out);
  fprintf(out, "output.samples %d\n", o->samples);
  fprintf(out, "output.antialias %s\n", o->antialias ? "true" : "false");
  line_color(out, "output.", "background", o->background);
  for (int i = 0; i < o->nstops; i++) {
    char key[32];
    snprintf(key, sizeof key, "background_stop[%d]", i);
    line_color(out, "output.", key, o->stops[i]);
  }
  if (o->backdrop) fprintf(out, "output.background_image \"%s\"\n", o->backdrop_name);
  const SceneSheet *sh = &o->sheet;
  if (!sh->texture) return;
  fprintf(out, "output.sheet \"%s\"\n", sh->texture);
  line_color(out, "output.sheet.", "color", sh->color);
  fprintf(out, "output.sheet.seed %d\n", sh->seed);
  line_num(out, "output.sheet.", "scale", sh->scale);
  line_num(out, "output.sheet.", "fibres", sh->fibres);
  line_num(out, "output.sheet.", "grain", sh->grain);
}

static void print_camera(const SceneCamera *c, FILE *out) {
  if (!c->present) { fputs("camera auto\n", out); return; }
  fprintf(out, "camera.kind %s\n", c->kind == CAMERA_ORTHO ? "ortho" : "perspective");
  fputs("camera.position ", out); put_vec3(out, c->position); fputc('\n', out);
  fputs("camera.look_at ", out); put_vec3(out, c->look_at); fputc('\n', out);
  fputs("camera.up ", out); put_vec3(out, c->up); fputc('\n', out);
  if (c->kind == CAMERA_ORTHO) line_num(out, "camera.", "ortho", c->ortho_height);
  else line_num(out, "camera.", "fov", c->fov);
}

static void print_light(int i, const SceneLight *l, FILE *out) {
  char pre[32];
  snprintf(pre, sizeof pre, "light[%d].", i);
  if (l->name) fprintf(out, "%sname %s\n", pre, l->name);
  if (l->kind != LIGHT_DIRECTIONAL) { fprintf(out, "%sposition ", pre); put_vec3(out, l->position); }
  else { fprintf(out, "%sdirection ", pre); put_vec3(out, l->direction); }
  fputc('\n', out);
  if (l->kind == LIGHT_SPOT) {
    fprintf(out, "%spoint_at ", pre);
    put_vec3(out, l->point_at);
    fputc('\n', out);
    line_num(out, pre, "cone", l->cone);
    line_num(out, pre, "penumbra", l->penumbra);
  }
  line_color(out, pre, "color", l->color);
  line_num(out, pre, "strength", l->strength);
  fprintf(out, "%sfalloff %s\n", pre, l->falloff == FALLOFF_INVERSE_SQUARE ? "inverse_square" : "none");
  if (!l->shadow) return;   /* scenes without shadows print as they always have */
  fprintf(out, "%sshadow true\n", pre);
  fprintf(out, "%sshadow_resolution %d\n", pre, l->shadow_resolution);
  line_num(out, pre, "shadow_bias", l->shadow_bias);
  line_num(out, pre, "shadow_filter", l->shadow_filter);
}

static void print_ramp(FILE *out, const char *pre, const char *key, const Color *c, int n) {
  if (!n) return;
  fprintf(out, "%s%s", pre, key);
  for (int i = 0; i < n; i++) { fputc(' ', out); put_color(out, c[i]); }
  fputc('\n', out);
}

static void print_bokashi(const char *pre, const ShadeBokashi *b, FILE *out) {
  if (b->has_lit) line_color(out, pre, "lit", b->lit);
  if (b->has_unlit) line_color(out, pre, "unlit", b->unlit);
  line_num(out, pre, "strength_mod", b->strength_mod);
  if (b->sphere) { fprintf(out, "%sper_pixel %s\n", pre, b->per_pixel ? "true" : "false"); return; }
  line_num(out, pre, "offset", b->offset);
  line_num(out, pre, "view_mod", b->view_mod);
  line_num(out, pre, "rate", b->rate);
}

static void print_list(FILE *out, const char *pre, const char *key, const double *x, int n) {
  fprintf(out, "%s%s", pre, key);
  for (int i = 0; i < n; i++) { fputc(' ', out); put_num(out, x[i]); }
  fputc('\n', out);
}

static void print_ink(const char *pre, const ShadeInk *k, FILE *out) {
  static const char *strengths[] = {"small", "medium", "large"};
  static const char *stages[] = {"gouraud", "quantised", "diffused", "filtered"};
  line_num(out, pre, "diffuse", k->diffuse);
  print_list(out, pre, "levels", k->levels, k->nlevels);
  if (k->ntones) print_list(out, pre, "tones", k->tones, k->ntones);
  fprintf(out, "%sdiffusion %s\n%spasses %d\n", pre, strengths[k->diffusion], pre, k->passes);
  line_num(out, pre, "ink_threshold", k->ink_threshold);
  line_num(out, pre, "water_threshold", k->water_threshold);
  line_num(out, pre, "roughness", k->roughness);
  fprintf(out, "%sbox_filter %d\n", pre, k->box_filter);
  line_color(out, pre, "color", k->color);
  fprintf(out, "%sstage %s\n", pre, stages[k->stage]);
  if (!k->nlights) return;
  fprintf(out, "%slights", pre);
  for (int i = 0; i < k->nlights; i++) fprintf(out, " %s", k->lights[i]);
  fputc('\n', out);
}

/* shade threshold's own fields, then one block of lines a layer. */
static void print_threshold(const char *pre, const ShadeThreshold *th, FILE *out) {
  static const char *proj[] = {"auto", "uv", "planar", "box", "cylindrical", "spherical"};
  static const char *kinds[] = {"hatch", "stipple", "image"}, *terms[] = {"both", "diffuse", "specular"};
  fprintf(out, "%sprojection %s\n", pre, proj[th->projection]);
  line_num(out, pre, "scale", th->scale);
  fprintf(out, "%sfilter %s\n", pre, th->filter ? "true" : "false");
  line_num(out, pre, "strength", th->strength);
  if (th->nfacing) print_list(out, pre, "facing", th->facing, th->nfacing);
  if (th->nlight) print_list(out, pre, "light", th->light, th->nlight);
  for (int i = 0; i < th->nlayers; i++) {
    const ThresholdLayer *l = &th->layers[i];
    char lp[96];
    fprintf(out, "%slayer[%d] %s\n", pre, i, kinds[l->kind]);
    snprintf(lp, sizeof lp, "%slayer[%d].", pre, i);
    fprintf(out, "%sterm %s\n", lp, terms[l->term]);
    fprintf(out, "%srange ", lp); put_num(out, l->range[0]); fputc(' ', out); put_num(out, l->range[1]); fputc('\n', out);
    line_num(out, lp, "angle", l->angle);
    if (l->kind == LAYER_IMAGE) {
      fprintf(out, "%sfile \"%s\"\n", lp, l->file);
      line_num(out, lp, "window", l->window);
      line_num(out, lp, "clip", l->clip);
      line_num(out, lp, "scale", l->scale);
    } else {
      line_num(out, lp, "spacing", l->spacing);
    }
    line_num(out, lp, "noise", l->noise);
    line_num(out, lp, "noise_scale", l->noise_scale);
  }
}

static void print_shade(const char *pre, const SceneShade *s, FILE *out) {
  static const char *names[] = {"none", "flat", "gouraud", "phong", "toon", "threshold", "bokashi", "ink", "origami"};
  fprintf(out, "%skind %s%s%s\n", pre, names[s->kind], s->subkind ? " " : "", s->subkind ? s->subkind : "");
  if (s->kind == SHADE_ORIGAMI) {
    static const char *modes[] = {"line", "illustration", "shaded"};
    fprintf(out, "%smode %s\n", pre, modes[s->origami_mode]);
    line_color(out, pre, "color", s->origami_color);
    fprintf(out, "%sweights ", pre);
    for (int i = 0; i < 3; i++) { if (i) fputc(' ', out); put_num(out, s->origami_weights[i]); }
    fputc('\n', out);
    line_num(out, pre, "radius", s->origami_radius);
    if (s->origami_texture) fprintf(out, "%stexture \"%s\"\n", pre, s->origami_texture);
    return;
  }
  if (s->kind == SHADE_BOKASHI) { print_bokashi(pre, &s->bokashi, out); return; }
  const ShadeToon *t = &s->toon;
  line_num(out, pre, "ambient", t->ambient);
  line_num(out, pre, "specular", t->specular);
  line_num(out, pre, "shininess", t->shininess);
  if (s->kind == SHADE_FLAT) fprintf(out, "%slit %s\n", pre, s->lit ? "true" : "false");
  if (s->kind == SHADE_INK) print_ink(pre, &s->ink, out);
  if (s->kind != SHADE_TOON && s->kind != SHADE_THRESHOLD) return;
  fprintf(out, "%sbands %d\n", pre, t->bands);
  line_num(out, pre, "threshold", t->threshold);
  print_ramp(out, pre, "ramp", t->ramp, t->nramp);
  print_ramp(out, pre, "specular_ramp", t->specular_ramp, t->nspecular_ramp);
  fprintf(out, "%sspecular_bands %d\n", pre, t->specular_bands);
  line_num(out, pre, "specular_threshold", t->specular_threshold);
  line_num(out, pre, "edge", t->edge);
  if (t->edge > 0) line_color(out, pre, "edge_color", t->edge_color);
  if (s->kind == SHADE_THRESHOLD) print_threshold(pre, &s->threshold, out);
}

static void print_lines(const char *pre, const SceneLines *l, FILE *out) {
  if (!l->present) { fprintf(out, "%.*s none\n", (int)strlen(pre) - 1, pre); return; }   /* "style[0].lines none" */
  fprintf(out, "%skinds", pre);
  if (l->kinds & EDGE_SILHOUETTE) fputs(" silhouette", out);
  if (l->kinds & EDGE_CREASE) { fputs(" crease(", out); put_num(out, l->crease_angle); fputc(')', out); }
  if (l->kinds & EDGE_BOUNDARY) fputs(" boundary", out);
  if (l->kinds & EDGE_FACE) fputs(" face_edges", out);
  fputc('\n', out);
  static const char *strokes[] = {"plain", "ribbon", "brush"};
  fprintf(out, "%sstroke %s\n", pre, strokes[l->stroke]);
  line_num(out, pre, "width", l->width);
  line_color(out, pre, "color", l->color);
  line_num(out, pre, "opacity", l->opacity);
  if (l->texture) fprintf(out, "%stexture \"%s\"\n", pre, l->texture);
  line_num(out, pre, "ref_scale", l->ref_scale);
  fprintf(out, "%ssearch_width %d\n%smax_misses %d\n%slink_depth %d\n", pre, l->search_width, pre, l->max_misses,
          pre, l->link_depth);
  line_num(out, pre, "link_angle", l->link_angle);
  line_num(out, pre, "miter_limit", l->miter_limit);
  line_num(out, pre, "min_length", l->min_length);
  line_num(out, pre, "depth_offset", l->depth_offset);
  /* the Chinese-painting properties only where they take part (other
  ** styles' snapshots stay as they were) */
  static const char *visibility[] = {"auto", "reference", "endpoints"};
  if (l->visibility != LINE_VIS_AUTO) fprintf(out, "%svisibility %s\n", pre, visibility[l->visibility]);
  if (scene_lines_endpoints(l)) {
    fprintf(out, "%scull_steps %d\n", pre, l->cull_steps);
    line_num(out, pre, "link_distance", l->link_distance);
  }
  if (l->stroke != STROKE_BRUSH) return;
  const SceneBrush *b = &l->brush;
  line_num(out, pre, "width_step", b->width_step);
  line_num(out, pre, "max_width", b->max_width);
  fprintf(out, "%ssectors %d\n%sbristles %d\n", pre, b->sectors, pre, b->bristles);
  line_num(out, pre, "brush_aspect", b->aspect);
  line_num(out, pre, "ink_load", b->ink_load);
  line_num(out, pre, "dry_probability", b->dry_probability);
  fprintf(out, "%sdry_max_gap %d\n", pre, b->dry_max_gap);
  line_num(out, pre, "pressure", b->pressure);
}

static void print_param(const char *pre, const SceneParam *p, FILE *out) {
  fprintf(out, "%s%s.%s", pre, p->pass, p->name);
  if (p->str) fprintf(out, " %s", p->str);
  for (int i = 0; i < p->n; i++) { fputc(' ', out); put_num(out, p->num[i]); }
  fputc('\n', out);
}

static void print_noise(const char *pre, const SceneNoise *n, FILE *out) {
  if (!n->present) return;
  line_num(out, pre, "amount", n->amount);
  line_num(out, pre, "scale", n->scale);
  if (n->image_name) { fprintf(out, "%simage \"%s\"\n", pre, n->image_name); return; }
  fprintf(out, "%sseed %d\n%soctaves %d\n", pre, n->seed, pre, n->octaves);
}

static void print_pattern(const char *pre, const ScenePattern *p, FILE *out) {
  if (!p->present) return;
  fprintf(out, "%simage \"%s\"\n", pre, p->image_name ? p->image_name : "");
  line_num(out, pre, "scale", p->scale);
  line_num(out, pre, "opacity", p->opacity);
  print_ramp(out, pre, "colors", p->colors, p->ncolors);
  fprintf(out, "%sblend %s\n", pre, p->blend == PATTERN_MULTIPLY ? "multiply" : "over");
}

static void print_style(int i, const SceneStyle *s, FILE *out) {
  char pre[64];
  snprintf(pre, sizeof pre, "style[%d].", i);
  fprintf(out, "%sname %s\n", pre, s->name ? s->name : "(anonymous)");
  line_color(out, pre, "base", s->base);
  if (s->texture) {
    fprintf(out, "%stexture \"%s\"\n", pre, s->texture_name);
    line_num(out, pre, "texture_repeat", s->texture_repeat);
  }
  snprintf(pre, sizeof pre, "style[%d].shade.", i);
  print_shade(pre, &s->shade, out);
  snprintf(pre, sizeof pre, "style[%d].lines.", i);
  print_lines(pre, &s->lines, out);
  snprintf(pre, sizeof pre, "style[%d].noise.", i);
  print_noise(pre, &s->noise, out);
  snprintf(pre, sizeof pre, "style[%d].pattern.", i);
  print_pattern(pre, &s->pattern, out);
  snprintf(pre, sizeof pre, "style[%d].", i);
  for (int k = 0; k < s->nparams; k++) print_param(pre, &s->params[k], out);
}

/* Small geometry is printed in full; large only as counts and bounds. */
#define PRINT_MAX_POINTS 64

static void print_bounds(const char *pre, const Vec3 *p, int n, FILE *out) {
  if (!n) return;
  Vec3 lo = p[0], hi = p[0];
  for (int i = 1; i < n; i++) {
    lo = v3(fmin(lo.x, p[i].x), fmin(lo.y, p[i].y), fmin(lo.z, p[i].z));
    hi = v3(fmax(hi.x, p[i].x), fmax(hi.y, p[i].y), fmax(hi.z, p[i].z));
  }
  fprintf(out, "%sbounds ", pre); put_vec3(out, lo); fputc(' ', out); put_vec3(out, hi); fputc('\n', out);
}

static void print_patches(const char *pre, const SceneGeometry *g, FILE *out) {
  fprintf(out, "%spatches %d\n", pre, g->npatches);
  int total = 0;
  for (int i = 0; i < g->npatches; i++) total += g->patches[i].bilinear ? 4 : 16;
  Vec3 *all = malloc((size_t)(total + 1) * sizeof *all);
  int k = 0;
  for (int i = 0; i < g->npatches; i++)
    for (int j = 0; j < (g->patches[i].bilinear ? 4 : 16); j++) all[k++] = g->patches[i].cp[j];
  print_bounds(pre, all, k, out);
  free(all);
  if (total > PRINT_MAX_POINTS) return;
  for (int i = 0; i < g->npatches; i++) {
    fprintf(out, "%spatch[%d]%s", pre, i, g->patches[i].bilinear ? " bilinear" : "");
    for (int j = 0; j < (g->patches[i].bilinear ? 4 : 16); j++) { fputc(' ', out); put_vec3(out, g->patches[i].cp[j]); }
    fputc('\n', out);
  }
}

static void print_mesh(const char *pre, const SceneGeometry *g, FILE *out) {
  fprintf(out, "%smesh %d vertices %d faces\n", pre, g->nverts, g->nfaces);
  print_bounds(pre, g->verts, g->nverts, out);
  if (g->nverts <= PRINT_MAX_POINTS) {
    for (int i = 0; i < g->nverts; i++) { fprintf(out, "%svertex[%d] ", pre, i); put_vec3(out, g->verts[i]); fputc('\n', out); }
    for (int f = 0; f < g->nfaces; f++) {
      fprintf(out, "%sface[%d]", pre, f);
      for (int j = g->face_start[f]; j < g->face_start[f + 1]; j++) fprintf(out, " %d", g->face_index[j]);
      fputc('\n', out);
    }
  }
  if (!g->subdiv_level) {   /* a CSG result: its intersection curves */
    if (g->ncreases) fprintf(out, "%screases %d\n", pre, g->ncreases);
    return;
  }
  fprintf(out, "%ssubdiv %s level %d boundary %s\n", pre, g->subdiv_scheme, g->subdiv_level,
          g->subdiv_boundary ? g->subdiv_boundary : "edge_and_corner");
  for (int i = 0; i < g->ncreases; i++) {
    fprintf(out, "%screase[%d] %d %d ", pre, i, g->creases[i].a, g->creases[i].b);
    put_num(out, g->creases[i].sharpness);
    fputc('\n', out);
  }
  for (int i = 0; i < g->ncorners; i++) {
    fprintf(out, "%scorner[%d] %d ", pre, i, g->corners[i].v);
    put_num(out, g->corners[i].sharpness);
    fputc('\n', out);
  }
}

static void print_object(int i, const SceneObject *o, FILE *out) {
  char pre[64];
  snprintf(pre, sizeof pre, "object[%d].", i);
  fprintf(out, "%sname %s\n", pre, o->name ? o->name : "(anonymous)");
  fprintf(out, "%sstyle %d\n", pre, o->style);
  if (o->tess_kind == TESS_ADAPTIVE) { fprintf(out, "%stessellate adaptive(", pre); put_num(out, o->tess_px); fputs(")\n", out); }
  else fprintf(out, "%stessellate %d\n", pre, o->tess_n);
  fprintf(out, "%stransform ", pre); put_mat(out, &o->transform); fputc('\n', out);
  if (o->has_centre) { fprintf(out, "%scentre ", pre); put_vec3(out, o->centre); fputc('\n', out); }
  snprintf(pre, sizeof pre, "object[%d].geometry.", i);
  if (!o->geometry) return;
  if (o->geometry->kind == GEOM_PATCHES) print_patches(pre, o->geometry, out);
  else print_mesh(pre, o->geometry, out);
}

static void print_origami(int i, const SceneOrigami *o, FILE *out) {
  char pre[64];
  snprintf(pre, sizeof pre, "origami[%d].", i);
  fprintf(out, "%sname %s\n", pre, o->name ? o->name : "(anonymous)");
  if (o->fold_file) fprintf(out, "%sfold_file %s\n", pre, o->fold_file);
  fprintf(out, "%svertices %d\n", pre, o->nverts);
  for (int k = 0; k < o->nverts && o->nverts <= PRINT_MAX_POINTS; k++) {
    fprintf(out, "%svertex[%d] ", pre, k);
    put_num(out, o->verts[k].x); fputc(' ', out); put_num(out, o->verts[k].y); fputc('\n', out);
  }
  fprintf(out, "%screases %d\n", pre, o->ncreases);
  for (int k = 0; k < o->ncreases && o->ncreases <= PRINT_MAX_POINTS; k++)
    fprintf(out, "%screase[%d] %d %d %c\n", pre, k, o->creases[k].a, o->creases[k].b, o->creases[k].assignment);
  fprintf(out, "%sfaces %d\n", pre, o->nfaces);
  for (int f = 0; f < o->nfaces && o->nfaces <= PRINT_MAX_POINTS; f++) {
    fprintf(out, "%sface[%d]", pre, f);
    for (int j = o->face_start[f]; j < o->face_start[f + 1]; j++) fprintf(out, " %d", o->face_index[j]);
    fputc('\n', out);
  }
  if (o->has_folded)
    for (int k = 0; k < o->nverts && o->nverts <= PRINT_MAX_POINTS; k++) {
      fprintf(out, "%sfolded[%d] ", pre, k);
      put_num(out, o->folded[k].x); fputc(' ', out); put_num(out, o->folded[k].y); fputc('\n', out);
    }
  fprintf(out, "%sfixed %d\n", pre, o->fixed);
  for (int k = 0; k < o->nabove; k++) fprintf(out, "%sabove %d %d\n", pre, o->above[k].upper, o->above[k].lower);
  for (int k = 0; k < o->noverlap; k++) fprintf(out, "%soverlap[%d] %s\n", pre, k, o->overlap[k]);
  fprintf(out, "%sstyle %d\n", pre, o->style);
  fprintf(out, "%stransform ", pre); put_mat(out, &o->transform); fputc('\n', out);
}

void scene_print(const Scene *s, FILE *out) {
  print_output(&s->output, out);
  print_camera(&s->camera, out);
  for (int i = 0; i < s->nlights; i++) print_light(i, &s->lights[i], out);
  for (int i = 0; i < s->nstyles; i++) print_style(i, &s->styles[i], out);
  for (int i = 0; i < s->nobjects; i++) print_object(i, &s->objects[i], out);
  for (int i = 0; i < s->norigami; i++) print_origami(i, &s->origami[i], out);
  fputs("clock ", out); put_num(out, s->clock); fprintf(out, "\nframe %d\n", s->frame);
}
