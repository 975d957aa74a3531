// The HTML report: one self-contained page (inline CSS, no scripts, no
// assets, nothing from the network). Every string that came from the device,
// the vectors or the command line goes through xml_escape.
#include <fmt/format.h>

#include "sabus/reports/writers.hpp"

namespace sabus::reports {

namespace {

std::string e(std::string_view s) { return xml_escape(s); }

const char* outcome_class(const std::string& outcome) {
  if (outcome == "pass") return "pass";
  if (outcome == "fail" || outcome == "unexpected pass") return "fail";
  if (outcome == "known failure") return "known";
  return "skip";
}

// A cell coloured by its worst outcome: fail, known, pass, skip.
std::string tally_cell(const Tally& t) {
  if (t.total() == 0) return "<td class=\"none\">–</td>";
  const char* cls = t.failed ? "fail" : t.known ? "known" : t.passed ? "pass" : "skip";
  std::string text;
  auto part = [&](std::size_t n, const char* what) {
    if (n) text += fmt::format("{}{} {}", text.empty() ? "" : ", ", n, what);
  };
  part(t.passed, "pass");
  part(t.failed, "fail");
  part(t.known, "known");
  part(t.skipped, "skip");
  return fmt::format("<td class=\"{}\">{}</td>", cls, text);
}

std::string anchor(const std::string& id) {
  std::string out = "v-";
  for (char c : id) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  return out;
}

constexpr const char* kStyle = R"(
body{font-family:system-ui,sans-serif;margin:1.5em;color:#222;max-width:1400px}
table{border-collapse:collapse;margin:.5em 0}
th,td{border:1px solid #bbb;padding:2px 6px;text-align:left;vertical-align:top;font-size:13px}
th{background:#eee}
.pass{background:#c8ecc8}.fail{background:#f6c1c1}.known{background:#f7e3a6}.skip{background:#e4e4e4}.none{color:#999}
.verdict{padding:2px 10px;border-radius:4px}
.PASS{background:#2e8b2e;color:#fff}.FAIL,.ABORTED,.INCOMPLETE{background:#b22222;color:#fff}
code,.hex{font-family:ui-monospace,monospace;font-size:12px}
details{margin:2px 0;border:1px solid #ddd;padding:2px 6px}
details>summary{cursor:pointer}
blockquote{margin:.3em 0 .3em 1em;padding-left:.6em;border-left:3px solid #aaa;color:#444}
.fields td{font-size:12px}
)";

std::string identity_table(const RunDocument& d) {
  std::string out = "<table id=\"identity\">\n";
  auto row = [&](const char* k, const std::string& v) { out += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", k, e(v)); };
  if (d.identity.ok) {
    row("Controller type", d.identity.controller_type);
    row("Firmware version", d.identity.firmware_version);
  } else {
    row("Identity", "unknown: " + d.identity.error);
  }
  if (!d.identity.reply_hex.empty()) row("30h reply", d.identity.reply_hex);
  row("Device", d.device);
  row("Profile", d.profile);
  row("Address", fmt::format("0x{:02X} ({})", d.address, d.address));
  std::string faults;
  for (const auto& f : d.faults) faults += (faults.empty() ? "" : ", ") + f;
  if (!faults.empty()) row("Injected faults", faults);
  row("Options", d.options.dump());
  row("Started", d.started_at);
  row("Finished", d.finished_at);
  row("Status", d.status + (d.abort_reason.empty() ? "" : ": " + d.abort_reason));
  return out + "</table>\n";
}

std::string paragraph_table(const RunDocument& d) {
  std::string out = "<table id=\"paragraphs\">\n<tr><th>Paragraph</th><th>must</th><th>should</th><th>informative</th></tr>\n";
  for (const auto& [paragraph, levels] : paragraph_levels(d)) {
    out += fmt::format("<tr><td>§{}</td>", e(paragraph));
    for (const char* level : {"must", "should", "informative"}) {
      const auto it = levels.find(level);
      out += tally_cell(it == levels.end() ? Tally{} : it->second);
    }
    out += "</tr>\n";
  }
  return out + "</table>\n";
}

std::string coverage_table(const RunDocument& d) {
  std::string out =
      "<table id=\"coverage\">\n<tr><th>Code</th><th>Command</th><th>§</th><th>Form</th>"
      "<th>ACK</th><th>NAK</th><th>offline</th><th>ignore</th></tr>\n";
  for (const auto& r : coverage(d)) {
    out += fmt::format("<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td>", e(r.command), e(r.name),
                       e(r.paragraph), r.form.empty() ? "–" : e(r.form));
    for (const char* p : kPaths) {
      const auto it = r.paths.find(p);
      out += tally_cell(it == r.paths.end() ? Tally{} : it->second);
    }
    out += "</tr>\n";
  }
  return out + "</table>\n";
}

std::string transcript_table(const VectorRecord& v) {
  std::string out = "<table class=\"transcript\">\n<tr><th>t (ms)</th><th>dir</th><th>bytes</th><th>decoded</th></tr>\n";
  for (const auto& f : v.transcript) {
    std::string decoded = e(f.note);
    if (!f.command.empty() || !f.form.empty() || !f.path.empty())
      decoded += fmt::format("<br><small>command {}{}{}</small>", e(f.command), f.form.empty() ? "" : ", form " + e(f.form),
                             f.path.empty() ? "" : ", path " + e(f.path));
    if (!f.fields.empty()) {
      decoded += "<table class=\"fields\"><tr><th>bytes</th><th>field</th><th>raw</th><th>meaning</th></tr>";
      for (const auto& x : f.fields)
        decoded += fmt::format("<tr{}><td>{}</td><td>{}</td><td><code>{}</code></td><td>{}</td></tr>", x.ok ? "" : " class=\"fail\"",
                               x.first == x.last ? fmt::format("{}", x.first) : fmt::format("{}-{}", x.first, x.last),
                               e(x.name), e(x.raw), e(x.meaning));
      decoded += "</table>";
    }
    out += fmt::format("<tr><td>{:.3f}</td><td>{}</td><td class=\"hex\">{}</td><td>{}</td></tr>\n", f.t_ms, e(f.dir),
                       e(f.hex), decoded);
  }
  return out + "</table>\n";
}

std::string vector_section(const VectorRecord& v) {
  std::string out = fmt::format(
      "<details id=\"{}\"{}><summary><span class=\"{}\">{}</span> <b>{}</b> §{} {} — {:.1f} ms</summary>\n", anchor(v.id),
      v.is_failure() ? " open" : "", outcome_class(v.outcome), e(v.outcome), e(v.id), e(v.paragraph), e(v.level),
      v.duration_ms);
  if (!v.quote.empty()) out += "<blockquote>" + e(v.quote) + "</blockquote>\n";
  if (!v.comment.empty()) out += "<p>" + e(v.comment) + "</p>\n";
  if (!v.file.empty()) out += "<p><small>" + e(v.file) + "</small></p>\n";
  for (const auto& f : v.failures) out += "<p class=\"fail\">" + e(f) + "</p>\n";
  if (!v.skip_reason.empty()) out += "<p class=\"skip\">skipped: " + e(v.skip_reason) + "</p>\n";
  if (!v.known_issue.empty()) out += "<p class=\"known\">known issue: " + e(v.known_issue) + "</p>\n";
  if (v.repeats > 0) out += fmt::format("<p>repeated {} times, failed {} of them</p>\n", v.repeats, v.repeat_failures);
  if (!v.transcript.empty()) out += transcript_table(v);
  return out + "</details>\n";
}

}  // namespace

std::string html_report(const RunDocument& d) {
  const Summary c = d.counts();
  const std::string verdict = d.verdict();
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  // No network: forbid every fetch, even if a string slipped through.
  out += "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; style-src 'unsafe-inline'\">\n";
  out += fmt::format("<title>sabus conformance run: {}</title>\n<style>{}</style>\n</head>\n<body>\n", verdict, kStyle);
  out += fmt::format("<h1>SAbus conformance run <span class=\"verdict {0}\" id=\"verdict\">{0}</span></h1>\n", verdict);
  out += fmt::format("<p id=\"summary\">{}</p>\n", e(summary_line(c)));
  if (!d.abort_reason.empty()) out += "<p class=\"fail\">Aborted: " + e(d.abort_reason) + "</p>\n";
  out += "<h2>Device</h2>\n" + identity_table(d);
  out += "<h2>Summary per paragraph and level</h2>\n" + paragraph_table(d);
  std::string failures;
  for (const auto& v : d.vectors)
    if (v.is_failure())
      failures += fmt::format("<li><a href=\"#{}\">{}</a> §{} {}: {}</li>\n", anchor(v.id), e(v.id), e(v.paragraph),
                              e(v.level), e(v.difference()));
  if (!failures.empty()) out += "<h2>Failures</h2>\n<ul id=\"failures\">\n" + failures + "</ul>\n";
  bool dead = false;
  for (const auto& l : d.liveness) dead |= !l.alive;
  if (dead || !d.restore.empty()) {
    out += "<h2>Liveness and restore</h2>\n<ul>\n";
    for (const auto& l : d.liveness)
      if (!l.alive) out += "<li class=\"fail\">no answer " + e(l.when) + ": " + e(l.detail) + "</li>\n";
    for (const auto& r : d.restore) out += "<li>" + e(r) + "</li>\n";
    out += "</ul>\n";
  }
  out += "<h2>Coverage: command × form × path</h2>\n" + coverage_table(d);
  out += "<h2>Vectors</h2>\n";
  for (const auto& v : d.vectors) out += vector_section(v);
  out += fmt::format("<p><small>{} · schema sabus-run v{}</small></p>\n</body>\n</html>\n", e(d.generator), d.schema_version);
  return out;
}

}  // namespace sabus::reports
