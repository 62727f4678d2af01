/*
** The `sumi` command line: subcommands, options and exit codes.
**
**   0  success (warnings allowed)
**   1  a diagnostic: the scene, or a file it names, is bad
**   2  bad usage: unknown option, missing argument
*/
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "base/frames.h"
#include "base/mem.h"
#include "geom/origami.h"
#include "geom/origami_layers.h"
#include "io/assemble.h"
#include "io/crease.h"
#include "io/fold.h"
#include "io/mesh_export.h"
#include "io/mesh_import.h"
#include "geom/refine.h"
#include "geom/subdiv.h"
#include "lang/ast.h"
#include "lang/diag.h"
#include "lang/eval.h"
#include "lang/parse.h"
#include "io/image.h"
#include "io/outfile.h"
#include "io/progress.h"
#include "io/tempfile.h"
#include "render/render.h"
#include "render/stats.h"
#include "render/svg.h"
#include "render/tile.h"

#define SUMI_VERSION "0.1.0"

/* Everything the command line can say; each subcommand reads what it needs. */
typedef struct Options {
  const char *command;
  const char *input;
  const char **inputs; int ninputs;   /* every file named (sumi assemble takes several) */
  const char *output;
  int ast, scene, compare, stats, quiet, loop, resume;
  int width, height, threads;
  const char *frames, *only, *aov, *tile;
  const char **defines; int ndefines;
  const char **include_dirs; int ninclude_dirs;
  long limits[8];   /* --max-* values, 0 = default (see LIMIT_OPTIONS) */
  int count;        /* sumi fold: --count, --limit N, --state K, --export FILE */
  long limit, state;
  const char *export_path;
  DiagFormat diag_format;
} Options;

/* Limit options, in the order of Options.limits. */
static const char *const limit_options[] = {
  "--max-recursion", "--max-iterations", "--max-list", "--max-memory-mb", NULL,
};

static void usage(FILE *out) {
  fputs(
    "usage: sumi COMMAND FILE [options]      (FILE may be - for standard input)\n"
    "\n"
    "commands:\n"
    "  render FILE -o OUT   render the scene to an image (png, tif, exr, jpg) or svg\n"
    "  check FILE           parse and evaluate; print diagnostics only\n"
    "  parse FILE [--ast]   parse only; --ast prints the syntax tree\n"
    "  eval FILE --scene    print the evaluated scene as text\n"
    "  faces FILE           list the faces of every origami block\n"
    "  fold FILE            find the flat-folded states of a crease pattern (.fold,\n"
    "                       .opx, .cp): print its components; --count counts each\n"
    "                       one's states (up to --limit N, default 10000); --export\n"
    "                       OUT.fold writes state --state K (default 0) with faceOrders\n"
    "  export FILE -o OUT.stl  write the scene's solids as one binary STL mesh: the\n"
    "                       triangles CSG uses (round shapes 32 a patch side)\n"
    "  refine FILE --compare  compare our tessellation with OpenSubdiv's limit surface\n"
    "  watch FILE -o OUT    render, then render again whenever the scene or a file it\n"
    "                       includes changes (Ctrl-C stops)\n"
    "  assemble TILES... -o OUT  stitch the tiles of render --tile into their frame\n"
    "                       (the bytes one render writes)\n"
    "\n"
    "options:\n"
    "  -o FILE              output file\n"
    "  -W N, -H N           image width / height (one alone keeps the aspect ratio)\n"
    "  -D name=value        override a top-level let (value is an expression)\n"
    "  -I DIR               add an include folder\n"
    "  --frames A:B         render frames A..B; clock runs 0..1 over them, frame is the\n"
    "                       number; OUT's #### (or a 4-digit suffix) takes the frame;\n"
    "                       A:B:STEP every STEP-th, or a list: 1,5,9:12 (the clock\n"
    "                       runs from the lowest frame named to the highest)\n"
    "  --only LIST          with --frames: only these of its frames (e.g. 17, or\n"
    "                       $SLURM_ARRAY_TASK_ID), the clock still the animation's\n"
    "  --loop               with --frames: a loop, clock in [0, 1) (B is not A again)\n"
    "  --resume             skip a frame (or tile) whose file is already whole\n"
    "  --tile I/N, --tile I/CxR  render tile I (from 1, row by row) of the frame cut\n"
    "                       into N rows of tiles, or C columns and R rows; writes a\n"
    "                       .png, .tif or .exr that knows its place (sumi assemble)\n"
    "  --threads N          worker threads (output is identical at any count)\n"
    "  --stats              print per-stage times and peak memory\n"
    "  --aov LIST           also write depth,normal,object,face passes\n"
    "  --diagnostics json   diagnostics as JSON lines (default: text)\n"
    "  --max-recursion N, --max-iterations N, --max-list N, --max-memory-mb N\n"
    "                       evaluation limits\n"
    "  --quiet              no progress line (shown on a terminal only) and no\n"
    "                       frame-by-frame notes\n"
    "  -h, --help           this text\n"
    "  --version            the version\n", out);
}

static _Noreturn void bad_usage(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static _Noreturn void bad_usage(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fputs("sumi: ", stderr);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputs("\nTry `sumi --help`.\n", stderr);
  exit(2);
}

static int parse_int_arg(const char *opt, const char *v, long lo, long hi) {
  char *end;
  errno = 0;
  long n = strtol(v, &end, 10);
  if (errno || *end || end == v || n < lo || n > hi) {
    fprintf(stderr, "sumi: %s needs a whole number from %ld to %ld, got `%s`\nTry `sumi --help`.\n", opt, lo, hi, v);
    exit(2);
  }
  return (int)n;
}

static const char **push_str(const char **list, int *n, const char *s) {
  list = xrealloc((void *)list, (size_t)(*n + 1) * sizeof *list);
  list[(*n)++] = s;
  return list;
}

static void parse_options(int argc, char **argv, Options *o) {
  DiagFormat fmt = DIAG_TEXT;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED_VALUE() do { if (!v) bad_usage("option `%s` needs a value", a); i++; } while (0)
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) { usage(stdout); exit(0); }
    else if (!strcmp(a, "--version")) { printf("sumi %s\n", SUMI_VERSION); exit(0); }
    else if (!strcmp(a, "--ast")) o->ast = 1;
    else if (!strcmp(a, "--scene")) o->scene = 1;
    else if (!strcmp(a, "--compare")) o->compare = 1;
    else if (!strcmp(a, "--stats")) o->stats = 1;
    else if (!strcmp(a, "--quiet")) o->quiet = 1;
    else if (!strcmp(a, "--loop")) o->loop = 1;
    else if (!strcmp(a, "--resume")) o->resume = 1;
    else if (!strcmp(a, "-o")) { NEED_VALUE(); o->output = v; }
    else if (!strcmp(a, "-W")) { NEED_VALUE(); o->width = parse_int_arg(a, v, 1, RENDER_MAX_SIZE); }
    else if (!strcmp(a, "-H")) { NEED_VALUE(); o->height = parse_int_arg(a, v, 1, RENDER_MAX_SIZE); }
    else if (!strcmp(a, "--threads")) { NEED_VALUE(); o->threads = parse_int_arg(a, v, 1, 256); }
    else if (!strcmp(a, "-D")) { NEED_VALUE(); o->defines = push_str(o->defines, &o->ndefines, v); }
    else if (!strcmp(a, "-I")) { NEED_VALUE(); o->include_dirs = push_str(o->include_dirs, &o->ninclude_dirs, v); }
    else if (!strcmp(a, "--frames")) { NEED_VALUE(); o->frames = v; }
    else if (!strcmp(a, "--only")) { NEED_VALUE(); o->only = v; }
    else if (!strcmp(a, "--tile")) { NEED_VALUE(); o->tile = v; }
    else if (!strcmp(a, "--aov")) { NEED_VALUE(); o->aov = v; }
    else if (!strcmp(a, "--count")) o->count = 1;
    else if (!strcmp(a, "--limit")) { NEED_VALUE(); o->limit = parse_int_arg(a, v, 1, 1000000000); }
    else if (!strcmp(a, "--state")) { NEED_VALUE(); o->state = parse_int_arg(a, v, 0, 2000000000); }
    else if (!strcmp(a, "--export")) { NEED_VALUE(); o->export_path = v; }
    else if (!strcmp(a, "--diagnostics")) {
      NEED_VALUE();
      if (!strcmp(v, "json")) fmt = DIAG_JSON;
      else if (!strcmp(v, "text")) fmt = DIAG_TEXT;
      else bad_usage("--diagnostics takes `text` or `json`, not `%s`", v);
    } else if (a[0] == '-' && a[1] == '-' && strncmp(a, "--max-", 6) == 0) {
      int k = 0;
      while (limit_options[k] && strcmp(limit_options[k], a)) k++;
      if (!limit_options[k]) bad_usage("unknown option `%s`", a);
      NEED_VALUE();
      o->limits[k] = parse_int_arg(a, v, 1, 2000000000);
    } else if (a[0] == '-' && a[1] != '\0') bad_usage("unknown option `%s`", a);
    else if (!o->command) o->command = a;
    else {
      o->inputs = push_str(o->inputs, &o->ninputs, a);
      o->input = o->inputs[0];
    }
#undef NEED_VALUE
  }
  if (!o->command) { usage(stderr); exit(2); }
  if (o->loop && !o->frames) bad_usage("--loop makes a loop of --frames A:B: give the frames too");
  if (o->only && !o->frames) bad_usage("--only picks frames of --frames A:B: give the frames too");
  o->diag_format = fmt;
  diag_init(fmt);
}

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Load and parse the input; NULL (after diagnostics) when it cannot be read. */
static AstNode *load_and_parse(const Options *o, Arena *arena, int *file) {
  const char *why;
  *file = diag_load_file(o->input, -1, src_none(), &why);
  if (*file < 0) {
    fprintf(stderr, "sumi: cannot read `%s`: %s\n", o->input, why);
    return NULL;
  }
  return parse_file(*file, arena);
}

/* sumi parse FILE [--ast] */
static int cmd_parse(const Options *o) {
  Arena arena;
  arena_init(&arena);
  int file;
  double t0 = now_seconds();
  AstNode *prog = load_and_parse(o, &arena, &file);
  int status = !prog || diag_error_count() ? 1 : 0;
  if (o->stats && file >= 0)
    fprintf(stderr, "stats: parse %.1f ms, %.1f MB source, %.1f MB syntax tree\n", (now_seconds() - t0) * 1e3,
            diag_file(file)->len / 1e6, arena.used_total / 1e6);
  if (prog && o->ast && !status) ast_print(prog, stdout);
  arena_free(&arena);
  return status;
}

/* The stdlib folder beside the binary (build/stdlib), else the installed
** one (PREFIX/share/sumi/stdlib for PREFIX/bin/sumi); NULL if neither. */
static const char *find_stdlib(void) {
  static char dir[4200];   /* room for exe and the suffixes */
  char exe[4096];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return NULL;
  exe[n] = 0;
  char *slash = strrchr(exe, '/');
  if (!slash) return NULL;
  *slash = 0;
  struct stat st;
  snprintf(dir, sizeof dir, "%s/stdlib", exe);
  if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode)) return dir;
  snprintf(dir, sizeof dir, "%s/../share/sumi/stdlib", exe);
  if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode)) return dir;
  return NULL;
}

/* Evaluation options from the command line (-D, -I, limits). */
static void eval_options_from(const Options *o, EvalOptions *eo) {
  eval_options_init(eo);
  eo->defines = o->defines;
  eo->ndefines = o->ndefines;
  eo->include_dirs = o->include_dirs;
  eo->ninclude_dirs = o->ninclude_dirs;
  eo->stdlib_dir = find_stdlib();
  if (o->limits[0]) eo->max_recursion = (int)o->limits[0];
  if (o->limits[1]) eo->max_iterations = o->limits[1];
  if (o->limits[2]) eo->max_list = o->limits[2];
  if (o->limits[3]) eo->max_memory = (long long)o->limits[3] << 20;
}

/* Parse and evaluate FILE into *scene; the exit status (0 ok, 1 errors);
** *main_file (when not NULL) the diag number of FILE. */
static int evaluate(const Options *o, Arena *arena, Scene *scene, int *main_file) {
  int file = -1;
  AstNode *prog = load_and_parse(o, arena, &file);
  if (!prog || diag_error_count()) return 1;
  if (prog->list.count == 0)
    diag_warning(ast_range(prog), "`%s` is empty: there is nothing to render", diag_file(file)->name);
  EvalOptions eo;
  eval_options_from(o, &eo);
  if (main_file) *main_file = file;
  return eval_program(prog, file, arena, &eo, scene) ? 1 : 0;
}

/* A scene that styles things but has nothing to style draws the background
** alone: a warning at its first style (the main file's, before an
** include's), for check and render (`eval` prints such scenes on purpose). */
static void warn_nothing_drawn(const Scene *sc, int main_file) {
  if (sc->nobjects || sc->norigami || !sc->nstyles) return;
  const SceneStyle *st = &sc->styles[0];
  for (int i = sc->nstyles - 1; i >= 0; i--)
    if (sc->styles[i].loc.file == main_file) st = &sc->styles[i];
  diag_warning(st->loc, "%s%s%s is defined, but the scene has no object or origami to draw: the "
               "picture is the background alone", st->name ? "style `" : "a style",
               st->name ? st->name : "", st->name ? "`" : "");
}

/* `shade origami` shades origami paper (render/origami.c); an object's
** surface in it is drawn with Phong shading: a warning at the first such
** object of each style, for check and render. */
static void warn_origami_shade_on_objects(const Scene *sc) {
  for (int s = 0; s < sc->nstyles; s++) {
    const SceneStyle *st = &sc->styles[s];
    if (st->shade.kind != SHADE_ORIGAMI) continue;
    for (int i = 0; i < sc->nobjects; i++)
      if (sc->objects[i].style == s) {
        diag_warning(sc->objects[i].loc, "%s%s%s has `shade origami`, which shades origami paper: "
                     "this object is drawn with Phong shading", st->name ? "style `" : "its style",
                     st->name ? st->name : "", st->name ? "`" : "");
        break;
      }
  }
}

/* sumi check FILE: parse and evaluate, diagnostics only. */
static int cmd_check(const Options *o) {
  Arena arena;
  arena_init(&arena);
  Scene scene;
  scene_init(&scene);
  int file;
  int status = evaluate(o, &arena, &scene, &file);
  if (status == 0) warn_nothing_drawn(&scene, file);
  if (status == 0) warn_origami_shade_on_objects(&scene);
  if (status == 0 && origami_check_scene(&scene) > 0) status = 1;   /* faces, orders, flat-foldability */
  scene_free(&scene);
  arena_free(&arena);
  return status;
}

/* sumi faces FILE: every origami block's faces (id, vertex cycle, centroids,
** overlapping faces), for writing `above` relations. */
static int cmd_faces(const Options *o) {
  Arena arena;
  arena_init(&arena);
  Scene scene;
  scene_init(&scene);
  int status = evaluate(o, &arena, &scene, NULL);
  if (status == 0) status = origami_list_scene(&scene, stdout);
  scene_free(&scene);
  arena_free(&arena);
  return status;
}

/* sumi fold FILE: the crease pattern's layer orders (geom/origami_layers.h). */
static int cmd_fold(const Options *o) {
  Arena arena;
  arena_init(&arena);
  SceneOrigami src;
  char err[512] = "";
  int status = 1;
  memset(&src, 0, sizeof src);
  int bad = crease_is_oripa(o->input) ? crease_read(o->input, &src, &arena, err, sizeof err)
                                      : fold_read(o->input, &src, &arena, err, sizeof err);
  if (bad) {
    fprintf(stderr, "sumi: %s\n", err);
    arena_free(&arena);
    return 1;
  }
  const char *why;
  src.loc = src_none();
  src.loc.file = diag_load_file(o->input, -1, src_none(), &why);   /* a .cp/.opx read registered it too */
  src.loc.line = src.loc.col = src.loc.end_line = 1, src.loc.end_col = 2;
  src.overlap_auto = 1;
  OrigamiModel *m = origami_build_folded(&src);
  OrigamiLayers l;
  LayerSolver *s = NULL;
  if (m) {
    origami_layers_init(m, &l);
    s = layer_new(&l.in, err, sizeof err);
    if (!s) diag_error(m->loc, "no layer order: %s", err);
    else if (layer_conflict(s)) origami_layers_report(m, &l, layer_conflict(s));
    else status = origami_layers_print(stdout, m, &l, s, o->count, o->limit ? o->limit : ORIGAMI_STATE_LIMIT);
  }
  if (status == 0 && o->export_path) {
    double total;
    long n = 0;
    if (!origami_layers_pick(s, o->state, o->limit ? o->limit : ORIGAMI_STATE_LIMIT, &total)) {
      fprintf(stderr, "sumi: state %ld does not exist: there are %.0f\n", o->state, total);
      status = 1;
    } else {
      origami_layers_apply(m, &l, s);
      int (*orders)[2] = origami_layers_orders(s, &n);
      FoldState st = {NULL, m->nverts, m->folded, l.in.nedges, l.in.edge_verts, l.assign, m->nfaces,
                      m->face_start, m->face_index, m->flipped, n, (const int (*)[2])orders};
      for (int e = 0; e < l.in.nedges; e++)           /* solved U creases */
        if (l.edge_crease[e] >= 0) l.assign[e] = m->creases[l.edge_crease[e]].assignment;
      if (fold_write_state(o->export_path, &st, err, sizeof err)) {
        fprintf(stderr, "sumi: %s\n", err);
        status = 1;
      }
      free(orders);
    }
  }
  if (m) origami_layers_free(&l);
  layer_free(s);
  origami_free(m);
  arena_free(&arena);
  return status;
}

/* sumi eval FILE --scene: evaluate and print the scene as text. */
static int cmd_eval(const Options *o) {
  if (!o->scene) bad_usage("`sumi eval` needs --scene");
  Arena arena;
  arena_init(&arena);
  Scene scene;
  scene_init(&scene);
  int status = evaluate(o, &arena, &scene, NULL);
  if (status == 0) scene_print(&scene, stdout);
  scene_free(&scene);
  arena_free(&arena);
  return status;
}

/* sumi refine FILE --compare: evaluate, frame the camera as a render would,
** and report how our patches, tessellations and subdivided meshes deviate
** from OpenSubdiv's limit surfaces (geom/refine.h). */
static int cmd_refine(const Options *o) {
  if (!o->compare) bad_usage("`sumi refine` needs --compare");
  Arena arena;
  arena_init(&arena);
  Scene scene;
  scene_init(&scene);
  int status = evaluate(o, &arena, &scene, NULL);
  if (status == 0) {
    RenderOptions ro;
    memset(&ro, 0, sizeof ro);
    render_resolve_size(&scene, o->width, o->height, &ro.width, &ro.height);
    ro.threads = 1;
    RenderFrame f;
    status = render_prepare(&scene, &ro, &f) ? refine_compare(&scene, &f.camera, stdout) : 1;
    render_frame_free(&f);
  }
  scene_free(&scene);
  arena_free(&arena);
  return status;
}

/* The output file fed by the renderer a band of rows at a time while it
** renders (RenderRows), when the frame's format takes its 8-bit codes as
** they are; otherwise begun stays 0 and the whole image is written after. */
typedef struct OutputStream {
  const char *path;
  const ImageTile *tile;      /* the file is this tile of a frame, or NULL */
  int begun;
  ImageStream *file;          /* once begun: NULL when the file could not be opened */
  char err[512];              /* why it could not */
} OutputStream;

static int stream_begin(void *ctx, const Image *img) {
  OutputStream *os = ctx;
  if (!image_stream_fits(os->path, img->channels)) return 0;   /* image_write converts it */
  os->begun = 1;
  os->file = image_stream_open_tile(os->path, img->width, img->height, img->channels, os->tile, os->err,
                                    sizeof os->err);
  return 1;
}

static void stream_rows(void *ctx, const Image *band, int y0, int y1) {
  OutputStream *os = ctx;
  if (os->file) image_stream_rows(os->file, y0, y1, band->data8);
}

/* Samples from which a frame's heap is backed by huge pages (base/mem.h):
** they save ~1.5 ms of page faults at 1080p and cost a small render ~4 MB
** of memory it does not use. */
#define HUGE_HEAP_SAMPLES (1L << 20)

/* Back the heap with huge pages once, before the first big frame (or tile). */
static void heap_for_frame(const Scene *scene, const RenderOptions *ro) {
  static int done;
  long n = scene->output.samples > 0 ? scene->output.samples : 1;
  RenderWindow w = ro->window;
  long pixels = render_window_empty(w) ? (long)ro->width * ro->height : (long)(w.x1 - w.x0) * (w.y1 - w.y0);
  if (done || pixels * n * n < HUGE_HEAP_SAMPLES) return;
  mem_heap_setup(1);
  done = 1;
}

/* Start loading OpenImageIO on a thread when this render will need it
** (image.h): for the output format or the AOVs, known from the command
** line; for an input image, known once the scene is evaluated. */
static void prefetch_for_output(const Options *o) {
  const char *ext = strrchr(o->output, '.');
  if (o->aov || (!(ext && !strcmp(ext, ".svg")) && image_write_needs_bridge(o->output)))
    image_bridge_prefetch();
}

/* A name for what a render of scene at w x h draws, the same in every job
** that renders it: a hash (FNV-1a, 64 bits) of the evaluated scene as
** `sumi eval --scene` prints it, and the size. */
static void render_key(const Scene *scene, int w, int h, char *out, size_t n) {
  char *text = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&text, &len);
  if (!f) sumi_fatal("out of memory");
  scene_print(scene, f);
  fprintf(f, "size %dx%d\n", w, h);
  fclose(f);
  unsigned long long hash = 1469598103934665603ULL;
  for (size_t i = 0; i < len; i++) hash = (hash ^ (unsigned char)text[i]) * 1099511628211ULL;
  free(text);
  snprintf(out, n, "%016llx", hash);
}

/* The window of --tile in the frame ro is resolved for, and the tile's
** place for its file (a frame too small for the split is bad usage). */
static void tile_window(const Options *o, const Scene *scene, RenderOptions *ro, ImageTile *it) {
  TileSpec t;
  char err[256];
  if (!tile_parse(o->tile, &t, err, sizeof err) || !tile_rect(&t, ro->width, ro->height, &ro->window, err, sizeof err))
    bad_usage("%s", err);
  memset(it, 0, sizeof *it);
  it->x = ro->window.x0;
  it->y = ro->window.y0;
  it->full_width = ro->width;
  it->full_height = ro->height;
  tile_format(&t, it->name, sizeof it->name);
  render_key(scene, ro->width, ro->height, it->render, sizeof it->render);
}

/* Render the evaluated scene to path (an image, or the strokes as SVG),
** with the --aov passes beside it. Returns the exit status. */
static int render_to(const Options *o, const Scene *scene, const char *path) {
  RenderOptions ro;
  memset(&ro, 0, sizeof ro);
  render_resolve_size(scene, o->width, o->height, &ro.width, &ro.height);
  ImageTile tile;
  if (o->tile) tile_window(o, scene, &ro, &tile);
  heap_for_frame(scene, &ro);
  ro.threads = o->threads;
  ro.stats = o->stats;
  ro.progress = progress_hook();
  const char *ext = strrchr(path, '.');
  if (ext && !strcmp(ext, ".svg")) return svg_render_scene(scene, &ro, path);   /* line art (render/svg.h) */
  ro.out8 = image_write_is_8bit(path);
  OutputStream os = {path, o->tile ? &tile : NULL, 0, NULL, ""};
  RenderRows rows = {&os, stream_begin, stream_rows};
  ro.rows = &rows;
  Image *img = NULL;
  GBuffer *gb = NULL;
  int status = 1;
  int rendered = render_scene(scene, &ro, &img, o->aov ? &gb : NULL) == 0;
  progress_clear();   /* whatever is said next has the terminal to itself */
  if (rendered) {
    char err[512];
    /* the passes before the image: a frame whose image is whole has them
    ** all (--resume judges a frame by its image) */
    int aovs = !gb || render_write_aovs(gb, path, o->aov, err, sizeof err);
    double t0 = now_seconds();
    ImageWriteOptions wo = {0, 0, 0, os.tile};
    if (!aovs) {
      if (os.file) image_stream_discard(os.file);
    } else if (!os.begun) status = image_write_opts(path, img, &wo, err, sizeof err) ? 0 : 1;
    else if (os.file) status = image_stream_close(os.file, err, sizeof err) ? 0 : 1;
    else snprintf(err, sizeof err, "%s", os.err);
    if (status) fprintf(stderr, "sumi: %s\n", err);
    /* dlopen of OpenImageIO: the time the render waited for it, and (as
    ** cpu) the whole load, which a prefetch thread overlaps with the work */
    double waited = image_bridge_wait_seconds();
    if (image_bridge_load_seconds() > 0) {
      stats_record("image library", waited);
      stats_record_cpu("image library", image_bridge_load_seconds());
    }
    stats_record("write", now_seconds() - t0 - (os.begun ? 0 : waited));
  } else if (os.file) {
    image_stream_discard(os.file);
  }
  image_destroy(img);
  gbuf_destroy(gb);
  return status;
}

/* Parse, evaluate (with clock and frame) and render one frame to path. */
static int render_frame_to(const Options *o, double clock, int frame, const char *path) {
  Arena arena;
  arena_init(&arena);
  int file, status = 1;
  double t0 = now_seconds();
  AstNode *prog = load_and_parse(o, &arena, &file);
  Scene scene;
  scene_init(&scene);
  EvalOptions eo;
  eval_options_from(o, &eo);
  eo.clock = clock;
  eo.frame = frame;
  double t1 = now_seconds();
  long kept = mesh_import_cache_hits();
  int ok = prog && !diag_error_count() && eval_program(prog, file, &arena, &eo, &scene) == 0;
  kept = mesh_import_cache_hits() - kept;
  if (ok) warn_nothing_drawn(&scene, file);
  if (ok) warn_origami_shade_on_objects(&scene);
  if (ok && scene_any_image(&scene, image_read_needs_bridge)) image_bridge_prefetch();
  if (ok && origami_check_scene(&scene) == 0) {
    stats_record("parse", t1 - t0);
    stats_record("eval", now_seconds() - t1);
    if (kept) stats_record_count("eval", "meshes kept", kept);
    long refined = subdiv_cache_hits();
    status = render_to(o, &scene, path);
    refined = subdiv_cache_hits() - refined;
    if (refined) stats_record_count("subdiv", "meshes kept", refined);
  }
  if (o->stats) stats_print(stderr);
  scene_free(&scene);
  arena_free(&arena);
  return status;
}

/* Before any work: path's folder must exist and take files, and a file
** already at path must be a regular one we may replace (the rename would
** silently replace a read-only file, or a device node). 1, or 0 after
** saying why, as a failed write does. */
static int output_writable(const char *path) {
  struct stat st;
  char why[4400] = "", dir[4096];
  const char *slash = strrchr(path, '/');
  snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) + (slash == path) : 1, slash ? path : ".");
  if (stat(path, &st) == 0) {
    if (S_ISDIR(st.st_mode)) snprintf(why, sizeof why, "is a directory");
    else if (!S_ISREG(st.st_mode)) snprintf(why, sizeof why, "is not a regular file");
    else if (access(path, W_OK) != 0 || !(st.st_mode & 0222))
      snprintf(why, sizeof why, "it exists and is read-only (sumi does not replace it)");
  } else if (stat(dir, &st) != 0) snprintf(why, sizeof why, "its folder `%s` does not exist", dir);
  else if (!S_ISDIR(st.st_mode)) snprintf(why, sizeof why, "`%s` is not a folder", dir);
  else if (access(dir, W_OK | X_OK) != 0) snprintf(why, sizeof why, "its folder `%s` is not writable", dir);
  if (!why[0]) return 1;
  fprintf(stderr, "sumi: cannot write '%s': %s\n", path, why);
  return 0;
}

/* The checks of an output and --aov made before any work; exits with
** usage for a bad --aov, returns 0 when the output cannot be written. */
static int render_checks(const Options *o, const char *path) {
  char err[256];
  if (o->aov && !render_aov_list_ok(o->aov, err, sizeof err)) bad_usage("%s", err);
  tempfile_handle_signals();   /* an interrupted write removes its temporary */
  return output_writable(path);
}

/* --resume: is path already whole (io/outfile.h)? Says so unless quiet. */
static int done_already(const Options *o, const char *path) {
  if (!o->resume || !outfile_complete(path)) return 0;
  progress_clear();
  if (!o->quiet) fprintf(stderr, "sumi: %s is complete: not rendered again (--resume)\n", path);
  return 1;
}

/* sumi render FILE -o OUT [--frames SPEC [--only LIST]]: one image, or one
** a frame (base/frames.h). */
static int cmd_render(const Options *o) {
  if (o->tile) {   /* the spec now, the frame's size once the scene is in */
    TileSpec t;
    char err[256];
    if (!tile_parse(o->tile, &t, err, sizeof err)) bad_usage("%s", err);
    if (!image_keeps_tiles(o->output))
      bad_usage("--tile writes .png, .tif or .exr files (exact pixels, and their place in the frame), not `%s`",
                o->output);
  }
  RenderOptions threads = {.threads = o->threads};
  subdiv_threads(render_thread_count(&threads));   /* subdivided meshes (render and CSG) */
  FrameSet fs;
  char err[512];
  if (o->frames && !frames_parse(o->frames, o->only, &fs, err, sizeof err)) bad_usage("%s", err);
  if (o->frames && !strcmp(o->input, "-")) bad_usage("--frames reads the scene once a frame: give a file, not -");
  if (!o->frames) {
    if (!render_checks(o, o->output)) return 1;
    if (done_already(o, o->output)) return 0;
    prefetch_for_output(o);
    progress_begin(1, o->quiet);
    int status = render_frame_to(o, 0, 0, o->output);
    progress_end();
    return status;
  }
  prefetch_for_output(o);
  progress_begin(fs.count, o->quiet);
  /* a static mesh file is the same every frame: read it once; a static
  ** subdivided mesh too: refine it once */
  if (fs.count > 1) {
    mesh_import_cache_keep(SUBDIV_CACHE_FRAMES);
    subdiv_cache_keep(SUBDIV_CACHE_FRAMES);
  }
  int status = 0;
  for (int k = 0; k < fs.count && !status; k++) {
    int fr = fs.frames[k];
    char path[4096];
    frames_path(path, sizeof path, o->output, fr);
    progress_frame(k + 1);
    if (!render_checks(o, path)) status = 1;
    else if (!done_already(o, path)) {
      double clock = scene_frame_clock(fs.first, fs.last, fr, o->loop);
      progress_clear();
      if (!o->quiet) fprintf(stderr, "sumi: frame %d (clock %g) -> %s\n", fr, clock, path);
      status = render_frame_to(o, clock, fr, path);
    }
  }
  progress_end();
  subdiv_cache_clear();
  mesh_import_cache_clear();
  frames_free(&fs);
  return status;
}

/* A loaded source as watch saw it: its name, modification time and size. */
typedef struct Watched {
  char *name;
  struct timespec mtime;
  off_t size;
} Watched;

static int watched_changed(const Watched *w) {
  struct stat st;
  if (stat(w->name, &st) != 0) return 0;   /* mid-save: wait for it to come back */
  return st.st_mtim.tv_sec != w->mtime.tv_sec || st.st_mtim.tv_nsec != w->mtime.tv_nsec ||
         st.st_size != w->size;
}

/* sumi watch FILE -o OUT: render, then poll the scene and every file it
** included (every 200 ms) and render again when one changes. */
static int cmd_watch(const Options *o) {
  if (!strcmp(o->input, "-")) bad_usage("`sumi watch` needs a file to watch, not -");
  if (!render_checks(o, o->output)) return 1;
  prefetch_for_output(o);
  for (;;) {
    progress_begin(1, o->quiet);
    int status = render_frame_to(o, 0, 0, o->output);
    progress_end();
    if (!o->quiet)
      fprintf(stderr, status ? "sumi: watch: not written (see above); waiting for a change\n"
                             : "sumi: watch: wrote %s; waiting for a change\n", o->output);
    int n = diag_file_count(), nw = 0;
    Watched *w = xcalloc((size_t)n + 1, sizeof *w);
    for (int i = 0; i < n; i++) {
      struct stat st;
      const char *name = diag_file(i)->name;
      if (stat(name, &st) != 0) continue;
      w[nw].name = xstrdup(name);
      w[nw].mtime = st.st_mtim;
      w[nw].size = st.st_size;
      nw++;
    }
    diag_shutdown();   /* a fresh start for the next render's diagnostics */
    diag_init(o->diag_format);
    for (int changed = 0; !changed;) {
      struct timespec pause = {0, 200 * 1000 * 1000};
      nanosleep(&pause, NULL);
      for (int i = 0; i < nw && !changed; i++) changed = watched_changed(&w[i]);
    }
    for (int i = 0; i < nw; i++) free(w[i].name);
    free(w);
  }
}

/* sumi assemble TILES... -o OUT: the tiles of `render --tile` stitched into
** their frame (io/assemble.h). */
static int cmd_assemble(const Options *o) {
  char err[1200];
  tempfile_handle_signals();   /* an interrupted write removes its temporary */
  if (!output_writable(o->output)) return 1;
  if (assemble_tiles(o->inputs, o->ninputs, o->output, err, sizeof err)) return 0;
  fprintf(stderr, "sumi: assemble: %s\n", err);
  return 1;
}

/* sumi export FILE -o OUT: evaluate and write the solids (io/mesh_export.h). */
static int cmd_export(const Options *o) {
  tempfile_handle_signals();
  if (!output_writable(o->output)) return 1;
  Arena arena;
  arena_init(&arena);
  Scene scene;
  scene_init(&scene);
  int status = evaluate(o, &arena, &scene, NULL);
  if (status == 0) status = mesh_export_scene(&scene, o->output) ? 0 : 1;
  scene_free(&scene);
  arena_free(&arena);
  return status;
}

typedef struct Command {
  const char *name;
  int (*run)(const Options *o);
  int needs_output;
} Command;

static const Command commands[] = {
  {"parse", cmd_parse, 0},
  {"check", cmd_check, 0},
  {"faces", cmd_faces, 0},
  {"fold", cmd_fold, 0},
  {"eval", cmd_eval, 0},
  {"export", cmd_export, 1},
  {"refine", cmd_refine, 0},
  {"render", cmd_render, 1},
  {"watch", cmd_watch, 1},
  {"assemble", cmd_assemble, 1},
};

int main(int argc, char **argv) {
  Options o;
  memset(&o, 0, sizeof o);
  parse_options(argc, argv, &o);
  const Command *cmd = NULL;
  for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
    if (!strcmp(commands[i].name, o.command)) cmd = &commands[i];
  if (!cmd) bad_usage("unknown command `%s`", o.command);
  if (!o.input) bad_usage("`sumi %s` needs an input file (or - for standard input)", o.command);
  if (o.ninputs > 1 && cmd->run != cmd_assemble)
    bad_usage("unexpected argument `%s` (one input file only)", o.inputs[1]);
  if (cmd->needs_output && !o.output) bad_usage("`sumi %s` needs an output file: -o FILE", o.command);
  mem_heap_setup(0);   /* huge pages come later, for a big frame (heap_for_frame) */
  diag_before_output(progress_clear);   /* a diagnostic takes the progress line off first */
  int status = cmd->run(&o);
  image_bridge_join();
  diag_shutdown();
  free((void *)o.defines);
  free((void *)o.inputs);
  free((void *)o.include_dirs);
  return status;
}
