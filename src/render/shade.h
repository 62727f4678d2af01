/*
** Shading models: the colour of one G-buffer sample from its surface point,
** normal and view vector, by its object's style. One function per model
** behind a table (shade_model), one file per model family:
**   shade.c       lights, the shared terms, flat, gouraud, phong, unlit
**   shade_toon.c  toon: T_n bands on the diffuse and specular terms
**                 separately, or 1D colour ramps, and the n.v silhouette
**                 edge (004; 002 section 2)
**   shade_bokashi.c  bokashi: the ukiyo-e gradations around the object's
**                 centre, sphere (bokashi 2) and linear (bokashi 1) (001
**                 section 2.2.3)
**   shade_ink.c   ink: the Gouraud grey per vertex and its quantisation
**                 (003 ch. 5.2); the canvas paints it after the pass (ink.h)
**   shade_threshold.c  threshold textures: toon's T_n with the threshold
**                 read from hatching, stipple and CLAHE'd image layers,
**                 filtered (002 sections 3-5)
** The tile pass shades a row of samples in two steps: it rebuilds each
** sample's surface from its triangle's corners into a ShadeRow, plane by
** plane (shade_row_rebuild per run of samples of one triangle, several
** samples side by side), and the model's span shader
** (shade_span_model) colours each run of samples of one object.
** The lighting equation every lit model shares (002 eq. 1):
**   I = m_a l_a + sum_i m_d T(f_d) l_i + sum_i m_s T(f_s) l_i
** with m_a = m_d = the style's base colour, l_a = ambient (white),
** m_s = specular (white), f_d = max(0, n.l), f_s = max(0, n.h)^shininess
** (Blinn's half vector, 0 where n.l <= 0), and T the identity except in
** toon. All colours are linear.
*/
#ifndef render_shade_h
#define render_shade_h

#include <math.h>

#include "render.h"

/* What a shading model sees of one sample. */
typedef struct ShadeSample {
  const RenderFrame *frame;
  const RenderObject *obj;
  int face;            /* triangle of obj->mesh */
  float b1, b2;        /* barycentrics in it (gbuffer.h) */
  float p[3];          /* world point */
  float n[3];          /* unit shading normal, turned toward the viewer */
  float v[3];          /* unit vector toward the viewer */
  float uv[2];
  float base[3];       /* the base colour here: the style's, or its image map's over it */
  int sx, sy;          /* its column and row in the frame's sample grid */
} ShadeSample;

/* A shading model: the linear colour of s into rgb. */
typedef void (*ShadeFn)(const ShadeSample *s, float rgb[3]);

/* The model for a shade kind. Kinds whose own model is not in this table
** (their stages add it) shade as phong. */
ShadeFn shade_model(ShadeKind kind);

/* A row of samples rebuilt from the G-buffer, one plane per quantity
** (structure of arrays), so the span shaders run several samples side by
** side. Sample k of the row shows triangle face[k] of its object at
** barycentrics bary[k] (the G-buffer's planes); the rebuilt planes hold its
** world point p, unit shading normal n (turned toward the viewer on a back
** face), unit vector v toward the viewer, and uv (0 unless some style
** reads it). Screen-space models (bokashi linear, the noise and pattern
** layer) read the samples' grid positions: sample k is at column sx0 + k
** of row sy, in samples (frame->samples a pixel side). */
/* Terms a sample's step levels hold (ShadeRow.step_key). */
#define SHADE_STEP_TERMS 4

typedef struct ShadeRow {
  const RenderFrame *frame;
  const int32_t *face;
  const float (*bary)[2];
  float *px, *py, *pz;
  float *nx, *ny, *nz;
  float *vx, *vy, *vz;
  float *u, *v;
  float *br, *bg, *bb; /* per sample base colour where the object's style has an image map
                          (shade_image_run), else not read */
  int sx0, sy;         /* sample 0's column and the row in the frame's sample grid */
  float ray_base[3];   /* the row's view rays' part along fwd and up (shade_row_start) */
  /* antialiased (else NULL): where a model's colour steps (toon's bands,
  ** highlight and edge; antialias.h filters them): per sample, the level
  ** of each of up to SHADE_STEP_TERMS terms, one signed byte each (byte t
  ** for term t). The tile pass zeroes it first: a model that does not step
  ** writes nothing. shade_step_value gives a term's smooth value. */
  uint32_t *step_key;
} ShadeRow;

/* Term t of a sample of object o on its triangle face (ShadeRow.step_key),
** from its point p, unit normal n and view vector v: its smooth value, in units
** where the step from level L to L + 1 is at L + 1, so that between two
** samples a step lies where the value, taken linear, crosses it; NAN for
** a term the style does not have. */
float shade_step_value(const RenderFrame *f, const RenderObject *o, int face, int t, const float p[3],
                       const float n[3], const float v[3]);

/* Samples shade_row_rebuild works on side by side. */
#define SHADE_LANES 4

/* A row of n samples for frame f, its planes zeroed, each with
** SHADE_LANES spare samples past n; shade_row_free releases them. */
void shade_row_alloc(ShadeRow *r, const RenderFrame *f, int n);
void shade_row_free(ShadeRow *r);

/* The camera as the rebuild needs it. The unit view vector v (toward the viewer) of a sample. Perspective:
** minus the camera's ray through the sample's centre (sx + 0.5, sy + 0.5)
** of the frame's sample grid, ray = fwd + ax right + ay up with
** ax = (sx + 0.5) kx - cx and ay = cy - (sy + 0.5) ky, normalised. That is
** the direction from the point seen there to the eye, without subtracting
** two nearly equal positions: a camera 1e-9 from a surface (eye - p far
** below the points' float rounding) keeps its n.v edge test. Ortho: v =
** back (-forward, unit). */
typedef struct ShadeView {
  int ortho;
  float fwd[3], right[3], up[3];
  float kx, cx, ky, cy;
  float back[3];
  int want_uv;         /* some style's model reads uv */
} ShadeView;

/* The view of camera c over a grid of samples x samples a pixel
** (want_uv cleared). */
void shade_view_init(ShadeView *view, const Camera *c, int samples);

/* Start r on the row of samples from (sx0, sy) of the frame's sample
** grid under view: its place and what its view rays share. */
void shade_row_start(ShadeRow *r, const ShadeView *view, int sx0, int sy);

/* Rebuild samples k0..k1-1 of r (started on its row under view), which all show triangle face of object o,
** into r's planes: the point, the unit normal (turned toward the viewer on
** a back face; a zero one stays zero) and the unit view vector, SHADE_LANES
** samples at a time. The last lanes may write up to SHADE_LANES - 1
** samples past k1 (the planes' spare samples, or ones the next run
** rebuilds), so a row is rebuilt run after run from left to right. */
void shade_row_rebuild(ShadeRow *r, const ShadeView *view, const RenderObject *o, int face,
                       int k0, int k1);

/* The surface of one sample alone: the point p, unit normal n (turned
** toward the viewer on a back face) and unit view vector v where
** triangle face of o is at barycentrics (b1, b2), as shade_row_rebuild
** makes them (to rounding). */
void shade_surface_at(const ShadeView *view, const RenderObject *o, int face, float b1, float b2,
                      int sx, int sy, float p[3], float n[3], float v[3]);

/* The base colour of samples k0..k1-1 of r, which show triangle face of
** object o whose style has an image map (RenderStyle.image), into r's
** base planes (br, bg, bb): the map's filtered colour at each sample's
** (u, v) over the style's base (imagemap.h). */
void shade_image_run(ShadeRow *r, const RenderObject *o, int face, int k0, int k1);

/* The base colours of samples k0..k0+n-1 of r (object o) into R, G, B:
** the image map's (shade_image_run) or the style's base. */
void shade_base_block(const ShadeRow *r, const RenderObject *o, int k0, int n, float *R, float *G, float *B);

/* Sample k of r, which shows object o, as one ShadeSample. */
void shade_row_sample(const ShadeRow *r, const RenderObject *o, int k, ShadeSample *s);

/* Shade samples k0..k1-1 of r, which all show object o, into rgb: sample
** k's colour at rgb[k * stride + 0..2]. */
typedef void (*ShadeSpanFn)(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                            int stride);

/* The span shader for a shade kind: a model's own loop where it has one
** (toon), else shade_span_generic, which calls the kind's ShadeFn per
** sample. Both give the colours the ShadeFn gives, bit for bit. */
ShadeSpanFn shade_span_model(ShadeKind kind);
void shade_span_generic(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                        int stride);
void shade_toon_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                     int stride);
void shade_bokashi_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                        int stride);

/* A bokashi object's constants, set once a frame (shade_bokashi_prepare). */
typedef struct BokashiObject {
  float k[3];                  /* sphere: sum of the lights' d^ s / |d|^2 s_mod; f = n^.k */
  float g[2];                  /* linear: the gradation point on screen, output pixels */
  float dir[2];                /* linear: unit screen direction of the light's rays at c */
  float rate;                  /* linear: gradation per output pixel at c's depth */
  int light;                   /* linear: the strongest light at c (-1: none) */
  /* when some light casts shadows (the object has wfnrm): each light's own
  ** part of k (sphere), so that its shadow takes its share away, and for
  ** the per-vertex sphere n.k_i at each vertex (nverts rows of nlights) */
  float (*kl)[3];
  float *vk;
} BokashiObject;

/* o->bokashi for f's camera and lights (o's centre set first), and for the
** per-vertex sphere o->vcolor; shade_bokashi_free releases it. */
void shade_bokashi_prepare(const RenderFrame *f, RenderObject *o);
void shade_bokashi_free(RenderObject *o);
void shade_threshold_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                          int stride);

/* Sample s shaded by span shader span as a row of one, into rgb: a
** model's ShadeFn over its span shader, so both give the same bits. */
void shade_span_one(const ShadeSample *s, ShadeSpanFn span, float rgb[3]);

/* Whether the model for kind reads ShadeSample.uv (else it is left 0). */
int shade_reads_uv(ShadeKind kind);

/* A bokashi's unlit colour when the style gives none: the base times this
** (linear light). */
#define BOKASHI_UNLIT_DEFAULT 0.25f

/* Resolve a style's shading constants (defaults for unset values: bands
** 0 -> 3 (2 for threshold), specular_bands 0 -> 2, shininess 0 -> 32) and
** its model's own (a threshold style's layers and images). Returns 1, or 0
** after a diagnostic (an image that cannot be read). shade_style_free
** releases what it made, even after a failure. */
int shade_style_init(RenderStyle *rs, const SceneStyle *st);
void shade_style_free(RenderStyle *rs);

/* What object o's model keeps per vertex or triangle for the frame's
** camera (gouraud: vertex colours; bokashi: its constants; threshold:
** texture coordinates), freed
** with the frame. Returns 0 after a diagnostic (threshold: a projection
** that needs coordinates the geometry does not have). */
int shade_prepare_object(const RenderFrame *f, RenderObject *o);

/* shade threshold's part of the above (shade_threshold.c). */
int shade_threshold_init(RenderStyle *rs, const SceneStyle *st);
void shade_threshold_free(RenderStyle *rs);
int shade_threshold_prepare(const RenderFrame *f, RenderObject *o);

/* Unit vector toward point light lt from world point (x, y, z) into l*;
** returns the falloff factor there (1 / d^2 for an inverse-square light,
** else 1). shade_light and the toon bands' blocks share it, so a sample
** gets the same bits shaded alone or side by side with others. */
static inline float shade_point_light(const RenderLight *lt, float x, float y, float z, float *lx,
                                      float *ly, float *lz) {
  float dx = lt->pos[0] - x, dy = lt->pos[1] - y, dz = lt->pos[2] - z;
  float d2 = dx * dx + dy * dy + dz * dz;
  float inv = d2 > 0 ? 1 / sqrtf(d2) : 0;
  *lx = dx * inv; *ly = dy * inv; *lz = dz * inv;
  return lt->inverse_square & (d2 > 0) ? 1 / d2 : 1;
}

/* Spot light lt's factor for unit vector (lx, ly, lz) toward it: 1 within
** its cone less the penumbra, 0 outside the cone, and between them a
** smoothstep in the cosine of the angle off the axis. Its callers multiply
** the falloff by it after shade_point_light, in that order, so the bits
** are the same everywhere. */
static inline float shade_spot(const RenderLight *lt, float lx, float ly, float lz) {
  float c = -(lx * lt->axis[0] + ly * lt->axis[1] + lz * lt->axis[2]);   /* cos off the axis */
  float t = (c - lt->cos_edge) * lt->inv_fade;
  t = t > 0 ? (t < 1 ? t : 1) : 0;                   /* NaN (a light at p) too goes to 0 */
  return t * t * (3 - 2 * t);
}

/* Unit vector toward light i from world point p into l, and the light's
** colour arriving there (with falloff and a spot's cone; no shadow) into
** col. */
static inline void shade_light(const RenderFrame *f, int i, const float p[3], float l[3], float col[3]) {
  const RenderLight *lt = &f->lights[i];
  float k = 1;
  if (lt->directional) {
    l[0] = lt->dir[0]; l[1] = lt->dir[1]; l[2] = lt->dir[2];
  } else {
    k = shade_point_light(lt, p[0], p[1], p[2], &l[0], &l[1], &l[2]);
    if (lt->spot) k *= shade_spot(lt, l[0], l[1], l[2]);
  }
  col[0] = lt->color[0] * k;
  col[1] = lt->color[1] * k;
  col[2] = lt->color[2] * k;
}

/* The share of light i reaching world point p on triangle face of o: its
** shadow map's visibility there (shadow.h), 1 for a light that casts no
** shadow. */
float shade_reach(const RenderFrame *f, int i, const RenderObject *o, int face, const float p[3]);

/* The smooth diffuse term f_d = max(0, n.l). */
static inline float shade_diffuse(const float n[3], const float l[3]) {
  float d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
  return d > 0 ? d : 0;
}

/* The smooth specular term f_s = max(0, n.h)^shininess with h the unit
** half vector of l and v; 0 where the light is behind the surface. */
float shade_specular(const float n[3], const float l[3], const float v[3], float shininess);

/* The multi-band step T_n(x, t) = (floor(x n) + T(frac(x n), t)) / n with
** T(y, t) = 0 if y < t else 1; x is clamped to [0, 1] first (NaN to 0).
** n >= 1; gives the n + 1 levels 0, 1/n, ..., 1 (002 eq. 4). inv_n is
** 1 / n, passed in so the shading loop does not divide. */
static inline float shade_step_inv(float x, float t, int n, float inv_n) {
  x = x > 0 ? (x < 1 ? x : 1) : 0;                  /* NaN too goes to 0 */
  float xn = x * n;
  float whole = (float)(int)xn;                      /* floor: xn >= 0 */
  float frac = xn - whole;
  return (whole + (frac < t ? 0.0f : 1.0f)) * inv_n; /* T(frac(xn), t) adds the last step */
}

static inline float shade_step(float x, float t, int n) { return shade_step_inv(x, t, n, 1.0f / n); }

/* Per-vertex colours of a gouraud object (o->vcolor, allocated here):
** the phong terms at each vertex with its normal turned toward the
** viewer; where the mesh has corner normals (hard edges, as phong
** honours them), at each triangle corner with its own. */
void shade_vertex_colors(const RenderFrame *f, RenderObject *o);

/* The centre of o (SceneObject.centre, default its origin) in world space
** and on f's screen (o->centre). */
void shade_centre_init(const RenderFrame *f, RenderObject *o);

/* Models (shade_model's table). */
void shade_unlit(const ShadeSample *s, float rgb[3]);
void shade_flat(const ShadeSample *s, float rgb[3]);
void shade_gouraud(const ShadeSample *s, float rgb[3]);
void shade_phong(const ShadeSample *s, float rgb[3]);
void shade_toon(const ShadeSample *s, float rgb[3]);
void shade_bokashi(const ShadeSample *s, float rgb[3]);
/* shade ink (shade_ink.c): nothing, transparent: the canvas paints it
** (the span shader fills the run with zeros, reading no surface). */
void shade_ink(const ShadeSample *s, float rgb[3]);
void shade_threshold(const ShadeSample *s, float rgb[3]);
void shade_ink_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb, int stride);

#endif
