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

namespace posix {

void set_7e1(int fd, const std::string& what) {
  termios t{};
  if (::tcgetattr(fd, &t) != 0) throw LineError(what + ": not a terminal device: " + error_text(errno));
  t.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARODD | CMSPAR);
  t.c_cflag |= CS7 | PARENB;
  // INPCK: the UART's parity verdict reaches us. PARMRK: as FF 00 c, so the
  // runner can report the character instead of losing it (IGNPAR would drop
  // it, plain INPCK would turn it into 00). ISTRIP: bit 7 of a correct
  // character is 0 whatever the adapter leaves there, so FF is only ever a
  // mark (with ISTRIP off a real FF would arrive doubled).
  t.c_iflag |= INPCK | PARMRK | ISTRIP;
  t.c_iflag &= ~static_cast<tcflag_t>(IGNPAR);
  int r;
  do r = ::tcsetattr(fd, TCSANOW, &t);
  while (r != 0 && errno == EINTR);
  if (r != 0) throw LineError(what + ": cannot set 7E1: " + error_text(errno));
  // tcsetattr() succeeds when any one setting took (a pty keeps CS8 and
  // drops PARENB but takes the input flags): read them back.
  termios back{};
  if (::tcgetattr(fd, &back) != 0) throw LineError(what + ": tcgetattr failed: " + error_text(errno));
  const tcflag_t marks = INPCK | PARMRK | ISTRIP;
  if ((back.c_cflag & CSIZE) != CS7 || (back.c_cflag & (PARENB | PARODD)) != PARENB ||
      (back.c_iflag & marks) != marks || (back.c_iflag & IGNPAR) != 0)
    throw LineError(what + ": the port did not accept 7E1 (7 data bits, even parity)");
}

}  // namespace posix

std::unique_ptr<TermiosSerialLine> TermiosSerialLine::open(const std::string& path, int baud, CharFormat format) {
  check_char_format(path, format);
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
  std::unique_ptr<TermiosSerialLine> line(new TermiosSerialLine(std::move(owned), path, baud, format));
  // Not on a pty: a PtyLine server keeps the slave open, so TIOCEXCL would
  // outlive a client that dies without clearing it and lock out every later
  // (non-root) client with EBUSY until the server restarts. The flock is
  // released by the kernel when the process dies.
  if (!is_pseudo_terminal(path)) posix::set_exclusive(fd, path);
  posix::set_raw_8n1(fd, baud, "serial " + path);
  if (format == CharFormat::k7E1) posix::set_7e1(fd, "serial " + path);
  // Bytes left over from an earlier user of the port (or replies a pty server
  // wrote to a client that went away) are not ours.
  while (::tcflush(fd, TCIOFLUSH) != 0 && errno == EINTR) {
  }
  return line;
}

TermiosSerialLine::TermiosSerialLine(UniqueFd fd, const std::string& path, int baud, CharFormat format)
    : FdLine(std::move(fd), Kind::tty), description_("serial " + path) {
  char resolved[PATH_MAX];
  if (::realpath(path.c_str(), resolved) != nullptr && path != resolved) description_ += std::string(" (") + resolved + ")";
  // Appended piece by piece: GCC 12 warns (-Wrestrict) on "literal" + std::string here.
  description_.append(" ").append(std::to_string(baud)).append(" ").append(to_string(format)).append(" (termios)");
}

TermiosSerialLine::~TermiosSerialLine() { posix::clear_exclusive(fd()); }

std::string TermiosSerialLine::describe() const { return description_; }

}  // namespace sabus::harness
