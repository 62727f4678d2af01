/*
** A pool of numbered tasks on worker threads: each worker takes the next
** task number until none is left. The caller's thread is one of the
** workers. Tasks must write only their own results, so what they make
** does not depend on which thread ran which task.
*/
#ifndef base_tasks_h
#define base_tasks_h

/* Run fn(ctx, task) for every task 0..ntasks-1 on up to nthreads threads
** (fewer when a thread cannot be started; at most TASKS_MAX_THREADS). */
void tasks_run(int ntasks, int nthreads, void (*fn)(void *ctx, int task), void *ctx);

/* Most threads one call starts. */
#define TASKS_MAX_THREADS 64

#endif
