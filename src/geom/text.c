/*
** Text as outlines (see text.h): fontconfig finds the font, HarfBuzz
** shapes the string in it, FreeType reads each glyph's outline in font
** units, and its conic and cubic segments are flattened here.
*/
#include "text.h"

#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H
#include <hb.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "../base/mem.h"
#include "../base/utf8.h"

/* ---- the libraries, set up once ------------------------------------------ */

static FT_Library ft_lib;
static int libs_ok;
static pthread_once_t libs_once = PTHREAD_ONCE_INIT;
static pthread_mutex_t libs_lock = PTHREAD_MUTEX_INITIALIZER;   /* FreeType's library is not shared safely */

static void libs_init(void) { libs_ok = FcInit() && FT_Init_FreeType(&ft_lib) == 0; }

/* ---- finding the font --------------------------------------------------- */

typedef struct FontFile {
  char path[4096];
  int index;
} FontFile;

/* Whether a code point needs a glyph (not a space, a control, or a
** default-ignorable joiner or variation selector). */
static int needs_glyph(uint32_t c) {
  return c > 0x20 && !(c >= 0x7F && c <= 0xA0) && !(c >= 0x200B && c <= 0x200F) && !(c >= 0x2028 && c <= 0x202E) &&
         !(c >= 0x2060 && c <= 0x206F) && !(c >= 0xFE00 && c <= 0xFE0F) && c != 0xFEFF;
}

/* The text's code points that need glyphs, as a set (NULL when none). */
static FcCharSet *text_chars(const char *s, int len) {
  FcCharSet *cs = FcCharSetCreate();
  const unsigned char *p = (const unsigned char *)s, *end = p + len;
  while (p < end) {
    uint32_t c = 0;
    int n = utf8_decode(p, end, &c);
    if (n <= 0) { p++; continue; }
    if (needs_glyph(c)) FcCharSetAddChar(cs, c);
    p += n;
  }
  return cs;
}

/* The first code point of want that font's set lacks, or 0. */
static uint32_t first_missing(const FcCharSet *want, FcPattern *font) {
  FcCharSet *have = NULL;
  if (FcPatternGetCharSet(font, FC_CHARSET, 0, &have) != FcResultMatch) return 0;
  FcChar32 map[FC_CHARSET_MAP_SIZE], next, base;
  for (base = FcCharSetFirstPage(want, map, &next); base != FC_CHARSET_DONE; base = FcCharSetNextPage(want, map, &next))
    for (int w = 0; w < FC_CHARSET_MAP_SIZE; w++)
      for (int b = 0; b < 32; b++)
        if (map[w] >> b & 1 && !FcCharSetHasChar(have, base + 32 * (FcChar32)w + (FcChar32)b))
          return base + 32 * (FcChar32)w + (FcChar32)b;
  return 0;
}

/* Whether any family of font is family (fontconfig names one font several
** ways: "Noto Sans CJK JP", "Noto Sans CJK JP Regular"). */
static int has_family(FcPattern *font, const char *family) {
  FcChar8 *f;
  for (int i = 0; FcPatternGetString(font, FC_FAMILY, i, &f) == FcResultMatch; i++)
    if (!strcasecmp((const char *)f, family)) return 1;
  return 0;
}

static FcPattern *match(FcPattern *pat) {
  FcResult r;
  FcConfigSubstitute(NULL, pat, FcMatchPattern);
  FcDefaultSubstitute(pat);
  return FcFontMatch(NULL, pat, &r);
}

/* The font for name that draws all of text: the best match of name, or,
** when it lacks characters, the best match of name that has them all. */
static int find_font(const TextLayout *t, FontFile *ff, TextOutline *out, char *err, size_t errlen) {
  const char *name = t->font ? t->font : TEXT_DEFAULT_FONT;
  FcPattern *pat = FcNameParse((const FcChar8 *)name);
  if (!pat) { snprintf(err, errlen, "`%s` is not a font name fontconfig reads", name); return -1; }
  FcChar8 *want_family = NULL;
  FcPatternGetString(pat, FC_FAMILY, 0, &want_family);
  char family[128];
  snprintf(family, sizeof family, "%s", want_family ? (const char *)want_family : "");
  FcCharSet *chars = text_chars(t->text, t->len);
  FcPattern *font = match(pat), *second = NULL;
  int rc = -1;
  if (!font) { snprintf(err, errlen, "no font is installed (fonts-dejavu-core has the default one)"); goto out; }
  if (first_missing(chars, font)) {   /* the best font with every character */
    FcPattern *p2 = FcNameParse((const FcChar8 *)name);
    FcPatternAddCharSet(p2, FC_CHARSET, chars);
    second = match(p2);
    FcPatternDestroy(p2);
    uint32_t c = second ? first_missing(chars, second) : 1;
    if (c) {
      char u[16] = "";
      int private_use = (c >= 0xE000 && c <= 0xF8FF) || c >= 0xF0000;
      int cjk = (c >= 0x2E80 && c <= 0x9FFF) || (c >= 0xAC00 && c <= 0xD7AF) || (c >= 0xF900 && c <= 0xFAFF) ||
                (c >= 0x20000 && c <= 0x3FFFF);
      if (!private_use) {
        char ch[5] = "";
        utf8_encode(c, ch);
        snprintf(u, sizeof u, "`%s` ", ch);
      }
      snprintf(err, errlen, "no installed font has a glyph for %s(U+%04X)%s", u, (unsigned)c,
               cjk ? "; fonts-noto-cjk has Chinese, Japanese and Korean" : "");
      goto out;
    }
    FcPatternDestroy(font);
    font = second;
    second = NULL;
    out->fallback = 1;
  }
  FcChar8 *file = NULL, *fam = NULL;
  int index = 0;
  if (FcPatternGetString(font, FC_FILE, 0, &file) != FcResultMatch) {
    snprintf(err, errlen, "fontconfig found no file for `%s`", name);
    goto out;
  }
  FcPatternGetInteger(font, FC_INDEX, 0, &index);
  FcPatternGetString(font, FC_FAMILY, 0, &fam);
  snprintf(ff->path, sizeof ff->path, "%s", (const char *)file);
  ff->index = index;
  snprintf(out->family, sizeof out->family, "%s", fam ? (const char *)fam : "?");
  out->substituted = t->font && family[0] && !has_family(font, family) && !out->fallback;
  rc = 0;
out:
  if (font) FcPatternDestroy(font);
  if (second) FcPatternDestroy(second);
  FcCharSetDestroy(chars);
  FcPatternDestroy(pat);
  return rc;
}

/* ---- flattening outlines ------------------------------------------------- */

typedef struct Flat {
  Vec2 *pts;
  int npts, cap;
  int *start;
  int ncontours, capc;
  int max_points, over;
  double tol;                 /* font units */
  double ox, oy, scale;       /* the glyph's origin (font units) and font units -> scene */
  double cx, cy;              /* the pen's place in the outline (font units) */
} Flat;

static void emit(Flat *f, double x, double y) {
  f->cx = x, f->cy = y;
  if (f->npts >= f->max_points) { f->over = 1; return; }
  if (f->npts == f->cap) f->pts = xgrow(f->pts, &f->cap, f->npts + 1, sizeof *f->pts);
  f->pts[f->npts++] = (Vec2){(f->ox + x) * f->scale, (f->oy + y) * f->scale};
}

/* End the open contour: the closing point that repeats the first goes,
** and one of fewer than 3 points is dropped. */
static void close_contour(Flat *f) {
  int s = f->start[f->ncontours];
  if (f->npts - s > 1 && f->pts[f->npts - 1].x == f->pts[s].x && f->pts[f->npts - 1].y == f->pts[s].y) f->npts--;
  if (f->npts - s < 3) { f->npts = s; return; }
  if (f->ncontours + 2 > f->capc) f->start = xgrow(f->start, &f->capc, f->ncontours + 2, sizeof *f->start);
  f->start[++f->ncontours] = f->npts;
}

static int on_move(const FT_Vector *to, void *user) {
  Flat *f = user;
  close_contour(f);
  emit(f, (double)to->x, (double)to->y);
  return 0;
}

static int on_line(const FT_Vector *to, void *user) {
  emit(user, (double)to->x, (double)to->y);
  return 0;
}

/* Segments a curve needs: a polyline of n equal parameter steps strays at
** most |B''|max / (8 n^2) from a Bezier B. */
static int steps_for(double second_diff, double tol) {
  double n = ceil(sqrt(second_diff / (8 * tol)));
  return n < 1 ? 1 : n > 256 ? 256 : (int)n;
}

static int on_conic(const FT_Vector *c, const FT_Vector *to, void *user) {
  Flat *f = user;
  double x0 = f->cx, y0 = f->cy, x1 = (double)c->x, y1 = (double)c->y, x2 = (double)to->x, y2 = (double)to->y;
  int n = steps_for(2 * hypot(x0 - 2 * x1 + x2, y0 - 2 * y1 + y2), f->tol);   /* B'' = 2 (P0 - 2 P1 + P2) */
  for (int i = 1; i <= n; i++) {
    double t = (double)i / n, u = 1 - t;
    emit(f, u * u * x0 + 2 * u * t * x1 + t * t * x2, u * u * y0 + 2 * u * t * y1 + t * t * y2);
  }
  return 0;
}

static int on_cubic(const FT_Vector *c1, const FT_Vector *c2, const FT_Vector *to, void *user) {
  Flat *f = user;
  double x0 = f->cx, y0 = f->cy, x1 = (double)c1->x, y1 = (double)c1->y, x2 = (double)c2->x, y2 = (double)c2->y,
         x3 = (double)to->x, y3 = (double)to->y;
  /* |B''| <= 6 max(|P0 - 2 P1 + P2|, |P1 - 2 P2 + P3|) */
  double d = 6 * fmax(hypot(x0 - 2 * x1 + x2, y0 - 2 * y1 + y2), hypot(x1 - 2 * x2 + x3, y1 - 2 * y2 + y3));
  int n = steps_for(d, f->tol);
  for (int i = 1; i <= n; i++) {
    double t = (double)i / n, u = 1 - t;
    emit(f, u * u * u * x0 + 3 * u * u * t * x1 + 3 * u * t * t * x2 + t * t * t * x3,
         u * u * u * y0 + 3 * u * u * t * y1 + 3 * u * t * t * y2 + t * t * t * y3);
  }
  return 0;
}

/* ---- laying out ---------------------------------------------------------- */

static hb_buffer_t *shaped(const TextLayout *t, hb_font_t *font) {
  hb_buffer_t *buf = hb_buffer_create();
  hb_buffer_add_utf8(buf, t->text, t->len, 0, t->len);
  if (t->direction != TEXT_AUTO)
    hb_buffer_set_direction(buf, t->direction == TEXT_LTR ? HB_DIRECTION_LTR
                                 : t->direction == TEXT_RTL ? HB_DIRECTION_RTL : HB_DIRECTION_TTB);
  if (t->script) hb_buffer_set_script(buf, hb_script_from_string(t->script, -1));
  if (t->language) hb_buffer_set_language(buf, hb_language_from_string(t->language, -1));
  hb_buffer_guess_segment_properties(buf);
  hb_shape(font, buf, NULL, 0);
  return buf;
}

/* Move the outline by the alignment: horizontally by the advance and the
** height above and below the baseline (as OpenSCAD), vertically by the
** outline's extent. */
static void align(const TextLayout *t, int vertical, Flat *f, double advance) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY, dx = 0, dy = 0;
  for (int i = 0; i < f->npts; i++) {
    x0 = fmin(x0, f->pts[i].x), x1 = fmax(x1, f->pts[i].x);
    y0 = fmin(y0, f->pts[i].y), y1 = fmax(y1, f->pts[i].y);
  }
  if (f->npts == 0) x0 = x1 = y0 = y1 = 0;
  if (!vertical) {
    double asc = fmax(0, y1), desc = fmax(0, -y0);
    dx = t->halign == TEXT_RIGHT ? -advance : t->halign == TEXT_CENTER ? -advance / 2 : 0;
    dy = t->valign == TEXT_TOP ? -asc : t->valign == TEXT_VCENTER ? (desc - asc) / 2 : t->valign == TEXT_BOTTOM ? desc : 0;
  } else {
    dx = t->halign == TEXT_RIGHT ? -x1 : t->halign == TEXT_CENTER ? -(x0 + x1) / 2 : -x0;
    dy = t->valign == TEXT_TOP ? -y1 : t->valign == TEXT_VCENTER ? -(y0 + y1) / 2 : t->valign == TEXT_BOTTOM ? -y0 : 0;
  }
  for (int i = 0; i < f->npts; i++) f->pts[i].x += dx, f->pts[i].y += dy;
}

/* Outline every glyph of buf at its place; the pen's travel in *advance. */
static int outline_glyphs(const TextLayout *t, FT_Face face, hb_buffer_t *buf, double scale, Flat *f,
                          double *advance, char *err, size_t errlen) {
  unsigned n;
  hb_glyph_info_t *info = hb_buffer_get_glyph_infos(buf, &n);
  hb_glyph_position_t *pos = hb_buffer_get_glyph_positions(buf, &n);
  FT_Outline_Funcs funcs = {on_move, on_line, on_conic, on_cubic, 0, 0};
  double px = 0, py = 0;
  for (unsigned i = 0; i < n && !f->over; i++) {
    FT_Error e = FT_Load_Glyph(face, info[i].codepoint, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP);
    if (e) { snprintf(err, errlen, "FreeType cannot load glyph %u (error %d)", info[i].codepoint, e); return -1; }
    f->ox = px + pos[i].x_offset, f->oy = py + pos[i].y_offset;
    if (face->glyph->format == FT_GLYPH_FORMAT_OUTLINE) {
      FT_Outline_Decompose(&face->glyph->outline, &funcs, f);
      close_contour(f);
    }
    px += pos[i].x_advance * t->spacing, py += pos[i].y_advance * t->spacing;
  }
  *advance = hypot(px, py) * scale;
  return 0;
}

int text_outline(const TextLayout *t, int max_points, TextOutline *out, char *err, size_t errlen) {
  memset(out, 0, sizeof *out);
  pthread_once(&libs_once, libs_init);
  if (!libs_ok) { snprintf(err, errlen, "fontconfig or FreeType did not start"); return -1; }
  FontFile ff;
  if (find_font(t, &ff, out, err, errlen)) return -1;
  pthread_mutex_lock(&libs_lock);
  FT_Face face = NULL;
  hb_blob_t *blob = NULL;
  hb_face_t *hface = NULL;
  hb_font_t *hfont = NULL;
  hb_buffer_t *buf = NULL;
  Flat f = {0};
  int rc = -1;
  FT_Error e = FT_New_Face(ft_lib, ff.path, ff.index, &face);
  if (e) { snprintf(err, errlen, "FreeType cannot read the font `%s` (error %d)", ff.path, e); goto out; }
  blob = hb_blob_create_from_file_or_fail(ff.path);
  if (!blob) { snprintf(err, errlen, "HarfBuzz cannot read the font `%s`", ff.path); goto out; }
  hface = hb_face_create(blob, (unsigned)ff.index);
  hfont = hb_font_create(hface);   /* positions in font units: the scale is the em */
  double upem = hb_face_get_upem(hface);
  hb_font_set_scale(hfont, (int)upem, (int)upem);
  buf = shaped(t, hfont);
  double scale = t->size * TEXT_EM_PER_SIZE / upem;
  f.tol = TEXT_TOLERANCE_EM * upem;
  f.scale = scale;
  f.max_points = max_points;
  f.start = xgrow(NULL, &f.capc, 2, sizeof *f.start);
  f.start[0] = 0;
  if (outline_glyphs(t, face, buf, scale, &f, &out->advance, err, errlen)) goto out;
  if (f.over) {
    snprintf(err, errlen, "its outline has more than %d points", max_points);
    goto out;
  }
  align(t, HB_DIRECTION_IS_VERTICAL(hb_buffer_get_direction(buf)), &f, out->advance);
  out->ncontours = f.ncontours;
  out->start = f.start;
  out->pts = f.pts;
  out->nglyphs = (int)hb_buffer_get_length(buf);
  f.start = NULL, f.pts = NULL;
  rc = 0;
out:
  free(f.start);
  free(f.pts);
  if (buf) hb_buffer_destroy(buf);
  if (hfont) hb_font_destroy(hfont);
  if (hface) hb_face_destroy(hface);
  if (blob) hb_blob_destroy(blob);
  if (face) FT_Done_Face(face);
  pthread_mutex_unlock(&libs_lock);
  return rc;
}

void text_outline_free(TextOutline *o) {
  free(o->start);
  free(o->pts);
  o->start = NULL;
  o->pts = NULL;
  o->ncontours = 0;
}
