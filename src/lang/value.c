/*
** Values: type names, truthiness, equality, and the echo() text format
** (OpenSCAD 2021's, so scripts and tests read the same in both).
*/
#include "value.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

const char *val_type_name(const Value *v) {
  switch ((ValueKind)v->kind) {
  case V_UNDEF: return "undef";
  case V_BOOL: return "bool";
  case V_NUM: return "number";
  case V_STR: return "string";
  case V_LIST: return "list";
  case V_RANGE: return "range";
  case V_COLOR: return "colour";
  case V_XFORM: return "transform";
  case V_FUNC: return "function";
  case V_MODULE: return "module";
  case V_GEOM: return "geometry";
  case V_STYLE: return "style";
  case V_SYMBOL: return "symbol";
  case V_PAPER: return "crease pattern";
  case V_UNSET: return "undefined value";
  case V_ERR: return "error";
  }
  return "?";
}

int val_truthy(const Value *v) {
  switch ((ValueKind)v->kind) {
  case V_UNDEF: case V_UNSET: case V_ERR: return 0;
  case V_BOOL: case V_NUM: return v->u.n != 0;
  case V_STR: return v->u.s->len > 0;
  case V_LIST: return v->u.l->n > 0;
  default: return 1;
  }
}

double val_range_count(const Range *r) {
  double span = (r->end - r->start) / r->step;
  if (!(span >= 0)) return 0;   /* step points away from the end (or NaN) */
  /* a hair of tolerance so [0:0.1:1] has 11 elements despite rounding */
  return floor(span + 1e-9) + 1;
}

static int list_equal(const List *a, const List *b) {
  if (a->n != b->n) return 0;
  for (int i = 0; i < a->n; i++)
    if (!val_equal(&a->v[i], &b->v[i])) return 0;
  return 1;
}

int val_equal(const Value *a, const Value *b) {
  if (a->kind != b->kind) return 0;
  switch ((ValueKind)a->kind) {
  case V_UNDEF: return 1;
  case V_BOOL: case V_NUM: return a->u.n == b->u.n;
  case V_STR: return a->u.s->len == b->u.s->len && memcmp(a->u.s->s, b->u.s->s, (size_t)a->u.s->len) == 0;
  case V_LIST: return list_equal(a->u.l, b->u.l);
  case V_RANGE: return a->u.r->start == b->u.r->start && a->u.r->step == b->u.r->step &&
                       a->u.r->end == b->u.r->end;
  case V_COLOR: return memcmp(a->u.c, b->u.c, sizeof(Color)) == 0;
  case V_XFORM: return memcmp(a->u.m, b->u.m, sizeof(Mat4)) == 0;
  case V_STYLE: return a->aux == b->aux;
  case V_SYMBOL: return strcmp(a->u.sym->name, b->u.sym->name) == 0;
  default: return a->u.s == b->u.s;   /* functions, geometry: identity */
  }
}

/* ---- text ----------------------------------------------------------- */

void sb_putn(StrBuf *b, const char *s, size_t n) {
  if (b->over) return;
  if (b->max && n > b->max - b->len) { b->over = SB_OVER_BYTES; return; }
  if (b->len + n + 1 > b->cap) {
    size_t cap = b->cap ? b->cap : 64;
    while (cap < b->len + n + 1) cap *= 2;
    if (b->max && cap > b->max + 1) cap = b->max + 1;   /* never more than max asks */
    b->s = xrealloc(b->s, b->cap = cap);
  }
  memcpy(b->s + b->len, s, n);
  b->len += n;
  b->s[b->len] = 0;
}

void sb_putc(StrBuf *b, char c) { sb_putn(b, &c, 1); }

void sb_puts(StrBuf *b, const char *s) {
  sb_putn(b, s, strlen(s));
}

void sb_printf(StrBuf *b, const char *fmt, ...) {
  char tmp[256];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(tmp, sizeof tmp, fmt, ap);
  va_end(ap);
  sb_puts(b, tmp);
}

/* Drop trailing zeros after a decimal point, and the point itself. */
static void strip_zeros(char *s) {
  if (!strchr(s, '.')) return;
  size_t n = strlen(s);
  while (n > 0 && s[n - 1] == '0') s[--n] = 0;
  if (n > 0 && s[n - 1] == '.') s[--n] = 0;
}

/* Six significant digits; fixed notation for exponents -5..5, otherwise
** scientific with an unpadded exponent (1e+6, 1e-6), trailing zeros dropped:
** what OpenSCAD 2021 prints. */
void val_format_number(char *buf, size_t n, double x) {
  if (isnan(x)) { snprintf(buf, n, "nan"); return; }
  if (isinf(x)) { snprintf(buf, n, x < 0 ? "-inf" : "inf"); return; }
  if (x == 0) { snprintf(buf, n, "0"); return; }   /* also -0 */
  char sci[64];
  snprintf(sci, sizeof sci, "%.5e", x);            /* rounded mantissa, exponent */
  char *e = strchr(sci, 'e');
  int ex = atoi(e + 1);
  char out[128];
  if (ex < -5 || ex >= 6) {
    *e = 0;
    strip_zeros(sci);
    snprintf(out, sizeof out, "%se%c%d", sci, ex < 0 ? '-' : '+', abs(ex));
  } else {
    snprintf(out, sizeof out, "%.*f", 5 - ex, x);
    strip_zeros(out);
  }
  snprintf(buf, n, "%s", out);
}

static void format_string(StrBuf *b, const Str *s) {
  sb_putc(b, '"');
  for (int i = 0; i < s->len && !b->over; i++) {
    char c = s->s[i];
    if (c == '"' || c == '\\') { sb_putc(b, '\\'); sb_putc(b, c); }
    else if (c == '\n') sb_puts(b, "\\n");
    else if (c == '\t') sb_puts(b, "\\t");
    else sb_putc(b, c);
  }
  sb_putc(b, '"');
}

static void format_color(StrBuf *b, const Color *c) {
  double ch[4] = {val_linear_to_srgb(c->r), val_linear_to_srgb(c->g), val_linear_to_srgb(c->b), c->a};
  sb_putc(b, '#');
  for (int i = 0; i < 4; i++) {
    double x = ch[i] < 0 ? 0 : ch[i] > 1 ? 1 : ch[i];
    sb_printf(b, "%02x", (int)lround(x * 255));
  }
}

static void format_matrix(StrBuf *b, const Mat4 *m) {
  char num[32];
  sb_putc(b, '[');
  for (int i = 0; i < 4; i++) {
    sb_puts(b, i ? ", [" : "[");
    for (int j = 0; j < 4; j++) {
      val_format_number(num, sizeof num, m->m[i][j]);
      if (j) sb_puts(b, ", ");
      sb_puts(b, num);
    }
    sb_putc(b, ']');
  }
  sb_putc(b, ']');
}

void val_format(StrBuf *b, const Value *v, int raw) {
  char num[32];
  if (b->max_work && ++b->work > b->max_work) b->over = SB_OVER_WORK;
  if (b->over) return;
  switch ((ValueKind)v->kind) {
  case V_UNDEF: case V_UNSET: case V_ERR: sb_puts(b, "undef"); break;
  case V_BOOL: sb_puts(b, v->u.n ? "true" : "false"); break;
  case V_NUM: val_format_number(num, sizeof num, v->u.n); sb_puts(b, num); break;
  case V_STR:
    if (raw) {
      b->work += v->u.s->len / 16;
      sb_putn(b, v->u.s->s, (size_t)v->u.s->len);
    }
    else format_string(b, v->u.s);
    break;
  case V_LIST:
    sb_putc(b, '[');
    for (int i = 0; i < v->u.l->n && !b->over; i++) {
      if (i) sb_puts(b, ", ");
      val_format(b, &v->u.l->v[i], 0);
    }
    sb_putc(b, ']');
    break;
  case V_RANGE: {
    char s1[32], s2[32], s3[32];
    val_format_number(s1, sizeof s1, v->u.r->start);
    val_format_number(s2, sizeof s2, v->u.r->step);
    val_format_number(s3, sizeof s3, v->u.r->end);
    sb_printf(b, "[%s : %s : %s]", s1, s2, s3);
    break;
  }
  case V_COLOR: format_color(b, v->u.c); break;
  case V_XFORM: format_matrix(b, v->u.m); break;
  case V_FUNC: sb_puts(b, "function"); break;
  case V_MODULE: sb_puts(b, "module"); break;
  case V_GEOM:
    if (v->u.g->kind == GEOM_PATCHES) sb_printf(b, "geometry(%d patches)", v->u.g->npatches);
    else sb_printf(b, "geometry(%d vertices, %d faces)", v->u.g->nverts, v->u.g->nfaces);
    break;
  case V_STYLE: sb_printf(b, "style(%d)", v->aux); break;
  case V_PAPER: sb_printf(b, "paper(%d vertices)", v->u.paper->nverts); break;
  case V_SYMBOL:
    sb_puts(b, v->u.sym->name);
    if (v->u.sym->args) {
      Value l = val_ptr(V_LIST, v->u.sym->args);
      StrBuf t = {.max = b->max};
      val_format(&t, &l, 0);
      if (t.over) { b->over = 1; free(t.s); break; }
      t.s[t.len - 1] = ')';
      t.s[0] = '(';
      sb_puts(b, t.s);
      free(t.s);
    }
    break;
  }
}

void val_print(FILE *out, const Value *v, int raw) {
  StrBuf b = {0};
  val_format(&b, v, raw);
  if (b.s) fwrite(b.s, 1, b.len, out);
  free(b.s);
}

int val_to_point(const Value *v, Vec3 *out) {
  if (v->kind != V_LIST || v->u.l->n < 2 || v->u.l->n > 3) return 0;
  double c[3] = {0, 0, 0};
  for (int i = 0; i < v->u.l->n; i++) {
    if (v->u.l->v[i].kind != V_NUM) return 0;
    c[i] = v->u.l->v[i].u.n;
  }
  *out = v3(c[0], c[1], c[2]);
  return 1;
}

double val_srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

double val_linear_to_srgb(double c) {
  return c <= 0.0031308 ? c * 12.92 : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}
