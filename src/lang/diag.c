/*
** Diagnostics: the table of loaded sources and the printing of messages in
** the style of a compiler (text with a source line and a caret), or as one
** JSON object a line for editors.
*/
#include "diag.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../base/mem.h"
#include "../base/utf8.h"
#include "../io/infile.h"

/* A source line longer than this many characters is shown as a window
** around the error column. */
#define DIAG_LINE_WINDOW 100

static struct {
  SrcFile *files;
  int nfiles, capfiles;
  DiagFormat format;
  int errors, warnings;
  int suppressed;   /* the last error was past the cap: drop its notes */
  int said_too_many;
} D;

static void (*before_output)(void);   /* kept across diag_init */

void diag_before_output(void (*fn)(void)) { before_output = fn; }

void diag_init(DiagFormat format) {
  memset(&D, 0, sizeof D);
  D.format = format;
}

void diag_shutdown(void) {
  for (int i = 0; i < D.nfiles; i++) {
    free(D.files[i].name);
    free(D.files[i].text);
    free(D.files[i].line_start);
    free(D.files[i].wide);
  }
  free(D.files);
  memset(&D, 0, sizeof D);
}

SrcRange src_none(void) {
  SrcRange r = {-1, 0, 0, 0, 0};
  return r;
}

SrcRange src_join(SrcRange a, SrcRange b) {
  if (a.file < 0) return b;
  if (b.file < 0 || b.file != a.file) return a;
  a.end_line = b.end_line;
  a.end_col = b.end_col;
  return a;
}

/* Find the file's multibyte characters, stepping as the lexer does (a
** character never spans a newline, so stepping from the file's start meets
** every line's start). */
static void find_wide(SrcFile *f) {
  const unsigned char *p = (const unsigned char *)f->text, *end = p + f->len;
  int cap = 0;
  uint32_t extra = 0;
  f->nwide = 0;
  while (p < end) {
    if (*p < 0x80) { p++; continue; }
    uint32_t cp;
    int n = utf8_decode(p, end, &cp);
    if (n > 1) {
      extra += (uint32_t)n - 1;
      f->wide = xgrow(f->wide, &cap, f->nwide + 1, sizeof *f->wide);
      f->wide[f->nwide++] = (SrcWide){(uint32_t)(p - (const unsigned char *)f->text), extra};
    }
    p += n ? n : 1;
  }
}

/* Bytes beyond one taken by the multibyte characters before offset at. */
static uint32_t wide_extra(const SrcFile *f, uint32_t at) {
  int lo = 0, hi = f->nwide;   /* the first character at or after `at` */
  while (lo < hi) {
    int mid = lo + (hi - lo) / 2;
    if (f->wide[mid].at < at) lo = mid + 1;
    else hi = mid;
  }
  return lo ? f->wide[lo - 1].extra : 0;
}

/* Line and column of byte offset at (a character boundary): the last line
** starting at or before it, then its bytes from that line's start less
** those the multibyte characters take beyond one each. Both searches are
** binary, so even a megabyte on one line costs little per node. */
static void position(SrcFile *f, uint32_t at, int *line, int *col) {
  if (f->nwide < 0) find_wide(f);
  int lo = 0, hi = f->nlines - 1;
  while (lo < hi) {
    int mid = lo + (hi - lo + 1) / 2;
    if ((uint32_t)f->line_start[mid] <= at) lo = mid;
    else hi = mid - 1;
  }
  uint32_t start = (uint32_t)f->line_start[lo];
  *line = lo + 1;
  *col = 1 + (int)(at - start - (wide_extra(f, at) - wide_extra(f, start)));
}

SrcRange diag_range(int file, uint32_t start, uint32_t end) {
  if (file < 0 || file >= D.nfiles) return src_none();
  SrcFile *f = &D.files[file];
  SrcRange r = {file, 0, 0, 0, 0};
  position(f, start, &r.line, &r.col);
  position(f, end, &r.end_line, &r.end_col);
  return r;
}

/* ---- the source table ------------------------------------------------ */

int diag_add_file(const char *name, char *text, size_t len, int included_from, SrcRange include_loc) {
  D.files = xgrow(D.files, &D.capfiles, D.nfiles + 1, sizeof(SrcFile));
  SrcFile *f = &D.files[D.nfiles];
  f->name = xstrdup(name);
  f->text = text;
  f->len = len;
  f->included_from = included_from;
  f->include_loc = include_loc;
  f->wide = NULL;
  f->nwide = -1;
  int cap = 0;
  f->line_start = NULL;
  f->nlines = 0;
  f->line_start = xgrow(f->line_start, &cap, 1, sizeof(int));
  f->line_start[f->nlines++] = 0;
  /* memchr scans many bytes a step (a byte loop was 5% of a parse) */
  const char *end = text + len;
  for (const char *nl = memchr(text, '\n', len); nl; nl = memchr(nl + 1, '\n', (size_t)(end - nl - 1))) {
    f->line_start = xgrow(f->line_start, &cap, f->nlines + 1, sizeof(int));
    f->line_start[f->nlines++] = (int)(nl + 1 - text);
  }
  return D.nfiles++;
}

const SrcFile *diag_file(int index) {
  return index >= 0 && index < D.nfiles ? &D.files[index] : NULL;
}

int diag_file_count(void) { return D.nfiles; }

const char *diag_path_beside(SrcRange at, const char *name, char *out, size_t n) {
  const SrcFile *f = at.file >= 0 ? diag_file(at.file) : NULL;
  const char *slash = f ? strrchr(f->name, '/') : NULL;
  if (name[0] == '/' || !slash) return name;
  snprintf(out, n, "%.*s/%s", (int)(slash - f->name), f->name, name);
  return out;
}

/* Largest source accepted, so offsets fit in an int. */
#define DIAG_MAX_SOURCE_BYTES ((size_t)1 << 30)

static char *read_stream(FILE *f, size_t *len) {
  size_t cap = 1 << 16, n = 0;
  struct stat st;   /* a regular file is read in one go, without regrowing */
  if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && (size_t)st.st_size < DIAG_MAX_SOURCE_BYTES)
    cap = (size_t)st.st_size + 1;
  char *buf = xmalloc(cap + 1);
  mem_advise_huge(buf, cap + 1);
  for (;;) {
    size_t got = fread(buf + n, 1, cap - n, f);
    n += got;
    if (n > DIAG_MAX_SOURCE_BYTES) { free(buf); errno = EFBIG; return NULL; }
    if (got == 0) break;
    if (n == cap) { cap *= 2; buf = xrealloc(buf, cap + 1); }
  }
  if (ferror(f)) { free(buf); return NULL; }
  buf[n] = '\0';
  *len = n;
  return buf;
}

int diag_load_file(const char *path, int included_from, SrcRange include_loc, const char **why) {
  FILE *f = stdin;
  if (strcmp(path, "-") != 0) {
    static char reason[160];
    if (!infile_check(path, INFILE_MAX_SOURCE, "a scene file", reason, sizeof reason)) { *why = reason; return -1; }
    f = fopen(path, "rb");
    if (!f) { *why = strerror(errno); return -1; }
  }
  size_t len = 0;
  char *text = read_stream(f, &len);
  int err = errno;
  if (f != stdin) fclose(f);
  if (!text) { *why = err == EFBIG ? "file is larger than 1 GiB" : strerror(err); return -1; }
  return diag_add_file(strcmp(path, "-") == 0 ? "<stdin>" : path, text, len, included_from, include_loc);
}

/* ---- printing -------------------------------------------------------- */

static const char *severity_name(DiagSeverity s) {
  return s == DIAG_ERROR ? "error" : s == DIAG_WARNING ? "warning" : "note";
}

/* Byte offset in [begin, end) of the character with 1-based index col, or
** end when the line is shorter. Invalid bytes count as one character each. */
static const char *char_at(const char *begin, const char *end, int col) {
  const unsigned char *p = (const unsigned char *)begin;
  for (int c = 1; c < col && p < (const unsigned char *)end; c++) {
    uint32_t cp;
    int n = utf8_decode(p, (const unsigned char *)end, &cp);
    p += n ? n : 1;
  }
  return (const char *)p;
}

/* Print [a, b) of a source line, with tabs as one space and anything that is
** not printable UTF-8 as '?', so one character is one column. */
static void put_visible(FILE *out, const char *a, const char *b) {
  const unsigned char *p = (const unsigned char *)a;
  while (p < (const unsigned char *)b) {
    uint32_t cp;
    int n = utf8_decode(p, (const unsigned char *)b, &cp);
    if (n == 0) { fputc('?', out); p++; continue; }
    if (cp == '\t') fputc(' ', out);
    else if (cp < 0x20 || cp == 0x7F) fputc('?', out);
    else fwrite(p, 1, (size_t)n, out);
    p += n;
  }
}

static int count_chars(const char *a, const char *b) {
  int n = 0;
  const unsigned char *p = (const unsigned char *)a;
  while (p < (const unsigned char *)b) {
    uint32_t cp;
    int k = utf8_decode(p, (const unsigned char *)b, &cp);
    p += k ? k : 1;
    n++;
  }
  return n;
}

/* The source line of `at`, and a caret line under the range:
**    12 |   lines { widht 2; }
**       |           ^~~~~                                                  */
static void print_source_line(FILE *out, SrcRange at) {
  const SrcFile *f = diag_file(at.file);
  if (!f || at.line < 1 || at.line > f->nlines) return;
  const char *begin = f->text + f->line_start[at.line - 1];
  const char *end = at.line < f->nlines ? f->text + f->line_start[at.line] - 1 : f->text + f->len;
  if (end > begin && end[-1] == '\r') end--;
  int ncols = count_chars(begin, end);
  int first = 1, last = ncols;   /* window of columns shown */
  if (ncols > DIAG_LINE_WINDOW) {
    first = at.col - DIAG_LINE_WINDOW / 2;
    if (first < 1) first = 1;
    last = first + DIAG_LINE_WINDOW - 1;
    if (last > ncols) { last = ncols; first = last - DIAG_LINE_WINDOW + 1; }
  }
  int span = at.end_line == at.line ? at.end_col - at.col : ncols + 1 - at.col;
  if (span < 1) span = 1;
  if (at.col + span - 1 > last + 1) span = last + 2 - at.col;
  char gutter[16];
  int gw = snprintf(gutter, sizeof gutter, "%5d", at.line);
  fprintf(out, "%s | %s", gutter, first > 1 ? "..." : "");
  put_visible(out, char_at(begin, end, first), char_at(begin, end, last + 1));
  fprintf(out, "%s\n", last < ncols ? "..." : "");
  fprintf(out, "%*s | %s", gw, "", first > 1 ? "   " : "");
  for (int c = first; c < at.col; c++) fputc(' ', out);
  fputc('^', out);
  for (int i = 1; i < span; i++) fputc('~', out);
  fputc('\n', out);
}

/* "In file included from a.npr:3:1:" lines, outermost last, as gcc does. */
static void print_include_chain(FILE *out, int file) {
  const SrcFile *f = diag_file(file);
  int first = 1;
  while (f && f->included_from >= 0) {
    const SrcFile *parent = diag_file(f->included_from);
    fprintf(out, "%s %s:%d:%d:\n", first ? "In file included from" : "                 from",
            parent->name, f->include_loc.line, f->include_loc.col);
    first = 0;
    f = parent;
  }
}

static void print_json(DiagSeverity sev, SrcRange at, const char *msg) {
  cJSON *o = cJSON_CreateObject();
  const SrcFile *f = diag_file(at.file);
  cJSON_AddStringToObject(o, "file", f ? f->name : "");
  cJSON_AddNumberToObject(o, "line", f ? at.line : 0);
  cJSON_AddNumberToObject(o, "column", f ? at.col : 0);
  cJSON *end = cJSON_AddObjectToObject(o, "end");
  cJSON_AddNumberToObject(end, "line", f ? at.end_line : 0);
  cJSON_AddNumberToObject(end, "column", f ? at.end_col : 0);
  cJSON_AddStringToObject(o, "severity", severity_name(sev));
  cJSON_AddStringToObject(o, "message", msg);
  if (f && f->included_from >= 0) {
    cJSON *chain = cJSON_AddArrayToObject(o, "included_from");
    for (const SrcFile *g = f; g->included_from >= 0; g = diag_file(g->included_from)) {
      char loc[64];
      const SrcFile *p = diag_file(g->included_from);
      snprintf(loc, sizeof loc, ":%d:%d", g->include_loc.line, g->include_loc.col);
      char *s = xmalloc(strlen(p->name) + sizeof loc);
      strcpy(s, p->name);
      strcat(s, loc);
      cJSON_AddItemToArray(chain, cJSON_CreateString(s));
      free(s);
    }
  }
  char *text = cJSON_PrintUnformatted(o);
  if (!text) sumi_fatal("out of memory printing a diagnostic");
  fprintf(stderr, "%s\n", text);
  cJSON_free(text);
  cJSON_Delete(o);
}

void diag_report(DiagSeverity sev, SrcRange at, const char *fmt, ...) {
  if (sev == DIAG_NOTE && D.suppressed) return;
  if (sev == DIAG_ERROR) {
    D.suppressed = D.errors >= DIAG_MAX_ERRORS;
    D.errors++;
    if (D.suppressed) {
      if (!D.said_too_many) {
        D.said_too_many = 1;
        if (before_output && D.format == DIAG_TEXT) before_output();
        if (D.format == DIAG_TEXT) fprintf(stderr, "sumi: too many errors (limit is %d), stopping\n", DIAG_MAX_ERRORS);
      }
      return;
    }
  } else if (sev == DIAG_WARNING) {
    D.warnings++;
    D.suppressed = 0;
  }
  if (D.format == DIAG_SILENT) return;
  if (before_output) before_output();
  char msg[2048];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  if (D.format == DIAG_JSON) { print_json(sev, at, msg); return; }
  const SrcFile *f = diag_file(at.file);
  if (!f) { fprintf(stderr, "sumi: %s: %s\n", severity_name(sev), msg); return; }
  if (sev != DIAG_NOTE) print_include_chain(stderr, at.file);
  fprintf(stderr, "%s:%d:%d: %s: %s\n", f->name, at.line, at.col, severity_name(sev), msg);
  print_source_line(stderr, at);
}

int diag_error_count(void) { return D.errors; }
int diag_warning_count(void) { return D.warnings; }
int diag_too_many(void) { return D.errors > DIAG_MAX_ERRORS; }
