// The document layer of the vector loader (vectors/*.yaml; its keys are
// vector_schema.hpp's table, worked examples vectors/README.md): one file read
// strictly (yaml_reader.hpp: every key checked, duplicates found, marks
// kept) into its notes, groups and vectors, each vector's error kept apart
// from the others'. The steps of a
// vector are the step schema's (vector_steps.cpp), which checks each send
// against the command catalog and the codecs; what needs the whole suite or
// the errata is lint()'s (vector_lint.cpp).
#include "sabus/harness/vector_loader.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <tuple>

#include "sabus/harness/data_dir.hpp"
#include "sabus/harness/expressions.hpp"
#include "sabus/harness/vector_schema.hpp"
#include "vector_loader_internal.hpp"

namespace sabus::harness::vector_loader_internal {
namespace {

// Files that follow one behaviour through several paragraphs rather than
// testing one paragraph: their vectors may cite any paragraph.
constexpr std::string_view kCrossCutting[] = {"framing", "ignore",    "nak",   "offline",
                                              "parity",  "multidrop", "timing", "pacing"};

std::string level_names() {
  std::string out;
  for (const auto& level : kLevels) out += (out.empty() ? "" : ", ") + std::string(level.first);
  return out;
}

std::string to_text(const YAML::Node& v, const At& at, std::size_t max) {
  const std::string& s = scalar(v, at, "text");
  if (s.empty()) fail(at, "must not be empty");
  if (s.size() > max) fail(at, "has " + std::to_string(s.size()) + " characters, at most " + std::to_string(max));
  return s;
}

Level to_level(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a level");
  for (const auto& [name, level] : kLevels)
    if (s == name) return level;
  fail(at, quoted_clip(s) + " is not a level: " + level_names() + " (READING-NOTES \"Result levels\")");
}

std::vector<std::string> to_names(const YAML::Node& v, const At& at, bool (*valid)(std::string_view), std::string_view what) {
  std::vector<std::string> out;
  for_each_element(v, at, kMaxEntries, [&](const YAML::Node& e, const At& ea) {
    const std::string& s = scalar(e, ea, what);
    if (!valid(s)) fail(ea, quoted_clip(s) + " is not " + std::string(what));
    if (contains(out, s)) fail(ea, quoted_clip(s) + " is listed twice");
    out.push_back(s);
  });
  return out;
}

std::vector<std::string> merged(std::vector<std::string> a, const std::vector<std::string>& b) {
  for (const auto& s : b)
    if (!contains(a, s)) a.push_back(s);
  return a;
}

// What a group gives each of its vectors.
struct GroupDefaults {
  std::vector<Requirement> requires_;
  std::vector<std::string> needs;
  std::vector<Step> setup, teardown;
  std::vector<std::string> tags, flags;
  std::optional<Level> level;
  Captures captures;  // captured by the group's setup
};

// `needs`: profile expressions that must be available on the device's
// profile ("{store_room('SABUS TEST')}"); their values are not used. They
// read no capture: they are decided before the vector runs.
std::vector<std::string> read_needs(const YAML::Node& v, const At& at) {
  std::vector<std::string> out;
  for_each_element(v, at, kMaxValues, [&](const YAML::Node& e, const At& ea) {
    const std::string& s = scalar(e, ea, "a profile expression");
    if (!has_placeholder(s)) fail(ea, quoted_clip(s) + " is not a profile expression: write \"{...}\"");
    if (auto err = check_template(s, {})) fail(ea, *err + " (needs are decided before the vector runs: no captures)");
    if (!contains(out, s)) out.push_back(s);
  });
  return out;
}

void read_spec(const YAML::Node& v, const At& at, const FileInfo& file, Vector& vec) {
  MapReader r(v, at, schema_keys(SchemaNode::kSpec));
  require_keys(r, at, {"paragraph", "quote"}, "spec");
  r.with("paragraph", [&](const YAML::Node& n, const At& a) {
    vec.paragraph = scalar(n, a, "a paragraph");
    if (!is_spec_paragraph(vec.paragraph))
      fail(a, quoted_clip(vec.paragraph) + " is not a paragraph of the spec (1, 2, 3, 4, 3.1 ... 3.25)");
    if (!file.cross_cutting && vec.paragraph != file.paragraph)
      fail(a, "the file is about §" + file.paragraph + "; only cross-cutting files (" + joined(kCrossCutting) +
                  ") cite other paragraphs");
  });
  r.read("quote", vec.quote, [](const YAML::Node& n, const At& a) { return to_text(n, a, kMaxQuote); });
}

// The id as written, so that an error found before it is read (a duplicate
// key, an unknown key) still names the vector.
std::string peek_id(const YAML::Node& v) {
  if (!v.IsMap()) return "";
  const YAML::Node id = v["id"];  // const lookup: never inserts; invalid when absent
  return id.IsDefined() && id.IsScalar() && is_id_text(id.Scalar()) ? id.Scalar() : "";
}

Vector read_vector(const YAML::Node& v, const At& at, const FileInfo& file, const GroupDefaults& g, std::string& id) {
  file.spend(at);
  id = peek_id(v);
  MapReader r(v, at, schema_keys(SchemaNode::kVector));
  Vector vec;
  vec.where = file.loc(at.mark);
  require_keys(r, at, {"id"}, "a vector");
  r.with("id", [&](const YAML::Node& n, const At& a) {
    const std::string& text = scalar(n, a, "an id");
    if (!is_id_text(text)) fail(a, quoted_clip(text) + " is not an id: letters, digits, '.', '-', '_', ':'");
    vec.id = id = text;
    if (vec.id.rfind(file.paragraph + "-", 0) != 0) fail(a, "an id in this file starts with \"" + file.paragraph + "-\"");
  });
  require_keys(r, at, {"comment", "spec", "steps"}, "a vector");
  r.read("comment", vec.comment, [](const YAML::Node& n, const At& a) { return to_text(n, a, kMaxText); });
  r.with("spec", [&](const YAML::Node& n, const At& a) { read_spec(n, a, file, vec); });
  if (!r.has("level") && !g.level) fail_missing(at, "level", "a vector needs level (must, should or informative), here or in its group");
  vec.level = g.level.value_or(Level::kMust);
  r.read("level", vec.level, to_level);
  std::vector<std::string> flags, tags;
  r.read("flags", flags, [](const YAML::Node& n, const At& a) { return to_names(n, a, is_flag_name, "a flag name"); });
  r.read("tags", tags, [](const YAML::Node& n, const At& a) { return to_names(n, a, is_tag_text, "a tag"); });
  vec.flags = merged(g.flags, flags);
  vec.tags = merged(g.tags, tags);
  vec.requires_ = file.requires_;
  vec.requires_.insert(vec.requires_.end(), g.requires_.begin(), g.requires_.end());
  r.with("requires", [&](const YAML::Node& n, const At& a) {
    auto own = read_requires(n, a, file);
    vec.requires_.insert(vec.requires_.end(), own.begin(), own.end());
  });
  vec.needs = merged(file.needs, g.needs);
  r.with("needs", [&](const YAML::Node& n, const At& a) { vec.needs = merged(vec.needs, read_needs(n, a)); });
  StepContext cx{file, g.captures};
  vec.setup = g.setup;
  r.with("setup", [&](const YAML::Node& n, const At& a) {
    auto own = read_steps(n, a, cx);
    vec.setup.insert(vec.setup.end(), own.begin(), own.end());
  });
  StepContext steps_cx = cx;  // $slot is the steps' own: the teardown runs once, after every slot
  steps_cx.steps = true;
  r.with("each_slot", [&](const YAML::Node& n, const At& a) {
    vec.each_slot = scalar(n, a, "a stored list");
    if (!slot_what(vec.each_slot)) fail(a, quoted_clip(vec.each_slot) + " is not a stored list: " + slot_list_names());
    steps_cx.captures.insert("$slot");
  });
  r.read("steps", vec.steps, [&](const YAML::Node& n, const At& a) { return read_steps(n, a, steps_cx); });
  if (vec.steps.empty()) fail(r.at("steps"), "a vector needs at least one step");
  cx.captures = steps_cx.captures;  // the teardown reads what the steps captured (the last slot's)
  if (!vec.each_slot.empty()) cx.captures.erase("$slot");
  cx.teardown = true;
  r.read("teardown", vec.teardown, [&](const YAML::Node& n, const At& a) { return read_steps(n, a, cx); });
  vec.teardown.insert(vec.teardown.end(), g.teardown.begin(), g.teardown.end());
  return vec;
}

LoadError to_error(const std::string& file, const Failure& f, const std::string& id) {
  return LoadError{SourceLocation{file, one_based(f.at.mark.line), one_based(f.at.mark.column)}, id, f.at.path, f.message};
}

// One vector's error does not stop the others: each is read on its own, with
// paths relative to it ("steps[1].send.command") and its id in the error.
void read_vector_list(const YAML::Node& v, const At& at, const FileInfo& file, const GroupDefaults& g,
                      std::vector<Vector>& out, std::vector<LoadError>& errors) {
  for_each_element(v, at, kMaxVectors, [&](const YAML::Node& e, const At& ea) {
    std::string id;
    try {
      out.push_back(read_vector(e, At{"", ea.mark}, file, g, id));
    } catch (const Failure& f) {
      errors.push_back(to_error(file.name, f, id));
    }
  });
  if (v.size() == 0) fail(at, "no vector given");
}

void read_group(const YAML::Node& v, const At& at, const FileInfo& file, std::vector<Vector>& out,
                std::vector<LoadError>& errors) {
  MapReader r(v, at, schema_keys(SchemaNode::kGroup));
  require_keys(r, at, {"vectors"}, "a group");
  GroupDefaults g;
  r.with("comment", [](const YAML::Node& n, const At& a) { to_text(n, a, kMaxText); });
  r.read("requires", g.requires_, [&](const YAML::Node& n, const At& a) { return read_requires(n, a, file); });
  r.read("needs", g.needs, read_needs);
  r.read("tags", g.tags, [](const YAML::Node& n, const At& a) { return to_names(n, a, is_tag_text, "a tag"); });
  r.read("flags", g.flags, [](const YAML::Node& n, const At& a) { return to_names(n, a, is_flag_name, "a flag name"); });
  r.with("level", [&](const YAML::Node& n, const At& a) { g.level = to_level(n, a); });
  StepContext cx{file, {}};
  r.read("setup", g.setup, [&](const YAML::Node& n, const At& a) { return read_steps(n, a, cx); });
  g.captures = cx.captures;
  // A group's teardown runs after each vector's steps but may only use what
  // the group's own setup captured: it cannot know any one vector's.
  cx.teardown = true;
  r.read("teardown", g.teardown, [&](const YAML::Node& n, const At& a) { return read_steps(n, a, cx); });
  r.with("vectors", [&](const YAML::Node& n, const At& a) { read_vector_list(n, a, file, g, out, errors); });
}

// "E-7": the form of an ERRATA.md entry id (that it exists is lint's check).
std::string to_errata_ref(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "an errata entry (E-7)");
  std::size_t n = 0;
  if (s.size() < 3 || s.size() > 6 || s.compare(0, 2, "E-") != 0 || s[2] == '0' || !parse_whole(std::string_view(s).substr(2), n))
    fail(at, quoted_clip(s) + " is not an errata entry id like E-7 (protocol/ERRATA.md)");
  return s;
}

std::map<std::string, Note> read_notes(const YAML::Node& v, const At& at, const FileInfo& file) {
  std::map<std::string, Note> notes;
  for_each_entry(v, at, kMaxEntries, [&](const std::string& flag, const YAML::Node& value, const At& fa) {
    if (!is_flag_name(flag)) fail(fa, quoted_clip(flag) + " is not a flag name: a letter, then letters, digits, '_'");
    MapReader r(value, fa, schema_keys(SchemaNode::kNote));
    require_keys(r, fa, {"description"}, "a note");
    Note n;
    r.read("description", n.description, [](const YAML::Node& d, const At& a) { return to_text(d, a, kMaxText); });
    r.read("errata", n.errata, to_errata_ref);
    n.where = file.loc(fa.mark);
    notes.emplace(flag, std::move(n));
  });
  return notes;
}

std::string to_file_paragraph(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a paragraph");
  if (!is_spec_paragraph(s) && !contains(kCrossCutting, s))
    fail(at, quoted_clip(s) + " is neither a spec paragraph (3.2) nor a cross-cutting topic (" + joined(kCrossCutting) + ")");
  return s;
}

void read_file(const YAML::Node& root, FileInfo& info, VectorFile& f, std::vector<LoadError>& errors) {
  const At at{"", root.Mark()};
  if (root.IsNull()) fail(at, "an empty file: a vector file needs paragraph, title and vectors");
  MapReader r(root, at, schema_keys(SchemaNode::kFile));
  require_keys(r, at, {"paragraph", "title"}, "a vector file");
  if (!r.has("groups") && !r.has("vectors")) fail_missing(at, "vectors", "a vector file needs vectors or groups");
  r.read("paragraph", f.paragraph, to_file_paragraph);
  r.read("title", f.title, [](const YAML::Node& n, const At& a) { return to_text(n, a, kMaxText); });
  r.read("notes", f.notes, [&](const YAML::Node& n, const At& a) { return read_notes(n, a, info); });
  info.paragraph = f.paragraph;
  info.cross_cutting = contains(kCrossCutting, f.paragraph);
  r.read("requires", info.requires_, [&](const YAML::Node& n, const At& a) { return read_requires(n, a, info); });
  r.read("needs", info.needs, read_needs);
  r.with("groups", [&](const YAML::Node& n, const At& a) {
    for_each_element(n, a, kMaxGroups, [&](const YAML::Node& g, const At& ga) {
      try {
        read_group(g, ga, info, f.vectors, errors);
      } catch (const Failure& fl) {
        errors.push_back(to_error(info.name, fl, ""));
      }
    });
  });
  r.with("vectors", [&](const YAML::Node& n, const At& a) { read_vector_list(n, a, info, GroupDefaults{}, f.vectors, errors); });
}

LoadError file_error(const std::string& file, std::string message) {
  return LoadError{SourceLocation{file, 0, 0}, "", "", std::move(message)};
}

bool by_position(const LoadError& a, const LoadError& b) {
  return std::tie(a.where.file, a.where.line, a.where.column) < std::tie(b.where.file, b.where.line, b.where.column);
}

// Runs read(), turning whatever it throws into an error of the file: the
// loader never throws.
template <class F>
void catching(const std::string& name, std::vector<LoadError>& errors, F&& read) {
  try {
    read();
  } catch (const Failure& f) {
    errors.push_back(to_error(name, f, ""));
  } catch (const OverBudget& o) {
    errors.push_back(to_error(name, Failure{o.at, "more than " + std::to_string(kWorkBudget) +
                                                      " units of checking (a vector, step or matcher is one, a regex or a"
                                                      " requirement value ten; an alias counts each time); split the file"}, ""));
  } catch (const YAML::Exception& e) {  // syntax errors, including DeepRecursion
    errors.push_back({SourceLocation{name, one_based(e.mark.line), one_based(e.mark.column)}, "", "", "YAML syntax: " + e.msg});
  } catch (const std::exception& e) {  // bad_alloc and anything else: never out of the loader
    errors.push_back(file_error(name, std::string("cannot read the file: ") + e.what()));
  }
}

}  // namespace
}  // namespace sabus::harness::vector_loader_internal

namespace sabus::harness {

using namespace vector_loader_internal;

LoadResult load_vector_tree(const YAML::Node& root, const std::string& name) {
  LoadResult result;
  std::size_t work = 0;
  FileInfo info{name, "", false, {}, {}, &work};
  VectorFile file;
  file.path = name;
  catching(name, result.errors, [&] { read_file(root, info, file, result.errors); });
  std::stable_sort(result.errors.begin(), result.errors.end(), by_position);
  if (result.errors.empty()) result.files.push_back(std::move(file));
  return result;
}

LoadResult load_vector_text(const std::string& yaml, const std::string& name) {
  LoadResult result;
  if (yaml.size() > kMaxFileBytes) {
    result.errors.push_back(file_error(name, "larger than " + std::to_string(kMaxFileBytes) + " bytes"));
    return result;
  }
  YAML::Node root;
  catching(name, result.errors, [&] {
    require_single_document(yaml, "a vector file");
    root = YAML::Load(yaml);
  });
  if (!result.errors.empty()) return result;
  return load_vector_tree(root, name);
}

LoadResult load_vector_file(const std::string& path) {
  std::string error;
  auto text = read_capped(path, kMaxFileBytes, error);
  if (!text) return LoadResult{{}, {file_error(path, error)}};
  return load_vector_text(*text, path);
}

LoadResult load_vectors(const std::vector<std::string>& paths) {
  namespace fs = std::filesystem;
  LoadResult result;
  std::vector<std::string> files;
  for (const auto& p : paths) {
    std::error_code ec;
    if (!fs::is_directory(p, ec)) {
      files.push_back(p);  // a missing file is reported by load_vector_file
      continue;
    }
    std::vector<std::string> found;
    for (auto it = fs::recursive_directory_iterator(p, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      const fs::path& path = it->path();
      const std::string leaf = path.filename().string();
      // Not vector files: profiles/ and examples/. regression/ holds vectors
      // recorded from one controller (`sabus record`), not conformance: run
      // them by naming the folder or a file (vectors/README.md).
      if (it->is_directory(ec) && (leaf == "profiles" || leaf == "examples" || leaf == "regression"))
        it.disable_recursion_pending();
      else if (path.extension() == ".yaml" && it->is_regular_file(ec)) found.push_back(path.string());
    }
    if (ec) result.errors.push_back(file_error(p, "cannot list: " + ec.message()));
    std::sort(found.begin(), found.end());
    files.insert(files.end(), found.begin(), found.end());
  }
  for (const auto& f : files) {
    LoadResult one = load_vector_file(f);
    for (auto& vf : one.files) result.files.push_back(std::move(vf));
    for (auto& e : one.errors) result.errors.push_back(std::move(e));
  }
  return result;
}

std::string default_vectors_dir() { return data_path("vectors"); }

}  // namespace sabus::harness
