/*
** The line stage's entry point: runs the stages in order, times them, and
** scales the polylines from the reference image to the output.
*/
#include "lines.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../base/mem.h"
#include "../geom/origami.h"
#include "../lang/diag.h"
#include "edgeref.h"
#include "link.h"
#include "silhouette.h"
#include "stats.h"
#include "trace.h"

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int draws_lines(const LineObject *o) {
  return o->lines && o->lines->present && o->lines->kinds && o->mesh && o->mesh->ntris > 0;
}

void line_ref_size(const LineObject *objs, int nobj, const Camera *cam, int *w, int *h) {
  double scale = 0;
  for (int i = 0; i < nobj; i++)
    if (draws_lines(&objs[i]) && objs[i].lines->ref_scale > scale) scale = objs[i].lines->ref_scale;
  if (!(scale > 0)) scale = 1;
  *w = (int)fmax(1, floor(cam->width * scale + 0.5));
  *h = (int)fmax(1, floor(cam->height * scale + 0.5));
}

/* A copy of objs for one front end: the lines of the objects the other
** one draws are taken away (they still occlude). The caller frees it. */
static LineObject *objects_for(const LineObject *objs, int nobj, int endpoints) {
  LineObject *o = xmalloc(((size_t)nobj + 1) * sizeof *o);
  memcpy(o, objs, (size_t)nobj * sizeof *o);
  for (int i = 0; i < nobj; i++)
    if (draws_lines(&o[i]) && scene_lines_endpoints(o[i].lines) != endpoints) o[i].lines = NULL;
  return o;
}

/* The edges of objs and their visibility (edgeref.h), the first two
** stages of either front end; 0 with a reason in err when the walks are
** over LINE_MAX_STEPS (nothing left to free then). */
static int tested_edges(LineEdges *edges, LineRef *ref, const LineObject *objs, int nobj,
                        const Camera *ref_cam, int threads, LineStats *st, char *err, size_t errlen) {
  double t0 = now_seconds();
  line_edges_build(edges, objs, nobj, ref_cam, threads);
  double t1 = now_seconds();
  if (!line_ref_build(ref, edges, objs, ref_cam->width, ref_cam->height, threads)) {
    snprintf(err, errlen, "the important edges come to %zu reference pixels, over the limit of %lld "
             "(LINE_MAX_STEPS); lower ref_scale, or draw fewer kinds of edges", ref->step0[ref->nids],
             (long long)LINE_MAX_STEPS);
    line_ref_free(ref);
    line_edges_free(edges);
    return 0;
  }
  st->important += edges->n;
  st->t_edges += t1 - t0;
  st->t_ref += now_seconds() - t1;
  return 1;
}

/* The reference-image front end (001): tested edges, traced, linked
** through the mesh graph, into *polys. */
static int reference_polys(LinePolys *polys, const LineObject *objs, int nobj, const Camera *ref_cam,
                           double px_scale, int threads, LineStats *st, char *err, size_t errlen) {
  LineEdges edges;
  LineRef ref;
  if (!tested_edges(&edges, &ref, objs, nobj, ref_cam, threads, st, err, errlen)) return 0;
  double t2 = now_seconds();
  LineTrace tr;
  line_trace_build(&tr, &ref, &edges, px_scale, threads);
  double t3 = now_seconds();
  line_link_build(polys, &ref, &tr, &edges);
  double t4 = now_seconds();
  st->visible = tr.nvisible;
  st->segments = tr.nseg;
  st->t_trace = t3 - t2; st->t_link = t4 - t3;
  line_trace_free(&tr);
  line_ref_free(&ref);
  line_edges_free(&edges);
  return 1;
}

/* The endpoint front end (003): tested edges, culled by their ends
** (bisected where one is hidden), linked within 2 pixels, into *polys;
** px_scale takes output pixels to reference pixels. */
static int endpoint_polys(LinePolys *polys, const LineObject *objs, int nobj, const Camera *ref_cam,
                          double px_scale, int threads, LineStats *st, char *err, size_t errlen) {
  LineEdges edges;
  LineRef ref;
  if (!tested_edges(&edges, &ref, objs, nobj, ref_cam, threads, st, err, errlen)) return 0;
  double t2 = now_seconds();
  SilPieces pieces;
  sil_cull(&pieces, &ref, &edges);
  double t3 = now_seconds();
  sil_link(polys, &pieces, &edges, px_scale);
  double t4 = now_seconds();
  st->tested = pieces.tested; st->whole = pieces.whole; st->cut = pieces.cut; st->dropped = pieces.dropped;
  st->t_cull = t3 - t2; st->t_chain = t4 - t3;
  sil_pieces_free(&pieces);
  line_ref_free(&ref);
  line_edges_free(&edges);
  return 1;
}

/* a's and b's polylines in one list, objects in order (each list is in
** object order, and an object is in one of them only); frees a and b. */
static void merge_polys(LinePolys *out, LinePolys *a, LinePolys *b) {
  memset(out, 0, sizeof *out);
  for (int i = 0, j = 0; i < a->n || j < b->n;) {
    int take_a = j >= b->n || (i < a->n && a->obj[i] <= b->obj[j]);
    LinePolys *p = take_a ? a : b;
    int k = take_a ? i++ : j++;
    line_polys_append(out, p->pts + 2 * p->start[k], p->start[k + 1] - p->start[k], p->obj[k]);
  }
  line_polys_free(a);
  line_polys_free(b);
}

/* The polylines of objs from the front end each object's lines ask for
** (only the reference image's stages when no object asks for the
** endpoint test, as before it existed); 0 with a reason in err. */
static int front_ends(LinePolys *polys, const LineObject *objs, int nobj, const Camera *ref_cam,
                      double px_scale, int threads, int nend, LineStats *st, char *err, size_t errlen) {
  memset(polys, 0, sizeof *polys);
  if (nend == 0) return reference_polys(polys, objs, nobj, ref_cam, px_scale, threads, st, err, errlen);
  LinePolys ref_polys, end_polys;
  memset(&ref_polys, 0, sizeof ref_polys);
  memset(&end_polys, 0, sizeof end_polys);
  int ok = 1;
  if (st->objects > nend) {
    LineObject *o = objects_for(objs, nobj, 0);
    ok = reference_polys(&ref_polys, o, nobj, ref_cam, px_scale, threads, st, err, errlen);
    free(o);
  }
  if (ok) {
    LineObject *o = objects_for(objs, nobj, 1);
    ok = endpoint_polys(&end_polys, o, nobj, ref_cam, px_scale, threads, st, err, errlen);
    free(o);
  }
  merge_polys(polys, &ref_polys, &end_polys);
  return ok;
}

/* Record the stages that ran in the --stats table. */
static void record_stats(const LineStats *st, int reference, int endpoints) {
  stats_record("lines edges", st->t_edges);
  stats_record_count("lines edges", "important", st->important);
  stats_record("lines reference", st->t_ref);
  if (reference) {
    stats_record_count("lines reference", "visible", st->visible);
    stats_record("lines trace", st->t_trace);
    stats_record_count("lines trace", "segments", st->segments);
    stats_record("lines link", st->t_link);
    stats_record_count("lines link", "polylines", st->polylines);
  }
  if (endpoints) {
    stats_record("lines cull", st->t_cull);
    stats_record_count("lines cull", "cut", st->cut);
    stats_record("lines chain", st->t_chain);
    stats_record_count("lines chain", "polylines", st->polylines);
  }
  stats_record("lines strokes", st->t_build);
  stats_record_count("lines strokes", "strokes", st->strokes);
  stats_record("lines draw", st->t_draw);
  if (st->brush_steps) stats_record_count("lines draw", "brush steps", st->brush_steps);
}

int line_render(const LineObject *objs, int nobj, const Camera *cam, Image *target, int threads,
                LineStats *stats, StrokeList **strokes_out, char *err, size_t errlen) {
  LineStats st;
  memset(&st, 0, sizeof st);
  if (strokes_out) *strokes_out = NULL;
  if (threads < 1) threads = 1;
  int nend = 0;
  for (int i = 0; i < nobj; i++) {
    st.objects += draws_lines(&objs[i]);
    nend += draws_lines(&objs[i]) && scene_lines_endpoints(objs[i].lines);
  }
  if (st.objects == 0 || cam->width < 1 || cam->height < 1) {   /* nothing to draw: no work */
    if (stats) *stats = st;
    return 1;
  }
  int rw, rh;
  line_ref_size(objs, nobj, cam, &rw, &rh);
  if ((long long)rw * rh > LINE_MAX_REF_PIXELS) {
    snprintf(err, errlen, "reference image %dx%d is over the limit of %lld pixels (LINE_MAX_REF_PIXELS); "
             "lower ref_scale", rw, rh, (long long)LINE_MAX_REF_PIXELS);
    return 0;
  }
  st.ref_width = rw;
  st.ref_height = rh;
  Camera ref_cam = *cam;   /* the same projection; only the pixel grid changes */
  ref_cam.width = rw;
  ref_cam.height = rh;

  LinePolys polys;
  if (!front_ends(&polys, objs, nobj, &ref_cam, (double)rw / cam->width, threads, nend, &st, err, errlen)) {
    line_polys_free(&polys);
    return 0;
  }
  double t4 = now_seconds();
  StrokeList *sl = NULL;
  int ok = stroke_build(&sl, &polys, objs, (double)cam->width / rw, (double)cam->height / rh, err,
                        errlen);
  double t5 = now_seconds();
  if (ok && target) stroke_render(sl, target, threads);
  double t6 = now_seconds();

  st.polylines = polys.n;
  st.strokes = sl ? sl->n : 0;
  for (int i = 0; i < st.strokes; i++)
    if (sl->s[i].brush) st.brush_steps += sl->s[i].brush->nsteps;
  st.t_build = t5 - t4; st.t_draw = t6 - t5;
  if (stats) *stats = st;
  record_stats(&st, st.objects > nend, nend > 0);
  line_polys_free(&polys);
  if (ok && strokes_out) *strokes_out = sl;
  else stroke_list_free(sl);
  return ok;
}

void line_stats_print(FILE *f, const LineStats *s) {
  fprintf(f, "lines: %d objects, reference %dx%d\n", s->objects, s->ref_width, s->ref_height);
  fprintf(f, "lines: edges %d important, %d visible; %d segments, %d polylines, %d strokes\n",
          s->important, s->visible, s->segments, s->polylines, s->strokes);
  if (s->tested)
    fprintf(f, "lines: endpoint test: %d edges, %d kept whole, %d bisected, %d hidden; cull %.2f ms, "
            "chain %.2f ms\n", s->tested, s->whole, s->cut, s->dropped, s->t_cull * 1e3, s->t_chain * 1e3);
  fprintf(f, "lines: time edges %.2f ms, reference %.2f ms, trace %.2f ms, link %.2f ms, "
          "strokes %.2f ms, draw %.2f ms, total %.2f ms\n",
          s->t_edges * 1e3, s->t_ref * 1e3, s->t_trace * 1e3, s->t_link * 1e3, s->t_build * 1e3,
          s->t_draw * 1e3,
          (s->t_edges + s->t_ref + s->t_trace + s->t_link + s->t_build + s->t_draw) * 1e3);
}

int line_frame_objects(const RenderFrame *f, LineObject **out) {
  LineObject *o = xcalloc((size_t)f->nobjects + 1, sizeof *o);
  for (int i = 0; i < f->nobjects; i++) {
    const RenderObject *ro = &f->objects[i];
    o[i].mesh = ro->mesh;
    o[i].object_to_world = ro->object_to_world;
    o[i].lines = ro->style && ro->style->src ? &ro->style->src->lines : NULL;
    o[i].id = i;
    o[i].hidden = ro->cull_back ? ro->backfacing : NULL;
    if (ro->style) o[i].fill = (Color){ro->style->fill[0], ro->style->fill[1], ro->style->fill[2], 1};
  }
  *out = o;
  return f->nobjects;
}

/* lines->texture as a path relative to the folder of the scene file that
** wrote it (as mesh("file") is), into out; the built-in names stay. */
static const char *texture_path(const SceneLines *ls, char *out, size_t n) {
  const char *t = ls->texture;
  if (!t || !strcmp(t, "ink") || !strcmp(t, "solid")) return t;
  return diag_path_beside(ls->loc, t, out, n);
}

int line_frame_draws(const RenderFrame *f) {
  for (int i = 0; i < f->nobjects; i++) {
    const RenderObject *ro = &f->objects[i];
    LineObject o = {.mesh = ro->mesh,
                    .lines = ro->style && ro->style->src ? &ro->style->src->lines : NULL};
    if (draws_lines(&o)) return 1;
  }
  return 0;
}

/* The folded sheets of the scene's origami blocks as occluders (no lines
** of their own: the origami draws its creases), appended to *objs after
** its n entries; their meshes go into *sheets (*nsheets of them; the
** caller destroys them and frees the list). A flat sheet hides what is
** behind it from either side. Returns the new count. */
static int add_sheets(const Scene *s, LineObject **objs, int n, Mesh ***sheets, int *nsheets) {
  if (!s || s->norigami == 0) return n;
  *objs = xrealloc(*objs, ((size_t)n + (size_t)s->norigami + 1) * sizeof **objs);
  *sheets = xcalloc((size_t)s->norigami, sizeof **sheets);
  for (int i = 0; i < s->norigami; i++) {
    OrigamiModel *om = origami_build_folded(&s->origami[i]);   /* rendering built it already */
    if (!om) continue;
    Mesh *m = mesh_create(om->nverts, om->ntris);
    for (int v = 0; v < om->nverts; v++) m->pos[v] = v3(om->folded[v].x, om->folded[v].y, 0);
    memcpy(m->tri, om->tri, (size_t)om->ntris * sizeof *m->tri);
    memcpy(m->tri_face, om->tri_face, (size_t)om->ntris * sizeof *m->tri_face);
    mesh_build_edges(m);
    origami_free(om);
    LineObject *o = &(*objs)[n++];
    memset(o, 0, sizeof *o);
    o->mesh = m;
    o->object_to_world = s->origami[i].transform;
    o->id = s->nobjects + i;
    (*sheets)[(*nsheets)++] = m;
  }
  return n;
}

/* Warn about the objects of f whose lines cannot be drawn as asked: a
** mesh with no faces (nothing to draw), and, for the endpoint method,
** edges with more than two faces (003 ch. 2.2 assumes at most two). */
static void warn_meshes(const RenderFrame *f) {
  for (int i = 0; i < f->nobjects; i++) {
    const RenderObject *ro = &f->objects[i];
    const SceneLines *ls = ro->style && ro->style->src ? &ro->style->src->lines : NULL;
    if (!ls || !ls->present || !ls->kinds || !ro->mesh || !ro->src) continue;
    /* at the geometry (the mesh(...) call), else the object */
    SrcRange at = ro->src->geometry && ro->src->geometry->loc.file >= 0 ? ro->src->geometry->loc : ro->src->loc;
    char name[160];
    if (ro->src->name) snprintf(name, sizeof name, "object `%s`", ro->src->name);
    else snprintf(name, sizeof name, "an object");
    if (ro->mesh->ntris == 0) {
      diag_warning(at, "%s has no faces: its lines are skipped", name);
      continue;
    }
    if (!scene_lines_endpoints(ls)) continue;
    int bad = 0, first = -1;
    for (int e = 0; e < ro->mesh->nedges; e++)
      if (ro->mesh->edges[e].nonmanifold && bad++ == 0) first = e;
    if (bad) {
      const MeshEdge *me = &ro->mesh->edges[first];
      Vec3 a = ro->mesh->pos[me->v[0]], b = ro->mesh->pos[me->v[1]];
      diag_warning(at, "%s has %d edge%s with more than two faces (the first from [%g, %g, %g] "
                   "to [%g, %g, %g]); the silhouette test reads the first two faces of each",
                   name, bad, bad > 1 ? "s" : "", a.x, a.y, a.z, b.x, b.y, b.z);
    }
  }
}

int line_render_frame(const RenderFrame *f, int threads, Image *target, StrokeList **strokes_out,
                      LineStats *stats) {
  warn_meshes(f);
  LineObject *objs;
  int n = line_frame_objects(f, &objs);
  Mesh **sheets = NULL;
  int nsheets = 0;
  if (line_frame_draws(f)) n = add_sheets(f->scene, &objs, n, &sheets, &nsheets);
  SceneLines *ls = xcalloc((size_t)n + 1, sizeof *ls);    /* with resolved texture paths */
  char (*paths)[1024] = xcalloc((size_t)n + 1, sizeof *paths);
  for (int i = 0; i < n; i++)
    if (objs[i].lines) {
      ls[i] = *objs[i].lines;
      ls[i].texture = texture_path(objs[i].lines, paths[i], sizeof paths[i]);
      objs[i].lines = &ls[i];
    }
  char err[1200];
  /* a window of the frame (a tile): the strokes of the whole view, drawn
  ** into the window's pixels */
  int window = target && (f->win.x0 || f->win.y0 || f->win.x1 != f->width || f->win.y1 != f->height);
  StrokeList *sl = NULL;
  int ok = line_render(objs, n, &f->camera, window ? NULL : target, threads, stats,
                       window ? &sl : strokes_out, err, sizeof err);
  if (ok && window) {
    double t0 = now_seconds();
    stroke_render_at(sl, target, f->win.x0, f->win.y0, threads);
    stats_record("lines draw", now_seconds() - t0);
    if (strokes_out) *strokes_out = sl;
    else stroke_list_free(sl);
  }
  if (!ok) {
    SrcRange at = src_none();
    for (int i = 0; i < n; i++)
      if (objs[i].lines && objs[i].lines->present) { at = objs[i].lines->loc; break; }
    diag_error(at, "%s", err);
  }
  for (int i = 0; i < nsheets; i++) mesh_destroy(sheets[i]);
  free(sheets);
  free(objs);
  free(ls);
  free(paths);
  return ok;
}
