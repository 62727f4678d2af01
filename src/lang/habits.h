/*
** Hints for POV-Ray and OpenSCAD habits: what a user of either writes that
** sumi spells another way (`sphere { radius 1; }`, `color("red") cube(1);`,
** `scale 2;` in an object, `base red;`, `#declare`, `$fn`),
** and how sumi spells it. One table (habits.c); the lexer, the parser, the
** evaluator and the schema checker ask it where each reports an error, and
** append the hint to the message.
*/
#ifndef lang_habits_h
#define lang_habits_h

#include <stddef.h>

/* Where the habit shows. */
typedef enum {
  HABIT_BLOCK,     /* an unknown block kind: `sphere { radius 1; }` */
  HABIT_PROPERTY,  /* an unknown property: `scale 2;` in an object */
  HABIT_MODULE,    /* a statement calling what is no module: `color("red") cube(1);` */
  HABIT_ARGS,      /* a builtin given arguments it does not take: `translate(1, 0, 0)` */
  HABIT_NAME,      /* an unknown name: `red` (see lib_dir below) */
  HABIT_TOKEN      /* something sumi has no token for: `<1, 2, 3>`, `#declare`, `$fn`, `function` */
} HabitPlace;

/* The hint for name at place, as "; hint" into out (n bytes), or "" when
** there is none; returns whether there is one. For HABIT_NAME, lib_dir
** (the stdlib folder, or NULL) is where a name a library defines (`red`
** in colors.npr) is looked for. */
int habit_hint(HabitPlace place, const char *name, const char *lib_dir, char *out, size_t n);

#endif
