// Fuzz target: the device profile loader (vectors/profiles/*.yaml) on any text.
// Oracles: a malformed file gives an error that names where and why (never a
// crash, a hang or an unbounded allocation: the run's -malloc_limit_mb and
// -rss_limit_mb catch those); a file that loads writes back (to_yaml) as YAML
// that loads to an equal profile.
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "sabus/harness/profile_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto r = sabus::harness::load_profile_text(text, "fuzz.yaml");
  if (r.profile.has_value() == r.error.has_value()) std::abort();  // exactly one of the two
  if (r.error) {
    if (r.error->message.empty() || r.error->file != "fuzz.yaml") std::abort();  // an error must say why and where
    return 0;
  }
  const std::string yaml = sabus::harness::to_yaml(*r.profile);
  const auto again = sabus::harness::load_profile_text(yaml, "again.yaml");
  if (!again) {
    std::fprintf(stderr, "to_yaml output does not load: %s\n%s\n", again.error->text().c_str(), yaml.c_str());
    std::abort();
  }
  sabus::harness::Profile a = *r.profile, b = *again.profile;
  a.source = b.source = "";
  if (sabus::harness::to_yaml(a) != sabus::harness::to_yaml(b)) std::abort();  // the round trip changed the profile
  return 0;
}
