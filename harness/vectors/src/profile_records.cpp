// A profile's stored data as requests and replies (profile_records.hpp).
#include "sabus/harness/profile_records.hpp"

#include <algorithm>
#include <cstdlib>

namespace sabus::harness {
namespace {

template <class T>
const T* slot_of(const std::vector<T>& list, std::uint32_t index) {
  const auto it = std::find_if(list.begin(), list.end(), [&](const T& e) { return e.index == index; });
  return it == list.end() ? nullptr : &*it;
}

// §3.23 writes degrees and minutes as one integer: sddmm / sdddmm.
std::int32_t ddmm(std::int32_t minutes) {
  return (minutes < 0 ? -1 : 1) * (std::abs(minutes) / 60 * 100 + std::abs(minutes) % 60);
}

}  // namespace

bool takes_profile_record(std::uint8_t code) {
  switch (code) {
    case 0x35: case 0x39: case 0x3A: case 0x3B: case 0x3C: case 0x43: case 0x44: case 0x45: case 0x46: return true;
    default: return false;
  }
}

long long max_record_index(std::uint8_t code) {
  switch (code) {
    case 0x35: return 50;
    case 0x3B: case 0x3C: return 10;
    default: return 20;
  }
}

bool record_is_indexed(std::uint8_t code) { return takes_profile_record(code) && code != 0x45 && code != 0x46; }

RecordRequest profile_write(const Profile& p, std::uint8_t code, std::uint32_t index) {
  switch (code) {
    case 0x39:
      if (const auto* s = slot_of(p.presets, index)) return {WriteSatellite{index, s->data}, {}};
      return {std::nullopt, "preset satellite " + std::to_string(index) + " stored in the profile"};
    case 0x3B:
      if (const auto* t = slot_of(p.tles, index)) return {WriteTle{index, t->line1, t->line2}, {}};
      return {std::nullopt, "TLE " + std::to_string(index) + " stored in the profile"};
    case 0x43:
      if (const auto* s = slot_of(p.signposts, index)) return {WriteSignpost{index, s->data}, {}};
      return {std::nullopt, "signpost " + std::to_string(index) + " stored in the profile"};
    case 0x46: {
      const Navigation& n = p.navigation;
      if (!n.latitude_min || !n.longitude_min || !n.heading_tenths)
        return {std::nullopt, "navigation data (latitude, longitude and heading) in the profile"};
      return {WriteNavigation{ddmm(*n.latitude_min), ddmm(*n.longitude_min), *n.heading_tenths, ""}, {}};
    }
    default: return {std::nullopt, "a command that writes stored data"};
  }
}

RecordReply profile_read_reply(const Profile& p, std::uint8_t code, std::uint32_t index) {
  switch (code) {
    case 0x35:  // the STORE list's entry `index` and the number of entries (§3.6)
      if (index >= 1 && index <= p.store.size())
        return {QueryNameReply{index, static_cast<std::uint32_t>(p.store.size()), p.store[index - 1].name}, {}};
      return {std::nullopt, "STORE entry " + std::to_string(index) + " in the profile"};
    case 0x3A: return {satellite_reply(slot_of(p.presets, index)), {}};  // empty: 7Fh 7Fh (READING-NOTES 18)
    case 0x3C: return {tle_reply(slot_of(p.tles, index)), {}};
    case 0x44: return {signpost_reply(slot_of(p.signposts, index)), {}};
    case 0x45: return {navigation_reply(p.navigation), {}};
    default: return {std::nullopt, "a command that reads stored data"};
  }
}

}  // namespace sabus::harness
