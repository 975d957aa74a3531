// The JSON the commands print (`--json` of decode, vectors list, vectors
// coverage and ports): one serializer for all of them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace sabus::cli {

// Indented two spaces, with a final newline. Text that is not UTF-8 (a file
// name is any bytes but / and NUL: `sabus vectors list DIR --json` prints the
// files' paths) has each byte that is not replaced by U+FFFD: json's dump()
// throws type_error 316 on it, which ended the command in std::terminate.
inline std::string json_text(const nlohmann::json& doc) {
  return doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace sabus::cli
