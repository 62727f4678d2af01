/*
** Text outlines: advances match FreeType's own metrics (digits, a kerned
** pair from the font's kern table, spacing), CJK glyphs are one em wide
** and tall, fontconfig's fallbacks are reported, alignment puts the
** outline where OpenSCAD does, and glyphs keep their holes.
*/
#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H
#include FT_BBOX_H
#include <string.h>

#include "../../src/geom/shape2d.h"
#include "../../src/geom/text.h"
#include "unit.h"

static const char *const DEJAVU = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
static char err[512];

static TextLayout layout(const char *s, const char *font) {
  TextLayout t = {s, (int)strlen(s), 10, font, TEXT_LEFT, TEXT_BASELINE, 1, TEXT_AUTO, NULL, NULL};
  return t;
}

static int outline(const TextLayout *t, TextOutline *o) {
  int r = text_outline(t, SHAPE2D_MAX_POINTS, o, err, sizeof err);
  if (r) fprintf(stderr, "text: %s\n", err);
  return r;
}

static void bounds(const TextOutline *o, double *x0, double *x1, double *y0, double *y1) {
  *x0 = *y0 = INFINITY, *x1 = *y1 = -INFINITY;
  for (int i = 0; i < o->start[o->ncontours]; i++) {
    *x0 = fmin(*x0, o->pts[i].x), *x1 = fmax(*x1, o->pts[i].x);
    *y0 = fmin(*y0, o->pts[i].y), *y1 = fmax(*y1, o->pts[i].y);
  }
}

/* FreeType's advance of character c in font units, read directly. */
static FT_Face face;
static double ft_advance(unsigned c) {
  FT_Load_Glyph(face, FT_Get_Char_Index(face, c), FT_LOAD_NO_SCALE);
  return (double)face->glyph->advance.x;
}

TEST(digit_advances_match_freetype) {
  TextLayout t = layout("0123456789", "DejaVu Sans");
  TextOutline o;
  CHECK(outline(&t, &o) == 0);
  double s = 10 / 0.72 / face->units_per_EM, want = 0;
  for (const char *p = t.text; *p; p++) want += ft_advance((unsigned char)*p);
  CHECK_NEAR(o.advance, want * s, 1e-9);
  CHECK_EQ_INT(o.nglyphs, 10);
  CHECK(!strcmp(o.family, "DejaVu Sans"));
  CHECK(!o.substituted && !o.fallback);
  text_outline_free(&o);
  t.spacing = 1.5;   /* spacing multiplies every advance */
  CHECK(outline(&t, &o) == 0);
  CHECK_NEAR(o.advance, 1.5 * want * s, 1e-9);
  text_outline_free(&o);
}

TEST(kerned_pair_matches_freetype) {
  /* HarfBuzz kerns "AV" by the amount FreeType reads from the font */
  TextLayout t = layout("AV", "DejaVu Sans");
  TextOutline o;
  CHECK(outline(&t, &o) == 0);
  FT_Vector k;
  FT_Get_Kerning(face, FT_Get_Char_Index(face, 'A'), FT_Get_Char_Index(face, 'V'), FT_KERNING_UNSCALED, &k);
  CHECK(k.x < 0);
  double s = 10 / 0.72 / face->units_per_EM;
  CHECK_NEAR(o.advance, (ft_advance('A') + ft_advance('V') + (double)k.x) * s, 1e-9);
  text_outline_free(&o);
}

TEST(outline_matches_freetype_bbox) {
  /* "I" alone: its outline spans FreeType's control box, scaled */
  TextLayout t = layout("I", "DejaVu Sans");
  TextOutline o;
  CHECK(outline(&t, &o) == 0);
  FT_Load_Glyph(face, FT_Get_Char_Index(face, 'I'), FT_LOAD_NO_SCALE);
  FT_BBox b;
  FT_Outline_Get_BBox(&face->glyph->outline, &b);
  double s = 10 / 0.72 / face->units_per_EM, x0, x1, y0, y1;
  bounds(&o, &x0, &x1, &y0, &y1);
  CHECK_NEAR(x0, b.xMin * s, 1e-9);
  CHECK_NEAR(x1, b.xMax * s, 1e-9);
  CHECK_NEAR(y0, b.yMin * s, 1e-9);
  CHECK_NEAR(y1, b.yMax * s, 1e-9);
  CHECK(y1 > 9 && y1 < 11);   /* a capital stands about `size` tall */
  text_outline_free(&o);
}

TEST(glyphs_keep_their_holes) {
  /* "o": an outer contour and its counter, filled non-zero to a ring */
  TextLayout t = layout("o", NULL);
  TextOutline o;
  CHECK(outline(&t, &o) == 0);
  CHECK_EQ_INT(o.ncontours, 2);
  Arena a;
  arena_init(&a);
  SceneGeometry *g = shape2d_from_contours(&a, o.pts, o.start, o.ncontours, SUMI_P2D_NON_ZERO, err, sizeof err);
  CHECK(g && g->ncontours == 2);
  double x0, x1, y0, y1;
  bounds(&o, &x0, &x1, &y0, &y1);
  CHECK(shape2d_area(g) > 0 && shape2d_area(g) < 0.6 * (x1 - x0) * (y1 - y0));
  arena_free(&a);
  text_outline_free(&o);
}

TEST(alignment) {
  TextOutline o;
  double x0, x1, y0, y1;
  TextLayout t = layout("Hg", NULL);
  t.halign = TEXT_RIGHT, t.valign = TEXT_TOP;
  CHECK(outline(&t, &o) == 0);
  bounds(&o, &x0, &x1, &y0, &y1);
  CHECK(x1 <= 0 && x1 > -10 / 0.72 / 4);   /* the advance ends at 0, a little past the ink */
  CHECK_NEAR(y1, 0, 1e-12);
  text_outline_free(&o);
  t.halign = TEXT_CENTER, t.valign = TEXT_BOTTOM;
  CHECK(outline(&t, &o) == 0);
  double adv = o.advance;
  bounds(&o, &x0, &x1, &y0, &y1);
  CHECK_NEAR(y0, 0, 1e-12);
  text_outline_free(&o);
  t.halign = TEXT_LEFT;
  CHECK(outline(&t, &o) == 0);
  double l0, l1, m0, m1;
  bounds(&o, &l0, &l1, &m0, &m1);
  CHECK_NEAR(x0, l0 - adv / 2, 1e-9);   /* centred: moved back half the advance */
  text_outline_free(&o);
  t.valign = TEXT_VCENTER;
  CHECK(outline(&t, &o) == 0);
  bounds(&o, &x0, &x1, &y0, &y1);
  CHECK_NEAR(y0 + y1, 0, 1e-9);
  text_outline_free(&o);
}

TEST(cjk_is_one_em_a_glyph) {
  /* Noto Sans CJK's ideographs advance one em, across and down */
  TextLayout t = layout("\xe6\xbc\xa2\xe5\xad\x97", "Noto Sans CJK JP");   /* 漢字 */
  TextOutline o;
  CHECK(outline(&t, &o) == 0);
  CHECK(!strcmp(o.family, "Noto Sans CJK JP"));
  CHECK_NEAR(o.advance, 2 * 10 / 0.72, 1e-9);
  CHECK(o.ncontours >= 6);
  text_outline_free(&o);
  t.direction = TEXT_TTB;
  CHECK(outline(&t, &o) == 0);
  CHECK_NEAR(o.advance, 2 * 10 / 0.72, 1e-9);
  double x0, x1, y0, y1;
  bounds(&o, &x0, &x1, &y0, &y1);
  CHECK(y1 - y0 > 1.5 * 10 / 0.72 && x1 - x0 < 10 / 0.72);   /* a column, not a row */
  text_outline_free(&o);
}

TEST(fallback_and_substitution) {
  TextOutline o;
  TextLayout t = layout("\xe5\xa2\xa8", NULL);   /* 墨: not in DejaVu: fontconfig's choice draws it */
  CHECK(outline(&t, &o) == 0);
  CHECK(o.fallback && !o.substituted);
  CHECK(strstr(o.family, "CJK") != NULL);
  text_outline_free(&o);
  t = layout("abc", "No Such Font Family");
  CHECK(outline(&t, &o) == 0);
  CHECK(o.substituted);
  text_outline_free(&o);
  t = layout("\xee\x80\x80", NULL);   /* U+E000, private use: no font has it */
  CHECK(text_outline(&t, SHAPE2D_MAX_POINTS, &o, err, sizeof err) != 0);
  CHECK(strstr(err, "U+E000") != NULL);
}

TEST(point_limit) {
  TextLayout t = layout("sumi", NULL);
  TextOutline o;
  CHECK(text_outline(&t, 50, &o, err, sizeof err) != 0);
  CHECK(strstr(err, "more than 50 points") != NULL);
}

int main(void) {
  FT_Library lib;
  FT_Init_FreeType(&lib);
  if (FT_New_Face(lib, DEJAVU, 0, &face)) {
    printf("0 passed, 1 failed\n");
    fprintf(stderr, "cannot read %s (fonts-dejavu-core)\n", DEJAVU);
    return 1;
  }
  RUN(digit_advances_match_freetype);
  RUN(kerned_pair_matches_freetype);
  RUN(outline_matches_freetype_bbox);
  RUN(glyphs_keep_their_holes);
  RUN(alignment);
  RUN(cjk_is_one_em_a_glyph);
  RUN(fallback_and_substitution);
  RUN(point_limit);
  FT_Done_Face(face);
  FT_Done_FreeType(lib);
  return unit_done();
}
