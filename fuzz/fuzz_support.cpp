// Shared parts of the fuzz targets (fuzz_support.hpp).
#include "fuzz_support.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <set>

#include "sabus/harness/profile_loader.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"

namespace sabus::fuzz {

const std::vector<harness::Profile>& profiles() {
  static const std::vector<harness::Profile> all = [] {
    std::vector<harness::Profile> v;
    for (std::size_t i = 0; i < kEmbeddedProfileCount; ++i) {
      auto r = harness::load_profile_text(kEmbeddedProfiles[i].yaml, kEmbeddedProfiles[i].name);
      if (!r) {
        std::fprintf(stderr, "embedded profile: %s\n", r.error->text().c_str());
        std::abort();
      }
      v.push_back(*r.profile);
    }
    if (v.empty()) v.emplace_back();
    return v;
  }();
  return all;
}

bool controller_stream_is_wire(const std::uint8_t*) { return true; }

void parse_controller_input(const std::uint8_t* data, std::size_t size, ControllerInput& out) {
  const auto& all = profiles();
  const std::uint8_t profile = size > 0 ? data[0] : 0, step = size > 1 ? data[1] : 0;
  out.profile = &all[profile % all.size()];
  out.step = std::chrono::milliseconds(20 * step);
  out.chunks.clear();
  if (size <= kControllerHeader) return;
  const ByteView stream(data + kControllerHeader, size - kControllerHeader);
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= stream.size(); ++i) {
    if (i == stream.size() || (stream[i] & 0x7F) == STX) {
      out.chunks.push_back(stream.subspan(begin, i - begin));
      begin = i;
    }
  }
}

}  // namespace sabus::fuzz
