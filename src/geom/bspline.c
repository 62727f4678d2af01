/*
** Bezier to B-spline conversion and the OpenSubdiv reference patch (see
** bspline.h for the method).
*/
#include "bspline.h"

#include <string.h>

#include "patch.h"

/* A^-1: Bezier points of one row to the uniform cubic B-spline points. */
static const double BEZ_TO_BSP[4][4] = {
  {6, -7, 2, 0}, {0, 2, -1, 0}, {0, -1, 2, 0}, {0, 2, -7, 6}
};

/* The 4 x 4 vertex grid of the net: 9 quads, counter-clockwise in (u, v). */
enum { GRID_FACES = 9, GRID_CENTRE = 4 };
static const int GRID_FACE_SIZE[GRID_FACES] = {4, 4, 4, 4, 4, 4, 4, 4, 4};
/* Face (fi, fj) = 3 fj + fi has corners v, v+1, v+5, v+4 with v = 4 fj + fi. */
static const int GRID_FACE_INDEX[4 * GRID_FACES] = {
  0, 1, 5, 4,   1, 2, 6, 5,    2, 3, 7, 6,
  4, 5, 9, 8,   5, 6, 10, 9,   6, 7, 11, 10,
  8, 9, 13, 12, 9, 10, 14, 13, 10, 11, 15, 14
};

void bspline_from_bezier(const Vec3 bez[16], Vec3 out[16]) {
  Vec3 rows[16];  /* A^-1 applied along u (within each row j) */
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) {
      Vec3 s = v3(0, 0, 0);
      for (int l = 0; l < 4; l++) s = v3_add(s, v3_mul(bez[4 * j + l], BEZ_TO_BSP[i][l]));
      rows[4 * j + i] = s;
    }
  for (int j = 0; j < 4; j++)  /* then along v (across rows) */
    for (int i = 0; i < 4; i++) {
      Vec3 s = v3(0, 0, 0);
      for (int k = 0; k < 4; k++) s = v3_add(s, v3_mul(rows[4 * k + i], BEZ_TO_BSP[j][k]));
      out[4 * j + i] = s;
    }
}

void bspline_bezier_net(const ScenePatch *p, Vec3 out[16]) {
  if (p->bilinear) {
    ScenePatch e;
    patch_elevate_bilinear(p, &e);
    memcpy(out, e.cp, sizeof e.cp);
  } else {
    memcpy(out, p->cp, sizeof p->cp);
  }
}

int bspline_ref_init(BsplineRef *r, const ScenePatch *p, char *err, size_t errlen) {
  Vec3 bez[16], bsp[16];
  bspline_bezier_net(p, bez);
  bspline_from_bezier(bez, bsp);
  for (int k = 0; k < 16; k++) {
    r->pos[3 * k] = bsp[k].x;
    r->pos[3 * k + 1] = bsp[k].y;
    r->pos[3 * k + 2] = bsp[k].z;
  }
  SumiOsdTopology t = {0};
  t.nverts = 16;
  t.nfaces = GRID_FACES;
  t.face_size = GRID_FACE_SIZE;
  t.face_index = GRID_FACE_INDEX;
  t.scheme = SUMI_OSD_CATMARK;
  t.boundary = SUMI_OSD_BOUNDARY_EDGE_ONLY;
  r->regular = 0;
  return sumi_osd_create(&t, &r->osd, err, errlen);
}

int bspline_ref_eval(BsplineRef *r, int npts, const double *uv, Vec3 *P, Vec3 *du, Vec3 *dv,
                     char *err, size_t errlen) {
  return sumi_osd_eval_face(r->osd, r->pos, GRID_CENTRE, npts, uv, (double *)P, (double *)du,
                            (double *)dv, &r->regular, err, errlen);
}

void bspline_ref_free(BsplineRef *r) {
  sumi_osd_destroy(r->osd);
  r->osd = NULL;
}
