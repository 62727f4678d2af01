/*
** Values of the .npr language: a 16-byte tagged union. Numbers and bools
** live inline; everything else points into the evaluator's arena (values
** are immutable, so sharing is safe and nothing is freed until the end).
*/
#ifndef lang_value_h
#define lang_value_h

#include <stdint.h>
#include <stdio.h>

#include "../base/vec.h"
#include "../scene/scene.h"

typedef enum {
  V_UNDEF, V_BOOL, V_NUM, V_STR, V_LIST, V_RANGE, V_COLOR, V_XFORM,
  V_FUNC,      /* a closure or a builtin function */
  V_MODULE,    /* a module (not a first-class value: only callable as a statement) */
  V_GEOM,      /* a geometry block value (SceneGeometry) */
  V_STYLE,     /* a style: index into Scene.styles */
  V_SYMBOL,    /* a bare word in a property, maybe with arguments: crease(40) */
  V_PAPER,     /* a crease pattern read by fold_file() (SceneOrigami) */
  V_UNSET,     /* internal: a slot whose let has not run yet */
  V_ERR        /* internal: an error was reported; propagate quietly */
} ValueKind;

typedef struct Str { int len; char s[]; } Str;
typedef struct List List;
typedef struct Range { double start, step, end; } Range;
typedef struct Closure Closure;
typedef struct Symbol { const char *name; List *args; } Symbol;

typedef struct Value {
  uint32_t kind;
  int32_t aux;          /* V_STYLE: style index */
  union {
    double n;           /* V_NUM, V_BOOL (0/1) */
    Str *s;
    List *l;
    Range *r;
    Color *c;           /* linear RGBA */
    Mat4 *m;
    Closure *f;
    SceneGeometry *g;
    Symbol *sym;
    SceneOrigami *paper;
  } u;
} Value;

/* v points just past the header, or (a long list built by a comprehension)
** at the evaluator's scratch buffer, taken over to save a copy. */
struct List { int n; Value *v; };

static inline Value val_num(double n) { Value v; v.kind = V_NUM; v.aux = 0; v.u.n = n; return v; }
static inline Value val_bool(int b) { Value v; v.kind = V_BOOL; v.aux = 0; v.u.n = b ? 1 : 0; return v; }
static inline Value val_undef(void) { Value v; v.kind = V_UNDEF; v.aux = 0; v.u.n = 0; return v; }
static inline Value val_err(void) { Value v; v.kind = V_ERR; v.aux = 0; v.u.n = 0; return v; }
static inline Value val_unset(void) { Value v; v.kind = V_UNSET; v.aux = 0; v.u.n = 0; return v; }
static inline Value val_ptr(ValueKind k, void *p) {
  Value v; v.kind = k; v.aux = 0; v.u.s = p; return v;
}

/* The type name users see in messages ("number", "list", ...). */
const char *val_type_name(const Value *v);
/* OpenSCAD truthiness: false, 0, "", [], undef are false. */
int val_truthy(const Value *v);
/* Structural equality (== in the language); different kinds are unequal. */
int val_equal(const Value *a, const Value *b);
/* Number of elements of a range (0 when empty); the step is not 0. */
double val_range_count(const Range *r);

/* Print a value as echo() does (OpenSCAD 2021 text); strings quoted unless
** raw (str() prints top-level strings raw). */
void val_print(FILE *out, const Value *v, int raw);
/* The same into a growing malloc'd buffer. */
/* Text built a piece at a time. With max set, it holds at most max bytes;
** with max_work set, val_format visits at most max_work values (a raw
** string costs one a 16 bytes), counted in work. What would go past is
** dropped and over set (SB_OVER_BYTES or SB_OVER_WORK), and val_format
** stops early, so a huge value costs no more than the limits. */
enum { SB_OVER_BYTES = 1, SB_OVER_WORK = 2 };
typedef struct StrBuf { char *s; size_t len, cap, max; long long work, max_work; int over; } StrBuf;
void sb_putc(StrBuf *b, char c);
void sb_putn(StrBuf *b, const char *s, size_t n);
void sb_puts(StrBuf *b, const char *s);
void sb_printf(StrBuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void val_format(StrBuf *b, const Value *v, int raw);
/* A number as OpenSCAD 2021 prints it: %g with 6 digits, exponent unpadded. */
void val_format_number(char *buf, size_t n, double x);

/* sRGB <-> linear transfer for one component. */
double val_srgb_to_linear(double c);
/* A point: [x, y, z] or [x, y] (z = 0) of numbers; 0 when v is not one. */
int val_to_point(const Value *v, Vec3 *out);
double val_linear_to_srgb(double c);

#endif
