/*
** FOLD import: JSON (through cJSON) into a SceneOrigami. See fold.h for
** what is read and how the folded frame and faceOrders are interpreted.
*/
#include "fold.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../geom/origami.h"
#include "infile.h"
#include "tempfile.h"

/* Frames inherit through at most this many parents (a cycle stops here). */
#define FOLD_MAX_INHERIT 64

typedef struct FoldCtx {
  const char *path;
  char *err;
  size_t errlen;
  cJSON *root;
  cJSON *frames;          /* file_frames, or NULL */
  int nframes;            /* 1 + entries of file_frames */
} FoldCtx;

static int fail(FoldCtx *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static int fail(FoldCtx *c, const char *fmt, ...) {
  int n = snprintf(c->err, c->errlen, "%s: ", c->path);
  if (n < 0 || (size_t)n >= c->errlen) return 0;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(c->err + n, c->errlen - (size_t)n, fmt, ap);
  va_end(ap);
  return 0;
}

/* ---- frames -------------------------------------------------------------- */

static cJSON *frame(const FoldCtx *c, int k) {
  return k == 0 ? c->root : cJSON_GetArrayItem(c->frames, k - 1);
}

/* The key's value in frame k, following frame_inherit to parents. */
static cJSON *frame_get(const FoldCtx *c, int k, const char *key) {
  for (int depth = 0; depth < FOLD_MAX_INHERIT && k >= 0 && k < c->nframes; depth++) {
    cJSON *f = frame(c, k);
    if (!cJSON_IsObject(f)) return NULL;
    cJSON *v = cJSON_GetObjectItemCaseSensitive(f, key);
    if (v) return v;
    if (k == 0 || !cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(f, "frame_inherit"))) return NULL;
    cJSON *p = cJSON_GetObjectItemCaseSensitive(f, "frame_parent");
    k = cJSON_IsNumber(p) ? (int)p->valuedouble : 0;
  }
  return NULL;
}

static int frame_has_class(const FoldCtx *c, int k, const char *cls) {
  cJSON *f = frame(c, k), *cl = cJSON_IsObject(f) ? cJSON_GetObjectItemCaseSensitive(f, "frame_classes") : NULL, *e;
  cJSON_ArrayForEach(e, cl)
    if (cJSON_IsString(e) && strcmp(e->valuestring, cls) == 0) return 1;
  return 0;
}

/* "file_frames[0].vertices_coords" or "vertices_coords": a key's name in
** messages. */
static const char *key_name(int k, const char *key, char *buf, size_t n) {
  if (k == 0) snprintf(buf, n, "%s", key);
  else snprintf(buf, n, "file_frames[%d].%s", k - 1, key);
  return buf;
}

/* ---- values ---------------------------------------------------------- */

static int get_index(const cJSON *v, int *out) {
  if (!cJSON_IsNumber(v)) return 0;
  double d = v->valuedouble;
  if (d != floor(d) || d < 0 || d > 2147483647.0) return 0;
  *out = (int)d;
  return 1;
}

/* Read a coordinate list into p (n points, 3 components; z = 0 for 2D). */
static int read_coords(FoldCtx *c, const cJSON *a, const char *name, Arena *arena, Vec3 **p, int *n) {
  if (!cJSON_IsArray(a)) return fail(c, "%s must be a list of points", name);
  *n = cJSON_GetArraySize(a);
  if (*n > ORIGAMI_MAX_VERTS)
    return fail(c, "%s: %d vertices (limit ORIGAMI_MAX_VERTS is %d)", name, *n, ORIGAMI_MAX_VERTS);
  *p = arena_alloc(arena, (size_t)(*n ? *n : 1) * sizeof **p);
  int i = 0;
  const cJSON *e;
  cJSON_ArrayForEach(e, a) {
    int d = cJSON_GetArraySize(e);
    if (!cJSON_IsArray(e) || d < 2 || d > 3)
      return fail(c, "%s[%d] must be a point of 2 or 3 numbers", name, i);
    double x[3] = {0, 0, 0};
    for (int k = 0; k < d; k++) {
      const cJSON *q = cJSON_GetArrayItem(e, k);
      if (!cJSON_IsNumber(q) || !isfinite(q->valuedouble))
        return fail(c, "%s[%d] must be a point of 2 or 3 numbers", name, i);
      x[k] = q->valuedouble;
    }
    (*p)[i++] = v3(x[0], x[1], x[2]);
  }
  return 1;
}

/* Bring points lying in one plane into the xy-plane; 0 if they do not.
** Coordinate planes are kept as they are (XZ: x, z), others projected on
** an orthonormal basis of the plane. */
static int flatten(Vec3 *p, int n) {
  if (n == 0) return 1;
  Vec3 lo = p[0], hi = p[0];
  for (int i = 1; i < n; i++) {
    lo = v3(fmin(lo.x, p[i].x), fmin(lo.y, p[i].y), fmin(lo.z, p[i].z));
    hi = v3(fmax(hi.x, p[i].x), fmax(hi.y, p[i].y), fmax(hi.z, p[i].z));
  }
  double tol = 1e-7 * fmax(v3_len(v3_sub(hi, lo)), 1e-300);
  if (hi.z - lo.z <= tol) {
    for (int i = 0; i < n; i++) p[i].z = 0;
    return 1;
  }
  if (hi.y - lo.y <= tol) {
    for (int i = 0; i < n; i++) p[i] = v3(p[i].x, p[i].z, 0);
    return 1;
  }
  if (hi.x - lo.x <= tol) {
    for (int i = 0; i < n; i++) p[i] = v3(p[i].y, p[i].z, 0);
    return 1;
  }
  /* a general plane: the normal from the widest triangle on point 0 */
  int a = 0;
  double best = 0;
  for (int i = 1; i < n; i++) {
    double d = v3_len(v3_sub(p[i], p[0]));
    if (d > best) best = d, a = i;
  }
  Vec3 u = v3_norm(v3_sub(p[a], p[0])), nrm = v3(0, 0, 0);
  best = 0;
  for (int i = 1; i < n; i++) {
    Vec3 x = v3_cross(u, v3_sub(p[i], p[0]));
    if (v3_len(x) > best) best = v3_len(x), nrm = x;
  }
  nrm = v3_norm(nrm);
  for (int i = 0; i < n; i++)
    if (fabs(v3_dot(nrm, v3_sub(p[i], p[0]))) > tol) return 0;
  Vec3 w = v3_cross(nrm, u);
  for (int i = 0; i < n; i++) {
    Vec3 d = v3_sub(p[i], p[0]);
    p[i] = v3(v3_dot(d, u), v3_dot(d, w), 0);
  }
  return 1;
}

static char assignment(const char *s) {
  switch (s[0] && !s[1] ? s[0] : 0) {
    case 'M': case 'm': return 'M';
    case 'V': case 'v': return 'V';
    case 'B': case 'b': case 'C': case 'c': return 'B';   /* C: a cut is paper's edge */
    case 'F': case 'f': case 'J': case 'j': return 'F';   /* J: a join folds nothing */
    case 'U': case 'u': return 'U';
    default: return 0;
  }
}

/* ---- sections -------------------------------------------------------- */

static int read_edges(FoldCtx *c, SceneOrigami *o, Arena *arena) {
  cJSON *ev = frame_get(c, 0, "edges_vertices"), *ea = frame_get(c, 0, "edges_assignment");
  if (!ev) return 1;                                         /* faces give the edges */
  if (!cJSON_IsArray(ev)) return fail(c, "edges_vertices must be a list of vertex pairs");
  int n = cJSON_GetArraySize(ev);
  if (n > ORIGAMI_MAX_CREASES)
    return fail(c, "edges_vertices: %d edges (limit ORIGAMI_MAX_CREASES is %d)", n, ORIGAMI_MAX_CREASES);
  if (ea && (!cJSON_IsArray(ea) || cJSON_GetArraySize(ea) != n))
    return fail(c, "edges_assignment must be a list of %d strings, one per edge", n);
  o->creases = arena_alloc(arena, (size_t)(n ? n : 1) * sizeof *o->creases);
  o->ncreases = n;
  const cJSON *e, *as = ea ? ea->child : NULL;
  int i = 0;
  cJSON_ArrayForEach(e, ev) {
    OrigamiCrease *cr = &o->creases[i];
    if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 2 || !get_index(cJSON_GetArrayItem(e, 0), &cr->a) ||
        !get_index(cJSON_GetArrayItem(e, 1), &cr->b))
      return fail(c, "edges_vertices[%d] must be a pair of vertex indices", i);
    if (cr->a >= o->nverts || cr->b >= o->nverts)
      return fail(c, "edges_vertices[%d]: vertex %d does not exist (%d vertices)", i,
                  cr->a >= o->nverts ? cr->a : cr->b, o->nverts);
    cr->assignment = 'U';
    if (as) {
      if (!cJSON_IsString(as) || !(cr->assignment = assignment(as->valuestring)))
        return fail(c, "edges_assignment[%d] must be one of \"B\", \"M\", \"V\", \"F\", \"U\", "
                    "\"C\", \"J\"", i);
      as = as->next;
    }
    cr->loc = src_none();
    i++;
  }
  return 1;
}

static int read_faces(FoldCtx *c, SceneOrigami *o, Arena *arena) {
  cJSON *fv = frame_get(c, 0, "faces_vertices");
  if (!fv) return 1;                                         /* origami_build traces them */
  if (!cJSON_IsArray(fv)) return fail(c, "faces_vertices must be a list of vertex lists");
  int n = cJSON_GetArraySize(fv), total = 0;
  if (n > ORIGAMI_MAX_FACES)
    return fail(c, "faces_vertices: %d faces (limit ORIGAMI_MAX_FACES is %d)", n, ORIGAMI_MAX_FACES);
  const cJSON *f, *e;
  cJSON_ArrayForEach(f, fv) total += cJSON_IsArray(f) ? cJSON_GetArraySize(f) : 0;
  o->nfaces = n;
  o->face_start = arena_alloc(arena, (size_t)(n + 1) * sizeof(int));
  o->face_index = arena_alloc(arena, (size_t)(total ? total : 1) * sizeof(int));
  int i = 0, k = 0;
  cJSON_ArrayForEach(f, fv) {
    if (!cJSON_IsArray(f) || cJSON_GetArraySize(f) < 3)
      return fail(c, "faces_vertices[%d] must be a list of at least 3 vertex indices", i);
    o->face_start[i] = k;
    cJSON_ArrayForEach(e, f) {
      int v;
      if (!get_index(e, &v)) return fail(c, "faces_vertices[%d] must hold vertex indices", i);
      if (v >= o->nverts)
        return fail(c, "faces_vertices[%d]: vertex %d does not exist (%d vertices)", i, v, o->nverts);
      o->face_index[k++] = v;
    }
    i++;
  }
  o->face_start[n] = k;
  return 1;
}

/* Edges from the faces when the file has none: an edge of one face is the
** paper's boundary, one shared by two faces an unassigned crease. */
static void edges_from_faces(SceneOrigami *o, Arena *arena) {
  int total = o->face_start[o->nfaces], n = 0;
  o->creases = arena_alloc(arena, (size_t)(total ? total : 1) * sizeof *o->creases);
  for (int f = 0; f < o->nfaces; f++)
    for (int k = o->face_start[f]; k < o->face_start[f + 1]; k++) {
      int u = o->face_index[k], v = o->face_index[k + 1 < o->face_start[f + 1] ? k + 1 : o->face_start[f]];
      int seen = -1;
      for (int i = 0; i < n && seen < 0; i++)
        if ((o->creases[i].a == v && o->creases[i].b == u) || (o->creases[i].a == u && o->creases[i].b == v)) seen = i;
      if (seen >= 0) { o->creases[seen].assignment = 'U'; continue; }
      o->creases[n++] = (OrigamiCrease){u, v, 'B', src_none()};
    }
  o->ncreases = n;
}

static double face_area2(const SceneOrigami *o, const Vec3 *p, int f) {
  double a = 0;
  for (int k = o->face_start[f]; k < o->face_start[f + 1]; k++) {
    int u = o->face_index[k], v = o->face_index[k + 1 < o->face_start[f + 1] ? k + 1 : o->face_start[f]];
    a += p[u].x * p[v].y - p[v].x * p[u].y;
  }
  return a;
}

/* Whether faces wind both ways over points p (a folded state). */
static int mixed_winding(const SceneOrigami *o, const Vec3 *p) {
  int pos = 0, neg = 0;
  for (int f = 0; f < o->nfaces; f++) {
    double a = face_area2(o, p, f);
    pos += a > 0, neg += a < 0;
  }
  return pos > 0 && neg > 0;
}

typedef struct UnfoldUser { const SceneOrigami *o; const Vec3 *p; } UnfoldUser;

static int unfold_edge(void *user, int fa, int fb, int u, int v) {
  const UnfoldUser *uu = user;
  return (face_area2(uu->o, uu->p, fa) > 0) != (face_area2(uu->o, uu->p, fb) > 0);
}

/* The crease pattern of a file that holds only its folded state: unfold
** from face 0 across every edge between faces of opposite winding, so that
** every face winds counter-clockwise on the paper. */
static void unfold(SceneOrigami *o, const Vec3 *folded, Arena *arena) {
  Vec2 *from = xmalloc((size_t)o->nverts * sizeof *from);
  for (int v = 0; v < o->nverts; v++) from[v] = (Vec2){folded[v].x, folded[v].y};
  UnfoldUser uu = {o, folded};
  o->verts = arena_alloc(arena, (size_t)(o->nverts ? o->nverts : 1) * sizeof *o->verts);
  origami_reflect(o->nverts, from, o->nfaces, o->face_start, o->face_index, 0, unfold_edge, &uu, 0,
                  o->verts, NULL, NULL);
  if (o->nfaces > 0 && face_area2(o, folded, 0) < 0)          /* face 0 shows its back: mirror */
    for (int v = 0; v < o->nverts; v++) o->verts[v].x = -o->verts[v].x;
  free(from);
}

typedef struct EdgeAsg { long long key; char a; } EdgeAsg;

static int cmp_edgeasg(const void *x, const void *y) {
  long long a = ((const EdgeAsg *)x)->key, b = ((const EdgeAsg *)y)->key;
  return a < b ? -1 : a > b;
}

static long long pair_key(int u, int v) { return u < v ? (long long)u << 32 | v : (long long)v << 32 | u; }

typedef struct FoldUser { const EdgeAsg *t; int n; } FoldUser;

static int fold_edge(void *user, int fa, int fb, int u, int v) {
  const FoldUser *fu = user;
  EdgeAsg key = {pair_key(u, v), 0};
  const EdgeAsg *e = fu->n ? bsearch(&key, fu->t, (size_t)fu->n, sizeof key, cmp_edgeasg) : NULL;
  return e && (e->a == 'M' || e->a == 'V');
}

/* The folded state by reflection across the M and V edges from face 0,
** for reading faceOrders of a file that gives none (malloc'd). */
static Vec3 *fold_from_paper(const SceneOrigami *o) {
  EdgeAsg *t = xmalloc((size_t)(o->ncreases ? o->ncreases : 1) * sizeof *t);
  for (int i = 0; i < o->ncreases; i++) t[i] = (EdgeAsg){pair_key(o->creases[i].a, o->creases[i].b), o->creases[i].assignment};
  if (o->ncreases > 1) qsort(t, (size_t)o->ncreases, sizeof *t, cmp_edgeasg);
  FoldUser fu = {t, o->ncreases};
  Vec2 *to = xmalloc((size_t)(o->nverts ? o->nverts : 1) * sizeof *to);
  origami_reflect(o->nverts, o->verts, o->nfaces, o->face_start, o->face_index, 0, fold_edge, &fu, 0, to,
                  NULL, NULL);
  Vec3 *r = xmalloc((size_t)(o->nverts ? o->nverts : 1) * sizeof *r);
  for (int v = 0; v < o->nverts; v++) r[v] = v3(to[v].x, to[v].y, 0);
  free(to);
  free(t);
  return r;
}

static int read_orders(FoldCtx *c, SceneOrigami *o, int k, const Vec3 *folded, Arena *arena) {
  char kb[64];
  cJSON *fo = frame_get(c, k, "faceOrders");
  if (!fo) return 1;
  const char *name = key_name(k, "faceOrders", kb, sizeof kb);
  if (!cJSON_IsArray(fo)) return fail(c, "%s must be a list of [f, g, s] triples", name);
  if (o->nfaces == 0) return fail(c, "%s needs faces_vertices (face ids)", name);
  int n = cJSON_GetArraySize(fo), i = 0;
  o->above = arena_alloc(arena, (size_t)(n ? n : 1) * sizeof *o->above);
  const cJSON *e;
  cJSON_ArrayForEach(e, fo) {
    int f, g;
    const cJSON *s = cJSON_GetArrayItem(e, 2);
    if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 3 || !get_index(cJSON_GetArrayItem(e, 0), &f) ||
        !get_index(cJSON_GetArrayItem(e, 1), &g) || !cJSON_IsNumber(s) ||
        (s->valuedouble != 1 && s->valuedouble != -1 && s->valuedouble != 0))
      return fail(c, "%s[%d] must be [face, face, +1 | -1 | 0]", name, i);
    if (f >= o->nfaces || g >= o->nfaces)
      return fail(c, "%s[%d]: face %d does not exist (%d faces)", name, i, f >= o->nfaces ? f : g, o->nfaces);
    i++;
    if (s->valuedouble == 0) continue;                       /* 0: no order (spec 1.2) */
    double ag = face_area2(o, folded, g);
    int f_over = s->valuedouble * ag > 0;
    o->above[o->nabove++] = (OrigamiAbove){f_over ? f : g, f_over ? g : f, src_none()};
  }
  return 1;
}

/* The folded frame, or -1: the first frame classed "foldedForm" past the
** top level. */
static int folded_frame(const FoldCtx *c) {
  for (int k = 1; k < c->nframes; k++)
    if (frame_has_class(c, k, "foldedForm")) return k;
  return -1;
}

static int read_model(FoldCtx *c, SceneOrigami *o, Arena *arena) {
  Vec3 *coords;
  cJSON *vc = frame_get(c, 0, "vertices_coords");
  if (!vc) return fail(c, "vertices_coords is missing");
  if (!read_coords(c, vc, "vertices_coords", arena, &coords, &o->nverts)) return 0;
  if (!read_faces(c, o, arena) || !read_edges(c, o, arena)) return 0;
  if (!frame_get(c, 0, "edges_vertices")) {
    if (o->nfaces == 0) return fail(c, "neither edges_vertices nor faces_vertices is given");
    edges_from_faces(o, arena);
  }
  int k = folded_frame(c);
  int planar = flatten(coords, o->nverts);
  Vec3 *folded = NULL;
  if (k > 0) {                                               /* crease pattern + folded frame */
    char kb[64];
    const char *name = key_name(k, "vertices_coords", kb, sizeof kb);
    if (!planar) return fail(c, "vertices_coords: the crease pattern is not flat");
    cJSON *fc = frame_get(c, k, "vertices_coords");
    int n = 0;
    if (!fc) return fail(c, "%s is missing", name);
    if (!read_coords(c, fc, name, arena, &folded, &n)) return 0;
    if (n != o->nverts) return fail(c, "%s has %d vertices; the crease pattern has %d", name, n, o->nverts);
    if (!flatten(folded, n))
      return fail(c, "frame %d is folded in 3D, not flat (sumi renders flat-folded states only)", k);
  } else if (!planar) {
    return fail(c, "vertices_coords are folded in 3D, not flat (sumi renders flat-folded states only)");
  } else if (!frame_has_class(c, 0, "creasePattern") && o->nfaces > 0 && mixed_winding(o, coords)) {
    k = 0;                                                   /* the top level is the folded state */
    folded = coords;
  }
  if (k >= 0 && folded == coords) unfold(o, coords, arena);
  else {
    o->verts = arena_alloc(arena, (size_t)(o->nverts ? o->nverts : 1) * sizeof *o->verts);
    for (int v = 0; v < o->nverts; v++) o->verts[v] = (Vec2){coords[v].x, coords[v].y};
  }
  if (folded) {
    o->has_folded = 1;
    o->folded = folded;
  }
  if (folded || !frame_get(c, 0, "faceOrders")) return read_orders(c, o, k >= 0 ? k : 0, folded ? folded : coords, arena);
  if (o->nfaces == 0) return fail(c, "faceOrders: without faces_vertices its face numbers name no faces");
  Vec3 *state = fold_from_paper(o);                          /* orders without a folded frame */
  int ok = read_orders(c, o, 0, state, arena);
  free(state);
  return ok;
}

/* Line of a byte offset, for JSON syntax errors. */
static int line_of(const char *text, const char *at) {
  int line = 1;
  for (const char *p = text; p < at && *p; p++) line += *p == '\n';
  return line;
}

static int read_file(const char *path, SceneOrigami *out, Arena *arena, char *err, size_t errlen) {
  FoldCtx c = {.path = path, .err = err, .errlen = errlen};
  if (errlen) err[0] = 0;
  char why[256];
  if (!infile_check(path, INFILE_MAX_FOLD, "a FOLD file", why, sizeof why)) return fail(&c, "cannot read: %s", why);
  FILE *fp = fopen(path, "rb");
  if (!fp) return fail(&c, "cannot open: %s", strerror(errno));
  size_t cap = 1 << 16, len = 0;
  char *text = xmalloc(cap);
  for (size_t got; (got = fread(text + len, 1, cap - len - 1, fp)) > 0;) {
    len += got;
    if (len + 1 == cap) text = xrealloc(text, cap *= 2);
  }
  int rerr = ferror(fp);
  fclose(fp);
  text[len] = 0;
  if (rerr) {
    free(text);
    return fail(&c, "read error");
  }
  const char *end = NULL;
  c.root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
  if (!c.root) {
    int line = line_of(text, end ? end : text);
    free(text);
    return fail(&c, "line %d: not valid JSON", line);
  }
  memset(out, 0, sizeof *out);
  out->transform = m4_identity();
  out->style = -1;
  out->loc = out->overlap_loc = src_none();
  out->fold_file = arena_strndup(arena, path, strlen(path));
  int ok;
  if (!cJSON_IsObject(c.root)) ok = fail(&c, "the top level must be a JSON object");
  else {
    c.frames = cJSON_GetObjectItemCaseSensitive(c.root, "file_frames");
    if (c.frames && !cJSON_IsArray(c.frames)) c.frames = NULL;   /* malformed: ignored */
    c.nframes = 1 + (c.frames ? cJSON_GetArraySize(c.frames) : 0);
    ok = read_model(&c, out, arena);
  }
  cJSON_Delete(c.root);
  free(text);
  return ok;
}

int fold_read(const char *path, SceneOrigami *out, Arena *arena, char *err, size_t errlen) {
  return read_file(path, out, arena, err, errlen) ? 0 : 1;
}

/* ---- writing a folded state ---------------------------------------------- */

static cJSON *int_pair(int a, int b) {
  int v[2] = {a, b};
  return cJSON_CreateIntArray(v, 2);
}

int fold_write_state(const char *path, const FoldState *st, char *err, size_t errlen) {
  cJSON *root = cJSON_CreateObject();
  cJSON_AddNumberToObject(root, "file_spec", 1.1);
  cJSON_AddStringToObject(root, "file_creator", "sumi");
  if (st->title) cJSON_AddStringToObject(root, "file_title", st->title);
  cJSON_AddItemToObject(root, "file_classes", cJSON_CreateStringArray((const char *[]){"singleModel"}, 1));
  cJSON_AddItemToObject(root, "frame_classes", cJSON_CreateStringArray((const char *[]){"foldedForm"}, 1));
  cJSON *vc = cJSON_AddArrayToObject(root, "vertices_coords");
  for (int v = 0; v < st->nverts; v++) {
    double p[2] = {st->coords[v].x, st->coords[v].y};
    cJSON_AddItemToArray(vc, cJSON_CreateDoubleArray(p, 2));
  }
  cJSON *ev = cJSON_AddArrayToObject(root, "edges_vertices"), *ea = cJSON_AddArrayToObject(root, "edges_assignment");
  for (int e = 0; e < st->nedges; e++) {
    char a[2] = {st->assign[e], 0};
    cJSON_AddItemToArray(ev, int_pair(st->edge_verts[e][0], st->edge_verts[e][1]));
    cJSON_AddItemToArray(ea, cJSON_CreateString(a));
  }
  cJSON *fv = cJSON_AddArrayToObject(root, "faces_vertices");
  for (int f = 0; f < st->nfaces; f++)
    cJSON_AddItemToArray(fv, cJSON_CreateIntArray(st->face_index + st->face_start[f],
                                                  st->face_start[f + 1] - st->face_start[f]));
  cJSON *fo = cJSON_AddArrayToObject(root, "faceOrders");
  for (long k = 0; k < st->norders; k++) {
    int f = st->orders[k][0], g = st->orders[k][1], o[3] = {f, g, st->flipped[g] ? -1 : 1};
    cJSON_AddItemToArray(fo, cJSON_CreateIntArray(o, 3));
  }
  char *text = cJSON_Print(root);
  cJSON_Delete(root);
  char tmp[4096];
  snprintf(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid());
  FILE *f = fopen(tmp, "w");
  if (f) tempfile_add(tmp);
  int bad = !f || fputs(text, f) < 0 || fputc('\n', f) < 0;
  if (f && fclose(f) != 0) bad = 1;
  if (!bad && rename(tmp, path) != 0) bad = 1;
  if (bad) {
    snprintf(err, errlen, "%s: cannot write: %s", path, strerror(errno));
    tempfile_discard(tmp);
  } else tempfile_forget(tmp);
  free(text);
  return bad;
}
