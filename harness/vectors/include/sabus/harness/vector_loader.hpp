// Reads vector files (vectors/*.yaml) and lints the suite. Every error names
// file:line:column, the vector id and the key: unknown keys, wrong types,
// duplicate keys (which yaml-cpp accepts silently), commands, forms and fields
// the codecs do not know, lengths that contradict the catalog.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/harness/expressions.hpp"
#include "sabus/harness/profile.hpp"
#include "sabus/harness/vector.hpp"

namespace YAML {
class Node;
}

namespace sabus::harness {

// How many entries one list of a file may hold (vectors/README.md: a whole
// file is read at a bounded cost); a longer list is an error at that list.
inline constexpr std::size_t kMaxGroups = 100;
inline constexpr std::size_t kMaxVectors = 500;  // in one `vectors` list
inline constexpr std::size_t kMaxSteps = 64;     // in one setup, steps or teardown list
inline constexpr std::size_t kMaxEntries = 64;   // fields, matchers, notes, requirements, flags, tags
inline constexpr std::size_t kMaxValues = 32;    // one_of, requirement values, modifier lists

// A file with any load error is left out of `files` (lint the rest): its
// errors come first, and a half-read file would make lint report flags and
// notes of the vectors that failed.
struct LoadResult {
  std::vector<VectorFile> files;
  std::vector<LoadError> errors;
  bool ok() const { return errors.empty(); }
};

LoadResult load_vector_text(const std::string& yaml, const std::string& name);
// The schema alone: a vector file already parsed into a YAML tree (what
// load_vector_text reads after its size check and the parser; fuzz targets
// build trees in code). Errors point at the marks the tree's nodes carry
// (line 0 for a node built in code).
LoadResult load_vector_tree(const YAML::Node& root, const std::string& name);
LoadResult load_vector_file(const std::string& path);
// Files, or directories searched recursively for *.yaml (except the folders
// profiles/, examples/ and regression/ below a directory given).
LoadResult load_vectors(const std::vector<std::string>& paths);

// Suite-wide checks beyond one file: unique ids, every flag defined in its
// file's notes, every referenced command, form and field known to the codecs.
// Every vector's spec.quote is checked against the spec text read from
// spec_text_path(); where it is absent, quotes are not checked (`sabus
// vectors lint` says so). The errata are read from the data directory
// (data_dir.hpp); lint throws DataDirNotFound when there is none.
std::vector<LoadError> lint(const std::vector<VectorFile>& files);
// The same with the spec text given (nullopt: quotes are not checked).
std::vector<LoadError> lint(const std::vector<VectorFile>& files, const std::optional<std::string>& spec_text);
// The spec text is the vendor's, not shipped: beside the repository
// (../shared/spec/) when the data directory is the source tree, spec/ in the
// data directory otherwise.
std::string spec_text_path();
std::optional<std::string> read_spec_text();

// vectors/ in the data directory (data_dir.hpp); throws DataDirNotFound
// when there is none.
std::string default_vectors_dir();

// The bytes of a raw template (RawBytes::hex) for a device at `address`, with
// captured values by name ("$track" -> its text). Errors: bad hex, an unknown
// placeholder, a capture not in `captures`, a byte above 7Fh.
Expected<Bytes> expand_raw_bytes(std::string_view hex, std::uint8_t address,
                                 const std::map<std::string, std::string>& captures = {});

// A raw template with its profile expressions ("{pad2(first_filled(presets))}")
// written as the hex of their text; {addr}, {lrc} and {$name} are left for
// expand_raw_bytes. For the runner, before it expands a raw send or an
// expected reply.
Expansion expand_raw_expressions(std::string_view hex, const ExprContext& cx);

// The command bytes a send or poll step puts on the wire before its
// modifiers: the structured command built by the codecs, or the raw template
// expanded. With `blank_missing_captures`, a capture not in `captures` is one
// blank (20h) instead of an error: for static analysis (coverage, seeds),
// where values captured at run time are not known.
Expected<Bytes> step_bytes(const Step& step, std::uint8_t address,
                           const std::map<std::string, std::string>& captures = {},
                           bool blank_missing_captures = false);

// Whether the linter asks `length_mismatch: true` of a raw send of these
// bytes: its last frame (last_frame_start) is a command frame whose length
// is not the catalog's request length. For tools that write vectors.
bool needs_length_mismatch(ByteView raw_send);

// Whether a device profile meets every requirement (each key's value is one
// of the requirement's values; values are compared as to_yaml writes them).
bool requirements_hold(const Profile& profile, const std::vector<Requirement>& requirements);
// Why the profile does not meet one requirement ("polarization is circular,
// needs single_port"), or nullopt when it does.
std::optional<std::string> unmet_requirement(const Profile& profile, const Requirement& r);

}  // namespace sabus::harness
