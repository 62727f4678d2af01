/*
** Outlines that hold: the outer contour of each object against the
** background (read from the object-id plane of the G-buffer, the --aov
** object pass) must be covered by stroke ink within 1.5 pixels, on the
** sphere and the teapot at every tessellation and reference scale, and on
** the closed meshes of Debian's assimp-testmodels when it is installed.
** Scenes are written in the scene language and rendered small.
*/
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../../src/lang/diag.h"
#include "../../src/lang/eval.h"
#include "../../src/lang/parse.h"
#include "../../src/render/lines.h"
#include "../../src/render/render.h"
#include "unit.h"

/* Ink at least this opaque counts as a stroke. */
#define OUTLINE_INK 0.5f
/* A contour pixel is covered when ink lies within this distance. */
#define OUTLINE_REACH 1.5
/* The coverage every scene must reach. */
#define OUTLINE_MIN_COVERAGE 0.99

#define ASSIMP_MODELS "/usr/share/assimp/models"

/* Evaluate text (a scene file in the repository root's terms) into *s,
** which is scene_init'ed first (scene_free it either way); 0 on errors. */
static int eval_text(const char *name, const char *text, Arena *arena, Scene *s) {
  scene_init(s);
  size_t n = strlen(text);
  char *copy = xmalloc(n + 1);
  memcpy(copy, text, n + 1);
  int file = diag_add_file(name, copy, n, -1, src_none());
  AstNode *prog = parse_file(file, arena);
  if (!prog || diag_error_count()) return 0;
  EvalOptions eo;
  eval_options_init(&eo);
  eo.stdlib_dir = "stdlib";
  return eval_program(prog, file, arena, &eo, s) == 0;
}

typedef struct Coverage {
  int contour;   /* contour pixels */
  int covered;   /* of them, with ink within OUTLINE_REACH */
} Coverage;

static double coverage_ratio(Coverage c) { return c.contour ? (double)c.covered / c.contour : 0; }

/* Is (x, y) inside the w x h grid and the background in ids? */
static int background_at(const int32_t *ids, int w, int h, int x, int y) {
  return x >= 0 && y >= 0 && x < w && y < h && ids[(size_t)y * w + x] == GBUF_NO_ID;
}

/* Is any pixel within OUTLINE_REACH of (x, y) inked in alpha? */
static int inked_near(const float *alpha, int w, int h, int x, int y) {
  int r = (int)OUTLINE_REACH;
  for (int dy = -r; dy <= r; dy++)
    for (int dx = -r; dx <= r; dx++) {
      int u = x + dx, v = y + dy;
      if (dx * dx + dy * dy > OUTLINE_REACH * OUTLINE_REACH || u < 0 || v < 0 || u >= w || v >= h)
        continue;
      if (alpha[(size_t)v * w + u] >= OUTLINE_INK) return 1;
    }
  return 0;
}

/* Write the frame with missed contour pixels in magenta and covered ones
** in green, OUTLINE_ZOOM times larger, to build/test-out/outline_NAME.png,
** for a failing case. */
#define OUTLINE_ZOOM 3
static void write_misses(const char *name, const int32_t *ids, const float *alpha, int w, int h,
                         const unsigned char *miss) {
  mkdir("build", 0777);
  mkdir("build/test-out", 0777);
  Image *img = image_create(w * OUTLINE_ZOOM, h * OUTLINE_ZOOM, 3);
  for (int y = 0; y < h * OUTLINE_ZOOM; y++)
    for (int x = 0; x < w * OUTLINE_ZOOM; x++) {
      int i = y / OUTLINE_ZOOM * w + x / OUTLINE_ZOOM;
      float *p = img->data + ((size_t)y * w * OUTLINE_ZOOM + x) * 3;
      float g = ids[i] == GBUF_NO_ID ? 1.0f : 0.6f;
      for (int k = 0; k < 3; k++) p[k] = g * (1 - alpha[i]);
      if (miss[i] == 1) { p[0] = 1; p[1] = 0; p[2] = 1; }
      if (miss[i] == 2) { p[0] = 0.3f * p[0]; p[1] = 0.5f + 0.5f * p[1]; p[2] = 0.3f * p[2]; }
    }
  char path[512], err[256];
  snprintf(path, sizeof path, "build/test-out/outline_%s.png", name);
  if (!image_write(path, img, err, sizeof err)) fprintf(stderr, "%s\n", err);
  else fprintf(stderr, "  misses: %s\n", path);
  image_destroy(img);
}

/* A scene rendered at w x h, one sample a pixel: its image (linear RGB),
** the object drawn at each pixel (the G-buffer's, as --aov object writes
** it: GBUF_NO_ID for the background, nobjects for an origami sheet), and
** the alpha of its strokes drawn alone over nothing. */
typedef struct Rendered { int w, h, nobjects; Image *img; int32_t *ids; float *ink; } Rendered;

static void rendered_free(Rendered *r) {
  image_destroy(r->img);
  free(r->ids);
  free(r->ink);
  memset(r, 0, sizeof *r);
}

/* Render the scene in text into *r; 0 (reported) when it does not. */
static int render_text(const char *name, const char *text, int w, int h, Rendered *r) {
  memset(r, 0, sizeof *r);
  Arena arena;
  arena_init(&arena);
  Scene s;
  int ok = eval_text(name, text, &arena, &s);
  if (!ok) fprintf(stderr, "%s: the scene does not evaluate\n", name);
  RenderOptions ro;
  memset(&ro, 0, sizeof ro);
  ro.width = w;
  ro.height = h;
  ro.threads = 1;
  ro.samples = 1;   /* object ids a pixel */
  GBuffer *gb = NULL;
  if (ok && render_scene(&s, &ro, &r->img, &gb) != 0) {
    fprintf(stderr, "%s: the scene does not render\n", name);
    ok = 0;
  }
  if (ok) {
    RenderFrame f;
    Image *ink = image_create(w, h, 4);   /* transparent: the strokes alone */
    ok = render_prepare(&s, &ro, &f) && line_render_frame(&f, 1, ink, NULL, NULL);
    render_frame_free(&f);
    r->w = w;
    r->h = h;
    r->nobjects = s.nobjects;
    r->ids = xmalloc((size_t)w * h * sizeof *r->ids);
    memcpy(r->ids, gb->object, (size_t)w * h * sizeof *r->ids);
    r->ink = xmalloc((size_t)w * h * sizeof *r->ink);
    for (int i = 0; i < w * h; i++) r->ink[i] = ink->data[(size_t)i * 4 + 3];
    image_destroy(ink);
  }
  gbuf_destroy(gb);
  scene_free(&s);
  arena_free(&arena);
  if (!ok) rendered_free(r);
  return ok;
}

/* The contour coverage of the scene in text at w x h. */
static Coverage measure(const char *name, const char *text, int w, int h) {
  Coverage c = {0, 0};
  Rendered r;
  if (!render_text(name, text, w, h, &r)) return c;
  unsigned char *miss = xcalloc((size_t)w * h, 1);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      if (r.ids[(size_t)y * w + x] == GBUF_NO_ID) continue;
      if (!background_at(r.ids, w, h, x - 1, y) && !background_at(r.ids, w, h, x + 1, y) &&
          !background_at(r.ids, w, h, x, y - 1) && !background_at(r.ids, w, h, x, y + 1))
        continue;
      c.contour++;
      int hit = inked_near(r.ink, w, h, x, y);
      c.covered += hit;
      miss[(size_t)y * w + x] = hit ? 2 : 1;
    }
  if (coverage_ratio(c) < OUTLINE_MIN_COVERAGE) write_misses(name, r.ids, r.ink, w, h, miss);
  free(miss);
  rendered_free(&r);
  return c;
}

/* Check one scene: print its figure, fail below OUTLINE_MIN_COVERAGE. */
static void check_scene(const char *name, const char *text, int w, int h) {
  Coverage c = measure(name, text, w, h);
  double r = coverage_ratio(c);
  printf("  %-28s %5d contour px, %6.2f %% covered\n", name, c.contour, 100 * r);
  if (!(r >= OUTLINE_MIN_COVERAGE)) {
    char m[256];
    snprintf(m, sizeof m, "%s: contour %.2f %% covered (%d of %d), below %.0f %%", name, 100 * r,
             c.covered, c.contour, 100 * OUTLINE_MIN_COVERAGE);
    unit_fail(__FILE__, __LINE__, m);
  }
}

/* ---- patches ----------------------------------------------------------------- */

static const char *const TESS[] = {"4", "8", "16", "32", "adaptive(1)", "adaptive(0.25)"};
static const char *const REF_SCALE[] = {"0.5", "1", "2", "4"};

/* check_scene at every tessellation and scale for the scene head (up to
** an open style s), its lines' kinds and the object's geometry, named
** NAME_tT_rR. */
static void check_settings(const char *name, const char *head, const char *kinds, const char *geometry) {
  for (size_t t = 0; t < sizeof TESS / sizeof *TESS; t++)
    for (size_t r = 0; r < sizeof REF_SCALE / sizeof *REF_SCALE; r++) {
      char text[1024], full[64];
      snprintf(text, sizeof text,
               "%s  lines { kinds %s; width 2; ref_scale %s; } }\n"
               "object { geometry %s; style s; tessellate %s; }\n",
               head, kinds, REF_SCALE[r], geometry, TESS[t]);
      snprintf(full, sizeof full, "%s_t%s_r%s", name, TESS[t], REF_SCALE[r]);
      check_scene(full, text, 256, 192);
    }
}

/* The sphere of the report (seen along -y, a silhouette along the seams of
** its patches) at every tessellation and reference scale. */
TEST(sphere_contour) {
  check_settings("sphere",
                 "include \"shapes.npr\";\n"
                 "camera { position [0, -10, 0]; look_at [0, 0, 0]; fov 30; }\n"
                 "style s { base #3a6ea5; shade toon { }\n",
                 "silhouette", "sphere(1)");
}

/* The teapot (open at the spout: boundary edges outline it there) from
** above and the side, at every tessellation and reference scale. */
TEST(teapot_contour) {
  check_settings("teapot",
                 "include \"teapot.npr\";\n"
                 "camera { position [5, -9, 5]; look_at [0.2, 0, 1.2]; fov 35; }\n"
                 "style s { base #e8d5b0;\n",
                 "silhouette, boundary", "teapot()");
}

/* ---- meshes from assimp-testmodels --------------------------------------------- */

/* Closed meshes of several formats, and the two open shells the report
** names (Wuson, the spider), whose outer contour is silhouette and
** boundary edges. transform and camera frame each; "" keeps the default. */
typedef struct MeshCase { const char *file, *transform, *camera; } MeshCase;

static const MeshCase MESHES[] = {
  {"OBJ/spider.obj", "scale(0.03) * rotate([90, 0, 0])", "position [0, -6, 3]; look_at [0, 0, 0]; fov 40;"},
  {"OBJ/WusonOBJ.obj", "rotate([90, 0, -30])", ""},
  /* every closed mesh that imports, one file per model where a model comes
  ** in several formats of the same mesh, turned off its axes */
  {"3DS/RotatingCube.3DS", "rotate([10, 20, 30])", ""},
  {"3DS/cubes_with_alpha.3DS", "rotate([10, 20, 30])", ""},
  {"AC/SphereWithLight.ac", "scale(1)", ""},
  {"AC/SphereWithLight_UTF8BOM.ac", "scale(1)", ""},
  {"ASE/ThreeCubesGreen.ASE", "rotate([10, 20, 30])", ""},
  {"BLEND/4Cubes4Mats_248.blend", "rotate([10, 20, 30])", ""},
  {"BLEND/NoisyTexturedCube_VoronoiGlob_248.blend", "rotate([10, 20, 30])", ""},
  {"BLEND/SmoothVsSolidCube_248.blend", "rotate([10, 20, 30])", ""},
  {"Collada/sphere.dae", "scale(1)", ""},
  {"FBX/cubes_with_names.fbx", "rotate([10, 20, 30])", ""},
  {"LWO/LWO2/sphere_with_gradient.lwo", "scale(1)", ""},
  {"MD5/SimpleCube.md5mesh", "rotate([10, 20, 30])", ""},
  {"MS3D/twospheres.ms3d", "scale(1)", ""},
  {"NFF/NFF/spheres.nff", "scale(1)", ""},
  {"OFF/Cube.off", "rotate([10, 20, 30])", ""},
  {"PLY/cube.ply", "rotate([10, 20, 30])", ""},
  {"glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", "rotate([10, 20, 30])", ""},
};

TEST(assimp_meshes) {
  struct stat st;
  if (stat(ASSIMP_MODELS, &st) != 0) {
    printf("  skipped: %s not installed (Debian package assimp-testmodels)\n", ASSIMP_MODELS);
    return;
  }
  for (size_t i = 0; i < sizeof MESHES / sizeof *MESHES; i++)
    for (size_t r = 0; r < sizeof REF_SCALE / sizeof *REF_SCALE; r++) {
      const MeshCase *mc = &MESHES[i];
      char text[2048], name[128];
      snprintf(text, sizeof text,
               "%s%s%s\n"
               "style s { base #c0c0c0; lines { kinds silhouette, boundary; width 2; ref_scale %s; } }\n"
               "object { geometry mesh(\"%s/%s\"); transform %s; style s; }\n",
               mc->camera[0] ? "camera { " : "", mc->camera, mc->camera[0] ? " }" : "", REF_SCALE[r],
               ASSIMP_MODELS, mc->file, mc->transform);
      const char *base = strrchr(mc->file, '/');
      snprintf(name, sizeof name, "%s_r%s", base ? base + 1 : mc->file, REF_SCALE[r]);
      check_scene(name, text, 256, 192);
    }
}

/* ---- what hides lines, and what lines hide -------------------------------------- */

/* Is every pixel within r of (x, y) inside the image and object obj? */
static int deep_inside(const Rendered *r, int obj, int x, int y, int rad) {
  for (int dy = -rad; dy <= rad; dy++)
    for (int dx = -rad; dx <= rad; dx++) {
      int u = x + dx, v = y + dy;
      if (u < 0 || v < 0 || u >= r->w || v >= r->h || r->ids[(size_t)v * r->w + u] != obj) return 0;
    }
  return 1;
}

/* An origami sheet in front of the sphere of the report hides the part of
** its outline behind it: no stroke ink on the sheet 4 px in from its
** edge (a segment whose last max_misses = 2 steps are hidden still runs to
** its edge's end, 001 §2.1.4, and a stroke 3 px wide spreads 2 px about
** its line), and the outline still shows beside it. */
TEST(origami_hides_lines) {
  static const char *text =
      "include \"shapes.npr\";\n"
      "camera { position [0, -10, 0]; look_at [0, 0, 0]; fov 30; }\n"
      "style s { base #3a6ea5; shade toon { } lines { kinds silhouette; width 3; color #cc0000; } }\n"
      "object { geometry sphere(1); style s; }\n"
      "origami { paper { vertices [[0, 0], [2, 0], [2, 2], [0, 2]];\n"
      "                  creases [[0, 1, \"B\"], [1, 2, \"B\"], [2, 3, \"B\"], [3, 0, \"B\"]]; }\n"
      "          transform translate([-0.5, -3, -2]) * rotate([90, 0, 0]); }\n";
  Rendered r;
  CHECK(render_text("origami_hides_lines", text, 160, 120, &r));
  if (!r.ids) return;
  int sheet = 0, inked = 0, sphere_ink = 0;
  for (int y = 0; y < r.h; y++)
    for (int x = 0; x < r.w; x++) {
      size_t p = (size_t)y * r.w + x;
      if (deep_inside(&r, r.nobjects, x, y, 4)) {
        sheet++;
        inked += r.ink[p] > 0.05f;
      }
      sphere_ink += r.ids[p] == 0 && r.ink[p] >= OUTLINE_INK;
    }
  CHECK(sheet > 500);
  CHECK_EQ_INT(inked, 0);
  CHECK(sphere_ink > 40);   /* the visible part of the outline is drawn */
  rendered_free(&r);
}

/* The same sheet behind the sphere, with creases and the line mode: the
** sphere's pixels are the same with the sheet as without it (no crease,
** and no Sobel edge along the sphere's outline, is drawn over it), and the
** sheet's outline shows beside the sphere. */
TEST(objects_hide_origami_lines) {
  static const char *sphere =
      "include \"shapes.npr\";\n"
      "camera { position [0, -10, 0]; look_at [0, 0, 0]; fov 30; }\n"
      "style s { base #3a6ea5; shade toon { } }\n"
      "style paper { shade origami { mode line; } lines { kinds face_edges; width 3; } }\n"
      "object { geometry sphere(1); style s; transform translate([0.3, -1, 0]); }\n";
  static const char *sheet =
      "origami { paper { vertices [[0, 0], [2, 0], [2, 2], [0, 2], [1, 0], [1, 2], [0, 1], [2, 1]];\n"
      "  creases [[0, 4, \"B\"], [4, 1, \"B\"], [1, 7, \"B\"], [7, 2, \"B\"], [2, 5, \"B\"],\n"
      "           [5, 3, \"B\"], [3, 6, \"B\"], [6, 0, \"B\"], [4, 5, \"F\"], [6, 7, \"F\"]]; }\n"
      "  style paper; transform translate([-1.5, 0, -1]) * rotate([90, 0, 0]); }\n";
  char both[2048];
  snprintf(both, sizeof both, "%s%s", sphere, sheet);
  Rendered a, b;
  CHECK(render_text("objects_hide_origami_lines_alone", sphere, 160, 120, &a));
  CHECK(render_text("objects_hide_origami_lines", both, 160, 120, &b));
  if (a.ids && b.ids) {
    int on_sphere = 0, differ = 0, paper = 0;
    for (size_t p = 0; p < (size_t)a.w * a.h; p++) {
      if (b.ids[p] == b.nobjects) paper++;
      if (b.ids[p] != 0) continue;
      on_sphere++;
      for (int k = 0; k < 3; k++) differ += a.img->data[p * 3 + k] != b.img->data[p * 3 + k];
    }
    CHECK(paper > 500);
    CHECK(on_sphere > 500);
    CHECK_EQ_INT(differ, 0);
  }
  rendered_free(&a);
  rendered_free(&b);
}

int main(void) {
  diag_init(DIAG_TEXT);
  RUN(origami_hides_lines);
  RUN(objects_hide_origami_lines);
  RUN(sphere_contour);
  RUN(teapot_contour);
  RUN(assimp_meshes);
  diag_shutdown();
  return unit_done();
}
