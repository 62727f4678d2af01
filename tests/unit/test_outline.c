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

/* Evaluate text (a scene file in the repository root's terms) into *s;
** 0 on errors. */
static int eval_text(const char *name, const char *text, Arena *arena, Scene *s) {
  size_t n = strlen(text);
  char *copy = xmalloc(n + 1);
  memcpy(copy, text, n + 1);
  int file = diag_add_file(name, copy, n, -1, src_none());
  AstNode *prog = parse_file(file, arena);
  if (!prog || diag_error_count()) return 0;
  EvalOptions eo;
  eval_options_init(&eo);
  eo.stdlib_dir = "stdlib";
  scene_init(s);
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

/* The contour coverage of the scene in text at w x h. */
static Coverage measure(const char *name, const char *text, int w, int h) {
  Coverage c = {0, 0};
  Arena arena;
  arena_init(&arena);
  Scene s;
  if (!eval_text(name, text, &arena, &s)) {
    fprintf(stderr, "%s: the scene does not evaluate\n", name);
    arena_free(&arena);
    return c;
  }
  RenderOptions ro;
  memset(&ro, 0, sizeof ro);
  ro.width = w;
  ro.height = h;
  ro.threads = 1;
  ro.samples = 1;   /* object ids a pixel */
  Image *img = NULL;
  GBuffer *gb = NULL;
  RenderFrame f;
  Image *ink = image_create(w, h, 4);   /* transparent: the strokes alone */
  if (render_scene(&s, &ro, &img, &gb) != 0 || !render_prepare(&s, &ro, &f)) {
    fprintf(stderr, "%s: the scene does not render\n", name);
  } else if (line_render_frame(&f, 1, ink, NULL, NULL)) {
    float *alpha = xmalloc((size_t)w * h * sizeof *alpha);
    for (int i = 0; i < w * h; i++) alpha[i] = ink->data[(size_t)i * 4 + 3];
    unsigned char *miss = xcalloc((size_t)w * h, 1);
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w; x++) {
        if (gb->object[(size_t)y * w + x] == GBUF_NO_ID) continue;
        if (!background_at(gb->object, w, h, x - 1, y) && !background_at(gb->object, w, h, x + 1, y) &&
            !background_at(gb->object, w, h, x, y - 1) && !background_at(gb->object, w, h, x, y + 1))
          continue;
        c.contour++;
        int hit = inked_near(alpha, w, h, x, y);
        c.covered += hit;
        miss[(size_t)y * w + x] = hit ? 2 : 1;
      }
    if (coverage_ratio(c) < OUTLINE_MIN_COVERAGE) write_misses(name, gb->object, alpha, w, h, miss);
    free(miss);
    free(alpha);
  }
  render_frame_free(&f);
  image_destroy(ink);
  image_destroy(img);
  gbuf_destroy(gb);
  scene_free(&s);
  arena_free(&arena);
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

/* The sphere of the report (seen along -y, a silhouette along the seams of
** its patches) at every tessellation and reference scale. */
TEST(sphere_contour) {
  for (size_t t = 0; t < sizeof TESS / sizeof *TESS; t++)
    for (size_t r = 0; r < sizeof REF_SCALE / sizeof *REF_SCALE; r++) {
      char text[1024], name[64];
      snprintf(text, sizeof text,
               "include \"shapes.npr\";\n"
               "camera { position [0, -10, 0]; look_at [0, 0, 0]; fov 30; }\n"
               "style s { base #3a6ea5; shade toon { }\n"
               "  lines { kinds silhouette; width 2; ref_scale %s; } }\n"
               "object { geometry sphere(1); style s; tessellate %s; }\n",
               REF_SCALE[r], TESS[t]);
      snprintf(name, sizeof name, "sphere_t%s_r%s", TESS[t], REF_SCALE[r]);
      check_scene(name, text, 256, 192);
    }
}

/* The teapot (open at the spout: boundary edges outline it there) from
** above and the side, at every tessellation and reference scale. */
TEST(teapot_contour) {
  for (size_t t = 0; t < sizeof TESS / sizeof *TESS; t++)
    for (size_t r = 0; r < sizeof REF_SCALE / sizeof *REF_SCALE; r++) {
      char text[1024], name[64];
      snprintf(text, sizeof text,
               "include \"teapot.npr\";\n"
               "camera { position [5, -9, 5]; look_at [0.2, 0, 1.2]; fov 35; }\n"
               "style s { base #e8d5b0;\n"
               "  lines { kinds silhouette, boundary; width 2; ref_scale %s; } }\n"
               "object { geometry teapot(); style s; tessellate %s; }\n",
               REF_SCALE[r], TESS[t]);
      snprintf(name, sizeof name, "teapot_t%s_r%s", TESS[t], REF_SCALE[r]);
      check_scene(name, text, 256, 192);
    }
}

/* ---- meshes from assimp-testmodels --------------------------------------------- */

/* Closed meshes of several formats, and the two open shells the report
** names (Wuson, the spider), whose outer contour is silhouette and
** boundary edges. transform and camera frame each; "" keeps the default. */
typedef struct MeshCase { const char *file, *transform, *camera; } MeshCase;

static const MeshCase MESHES[] = {
  {"OBJ/spider.obj", "scale(0.03) * rotate([90, 0, 0])", "position [0, -6, 3]; look_at [0, 0, 0]; fov 40;"},
  {"OBJ/WusonOBJ.obj", "rotate([90, 0, -30])", ""},
  {"PLY/cube.ply", "rotate([10, 20, 30])", ""},
  {"3DS/cubes_with_alpha.3DS", "scale(1)", ""},
  {"ASE/ThreeCubesGreen.ASE", "scale(1)", ""},
  {"FBX/cubes_with_names.fbx", "scale(1)", ""},
  {"BLEND/NoisyTexturedCube_VoronoiGlob_248.blend", "rotate([10, 20, 30])", ""},
  {"Collada/sphere.dae", "scale(1)", ""},
  {"AC/SphereWithLight.ac", "scale(1)", ""},
  {"LWO/LWO2/sphere_with_gradient.lwo", "scale(1)", ""},
  {"MS3D/twospheres.ms3d", "scale(1)", ""},
  {"NFF/NFF/spheres.nff", "scale(1)", ""},
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

int main(void) {
  diag_init(DIAG_TEXT);
  RUN(sphere_contour);
  RUN(teapot_contour);
  RUN(assimp_meshes);
  diag_shutdown();
  return unit_done();
}
