/*
** ORIPA crease patterns (crease.h): segments from .cp lines or .opx
** objects, then vertices by merging the segments' ends.
*/
#include "crease.h"

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "../lang/diag.h"

#define CREASE_MERGE_LOG2 20          /* ends within shortest / 2^20 merge */

typedef struct Segment { Vec2 a, b; char type; SrcRange loc; } Segment;
typedef struct Segments { Segment *s; int n, cap; } Segments;

static void seg_add(Segments *l, Vec2 a, Vec2 b, char type, SrcRange loc) {
  l->s = xgrow(l->s, &l->cap, l->n + 1, sizeof *l->s);
  l->s[l->n++] = (Segment){a, b, type, loc};
}

static SrcRange line_range(int file, int line) {
  const SrcFile *f = diag_file(file);
  SrcRange r = {file, line, 1, line, 2};
  if (line >= 1 && line <= f->nlines) {                     /* the whole line */
    size_t start = (size_t)f->line_start[line - 1], end = start;
    while (end < f->len && f->text[end] != '\n' && f->text[end] != '\r') end++;
    if (end > start) r = diag_range(file, (uint32_t)start, (uint32_t)end);
  }
  return r;
}

/* .cp: "type x1 y1 x2 y2" a line; blank lines are skipped. */
static int read_cp(int file, Segments *out, char *err, size_t errlen) {
  const SrcFile *f = diag_file(file);
  static const char types[] = "UBMVF";
  for (int line = 1; line <= f->nlines; line++) {
    const char *p = f->text + f->line_start[line - 1];
    while (*p == ' ' || *p == '\t') p++;
    if (*p == '\n' || *p == '\r' || *p == 0) continue;
    int type, used = 0;
    double x1, y1, x2, y2;
    if (sscanf(p, "%d %lf %lf %lf %lf%n", &type, &x1, &y1, &x2, &y2, &used) != 5 || !isfinite(x1) ||
        !isfinite(y1) || !isfinite(x2) || !isfinite(y2)) {
      snprintf(err, errlen, "%s:%d: expected `type x1 y1 x2 y2`", f->name, line);
      return 1;
    }
    seg_add(out, (Vec2){x1, y1}, (Vec2){x2, y2}, type >= 0 && type <= 4 ? types[type] : 'U', line_range(file, line));
  }
  return 0;
}

/* The number in an .opx property node: <void property="x0"><double>1</double></void>. */
static int opx_number(xmlNode *prop, double *out) {
  for (xmlNode *c = prop->children; c; c = c->next) {
    if (c->type != XML_ELEMENT_NODE) continue;
    xmlChar *text = xmlNodeGetContent(c);
    char *end;
    *out = strtod((const char *)text, &end);
    int ok = end != (char *)text && isfinite(*out);
    xmlFree(text);
    return ok;
  }
  return 0;
}

static void opx_line(int file, xmlNode *obj, Segments *out) {
  static const char types[] = "FBMV";
  double v[5] = {0, 0, 0, 0, 0};                            /* x0 y0 x1 y1 type */
  static const char *names[5] = {"x0", "y0", "x1", "y1", "type"};
  for (xmlNode *c = obj->children; c; c = c->next) {
    if (c->type != XML_ELEMENT_NODE) continue;
    xmlChar *prop = xmlGetProp(c, (const xmlChar *)"property");
    for (int k = 0; prop && k < 5; k++)
      if (!strcmp((const char *)prop, names[k])) opx_number(c, &v[k]);
    xmlFree(prop);
  }
  int t = (int)v[4];
  seg_add(out, (Vec2){v[0], v[1]}, (Vec2){v[2], v[3]}, t >= 0 && t <= 3 ? types[t] : 'U',
          line_range(file, (int)xmlGetLineNo(obj)));
}

static void opx_walk(int file, xmlNode *n, Segments *out) {
  for (; n; n = n->next) {
    if (n->type != XML_ELEMENT_NODE) continue;
    xmlChar *cls = xmlGetProp(n, (const xmlChar *)"class");
    int line = cls && !strcmp((const char *)n->name, "object") && !strcmp((const char *)cls, "oripa.OriLineProxy");
    xmlFree(cls);
    if (line) opx_line(file, n, out);
    else opx_walk(file, n->children, out);
  }
}

static int read_opx(int file, Segments *out, char *err, size_t errlen) {
  const SrcFile *f = diag_file(file);
  xmlDoc *doc = xmlReadMemory(f->text, (int)f->len, f->name, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR |
                              XML_PARSE_NOWARNING);
  if (!doc) {
    const xmlError *e = xmlGetLastError();
    snprintf(err, errlen, "%s:%d: not well-formed XML: %s", f->name, e ? e->line : 0,
             e && e->message ? strtok(e->message, "\n") : "parse error");
    return 1;
  }
  opx_walk(file, xmlDocGetRootElement(doc), out);
  xmlFreeDoc(doc);
  return 0;
}

typedef struct End { double x, y; int seg; } End;

static int cmp_end(const void *a, const void *b) {
  const End *p = a, *q = b;
  return p->x < q->x ? -1 : p->x > q->x;
}

/* Vertices: segment ends within eps of an earlier one share its vertex. */
static void make_vertices(const Segments *l, SceneOrigami *o, Arena *arena) {
  int n = l->n;
  double shortest = INFINITY;
  for (int i = 0; i < n; i++) shortest = fmin(shortest, hypot(l->s[i].b.x - l->s[i].a.x, l->s[i].b.y - l->s[i].a.y));
  double eps = shortest > 0 && isfinite(shortest) ? ldexp(shortest, -CREASE_MERGE_LOG2) : 0;
  End *e = xmalloc((size_t)(2 * n + 1) * sizeof *e);
  for (int i = 0; i < 2 * n; i++) {
    Vec2 p = i & 1 ? l->s[i / 2].b : l->s[i / 2].a;
    e[i] = (End){p.x, p.y, i};
  }
  qsort(e, (size_t)(2 * n), sizeof *e, cmp_end);
  int *vert = xmalloc((size_t)(2 * n + 1) * sizeof *vert);
  o->verts = arena_alloc(arena, (size_t)(2 * n + 1) * sizeof *o->verts);
  o->vert_loc = arena_alloc(arena, (size_t)(2 * n + 1) * sizeof *o->vert_loc);
  for (int i = 0; i < 2 * n; i++) {
    int v = -1;
    for (int j = i - 1; j >= 0 && e[i].x - e[j].x <= eps && v < 0; j--)
      if (fabs(e[i].y - e[j].y) <= eps) v = vert[e[j].seg];
    if (v < 0) {
      v = o->nverts++;
      o->verts[v] = (Vec2){e[i].x, e[i].y};
      o->vert_loc[v] = l->s[e[i].seg / 2].loc;
    }
    vert[e[i].seg] = v;
  }
  o->creases = arena_alloc(arena, (size_t)(n + 1) * sizeof *o->creases);
  for (int i = 0; i < n; i++) {
    if (vert[2 * i] == vert[2 * i + 1]) continue;           /* a zero-length segment */
    o->creases[o->ncreases++] = (OrigamiCrease){vert[2 * i], vert[2 * i + 1], l->s[i].type, l->s[i].loc};
  }
  free(vert);
  free(e);
}

int crease_is_oripa(const char *path) {
  const char *dot = strrchr(path, '.');
  return dot && (!strcasecmp(dot, ".opx") || !strcasecmp(dot, ".cp"));
}

int crease_read(const char *path, SceneOrigami *out, Arena *arena, char *err, size_t errlen) {
  memset(out, 0, sizeof *out);
  const char *why;
  int file = diag_load_file(path, -1, src_none(), &why);
  if (file < 0) {
    snprintf(err, errlen, "%s: cannot read: %s", path, why);
    return 1;
  }
  Segments l = {0};
  const char *dot = strrchr(path, '.');
  int bad = !strcasecmp(dot, ".opx") ? read_opx(file, &l, err, errlen) : read_cp(file, &l, err, errlen);
  if (!bad && l.n == 0) {
    snprintf(err, errlen, "%s: no crease lines", path);
    bad = 1;
  }
  if (!bad && l.n > 2 * 200000) {
    snprintf(err, errlen, "%s: %d lines (limit ORIGAMI_MAX_CREASES is 200000)", path, l.n);
    bad = 1;
  }
  if (!bad) make_vertices(&l, out, arena);
  free(l.s);
  out->loc = out->overlap_loc = out->state_loc = src_none();
  out->transform = m4_identity();
  out->style = -1;
  return bad;
}
