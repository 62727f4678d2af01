/*
** bench/origami.sh's driver: the origami render stages (src/render/origami.c)
** on FOLD files at 512 x 512, framed as a scene of origami alone is (ortho
** from +z), each mode timed as the median (and the minimum) of 15 runs: the
** machines are shared, and the minimum is the stage's own cost.
**
**   origami_bench FILE.fold [SIZE]
*/
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../src/geom/origami.h"
#include "../src/io/fold.h"
#include "../src/render/camera.h"
#include "../src/render/origami.h"

#define RUNS 15

static double now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: origami_bench FILE.fold [SIZE]\n");
    return 2;
  }
  int size = argc > 2 ? atoi(argv[2]) : 512;
  diag_init(DIAG_TEXT);
  Arena arena;
  arena_init(&arena);
  SceneOrigami src;
  char err[512];
  if (fold_read(argv[1], &src, &arena, err, sizeof err) != 0) {
    fprintf(stderr, "%s\n", err);
    return 1;
  }
  double t0 = now_ms();
  OrigamiModel *m = origami_build(&src, 0);
  double t_build = now_ms() - t0;
  if (!m) return 1;
  Vec3 lo, hi;
  Mat4 id = m4_identity();
  origami_world_bounds(m, &id, &lo, &hi);
  SceneCamera sc;
  memset(&sc, 0, sizeof sc);
  Camera cam;
  const char *why = NULL;
  if (!camera_setup(&cam, &sc, size, size, lo, hi, 1, &why)) {
    fprintf(stderr, "camera: %s\n", why);
    return 1;
  }
  SceneStyle style;
  memset(&style, 0, sizeof style);
  style.shade.kind = SHADE_ORIGAMI;
  style.shade.origami_radius = ORIGAMI_DEFAULT_RADIUS;
  float *rgba = xmalloc((size_t)size * size * 4 * sizeof *rgba);
  int32_t *ids = xmalloc((size_t)size * size * sizeof *ids);
  const char *modes[3] = {"line", "illustration", "shaded"};
  const char *base = strrchr(argv[1], '/') ? strrchr(argv[1], '/') + 1 : argv[1];
  printf("%s: %d faces, %d triangles; build %.2f ms\n", base, m->nfaces, m->ntris, t_build);
  double t[RUNS];
  for (int r = 0; r < RUNS; r++) {
    double s = now_ms();
    origami_render_ids(m, &cam.world_to_clip, size, size, NULL, ids);
    t[r] = now_ms() - s;
  }
  qsort(t, RUNS, sizeof *t, cmp_double);
  printf("  face-ID buffer      %7.2f ms  (min %.2f)\n", t[RUNS / 2], t[0]);
  for (int mode = 0; mode < 3; mode++) {
    style.shade.origami_mode = mode;
    style.lines.present = mode > 0;
    style.lines.kinds = EDGE_FACE;
    style.lines.opacity = 1;
    for (int r = 0; r < RUNS; r++) {
      memset(rgba, 0, (size_t)size * size * 4 * sizeof *rgba);
      OrigamiTarget tg = {size, size, rgba, ids, NULL, 1};
      double s = now_ms();
      origami_render(m, &style, &cam.world_to_clip, NULL, &tg);
      t[r] = now_ms() - s;
    }
    qsort(t, RUNS, sizeof *t, cmp_double);
    printf("  %-12s (all)   %7.2f ms  (min %.2f)\n", modes[mode], t[RUNS / 2], t[0]);
  }
  free(ids);
  free(rgba);
  origami_free(m);
  arena_free(&arena);
  return 0;
}
