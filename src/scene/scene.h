/*
** The evaluated scene: plain C structs, no AST pointers. The evaluator
** (src/lang/eval.c) fills it; the prepare and render stages read it.
** Every entity keeps the source location it came from so later stages can
** still point at the script in a diagnostic.
**
** Colours are linear RGBA (sRGB literals are converted on evaluation).
** Everything here lives in Scene.arena and is freed with scene_free().
*/
#ifndef scene_scene_h
#define scene_scene_h

#include "../base/mem.h"
#include "../base/vec.h"
#include "../lang/diag.h"

typedef struct Color { float r, g, b, a; } Color;

/* The paper under the whole image (`sheet "xuan";` or `sheet { ... }` in
** output; Yeh ch. 6): it replaces the background colour. */
typedef struct SceneSheet {
  const char *texture;        /* "xuan" (procedural) or an image file as written; NULL = no sheet */
  Color color;                /* the procedural paper's tint (linear) */
  int seed;                   /* the procedural fibres' */
  double scale;               /* fibre size, or texels a pixel of an image */
  double fibres;              /* how many fibres, 1 = the default density */
  double grain;               /* how strongly ink follows the absorbency, 0..1 */
  SrcRange loc;
} SceneSheet;

/* Most colours a vertical background gradient may have. */
#define SCENE_MAX_BACKGROUND_STOPS 16

typedef struct SceneOutput {
  int width, height;          /* 0 = not set (defaults to 640x480) */
  int samples;                /* N x N samples a pixel, >= 1 */
  int antialias;              /* 1 (default): edges and toon bands by coverage */
  Color background;           /* a flat background; a gradient's top colour, opaque */
  int nstops;                 /* `background c1, c2, ...`: a vertical gradient from c1 at
                                 the top to the last at the bottom (>= 2), else 0 */
  Color *stops;
  const char *backdrop;       /* `background "file"`: an image scaled to the frame (resolved
                                 against the scene's folder), else NULL */
  const char *backdrop_name;  /* as written, for messages */
  SrcRange background_loc;
  SceneSheet sheet;
  SrcRange loc;
} SceneOutput;

typedef enum { CAMERA_PERSPECTIVE, CAMERA_ORTHO } CameraKind;

typedef struct SceneCamera {
  int present;                /* 0: frame automatically */
  CameraKind kind;
  Vec3 position, look_at, up; /* up defaults to +z */
  double fov;                 /* vertical, degrees (perspective) */
  double ortho_height;        /* scene units shown vertically (ortho) */
  SrcRange loc;
} SceneCamera;

typedef enum { LIGHT_POINT, LIGHT_DIRECTIONAL, LIGHT_SPOT } LightKind;
typedef enum { FALLOFF_NONE, FALLOFF_INVERSE_SQUARE } LightFalloff;

typedef struct SceneLight {
  const char *name;           /* `light NAME { }`, or NULL */
  LightKind kind;
  Vec3 position;              /* LIGHT_POINT, LIGHT_SPOT */
  Vec3 direction;             /* LIGHT_DIRECTIONAL: the way the rays travel */
  Vec3 point_at;              /* LIGHT_SPOT: a point on its axis */
  double cone;                /* LIGHT_SPOT: degrees from the axis to the cone's edge */
  double penumbra;            /* LIGHT_SPOT: degrees inside the edge over which it fades in */
  Color color;
  double strength;
  LightFalloff falloff;
  int shadow;                 /* casts shadows (shadow maps: render/shadow.h) */
  int shadow_resolution;      /* texels a side of each of its maps */
  double shadow_bias;         /* depth bias, in texels of its map */
  double shadow_filter;       /* percentage-closer filter: a box this many texels wide */
  SrcRange loc;
} SceneLight;

/* ---- styles ---------------------------------------------------------- */

typedef enum {
  SHADE_NONE, SHADE_FLAT, SHADE_GOURAUD, SHADE_PHONG, SHADE_TOON,
  SHADE_THRESHOLD, SHADE_BOKASHI, SHADE_INK, SHADE_ORIGAMI
} ShadeKind;

typedef struct ShadeToon {
  int bands;                  /* K >= 2 tones: T_n with n = K - 1 */
  double threshold;           /* t in T_n */
  Color *ramp; int nramp;     /* diffuse ramp; replaces bands when nramp > 0 */
  Color *specular_ramp; int nspecular_ramp;
  double specular, shininess;
  int specular_bands;
  double specular_threshold;
  double ambient;
  double edge;                /* n.v cutoff for the silhouette ramp, 0 = off */
  Color edge_color;
} ShadeToon;

/* `shade bokashi linear | sphere` (001 section 2.2.3): the gradation's two
** colours and the paper's modifiers; sumi's readings are in docs/styles.md. */
typedef struct ShadeBokashi {
  int sphere;                 /* 1: bokashi 2 (sphere), 0: bokashi 1 (linear) */
  Color lit, unlit;           /* the two ends of the gradation */
  int has_lit, has_unlit;     /* given: else lit = base, unlit = a darker base */
  double strength_mod;        /* s_mod: times the light's strength at the centre */
  double offset;              /* o: the gradation point's offset along the light ray */
  double view_mod;            /* m_base: m = (v.l) m_base, scene units */
  double rate;                /* gradation per scene unit at the centre's depth */
  int per_pixel;              /* sphere: 1 Phong (per pixel), 0 Gouraud (per vertex) */
} ShadeBokashi;
/* shade ink (Yeh ch. 5.2): quantised Gouraud, ink diffusion, box filter. */
#define INK_MAX_TONES 8
/* Most diffusion passes a style may ask for: each pass moves ink one pixel,
** so this bounds how far ink runs (and the work) whatever the strength. */
#define INK_MAX_PASSES 256
/* Largest box filter side: its window is side x side pixels. */
#define INK_MAX_BOX 31
typedef enum { INK_SMALL, INK_MEDIUM, INK_LARGE } InkStrength;
typedef enum { INK_STAGE_GOURAUD, INK_STAGE_QUANTISED, INK_STAGE_DIFFUSED, INK_STAGE_FILTERED } InkStage;

typedef struct ShadeInk {
  double diffuse;             /* k_d of the high-contrast Gouraud image (ambient, specular and
                                 shininess are in ShadeToon) */
  int nlevels;                /* thresholds: [0, levels[0]) is the darkest range ... */
  double levels[INK_MAX_TONES - 1];
  int ntones;                 /* the value each range becomes (nlevels + 1 of them); 0 = the
                                 levels, then 1 */
  double tones[INK_MAX_TONES];
  int diffusion;              /* InkStrength */
  int passes;                 /* diffusion passes; 0 = the strength's */
  double ink_threshold;       /* rule 3: the least ink difference that transfers */
  double water_threshold;     /* rule 1: the water a pixel needs to transfer */
  double roughness;           /* spread of the paper's resistance to the ink, 0..1 */
  int box_filter;             /* side of the last box filter, odd; 1 = none */
  Color color;                /* the ink (linear) */
  int stage;                  /* InkStage: the last stage drawn */
  int nlights;                /* `lights a, b;`: the lights of the Gouraud image; 0 = all */
  const char **lights;
  int *light_index;           /* their indices into Scene.lights (once evaluated) */
  SrcRange levels_loc, tones_loc, lights_loc;
} ShadeInk;
/* shade threshold (002 sections 3-5): toon's T_n with the threshold t read
** from layers of threshold textures. */
typedef enum { LAYER_HATCH, LAYER_STIPPLE, LAYER_IMAGE } ThresholdLayerKind;
typedef enum { TERM_BOTH, TERM_DIFFUSE, TERM_SPECULAR } ThresholdTerm;
typedef enum {
  PROJ_AUTO, PROJ_UV, PROJ_PLANAR, PROJ_BOX, PROJ_CYLINDRICAL, PROJ_SPHERICAL
} TexProjection;

typedef struct ThresholdLayer {
  ThresholdLayerKind kind;
  int term;                   /* ThresholdTerm: which smooth term it thresholds */
  double range[2];            /* tone range: solid below range[0], absent above range[1] */
  double angle;               /* degrees in texture space */
  double spacing;             /* hatch, stipple: pixels between lines or dots on screen */
  const char *file;           /* image: the path, resolved against the scene's folder */
  double window;              /* image: CLAHE window, texels a side */
  double clip;                /* image: CLAHE clip limit (OpenCV's scale; 0 = none) */
  double scale;               /* image: texture units one copy of the image covers */
  double noise;               /* displacement by noise, in the layer's features */
  double noise_scale;         /* texture units a noise cell spans */
  SrcRange loc;
  SrcRange file_loc;
} ThresholdLayer;

/* Most layers one `shade threshold` may have. */
#define SCENE_MAX_LAYERS 8

typedef struct ShadeThreshold {
  int projection;             /* TexProjection */
  double scale;               /* texture space = projected coordinates / scale */
  int filter;                 /* percentage-closer filtering of the thresholded result */
  double strength;            /* blend of thresholded over smooth shading */
  double *facing; int nfacing;   /* strength curve over n.v (NULL: 1) */
  double *light; int nlight;     /* strength curve over the smooth term (NULL: 1) */
  ThresholdLayer *layers; int nlayers;
  SrcRange projection_loc;
} ShadeThreshold;

typedef struct SceneShade {
  ShadeKind kind;
  const char *subkind;        /* e.g. "sphere" for `shade bokashi sphere` */
  ShadeToon toon;             /* also holds specular/shininess/ambient for phong etc. */
  int lit;                    /* shade flat: 0 = unlit, the base colour as it is */
  ShadeBokashi bokashi;
  ShadeThreshold threshold;   /* shade threshold: its layers and strength */
  /* shade origami */
  int origami_mode;           /* 0 line, 1 illustration, 2 shaded */
  Color origami_color;        /* linear like every colour; default is Mitani's display (1, 1, 0.95) */
  double origami_weights[3];  /* wa, wb, wc: default 0.675, 0.225, 0.15 */
  double origami_radius;      /* shaded mode's disk, pixels */
  const char *origami_texture;
  ShadeInk ink;
  SrcRange loc;
} SceneShade;

typedef enum { EDGE_SILHOUETTE = 1, EDGE_CREASE = 2, EDGE_BOUNDARY = 4, EDGE_FACE = 8 } EdgeKindBits;
typedef enum { STROKE_PLAIN, STROKE_RIBBON, STROKE_BRUSH } StrokeKind;
/* How visible edges are found and chained: auto (endpoints for brush
** strokes, else reference), the reference image of 001 §2.1.2-2.1.5, or
** the endpoint depth test and 2-px chaining of 003 ch. 2.5 and 3.3. */
typedef enum { LINE_VIS_AUTO, LINE_VIS_REFERENCE, LINE_VIS_ENDPOINTS } LineVisibility;

/* The Chinese brush of 003 ch. 3.4-4.6 (stroke brush). Lengths are output
** pixels. */
/* Most bristles a brush holds (sectors x bristles): the dry brush keeps a
** byte per bristle and pixel of a stroke, 4 KiB a pixel at this size. */
#define SCENE_BRUSH_MAX_BRISTLES 4096
typedef struct SceneBrush {
  double width_step, max_width;  /* width profile: half-width grows by width_step a
                                    control point up to max_width */
  int sectors, bristles;         /* bristles in polar position: sectors x bristles a radius */
  double aspect;                 /* contact ellipse: short axis (along) / long axis (across) */
  double ink_load;               /* ink a bristle deposits per pixel it travels, 0..1 */
  double dry_probability;        /* chance a bristle out of a gap starts a new one */
  int dry_max_gap;               /* a new gap lasts 0..dry_max_gap steps */
  double pressure;               /* brush pressure on a straight run; turns press up to 1 */
} SceneBrush;

typedef struct SceneLines {
  int present;
  unsigned kinds;             /* EdgeKindBits */
  double crease_angle;        /* degrees, for EDGE_CREASE */
  StrokeKind stroke;
  double width;               /* output pixels */
  Color color;
  double opacity;
  const char *texture;        /* built-in name or image path, NULL = default */
  double ref_scale;
  int search_width, max_misses, link_depth;
  double link_angle, miter_limit, min_length, depth_offset;
  LineVisibility visibility;
  int cull_steps;             /* endpoints: most bisection steps toward the visible end */
  double link_distance;       /* endpoints: chain ends this close (output pixels) */
  SceneBrush brush;
  SrcRange loc;
} SceneLines;

/* Does l find its edges by the endpoint test (003) rather than the
** reference image (001)? `visibility auto` picks it for brush strokes. */
static inline int scene_lines_endpoints(const SceneLines *l) {
  return l->visibility == LINE_VIS_ENDPOINTS || (l->visibility == LINE_VIS_AUTO && l->stroke == STROKE_BRUSH);
}

/* A property of a pass that has no field of its own (threshold, bokashi,
** ink, noise, pattern): the schema checked its name and type; the renderer
** reads it with scene_style_param(). */
typedef struct SceneParam {
  const char *pass;           /* "shade", "noise", "pattern" */
  const char *name;
  int n;                      /* numbers: a number, a vector, or a colour's linear r, g, b, a */
  double *num;
  const char *str;            /* a string, or a symbol's name (its arguments in num), else NULL */
  SrcRange loc;
} SceneParam;

/* Most octaves of the procedural noise: its tile holds 8 cells across at
** the first octave, 256 texels, so the fifth octave's cells are 2 texels. */
#define SCENE_MAX_NOISE_OCTAVES 5

/* `noise { }` (001 section 2.2.1): grain added to the object's colour in
** screen space, following its centre. */
typedef struct SceneNoise {
  int present;
  double amount;              /* the largest change of a channel, display units */
  double scale;               /* scene units at the centre: the coarsest grain
                                 (procedural) or one copy of the image's width */
  int seed;
  int octaves;                /* procedural: 1 .. SCENE_MAX_NOISE_OCTAVES */
  const char *image;          /* resolved path of an image, or NULL: procedural */
  const char *image_name;     /* as written, for messages */
  SrcRange loc, image_loc;
} SceneNoise;

typedef enum { PATTERN_OVER, PATTERN_MULTIPLY } PatternBlend;

/* Most stops of a pattern's colour mapping. */
#define SCENE_MAX_PATTERN_COLORS 16

/* `pattern { image "..."; }` (001 section 2.2.2): a printed pattern mapped
** like the noise, under it. */
typedef struct ScenePattern {
  int present;
  const char *image;          /* resolved path (required) */
  const char *image_name;
  double scale;               /* scene units one copy of the image spans */
  double opacity;
  Color *colors; int ncolors; /* colour mapping: the image's grey value indexes this ramp */
  int blend;                  /* PatternBlend */
  SrcRange loc, image_loc;
} ScenePattern;

typedef struct SceneStyle {
  const char *name;           /* NULL for an anonymous style */
  Color base;
  const char *texture;        /* `texture "file"`: an image on the (u, v), resolved against the
                                 scene's folder, in place of base (render/imagemap.h); or NULL */
  const char *texture_name;   /* as written, for messages */
  double texture_repeat;      /* copies of the image across a unit of u and of v (1) */
  SrcRange texture_loc;
  SceneShade shade;
  SceneLines lines;
  SceneNoise noise;
  ScenePattern pattern;
  int nparams;
  SceneParam *params;
  SrcRange loc;
} SceneStyle;

/* ---- geometry -------------------------------------------------------- */

typedef enum { GEOM_PATCHES, GEOM_MESH } GeomKind;

/* A bicubic Bezier patch: 16 control points, rows of 4 along u
** (cp[4 * j + i] is row j, column i). A bilinear patch uses cp[0..3]. */
typedef struct ScenePatch {
  int bilinear;
  Vec3 cp[16];
} ScenePatch;

typedef enum { TESS_UNIFORM, TESS_ADAPTIVE } TessKind;

/* An object that says nothing is tessellated adaptive(1): patches are cut
** until the tessellator's bound on their deviation from the surface is 1
** pixel of the frame (a conservative bound: a sphere filling the frame
** strays 0.4 px at most), so a patch gets the triangles its size on
** screen needs and no more. */
#define SCENE_DEFAULT_TESS_PX 1.0

typedef struct SceneGeometry {
  GeomKind kind;
  int npatches;
  ScenePatch *patches;
  /* GEOM_MESH: an indexed polygon mesh (faces of any size >= 3) */
  int nverts;
  Vec3 *verts;
  int nfaces;
  int *face_start;            /* nfaces + 1 offsets into face_index */
  int *face_index;
  Vec2 *face_uv;              /* per corner (parallel to face_index): an imported mesh's own
                                 texture coordinates, or NULL */
  Vec3 *face_nrm;             /* per corner: unit shading normals a CSG result keeps from its
                                 operands' surfaces, or NULL (normals from the faces) */
  int *face_group;            /* per face: the source face it was cut from (a CSG result's
                                 triangles of one operand polygon or patch), or NULL */
  /* A 2D shape (circle, square, polygon, text and their booleans) when
  ** ncontours > 0: closed contours in the xy-plane, outer boundaries
  ** counter-clockwise and holes clockwise. The mesh above is their
  ** triangulation facing +z, so the shape draws flat; the extrusions read
  ** the contours. */
  int ncontours;
  int *contour_start;         /* ncontours + 1 offsets into contour_pts */
  Vec2 *contour_pts;
  int tess_n;                 /* a CSG operand's `tessellate N` (0: by tolerance) */
  /* subdivision (through OpenSubdiv) when subdiv_level > 0 */
  int subdiv_level;
  const char *subdiv_scheme;  /* "catmark", "loop", "bilinear" */
  const char *subdiv_boundary;/* "edge_and_corner" (NULL), "edge_only", "none" */
  int ncreases;               /* subdivision creases; on a mesh drawn as it is, edges `lines`
                                 draws as creases (a CSG result's intersection curves) */
  struct { int a, b; double sharpness; } *creases;
  int ncorners;
  struct { int v; double sharpness; } *corners;
  SrcRange loc;
} SceneGeometry;

typedef struct SceneObject {
  const char *name;           /* NULL when anonymous */
  SceneGeometry *geometry;
  Mat4 transform;             /* object -> world */
  int style;                  /* index into Scene.styles, -1 = default style */
  TessKind tess_kind;
  int tess_n;                 /* uniform: segments a patch side */
  double tess_px;             /* adaptive: screen tolerance in pixels */
  Vec3 centre;                /* object space; noise, pattern and bokashi follow it */
  int has_centre;
  SrcRange loc;
} SceneObject;

/* ---- origami -------------------------------------------------------- */

/* A crease: an edge of the crease pattern between two vertices, with its
** assignment: 'M' mountain, 'V' valley, 'B' boundary, 'F' flat, 'U' unknown. */
typedef struct OrigamiCrease {
  int a, b;
  char assignment;
  SrcRange loc;
} OrigamiCrease;

/* `above [i, j]`: face i lies over face j where they overlap (toward +z). */
typedef struct OrigamiAbove {
  int upper, lower;
  SrcRange loc;
} OrigamiAbove;

/* An origami block as written (or read from a FOLD file by the evaluator's
** fold_file()). Faces, the folded state and the overlap relation are
** derived later (src/geom/origami.c) when not given. */
typedef struct SceneOrigami {
  const char *name;
  int nverts;
  Vec2 *verts;                /* paper coordinates */
  SrcRange *vert_loc;
  int ncreases;
  OrigamiCrease *creases;
  int nfaces;                 /* 0: derive from the planar graph */
  int *face_start;            /* nfaces + 1 offsets into face_index */
  int *face_index;
  SrcRange *face_loc;
  int has_folded;
  Vec3 *folded;               /* nverts folded positions (z ignored: flat) */
  int fixed;                  /* face that keeps its paper position */
  int nabove;
  OrigamiAbove *above;
  int noverlap;               /* rows of the full matrix, 0 if not given */
  const char **overlap;       /* "-UL" strings, one per face */
  SrcRange overlap_loc;
  int overlap_auto;           /* `overlap auto`: the layer-order solver finds the relation */
  long state;                 /* with overlap_auto: which of its states (0 = the first found) */
  SrcRange state_loc;
  const char *fold_file;      /* the FOLD file it came from, or NULL */
  Mat4 transform;
  int style;                  /* index into Scene.styles, -1 = default */
  SrcRange loc;
} SceneOrigami;

typedef struct Scene {
  Arena arena;
  SceneOutput output;
  SceneCamera camera;
  int nlights; SceneLight *lights;
  int nstyles; SceneStyle *styles;
  int nobjects; SceneObject *objects;
  int norigami; SceneOrigami *origami;
  double clock; int frame;
} Scene;

void scene_init(Scene *s);
void scene_free(Scene *s);
/* The clock of frame `frame` of an animation of frames first..last: 0 at
** the first and 1 at the last; with loop, 0 at the first and
** (n - 1) / n at the last of n, so that the frame after the last would be
** the first again (a loop of n frames repeats with period 1). 0 for a
** single frame. */
double scene_frame_clock(int first, int last, int frame, int loop);
/* The style every object without one gets. */
SceneStyle scene_default_style(void);
/* shade ink's defaults (Yeh ch. 5.2) and the sheet's (ch. 6), as the
** schema fills them for a block that sets nothing. */
ShadeInk scene_default_ink(void);
SceneSheet scene_default_sheet(void);
/* A pass parameter without a field of its own, or NULL when not given. */
const SceneParam *scene_style_param(const SceneStyle *s, const char *pass, const char *name);

/* Whether pred holds for a name of an image the scene may read: a line or
** origami texture, a texture parameter (noise, pattern, threshold), the
** output sheet (built-in names included: pred tells them apart). */
int scene_any_image(const Scene *s, int (*pred)(const char *name));

#endif
