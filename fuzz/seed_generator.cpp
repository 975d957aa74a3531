// Generates the seed corpora and dictionaries of the fuzz targets, so seeds
// follow the codecs and the vector suite instead of being copied by hand:
//   fuzz_seed_generator OUTDIR VECTORS_DIR
// writes OUTDIR/<target>/<name> and OUTDIR/<target>.dict:
//  - one seed per conformance vector (whatever vectors/ holds when it runs)
//    for the receiver, the whole-controller and the differential targets:
//    its send and poll steps (setup, steps, teardown) encoded as the runner
//    encodes them (step_bytes, then apply_modifiers, parity and parity flips);
//  - one seed per reply type (the codecs' defaults) and per vector reply
//    given as bytes, for the reply decoders;
//  - each vector file and each device profile, for the loaders;
//  - one tree text (vector_tree.hpp) per vector, its file's keys around it,
//    for the schema target;
//  - dictionaries from the catalog (fuzz_support.cpp dictionary_tokens) and,
//    for the YAML loaders and the schema target, every key the seed files use.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "fuzz_support.hpp"
#include "record_support.hpp"
#include "vector_tree.hpp"
#include "sabus/harness/faults.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/reports/writers.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"

namespace fs = std::filesystem;
using sabus::Bytes;
namespace harness = sabus::harness;

namespace {

void write(const fs::path& dir, const std::string& name, const Bytes& bytes) {
  fs::create_directories(dir);
  std::ofstream out(dir / name, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

std::string file_name(const std::string& id) {
  std::string s;
  for (char c : id) s.push_back(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_');
  return s;
}

// One of each reply type, as the codecs encode them.
template <std::size_t... I>
void reply_seeds(const fs::path& dir, std::index_sequence<I...>) {
  auto one = [&]<class T>(std::type_identity<T>) {
    if constexpr (requires { T::kKind; }) {
      for (const auto& info : sabus::catalog()) {
        if (info.reply != T::kKind) continue;
        const auto frame = sabus::reply_frame(sabus::Reply{T{}}, '2', info.code);
        const std::uint8_t selector = static_cast<std::uint8_t>(info.code - sabus::kFirstCommand);
        Bytes seed = {selector, 0};
        seed.insert(seed.end(), frame.value().data.begin(), frame.value().data.end());
        char name[32];
        std::snprintf(name, sizeof name, "reply-%02x", info.code);
        write(dir, name, seed);
      }
    }
  };
  (one(std::type_identity<std::variant_alternative_t<I, sabus::Reply>>{}), ...);
}

// fuzz_receiver's header: its options byte and byte 1 with the receiver's
// address, every seed also fed in pieces (kReceiverInPieces).
Bytes receiver_header(std::uint8_t options, std::uint8_t address) {
  return {options, static_cast<std::uint8_t>(sabus::fuzz::kReceiverInPieces | sabus::fuzz::receiver_address_knob(address))};
}

// One of each request, for the receiver (as 7-bit characters and on the wire).
template <std::size_t... I>
void request_seeds(const fs::path& dir, std::index_sequence<I...>) {
  auto one = [&]<class T>(std::type_identity<T>) {
    const Bytes frame = sabus::encode_request(sabus::Request{T{}}, '2');
    char name[32];
    std::snprintf(name, sizeof name, "request-%02x", T::kCode);
    write(dir, std::string(name) + "-chars", cat({receiver_header(0x06, '2'), frame}));
    write(dir, std::string(name) + "-wire", cat({receiver_header(0x07, '2'), sabus::add_even_parity(frame)}));
  };
  (one(std::type_identity<std::variant_alternative_t<I, sabus::Request>>{}), ...);
}

// The seeds of one vector.
struct VectorSeeds {
  Bytes wire;          // every send, as the runner puts it on the line
  Bytes structured;    // the differential target's encoding of its structured commands
  std::vector<Bytes> replies;  // expected replies given as bytes, for the decoders
};

std::size_t catalog_index(const sabus::CommandInfo* info) {
  return static_cast<std::size_t>(info - sabus::catalog().data());
}

VectorSeeds vector_seeds(const harness::Vector& v, std::uint8_t address) {
  VectorSeeds out;
  auto add_step = [&](const harness::Step& s) {
    if (s.kind == harness::Step::Kind::kWait) return;
    // The runner's step encoding: step_bytes (captured values, unknown
    // here, are blanks), then apply_modifiers, parity and parity flips as
    // the runner's exchange sends them.
    const auto chars = harness::step_bytes(s, address, {}, true);
    if (!chars) return;
    if (s.command) {
      const auto* info = sabus::find_command(s.command->command);
      if (info && sabus::build_request(*info, s.command->form, s.command->fields)) {
        // The differential target: command, form, then each field's value.
        out.structured.push_back(static_cast<std::uint8_t>(catalog_index(info)));
        std::size_t form = 0;
        for (std::size_t i = 0; i < info->forms.size(); ++i)
          if (info->forms[i].id == s.command->form) form = i;
        out.structured.push_back(static_cast<std::uint8_t>(form));
        for (const auto& name : sabus::request_field_names(*info, s.command->form)) {
          auto it = s.command->fields.find(name);
          if (it == s.command->fields.end() || it->second.size() >= 0x80) {
            out.structured.push_back(0x80);
          } else {
            out.structured.push_back(static_cast<std::uint8_t>(it->second.size()));
            out.structured.insert(out.structured.end(), it->second.begin(), it->second.end());
          }
        }
      }
    }
    Bytes wire = sabus::add_even_parity(harness::apply_modifiers(chars.value(), s.modifiers));
    for (auto p : s.modifiers.parity_flip)
      if (p < wire.size()) wire[p] ^= 0x80;
    out.wire.insert(out.wire.end(), wire.begin(), wire.end());
    if (s.expect.bytes) {
      auto r = harness::expand_raw_bytes(s.expect.bytes->hex, address);
      if (r && r.value().size() >= 5) out.replies.push_back(r.value());
    }
  };
  for (const auto* list : {&v.setup, &v.steps, &v.teardown})
    for (const auto& s : *list) add_step(s);
  return out;
}

// Keys ("name:") of YAML text, for the loaders' dictionary.
void yaml_keys(const std::string& text, std::set<std::string>& keys) {
  static const std::regex key(R"(([A-Za-z_][A-Za-z0-9_]*):)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), key); it != std::sregex_iterator(); ++it)
    keys.insert((*it)[1].str() + ":");
}

std::string dict_escape(const Bytes& b) {
  std::string s;
  char buf[8];
  for (std::uint8_t c : b) {
    if (c >= 0x20 && c < 0x7F && c != '"' && c != '\\') {
      s.push_back(static_cast<char>(c));
    } else {
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      s += buf;
    }
  }
  return s;
}

// The dictionary of a loader: every key, then the syntax of its input.
std::vector<sabus::fuzz::Token> key_tokens(const std::set<std::string>& keys, const char* what,
                                           std::initializer_list<const char*> syntax) {
  std::vector<sabus::fuzz::Token> out;
  for (const auto& k : keys) out.push_back({"key", Bytes(k.begin(), k.end())});
  for (const char* s : syntax) out.push_back({what, Bytes(s, s + std::char_traits<char>::length(s))});
  return out;
}

void write_dict(const fs::path& file, const std::vector<sabus::fuzz::Token>& tokens) {
  std::ofstream out(file);
  out << "# Generated by fuzz_seed_generator; do not edit.\n";
  std::set<std::string> seen;
  for (const auto& t : tokens) {
    const std::string entry = dict_escape(t.bytes);
    if (!seen.insert(entry).second) continue;
    out << "# " << t.comment << "\n\"" << entry << "\"\n";
  }
}

// A vector file's own keys (paragraph, title, requires, and notes when
// `notes`) with `key` (vectors or groups) set to `list`.
YAML::Node file_with(const YAML::Node& root, const char* key, const YAML::Node& list, bool notes) {
  YAML::Node f(YAML::NodeType::Map);
  for (const auto& e : root) {
    const std::string& k = e.first.Scalar();
    if (k != "groups" && k != "vectors" && (notes || k != "notes")) f.force_insert(e.first, e.second);
  }
  f.force_insert(key, list);
  return f;
}

YAML::Node list_of(const YAML::Node& one) {
  YAML::Node l(YAML::NodeType::Sequence);
  l.push_back(one);
  return l;
}

// One tree per vector of a vector file: the file with only that vector (in
// its group, with the group's keys, when it has one). The file's notes,
// which no vector's reading depends on, are in the first tree only: the
// smaller a seed, the faster the fuzzer runs its mutations.
std::vector<YAML::Node> vector_seed_trees(const YAML::Node& root) {
  std::vector<YAML::Node> out;
  auto list_at = [](const YAML::Node& map, const char* key) {  // const lookups: never insert
    const YAML::Node l = map.IsMap() ? map[key] : YAML::Node();
    return l.IsDefined() && l.IsSequence() ? l : YAML::Node(YAML::NodeType::Sequence);
  };
  for (const auto& v : list_at(root, "vectors")) out.push_back(file_with(root, "vectors", list_of(v), out.empty()));
  for (const auto& g : list_at(root, "groups")) {
    for (const auto& v : list_at(g, "vectors")) {
      YAML::Node group(YAML::NodeType::Map);
      for (const auto& e : g)
        if (e.first.Scalar() != "vectors") group.force_insert(e.first, e.second);
      group.force_insert("vectors", list_of(v));
      out.push_back(file_with(root, "groups", list_of(group), out.empty()));
    }
  }
  return out;
}

// The trees of vector_seed_trees as tree text: DIR/FILE-0, FILE-1, ...
void write_tree_seeds(const fs::path& dir, const std::string& file, const YAML::Node& root) {
  const auto trees = vector_seed_trees(root);
  for (std::size_t i = 0; i < trees.size(); ++i) {
    const std::string tree = sabus::fuzz::tree_text(trees[i]);
    write(dir, file + "-" + std::to_string(i), Bytes(tree.begin(), tree.end()));
  }
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

// What the reference controller answers to each command of fuzz_record's
// run, recorded as that target's script: the replies a transport passes on.
class RecordingTransport final : public harness::Transport {
 public:
  explicit RecordingTransport(harness::Transport& device) : device_(device) {}
  void send(sabus::ByteView chars, std::span<const std::size_t> wrong_parity) override {
    device_.send(chars, wrong_parity);
    script.replies.emplace_back();
  }
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override {
    const std::size_t n = device_.receive(buf, timeout);
    if (!script.replies.empty()) script.replies.back().insert(script.replies.back().end(), buf.begin(), buf.begin() + n);
    return n;
  }
  void pause(std::chrono::milliseconds d) override { device_.pause(d); }
  harness::TimePoint now() const override { return device_.now(); }
  bool in_process() const override { return true; }
  bool can_send_parity_errors() const override { return true; }
  int baud() const override { return 0; }
  std::string describe() const override { return device_.describe(); }
  sabus::fuzz::record::Script script;

 private:
  harness::Transport& device_;
};

// fuzz_record: the replies of the reference controller, clean and with each
// of its faults, to the target's run (the same options as the target's).
std::size_t record_seeds(const fs::path& dir) {
  namespace record = sabus::fuzz::record;
  std::vector<std::pair<std::string, harness::FaultSet>> devices = {{"clean", {}}};
  for (const auto& f : harness::all_faults()) {
    harness::FaultSet set;
    set.set(f.fault);
    devices.push_back({std::string(f.name), set});
  }
  for (const auto& [name, faults] : devices) {
    auto device = harness::make_in_process_transport(harness::bus_of(record::profile()), faults);
    RecordingTransport recording(*device);
    (void)sabus::reports::query_identity(recording, record::profile().address);
    harness::Runner(recording, record::profile(), record::run_options()).run(record::vectors());
    write(dir, "fault-" + file_name(name), record::script_input(recording.script));
    if (name == "clean") {  // the device lost half way: the run aborted
      record::Script lost = recording.script;
      lost.lost_at = lost.replies.size() / 2;
      write(dir, "lost-half-way", record::script_input(lost));
    }
  }
  return devices.size() + 1;
}

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: fuzz_seed_generator OUTDIR VECTORS_DIR\n");
    return 2;
  }
  const fs::path out = argv[1];
  const fs::path vectors_dir = argv[2];
  reply_seeds(out / "fuzz_reply_decoders", std::make_index_sequence<std::variant_size_v<sabus::Reply>>{});
  request_seeds(out / "fuzz_receiver", std::make_index_sequence<std::variant_size_v<sabus::Request>>{});
  // Framing cases for the receiver: bad LRC, STX STX, a check byte of 02h.
  const Bytes poll = sabus::encode_request(sabus::StatusPoll{}, '2');
  Bytes bad = poll;
  bad.back() ^= 1;
  write(out / "fuzz_receiver", "framing-bad-lrc", cat({receiver_header(0x06, '2'), bad, poll}));
  write(out / "fuzz_receiver", "framing-stx-stx", cat({receiver_header(0x06, '2'), {sabus::STX}, poll}));
  write(out / "fuzz_receiver", "framing-noise", cat({receiver_header(0x06, 0x6F), {0x41, 0x42, 0x03, 0x7f}, poll}));

  // One seed per vector of the suite, whatever it holds now. A file that
  // does not load is reported and left out; the rest still give seeds.
  const auto& profiles = sabus::fuzz::profiles();
  const auto loaded = harness::load_vectors({vectors_dir.string()});
  for (const auto& e : loaded.errors) std::fprintf(stderr, "seed generator: skipped: %s\n", e.text().c_str());
  std::size_t vectors = 0, replies = 0;
  std::set<std::string> keys;
  for (const auto& file : loaded.files) {
    const std::string text = read_text(file.path);
    const std::string leaf = file_name(fs::path(file.path).filename().string());
    write(out / "fuzz_vector_loader", leaf, Bytes(text.begin(), text.end()));
    yaml_keys(text, keys);
    write_tree_seeds(out / "fuzz_vector_schema", leaf, YAML::Load(text));  // the file loaded: it parses
    for (const auto& v : file.vectors) {
      // The first profile (by name) the vector can run on, as the runner would pick.
      std::size_t p = 0;
      while (p < profiles.size() && !harness::requirements_hold(profiles[p], v.requires_)) ++p;
      if (p == profiles.size()) p = 0;
      const std::uint8_t address = profiles[p].address;
      const VectorSeeds s = vector_seeds(v, address);
      const std::string name = file_name(v.id);
      if (!s.wire.empty()) {
        write(out / "fuzz_controller", name, cat({{static_cast<std::uint8_t>(p), 5}, s.wire}));
        write(out / "fuzz_receiver", "vector-" + name, cat({receiver_header(0x07, address), s.wire}));
      }
      if (!s.structured.empty()) write(out / "fuzz_differential", name, cat({{static_cast<std::uint8_t>(p)}, s.structured}));
      for (std::size_t i = 0; i < s.replies.size(); ++i) {
        const Bytes& r = s.replies[i];
        const auto* info = sabus::find_command(r[2]);
        if (!info) continue;
        Bytes seed = {static_cast<std::uint8_t>((info->code - sabus::kFirstCommand) | (r[0] == sabus::NAK ? 0x80 : 0)), 0};
        seed.insert(seed.end(), r.begin() + 3, r.end() - 2);
        write(out / "fuzz_reply_decoders", name + "-reply" + std::to_string(i), seed);
        ++replies;
      }
      ++vectors;
    }
  }
  for (std::size_t i = 0; i < sabus::fuzz::kEmbeddedProfileCount; ++i) {
    const std::string text = sabus::fuzz::kEmbeddedProfiles[i].yaml;
    write(out / "fuzz_profile_loader", file_name(sabus::fuzz::kEmbeddedProfiles[i].name), Bytes(text.begin(), text.end()));
    yaml_keys(text, keys);
  }
  const std::size_t records = record_seeds(out / "fuzz_record");
  // The differential target needs at least one seed even with no vectors.
  write(out / "fuzz_differential", "status-poll", {0, 1, 0});

  const auto tokens = sabus::fuzz::dictionary_tokens();
  for (const char* t : {"fuzz_receiver", "fuzz_controller", "fuzz_reply_decoders", "fuzz_differential", "fuzz_record"})
    write_dict(out / (std::string(t) + ".dict"), tokens);
  const auto yaml = key_tokens(keys, "YAML syntax", {"- ", "{", "}", "[", "]", "\"", "'", "&a", "*a", "!!str", "---", "|", ">", "#", "0x"});
  write_dict(out / "fuzz_vector_loader.dict", yaml);
  write_dict(out / "fuzz_profile_loader.dict", yaml);
  write_dict(out / "fuzz_vector_schema.dict",
             key_tokens(keys, "tree text", {"{", "}", "[", "]", ": ", ", ", "\"", "'", "~", "*0", "*1", "any", "true", "{addr}", "{lrc}"}));
  std::printf("seed corpora written to %s: %zu vectors, %zu vector replies, %zu recorded runs, %zu files skipped\n",
              out.c_str(), vectors, replies, records, loaded.errors.size());
  return 0;
}
