/*
** Mesh import through Assimp's C API (see mesh_import.h): read, flatten
** the node hierarchy, drop points and lines, weld equal positions, and
** copy the polygons into the scene arena.
*/
#include "mesh_import.h"

#include "infile.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

/* Pre-transform: every mesh in world placement, one flat list.
** Join identical vertices inside each mesh; check the data; sort points
** and lines apart so they can be dropped. No triangulation. */
static const unsigned IMPORT_FLAGS = aiProcess_JoinIdenticalVertices |
                                     aiProcess_PreTransformVertices |
                                     aiProcess_ValidateDataStructure | aiProcess_SortByPType;

/* ---- welding ------------------------------------------------------------ */

/* A vertex position with its input index: sorted, equal positions meet. */
typedef struct WeldKey { Vec3 p; int i; } WeldKey;

static int weld_cmp(const void *a, const void *b) {
  const WeldKey *p = a, *q = b;
  if (p->p.x != q->p.x) return p->p.x < q->p.x ? -1 : 1;
  if (p->p.y != q->p.y) return p->p.y < q->p.y ? -1 : 1;
  if (p->p.z != q->p.z) return p->p.z < q->p.z ? -1 : 1;
  return (p->i > q->i) - (p->i < q->i);
}

/* remap[i] = the new index of pos[i]: equal positions share one, numbered
** in order of first appearance; returns the count of distinct positions.
** (Ties sort by index, so the result is deterministic.) */
static int weld(const Vec3 *pos, int n, int *remap) {
  WeldKey *key = xmalloc(sizeof *key * (size_t)(n > 0 ? n : 1));
  int *first = xmalloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  for (int i = 0; i < n; i++) key[i] = (WeldKey){pos[i], i};
  qsort(key, (size_t)n, sizeof *key, weld_cmp);
  for (int k = 0; k < n; k++) {
    int same = k > 0 && key[k - 1].p.x == key[k].p.x && key[k - 1].p.y == key[k].p.y &&
               key[k - 1].p.z == key[k].p.z;
    first[key[k].i] = same ? first[key[k - 1].i] : key[k].i;
  }
  int count = 0;
  for (int i = 0; i < n; i++) remap[i] = first[i] == i ? count++ : -1;
  for (int i = 0; i < n; i++) if (remap[i] < 0) remap[i] = remap[first[i]];
  free(key);
  free(first);
  return count;
}

/* ---- reading ------------------------------------------------------------- */

static int failf(char *err, size_t errlen, const char *fmt, ...)
  __attribute__((format(printf, 3, 4)));
static int failf(char *err, size_t errlen, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, errlen, fmt, ap);
  va_end(ap);
  return 0;
}

/* Count the vertices and polygon corners of the scene's polygon faces. */
static int count_scene(const struct aiScene *sc, long *nverts, long *nfaces, long *nidx) {
  *nverts = *nfaces = *nidx = 0;
  for (unsigned m = 0; m < sc->mNumMeshes; m++) {
    const struct aiMesh *mesh = sc->mMeshes[m];
    *nverts += mesh->mNumVertices;
    for (unsigned f = 0; f < mesh->mNumFaces; f++)
      if (mesh->mFaces[f].mNumIndices >= 3) {
        (*nfaces)++;
        *nidx += mesh->mFaces[f].mNumIndices;
      }
  }
  return 1;
}

/* Copy the polygons into out (arena), welding positions; drops repeated
** corners and faces left with fewer than 3. */
static void copy_scene(const struct aiScene *sc, long nverts, long nfaces, long nidx,
                       SceneGeometry *out, Arena *arena) {
  Vec3 *pos = xmalloc(sizeof(Vec3) * (size_t)(nverts > 0 ? nverts : 1));
  int *remap = xmalloc(sizeof(int) * (size_t)(nverts > 0 ? nverts : 1));
  long v = 0;
  for (unsigned m = 0; m < sc->mNumMeshes; m++)
    for (unsigned i = 0; i < sc->mMeshes[m]->mNumVertices; i++, v++) {
      struct aiVector3D p = sc->mMeshes[m]->mVertices[i];
      pos[v] = v3(p.x, p.y, p.z);
    }
  int nunique = weld(pos, (int)nverts, remap);
  out->verts = arena_alloc(arena, sizeof(Vec3) * (size_t)(nunique > 0 ? nunique : 1));
  for (long i = 0; i < nverts; i++) out->verts[remap[i]] = pos[i];
  out->nverts = nunique;
  out->face_start = arena_alloc(arena, sizeof(int) * (size_t)(nfaces + 1));
  out->face_index = arena_alloc(arena, sizeof(int) * (size_t)(nidx > 0 ? nidx : 1));
  int has_uv = 0;   /* any mesh's first UV channel; the others' corners read (0, 0) */
  for (unsigned m = 0; m < sc->mNumMeshes; m++) has_uv |= sc->mMeshes[m]->mTextureCoords[0] != NULL;
  if (has_uv) out->face_uv = arena_alloc(arena, sizeof(Vec2) * (size_t)(nidx > 0 ? nidx : 1));
  int nf = 0, k = 0;
  long base = 0;
  for (unsigned m = 0; m < sc->mNumMeshes; m++) {
    const struct aiMesh *mesh = sc->mMeshes[m];
    const struct aiVector3D *uv = mesh->mTextureCoords[0];
    for (unsigned f = 0; f < mesh->mNumFaces; f++) {
      const struct aiFace *face = &mesh->mFaces[f];
      if (face->mNumIndices < 3) continue;
      int start = k;
      for (unsigned c = 0; c < face->mNumIndices; c++) {
        int w = remap[base + face->mIndices[c]];
        if (k > start && out->face_index[k - 1] == w) continue;  /* repeated corner */
        if (has_uv) out->face_uv[k] = uv ? (Vec2){uv[face->mIndices[c]].x, uv[face->mIndices[c]].y} : (Vec2){0, 0};
        out->face_index[k++] = w;
      }
      if (k - start > 1 && out->face_index[k - 1] == out->face_index[start]) k--;
      if (k - start < 3) { k = start; continue; }
      out->face_start[nf++] = start;
    }
    base += mesh->mNumVertices;
  }
  out->face_start[nf] = k;
  out->nfaces = nf;
  free(pos);
  free(remap);
}

/* ---- OBJ vertex order ---------------------------------------------------- */

/* A file vertex: its position and its `v` line number (0-based). */
typedef struct FileVert { Vec3 p; int i; } FileVert;

static int filevert_cmp(const void *a, const void *b) {
  const FileVert *p = a, *q = b;
  if (p->p.x != q->p.x) return p->p.x < q->p.x ? -1 : 1;
  return (p->i > q->i) - (p->i < q->i);
}

static int has_suffix(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

/* The `v` lines of an OBJ file; NULL when it cannot be read again. */
static FileVert *obj_vertices(const char *path, int *n) {
  FILE *f = fopen(path, "r");
  if (!f) return NULL;
  FileVert *v = NULL;
  int cap = 0;
  char line[512];
  *n = 0;
  while (fgets(line, sizeof line, f)) {
    double x, y, z;
    if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t') &&
        sscanf(line + 2, "%lf %lf %lf", &x, &y, &z) == 3) {
      v = xgrow(v, &cap, *n + 1, sizeof *v);
      v[*n] = (FileVert){v3(x, y, z), *n};
      (*n)++;
    }
  }
  fclose(f);
  return v;
}

/* The `f` lines of an OBJ file (each one face as written), or -1 when it
** cannot be read again. */
static long obj_face_lines(const char *path) {
  FILE *f = fopen(path, "r");
  if (!f) return -1;
  long n = 0;
  int c, col = 0, first = 0;   /* col: characters read on this line */
  while ((c = getc(f)) != EOF) {
    if (col == 0) first = c;
    if (col == 1 && first == 'f' && (c == ' ' || c == '\t' || c == '\n' || c == '\r')) n++;
    col = c == '\n' ? 0 : col + 1;
  }
  if (col == 1 && first == 'f') n++;   /* a last line of just `f` */
  fclose(f);
  return n;
}

/* The first file vertex within a float's rounding of q, or -1. */
static int find_file_vertex(const FileVert *v, int n, Vec3 q) {
  double eps = 1e-6 * (1 + fabs(q.x) + fabs(q.y) + fabs(q.z));
  int lo = 0, hi = n;   /* first v[k].p.x >= q.x - eps */
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (v[mid].p.x < q.x - eps) lo = mid + 1; else hi = mid;
  }
  int best = -1;
  for (int k = lo; k < n && v[k].p.x <= q.x + eps; k++)
    if (fabs(v[k].p.y - q.y) <= eps && fabs(v[k].p.z - q.z) <= eps && (best < 0 || v[k].i < best))
      best = v[k].i;
  return best;
}

/* Assimp numbers an OBJ's vertices in the order its faces first use them;
** put them back in the file's `v` order (vertices no face uses left out),
** so indices read off the file (for creases and corners) hold. Leaves g
** as it is when the positions cannot be matched one to one. */
static void obj_file_order(const char *path, SceneGeometry *g) {
  int n;
  FileVert *fv = obj_vertices(path, &n);
  if (!fv) return;
  qsort(fv, (size_t)n, sizeof *fv, filevert_cmp);
  int *line = xmalloc(sizeof(int) * (size_t)(g->nverts + 1));
  int *seen = xcalloc((size_t)n + 1, sizeof(int));
  int ok = 1;
  for (int i = 0; i < g->nverts && ok; i++) {
    line[i] = find_file_vertex(fv, n, g->verts[i]);
    ok = line[i] >= 0 && !seen[line[i]]++;
  }
  if (ok) {
    int *rank = xcalloc((size_t)n + 1, sizeof(int));   /* file line -> new index */
    for (int i = 0; i < g->nverts; i++) rank[line[i]] = 1;
    for (int k = 0, r = 0; k < n; k++) rank[k] = rank[k] ? r++ : -1;
    Vec3 *pos = xmalloc(sizeof(Vec3) * (size_t)(g->nverts + 1));
    for (int i = 0; i < g->nverts; i++) pos[rank[line[i]]] = g->verts[i];
    memcpy(g->verts, pos, sizeof(Vec3) * (size_t)g->nverts);
    for (int k = 0; k < g->face_start[g->nfaces]; k++)
      g->face_index[k] = rank[line[g->face_index[k]]];
    free(pos);
    free(rank);
  }
  free(line);
  free(seen);
  free(fv);
}

static int check_file(const char *path, char *err, size_t errlen) {
  struct stat st;
  if (!infile_check(path, INFILE_MAX_MESH, "a mesh", err, errlen) || stat(path, &st) != 0) return 0;
  FILE *f = fopen(path, "rb");
  if (!f) return failf(err, errlen, "%s", strerror(errno));
  fclose(f);
  if (st.st_size == 0) return failf(err, errlen, "the file is empty");
  return 1;
}

/* Assimp's messages can span lines; keep the first line. */
static void first_line(char *s) {
  s[strcspn(s, "\r\n")] = 0;
}

static int import_file(const char *path, SceneGeometry *out, Arena *arena, char *err,
                       size_t errlen) {
  memset(out, 0, sizeof *out);
  out->kind = GEOM_MESH;
  if (!check_file(path, err, errlen)) return 0;
  const struct aiScene *sc = aiImportFile(path, IMPORT_FLAGS);
  if (!sc) {
    const char *why = aiGetErrorString();
    int ok = strstr(why, "No suitable reader")
                 ? failf(err, errlen, "unreadable: not a mesh format Assimp knows")
                 : failf(err, errlen, "unreadable: %s", why);
    first_line(err);
    return ok;
  }
  int ok = 1;
  long nverts = 0, nfaces = 0, nidx = 0;
  if (sc->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
    ok = failf(err, errlen, "the file holds no complete scene");
  else if (count_scene(sc, &nverts, &nfaces, &nidx), nfaces == 0)
    ok = failf(err, errlen, "the file holds no polygons (only points, lines or nothing)");
  else if (nverts > MESH_IMPORT_MAX_VERTS)
    ok = failf(err, errlen, "%ld vertices; the limit is %d (MESH_IMPORT_MAX_VERTS)", nverts,
               MESH_IMPORT_MAX_VERTS);
  else if (nfaces > MESH_IMPORT_MAX_FACES || nidx > 4L * MESH_IMPORT_MAX_FACES)
    ok = failf(err, errlen, "%ld faces; the limit is %d (MESH_IMPORT_MAX_FACES)", nfaces,
               MESH_IMPORT_MAX_FACES);
  else
    copy_scene(sc, nverts, nfaces, nidx, out, arena);
  long written = ok ? nfaces : 0;   /* the faces as the file has them */
  if (ok && has_suffix(path, ".obj")) {
    obj_file_order(path, out);
    long lines = obj_face_lines(path);
    if (lines > written) written = lines;
  }
  aiReleaseImport(sc);
  if (ok && out->nfaces == 0)
    ok = failf(err, errlen, "the file holds no polygon with 3 distinct corners");
  else if (ok && written > out->nfaces)   /* a note, not a failure: the rest still draws */
    snprintf(err, errlen, "%ld of its %ld faces %s not imported (fewer than 3 distinct corners, or "
             "unreadable): the mesh may show holes", written - out->nfaces, written,
             written - out->nfaces == 1 ? "was" : "were");
  return ok;
}

/* ---- isolation ------------------------------------------------------------ */

/* Assimp crashes or loops on some malformed files (seen with PLY), so it
** reads each file in a child process: a crash or a runaway there becomes
** an error here. The child sends its result down a pipe:
**   int ok; then either int len + len bytes of reason,
**   or int nverts, nfaces, nidx, has_uv + verts (3 doubles each) + face_start
**   (nfaces + 1 ints) + face_index (nidx ints) + with has_uv, face_uv (nidx
**   pairs of doubles). */

static int write_all(int fd, const void *p, size_t n) {
  const char *c = p;
  while (n > 0) {
    ssize_t k = write(fd, c, n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return 0;
    c += k;
    n -= (size_t)k;
  }
  return 1;
}

static _Noreturn void child_import(const char *path, int fd, int timeout_s) {
  alarm((unsigned)timeout_s);   /* SIGALRM ends a runaway */
#if !defined(__SANITIZE_ADDRESS__)
  /* a huge count in a header fails to allocate instead of swapping: the
  ** address space we have now plus MESH_IMPORT_MAX_MEMORY */
  long pages = 0;
  FILE *statm = fopen("/proc/self/statm", "r");
  if (statm) {
    if (fscanf(statm, "%ld", &pages) != 1) pages = 0;
    fclose(statm);
  }
  rlim_t limit = (rlim_t)pages * (rlim_t)sysconf(_SC_PAGESIZE) + (rlim_t)MESH_IMPORT_MAX_MEMORY;
  struct rlimit rl = {limit, limit};
  setrlimit(RLIMIT_AS, &rl);
#endif
  Arena a;
  arena_init(&a);
  SceneGeometry g;
  char err[512] = "";
  int ok = import_file(path, &g, &a, err, sizeof err);
  int w = write_all(fd, &ok, sizeof ok);
  int len = (int)strlen(err);
  if (!ok) {
    w = w && write_all(fd, &len, sizeof len) && write_all(fd, err, (size_t)len);
  } else {
    int head[5] = {g.nverts, g.nfaces, g.face_start[g.nfaces], g.face_uv != NULL, len};
    w = w && write_all(fd, head, sizeof head) && write_all(fd, err, (size_t)len) &&
        write_all(fd, g.verts, sizeof(Vec3) * (size_t)g.nverts) &&
        write_all(fd, g.face_start, sizeof(int) * (size_t)(g.nfaces + 1)) &&
        write_all(fd, g.face_index, sizeof(int) * (size_t)head[2]) &&
        (!g.face_uv || write_all(fd, g.face_uv, sizeof(Vec2) * (size_t)head[2]));
  }
  _exit(w ? 0 : 1);   /* no atexit handlers, no flushing the parent's buffers */
}

/* Everything the child wrote, until it closes the pipe; *n bytes. */
static char *read_all(int fd, size_t *n) {
  size_t cap = 1 << 16;
  char *buf = xmalloc(cap);
  *n = 0;
  for (;;) {
    if (*n == cap) buf = xrealloc(buf, cap *= 2);
    ssize_t k = read(fd, buf + *n, cap - *n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) break;
    *n += (size_t)k;
  }
  return buf;
}

/* Take bytes from the child's message; 0 when it is shorter than that. */
typedef struct Reader { const char *p; size_t left; } Reader;
static int take(Reader *r, void *dst, size_t n) {
  if (r->left < n) return 0;
  memcpy(dst, r->p, n);
  r->p += n;
  r->left -= n;
  return 1;
}

/* Rebuild the geometry (in arena) from the child's message. */
static int unpack(const char *buf, size_t n, SceneGeometry *out, Arena *arena, char *err,
                  size_t errlen) {
  Reader r = {buf, n};
  int ok, head[5], len;
  if (!take(&r, &ok, sizeof ok)) return failf(err, errlen, "Assimp ended without an answer");
  if (!ok) {
    if (!take(&r, &len, sizeof len) || len < 0 || (size_t)len > r.left)
      return failf(err, errlen, "Assimp ended without an answer");
    return failf(err, errlen, "%.*s", len, r.p);
  }
  if (!take(&r, head, sizeof head) || head[0] < 1 || head[1] < 1 || head[2] < 3 || (head[3] & ~1) ||
      head[4] < 0 || (size_t)head[4] >= errlen ||
      r.left != (size_t)head[4] + sizeof(Vec3) * (size_t)head[0] +
                    sizeof(int) * ((size_t)head[1] + 1 + (size_t)head[2]) +
                    (head[3] ? sizeof(Vec2) * (size_t)head[2] : 0))
    return failf(err, errlen, "Assimp ended without a whole answer");
  take(&r, err, (size_t)head[4]);   /* the note on faces not imported, or "" */
  err[head[4]] = 0;
  out->nverts = head[0];
  out->nfaces = head[1];
  out->verts = arena_alloc(arena, sizeof(Vec3) * (size_t)head[0]);
  out->face_start = arena_alloc(arena, sizeof(int) * ((size_t)head[1] + 1));
  out->face_index = arena_alloc(arena, sizeof(int) * (size_t)head[2]);
  take(&r, out->verts, sizeof(Vec3) * (size_t)head[0]);
  take(&r, out->face_start, sizeof(int) * ((size_t)head[1] + 1));
  take(&r, out->face_index, sizeof(int) * (size_t)head[2]);
  if (head[3]) {
    out->face_uv = arena_alloc(arena, sizeof(Vec2) * (size_t)head[2]);
    take(&r, out->face_uv, sizeof(Vec2) * (size_t)head[2]);
  }
  return 1;
}

/* Why the child ended without an answer. */
static int child_failed(int status, int timeout_s, char *err, size_t errlen) {
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM)
    return failf(err, errlen, "Assimp took longer than %d s on it (MESH_IMPORT_TIMEOUT)",
                 timeout_s);
  if (WIFSIGNALED(status))
    return failf(err, errlen, "Assimp crashed reading it (%s): the file is malformed",
                 strsignal(WTERMSIG(status)));
  return failf(err, errlen, "Assimp failed reading it (out of memory?)");
}

/* ---- the cache across frames ---------------------------------------------- */

/* One file's import as the file was then (its identity, time and size),
** with the note it gave. */
typedef struct Kept {
  char *path;
  dev_t dev;
  ino_t ino;
  struct timespec mtime;
  off_t size;
  char *note;
  int nverts, nfaces, nidx;
  Vec3 *verts;
  int *face_start, *face_index;
  Vec2 *face_uv;               /* NULL: no texture coordinates */
} Kept;

static struct {
  int max, n, next;            /* entries kept (0: no cache), held, replaced next */
  Kept *e;
  long hits;
} kept;

static void *dup_bytes(const void *p, size_t n, void *dst) {
  if (!dst) dst = xmalloc(n + 1);
  if (n) memcpy(dst, p, n);
  return dst;
}

static void kept_free(Kept *k) {
  free(k->path);
  free(k->note);
  free(k->verts);
  free(k->face_start);
  free(k->face_index);
  free(k->face_uv);
  memset(k, 0, sizeof *k);
}

void mesh_import_cache_keep(int entries) {
  mesh_import_cache_clear();
  kept.max = entries > 0 ? entries : 0;
  kept.e = kept.max ? xcalloc((size_t)kept.max, sizeof *kept.e) : NULL;
}

void mesh_import_cache_clear(void) {
  for (int i = 0; i < kept.n; i++) kept_free(&kept.e[i]);
  free(kept.e);
  memset(&kept, 0, sizeof kept);
}

long mesh_import_cache_hits(void) {
  return kept.hits;
}

static int same_file(const Kept *k, const char *path, const struct stat *st) {
  return !strcmp(k->path, path) && k->dev == st->st_dev && k->ino == st->st_ino &&
         k->mtime.tv_sec == st->st_mtim.tv_sec && k->mtime.tv_nsec == st->st_mtim.tv_nsec &&
         k->size == st->st_size;
}

/* The kept import of path as it is now into out (in arena): 1, or 0 when
** there is none. */
static int kept_take(const char *path, const struct stat *st, SceneGeometry *out, Arena *arena,
                     char *err, size_t errlen) {
  for (int i = 0; i < kept.n; i++) {
    const Kept *k = &kept.e[i];
    if (!same_file(k, path, st)) continue;
    out->nverts = k->nverts;
    out->nfaces = k->nfaces;
    out->verts = dup_bytes(k->verts, sizeof(Vec3) * (size_t)k->nverts,
                           arena_alloc(arena, sizeof(Vec3) * (size_t)k->nverts));
    out->face_start = dup_bytes(k->face_start, sizeof(int) * ((size_t)k->nfaces + 1),
                                arena_alloc(arena, sizeof(int) * ((size_t)k->nfaces + 1)));
    out->face_index = dup_bytes(k->face_index, sizeof(int) * (size_t)k->nidx,
                                arena_alloc(arena, sizeof(int) * (size_t)k->nidx));
    if (k->face_uv)
      out->face_uv = dup_bytes(k->face_uv, sizeof(Vec2) * (size_t)k->nidx,
                               arena_alloc(arena, sizeof(Vec2) * (size_t)k->nidx));
    snprintf(err, errlen, "%s", k->note);
    kept.hits++;
    return 1;
  }
  return 0;
}

/* Keep g, read from path as st has it, with its note (the oldest entry
** goes when the cache is full). */
static void kept_store(const char *path, const struct stat *st, const SceneGeometry *g,
                       const char *note) {
  Kept *k;
  if (kept.n < kept.max) k = &kept.e[kept.n++];
  else {
    k = &kept.e[kept.next];
    kept.next = (kept.next + 1) % kept.max;
    kept_free(k);
  }
  k->path = xstrdup(path);
  k->dev = st->st_dev;
  k->ino = st->st_ino;
  k->mtime = st->st_mtim;
  k->size = st->st_size;
  k->note = xstrdup(note);
  k->nverts = g->nverts;
  k->nfaces = g->nfaces;
  k->nidx = g->face_start[g->nfaces];
  k->verts = dup_bytes(g->verts, sizeof(Vec3) * (size_t)g->nverts, NULL);
  k->face_start = dup_bytes(g->face_start, sizeof(int) * ((size_t)g->nfaces + 1), NULL);
  k->face_index = dup_bytes(g->face_index, sizeof(int) * (size_t)k->nidx, NULL);
  k->face_uv = g->face_uv ? dup_bytes(g->face_uv, sizeof(Vec2) * (size_t)k->nidx, NULL) : NULL;
}

/* ---- the entry points ------------------------------------------------------ */

static int import_isolated(const char *path, SceneGeometry *out, Arena *arena, char *err,
                           size_t errlen, int timeout_s);

int mesh_import_file_limited(const char *path, SceneGeometry *out, Arena *arena, char *err,
                             size_t errlen, int timeout_s) {
  memset(out, 0, sizeof *out);
  out->kind = GEOM_MESH;
  if (!check_file(path, err, errlen)) return 1;
  struct stat st;
  int known = kept.max > 0 && stat(path, &st) == 0;
  if (known && kept_take(path, &st, out, arena, err, errlen)) return 0;
  int status = import_isolated(path, out, arena, err, errlen, timeout_s);
  if (known && status == 0) kept_store(path, &st, out, err);
  return status;
}

/* Assimp's read in a child process (see "isolation" above). */
static int import_isolated(const char *path, SceneGeometry *out, Arena *arena, char *err,
                           size_t errlen, int timeout_s) {
  int fd[2];
  if (pipe(fd) != 0) return import_file(path, out, arena, err, errlen) ? 0 : 1;
  fflush(NULL);   /* the child must not write our buffered output twice */
  pid_t pid = fork();
  if (pid < 0) {
    close(fd[0]);
    close(fd[1]);
    return import_file(path, out, arena, err, errlen) ? 0 : 1;
  }
  if (pid == 0) {
    close(fd[0]);
    child_import(path, fd[1], timeout_s);
  }
  close(fd[1]);
  size_t n;
  char *buf = read_all(fd[0], &n);
  close(fd[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  int ok = WIFEXITED(status) && WEXITSTATUS(status) == 0
               ? unpack(buf, n, out, arena, err, errlen)
               : child_failed(status, timeout_s, err, errlen);
  free(buf);
  if (!ok) {
    memset(out, 0, sizeof *out);
    out->kind = GEOM_MESH;
  }
  return ok ? 0 : 1;
}

int mesh_import_file(const char *path, SceneGeometry *out, Arena *arena, char *err,
                     size_t errlen) {
  return mesh_import_file_limited(path, out, arena, err, errlen, MESH_IMPORT_TIMEOUT);
}

int mesh_import_file_in_process(const char *path, SceneGeometry *out, Arena *arena, char *err,
                                size_t errlen) {
  return import_file(path, out, arena, err, errlen) ? 0 : 1;
}
