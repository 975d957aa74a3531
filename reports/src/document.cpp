// The run document: building it from runner results, and its JSON form
// (reports/SCHEMA.md).
#include "sabus/reports/document.hpp"

#include <algorithm>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>
#include <type_traits>
#include <utility>

#include "sabus/protocol/catalog.hpp"
#include "sabus/reports/writers.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/frame.hpp"

namespace sabus::reports {

using nlohmann::json;
using nlohmann::ordered_json;

std::string VectorRecord::difference() const {
  if (!failures.empty()) return failures.front();
  if (outcome == "unexpected pass") return "passed but is listed as a known issue (" + known_issue + ")";
  if (is_inconclusive()) return "inconclusive: " + inconclusive_reason;
  if (is_error()) return "error: " + error_reason;
  return "";
}

std::string line_counts_problem(const harness::LineFaultCounts& c) {
  if (c.faults > c.exchanges)
    return std::to_string(c.faults) + " faults in " + std::to_string(c.exchanges) + " exchanges: a fault is an exchange";
  if (c.recovered > c.faults)
    return std::to_string(c.recovered) + " recovered of " + std::to_string(c.faults) + " faults: a recovered fault is a fault";
  if (c.repeats > c.exchanges)
    return std::to_string(c.repeats) + " repeats in " + std::to_string(c.exchanges) + " exchanges: a repeat is an exchange";
  if (c.faults + c.surveyed > c.exchanges)
    return std::to_string(c.faults) + " faults and " + std::to_string(c.surveyed) + " surveyed in " + std::to_string(c.exchanges) +
           " exchanges: each is an exchange";
  return "";
}

double line_fault_rate(const harness::LineFaultCounts& c) {
  // Every garbled reply seen, the survey's too: the line's rate, not the recoveries'.
  return c.exchanges == 0 ? 0.0 : static_cast<double>(c.faults + c.surveyed) / static_cast<double>(c.exchanges);
}

Summary RunDocument::counts() const {
  Summary s;
  for (const auto& v : vectors) {
    if (v.outcome == "pass") ++s.passed;
    else if (v.outcome == "fail") ++s.failed;
    else if (v.outcome == "skip") {
      ++s.skipped;
      ++s.skipped_by_cause[v.skip_cause];
    }
    else if (v.outcome == "known failure") ++s.known;
    else if (v.outcome == "unexpected pass") ++s.unexpected;
    else if (v.is_inconclusive()) ++s.inconclusive;
    else if (v.is_error()) ++s.errors;
    if (!summary) s.line += v.line;
  }
  s.exit_code = summary ? summary->exit_code : 1;
  if (summary) s.line = summary->line;
  return s;
}

bool VectorRecord::lost_device() const {
  return outcome == "fail" && std::any_of(failures.begin(), failures.end(), [](const std::string& f) {
           return std::string_view(f).substr(0, harness::kDeviceLostFailure.size()) == harness::kDeviceLostFailure;
         });
}

bool RunDocument::stopped() const {
  return status == "aborted" && summary && summary->exit_code == harness::kStoppedExitCode;
}

std::string RunDocument::unfinished_reason() const {
  if (status == "complete") return "";
  if (status == "aborted") return abort_reason.empty() ? "aborted" : abort_reason;
  return "the run has no end record: it was killed, or it is still running";
}

std::string RunDocument::verdict() const {
  if (stopped()) return "STOPPED";
  if (status == "aborted") return "ABORTED";
  if (status != "complete") return "INCOMPLETE";
  if (!summary) return "FAIL";
  switch (summary->exit_code) {
    case 0: return "PASS";
    case harness::kNothingRanExitCode: return "NOTHING RAN";
    case harness::kLineErrorExitCode: return "ERROR";
    default: return "FAIL";
  }
}

namespace {

std::string reply_path(const FrameRecord& rx) {
  if (rx.hex.empty()) return "";
  const auto bytes = parse_hex(rx.hex);
  if (!bytes || bytes->empty()) return "";
  auto decoded = decode_frame(*bytes);
  if (decoded && is_offline_reply(decoded.value())) return "offline";
  return (*bytes)[0] == NAK ? "nak" : (*bytes)[0] == ACK ? "ack" : "";
}

}  // namespace

FrameRecord frame_record(const harness::TranscriptEntry& e) {
  FrameRecord f;
  f.t_ms = e.t_ms;
  f.dir = e.sent ? "tx" : "rx";
  f.hex = to_hex(e.bytes);
  f.note = e.note;
  f.expect = e.expect;
  if (!e.bytes.empty()) {
    // The runner's description of the frame, made when it was sent or
    // received; described here only for an entry that came without it.
    const std::vector<FieldDescription> described = e.fields.empty() ? describe_frame(e.bytes).fields
                                                                      : std::vector<FieldDescription>{};
    const std::vector<FieldDescription>& fields = e.fields.empty() ? described : e.fields;
    f.fields.reserve(fields.size());
    for (const auto& fd : fields) f.fields.push_back({fd.first, fd.last, fd.name, fd.raw, fd.meaning, fd.ok});
    if (e.sent) {
      // The command frame the device answers, and its form (one classifier
      // for reports and `sabus vectors coverage`).
      const CommandForm c = classify_command(e.bytes);
      if (c.info) f.command = std::string(c.info->key);
      if (c.form) f.form = std::string(c.form->id);
    } else if (e.bytes.size() >= 3) {
      // A reply: ACK/NAK, address, the command it answers.
      if (const CommandInfo* info = find_command(e.bytes[2])) f.command = std::string(info->key);
    }
  }
  return f;
}

void assign_paths(std::vector<FrameRecord>& t) {
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i].dir != "tx" || t[i].expect.empty()) continue;
    if (t[i].expect == "silence") {
      t[i].path = "ignore";
    } else if (t[i].expect != "any" && t[i].expect != "answered") {
      t[i].path = t[i].expect;
    } else {
      std::string seen;
      for (std::size_t j = i + 1; j < t.size() && t[j].dir == "rx" && seen.empty(); ++j) seen = reply_path(t[j]);
      t[i].path = seen.empty() ? "ignore" : seen;
    }
  }
}

VectorRecord vector_record(const harness::VectorResult& r) {
  VectorRecord v;
  v.id = r.id;
  v.paragraph = r.paragraph;
  v.file = r.file;
  v.level = std::string(harness::to_string(r.level));
  v.outcome = std::string(harness::to_string(r.verdict));
  v.failures = r.failures;
  v.inconclusive_reason = r.inconclusive_reason;
  v.error_reason = r.error_reason;
  v.line = r.line;
  v.skip_reason = r.skip_reason;
  v.skip_cause = std::string(harness::to_string(r.skip_cause));
  v.known_issue = r.known_issue_reason;
  v.quote = r.quote;
  v.comment = r.comment;
  v.duration_ms = r.duration_ms;
  v.repeats = r.repeats;
  v.repeat_failures = r.repeat_failures;
  for (const auto& e : r.transcript) v.transcript.push_back(frame_record(e));
  assign_paths(v.transcript);
  return v;
}

void compact_for_reports(VectorRecord& v) {
  if (v.has_failed_steps()) return;
  for (auto& f : v.transcript) {
    f.fields.clear();
    f.fields.shrink_to_fit();
  }
}

void finish(RunDocument& doc, const harness::RunResult& run, std::string finished_at) {
  doc.status = run.aborted ? "aborted" : "complete";
  doc.abort_reason = run.abort_reason;
  doc.stopped_by = run.stopped_by;
  doc.backup = run.backup.file;
  doc.finished_at = std::move(finished_at);
  doc.summary = Summary{run.passed, run.failed, run.skipped, run.known, run.unexpected, run.exit_code(), {}, run.inconclusive,
                        run.errors, run.line};
  for (const auto& [cause, n] : run.skipped_by_cause) doc.summary->skipped_by_cause[std::string(harness::to_string(cause))] = n;
  doc.liveness.clear();
  for (const auto& l : run.liveness) doc.liveness.push_back({l.when, l.alive, l.detail});
  doc.restore = run.restore_notes;
  doc.traffic = {{"bytes_sent", run.bytes_sent},
                 {"bytes_received", run.bytes_received},
                 {"silence_windows", run.silence_windows},
                 {"silence_listened_ms", run.silence_listened.count() / 1000.0},
                 {"measured_turnaround_ms", run.measured_turnaround.count() / 1000.0}};
}

// ---- JSON ------------------------------------------------------------------------

ordered_json line_json(const harness::LineFaultCounts& c) {
  return {{"exchanges", c.exchanges}, {"faults", c.faults}, {"recovered", c.recovered}, {"repeats", c.repeats},
          {"surveyed", c.surveyed}};
}

ordered_json header_json(const RunDocument& d) {
  const auto text = [](const std::string& s) { return json_string(s); };
  ordered_json j = {{"schema", kSchemaName},
                    {"schema_version", kSchemaVersion},  // the layout written is this version's, whatever was read
                    {"generator", text(d.generator)},
                    {"started_at", text(d.started_at)},
                    {"finished_at", text(d.finished_at)},
                    {"status", text(d.status)},
                    {"abort_reason", text(d.abort_reason)}};
  if (!d.stopped_by.empty()) j["stopped_by"] = text(d.stopped_by);
  if (!d.journal.empty()) j["journal"] = text(d.journal);
  j["device"] = text(d.device);
  j["identity"] = {{"ok", d.identity.ok},
                   {"controller_type", text(d.identity.controller_type)},
                   {"firmware_version", text(d.identity.firmware_version)},
                   {"reply_hex", text(d.identity.reply_hex)},
                   {"error", text(d.identity.error)}};
  j["profile"] = text(d.profile);
  j["address"] = d.address;
  ordered_json faults = ordered_json::array();
  for (const auto& f : d.faults) faults.push_back(text(f));
  j["faults"] = std::move(faults);
  j["options"] = json_value(d.options);
  if (const auto& i = d.invocation)
    j["invocation"] = {{"profile", text(i->profile)}, {"port", text(i->port)},
                       {"tcp", text(i->tcp)},         {"baud", i->baud},
                       {"line", text(i->line)},       {"serial_backend", text(i->serial_backend)},
                       {"reading", text(i->reading)}, {"json", text(i->json)},
                       {"junit", text(i->junit)},     {"html", text(i->html)},
                       {"md", text(i->md)},           {"report_dir", text(i->report_dir)}};
  j["planned"] = d.planned;
  if (!d.resumptions.empty()) {
    ordered_json stops = ordered_json::array();
    for (const auto& r : d.resumptions) {
      ordered_json restore = ordered_json::array();
      for (const auto& n : r.restore) restore.push_back(text(n));
      stops.push_back({{"stopped_at", text(r.stopped_at)}, {"stopped_by", text(r.stopped_by)},
                       {"abort_reason", text(r.abort_reason)}, {"resumed_at", text(r.resumed_at)},
                       {"kept", r.kept}, {"restore", std::move(restore)}});
    }
    j["resumptions"] = std::move(stops);
  }
  if (d.summary) {
    ordered_json causes = ordered_json::object();
    for (const auto& [cause, n] : d.summary->skipped_by_cause) causes[valid_utf8(cause)] = n;
    j["summary"] = {{"passed", d.summary->passed},   {"failed", d.summary->failed},
                    {"skipped", d.summary->skipped}, {"known", d.summary->known},
                    {"unexpected", d.summary->unexpected}, {"inconclusive", d.summary->inconclusive},
                    {"errors", d.summary->errors}, {"line", line_json(d.summary->line)},
                    {"exit_code", d.summary->exit_code}, {"skipped_by_cause", std::move(causes)}};
  }
  ordered_json live = ordered_json::array();
  for (const auto& l : d.liveness) live.push_back({{"when", text(l.when)}, {"alive", l.alive}, {"detail", text(l.detail)}});
  j["liveness"] = live;
  ordered_json restore = ordered_json::array();
  for (const auto& r : d.restore) restore.push_back(text(r));
  j["restore"] = std::move(restore);
  if (!d.backup.empty()) j["backup"] = text(d.backup);
  j["traffic"] = json_value(d.traffic);
  return j;
}

namespace {

// A run file may have been edited or written by another tool: a count is a
// whole number within its type (json's get<> casts 1e300 or -1 as is, the
// first undefined behaviour, the second a wrapped count).
template <class T>
T get(const json& j, const char* key, T fallback) {
  const auto it = j.find(key);
  if (it == j.end() || it->is_null()) return fallback;
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    const bool fits = it->is_number_unsigned()  ? std::in_range<T>(it->get<std::uint64_t>())
                      : it->is_number_integer() ? std::in_range<T>(it->get<std::int64_t>())
                                                : false;
    if (!fits)
      throw json::type_error::create(302, std::string(key) + ": expected a whole number " +
                                              std::to_string(std::numeric_limits<T>::min()) + " to " +
                                              std::to_string(std::numeric_limits<T>::max()) + ", got " + it->dump(), &*it);
  }
  return it->get<T>();
}

// "line" {exchanges, faults, recovered, repeats} (v5), surveyed (v6): zero
// when absent, as in documents of older versions; counts
// line_counts_problem refuses are an error naming them.
harness::LineFaultCounts line_from_json(const json& j) {
  harness::LineFaultCounts c;
  const json line = get<json>(j, "line", json::object());
  if (!line.is_object()) throw json::type_error::create(302, "line: expected an object, got " + line.dump(), &line);
  c.exchanges = get<std::size_t>(line, "exchanges", 0);
  c.faults = get<std::size_t>(line, "faults", 0);
  c.recovered = get<std::size_t>(line, "recovered", 0);
  c.repeats = get<std::size_t>(line, "repeats", 0);
  c.surveyed = get<std::size_t>(line, "surveyed", 0);
  if (const std::string why = line_counts_problem(c); !why.empty())
    throw json::other_error::create(501, "line: " + why, &line);
  return c;
}

}  // namespace

VectorRecord vector_from_json(const json& v) {
  VectorRecord r;
  r.id = v.at("id").get<std::string>();
  r.paragraph = get<std::string>(v, "paragraph", "");
  r.file = get<std::string>(v, "file", "");
  r.level = get<std::string>(v, "level", "");
  r.outcome = v.at("outcome").get<std::string>();
  r.failures = get<std::vector<std::string>>(v, "failures", {});
  r.inconclusive_reason = get<std::string>(v, "inconclusive_reason", "");
  r.error_reason = get<std::string>(v, "error_reason", "");
  r.line = line_from_json(v);
  r.skip_reason = get<std::string>(v, "skip_reason", "");
  r.skip_cause = get<std::string>(v, "skip_cause", "");
  r.known_issue = get<std::string>(v, "known_issue", "");
  r.quote = get<std::string>(v, "quote", "");
  r.comment = get<std::string>(v, "comment", "");
  r.duration_ms = get<double>(v, "duration_ms", 0);
  if (const auto it = v.find("wall_ms"); it != v.end() && !it->is_null()) r.wall_ms = it->get<double>();
  r.repeats = get<int>(v, "repeats", 0);
  r.repeat_failures = get<int>(v, "repeat_failures", 0);
  for (const auto& t : get<json>(v, "transcript", json::array())) {
    FrameRecord f;
    f.t_ms = get<double>(t, "t_ms", 0);
    f.dir = get<std::string>(t, "dir", "");
    f.hex = get<std::string>(t, "hex", "");
    f.note = get<std::string>(t, "note", "");
    f.command = get<std::string>(t, "command", "");
    f.form = get<std::string>(t, "form", "");
    f.expect = get<std::string>(t, "expect", "");
    f.path = get<std::string>(t, "path", "");
    for (const auto& x : get<json>(t, "fields", json::array()))
      f.fields.push_back({get<std::size_t>(x, "first", 0), get<std::size_t>(x, "last", 0), get<std::string>(x, "name", ""),
                          get<std::string>(x, "raw", ""), get<std::string>(x, "meaning", ""), get<bool>(x, "ok", true)});
    r.transcript.push_back(std::move(f));
  }
  return r;
}

std::optional<RunDocument> from_json(const json& j, std::string& error) {
  if (!j.is_object()) {
    error = "not a JSON object";
    return std::nullopt;
  }
  if (get<std::string>(j, "schema", "") != kSchemaName) {
    error = "schema: expected \"sabus-run\", got " + (j.contains("schema") ? j["schema"].dump() : std::string("nothing"));
    return std::nullopt;
  }
  RunDocument d;
  std::string where = "header";
  try {
    d.schema_version = get<int>(j, "schema_version", 0);
    if (d.schema_version < 1 || d.schema_version > kSchemaVersion) {
      error = "schema_version: " + std::to_string(d.schema_version) + " is not 1 to " + std::to_string(kSchemaVersion);
      return std::nullopt;
    }
    d.generator = get<std::string>(j, "generator", "sabus");
    d.started_at = get<std::string>(j, "started_at", "");
    d.finished_at = get<std::string>(j, "finished_at", "");
    d.status = get<std::string>(j, "status", "running");
    d.abort_reason = get<std::string>(j, "abort_reason", "");
    d.stopped_by = get<std::string>(j, "stopped_by", "");
    d.journal = get<std::string>(j, "journal", "");
    d.device = get<std::string>(j, "device", "");
    if (auto it = j.find("identity"); it != j.end() && it->is_object()) {
      where = "identity";
      d.identity.ok = get<bool>(*it, "ok", false);
      d.identity.controller_type = get<std::string>(*it, "controller_type", "");
      d.identity.firmware_version = get<std::string>(*it, "firmware_version", "");
      d.identity.reply_hex = get<std::string>(*it, "reply_hex", "");
      d.identity.error = get<std::string>(*it, "error", "");
    } else {
      d.identity.error = "not recorded (schema version 1)";
    }
    where = "header";
    d.profile = get<std::string>(j, "profile", "");
    d.address = get<int>(j, "address", 0);
    d.faults = get<std::vector<std::string>>(j, "faults", {});
    d.options = get<json>(j, "options", json::object());
    if (auto it = j.find("invocation"); it != j.end() && !it->is_null()) {
      where = "invocation";
      Invocation i;
      i.profile = get<std::string>(*it, "profile", "");
      i.port = get<std::string>(*it, "port", "");
      i.tcp = get<std::string>(*it, "tcp", "");
      i.baud = get<int>(*it, "baud", 0);
      i.line = get<std::string>(*it, "line", "");
      i.serial_backend = get<std::string>(*it, "serial_backend", "");
      i.reading = get<std::string>(*it, "reading", "");
      i.json = get<std::string>(*it, "json", "");
      i.junit = get<std::string>(*it, "junit", "");
      i.html = get<std::string>(*it, "html", "");
      i.md = get<std::string>(*it, "md", "");
      i.report_dir = get<std::string>(*it, "report_dir", "");
      d.invocation = std::move(i);
      where = "header";
    }
    d.planned = get<std::size_t>(j, "planned", 0);
    for (const auto& r : get<json>(j, "resumptions", json::array())) {
      where = "resumptions";
      d.resumptions.push_back({get<std::string>(r, "stopped_at", ""), get<std::string>(r, "stopped_by", ""),
                               get<std::string>(r, "abort_reason", ""), get<std::string>(r, "resumed_at", ""),
                               get<std::size_t>(r, "kept", 0), get<std::vector<std::string>>(r, "restore", {})});
    }
    where = "header";
    if (auto it = j.find("summary"); it != j.end() && it->is_object()) {
      where = "summary";
      d.summary = Summary{get<std::size_t>(*it, "passed", 0), get<std::size_t>(*it, "failed", 0),
                          get<std::size_t>(*it, "skipped", 0), get<std::size_t>(*it, "known", 0),
                          get<std::size_t>(*it, "unexpected", 0), get<int>(*it, "exit_code", 1),
                          get<std::map<std::string, std::size_t>>(*it, "skipped_by_cause", {}),
                          get<std::size_t>(*it, "inconclusive", 0), get<std::size_t>(*it, "errors", 0),
                          line_from_json(*it)};
    }
    for (const auto& l : get<json>(j, "liveness", json::array())) {
      where = "liveness";
      d.liveness.push_back({get<std::string>(l, "when", ""), get<bool>(l, "alive", true), get<std::string>(l, "detail", "")});
    }
    d.restore = get<std::vector<std::string>>(j, "restore", {});
    d.backup = get<std::string>(j, "backup", "");
    d.traffic = get<json>(j, "traffic", json::object());
    if (const auto vectors = j.find("vectors"); vectors != j.end() && !vectors->is_null()) {
      where = "vectors";
      if (!vectors->is_array()) throw json::type_error::create(302, "not an array", &*vectors);
      for (std::size_t i = 0; i < vectors->size(); ++i) {
        const json& v = (*vectors)[i];
        where = "vectors[" + std::to_string(i) + "]";
        if (const auto id = v.find("id"); id != v.end() && id->is_string()) where += " (" + id->get<std::string>() + ")";
        d.vectors.push_back(vector_from_json(v));
      }
    }
  } catch (const json::exception& e) {
    error = where + ": " + e.what();
    return std::nullopt;
  }
  return d;
}

std::optional<RunDocument> read_run_file(const std::string& path, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = path + ": cannot read";
    return std::nullopt;
  }
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    error = path + ": not JSON: " + e.what();
    return std::nullopt;
  }
  auto d = from_json(j, error);
  if (!d) error = path + ": " + error;
  return d;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace sabus::reports
