/*
** Builtin functions. Each takes its arguments already bound to positions
** (V_UNSET where an optional one was not given) and reports type errors at
** the offending argument: "`sqrt` expects a number as argument 1; found a
** string". Written bottom-up: argument helpers, then each family, then the
** table (the one place a builtin is registered).
**
** Conventions a user relies on: angles in degrees; round() sends halves
** away from zero; log is base 10, ln natural; range(a, b, step) and
** slice(list, a, b) exclude b (as Python), range(n) is [0, ..., n-1];
** search is OpenSCAD 2021's; rands uses PCG32. Builtins sharing OpenSCAD's
** names answer as OpenSCAD 2021's do, except where the language reference
** says why not (an error where OpenSCAD warns and gives undef).
*/
#include "builtins.h"

#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "../base/rng.h"
#include "../base/utf8.h"

#include "../geom/subdiv.h"
#include "../io/crease.h"
#include "../io/fold.h"
#include "../io/mesh_import.h"

/* Subdivision multiplies faces by 4 a level; 6 levels is 4096 faces for
** every input quad, already finer than any pixel at 1080p for a sane mesh. */
#define EVAL_MAX_SUBDIV_LEVEL 6

/* ---- argument helpers ------------------------------------------------- */

SrcRange bi_arg_loc(const ENode *call, int i) {
  return i < call->n ? call->kids[i]->range : call->range;
}

const char *bi_name(const ENode *call) {
  return call->what ? call->what : "this function";
}

static const char *article(const Value *v) {
  const char *t = val_type_name(v);
  return strchr("aeiou", t[0]) ? "an" : "a";
}

int bi_type_error(Eval *ev, const ENode *call, int i, const char *want, const Value *v) {
  ev_error(ev, bi_arg_loc(call, i), "`%s` expects %s as argument %d; found %s %s", bi_name(call), want, i + 1,
           article(v), val_type_name(v));
  return -1;
}

int bi_num(Eval *ev, Value *a, int i, const ENode *call, double *out) {
  *out = 0;
  if (a[i].kind == V_NUM) { *out = a[i].u.n; return 0; }
  return bi_type_error(ev, call, i, "a number", &a[i]);
}

int bi_opt_num(Eval *ev, Value *a, int i, const ENode *call, double def, double *out) {
  *out = def;
  if (a[i].kind == V_UNSET || a[i].kind == V_UNDEF) { *out = def; return 0; }
  return bi_num(ev, a, i, call, out);
}

int bi_list(Eval *ev, Value *a, int i, const ENode *call, List **out) {
  *out = NULL;
  if (a[i].kind == V_LIST) { *out = a[i].u.l; return 0; }
  return bi_type_error(ev, call, i, "a list", &a[i]);
}

static int vec3_finite(Vec3 p) { return isfinite(p.x) && isfinite(p.y) && isfinite(p.z); }

int bi_vec3(Eval *ev, Value *a, int i, const ENode *call, Vec3 *out) {
  *out = v3(0, 0, 0);
  if (val_to_point(&a[i], out)) return 0;
  return bi_type_error(ev, call, i, "a point [x, y, z]", &a[i]);
}

static Value num_list(Eval *ev, const double *x, int n) {
  List *l = ev_list(ev, n);
  for (int i = 0; i < n; i++) l->v[i] = val_num(x[i]);
  return val_ptr(V_LIST, l);
}

static Value vec3_value(Eval *ev, Vec3 p) {
  double x[3] = {p.x, p.y, p.z};
  return num_list(ev, x, 3);
}

/* ---- math --------------------------------------------------------------- */

/* Exact at multiples of 90 degrees, so sin(180) is 0, not 1.2e-16. */
static double sin_deg(double d) {
  double q = fmod(d, 360.0);
  if (q < 0) q += 360.0;
  if (q == 0 || q == 180) return 0;
  if (q == 90) return 1;
  if (q == 270) return -1;
  return sin(d * M_PI / 180.0);
}

static double cos_deg(double d) { return sin_deg(d + 90.0); }
static double tan_deg(double d) {
  double c = cos_deg(d);
  return c == 0 ? (sin_deg(d) > 0 ? INFINITY : -INFINITY) : sin_deg(d) / c;
}

typedef double (*Math1)(double);
static double asin_deg(double x) { return asin(x) * 180.0 / M_PI; }
static double acos_deg(double x) { return acos(x) * 180.0 / M_PI; }
static double atan_deg(double x) { return atan(x) * 180.0 / M_PI; }
static double sign_of(double x) { return x > 0 ? 1 : x < 0 ? -1 : 0; }

/* One-argument math by name; applied element-wise to vectors. */
static Value math1(Eval *ev, Value v, Math1 f, const ENode *call) {
  if (v.kind == V_NUM) return val_num(f(v.u.n));
  if (v.kind == V_LIST) {
    List *l = ev_list(ev, v.u.l->n);
    for (int i = 0; i < v.u.l->n; i++)
      if ((l->v[i] = math1(ev, v.u.l->v[i], f, call)).kind == V_ERR) return val_err();
    return val_ptr(V_LIST, l);
  }
  bi_type_error(ev, call, 0, "a number or a vector", &v);
  return val_err();
}

#define MATH1(cname, f) \
  static Value cname(Eval *ev, Value *a, int n, const ENode *call) { return math1(ev, a[0], f, call); }
MATH1(bi_sin, sin_deg) MATH1(bi_cos, cos_deg) MATH1(bi_tan, tan_deg)
MATH1(bi_asin, asin_deg) MATH1(bi_acos, acos_deg) MATH1(bi_atan, atan_deg)
MATH1(bi_sqrt, sqrt) MATH1(bi_exp, exp) MATH1(bi_ln, log) MATH1(bi_log10, log10)
MATH1(bi_abs, fabs) MATH1(bi_sign, sign_of) MATH1(bi_floor, floor) MATH1(bi_ceil, ceil)
MATH1(bi_round, round)

/* log(x) is base 10; log(b, x) is base b (OpenSCAD 2021's two-argument form). */
static Value bi_log(Eval *ev, Value *a, int n, const ENode *call) {
  if (a[1].kind == V_UNSET) return bi_log10(ev, a, n, call);
  double b, x;
  if (bi_num(ev, a, 0, call, &b) || bi_num(ev, a, 1, call, &x)) return val_err();
  return val_num(log(x) / log(b));
}

static Value bi_atan2(Eval *ev, Value *a, int n, const ENode *call) {
  double y, x;
  if (bi_num(ev, a, 0, call, &y) || bi_num(ev, a, 1, call, &x)) return val_err();
  return val_num(atan2(y, x) * 180.0 / M_PI);
}

static Value bi_pow(Eval *ev, Value *a, int n, const ENode *call) {
  double x, y;
  if (bi_num(ev, a, 0, call, &x) || bi_num(ev, a, 1, call, &y)) return val_err();
  return val_num(pow(x, y));
}

/* min/max of the arguments, or of one list argument. */
static Value minmax(Eval *ev, Value *a, int n, const ENode *call, int want_max) {
  Value *v = a;
  if (n == 1 && a[0].kind == V_LIST) { v = a[0].u.l->v; n = a[0].u.l->n; }
  if (n == 0) return val_undef();
  double best = 0;
  for (int i = 0; i < n; i++) {
    if (v[i].kind != V_NUM) {
      bi_type_error(ev, call, v == a ? i : 0, "numbers (or one list of numbers)", &v[i]);
      return val_err();
    }
    if (i == 0 || (want_max ? v[i].u.n > best : v[i].u.n < best)) best = v[i].u.n;
  }
  return val_num(best);
}

static Value bi_min(Eval *ev, Value *a, int n, const ENode *call) { return minmax(ev, a, n, call, 0); }
static Value bi_max(Eval *ev, Value *a, int n, const ENode *call) { return minmax(ev, a, n, call, 1); }

static Value bi_clamp(Eval *ev, Value *a, int n, const ENode *call) {
  double x, lo, hi;
  if (bi_num(ev, a, 0, call, &x) || bi_num(ev, a, 1, call, &lo) || bi_num(ev, a, 2, call, &hi)) return val_err();
  return val_num(x < lo ? lo : x > hi ? hi : x);
}

static Value bi_smoothstep(Eval *ev, Value *a, int n, const ENode *call) {
  double e0, e1, x;
  if (bi_num(ev, a, 0, call, &e0) || bi_num(ev, a, 1, call, &e1) || bi_num(ev, a, 2, call, &x)) return val_err();
  double t = e1 == e0 ? (x < e0 ? 0 : 1) : (x - e0) / (e1 - e0);
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  return val_num(t * t * (3 - 2 * t));
}

/* lerp(a, b, t) = a + (b - a) * t on numbers, vectors and colours. */
static Value bi_lerp(Eval *ev, Value *a, int n, const ENode *call) {
  double t;
  if (bi_num(ev, a, 2, call, &t)) return val_err();
  if (a[0].kind == V_NUM && a[1].kind == V_NUM) return val_num(a[0].u.n + (a[1].u.n - a[0].u.n) * t);
  if (a[0].kind == V_COLOR && a[1].kind == V_COLOR) {
    const Color *p = a[0].u.c, *q = a[1].u.c;
    return ev_color(ev, p->r + (q->r - p->r) * t, p->g + (q->g - p->g) * t, p->b + (q->b - p->b) * t,
                    p->a + (q->a - p->a) * t);
  }
  if (a[0].kind == V_LIST && a[1].kind == V_LIST && a[0].u.l->n == a[1].u.l->n) {
    List *l = ev_list(ev, a[0].u.l->n);
    for (int i = 0; i < l->n; i++) {
      Value x = a[0].u.l->v[i], y = a[1].u.l->v[i];
      if (x.kind != V_NUM || y.kind != V_NUM) {
        bi_type_error(ev, call, 0, "two vectors of numbers", &x);
        return val_err();
      }
      l->v[i] = val_num(x.u.n + (y.u.n - x.u.n) * t);
    }
    return val_ptr(V_LIST, l);
  }
  ev_error(ev, call->range, "`lerp` expects two numbers, two vectors of one length or two colours; found %s %s and %s %s",
           article(&a[0]), val_type_name(&a[0]), article(&a[1]), val_type_name(&a[1]));
  return val_err();
}

/* ---- vectors ------------------------------------------------------------- */

static int num_vector(Eval *ev, Value *a, int i, const ENode *call, List **out) {
  if (bi_list(ev, a, i, call, out)) return -1;
  for (int k = 0; k < (*out)->n; k++)
    if ((*out)->v[k].kind != V_NUM) return bi_type_error(ev, call, i, "a vector of numbers", &a[i]);
  return 0;
}

static Value bi_dot(Eval *ev, Value *a, int n, const ENode *call) {
  List *x, *y;
  if (num_vector(ev, a, 0, call, &x) || num_vector(ev, a, 1, call, &y)) return val_err();
  if (x->n != y->n) {
    ev_error(ev, call->range, "`dot` needs vectors of one length; found %d and %d", x->n, y->n);
    return val_err();
  }
  double s = 0;
  for (int i = 0; i < x->n; i++) s += x->v[i].u.n * y->v[i].u.n;
  return val_num(s);
}

/* cross(a, b) of 3-vectors; of 2-vectors, the number a.x b.y - a.y b.x (as OpenSCAD). */
static Value bi_cross(Eval *ev, Value *a, int n, const ENode *call) {
  List *x, *y;
  if (a[0].kind == V_LIST && a[1].kind == V_LIST && (x = a[0].u.l)->n == 2 && (y = a[1].u.l)->n == 2 &&
      x->v[0].kind == V_NUM && x->v[1].kind == V_NUM && y->v[0].kind == V_NUM && y->v[1].kind == V_NUM)
    return val_num(x->v[0].u.n * y->v[1].u.n - x->v[1].u.n * y->v[0].u.n);
  Vec3 p, q;
  if (bi_vec3(ev, a, 0, call, &p) || bi_vec3(ev, a, 1, call, &q)) return val_err();
  return vec3_value(ev, v3_cross(p, q));
}

static Value bi_norm(Eval *ev, Value *a, int n, const ENode *call) {
  List *x;
  if (num_vector(ev, a, 0, call, &x)) return val_err();
  double s = 0;
  for (int i = 0; i < x->n; i++) s += x->v[i].u.n * x->v[i].u.n;
  return val_num(sqrt(s));
}

static Value bi_normalize(Eval *ev, Value *a, int n, const ENode *call) {
  Value len = bi_norm(ev, a, n, call);
  if (len.kind == V_ERR) return len;
  List *x = a[0].u.l, *l = ev_list(ev, x->n);
  for (int i = 0; i < x->n; i++) l->v[i] = val_num(len.u.n > 0 ? x->v[i].u.n / len.u.n : 0);
  return val_ptr(V_LIST, l);
}

/* ---- lists and strings ---------------------------------------------------- */

static int utf8_count(const Str *s) {
  int n = 0;
  for (int i = 0; i < s->len; i++) n += ((unsigned char)s->s[i] & 0xC0) != 0x80;
  return n;
}

static Value bi_len(Eval *ev, Value *a, int n, const ENode *call) {
  switch (a[0].kind) {
  case V_LIST: return val_num(a[0].u.l->n);
  case V_STR: return val_num(utf8_count(a[0].u.s));
  case V_RANGE: return val_num(val_range_count(a[0].u.r));
  default: bi_type_error(ev, call, 0, "a list, a string or a range", &a[0]); return val_err();
  }
}

static Value bi_concat(Eval *ev, Value *a, int n, const ENode *call) {
  long long total = 0;
  for (int i = 0; i < n; i++) total += a[i].kind == V_LIST ? a[i].u.l->n : 1;
  if (ev_list_limit(ev, total, call->range)) return val_err();
  List *l = ev_list(ev, (int)total);
  int k = 0;
  for (int i = 0; i < n; i++) {
    if (a[i].kind != V_LIST) { l->v[k++] = a[i]; continue; }
    memcpy(l->v + k, a[i].u.l->v, (size_t)a[i].u.l->n * sizeof(Value));
    k += a[i].u.l->n;
  }
  return val_ptr(V_LIST, l);
}

static Value bi_reverse(Eval *ev, Value *a, int n, const ENode *call) {
  if (a[0].kind == V_STR) {
    const Str *s = a[0].u.s;
    Value out = ev_str(ev, s->s, s->len);
    char *d = out.u.s->s;
    for (int i = 0; i < s->len;) {   /* reverse by characters, keeping UTF-8 intact */
      int j = i + 1;
      while (j < s->len && ((unsigned char)s->s[j] & 0xC0) == 0x80) j++;
      memcpy(d + s->len - j, s->s + i, (size_t)(j - i));
      i = j;
    }
    return out;
  }
  List *x;
  if (bi_list(ev, a, 0, call, &x)) return val_err();
  List *l = ev_list(ev, x->n);
  for (int i = 0; i < x->n; i++) l->v[i] = x->v[x->n - 1 - i];
  return val_ptr(V_LIST, l);
}

/* slice(list, start, end = len): elements start .. end-1; negative
** positions count from the end. */
static Value bi_slice(Eval *ev, Value *a, int n, const ENode *call) {
  List *x;
  double s, e;
  if (bi_list(ev, a, 0, call, &x) || bi_num(ev, a, 1, call, &s) || bi_opt_num(ev, a, 2, call, x->n, &e))
    return val_err();
  double d0 = floor(s), d1 = floor(e);   /* clamped as doubles: 1e30 fits no integer */
  if (d0 < 0) d0 += x->n;
  if (d1 < 0) d1 += x->n;
  if (!(d0 > 0)) d0 = 0;
  if (!(d1 < x->n)) d1 = isnan(d1) ? 0 : x->n;
  int i0 = d0 < x->n ? (int)d0 : x->n, i1 = d1 > 0 ? (int)d1 : 0;
  int m = i1 > i0 ? i1 - i0 : 0;
  List *l = ev_list(ev, m);
  if (m) memcpy(l->v, x->v + i0, (size_t)m * sizeof(Value));
  return val_ptr(V_LIST, l);
}

static Value bi_range(Eval *ev, Value *a, int n, const ENode *call) {
  double lo = 0, hi, step;
  if (a[1].kind == V_UNSET) { if (bi_num(ev, a, 0, call, &hi)) return val_err(); }
  else if (bi_num(ev, a, 0, call, &lo) || bi_num(ev, a, 1, call, &hi)) return val_err();
  if (bi_opt_num(ev, a, 2, call, 1, &step)) return val_err();
  if (step == 0) {
    ev_error(ev, bi_arg_loc(call, 2), "`range` needs a step other than 0");
    return val_err();
  }
  double count = ceil((hi - lo) / step);
  if (!(count > 0)) count = 0;
  if (ev_list_limit(ev, count, call->range)) return val_err();
  List *l = ev_list(ev, (int)count);
  for (int i = 0; i < l->n; i++) l->v[i] = val_num(lo + i * step);
  return val_ptr(V_LIST, l);
}

/* ---- search (OpenSCAD 2021's) -------------------------------------------- */

/* search(match, table, num_returns = 1, index_col = 0) answers as OpenSCAD
** 2021's does. An element of a list table matches a value when it equals
** it (with index_col 0), or when it is a list whose index_col-th entry
** equals it. A number gives the flat list of matching indices (the first
** num_returns of them; 0: all). A list gives one result per element: with
** num_returns 1 the index (or [] when absent), else the list of indices.
** A string is searched character by character: in a string, for the
** equal characters; in a list, for the entries whose index_col-th value
** begins with that character (an entry with fewer values makes the whole
** answer []); with num_returns 1 an absent character gives nothing, else
** []. Anything else to find gives undef. */
typedef struct Search {
  Eval *ev;
  const Value *table;   /* a list table's elements, or NULL */
  const uint32_t *chars;/* a string table's code points, or NULL */
  int n;                /* elements or code points */
  unsigned limit;       /* matches wanted for one value; 0: all */
  int col;
  int *hit, nhit, cap;  /* the indices found for the value being searched */
  const ENode *call;
  int failed;           /* the iteration limit was hit */
} Search;

/* Count a scan of j table entries (search's inner loop) against the limit. */
static void search_steps(Search *s, int j) {
  if (!s->failed && ev_steps(s->ev, j, s->call->range, "`search`")) s->failed = 1;
}

static Value hits_list(Search *s) {
  List *l = ev_list(s->ev, s->nhit);
  for (int i = 0; i < s->nhit; i++) l->v[i] = val_num(s->hit[i]);
  return val_ptr(V_LIST, l);
}

static void add_hit(Search *s, int j) {
  s->hit = xgrow(s->hit, &s->cap, s->nhit + 1, sizeof *s->hit);
  s->hit[s->nhit++] = j;
}

static int more(const Search *s) { return s->limit == 0 || (unsigned)s->nhit < s->limit; }

/* The code points of UTF-8 text t into a new array; *n of them. */
static uint32_t *code_points(const char *t, int *n) {
  size_t len = strlen(t);
  uint32_t *cp = xmalloc((len + 1) * sizeof *cp);
  const unsigned char *p = (const unsigned char *)t, *end = p + len;
  *n = 0;
  while (p < end) {
    int k = utf8_decode(p, end, &cp[*n]);
    p += k ? k : 1;
    (*n)++;
  }
  return cp;
}

/* The first code point of v as str() writes it (0 when empty). */
static uint32_t first_code_point(const Value *v) {
  StrBuf b = {.max = 8};   /* one character is at most 4 bytes */
  val_format(&b, v, 1);
  uint32_t c = 0;
  if (b.s && b.len && !utf8_decode((const unsigned char *)b.s, (const unsigned char *)b.s + b.len, &c)) c = 0;
  free(b.s);
  return c;
}

static void search_value(Search *s, const Value *want) {
  s->nhit = 0;
  int j;
  for (j = 0; s->table && j < s->n && more(s); j++) {
    const Value *e = &s->table[j];
    if ((s->col == 0 && val_equal(want, e)) ||
        (e->kind == V_LIST && s->col < e->u.l->n && val_equal(want, &e->u.l->v[s->col])))
      add_hit(s, j);
  }
  search_steps(s, j);
}

static void search_char(Search *s, uint32_t c) {
  s->nhit = 0;
  int j;
  for (j = 0; j < s->n && more(s); j++)
    if (c == (s->chars ? s->chars[j] : first_code_point(&s->table[j].u.l->v[s->col]))) add_hit(s, j);
  search_steps(s, j);
}

static Value search_string(Search *s, const char *find) {
  for (int j = 0; s->table && j < s->n; j++)
    if (s->table[j].kind != V_LIST || s->table[j].u.l->n <= s->col) return val_ptr(V_LIST, ev_list(s->ev, 0));
  int nf;
  uint32_t *f = code_points(find, &nf);
  List *out = ev_list(s->ev, nf);
  int k = 0;
  for (int i = 0; i < nf && !s->failed; i++) {
    search_char(s, f[i]);
    if (s->limit != 1) out->v[k++] = hits_list(s);
    else if (s->nhit) out->v[k++] = val_num(s->hit[0]);
  }
  out->n = k;
  free(f);
  return val_ptr(V_LIST, out);
}

static Value bi_search(Eval *ev, Value *a, int n, const ENode *call) {
  double num, col;
  if (bi_opt_num(ev, a, 2, call, 1, &num) || bi_opt_num(ev, a, 3, call, 0, &col)) return val_err();
  if (col < 0 || col != floor(col) || col > INT_MAX) {
    bi_type_error(ev, call, 3, "a column index (a whole number, 0 or more)", &a[3]);
    return val_err();
  }
  /* OpenSCAD takes the count as an unsigned integer: a negative one asks for all */
  Search s = {ev, NULL, NULL, 0, num < 0 || num >= UINT_MAX ? 0 : (unsigned)num, (int)col, NULL, 0, 0, call, 0};
  double chars_bytes = 4.0 * ((a[0].kind == V_STR ? a[0].u.s->len : 0) + (a[1].kind == V_STR ? a[1].u.s->len : 0));
  if (ev_buffer_limit(ev, chars_bytes, call->range, "`search`")) return val_err();
  uint32_t *chars = NULL;
  if (a[1].kind == V_LIST) { s.table = a[1].u.l->v; s.n = a[1].u.l->n; }
  if (a[1].kind == V_STR) s.chars = chars = code_points(a[1].u.s->s, &s.n);
  Value r = val_undef();
  if (a[0].kind == V_STR) r = search_string(&s, a[0].u.s->s);
  else if (a[0].kind == V_NUM) { search_value(&s, &a[0]); r = hits_list(&s); }
  else if (a[0].kind == V_LIST) {
    List *out = ev_list(ev, a[0].u.l->n);
    for (int i = 0; i < out->n && !s.failed; i++) {
      search_value(&s, &a[0].u.l->v[i]);
      out->v[i] = s.limit == 1 && s.nhit == 1 ? val_num(s.hit[0]) : hits_list(&s);
    }
    r = val_ptr(V_LIST, out);
  }
  free(chars);
  free(s.hit);
  return s.failed ? val_err() : r;
}

/* "`str`": how a builtin's limit message names the call. */
static const char *bquoted(const ENode *call) {
  static char buf[80];
  snprintf(buf, sizeof buf, "`%s`", bi_name(call));
  return buf;
}

static Value bi_str(Eval *ev, Value *a, int n, const ENode *call) {
  StrBuf b = ev_text_buf(ev);
  for (int i = 0; i < n && !b.over; i++) val_format(&b, &a[i], 1);
  if (ev_text_over(ev, &b, call->range, bquoted(call))) { free(b.s); return val_err(); }
  Value r = ev_str(ev, b.s ? b.s : "", (int)b.len);
  free(b.s);
  return r;
}

static int put_utf8(char *d, unsigned c) {
  if (c < 0x80) { d[0] = (char)c; return 1; }
  if (c < 0x800) { d[0] = (char)(0xC0 | c >> 6); d[1] = (char)(0x80 | (c & 63)); return 2; }
  if (c < 0x10000) {
    d[0] = (char)(0xE0 | c >> 12); d[1] = (char)(0x80 | ((c >> 6) & 63)); d[2] = (char)(0x80 | (c & 63));
    return 3;
  }
  d[0] = (char)(0xF0 | c >> 18); d[1] = (char)(0x80 | ((c >> 12) & 63));
  d[2] = (char)(0x80 | ((c >> 6) & 63)); d[3] = (char)(0x80 | (c & 63));
  return 4;
}

/* The UTF-8 of code point v at buf + *len; nonzero (reported as argument i) when v is none. */
static int put_code(Eval *ev, const ENode *call, int i, const Value *v, char *buf, int *len) {
  if (v->kind != V_NUM || v->u.n < 1 || v->u.n > 0x10FFFF || (v->u.n >= 0xD800 && v->u.n < 0xE000))
    return bi_type_error(ev, call, i, "Unicode code points (1 to 0x10FFFF)", v);
  *len += put_utf8(buf + *len, (unsigned)v->u.n);
  return 0;
}

/* chr(code, ...), each argument a code point or a list of them: the string of them all. */
static Value bi_chr(Eval *ev, Value *a, int n, const ENode *call) {
  size_t m = 0;
  for (int i = 0; i < n; i++) m += a[i].kind == V_LIST ? (size_t)a[i].u.l->n : 1;
  if (m * 4 > ev_text_room(ev)) {
    StrBuf over = {.max = ev_text_room(ev), .over = 1};
    ev_text_over(ev, &over, call->range, bquoted(call));
    return val_err();
  }
  char *buf = xmalloc(m * 4 + 1);
  int len = 0, bad = 0;
  for (int i = 0; i < n && !bad; i++) {
    if (a[i].kind != V_LIST) { bad = put_code(ev, call, i, &a[i], buf, &len); continue; }
    for (int k = 0; k < a[i].u.l->n && !bad; k++) bad = put_code(ev, call, i, &a[i].u.l->v[k], buf, &len);
  }
  Value r = bad ? val_err() : ev_str(ev, buf, len);
  free(buf);
  return r;
}

static Value bi_ord(Eval *ev, Value *a, int n, const ENode *call) {
  if (a[0].kind != V_STR || a[0].u.s->len == 0) {
    bi_type_error(ev, call, 0, "a non-empty string", &a[0]);
    return val_err();
  }
  const unsigned char *s = (const unsigned char *)a[0].u.s->s;
  unsigned c = s[0];
  int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
  c &= extra == 3 ? 7 : extra == 2 ? 15 : extra == 1 ? 31 : 127;
  for (int i = 1; i <= extra && i < a[0].u.s->len; i++) c = c << 6 | (s[i] & 63);
  return val_num(c);
}

/* rands(min, max, n, seed = 0): n uniform numbers from PCG32, stream 0. */
static Value bi_rands(Eval *ev, Value *a, int n, const ENode *call) {
  double lo, hi, cnt, seed;
  if (bi_num(ev, a, 0, call, &lo) || bi_num(ev, a, 1, call, &hi) || bi_num(ev, a, 2, call, &cnt) ||
      bi_opt_num(ev, a, 3, call, 0, &seed))
    return val_err();
  if (!(cnt >= 0) || ev_list_limit(ev, cnt, call->range)) {
    if (!(cnt >= 0)) ev_error(ev, bi_arg_loc(call, 2), "`rands` needs a count of 0 or more");
    return val_err();
  }
  if (!(fabs(seed) < 0x1p63)) {
    ev_error(ev, bi_arg_loc(call, 3), "`rands` needs a seed between -2^63 and 2^63");
    return val_err();
  }
  Rng r;
  rng_seed(&r, (uint64_t)(int64_t)seed, 0);
  List *l = ev_list(ev, (int)cnt);
  for (int i = 0; i < l->n; i++) l->v[i] = val_num(lo + (hi - lo) * rng_uniform(&r));
  return val_ptr(V_LIST, l);
}

/* ---- type tests ------------------------------------------------------ */

#define IS(cname, cond) \
  static Value cname(Eval *ev, Value *a, int n, const ENode *call) { return val_bool(cond); }
IS(bi_is_undef, a[0].kind == V_UNDEF) IS(bi_is_num, a[0].kind == V_NUM && !isnan(a[0].u.n)) IS(bi_is_string, a[0].kind == V_STR)
IS(bi_is_list, a[0].kind == V_LIST) IS(bi_is_bool, a[0].kind == V_BOOL) IS(bi_is_function, a[0].kind == V_FUNC)

/* ---- transforms and colours ------------------------------------------- */

static Value bi_translate(Eval *ev, Value *a, int n, const ENode *call) {
  Vec3 t;
  if (bi_vec3(ev, a, 0, call, &t)) return val_err();
  return ev_xform(ev, m4_translate(t));
}

/* rotate([ax, ay, az]) about x, then y, then z; rotate(a) about z;
** rotate(a, v) by a degrees about axis v (OpenSCAD's three forms). */
static Value bi_rotate(Eval *ev, Value *a, int n, const ENode *call) {
  Vec3 r, axis;
  if (a[1].kind != V_UNSET) {
    if (bi_num(ev, a, 0, call, &r.x) || bi_vec3(ev, a, 1, call, &axis)) return val_err();
    if (v3_len(axis) == 0) {
      ev_error(ev, bi_arg_loc(call, 1), "`rotate`: the axis [0, 0, 0] has no direction");
      return val_err();
    }
    return ev_xform(ev, m4_rotate_axis(r.x, axis));
  }
  if (a[0].kind == V_NUM) r = v3(0, 0, a[0].u.n);
  else if (bi_vec3(ev, a, 0, call, &r)) return val_err();
  return ev_xform(ev, m4_rotate_xyz(r));
}

static Value bi_scale(Eval *ev, Value *a, int n, const ENode *call) {
  Vec3 s;
  if (a[0].kind == V_NUM) s = v3(a[0].u.n, a[0].u.n, a[0].u.n);
  else if (!val_to_point(&a[0], &s)) {
    bi_type_error(ev, call, 0, "a number or [sx, sy, sz]", &a[0]);
    return val_err();
  } else if (a[0].u.l->n == 2) s.z = 1;   /* OpenSCAD's 2D scale([sx, sy]) */
  return ev_xform(ev, m4_scale(s));
}

/* matrix(rows): 4 rows of 4, or 3 rows of 4 (the last row is 0 0 0 1). */
static Value bi_matrix(Eval *ev, Value *a, int n, const ENode *call) {
  List *rows;
  if (bi_list(ev, a, 0, call, &rows)) return val_err();
  Mat4 m = m4_identity();
  if (rows->n != 3 && rows->n != 4) goto bad;
  for (int i = 0; i < rows->n; i++) {
    Value r = rows->v[i];
    if (r.kind != V_LIST || r.u.l->n != 4) goto bad;
    for (int j = 0; j < 4; j++) {
      if (r.u.l->v[j].kind != V_NUM) goto bad;
      m.m[i][j] = r.u.l->v[j].u.n;
    }
  }
  return ev_xform(ev, m);
bad:
  bi_type_error(ev, call, 0, "3 or 4 rows of 4 numbers", &a[0]);
  return val_err();
}

/* rgb(r, g, b, a = 1): components as a colour literal's, sRGB in [0, 1]. */
static Value bi_rgb(Eval *ev, Value *a, int n, const ENode *call) {
  double c[4];
  for (int i = 0; i < 3; i++)
    if (bi_num(ev, a, i, call, &c[i])) return val_err();
  if (bi_opt_num(ev, a, 3, call, 1, &c[3])) return val_err();
  return ev_color(ev, val_srgb_to_linear(c[0]), val_srgb_to_linear(c[1]), val_srgb_to_linear(c[2]), c[3]);
}

/* ---- geometry ------------------------------------------------------------ */

SceneGeometry *bi_geom_new(Eval *ev, GeomKind kind, const ENode *call) {
  SceneGeometry *g = arena_alloc(&ev->scene->arena, sizeof *g);
  g->kind = kind;
  g->loc = call->range;
  return g;
}

/* A list of points into scene memory; -1 (reported) on a bad element. */
int bi_points(Eval *ev, Value *a, int i, const ENode *call, Vec3 **out, int *n) {
  List *l;
  if (bi_list(ev, a, i, call, &l)) return -1;
  *out = arena_alloc(&ev->scene->arena, (size_t)(l->n ? l->n : 1) * sizeof **out);
  *n = l->n;
  for (int k = 0; k < l->n; k++) {
    if (!val_to_point(&l->v[k], &(*out)[k])) {
      ev_error(ev, bi_arg_loc(call, i), "`%s` expects points [x, y, z]; element %d is %s %s", bi_name(call), k,
               article(&l->v[k]), val_type_name(&l->v[k]));
      return -1;
    }
    if (!vec3_finite((*out)[k])) {   /* a NaN or infinite point would draw a silently wrong image */
      ev_error(ev, bi_arg_loc(call, i), "`%s`: point %d is not finite (it has a nan or inf coordinate)", bi_name(call), k);
      return -1;
    }
  }
  return 0;
}

static Value bi_bezier(Eval *ev, Value *a, int n, const ENode *call) {
  Vec3 *p;
  int np;
  if (bi_points(ev, a, 0, call, &p, &np)) return val_err();
  if (np != 16) {
    ev_error(ev, bi_arg_loc(call, 0), "`bezier` needs 16 control points (4 rows of 4); found %d", np);
    return val_err();
  }
  SceneGeometry *g = bi_geom_new(ev, GEOM_PATCHES, call);
  g->npatches = 1;
  g->patches = arena_alloc(&ev->scene->arena, sizeof *g->patches);
  memcpy(g->patches[0].cp, p, 16 * sizeof(Vec3));
  return val_ptr(V_GEOM, g);
}

/* An index into n points, from a number value. */
static int get_index(const Value *v, int n, int *out) {
  if (v->kind != V_NUM || v->u.n != floor(v->u.n) || v->u.n < 0 || v->u.n >= n) return 0;
  *out = (int)v->u.n;
  return 1;
}

static Value bi_bezier_patches(Eval *ev, Value *a, int n, const ENode *call) {
  Vec3 *p;
  int np;
  List *idx;
  if (bi_points(ev, a, 0, call, &p, &np) || bi_list(ev, a, 1, call, &idx)) return val_err();
  SceneGeometry *g = bi_geom_new(ev, GEOM_PATCHES, call);
  g->npatches = idx->n;
  g->patches = arena_alloc(&ev->scene->arena, (size_t)(idx->n ? idx->n : 1) * sizeof *g->patches);
  for (int i = 0; i < idx->n; i++) {
    const Value *row = &idx->v[i];
    if (row->kind != V_LIST || row->u.l->n != 16) {
      ev_error(ev, bi_arg_loc(call, 1), "patch %d needs a list of 16 point indices", i);
      return val_err();
    }
    for (int k = 0; k < 16; k++) {
      int j;
      if (!get_index(&row->u.l->v[k], np, &j)) {
        ev_error(ev, bi_arg_loc(call, 1), "patch %d, index %d: not a point index (0 to %d)", i, k, np - 1);
        return val_err();
      }
      g->patches[i].cp[k] = p[j];
    }
  }
  return val_ptr(V_GEOM, g);
}

static Value bi_bilinear(Eval *ev, Value *a, int n, const ENode *call) {
  SceneGeometry *g = bi_geom_new(ev, GEOM_PATCHES, call);
  g->npatches = 1;
  g->patches = arena_alloc(&ev->scene->arena, sizeof *g->patches);
  g->patches[0].bilinear = 1;
  for (int i = 0; i < 4; i++) {
    if (bi_vec3(ev, a, i, call, &g->patches[0].cp[i])) return val_err();
    if (!vec3_finite(g->patches[0].cp[i])) {
      ev_error(ev, bi_arg_loc(call, i), "`bilinear`: corner %d is not finite (it has a nan or inf coordinate)", i);
      return val_err();
    }
  }
  return val_ptr(V_GEOM, g);
}

/* A path relative to the folder of the file that names it. */
static void resolve_path(const ENode *call, const char *name, char *out, size_t n) {
  const SrcFile *f = call->range.file >= 0 ? diag_file(call->range.file) : NULL;
  const char *slash = f ? strrchr(f->name, '/') : NULL;
  if (name[0] == '/' || !slash) snprintf(out, n, "%s", name);
  else snprintf(out, n, "%.*s/%s", (int)(slash - f->name), f->name, name);
}

static Value mesh_import(Eval *ev, const Str *path, const ENode *call) {
  char full[4096], err[512] = "";
  resolve_path(call, path->s, full, sizeof full);
  SceneGeometry *g = bi_geom_new(ev, GEOM_MESH, call);
  if (mesh_import_file(full, g, &ev->scene->arena, err, sizeof err) != 0) {
    ev_error(ev, bi_arg_loc(call, 0), "cannot import `%s`: %s", path->s, err);
    return val_err();
  }
  if (err[0]) diag_warning(bi_arg_loc(call, 0), "`%s`: %s", path->s, err);
  g->loc = call->range;
  return val_ptr(V_GEOM, g);
}

int bi_faces(Eval *ev, List *faces, int nverts, const ENode *call, int arg, SceneGeometry *g) {
  int total = 0;
  for (int i = 0; i < faces->n; i++) {
    const Value *f = &faces->v[i];
    if (f->kind != V_LIST || f->u.l->n < 3) {
      ev_error(ev, bi_arg_loc(call, arg), "face %d needs a list of 3 or more vertex indices", i);
      return -1;
    }
    total += f->u.l->n;
  }
  g->nfaces = faces->n;
  g->face_start = arena_alloc(&ev->scene->arena, (size_t)(faces->n + 1) * sizeof(int));
  g->face_index = arena_alloc(&ev->scene->arena, (size_t)(total ? total : 1) * sizeof(int));
  int k = 0;
  for (int i = 0; i < faces->n; i++) {
    g->face_start[i] = k;
    const List *f = faces->v[i].u.l;
    for (int j = 0; j < f->n; j++)
      if (!get_index(&f->v[j], nverts, &g->face_index[k++])) {
        ev_error(ev, bi_arg_loc(call, arg), "face %d, index %d: not a vertex index (0 to %d)", i, j, nverts - 1);
        return -1;
      }
  }
  g->face_start[faces->n] = k;
  return 0;
}

static Value bi_mesh(Eval *ev, Value *a, int n, const ENode *call) {
  if (a[0].kind == V_STR && a[1].kind == V_UNSET) return mesh_import(ev, a[0].u.s, call);
  SceneGeometry *g = bi_geom_new(ev, GEOM_MESH, call);
  List *faces;
  if (bi_points(ev, a, 0, call, &g->verts, &g->nverts) || bi_list(ev, a, 1, call, &faces)) return val_err();
  if (bi_faces(ev, faces, g->nverts, call, 1, g)) return val_err();
  return val_ptr(V_GEOM, g);
}

static int get_creases(Eval *ev, Value *a, const ENode *call, SceneGeometry *g) {
  if (a[1].kind == V_UNSET) return 0;
  List *l;
  if (bi_list(ev, a, 1, call, &l)) return -1;
  g->ncreases = l->n;
  g->creases = arena_alloc(&ev->scene->arena, (size_t)(l->n ? l->n : 1) * sizeof *g->creases);
  for (int i = 0; i < l->n; i++) {
    const Value *c = &l->v[i];
    if (c->kind != V_LIST || c->u.l->n != 3 || !get_index(&c->u.l->v[0], g->nverts, &g->creases[i].a) ||
        !get_index(&c->u.l->v[1], g->nverts, &g->creases[i].b) || c->u.l->v[2].kind != V_NUM ||
        c->u.l->v[2].u.n < 0) {
      ev_error(ev, bi_arg_loc(call, 1), "crease %d: expected [vertex, vertex, sharpness >= 0] with vertices 0 to %d", i,
               g->nverts - 1);
      return -1;
    }
    g->creases[i].sharpness = c->u.l->v[2].u.n;
  }
  return 0;
}

/* corners: [v, ...] (infinitely sharp) or [[v, sharpness], ...]. */
static int get_corners(Eval *ev, Value *a, const ENode *call, SceneGeometry *g) {
  if (a[2].kind == V_UNSET) return 0;
  List *l;
  if (bi_list(ev, a, 2, call, &l)) return -1;
  g->ncorners = l->n;
  g->corners = arena_alloc(&ev->scene->arena, (size_t)(l->n ? l->n : 1) * sizeof *g->corners);
  for (int i = 0; i < l->n; i++) {
    const Value *c = &l->v[i];
    int ok;
    if (c->kind == V_LIST)
      ok = c->u.l->n == 2 && get_index(&c->u.l->v[0], g->nverts, &g->corners[i].v) && c->u.l->v[1].kind == V_NUM &&
           (g->corners[i].sharpness = c->u.l->v[1].u.n) >= 0;
    else ok = get_index(c, g->nverts, &g->corners[i].v) && (g->corners[i].sharpness = 10, 1);
    if (!ok) {
      ev_error(ev, bi_arg_loc(call, 2), "corner %d: expected a vertex index or [vertex, sharpness]", i);
      return -1;
    }
  }
  return 0;
}

/* subdiv(mesh, creases, corners, level = 2, scheme = "catmark") */
static Value bi_subdiv(Eval *ev, Value *a, int n, const ENode *call) {
  if (a[0].kind != V_GEOM || a[0].u.g->kind != GEOM_MESH) {
    bi_type_error(ev, call, 0, "a mesh (from mesh())", &a[0]);
    return val_err();
  }
  SceneGeometry *g = bi_geom_new(ev, GEOM_MESH, call);
  *g = *a[0].u.g;
  g->loc = call->range;
  double level;
  if (bi_opt_num(ev, a, 3, call, 2, &level)) return val_err();
  if (level < 1 || level > EVAL_MAX_SUBDIV_LEVEL || level != floor(level)) {
    ev_error(ev, bi_arg_loc(call, 3), "`subdiv` level must be a whole number from 1 to %d (the limit)",
             EVAL_MAX_SUBDIV_LEVEL);
    return val_err();
  }
  g->subdiv_level = (int)level;
  g->subdiv_scheme = "catmark";
  if (a[4].kind != V_UNSET) {
    static const char *schemes[] = {"catmark", "loop", "bilinear"};
    int k = 0;
    while (k < 3 && (a[4].kind != V_STR || strcmp(a[4].u.s->s, schemes[k]) != 0)) k++;
    if (k == 3) {
      bi_type_error(ev, call, 4, "\"catmark\", \"loop\" or \"bilinear\"", &a[4]);
      return val_err();
    }
    g->subdiv_scheme = schemes[k];
  }
  if (a[5].kind != V_UNSET) {
    SumiOsdBoundary b;
    if (a[5].kind != V_STR || !subdiv_boundary_parse(a[5].u.s->s, &b)) {
      bi_type_error(ev, call, 5, "\"edge_and_corner\", \"edge_only\" or \"none\"", &a[5]);
      return val_err();
    }
    g->subdiv_boundary = a[5].u.s->s;
  }
  if (get_creases(ev, a, call, g) || get_corners(ev, a, call, g)) return val_err();
  /* Crease and corner indices, the face limit: caught here, at the script,
  ** rather than at render time. */
  char why[256];
  SumiOsdBoundary boundary;
  subdiv_boundary_parse(g->subdiv_boundary, &boundary);
  if (!subdiv_check(g, boundary, why, sizeof why)) {
    ev_error(ev, call->range, "`subdiv`: %s", why);
    return val_err();
  }
  return val_ptr(V_GEOM, g);
}

static Value bi_fold_file(Eval *ev, Value *a, int n, const ENode *call) {
  if (a[0].kind != V_STR) {
    bi_type_error(ev, call, 0, "a file name", &a[0]);
    return val_err();
  }
  char full[4096], err[512] = "";
  resolve_path(call, a[0].u.s->s, full, sizeof full);
  SceneOrigami *o = arena_alloc(&ev->scene->arena, sizeof *o);
  int bad = crease_is_oripa(full) ? crease_read(full, o, &ev->scene->arena, err, sizeof err)
                                  : fold_read(full, o, &ev->scene->arena, err, sizeof err);
  if (bad) {
    ev_error(ev, bi_arg_loc(call, 0), "%s", err);   /* err names the file */
    return val_err();
  }
  o->fold_file = arena_strndup(&ev->scene->arena, full, strlen(full));
  return val_ptr(V_PAPER, o);
}

/* ---- statements: echo, assert, children ---------------------------------- */

static Value bi_echo(Eval *ev, Value *a, int n, const ENode *call) {
  StrBuf b = ev_text_buf(ev);
  sb_puts(&b, "ECHO: ");
  for (int i = 0; i < n; i++) {
    if (i) sb_puts(&b, ", ");
    if (call->names[i]) sb_printf(&b, "%s = ", call->names[i]);
    val_format(&b, &a[i], 0);
  }
  sb_putc(&b, '\n');
  if (ev_text_over(ev, &b, call->range, bquoted(call))) { free(b.s); return val_err(); }
  fflush(stdout);
  fputs(b.s, stderr);
  free(b.s);
  return val_undef();
}

static Value bi_assert(Eval *ev, Value *a, int n, const ENode *call) {
  if (val_truthy(&a[0])) return val_undef();
  if (a[1].kind == V_UNSET) ev_error(ev, call->range, "assertion failed");
  else {
    StrBuf b = {.max = 4096};   /* a message, not a dump: longer ones end in ... */
    val_format(&b, &a[1], 1);
    ev_error(ev, call->range, "assertion failed: %s%s", b.s ? b.s : "", b.over ? "..." : "");
    free(b.s);
  }
  return val_err();
}

static Value bi_children(Eval *ev, Value *a, int n, const ENode *call) {
  double i = -1;
  if (bi_opt_num(ev, a, 0, call, -1, &i)) return val_err();
  return ev_children(ev, (int)i, call->range) ? val_err() : val_undef();
}

/* ---- the table ---------------------------------------------------------- */

/* One row per builtin: name, function, parameter names, min and max args. */
static const Builtin builtins[] = {
  {"sin", bi_sin, "x", 1, 1, 0}, {"cos", bi_cos, "x", 1, 1, 0}, {"tan", bi_tan, "x", 1, 1, 0},
  {"asin", bi_asin, "x", 1, 1, 0}, {"acos", bi_acos, "x", 1, 1, 0}, {"atan", bi_atan, "x", 1, 1, 0},
  {"atan2", bi_atan2, "y,x", 2, 2, 0}, {"sqrt", bi_sqrt, "x", 1, 1, 0}, {"pow", bi_pow, "x,y", 2, 2, 0},
  {"exp", bi_exp, "x", 1, 1, 0}, {"ln", bi_ln, "x", 1, 1, 0}, {"log", bi_log, "x,y", 1, 2, 0},
  {"abs", bi_abs, "x", 1, 1, 0}, {"sign", bi_sign, "x", 1, 1, 0}, {"min", bi_min, "", 1, -1, 0},
  {"max", bi_max, "", 1, -1, 0}, {"floor", bi_floor, "x", 1, 1, 0}, {"ceil", bi_ceil, "x", 1, 1, 0},
  {"round", bi_round, "x", 1, 1, 0}, {"lerp", bi_lerp, "a,b,t", 3, 3, 0},
  {"clamp", bi_clamp, "x,lo,hi", 3, 3, 0}, {"smoothstep", bi_smoothstep, "edge0,edge1,x", 3, 3, 0},
  {"dot", bi_dot, "a,b", 2, 2, 0}, {"cross", bi_cross, "a,b", 2, 2, 0}, {"norm", bi_norm, "v", 1, 1, 0},
  {"normalize", bi_normalize, "v", 1, 1, 0}, {"len", bi_len, "x", 1, 1, 0}, {"concat", bi_concat, "", 0, -1, 0},
  {"reverse", bi_reverse, "x", 1, 1, 0}, {"slice", bi_slice, "list,start,end", 2, 3, 0},
  {"range", bi_range, "start,end,step", 1, 3, 0}, {"search", bi_search, "match_value,string_or_vector,num_returns_per_match,index_col_num", 2, 4, 0},
  {"str", bi_str, "", 0, -1, 0}, {"chr", bi_chr, "", 1, -1, 0}, {"ord", bi_ord, "s", 1, 1, 0},
  {"rands", bi_rands, "min,max,n,seed", 3, 4, 0},
  {"is_undef", bi_is_undef, "x", 1, 1, 0}, {"is_num", bi_is_num, "x", 1, 1, 0},
  {"is_string", bi_is_string, "x", 1, 1, 0}, {"is_list", bi_is_list, "x", 1, 1, 0},
  {"is_bool", bi_is_bool, "x", 1, 1, 0}, {"is_function", bi_is_function, "x", 1, 1, 0},
  {"translate", bi_translate, "v", 1, 1, 0}, {"rotate", bi_rotate, "a,v", 1, 2, 0},
  {"scale", bi_scale, "s", 1, 1, 0}, {"matrix", bi_matrix, "rows", 1, 1, 0},
  {"rgb", bi_rgb, "r,g,b,a", 3, 4, 0},
  {"bezier", bi_bezier, "points", 1, 1, 0}, {"bezier_patches", bi_bezier_patches, "points,patches", 2, 2, 0},
  {"bilinear", bi_bilinear, "p0,p1,p2,p3", 4, 4, 0}, {"mesh", bi_mesh, "points,faces", 1, 2, 0},
  {"subdiv", bi_subdiv, "mesh,creases,corners,level,scheme,boundary", 1, 6, 0},
  {"fold_file", bi_fold_file, "path", 1, 1, 0},
  {"echo", bi_echo, "", 0, -1, 1}, {"assert", bi_assert, "condition,message", 1, 2, 1},
  {"children", bi_children, "index", 0, 1, 1},
};

static Builtin *all_builtins;
static int nall_builtins;
static pthread_once_t all_once = PTHREAD_ONCE_INIT;

static void join_tables(void) {
  int nm, n2, nb = (int)(sizeof builtins / sizeof builtins[0]);
  const Builtin *model = builtin_model_table(&nm), *two = builtin_2d_table(&n2);
  all_builtins = xmalloc((size_t)(nb + nm + n2) * sizeof *all_builtins);
  memcpy(all_builtins, builtins, sizeof builtins);
  memcpy(all_builtins + nb, model, (size_t)nm * sizeof *model);
  memcpy(all_builtins + nb + nm, two, (size_t)n2 * sizeof *two);
  nall_builtins = nb + nm + n2;
}

const Builtin *builtin_table(int *n) {
  pthread_once(&all_once, join_tables);
  *n = nall_builtins;
  return all_builtins;
}

int builtin_index(const char *name) {
  int n;
  const Builtin *t = builtin_table(&n);
  for (int i = 0; i < n; i++)
    if (strcmp(t[i].name, name) == 0) return i;
  return -1;
}

/* Position of a named parameter in the builtin's "a,b,c" list. */
int builtin_param(const Builtin *bi, const char *name) {
  const char *p = bi->params;
  size_t len = strlen(name);
  for (int k = 0; *p; k++) {
    const char *comma = strchr(p, ',');
    size_t l = comma ? (size_t)(comma - p) : strlen(p);
    if (l == len && strncmp(p, name, len) == 0) return k;
    if (!comma) break;
    p = comma + 1;
  }
  return -1;
}

int builtin_constant_time(const Builtin *bi) {
  static const BuiltinFn o1[] = {bi_len, bi_is_undef, bi_is_num, bi_is_string, bi_is_list, bi_is_bool, bi_is_function};
  for (size_t i = 0; i < sizeof o1 / sizeof o1[0]; i++)
    if (bi->fn == o1[i]) return 1;
  return 0;
}
