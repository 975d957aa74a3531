// `sabus record`: regression vectors from a proxy log or a run JSON
// (recording.hpp). The file is checked with the vector loader and linter
// before it is written, so what it writes is what `sabus run` accepts.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>

#include "commands.hpp"
#include "sabus/reports/writers.hpp"
#include "sabus/harness/capture.hpp"
#include "sabus/harness/recording.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace sabus::cli {
namespace {

using namespace sabus::harness;
namespace fs = std::filesystem;

struct RecordCliOptions {
  std::string input, out, name, paragraph;
};

int run_record(const RecordCliOptions& o) {
  std::ifstream in(o.input, std::ios::binary);
  if (!in) {
    std::cerr << "sabus record: cannot read " << o.input << "\n";
    return kExitUsage;
  }
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string error;
  auto capture = read_capture(text, error);
  if (!capture) {
    std::cerr << "sabus record: " << o.input << ": " << error << "\n";
    return kExitUsage;
  }
  RecordOptions ro;
  ro.name = o.name.empty() ? fs::path(o.out).stem().string() : o.name;
  ro.paragraph = o.paragraph;
  ro.source = fs::path(o.input).filename().string();
  auto rec = record_vectors(*capture, ro, error);
  if (!rec) {
    std::cerr << "sabus record: " << o.input << ": " << error << "\n";
    return kExitFailed;
  }
  // The same checks as `sabus vectors lint`, on the text about to be written.
  LoadResult loaded = load_vector_text(rec->yaml, o.out);
  auto errors = loaded.errors;
  auto more = lint(loaded.files);
  errors.insert(errors.end(), more.begin(), more.end());
  if (!errors.empty()) {
    for (const auto& e : errors) std::cerr << e.text() << "\n";
    std::cerr << "sabus record: the recording does not pass the vector lint; " << o.out << " not written\n";
    return kExitFailed;
  }
  const fs::path dir = fs::path(o.out).parent_path();
  std::error_code ec;
  if (!dir.empty() && !fs::create_directories(dir, ec) && ec) {
    std::cerr << "sabus record: cannot make the folder " << dir.string() << ": " << ec.message() << "; " << o.out
              << " not written\n";
    return kExitUsage;
  }
  // Written whole or not at all, and never through a device or a link to one
  // (the reports' file writer).
  if (std::string why; !reports::write_file(o.out, rec->yaml, why)) {
    std::cerr << "sabus record: " << why << "; " << o.out << " not written\n";
    return kExitUsage;
  }
  for (const auto& n : rec->notes) std::cout << "note: " << n << "\n";
  std::cout << fmt::format("recorded {} vector(s), {} step(s), paragraph {} from the {} {} into {}\n", rec->vectors,
                           rec->steps, rec->paragraph, to_string(capture->source), o.input, o.out);
  return kExitOk;
}

}  // namespace

Command add_record_command(CLI::App& app) {
  auto o = std::make_shared<RecordCliOptions>();
  CLI::App* sub = app.add_subcommand("record", "Turn a proxy log or a run JSON into regression vectors");
  sub->add_option("transcript", o->input, "A proxy log (sabus proxy --log) or a run JSON (sabus run --json)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--out", o->out, "The vector file to write, e.g. vectors/regression/NAME.yaml")->required();
  sub->add_option("--name", o->name, "Vector ids are PARAGRAPH-NAME-...; default: the --out file's stem");
  sub->add_option("--paragraph", o->paragraph,
                  "The file's paragraph (default: the command's for one command, else framing)");
  return {sub, [o] { return run_record(*o); }};
}

}  // namespace sabus::cli
