// Choosing a serial backend: termios for pseudo-terminals (libserialport
// 0.1.1 cannot open them, TOOLCHAIN-NOTES), libserialport for real ports.
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <climits>

#include "sabus/harness/line.hpp"

namespace sabus::harness {

std::string_view to_string(SerialBackend backend) {
  switch (backend) {
    case SerialBackend::libserialport: return "libserialport";
    case SerialBackend::termios: return "termios";
    case SerialBackend::automatic: break;
  }
  return "auto";
}

std::optional<SerialBackend> parse_serial_backend(std::string_view name) {
  if (name == "auto") return SerialBackend::automatic;
  if (name == "libserialport") return SerialBackend::libserialport;
  if (name == "termios") return SerialBackend::termios;
  return std::nullopt;
}

std::string_view to_string(CharFormat format) { return format == CharFormat::k7E1 ? "7E1" : "8N1"; }

bool is_pseudo_terminal(const std::string& path) {
  char resolved[PATH_MAX];
  if (::realpath(path.c_str(), resolved) != nullptr && std::string_view(resolved).starts_with("/dev/pts/"))
    return true;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISCHR(st.st_mode)) return false;
  // Documented Linux device numbers (devices.txt): 136-143 Unix98 pty
  // slaves (also inside containers with their own devpts), 5:2 /dev/ptmx,
  // 2 and 3 the legacy BSD pty masters and slaves.
  const unsigned maj = major(st.st_rdev);
  return (maj >= 136 && maj <= 143) || (maj == 5 && minor(st.st_rdev) == 2) || maj == 2 || maj == 3;
}

void check_char_format(const std::string& path, CharFormat format) {
  if (format == CharFormat::k7E1 && is_pseudo_terminal(path))
    throw LineError(path +
                    " is a pseudo-terminal, which carries 8 data bits and no parity: it cannot be opened 7E1 "
                    "(use software parity, 8N1 with the parity bit in bit 7, the default)");
}

std::unique_ptr<Line> open_serial_line(const std::string& path, int baud, SerialBackend backend, std::string* note) {
  return open_serial_line(path, baud, backend, CharFormat::k8N1, note);
}

std::unique_ptr<Line> open_serial_line(const std::string& path, int baud, SerialBackend backend, CharFormat format,
                                       std::string* note) {
  std::string why;
  if (backend == SerialBackend::automatic) {
    if (is_pseudo_terminal(path)) {
      backend = SerialBackend::termios;
      why = "serial backend termios: " + path +
            " is a pseudo-terminal, which libserialport 0.1.1 cannot open";
    } else {
      backend = SerialBackend::libserialport;
      why = "serial backend libserialport: " + path + " is not a pseudo-terminal";
    }
  } else {
    why = "serial backend " + std::string(to_string(backend)) + ", as asked";
  }
  if (note != nullptr) *note = why + ".";
  if (backend == SerialBackend::termios) return TermiosSerialLine::open(path, baud, format);
  return LibSerialPortLine::open(path, baud, format);
}

}  // namespace sabus::harness
