// LineTransport: the runner's bytes over a Line (serial port or TCP serial
// device server), with the parity bit made in software (the default,
// READING-NOTES 1) or by a UART opened 7E1.
#include <algorithm>
#include <stdexcept>
#include <thread>

#include "sabus/harness/transports.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus::harness {

Bytes with_software_parity(ByteView chars, std::span<const std::size_t> wrong_parity) {
  Bytes wire = add_even_parity(chars);
  for (const std::size_t i : wrong_parity) {
    if (i >= wire.size())
      throw std::invalid_argument("wrong parity asked for byte " + std::to_string(i) + " of a " +
                                  std::to_string(wire.size()) + "-byte message");
    wire[i] ^= 0x80;
  }
  return wire;
}

std::string_view to_string(LineMode mode) { return mode == LineMode::kTrue7E1 ? "7e1" : "software"; }

std::optional<LineMode> parse_line_mode(std::string_view name) {
  if (name == "software") return LineMode::kSoftwareParity8N1;
  if (name == "7e1") return LineMode::kTrue7E1;
  return std::nullopt;
}

std::size_t ParityMarkDecoder::decode(std::span<std::uint8_t> bytes) {
  // Writes trail reads (each input byte yields at most one output byte), so
  // decoding in place is safe.
  std::size_t out = 0;
  for (const std::uint8_t b : bytes) {
    switch (state_) {
      case State::kPlain:
        if (b == 0xFF)
          state_ = State::kAfterFF;
        else
          bytes[out++] = b;
        break;
      case State::kAfterFF:
        if (b == 0x00) {
          state_ = State::kAfterFF00;
        } else {
          bytes[out++] = b;  // FF FF: an FF received as data
          state_ = State::kPlain;
        }
        break;
      case State::kAfterFF00:
        bytes[out++] = static_cast<std::uint8_t>(b | 0x80);  // the flagged character
        state_ = State::kPlain;
        break;
    }
  }
  return out;
}

LineTransport::LineTransport(std::unique_ptr<Line> line, LineMode mode, int baud)
    : line_(std::move(line)), mode_(mode), baud_(baud) {}

void LineTransport::send(ByteView chars, std::span<const std::size_t> wrong_parity) {
  Bytes wire;
  if (mode_ == LineMode::kSoftwareParity8N1) {
    wire = with_software_parity(chars, wrong_parity);
  } else {
    if (!wrong_parity.empty())
      throw std::invalid_argument(describe() + ": a 7E1 port makes its parity in the UART; it cannot send wrong parity");
    wire.assign(chars.begin(), chars.end());
    for (auto& c : wire) c &= 0x7F;  // the UART sends 7 data bits; be explicit
  }
  try {
    line_->write(wire);
  } catch (const LineError& e) {
    throw TransportLost(e.what());
  }
}

std::size_t LineTransport::receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) {
  using Steady = std::chrono::steady_clock;
  const auto deadline = Steady::now() + std::max(timeout, std::chrono::milliseconds{0});
  try {
    for (;;) {
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Steady::now());
      const std::size_t n = line_->read(buf, std::max(left, std::chrono::milliseconds{0}));
      if (n == 0 || mode_ == LineMode::kSoftwareParity8N1) return n;
      const std::size_t decoded = marks_.decode(buf.first(n));
      // Only the start of a mark came: its character follows at once; wait
      // for it within the same timeout.
      if (decoded > 0 || Steady::now() >= deadline) return decoded;
    }
  } catch (const LineError& e) {
    throw TransportLost(e.what());
  }
}

void LineTransport::pause(std::chrono::milliseconds d) {
  if (d > std::chrono::milliseconds{0}) std::this_thread::sleep_for(d);
}

std::string LineTransport::describe() const {
  return line_->describe() + (mode_ == LineMode::kSoftwareParity8N1 ? ", software even parity in bit 7"
                                                                    : ", parity by the UART (true 7E1)");
}

std::unique_ptr<LineTransport> make_serial_transport(const std::string& path, int baud, SerialBackend backend,
                                                     LineMode mode, std::string* note) {
  const CharFormat format = mode == LineMode::kTrue7E1 ? CharFormat::k7E1 : CharFormat::k8N1;
  return std::make_unique<LineTransport>(open_serial_line(path, baud, backend, format, note), mode, baud);
}

std::unique_ptr<LineTransport> make_tcp_transport(const std::string& host, std::uint16_t port,
                                                  std::chrono::milliseconds timeout, int baud) {
  return std::make_unique<LineTransport>(TcpLine::connect(host, port, timeout), LineMode::kSoftwareParity8N1, baud);
}

std::unique_ptr<LineTransport> make_rfc2217_transport(const std::string& host, std::uint16_t port, int baud,
                                                      LineMode mode, std::chrono::milliseconds timeout,
                                                      TelnetNote note) {
  const CharFormat format = mode == LineMode::kTrue7E1 ? CharFormat::k7E1 : CharFormat::k8N1;
  return std::make_unique<LineTransport>(Rfc2217Line::connect(host, port, baud, format, timeout, std::move(note)),
                                         mode, baud);
}

}  // namespace sabus::harness
