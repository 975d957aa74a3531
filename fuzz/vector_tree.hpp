// YAML trees of vector files without a YAML parser, for the schema target
// (fuzz_vector_schema.cpp) and its seeds (seed_generator.cpp).
//
// Tree text is a small flow notation that reads straight into a YAML::Node
// tree, so a fuzz input costs no YAML parsing (yaml-cpp's scanner took most of
// fuzz_vector_loader's time):
//   {key: value, ...}   a map; keys are nodes too, and may repeat (the loader
//                       must find duplicate keys itself, as yaml-cpp keeps them)
//   [a, b, ...]         a list
//   "text"              a quoted scalar (Tag "!", as yaml-cpp tags quoted
//                       scalars): \" \\ \n \t \xNN escapes
//   'text'              a plain scalar with any characters ('' is one quote):
//                       plain as YAML reads `any`, `true` or 12
//   word                a plain scalar: any run of characters other than
//                       blanks and {}[],:"'
//   ~                   null (YAML's empty value)
//   *N                  the N-th map or list completed so far, shared (a YAML
//                       alias: the loader's work budget must hold)
// Any byte string reads as some tree: a stray character is skipped, an open
// map, list or string ends at the end of the input, a value left out is null,
// and nesting deeper than kMaxTreeDepth reads as null. Trees carry no marks:
// the loader's errors on them have line 0.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>

#include "sabus/harness/vector.hpp"

namespace sabus::fuzz {

inline constexpr std::size_t kMaxTreeDepth = 24;

// The tree of a tree text.
YAML::Node parse_tree(std::string_view text);

// The tree text of a tree (shared nodes written out each time): parse_tree
// reads it back to an equal tree.
std::string tree_text(const YAML::Node& node);

// One loaded vector written back as the tree text of a file that holds it
// alone (with the file's paragraph, title and notes): every list of the
// vector as the loader read it, with its file's and group's parts, so the
// file's and a group's keys hold what exceeds the vector's own list bounds.
// Loading this tree gives the same vector again (fuzz_vector_schema checks
// it).
std::string vector_file_text(const harness::VectorFile& file, const harness::Vector& vector);

}  // namespace sabus::fuzz
