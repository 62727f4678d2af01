/*
** Mesh import through Assimp: polygons kept, positions welded across
** faces and meshes, clear errors for missing, empty, malformed and
** polygon-less files. Real models come from the assimp-testmodels package
** ($SUMI_ASSIMP_MODELS, default its Debian location); those tests skip
** cleanly where it is not installed.
*/
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "../../src/base/mem.h"
#include "../../src/geom/tessellate.h"
#include "../../src/io/mesh_import.h"
#include "unit.h"

static char tmpdir[256];

/* Write text into a fresh file named name inside tmpdir; returns its path. */
static const char *write_file(const char *name, const char *text) {
  static char path[512];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  FILE *f = fopen(path, "wb");
  if (!f) return path;
  fputs(text, f);
  fclose(f);
  return path;
}

static int import(const char *path, SceneGeometry *g, Arena *a, char *err, size_t errlen) {
  int ok = mesh_import_file(path, g, a, err, errlen) == 0;
  if (!ok && getenv("VERBOSE")) fprintf(stderr, "  %s\n", err);
  return ok;
}

/* Euler characteristic V - E + F of the imported polygons (E counted by
** distinct undirected pairs, quadratic: tests only). */
static int euler(const SceneGeometry *g) {
  int ne = 0, cap = 0, (*edges)[2] = NULL;
  for (int f = 0; f < g->nfaces; f++) {
    int s = g->face_start[f], n = g->face_start[f + 1] - s;
    for (int k = 0; k < n; k++) {
      int a = g->face_index[s + k], b = g->face_index[s + (k + 1) % n];
      if (a > b) { int t = a; a = b; b = t; }
      int seen = 0;
      for (int e = 0; e < ne && !seen; e++) seen = edges[e][0] == a && edges[e][1] == b;
      if (seen) continue;
      edges = xgrow(edges, &cap, ne + 1, sizeof *edges);
      edges[ne][0] = a;
      edges[ne++][1] = b;
    }
  }
  free(edges);
  return g->nverts - ne + g->nfaces;
}

/* ---- our own files ---------------------------------------------------------- */

static const char *CUBE_OBJ =
    "# a unit cube, quads, per-face normals (so corners are split per face)\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 1 0 0\nvn 0 1 0\nvn -1 0 0\n"
    "f 1//1 4//1 3//1 2//1\nf 5//2 6//2 7//2 8//2\nf 1//3 2//3 6//3 5//3\n"
    "f 2//4 3//4 7//4 6//4\nf 3//5 4//5 8//5 7//5\nf 4//6 1//6 5//6 8//6\n";

TEST(obj_cube_quads_welded) {
  Arena a;
  arena_init(&a);
  SceneGeometry g;
  char err[256];
  CHECK(import(write_file("cube.obj", CUBE_OBJ), &g, &a, err, sizeof err));
  CHECK_EQ_INT(g.kind, GEOM_MESH);
  CHECK_EQ_INT(g.nverts, 8);
  CHECK_EQ_INT(g.nfaces, 6);
  for (int f = 0; f < g.nfaces; f++) CHECK_EQ_INT(g.face_start[f + 1] - g.face_start[f], 4);
  CHECK_EQ_INT(euler(&g), 2);            /* closed: welded across faces */
  /* vertex numbers as the file's `v` lines (Assimp's own order is first use) */
  static const double xyz[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int v = 0; v < 8 && g.nverts == 8; v++) {
    CHECK_NEAR(g.verts[v].x, xyz[v][0], 0);
    CHECK_NEAR(g.verts[v].y, xyz[v][1], 0);
    CHECK_NEAR(g.verts[v].z, xyz[v][2], 0);
  }
  static const int face0[4] = {0, 3, 2, 1};   /* "f 1//1 4//1 3//1 2//1" */
  for (int k = 0; k < 4; k++) CHECK_EQ_INT(g.face_index[g.face_start[0] + k], face0[k]);
  CHECK_EQ_INT(g.subdiv_level, 0);
  arena_free(&a);
}

TEST(obj_pentagon_and_lines) {
  /* A pentagon stays one face; a line element is dropped. */
  Arena a;
  arena_init(&a);
  SceneGeometry g;
  char err[256];
  const char *obj = "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\nl 1 3\n";
  CHECK(import(write_file("pent.obj", obj), &g, &a, err, sizeof err));
  CHECK_EQ_INT(g.nfaces, 1);
  CHECK_EQ_INT(g.face_start[1], 5);
  CHECK_NEAR(g.verts[g.face_index[2]].x, 3, 0);
  arena_free(&a);
}

TEST(errors_for_bad_files) {
  Arena a;
  arena_init(&a);
  SceneGeometry g;
  char err[256];
  char missing[512];
  snprintf(missing, sizeof missing, "%s/no-such-mesh.obj", tmpdir);
  CHECK(!import(missing, &g, &a, err, sizeof err));
  CHECK(strstr(err, "No such file") != NULL);

  CHECK(!import(write_file("empty.obj", ""), &g, &a, err, sizeof err));
  CHECK(strstr(err, "empty") != NULL);

  CHECK(!import(tmpdir, &g, &a, err, sizeof err));
  CHECK(strstr(err, "is a directory") != NULL);

  CHECK(!import(write_file("points.obj", "v 0 0 0\nv 1 0 0\np 1\np 2\n"), &g, &a, err, sizeof err));
  CHECK(strstr(err, "no polygons") != NULL);

  CHECK(!import(write_file("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), &g, &a, err,
                sizeof err));
  CHECK(err[0] != 0);

  CHECK(!import(write_file("junk.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 99\n"
                                       "property float x\nend_header\n\x01\x02"),
                &g, &a, err, sizeof err));
  CHECK(strstr(err, "unreadable") != NULL);

  CHECK(!import(write_file("garbage.xyzzy", "\x7f\x45\x4c\x46 not a mesh at all"), &g, &a, err,
                sizeof err));
  CHECK(strstr(err, "unreadable") != NULL);
  CHECK(strchr(err, '\n') == NULL);
  arena_free(&a);
}

/* ---- files that break Assimp itself ------------------------------------------------ */

/* Two mutations of the cube PLY files from assimp-testmodels that Assimp
** 5.2.5 does not survive: a binary PLY whose vertex count says 8999999
** (it reads past its buffer and crashes) and an ASCII PLY with a broken
** header (it loops). Written out byte for byte so the test needs no
** package. A newer Assimp may read them or reject them cleanly; either
** way the import must come back, within its time limit, without taking
** this process down. */
static const unsigned char PLY_CRASH[402] = {
  0x70, 0x6c, 0x79, 0x0a, 0x66, 0x6f, 0x72, 0x6d, 0x61, 0x74, 0x20, 0x62, 0x69, 0x6e, 0x61, 0x72,
  0x79, 0x5f, 0x6c, 0x69, 0x74, 0x74, 0x6c, 0x65, 0x5f, 0x65, 0x6e, 0x64, 0x69, 0x61, 0x6e, 0x20,
  0x31, 0x2e, 0x30, 0x0a, 0x63, 0x6f, 0x6d, 0x6d, 0x65, 0x6e, 0x74, 0x20, 0x56, 0x43, 0x47, 0x4c,
  0x49, 0x42, 0x20, 0x67, 0x65, 0x6e, 0x65, 0x72, 0x61, 0x74, 0x65, 0x64, 0x0a, 0x65, 0x6c, 0x65,
  0x6d, 0x65, 0x6e, 0x74, 0x20, 0x76, 0x65, 0x72, 0x74, 0x65, 0x78, 0x20, 0x38, 0x39, 0x39, 0x39,
  0x39, 0x39, 0x39, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x66, 0x6c, 0x6f,
  0x61, 0x28, 0x20, 0x78, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x66, 0x6c,
  0x6f, 0x61, 0x74, 0x20, 0x79, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x66,
  0x6c, 0x6f, 0x65, 0x20, 0x31, 0x32, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20,
  0x6c, 0x69, 0x73, 0x74, 0x20, 0x75, 0x63, 0x68, 0x61, 0x72, 0x20, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x00, 0x00, 0x00, 0x9a, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00,
  0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00,
  0x00, 0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00,
  0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x00, 0xae, 0x00,
  0x03, 0x00, 0x00, 0x00, 0x00, 0x02, 0x2d, 0x31, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x03,
  0x07, 0x00, 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0x03, 0x07, 0x00, 0x00,
  0x00, 0x05, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00,
  0x00, 0x00, 0x05, 0xe8, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0x01,
  0x00, 0x00, 0x00, 0x03, 0x01, 0x00, 0x00, 0x00, 0x05, 0x00, 0x9d, 0x00, 0x06, 0x00, 0x00, 0x00,
  0x03, 0x01, 0x00, 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x03, 0x02, 0x00,
  0x00, 0x00, 0x0a, 0x06, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x03, 0x02, 0x00, 0x00, 0x00,
  0x07, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x03, 0x03, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00,
  0x00, 0x04, 0x00, 0x00, 0x00, 0x03, 0x03, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x00,
};
static const unsigned char PLY_LOOP[260] = {
  0x70, 0x6c, 0x79, 0x0a, 0x66, 0x6f, 0x72, 0x6d, 0x61, 0x74, 0x20, 0x61, 0x73, 0x63, 0x69, 0x69,
  0x20, 0x6c, 0x65, 0x6d, 0x65, 0x6e, 0x74, 0x0b, 0x20, 0x20, 0x20, 0x20, 0x20, 0x61, 0x74, 0x33,
  0x32, 0x20, 0x78, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x0a, 0x70, 0x72, 0x6f,
  0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x66, 0x6c, 0x6f, 0x61, 0x74, 0x33, 0x32, 0x20, 0x79, 0x20,
  0x20, 0x20, 0x20, 0x20, 0x68, 0x20, 0x20, 0x20, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74,
  0x79, 0x20, 0x66, 0x6c, 0x6f, 0x61, 0x74, 0x33, 0x32, 0x20, 0x7a, 0x20, 0x20, 0x20, 0x20, 0x20,
  0x20, 0x20, 0x20, 0x20, 0x0a, 0x65, 0x6c, 0x65, 0x6d, 0x65, 0x6e, 0x74, 0x20, 0x66, 0x61, 0x0a,
  0x63, 0x65, 0x20, 0x36, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20,
  0x20, 0x0a, 0x70, 0x72, 0x6f, 0x70, 0x65, 0x72, 0x74, 0x79, 0x20, 0x6c, 0x69, 0x73, 0x74, 0x20,
  0x75, 0x69, 0x6e, 0x74, 0x38, 0x20, 0x69, 0x6e, 0x74, 0x33, 0x32, 0x20, 0x76, 0x65, 0x72, 0x74,
  0x65, 0x78, 0x5f, 0x69, 0x6e, 0x64, 0x65, 0x78, 0x20, 0x0a, 0x65, 0x6e, 0x64, 0x5f, 0x68, 0x65,
  0x61, 0x64, 0x6e, 0x61, 0x6e, 0x65, 0x72, 0x0a, 0x30, 0x20, 0x30, 0x20, 0x30, 0x0a, 0x30, 0x20,
  0x30, 0x20, 0x31, 0x0a, 0x30, 0x20, 0x31, 0x20, 0x31, 0x0a, 0x30, 0x20, 0x31, 0x20, 0x30, 0x0a,
  0x31, 0x20, 0x30, 0x20, 0x34, 0x0a, 0x34, 0x20, 0x30, 0x20, 0x34, 0x20, 0x35, 0x20, 0x31, 0x0a,
  0x34, 0x20, 0x31, 0x20, 0x35, 0xb6, 0x36, 0x20, 0x32, 0x39, 0x39, 0x39, 0x39, 0xa0, 0x39, 0x0a,
  0x34, 0x20, 0x32, 0x51, 0x36, 0x20, 0x37, 0x20, 0x33, 0x0a, 0x34, 0x20, 0xb5, 0x18, 0x37, 0x20,
  0x34, 0x20, 0x30, 0x0a,
};

static const char *write_bytes(const char *name, const unsigned char *b, size_t n) {
  static char path[512];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  FILE *f = fopen(path, "wb");
  if (f) {
    fwrite(b, 1, n, f);
    fclose(f);
  }
  return path;
}

TEST(assimp_crash_and_loop_are_errors) {
  Arena a;
  arena_init(&a);
  SceneGeometry g;
  char err[256] = "";
  int r = mesh_import_file_limited(write_bytes("crash.ply", PLY_CRASH, sizeof PLY_CRASH), &g, &a,
                                   err, sizeof err, 10);
  if (r != 0) {
    CHECK(err[0] != 0);
    if (getenv("VERBOSE")) fprintf(stderr, "  crash.ply: %s\n", err);
  }
  time_t t0 = time(NULL);
  r = mesh_import_file_limited(write_bytes("loop.ply", PLY_LOOP, sizeof PLY_LOOP), &g, &a, err,
                               sizeof err, 2);
  CHECK(time(NULL) - t0 <= 4);
  if (r != 0) {
    CHECK(err[0] != 0);
    if (getenv("VERBOSE")) fprintf(stderr, "  loop.ply: %s\n", err);
  }
  arena_free(&a);
}

/* ---- assimp-testmodels ---------------------------------------------------------- */

static const char *models_dir(void) {
  const char *d = getenv("SUMI_ASSIMP_MODELS");
  return d ? d : "/usr/share/assimp/models";
}

/* Path of a test model, or NULL (and a skip line) when it is not installed. */
static const char *model(const char *rel) {
  static char path[1024];
  snprintf(path, sizeof path, "%s/%s", models_dir(), rel);
  if (access(path, R_OK) != 0) {
    printf("skip: %s (assimp-testmodels not installed)\n", rel);
    return NULL;
  }
  return path;
}

TEST(testmodels_read) {
  static const struct { const char *file; int nverts, nfaces, euler; } cases[] = {
      {"OBJ/box.obj", 8, 6, 2},
      {"PLY/cube.ply", 8, 6, 2},
      {"STL/triangle.stl", 3, 1, 1},
      {"glTF2/BoxTextured-glTF/BoxTextured.gltf", 8, 12, 2},
      {"OBJ/spider.obj", -1, -1, 0},
      /* Assimp drops the one triangle with an index out of range, keeps 11 */
      {"glTF2/IndexOutOfRange/IndexOutOfRange.gltf", -1, -1, 0},
      {"PLY/Wuson.ply", -1, -1, 0},
      {"STL/Spider_binary.stl", -1, -1, 0},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    const char *path = model(cases[i].file);
    if (!path) continue;
    Arena a;
    arena_init(&a);
    SceneGeometry g;
    char err[512];
    int ok = import(path, &g, &a, err, sizeof err);
    if (!ok) fprintf(stderr, "%s: %s\n", cases[i].file, err);
    CHECK(ok);
    if (ok && cases[i].nverts >= 0) {
      CHECK_EQ_INT(g.nverts, cases[i].nverts);
      CHECK_EQ_INT(g.nfaces, cases[i].nfaces);
      CHECK_EQ_INT(euler(&g), cases[i].euler);
    }
    if (ok) {
      CHECK(g.nfaces > 0);
      for (int k = 0; k < g.face_start[g.nfaces]; k++)
        CHECK(g.face_index[k] >= 0 && g.face_index[k] < g.nverts);
    }
    arena_free(&a);
  }
}

TEST(testmodels_broken) {
  static const char *broken[] = {
      "invalid/empty.obj", "invalid/empty.ply", "invalid/empty.off", "invalid/empty.x",
      "OBJ/testpoints.obj",
      "glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf",
      "glTF2/MissingBin/BoxTextured.gltf", "OFF/invalid.off",
  };
  for (size_t i = 0; i < sizeof broken / sizeof broken[0]; i++) {
    const char *path = model(broken[i]);
    if (!path) continue;
    Arena a;
    arena_init(&a);
    SceneGeometry g;
    char err[512] = "";
    int ok = import(path, &g, &a, err, sizeof err);
    if (ok) fprintf(stderr, "%s: imported %d faces, expected an error\n", broken[i], g.nfaces);
    CHECK(!ok);
    CHECK(err[0] != 0);
    arena_free(&a);
  }
}

/* Texture coordinates come along, per face corner: two quads side by side
** whose shared edge is a UV seam (each quad maps the whole unit square) give
** the shared vertices two coordinates, one in each quad's triangles. */
TEST(obj_uvs_per_corner) {
  const char *obj =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
      "f 1/1 2/2 3/3 4/4\nf 2/1 5/2 6/3 3/4\n";
  Arena a;
  arena_init(&a);
  SceneGeometry g;
  char err[256];
  CHECK(import(write_file("seam.obj", obj), &g, &a, err, sizeof err));
  CHECK(g.face_uv != NULL);
  CHECK_EQ_INT(g.nverts, 6);   /* welded: the seam's vertices are shared */
  Mesh *m = tess_polygons(&g);
  CHECK(m->uv != NULL && m->corner_uv != NULL);
  int seen = 0;
  for (int t = 0; t < m->ntris; t++)
    for (int k = 0; k < 3; k++) {
      Vec3 p = m->pos[m->tri[t][k]];
      Vec2 uv = mesh_corner_uv(m, t, k);
      double x0 = m->tri_face[t];   /* quad 0 spans x 0..1, quad 1 spans 1..2 */
      CHECK_NEAR(uv.x, p.x - x0, 1e-6);
      CHECK_NEAR(uv.y, p.y, 1e-6);
      seen++;
    }
  CHECK_EQ_INT(seen, 12);
  mesh_destroy(m);
  arena_free(&a);
  /* a file without coordinates has none */
  arena_init(&a);
  CHECK(import(write_file("cube.obj", CUBE_OBJ), &g, &a, err, sizeof err));
  CHECK(g.face_uv == NULL);
  m = tess_polygons(&g);
  CHECK(m->uv == NULL);
  mesh_destroy(m);
  arena_free(&a);
}

/* Across frames: a file read again unchanged comes from the cache, the
** same geometry and the same note; a file rewritten (another size) or
** touched (another time) is read again; a failed read is not kept. */
static int same_geometry(const SceneGeometry *a, const SceneGeometry *b) {
  int nidx = a->face_start[a->nfaces];
  return a->nverts == b->nverts && a->nfaces == b->nfaces && nidx == b->face_start[b->nfaces] &&
         !memcmp(a->verts, b->verts, sizeof(Vec3) * (size_t)a->nverts) &&
         !memcmp(a->face_start, b->face_start, sizeof(int) * ((size_t)a->nfaces + 1)) &&
         !memcmp(a->face_index, b->face_index, sizeof(int) * (size_t)nidx) &&
         (a->face_uv == NULL) == (b->face_uv == NULL) &&
         (!a->face_uv || !memcmp(a->face_uv, b->face_uv, sizeof(Vec2) * (size_t)nidx));
}

TEST(cache_across_frames) {
  Arena a;
  arena_init(&a);
  SceneGeometry g0, g1, g2, g3;
  char err0[256], err1[256], err2[256];
  /* one face of three distinct corners, one dropped: a note */
  const char *obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 1 1 2\n";
  const char *path = write_file("kept.obj", obj);
  CHECK(import(path, &g0, &a, err0, sizeof err0));   /* no cache yet: not kept */
  mesh_import_cache_keep(2);
  long hits = mesh_import_cache_hits();
  CHECK(import(path, &g1, &a, err1, sizeof err1));
  CHECK_EQ_INT(mesh_import_cache_hits(), hits);
  CHECK(import(path, &g2, &a, err2, sizeof err2));
  CHECK_EQ_INT(mesh_import_cache_hits(), hits + 1);
  CHECK(same_geometry(&g0, &g1) && same_geometry(&g0, &g2) && g2.face_uv != NULL);
  CHECK(g2.verts != g1.verts);   /* a copy in the caller's arena */
  CHECK(err0[0] && !strcmp(err0, err1) && !strcmp(err0, err2));
  /* rewritten: a second triangle */
  write_file("kept.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  CHECK(import(path, &g3, &a, err2, sizeof err2));
  CHECK_EQ_INT(mesh_import_cache_hits(), hits + 1);
  CHECK_EQ_INT(g3.nfaces, 2);
  CHECK(!err2[0]);
  /* the same bytes with another modification time are read again */
  struct timespec times[2] = {{0, UTIME_OMIT}, {1000000000, 0}};
  CHECK(utimensat(AT_FDCWD, path, times, 0) == 0);
  CHECK(import(path, &g3, &a, err2, sizeof err2));
  CHECK_EQ_INT(mesh_import_cache_hits(), hits + 1);
  CHECK(import(path, &g3, &a, err2, sizeof err2));
  CHECK_EQ_INT(mesh_import_cache_hits(), hits + 2);
  CHECK_EQ_INT(g3.nfaces, 2);
  /* a failure is said again, not kept */
  write_file("kept.obj", "v 0 0 0\nv 1 0 0\n");
  CHECK(!import(path, &g3, &a, err2, sizeof err2));
  CHECK(!import(path, &g3, &a, err2, sizeof err2));
  CHECK_EQ_INT(mesh_import_cache_hits(), hits + 2);
  mesh_import_cache_clear();
  write_file("kept.obj", obj);
  arena_free(&a);
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "%s/sumi-import-XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
  if (!mkdtemp(tmpdir)) { perror("mkdtemp"); return 1; }
  RUN(obj_cube_quads_welded);
  RUN(obj_pentagon_and_lines);
  RUN(obj_uvs_per_corner);
  RUN(errors_for_bad_files);
  RUN(assimp_crash_and_loop_are_errors);
  RUN(testmodels_read);
  RUN(testmodels_broken);
  RUN(cache_across_frames);
  /* remove what we wrote */
  static const char *files[] = {"cube.obj", "seam.obj", "pent.obj", "empty.obj", "points.obj", "range.obj",
                                "junk.ply", "garbage.xyzzy", "crash.ply", "loop.ply", "kept.obj"};
  for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
    char p[512];
    snprintf(p, sizeof p, "%s/%s", tmpdir, files[i]);
    remove(p);
  }
  rmdir(tmpdir);
  return unit_done();
}
