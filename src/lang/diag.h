/*
** Diagnostics: source files, locations, and compiler-style messages
**
**   file:line:col: error: message
**      12 |   lines { widht 2; }
**         |           ^~~~~
**
** Every stage reports through here. Messages are collected (capped at
** DIAG_MAX_ERRORS errors) and printed as they arrive, as text or as JSON
** lines for editors.
*/
#ifndef lang_diag_h
#define lang_diag_h

#include <stddef.h>
#include <stdint.h>

/* A source range. file indexes the table of loaded sources (diag_file);
** line and col are 1-based and count characters, not bytes; (end_line,
** end_col) is the position just past the last character (exclusive).
** file = -1 means "no location". */
typedef struct SrcRange {
  int file;
  int line, col;
  int end_line, end_col;
} SrcRange;

/* A character of more than one byte: where it is, and how many bytes
** beyond one it and the multibyte characters before it take. */
typedef struct SrcWide {
  uint32_t at, extra;
} SrcWide;

typedef struct SrcFile {
  char *name;          /* as given on the command line or the include path */
  char *text;          /* whole contents, NUL-terminated (may hold NULs: use len) */
  size_t len;
  int *line_start;     /* byte offset of each line's first byte */
  int nlines;
  SrcWide *wide;       /* the multibyte characters, for columns (diag_range) */
  int nwide;           /* -1 until diag_range first needs them */
  int included_from;   /* file index of the includer, -1 for the main file */
  SrcRange include_loc;/* where the include statement is */
} SrcFile;

typedef enum { DIAG_ERROR, DIAG_WARNING, DIAG_NOTE } DiagSeverity;
typedef enum { DIAG_TEXT, DIAG_JSON, DIAG_SILENT } DiagFormat;   /* SILENT: count only (fuzzing) */

/* Errors past this many are not printed; "too many errors" is said once. */
#define DIAG_MAX_ERRORS 20

void diag_init(DiagFormat format);
void diag_shutdown(void);   /* frees every loaded source */

/* Register a source file; takes ownership of text (malloc'd, len bytes plus
** a NUL). Returns its index. */
int diag_add_file(const char *name, char *text, size_t len, int included_from, SrcRange include_loc);
const SrcFile *diag_file(int index);
/* Read a file ("-" is standard input) and register it. Returns its index,
** or -1 with *why set to a static reason (strerror, "is a directory"). */
int diag_load_file(const char *path, int included_from, SrcRange include_loc, const char **why);
int diag_file_count(void);
/* name as a path relative to the folder of the source file at points into
** (as mesh("file") and texture names are read), into out (n bytes); an
** absolute name, or a source with no folder, gives name itself. */
const char *diag_path_beside(SrcRange at, const char *name, char *out, size_t n);

/* Report a diagnostic. fmt is printf-style. A note attaches to the message
** before it. */
void diag_report(DiagSeverity sev, SrcRange at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
#define diag_error(at, ...) diag_report(DIAG_ERROR, (at), __VA_ARGS__)
#define diag_warning(at, ...) diag_report(DIAG_WARNING, (at), __VA_ARGS__)
#define diag_note(at, ...) diag_report(DIAG_NOTE, (at), __VA_ARGS__)

/* fn (NULL: none) runs before a diagnostic is printed, so a progress line
** on the terminal (io/progress.h) can take itself off first. */
void diag_before_output(void (*fn)(void));

int diag_error_count(void);
int diag_warning_count(void);
int diag_too_many(void);      /* the cap was reached: callers may stop early */

/* Location helpers */
SrcRange src_none(void);
SrcRange src_join(SrcRange a, SrcRange b);   /* from a's start to b's end */
/* The range of the bytes [start, end) of a loaded file, in lines and
** columns counted as the lexer counts them. Syntax tree nodes keep the two
** offsets (8 bytes) rather than a SrcRange (20): ast.h's ast_range. */
SrcRange diag_range(int file, uint32_t start, uint32_t end);

#endif
