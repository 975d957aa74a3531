// Captured bench traffic: the proxy log that `sabus proxy` writes (JSON
// Lines, tools/PROXY-LOG.md) and the reader that turns a proxy log or a run
// JSON (`sabus run --json`, schema "sabus-run") into one list of timed,
// directed frames, for `sabus decode` and `sabus record`.
#pragma once

#include <cstdint>
#include <functional>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::harness {

// Which way bytes went: from the M&C system (the master) to the device, or
// back.
enum class Direction : std::uint8_t { kToDevice, kFromDevice };
std::string_view to_string(Direction d);  // "mc->dev", "dev->mc"
std::optional<Direction> parse_direction(std::string_view text);

// ---- writing a proxy log ---------------------------------------------------------

inline constexpr std::string_view kProxyLogSchema = "sabus-proxy-log";
inline constexpr int kProxyLogVersion = 1;

// "2024-05-06T12:34:56.789Z": the wall time of a record, UTC, milliseconds.
std::string iso_utc_now();

// One record a line; every record but the header has "type", "t_ms" (since
// the proxy started) and "wall". See tools/PROXY-LOG.md.
nlohmann::json proxy_header(const std::string& mc_side, const std::string& device_side, const std::string& line);
nlohmann::json proxy_chunk(double t_ms, Direction d, ByteView wire);
// A frame as the §1 receiver framed it (7-bit characters) with describe_frame.
// Requests carry `seq` (1, 2, ...); replies carry `reply_to`, the seq of the
// last request before them (null before the first request).
nlohmann::json proxy_frame(double t_ms, Direction d, ByteView chars, std::optional<std::uint64_t> seq,
                           std::optional<std::uint64_t> reply_to);
nlohmann::json proxy_discard(double t_ms, Direction d, const Discard& discard, ByteView wire_bytes);
nlohmann::json proxy_event(double t_ms, std::string_view what, const std::string& detail);
// A record as one line of the log, its newline included. Text that is not
// UTF-8 (a path given on the command line, an error naming it) has each
// byte that is not replaced by U+FFFD: json's dump() throws type_error 316
// on it, which ended the proxy before its first line.
std::string proxy_log_line(const nlohmann::json& record);

// ---- reading a capture -------------------------------------------------------------

// A frame, or a run of ignored bytes, at a time and in a direction.
struct CapturedItem {
  double t_ms = 0;
  std::string wall;         // ISO time; empty in a run JSON
  Direction dir = Direction::kToDevice;
  Bytes chars;              // 7-bit characters: one frame, or what a run JSON sent in one write
  bool ignored = false;     // bytes the receiver discarded (note says why)
  std::string note;         // the summary or the discard reason
  std::optional<std::uint64_t> seq, reply_to;  // proxy log pairing
};

// A proxy session is one segment; a run JSON has one segment per vector.
struct CapturedSegment {
  std::string id;           // the vector id; "" for a proxy session
  std::string paragraph, level, outcome;
  std::vector<CapturedItem> items;
};

struct Capture {
  enum class Source : std::uint8_t { kProxyLog, kRunJson } source = Source::kProxyLog;
  std::string device;       // the device side as the log or run names it
  std::vector<CapturedSegment> segments;
  std::vector<std::string> events;  // proxy events ("device lost ...") in order
};
std::string_view to_string(Capture::Source s);  // "proxy log", "run JSON"

// True when `text` looks like a proxy log or a run JSON (cheap: the first
// JSON value's schema), for `sabus decode` to choose its reader.
bool looks_like_capture(const std::string& text);
// Reads a proxy log (JSON Lines) or a run JSON (schema "sabus-run", version
// 1 or 2: only vectors[].id, paragraph, level, outcome and transcript[] with
// t_ms, dir, hex, note are used). On bad input returns nullopt and sets
// `error` to "line N: reason" (proxy log) or "vectors[i].transcript[j]: reason".
std::optional<Capture> read_capture(const std::string& text, std::string& error);
// Whether a capture's first line is a proxy log's header.
bool is_proxy_log_header(const std::string& first_line);
// A proxy log read a record at a time, for a log too large to hold: the
// header's device side and the events go into `capture` (its segments stay
// empty), each frame and discard to `on_item` as it is read. On bad input
// returns false with `error` as read_capture sets it (the items before the
// bad line have been handed over).
bool read_proxy_log(std::istream& in, Capture& capture, const std::function<void(CapturedItem&&)>& on_item,
                    std::string& error);

}  // namespace sabus::harness
