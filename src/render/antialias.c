/*
** Antialiasing of the edges between surfaces (antialias.h): the walk's
** data per object, the walk across a mesh, the boundary between two
** neighbouring samples, the shares of their squares, and the blend.
*/
#include "antialias.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/tasks.h"

/* ---- the walk's data ----------------------------------------------------- */

static inline float dot3(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Corners of unit normals that count as the same (shading does not jump). */
#define AA_SAME_NORMAL 0.99999f

/* The corner of triangle t at vertex v (0..2), or -1. */
static int corner_of(const int t[3], int v) {
  return t[0] == v ? 0 : t[1] == v ? 1 : t[2] == v ? 2 : -1;
}

/* Whether the shading of o can jump between its triangles at all: lit
** flat shading (facets), or corner normals that may differ. Bokashi's
** colour follows the point's place alone (its normal is the direction from
** the centre), never the mesh's normals. */
static int may_jump(const RenderObject *o) {
  if (o->style->kind == SHADE_FLAT && !o->style->lit) return 0;   /* one colour, facets or not */
  if (o->style->kind == SHADE_BOKASHI) return 0;
  return o->style->kind == SHADE_FLAT || o->wcnrm;
}

/* Whether the shading of o jumps across edge k of triangle t into
** triangle g: their corner normals differ at a shared vertex, or (lit
** flat shading) their planes do. */
static int shading_jumps(const RenderObject *o, int t, int k, int g) {
  const Mesh *m = o->mesh;
  if (!may_jump(o)) return 0;
  if (o->style->kind == SHADE_FLAT) {
    float n[2][3];
    for (int i = 0; i < 2; i++) {
      const int *c = m->tri[i ? g : t];
      const float *a = o->wpos[c[0]], *b = o->wpos[c[1]], *d = o->wpos[c[2]];
      float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
      n[i][0] = e1[1] * e2[2] - e1[2] * e2[1];
      n[i][1] = e1[2] * e2[0] - e1[0] * e2[2];
      n[i][2] = e1[0] * e2[1] - e1[1] * e2[0];
    }
    float l = sqrtf(dot3(n[0], n[0]) * dot3(n[1], n[1]));
    return !(dot3(n[0], n[1]) > AA_SAME_NORMAL * l);
  }
  if (!o->wcnrm) return 0;
  for (int j = 0; j < 2; j++) {   /* a smooth vertex's corners carry the same normal, bit for bit */
    int v = m->tri[t][(k + j) % 3], cg = corner_of(m->tri[g], v);
    if (cg < 0 || memcmp(o->wcnrm[t][(k + j) % 3], o->wcnrm[g][cg], sizeof o->wcnrm[g][cg])) return 1;
  }
  return 0;
}

/* A projected vertex as the walk reads it: sample-grid x, y and window
** depth, x NaN when it is outside the planes the rasterizer clips against
** (exact: the grid position is an integer under 2^24 over a power of 2). */
static inline void aa_vertex(const RastVert *r, float p[3]) {
  p[0] = r->outcode ? NAN : (float)r->X / (1 << RAST_SUBPIXEL_BITS);
  p[1] = (float)r->Y / (1 << RAST_SUBPIXEL_BITS);
  p[2] = r->z;
}

/* Samples a walk may reach: the window's, its apron, and a margin of two
** (a walk ends a step from a sample centre). */
typedef struct WalkBox {
  float x0, y0, x1, y1;
} WalkBox;

/* The sides of b a vertex at sample-grid position p lies beyond: bit 0
** left, 1 right, 2 above, 3 below (none for a vertex not projected, x
** NaN). A triangle all of whose corners are beyond one side (the AND of
** their codes) is wholly outside b. */
static unsigned away_code(const float p[3], const WalkBox *b) {
  if (isnan(p[0])) return 0;
  return (unsigned)(p[0] < b->x0) | (unsigned)(p[0] > b->x1) << 1 | (unsigned)(p[1] < b->y0) << 2 |
         (unsigned)(p[1] > b->y1) << 3;
}

/* The triangle across edge k of triangle t of m, from its topology (-1:
** a boundary, a non-manifold edge, no topology). */
static inline int neighbour(const Mesh *m, int t, int k) {
  if (!m->tri_edges) return -1;
  const MeshEdge *e = &m->edges[m->tri_edges[t][k]];
  return e->nonmanifold ? -1 : e->f[0] == t ? e->f[1] : e->f[0];
}

/* How the shading of o can jump between its triangles (shading_jumps):
** 0 never, 1 lit flat shading (its planes), 2 corner normals. */
static int jump_kind(const RenderObject *o) {
  return !may_jump(o) ? 0 : o->style->kind == SHADE_FLAT ? 1 : 2;
}

/* The walk's neighbours of a mesh kept for later frames (mesh_derived):
** neighbour(), less the edges across which the shading jumps, which
** depend on the mesh, the kind of jump and the world copies the
** transform makes of its points and normals. */
typedef struct WalkNeighbours {
  Mat4 M;                      /* the transform and */
  int kind;                    /* jump_kind the jumps were found for */
  int32_t (*nb)[3];
} WalkNeighbours;

static const char neighbours_tag;

static void walk_neighbours_free(void *data) {
  WalkNeighbours *w = data;
  free(w->nb);
  free(w);
}

/* The walk neighbours kept with o's mesh, when they were found for o's
** transform and kind of jump; else NULL, with *made a new table for
** init_triangles to fill when the mesh keeps such data (without it, the
** walk's data is made from the topology: no table in memory beside it). */
static const int32_t (*kept_neighbours(const RenderObject *o, WalkNeighbours **made))[3] {
  const Mesh *m = o->mesh;
  int kind = jump_kind(o);
  const WalkNeighbours *w = mesh_derived(m, &neighbours_tag);
  *made = NULL;
  if (w && w->kind == kind && (kind == 0 || !memcmp(&w->M, &o->object_to_world, sizeof w->M)))
    return (const int32_t(*)[3])w->nb;
  if (!m->keeps_derived) return NULL;
  *made = xmalloc(sizeof **made);
  **made = (WalkNeighbours){o->object_to_world, kind, xmalloc(((size_t)m->ntris + 1) * sizeof (*made)->nb[0])};
  return NULL;
}

/* One object's walk data, made in chunks of AA_CHUNK vertices or
** triangles on worker threads (tasks.h): each chunk writes its own range,
** so the tables do not depend on the threads. */
enum { AA_CHUNK = 16384 };

typedef struct AaInit {
  const RenderObject *o;
  const RastVert *rv;
  const WalkBox *box;
  unsigned char *code;         /* per vertex: away_code */
  unsigned char *any;          /* per vertex chunk: the OR of its codes */
  int32_t (*fill)[3];          /* the walk neighbours to find, or NULL */
  int jumps;
} AaInit;

static void init_vertices(void *ctx, int k) {
  AaInit *in = ctx;
  const Mesh *m = in->o->mesh;
  int v1 = (k + 1) * AA_CHUNK < m->nverts ? (k + 1) * AA_CHUNK : m->nverts;
  unsigned any = 0;
  for (int v = k * AA_CHUNK; v < v1; v++) {
    float sv[3];
    aa_vertex(&in->rv[v], sv);
    in->code[v] = (unsigned char)away_code(sv, in->box);
    any |= in->code[v];
  }
  in->any[k] = (unsigned char)any;
}

static void init_neighbours(void *ctx, int k) {
  const AaInit *in = ctx;
  const RenderObject *o = in->o;
  const Mesh *m = o->mesh;
  int t1 = (k + 1) * AA_CHUNK < m->ntris ? (k + 1) * AA_CHUNK : m->ntris;
  for (int t = k * AA_CHUNK; t < t1; t++)
    for (int j = 0; j < 3; j++) {
      int g = neighbour(m, t, j);
      in->fill[t][j] = g >= 0 && in->jumps && shading_jumps(o, t, j, g) ? -1 : g;
    }
}

static void object_init(AaObject *a, const RenderObject *o, const RastVert *rv, const WalkBox *box,
                        int nthreads) {
  const Mesh *m = o->mesh;
  a->clear = o->style->alpha == 0;
  a->tri = (const int(*)[3])m->tri;
  a->rv = rv;
  a->back = o->backfacing;
  int nvc = (m->nverts + AA_CHUNK - 1) / AA_CHUNK, ntc = (m->ntris + AA_CHUNK - 1) / AA_CHUNK;
  AaInit in = {o, rv, box, xmalloc((size_t)m->nverts + 1), xcalloc((size_t)nvc + 1, 1), NULL, may_jump(o)};
  tasks_run(nvc, nthreads, init_vertices, &in);
  unsigned any = 0;
  for (int k = 0; k < nvc; k++) any |= in.any[k];
  free(in.any);
  a->away = any ? in.code : NULL;   /* some vertex lies away from the window */
  if (!any) free(in.code);
  WalkNeighbours *made;
  a->nb = kept_neighbours(o, &made);
  if (a->nb) return;
  in.fill = made ? made->nb : xmalloc(((size_t)m->ntris + 1) * sizeof *in.fill);
  tasks_run(ntc, nthreads, init_neighbours, &in);
  a->nb = (const int32_t(*)[3])in.fill;
  /* an addition to the mesh, not a change: it stays the caller's */
  if (made) mesh_derived_set((Mesh *)m, &neighbours_tag, made, walk_neighbours_free);
  else a->own = in.fill;   /* this frame's alone */
}

void aa_frame_init(AaFrame *af, const RenderFrame *f, RastVert *const *verts, int apron, int nthreads) {
  int n = f->samples;
  float g = (float)apron + 2;
  WalkBox box = {(float)f->win.x0 * n - g, (float)f->win.y0 * n - g, (float)f->win.x1 * n + g,
                 (float)f->win.y1 * n + g};
  af->f = f;
  af->nobjects = f->nobjects;
  af->objects = xcalloc((size_t)f->nobjects + 1, sizeof *af->objects);
  for (int i = 0; i < f->nobjects; i++) object_init(&af->objects[i], &f->objects[i], verts[i], &box, nthreads);
}

void aa_frame_free(AaFrame *af) {
  for (int i = 0; i < af->nobjects; i++) {
    free(af->objects[i].own);
    free(af->objects[i].away);
  }
  free(af->objects);
  memset(af, 0, sizeof *af);
}

/* ---- the walk -------------------------------------------------------------- */

/* The triangle across edge k of triangle t of o the walk goes on into, or
** -1 where it stops: the surface ends, turns away (an outline) or its
** shading jumps, or t lies wholly away from the window. */
static inline int wholly_away(const AaObject *o, int t) {
  const int *c = o->tri[t];
  return o->away && (o->away[c[0]] & o->away[c[1]] & o->away[c[2]]);
}

static inline int walk_next(const AaObject *o, int t, int k) {
  int g = o->nb[t][k];
  return g < 0 || o->back[g] != o->back[t] || wholly_away(o, t) ? -1 : g;
}

typedef enum { WALK_FAIL, WALK_SAME, WALK_EDGE, WALK_PAST } WalkKind;

typedef struct Walk {
  WalkKind kind;
  float s;          /* WALK_EDGE: where the segment leaves the surface, 0..1 */
  float ex, ey;     /* WALK_EDGE: that edge's direction on the sample grid */
  int tri;          /* WALK_PAST: the triangle holding the segment's end */
} Walk;

/* Walk o's mesh from triangle tri at the sample centre (cx, cy) along the
** unit segment to the neighbouring centre one step along axis (0: x, 1:
** y) in direction dir (+1 or -1): WALK_SAME when it reaches triangle goal
** (the neighbour's, when it shows the same object; else -1), WALK_EDGE
** at the first edge where the walk stops (walk_next -1), WALK_PAST when the
** segment ends inside a triangle that is not goal, WALK_FAIL on a
** triangle it cannot follow (not projected, degenerate, too far). */
static Walk walk(const AaObject *o, int tri, float cx, float cy, int axis, float dir, int goal) {
  Walk w = {WALK_FAIL, 0, 0, 0, tri};
  float dx = axis == 0 ? dir : 0, dy = axis == 1 ? dir : 0;
  int entry = -1;
  for (int step = 0; step < AA_MAX_STEPS; step++) {
    if (tri == goal) { w.kind = WALK_SAME; return w; }
    const int *t = o->tri[tri];
    float v[3][3];
    for (int k = 0; k < 3; k++) aa_vertex(&o->rv[t[k]], v[k]);
    if (isnan(v[0][0]) || isnan(v[1][0]) || isnan(v[2][0])) return w;
    float area = (v[1][0] - v[0][0]) * (v[2][1] - v[0][1]) - (v[2][0] - v[0][0]) * (v[1][1] - v[0][1]);
    if (area == 0) return w;
    float sg = area > 0 ? 1.0f : -1.0f, best = INFINITY;
    int kb = -1;
    for (int k = 0; k < 3; k++) {   /* the edge the segment leaves through, first */
      if (k == entry) continue;
      const float *a = v[k], *b = v[(k + 1) % 3];
      float ex = b[0] - a[0], ey = b[1] - a[1];
      float de = ex * dy - ey * dx;   /* the edge function's change along the segment */
      if (!(sg * de < 0)) continue;   /* not leaving through k */
      float sk = -(ex * (cy - a[1]) - ey * (cx - a[0])) / de;
      if (sk < best) { best = sk; kb = k; }
    }
    if (kb < 0) return w;
    if (best >= 1) { w.kind = WALK_PAST; w.tri = tri; return w; }
    int next = walk_next(o, tri, kb);
    if (next < 0) {
      w.kind = WALK_EDGE;
      w.s = best > 0 ? best : 0;
      w.ex = v[(kb + 1) % 3][0] - v[kb][0];
      w.ey = v[(kb + 1) % 3][1] - v[kb][1];
      return w;
    }
    entry = -1;   /* the edge back to tri (the same facing as next): none from a triangle away */
    for (int k = 0; k < 3; k++) entry = o->nb[next][k] == tri ? k : entry;
    if (wholly_away(o, next)) entry = -1;
    tri = next;
  }
  return w;
}

/* ---- the boundary between two samples --------------------------------------- */

/* Window depth of triangle tri of o at (x, y), from its plane on the
** sample grid; NaN when it has none. */
static float depth_at(const AaObject *o, int tri, float x, float y) {
  const int *t = o->tri[tri];
  float a[3], b[3], c[3];
  aa_vertex(&o->rv[t[0]], a), aa_vertex(&o->rv[t[1]], b), aa_vertex(&o->rv[t[2]], c);
  float e1x = b[0] - a[0], e1y = b[1] - a[1], e2x = c[0] - a[0], e2y = c[1] - a[1];
  float det = e1x * e2y - e2x * e1y;
  if (det == 0 || isnan(a[0]) || isnan(b[0]) || isnan(c[0])) return NAN;
  float z1 = b[2] - a[2], z2 = c[2] - a[2];
  float zx = (z1 * e2y - z2 * e1y) / det, zy = (z2 * e1x - z1 * e2x) / det;
  return a[2] + zx * (x - a[0]) + zy * (y - a[1]);
}

/* A boundary: where it crosses the segment from P to Q (0..1 from P),
** and its direction. */
typedef struct Crossing {
  float s, ex, ey;
} Crossing;

/* Two surfaces passing through each other between centres ca (where
** triangle ta of object a shows) and cb (tb of b): where their depth
** planes meet on the segment, from ca, and the line they meet along. */
static int planes_meet(const AaObject *a, int ta, const float ca[2], const AaObject *b, int tb,
                       const float cb[2], Crossing *x) {
  float da = depth_at(a, ta, ca[0], ca[1]) - depth_at(b, tb, ca[0], ca[1]);   /* < 0: a in front */
  float db = depth_at(a, ta, cb[0], cb[1]) - depth_at(b, tb, cb[0], cb[1]);   /* > 0: b in front */
  if (!(da < 0 && db > 0)) return 0;
  x->s = da / (da - db);
  /* the difference of the planes changes along the segment and across it */
  float ax = cb[0] - ca[0], ay = cb[1] - ca[1];   /* a unit step along x or y */
  float across = (depth_at(a, ta, ca[0] + ay, ca[1] + ax) - depth_at(b, tb, ca[0] + ay, ca[1] + ax)) - da;
  float along = db - da;
  /* the zero line's direction: across the axis by `along`, along it by -`across` */
  x->ex = ax != 0 ? -across : along;
  x->ey = ax != 0 ? along : -across;
  return isfinite(x->s) && isfinite(x->ex) && isfinite(x->ey);
}

/* Whether triangles f and g of o share an edge the walk crosses (the
** surface goes on smoothly from one to the other). */
/* Is a sample of object obj (-1: background) transparent in the tile pass? */
static int clear_sample(const AaFrame *af, int32_t obj) {
  return obj < 0 ? af->f->background.a == 0 : af->objects[obj].clear;
}

static int adjacent(const AaObject *o, int f, int g) {
  const int32_t *n = o->nb[f];   /* g is a triangle: walk_next(o, f, k) == g */
  return (n[0] == g || n[1] == g || n[2] == g) && o->back[g] == o->back[f] && !wholly_away(o, f);
}

/* Whether samples i and j of rt show one smooth surface: the same object,
** the same or adjacent triangles. */
static int smooth(const AaFrame *af, const RastTarget *rt, int i, int j) {
  int o = rt->object[i];
  return o >= 0 && o == rt->object[j] &&
         (rt->face[i] == rt->face[j] || adjacent(&af->objects[o], rt->face[i], rt->face[j]));
}

/* The boundary between samples ip and iq of rt, where iq is one step
** along axis from ip, whose centre is c[0], when they show different
** triangles: 1 with *x where different surfaces meet between them, 0 when
** they show one surface after all (the walk from one reaches the other's
** triangle), -1 when neither can be told. The nearer surface's mesh is
** walked first; if it goes on past the other centre (the other surface
** is in front there), the other's; surfaces that both go on pass through
** each other. */
static int boundary(const AaFrame *af, const RastTarget *rt, int ip, int iq, const float c[2][2],
                    int axis, Crossing *x) {
  int id[2] = {ip, iq}, obj[2] = {rt->object[ip], rt->object[iq]};
  int face[2] = {rt->face[ip], rt->face[iq]};
  int first = obj[1] < 0 || (obj[0] >= 0 && rt->depth[id[0]] <= rt->depth[id[1]]) ? 0 : 1;
  int past = -1, past_tri = -1;
  for (int n = 0; n < 2; n++) {
    int a = n == 0 ? first : 1 - first, b = 1 - a;
    if (obj[a] < 0) continue;
    const AaObject *o = &af->objects[obj[a]];
    Walk w = walk(o, face[a], c[a][0], c[a][1], axis, a == 0 ? 1.0f : -1.0f,
                  obj[b] == obj[a] ? face[b] : -1);
    if (w.kind == WALK_SAME) return 0;
    if (w.kind == WALK_EDGE) {
      x->s = a == 0 ? w.s : 1 - w.s;
      x->ex = w.ex;
      x->ey = w.ey;
      return 1;
    }
    if (w.kind == WALK_PAST && past < 0) { past = a; past_tri = w.tri; }
  }
  if (past < 0 || obj[0] < 0 || obj[1] < 0) return -1;
  int b = 1 - past;
  if (!planes_meet(&af->objects[obj[past]], past_tri, c[past], &af->objects[obj[b]], face[b], c[b], x))
    return -1;
  if (past == 1) x->s = 1 - x->s;
  return 1;
}

/* Term t's smooth value at sample i of rt (shade_step_value). */
static float step_value(const AaFrame *af, const RastTarget *rt, const AaSteps *st, int i, int t) {
  size_t m = (size_t)i * SHADE_STEP_TERMS + (size_t)t;
  if (st->seen[m] == st->stamp) return st->memo[m];
  const RenderObject *o = &af->f->objects[rt->object[i]];
  float p[3], n[3], v[3];
  shade_surface_at(st->view, o, rt->face[i], rt->bary[i][0], rt->bary[i][1], rt->ox + i % rt->stride,
                   rt->oy + i / rt->stride, p, n, v);
  st->seen[m] = st->stamp;
  return st->memo[m] = shade_step_value(af->f, o, rt->face[i], t, p, n, v);
}

/* How term t's smooth value changes one step across the axis at sample
** i of rt (y for a pair along x), whose value is ui, from the neighbours
** on either side that show i's surface (a central difference where both
** do); 0 where none does. */
static float across_change(const AaFrame *af, const RastTarget *rt, const AaSteps *st, int i,
                           float ui, int x, int y, int axis, int t) {
  int step = axis == 0 ? rt->stride : 1;
  int lo = axis == 0 ? y - 1 >= rt->y0 : x - 1 >= rt->x0;
  int hi = axis == 0 ? y + 1 < rt->y1 : x + 1 < rt->x1;
  lo = lo && smooth(af, rt, i, i - step);
  hi = hi && smooth(af, rt, i, i + step);
  if (lo && hi) return 0.5f * (step_value(af, rt, st, i + step, t) - step_value(af, rt, st, i - step, t));
  if (hi) return step_value(af, rt, st, i + step, t) - ui;
  if (lo) return ui - step_value(af, rt, st, i - step, t);
  return 0;
}

/* A step of the shading (a band's border) between samples ip and iq of
** one smooth surface: the first term whose levels differ by one, where
** its smooth value, taken linear between the centres, crosses the step,
** and the line it crosses along (perpendicular to the value's change).
** Returns 0 when no term steps once between them. */
static int step_crossing(const AaFrame *af, const RastTarget *rt, const AaSteps *st, int ip, int iq,
                         int x, int y, int axis, Crossing *c) {
  uint32_t kp = st->key[ip], kq = st->key[iq];
  for (int t = 0; t < SHADE_STEP_TERMS; t++) {
    int lp = (int8_t)(kp >> (8 * t)), lq = (int8_t)(kq >> (8 * t));
    if (lp == lq) continue;
    if (lp - lq != 1 && lq - lp != 1) return 0;   /* several steps: no line to find */
    float up = step_value(af, rt, st, ip, t), uq = step_value(af, rt, st, iq, t);
    float along = uq - up, b = (float)(lp > lq ? lp : lq);
    if (!(lq > lp ? along > 0 : along < 0)) return 0;   /* the values disagree with the levels */
    c->s = (b - up) / along;
    c->s = c->s > 0 ? (c->s < 1 ? c->s : 1) : 0;
    float across = across_change(af, rt, st, ip, up, x, y, axis, t);
    c->ex = axis == 0 ? -across : -along;   /* (along, across) turned a quarter */
    c->ey = axis == 0 ? along : across;
    return 1;
  }
  return 0;
}

/* The share of a sample's unit square beyond a straight line crossing
** its row (or column) a from its far side, toward its centre: the
** integral over the square's height of max(0, a + m y), y in
** [-1/2, 1/2], with |m| <= 1 the line's slope across the axis. */
static float share(float a, float m) {
  float h = 0.5f * fabsf(m);
  if (a >= h) return a;
  if (a <= -h) return 0;
  return (a + h) * (a + h) / (4 * h);
}

/* The blends of the pair (ip, iq) whose boundary is x into out: P's
** square beyond the boundary takes Q's colour, Q's beyond it P's; only
** for the samples inside the tile (inside[0], inside[1]). Returns how
** many were written. */
static int pair_blends(const Crossing *x, int ip, int iq, int axis, const int inside[2],
                       AaBlend *out) {
  /* each boundary once: the steep ones across rows, the flat ones across columns */
  float along = axis == 0 ? x->ex : x->ey, across = axis == 0 ? x->ey : x->ex;
  if (axis == 0 ? !(fabsf(along) <= fabsf(across)) : !(fabsf(along) < fabsf(across))) return 0;
  float m = along / across;
  float ap = share(0.5f - x->s, m), aq = share(x->s - 0.5f, m);
  int n = 0;
  if (inside[0] && ap > 0) out[n++] = (AaBlend){ip, iq, ap};
  if (inside[1] && aq > 0) out[n++] = (AaBlend){iq, ip, aq};
  return n;
}

/* The boundary of the pair (x, y), (x + ax, y + ay) of differing samples
** ip, iq: between surfaces, or else (one smooth surface) between steps
** of its shading; 1 with *c when there is one. */
static int pair_crossing(const AaFrame *af, const RastTarget *rt, const AaSteps *st, int ip, int iq,
                         int x, int y, int axis, Crossing *c) {
  int one = smooth(af, rt, ip, iq);
  if (!one) {
    float cc[2][2] = {{x + 0.5f, y + 0.5f}, {x + (axis == 0) + 0.5f, y + (axis == 1) + 0.5f}};
    int b = boundary(af, rt, ip, iq, (const float(*)[2])cc, axis, c);
    if (b != 0) return b > 0;
  }
  return st->key[ip] != st->key[iq] && step_crossing(af, rt, st, ip, iq, x, y, axis, c);
}


/* Most samples in a row of a tile with its apron. */
#define AA_ROW (RENDER_TILE * RENDER_MAX_SAMPLES + 2)

int aa_tile(const AaFrame *af, const RastTarget *rt, const AaSteps *st, int x0, int y0, int x1,
            int y1, AaBlend *out) {
  int n = 0;
  for (int axis = 0; axis < 2; axis++) {
    /* pairs (x, y) - (x + 1, y) along x, (x, y) - (x, y + 1) along y, with a sample in the tile */
    int ax = axis == 0, ay = axis == 1, step = ax ? 1 : rt->stride;
    int px0 = ax && x0 - 1 >= rt->x0 ? x0 - 1 : x0, py0 = ay && y0 - 1 >= rt->y0 ? y0 - 1 : y0;
    int px1 = ax && x1 >= rt->x1 ? x1 - 1 : x1, py1 = ay && y1 >= rt->y1 ? y1 - 1 : y1;
    int m = px1 - px0;
    for (int y = py0; y < py1; y++) {
      int i0 = (y - rt->oy) * rt->stride + (px0 - rt->ox);
      const int32_t *o0 = rt->object + i0, *o1 = o0 + step, *f0 = rt->face + i0, *f1 = f0 + step;
      /* which pairs show different triangles or step levels, side by side; most show neither */
      uint32_t diff[AA_ROW], any = 0;
      const uint32_t *k0 = st->key + i0, *k1 = k0 + step;
      for (int k = 0; k < m; k++) {
        /* all ones where P and Q both show an object: a background sample's face
        ** is never written, and (o0 ^ o1) already tells it from an object's */
        uint32_t drawn = ~(uint32_t)((o0[k] | o1[k]) >> 31);
        uint32_t d = (uint32_t)(o0[k] ^ o1[k]) | (((uint32_t)(f0[k] ^ f1[k]) | (k0[k] ^ k1[k])) & drawn);
        diff[k] = d;
        any |= d;
      }
      if (!any) continue;
      uint8_t flag[AA_ROW + 8];   /* the differing pairs, a byte each, read 8 at a time */
      for (int k = 0; k < m; k++) flag[k] = diff[k] != 0;
      memset(flag + m, 0, 8);
      for (int k8 = 0; k8 < m; k8 += 8) {
        uint64_t bits;
        memcpy(&bits, flag + k8, 8);
        for (; bits; bits &= bits - 1) {
          int k = k8 + (__builtin_ctzll(bits) >> 3);
          /* triangles of one surface meeting smoothly at one level: the most common case, here */
          if (o0[k] == o1[k] && k0[k] == k1[k] && adjacent(&af->objects[o0[k]], f0[k], f1[k])) continue;
          if (clear_sample(af, o0[k]) && clear_sample(af, o1[k])) continue;   /* both transparent */
          int x = px0 + k, ip = i0 + k, iq = ip + step;
          /* whether P and Q are in the tile: only the apron side of a pair can be out */
          int inside[2] = {ax ? x >= x0 : y >= y0, ax ? x + 1 < x1 : y + 1 < y1};
          Crossing c;
          if (pair_crossing(af, rt, st, ip, iq, x, y, axis, &c))
            n += pair_blends(&c, ip, iq, axis, inside, out + n);
        }
      }
    }
  }
  return n;
}

/* ---- blending ------------------------------------------------------------------ */

void aa_apply(const AaBlend *b, int n, float *col, int nc, int unassociated, AaScratch *sc) {
  int pre = unassociated && nc == 4;   /* mix by alpha, as premultiplied colours */
  int ntouched = 0;
  for (int i = 0; i < n; i++) {   /* the shares and colours each sample takes, in blend order */
    int at = b[i].at;
    if (sc->sum[at] == 0) sc->touched[ntouched++] = at;
    const float *f = col + (size_t)b[i].from * nc;
    float w = b[i].a, wf = pre ? f[3] * w : w;
    float *acc = sc->acc + (size_t)at * 4;
    for (int k = 0; k < nc; k++) acc[k] += f[k] * (k < 3 ? wf : w);
    sc->sum[at] += w;
  }
  for (int i = 0; i < ntouched; i++) {   /* all read: now each sample's blend, and the planes cleared */
    int at = sc->touched[i];
    float *c = col + (size_t)at * nc, *acc = sc->acc + (size_t)at * 4;
    float sum = sc->sum[at], scale = sum > 1 ? 1 / sum : 1;
    float keep = 1 - sum * scale, wa = pre ? c[3] * keep : keep, o[4];
    for (int k = 0; k < nc; k++) o[k] = c[k] * (k < 3 ? wa : keep) + acc[k] * scale;
    if (pre) {
      float inv = o[3] > 0 ? 1 / o[3] : 0;
      for (int k = 0; k < 3; k++) o[k] *= inv;
    }
    memcpy(c, o, (size_t)nc * sizeof *c);
    acc[0] = acc[1] = acc[2] = acc[3] = 0;
    sc->sum[at] = 0;
  }
}
