/*
** Block schemas: one table per block kind (output, camera, light, style,
** shade <kind>, lines, noise, pattern, object, origami, paper) giving each
** property's name, type, range, default, and whether it may repeat. The
** evaluator hands finished blocks to schema_emit, which checks them and
** fills the Scene. Adding a property is one table row in schema.c.
*/
#ifndef lang_schema_h
#define lang_schema_h

#include "eval_int.h"

/* Largest image side `output { size [w, h]; }` may ask for. */
#define SCHEMA_MAX_IMAGE_SIDE 16384
/* Most segments a patch side `tessellate N` may ask for. */
#define SCHEMA_MAX_TESSELLATE 256
/* Most samples a pixel side `samples N` may ask for. */
#define SCHEMA_MAX_SAMPLES 16

/* Largest side of a shadow map `shadow_resolution N` may ask for (a float
** map of 8192 x 8192 is 256 MiB; render/shadow.h bounds a frame's total). */
#define SCHEMA_MAX_SHADOW_RESOLUTION 8192

/* Most points a strength curve (`facing`, `light` in shade threshold) may have. */
#define SCHEMA_MAX_CURVE 64

int schema_emit(Eval *ev, BlockVal *b);
/* An object made by a statement (`cube(1);`, `difference() { ... }`):
** geometry g placed by transform, with like's style, name and settings
** (a CSG result keeps its first operand's), or the defaults when like is
** NULL. */
void schema_emit_object(Eval *ev, const SceneObject *like, SceneGeometry *g, Mat4 transform, SrcRange loc);
/* The checks that need the whole scene, once every block is in: the
** lights a shade ink style names (a light may come after the style). */
void schema_finish(Eval *ev);
int schema_wants_symbol(const char *kind, const char *word, const char *prop);
/* Whether name is one of the words property prop of block kind (word: its
** sub-kind) knows. A bare word there that it does not know and that names
** a variable in scope is that variable's value, so `let m = "line"; mode
** m;` works and -D can switch a mode. */
int schema_knows_word(const char *kind, const char *word, const char *prop, const char *name);
int schema_known_kind(const char *kind);

#endif
