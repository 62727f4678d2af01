/*
** The check every named input passes before it is opened (infile.h).
*/
#include "infile.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static const char *what_it_is(mode_t m) {
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISSOCK(m)) return "a socket";
  return "not a file";
}

/* 1.5 GB, 300 MB, 12 KB: a size as a reader says it. */
static void human_size(char *out, size_t n, double bytes) {
  static const char *const unit[] = {"bytes", "KB", "MB", "GB", "TB"};
  int u = 0;
  while (bytes >= 1024 && u < 4) bytes /= 1024, u++;
  if (u == 0) snprintf(out, n, "%.0f bytes", bytes);
  else snprintf(out, n, bytes < 10 && bytes != (int)bytes ? "%.1f %s" : "%.0f %s", bytes, unit[u]);
}

int infile_check(const char *path, long long max, const char *kind, char *why, size_t n) {
  struct stat st;
  if (stat(path, &st) != 0) {
    snprintf(why, n, "%s", strerror(errno));
    return 0;
  }
  if (S_ISDIR(st.st_mode)) {
    snprintf(why, n, "is a directory");
    return 0;
  }
  if (!S_ISREG(st.st_mode)) {
    snprintf(why, n, "is not a regular file (%s)", what_it_is(st.st_mode));
    return 0;
  }
  if ((long long)st.st_size > max) {
    char have[32], cap[32];
    human_size(have, sizeof have, (double)st.st_size);
    human_size(cap, sizeof cap, (double)max);
    snprintf(why, n, "is %s; the limit for %s is %s", have, kind, cap);
    return 0;
  }
  return 1;
}
