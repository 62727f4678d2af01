/*
** A pool of numbered tasks on worker threads (tasks.h).
*/
#include "tasks.h"

#include <pthread.h>
#include <stdatomic.h>

typedef struct TaskPool {
  void (*fn)(void *ctx, int task);
  void *ctx;
  int ntasks;
  atomic_int next;
} TaskPool;

static void *task_worker(void *arg) {
  TaskPool *pool = arg;
  for (int k; (k = atomic_fetch_add(&pool->next, 1)) < pool->ntasks;) pool->fn(pool->ctx, k);
  return 0;
}

void tasks_run(int ntasks, int nthreads, void (*fn)(void *ctx, int task), void *ctx) {
  TaskPool pool = {fn, ctx, ntasks, 0};
  atomic_init(&pool.next, 0);
  if (nthreads > ntasks) nthreads = ntasks;
  if (nthreads > TASKS_MAX_THREADS) nthreads = TASKS_MAX_THREADS;
  pthread_t tid[TASKS_MAX_THREADS];
  int started = 0;
  for (; started < nthreads - 1; started++)
    if (pthread_create(&tid[started], 0, task_worker, &pool) != 0) break;   /* fewer is fine */
  task_worker(&pool);
  for (int i = 0; i < started; i++) pthread_join(tid[i], 0);
}
