// Proxy log records and the capture reader (capture.hpp, tools/PROXY-LOG.md).
#include "sabus/harness/capture.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <sstream>

#include "sabus/protocol/codec.hpp"

namespace sabus::harness {

std::string_view to_string(Direction d) { return d == Direction::kToDevice ? "mc->dev" : "dev->mc"; }

std::optional<Direction> parse_direction(std::string_view text) {
  // The proxy log's names and the run JSON's ("tx": the harness, as master,
  // sent it; "rx": the device's).
  if (text == "mc->dev" || text == "tx") return Direction::kToDevice;
  if (text == "dev->mc" || text == "rx") return Direction::kFromDevice;
  return std::nullopt;
}

std::string_view to_string(Capture::Source s) { return s == Capture::Source::kProxyLog ? "proxy log" : "run JSON"; }

std::string iso_utc_now() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t secs = std::chrono::system_clock::to_time_t(now);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char buf[40];
  const std::size_t n = std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  std::snprintf(buf + n, sizeof buf - n, ".%03dZ", static_cast<int>(ms));
  return buf;
}

namespace {

// Milliseconds with microsecond resolution: enough to order and pair records.
double rounded(double t_ms) { return std::round(t_ms * 1000.0) / 1000.0; }

nlohmann::json base(std::string_view type, double t_ms) {
  return {{"type", type}, {"t_ms", rounded(t_ms)}, {"wall", iso_utc_now()}};
}

nlohmann::json optional_number(std::optional<std::uint64_t> v) { return v ? nlohmann::json(*v) : nlohmann::json(); }

}  // namespace

nlohmann::json proxy_header(const std::string& mc_side, const std::string& device_side, const std::string& line) {
  return {{"schema", kProxyLogSchema}, {"version", kProxyLogVersion}, {"start", iso_utc_now()},
          {"mc", mc_side},             {"device", device_side},       {"line", line}};
}

nlohmann::json proxy_chunk(double t_ms, Direction d, ByteView wire) {
  auto j = base("chunk", t_ms);
  j["dir"] = to_string(d);
  j["hex"] = to_hex(wire);
  return j;
}

nlohmann::json proxy_frame(double t_ms, Direction d, ByteView chars, std::optional<std::uint64_t> seq,
                           std::optional<std::uint64_t> reply_to) {
  const FrameDescription desc = describe_frame(chars);
  nlohmann::json fields = nlohmann::json::array();
  for (const auto& f : desc.fields)
    fields.push_back({{"first", f.first}, {"last", f.last}, {"name", f.name}, {"raw", f.raw},
                      {"meaning", f.meaning}, {"ok", f.ok}});
  auto j = base("frame", t_ms);
  j["dir"] = to_string(d);
  j["seq"] = optional_number(seq);
  j["reply_to"] = optional_number(reply_to);
  j["hex"] = to_hex(chars);
  j["summary"] = desc.summary;
  j["error"] = desc.error ? nlohmann::json(desc.error->message()) : nlohmann::json();
  j["fields"] = std::move(fields);
  return j;
}

nlohmann::json proxy_discard(double t_ms, Direction d, const Discard& discard, ByteView wire_bytes) {
  auto j = base("discard", t_ms);
  j["dir"] = to_string(d);
  j["reason"] = std::string(to_string(discard.reason));
  j["message"] = discard.message();
  j["length"] = discard.length;
  j["hex"] = to_hex(wire_bytes);
  return j;
}

nlohmann::json proxy_event(double t_ms, std::string_view what, const std::string& detail) {
  auto j = base("event", t_ms);
  j["what"] = what;
  j["detail"] = detail;
  return j;
}

std::string proxy_log_line(const nlohmann::json& record) {
  return record.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + '\n';
}

// ---- reading --------------------------------------------------------------------------

namespace {

struct BadInput {
  std::string message;
};

const nlohmann::json& need(const nlohmann::json& j, const char* key, nlohmann::json::value_t type, const std::string& where) {
  auto it = j.find(key);
  if (it == j.end()) throw BadInput{where + ": no \"" + key + "\""};
  const bool number_ok = type == nlohmann::json::value_t::number_float && it->is_number();
  if (it->type() != type && !number_ok) throw BadInput{where + ": \"" + key + "\" has the wrong type (" + it->type_name() + ")"};
  return *it;
}

std::string need_string(const nlohmann::json& j, const char* key, const std::string& where) {
  return need(j, key, nlohmann::json::value_t::string, where).get<std::string>();
}

Bytes need_hex(const nlohmann::json& j, const std::string& where) {
  auto b = parse_hex(need_string(j, "hex", where));
  if (!b) throw BadInput{where + ": \"hex\": " + b.error().message()};
  return std::move(b).value();
}

Direction need_direction(const nlohmann::json& j, const std::string& where) {
  auto d = parse_direction(need_string(j, "dir", where));
  if (!d) throw BadInput{where + ": \"dir\" is not mc->dev, dev->mc, tx or rx"};
  return *d;
}

std::optional<std::uint64_t> optional_uint(const nlohmann::json& j, const char* key, const std::string& where) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return std::nullopt;
  if (!it->is_number_unsigned()) throw BadInput{where + ": \"" + key + "\" is not a count"};
  return it->get<std::uint64_t>();
}

std::string schema_of(const nlohmann::json& j) {
  if (!j.is_object()) return "";
  auto it = j.find("schema");
  return it != j.end() && it->is_string() ? it->get<std::string>() : "";
}

// A proxy log from `in`, a record a line: the header's device side and the
// events into `c`, each frame and discard to `on_item` as it is read.
void read_proxy_log(std::istream& in, Capture& c, const std::function<void(CapturedItem&&)>& on_item) {
  c.source = Capture::Source::kProxyLog;
  std::size_t n = 0;
  bool header = false;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = "line " + std::to_string(n);
    nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object()) throw BadInput{where + ": not a JSON object"};
    if (!header) {
      if (schema_of(j) != kProxyLogSchema) throw BadInput{where + ": the first record is not the sabus-proxy-log header"};
      const auto& v = need(j, "version", nlohmann::json::value_t::number_unsigned, where);
      if (v.get<int>() != kProxyLogVersion)
        throw BadInput{where + ": proxy log version " + v.dump() + "; this sabus reads version " + std::to_string(kProxyLogVersion)};
      c.device = need_string(j, "device", where);
      header = true;
      continue;
    }
    const std::string type = need_string(j, "type", where);
    if (type == "chunk") continue;  // the frames and discards say the same, framed
    CapturedItem item;
    item.t_ms = need(j, "t_ms", nlohmann::json::value_t::number_float, where).get<double>();
    auto wall = j.find("wall");
    if (wall != j.end() && wall->is_string()) item.wall = wall->get<std::string>();
    if (type == "event") {
      c.events.push_back(need_string(j, "what", where) + ": " + j.value("detail", std::string()));
      continue;
    }
    if (type != "frame" && type != "discard") throw BadInput{where + ": unknown record type \"" + type + "\""};
    item.dir = need_direction(j, where);
    item.chars = need_hex(j, where);
    if (type == "frame") {
      item.note = need_string(j, "summary", where);
      item.seq = optional_uint(j, "seq", where);
      item.reply_to = optional_uint(j, "reply_to", where);
    } else {
      item.ignored = true;
      item.note = need_string(j, "message", where);
    }
    on_item(std::move(item));
  }
  if (!header) throw BadInput{"line 1: empty log"};
}

Capture read_proxy_log(const std::string& text) {
  Capture c;
  c.segments.emplace_back();
  std::istringstream in(text);
  read_proxy_log(in, c, [&](CapturedItem&& item) { c.segments.front().items.push_back(std::move(item)); });
  return c;
}

Capture read_run_json(const nlohmann::json& doc) {
  Capture c;
  c.source = Capture::Source::kRunJson;
  if (auto it = doc.find("device"); it != doc.end() && it->is_string()) c.device = it->get<std::string>();
  const auto& vectors = need(doc, "vectors", nlohmann::json::value_t::array, "run JSON");
  for (std::size_t i = 0; i < vectors.size(); ++i) {
    const std::string where = "vectors[" + std::to_string(i) + "]";
    const auto& v = vectors[i];
    if (!v.is_object()) throw BadInput{where + ": not an object"};
    CapturedSegment s;
    s.id = need_string(v, "id", where);
    s.paragraph = v.value("paragraph", std::string());
    s.level = v.value("level", std::string());
    s.outcome = v.value("outcome", std::string());
    const auto& transcript = need(v, "transcript", nlohmann::json::value_t::array, where);
    for (std::size_t k = 0; k < transcript.size(); ++k) {
      const std::string at = where + ".transcript[" + std::to_string(k) + "]";
      const auto& t = transcript[k];
      if (!t.is_object()) throw BadInput{at + ": not an object"};
      CapturedItem item;
      item.t_ms = need(t, "t_ms", nlohmann::json::value_t::number_float, at).get<double>();
      item.dir = need_direction(t, at);
      item.chars = need_hex(t, at);
      item.note = t.value("note", std::string());
      // The runner records what its receiver ignored as an entry with no bytes.
      item.ignored = item.chars.empty();
      s.items.push_back(std::move(item));
    }
    c.segments.push_back(std::move(s));
  }
  return c;
}

}  // namespace

bool looks_like_capture(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || text[first] != '{') return false;
  const auto eol = text.find('\n', first);
  nlohmann::json head = nlohmann::json::parse(text.substr(first, eol == std::string::npos ? std::string::npos : eol - first),
                                              nullptr, false);
  if (schema_of(head) == kProxyLogSchema) return true;
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  return schema_of(doc) == "sabus-run";
}

bool is_proxy_log_header(const std::string& first_line) {
  return schema_of(nlohmann::json::parse(first_line, nullptr, false)) == kProxyLogSchema;
}

bool read_proxy_log(std::istream& in, Capture& capture, const std::function<void(CapturedItem&&)>& on_item,
                    std::string& error) {
  try {
    read_proxy_log(in, capture, on_item);
    return true;
  } catch (const BadInput& e) {
    error = e.message;
  } catch (const nlohmann::json::exception& e) {
    error = e.what();
  }
  return false;
}

std::optional<Capture> read_capture(const std::string& text, std::string& error) {
  try {
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) throw BadInput{"empty input"};
    const auto eol = text.find('\n', first);
    nlohmann::json head =
        nlohmann::json::parse(text.substr(first, eol == std::string::npos ? std::string::npos : eol - first), nullptr, false);
    if (schema_of(head) == kProxyLogSchema) return read_proxy_log(text);
    nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded()) throw BadInput{"neither a proxy log (JSON Lines) nor a run JSON: not JSON"};
    if (schema_of(doc) != "sabus-run")
      throw BadInput{"neither a proxy log nor a run JSON: the schema is \"" + schema_of(doc) +
                     "\", expected \"sabus-proxy-log\" or \"sabus-run\""};
    return read_run_json(doc);
  } catch (const BadInput& e) {
    error = e.message;
  } catch (const nlohmann::json::exception& e) {
    error = e.what();
  }
  return std::nullopt;
}

}  // namespace sabus::harness
