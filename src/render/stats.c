/*
** The --stats table (stats.h): a fixed array of named stages behind a
** mutex, the monotonic clock, and the peak RSS from getrusage.
*/
#include "stats.h"

#include <pthread.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

typedef struct Stage {
  char name[32];
  double wall, cpu;
  char what[24];
  long long count;
  int has_cpu, has_count;
} Stage;

static Stage stages[STATS_MAX_STAGES];
static int nstages, overflow_said;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

double stats_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The stage called name, added when new; NULL when the table is full.
** Called with the lock held. */
static Stage *find(const char *name) {
  for (int i = 0; i < nstages; i++)
    if (strncmp(stages[i].name, name, sizeof stages[i].name - 1) == 0) return &stages[i];
  if (nstages == STATS_MAX_STAGES) {
    if (!overflow_said) fprintf(stderr, "stats: more than %d stages, the rest dropped\n", STATS_MAX_STAGES);
    overflow_said = 1;
    return NULL;
  }
  Stage *s = &stages[nstages++];
  memset(s, 0, sizeof *s);
  strncpy(s->name, name, sizeof s->name - 1);
  return s;
}

void stats_record(const char *stage, double seconds) {
  pthread_mutex_lock(&lock);
  Stage *s = find(stage);
  if (s) s->wall += seconds;
  pthread_mutex_unlock(&lock);
}

void stats_record_cpu(const char *stage, double seconds) {
  pthread_mutex_lock(&lock);
  Stage *s = find(stage);
  if (s) { s->cpu += seconds; s->has_cpu = 1; }
  pthread_mutex_unlock(&lock);
}

void stats_record_count(const char *stage, const char *what, long long n) {
  pthread_mutex_lock(&lock);
  Stage *s = find(stage);
  if (s) {
    strncpy(s->what, what, sizeof s->what - 1);
    s->count += n;
    s->has_count = 1;
  }
  pthread_mutex_unlock(&lock);
}

long stats_peak_rss_kb(void) {
  struct rusage ru;
  if (getrusage(RUSAGE_SELF, &ru) != 0) return 0;
  return ru.ru_maxrss;   /* KiB on Linux */
}

void stats_print(FILE *out) {
  pthread_mutex_lock(&lock);
  for (int i = 0; i < nstages; i++) {
    const Stage *s = &stages[i];
    if (s->wall == 0 && s->has_cpu)   /* measured on the workers only */
      fprintf(out, "stats: %-16s %9.2f ms cpu", s->name, s->cpu * 1e3);
    else {
      fprintf(out, "stats: %-16s %9.2f ms", s->name, s->wall * 1e3);
      if (s->has_cpu) fprintf(out, "   (cpu %.2f ms)", s->cpu * 1e3);
    }
    if (s->has_count) fprintf(out, "   %s %lld", s->what, s->count);
    fputc('\n', out);
  }
  pthread_mutex_unlock(&lock);
  fprintf(out, "stats: %-16s %9.1f MiB\n", "peak RSS", stats_peak_rss_kb() / 1024.0);
}

void stats_reset(void) {
  pthread_mutex_lock(&lock);
  nstages = 0;
  overflow_said = 0;
  pthread_mutex_unlock(&lock);
}
