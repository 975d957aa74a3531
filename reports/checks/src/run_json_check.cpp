// The run JSON and its journal read back: nlohmann's parser (strict: one
// JSON text, UTF-8), the JSON Schema validator valijson with
// reports/run.schema.json (embedded at build time), and the consistency a
// schema cannot state.
// GCC 12 warns, falsely, of an overlapping memcpy in std::string::replace
// as valijson's json_pointer.hpp inlines it (-Wrestrict; GCC bug 105329).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "embedded_schemas.hpp"
#include "sabus/reports/checks.hpp"

namespace sabus::reports::checks {
namespace {

using nlohmann::json;

// JSON text parsed, or the parser's error (with where it is).
bool parse(std::string_view text, json& doc, Problems& problems, const std::string& what) {
  try {
    doc = json::parse(text);
    return true;
  } catch (const json::parse_error& e) {
    problems.push_back(what + ": not JSON: " + e.what());
    return false;
  }
}

// The schema of the run JSON, and of the two parts of a journal: the header
// members (a record's "run") and one vector. The last two are the file with
// its top level replaced by a reference to the definition, so every
// reference inside resolves as in the file.
class Schemas {
 public:
  static const Schemas& get() {
    static const Schemas schemas;
    return schemas;
  }
  const valijson::Schema& run() const { return run_; }
  const valijson::Schema& header() const { return header_; }
  const valijson::Schema& vector() const { return vector_; }

 private:
  Schemas() {
    const json source = json::parse(generated::kRunSchemaJson);
    load(source, run_);
    load(only(source, "#/definitions/header"), header_);
    load(only(source, "#/definitions/vector"), vector_);
  }
  static json only(json d, const char* ref) {
    d["allOf"] = json::array({{{"$ref", ref}}});
    return d;
  }
  static void load(const json& d, valijson::Schema& schema) {
    valijson::SchemaParser parser(valijson::SchemaParser::kDraft4);
    valijson::adapters::NlohmannJsonAdapter adapter(d);
    parser.populateSchema(adapter, schema);
  }
  valijson::Schema run_, header_, vector_;
};

// Where an error is, as a JSON pointer: valijson's context ("<root>",
// "[vectors]", "[0]", ...) joined.
std::string where(const std::vector<std::string>& context) {
  std::string out;
  for (const auto& c : context)
    if (c.size() >= 2 && c.front() == '[' && c.back() == ']') out += "/" + c.substr(1, c.size() - 2);
  return out.empty() ? "/" : out;
}

// The deepest place `value` breaks `schema`, with what it breaks there.
void validate(const json& value, const valijson::Schema& schema, Problems& problems, const std::string& what) {
  valijson::Validator validator;
  valijson::ValidationResults results;
  if (validator.validate(schema, valijson::adapters::NlohmannJsonAdapter(value), &results)) return;
  valijson::ValidationResults::Error e;
  if (!results.popError(e)) {
    problems.push_back(what + ": not valid against reports/run.schema.json");
    return;
  }
  problems.push_back(what + ": at " + where(e.context) + ": " + e.description + " (reports/run.schema.json)");
}

// Two lowercase hex digits a byte, one space between (the schema's "hex").
bool hex_text(std::string_view hex) {
  const auto digit = [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); };
  if (hex.empty()) return true;
  if ((hex.size() + 1) % 3 != 0) return false;
  for (std::size_t i = 0; i < hex.size(); ++i)
    if (i % 3 == 2 ? hex[i] != ' ' : !digit(hex[i])) return false;
  return true;
}

// A "line" object's counts, as the schema let them through.
harness::LineFaultCounts line_counts(const json& line) {
  return {line["exchanges"].get<std::size_t>(), line["faults"].get<std::size_t>(), line["recovered"].get<std::size_t>(),
          line["repeats"].get<std::size_t>(), line.value("surveyed", std::size_t{0})};
}

// Line counts that cannot be what a run counted (line_counts_problem, the
// readers' own rule).
void check_line(const json& line, Problems& problems, const std::string& what) {
  if (const std::string why = line_counts_problem(line_counts(line)); !why.empty())
    problems.push_back(what + ": line: " + why);
}

// What the schema cannot say of one vector: each frame's hex is bytes, each
// field's bytes lie within its frame, in order, and its line counts are
// possible.
void check_vector(const json& v, Problems& problems, const std::string& what) {
  check_line(v["line"], problems, what + ": at /line");
  const auto& transcript = v["transcript"];
  for (std::size_t i = 0; i < transcript.size(); ++i) {
    const auto& frame = transcript[i];
    const std::string& hex = frame["hex"].get_ref<const std::string&>();
    if (!hex_text(hex)) {
      problems.push_back(what + ": at /transcript/" + std::to_string(i) + "/hex: not bytes as hex: \"" + hex.substr(0, 40) + "\"");
      continue;
    }
    const std::size_t bytes = hex.empty() ? 0 : (hex.size() + 1) / 3;
    const auto& fields = frame["fields"];
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const auto first = fields[k]["first"].get<std::uint64_t>(), last = fields[k]["last"].get<std::uint64_t>();
      if (first > last || last >= bytes)
        problems.push_back(what + ": transcript[" + std::to_string(i) + "] field " + std::to_string(k) + " (" +
                           fields[k]["name"].get<std::string>() + ") is bytes " + std::to_string(first) + "-" +
                           std::to_string(last) + " of a frame of " + std::to_string(bytes));
    }
  }
}

// The summary of an ended run against its vectors, and vector ids unique.
void check_run(const json& run, const std::vector<const json*>& vectors, Problems& problems, const std::string& what) {
  if (!hex_text(run["identity"]["reply_hex"].get_ref<const std::string&>()))
    problems.push_back(what + ": at /identity/reply_hex: not bytes as hex");
  std::set<std::string> ids;
  std::map<std::string, std::uint64_t> outcomes, causes;
  harness::LineFaultCounts line;  // the vectors' together
  for (const auto* v : vectors) {
    line += line_counts((*v)["line"]);
    const std::string& id = (*v)["id"].get_ref<const std::string&>();
    if (!ids.insert(id).second) problems.push_back(what + ": vector id \"" + id + "\" twice");
    const std::string& outcome = (*v)["outcome"].get_ref<const std::string&>();
    ++outcomes[outcome];
    if (outcome == "skip") ++causes[(*v)["skip_cause"].get<std::string>()];
  }
  if (!run.contains("summary")) return;
  const auto& s = run["summary"];
  const std::pair<const char*, const char*> counts[] = {
      {"passed", "pass"},         {"failed", "fail"},
      {"skipped", "skip"},        {"known", "known failure"},
      {"unexpected", "unexpected pass"}, {"inconclusive", "inconclusive"},
      {"errors", "error"}};
  for (const auto& [key, outcome] : counts)
    if (s[key].get<std::uint64_t>() != outcomes[outcome])
      problems.push_back(what + ": summary." + key + " is " + s[key].dump() + ", the vectors have " +
                         std::to_string(outcomes[outcome]) + " " + outcome);
  // The run's line counts are the vectors' and those of the exchanges of no
  // vector (liveness probes, the stored-data backup): at least the vectors'.
  check_line(s["line"], problems, what + ": summary");
  const harness::LineFaultCounts run_line = line_counts(s["line"]);
  const std::pair<const char*, std::size_t harness::LineFaultCounts::*> figures[] = {
      {"exchanges", &harness::LineFaultCounts::exchanges},
      {"faults", &harness::LineFaultCounts::faults},
      {"recovered", &harness::LineFaultCounts::recovered},
      {"repeats", &harness::LineFaultCounts::repeats},
      {"surveyed", &harness::LineFaultCounts::surveyed}};
  for (const auto& [key, figure] : figures)
    if (run_line.*figure < line.*figure)
      problems.push_back(what + ": summary.line." + key + " is " + std::to_string(run_line.*figure) + ", less than the vectors' " +
                         std::to_string(line.*figure));
  // A run with a vector in error and no failure exits 6; one without any
  // never does.
  const int exit_code = s["exit_code"].get<int>();
  if (exit_code == harness::kLineErrorExitCode && outcomes["error"] == 0)
    problems.push_back(what + ": summary.exit_code is 6 (some vector in error), but no vector ended in error");
  for (const auto& [cause, n] : s["skipped_by_cause"].items())
    if (n.get<std::uint64_t>() != causes[cause])
      problems.push_back(what + ": summary.skipped_by_cause." + cause + " is " + n.dump() + ", the vectors have " +
                         std::to_string(causes[cause]));
}

}  // namespace

Problems run_json_problems(std::string_view text) {
  Problems problems;
  json doc;
  if (!parse(text, doc, problems, "run JSON")) return problems;
  validate(doc, Schemas::get().run(), problems, "run JSON");
  if (!problems.empty()) return problems;
  std::vector<const json*> vectors;
  const auto& list = doc["vectors"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    vectors.push_back(&list[i]);
    check_vector(list[i], problems, "run JSON: vectors[" + std::to_string(i) + "] (" + list[i]["id"].get<std::string>() + ")");
  }
  check_run(doc, vectors, problems, "run JSON");
  return problems;
}

Problems journal_problems(std::string_view text) {
  Problems problems;
  if (text.empty()) return {"journal: empty"};
  if (text.back() != '\n') problems.push_back("journal: the last line has no newline (cut short)");
  std::vector<json> lines;
  std::size_t start = 0;
  for (std::size_t line_no = 1; start < text.size(); ++line_no) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    json& d = lines.emplace_back();
    if (!parse(text.substr(start, end - start), d, problems, "journal line " + std::to_string(line_no))) return problems;
    start = end + 1;
  }
  const Schemas& schemas = Schemas::get();
  std::vector<const json*> vectors;
  const json* end_run = nullptr;
  const json* backup_file = nullptr;  // the backup record's
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string what = "journal line " + std::to_string(i + 1);
    const json& d = lines[i];
    const bool record = d.is_object() && d.contains("record");
    const bool first = i == 0, last = i + 1 == lines.size();
    if (!record) {
      if (first) {
        problems.push_back(what + ": the first line is not a header record");
        continue;
      }
      validate(d, schemas.vector(), problems, what);
      if (problems.empty()) {
        check_vector(d, problems, what);
        vectors.push_back(&d);
      }
      continue;
    }
    const auto& type = d["record"];
    const std::string kind = type.is_string() ? type.get<std::string>() : "";
    if (kind == "backup") {
      // Between the header and the end, once: the run takes one backup.
      const bool named = d.size() == 2 && d.contains("file") && d["file"].is_string() && !d["file"].get<std::string>().empty();
      if (first || end_run || !named || backup_file)
        problems.push_back(what + ": a backup record that is not {\"record\": \"backup\", \"file\": FILE} once, after the "
                                  "header and before the end");
      else backup_file = &d["file"];
      continue;
    }
    const bool placed = (kind == "header" && first) || (kind == "end" && last && !first);
    if (!placed || d.size() != 2 || !d.contains("run")) {
      problems.push_back(what + ": a record that is not {\"record\": \"header\"} first or {\"record\": \"end\"} last, each with its \"run\"");
      continue;
    }
    validate(d["run"], schemas.header(), problems, what + " (" + kind + " record)");
    if (kind == "end") end_run = &d["run"];
    else if (d["run"].contains("summary")) problems.push_back(what + ": the header record has a summary");
  }
  if (problems.empty() && end_run && backup_file && end_run->value("backup", "") != backup_file->get<std::string>())
    problems.push_back("journal end record: backup " + end_run->value("backup", std::string("absent")) +
                       ", not the backup record's " + backup_file->get<std::string>());
  if (problems.empty() && end_run) check_run(*end_run, vectors, problems, "journal end record");
  return problems;
}

}  // namespace sabus::reports::checks
