/*
** Live temporaries in a fixed table the signal handler can walk without
** locking or allocating (tempfile.h).
*/
#include "tempfile.h"

#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* At most this many temporaries at once (an image, its AOVs, a stream). */
#define TEMPFILE_SLOTS 32

static char names[TEMPFILE_SLOTS][PATH_MAX + 64];
static volatile sig_atomic_t live[TEMPFILE_SLOTS];
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

static void on_signal(int sig) {
  for (int i = 0; i < TEMPFILE_SLOTS; i++)
    if (live[i]) unlink(names[i]);   /* async-signal-safe */
  signal(sig, SIG_DFL);              /* then end as the signal would have */
  raise(sig);
}

static void install(void) {
  static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
  for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    struct sigaction old;
    sigaction(sigs[i], NULL, &old);
    if (old.sa_handler == SIG_IGN) continue;   /* nohup and friends: keep ignoring */
    sigaction(sigs[i], &sa, NULL);
  }
}

void tempfile_handle_signals(void) {
  static pthread_once_t once = PTHREAD_ONCE_INIT;
  pthread_once(&once, install);
}

void tempfile_add(const char *path) {
  pthread_mutex_lock(&lock);
  for (int i = 0; i < TEMPFILE_SLOTS; i++)
    if (!live[i]) {
      snprintf(names[i], sizeof names[i], "%s", path);
      live[i] = 1;
      break;
    }
  pthread_mutex_unlock(&lock);
}

void tempfile_forget(const char *path) {
  pthread_mutex_lock(&lock);
  for (int i = 0; i < TEMPFILE_SLOTS; i++)
    if (live[i] && !strcmp(names[i], path)) {
      live[i] = 0;
      break;
    }
  pthread_mutex_unlock(&lock);
}

void tempfile_discard(const char *path) {
  unlink(path);
  tempfile_forget(path);
}
