// One interface for a byte line (pty, serial port, TCP), used by `sabus sim`
// to serve the reference controller and by the conformance runner's
// transports. The core never touches a port: it reads and writes a Line
// (libmodbus keeps its backends behind one small table of functions the same
// way). Each backend is a small class in its own harness/line/src/line_*.cpp.
//
// Lines carry 8-bit bytes unchanged. SAbus is 7E1 on the wire; by default
// every backend opens 8N1 and the protocol library puts the even-parity bit in
// bit 7 itself (READING-NOTES 1; a pty cannot do 7E1 at all, TOOLCHAIN-NOTES).
// A serial port can also be opened true 7E1 (CharFormat::k7E1), where the
// UART makes and checks the parity.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sabus/protocol/bytes.hpp"

struct sp_port;  // libserialport

namespace sabus::harness {

// How characters are framed on a serial port. Both are 10 bits a character on
// the wire (READING-NOTES 1, 2).
enum class CharFormat : std::uint8_t {
  // The default: 8 data bits, no parity. SAbus's parity bit travels as bit 7
  // of each byte, made and checked in software, so deliberately wrong parity
  // can be sent.
  k8N1,
  // 7 data bits and even parity made by the UART. Input is read with
  // INPCK|PARMRK|ISTRIP (termios(3)): a correct character arrives as its 7
  // bits; one the UART received with a parity or framing error arrives as the
  // three bytes FF 00 c, and a break as FF 00 00 (the reader must decode
  // these marks). Output bytes lose bit 7. Not possible on a pseudo-terminal.
  k7E1,
};
std::string_view to_string(CharFormat format);  // "8N1", "7E1"

// A line that cannot be opened, or is lost (end of file, EIO, hangup, closed
// socket, a write that makes no progress). The message names the line.
struct LineError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A Line is used by one thread at a time.
class Line {
 public:
  Line() = default;
  Line(const Line&) = delete;
  Line& operator=(const Line&) = delete;
  virtual ~Line();

  // Waits up to `timeout` for bytes and returns how many were read (at most
  // buf.size()); 0 when none came in time. Throws LineError when the line is
  // lost. A timeout of 0 only looks.
  virtual std::size_t read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) = 0;
  // Writes all bytes, or throws LineError.
  virtual void write(ByteView bytes) = 0;
  // Waits until the written bytes have left the port (tcdrain); a no-op
  // where that means nothing (TCP, the master side of a pty).
  virtual void drain() {}
  // "pty /dev/pts/3 (link /tmp/rc3000)", "serial /dev/ttyUSB0 9600 8N1
  // (libserialport)", "tcp 127.0.0.1:4001".
  virtual std::string describe() const = 0;
  // The file descriptor to poll() for input alongside others (`sabus proxy`
  // waits on two lines at once); -1 when there is none.
  virtual int poll_fd() const { return -1; }
  // The network round trip to the device server in front of the device,
  // measured when the line was opened; 0 for a line with no network in it
  // (or none measured: raw TCP has no way to ask). The runner adds it to its
  // reply and silence windows.
  virtual std::chrono::microseconds round_trip() const { return {}; }
};

// Small POSIX helpers the backends share; usable by tests too.
namespace posix {
// poll() on one fd, retried on EINTR with the time that is left. Returns
// revents, 0 on timeout.
short poll_one(int fd, short events, std::chrono::milliseconds timeout);
// strerror(err) with the errno name's meaning, e.g. "Device or resource busy".
std::string error_text(int err);
// Exclusive use of a serial port among cooperating programs (sabus, and
// anything else that flocks ports): flock(LOCK_EX|LOCK_NB), held until the fd
// is closed. Throws LineError "<path> is in use by another process" when
// another open file already holds it.
void lock_port(int fd, const std::string& path);
// TIOCEXCL: keeps out programs that do not flock (their open() gets EBUSY;
// root is exempt). Throws LineError.
void set_exclusive(int fd, const std::string& path);
// Puts a tty in raw mode, 8 data bits, no parity, 1 stop bit, no flow
// control, receiver on, modem lines ignored (CLOCAL), read() returning as soon
// as one byte is there, at `baud` (300..115200), and checks that the settings
// took. Throws LineError naming `what`.
void set_raw_8n1(int fd, int baud, const std::string& what);
// Switches a raw port (after set_raw_8n1, or libserialport's sp_set_config)
// to CharFormat::k7E1: 7 data bits, even parity, INPCK|PARMRK|ISTRIP on and
// IGNPAR off, and checks that the settings took (a pty reads back 8N1).
// Throws LineError naming `what`.
void set_7e1(int fd, const std::string& what);
// Clears TIOCEXCL before close: the flag lives as long as the tty is open
// anywhere, not just in this process.
void clear_exclusive(int fd) noexcept;
}  // namespace posix

// A file descriptor with one owner; closed on destruction.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept {
    if (this != &other) reset(std::exchange(other.fd_, -1));
    return *this;
  }
  ~UniqueFd() { reset(); }
  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  void reset(int fd = -1) noexcept;

 private:
  int fd_ = -1;
};

// A Line over a non-blocking file descriptor: poll() for the timeout, then
// read()/write() (send() with MSG_NOSIGNAL on sockets, so a closed peer is an
// error, not SIGPIPE). Lost means: read() returns 0 (end of file, a hung-up
// tty), EIO, a reset connection, or poll() reporting a hangup with nothing
// left to read.
class FdLine : public Line {
 public:
  std::size_t read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override;
  void write(ByteView bytes) override;
  void drain() override;
  // How long write() waits for the other side to take more bytes before it
  // gives up with LineError (a pty client that never reads, a stuck socket).
  void set_write_timeout(std::chrono::milliseconds t) { write_timeout_ = t; }
  int poll_fd() const override { return fd_.get(); }

 protected:
  enum class Kind { tty, pty_master, socket };
  FdLine(UniqueFd fd, Kind kind) : fd_(std::move(fd)), kind_(kind) {}
  int fd() const { return fd_.get(); }

 private:
  UniqueFd fd_;
  Kind kind_;
  std::chrono::milliseconds write_timeout_{5000};
};

// The server end of a pseudo-terminal: `sabus sim --pty /tmp/rc3000` makes a
// pty, links /tmp/rc3000 to its slave (/dev/pts/N) and serves on the master;
// clients open the link as if it were a serial port.
class PtyLine final : public FdLine {
 public:
  // Opens a pty in raw 8N1 mode and, unless link_path is empty, symlinks
  // link_path to the slave. A stale symlink (to nothing) is replaced; a link
  // to a live pty (another server's), a link to anything else and any other
  // file are refused. Throws LineError.
  static std::unique_ptr<PtyLine> create(const std::string& link_path);
  ~PtyLine() override;  // removes the link it made, if it still points at this pty

  std::string describe() const override;
  const std::string& slave_name() const { return slave_name_; }
  const std::string& link_path() const { return link_path_; }

 private:
  PtyLine(UniqueFd master, UniqueFd slave, std::string slave_name);
  // Kept open for the life of the server: with no slave fd open anywhere,
  // read() on the master fails with EIO (and poll() reports POLLHUP at once,
  // so waiting would spin), which would look like a lost line whenever no
  // client is connected. Holding one slave fd here makes "no client" simply
  // "no bytes". The cost: bytes written while no client is there wait in the
  // slave's input queue; both serial backends flush it when they open.
  // (Termios settings persist between clients either way.)
  UniqueFd slave_;
  std::string slave_name_;
  std::string link_path_;  // empty when no link was made
};

// A serial port through plain POSIX termios: works on real ports and on ptys.
class TermiosSerialLine final : public FdLine {
 public:
  // Opens `path` (symlinks allowed) 8N1 (or `format`) raw at `baud`
  // (300..115200), no flow control, exclusively (posix::lock_port; and
  // posix::set_exclusive except on a pty), and discards stale input.
  // Throws LineError (7E1 on a pty: check_char_format).
  static std::unique_ptr<TermiosSerialLine> open(const std::string& path, int baud,
                                                 CharFormat format = CharFormat::k8N1);
  ~TermiosSerialLine() override;

  std::string describe() const override;

 private:
  TermiosSerialLine(UniqueFd fd, const std::string& path, int baud, CharFormat format);
  std::string description_;
};

// A serial port through libserialport (sp_open, 8N1 or 7E1, no flow control,
// DTR and RTS on). libserialport 0.1.1 cannot open a pty (TOOLCHAIN-NOTES); tests
// reach it on a pty through tests/support/ptyshim.c.
class LibSerialPortLine final : public Line {
 public:
  // `path` may be a symlink (/dev/serial/by-id/...): it is resolved first,
  // because libserialport looks the name up in /sys/class/tty verbatim.
  static std::unique_ptr<LibSerialPortLine> open(const std::string& path, int baud,
                                                 CharFormat format = CharFormat::k8N1);
  ~LibSerialPortLine() override;

  std::size_t read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override;
  void write(ByteView bytes) override;
  void drain() override;
  std::string describe() const override;
  int poll_fd() const override { return fd_; }

 private:
  LibSerialPortLine(UniqueFd lock, sp_port* port, std::string path, std::string resolved, int baud,
                    CharFormat format);
  UniqueFd lock_;  // a second fd on the port that holds the flock
  sp_port* port_;
  int fd_ = -1;    // sp_get_port_handle; owned by port_
  std::string path_, resolved_;
  int baud_;
  CharFormat format_;
};

enum class SerialBackend { automatic, libserialport, termios };
std::string_view to_string(SerialBackend backend);
std::optional<SerialBackend> parse_serial_backend(std::string_view name);  // "auto", "libserialport", "termios"

// True when `path` (after symlinks) is a pseudo-terminal slave or master.
bool is_pseudo_terminal(const std::string& path);
// Throws LineError when `path` cannot carry `format`: 7E1 on a
// pseudo-terminal, which has 8 data bits and no parity whatever is asked
// (TOOLCHAIN-NOTES). Both serial backends check this before touching the port.
void check_char_format(const std::string& path, CharFormat format);

// Opens a serial line with the chosen backend. `automatic` picks termios for a
// pseudo-terminal (libserialport 0.1.1 cannot open one) and libserialport
// otherwise. When `note` is given it receives one sentence saying which
// backend was used and why, for the caller to print once.
std::unique_ptr<Line> open_serial_line(const std::string& path, int baud, SerialBackend backend,
                                       std::string* note = nullptr);
// The same with the character format chosen.
std::unique_ptr<Line> open_serial_line(const std::string& path, int baud, SerialBackend backend, CharFormat format,
                                       std::string* note = nullptr);

// A TCP connection carrying raw bytes, as to a serial device server.
class TcpLine final : public FdLine {
 public:
  // Connects within `timeout`, with TCP_NODELAY. Throws LineError.
  static std::unique_ptr<TcpLine> connect(const std::string& host, std::uint16_t port,
                                          std::chrono::milliseconds timeout);
  std::string describe() const override { return description_; }
  // True once the peer has closed its end (FIN or reset), without reading:
  // a server deciding whether a newcomer finds the port in use asks this,
  // since the last client's close may not have been read yet.
  bool peer_closed() const;

 private:
  friend class TcpListener;
  TcpLine(UniqueFd fd, std::string description);
  std::string description_;
};

// The server side: raw TCP, one client at a time (TcpServe in serve.hpp).
class TcpListener {
 public:
  // Port 0 picks a free port; see port(). Throws LineError.
  static std::unique_ptr<TcpListener> listen(const std::string& host, std::uint16_t port);
  // The next client, or nullptr when none came within `timeout`.
  std::unique_ptr<TcpLine> accept(std::chrono::milliseconds timeout);
  std::uint16_t port() const { return port_; }
  std::string describe() const;  // "tcp 127.0.0.1:4001 (listening)"

 private:
  TcpListener(UniqueFd fd, std::string address, std::uint16_t port);
  UniqueFd fd_;
  std::string address_;
  std::uint16_t port_;
};

// What libserialport knows about a port, for `sabus ports`.
struct SerialPortInfo {
  enum class Transport { native, usb, bluetooth };
  std::string name;  // "/dev/ttyUSB0"
  std::string description;
  Transport transport = Transport::native;
  std::optional<int> usb_vid, usb_pid, usb_bus, usb_address;
  std::string manufacturer, product, serial_number;  // USB only; empty when unknown
  std::string bluetooth_address;
};
std::string_view to_string(SerialPortInfo::Transport transport);
// Every port libserialport lists (ptys are never listed). Throws LineError.
std::vector<SerialPortInfo> list_serial_ports();

}  // namespace sabus::harness
