// `sabus vectors lint|list`: checks the conformance vector suite (vectors/*.yaml)
// and lists its vectors. The loader and linter are sabus::vectors
// (vector_loader.hpp); this file only prints.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "commands.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace sabus::cli {
namespace {

using harness::LoadError;
using harness::LoadResult;
using harness::Vector;

struct VectorsOptions {
  std::vector<std::string> paths;
  bool json = false;
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
  return {sub, [opts, lint] { return lint->parsed() ? run_lint(*opts) : run_list(*opts); }};
}

}  // namespace sabus::cli
