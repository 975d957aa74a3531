// The JSON serializer of the run JSON and its journal (reports/SCHEMA.md):
// RapidJSON's Writer, which places every bracket, comma and quote and
// escapes every string, fed from the run document. No JSON text is made here
// by hand or kept from one write to the next.
#pragma once

#include "rapidjson_headers.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/reports/document.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports::json_out {

// A RapidJSON output stream into a std::ostream, in pieces of 64 KiB. Its
// Put is a store and a compare: a run JSON is megabytes, copied a character
// at a time by the writer.
class OStreamBuffer {
 public:
  using Ch = char;
  explicit OStreamBuffer(std::ostream& out) : out_(out), buf_(kPiece), at_(buf_.data()), end_(buf_.data() + kPiece) {}
  OStreamBuffer(const OStreamBuffer&) = delete;
  OStreamBuffer& operator=(const OStreamBuffer&) = delete;
  ~OStreamBuffer() { Flush(); }
  void Put(char c) {
    *at_++ = c;
    if (at_ == end_) Flush();
  }
  void Flush() {
    out_.write(buf_.data(), at_ - buf_.data());
    at_ = buf_.data();
  }

 private:
  static constexpr std::size_t kPiece = 1 << 16;
  std::ostream& out_;
  std::vector<char> buf_;
  char* at_;
  char* end_;
};

// One JSON text on one line (a journal record, a vector of the run JSON).
using LineWriter = rapidjson::Writer<rapidjson::StringBuffer>;
// The run JSON: one member a line, indented; each vector on one line of its
// own (written by a LineWriter and placed with RawValue).
using FileWriter = rapidjson::PrettyWriter<OStreamBuffer>;

// A string as JSON carries it: valid UTF-8 (a byte that is not is U+FFFD,
// valid_utf8), escaped by the writer.
template <class Writer>
void put_string(Writer& w, std::string_view s) {
  if (is_valid_utf8(s)) {
    w.String(s.data(), static_cast<rapidjson::SizeType>(s.size()));
  } else {
    const std::string repaired = valid_utf8(s);
    w.String(repaired.data(), static_cast<rapidjson::SizeType>(repaired.size()));
  }
}

// A number; JSON has no NaN or infinity, which are written as null (as
// nlohmann writes them).
template <class Writer>
void put_number(Writer& w, double d) {
  if (std::isfinite(d)) w.Double(d);
  else w.Null();
}

// A value of the run document's nlohmann trees (its header, options,
// traffic), event by event.
template <class Writer, class Json>
void put_json(Writer& w, const Json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::object:
      w.StartObject();
      for (const auto& [key, value] : j.items()) {
        const std::string repaired = valid_utf8(key);
        w.Key(repaired.data(), static_cast<rapidjson::SizeType>(repaired.size()));
        put_json(w, value);
      }
      w.EndObject();
      return;
    case nlohmann::json::value_t::array:
      w.StartArray();
      for (const auto& value : j) put_json(w, value);
      w.EndArray();
      return;
    case nlohmann::json::value_t::string: put_string(w, j.template get_ref<const std::string&>()); return;
    case nlohmann::json::value_t::boolean: w.Bool(j.template get<bool>()); return;
    case nlohmann::json::value_t::number_integer: w.Int64(j.template get<std::int64_t>()); return;
    case nlohmann::json::value_t::number_unsigned: w.Uint64(j.template get<std::uint64_t>()); return;
    case nlohmann::json::value_t::number_float: put_number(w, j.template get<double>()); return;
    case nlohmann::json::value_t::null:
    case nlohmann::json::value_t::binary:     // the document holds none
    case nlohmann::json::value_t::discarded:  // nor this parser's marker
      w.Null();
      return;
  }
}

}  // namespace sabus::reports::json_out
