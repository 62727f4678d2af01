/*
** The table of POV-Ray and OpenSCAD habits and sumi's spelling of each
** (see habits.h).
*/
#include "habits.h"

#include <stdio.h>
#include <string.h>

typedef struct Habit {
  HabitPlace place;
  const char *names;   /* "a|b|c": the names it matches */
  const char *hint;    /* how sumi spells it */
} Habit;

#define SHAPE "a shape is a call: `sphere(1);`, or an object's geometry: `object { geometry sphere(1); style s; }` " \
              "(builtins: sphere, cube, cylinder, cone, torus, plane, polyhedron)"
#define TRANSFORM "a transform moves what follows it, `translate([1, 0, 0]) cube(1);`, or is the property of " \
                  "an object: `object { geometry …; transform translate([1, 0, 0]); }` (compose with `*`)"
#define LOOK "an object's colour and shading come from its style: `style s { base #ff0000; shade " \
             "phong { } }`, then `style s;` in the object"

/* One row per habit. */
static const Habit habits[] = {
  /* POV-Ray */
  {HABIT_BLOCK, "sphere|box|cylinder|cone|torus|plane|mesh|mesh2|polygon|prism|lathe|sor|superellipsoid", SHAPE},
  {HABIT_BLOCK, "union|difference|intersection|merge",
   "CSG is written as in OpenSCAD, a call with the shapes as children: `difference() { cube(2, center = true); "
   "sphere(1.3); }` (union, difference, intersection; POV-Ray's merge is union)"},
  {HABIT_BLOCK, "light_source", "a light is `light { position [x, y, z]; }` (or `direction` for a sun)"},
  {HABIT_BLOCK, "pigment|texture|finish|normal|material", LOOK},
  {HABIT_BLOCK, "background|global_settings", "the background colour is `output { background #rrggbb; }`"},
  {HABIT_PROPERTY, "location", "the camera's place is `position [x, y, z]`"},
  {HABIT_PROPERTY, "translate|rotate|scale|matrix", TRANSFORM},
  {HABIT_PROPERTY, "pigment|color|colour|texture|finish", LOOK},
  {HABIT_TOKEN, "<", "a vector is written `[x, y, z]`"},
  {HABIT_TOKEN, "#declare|#local", "a definition is `let name = value;`"},
  {HABIT_TOKEN, "#include", "a library is brought in with `include \"file.npr\";`"},
  {HABIT_TOKEN, "#macro", "a reusable piece of scene is `module name(args) { … }`"},
  {HABIT_TOKEN, "#if|#for|#while|#switch", "control is `if (c) { … }` and `for (i = [0:9]) { … }`"},
  /* OpenSCAD */
  {HABIT_MODULE, "resize", "sumi has no resize: `scale([sx, sy, sz])` the shape"},
  {HABIT_MODULE, "color", LOOK},
  {HABIT_MODULE, "hull|minkowski", "sumi has no hull or minkowski: its CSG is union, difference and intersection"},
  {HABIT_MODULE, "render", "sumi needs no render(): union, difference and intersection are computed where they stand"},
  {HABIT_MODULE, "projection", "sumi has no projection of a 3D shape to 2D: draw the 2D shape itself "
                               "(circle, square, polygon, text) and `linear_extrude` it"},
  {HABIT_MODULE, "import", "a mesh file is read by `mesh(\"file.obj\")`, the geometry of an object"},
  {HABIT_ARGS, "rotate", "`rotate([ax, ay, az])` turns about x, then y, then z, in degrees; `rotate(a)` about z; "
                         "`rotate(a, [x, y, z])` about an axis"},
  {HABIT_ARGS, "translate", "`translate([x, y, z])` takes one vector"},
  {HABIT_ARGS, "scale", "`scale(s)` or `scale([sx, sy, sz])` takes one number or vector"},
  {HABIT_TOKEN, "$fn|$fa|$fs", "`$fn`, `$fa` and `$fs` are named arguments of the calls that take them "
                                "(`circle(1, $fn = 64)`), not variables; an object's triangles are `tessellate N;` "
                                "or `tessellate adaptive(pixels);`"},
  {HABIT_TOKEN, "function", "a function is `fn name(x) = …;`"},
  {HABIT_TOKEN, "include <|use <", "a file name is a string: `include \"file.npr\";`"},
  /* names a library defines (names: the library file): "`red` is …" */
  {HABIT_NAME, "colors.npr", "is a colour of the library: `include \"colors.npr\";` first"},
};

/* Whether name is one of "a|b|c". */
static int listed(const char *names, const char *name) {
  size_t n = strlen(name);
  for (const char *w = names; w; w = strchr(w, '|'), w = w ? w + 1 : NULL)
    if (!strncmp(w, name, n) && (w[n] == '|' || w[n] == 0)) return 1;
  return 0;
}

/* Whether library file lib in lib_dir defines name at the top level (a
** line `let name = …` or `fn name(…`). */
static int library_defines(const char *lib_dir, const char *lib, const char *name) {
  char path[4096], line[512];
  if (!lib_dir) return 0;
  snprintf(path, sizeof path, "%s/%s", lib_dir, lib);
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  size_t n = strlen(name);
  int found = 0;
  while (!found && fgets(line, sizeof line, f)) {
    const char *s = !strncmp(line, "let ", 4) ? line + 4 : !strncmp(line, "fn ", 3) ? line + 3 : NULL;
    found = s && !strncmp(s, name, n) && strchr(" =(", s[n]);
  }
  fclose(f);
  return found;
}

int habit_hint(HabitPlace place, const char *name, const char *lib_dir, char *out, size_t n) {
  out[0] = 0;
  for (size_t i = 0; name && i < sizeof habits / sizeof habits[0]; i++) {
    const Habit *h = &habits[i];
    if (h->place != place) continue;
    if (place == HABIT_NAME ? library_defines(lib_dir, h->names, name) : listed(h->names, name)) {
      if (place == HABIT_NAME) snprintf(out, n, "; `%s` %s", name, h->hint);
      else snprintf(out, n, "; %s", h->hint);
      return 1;
    }
  }
  return 0;
}
