/*
** --stats: per-stage wall time and the process's peak memory, printed to
** standard error at the end of a command. Any stage records into one
** process-wide table (thread-safe); a stage recorded twice adds up.
**
**   double t0 = stats_now();
**   ... work ...
**   stats_record("raster", stats_now() - t0);
**
** Stages that run on several threads may also record the CPU time their
** workers spent (stats_record_cpu), printed beside the wall time.
*/
#ifndef render_stats_h
#define render_stats_h

#include <stdio.h>

/* Stages the table holds; later ones are dropped (and said so once). */
#define STATS_MAX_STAGES 48

/* Seconds on a monotonic clock (an arbitrary origin). */
double stats_now(void);

/* Add seconds of wall time to stage (name copied, up to 31 characters). */
void stats_record(const char *stage, double seconds);
/* Add seconds of summed worker CPU time to stage. */
void stats_record_cpu(const char *stage, double seconds);
/* Record a count for a stage (triangles, samples, ...), printed after it. */
void stats_record_count(const char *stage, const char *what, long long n);

/* Peak resident set size of the process so far, in KiB. */
long stats_peak_rss_kb(void);

/* Print every stage in the order first recorded, then the peak RSS:
**   stats: raster          12.31 ms   (cpu 23.90 ms)  triangles 28800
**   stats: peak RSS        48.2 MiB */
void stats_print(FILE *out);

/* Forget every stage (tests, benchmarks running several frames). */
void stats_reset(void);

#endif
