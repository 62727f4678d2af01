/*
** Text as outlines: a string laid out by HarfBuzz (shaping: kerning,
** ligatures, marks, right-to-left and vertical runs) in a font fontconfig
** finds by name, each glyph's outline read by FreeType and its curves
** flattened into polygons. The contours come back in scene units, to be
** filled non-zero (shape2d_from_contours), as OpenSCAD's text() makes
** them: the em is size / 0.72, so capitals stand about size tall.
*/
#ifndef geom_text_h
#define geom_text_h

#include <stddef.h>

#include "../base/vec.h"

/* The em square of text of size s: s / 0.72 (OpenSCAD's scale). */
#define TEXT_EM_PER_SIZE (1 / 0.72)
/* Curves are flattened until they stray at most this fraction of the em
** from the true outline. */
#define TEXT_TOLERANCE_EM 1e-3
/* The font a text names none of. */
#define TEXT_DEFAULT_FONT "DejaVu Sans"

typedef enum { TEXT_LEFT, TEXT_CENTER, TEXT_RIGHT } TextHAlign;
typedef enum { TEXT_BASELINE, TEXT_TOP, TEXT_VCENTER, TEXT_BOTTOM } TextVAlign;
typedef enum { TEXT_AUTO, TEXT_LTR, TEXT_RTL, TEXT_TTB } TextDirection;

typedef struct TextLayout {
  const char *text;           /* UTF-8, len bytes */
  int len;
  double size;                /* > 0 */
  const char *font;           /* a fontconfig name ("DejaVu Sans:style=Bold"); NULL: the default */
  TextHAlign halign;
  TextVAlign valign;
  double spacing;             /* advances are multiplied by it */
  TextDirection direction;    /* TEXT_AUTO: from the script (right-to-left for Arabic, Hebrew) */
  const char *language;       /* BCP 47 ("ja"), or NULL: from the locale-free default */
  const char *script;         /* ISO 15924 ("Jpan"), or NULL: detected */
} TextLayout;

typedef struct TextOutline {
  int ncontours;
  int *start;                 /* ncontours + 1 offsets into pts (malloc'd) */
  Vec2 *pts;                  /* malloc'd */
  int nglyphs;
  double advance;             /* the pen's travel along the line, spacing included (scene units) */
  char family[128];           /* the font's family as fontconfig names it */
  int substituted;            /* the named font is not installed: another drew the text */
  int fallback;               /* the named font lacks some of the text's characters: another drew it */
} TextOutline;

/* Lay out and outline t into *out (release with text_outline_free);
** nonzero with a one-line reason in err when no font can draw it or a
** font file cannot be read. max_points bounds the outline's points. */
int text_outline(const TextLayout *t, int max_points, TextOutline *out, char *err, size_t errlen);
void text_outline_free(TextOutline *o);

#endif
