/*
** The frame pipeline: a Scene in, an Image out.
**
**   prepare   tessellate every object (tessellate.h), move it to world
**             space, frame the camera, resolve lights and styles
**   raster    clip, set up and bin the triangles into screen tiles, then
**             scan-convert each tile into the G-buffer (raster.h); back
**             faces of closed meshes seen from outside are skipped
**   shade     each sample by its object's style (shade.h), box-filter the
**             samples of each pixel (`samples N`) over the background
**   lines     the line stage (lines.h) draws its strokes over the image
** Setup, raster and shade run in chunks and screen tiles on --threads
** workers; every chunk's and tile's result depends only on the scene, so
** the image is byte-identical at any thread count. An 8-bit frame nothing
** is drawn over goes to its file a band of tile rows at a time while the
** pass runs (RenderRows): encoding it is work the workers share. Each
** stage records its time in the --stats table (stats.h).
**
** The prepared frame (RenderFrame) is public so later stages (lines, AOVs)
** read the same meshes, camera and lights the rasterizer used.
*/
#ifndef render_render_h
#define render_render_h

#include "../geom/mesh.h"
#include "../io/image.h"
#include "../scene/scene.h"
#include "camera.h"
#include "gbuffer.h"

/* Largest output side in pixels, and largest side of the sample grid
** (output side times `samples`): the rasterizer's fixed-point limit. */
#define RENDER_MAX_SIZE 16384
#define RENDER_MAX_SAMPLE_DIM 32768
/* Most output pixels: the float RGBA image alone is 16 bytes a pixel, so
** 8192 x 8192 is 1 GiB. */
#define RENDER_MAX_PIXELS (8192LL * 8192LL)
/* Most samples per pixel side (`samples N`): 16 x 16 = 256 a pixel. */
#define RENDER_MAX_SAMPLES 16
/* Image size when neither the scene nor the command line sets one. */
#define RENDER_DEFAULT_WIDTH 640
#define RENDER_DEFAULT_HEIGHT 480
/* Segments a patch side gets when an object asks for none (uniform). */
#define RENDER_DEFAULT_TESS 16

/* Most triangles a frame's uniformly tessellated and polygon objects may
** ask for before anything is built (about 100 bytes each through the
** pipeline: 20 M is ~2 GB). Subdivision has its own (SUBDIV_MAX_FACES);
** adaptive tessellation is bounded per patch (TESS_MAX_SEGMENTS). */
#define RENDER_MAX_TRIANGLES 20000000LL
/* Screen tiles, in output pixels a side (a tile is TILE * samples samples). */
#define RENDER_TILE 64

/* A taker of an 8-bit frame's finished rows, so that encoding the file
** overlaps rendering. render_scene uses it when nothing is drawn over the
** frame after the tile pass (no lines, no origami): begin once, with the
** frame's image (size, channels), before the tile pass; then rows with
** rows y0..y1-1 of img as soon as they and every row above them are
** shaded, in order, one call at a time, from whichever worker finished
** them. Without begin having been called, the caller writes the frame. */
typedef struct RenderRows {
  void *ctx;
  void (*begin)(void *ctx, const Image *img);
  void (*rows)(void *ctx, const Image *img, int y0, int y1);
} RenderRows;

typedef struct RenderOptions {
  int width, height;   /* after -W/-H (render_resolve_size); 0: the scene's, or 640 x 480 */
  int threads;         /* workers, >= 1; 0 = one per online CPU */
  int stats;           /* the caller prints stats.h's table (stages always record) */
  int samples;         /* 0: the scene's `samples`; else overrides it */
  int out8;            /* the frame goes to an 8-bit file: render_scene may make it 8-bit */
  int aliased;         /* 1: no antialiasing whatever the scene says (a frame whose colour
                          regions are traced: the blended colours of edge pixels would make
                          slivers) */
  const RenderRows *rows;   /* with out8: the file's encoder, or NULL */
  struct StrokeList **strokes;   /* when set, render_scene hands the line stage's strokes
                                    back here (stroke_list_free) instead of drawing them */
} RenderOptions;

/* A light resolved for shading: floats, world space. A spot is a point
** light whose light is limited to a cone (shade_spot). */
typedef struct RenderLight {
  int directional;
  float pos[3];        /* point light position */
  float dir[3];        /* directional: unit vector toward the light */
  float color[3];      /* linear colour times strength */
  int inverse_square;  /* point light falls off as 1 / d^2 */
  int spot;            /* a spot: lit within its cone only */
  float axis[3];       /* spot: unit vector along its axis, away from the light */
  float cos_edge;      /* spot: cosine of the angle from the axis to the cone's edge */
  float inv_fade;      /* spot: 1 / (cos of where the fade ends - cos_edge) */
  const struct ShadowMap *shadow;   /* its shadow maps (shadow.h), or NULL: it casts none */
} RenderLight;

/* shade threshold's layers, resolved once a frame (shade_threshold.c), and
** a triangle's texture coordinates (texcoord.h). */
typedef struct ThresholdStyle ThresholdStyle;
typedef struct TexTriangle TexTriangle;

/* Per-style shading constants, resolved once a frame (floats, linear). */
typedef struct RenderStyle {
  const SceneStyle *src;
  ShadeKind kind;
  float base[3];
  float ambient;
  float specular, shininess;
  int bands_n;                 /* T_n's n for the diffuse term (bands - 1) */
  float inv_bands_n;           /* 1 / bands_n */
  float threshold;
  int spec_n;                  /* T_n's n for the specular term */
  float inv_spec_n;
  float spec_threshold;
  float spec_cut;              /* n.h below which T_n(f_s) is surely 0 */
  float edge;                  /* n.v cutoff, 0 = no silhouette ramp */
  float edge_color[3];
  int lit;                     /* flat: 0 = the base colour as it is */
  float fill[3];               /* the flat colour of its regions in an SVG */
  float lit_color[3], unlit_color[3];   /* bokashi: the gradation's two ends */
  const struct ScreenTex *tex; /* its noise and pattern layer (screentex.h), or NULL */
  float alpha;                 /* the alpha its samples get in the tile pass: 1, or 0 for
                                  shade ink, which the canvas paints afterwards */
  struct InkStyle *ink;        /* shade ink: its parameters (ink.h), else NULL */
  ThresholdStyle *layers;      /* shade threshold: its layers, else NULL */
} RenderStyle;

/* Where an object's centre (SceneObject.centre) lands: the noise, the
** pattern and both bokashi follow it. */
typedef struct RenderCentre {
  float world[3];              /* world space */
  float px[2];                 /* screen position in output pixels (y down) */
  float wpp;                   /* scene units one output pixel spans at its depth */
} RenderCentre;

/* One object ready to draw. Its mesh stays in object space (the line
** stages want it there, with object_to_world); the rasterizer and shading
** use the world copies. */
typedef struct RenderObject {
  const SceneObject *src;
  const RenderStyle *style;
  Mesh *mesh;                  /* owned; topology built; winding is
                                  counter-clockwise in world space too */
  Mat4 object_to_world;
  float (*wpos)[3];            /* mesh->nverts world positions */
  float (*wnrm)[3];            /* mesh->nverts world unit normals */
  float (*wcnrm)[3][3];        /* per triangle corner world normals where the mesh has
                                  hard edges (Mesh.corner_nrm), else NULL */
  unsigned char *backfacing;   /* per triangle: its front faces away from the camera */
  int cull_back;               /* closed, outward and seen from outside: back faces
                                  are hidden, the rasterizer skips them */
  float (*vcolor)[3];          /* gouraud: per-vertex lit colour (per triangle corner, 3 a
                                  triangle, where wcnrm is set), else NULL */
  RenderCentre centre;
  const struct ScreenTexObject *tex;   /* its noise and pattern mapping, or NULL */
  struct BokashiObject *bokashi;       /* its bokashi constants (shade_bokashi.c), or NULL */
  float *vink;                 /* shade ink: per-vertex Gouraud grey (ink.h), else NULL */
  TexTriangle *texcoords;      /* threshold: per triangle, its texture coordinates, else NULL */
} RenderObject;

typedef struct RenderFrame {
  int width, height;           /* output pixels */
  int samples;                 /* N: N x N samples a pixel */
  int antialias;               /* `output { antialias }`: edges and bands are filtered
                                  by coverage (antialias.h) */
  Camera camera;               /* for the output size (camera_scaled for others) */
  Color background;
  int nobjects;
  RenderObject *objects;       /* Scene.objects, in order */
  int nlights;
  RenderLight *lights;         /* the scene's, or the default key light */
  int nstyles;
  RenderStyle *styles;         /* Scene.styles, then the default style */
  SceneStyle default_style;
  long long ntriangles;
  struct ScreenTexFrame *screentex;   /* the noise and pattern layers (screentex.h) */
  const Scene *scene;          /* what it was prepared from (the line stage reads its
                                  origami sheets, which hide lines too) */
} RenderFrame;

/* Output size from the scene and -W/-H (0 = not given): both given wins;
** one alone keeps the scene's aspect ratio; neither takes the scene's size
** or 640 x 480. */
void render_resolve_size(const Scene *s, int cli_w, int cli_h, int *w, int *h);

/* Prepare *f from s for an output of o->width x o->height (already
** resolved). Returns 1, or 0 with a diagnostic reported (diag.h) when the
** scene cannot be rendered (size or sample limits, a bad camera). Free with
** render_frame_free even on failure. */
int render_prepare(const Scene *s, const RenderOptions *o, RenderFrame *f);
void render_frame_free(RenderFrame *f);

/* Rasterize and shade f into out (an image of f's size created by the
** caller: RGB, or RGBA when the background is not opaque). With rows (its
** begin already called), out's bands go to it as they are finished. When
** gbuf_out is not NULL, *gbuf_out receives the whole G-buffer (caller
** frees with gbuf_destroy); otherwise each worker keeps only the tile it
** is drawing. */
void render_frame(const RenderFrame *f, const RenderOptions *o, const RenderRows *rows, Image *out,
                  GBuffer **gbuf_out);

/* The whole pipeline: prepare, rasterize, shade, lines. *out receives a
** new image (image_destroy): RGB when the background is opaque, else RGBA
** (unassociated alpha); 8-bit (Image.data8) when o->out8 asks and no
** origami sheet is composited over it, else float. Returns 0 on success, 1
** when the scene cannot be rendered (diagnostics reported). */
int render_scene(const Scene *s, const RenderOptions *o, Image **out, GBuffer **gbuf_out);

/* Fill the attribute planes (normal, uv, position) of g from f. */
void render_gbuffer_attributes(GBuffer *g, const RenderFrame *f);

/* --aov: write the passes named in list (comma-separated: depth, normal,
** position, uv, object, face, or all) of g beside output: "out.png" gives
** out.depth.exr (channel Z, the window depth of camera.h; background
** +inf), out.normal.exr (N.x, N.y, N.z), out.position.exr (P.x, P.y, P.z),
** out.uv.exr (u, v), out.object.tif and out.face.tif (int32 ids, -1 =
** background), all at the sample resolution. Returns 1, or 0 with a reason
** in err (an unknown pass name, a failed write). */
int render_write_aovs(GBuffer *g, const char *output, const char *list, char *err, size_t errlen);

/* 1 when every name in the --aov list is a pass (checked before any
** work); else 0 with the first unknown one in err. */
int render_aov_list_ok(const char *list, char *err, size_t errlen);

#endif
