// fuzz_record's vectors, device and input layout (record_support.hpp).
#include "record_support.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "fuzz_support.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus::fuzz::record {

// vectors/*.yaml, embedded by fuzz/CMakeLists.txt.
struct EmbeddedVectorFile {
  const char* name;
  const char* yaml;
};
extern const EmbeddedVectorFile kEmbeddedVectorFiles[];

const std::vector<harness::Vector>& vectors() {
  static const std::vector<harness::Vector> selected = [] {
    std::map<std::string, harness::Vector> by_id;
    for (const EmbeddedVectorFile* f = kEmbeddedVectorFiles; f->name; ++f) {
      const harness::LoadResult r = harness::load_vector_text(f->yaml, f->name);
      if (!r.ok()) throw std::runtime_error(std::string("fuzz_record: ") + r.errors.front().text());
      for (const auto& file : r.files)
        for (const auto& v : file.vectors) by_id.emplace(v.id, v);
    }
    std::vector<harness::Vector> out;
    for (const char* id : kVectorIds) {
      const auto it = by_id.find(id);
      if (it == by_id.end()) throw std::runtime_error(std::string("fuzz_record: the suite has no vector ") + id);
      out.push_back(it->second);
    }
    return out;
  }();
  return selected;
}

harness::RunOptions run_options() {
  harness::RunOptions options;
  options.keep_transcripts = false;
  options.backup_stored_data = false;
  options.repeat = 1;
  options.known_issues = {{kKnownIssueId, "a known issue of the scripted device"}};
  return options;
}

const harness::Profile& profile() {
  for (const auto& p : profiles())
    if (p.name == "rc3000-1.59") return p;
  throw std::runtime_error("fuzz_record: no profile rc3000-1.59 among the embedded ones");
}

Script parse_script(const std::uint8_t* data, std::size_t size) {
  Script s;
  if (size == 0) return s;
  s.true_7e1 = data[0] & kTrue7E1;
  for (std::size_t i = 1; i + 1 < size;) {
    const std::uint8_t flags = data[i];
    if ((flags & kLost) && !s.lost_at) s.lost_at = s.replies.size();
    const std::size_t length = std::min<std::size_t>(data[i + 1], size - i - 2);
    Bytes reply(data + i + 2, data + i + 2 + length);
    if (flags & kWithParity)
      for (auto& b : reply) b = with_even_parity(static_cast<std::uint8_t>(b & 0x7F));
    s.replies.push_back(std::move(reply));
    i += 2 + length;
  }
  return s;
}

Bytes script_input(const Script& s) {
  Bytes out{static_cast<std::uint8_t>(s.true_7e1 ? kTrue7E1 : 0)};
  for (std::size_t i = 0; i < s.replies.size(); ++i) {
    const Bytes& r = s.replies[i];
    const std::size_t length = std::min<std::size_t>(r.size(), 255);
    out.push_back(s.lost_at == i ? kLost : 0);
    out.push_back(static_cast<std::uint8_t>(length));
    out.insert(out.end(), r.begin(), r.begin() + static_cast<std::ptrdiff_t>(length));
  }
  return out;
}

}  // namespace sabus::fuzz::record
