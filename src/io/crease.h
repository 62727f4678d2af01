/*
** Crease patterns drawn in ORIPA: `.opx` (its XML save format, read with
** libxml2) and `.cp` (one line a segment: `type x1 y1 x2 y2`), read into a
** SceneOrigami of vertices and creases (faces are traced later).
**
** Types: .cp 1 border (B), 2 mountain, 3 valley, 4 flat (auxiliary);
** .opx (oripa.OriLineProxy) 0 auxiliary (F), 1 cut (B), 2 mountain, 3
** valley; any other type is unassigned (U). Segment ends closer than the
** shortest segment / 2^20 are one vertex. Each crease's location is its
** line in the file (registered with diag_load_file), so diagnostics about
** it quote that line.
*/
#ifndef io_crease_h
#define io_crease_h

#include <stddef.h>

#include "../base/mem.h"
#include "../scene/scene.h"

/* Whether path names an ORIPA file (.opx or .cp, any case). */
int crease_is_oripa(const char *path);

/* Read the .opx or .cp file at path into *out (arrays from arena).
** Returns 0, or nonzero with a message naming the file (and line) in err. */
int crease_read(const char *path, SceneOrigami *out, Arena *arena, char *err, size_t errlen);

#endif
