// What every fd-based line shares: the Line base, EINTR-safe poll, the
// exclusive-use lock of a serial port, and FdLine's read/write/drain.
#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "sabus/harness/line.hpp"

namespace sabus::harness {

Line::~Line() = default;

namespace posix {

short poll_one(int fd, short events, std::chrono::milliseconds timeout) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::max(timeout, std::chrono::milliseconds{0});
  for (;;) {
    // Round the time left up, so a sub-millisecond remainder waits instead of spinning.
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
    const int ms = static_cast<int>(std::clamp<std::int64_t>(left.count(), 0, 1'000'000'000));
    pollfd p{fd, events, 0};
    const int r = ::poll(&p, 1, ms);
    if (r > 0) return p.revents;
    if (r == 0) return 0;
    if (errno != EINTR) throw LineError(std::string("poll failed: ") + error_text(errno));
  }
}

std::string error_text(int err) { return std::strerror(err); }

void lock_port(int fd, const std::string& path) {
  int r;
  do r = ::flock(fd, LOCK_EX | LOCK_NB);
  while (r != 0 && errno == EINTR);
  if (r != 0) {
    if (errno == EWOULDBLOCK)
      throw LineError(path + " is in use by another process (it holds an exclusive lock on the port)");
    throw LineError(path + ": cannot lock the port: " + error_text(errno));
  }
}

void set_exclusive(int fd, const std::string& path) {
  if (::ioctl(fd, TIOCEXCL) != 0)
    throw LineError(path + ": cannot make the port exclusive (TIOCEXCL): " + error_text(errno));
}

namespace {
struct BaudSpeed {
  int baud;
  speed_t speed;
};
constexpr BaudSpeed kSpeeds[] = {{300, B300},     {600, B600},     {1200, B1200},   {2400, B2400},
                                 {4800, B4800},   {9600, B9600},   {19200, B19200}, {38400, B38400},
                                 {57600, B57600}, {115200, B115200}};
}  // namespace

void set_raw_8n1(int fd, int baud, const std::string& what) {
  const BaudSpeed* found = nullptr;
  for (const auto& s : kSpeeds)
    if (s.baud == baud) found = &s;
  if (found == nullptr)
    throw LineError(what + ": unsupported baud rate " + std::to_string(baud) +
                    " (300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600 or 115200)");
  termios t{};
  if (::tcgetattr(fd, &t) != 0) throw LineError(what + ": not a terminal device: " + error_text(errno));
  ::cfmakeraw(&t);  // no echo, no line editing, no CR/LF mapping, no signals, CS8, no parity
  t.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | CSTOPB | CRTSCTS);
  t.c_cflag |= CS8 | CREAD | CLOCAL;
  t.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY | INPCK);
  t.c_cc[VMIN] = 1;  // with O_NONBLOCK: EAGAIN when empty, so read() == 0 only on hangup
  t.c_cc[VTIME] = 0;
  if (::cfsetispeed(&t, found->speed) != 0 || ::cfsetospeed(&t, found->speed) != 0)
    throw LineError(what + ": cannot set " + std::to_string(baud) + " baud: " + error_text(errno));
  int r;
  do r = ::tcsetattr(fd, TCSANOW, &t);
  while (r != 0 && errno == EINTR);
  if (r != 0) throw LineError(what + ": cannot set " + std::to_string(baud) + " 8N1: " + error_text(errno));
  // tcsetattr() succeeds when any one setting took; read them back.
  termios back{};
  if (::tcgetattr(fd, &back) != 0) throw LineError(what + ": tcgetattr failed: " + error_text(errno));
  if ((back.c_cflag & CSIZE) != CS8 || (back.c_cflag & (PARENB | CSTOPB)) != 0 ||
      ::cfgetospeed(&back) != found->speed || (back.c_lflag & (ICANON | ECHO)) != 0)
    throw LineError(what + ": the port did not accept " + std::to_string(baud) + " 8N1 raw mode");
}

void clear_exclusive(int fd) noexcept {
  if (fd >= 0) (void)::ioctl(fd, TIOCNXCL);
}

}  // namespace posix

void UniqueFd::reset(int fd) noexcept {
  // close() is not retried on EINTR: on Linux the fd is released anyway.
  if (fd_ >= 0) (void)::close(fd_);
  fd_ = fd;
}

std::size_t FdLine::read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) {
  if (buf.empty()) return 0;
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    const short rev = posix::poll_one(fd(), POLLIN, std::max(left, std::chrono::milliseconds{0}));
    if (rev == 0) return 0;
    if (rev & POLLNVAL) throw LineError(describe() + ": the line is closed");
    if (rev & (POLLIN | POLLHUP | POLLERR)) {
      // Read even on POLLHUP/POLLERR: bytes that came before a hangup are
      // still delivered, and read() names the error.
      const ssize_t n = ::read(fd(), buf.data(), buf.size());
      if (n > 0) return static_cast<std::size_t>(n);
      if (n == 0) {
        // Raw ttys here have VMIN=1 and O_NONBLOCK, so 0 only comes from a
        // hung-up tty; on a socket it is the peer's close.
        throw LineError(describe() + (kind_ == Kind::socket ? ": the connection was closed by the other side"
                                                            : ": end of file (the other side hung up)"));
      }
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        // A hangup or error with nothing to read: the line is gone (and
        // poll() would keep reporting it, so looping would spin).
        if (rev & (POLLHUP | POLLERR)) throw LineError(describe() + ": hangup (the other side went away)");
        continue;  // a spurious wake-up
      }
      if (errno == EIO)
        throw LineError(describe() + ": input/output error (hangup: the device or the other side went away)");
      throw LineError(describe() + ": read failed: " + posix::error_text(errno));
    }
  }
}

void FdLine::write(ByteView bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::uint8_t* p = bytes.data() + done;
    const std::size_t n = bytes.size() - done;
    const ssize_t w = kind_ == Kind::socket ? ::send(fd(), p, n, MSG_NOSIGNAL) : ::write(fd(), p, n);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
      continue;
    }
    if (w < 0 && errno == EINTR) continue;
    if (w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      const short rev = posix::poll_one(fd(), POLLOUT, write_timeout_);
      if (rev == 0)
        throw LineError(describe() + ": write made no progress for " + std::to_string(write_timeout_.count()) +
                        " ms (nobody reads the other side)");
      if (rev & POLLNVAL) throw LineError(describe() + ": the line is closed");
      continue;  // POLLOUT, or POLLHUP/POLLERR: the next write() names the error
    }
    if (w < 0 && (errno == EPIPE || errno == ECONNRESET))
      throw LineError(describe() + ": the connection was closed by the other side");
    if (w < 0 && errno == EIO)
      throw LineError(describe() + ": input/output error (hangup: the device or the other side went away)");
    throw LineError(describe() + ": write failed: " + (w < 0 ? posix::error_text(errno) : "wrote nothing"));
  }
}

void FdLine::drain() {
  if (kind_ != Kind::tty) return;
  while (::tcdrain(fd()) != 0) {
    if (errno == EINTR) continue;
    if (errno == EIO) throw LineError(describe() + ": input/output error while draining (hangup)");
    throw LineError(describe() + ": tcdrain failed: " + posix::error_text(errno));
  }
}

}  // namespace sabus::harness
