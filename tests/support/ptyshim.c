/*
 * ptyshim: a test-only LD_PRELOAD library that lets libserialport 0.1.1 open a
 * pseudo-terminal, so the libserialport line backend runs in CI without
 * serial hardware. Never link it into anything; tests preload it into one
 * test executable (tests/harness/line/CMakeLists.txt).
 *
 * What stops libserialport 0.1.1 (Debian 12) on a pty, and what this answers,
 * found by experiment with LIBSERIALPORT_DEBUG=1:
 *
 * 1. sp_get_port_by_name("/dev/pts/N") fails with "Device not found"
 *    (sp_last_error_message() says "No such file or directory"). Its Linux
 *    get_port_details() requires the name to start with "/dev/", then calls
 *    __lxstat("/sys/class/tty/<name without /dev/>") and readlink() on that
 *    path (or on ".../device" when it is not a link) to classify the port;
 *    /sys/class/tty has no entry for ptys, so /sys/class/tty/pts/N is missing.
 *    A symlink does not help: the name is used verbatim, so /dev/foo ->
 *    /dev/pts/N looks up /sys/class/tty/foo (missing too), and a link outside
 *    /dev/ (/tmp/rc3000) fails the "/dev/" check ("Device name not
 *    recognized").
 *    The shim answers __lxstat (what 0.1.1 imports; lstat too, for builds
 *    against glibc >= 2.33) with "a symbolic link" and readlink with
 *    "../../devices/virtual/tty/pts/N" for exactly the paths
 *    /sys/class/tty/<dev> where /dev/<dev> is a pty slave. The target names
 *    neither "usb" nor "bluetooth", so the port's transport is
 *    SP_TRANSPORT_NATIVE and no further sysfs files are read; its description
 *    is "pts/N".
 *    (With the shim, /dev/foo -> /dev/pts/N works too: the shim stat()s
 *    /dev/foo, which follows the link.)
 * 2. sp_open() then fails with sysfs answered alone (checked: "get_config
 *    returning SP_ERR_FAIL: TIOCMGET ioctl failed: Inappropriate ioctl for
 *    device"): it reads the modem lines with ioctl(TIOCMGET), which a pty
 *    refuses with ENOTTY, and sets DTR/RTS with TIOCMBIS/TIOCMBIC. The shim answers TIOCMGET, TIOCMSET,
 *    TIOCMBIS and TIOCMBIC on pty fds (slave major 136-143, or the master
 *    /dev/ptmx 5:2) from a small per-fd table: DTR and RTS as set by the
 *    caller (both on at first), CTS, DSR and CD always on, as if a null-modem
 *    peer were present. Every other ioctl, and these four on non-pty fds, go
 *    to the real ioctl.
 *
 * With both, sp_get_port_by_name, sp_open, sp_set_config (9600 or 19200,
 * 8N1, no flow control, DTR/RTS on), sp_flush, sp_nonblocking_write,
 * sp_blocking_write, sp_nonblocking_read, sp_blocking_read and sp_drain all
 * succeed on /dev/pts/N, and bytes 00h-FFh pass both ways unchanged
 * (tests/harness/line/line_test.cpp, LibSerialPortOverPty). sp_list_ports still
 * lists no ptys (it walks /sys/class/tty, which the shim does not add to).
 * A pty still refuses 7 data bits or parity (TOOLCHAIN-NOTES). The name
 * given to libserialport must be under /dev/; LibSerialPortLine hands it the
 * resolved name (realpath), so a pty server's link anywhere (/tmp/rc3000)
 * works.
 *
 * Global state: the modem-line table and the real function pointers. Test
 * processes use each port from one thread, so plain ints suffice.
 */
#undef _FORTIFY_SOURCE
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/types.h>
#include <unistd.h>

/* Removed from glibc's headers in 2.33 but still what libserialport 0.1.1
 * (built against an older glibc) imports. */
int __lxstat(int ver, const char *path, struct stat *buf);

static const char kSysClassTty[] = "/sys/class/tty/";

/* dlsym() returns an object pointer; ISO C has no cast to a function
 * pointer, POSIX guarantees the representation, so copy the bits. */
#define LOAD_NEXT(var, sym)                  \
  do {                                       \
    void *found_ = (sym);                    \
    memcpy(&(var), &found_, sizeof(var));    \
  } while (0)

static int is_pty_rdev(dev_t rdev) {
  unsigned maj = major(rdev);
  return (maj >= 136 && maj <= 143) || (maj == 5 && minor(rdev) == 2);
}

static int is_pty_fd(int fd) {
  struct stat st;
  return fstat(fd, &st) == 0 && S_ISCHR(st.st_mode) && is_pty_rdev(st.st_rdev);
}

/* The <dev> of "/sys/class/tty/<dev>" when "/dev/<dev>" is a pty, else NULL. */
static const char *pty_sysfs_dev(const char *path) {
  char dev_path[4096];
  struct stat st;
  const char *dev;
  if (path == NULL || strncmp(path, kSysClassTty, sizeof kSysClassTty - 1) != 0) return NULL;
  dev = path + sizeof kSysClassTty - 1;
  if (*dev == '\0' || strstr(dev, "..") != NULL) return NULL;
  if (snprintf(dev_path, sizeof dev_path, "/dev/%s", dev) >= (int)sizeof dev_path) return NULL;
  if (stat(dev_path, &st) != 0 || !S_ISCHR(st.st_mode) || !is_pty_rdev(st.st_rdev)) return NULL;
  return dev;
}

static void fake_link_stat(struct stat *buf) {
  memset(buf, 0, sizeof *buf);
  buf->st_mode = S_IFLNK | 0777;
  buf->st_nlink = 1;
}

int __lxstat(int ver, const char *path, struct stat *buf) {
  typedef int (*fn_t)(int, const char *, struct stat *);
  static fn_t real;
  if (pty_sysfs_dev(path) != NULL) {
    fake_link_stat(buf);
    return 0;
  }
  if (real == NULL) LOAD_NEXT(real, dlvsym(RTLD_NEXT, "__lxstat", "GLIBC_2.2.5"));
  if (real == NULL) return lstat(path, buf); /* same struct layout as _STAT_VER 1 on x86-64 */
  return real(ver, path, buf);
}

int lstat(const char *restrict path, struct stat *restrict buf) {
  typedef int (*fn_t)(const char *, struct stat *);
  static fn_t real;
  if (pty_sysfs_dev(path) != NULL) {
    fake_link_stat(buf);
    return 0;
  }
  if (real == NULL) LOAD_NEXT(real, dlsym(RTLD_NEXT, "lstat"));
  if (real == NULL) {
    errno = ENOSYS;
    return -1;
  }
  return real(path, buf);
}

ssize_t readlink(const char *restrict path, char *restrict buf, size_t len) {
  typedef ssize_t (*fn_t)(const char *, char *, size_t);
  static fn_t real;
  const char *dev = pty_sysfs_dev(path);
  if (dev != NULL) {
    char target[4096];
    int n = snprintf(target, sizeof target, "../../devices/virtual/tty/%s", dev);
    size_t count = (size_t)n < len ? (size_t)n : len; /* readlink truncates silently */
    memcpy(buf, target, count);
    return (ssize_t)count;
  }
  if (real == NULL) LOAD_NEXT(real, dlsym(RTLD_NEXT, "readlink"));
  if (real == NULL) {
    errno = ENOSYS;
    return -1;
  }
  return real(path, buf, len);
}

/* Modem lines per fd: the device the fd was last seen on, and DTR/RTS. */
enum { kMaxFds = 1024 };
static dev_t modem_dev[kMaxFds];
static int modem_out[kMaxFds];
static const int kAlwaysOn = TIOCM_CTS | TIOCM_DSR | TIOCM_CAR;
static const int kOutputs = TIOCM_DTR | TIOCM_RTS;

static int *modem_bits(int fd) {
  struct stat st;
  if (fd < 0 || fd >= kMaxFds || fstat(fd, &st) != 0) return NULL;
  if (modem_dev[fd] != st.st_rdev) { /* a new port on a reused fd number */
    modem_dev[fd] = st.st_rdev;
    modem_out[fd] = kOutputs;
  }
  return &modem_out[fd];
}

int ioctl(int fd, unsigned long request, ...) {
  typedef int (*fn_t)(int, unsigned long, void *);
  static fn_t real;
  va_list ap;
  void *arg;
  va_start(ap, request);
  arg = va_arg(ap, void *);
  va_end(ap);

  if ((request == TIOCMGET || request == TIOCMSET || request == TIOCMBIS || request == TIOCMBIC) &&
      is_pty_fd(fd)) {
    int *bits = modem_bits(fd);
    int *value = (int *)arg;
    if (bits != NULL && value != NULL) {
      switch (request) {
        case TIOCMGET: *value = *bits | kAlwaysOn; break;
        case TIOCMSET: *bits = *value & kOutputs; break;
        case TIOCMBIS: *bits |= *value & kOutputs; break;
        default: *bits &= ~(*value & kOutputs); break;
      }
      return 0;
    }
  }
  if (real == NULL) LOAD_NEXT(real, dlsym(RTLD_NEXT, "ioctl"));
  if (real == NULL) {
    errno = ENOSYS;
    return -1;
  }
  return real(fd, request, arg);
}
