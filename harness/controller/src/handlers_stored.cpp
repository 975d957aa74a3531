// The handlers of the controller's stored data: §3.6 Query Name (the STORE
// list), §3.10-§3.13 preset satellites and TLEs, §3.14 / §3.15 IESS, §3.19
// Remote Store, §3.20 / §3.21 signposts, §3.22 / §3.23 navigation data.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "handlers.hpp"
#include "sabus/harness/look_angles.hpp"

namespace sabus::harness {
namespace {

// A TLE line's own checksum (READING-NOTES 19): the last digit is the sum of
// the other digits, with '-' counting 1, modulo 10.
bool tle_checksum_ok(const std::string& line) {
  if (line.size() != 69 || line.back() < '0' || line.back() > '9') return false;
  int sum = 0;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    if (line[i] >= '0' && line[i] <= '9') sum += line[i] - '0';
    else if (line[i] == '-') sum += 1;
  }
  return sum % 10 == line.back() - '0';
}

double wrap_pol(double deg) { return deg > 90 ? deg - 180 : deg < -90 ? deg + 180 : deg; }

// ERRATA E-58 other-2: the polarization skew of a geostationary satellite
// seen from the site, atan(sin(satellite - site longitude) / tan(latitude)),
// to the tenth, in -90.0..90.0 (90.0 on the equator).
double polarization_skew_deg(const look::Site& site, double satellite_longitude_deg) {
  constexpr double kRad = 3.14159265358979323846 / 180;
  const double s = std::sin((satellite_longitude_deg - site.longitude_deg) * kRad);
  const double t = std::tan(site.latitude_deg * kRad);
  const double skew = std::abs(t) < 1e-12 ? (s < 0 ? -90.0 : 90.0) : std::atan(s / t) / kRad;
  return std::round(skew * 10) / 10;
}

// The slot a read of `index` answers from: `index` itself, or with `fault`
// (an index table off by one except at its ends) the next one, for every
// slot but the first and last of a list of `slots`.
std::size_t slot_read(const Controller& c, Fault fault, std::size_t index, std::size_t slots) {
  return c.faults().has(fault) && index > 1 && index < slots ? index + 1 : index;
}

// The reply to a read of slot `index` of `list` (3Ah, 3Ch, 44h): the slot's
// data by `make` (satellite_reply, tle_reply, signpost_reply) under the
// index asked for, or the empty slot's index when it holds none
// (READING-NOTES 18).
template <class List, class Make>
auto reply_to_read(const Controller& c, const List& list, std::uint32_t index, Make make) {
  const auto& slot = list[slot_read(c, Fault::kSlotReadShiftedInMiddle, index, list.size()) - 1];
  auto reply = make(slot ? &*slot : nullptr);
  reply.index = slot ? std::optional<std::uint8_t>(static_cast<std::uint8_t>(index)) : Handlers::empty_index(c);
  return reply;
}

// The slot a write of `index` stores into (39h, 3Bh, 43h): `index` itself, or
// slot 1 under the fault stores-into-first-slot.
std::size_t slot_written(const Controller& c, std::size_t index) {
  return c.faults().has(Fault::kStoresIntoFirstSlot) ? 1 : index;
}

}  // namespace

// ---- §3.6 Query Name --------------------------------------------------------------
Outcome Handlers::query_name(C& c, const QueryName& q) {
  const bool zero_based = c.faults_.has(Fault::kQueryNameZeroBased);
  const std::size_t first = zero_based ? 0 : 1;
  if (q.index < first || q.index - first >= c.state_.store.size())
    return nak(c, 0x35, NakRule::kQueryNameIndex, "index " + std::to_string(q.index));
  QueryNameReply r;
  r.index = q.index;
  r.total = static_cast<std::uint32_t>(c.state_.store.size()) + (c.faults_.has(Fault::kStoreCountOffByOne) ? 1 : 0);
  r.name = c.state_.store[slot_read(c, Fault::kStoreEntryShiftedInMiddle, q.index - first + 1, c.state_.store.size()) - 1].name;
  return ack(c, 0x35, r);
}

Outcome Handlers::write_iess(C& c, const WriteIess& w) {
  if (w.index < 1 || w.index > c.iess_.size()) return nak(c, 0x3D, NakRule::kIessIndex);
  c.iess_[w.index - 1] = w.payload;
  return stored(ack(c, 0x3D, AckReply{}));
}
Outcome Handlers::read_iess(C& c, const ReadIess& r) {
  if (r.index < 1 || r.index > c.iess_.size()) return nak(c, 0x3E, NakRule::kIessIndex);
  IessDataReply reply;
  const auto& slot = c.iess_[r.index - 1];
  if (slot) {
    reply.index = static_cast<std::uint8_t>(r.index);
    reply.payload = *slot;
  } else {
    reply.index = std::nullopt;
  }
  return ack(c, 0x3E, reply);
}

// ---- §3.10-§3.13 preset satellites and TLEs ---------------------------------------
Outcome Handlers::write_satellite(C& c, const WriteSatellite& w) {
  if (w.index < 1 || w.index > 20) return nak(c, 0x39, NakRule::kSatelliteIndex, "index " + std::to_string(w.index));
  if (!satellite_fields_ok(w.sat)) return nak(c, 0x39, NakRule::kSatelliteField);
  // ERRATA E-51: ephemeris data for the first 10 sets only; the other side stores the code.
  if (w.sat.ephemeris != '0' && w.index > 10 && !c.reads_other("E-51")) return nak(c, 0x39, NakRule::kEphemerisIndex);
  const std::size_t slot = slot_written(c, w.index);
  PresetSatellite p{static_cast<std::uint8_t>(slot), w.sat, false};
  if (const auto& old = c.state_.presets[slot - 1]) p.dual_band = old->dual_band;
  c.state_.presets[slot - 1] = p;
  return stored(ack(c, 0x39, AckReply{}, "preset " + std::to_string(w.index) + " written"));
}
Outcome Handlers::read_satellite(C& c, const ReadSatellite& r) {
  if (r.index < 1 || r.index > 20) return nak(c, 0x3A, NakRule::kSatelliteIndex, "index " + std::to_string(r.index));
  return ack(c, 0x3A, reply_to_read(c, c.state_.presets, r.index, satellite_reply));
}
std::optional<std::uint8_t> Handlers::empty_index(const C& c) {
  // READING-NOTES 18: 7Fh in both index bytes.
  return c.faults_.has(Fault::kEmptySlotZeros) ? std::optional<std::uint8_t>(0) : std::nullopt;
}
Outcome Handlers::write_tle(C& c, const WriteTle& w) {
  const std::uint32_t max = c.faults_.has(Fault::kTleIndexTo20) ? 20 : 10;
  if (w.index < 1 || w.index > max) return nak(c, 0x3B, NakRule::kTleIndex, "index " + std::to_string(w.index));
  if (c.profile_.nak_bad_tle_checksum && (!tle_checksum_ok(w.line1) || !tle_checksum_ok(w.line2)))
    return nak(c, 0x3B, NakRule::kTleChecksum);
  if (const std::size_t slot = slot_written(c, w.index); slot <= c.state_.tles.size())
    c.state_.tles[slot - 1] = TleSet{static_cast<std::uint8_t>(slot), w.line1, w.line2};
  return stored(ack(c, 0x3B, AckReply{}, "TLE " + std::to_string(w.index) + " written"));
}
Outcome Handlers::read_tle(C& c, const ReadTle& r) {
  if (r.index < 1 || r.index > 10) return nak(c, 0x3C, NakRule::kTleIndex, "index " + std::to_string(r.index));
  return ack(c, 0x3C, reply_to_read(c, c.state_.tles, r.index, tle_reply));
}

// ---- §3.19 Remote Store ----------------------------------------------------------------
Outcome Handlers::remote_store(C& c, const RemoteStore& s) {
  SatelliteData sat;
  if (s.preset.preset) {
    if (tens_malformed(c, s.preset)) return nak(c, 0x42, NakRule::kMalformedData, "tens digit 2 (E-29)");
    if (s.preset.index < 1 || s.preset.index > 20) return nak(c, 0x42, NakRule::kStoreIndex);
    const auto& p = c.state_.presets[s.preset.index - 1];
    if (!p) return nak(c, 0x42, NakRule::kStoreEmptyPreset);
    if (p->data.name.empty()) return nak(c, 0x42, NakRule::kStoreField, "a preset with no name");  // E-58
    sat = p->data;
  } else {
    if (!satellite_fields_ok(s.sat) || s.sat.name.empty()) return nak(c, 0x42, NakRule::kStoreField);
    if (lower_case_refused(c, s.sat.name)) return nak(c, 0x42, NakRule::kStoreField, "a lower-case name (E-68)");
    sat = s.sat;
  }
  // §3.6: stored names are in capital letters (ERRATA E-68).
  StoredSatellite entry{capitals(sat.name), c.state_.az.position, c.state_.el.position, 0, 0};
  if (c.profile_.pol_type != PolType::kCircular) {  // "not applicable if feed type is circular"
    const double pol = c.state_.pol.position;
    switch (s.pol_selection) {
      case 'C':
        // ERRATA E-66: the LOCATE must be "immediately prior"; the other side
        // takes no command in between, reads aside.
        // ERRATA E-83: one that ended in a range error counts on the other side only.
        if (!c.state_.last_located || (c.state_.located_out_of_range && !c.reads_other("E-83")) ||
            (c.reads_other("E-66") && c.state_.commands_since_locate > 0))
          return nak(c, 0x42, NakRule::kStoreNeedsLocate);
        entry.h_pol_deg = c.state_.last_located->pol_offset.value_or(0) / 10.0;
        // ERRATA E-58 other-2: H from the site and the satellite (the skew),
        // where the navigation data give a site and the satellite a longitude.
        if (c.reads_other_2("E-58") && c.state_.last_located->longitude)
          if (const auto site = look::site_of(c.state_.navigation, c.profile_.az_sensor, c.profile_.fluxgate_heading).site)
            entry.h_pol_deg = polarization_skew_deg(*site, *c.state_.last_located->longitude / 10.0);
        entry.v_pol_deg = wrap_pol(entry.h_pol_deg + 90);
        break;
      case 'S':
        if (!in_range(s.h_pos, -900, 900) || !in_range(s.v_pos, -900, 900)) return nak(c, 0x42, NakRule::kStoreField);
        entry.h_pol_deg = *s.h_pos / 10.0;
        entry.v_pol_deg = *s.v_pos / 10.0;
        break;
      // ERRATA E-58: the other position 90 deg away, folded into
      // -90.0..90.0; the other side puts V above H and keeps it unfolded.
      case 'H':
        entry.h_pol_deg = pol;
        entry.v_pol_deg = c.reads_other("E-58") ? pol + 90 : wrap_pol(pol + 90);
        break;
      default:  // 'V'
        entry.v_pol_deg = pol;
        entry.h_pol_deg = c.reads_other("E-58") ? pol - 90 : wrap_pol(pol - 90);
        break;
    }
  }
  auto it = std::find_if(c.state_.store.begin(), c.state_.store.end(),
                         [&](const StoredSatellite& x) { return x.name == entry.name; });
  // ERRATA E-65: a new name with the list full is NAKed at once, or (other
  // side) the STORE starts ("will be initiated") and ends STORE_LIST_FULL,
  // storing nothing.
  const bool full = it == c.state_.store.end() && c.state_.store.size() >= C::kMaxStored;
  if (full && !c.reads_other("E-65")) return nak(c, 0x42, NakRule::kStoreListFull);
  c.enter_mode("STORE_SAT_MODE", "STORE_ENTERING_MODE");
  // ERRATA E-52: back to MANUAL_MODE; other-2 (every command forces REMOTE) to REMOTE_MODE.
  const std::string_view exit = full ? "STORE_LIST_FULL" : "STORE_SAT_DATA_STORED_OK";
  if (c.reads_other_2("E-52")) c.enter_mode("REMOTE_MODE", "WAITING_FOR_USER_INPUT", exit);
  else c.enter_mode("MANUAL_MODE", "MANUAL_IDLE", exit);
  if (full) return ack(c, 0x42, AckReply{}, "STORE list full: " + entry.name + " not stored (E-65)");
  // "If a particular satellite name has already been STOREd, its data will be overwritten."
  if (it != c.state_.store.end()) *it = entry;
  else c.state_.store.push_back(entry);
  return stored(ack(c, 0x42, AckReply{}, "stored " + entry.name));
}

// ---- §3.20 / §3.21 Signposts -----------------------------------------------------------
bool Handlers::dvb(const C& c) { return c.profile_.dvb_receiver || c.faults_.has(Fault::kSignpostsWithoutDvb); }

// ERRATA E-23: without the option the reference side NAKs 43h and 44h; the
// other side gives them no reply (the text gives none); other-2 NAKs.
std::optional<Outcome> Handlers::without_dvb(C& c, std::uint8_t code) {
  if (dvb(c)) return std::nullopt;
  if (c.reads_other("E-23")) return unanswered("no DVB receiver option: no reply (E-23)");
  return nak(c, code, NakRule::kNoDvbOption);
}

Outcome Handlers::write_signpost(C& c, const WriteSignpost& w) {
  if (auto o = without_dvb(c, 0x43)) return *o;
  if (w.index < 1 || w.index > 20) return nak(c, 0x43, NakRule::kSignpostIndex);
  const SignpostData& d = w.signpost;
  if (!in_range(d.longitude, -1799, 1800) || !in_range(d.frequency, 10700, 12750) ||
      !in_range(d.symbol_rate, 1000, 30000))
    return nak(c, 0x43, NakRule::kSignpostField);
  // ERRATA E-23 other-2: priority "1 - 9", as §3.21 reads it back.
  if (d.priority == 0 && c.reads_other_2("E-23")) return nak(c, 0x43, NakRule::kSignpostField, "priority 0 (E-23)");
  // ERRATA E-32: 4 and 8 lie in the field's range "1 - 9" but name no code;
  // the reference side NAKs them as invalid data, the other stores them.
  const bool defined = std::any_of(std::begin(layouts::kFec), std::end(layouts::kFec),
                                   [&](const fields::ChoiceItem& i) { return i.ch == d.fec; });
  if (!defined && !c.reads_other("E-32"))
    return nak(c, 0x43, NakRule::kMalformedData, std::string("FEC code ") + d.fec + " is not defined (E-32)");
  const std::size_t slot = slot_written(c, w.index);
  c.state_.signposts[slot - 1] = Signpost{static_cast<std::uint8_t>(slot), d};
  return stored(ack(c, 0x43, AckReply{}, "signpost " + std::to_string(w.index) + " written"));
}
Outcome Handlers::read_signpost(C& c, const ReadSignpost& r) {
  if (auto o = without_dvb(c, 0x44)) return *o;
  if (r.index < 1 || r.index > 20) return nak(c, 0x44, NakRule::kSignpostIndex);
  auto reply = reply_to_read(c, c.state_.signposts, r.index, signpost_reply);
  // §3.21 bytes 30-33 "pad with zeros"; the fault fills them with blanks.
  if (reply.index && c.faults_.has(Fault::kSpareBytesBlank)) reply.signpost.spare = "    ";
  return ack(c, 0x44, reply);
}

// ---- §3.22 / §3.23 Navigation data ---------------------------------------------------
Outcome Handlers::read_navigation(C& c) {
  return ack(c, 0x45, navigation_reply(c.state_.navigation));
}
Outcome Handlers::write_navigation(C& c, const WriteNavigation& w) {
  // sddmm / sdddmm: degrees and minutes in one integer (§3.23).
  const std::int32_t lat_deg = std::abs(w.latitude) / 100, lat_min = std::abs(w.latitude) % 100;
  const std::int32_t lon_deg = std::abs(w.longitude) / 100, lon_min = std::abs(w.longitude) % 100;
  // "Valid" is ERRATA E-60: the reference takes 90°00' and 180°00' either
  // way; the other side NAKs the poles and -180°00' (the antimeridian is
  // +180°00' only, as a signpost's -179.9..180.0, E-62).
  const bool other = c.reads_other("E-60");
  const bool lat_ok = lat_min < 60 && (lat_deg < 90 || (lat_deg == 90 && lat_min == 0 && !other));
  const bool lon_ok = lon_min < 60 && (lon_deg < 180 || (lon_deg == 180 && lon_min == 0 && !(other && w.longitude < 0)));
  const bool heading_ok = in_range(w.heading, 0, 3599);
  if (!lat_ok || !lon_ok || !heading_ok)
    return nak(c, 0x46, NakRule::kNavigationField,
               !lat_ok ? "latitude" : !lon_ok ? "longitude" : "heading");
  Navigation& n = c.state_.navigation;
  n.latlon_source = 0b111;   // remotely entered
  n.heading_source = 0b111;
  n.latitude_min = (w.latitude < 0 ? -1 : 1) * (lat_deg * 60 + lat_min);
  n.longitude_min = (w.longitude < 0 ? -1 : 1) * (lon_deg * 60 + lon_min);
  n.heading_tenths = w.heading;
  // §3.23 NOTE: "invalidate (DELETE) any STOREd satellites".
  if (!c.faults_.has(Fault::kWriteNavKeepsStore)) c.state_.store.clear();
  return stored(ack(c, 0x46, AckReply{}, "navigation data written, STORE list deleted"));
}

}  // namespace sabus::harness
