/*
** Stitching tiles (assemble.h): read each tile as stored, check it against
** the first, paste it into the frame, and write the frame when every tile
** of the split is there.
*/
#include "assemble.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/split.h"
#include "image.h"

/* Bytes a sample of a raw image takes. */
static size_t sample_bytes(int type) {
  return type == IMAGE_RAW_U8 ? 1 : type == IMAGE_RAW_U16 ? 2 : sizeof(float);
}

/* The split a tile name ("I/N" or "I/CxR") belongs to: the part after '/'. */
static const char *split_of(const char *name) {
  const char *slash = strchr(name, '/');
  return slash ? slash + 1 : "";
}

/* Check tile raw (from path) against the first tile (first, from path0);
** 0 with the reason in err when they are not of one render. */
static int same_render(const ImageRaw *raw, const char *path, const ImageRaw *first, const char *path0, char *err,
                       size_t errlen) {
  const ImageTile *a = &raw->tile, *b = &first->tile;
  const char *why = NULL;
  if (strcmp(a->render, b->render)) why = "a different render (another scene, frame or size)";
  else if (strcmp(split_of(a->name), split_of(b->name))) why = "a different split";
  else if (a->full_width != b->full_width || a->full_height != b->full_height) why = "a different frame size";
  else if (raw->type != first->type || raw->channels != first->channels) why = "a different kind of pixel";
  if (!why) return 1;
  snprintf(err, errlen, "`%s` (tile %s of %dx%d) is from %s than `%s` (tile %s of %dx%d)", path, a->name,
           a->full_width, a->full_height, why, path0, b->name, b->full_width, b->full_height);
  return 0;
}

/* Check that raw (from path) is tile t of its split, where and as large
** as the split puts it; 0 with the reason in err. */
static int in_place(const ImageRaw *raw, const char *path, const TileSpec *t, char *err, size_t errlen) {
  int x0, y0, x1, y1;
  char why[256];
  const ImageTile *it = &raw->tile;
  if (!tile_split_rect(t, it->full_width, it->full_height, &x0, &y0, &x1, &y1, why, sizeof why)) {
    snprintf(err, errlen, "`%s`: %s", path, why);
    return 0;
  }
  if (it->x == x0 && it->y == y0 && raw->width == x1 - x0 && raw->height == y1 - y0) return 1;
  snprintf(err, errlen, "`%s` says it is tile %s, at %d,%d and %dx%d, but that tile is at %d,%d and %dx%d", path,
           it->name, it->x, it->y, raw->width, raw->height, x0, y0, x1 - x0, y1 - y0);
  return 0;
}

/* Copy raw's rows into the frame (fw pixels wide, at its place). */
static void paste(unsigned char *frame, int fw, const ImageRaw *raw) {
  size_t px = sample_bytes(raw->type) * (size_t)raw->channels, row = (size_t)raw->width * px;
  for (int y = 0; y < raw->height; y++)
    memcpy(frame + ((size_t)(raw->tile.y + y) * fw + (size_t)raw->tile.x) * px,
           (const unsigned char *)raw->data + (size_t)y * row, row);
}

/* Read paths[i] as a tile, check it against *first (read first when it is
** NULL) and paste it; seen[] marks the tiles pasted, with the file that
** gave each. 0 with the reason in err. */
static int add_tile(const char *const *paths, int i, ImageRaw *first, unsigned char **frame, int *seen,
                    char *err, size_t errlen) {
  ImageRaw raw;
  char why[768];
  if (!image_read_raw(paths[i], &raw, why, sizeof why)) {
    snprintf(err, errlen, "%s", why);
    return 0;
  }
  TileSpec t;
  int ok = raw.has_tile && tile_parse(raw.tile.name, &t, why, sizeof why);
  if (!ok) snprintf(err, errlen, "`%s` is not a tile of `sumi render --tile` (its description does not place it)", paths[i]);
  if (ok && first->data) ok = same_render(&raw, paths[i], first, paths[0], err, errlen);
  if (ok) ok = in_place(&raw, paths[i], &t, err, errlen);
  if (ok && seen[0] && seen[t.index] > 0) {
    snprintf(err, errlen, "tile %s is given twice: `%s` and `%s`", raw.tile.name, paths[seen[t.index] - 1], paths[i]);
    ok = 0;
  }
  if (ok && !first->data) {   /* the first tile sets the frame up */
    size_t n = (size_t)raw.tile.full_width * raw.tile.full_height * (size_t)raw.channels * sample_bytes(raw.type);
    *frame = xmalloc(n);
    seen[0] = t.cols * t.rows;
  }
  if (ok) {
    paste(*frame, raw.tile.full_width, &raw);
    seen[t.index] = i + 1;
  }
  if (ok && !first->data) {
    *first = raw;   /* kept: its header is what the others must match */
    return 1;
  }
  image_raw_free(&raw);
  return ok;
}

int assemble_tiles(const char *const *paths, int n, const char *out, char *err, size_t errlen) {
  ImageRaw first;
  memset(&first, 0, sizeof first);
  unsigned char *frame = NULL;
  int *seen = xcalloc(SPLIT_MAX_TILES + 1, sizeof *seen);   /* [0]: the split's count once known */
  int ok = n > 0;
  if (!ok) snprintf(err, errlen, "no tiles to assemble");
  for (int i = 0; i < n && ok; i++) ok = add_tile(paths, i, &first, &frame, seen, err, errlen);
  for (int k = 1; ok && k <= seen[0]; k++)
    if (!seen[k]) {
      snprintf(err, errlen, "tile %d/%s is missing (%d of %d tiles given)", k, split_of(first.tile.name), n,
               seen[0]);
      ok = 0;
    }
  if (ok) {
    ImageRaw whole = first;
    whole.width = first.tile.full_width;
    whole.height = first.tile.full_height;
    whole.data = frame;
    whole.has_tile = 0;
    ok = image_write_raw(out, &whole, err, errlen);
  }
  free(frame);
  free(seen);
  image_raw_free(&first);
  return ok;
}
