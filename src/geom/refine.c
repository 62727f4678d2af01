/*
** The refinement reference: our patches, tessellations and subdivided
** meshes measured against OpenSubdiv's limit surfaces (see refine.h).
*/
#include "refine.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../base/mem.h"
#include "bspline.h"
#include "patch.h"
#include "subdiv.h"
#include "tessellate.h"

/* ---- accumulating deviations ------------------------------------------------ */

static double now_ms(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

typedef struct Acc {
  long n, npx;
  double sum, max, sum_px, max_px;
  const Mat4 *to_world;
  const Camera *cam;
} Acc;

/* One pair: ours against the reference, both in object space. */
static void acc_add(Acc *a, Vec3 ours, Vec3 ref) {
  if (a->to_world) {
    ours = m4_point(*a->to_world, ours);
    ref = m4_point(*a->to_world, ref);
  }
  double d = v3_len(v3_sub(ours, ref));
  a->n++;
  a->sum += d;
  if (d > a->max) a->max = d;
  double x0, y0, z0, x1, y1, z1;
  if (a->cam && camera_to_pixel(a->cam, ours, &x0, &y0, &z0) &&
      camera_to_pixel(a->cam, ref, &x1, &y1, &z1)) {
    double dp = hypot(x1 - x0, y1 - y0);
    a->npx++;
    a->sum_px += dp;
    if (dp > a->max_px) a->max_px = dp;
  }
}

static void acc_finish(const Acc *a, RefineStats *st) {
  st->samples = a->n;
  st->max_units = a->max;
  st->mean_units = a->n ? a->sum / a->n : 0;
  st->max_px = a->max_px;
  st->mean_px = a->npx ? a->sum_px / a->npx : 0;
}

/* ---- patches ------------------------------------------------------------------ */

/* The borders of a net as control point indices: v = 0, v = 1, u = 0, u = 1. */
static const int BORDER[4][4] = {{0, 1, 2, 3}, {12, 13, 14, 15}, {0, 4, 8, 12}, {3, 7, 11, 15}};

static int border_collapsed(const Vec3 cp[16], int k) {
  for (int i = 1; i < 4; i++)
    if (v3_len(v3_sub(cp[BORDER[k][i]], cp[BORDER[k][0]])) != 0) return 0;
  return 1;
}

int refine_patch_degenerate(const ScenePatch *p) {
  Vec3 cp[16];
  bspline_bezier_net(p, cp);
  for (int k = 0; k < 4; k++)
    if (border_collapsed(cp, k)) return 1;
  return 0;
}

static double net_extent(const Vec3 cp[16]) {
  Vec3 lo = cp[0], hi = cp[0];
  for (int i = 1; i < 16; i++) {
    lo = v3(fmin(lo.x, cp[i].x), fmin(lo.y, cp[i].y), fmin(lo.z, cp[i].z));
    hi = v3(fmax(hi.x, cp[i].x), fmax(hi.y, cp[i].y), fmax(hi.z, cp[i].z));
  }
  return v3_len(v3_sub(hi, lo));
}

/* The parameters on patch p nearest to point q: a grid search, then
** Gauss-Newton steps kept inside [0, 1]^2. */
static Vec2 closest_uv(const ScenePatch *p, Vec3 q) {
  enum { G = 32 };
  Vec2 best = {0, 0};
  double bd = INFINITY;
  for (int j = 0; j <= G; j++)
    for (int i = 0; i <= G; i++) {
      double d = v3_len(v3_sub(patch_eval(p, (double)i / G, (double)j / G, NULL, NULL), q));
      if (d < bd) { bd = d; best.x = (double)i / G; best.y = (double)j / G; }
    }
  for (int it = 0; it < 30; it++) {
    Vec3 du, dv, r = v3_sub(patch_eval(p, best.x, best.y, &du, &dv), q);
    double a = v3_dot(du, du), b = v3_dot(du, dv), c = v3_dot(dv, dv);
    double gu = v3_dot(du, r), gv = v3_dot(dv, r), det = a * c - b * b;
    if (!(fabs(det) > 1e-300)) break;
    double su = (c * gu - b * gv) / det, sv = (a * gv - b * gu) / det;
    best.x = fmin(1, fmax(0, best.x - su));
    best.y = fmin(1, fmax(0, best.y - sv));
    if (fabs(su) + fabs(sv) < 1e-15) break;
  }
  return best;
}

/* Parameters of a triangle's corners on its own patch. A welded vertex
** keeps the uv of the patch that made it, so a corner whose uv does not
** give its position is found again on this patch; a corner on a collapsed
** border (a pole) takes the free parameter from the other two corners. */
static void triangle_uv(const Mesh *m, int t, const ScenePatch *p, const Vec3 cp[16], double tol,
                        Vec2 uv[3]) {
  int pole[3] = {-1, -1, -1};
  for (int k = 0; k < 3; k++) {
    int v = m->tri[t][k];
    uv[k] = m->uv[v];
    Vec3 q = m->pos[v];
    for (int b = 0; b < 4; b++)
      if (border_collapsed(cp, b) && v3_len(v3_sub(q, cp[BORDER[b][0]])) <= tol) pole[k] = b;
    if (pole[k] < 0 && v3_len(v3_sub(patch_eval(p, uv[k].x, uv[k].y, NULL, NULL), q)) > tol)
      uv[k] = closest_uv(p, q);
  }
  for (int k = 0; k < 3; k++) {
    if (pole[k] < 0) continue;
    int along_u = pole[k] < 2;   /* rows v = 0 or 1 collapse: u is free */
    double fixed = pole[k] == 0 || pole[k] == 2 ? 0 : 1, free_sum = 0;
    int nfree = 0;
    for (int o = 0; o < 3; o++)
      if (pole[o] < 0) { free_sum += along_u ? uv[o].x : uv[o].y; nfree++; }
    double f = nfree ? free_sum / nfree : 0.5;
    uv[k] = along_u ? (Vec2){f, fixed} : (Vec2){fixed, f};
  }
}

/* Barycentric sample points of a triangle: (i, j, k) / 4 with i + j + k = 4. */
enum { TRI_SAMPLES = 15 };
static void tri_weights(double w[TRI_SAMPLES][3]) {
  int s = 0;
  for (int i = 0; i <= 4; i++)
    for (int j = 0; i + j <= 4; j++, s++) {
      w[s][0] = i / 4.0;
      w[s][1] = j / 4.0;
      w[s][2] = (4 - i - j) / 4.0;
    }
}

static BsplineRef *make_refs(const SceneGeometry *g, double *ms, char *err, size_t errlen) {
  double t0 = now_ms();
  BsplineRef *refs = xcalloc((size_t)(g->npatches > 0 ? g->npatches : 1), sizeof *refs);
  for (int i = 0; i < g->npatches; i++)
    if (!bspline_ref_init(&refs[i], &g->patches[i], err, errlen)) {
      for (int k = 0; k < i; k++) bspline_ref_free(&refs[k]);
      free(refs);
      return NULL;
    }
  *ms += now_ms() - t0;
  return refs;
}

static void free_refs(BsplineRef *refs, int n) {
  for (int i = 0; i < n; i++) bspline_ref_free(&refs[i]);
  free(refs);
}

int refine_patch_mesh(const SceneGeometry *g, const Mesh *m, const Mat4 *object_to_world,
                      const Camera *cam, RefineStats *st, char *err, size_t errlen) {
  memset(st, 0, sizeof *st);
  st->ntris = m->ntris;
  if (!m->uv) { snprintf(err, errlen, "the tessellation carries no patch parameters"); return 0; }
  BsplineRef *refs = make_refs(g, &st->ref_ms, err, errlen);
  if (!refs) return 0;
  Acc a = {0};
  a.to_world = object_to_world;
  a.cam = cam;
  double w[TRI_SAMPLES][3], uv[2 * TRI_SAMPLES];
  Vec3 lim[TRI_SAMPLES];
  tri_weights(w);
  int ok = 1;
  for (int t = 0; t < m->ntris && ok; t++) {
    int f = m->tri_face[t];
    if (f < 0 || f >= g->npatches) continue;
    Vec3 cp[16];
    bspline_bezier_net(&g->patches[f], cp);
    Vec2 c[3];
    triangle_uv(m, t, &g->patches[f], cp, 1e-7 * net_extent(cp), c);
    for (int s = 0; s < TRI_SAMPLES; s++) {
      uv[2 * s] = w[s][0] * c[0].x + w[s][1] * c[1].x + w[s][2] * c[2].x;
      uv[2 * s + 1] = w[s][0] * c[0].y + w[s][1] * c[1].y + w[s][2] * c[2].y;
    }
    double t0 = now_ms();
    ok = bspline_ref_eval(&refs[f], TRI_SAMPLES, uv, lim, NULL, NULL, err, errlen);
    st->ref_ms += now_ms() - t0;
    for (int s = 0; s < TRI_SAMPLES && ok; s++) {
      Vec3 q = v3_add(v3_add(v3_mul(m->pos[m->tri[t][0]], w[s][0]),
                             v3_mul(m->pos[m->tri[t][1]], w[s][1])),
                      v3_mul(m->pos[m->tri[t][2]], w[s][2]));
      acc_add(&a, q, lim[s]);
    }
  }
  free_refs(refs, g->npatches);
  acc_finish(&a, st);
  return ok;
}

int refine_patch_eval(const SceneGeometry *g, int n, const Mat4 *object_to_world,
                      const Camera *cam, RefineStats *st, RefineStats *st_degenerate, char *err,
                      size_t errlen) {
  memset(st, 0, sizeof *st);
  memset(st_degenerate, 0, sizeof *st_degenerate);
  if (n < 1) n = 1;
  int npts = (n + 1) * (n + 1);
  double *uv = xmalloc(sizeof(double) * 2 * (size_t)npts);
  Vec3 *ours = xmalloc(sizeof(Vec3) * (size_t)npts), *ref = xmalloc(sizeof(Vec3) * (size_t)npts);
  for (int j = 0, k = 0; j <= n; j++)
    for (int i = 0; i <= n; i++, k++) {
      uv[2 * k] = (double)i / n;
      uv[2 * k + 1] = (double)j / n;
    }
  Acc a[2] = {{0}, {0}};
  RefineStats *out[2] = {st, st_degenerate};
  int ok = 1;
  for (int p = 0; p < g->npatches && ok; p++) {
    int d = refine_patch_degenerate(&g->patches[p]);
    double t0 = now_ms();
    for (int k = 0; k < npts; k++) ours[k] = patch_eval(&g->patches[p], uv[2 * k], uv[2 * k + 1], NULL, NULL);
    double t1 = now_ms();
    BsplineRef r;
    ok = bspline_ref_init(&r, &g->patches[p], err, errlen);
    if (ok) {
      ok = bspline_ref_eval(&r, npts, uv, ref, NULL, NULL, err, errlen);
      bspline_ref_free(&r);
    }
    out[d]->ms += t1 - t0;
    out[d]->ref_ms += now_ms() - t1;
    a[d].to_world = object_to_world;
    a[d].cam = cam;
    for (int k = 0; k < npts && ok; k++) acc_add(&a[d], ours[k], ref[k]);
  }
  for (int d = 0; d < 2; d++) acc_finish(&a[d], out[d]);
  free(uv);
  free(ours);
  free(ref);
  return ok;
}

/* ---- subdivided meshes ---------------------------------------------------------- */

/* A handle on the refined level itself: its control points, faces and the
** sharpness left at that level have the same limit surface as the base. */
static int level_handle(const SceneGeometry *g, SumiOsdBoundary boundary, const SumiOsdRefined *r,
                        SumiOsdMesh **out, char *err, size_t errlen) {
  SumiOsdTopology t = {0};
  if (!subdiv_scheme_parse(g->subdiv_scheme, &t.scheme)) return 0;
  t.boundary = boundary;
  t.nverts = r->nverts;
  t.nfaces = r->nfaces;
  int *size = xmalloc(sizeof(int) * (size_t)r->nfaces);
  for (int f = 0; f < r->nfaces; f++) size[f] = r->face_start[f + 1] - r->face_start[f];
  int *cv = xmalloc(sizeof(int) * (size_t)(2 * r->nsharp + 1)), nc = 0;
  float *cs = xmalloc(sizeof(float) * (size_t)(r->nsharp + 1));
  for (int e = 0; e < r->nsharp; e++)
    if (r->sharp_now[e] > 0) {
      cv[2 * nc] = r->sharp_verts[2 * e];
      cv[2 * nc + 1] = r->sharp_verts[2 * e + 1];
      cs[nc++] = r->sharp_now[e];
    }
  int *kv = xmalloc(sizeof(int) * (size_t)(r->nverts + 1)), nk = 0;
  float *ks = xmalloc(sizeof(float) * (size_t)(r->nverts + 1));
  for (int v = 0; v < r->nverts; v++)
    if (r->vert_sharpness[v] > 0) { kv[nk] = v; ks[nk++] = r->vert_sharpness[v]; }
  t.face_size = size;
  t.face_index = r->face_index;
  t.ncreases = nc; t.crease_verts = cv; t.crease_sharpness = cs;
  t.ncorners = nk; t.corner_verts = kv; t.corner_sharpness = ks;
  int ok = sumi_osd_create(&t, out, err, errlen);
  free(size); free(cv); free(cs); free(kv); free(ks);
  return ok;
}

/* Corner k of an n-sided refined face in Bfr's parameters. */
static Vec2 corner_uv(int n, int k) {
  static const Vec2 quad[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  static const Vec2 tri[3] = {{0, 0}, {1, 0}, {0, 1}};
  return n == 3 ? tri[k] : quad[k];
}

static int sample_face(const SumiOsdMesh *h, const SumiOsdRefined *r, const Mesh *m, int f,
                       int t0, Acc *a, char *err, size_t errlen) {
  const int *fv = r->face_index + r->face_start[f];
  int n = r->face_start[f + 1] - r->face_start[f];
  double w[TRI_SAMPLES][3], uv[2 * TRI_SAMPLES];
  Vec3 lim[TRI_SAMPLES];
  tri_weights(w);
  for (int t = t0; t < t0 + n - 2; t++) {
    Vec2 c[3];
    for (int k = 0; k < 3; k++) {
      int corner = 0;
      while (corner < n && fv[corner] != m->tri[t][k]) corner++;
      if (corner == n) { snprintf(err, errlen, "triangle %d is not in face %d", t, f); return 0; }
      c[k] = corner_uv(n, corner);
    }
    for (int s = 0; s < TRI_SAMPLES; s++) {
      uv[2 * s] = w[s][0] * c[0].x + w[s][1] * c[1].x + w[s][2] * c[2].x;
      uv[2 * s + 1] = w[s][0] * c[0].y + w[s][1] * c[1].y + w[s][2] * c[2].y;
    }
    if (!sumi_osd_eval_face(h, r->ctrl, f, TRI_SAMPLES, uv, (double *)lim, NULL, NULL, NULL,
                            err, errlen))
      return 0;
    for (int s = 0; s < TRI_SAMPLES; s++) {
      Vec3 q = v3_add(v3_add(v3_mul(m->pos[m->tri[t][0]], w[s][0]),
                             v3_mul(m->pos[m->tri[t][1]], w[s][1])),
                      v3_mul(m->pos[m->tri[t][2]], w[s][2]));
      acc_add(a, q, lim[s]);
    }
  }
  return 1;
}

int refine_subdiv(const SceneGeometry *g, SumiOsdBoundary boundary, const Mat4 *object_to_world,
                  const Camera *cam, RefineStats *st, char *err, size_t errlen) {
  memset(st, 0, sizeof *st);
  SumiOsdRefined r;
  double t0 = now_ms();
  Mesh *m = subdiv_mesh_ex(g, boundary, &r, err, errlen);
  st->ms = now_ms() - t0;
  if (!m) return 0;
  st->ntris = m->ntris;
  st->nfaces = r.nfaces;
  t0 = now_ms();
  SumiOsdMesh *h = NULL;
  int ok = level_handle(g, boundary, &r, &h, err, errlen);
  Acc a = {0};
  a.to_world = object_to_world;
  a.cam = cam;
  int stride = r.nfaces > REFINE_MAX_SUBDIV_FACES ? (r.nfaces + REFINE_MAX_SUBDIV_FACES - 1) /
                                                        REFINE_MAX_SUBDIV_FACES : 1;
  for (int f = 0, tri = 0; f < r.nfaces && ok; f++) {
    int n = r.face_start[f + 1] - r.face_start[f];
    if (f % stride == 0 && sumi_osd_face_has_limit(h, f)) {
      ok = sample_face(h, &r, m, f, tri, &a, err, errlen);
      st->nfaces_sampled++;
    }
    tri += n - 2;
  }
  st->ref_ms = now_ms() - t0;
  acc_finish(&a, st);
  sumi_osd_destroy(h);
  sumi_osd_refined_free(&r);
  mesh_destroy(m);
  return ok;
}

/* ---- the report ------------------------------------------------------------------- */

static void print_stats(FILE *out, const char *what, const RefineStats *st, int px) {
  fprintf(out, "  %-22s", what);
  if (st->ntris) fprintf(out, " %8d tris", st->ntris);
  else fprintf(out, " %13s", "");
  fprintf(out, "  max %.3g  mean %.3g units", st->max_units, st->mean_units);
  if (px) fprintf(out, "  max %.3g  mean %.3g px", st->max_px, st->mean_px);
  fprintf(out, "  (%ld samples; ours %.2f ms, osd %.2f ms)\n", st->samples, st->ms, st->ref_ms);
}

static int report_patches(const SceneObject *o, const Camera *cam, FILE *out) {
  const SceneGeometry *g = o->geometry;
  char err[256];
  int nd = 0;
  for (int p = 0; p < g->npatches; p++) nd += refine_patch_degenerate(&g->patches[p]);
  fprintf(out, "  %d patches, %d degenerate", g->npatches, nd);
  for (int p = 0; p < g->npatches && nd; p++)
    if (refine_patch_degenerate(&g->patches[p])) fprintf(out, " %d", p);
  fputc('\n', out);
  RefineStats ev, evd, un, ad;
  if (!refine_patch_eval(g, 16, &o->transform, cam, &ev, &evd, err, sizeof err)) goto fail;
  print_stats(out, "evaluation 17x17", &ev, cam != NULL);
  if (nd) print_stats(out, "evaluation, degenerate", &evd, cam != NULL);

  int n = o->tess_n > 0 ? o->tess_n : 16;
  double t0 = now_ms();
  Mesh *m = tess_uniform(g, n);
  double ms = now_ms() - t0;
  int ok = refine_patch_mesh(g, m, &o->transform, cam, &un, err, sizeof err);
  mesh_destroy(m);
  if (!ok) goto fail;
  un.ms = ms;
  char what[64];
  snprintf(what, sizeof what, "uniform n=%d", n);
  print_stats(out, what, &un, cam != NULL);

  double tol = o->tess_px > 0 ? o->tess_px : REFINE_DEFAULT_TOLERANCE_PX;
  Mat4 to_clip = cam ? m4_mul(cam->world_to_clip, o->transform) : o->transform;
  t0 = now_ms();
  m = tess_adaptive(g, cam ? &to_clip : NULL, cam ? cam->width : 0, cam ? cam->height : 0, tol);
  ms = now_ms() - t0;
  ok = refine_patch_mesh(g, m, &o->transform, cam, &ad, err, sizeof err);
  mesh_destroy(m);
  if (!ok) goto fail;
  ad.ms = ms;
  snprintf(what, sizeof what, "adaptive %g %s", tol, cam ? "px" : "units");
  print_stats(out, what, &ad, cam != NULL);
  return 0;
fail:
  fprintf(out, "  error: %s\n", err);
  return 1;
}

static int report_subdiv(const SceneObject *o, const Camera *cam, FILE *out) {
  const SceneGeometry *g = o->geometry;
  char err[256], what[64];
  RefineStats st;
  fprintf(out, "  mesh of %d vertices, %d faces, %s level %d, %d creases, %d corners\n", g->nverts,
          g->nfaces, g->subdiv_scheme ? g->subdiv_scheme : "catmark", g->subdiv_level,
          g->ncreases, g->ncorners);
  if (!refine_subdiv(g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, &o->transform, cam, &st, err,
                     sizeof err)) {
    fprintf(out, "  error: %s\n", err);
    return 1;
  }
  snprintf(what, sizeof what, "subdivided (drawn)");
  print_stats(out, what, &st, cam != NULL);
  if (st.nfaces_sampled < st.nfaces)
    fprintf(out, "  (compared %d of the %d refined faces, evenly spread; faces without a limit "
                 "surface are skipped)\n", st.nfaces_sampled, st.nfaces);
  return 0;
}

int refine_compare(const Scene *s, const Camera *cam, FILE *out) {
  int status = 0, shown = 0;
  if (cam)
    fprintf(out, "camera: %dx%d pixels; deviations by parameter from OpenSubdiv's limit surface\n",
            cam->width, cam->height);
  for (int i = 0; i < s->nobjects; i++) {
    const SceneObject *o = &s->objects[i];
    const SceneGeometry *g = o->geometry;
    if (!g) continue;
    int patches = g->kind == GEOM_PATCHES && g->npatches > 0;
    int sub = g->kind == GEOM_MESH && g->subdiv_level > 0;
    if (!patches && !sub) continue;
    fprintf(out, "object %d%s%s%s (line %d):\n", i, o->name ? " `" : "", o->name ? o->name : "",
            o->name ? "`" : "", o->loc.line);
    status |= patches ? report_patches(o, cam, out) : report_subdiv(o, cam, out);
    shown++;
  }
  if (!shown) fprintf(out, "no object with Bezier patches or subdivision to compare\n");
  return status;
}
