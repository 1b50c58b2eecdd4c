/* Test-only LD_PRELOAD shim: lets libserialport open a pseudo-terminal as if it were a UART.
 *
 * libserialport 0.1.1 looks a port up in /sys/class/tty/NAME (a pty has no entry there) and reads
 * and sets the modem lines (TIOCMGET/TIOCMSET/TIOCMBIS/TIOCMBIC), which a pty rejects with ENOTTY.
 * This shim answers exactly those, for pty slaves only (majors 136-143), so that popcut's
 * unmodified libserialport code path runs against `popcut sim-plotter` — as umockdev does for USB.
 * Everything else (termios, XON/XOFF in the kernel, reads, writes, hang-ups) is the real pty.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

static const char kSysPts[] = "/sys/class/tty/pts/";
/* The host's output lines (DTR, RTS) as it last set them; the "device" always asserts CTS, DSR, CD. */
static int g_lines = TIOCM_DTR | TIOCM_RTS;

static int is_pty_slave(int fd) {
  struct stat st;
  return fstat(fd, &st) == 0 && S_ISCHR(st.st_mode) && major(st.st_rdev) >= 136 && major(st.st_rdev) <= 143;
}

int ioctl(int fd, unsigned long request, ...) {
  static int (*real)(int, unsigned long, ...);
  va_list ap;
  va_start(ap, request);
  void *arg = va_arg(ap, void *);
  va_end(ap);
  if (!real) real = (int (*)(int, unsigned long, ...))dlsym(RTLD_NEXT, "ioctl");
  if ((request == TIOCMGET || request == TIOCMSET || request == TIOCMBIS || request == TIOCMBIC) && is_pty_slave(fd)) {
    int *bits = arg;
    if (request == TIOCMGET) *bits = g_lines | TIOCM_CTS | TIOCM_DSR | TIOCM_CD;
    else if (request == TIOCMSET) g_lines = *bits & (TIOCM_DTR | TIOCM_RTS);
    else if (request == TIOCMBIS) g_lines |= *bits & (TIOCM_DTR | TIOCM_RTS);
    else g_lines &= ~*bits;
    return 0;
  }
  return real(fd, request, arg);
}

/* libserialport 0.1.1 was built against glibc's versioned stat: lstat() reaches it as __lxstat. */
int __lxstat(int ver, const char *path, struct stat *st) {
  static int (*real)(int, const char *, struct stat *);
  if (!real) real = (int (*)(int, const char *, struct stat *))dlsym(RTLD_NEXT, "__lxstat");
  if (strncmp(path, kSysPts, sizeof kSysPts - 1) == 0) {
    memset(st, 0, sizeof *st);
    st->st_mode = S_IFLNK | 0777; /* like the class links of real ttys */
    return 0;
  }
  return real(ver, path, st);
}

ssize_t readlink(const char *path, char *buf, size_t size) {
  static ssize_t (*real)(const char *, char *, size_t);
  if (!real) real = (ssize_t(*)(const char *, char *, size_t))dlsym(RTLD_NEXT, "readlink");
  if (strncmp(path, kSysPts, sizeof kSysPts - 1) == 0) {
    /* A virtual (native) device: neither "usb" nor "bluetooth" in the path. */
    const int n = snprintf(buf, size, "../../devices/virtual/tty/pts%s", path + sizeof kSysPts - 1);
    return n < (int)size ? n : (ssize_t)size;
  }
  return real(path, buf, size);
}
