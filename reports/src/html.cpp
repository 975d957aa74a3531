// The HTML report: one self-contained page (inline CSS and SVG, one inline
// script, nothing from the network). Every string that came from the device,
// the vectors or the command line goes through xml_escape.
//
// Size: a failing vector shows its replies field by field; any other vector
// its frames as one line each (hex and summary), so the page of the full
// suite stays under a megabyte while run.json keeps every field.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "html_filter.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports {

namespace {

std::string e(std::string_view s) { return xml_escape(s); }

// The status the filter and the colours use: pass, fail (a failure or an
// unexpected pass), known, error (the line left it unjudged), inconclusive,
// skip.
const char* outcome_class(const std::string& outcome) {
  if (outcome == "pass") return "pass";
  if (outcome == "fail" || outcome == "unexpected pass") return "fail";
  if (outcome == "known failure") return "known";
  if (outcome == "inconclusive") return "inconclusive";
  if (outcome == "error") return "error";
  return "skip";
}

// A tally's worst outcome: fail, known, error (ran, the line left it
// unjudged), inconclusive (ran, checked nothing), pass, skip; "none" when
// empty.
const char* tally_class(const Tally& t) {
  if (t.total() == 0) return "none";
  return t.failed         ? "fail"
         : t.known        ? "known"
         : t.errors       ? "error"
         : t.inconclusive ? "inconclusive"
         : t.passed       ? "pass"
                          : "skip";
}

std::string tally_text(const Tally& t) {
  std::string text;
  auto part = [&](std::size_t n, const char* what) {
    if (n) text += fmt::format("{}{} {}", text.empty() ? "" : ", ", n, what);
  };
  part(t.passed, "pass");
  part(t.failed, "fail");
  part(t.known, "known");
  part(t.errors, "error");
  part(t.inconclusive, "inconclusive");
  part(t.skipped, "skip");
  return text;
}

// A cell coloured by its worst outcome.
std::string tally_cell(const Tally& t) {
  if (t.total() == 0) return "<td class=\"none\">–</td>";
  return fmt::format("<td class=\"{}\">{}</td>", tally_class(t), tally_text(t));
}

std::string anchor(const std::string& id) {
  std::string out = "v-";
  for (char c : id) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  return out;
}

// Three significant figures or so: "3.00 ms", "12.5 ms", "165 ms".
std::string ms_text(double ms) {
  return ms < 10 ? fmt::format("{:.2f} ms", ms) : ms < 100 ? fmt::format("{:.1f} ms", ms) : fmt::format("{:.0f} ms", ms);
}

// "3.00 ms (2.10–4.00 ms)"; one figure when they are all the same.
std::string spread_text(double min_ms, double median_ms, double max_ms) {
  if (min_ms == max_ms) return ms_text(median_ms);
  return fmt::format("{} ({}–{})", ms_text(median_ms), ms_text(min_ms), ms_text(max_ms));
}

// The CSP names the script by the base64 of its SHA-256 (CSP Level 2,
// "hash-source"); CMake gives the digest in hex.
std::string base64_of_hex(std::string_view hex) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) bytes += static_cast<char>(std::stoi(std::string(hex.substr(i, 2)), nullptr, 16));
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t chunk = 0;
    for (std::size_t k = 0; k < 3; ++k) chunk = chunk << 8 | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[chunk >> (18 - 6 * k) & 0x3f] : '=';
  }
  return out;
}

// Colours shared by the tables (CSS) and the charts (SVG fill).
constexpr const char* kPassColour = "#c8ecc8";
constexpr const char* kFailColour = "#f6c1c1";
constexpr const char* kKnownColour = "#f7e3a6";
constexpr const char* kInconclusiveColour = "#c6dcf2";
constexpr const char* kErrorColour = "#d9c6f2";  // violet: the bench's, beside the firmware's red
constexpr const char* kSkipColour = "#e4e4e4";
constexpr const char* kNoneColour = "#ffffff";

const char* class_colour(std::string_view cls) {
  if (cls == "pass") return kPassColour;
  if (cls == "fail") return kFailColour;
  if (cls == "known") return kKnownColour;
  if (cls == "inconclusive") return kInconclusiveColour;
  if (cls == "error") return kErrorColour;
  if (cls == "skip") return kSkipColour;
  return kNoneColour;
}

std::string style() {
  return fmt::format(R"(
body{{font-family:system-ui,sans-serif;margin:1.5em;color:#222;max-width:1400px}}
table{{border-collapse:collapse;margin:.5em 0}}
th,td{{border:1px solid #bbb;padding:2px 6px;text-align:left;vertical-align:top;font-size:13px}}
th{{background:#eee}}
.pass{{background:{}}}.fail{{background:{}}}.known{{background:{}}}.inconclusive{{background:{}}}.error{{background:{}}}.skip{{background:{}}}.none{{color:#999}}
.verdict{{padding:2px 10px;border-radius:4px}}
.PASS{{background:#2e8b2e;color:#fff}}.FAIL,.STOPPED,.ABORTED,.INCOMPLETE{{background:#b22222;color:#fff}}
.ERROR{{background:#5b3a8c;color:#fff}}
code,.hex,pre{{font-family:ui-monospace,monospace;font-size:12px}}
pre{{margin:.3em 0;white-space:pre-wrap}}
details{{margin:2px 0;border:1px solid #ddd;padding:2px 6px}}
details>summary{{cursor:pointer}}
blockquote{{margin:.3em 0 .3em 1em;padding-left:.6em;border-left:3px solid #aaa;color:#444}}
.fields td{{font-size:12px}}
nav a{{margin-right:1em}}
#filter{{position:sticky;top:0;background:#fff;padding:4px 0;border-bottom:1px solid #ddd}}
#filter label{{margin-right:1em}}
[hidden]{{display:none!important}}
svg text{{font-family:system-ui,sans-serif;font-size:11px;fill:#222}}
)",
                     kPassColour, kFailColour, kKnownColour, kInconclusiveColour, kErrorColour, kSkipColour);
}

// ---- tables ----------------------------------------------------------------------

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
  row("Started", d.started_at);
  row("Finished", d.finished_at);
  row("Status", d.status + (d.abort_reason.empty() ? "" : ": " + d.abort_reason));
  row("Suite version", d.generator);
  return out + "</table>\n";
}

// One row per option, in the order the run wrote them; lists joined.
std::string options_table(const RunDocument& d) {
  std::string out = "<table id=\"options\">\n<tr><th>Option</th><th>Value</th></tr>\n";
  for (const auto& [name, value] : d.options.items()) {
    std::string text;
    if (value.is_string()) {
      text = value.get<std::string>();
    } else if (value.is_array()) {
      for (const auto& item : value) text += (text.empty() ? "" : ", ") + (item.is_string() ? item.get<std::string>() : json_value_text(item));
    } else {
      text = json_value_text(value);
    }
    out += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", e(name), text.empty() ? "<span class=\"none\">–</span>" : e(text));
  }
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

// 29 vectors failing for one reason are one entry, with the vectors inside.
std::string failure_section(const RunDocument& d) {
  const auto groups = failure_groups(d);
  if (groups.empty()) return "";
  std::size_t failing = 0;
  for (const auto& g : groups) failing += g.vectors.size();
  std::string out = fmt::format("<h2 id=\"failures\">Failures: {} vectors, {} reasons</h2>\n<div id=\"failure-groups\">\n",
                                failing, groups.size());
  for (const auto& g : groups) {
    out += fmt::format("<details class=\"group\"><summary><b class=\"count\">{} ×</b> {}</summary>\n<ul>\n", g.vectors.size(),
                       e(g.reason));
    for (const auto* v : g.vectors)
      out += fmt::format("<li><a href=\"#{}\">{}</a> §{} {}{}</li>\n", anchor(v->id), e(v->id), e(v->paragraph), e(v->level),
                         v->outcome == "fail" ? "" : " (" + e(v->outcome) + ")");
    out += "</ul></details>\n";
  }
  return out + "</div>\n";
}

// ---- charts (inline SVG) ---------------------------------------------------------

// Reply time per command: a line from the fastest to the slowest reply, a
// mark at the median, the figures beside it.
std::string turnaround_chart(const std::vector<Turnaround>& rows) {
  constexpr int kLabel = 230, kPlot = 420, kFigures = 220, kRow = 18, kTop = 24;
  double top = 1;
  for (const auto& r : rows) top = std::max(top, r.max_ms);
  top *= 1.05;
  const int height = kTop + kRow * static_cast<int>(rows.size()) + 24;
  const int width = kLabel + kPlot + kFigures;
  auto x = [&](double ms) { return kLabel + ms / top * kPlot; };
  std::string out = fmt::format(
      "<svg id=\"chart-turnaround\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "role=\"img\" aria-label=\"Reply time per command\">\n<title>Reply time per command (ms, transport clock)</title>\n",
      width, height);
  // The axis: 0, half, full scale.
  for (double f : {0.0, 0.5, 1.0}) {
    const double ms = top * f;
    out += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"#ddd\"/>"
                       "<text x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">{4}</text>\n",
                       x(ms), kTop - 4, height - 20, height - 6, ms_text(ms));
  }
  out += fmt::format("<text x=\"{}\" y=\"14\">command</text><text x=\"{}\" y=\"14\">replies: median (min–max)</text>\n", 4,
                     kLabel + kPlot + 8);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Turnaround& r = rows[i];
    const int y = kTop + kRow * static_cast<int>(i) + kRow / 2;
    out += fmt::format(
        "<g class=\"bar\"><title>{0} ({1}, §{2}): {3} replies, min {4}, median {5}, max {6}</title>"
        "<text x=\"4\" y=\"{7}\">{1} §{2}</text>"
        "<line x1=\"{8:.1f}\" y1=\"{9}\" x2=\"{10:.1f}\" y2=\"{9}\" stroke=\"#7a9cc6\" stroke-width=\"6\" stroke-linecap=\"round\"/>"
        "<rect x=\"{11:.1f}\" y=\"{12}\" width=\"3\" height=\"12\" fill=\"#1f3f73\"/>"
        "<text x=\"{13}\" y=\"{7}\">{14}, {3}×</text></g>\n",
        e(r.command), e(r.name), e(r.paragraph), r.count, ms_text(r.min_ms), ms_text(r.median_ms), ms_text(r.max_ms), y + 4,
        x(r.min_ms), y, std::max(x(r.max_ms), x(r.min_ms) + 1), x(r.median_ms) - 1.5, y - 6, kLabel + kPlot + 8,
        spread_text(r.min_ms, r.median_ms, r.max_ms));
  }
  return out + "</svg>\n";
}

std::string legend_svg(int x, int y) {
  std::string out;
  int at = x;
  for (const char* cls : {"pass", "fail", "known", "error", "inconclusive", "skip", "none"}) {
    out += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"12\" height=\"12\" fill=\"{}\" stroke=\"#999\"/><text x=\"{}\" y=\"{}\">{}</text>",
                       at, y, class_colour(cls), at + 16, y + 10,
                       std::string_view(cls) == "none" ? "not exercised" : cls);
    at += std::string_view(cls) == "none" ? 100 : std::string_view(cls) == "inconclusive" ? 96 : 64;
  }
  return out + "\n";
}

// The coverage matrix as a heat map: a row per command and form, a column
// per path, each cell coloured by the worst outcome of the vectors in it.
std::string coverage_chart(const std::vector<CoverageRow>& rows) {
  constexpr int kLabel = 280, kCell = 72, kRow = 15, kTop = 22;
  const int height = kTop + kRow * static_cast<int>(rows.size()) + 28;
  constexpr int kLegend = 524;  // legend_svg's seven entries
  const int width = kLabel + std::max(kCell * 4 + 10, kLegend);
  std::string out = fmt::format(
      "<svg id=\"chart-coverage\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "role=\"img\" aria-label=\"Coverage matrix\">\n<title>Coverage: command × form × path, by outcome</title>\n",
      width, height);
  for (int p = 0; p < 4; ++p)
    out += fmt::format("<text x=\"{}\" y=\"14\" text-anchor=\"middle\">{}</text>", kLabel + kCell * p + kCell / 2, kPaths[p]);
  out += "\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CoverageRow& r = rows[i];
    const int y = kTop + kRow * static_cast<int>(i);
    const CommandInfo* info = find_command(r.command);
    const std::string label = (info ? fmt::format("{:02X}h ", info->code) : "") + r.name + (r.form.empty() ? "" : " form " + r.form);
    out += fmt::format("<text x=\"4\" y=\"{}\">{}</text>", y + 11, e(label));
    for (int p = 0; p < 4; ++p) {
      const auto it = r.paths.find(kPaths[p]);
      const Tally t = it == r.paths.end() ? Tally{} : it->second;
      out += fmt::format("<rect class=\"cell {}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\" stroke=\"#bbb\">"
                         "<title>{} {}: {}</title></rect>",
                         tally_class(t), kLabel + kCell * p, y, kCell, kRow, class_colour(tally_class(t)), e(label), kPaths[p],
                         t.total() ? tally_text(t) : "not exercised");
    }
    out += "\n";
  }
  out += legend_svg(kLabel, height - 18);
  return out + "</svg>\n";
}

std::string coverage_table(const std::vector<CoverageRow>& rows) {
  std::string out =
      "<table id=\"coverage\">\n<tr><th>Code</th><th>Command</th><th>§</th><th>Form</th>"
      "<th>ACK</th><th>NAK</th><th>offline</th><th>ignore</th></tr>\n";
  for (const auto& r : rows) {
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

// ---- timing ----------------------------------------------------------------------

std::string timing_section(const RunDocument& d) {
  double wall = 0, transport = 0;
  bool has_wall = false;
  for (const auto& v : d.vectors) {
    transport += v.duration_ms;
    if (v.wall_ms) {
      wall += *v.wall_ms;
      has_wall = true;
    }
  }
  std::string out = "<h2 id=\"timing\">Timing</h2>\n<table id=\"timing-figures\">\n";
  auto row = [&](const char* k, const std::string& v) { out += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", k, v); };
  row("Wall clock, all vectors", has_wall ? fmt::format("{:.3f} s", wall / 1000) : "not recorded (schema version 1 or 2)");
  row("Transport clock, all vectors", fmt::format("{:.3f} s (virtual in-process, real on a line)", transport / 1000));
  auto traffic = [&](const char* key) { return d.traffic.contains(key) && d.traffic[key].is_number() ? d.traffic[key].get<double>() : 0.0; };
  if (!d.traffic.empty()) {
    row("Measured turnaround", d.traffic.contains("measured_turnaround_ms") && traffic("measured_turnaround_ms") > 0
                                   ? ms_text(traffic("measured_turnaround_ms")) + " (request end to first reply byte, the largest seen)"
                                   : "not measured (in-process)");
    row("Silence windows", fmt::format("{:.0f}, {:.3f} s listened", traffic("silence_windows"), traffic("silence_listened_ms") / 1000));
    row("Bytes", fmt::format("{:.0f} sent, {:.0f} received", traffic("bytes_sent"), traffic("bytes_received")));
  }
  out += "</table>\n";
  const auto turnaround = turnaround_by_command(d);
  if (!turnaround.empty()) {
    out += "<h3>Reply time per command</h3>\n<p><small>From a command frame sent to its reply recorded, on the transport "
           "clock.</small></p>\n";
    out += turnaround_chart(turnaround);
  }
  // The slowest vectors by wall clock (by transport clock without it).
  std::vector<const VectorRecord*> ran;
  for (const auto& v : d.vectors)
    if (v.outcome != "skip") ran.push_back(&v);
  auto key = [](const VectorRecord* v) { return v->wall_ms.value_or(v->duration_ms); };
  std::stable_sort(ran.begin(), ran.end(), [&](auto* a, auto* b) { return key(a) > key(b); });
  if (ran.size() > 10) ran.resize(10);
  if (!ran.empty()) {
    out += "<h3>Slowest vectors</h3>\n<table id=\"slowest\">\n<tr><th>Vector</th><th>wall clock</th><th>transport clock</th></tr>\n";
    for (const auto* v : ran)
      out += fmt::format("<tr><td><a href=\"#{}\">{}</a></td><td>{}</td><td>{}</td></tr>\n", anchor(v->id), e(v->id),
                         v->wall_ms ? ms_text(*v->wall_ms) : "–", ms_text(v->duration_ms));
    out += "</table>\n";
  }
  return out;
}

// ---- vectors ---------------------------------------------------------------------

// A failing vector's frames: each reply field by field with byte ranges (the
// failures name reply fields); the commands it sent as hex and summary (their
// fields are in run.json).
std::string transcript_table(const VectorRecord& v) {
  std::string out = "<table class=\"transcript\">\n<tr><th>t (ms)</th><th>dir</th><th>bytes</th><th>decoded</th></tr>\n";
  for (const auto& f : v.transcript) {
    std::string decoded = e(f.note);
    if (!f.command.empty() || !f.form.empty() || !f.path.empty())
      decoded += fmt::format("<br><small>command {}{}{}</small>", e(f.command), f.form.empty() ? "" : ", form " + e(f.form),
                             f.path.empty() ? "" : ", path " + e(f.path));
    if (f.dir == "rx" && !f.fields.empty()) {
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

// Any other vector's frames, one line each.
std::string transcript_lines(const VectorRecord& v) {
  std::string out = "<pre class=\"transcript\">";
  for (const auto& f : v.transcript)
    out += fmt::format("{:10.3f} {} {}{}{}\n", f.t_ms, e(f.dir), e(f.hex), f.hex.empty() ? "" : "  ", e(f.note));
  return out + "</pre>\n";
}

std::string vector_section(const VectorRecord& v) {
  const std::string wall = v.wall_ms ? ", " + ms_text(*v.wall_ms) + " wall" : "";
  std::string out = fmt::format(
      "<details class=\"v\" id=\"{}\" data-status=\"{}\" data-level=\"{}\" data-paragraph=\"{}\"{}><summary><span class=\"{}\">{}</span> "
      "<b>{}</b> §{} {} — {}{}</summary>\n",
      anchor(v.id), outcome_class(v.outcome), e(v.level), e(v.paragraph), v.is_failure() ? " open" : "",
      outcome_class(v.outcome), e(v.outcome), e(v.id), e(v.paragraph), e(v.level), ms_text(v.duration_ms), wall);
  if (!v.quote.empty()) out += "<blockquote>" + e(v.quote) + "</blockquote>\n";
  if (!v.comment.empty()) out += "<p>" + e(v.comment) + "</p>\n";
  if (!v.file.empty()) out += "<p><small>" + e(v.file) + "</small></p>\n";
  for (const auto& f : v.failures) out += "<p class=\"fail\">" + e(f) + "</p>\n";
  if (!v.inconclusive_reason.empty()) out += "<p class=\"inconclusive\">inconclusive: " + e(v.inconclusive_reason) + "</p>\n";
  if (!v.error_reason.empty()) out += "<p class=\"error\">error: " + e(v.error_reason) + "</p>\n";
  // A vector's line figures where the line did something to it: the run's
  // are in the header.
  if (v.line.faults > 0 || v.is_error()) out += "<p class=\"line\">" + e(harness::describe(v.line)) + "</p>\n";
  if (!v.skip_reason.empty()) out += "<p class=\"skip\">skipped: " + e(v.skip_reason) + "</p>\n";
  if (!v.known_issue.empty()) out += "<p class=\"known\">known issue: " + e(v.known_issue) + "</p>\n";
  if (v.repeats > 0) out += fmt::format("<p>repeated {} times, failed {} of them</p>\n", v.repeats, v.repeat_failures);
  if (!v.transcript.empty()) out += v.has_failed_steps() ? transcript_table(v) : transcript_lines(v);
  return out + "</details>\n";
}

std::string select(const char* name, const char* label, const std::vector<std::pair<std::string, std::string>>& options) {
  std::string out = fmt::format("<label>{} <select name=\"{}\" id=\"f-{}\"><option value=\"\">all</option>", label, name, name);
  for (const auto& [value, text] : options) out += fmt::format("<option value=\"{}\">{}</option>", e(value), e(text));
  return out + "</select></label>\n";
}

// Shown by the script (hidden without it): status, level and paragraph.
std::string filter_form(const RunDocument& d) {
  std::vector<std::pair<std::string, std::string>> paragraphs;
  for (const auto& [paragraph, levels] : paragraph_levels(d)) paragraphs.push_back({paragraph, "§" + paragraph});
  std::string out = "<form id=\"filter\" hidden>\n";
  out += select("status", "Status",
                {{"fail", "failed (and unexpected passes)"},
                 {"known", "known failures"},
                 {"error", "in error (the line left them unjudged)"},
                 {"inconclusive", "inconclusive"},
                 {"pass", "passed"},
                 {"skip", "skipped"}});
  out += select("level", "Level", {{"must", "must"}, {"should", "should"}, {"informative", "informative"}});
  out += select("paragraph", "Paragraph", paragraphs);
  return out + "<output id=\"shown\"></output>\n</form>\n";
}

}  // namespace

std::string html_report(const RunDocument& d) {
  const Summary c = d.counts();
  const std::string verdict = d.verdict();
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  // No network, and no script but the filter's: whatever slipped through the
  // escaping could neither fetch nor run anything.
  out += fmt::format("<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; style-src 'unsafe-inline'; "
                     "script-src 'sha256-{}'\">\n",
                     base64_of_hex(generated::kFilterScriptSha256));
  out += fmt::format("<title>sabus conformance run: {}</title>\n<style>{}</style>\n</head>\n<body>\n", verdict, style());
  out += fmt::format("<h1>SAbus conformance run <span class=\"verdict {0}\" id=\"verdict\">{0}</span></h1>\n", verdict);
  out += fmt::format("<p id=\"summary\">{}</p>\n", e(summary_line(c)));
  // The line figures whenever exchanges were counted, a warning above a
  // healthy line's fault rate, and what the vectors in error mean.
  if (const std::string line = line_text(c); !line.empty()) out += fmt::format("<p id=\"line\">{}</p>\n", e(line));
  if (const std::string warning = line_warning(c); !warning.empty())
    out += fmt::format("<p id=\"line-warning\" class=\"known\">Warning: {}</p>\n", e(warning));
  if (const std::string errors = line_error_text(c); !errors.empty())
    out += fmt::format("<p id=\"line-errors\" class=\"error\">{}.{}</p>\n", e(errors),
                       c.exit_code == harness::kLineErrorExitCode ? " The firmware is neither accepted nor rejected." : "");
  out += fmt::format("<p id=\"suite\">{} · schema sabus-run v{} · {}{}</p>\n", e(d.generator), d.schema_version,
                     e(d.identity.ok ? "controller " + d.identity.controller_type + ", firmware " + d.identity.firmware_version
                                     : "identity unknown"),
                     d.profile.empty() ? "" : " · profile " + e(d.profile));
  if (!d.abort_reason.empty())
    out += std::string("<p class=\"fail\">") + (d.stopped() ? "Stopped before its end: " : "Aborted: ") + e(d.abort_reason) +
           "</p>\n";
  const bool failures = c.failed + c.unexpected > 0;
  out += std::string("<nav><a href=\"#device\">Device</a><a href=\"#run-options\">Options</a><a href=\"#per-paragraph\">Paragraphs</a>") +
         (failures ? "<a href=\"#failures\">Failures</a>" : "") +
         "<a href=\"#timing\">Timing</a><a href=\"#coverage-map\">Coverage</a><a href=\"#vectors\">Vectors</a></nav>\n";
  out += "<h2 id=\"device\">Device</h2>\n" + identity_table(d);
  out += "<h2 id=\"run-options\">Options</h2>\n" + options_table(d);
  out += "<h2 id=\"per-paragraph\">Summary per paragraph and level</h2>\n" + paragraph_table(d);
  out += failure_section(d);
  bool dead = false;
  for (const auto& l : d.liveness) dead |= !l.alive;
  if (dead || !d.restore.empty()) {
    out += "<h2>Liveness and restore</h2>\n<ul>\n";
    for (const auto& l : d.liveness)
      if (!l.alive) out += "<li class=\"fail\">no answer " + e(l.when) + ": " + e(l.detail) + "</li>\n";
    for (const auto& r : d.restore) out += "<li>" + e(r) + "</li>\n";
    out += "</ul>\n";
  }
  out += timing_section(d);
  const auto rows = coverage(d);
  out += "<h2 id=\"coverage-map\">Coverage: command × form × path</h2>\n" + coverage_chart(rows);
  out += "<details><summary>The same as a table, with counts</summary>\n" + coverage_table(rows) + "</details>\n";
  out += "<h2>Vectors</h2>\n" + filter_form(d) + "<div id=\"vectors\">\n";
  for (const auto& v : d.vectors) out += vector_section(v);
  out += "</div>\n";
  out += fmt::format("<p><small>{} · schema sabus-run v{}</small></p>\n", e(d.generator), d.schema_version);
  out += fmt::format("<script>{}</script>\n</body>\n</html>\n", generated::kFilterScript);
  return out;
}

}  // namespace sabus::reports
