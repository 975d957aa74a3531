// A checker of the proxy log against what tools/PROXY-LOG.md documents, for
// the tests of every path that writes it: each line one JSON object; the
// keys of each record type exactly those of the document's table (read from
// the document, so that a key added to the writer and not to the document,
// or the other way round, fails); each key's JSON type and values; the
// pairing of seq and reply_to; a frame's t_ms that of the chunk before it.
#pragma once

#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::test {

struct ProxyLogSpec {
  std::map<std::string, std::set<std::string>> keys;  // "(header)", "chunk", ... -> the record's keys
  std::set<std::string> field_keys;                   // of each entry of a frame's "fields"
  std::set<std::string> events;                       // an event's "what"
};

namespace proxy_log_detail {

// The `...` spans of a table cell, each up to a ':' ("schema: ..." -> "schema").
inline std::vector<std::string> code_spans(const std::string& cell) {
  std::vector<std::string> out;
  static const std::regex span("`([^`]*)`");
  for (std::sregex_iterator it(cell.begin(), cell.end(), span), end; it != end; ++it) {
    const std::string text = (*it)[1];
    out.push_back(text.substr(0, text.find(':')));
  }
  return out;
}

inline std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  for (std::size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '|') {
      out.push_back(cell);
      cell.clear();
    } else {
      cell += row[i];
    }
  }
  return out;
}

}  // namespace proxy_log_detail

// The table of "## Records": | `type` | keys | what |.
inline ProxyLogSpec read_proxy_log_spec(const std::string& markdown) {
  using namespace proxy_log_detail;
  ProxyLogSpec spec;
  std::istringstream in(markdown);
  bool table = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `type` |", 0) == 0) {
      table = true;
      continue;
    }
    if (!table || line.rfind("|---", 0) == 0) continue;
    if (line.rfind("|", 0) != 0) break;
    const auto c = cells(line);
    if (c.size() < 3) continue;
    const auto type = code_spans(c[0]);
    const std::string name = type.empty() ? "(header)" : type[0];
    std::set<std::string> keys;
    for (const auto& k : code_spans(c[1])) keys.insert(k);
    // "every other record has `type`, `t_ms` ... and `wall`" (## Records).
    if (name != "(header)") keys.insert({"type", "t_ms", "wall"});
    spec.keys[name] = keys;
    if (name == "frame") {
      const auto open = c[2].find("`fields` (");
      const auto close = c[2].find(')', open);
      if (open != std::string::npos)
        for (const auto& k : code_spans(c[2].substr(open + 10, close - open - 10))) spec.field_keys.insert(k);
    }
    if (name == "event")
      for (const auto& e : code_spans(c[2])) spec.events.insert(e);
  }
  return spec;
}

// Every problem of a log's text, "line N: ..."; empty when each line is one
// JSON object as the document says.
inline std::vector<std::string> proxy_log_problems(const std::string& text, const ProxyLogSpec& spec) {
  std::vector<std::string> problems;
  static const std::regex iso(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)");
  std::set<std::string> reasons;
#define SABUS_X(id, name, description) reasons.insert(name);
  SABUS_DISCARD_REASONS(SABUS_X)
#undef SABUS_X
  if (spec.keys.size() != 5 || spec.field_keys.empty() || spec.events.empty())
    problems.push_back("PROXY-LOG.md: the table of records was not found whole");
  if (text.empty() || text.back() != '\n') problems.push_back("the log does not end with a newline");
  std::istringstream in(text);
  std::size_t n = 0;
  double last_t = 0;
  std::optional<std::uint64_t> last_seq;
  std::map<std::string, double> chunk_t;  // dir -> t_ms of its last chunk
  for (std::string line; std::getline(in, line);) {
    const std::string at = "line " + std::to_string(++n) + ": ";
    auto problem = [&](const std::string& what) { problems.push_back(at + what + " in " + line); };
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object()) {
      problem("not a JSON object");
      continue;
    }
    const std::string type = n == 1 ? "(header)" : j.value("type", "");
    const auto spec_keys = spec.keys.find(type);
    if (spec_keys == spec.keys.end()) {
      problem("a record of type \"" + type + "\", which PROXY-LOG.md does not document");
      continue;
    }
    std::set<std::string> keys;
    for (const auto& [k, v] : j.items()) keys.insert(k);
    if (keys != spec_keys->second) problem("keys other than PROXY-LOG.md's for " + type);
    auto is_string = [&](const char* k) { return j.contains(k) && j[k].is_string(); };
    auto is_count = [&](const char* k) { return j.contains(k) && j[k].is_number_unsigned(); };
    auto is_count_or_null = [&](const char* k) { return j.contains(k) && (j[k].is_null() || j[k].is_number_unsigned()); };
    auto hex_of = [&](const char* k) -> std::optional<Bytes> {
      if (!is_string(k)) return std::nullopt;
      auto b = parse_hex(j[k].get<std::string>());
      return b ? std::optional<Bytes>(b.value()) : std::nullopt;
    };
    if (type == "(header)") {
      if (j.value("schema", "") != "sabus-proxy-log" || j.value("version", 0) != 1) problem("not the version 1 header");
      if (!is_string("mc") || !is_string("device")) problem("mc and device are not text");
      if (!is_string("start") || !std::regex_match(j["start"].get<std::string>(), iso)) problem("start is not ISO UTC");
      if (j.value("line", "") != "8N1" && j.value("line", "") != "7E1") problem("line is not 8N1 or 7E1");
      continue;
    }
    if (!j.contains("t_ms") || !j["t_ms"].is_number() || j["t_ms"].get<double>() < last_t) {
      problem("t_ms is not a number at or after the last");
    } else {
      last_t = j["t_ms"].get<double>();
    }
    if (!is_string("wall") || !std::regex_match(j["wall"].get<std::string>(), iso)) problem("wall is not ISO UTC");
    if (type == "event") {
      if (!is_string("what") || !spec.events.count(j["what"].get<std::string>())) problem("an event PROXY-LOG.md does not list");
      if (!is_string("detail")) problem("detail is not text");
      continue;
    }
    const std::string dir = j.value("dir", "");
    if (dir != "mc->dev" && dir != "dev->mc") problem("dir is not mc->dev or dev->mc");
    const auto hex = hex_of("hex");
    if (!hex) problem("hex is not hex text");
    if (type == "chunk") {
      if (hex && hex->empty()) problem("an empty chunk");
      chunk_t[dir] = j.value("t_ms", 0.0);
    } else if (type == "discard") {
      if (!is_string("reason") || !reasons.count(j["reason"].get<std::string>())) problem("a reason receiver.hpp does not have");
      if (!is_string("message")) problem("message is not text");
      if (!is_count("length") || j["length"].get<std::uint64_t>() == 0) problem("length is not a count of bytes");
      else if (hex && (hex->empty() || hex->size() > std::min<std::uint64_t>(j["length"].get<std::uint64_t>(), 4096)))
        problem("hex is not the run's last bytes (at most 4096)");
    } else if (type == "frame") {
      if (hex)
        for (auto b : *hex)
          if (b > 0x7F) problem("a frame's hex is not 7-bit characters");
      if (!is_string("summary")) problem("summary is not text");
      if (!j.contains("error") || !(j["error"].is_null() || j["error"].is_string())) problem("error is not text or null");
      if (!j.contains("fields") || !j["fields"].is_array()) {
        problem("fields is not an array");
      } else {
        for (const auto& f : j["fields"]) {
          std::set<std::string> fk;
          if (f.is_object())
            for (const auto& [k, v] : f.items()) fk.insert(k);
          if (fk != spec.field_keys || !f["first"].is_number_unsigned() || !f["last"].is_number_unsigned() ||
              f["first"] > f["last"] || !f["name"].is_string() || !f["raw"].is_string() || !f["meaning"].is_string() ||
              !f["ok"].is_boolean())
            problem("a field not as PROXY-LOG.md gives it: " + f.dump());
        }
      }
      // Pairing: commands count 1, 2, 3, ...; a reply names the last command.
      if (!is_count_or_null("seq") || !is_count_or_null("reply_to")) {
        problem("seq or reply_to is not a count or null");
      } else if (dir == "mc->dev") {
        if (!j["reply_to"].is_null() || !j["seq"].is_number() || j["seq"].get<std::uint64_t>() != (last_seq ? *last_seq + 1 : 1))
          problem("a command frame's seq is not the next count, or it has a reply_to");
        else last_seq = j["seq"].get<std::uint64_t>();
      } else if (!j["seq"].is_null() || j["reply_to"] != (last_seq ? nlohmann::json(*last_seq) : nlohmann::json())) {
        problem("a reply frame's reply_to is not the last command's seq, or it has a seq");
      }
      if (!chunk_t.count(dir) || chunk_t[dir] != j.value("t_ms", -1.0)) problem("a frame not at its chunk's t_ms");
    }
  }
  if (n == 0) problems.push_back("an empty log");
  return problems;
}

}  // namespace sabus::test
