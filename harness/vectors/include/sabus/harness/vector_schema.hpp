// The keys of a vector file (vectors/*.yaml), node by node: the one table
// the loader takes its accepted keys from (MapReader) and that
// `sabus vectors schema` prints for docs/reference/vector-schema.md, so that
// the loader and the reference page cannot disagree. What each value may
// hold, with examples, is vectors/README.md's.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace sabus::harness {

// A map of the format whose keys are fixed. Maps whose keys are data (a
// file's `notes`, `requires`, `fields`, `readings`) are not nodes: their
// keys are flag names, profile key paths, field names, ERRATA ids.
enum class SchemaNode {
  kFile,
  kNote,
  kGroup,
  kVector,
  kSpec,
  kStep,
  kWait,
  kSend,
  kModify,
  kPoll,
  kSurvey,
  kExpect,
  kReading,  // an alternative under `readings:`: an expectation's keys but `readings`
  kMatcher,
  kNear,
  kJogged,
};

struct SchemaKey {
  std::string_view key;
  // "yes", "" (optional), or when it is needed ("unless the group gives it").
  std::string_view required;
  std::string_view meaning;  // one line
};

struct SchemaNodeInfo {
  SchemaNode node;
  std::string_view name;   // "A vector", "`spec`"
  std::string_view where;  // where it appears in a file
  std::span<const SchemaKey> keys;
};

// Every node, in the order a file nests them.
std::span<const SchemaNodeInfo> vector_schema();
const SchemaNodeInfo& schema_node(SchemaNode node);

// The keys a node accepts, in the table's order: the `allowed` of its
// MapReader, and so the order an unknown-key error lists them in.
std::span<const std::string_view> schema_keys(SchemaNode node);

// The table as Markdown: one section a node, one row a key.
std::string schema_markdown();

}  // namespace sabus::harness
