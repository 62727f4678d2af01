/*
** The evaluated scene: initialisation, the default style, and lookups the
** render stages share.
*/
#include "scene.h"

#include <string.h>

void scene_init(Scene *s) {
  memset(s, 0, sizeof *s);
  arena_init(&s->arena);
  s->output.samples = 1;
  s->output.antialias = 1;
  s->output.background = (Color){1, 1, 1, 1};
  s->output.sheet = scene_default_sheet();
  s->output.loc = src_none();
  s->camera.up = v3(0, 0, 1);
  s->camera.fov = 30;
  s->camera.loc = src_none();
}

double scene_frame_clock(int first, int last, int frame, int loop) {
  int steps = last - first + (loop ? 1 : 0);   /* clock 1 is one step past the last when looping */
  return steps > 0 ? (double)(frame - first) / steps : 0;
}

void scene_free(Scene *s) {
  arena_free(&s->arena);
  memset(s, 0, sizeof *s);
}

/* Light grey toon with silhouettes and creases: the values are the schema's
** defaults (src/lang/schema.c) for a style that sets nothing but those. */
SceneStyle scene_default_style(void) {
  SceneStyle st;
  memset(&st, 0, sizeof st);
  st.base = (Color){0.6f, 0.6f, 0.6f, 1};
  st.texture_repeat = 1;
  st.shade.kind = SHADE_TOON;
  st.shade.toon.bands = 3;
  st.shade.toon.threshold = 0.5;
  st.shade.toon.shininess = 32;
  st.shade.toon.specular_bands = 2;
  st.shade.toon.specular_threshold = 0.5;
  st.shade.toon.ambient = 0.1;
  st.shade.lit = 1;
  st.shade.bokashi = (ShadeBokashi){.sphere = 1, .strength_mod = 1, .view_mod = 0.5, .rate = 1, .per_pixel = 1};
  st.shade.origami_color = (Color){1, 1, 0.8879231f, 1};   /* Mitani's display (1, 1, 0.95), linear */
  st.shade.origami_weights[0] = 0.675;
  st.shade.origami_weights[1] = 0.225;
  st.shade.origami_weights[2] = 0.15;
  st.shade.origami_radius = 8;
  st.shade.ink = scene_default_ink();
  st.shade.loc = src_none();
  SceneLines *l = &st.lines;
  l->present = 1;
  l->kinds = EDGE_SILHOUETTE | EDGE_CREASE | EDGE_BOUNDARY;
  l->crease_angle = 40;
  l->width = 1.5;
  l->color = (Color){0.0075f, 0.0075f, 0.0075f, 1};
  l->opacity = 1;
  l->ref_scale = 1;
  l->search_width = 2;
  l->max_misses = 2;
  l->link_depth = 3;
  l->link_angle = 40;
  l->miter_limit = 4;
  l->min_length = 4;
  l->cull_steps = 10;
  l->link_distance = 2;
  l->brush = (SceneBrush){.width_step = 2, .max_width = 7, .sectors = 28, .bristles = 7, .aspect = 0.5,
                          .ink_load = 0.35, .dry_probability = 0.39, .dry_max_gap = 4, .pressure = 0.6};
  l->loc = src_none();
  st.loc = src_none();
  return st;
}

ShadeInk scene_default_ink(void) {
  ShadeInk k;
  memset(&k, 0, sizeof k);
  k.diffuse = 0.9;
  k.nlevels = 3;   /* the thesis's thresholds 0.4, 0.6, 0.9; each range becomes its upper end */
  k.levels[0] = 0.4; k.levels[1] = 0.6; k.levels[2] = 0.9;
  k.diffusion = INK_MEDIUM;
  k.ink_threshold = 8;
  k.roughness = 0.35;
  k.box_filter = 5;
  k.color = (Color){0, 0, 0, 1};
  k.stage = INK_STAGE_FILTERED;
  k.levels_loc = k.tones_loc = k.lights_loc = src_none();
  return k;
}

SceneSheet scene_default_sheet(void) {
  SceneSheet sh;
  memset(&sh, 0, sizeof sh);
  sh.color = (Color){0.8714f, 0.8070f, 0.6939f, 1};   /* display #f0e8d9, a warm unbleached white */
  sh.scale = 1;
  sh.fibres = 1;
  sh.grain = 0.5;
  sh.loc = src_none();
  return sh;
}

const SceneParam *scene_style_param(const SceneStyle *s, const char *pass, const char *name) {
  for (int i = s->nparams - 1; i >= 0; i--)   /* the last one given wins */
    if (strcmp(s->params[i].pass, pass) == 0 && strcmp(s->params[i].name, name) == 0) return &s->params[i];
  return NULL;
}

int scene_any_image(const Scene *s, int (*pred)(const char *name)) {
  if (s->output.sheet.texture && pred(s->output.sheet.texture)) return 1;
  for (int i = 0; i < s->nstyles; i++) {
    const SceneStyle *st = &s->styles[i];
    if ((st->texture && pred(st->texture)) || (st->lines.present && st->lines.texture && pred(st->lines.texture)) ||
        (st->shade.kind == SHADE_ORIGAMI && st->shade.origami_texture && pred(st->shade.origami_texture)))
      return 1;
    for (int k = 0; k < st->nparams; k++)
      if (!strcmp(st->params[k].name, "texture") && st->params[k].str && pred(st->params[k].str)) return 1;
  }
  return 0;
}
