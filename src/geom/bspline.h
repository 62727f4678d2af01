/*
** Bezier to B-spline conversion, and OpenSubdiv's limit surface of a
** converted patch: the reference `sumi refine --compare` measures against.
**
** A bicubic Bezier net B (4 x 4, B[j][i] = cp[4 * j + i]) is the uniform
** cubic B-spline net P = A^-1 B A^-T, where A maps B-spline to Bezier
** points along one direction: A = 1/6 [[1,4,1,0],[0,4,2,0],[0,2,4,0],[0,1,4,1]],
** A^-1 = [[6,-7,2,0],[0,2,-1,0],[0,-1,2,0],[0,2,-7,6]]. The centre face of
** the 4 x 4 vertex grid of P (9 quads) is then a regular Catmull-Clark
** face whose limit surface is that patch, with its u and v run as the
** Bezier's (u along i, v along j).
*/
#ifndef geom_bspline_h
#define geom_bspline_h

#include <stddef.h>

#include "../scene/scene.h"
#include "osd_bridge.h"

/* out[4 * j + i] = (A^-1 B A^-T)[j][i] for the Bezier net bez. */
void bspline_from_bezier(const Vec3 bez[16], Vec3 out[16]);

/* The 16 control points of patch p as a bicubic Bezier net (a bilinear
** patch is degree-elevated). */
void bspline_bezier_net(const ScenePatch *p, Vec3 out[16]);

/* One patch converted and handed to OpenSubdiv. */
typedef struct BsplineRef {
  SumiOsdMesh *osd;
  double pos[48];      /* the B-spline net, 3 doubles a point */
  int regular;         /* Bfr took the centre face as a regular patch */
} BsplineRef;

/* Convert p and build its 3 x 3-face grid in OpenSubdiv. Returns 1, or 0
** with a reason in err. Release with bspline_ref_free(). */
int bspline_ref_init(BsplineRef *r, const ScenePatch *p, char *err, size_t errlen);

/* The limit surface at npts parameter pairs uv (2 a point, in [0, 1]^2):
** points into P, partial derivatives into du and dv (either may be NULL).
** Returns 1, or 0 with a reason in err. */
int bspline_ref_eval(BsplineRef *r, int npts, const double *uv, Vec3 *P, Vec3 *du, Vec3 *dv,
                     char *err, size_t errlen);

void bspline_ref_free(BsplineRef *r);

#endif
