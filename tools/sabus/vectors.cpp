// `sabus vectors lint|list|coverage`: checks the conformance vector suite
// (vectors/*.yaml), lists its vectors and prints its coverage matrix. The loader and linter are sabus::vectors
// (vector_loader.hpp); this file only prints.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "commands.hpp"
#include "sabus/harness/coverage.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace sabus::cli {
namespace {

using harness::LoadError;
using harness::LoadResult;
using harness::Vector;

struct VectorsOptions {
  std::vector<std::string> paths;
  bool json = false;
  bool missing_only = false;
};

LoadResult load(const VectorsOptions& o) {
  return harness::load_vectors(o.paths.empty() ? std::vector<std::string>{harness::default_vectors_dir()} : o.paths);
}

// Files seen: loaded ones and those that failed (each error names its file).
std::size_t file_count(const LoadResult& r) {
  std::set<std::string> names;
  for (const auto& f : r.files) names.insert(f.path);
  for (const auto& e : r.errors) names.insert(e.where.file);
  return names.size();
}

std::size_t vector_count(const LoadResult& r) {
  std::size_t n = 0;
  for (const auto& f : r.files) n += f.vectors.size();
  return n;
}

int run_lint(const VectorsOptions& o) {
  LoadResult r = load(o);
  std::vector<LoadError> errors = r.errors;
  const auto more = harness::lint(r.files);
  errors.insert(errors.end(), more.begin(), more.end());
  for (const auto& e : errors) std::cout << e.text() << "\n";
  std::cout << fmt::format("{} files, {} vectors, {} errors\n", file_count(r), vector_count(r), errors.size());
  return errors.empty() ? kExitOk : kExitFailed;
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ",") + s;
  return out.empty() ? "-" : out;
}

nlohmann::json vector_json(const Vector& v) {
  nlohmann::json requires_ = nlohmann::json::object();
  for (const auto& r : v.requires_) requires_[r.key] = r.values;
  return {{"id", v.id},
          {"paragraph", v.paragraph},
          {"level", std::string(harness::to_string(v.level))},
          {"tags", v.tags},
          {"flags", v.flags},
          {"requires", requires_},
          {"file", v.where.file},
          {"line", v.where.line},
          {"steps", v.steps.size()}};
}

// One line a vector: id, paragraph, level, tags. Load errors go to stderr
// and make the exit status 1; the vectors that loaded are listed anyway.
int run_list(const VectorsOptions& o) {
  LoadResult r = load(o);
  for (const auto& e : r.errors) std::cerr << e.text() << "\n";
  if (o.json) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& f : r.files)
      for (const auto& v : f.vectors) out.push_back(vector_json(v));
    std::cout << out.dump(2) << "\n";
  } else {
    for (const auto& f : r.files)
      for (const auto& v : f.vectors)
        std::cout << fmt::format("{:<44} §{:<5} {:<12} {}\n", v.id, v.paragraph, harness::to_string(v.level), joined(v.tags));
  }
  return r.errors.empty() ? kExitOk : kExitFailed;
}

// The matrix command x form x path, one line a cell with its vector ids;
// exit 1 when a cell the spec defines has none (CoverageMatrix::missing).
int run_coverage(const VectorsOptions& o) {
  LoadResult r = load(o);
  for (const auto& e : r.errors) std::cerr << e.text() << "\n";
  if (!r.errors.empty()) return kExitUsage;
  const harness::CoverageMatrix m = harness::coverage(r.files);
  const auto missing = m.missing();
  if (o.json) {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& row : m.rows) {
      nlohmann::json cells = nlohmann::json::object();
      for (auto p : harness::kCoveragePaths) cells[std::string(to_string(p))] = row.ids[static_cast<std::size_t>(p)];
      rows.push_back({{"command", fmt::format("{:02X}h", row.command->code)},
                      {"key", row.command->key},
                      {"paragraph", row.command->paragraph},
                      {"form", row.form ? std::string(row.form->id) : std::string()},
                      {"cells", cells}});
    }
    std::cout << nlohmann::json{{"rows", rows}, {"unknown_codes", {{"nak", m.unknown_codes}}}, {"missing", missing}}.dump(2)
              << "\n";
  } else {
    std::size_t covered = 0, cells = 0;
    for (const auto& row : m.rows) {
      for (auto p : harness::kCoveragePaths) {
        const auto& ids = row.ids[static_cast<std::size_t>(p)];
        ++cells;
        covered += !ids.empty();
        if (o.missing_only) continue;
        std::cout << fmt::format("{:<36} §{:<5} {:<8} {:>3}  {}\n", harness::row_label(row), row.command->paragraph,
                                 to_string(p), ids.size(), ids.empty() ? "-" : fmt::format("{}", fmt::join(ids, " ")));
      }
    }
    if (!o.missing_only)
      std::cout << fmt::format("{:<36} §{:<5} {:<8} {:>3}  {}\n", "other codes", "3", "nak", m.unknown_codes.size(),
                               m.unknown_codes.empty() ? "-" : fmt::format("{}", fmt::join(m.unknown_codes, " ")));
    for (const auto& line : missing) std::cout << "MISSING " << line << "\n";
    std::cout << fmt::format("{} of {} cells covered; {} required cell(s) without a vector\n", covered, cells,
                             missing.size());
  }
  return missing.empty() ? kExitOk : kExitFailed;
}

}  // namespace

Command add_vectors_command(CLI::App& app) {
  auto opts = std::make_shared<VectorsOptions>();
  CLI::App* sub = app.add_subcommand("vectors", "Check and list the conformance vectors (vectors/*.yaml)");
  sub->require_subcommand(1);
  const std::string where = "vector files or directories (default: " + harness::default_vectors_dir() + ")";
  CLI::App* lint = sub->add_subcommand("lint", "Load and lint the vectors; print every error, then a summary");
  lint->add_option("paths", opts->paths, where)->check(CLI::ExistingPath);
  CLI::App* list = sub->add_subcommand("list", "List the vectors: id, paragraph, level, tags");
  list->add_option("paths", opts->paths, where)->check(CLI::ExistingPath);
  list->add_flag("--json", opts->json, "Print JSON");
  CLI::App* cov = sub->add_subcommand(
      "coverage", "Print the matrix command x form x path (ack/nak/offline/ignore) -> vector ids; exit 1 when a cell "
                  "the spec defines has no vector");
  cov->add_option("paths", opts->paths, where)->check(CLI::ExistingPath);
  cov->add_flag("--json", opts->json, "Print JSON");
  cov->add_flag("--missing", opts->missing_only, "Print only the cells without a vector");
  return {sub, [opts, lint, cov] {
            if (lint->parsed()) return run_lint(*opts);
            if (cov->parsed()) return run_coverage(*opts);
            return run_list(*opts);
          }};
}

}  // namespace sabus::cli
