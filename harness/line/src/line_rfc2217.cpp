// Rfc2217Line (the client of a terminal server's RFC 2217 port) and
// Rfc2217ServerLine (one client of `sabus sim --rfc2217`).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>

#include "sabus/harness/rfc2217.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus::harness {

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
namespace cp = telnet::com_port;

constexpr std::string_view kScheme = "rfc2217://";

milliseconds left_until(Clock::time_point deadline) {
  return std::max(std::chrono::ceil<milliseconds>(deadline - Clock::now()), milliseconds{0});
}

// Hands out data kept by a line: as much as fits in `buf`.
std::size_t take(Bytes& data, std::size_t& taken, std::span<std::uint8_t> buf) {
  const std::size_t n = std::min(buf.size(), data.size() - taken);
  std::copy_n(data.begin() + static_cast<std::ptrdiff_t>(taken), n, buf.begin());
  taken += n;
  if (taken == data.size()) {
    data.clear();
    taken = 0;
  }
  return n;
}

// The options both sides of an RFC 2217 connection turn on.
std::vector<std::uint8_t> kept_options() {
  return {telnet::kBinary, telnet::kSuppressGoAhead, telnet::kComPortOption};
}

// The offer each end opens with (RFC 2217 §2; ser2net and pyserial's
// PortManager do the same): 8-bit data both ways (BINARY, RFC 856), no
// go-aheads (RFC 858), and COM-PORT-OPTION, which the client WILLs and the
// server DOs.
Bytes opening_offer(telnet::Options& options, bool client) {
  using namespace telnet;
  Bytes offer;
  for (const Bytes& b : {options.request_local(kBinary), options.request_remote(kBinary),
                         options.request_local(kSuppressGoAhead), options.request_remote(kSuppressGoAhead),
                         client ? options.request_local(kComPortOption) : options.request_remote(kComPortOption)})
    offer.insert(offer.end(), b.begin(), b.end());
  return offer;
}

}  // namespace

bool is_rfc2217_url(std::string_view text) { return text.substr(0, kScheme.size()) == kScheme; }

std::optional<Rfc2217Url> parse_rfc2217_url(std::string_view text, std::string& error) {
  if (!is_rfc2217_url(text)) {
    error = "not an rfc2217:// URL";
    return std::nullopt;
  }
  std::string_view rest = text.substr(kScheme.size());
  std::string_view query;
  if (const auto q = rest.find('?'); q != std::string_view::npos) {
    query = rest.substr(q + 1);
    rest = rest.substr(0, q);
  }
  // pyserial's query options that change nothing for sabus: it never waits
  // for SET-CONTROL's answer, logs by itself, and has its own timeouts.
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view item = query.substr(0, amp);
    const std::string_view key = item.substr(0, item.find('='));
    if (key != "ign_set_control" && key != "logging" && key != "timeout" && key != "poll_modem") {
      error = fmt::format("{}: unknown option \"{}\" (rfc2217://HOST:PORT, optionally ?ign_set_control)", text, key);
      return std::nullopt;
    }
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
  }
  Rfc2217Url url;
  const auto colon = rest.rfind(':');
  if (colon == std::string_view::npos || colon == 0) {
    error = fmt::format("{}: expected rfc2217://HOST:PORT", text);
    return std::nullopt;
  }
  std::string_view host = rest.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const std::string_view port = rest.substr(colon + 1);
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc{} || end != port.data() + port.size() || value == 0 || value > 65535) {
    error = fmt::format("{}: the port must be a number 1-65535", text);
    return std::nullopt;
  }
  url.host = std::string(host);
  url.port = static_cast<std::uint16_t>(value);
  return url;
}

// ---- client -------------------------------------------------------------------

Rfc2217Line::Rfc2217Line(std::unique_ptr<TcpLine> tcp, std::string endpoint, int baud, CharFormat format,
                         TelnetNote note)
    : tcp_(std::move(tcp)),
      endpoint_(std::move(endpoint)),
      baud_(baud),
      format_(format),
      note_(std::move(note)),
      options_(kept_options(), kept_options()) {}

std::unique_ptr<Rfc2217Line> Rfc2217Line::connect(const std::string& host, std::uint16_t port, int baud,
                                                  CharFormat format, milliseconds timeout, TelnetNote note) {
  auto tcp = TcpLine::connect(host, port, timeout);
  const std::string endpoint = tcp->describe().substr(4);  // "tcp HOST:PORT" -> "HOST:PORT"
  std::unique_ptr<Rfc2217Line> line(new Rfc2217Line(std::move(tcp), endpoint, baud, format, std::move(note)));
  line->negotiate(timeout);
  return line;
}

void Rfc2217Line::say(const std::string& text, bool important) const {
  if (note_) note_("rfc2217 " + endpoint_ + ": " + text, important);
}

bool Rfc2217Line::pump(milliseconds timeout) {
  std::array<std::uint8_t, 1024> raw{};
  std::size_t n = 0;
  try {
    n = tcp_->read(raw, timeout);
  } catch (const LineError& e) {
    throw LineError(fmt::format("rfc2217 {}: {}", endpoint_, e.what()));
  }
  if (n == 0) return false;
  std::vector<telnet::Event> events;
  decoder_.feed(ByteView(raw.data(), n), data_, events);
  for (const auto& e : events) handle(e);
  return true;
}

void Rfc2217Line::handle(const telnet::Event& e) {
  using Kind = telnet::Event::Kind;
  switch (e.kind) {
    case Kind::negotiation: {
      const Bytes answer = options_.receive(e.verb, e.option);
      if (!answer.empty()) tcp_->write(answer);
      if (e.option != telnet::kBinary && e.option != telnet::kSuppressGoAhead && e.option != telnet::kComPortOption)
        say("server " + telnet::describe(e) + (answer.empty() ? "" : ": refused"), false);
      return;
    }
    case Kind::subnegotiation: {
      if (e.option != telnet::kComPortOption || e.payload.empty()) {
        say("ignored " + telnet::describe(e), false);
        return;
      }
      const std::uint8_t code = e.payload[0];
      const ByteView value = ByteView(e.payload).subspan(1);
      if (code >= cp::kServerOffset + cp::kSetBaudrate && code <= cp::kServerOffset + cp::kSetControl) {
        answers_[code - cp::kServerOffset] = Bytes(value.begin(), value.end());
        return;
      }
      if (code == cp::kServerOffset + cp::kNotifyLinestate && !value.empty()) {
        // Bits 1-4 are errors on the server's serial side (overrun, parity,
        // framing, break): a reply may have been garbled there.
        const bool error = (value[0] & 0x1E) != 0;
        say("server line state: " + cp::linestate_text(value[0]), error);
        return;
      }
      if (code == cp::kServerOffset + cp::kNotifyModemstate && !value.empty()) {
        say("server modem state: " + cp::modemstate_text(value[0]), false);
        return;
      }
      say("ignored " + telnet::describe(e), false);
      return;
    }
    case Kind::command: return;  // NOP, GA, ...: nothing to do on a data line
    case Kind::error: say(e.reason, true); return;
  }
}

void Rfc2217Line::negotiate(milliseconds timeout) {
  using namespace telnet;
  // Stage 1 (RFC 2217 §2): the client offers COM-PORT-OPTION (WILL), and
  // both sides go 8-bit clean without go-aheads.
  const Bytes hello = opening_offer(options_, true);
  const auto sent = Clock::now();
  tcp_->write(hello);
  auto deadline = sent + timeout;
  std::optional<Clock::duration> first_answer;
  while (options_.local_pending(kComPortOption) || options_.local_pending(kBinary) ||
         options_.remote_pending(kBinary)) {
    if (Clock::now() >= deadline)
      throw LineError(fmt::format(
          "rfc2217 {}: no Telnet negotiation from the server within {} ms (is it a raw TCP port? use --tcp "
          "HOST:PORT for one)",
          endpoint_, timeout.count()));
    if (pump(left_until(deadline)) && !first_answer) first_answer = Clock::now() - sent;
  }
  if (!options_.local_on(kComPortOption))
    throw LineError(fmt::format("rfc2217 {}: the server refused COM-PORT-OPTION (RFC 2217): it cannot set the "
                                "serial port (for a raw TCP port use --tcp HOST:PORT)",
                                endpoint_));
  if (!options_.local_on(kBinary) || !options_.remote_on(kBinary))
    throw LineError(fmt::format("rfc2217 {}: the server refused BINARY (RFC 856) {}: SAbus needs all 8 bits",
                                endpoint_, options_.local_on(kBinary) ? "from us" : "to us"));

  // Stage 2: the port settings. 8N1 carries SAbus's parity in bit 7 (made
  // by sabus, READING-NOTES 1); 7E1 has the server's UART make it.
  const bool seven = format_ == CharFormat::k7E1;
  const std::uint8_t datasize = seven ? 7 : 8;
  const std::uint8_t parity = seven ? cp::kParityEven : cp::kParityNone;
  Bytes settings;
  for (const Bytes& b :
       {subnegotiation(kComPortOption, cp::set_baudrate(cp::kSetBaudrate, static_cast<std::uint32_t>(baud_))),
        subnegotiation(kComPortOption, Bytes{cp::kSetDatasize, datasize}),
        subnegotiation(kComPortOption, Bytes{cp::kSetParity, parity}),
        subnegotiation(kComPortOption, Bytes{cp::kSetStopsize, cp::kOneStopBit}),
        subnegotiation(kComPortOption, Bytes{cp::kSetControl, cp::kNoFlowControl})})
    settings.insert(settings.end(), b.begin(), b.end());
  const auto asked = Clock::now();
  tcp_->write(settings);
  deadline = asked + timeout;
  std::optional<Clock::duration> settings_answer;
  auto answered = [&] {
    return answers_[cp::kSetBaudrate] && answers_[cp::kSetDatasize] && answers_[cp::kSetParity] &&
           answers_[cp::kSetStopsize];
  };
  while (!answered()) {
    if (Clock::now() >= deadline) {
      std::string missing;
      for (std::uint8_t c = cp::kSetBaudrate; c <= cp::kSetStopsize; ++c)
        if (!answers_[c]) missing += (missing.empty() ? "" : ", ") + cp::command_name(c);
      throw LineError(fmt::format("rfc2217 {}: the server did not answer {} within {} ms", endpoint_, missing,
                                  timeout.count()));
    }
    const bool before = answers_[cp::kSetBaudrate].has_value();
    pump(left_until(deadline));
    if (!before && answers_[cp::kSetBaudrate]) settings_answer = Clock::now() - asked;
  }
  // The server answers with what it now uses; anything else is not the line asked for.
  Bytes baud_answer{cp::kSetBaudrate};
  baud_answer.insert(baud_answer.end(), answers_[cp::kSetBaudrate]->begin(), answers_[cp::kSetBaudrate]->end());
  const auto baud_now = cp::baudrate_of(baud_answer);
  if (!baud_now || *baud_now != static_cast<std::uint32_t>(baud_))
    throw LineError(fmt::format("rfc2217 {}: the server set {} baud, not the {} asked for", endpoint_,
                                baud_now ? std::to_string(*baud_now) : "an unreadable rate", baud_));
  auto check = [&](std::uint8_t code, std::uint8_t want, const std::string& what) {
    const Bytes& got = *answers_[code];
    if (got.empty() || got[0] != want)
      throw LineError(fmt::format("rfc2217 {}: the server did not accept {} (answered {} to {})", endpoint_, what,
                                  got.empty() ? "nothing" : std::to_string(got[0]), cp::command_name(code)));
  };
  check(cp::kSetDatasize, datasize, std::to_string(datasize) + " data bits");
  check(cp::kSetParity, parity, seven ? "even parity" : "no parity");
  check(cp::kSetStopsize, cp::kOneStopBit, "one stop bit");
  // SET-CONTROL's answer usually comes with the others; give it a moment
  // more, no longer (ser2net on a pty never sends one).
  const auto grace = Clock::now() + std::min(timeout, milliseconds{200});
  while (!answers_[cp::kSetControl] && Clock::now() < grace) pump(left_until(grace));
  if (!answers_[cp::kSetControl])
    say("the server did not acknowledge SET-CONTROL (no flow control); carrying on without it (ser2net on a "
        "pseudo-terminal cannot set DTR/RTS and never does)",
        true);
  // The round trip: request to first answer, the shorter of the two stages
  // (the first may include the server's own start-up).
  auto rt = settings_answer.value_or(first_answer.value_or(Clock::duration{0}));
  if (first_answer) rt = std::min(rt, *first_answer);
  round_trip_ = std::chrono::duration_cast<std::chrono::microseconds>(rt);
  say(fmt::format("negotiated BINARY, SUPPRESS-GO-AHEAD, COM-PORT-OPTION; {} baud {}; round trip {:.2f} ms", baud_,
                  to_string(format_), round_trip_.count() / 1000.0),
      false);
}

std::size_t Rfc2217Line::read(std::span<std::uint8_t> buf, milliseconds timeout) {
  if (buf.empty()) return 0;
  const auto deadline = Clock::now() + std::max(timeout, milliseconds{0});
  // Negotiation alone (a notification, a NOP) is not data: wait on for data
  // within the same timeout.
  while (data_.size() == taken_) {
    const auto left = left_until(deadline);
    if (!pump(left) && Clock::now() >= deadline) return 0;
    if (left.count() == 0 && data_.size() == taken_) return 0;
  }
  return take(data_, taken_, buf);
}

void Rfc2217Line::write(ByteView bytes) { tcp_->write(telnet::escaped(bytes)); }

std::string Rfc2217Line::describe() const {
  return fmt::format("rfc2217 {} {} {} (round trip {:.2f} ms)", endpoint_, baud_, to_string(format_),
                     round_trip_.count() / 1000.0);
}

// ---- server -------------------------------------------------------------------

Rfc2217ServerLine::Rfc2217ServerLine(std::unique_ptr<TcpLine> client, int baud, TelnetNote note)
    : client_(std::move(client)), note_(std::move(note)), options_(kept_options(), kept_options()), baud_(baud) {
  // What a device server offers a new client.
  client_->write(opening_offer(options_, false));
}

void Rfc2217ServerLine::say(const std::string& text, bool important) const {
  if (note_) note_("rfc2217: " + text, important);
}

std::optional<int> Rfc2217ServerLine::take_baud_change() { return std::exchange(baud_change_, std::nullopt); }

std::size_t Rfc2217ServerLine::read(std::span<std::uint8_t> buf, milliseconds timeout) {
  if (buf.empty()) return 0;
  const auto deadline = Clock::now() + std::max(timeout, milliseconds{0});
  while (data_.size() == taken_) {
    std::array<std::uint8_t, 1024> raw{};
    const std::size_t n = client_->read(raw, left_until(deadline));
    if (n == 0) return 0;
    std::vector<telnet::Event> events;
    const std::size_t before = data_.size();
    decoder_.feed(ByteView(raw.data(), n), data_, events);
    // A client's true 7E1 UART sends 7-bit characters; the reference
    // controller reads them as a line with parity in bit 7 carries them.
    if (seven_bit_parity())
      for (std::size_t i = before; i < data_.size(); ++i) data_[i] = with_even_parity(data_[i]);
    for (const auto& e : events) handle(e);
    if (data_.size() == taken_ && Clock::now() >= deadline) return 0;
  }
  return take(data_, taken_, buf);
}

void Rfc2217ServerLine::write(ByteView bytes) {
  if (!seven_bit_parity()) {
    client_->write(telnet::escaped(bytes));
    return;
  }
  Bytes seven(bytes.begin(), bytes.end());
  for (auto& b : seven) b &= 0x7F;  // the UART takes the parity bit off
  client_->write(telnet::escaped(seven));
}

std::string Rfc2217ServerLine::describe() const {
  return "rfc2217 " + client_->describe().substr(4) + " " + std::to_string(baud_) + " " +
         std::to_string(datasize_) + (parity_ == telnet::com_port::kParityEven ? "E1" : "N1");
}

void Rfc2217ServerLine::handle(const telnet::Event& e) {
  using Kind = telnet::Event::Kind;
  switch (e.kind) {
    case Kind::negotiation: {
      const Bytes answer = options_.receive(e.verb, e.option);
      if (!answer.empty()) client_->write(answer);
      return;
    }
    case Kind::subnegotiation:
      if (e.option == telnet::kComPortOption && !e.payload.empty()) com_port(e.payload);
      else say("ignored " + telnet::describe(e), false);
      return;
    case Kind::command: return;
    case Kind::error: say(e.reason, true); return;
  }
}

void Rfc2217ServerLine::reply(std::uint8_t code, ByteView value) {
  Bytes payload{static_cast<std::uint8_t>(code + cp::kServerOffset)};
  payload.insert(payload.end(), value.begin(), value.end());
  client_->write(telnet::subnegotiation(telnet::kComPortOption, payload));
}

void Rfc2217ServerLine::com_port(ByteView payload) {
  const std::uint8_t code = payload[0];
  const ByteView value = payload.subspan(1);
  const std::uint8_t v = value.empty() ? 0 : value[0];
  switch (code) {
    case cp::kSignature: {
      const std::string_view name = "sabus sim (reference RC3000)";
      reply(code, ByteView(reinterpret_cast<const std::uint8_t*>(name.data()), name.size()));
      return;
    }
    case cp::kSetBaudrate: {
      // 0 asks for the rate in force; any other is a request (RFC 2217
      // SET-BAUDRATE). The answer is the rate now in force.
      const auto asked = cp::baudrate_of(payload);
      if (asked && *asked >= 300 && *asked <= 115200 && static_cast<int>(*asked) != baud_) {
        baud_ = static_cast<int>(*asked);
        baud_change_ = baud_;  // the server loop logs it when it takes it
      } else if (asked && *asked != 0 && static_cast<int>(*asked) != baud_) {
        say(fmt::format("client asked for {} baud: kept {} (300-115200)", *asked, baud_), true);
      }
      const Bytes now = cp::set_baudrate(code, static_cast<std::uint32_t>(baud_));
      reply(code, ByteView(now).subspan(1));
      return;
    }
    case cp::kSetDatasize:
      if (v == 7 || v == 8) datasize_ = v;
      reply(code, Bytes{datasize_});
      return;
    case cp::kSetParity:
      if (v == cp::kParityNone || v == cp::kParityEven) parity_ = v;
      reply(code, Bytes{parity_});
      return;
    case cp::kSetStopsize:
      reply(code, Bytes{cp::kOneStopBit});
      return;
    case cp::kSetControl:
    case cp::kSetLinestateMask:
    case cp::kSetModemstateMask:
    case cp::kPurgeData:
      // No modem lines, flow control or buffers to act on in a simulation:
      // acknowledged with the value asked (pyserial waits for the echo).
      reply(code, value);
      return;
    default:
      say("ignored " + cp::command_name(code), false);
      return;
  }
}

}  // namespace sabus::harness
