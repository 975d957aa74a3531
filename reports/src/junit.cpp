// JUnit XML (reports/junit.xsd, the format Jenkins and GitLab read): one
// testsuite per spec paragraph, one testcase per vector. Times are the wall
// clock's; the transport clock's (virtual in-process) is a property. Every
// testsuite carries the run's properties: suite version, firmware, profile,
// seed. A failure carries the decoded difference and the hex transcript; a
// skipped vector its reason (a known failure is reported as skipped, with the
// known issue). What stopped the bench is an error, not a failure: a run that
// did not reach its end has a testsuite "run" whose one testcase holds an
// error naming why (SIGINT, SIGTERM, a lost device, killed), the vector
// during which the device was lost holds an error too, and so does a vector
// the line left unjudged (TTCN-3 error: the test system failed, which is
// what JUnit's <error> says), with what the line did and its line counts.
#include <fmt/format.h>

#include <cctype>
#include <map>
#include <optional>

#include "sabus/reports/writers.hpp"

namespace sabus::reports {

namespace {

std::string transcript_text(const VectorRecord& v) {
  std::string text;
  for (const auto& f : v.transcript)
    text += fmt::format("{:10.3f} ms {} {}{}{}\n", f.t_ms, f.dir, f.hex, f.hex.empty() ? "" : "  ", f.note);
  return text;
}

std::string property(std::string_view name, std::string_view value, std::string_view indent) {
  return fmt::format("{}<property name=\"{}\" value=\"{}\"/>\n", indent, xml_escape(name), xml_escape(value));
}

std::string seconds(double ms) { return fmt::format("{:.3f}", ms / 1000.0); }

// Jenkins splits a classname at its last dot into package and class: one
// package "sabus", one class per paragraph and level ("sabus.section_3_2_must").
std::string classname(const VectorRecord& v) {
  std::string paragraph = v.paragraph;
  for (char& c : paragraph)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return "sabus.section_" + paragraph + "_" + v.level;
}

// What every testsuite of the run shares: the suite version, the device
// under test, the selection.
std::string run_properties(const RunDocument& doc) {
  constexpr std::string_view in = "      ";
  std::string out = property("suite_version", doc.generator, in);
  out += property("firmware", doc.identity.ok ? doc.identity.firmware_version : "unknown: " + doc.identity.error, in);
  if (doc.identity.ok) out += property("controller_type", doc.identity.controller_type, in);
  out += property("profile", doc.profile, in);
  const auto seed = doc.options.find("seed");
  out += property("seed", seed == doc.options.end() ? "" : json_value_text(*seed), in);
  out += property("device", doc.device, in);
  std::string faults;
  for (const auto& f : doc.faults) faults += (faults.empty() ? "" : ",") + f;
  if (!faults.empty()) out += property("faults", faults, in);
  out += property("options", json_value_text(doc.options), in);
  out += property("started_at", doc.started_at, in);
  out += property("status", doc.status + (doc.abort_reason.empty() ? "" : ": " + doc.abort_reason), in);
  out += property("schema", std::string(kSchemaName) + " " + std::to_string(doc.schema_version), in);
  // What the line did to the run, when its exchanges were counted.
  if (const auto line = doc.counts().line; line.exchanges > 0) out += property("line", harness::describe(line), in);
  return out;
}

// Times are wall-clock seconds; a document without them (schema 1 or 2)
// gives none rather than the transport clock's, which is virtual in-process.
std::string time_attribute(std::optional<double> wall_ms) {
  return wall_ms ? " time=\"" + seconds(*wall_ms) + "\"" : "";
}

std::optional<double> wall_sum(const std::vector<const VectorRecord*>& vectors) {
  std::optional<double> sum;
  for (const auto* v : vectors)
    if (v->wall_ms) sum = sum.value_or(0) + *v->wall_ms;
  return sum;
}

// The type of the error of an unfinished run: "stopped" by the bench (exit
// code 4), "aborted" otherwise (the device stopped answering, no backup), or
// "killed" (no end record).
std::string_view unfinished_type(const RunDocument& doc) {
  return doc.stopped() ? "stopped" : doc.status == "aborted" ? "aborted" : "killed";
}

// The testsuite of the run itself, for a run that did not reach its end.
std::string unfinished_run_suite(const RunDocument& doc, const std::string& shared) {
  std::string out = fmt::format(
      "  <testsuite name=\"{}\" tests=\"1\" failures=\"0\" errors=\"1\" skipped=\"0\" timestamp=\"{}\" package=\"sabus\">\n",
      kJunitRunSuite, xml_escape(doc.started_at));
  out += "    <properties>\n" + shared + "    </properties>\n";
  out += fmt::format("    <testcase name=\"{}\" classname=\"{}\">\n", kJunitRunTestcase, kJunitRunClassname);
  out += fmt::format("      <error message=\"{}\" type=\"{}\">{} of {} planned vectors finished</error>\n",
                     xml_escape(doc.unfinished_reason()), unfinished_type(doc), doc.vectors.size(), doc.planned);
  return out + "    </testcase>\n  </testsuite>\n";
}

}  // namespace

std::string junit_xml(const RunDocument& doc) {
  std::map<std::string, std::vector<const VectorRecord*>> by_paragraph;
  std::vector<const VectorRecord*> all;
  for (const auto& v : doc.vectors) {
    by_paragraph[v.paragraph].push_back(&v);
    all.push_back(&v);
  }
  const bool unfinished = doc.status != "complete";
  const std::string shared = run_properties(doc);
  std::size_t all_failures = 0, all_errors = unfinished;
  for (const auto* v : all) {
    all_errors += v->lost_device() || v->is_error();
    all_failures += v->is_failure() && !v->lost_device();
  }
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += fmt::format("<testsuites name=\"sabus\" tests=\"{}\" failures=\"{}\" errors=\"{}\"{}>\n",
                     doc.vectors.size() + unfinished, all_failures, all_errors, time_attribute(wall_sum(all)));
  for (const auto& [paragraph, vectors] : by_paragraph) {
    std::size_t failures = 0, errors = 0, skipped = 0;
    double transport_ms = 0;
    for (const auto* v : vectors) {
      errors += v->lost_device() || v->is_error();
      failures += v->is_failure() && !v->lost_device();
      skipped += v->is_skip() || v->is_inconclusive();
      transport_ms += v->duration_ms;
    }
    out += fmt::format(
        "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\"{} "
        "timestamp=\"{}\" package=\"sabus\">\n",
        xml_escape("§" + paragraph), vectors.size(), failures, errors, skipped, time_attribute(wall_sum(vectors)),
        xml_escape(doc.started_at));
    out += "    <properties>\n" + shared + property("transport_time", seconds(transport_ms), "      ") + "    </properties>\n";
    for (const auto* v : vectors) {
      out += fmt::format("    <testcase name=\"{}\" classname=\"{}\"{}>\n", xml_escape(v->id), xml_escape(classname(*v)),
                         time_attribute(v->wall_ms));
      // The transport clock (virtual in-process), beside the wall-clock time.
      out += "      <properties>\n" + property("level", v->level, "        ") +
             property("transport_time", seconds(v->duration_ms), "        ") + "      </properties>\n";
      if (v->lost_device()) {
        std::string text;
        for (const auto& f : v->failures) text += f + "\n";
        out += fmt::format("      <error message=\"{}\" type=\"lost device\">{}</error>\n", xml_escape(v->difference()),
                           xml_escape(text + "\n" + transcript_text(*v)));
      } else if (v->is_failure()) {
        std::string text;
        for (const auto& f : v->failures) text += f + "\n";
        if (v->outcome == "unexpected pass") text += "unexpected pass: listed as a known issue: " + v->known_issue + "\n";
        text += "\n";
        text += transcript_text(*v);
        out += fmt::format("      <failure message=\"{}\" type=\"{}\">{}</failure>\n", xml_escape(v->difference()),
                           xml_escape(v->outcome), xml_escape(text));
      } else if (v->is_error()) {
        // The message is the reason alone: the element says it is an error.
        out += fmt::format("      <error message=\"{}\" type=\"line error\">{}</error>\n", xml_escape(v->error_reason),
                           xml_escape(v->error_reason + "\n" + harness::describe(v->line) + "\n\n" + transcript_text(*v)));
      } else if (v->is_inconclusive()) {
        // JUnit has no inconclusive: a skip is the verdict a CI reads as
        // "checked nothing", which is what it is (TTCN-3 inconc).
        out += fmt::format("      <skipped message=\"{}\"/>\n", xml_escape(v->difference()));
      } else if (v->is_skip()) {
        // Built with append: g++ 12 -O3 warns (-Wrestrict, a false positive) on literal + string here.
        std::string why = v->outcome == "skip" ? std::string() : std::string("known issue: ");
        why.append(v->outcome == "skip" ? v->skip_reason : v->known_issue);
        out += fmt::format("      <skipped message=\"{}\"/>\n", xml_escape(why));
      }
      out += "    </testcase>\n";
    }
    out += "  </testsuite>\n";
  }
  if (unfinished) out += unfinished_run_suite(doc, shared);
  out += "</testsuites>\n";
  return out;
}

}  // namespace sabus::reports
