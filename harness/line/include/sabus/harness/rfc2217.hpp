// Lines over Telnet with RFC 2217's COM-PORT-OPTION, as a serial device
// server (ser2net, Moxa NPort, Digi PortServer) offers them: the client
// (`--port rfc2217://HOST:PORT`, pyserial's URL form) and the server side of
// `sabus sim --rfc2217`. The telnet codec is telnet.hpp; these add the I/O.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "sabus/harness/line.hpp"
#include "sabus/harness/telnet.hpp"

namespace sabus::harness {

// Something the telnet layer saw that a person may want to know: a line
// state or modem state the server notified, an option it refused, a
// subnegotiation it garbled. `important` marks what a run should print even
// when not verbose (line errors, a missing acknowledgement).
using TelnetNote = std::function<void(const std::string& text, bool important)>;

// "rfc2217://HOST:PORT" or "rfc2217://HOST:PORT?ign_set_control" (pyserial's
// form; its query options are accepted when they change nothing here:
// ign_set_control, logging=..., timeout=...). nullopt when `text` does not
// start with rfc2217:// ; an error text when it does but is malformed.
struct Rfc2217Url {
  std::string host;
  std::uint16_t port = 0;
};
bool is_rfc2217_url(std::string_view text);
std::optional<Rfc2217Url> parse_rfc2217_url(std::string_view text, std::string& error);

class Rfc2217Line final : public Line {
 public:
  // Connects within `timeout`, negotiates BINARY both ways, SUPPRESS-GO-AHEAD
  // and COM-PORT-OPTION, and sets the server's UART to `baud`, 8N1 (SAbus's
  // parity made by sabus in bit 7) or 7E1 (made by the server's UART), one
  // stop bit, no flow control. Each stage waits at most `timeout`: a server
  // that never answers (a raw TCP port, a telnet server without RFC 2217) is
  // a LineError that says so. A SET-CONTROL left unanswered is only noted:
  // ser2net on a pseudo-terminal cannot set DTR/RTS and never answers it.
  static std::unique_ptr<Rfc2217Line> connect(const std::string& host, std::uint16_t port, int baud,
                                              CharFormat format, std::chrono::milliseconds timeout,
                                              TelnetNote note = {});

  std::size_t read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override;
  void write(ByteView bytes) override;
  // "rfc2217 127.0.0.1:7000 9600 8N1 (round trip 0.3 ms)"
  std::string describe() const override;
  int poll_fd() const override { return tcp_->poll_fd(); }
  // The network round trip measured while negotiating (request to answer).
  std::chrono::microseconds round_trip() const override { return round_trip_; }

 private:
  Rfc2217Line(std::unique_ptr<TcpLine> tcp, std::string endpoint, int baud, CharFormat format, TelnetNote note);
  // Reads once (up to `timeout`), answers negotiation, keeps data; false on timeout.
  bool pump(std::chrono::milliseconds timeout);
  void handle(const telnet::Event& e);
  void say(const std::string& text, bool important) const;
  void negotiate(std::chrono::milliseconds timeout);

  std::unique_ptr<TcpLine> tcp_;
  std::string endpoint_;
  int baud_;
  CharFormat format_;
  TelnetNote note_;
  telnet::Decoder decoder_;
  telnet::Options options_;
  Bytes data_;            // data received, not yet read
  std::size_t taken_ = 0;  // how much of data_ was read
  // The server's answers to SET-BAUDRATE .. SET-STOPSIZE and SET-CONTROL
  // (index: command code), the payload after the code.
  std::optional<Bytes> answers_[6];
  std::chrono::microseconds round_trip_{0};
};

// The server side of one RFC 2217 client (`sabus sim --rfc2217`): answers
// the client's negotiation and COM-PORT-OPTION requests as a device server
// does (each SET-... acknowledged with the server's code, command + 100, and
// the value now in force), unescapes its data and escapes what is written.
// The baud rate the client sets is reported by take_baud_change(), for the
// line emulation. When the client sets 7 data bits and even parity (a true
// 7E1 port on its side), the UART's work is done here: even parity put in
// bit 7 of what it sends (as the reference controller reads it,
// READING-NOTES 1) and taken off what it is sent.
class Rfc2217ServerLine final : public Line {
 public:
  Rfc2217ServerLine(std::unique_ptr<TcpLine> client, int baud, TelnetNote note = {});

  std::size_t read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override;
  void write(ByteView bytes) override;
  std::string describe() const override;
  int poll_fd() const override { return client_->poll_fd(); }

  // The baud rate set by the client since the last call, if it set one.
  std::optional<int> take_baud_change();
  int baud() const { return baud_; }

 private:
  void handle(const telnet::Event& e);
  void com_port(ByteView payload);
  void reply(std::uint8_t code, ByteView value);
  void say(const std::string& text, bool important) const;
  bool seven_bit_parity() const { return datasize_ == 7 && parity_ == telnet::com_port::kParityEven; }

  std::unique_ptr<TcpLine> client_;
  TelnetNote note_;
  telnet::Decoder decoder_;
  telnet::Options options_;
  int baud_;
  std::optional<int> baud_change_;
  std::uint8_t datasize_ = 8, parity_ = telnet::com_port::kParityNone;
  Bytes data_;
  std::size_t taken_ = 0;
};

}  // namespace sabus::harness
