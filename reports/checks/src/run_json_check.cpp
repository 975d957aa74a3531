// The run JSON and its journal read back: RapidJSON's parser (strict UTF-8),
// the JSON Schema validator valijson with reports/run.schema.json (embedded
// at build time), and the consistency a schema cannot state.
#include "sabus/reports/rapidjson_config.hpp"  // before RapidJSON's headers

#include <rapidjson/document.h>
#include <rapidjson/error/en.h>
#include <valijson/adapters/rapidjson_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

#include <map>
#include <set>
#include <string>

#include "embedded_schemas.hpp"
#include "sabus/reports/checks.hpp"

namespace sabus::reports::checks {
namespace {

// JSON text parsed, or the parser's error with its offset.
bool parse(std::string_view text, rapidjson::Document& doc, Problems& problems, const std::string& what) {
  doc.Parse<rapidjson::kParseFullPrecisionFlag | rapidjson::kParseValidateEncodingFlag>(text.data(), text.size());
  if (!doc.HasParseError()) return true;
  problems.push_back(what + ": not JSON at offset " + std::to_string(doc.GetErrorOffset()) + ": " +
                     rapidjson::GetParseError_En(doc.GetParseError()));
  return false;
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
    rapidjson::Document source;
    source.Parse(generated::kRunSchemaJson);
    if (source.HasParseError()) throw std::logic_error("reports/run.schema.json is not JSON");
    load(source, run_);
    load(only(source, "#/definitions/header"), header_);
    load(only(source, "#/definitions/vector"), vector_);
  }
  static rapidjson::Document only(const rapidjson::Document& source, const char* ref) {
    rapidjson::Document d;
    d.CopyFrom(source, d.GetAllocator());
    d.RemoveMember("allOf");
    rapidjson::Value target(rapidjson::kObjectType);
    target.AddMember("$ref", rapidjson::StringRef(ref), d.GetAllocator());
    rapidjson::Value all(rapidjson::kArrayType);
    all.PushBack(target, d.GetAllocator());
    d.AddMember("allOf", all, d.GetAllocator());
    return d;
  }
  static void load(const rapidjson::Document& d, valijson::Schema& schema) {
    valijson::SchemaParser parser(valijson::SchemaParser::kDraft4);
    valijson::adapters::RapidJsonAdapter adapter(d);
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
void validate(const rapidjson::Value& value, const valijson::Schema& schema, Problems& problems, const std::string& what) {
  valijson::Validator validator;
  valijson::ValidationResults results;
  if (validator.validate(schema, valijson::adapters::RapidJsonAdapter(value), &results)) return;
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

std::size_t hex_bytes(const rapidjson::Value& frame) {
  const auto& hex = frame["hex"];
  const std::size_t n = hex.GetStringLength();
  return n == 0 ? 0 : (n + 1) / 3;
}

// What the schema cannot say of one vector: each field's bytes lie within
// its frame, in order.
void check_vector(const rapidjson::Value& v, Problems& problems, const std::string& what) {
  const auto& transcript = v["transcript"];
  for (rapidjson::SizeType i = 0; i < transcript.Size(); ++i) {
    const auto& frame = transcript[i];
    if (!hex_text({frame["hex"].GetString(), frame["hex"].GetStringLength()})) {
      problems.push_back(what + ": at /transcript/" + std::to_string(i) + "/hex: not bytes as hex: \"" +
                         std::string(frame["hex"].GetString()).substr(0, 40) + "\"");
      continue;
    }
    const std::size_t bytes = hex_bytes(frame);
    const auto& fields = frame["fields"];
    for (rapidjson::SizeType k = 0; k < fields.Size(); ++k) {
      const auto first = fields[k]["first"].GetUint64(), last = fields[k]["last"].GetUint64();
      if (first > last || last >= bytes)
        problems.push_back(what + ": transcript[" + std::to_string(i) + "] field " + std::to_string(k) + " (" +
                           fields[k]["name"].GetString() + ") is bytes " + std::to_string(first) + "-" + std::to_string(last) +
                           " of a frame of " + std::to_string(bytes));
    }
  }
}

// The summary of an ended run against its vectors, and vector ids unique.
void check_run(const rapidjson::Value& run, const std::vector<const rapidjson::Value*>& vectors, Problems& problems,
               const std::string& what) {
  const auto& reply = run["identity"]["reply_hex"];
  if (!hex_text({reply.GetString(), reply.GetStringLength()}))
    problems.push_back(what + ": at /identity/reply_hex: not bytes as hex");
  std::set<std::string> ids;
  std::map<std::string, std::uint64_t> outcomes, causes;
  for (const auto* v : vectors) {
    const std::string id = (*v)["id"].GetString();
    if (!ids.insert(id).second) problems.push_back(what + ": vector id \"" + id + "\" twice");
    ++outcomes[(*v)["outcome"].GetString()];
    if (std::string_view((*v)["outcome"].GetString()) == "skip") ++causes[(*v)["skip_cause"].GetString()];
  }
  if (!run.HasMember("summary")) return;
  const auto& s = run["summary"];
  const std::pair<const char*, const char*> counts[] = {
      {"passed", "pass"}, {"failed", "fail"}, {"skipped", "skip"}, {"known", "known failure"}, {"unexpected", "unexpected pass"}};
  for (const auto& [key, outcome] : counts)
    if (s[key].GetUint64() != outcomes[outcome])
      problems.push_back(what + ": summary." + key + " is " + std::to_string(s[key].GetUint64()) + ", the vectors have " +
                         std::to_string(outcomes[outcome]) + " " + outcome);
  for (auto it = s["skipped_by_cause"].MemberBegin(); it != s["skipped_by_cause"].MemberEnd(); ++it)
    if (it->value.GetUint64() != causes[it->name.GetString()])
      problems.push_back(what + ": summary.skipped_by_cause." + it->name.GetString() + " is " +
                         std::to_string(it->value.GetUint64()) + ", the vectors have " +
                         std::to_string(causes[it->name.GetString()]));
}

}  // namespace

Problems run_json_problems(std::string_view text) {
  Problems problems;
  rapidjson::Document doc;
  if (!parse(text, doc, problems, "run JSON")) return problems;
  validate(doc, Schemas::get().run(), problems, "run JSON");
  if (!problems.empty()) return problems;
  std::vector<const rapidjson::Value*> vectors;
  const auto& list = doc["vectors"];
  for (rapidjson::SizeType i = 0; i < list.Size(); ++i) {
    vectors.push_back(&list[i]);
    check_vector(list[i], problems, "run JSON: vectors[" + std::to_string(i) + "] (" + list[i]["id"].GetString() + ")");
  }
  check_run(doc, vectors, problems, "run JSON");
  return problems;
}

Problems journal_problems(std::string_view text) {
  Problems problems;
  if (text.empty()) return {"journal: empty"};
  if (text.back() != '\n') problems.push_back("journal: the last line has no newline (cut short)");
  std::vector<rapidjson::Document> lines;
  std::size_t start = 0;
  for (std::size_t line_no = 1; start < text.size(); ++line_no) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string what = "journal line " + std::to_string(line_no);
    rapidjson::Document& d = lines.emplace_back();
    if (!parse(text.substr(start, end - start), d, problems, what)) return problems;
    start = end + 1;
  }
  const Schemas& schemas = Schemas::get();
  std::vector<const rapidjson::Value*> vectors;
  const rapidjson::Value* end_run = nullptr;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string what = "journal line " + std::to_string(i + 1);
    const rapidjson::Document& d = lines[i];
    const bool record = d.IsObject() && d.HasMember("record");
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
    const std::string kind = type.IsString() ? type.GetString() : "";
    const bool placed = (kind == "header" && first) || (kind == "end" && last && !first);
    if (!placed || d.MemberCount() != 2 || !d.HasMember("run")) {
      problems.push_back(what + ": a record that is not {\"record\": \"header\"} first or {\"record\": \"end\"} last, each with its \"run\"");
      continue;
    }
    validate(d["run"], schemas.header(), problems, what + " (" + kind + " record)");
    if (kind == "end") end_run = &d["run"];
    else if (d["run"].HasMember("summary")) problems.push_back(what + ": the header record has a summary");
  }
  if (problems.empty() && end_run) check_run(*end_run, vectors, problems, "journal end record");
  return problems;
}

}  // namespace sabus::reports::checks
