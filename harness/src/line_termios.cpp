// TermiosSerialLine: a serial port through plain POSIX termios. Works on real
// ports and on ptys (which libserialport 0.1.1 cannot open).
#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <climits>

#include "sabus/harness/line.hpp"

namespace sabus::harness {

namespace {

std::string open_error(const std::string& path, int err) {
  switch (err) {
    case ENOENT: return path + ": no such device";
    case EACCES: return path + ": permission denied (is the user in the dialout group?)";
    case EBUSY: return path + " is in use by another process (the port is open in exclusive mode)";
    default: return path + ": cannot open: " + posix::error_text(err);
  }
}

}  // namespace

std::unique_ptr<TermiosSerialLine> TermiosSerialLine::open(const std::string& path, int baud) {
  // O_NONBLOCK: open() must not wait for carrier detect, and reads wait in
  // poll() with a timeout instead of blocking.
  int fd;
  do fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  while (fd < 0 && errno == EINTR);
  if (fd < 0) throw LineError(open_error(path, errno));
  UniqueFd owned(fd);
  if (!::isatty(fd)) throw LineError(path + " is not a serial port (not a terminal device)");
  // flock first: it is what tells a second sabus apart (TIOCEXCL does not
  // stop root), and nothing about the port has been changed yet.
  posix::lock_port(fd, path);
  std::unique_ptr<TermiosSerialLine> line(new TermiosSerialLine(std::move(owned), path, baud));
  // Not on a pty: a PtyLine server keeps the slave open, so TIOCEXCL would
  // outlive a client that dies without clearing it and lock out every later
  // (non-root) client with EBUSY until the server restarts. The flock is
  // released by the kernel when the process dies.
  if (!is_pseudo_terminal(path)) posix::set_exclusive(fd, path);
  posix::set_raw_8n1(fd, baud, "serial " + path);
  // Bytes left over from an earlier user of the port (or replies a pty server
  // wrote to a client that went away) are not ours.
  while (::tcflush(fd, TCIOFLUSH) != 0 && errno == EINTR) {
  }
  return line;
}

TermiosSerialLine::TermiosSerialLine(UniqueFd fd, const std::string& path, int baud)
    : FdLine(std::move(fd), Kind::tty), description_("serial " + path) {
  char resolved[PATH_MAX];
  if (::realpath(path.c_str(), resolved) != nullptr && path != resolved) description_ += std::string(" (") + resolved + ")";
  description_ += " " + std::to_string(baud) + " 8N1 (termios)";
}

TermiosSerialLine::~TermiosSerialLine() { posix::clear_exclusive(fd()); }

std::string TermiosSerialLine::describe() const { return description_; }

}  // namespace sabus::harness
