/* Preloaded into poresph by reliability.py (LD_PRELOAD): logs every fsync
 * and rename, in the order they happen, to the file named by
 * $PORESPH_IO_ORDER_LOG, one line each ("fsync PATH", "rename OLD NEW"), so
 * that a test can check that each file was on the disk before it took its
 * final name and that its directory was synced after. The calls themselves
 * go on to the C library unchanged. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void log_line(const char* what, const char* a, const char* b) {
  const char* log = getenv("PORESPH_IO_ORDER_LOG");
  if (!log) return;
  char line[3 * PATH_MAX];
  int n = snprintf(line, sizeof line, "%s %s%s%s\n", what, a, b ? " " : "", b ? b : "");
  if (n <= 0) return;
  if (n >= (int)sizeof line) n = (int)sizeof line - 1;
  int fd = open(log, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return;
  ssize_t written = write(fd, line, (size_t)n); /* one write: lines of processes do not interleave */
  (void)written;
  close(fd);
}

int fsync(int fd) {
  static int (*real)(int) = 0;
  if (!real) real = (int (*)(int))dlsym(RTLD_NEXT, "fsync");
  char link[64], path[PATH_MAX];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  ssize_t n = readlink(link, path, sizeof path - 1);
  path[n > 0 ? n : 0] = '\0';
  int result = real(fd);
  log_line("fsync", path, 0);
  return result;
}

int rename(const char* from, const char* to) {
  static int (*real)(const char*, const char*) = 0;
  if (!real) real = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  char a[PATH_MAX], b[PATH_MAX];
  /* Absolute names, as fsync's come from /proc/self/fd. */
  if (!realpath(from, a)) snprintf(a, sizeof a, "%s", from);
  int result = real(from, to);
  if (!realpath(to, b)) snprintf(b, sizeof b, "%s", to);
  if (result == 0) log_line("rename", a, b);
  return result;
}
