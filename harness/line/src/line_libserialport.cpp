// LibSerialPortLine: a serial port through libserialport, and the port list
// for `sabus ports`. libserialport 0.1.1 specifics are in TOOLCHAIN-NOTES.
#include <libserialport.h>
#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <memory>

#include "sabus/harness/line.hpp"

namespace sabus::harness {

namespace {

constexpr unsigned kWriteTimeoutMs = 5000;

// libserialport's error code in words. Only for SP_ERR_FAIL is
// sp_last_error_message() the OS error of the failing call; after the other
// codes it holds whatever errno was left (TOOLCHAIN-NOTES), so it is not shown.
std::string sp_error(const std::string& what, sp_return r) {
  std::string out = what + ": ";
  switch (r) {
    case SP_ERR_ARG: out += "invalid argument or unknown port (SP_ERR_ARG)"; break;
    case SP_ERR_MEM: out += "out of memory (SP_ERR_MEM)"; break;
    case SP_ERR_SUPP: out += "not supported on this port (SP_ERR_SUPP)"; break;
    case SP_ERR_FAIL:
      out += "the OS reported a failure (SP_ERR_FAIL)";
      if (char* m = sp_last_error_message()) {
        out += std::string(": ") + m;
        sp_free_error_message(m);
      }
      break;
    default: out += "error " + std::to_string(static_cast<int>(r)); break;
  }
  return out + " (set LIBSERIALPORT_DEBUG=1 to see libserialport's own reason)";
}

// Frees a port on every path out of open() until the line owns it.
struct PortGuard {
  sp_port* port = nullptr;
  bool opened = false;
  ~PortGuard() {
    if (port == nullptr) return;
    if (opened) (void)sp_close(port);
    sp_free_port(port);
  }
};

struct ConfigGuard {
  sp_port_config* config = nullptr;
  ~ConfigGuard() {
    if (config != nullptr) sp_free_config(config);
  }
};

std::string str(const char* s) { return s != nullptr ? s : ""; }

}  // namespace

std::unique_ptr<LibSerialPortLine> LibSerialPortLine::open(const std::string& path, int baud, CharFormat format) {
  // libserialport (Linux) looks "/dev/<name>" up as /sys/class/tty/<name>
  // verbatim, so /dev/serial/by-id/... or a pty server's link would be
  // "not found": hand it the device's real name.
  char buf[PATH_MAX];
  if (::realpath(path.c_str(), buf) == nullptr)
    throw LineError(path + ": " + (errno == ENOENT ? std::string("no such device") : posix::error_text(errno)));
  const std::string resolved = buf;
  check_char_format(path, format);

  // The lock first, on a fd of our own, so that a port in use by another
  // process is refused before sp_open() touches its settings.
  int lfd;
  do lfd = ::open(resolved.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  while (lfd < 0 && errno == EINTR);
  if (lfd < 0) {
    if (errno == EBUSY) throw LineError(path + " is in use by another process (the port is open in exclusive mode)");
    throw LineError(path + ": cannot open: " + posix::error_text(errno));
  }
  UniqueFd lock(lfd);
  posix::lock_port(lock.get(), path);

  PortGuard guard;
  sp_return r = sp_get_port_by_name(resolved.c_str(), &guard.port);
  if (r != SP_OK) {
    guard.port = nullptr;
    std::string msg = sp_error(path + ": libserialport does not know this port", r);
    if (is_pseudo_terminal(resolved))
      msg += "; it is a pseudo-terminal, which libserialport 0.1.1 cannot open: use the termios backend";
    throw LineError(msg);
  }
  r = sp_open(guard.port, SP_MODE_READ_WRITE);
  if (r != SP_OK) {
    if (sp_last_error_code() == EBUSY)
      throw LineError(path + " is in use by another process (the port is open in exclusive mode)");
    std::string msg = sp_error(path + ": libserialport cannot open the port", r);
    if (is_pseudo_terminal(resolved)) msg += "; it is a pseudo-terminal: use the termios backend";
    throw LineError(msg);
  }
  guard.opened = true;
  std::unique_ptr<LibSerialPortLine> line(new LibSerialPortLine(std::move(lock), guard.port, path, resolved, baud, format));
  guard.port = nullptr;  // owned by line now
  r = sp_get_port_handle(line->port_, &line->fd_);
  if (r != SP_OK || line->fd_ < 0) throw LineError(sp_error(path + ": no file descriptor for the port", r));
  if (!is_pseudo_terminal(resolved)) posix::set_exclusive(line->fd_, path);  // see TermiosSerialLine::open

  ConfigGuard config;
  if (sp_new_config(&config.config) != SP_OK) throw LineError(path + ": out of memory");
  // 8N1 (or 7E1), no flow control; DTR and RTS on, as a terminal program
  // leaves them.
  const bool is_7e1 = format == CharFormat::k7E1;
  const std::string settings = std::to_string(baud) + " " + std::string(to_string(format));
  if ((r = sp_set_config_baudrate(config.config, baud)) != SP_OK ||
      (r = sp_set_config_bits(config.config, is_7e1 ? 7 : 8)) != SP_OK ||
      (r = sp_set_config_parity(config.config, is_7e1 ? SP_PARITY_EVEN : SP_PARITY_NONE)) != SP_OK ||
      (r = sp_set_config_stopbits(config.config, 1)) != SP_OK ||
      (r = sp_set_config_flowcontrol(config.config, SP_FLOWCONTROL_NONE)) != SP_OK ||
      (r = sp_set_config_dtr(config.config, SP_DTR_ON)) != SP_OK ||
      (r = sp_set_config_rts(config.config, SP_RTS_ON)) != SP_OK)
    throw LineError(sp_error(path + ": bad settings " + settings, r));
  if ((r = sp_set_config(line->port_, config.config)) != SP_OK)
    throw LineError(sp_error(path + ": cannot set " + settings, r));
  // libserialport sets CS7 and PARENB but leaves the input flags: mark the
  // characters the UART received with a parity error (CharFormat::k7E1), and
  // check that the port really took 7E1.
  if (is_7e1) posix::set_7e1(line->fd_, "serial " + path);
  // As with termios: what an earlier user left in the buffers is not ours.
  (void)sp_flush(line->port_, SP_BUF_BOTH);
  return line;
}

LibSerialPortLine::LibSerialPortLine(UniqueFd lock, sp_port* port, std::string path, std::string resolved, int baud,
                                     CharFormat format)
    : lock_(std::move(lock)),
      port_(port),
      path_(std::move(path)),
      resolved_(std::move(resolved)),
      baud_(baud),
      format_(format) {}

LibSerialPortLine::~LibSerialPortLine() {
  posix::clear_exclusive(fd_);
  (void)sp_close(port_);
  sp_free_port(port_);
}

// Not sp_blocking_read: it waits for the whole count, and
// sp_blocking_read_next, which returns the first bytes, cannot report a lost
// line: libserialport configures VMIN=0, so a hung-up tty reads 0 bytes just
// like an empty one and it waits out the timeout (and a timeout of 0 means
// "forever" there). So: poll() the port's handle (EINTR-safe, hangup seen in
// revents), then sp_nonblocking_read what is there.
std::size_t LibSerialPortLine::read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) {
  if (buf.empty()) return 0;
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    const short rev = posix::poll_one(fd_, POLLIN, std::max(left, std::chrono::milliseconds{0}));
    if (rev == 0) return 0;
    if (rev & POLLNVAL) throw LineError(describe() + ": the port is closed");
    const sp_return n = sp_nonblocking_read(port_, buf.data(), buf.size());
    if (n > 0) return static_cast<std::size_t>(n);
    if (n < 0) {
      if (sp_last_error_code() == EINTR) continue;
      throw LineError(sp_error(describe() + ": read failed (the device went away?)", n));
    }
    if (rev & (POLLHUP | POLLERR)) throw LineError(describe() + ": hangup (the device or the other side went away)");
    // POLLIN and nothing to read: a spurious wake-up.
  }
}

// Not sp_blocking_write either: libserialport 0.1.1 waits in select(),
// which aborts (fortified FD_SET) once the port's fd is 1024 or more, and a
// failure there does not say how much was written. poll() and
// sp_nonblocking_write keep the count exact.
void LibSerialPortLine::write(ByteView bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const sp_return n = sp_nonblocking_write(port_, bytes.data() + done, bytes.size() - done);
    if (n < 0) throw LineError(sp_error(describe() + ": write failed (the device went away?)", n));
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    const short rev = posix::poll_one(fd_, POLLOUT, std::chrono::milliseconds{kWriteTimeoutMs});
    if (rev == 0)
      throw LineError(describe() + ": write made no progress for " + std::to_string(kWriteTimeoutMs) + " ms");
    if (rev & POLLNVAL) throw LineError(describe() + ": the port is closed");
    if ((rev & (POLLHUP | POLLERR)) && !(rev & POLLOUT))
      throw LineError(describe() + ": hangup (the device or the other side went away)");
  }
}

void LibSerialPortLine::drain() {
  const sp_return r = sp_drain(port_);
  if (r != SP_OK) throw LineError(sp_error(describe() + ": drain failed", r));
}

std::string LibSerialPortLine::describe() const {
  std::string where = path_;
  if (resolved_ != path_) where += " (" + resolved_ + ")";
  return "serial " + where + " " + std::to_string(baud_) + " " + std::string(to_string(format_)) + " (libserialport)";
}

std::string_view to_string(SerialPortInfo::Transport transport) {
  switch (transport) {
    case SerialPortInfo::Transport::usb: return "usb";
    case SerialPortInfo::Transport::bluetooth: return "bluetooth";
    case SerialPortInfo::Transport::native: break;
  }
  return "native";
}

std::vector<SerialPortInfo> list_serial_ports() {
  sp_port** raw = nullptr;
  const sp_return r = sp_list_ports(&raw);
  if (r != SP_OK) throw LineError(sp_error("cannot list serial ports", r));
  const std::unique_ptr<sp_port*, void (*)(sp_port**)> list(raw, sp_free_port_list);
  std::vector<SerialPortInfo> out;
  for (sp_port** p = list.get(); *p != nullptr; ++p) {
    SerialPortInfo info;
    info.name = str(sp_get_port_name(*p));
    info.description = str(sp_get_port_description(*p));
    switch (sp_get_port_transport(*p)) {
      case SP_TRANSPORT_USB: {
        info.transport = SerialPortInfo::Transport::usb;
        int a = 0, b = 0;
        if (sp_get_port_usb_vid_pid(*p, &a, &b) == SP_OK) {
          info.usb_vid = a;
          info.usb_pid = b;
        }
        if (sp_get_port_usb_bus_address(*p, &a, &b) == SP_OK) {
          info.usb_bus = a;
          info.usb_address = b;
        }
        info.manufacturer = str(sp_get_port_usb_manufacturer(*p));
        info.product = str(sp_get_port_usb_product(*p));
        info.serial_number = str(sp_get_port_usb_serial(*p));
        break;
      }
      case SP_TRANSPORT_BLUETOOTH:
        info.transport = SerialPortInfo::Transport::bluetooth;
        info.bluetooth_address = str(sp_get_port_bluetooth_address(*p));
        break;
      case SP_TRANSPORT_NATIVE: break;
    }
    out.push_back(std::move(info));
  }
  return out;
}

}  // namespace sabus::harness
