/*
** The frame pipeline (render.h): prepare the scene, set up and bin the
** triangles, then rasterize and shade screen tiles on worker threads.
**
** Bottom-up: sizes and limits, the prepare stage (bounding box, camera,
** lights, styles, objects), triangle setup and binning, the tile pass
** (raster, shade, box filter), and the entry points.
*/
#include "render.h"

#include <float.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../base/mem.h"
#include "../base/tasks.h"
#include "../geom/origami.h"
#include "../geom/subdiv.h"
#include "../geom/tessellate.h"
#include "../lang/diag.h"
#include "antialias.h"
#include "canvas.h"
#include "ink.h"
#include "lines.h"
#include "origami.h"
#include "raster.h"
#include "screentex.h"
#include "shade.h"
#include "shadow.h"
#include "stats.h"
#include "tile.h"

/* ---- sizes and limits ------------------------------------------------------ */

void render_resolve_size(const Scene *s, int cli_w, int cli_h, int *w, int *h) {
  int sw = s->output.width, sh = s->output.height;
  if (sw <= 0 || sh <= 0) { sw = RENDER_DEFAULT_WIDTH; sh = RENDER_DEFAULT_HEIGHT; }
  if (cli_w > 0 && cli_h > 0) { *w = cli_w; *h = cli_h; }
  else if (cli_w > 0) { *w = cli_w; *h = (int)fmax(1, floor((double)cli_w * sh / sw + 0.5)); }
  else if (cli_h > 0) { *h = cli_h; *w = (int)fmax(1, floor((double)cli_h * sw / sh + 0.5)); }
  else { *w = sw; *h = sh; }
}

/* Check the frame's size against the named limits; reports and returns 0
** when one is crossed. */
static int check_limits(const Scene *s, int w, int h, int n) {
  SrcRange at = s->output.loc;
  if (w < 1 || h < 1 || w > RENDER_MAX_SIZE || h > RENDER_MAX_SIZE) {
    diag_error(at, "image size %d x %d is outside 1 .. %d a side (RENDER_MAX_SIZE)", w, h,
               RENDER_MAX_SIZE);
    return 0;
  }
  if ((long long)w * h > RENDER_MAX_PIXELS) {
    diag_error(at, "image size %d x %d is %lld pixels, more than %lld (RENDER_MAX_PIXELS)", w, h,
               (long long)w * h, (long long)RENDER_MAX_PIXELS);
    return 0;
  }
  if (n < 1 || n > RENDER_MAX_SAMPLES) {
    diag_error(at, "samples %d is outside 1 .. %d (RENDER_MAX_SAMPLES)", n, RENDER_MAX_SAMPLES);
    return 0;
  }
  if ((long)w * n > RENDER_MAX_SAMPLE_DIM || (long)h * n > RENDER_MAX_SAMPLE_DIM) {
    diag_error(at, "%d x %d pixels at samples %d is %ld x %ld samples, more than %d a side "
               "(RENDER_MAX_SAMPLE_DIM); lower the size or the samples", w, h, n, (long)w * n,
               (long)h * n, RENDER_MAX_SAMPLE_DIM);
    return 0;
  }
  return 1;
}

int render_thread_count(const RenderOptions *o) {
  if (o->threads > 0) return o->threads;
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

/* ---- prepare: bounding box and camera -------------------------------------- */

static void box_add(Vec3 *lo, Vec3 *hi, Vec3 p) {
  if (!(isfinite(p.x) && isfinite(p.y) && isfinite(p.z))) return;
  lo->x = fmin(lo->x, p.x); lo->y = fmin(lo->y, p.y); lo->z = fmin(lo->z, p.z);
  hi->x = fmax(hi->x, p.x); hi->y = fmax(hi->y, p.y); hi->z = fmax(hi->z, p.z);
}

/* The world box of an origami block's folded state (computed when the
** block gives none); 0 when it does not build (render checked it first). */
static int origami_box(const SceneOrigami *og, Vec3 *lo, Vec3 *hi) {
  OrigamiModel *m = origami_build(og, 0);
  if (!m) return 0;
  origami_world_bounds(m, &og->transform, lo, hi);
  origami_free(m);
  return 1;
}

/* The world box of every object's control points (a Bezier patch lies in
** the hull of its control net, a subdivision surface in its cage) and
** every origami sheet. */
static void scene_box(const Scene *s, Vec3 *lo, Vec3 *hi) {
  *lo = v3(DBL_MAX, DBL_MAX, DBL_MAX);
  *hi = v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
  for (int i = 0; i < s->nobjects; i++) {
    const SceneObject *o = &s->objects[i];
    const SceneGeometry *g = o->geometry;
    if (!g) continue;
    for (int p = 0; p < g->npatches; p++)
      for (int k = 0; k < (g->patches[p].bilinear ? 4 : 16); k++)
        box_add(lo, hi, m4_point(o->transform, g->patches[p].cp[k]));
    for (int v = 0; v < g->nverts; v++) box_add(lo, hi, m4_point(o->transform, g->verts[v]));
  }
  for (int i = 0; i < s->norigami; i++) {
    Vec3 blo, bhi;
    if (!origami_box(&s->origami[i], &blo, &bhi)) continue;
    box_add(lo, hi, blo);
    box_add(lo, hi, bhi);
  }
}

/* ---- prepare: lights and styles ------------------------------------------- */

static void set3(float d[3], Vec3 v) { d[0] = (float)v.x; d[1] = (float)v.y; d[2] = (float)v.z; }

static void prepare_lights(const Scene *s, RenderFrame *f) {
  if (s->nlights == 0) {
    /* the default key light: over the camera's right shoulder (behind
    ** the viewer, up and to the right), white, strength 1 */
    const Camera *c = &f->camera;
    Vec3 l = v3_add(v3_mul(c->forward, -1), v3_add(v3_mul(c->right, 0.6), v3_mul(c->up, 0.8)));
    f->nlights = 1;
    f->lights = xcalloc(1, sizeof *f->lights);
    f->lights[0].directional = 1;
    set3(f->lights[0].dir, v3_norm(l));
    f->lights[0].color[0] = f->lights[0].color[1] = f->lights[0].color[2] = 1;
    return;
  }
  f->nlights = s->nlights;
  f->lights = xcalloc((size_t)s->nlights, sizeof *f->lights);
  for (int i = 0; i < s->nlights; i++) {
    const SceneLight *sl = &s->lights[i];
    RenderLight *l = &f->lights[i];
    l->directional = sl->kind == LIGHT_DIRECTIONAL;
    set3(l->pos, sl->position);
    set3(l->dir, v3_norm(v3_mul(sl->direction, -1)));   /* rays travel along direction */
    l->color[0] = (float)(sl->color.r * sl->strength);
    l->color[1] = (float)(sl->color.g * sl->strength);
    l->color[2] = (float)(sl->color.b * sl->strength);
    l->inverse_square = sl->falloff == FALLOFF_INVERSE_SQUARE;
    l->spot = sl->kind == LIGHT_SPOT;
    if (!l->spot) continue;
    set3(l->axis, v3_norm(v3_sub(sl->point_at, sl->position)));
    double edge = cos(sl->cone * M_PI / 180), inner = cos((sl->cone - sl->penumbra) * M_PI / 180);
    l->cos_edge = (float)edge;
    l->inv_fade = inner - edge > 1e-7 ? (float)(1 / (inner - edge)) : 1e30f;   /* no penumbra: a hard edge */
  }
}

/* The styles' shading constants; 0 after a diagnostic (an image a style
** reads that cannot be). */
static int prepare_styles(const Scene *s, RenderFrame *f) {
  f->default_style = scene_default_style();
  f->nstyles = s->nstyles + 1;
  f->styles = xcalloc((size_t)f->nstyles, sizeof *f->styles);
  int ok = 1;
  for (int i = 0; i < s->nstyles; i++) ok &= shade_style_init(&f->styles[i], &s->styles[i]);
  ok &= shade_style_init(&f->styles[s->nstyles], &f->default_style);
  return ok;
}

/* ---- prepare: objects ------------------------------------------------------ */

/* Six times the signed volume the linear part of M gives a unit one
** (its determinant): negative for a mirroring transform. */
static double linear_det(const Mat4 *M) {
  return v3_dot(v3(M->m[0][0], M->m[1][0], M->m[2][0]),
                v3_cross(v3(M->m[0][1], M->m[1][1], M->m[2][1]), v3(M->m[0][2], M->m[1][2], M->m[2][2])));
}

/* A mesh's world copies for one transform, kept with a mesh kept across
** frames (mesh_derived): a static object under a moving camera moves the
** same points every frame. */
typedef struct WorldCopy {
  Mat4 M;
  float (*pos)[3], (*nrm)[3], (*cnrm)[3][3];
} WorldCopy;

static const char world_tag;

static void world_copy_free(void *data) {
  WorldCopy *w = data;
  free(w->pos);
  free(w->nrm);
  free(w->cnrm);
  free(w);
}

/* Keep o's world copies with its mesh when it keeps such data and holds
** none yet (another transform's stays: an object sharing the mesh may be
** reading it); o->world_kept says the mesh owns them. */
static void keep_world(RenderObject *o) {
  if (!o->mesh->keeps_derived || mesh_derived(o->mesh, &world_tag)) return;
  WorldCopy *w = xmalloc(sizeof *w);
  *w = (WorldCopy){o->object_to_world, o->wpos, o->wnrm, o->wcnrm};
  if (mesh_derived_set(o->mesh, &world_tag, w, world_copy_free)) o->world_kept = 1;
  else free(w);
}

/* World positions and normals of o's mesh. Normals go through the inverse
** transpose; a mirroring transform (negative determinant) would turn the
** triangles clockwise, so their winding is swapped back and the topology
** rebuilt. A kept mesh's copies for the same transform are used as they
** are. */
static void object_to_world(RenderObject *o) {
  Mesh *m = o->mesh;
  Mat4 M = o->object_to_world;
  const WorldCopy *kept = mesh_derived(m, &world_tag);
  if (kept && !memcmp(&kept->M, &M, sizeof M)) {
    o->wpos = kept->pos, o->wnrm = kept->nrm, o->wcnrm = kept->cnrm;
    o->world_kept = 1;
    return;
  }
  int ok;
  Mat4 nt = m4_transpose(m4_inverse(M, &ok));
  if (!ok) nt = M;
  o->wpos = xmalloc((size_t)m->nverts * sizeof *o->wpos);
  o->wnrm = xmalloc((size_t)m->nverts * sizeof *o->wnrm);
  for (int i = 0; i < m->nverts; i++) {
    set3(o->wpos[i], m4_point(M, m->pos[i]));
    set3(o->wnrm[i], v3_norm(m4_dir(nt, m->nrm[i])));
  }
  if (m->corner_nrm) {   /* hard edges: each corner shades with its own face's normal */
    o->wcnrm = xmalloc((size_t)m->ntris * sizeof *o->wcnrm);
    for (int t = 0; t < m->ntris; t++)
      for (int k = 0; k < 3; k++) set3(o->wcnrm[t][k], v3_norm(m4_dir(nt, m->corner_nrm[t][k])));
  }
  if (linear_det(&M) >= 0) {
    keep_world(o);
    return;
  }
  /* a mirroring transform: keep the winding counter-clockwise */
  o->subdiv_kept = 0;   /* changed: not the refinement the cache knows */
  /* tagged creases (subdivision, CSG curves) survive the rebuild: edge k
  ** of a turned triangle is its edge 2 - k before */
  float (*sharp)[3] = m->edges ? xmalloc(((size_t)m->ntris + 1) * sizeof *sharp) : NULL;
  for (int t = 0; sharp && t < m->ntris; t++)
    for (int k = 0; k < 3; k++) sharp[t][k] = m->edges[m->tri_edges[t][k]].sharpness;
  for (int t = 0; t < m->ntris; t++) {
    int k = m->tri[t][1];
    m->tri[t][1] = m->tri[t][2];
    m->tri[t][2] = k;
    if (o->wcnrm) {
      float c[3];
      memcpy(c, o->wcnrm[t][1], sizeof c);
      memcpy(o->wcnrm[t][1], o->wcnrm[t][2], sizeof c);
      memcpy(o->wcnrm[t][2], c, sizeof c);
    }
    if (m->corner_uv) {
      Vec2 uv = m->corner_uv[t][1];
      m->corner_uv[t][1] = m->corner_uv[t][2];
      m->corner_uv[t][2] = uv;
    }
  }
  mesh_build_edges(m);
  for (int t = 0; sharp && t < m->ntris; t++)
    for (int k = 0; k < 3; k++)
      if (sharp[t][2 - k] > 0) m->edges[m->tri_edges[t][k]].sharpness = sharp[t][2 - k];
  free(sharp);
}

/* Which triangles show their back to the camera: the geometric normal
** (counter-clockwise winding) points away from the viewer. */
static void object_facing(RenderObject *o, const Camera *c) {
  const Mesh *m = o->mesh;
  /* in locals: a store to the bytes of back could alias any of them */
  unsigned char *back = xmalloc((size_t)m->ntris + 1);
  const int(*tri)[3] = (const int(*)[3])m->tri;
  const float(*wpos)[3] = (const float(*)[3])o->wpos;
  int ortho = c->kind == CAMERA_ORTHO, n = m->ntris;
  Vec3 eye = c->eye, away = v3_mul(c->forward, -1);
  for (int t = 0; t < n; t++) {
    const float *a = wpos[tri[t][0]], *b = wpos[tri[t][1]], *d = wpos[tri[t][2]];
    Vec3 e1 = v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    Vec3 e2 = v3(d[0] - a[0], d[1] - a[1], d[2] - a[2]);
    Vec3 view = ortho ? away : v3_sub(eye, v3(a[0], a[1], a[2]));
    back[t] = v3_dot(v3_cross(e1, e2), view) < 0;
  }
  o->backfacing = back;
}

/* What can_cull_back needs of the mesh alone, kept with a mesh kept
** across frames (mesh_derived): whether it is closed (every edge between
** exactly two triangles) and oriented consistently (its two triangles run
** along an edge in opposite directions), and six times its signed volume
** in object space (sum of p0 . (p1 x p2)). */
typedef struct ClosedMesh {
  int closed;
  double volume;
} ClosedMesh;

static const char closed_tag;

static ClosedMesh closed_mesh(const Mesh *m) {
  ClosedMesh c = {0, 0};
  for (int e = 0; e < m->nedges; e++)
    if (m->edges[e].f[1] < 0 || m->edges[e].nonmanifold) return c;
  /* each triangle adds +1 to an edge it runs along from v[0] to v[1],
  ** -1 the other way: a consistent closed mesh leaves every sum at 0 */
  signed char *turn = xcalloc((size_t)m->nedges + 1, 1);
  for (int t = 0; t < m->ntris; t++) {
    for (int k = 0; k < 3; k++) {
      int e = m->tri_edges[t][k];
      turn[e] += m->tri[t][k] == m->edges[e].v[0] ? 1 : -1;
    }
    Vec3 p0 = m->pos[m->tri[t][0]], p1 = m->pos[m->tri[t][1]], p2 = m->pos[m->tri[t][2]];
    c.volume += v3_dot(p0, v3_cross(p1, p2));
  }
  c.closed = 1;
  for (int e = 0; e < m->nedges && c.closed; e++) c.closed = turn[e] == 0;
  free(turn);
  return c;
}

/* A closed mesh, oriented consistently and outward (positive volume in
** world space: the object-space volume times the transform's determinant,
** a mirror turning the winding too), lying wholly beyond the near plane,
** shows only front faces: each view ray enters it through one. Its back
** faces then need no drawing. */
static int can_cull_back(const RenderObject *o, const Camera *c) {
  Mesh *m = o->mesh;
  if (m->ntris == 0 || !m->edges || !m->tri_edges) return 0;
  const ClosedMesh *kept = mesh_derived(m, &closed_tag);
  ClosedMesh cm = kept ? *kept : closed_mesh(m);
  if (!kept) {   /* kept for the next frames when the mesh is */
    ClosedMesh *keep = xmalloc(sizeof *keep);
    *keep = cm;
    if (!mesh_derived_set(m, &closed_tag, keep, free)) free(keep);
  }
  if (!cm.closed || !(cm.volume * linear_det(&o->object_to_world) > 0)) return 0;
  double fx = c->forward.x, fy = c->forward.y, fz = c->forward.z;
  double limit = v3_dot(c->eye, c->forward) + c->znear * 1.001;
  for (int v = 0; v < m->nverts; v++) {   /* every vertex clearly in front of the near plane */
    const float *p = o->wpos[v];
    if (p[0] * fx + p[1] * fy + p[2] * fz <= limit) return 0;
  }
  return 1;
}

static int is_adaptive_patches(const SceneObject *so) {
  return so->tess_kind == TESS_ADAPTIVE && so->geometry && so->geometry->kind == GEOM_PATCHES;
}

/* Tessellate o's patches or polygons for f's camera (thread-safe: one
** object, no diagnostics). With fit, the mesh only frames an automatic
** camera and is made again for the framed view (retessellate_adaptive):
** adaptive patches are then cut uniformly, which frames them as well for
** a fraction of the work. */
static void tessellate_object(const RenderFrame *f, RenderObject *o, int fit) {
  const SceneObject *so = o->src;
  const SceneGeometry *g = so->geometry;
  Mat4 to_clip = m4_mul(f->camera.world_to_clip, so->transform);
  int n = so->tess_n > 0 ? so->tess_n : RENDER_DEFAULT_TESS;
  if (fit && is_adaptive_patches(so)) o->mesh = tess_uniform(g, RENDER_DEFAULT_TESS);
  else o->mesh = g ? tess_geometry(g, so->tess_kind, n, so->tess_px, &to_clip, f->width, f->height)
                   : mesh_create(0, 0);
  object_to_world(o);
}

/* Subdivide o's mesh through OpenSubdiv (subdiv.h) and move it to world
** space; returns 0 after a diagnostic when that fails. */
static int subdivide_object(RenderObject *o) {
  const SceneGeometry *g = o->src->geometry;
  char err[256];
  double t0 = stats_now();
  SumiOsdBoundary boundary;
  subdiv_boundary_parse(g->subdiv_boundary, &boundary);   /* checked by the evaluator */
  o->mesh = subdiv_mesh(g, boundary, err, sizeof err);
  stats_record("subdiv", stats_now() - t0);
  int ok = o->mesh != NULL;
  o->subdiv_kept = ok;
  if (!ok) {
    diag_error(g->loc, "%s", err);
    o->mesh = mesh_create(0, 0);
  }
  object_to_world(o);
  return ok;
}

static int is_subdiv(const SceneGeometry *g) {
  return g && g->kind == GEOM_MESH && g->subdiv_level > 0;
}

/* Objects tessellated in parallel, each on its own (the list of
** indices into f->objects). */
typedef struct TessJob {
  const RenderFrame *f;
  int *todo;
  int fit;                     /* the meshes frame an automatic camera first */
} TessJob;

static void tess_task(void *ctx, int k) {
  TessJob *job = ctx;
  tessellate_object(job->f, &job->f->objects[job->todo[k]], job->fit);
}

/* Triangles a uniform or polygon object will make (0 for the others). */
static long long planned_triangles(const SceneObject *so) {
  const SceneGeometry *g = so->geometry;
  if (!g || is_subdiv(g)) return 0;
  if (g->kind == GEOM_MESH) return g->nfaces > 0 ? g->face_start[g->nfaces] - 2LL * g->nfaces : 0;
  if (so->tess_kind != TESS_UNIFORM) return 0;
  long long n = so->tess_n > 0 ? so->tess_n : RENDER_DEFAULT_TESS;
  return g->npatches * n * n * 2;
}

/* The scene's triangle budget, checked before any is made. */
static int check_triangles(const Scene *s) {
  long long total = 0;
  for (int i = 0; i < s->nobjects; i++) {
    total += planned_triangles(&s->objects[i]);
    if (total > RENDER_MAX_TRIANGLES) {
      diag_error(s->objects[i].loc,
                 "the scene asks for more than %lld triangles by this object (the limit); lower `tessellate` "
                 "or use `tessellate adaptive(px)`", RENDER_MAX_TRIANGLES);
      return 0;
    }
  }
  return 1;
}

static int prepare_objects(const Scene *s, RenderFrame *f, int nthreads, int fit) {
  int ok = 1, ntodo = 0;
  f->nobjects = s->nobjects;
  f->objects = xcalloc((size_t)s->nobjects + 1, sizeof *f->objects);
  int *todo = xmalloc((size_t)s->nobjects * sizeof *todo + 1);
  for (int i = 0; i < s->nobjects; i++) {
    const SceneObject *so = &s->objects[i];
    RenderObject *o = &f->objects[i];
    o->src = so;
    o->object_to_world = so->transform;
    o->style = &f->styles[so->style >= 0 && so->style < s->nstyles ? so->style : s->nstyles];
    if (is_subdiv(so->geometry)) {   /* in order, on this thread */
      long hits = subdiv_cache_hits();
      ok &= subdivide_object(o);
      f->refined |= subdiv_cache_hits() == hits;
    } else {
      todo[ntodo++] = i;
    }
  }
  TessJob job = {f, todo, fit};
  tasks_run(ntodo, nthreads, tess_task, &job);
  free(todo);
  for (int i = 0; i < f->nobjects; i++) f->ntriangles += f->objects[i].mesh->ntris;
  return ok;
}

/* Adaptive patches were cut uniformly to frame the camera; now that it is
** framed, tessellate them for the final view, where the tolerance holds. */
static void retessellate_adaptive(RenderFrame *f) {
  for (int i = 0; i < f->nobjects; i++) {
    RenderObject *o = &f->objects[i];
    if (!is_adaptive_patches(o->src)) continue;
    f->ntriangles -= o->mesh->ntris;
    mesh_destroy(o->mesh);
    if (!o->world_kept) {
      free(o->wpos);
      free(o->wnrm);
      free(o->wcnrm);
    }
    o->wcnrm = NULL;
    o->world_kept = 0;
    tessellate_object(f, o, 0);
    f->ntriangles += o->mesh->ntris;
  }
}

/* An automatic camera framed the objects' control boxes; frame the
** surfaces themselves now that they exist (tighter, and centred), with
** the boxes of any origami sheets. */
static void refit_camera(const Scene *s, RenderFrame *f) {
  CameraFit fit;
  camera_fit_init(&fit, &f->camera);
  for (int i = 0; i < f->nobjects; i++) {
    const RenderObject *o = &f->objects[i];
    for (int v = 0; v < o->mesh->nverts; v++)
      camera_fit_add(&fit, &f->camera, v3(o->wpos[v][0], o->wpos[v][1], o->wpos[v][2]));
  }
  for (int i = 0; i < s->norigami; i++) {   /* a flat sheet: its box corners */
    Vec3 lo, hi;
    if (!origami_box(&s->origami[i], &lo, &hi)) continue;
    for (int c = 0; c < 8; c++)
      camera_fit_add(&fit, &f->camera, v3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z));
  }
  camera_fit_apply(&f->camera, &fit);
}

/* What depends on where the camera is: facing, and what the shading
** models keep per vertex or triangle (shade_prepare_object). Returns 0
** after a diagnostic. */
static int prepare_view(RenderFrame *f) {
  int ok = 1;
  for (int i = 0; i < f->nobjects; i++) {
    RenderObject *o = &f->objects[i];
    object_facing(o, &f->camera);
    o->cull_back = can_cull_back(o, &f->camera);
    shade_centre_init(f, o);
    ok &= shade_prepare_object(f, o);
    if (o->style->ink) shade_ink_vertex_values(f, o);
  }
  return ok;
}

int render_prepare(const Scene *s, const RenderOptions *o, RenderFrame *f) {
  memset(f, 0, sizeof *f);
  f->scene = s;
  double t0 = stats_now();
  int w = o->width, h = o->height;
  if (w <= 0 || h <= 0) render_resolve_size(s, w, h, &w, &h);
  f->width = w;
  f->height = h;
  f->win = (RenderWindow){0, 0, w, h};
  f->samples = o->samples > 0 ? o->samples : s->output.samples > 0 ? s->output.samples : 1;
  f->antialias = s->output.antialias && !o->aliased;
  f->background = s->output.background;
  if (!check_limits(s, w, h, f->samples)) return 0;
  Vec3 lo, hi;
  scene_box(s, &lo, &hi);
  const char *why = NULL;
  if (!camera_setup(&f->camera, &s->camera, w, h, lo, hi, s->nobjects == 0 && s->norigami > 0,
                    &why)) {
    diag_error(s->camera.loc, "%s", why);
    return 0;
  }
  if (!prepare_styles(s, f) || !check_triangles(s)) return 0;
  double t1 = stats_now();
  int refit = !s->camera.present && f->camera.kind == CAMERA_PERSPECTIVE;
  int ok = prepare_objects(s, f, render_thread_count(o), refit);
  double t2 = stats_now();
  double retess = 0;
  if (refit) {
    refit_camera(s, f);
    double t3 = stats_now();
    retessellate_adaptive(f);
    retess = stats_now() - t3;
  }
  prepare_lights(s, f);
  ok = ok && shadow_prepare(s, f, render_thread_count(o));
  ok &= shade_ink_prepare(f);
  ok &= prepare_view(f);
  ok = ok && screentex_prepare(f);
  stats_record("prepare", t1 - t0 + stats_now() - t2 - retess);
  stats_record("tessellate", t2 - t1 + retess);
  stats_record_count("tessellate", "triangles", f->ntriangles);
  return ok;
}

void render_frame_free(RenderFrame *f) {
  for (int i = 0; i < f->nobjects; i++) {
    RenderObject *o = &f->objects[i];
    if (o->subdiv_kept) {   /* back to the cache across frames (subdiv.h) */
      SumiOsdBoundary boundary;
      subdiv_boundary_parse(o->src->geometry->subdiv_boundary, &boundary);
      subdiv_mesh_done(o->src->geometry, boundary, o->mesh);
    } else if (o->mesh) {
      mesh_destroy(o->mesh);
    }
    if (!o->world_kept) {   /* else the mesh's (keep_world) */
      free(o->wpos);
      free(o->wnrm);
      free(o->wcnrm);
    }
    free(o->backfacing);
    free(o->vcolor);
    shade_bokashi_free(o);
    free(o->vink);
    free(o->texcoords);
    free(o->wfnrm);
    free(o->imgcoords);
  }
  shadow_free_all(f);
  screentex_free(f);
  shade_ink_free(f);
  free(f->objects);
  free(f->lights);
  for (int i = 0; i < f->nstyles; i++) shade_style_free(&f->styles[i]);
  free(f->styles);
  memset(f, 0, sizeof *f);
}

/* What binning and the tile pass read of a set-up triangle rather than
** the whole RastTri: the tiles it touches, columns tx0..tx1 and rows
** ty0..ty1 (RENDER_MAX_SAMPLE_DIM / RENDER_TILE fits in 16 bits), a depth
** no sample of it is nearer than, whether it faces away from the camera,
** and where it is: slot in its list's tris, or (a lazy one: a back face,
** see emit_chunk, not set up yet) in its lazy entries. */
typedef struct TileBox {
  uint16_t tx0, ty0, tx1, ty1;
  float zmin;
  uint16_t slot;
  uint8_t back, lazy;
} TileBox;

/* A lazy entry: the pixel box a setup would give (RastTri's x0..y1, each
** at most RAST_MAX_DIM) and the face; its object is its list's. Twelve
** bytes where a RastTri is 128: most of a fine mesh's back faces are
** hidden and never set up. */
typedef struct LazyTri {
  uint16_t x0, y0, x1, y1;
  int32_t face;
} LazyTri;

/* One setup chunk's entries in drawing order (boxes[0 .. n)), each a
** set-up triangle in tris or a lazy one in lazy. */
typedef struct SetupList {
  RastTriList tris;
  LazyTri *lazy;
  int nlazy, lazy_cap;
  TileBox *boxes;
  int n, cap;
  int object;
} SetupList;

/* The set-up triangles, in per-chunk lists (see setup_triangles), and the
** screen tiles with, for each, references to the triangles touching it in
** drawing order (objects in order, triangles in order): bin t holds
** items[start[t] .. start[t + 1]), each item chunk << BIN_LOCAL_BITS | the
** index of its entry in that chunk's list. */
typedef struct Bins {
  int nlists;
  SetupList *lists;
  int tiles_x, tiles_y, side;  /* tile side in samples */
  int tx0, ty0, tx1, ty1;      /* the tiles the frame's window touches, [tx0, tx1) x [ty0, ty1):
                                  only these are binned */
  int *start;
  int *nfront;                 /* per tile: its bin's front-facing triangles come first */
  uint32_t *items;
  int apron;                   /* 1 when antialiased: a bin also holds the triangles touching
                                  the samples just around its tile */
  RastVert **verts;            /* per object, its projected vertices (the edge walks and
                                  the lazy setups read them) */
  const RenderFrame *f;
  int gw, gh;                  /* the sample grid */
} Bins;

#define BIN_LOCAL_BITS 15

static inline const TileBox *bin_box(const Bins *b, uint32_t item) {
  return &b->lists[item >> BIN_LOCAL_BITS].boxes[item & ((1u << BIN_LOCAL_BITS) - 1)];
}

/* ---- triangle setup and binning ------------------------------------------- */

/* Setup runs in chunks: each projects a range of one object's vertices,
** then each sets up a range of its triangles into its own list; the bins
** refer to (chunk, index), so the drawing order is the mesh order at any
** thread count. A clipped triangle can become up to 7, so a chunk's list
** stays under 7 * SETUP_CHUNK < 2^BIN_LOCAL_BITS entries. */
enum { SETUP_CHUNK = 4096 };

typedef struct SetupChunk { int object, start, end; } SetupChunk;

typedef struct SetupJob {
  const RenderFrame *f;
  int gw, gh, side;            /* sample grid; tile side in samples */
  int side_shift;              /* log2 of side, or -1 when it is no power of two */
  int last_tx, last_ty;        /* the last tile column and row */
  int apron;                   /* samples a tile's bin reaches around it */
  int wx0, wy0, wx1, wy1;      /* the samples of the frame's window: triangles wholly
                                  outside it (and its apron) are not set up */
  RastVert **verts;            /* per object */
  SetupChunk *chunks;
  SetupList *lists;            /* per triangle chunk */
} SetupJob;

static void project_chunk(void *ctx, int k) {
  SetupJob *job = ctx;
  const SetupChunk *c = &job->chunks[k];
  const RenderObject *o = &job->f->objects[c->object];
  rast_vertices(&job->verts[c->object][c->start], (const float(*)[3])&o->wpos[c->start], c->end - c->start,
                job->f->camera.world_to_clip.m, job->gw, job->gh);
}

/* Is a triangle none of whose vertices needs clipping wholly outside the
** window and its apron (a sample's margin more for the fill rule)?
** Leaving it out changes no sample the window's tiles draw: the bins keep
** the others in order. Only asked when the window is not the whole grid. */
static int outside_window(const SetupJob *job, const RastVert *const tv[3]) {
  if (tv[0]->outcode | tv[1]->outcode | tv[2]->outcode) return 0;
  int64_t x0 = tv[0]->X, x1 = x0, y0 = tv[0]->Y, y1 = y0;
  for (int k = 1; k < 3; k++) {
    x0 = tv[k]->X < x0 ? tv[k]->X : x0, x1 = tv[k]->X > x1 ? tv[k]->X : x1;
    y0 = tv[k]->Y < y0 ? tv[k]->Y : y0, y1 = tv[k]->Y > y1 ? tv[k]->Y : y1;
  }
  /* fixed point to samples (an arithmetic shift floors), widened by one */
  int g = job->apron + 1;
  return (x1 >> RAST_SUBPIXEL_BITS) + g < job->wx0 || (x0 >> RAST_SUBPIXEL_BITS) - g >= job->wx1 ||
         (y1 >> RAST_SUBPIXEL_BITS) + g < job->wy0 || (y0 >> RAST_SUBPIXEL_BITS) - g >= job->wy1;
}

/* Tile of sample x: a shift when the tile side is a power of two (it is
** RENDER_TILE times the samples a side), else a division. */
static inline int tile_of(const SetupJob *job, int x) {
  return job->side_shift >= 0 ? x >> job->side_shift : x / job->side;
}

/* The tiles list entry box touches (pixel box x0..y1 grown by the apron),
** with depth bound zmin, into a new entry of list. */
static inline void push_box(const SetupJob *job, SetupList *list, int x0, int y0, int x1, int y1, float zmin,
                            int slot, int back, int lazy) {
  int g = job->apron, last_x = job->last_tx, last_y = job->last_ty;
  int tx1 = tile_of(job, x1 - 1 + g), ty1 = tile_of(job, y1 - 1 + g);
  if (list->n == list->cap) list->boxes = xgrow(list->boxes, &list->cap, list->n + 1, sizeof *list->boxes);
  list->boxes[list->n++] = (TileBox){(uint16_t)tile_of(job, x0 - g > 0 ? x0 - g : 0),
                                     (uint16_t)tile_of(job, y0 - g > 0 ? y0 - g : 0),
                                     (uint16_t)(tx1 < last_x ? tx1 : last_x),
                                     (uint16_t)(ty1 < last_y ? ty1 : last_y), zmin, (uint16_t)slot,
                                     (uint8_t)back, (uint8_t)lazy};
}

/* fminf inline (the library's is a call): the lesser, or the one that is
** not NaN. */
static inline float min_num(float a, float b) { return a < b || b != b ? a : b; }

static void emit_chunk(void *ctx, int k) {
  SetupJob *job = ctx;
  const SetupChunk *c = &job->chunks[k];
  const RenderObject *o = &job->f->objects[c->object];
  const Mesh *m = o->mesh;
  const RastVert *rv = job->verts[c->object];
  SetupList *list = &job->lists[k];
  RastTriList *tris = &list->tris;
  list->object = c->object;
  /* one entry a triangle, unless clipping splits some: pages never
  ** written are never touched */
  tris->cap = list->cap = list->lazy_cap = c->end - c->start;
  tris->tris = xmalloc((size_t)tris->cap * sizeof *tris->tris);
  list->boxes = xmalloc((size_t)list->cap * sizeof *list->boxes);
  list->lazy = xmalloc((size_t)list->lazy_cap * sizeof *list->lazy);
  /* in locals: a store to the lists could alias them */
  int cull = o->cull_back, windowed = !(job->wx0 == 0 && job->wy0 == 0 && job->wx1 == job->gw && job->wy1 == job->gh);
  const unsigned char *backfacing = o->backfacing;
  for (int t = c->start; t < c->end; t++) {
    if (cull && backfacing[t]) continue;   /* hidden by the object's front */
    const RastVert *tv[3] = {&rv[m->tri[t][0]], &rv[m->tri[t][1]], &rv[m->tri[t][2]]};
    if (windowed && outside_window(job, tv)) continue;
    int back = backfacing[t];
    if (back && !(tv[0]->outcode | tv[1]->outcode | tv[2]->outcode)) {
      /* A back face is drawn after the front ones and mostly hidden by
      ** them (raster_items skips it on its depth bound): work out only its
      ** box and bound now, and set it up when a tile draws it. */
      int bx[4];
      float z;
      if (!rast_bounds(tv, job->gw, job->gh, bx, &z)) continue;
      list->lazy[list->nlazy] = (LazyTri){(uint16_t)bx[0], (uint16_t)bx[1], (uint16_t)bx[2], (uint16_t)bx[3], t};
      push_box(job, list, bx[0], bx[1], bx[2], bx[3], z, list->nlazy++, 1, 1);
      continue;
    }
    int n0 = tris->n;
    double h[3][4];   /* clip coordinates: only a triangle to be clipped reads them */
    const double *const hv[3] = {h[0], h[1], h[2]};
    if (rast_needs_clip(tv))
      for (int i = 0; i < 3; i++) rast_clip_point(h[i], job->f->camera.world_to_clip.m, o->wpos[m->tri[t][i]]);
    rast_emit(tris, tv, hv, c->object, t, job->gw, job->gh);
    for (int i = n0; i < tris->n; i++) {   /* one, or the pieces clipping made */
      const RastTri *r = &tris->tris[i];
      /* depth is affine: its least value over the box of sample centres is
      ** at a corner; the margin covers the rounding of rast_triangle's sums */
      float fx0 = (float)r->x0 + 0.5f - r->ox, fx1 = (float)r->x1 - 0.5f - r->ox;
      float fy0 = (float)r->y0 + 0.5f - r->oy, fy1 = (float)r->y1 - 0.5f - r->oy;
      float zx = min_num(r->z[1] * fx0, r->z[1] * fx1), zy = min_num(r->z[2] * fy0, r->z[2] * fy1);
      push_box(job, list, r->x0, r->y0, r->x1, r->y1, r->z[0] + zx + zy - 1e-5f, i, back, 0);
    }
  }
  /* back to what was used: the unused tails go back to the heap for the
  ** next stages rather than lying in it as holes (peak memory) */
  tris->tris = xrealloc(tris->tris, ((size_t)tris->n + 1) * sizeof *tris->tris);
  list->boxes = xrealloc(list->boxes, ((size_t)list->n + 1) * sizeof *list->boxes);
  list->lazy = xrealloc(list->lazy, ((size_t)list->nlazy + 1) * sizeof *list->lazy);
  tris->cap = tris->n + 1, list->cap = list->n + 1, list->lazy_cap = list->nlazy + 1;
}

/* Chunks covering count(object) items of every object; returns how many. */
static int make_chunks(const RenderFrame *f, int tris, SetupChunk **out) {
  int n = 0, cap = 0;
  SetupChunk *c = NULL;
  for (int i = 0; i < f->nobjects; i++) {
    int total = tris ? f->objects[i].mesh->ntris : f->objects[i].mesh->nverts;
    for (int s = 0; s < total; s += SETUP_CHUNK) {
      c = xgrow(c, &cap, n + 1, sizeof *c);
      c[n++] = (SetupChunk){i, s, s + SETUP_CHUNK < total ? s + SETUP_CHUNK : total};
    }
  }
  *out = c;
  return n;
}

/* Project every vertex of every object and set up its triangles for a
** gw x gh sample grid, on nthreads threads, into b's lists. */
static void setup_triangles(const RenderFrame *f, int gw, int gh, int nthreads, Bins *b) {
  int N = f->samples;
  int shift = -1;
  for (int k = 0; k < 30; k++)
    if (b->side == 1 << k) shift = k;
  SetupJob job = {f, gw, gh, b->side, shift, (gw - 1) / b->side, (gh - 1) / b->side, b->apron,
                  f->win.x0 * N, f->win.y0 * N, f->win.x1 * N, f->win.y1 * N, NULL, NULL, NULL};
  job.verts = xcalloc((size_t)f->nobjects + 1, sizeof *job.verts);
  for (int i = 0; i < f->nobjects; i++)
    job.verts[i] = xmalloc((size_t)f->objects[i].mesh->nverts * sizeof **job.verts + 1);
  int n = make_chunks(f, 0, &job.chunks);
  tasks_run(n, nthreads, project_chunk, &job);
  free(job.chunks);
  n = make_chunks(f, 1, &job.chunks);
  job.lists = xcalloc((size_t)n + 1, sizeof *job.lists);
  tasks_run(n, nthreads, emit_chunk, &job);
  b->verts = job.verts;   /* the lazy setups and the edge walks read them */
  b->f = f, b->gw = gw, b->gh = gh;
  free(job.chunks);
  b->lists = job.lists;
  b->nlists = n;
}

/* Counting sort of triangle references by tile: two passes over the
** triangles. Each bin holds its front-facing triangles, then the ones
** facing away, each group in drawing order: back faces are mostly hidden
** by the front ones, and once those are drawn the tile pass can skip
** them whole (tile_worker). Each pass runs in bands of tile rows on
** worker threads; a band's task reads every entry but counts and fills
** only its own rows' bins, in the same order at any thread count. */
typedef struct BinJob {
  Bins *b;
  int nbands, pass;
  int *front, *back;           /* pass 1: per tile, the entries placed so far */
} BinJob;

static void bin_band(void *ctx, int band) {
  BinJob *job = ctx;
  Bins *b = job->b;
  int rows = b->ty1 - b->ty0;
  int by0 = b->ty0 + (int)((long)rows * band / job->nbands), by1 = b->ty0 + (int)((long)rows * (band + 1) / job->nbands);
  for (int l = 0; l < b->nlists; l++)
    for (int i = 0; i < b->lists[l].n; i++) {
      TileBox t = b->lists[l].boxes[i];
      if (t.ty1 < by0 || t.ty0 >= by1) continue;
      uint32_t item = (uint32_t)l << BIN_LOCAL_BITS | (uint32_t)i;
      int ty0 = t.ty0 > by0 ? t.ty0 : by0, ty1 = t.ty1 < by1 - 1 ? t.ty1 : by1 - 1;
      int tx0 = t.tx0 > b->tx0 ? t.tx0 : b->tx0, tx1 = t.tx1 < b->tx1 - 1 ? t.tx1 : b->tx1 - 1;
      for (int ty = ty0; ty <= ty1; ty++)
        for (int tx = tx0; tx <= tx1; tx++) {
          int k = ty * b->tiles_x + tx;
          if (!job->pass) {
            b->start[k + 1]++;
            b->nfront[k] += !t.back;
          } else if (t.back) {
            b->items[b->start[k] + b->nfront[k] + job->back[k]++] = item;
          } else {
            b->items[b->start[k] + job->front[k]++] = item;
          }
        }
    }
}

static void bin_triangles(Bins *b, int nthreads) {
  int ntiles = b->tiles_x * b->tiles_y;
  b->start = xcalloc((size_t)ntiles + 1, sizeof *b->start);
  b->nfront = xcalloc((size_t)ntiles + 1, sizeof *b->nfront);
  int rows = b->ty1 - b->ty0;
  BinJob job = {b, nthreads > 1 ? 2 * nthreads : 1, 0, NULL, NULL};   /* more bands than threads: */
  if (job.nbands > rows) job.nbands = rows > 0 ? rows : 1;           /* bands differ in work */
  tasks_run(job.nbands, nthreads, bin_band, &job);
  for (int k = 0; k < ntiles; k++) b->start[k + 1] += b->start[k];
  b->items = xmalloc((size_t)b->start[ntiles] * sizeof *b->items + 1);
  job.pass = 1;
  job.front = xcalloc((size_t)ntiles + 1, sizeof *job.front);
  job.back = xcalloc((size_t)ntiles + 1, sizeof *job.back);
  tasks_run(job.nbands, nthreads, bin_band, &job);
  free(job.front);
  free(job.back);
}

static void bins_free(Bins *b, int nobjects) {
  for (int i = 0; b->verts && i < nobjects; i++) free(b->verts[i]);
  free(b->verts);
  for (int l = 0; l < b->nlists; l++) {
    rast_list_free(&b->lists[l].tris);
    free(b->lists[l].lazy);
    free(b->lists[l].boxes);
  }
  free(b->lists);
  free(b->start);
  free(b->nfront);
  free(b->items);
}

/* ---- the tile pass --------------------------------------------------------- */

typedef struct TileJob {
  const RenderFrame *f;
  const Bins *bins;
  GBuffer *full;               /* the window's G-buffer, or NULL: per-worker tile planes */
  Image *out;
  int ox, oy;                  /* the frame pixel out's first pixel shows */
  int y0, y1;                  /* the frame rows this run shades, inside the window */
  int ty0, ntiles;             /* their first tile row; their tiles (of the window's columns) */
  const RenderProgress *progress;
  int progress_total;          /* with progress: the window's tiles, over every run */
  atomic_int done;             /* with progress: tiles shaded so far */
  ShadeSpanFn *span;           /* per style: its model's span shader */
  ShadeView view;              /* the camera as the rebuild needs it */
  atomic_int next;
  const RenderRows *rows;      /* finished bands go here during the pass, or NULL */
  atomic_int *band_left;       /* with rows: per tile row, its tiles not yet shaded */
  pthread_mutex_t band_lock;   /* held by the worker handing bands over */
  int next_band;               /* under band_lock: the first band not handed over */
  double write_s;              /* summed time of the rows calls */
  const RenderTileSink *sink;  /* each tile's samples go here too, or NULL */
  AaFrame aa;                  /* antialiased: the edge walks' meshes (antialias.h) */
} TileJob;

/* One worker's state: its tile planes (when there is no whole G-buffer)
** and the time it spent in each stage. */
typedef struct Worker {
  TileJob *job;
  float *depth;
  int32_t *object, *face;
  float (*bary)[2];
  float *rows;                 /* N rows of a tile's shaded samples (N > 1) */
  float *prow;                 /* a tile row of pixels bound for an 8-bit image */
  ShadeRow row;                /* a tile row's rebuilt surface samples */
  /* antialiased: the tile's shaded samples with their apron, indexed like
  ** the planes; the tile's blends and the colours aa_apply works out */
  float *tcol;
  uint32_t *tkey;              /* the shading's steps at them (ShadeRow.step_key) */
  float *memo;                 /* their values as worked out (AaSteps) */
  uint32_t *seen, stamp;
  AaBlend *blends;
  AaScratch scratch;
  double raster_s, shade_s, write_s;
} Worker;

/* A tile's samples, [x0, x1) x [y0, y1), and the target it is drawn
** into: that rectangle or, antialiased, the rectangle one sample larger
** (within the grid) in the worker's own planes. */
typedef struct Tile {
  RastTarget rt;
  int x0, y0, x1, y1;
} Tile;

/* The target for tile (tx, ty), cut to the window's columns and the run's
** rows: the window's G-buffer's planes, or the worker's own, with the
** rectangle cleared to the background when clear is set. */
static Tile tile_target(Worker *w, int tx, int ty, int clear) {
  const TileJob *job = w->job;
  const Bins *b = job->bins;
  GBuffer *g = b->apron ? NULL : job->full;   /* antialiased: copied to it after */
  Tile tl;
  RastTarget rt = {0};
  int N = job->f->samples, gw = job->f->width * N, gh = job->f->height * N;
  int wx0 = job->f->win.x0 * N, wx1 = job->f->win.x1 * N, wy0 = job->y0 * N, wy1 = job->y1 * N;
  int a = b->apron;
  tl.x0 = tx * b->side > wx0 ? tx * b->side : wx0;
  tl.y0 = ty * b->side > wy0 ? ty * b->side : wy0;
  tl.x1 = (tx + 1) * b->side < wx1 ? (tx + 1) * b->side : wx1;
  tl.y1 = (ty + 1) * b->side < wy1 ? (ty + 1) * b->side : wy1;
  rt.x0 = tl.x0 - a > 0 ? tl.x0 - a : 0;
  rt.y0 = tl.y0 - a > 0 ? tl.y0 - a : 0;
  rt.x1 = tl.x1 + a < gw ? tl.x1 + a : gw;
  rt.y1 = tl.y1 + a < gh ? tl.y1 + a : gh;
  if (g) {
    rt.ox = job->f->win.x0 * N;
    rt.oy = job->f->win.y0 * N;
    rt.stride = g->width;
    rt.depth = g->depth; rt.object = g->object; rt.face = g->face; rt.bary = g->bary;
  } else {
    rt.ox = tl.x0 - a;
    rt.oy = tl.y0 - a;
    rt.stride = b->side + 2 * a;
    rt.depth = w->depth; rt.object = w->object; rt.face = w->face; rt.bary = w->bary;
  }
  for (int y = rt.y0; clear && y < rt.y1; y++) {
    int i = (y - rt.oy) * rt.stride + (rt.x0 - rt.ox), n = rt.x1 - rt.x0;
    for (int k = 0; k < n; k++) rt.depth[i + k] = GBUF_NO_DEPTH;
    memset(rt.object + i, 0xff, (size_t)n * sizeof *rt.object);   /* -1 */
    if (g) {   /* a kept G-buffer shows face and bary everywhere; tile planes are read only where drawn */
      memset(rt.face + i, 0xff, (size_t)n * sizeof *rt.face);
      memset(rt.bary + i, 0, (size_t)n * sizeof *rt.bary);
    }
  }
  tl.rt = rt;
  return tl;
}

/* Shade the n samples of a tile row starting at plane index i (sample
** (sx, sy) of the grid) into out, nc floats a sample (3 or 4; the 4th is
** the alpha: 1 where shaded), the background bg where nothing was drawn.
** Two passes: rebuild the surface at every drawn sample into the worker's
** row, per run of one triangle; then shade them, one span call per run of
** one object, with its noise and pattern over them. */
static void shade_row(const TileJob *job, const RastTarget *rt, int i, int sx, int sy, int n, float *out,
                      int nc, const float bg[4], ShadeRow *row) {
  const int32_t *obj = rt->object + i, *face = rt->face + i;
  const RenderObject *objects = job->f->objects;
  row->face = face;
  shade_row_start(row, &job->view, sx, sy);
  row->bary = (const float(*)[2])rt->bary + i;
  for (int k = 0, e; k < n; k = e) {                    /* pass 1: the surface, left to right */
    if (obj[k] < 0) { e = k + 1; continue; }            /* background: its lanes go unused */
    for (e = k + 1; e < n && obj[e] == obj[k] && face[e] == face[k]; e++) {}
    if (objects[obj[k]].style->alpha > 0) {             /* ink reads no surface: the canvas paints it */
      shade_row_rebuild(row, &job->view, &objects[obj[k]], face[k], k, e);
      if (objects[obj[k]].style->image) shade_image_run(row, &objects[obj[k]], face[k], k, e);
    }
  }
  for (int k = 0, e; k < n; k = e) {                    /* pass 2: the colours */
    if (obj[k] < 0) {                                    /* a run of background */
      for (e = k; e < n && obj[e] < 0; e++) {
        float *o = out + e * nc;
        o[0] = bg[0]; o[1] = bg[1]; o[2] = bg[2];
        if (nc == 4) o[3] = bg[3];
      }
      continue;
    }
    for (e = k + 1; e < n && obj[e] == obj[k]; e++) {}
    const RenderObject *o = &objects[obj[k]];
    job->span[o->style - job->f->styles](row, o, k, e, out, nc);
    if (o->tex && o->style->alpha > 0) screentex_span(row, o, k, e, out, nc);   /* not under ink's alpha 0 */
    if (nc == 4)   /* 1, or 0 for a style the canvas paints afterwards (ink) */
      for (int j = k; j < e; j++) out[j * 4 + 3] = o->style->alpha;
  }
}

/* Where pixels x0.. of row y go: the float image itself, or (an 8-bit
** image) the worker's row, which put_row then encodes into it. */
static float *row_out(const TileJob *job, int x0, int y, float *prow) {
  const Image *img = job->out;
  size_t at = ((size_t)(y - job->oy) * img->width + (size_t)(x0 - job->ox)) * img->channels;
  return img->data ? &img->data[at] : prow;
}

static void put_row(const TileJob *job, int x0, int y, int n, const float *prow) {
  const Image *img = job->out;
  size_t at = ((size_t)(y - job->oy) * img->width + (size_t)(x0 - job->ox)) * img->channels;
  if (!img->data) image_encode8(prow, &img->data8[at], (size_t)n, img->channels);
}

/* Does a sample of object obj encode as the background's codes: the
** background itself, or (over a transparent one) a style the canvas paints
** later, whose samples are transparent black too? */
static inline int clear_at(const TileJob *job, int32_t obj, float bg_alpha) {
  return obj < 0 || (bg_alpha == 0 && job->f->objects[obj].style->alpha == 0);
}

/* One sample a pixel: the sample is the pixel. A float image is shaded in
** place. An 8-bit one gets each row's shaded runs encoded and its
** background runs copied from a row of background codes: most rows hold
** background only and are not shaded at all. A tile no triangle touches
** (empty) is all background, its planes not even read. */
static void shade_tile_1(const TileJob *job, const RastTarget *rt, int empty, ShadeRow *row,
                         float *prow) {
  Color bg = job->f->background;
  float bgu[4] = {bg.a > 0 ? bg.r : 0, bg.a > 0 ? bg.g : 0, bg.a > 0 ? bg.b : 0, bg.a};
  const Image *img = job->out;
  int nc = img->channels, n = rt->x1 - rt->x0;   /* 3, or 4 with alpha */
  uint8_t bgrow[RENDER_TILE * 4];
  if (img->data8) {
    image_encode8(bgu, bgrow, 1, nc);
    for (int x = 1; x < n; x++) memcpy(bgrow + x * nc, bgrow, (size_t)nc);
  }
  for (int y = rt->y0; y < rt->y1; y++) {
    int i = (y - rt->oy) * rt->stride + (rt->x0 - rt->ox);
    size_t at = ((size_t)(y - job->oy) * img->width + (size_t)(rt->x0 - job->ox)) * nc;
    if (!img->data8) {
      if (empty)
        for (int k = 0; k < n * nc; k++) img->data[at + k] = bgu[k % nc];
      else
        shade_row(job, rt, i, rt->x0, y, n, &img->data[at], nc, bgu, row);
      continue;
    }
    uint8_t *d = &img->data8[at];
    if (empty) {
      memcpy(d, bgrow, (size_t)(n * nc));
      continue;
    }
    const int32_t *obj = rt->object + i;
    uint32_t all = 0xffffffffu;   /* stays all ones when every sample is background (-1) */
    for (int k = 0; k < n; k++) all &= (uint32_t)obj[k];
    if (all == 0xffffffffu) {
      memcpy(d, bgrow, (size_t)(n * nc));
      continue;
    }
    shade_row(job, rt, i, rt->x0, y, n, prow, nc, bgu, row);
    for (int e, j = 0; j < n; j = e) {   /* runs of background and of shaded samples */
      int back = clear_at(job, obj[j], bg.a);
      for (e = j + 1; e < n && clear_at(job, obj[e], bg.a) == back; e++) {}
      if (back) memcpy(d + j * nc, bgrow, (size_t)((e - j) * nc));
      else image_encode8(prow + j * nc, d + j * nc, (size_t)(e - j), nc);
    }
  }
}

/* Shade the samples of the tile and box-filter each pixel's N x N of them
** (premultiplied, over the background) into the output image; rows holds
** N rows of the tile's samples, 4 floats each; row the worker's ShadeRow;
** prow a row of pixels for an 8-bit image. */
static void shade_tile(const TileJob *job, const RastTarget *rt, int empty, float *rows,
                       ShadeRow *row, float *prow) {
  const RenderFrame *f = job->f;
  int N = f->samples;
  if (N == 1) { shade_tile_1(job, rt, empty, row, prow); return; }
  Color bg = f->background;
  float bgp[4] = {bg.r * bg.a, bg.g * bg.a, bg.b * bg.a, bg.a};   /* premultiplied */
  float nn = (float)(N * N), inv_nn = 1.0f / nn;
  int nc = job->out->channels;       /* 3, or 4 with alpha */
  int n = rt->x1 - rt->x0;           /* samples a row */
  for (int py = rt->y0 / N; py < rt->y1 / N; py++) {
    for (int r = 0; r < N; r++) {    /* the pixel row's N sample rows, shaded */
      int i = (py * N + r - rt->oy) * rt->stride + (rt->x0 - rt->ox);
      shade_row(job, rt, i, rt->x0, py * N + r, n, rows + (size_t)r * n * 4, 4, bgp, row);
    }
    float *o = row_out(job, rt->x0 / N, py, prow), *o0 = o;
    for (int px = 0; px < n / N; px++, o += nc) {
      float acc[4] = {0, 0, 0, 0};
      for (int r = 0; r < N; r++) {
        const float *q = rows + ((size_t)r * n + (size_t)px * N) * 4;
        for (int k = 0; k < N; k++, q += 4) {
          acc[0] += q[0]; acc[1] += q[1]; acc[2] += q[2]; acc[3] += q[3];
        }
      }
      /* back to unassociated alpha: divide by the summed alpha (a
      ** multiply when the pixel is opaque, the common case) */
      float un = acc[3] == nn ? inv_nn : acc[3] > 0 ? 1 / acc[3] : 0;
      o[0] = acc[0] * un; o[1] = acc[1] * un; o[2] = acc[2] * un;
      if (nc == 4) o[3] = acc[3] * inv_nn;
    }
    put_row(job, rt->x0 / N, py, n / N, o0);
  }
}

/* Antialiased: the tile's samples and its apron are shaded into the
** worker's tile colours, with where the shading steps, the blends of the
** tile's edges (antialias.h) applied there, then written out: as they are
** at one sample a pixel, box-filtered otherwise. */
static void shade_tile_aa(const TileJob *job, const Tile *tl, Worker *w) {
  const RenderFrame *f = job->f;
  const RastTarget *rt = &tl->rt;
  const Image *img = job->out;
  int N = f->samples, nc = N == 1 ? img->channels : 4, n = tl->x1 - tl->x0;
  Color bg = f->background;
  float bgu[4] = {bg.a > 0 ? bg.r : 0, bg.a > 0 ? bg.g : 0, bg.a > 0 ? bg.b : 0, bg.a};
  float bgp[4] = {bg.r * bg.a, bg.g * bg.a, bg.b * bg.a, bg.a};   /* premultiplied, for the filter */
  const float *bgc = N == 1 ? bgu : bgp;
  int wn = rt->x1 - rt->x0;
  for (int y = rt->y0; y < rt->y1; y++) {   /* the apron too: the blends read its colours and steps */
    int i = (y - rt->oy) * rt->stride + (rt->x0 - rt->ox);
    w->row.step_key = w->tkey + i;
    memset(w->row.step_key, 0, (size_t)wn * sizeof *w->row.step_key);
    shade_row(job, rt, i, rt->x0, y, wn, w->tcol + (size_t)i * nc, nc, bgc, &w->row);
  }
  w->row.step_key = NULL;
  AaSteps steps = {w->tkey, &job->view, w->memo, w->seen, ++w->stamp};
  int nb = aa_tile(&job->aa, rt, &steps, tl->x0, tl->y0, tl->x1, tl->y1, w->blends);
  aa_apply(w->blends, nb, w->tcol, nc, N == 1, &w->scratch);
  if (N == 1) {   /* the samples are the pixels: into the float image, or encoded from the tile */
    for (int y = tl->y0; y < tl->y1; y++) {
      const float *c = w->tcol + (size_t)((y - rt->oy) * rt->stride + (tl->x0 - rt->ox)) * nc;
      if (img->data) memcpy(row_out(job, tl->x0, y, w->prow), c, (size_t)n * nc * sizeof *c);
      else put_row(job, tl->x0, y, n, c);
    }
    return;
  }
  float nn = (float)(N * N), inv_nn = 1.0f / nn;
  int oc = img->channels;
  for (int py = tl->y0 / N; py < tl->y1 / N; py++) {
    float *o = row_out(job, tl->x0 / N, py, w->prow), *o0 = o;
    for (int px = tl->x0 / N; px < tl->x1 / N; px++, o += oc) {
      float acc[4] = {0, 0, 0, 0};
      for (int r = 0; r < N; r++) {
        const float *q = w->tcol + (size_t)((py * N + r - rt->oy) * rt->stride + (px * N - rt->ox)) * 4;
        for (int k = 0; k < N; k++, q += 4) {
          acc[0] += q[0]; acc[1] += q[1]; acc[2] += q[2]; acc[3] += q[3];
        }
      }
      float un = acc[3] == nn ? inv_nn : acc[3] > 0 ? 1 / acc[3] : 0;   /* as shade_tile */
      o[0] = acc[0] * un; o[1] = acc[1] * un; o[2] = acc[2] * un;
      if (oc == 4) o[3] = acc[3] * inv_nn;
    }
    put_row(job, tl->x0 / N, py, n / N, o0);
  }
}

/* Antialiased with a whole G-buffer kept: the tile's samples, drawn in
** the worker's planes, go into it (face -1 and bary 0 on the
** background, as a kept G-buffer shows them). */
static void copy_tile(GBuffer *g, const RenderFrame *f, const Tile *tl) {
  const RastTarget *rt = &tl->rt;
  int gx0 = f->win.x0 * f->samples, gy0 = f->win.y0 * f->samples;   /* the window's first sample */
  for (int y = tl->y0; y < tl->y1; y++)
    for (int x = tl->x0; x < tl->x1; x++) {
      int i = (y - rt->oy) * rt->stride + (x - rt->ox);
      size_t j = (size_t)(y - gy0) * g->width + (size_t)(x - gx0);
      int drawn = rt->object[i] >= 0;
      g->depth[j] = rt->depth[i];
      g->object[j] = rt->object[i];
      g->face[j] = drawn ? rt->face[i] : GBUF_NO_ID;
      g->bary[j][0] = drawn ? rt->bary[i][0] : 0;
      g->bary[j][1] = drawn ? rt->bary[i][1] : 0;
    }
}

/* The farthest depth in rectangle [x0, x1) x [y0, y1) of rt
** (GBUF_NO_DEPTH if nothing is drawn at some sample of it; 0 for a
** rectangle of no samples). Eight running maxima, one per column mod 8,
** so the comparisons do not wait on each other; the same value as one
** running maximum. */
static float rect_far(const RastTarget *rt, int x0, int y0, int x1, int y1) {
  float far[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  int n = x1 - x0;
  for (int y = y0; y < y1; y++) {
    const float *d = rt->depth + (y - rt->oy) * rt->stride + (x0 - rt->ox);
    int x = 0;
    for (; x + 8 <= n; x += 8)
      for (int k = 0; k < 8; k++) far[k] = d[x + k] > far[k] ? d[x + k] : far[k];
    for (; x < n; x++) far[0] = d[x] > far[0] ? d[x] : far[0];
  }
  for (int k = 1; k < 8; k++) far[0] = far[k] > far[0] ? far[k] : far[0];
  return far[0];
}

static float tile_far(const RastTarget *rt) { return rect_far(rt, rt->x0, rt->y0, rt->x1, rt->y1); }

/* Rasterize bin items [i0, i1) into rt, but for those no nearer than far
** anywhere (their depth test would fail at every sample). With boxes set
** (the back faces, drawn after the front ones and mostly hidden by them),
** an item is also skipped when it is no nearer than the farthest depth
** in its own pixel box: reading that box costs a fraction of rasterizing
** the triangle only to fail the depth test row after row. */
static void raster_items(const Bins *b, int i0, int i1, float far, int boxes, RastTarget *rt) {
  for (int i = i0; i < i1; i++) {
    if (i + 2 < i1) {   /* the bin jumps around the lists: fetch ahead */
      uint32_t ahead = b->items[i + 2];
      __builtin_prefetch(&b->lists[ahead >> BIN_LOCAL_BITS].boxes[ahead & ((1u << BIN_LOCAL_BITS) - 1)]);
    }
    uint32_t item = b->items[i];
    const SetupList *list = &b->lists[item >> BIN_LOCAL_BITS];
    const TileBox *box = &list->boxes[item & ((1u << BIN_LOCAL_BITS) - 1)];
    float zmin = box->zmin;
    if (zmin >= far) continue;
    if (box->lazy) {   /* set up here, the same triangle emit_chunk would have made */
      const LazyTri *lz = &list->lazy[box->slot];
      int x0 = lz->x0 > rt->x0 ? lz->x0 : rt->x0, x1 = lz->x1 < rt->x1 ? lz->x1 : rt->x1;
      int y0 = lz->y0 > rt->y0 ? lz->y0 : rt->y0, y1 = lz->y1 < rt->y1 ? lz->y1 : rt->y1;
      if (x0 >= x1 || y0 >= y1 || zmin >= rect_far(rt, x0, y0, x1, y1)) continue;
      RastTri own;
      const int *v = b->f->objects[list->object].mesh->tri[lz->face];
      const RastVert *rv = b->verts[list->object];
      const RastVert *tv[3] = {&rv[v[0]], &rv[v[1]], &rv[v[2]]};
      rast_setup(&own, tv, list->object, lz->face, b->gw, b->gh);
      rast_triangle(&own, rt);
      continue;
    }
    const RastTri *t = &list->tris.tris[box->slot];
    if (boxes) {
      int x0 = t->x0 > rt->x0 ? t->x0 : rt->x0, x1 = t->x1 < rt->x1 ? t->x1 : rt->x1;
      int y0 = t->y0 > rt->y0 ? t->y0 : rt->y0, y1 = t->y1 < rt->y1 ? t->y1 : rt->y1;
      if (x0 >= x1 || y0 >= y1 || zmin >= rect_far(rt, x0, y0, x1, y1)) continue;
    }
    rast_triangle(t, rt);
  }
}

/* Hand job->rows every band (a tile row of the run) from the first not yet
** handed over that is wholly shaded (band_left 0: the last decrement of
** each came after its pixels were written). The caller holds band_lock or
** is alone. */
static void hand_bands(TileJob *job) {
  int nbands = (job->y1 - 1) / RENDER_TILE - job->ty0 + 1;
  for (; job->next_band < nbands && atomic_load(&job->band_left[job->next_band]) == 0; job->next_band++) {
    int y0 = (job->ty0 + job->next_band) * RENDER_TILE, y1 = y0 + RENDER_TILE;
    y0 = y0 > job->y0 ? y0 : job->y0;
    y1 = y1 < job->y1 ? y1 : job->y1;
    const Image *img = job->out;   /* the band's rows of out */
    Image band = {img->width, y1 - y0, img->channels, NULL,
                  img->data8 + (size_t)(y0 - job->oy) * img->width * img->channels};
    job->rows->rows(job->rows->ctx, &band, y0 - job->oy, y1 - job->oy);
  }
}

/* A tile of the run's band `band` is shaded. When that completes the
** band, hand the finished bands over, unless another worker is already
** doing so: it then goes back to tiles, and the band is taken by the busy
** worker's loop, the next band finished, or run_workers after the pass. */
static void tile_done(Worker *w, int band) {
  TileJob *job = w->job;
  if (atomic_fetch_sub(&job->band_left[band], 1) != 1) return;
  if (pthread_mutex_trylock(&job->band_lock) != 0) return;
  double t0 = stats_now();
  hand_bands(job);
  pthread_mutex_unlock(&job->band_lock);
  w->write_s += stats_now() - t0;
}

/* Count a shaded tile for the progress report (the worker that brings the
** count to a new value reports it; reports may arrive out of order by a
** tile or two, never at once). */
static void tile_progress(TileJob *job) {
  if (!job->progress) return;
  int done = atomic_fetch_add(&job->done, 1) + 1;
  job->progress->tiles(job->progress->ctx, done, job->progress_total);
}

static void *tile_worker(void *arg) {
  Worker *w = arg;
  TileJob *job = w->job;
  const Bins *b = job->bins;
  int ncols = b->tx1 - b->tx0;
  for (;;) {
    int k = atomic_fetch_add(&job->next, 1);
    if (k >= job->ntiles) break;
    double t0 = stats_now();
    int band = k / ncols, tx = b->tx0 + k % ncols, ty = job->ty0 + band, bin = ty * b->tiles_x + tx;
    /* a tile no triangle touches, one sample a pixel, no G-buffer kept:
    ** the background, without clearing planes to read them back */
    int empty = b->start[bin] == b->start[bin + 1] && job->f->samples == 1 && !job->full && !job->sink;
    Tile tl = tile_target(w, tx, ty, !empty);
    RastTarget *rt = &tl.rt;
    int first_back = b->start[bin] + b->nfront[bin];
    raster_items(b, b->start[bin], first_back, INFINITY, 0, rt);
    if (first_back < b->start[bin + 1])   /* behind all the front faces drawn: skipped */
      raster_items(b, first_back, b->start[bin + 1], tile_far(rt), 1, rt);
    if (job->sink) {   /* the tile's own samples, not its apron */
      RastTarget own = *rt;
      own.x0 = tl.x0, own.y0 = tl.y0, own.x1 = tl.x1, own.y1 = tl.y1;
      job->sink->tile(job->sink->ctx, &own);
    }
    double t1 = stats_now();
    if (!job->out) {   /* the G-buffer alone: nothing to shade */
      w->raster_s += t1 - t0;
      tile_progress(job);
      continue;
    }
    if (b->apron && job->full) copy_tile(job->full, job->f, &tl);
    if (b->apron && !empty) {
      shade_tile_aa(job, &tl, w);
    } else {   /* the tile's own samples (an empty tile's apron is its neighbours' to write) */
      RastTarget own = *rt;
      own.x0 = tl.x0, own.y0 = tl.y0, own.x1 = tl.x1, own.y1 = tl.y1;
      shade_tile(job, &own, empty, w->rows, &w->row, w->prow);
    }
    w->raster_s += t1 - t0;
    w->shade_s += stats_now() - t1;
    if (job->rows) tile_done(w, band);
    tile_progress(job);
  }
  return NULL;
}

static void run_workers(TileJob *job, int nthreads) {
  Worker *ws = xcalloc((size_t)nthreads, sizeof *ws);
  pthread_t *tid = xcalloc((size_t)nthreads, sizeof *tid);
  int apron = job->bins->apron;
  size_t side = (size_t)job->bins->side, wide = side + 2 * (size_t)apron, n = wide * wide;
  for (int i = 0; i < nthreads; i++) {
    ws[i].job = job;
    if (!job->full || apron) {
      ws[i].depth = xmalloc(n * sizeof *ws[i].depth);
      ws[i].object = xmalloc(n * sizeof *ws[i].object);
      ws[i].face = xmalloc(n * sizeof *ws[i].face);
      ws[i].bary = xmalloc(n * sizeof *ws[i].bary);
    }
    shade_row_alloc(&ws[i].row, job->f, (int)wide);
    if (job->f->samples > 1)
      ws[i].rows = xmalloc((size_t)job->f->samples * side * 4 * sizeof *ws[i].rows);
    ws[i].prow = xmalloc(side * 4 * sizeof *ws[i].prow);
    if (apron) {
      ws[i].tcol = xmalloc(n * 4 * sizeof *ws[i].tcol);
      ws[i].tkey = xmalloc(n * sizeof *ws[i].tkey);
      ws[i].memo = xmalloc(n * SHADE_STEP_TERMS * sizeof *ws[i].memo);
      ws[i].seen = xcalloc(n * SHADE_STEP_TERMS, sizeof *ws[i].seen);   /* stamps start at 1 */
      ws[i].blends = xmalloc(4 * n * sizeof *ws[i].blends);
      ws[i].scratch.sum = xcalloc(n, sizeof *ws[i].scratch.sum);
      ws[i].scratch.acc = xcalloc(4 * n, sizeof *ws[i].scratch.acc);
      ws[i].scratch.touched = xmalloc(n * sizeof *ws[i].scratch.touched);
    }
  }
  for (int i = 1; i < nthreads; i++)
    if (pthread_create(&tid[i], NULL, tile_worker, &ws[i]) != 0)
      sumi_fatal("cannot start render thread %d", i);
  tile_worker(&ws[0]);
  double raster = ws[0].raster_s, shade = ws[0].shade_s, write = ws[0].write_s;
  for (int i = 1; i < nthreads; i++) {
    pthread_join(tid[i], NULL);
    raster += ws[i].raster_s;
    shade += ws[i].shade_s;
    write += ws[i].write_s;
  }
  if (job->rows) {   /* bands a busy worker left */
    double t0 = stats_now();
    hand_bands(job);
    job->write_s = write + stats_now() - t0;
  }
  stats_record_cpu("raster", raster);
  stats_record_cpu("shade", shade);
  for (int i = 0; i < nthreads; i++) {
    free(ws[i].depth);
    free(ws[i].object);
    free(ws[i].face);
    free(ws[i].bary);
    free(ws[i].rows);
    free(ws[i].prow);
    free(ws[i].tcol);
    free(ws[i].tkey);
    free(ws[i].memo);
    free(ws[i].seen);
    free(ws[i].blends);
    free(ws[i].scratch.sum);
    free(ws[i].scratch.acc);
    free(ws[i].scratch.touched);
    shade_row_free(&ws[i].row);
  }
  free(ws);
  free(tid);
}

/* The tile pass of a frame's window: its triangles set up and binned once,
** then shaded a run of rows at a time. */
struct RenderPass {
  const RenderFrame *f;
  Bins bins;
  int nthreads;
  const RenderProgress *progress;
  const RenderTileSink *sink;
  int done, total;             /* with progress: tiles shaded by earlier runs; all of them */
};

/* The pass of f with antialiasing's apron (antialias: f->antialias), or
** none (0: a pass drawing the G-buffer alone, whose samples do not depend
** on the tiles that draw them). */
static RenderPass *pass_begin(const RenderFrame *f, const RenderOptions *o, int antialias) {
  int N = f->samples, gw = f->width * N, gh = f->height * N;
  double t0 = stats_now();
  RenderPass *p = xcalloc(1, sizeof *p);
  p->f = f;
  p->nthreads = render_thread_count(o);
  p->progress = o->progress;
  p->sink = o->tiles;
  Bins *b = &p->bins;
  b->side = RENDER_TILE * N;
  b->apron = antialias;
  setup_triangles(f, gw, gh, p->nthreads, b);
  b->tiles_x = (gw + b->side - 1) / b->side;
  b->tiles_y = (gh + b->side - 1) / b->side;
  b->tx0 = f->win.x0 / RENDER_TILE;
  b->ty0 = f->win.y0 / RENDER_TILE;
  b->tx1 = (f->win.x1 + RENDER_TILE - 1) / RENDER_TILE;
  b->ty1 = (f->win.y1 + RENDER_TILE - 1) / RENDER_TILE;
  bin_triangles(b, p->nthreads);
  p->total = (b->tx1 - b->tx0) * (b->ty1 - b->ty0);
  long long nset = 0;
  for (int l = 0; l < b->nlists; l++) nset += b->lists[l].n;
  stats_record("setup", stats_now() - t0);
  stats_record_count("setup", "raster triangles", nset);
  return p;
}

RenderPass *render_pass_begin(const RenderFrame *f, const RenderOptions *o) {
  return pass_begin(f, o, f->antialias);
}

void render_pass_run(RenderPass *p, int y0, int y1, const RenderRows *rows, Image *out, GBuffer **gbuf_out) {
  const RenderFrame *f = p->f;
  int N = f->samples;
  double t1 = stats_now();
  TileJob job;
  memset(&job, 0, sizeof job);
  job.f = f;
  job.bins = &p->bins;
  job.out = out;
  job.ox = f->win.x0;
  job.oy = y0;
  job.y0 = y0;
  job.y1 = y1;
  job.ty0 = y0 / RENDER_TILE;
  int nbands = (y1 - 1) / RENDER_TILE - job.ty0 + 1, ncols = p->bins.tx1 - p->bins.tx0;
  job.ntiles = nbands * ncols;
  job.progress = p->progress;
  job.progress_total = p->total;
  job.sink = p->sink;
  atomic_init(&job.done, p->done);
  shade_view_init(&job.view, &f->camera, N);
  job.span = xmalloc((size_t)f->nstyles * sizeof *job.span);
  for (int i = 0; i < f->nstyles; i++) {
    job.span[i] = shade_span_model(f->styles[i].kind);
    job.view.want_uv |= shade_reads_uv(f->styles[i].kind);
  }
  atomic_init(&job.next, 0);
  if (rows) {
    job.rows = rows;
    job.band_left = xmalloc((size_t)nbands * sizeof *job.band_left);
    for (int k = 0; k < nbands; k++) atomic_init(&job.band_left[k], ncols);
    pthread_mutex_init(&job.band_lock, NULL);
  }
  if (gbuf_out) {   /* the window's samples, seen by the frame's camera at sample resolution */
    job.full = gbuf_create(f->win.x1 - f->win.x0, f->win.y1 - f->win.y0, N);
    job.full->camera = camera_scaled(&f->camera, f->width * N, f->height * N);
  }
  if (p->bins.apron) aa_frame_init(&job.aa, f, p->bins.verts, p->bins.apron, p->nthreads);
  run_workers(&job, p->nthreads < job.ntiles ? p->nthreads : job.ntiles);
  p->done += job.ntiles;
  stats_record("raster+shade", stats_now() - t1);
  if (gbuf_out) *gbuf_out = job.full;
  if (rows) {
    stats_record_cpu("write", job.write_s);   /* the file's encoding, inside the pass */
    free(job.band_left);
    pthread_mutex_destroy(&job.band_lock);
  }
  free(job.span);
  if (p->bins.apron) aa_frame_free(&job.aa);
}

void render_pass_end(RenderPass *p) {
  if (!p) return;
  bins_free(&p->bins, p->f->nobjects);
  free(p);
}

void render_frame(const RenderFrame *f, const RenderOptions *o, const RenderRows *rows, Image *out,
                  GBuffer **gbuf_out) {
  RenderPass *p = pass_begin(f, o, out ? f->antialias : 0);
  render_pass_run(p, f->win.y0, f->win.y1, rows, out, gbuf_out);
  render_pass_end(p);
}

/* ---- origami sheets (Mitani's method, render/origami.h) ------------------------ */

/* Draw every origami block at sample resolution, depth-tested against the
** meshes in g, box-filter it to output pixels and composite it over out.
** Origami pixels get object id f->nobjects and their face ids in g (the
** FOLD file's faces_vertices indices for an imported file). Returns 0 after
** a diagnostic. */
static int composite_origami(const Scene *s, const RenderFrame *f, Image *out, GBuffer *g) {
  int N = f->samples, ww = f->win.x1 - f->win.x0, wh = f->win.y1 - f->win.y0, gw = ww * N, gh = wh * N;
  size_t n = (size_t)gw * gh;
  OrigamiTarget t;
  memset(&t, 0, sizeof t);
  t.width = gw;   /* the window's samples of the frame's */
  t.height = gh;
  t.x0 = f->win.x0 * N;
  t.y0 = f->win.y0 * N;
  t.full_width = f->width * N;
  t.full_height = f->height * N;
  t.rgba = xcalloc(n * 4, sizeof *t.rgba);
  t.face_id = xmalloc(n * sizeof *t.face_id);
  for (size_t i = 0; i < n; i++) t.face_id[i] = GBUF_NO_ID;
  t.depth = g->depth;
  t.pixel_scale = N;
  Camera cam = camera_scaled(&f->camera, t.full_width, t.full_height);
  int ok = origami_draw_scene(s, &cam.world_to_clip, &t);
  for (size_t i = 0; i < n; i++)
    if (t.face_id[i] != GBUF_NO_ID) { g->object[i] = f->nobjects; g->face[i] = t.face_id[i]; }
  int ch = out->channels;
  float inv = 1.0f / (float)(N * N);
  for (int y = 0; y < wh; y++)
    for (int x = 0; x < ww; x++) {
      float p[3] = {0, 0, 0}, a = 0;   /* premultiplied average over the N x N samples */
      for (int sy = 0; sy < N; sy++)
        for (int sx = 0; sx < N; sx++) {
          const float *q = t.rgba + ((size_t)(y * N + sy) * gw + (size_t)(x * N + sx)) * 4;
          p[0] += q[0] * q[3]; p[1] += q[1] * q[3]; p[2] += q[2] * q[3];
          a += q[3];
        }
      a *= inv;
      if (a <= 0) continue;
      float *o = out->data + ((size_t)y * ww + x) * ch;
      float under = ch == 4 ? o[3] : 1, alpha = a + under * (1 - a);
      for (int k = 0; k < 3; k++) o[k] = (p[k] * inv + o[k] * under * (1 - a)) / alpha;
      if (ch == 4) o[3] = alpha;
    }
  free(t.rgba);
  free(t.face_id);
  return ok;
}

/* ---- entry points ------------------------------------------------------------ */

int render_stages(const Scene *s, const RenderOptions *o, RenderFrame *f, int canvas, Image **out,
                  GBuffer **gbuf_out) {
  /* RGB over an opaque background (smaller, and PNG encodes it faster);
  ** 8-bit when it goes to an 8-bit file, encoded by the tile workers as
  ** they finish each row, unless origami sheets or the canvas (both in
  ** float) come over it */
  int nc = f->background.a >= 1 ? 3 : 4, ww = f->win.x1 - f->win.x0, wh = f->win.y1 - f->win.y0;
  double t0 = stats_now();
  if (o->out8 && s->norigami == 0 && !canvas) {
    /* the tile pass writes every byte: no clearing, and each page is first
    ** touched by the worker filling it (clearing and faulting the pages in
    ** here cost ~3 ms at 1080p, alone) */
    *out = image_create8_unset(ww, wh, nc);
  } else if (canvas && s->norigami == 0) {
    *out = image_create_unset(ww, wh, nc);   /* every value written, as above */
  } else {
    *out = image_create(ww, wh, nc);
    mem_advise_huge((*out)->data, (size_t)ww * wh * nc * sizeof(float));
  }
  stats_record("setup", stats_now() - t0);   /* the frame's buffer is set up with it */
  /* an 8-bit frame nothing is drawn over goes to its file while the pass runs */
  const RenderRows *rows = o->rows && (*out)->data8 && !canvas && !line_frame_draws(f) ? o->rows : NULL;
  if (rows && !rows->begin(rows->ctx, *out)) rows = NULL;
  /* origami composes with meshes through the sample depths, and the canvas
  ** reads the ink objects' samples: both need the G-buffer */
  GBuffer *gbuf = NULL;
  /* a canvas over ink alone reads the pass's G-buffer, never its image;
  ** without origami (which writes into the G-buffer) it takes the ink's
  ** samples tile by tile as they are drawn, and no G-buffer is kept */
  Image *shaded = canvas && !canvas_reads_layer(s, f) ? NULL : *out;
  Canvas *cv = NULL;
  int ok = !(canvas && s->norigami == 0 && !gbuf_out) || canvas_begin(s, f, &cv);
  RenderOptions ro = *o;
  ro.tiles = cv ? canvas_sink(cv) : NULL;
  if (ok) render_frame(f, &ro, rows, shaded, gbuf_out || s->norigami > 0 || (canvas && !cv) ? &gbuf : NULL);
  /* A refinement's peak (OpenSubdiv's tables) left the heap mostly free
  ** but cut up, and the tile pass's lists are freed now: the line stages'
  ** big buffers fit in none of the pieces and would come on top (Wuson L4:
  ** +50 MB of peak RSS). A frame taking its meshes from the cache keeps
  ** its heap for the next frame. */
  if (f->refined) mem_heap_release();
  if (gbuf_out) *gbuf_out = gbuf;
  if (ok && s->norigami > 0) {
    double t1 = stats_now();
    ok = composite_origami(s, f, *out, gbuf);
    stats_record("origami", stats_now() - t1);
  }
  if (ok && cv) ok = canvas_finish(cv, out, o->out8);
  else if (ok && canvas) ok = canvas_paint(s, f, gbuf, out, o->out8);
  if (!gbuf_out) gbuf_destroy(gbuf);
  /* lines (src/render/lines.h): strokes composited over the shaded image */
  if (!ok || !line_render_frame(f, render_thread_count(o), o->strokes ? NULL : *out, o->strokes, NULL)) {
    if (gbuf_out && *gbuf_out) { gbuf_destroy(*gbuf_out); *gbuf_out = NULL; }
    image_destroy(*out);
    *out = NULL;
    return 0;
  }
  if (gbuf_out) render_gbuffer_attributes(*gbuf_out, f);
  return 1;
}

int render_scene(const Scene *s, const RenderOptions *o, Image **out, GBuffer **gbuf_out) {
  RenderFrame f;
  *out = NULL;
  if (gbuf_out) *gbuf_out = NULL;
  if (!render_prepare(s, o, &f)) {
    render_frame_free(&f);
    return 1;
  }
  /* a sheet or ink objects: the tile pass draws over nothing (a
  ** transparent background) and the canvas (canvas.h) paints the paper and
  ** the ink under it afterwards, from the G-buffer */
  int canvas = canvas_wanted(s, &f);
  if (canvas) f.background = (Color){0, 0, 0, 0};
  int ok = render_window_empty(o->window) ? render_stages(s, o, &f, canvas, out, gbuf_out)
                                           : tile_render(s, o, &f, canvas, out, gbuf_out);
  render_frame_free(&f);
  return ok ? 0 : 1;
}

void render_gbuffer_attributes(GBuffer *g, const RenderFrame *f) {
  gbuf_alloc_attributes(g);
  size_t n = (size_t)g->width * g->height;
  for (size_t i = 0; i < n; i++) {
    int obj = g->object[i];
    if (obj < 0 || obj >= f->nobjects) {   /* background, or an origami sheet */
      memset(g->normal[i], 0, sizeof g->normal[i]);
      memset(g->uv[i], 0, sizeof g->uv[i]);
      memset(g->position[i], 0, sizeof g->position[i]);
      continue;
    }
    const RenderObject *o = &f->objects[obj];
    const int *t = o->mesh->tri[g->face[i]];
    float b1 = g->bary[i][0], b2 = g->bary[i][1], b0 = 1 - b1 - b2;
    float nl = 0;
    for (int k = 0; k < 3; k++) {
      g->position[i][k] = b0 * o->wpos[t[0]][k] + b1 * o->wpos[t[1]][k] + b2 * o->wpos[t[2]][k];
      g->normal[i][k] = o->wcnrm ? b0 * o->wcnrm[g->face[i]][0][k] + b1 * o->wcnrm[g->face[i]][1][k] +
                                       b2 * o->wcnrm[g->face[i]][2][k]
                                 : b0 * o->wnrm[t[0]][k] + b1 * o->wnrm[t[1]][k] + b2 * o->wnrm[t[2]][k];
      nl += g->normal[i][k] * g->normal[i][k];
    }
    nl = nl > 0 ? 1 / sqrtf(nl) : 0;
    if (o->backfacing[g->face[i]]) nl = -nl;
    for (int k = 0; k < 3; k++) g->normal[i][k] *= nl;
    const Vec2 *uv = o->mesh->uv;
    g->uv[i][0] = uv ? (float)(b0 * uv[t[0]].x + b1 * uv[t[1]].x + b2 * uv[t[2]].x) : 0;
    g->uv[i][1] = uv ? (float)(b0 * uv[t[0]].y + b1 * uv[t[1]].y + b2 * uv[t[2]].y) : 0;
  }
}

/* ---- AOVs ----------------------------------------------------------------------- */

/* output without its extension, plus "." name "." ext, into buf. */
static void aov_path(char *buf, size_t n, const char *output, const char *name, const char *ext) {
  const char *dot = strrchr(output, '.'), *slash = strrchr(output, '/');
  int stem = dot && (!slash || dot > slash) ? (int)(dot - output) : (int)strlen(output);
  snprintf(buf, n, "%.*s.%s.%s", stem, output, name, ext);
}

/* Write one pass; 0 with err set on failure or an unknown name. */
static int write_aov(GBuffer *g, const char *output, const char *name, char *err, size_t errlen) {
  static const char *const depth_ch[] = {"Z"}, *const n_ch[] = {"N.x", "N.y", "N.z"},
                           *const p_ch[] = {"P.x", "P.y", "P.z"}, *const uv_ch[] = {"u", "v"};
  char path[4096];
  int w = g->width, h = g->height;
  if (!strcmp(name, "object") || !strcmp(name, "face")) {
    aov_path(path, sizeof path, output, name, "tif");
    return image_write_ids_tiff(path, w, h, name[0] == 'o' ? g->object : g->face, err, errlen);
  }
  aov_path(path, sizeof path, output, name, "exr");
  if (!strcmp(name, "depth")) return image_write_aov_exr(path, w, h, 1, (const char **)depth_ch, g->depth, err, errlen);
  if (!strcmp(name, "normal"))
    return image_write_aov_exr(path, w, h, 3, (const char **)n_ch, &g->normal[0][0], err, errlen);
  if (!strcmp(name, "position"))
    return image_write_aov_exr(path, w, h, 3, (const char **)p_ch, &g->position[0][0], err, errlen);
  if (!strcmp(name, "uv")) return image_write_aov_exr(path, w, h, 2, (const char **)uv_ch, &g->uv[0][0], err, errlen);
  snprintf(err, errlen, "--aov: unknown pass `%s` (depth, normal, position, uv, object, face, all)", name);
  return 0;
}

static const char *const aov_names[] = {"depth", "normal", "position", "uv", "object", "face"};

int render_aov_list_ok(const char *list, char *err, size_t errlen) {
  char name[32];
  for (const char *p = list;; p++) {
    size_t n = strcspn(p, ",");
    snprintf(name, sizeof name, "%.*s", (int)(n < sizeof name ? n : sizeof name - 1), p);
    int known = !strcmp(name, "all");
    for (int i = 0; i < 6 && !known; i++) known = !strcmp(name, aov_names[i]);
    if (!known || n >= sizeof name) {
      snprintf(err, errlen, "--aov: unknown pass `%s` (depth, normal, position, uv, object, face, all)", name);
      return 0;
    }
    p += n;
    if (!*p) return 1;
  }
}

int render_write_aovs(GBuffer *g, const char *output, const char *list, char *err, size_t errlen) {
  const char *const *all = aov_names;
  char name[32];
  for (const char *p = list; *p;) {
    size_t n = strcspn(p, ",");
    snprintf(name, sizeof name, "%.*s", (int)(n < sizeof name ? n : sizeof name - 1), p);
    if (!strcmp(name, "all")) {
      for (int i = 0; i < 6; i++)
        if (!write_aov(g, output, all[i], err, errlen)) return 0;
    } else if (!write_aov(g, output, name, err, errlen)) {
      return 0;
    }
    p += n + (p[n] == ',');
  }
  return 1;
}
