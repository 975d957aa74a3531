// What the shipped suite holds, read from its files, for tests of the CLI
// whose expected counts move as vectors are added.
#pragma once

#include <cstddef>
#include <fstream>
#include <regex>
#include <string>

namespace sabus::test {

// The vectors of vectors/FILE (under `source_dir`) whose id starts with
// `id_prefix` ("3.2-"), counted from their `- id:` lines: what a selection
// of their paragraph takes.
inline std::size_t shipped_vectors_in(const std::string& source_dir, const std::string& file, const std::string& id_prefix) {
  std::ifstream in(source_dir + "/vectors/" + file);
  const std::regex id("^\\s*- id: " + std::regex_replace(id_prefix, std::regex(R"([.])"), R"(\.)"));
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);)
    if (std::regex_search(line, id)) ++n;
  return n;
}

}  // namespace sabus::test
