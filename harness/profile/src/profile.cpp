// Profiles for several controllers on one bus; navigation data as read.
#include "sabus/harness/profile.hpp"

#include <string>

namespace sabus::harness {

// §1 Address Character: every controller on a multi-drop RS-422 line has its
// own address; everything else is shared. The name gets the decimal address
// (the controller's own notation, ERRATA E-4) so reports tell them apart.
// The addresses are taken as given: the caller has parsed and checked them.
std::vector<Profile> bus_of(const Profile& profile) {
  if (profile.bus_peers.empty()) return {profile};
  Profile base = profile;
  base.bus_peers.clear();
  std::vector<std::uint8_t> addresses{profile.address};
  addresses.insert(addresses.end(), profile.bus_peers.begin(), profile.bus_peers.end());
  return multi_drop(base, addresses);
}

std::vector<Profile> multi_drop(const Profile& base, const std::vector<std::uint8_t>& addresses) {
  std::vector<Profile> out;
  out.reserve(addresses.size());
  for (std::uint8_t address : addresses) {
    Profile& p = out.emplace_back(base);
    p.address = address;
    p.name.push_back('-');
    p.name.append(std::to_string(address));
  }
  return out;
}

NavigationDataReply navigation_reply(const Navigation& n) {
  NavigationDataReply r;
  r.latlon_source = n.latlon_source;
  r.latitude = n.latitude_min;
  r.longitude = n.longitude_min;
  r.heading_source = n.heading_source;
  r.heading = n.heading_tenths;
  r.magvar_status = n.magvar_tenths ? 1 : 0;  // §3.22 byte 35: 41h ready, 40h not
  r.magvar = n.magvar_tenths;
  return r;
}

namespace {

// A slot's reply: empty (no index) unless the slot holds data, then its
// index and what `fill` copies of its data.
template <class Reply, class Slot, class Fill>
Reply slot_reply(const Slot* slot, Fill fill) {
  Reply r;
  r.index = std::nullopt;
  if (slot) {
    r.index = slot->index;
    fill(r, *slot);
  }
  return r;
}

}  // namespace

SatelliteDataReply satellite_reply(const PresetSatellite* slot) {
  return slot_reply<SatelliteDataReply>(slot, [](auto& r, const PresetSatellite& s) { r.sat = s.data; });
}

TleDataReply tle_reply(const TleSet* slot) {
  return slot_reply<TleDataReply>(slot, [](auto& r, const TleSet& s) {
    r.line1 = s.line1;
    r.line2 = s.line2;
  });
}

SignpostDataReply signpost_reply(const Signpost* slot) {
  return slot_reply<SignpostDataReply>(slot, [](auto& r, const Signpost& s) { r.signpost = s.data; });
}

}  // namespace sabus::harness
