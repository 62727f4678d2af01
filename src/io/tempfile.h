/*
** Temporary output files (written under a temporary name, then renamed
** over the target) are registered while they exist, so SIGINT, SIGTERM or
** SIGHUP removes them before the program ends: an interrupted render
** leaves neither a truncated image nor its temporary behind. (SIGKILL
** cannot be caught; its temporary stays, under its .tmp- name.)
*/
#ifndef io_tempfile_h
#define io_tempfile_h

/* Install the handlers (once; later calls do nothing). */
void tempfile_handle_signals(void);

/* Remember path (copied) as a temporary to remove on a signal. Thread-safe. */
void tempfile_add(const char *path);

/* Forget path: it was renamed or removed. Thread-safe. */
void tempfile_forget(const char *path);

/* Remove path and forget it. */
void tempfile_discard(const char *path);

#endif
