/*
** Bezier patch evaluation: points, partial derivatives and normals of the
** bicubic (and bilinear) patches of a SceneGeometry.
**
** Parameterisation (the lecture's, 004): cp[4 * j + i] is row j, column i;
** i runs along u, j along v, both in [0, 1]:
**   P(u, v) = sum_j sum_i B_i(u) B_j(v) cp[4 * j + i]    (cubic Bernstein B)
** A bilinear patch uses cp[0..3] = p00, p10, p01, p11 (p_uv), i.e. the
** lecture's p0, p1, p2, p3, so bilinear(p0, p1, p2, p3) stores them as given:
**   P(u, v) = (1-u)(1-v) p0 + u(1-v) p1 + (1-u)v p2 + uv p3
** The normal is dP/du x dP/dv, normalised: a flat patch with u along +x and
** v along +y faces +z.
*/
#ifndef geom_patch_h
#define geom_patch_h

#include "../scene/scene.h"

/* The point at (u, v); the partial derivatives into *du and *dv when they
** are not NULL. */
Vec3 patch_eval(const ScenePatch *p, double u, double v, Vec3 *du, Vec3 *dv);

/* The unit normal normalize(dP/du x dP/dv) at (u, v). Where a tangent
** vanishes (a collapsed edge, as on the teapot's lid and bottom) the normal
** is the limit taken from inside the patch, so it is always finite and
** oriented as the patch; a patch degenerate everywhere (a point or a line)
** gives (0, 0, 1). Never NaN. */
Vec3 patch_normal(const ScenePatch *p, double u, double v);

/* The point at (u, v), and patch_normal(p, u, v) into *normal, from one
** evaluation (what the tessellator uses). */
Vec3 patch_eval_normal(const ScenePatch *p, double u, double v, Vec3 *normal);

/* The rows of a patch summed at one u (and their u-derivatives): all that
** depends on u alone, so points sharing a u (a grid's column) share them.
** n is the rows' count, 4 (cubic) or 2 (bilinear). */
typedef struct PatchRows {
  int n;
  Vec3 r[4], ru[4];
} PatchRows;

/* The rows of p at u, for patch_eval_normal_rows. */
void patch_rows(const ScenePatch *p, double u, PatchRows *rows);

/* The Bernstein weights at one v and their derivatives (cubic, or linear
** padded with zeros): all that depends on v alone, so a grid's rows share
** them. */
typedef struct PatchWeights {
  double b[4], d[4];
} PatchWeights;

/* The weights of p at v, for patch_eval_normal_rows. */
void patch_weights(const ScenePatch *p, double v, PatchWeights *w);

/* patch_eval_normal(p, u, v, normal) from p's rows at u and weights at v
** (bit for bit the same). */
Vec3 patch_eval_normal_rows(const ScenePatch *p, const PatchRows *rows, const PatchWeights *w,
                            double u, double v, Vec3 *normal);

/* The 16 control points of the bicubic patch that represents the bilinear
** patch p exactly (degree elevation), into *out (bilinear = 0). */
void patch_elevate_bilinear(const ScenePatch *p, ScenePatch *out);

/* Fills *out with the bilinear patch p00, p10, p01, p11 (see above). */
void patch_bilinear(ScenePatch *out, Vec3 p00, Vec3 p10, Vec3 p01, Vec3 p11);

#endif
