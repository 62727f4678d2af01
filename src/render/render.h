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
** frame after the tile pass (no lines, no origami), or for a tile (tile.h)
** drawn a band at a time: begin once, with an image of the file's size
** and channels (its pixels are not read), before the tile pass (it
** returns 0 when the file cannot take rows so: nothing more is handed to
** it, and the caller writes the image whole); then rows
** with rows y0..y1-1 of the file, held in band (an image of y1 - y0 rows),
** as soon as they and every row above them are done, in order, one call at
** a time, from whichever worker finished them. Without begin having been
** called, the caller writes the frame. */
typedef struct RenderRows {
  void *ctx;
  int (*begin)(void *ctx, const Image *img);
  void (*rows)(void *ctx, const Image *band, int y0, int y1);
} RenderRows;

/* A rectangle of the frame in output pixels, [x0, x1) x [y0, y1): a tile,
** or the part of the frame a tile's stages work on. */
typedef struct RenderWindow { int x0, y0, x1, y1; } RenderWindow;

/* Is w empty (x1 <= x0 or y1 <= y0)? An empty window in RenderOptions
** means the whole frame. */
static inline int render_window_empty(RenderWindow w) { return w.x1 <= w.x0 || w.y1 <= w.y0; }

/* Told how far a frame's tile pass has got: done of total screen tiles,
** from whichever worker finished one, so possibly from several at once
** (the callee is thread-safe and cheap: it is called once a tile). */
typedef struct RenderProgress {
  void *ctx;
  void (*tiles)(void *ctx, int done, int total);
} RenderProgress;

/* Each tile's samples as the tile pass draws them, for a stage that reads
** them tile by tile instead of from a whole G-buffer kept (the canvas's
** ink). tile is called once per tile of the window, from the worker that
** drew it (several at once, for different tiles), with rt's rectangle the
** tile's own samples (frame sample coordinates; plane index (y - oy) *
** stride + (x - ox)); face and bary are set only where object >= 0. */
struct RastTarget;
typedef struct RenderTileSink {
  void *ctx;
  void (*tile)(void *ctx, const struct RastTarget *rt);
} RenderTileSink;

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
  RenderWindow window; /* render only this part of the frame (tile.h); empty: all of it */
  const RenderProgress *progress;   /* or NULL */
  const RenderTileSink *tiles;      /* the tile pass hands its tiles here too, or NULL */
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
  struct ShadowMap *shadow;   /* its shadow maps (shadow.h), or NULL: it casts none */
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
  struct ImageStyle *image;    /* `texture "file"`: its map and the frame's view (shade.c), else NULL */
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
  int subdiv_kept;             /* mesh is subdiv_mesh's, unchanged: freeing the frame gives
                                  it back to the cache across frames (subdiv_mesh_done) */
  Mat4 object_to_world;
  float (*wpos)[3];            /* mesh->nverts world positions */
  float (*wnrm)[3];            /* mesh->nverts world unit normals */
  float (*wcnrm)[3][3];        /* per triangle corner world normals where the mesh has
                                  hard edges (Mesh.corner_nrm), else NULL */
  int world_kept;              /* wpos, wnrm and wcnrm are the mesh's, kept with it across
                                  frames (mesh_derived): not the frame's to free */
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
  TexTriangle *imgcoords;      /* a style's image map: per triangle, its (u, v) (texcoord.h) */
  float (*wfnrm)[3];           /* per triangle, its unit world normal, when some light casts
                                  shadows (shadow.h: the receivers' planes), else NULL */
} RenderObject;

typedef struct RenderFrame {
  int width, height;           /* output pixels */
  RenderWindow win;            /* the part the stages draw (the whole frame, or a tile and
                                  the margin its stages need): images and G-buffers cover
                                  it, in the frame's pixel coordinates */
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
  int refined;                 /* some subdivision was refined for this frame, not taken
                                  from the cache (subdiv.h) */
  struct ScreenTexFrame *screentex;   /* the noise and pattern layers (screentex.h) */
  const Scene *scene;          /* what it was prepared from (the line stage reads its
                                  origami sheets, which hide lines too) */
} RenderFrame;

/* Worker threads o asks for (0: one per online CPU). */
int render_thread_count(const RenderOptions *o);

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

/* Rasterize and shade f's window (f->win: the whole frame unless a tile)
** into out (an image of the window's size created by the caller: RGB, or
** RGBA when the background is not opaque). With rows (its begin already
** called), out's bands go to it as they are finished. When gbuf_out is
** not NULL, *gbuf_out receives the window's G-buffer (caller frees with
** gbuf_destroy); otherwise each worker keeps only the tile it is drawing.
** With out NULL (and gbuf_out given) the pass draws the G-buffer alone and
** shades nothing. */
void render_frame(const RenderFrame *f, const RenderOptions *o, const RenderRows *rows, Image *out,
                  GBuffer **gbuf_out);

/* The tile pass in steps, for a caller that shades a window a band of rows
** at a time (tile.c): begin sets up and bins f's triangles for f->win;
** each run rasterizes and shades frame rows y0..y1-1 of the window into
** out, an image of the window's width and y1 - y0 rows (rows and gbuf_out
** as for render_frame: rows' y0 and y1 count from out's first row); end
** frees it. render_frame is one run over the whole window. */
typedef struct RenderPass RenderPass;
RenderPass *render_pass_begin(const RenderFrame *f, const RenderOptions *o);
void render_pass_run(RenderPass *p, int y0, int y1, const RenderRows *rows, Image *out, GBuffer **gbuf_out);
void render_pass_end(RenderPass *p);

/* The stages after prepare over f's window (f->win): the tile pass, the
** origami sheets, the canvas (canvas: canvas_wanted, with f's background
** made transparent) and the lines, into *out (an image of the window's
** size) and, with gbuf_out, its G-buffer. Returns 1, or 0 after a
** diagnostic (*out NULL then). */
int render_stages(const Scene *s, const RenderOptions *o, RenderFrame *f, int canvas, Image **out,
                  GBuffer **gbuf_out);

/* The whole pipeline: prepare, rasterize, shade, lines. *out receives a
** new image (image_destroy): RGB when the background is opaque, else RGBA
** (unassociated alpha); 8-bit (Image.data8) when o->out8 asks and no
** origami sheet is composited over it, else float. With o->window, only
** that part of the frame (tile.h): *out is the window's pixels, exactly as
** the whole frame has them (with o->rows, an 8-bit window may go to its
** file band by band: *out then has no pixels). Returns 0 on success, 1
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
