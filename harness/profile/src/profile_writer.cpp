// The device profile writer: to_yaml writes every key of the schema
// (vectors/profiles/README.md), which load_profile_text reads back to an
// equal profile. The text is built here rather than by YAML::Emitter, for
// speed (yaml_writer.hpp says why); every text value goes through
// yaml_writer::double_quoted, and tests read every branch back.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <span>
#include <string>
#include <utility>

#include "profile_tables.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/yaml_reader.hpp"
#include "sabus/harness/yaml_writer.hpp"

namespace sabus::harness {
namespace {

using namespace profile_internal;
using yaml_reader::number_text;

// Text values double-quoted (yaml_writer.hpp): the loader's text fields are
// printable ASCII, read back exactly; anything else is escaped, so the
// output stays well-formed YAML and the loader names the field.
std::string quoted(std::string_view s) { return yaml_writer::double_quoted(s); }

// (Appended, not "-" + std::to_string(...): GCC 12 warns falsely, -Wrestrict,
// where that operator+ is inlined.)
std::string tenths_text(std::int32_t t) {
  long long a = std::llabs(static_cast<long long>(t));
  std::string out = t < 0 ? "-" : "";
  out += std::to_string(a / 10);
  out += '.';
  out += std::to_string(a % 10);
  return out;
}
std::string bool_text(bool b) { return b ? "true" : "false"; }
std::string opt_text(const std::optional<std::int32_t>& v, std::string (*text)(std::int32_t)) {
  return v ? text(*v) : "~";
}
std::string int_text(std::int32_t v) { return std::to_string(v); }

std::string minutes_text(const std::optional<std::int32_t>& m, int width, char pos, char neg) {
  if (!m) return "~";
  int a = std::abs(*m);
  std::string deg = std::to_string(a / 60);
  std::string min = std::to_string(a % 60);
  return quoted(std::string(static_cast<std::size_t>(std::max(0, width - static_cast<int>(deg.size()))), '0') + deg +
                "." + (min.size() < 2 ? "0" : "") + min + " " + (*m < 0 ? neg : pos));
}

template <class T, std::size_t N>
std::string name_text(const Named<T> (&table)[N], T value) {
  const std::string_view name = name_of(table, value);
  if (!name.empty()) return std::string(name);
  return std::to_string(static_cast<long long>(value));  // a raw source code 1-7
}

std::string item_text(std::span<const fields::ChoiceItem> items, char ch, bool by_char) {
  for (const auto& i : items)
    if (i.ch == ch) return by_char ? std::string(1, ch) : std::string(i.meaning);
  return quoted(std::string(1, ch));  // not in the table: the loader will say so
}

using Pairs = std::initializer_list<std::pair<std::string_view, std::string>>;
std::string flow(Pairs pairs) {
  std::string out = "{";
  for (const auto& [k, v] : pairs) out += (out.size() > 1 ? ", " : "") + std::string(k) + ": " + v;
  return out + "}";
}

std::string axis_text(const AxisProfile& a) {
  return flow({{"fast_dps", number_text(a.fast_dps)},
               {"slow_dps", number_text(a.slow_dps)},
               {"min_deg", number_text(a.min_deg)},
               {"max_deg", number_text(a.max_deg)},
               {"initial_deg", number_text(a.initial_deg)},
               {"has_stow_limit", bool_text(a.has_stow_limit)},
               {"stow_deg", number_text(a.stow_deg)},
               {"deploy_deg", a.deploy_deg ? number_text(*a.deploy_deg) : "~"},
               {"tolerance_deg", number_text(a.tolerance_deg)},
               {"accel_dps2", a.accel_dps2 ? number_text(*a.accel_dps2) : "~"},
               {"power_on_speed", name_text(kAxisSpeeds, a.power_on_speed)},
               {"ad_error", bool_text(a.ad_error)}});
}

// A list of flow maps, one entry a line; "[]" when empty.
template <class T, class F>
void write_list(std::string& out, std::string_view key, const std::vector<T>& items, F&& entry) {
  out += std::string(key) + ":" + (items.empty() ? " []\n" : "\n");
  for (const auto& item : items) out += "  - " + entry(item) + "\n";
}

// The stored lists (§3.6, §3.10, §3.12, §3.20), one entry a line.
void write_stored_data(std::string& out, const Profile& p) {
  write_list(out, "store", p.store, [](const StoredSatellite& s) {
    return flow({{"name", quoted(s.name)},
                 {"az_deg", number_text(s.az_deg)},
                 {"el_deg", number_text(s.el_deg)},
                 {"h_pol_deg", number_text(s.h_pol_deg)},
                 {"v_pol_deg", number_text(s.v_pol_deg)}});
  });
  write_list(out, "presets", p.presets, [](const PresetSatellite& s) {
    return flow({{"index", std::to_string(s.index)},
                 {"name", quoted(s.data.name)},
                 {"longitude", opt_text(s.data.longitude, tenths_text)},
                 {"inclination", opt_text(s.data.inclination, int_text)},
                 {"band", item_text(layouts::kBands, s.data.band, false)},
                 {"ephemeris", item_text(layouts::kEphemeris, s.data.ephemeris, false)},
                 {"pol_offset", opt_text(s.data.pol_offset, tenths_text)},
                 {"dual_band", bool_text(s.dual_band)}});
  });
  write_list(out, "tles", p.tles, [](const TleSet& t) {
    return flow({{"index", std::to_string(t.index)}, {"line1", quoted(t.line1)}, {"line2", quoted(t.line2)}});
  });
  write_list(out, "signposts", p.signposts, [](const Signpost& s) {
    return flow({{"index", std::to_string(s.index)},
                 {"longitude", opt_text(s.data.longitude, tenths_text)},
                 {"frequency", opt_text(s.data.frequency, int_text)},
                 {"symbol_rate", opt_text(s.data.symbol_rate, int_text)},
                 {"fec", item_text(layouts::kFec, s.data.fec, false)},
                 {"polarization", item_text(layouts::kSignpostPol, s.data.polarization, true)},
                 {"id", quoted(s.data.id)},
                 {"priority", std::to_string(s.data.priority)}});
  });
}

}  // namespace

std::string to_yaml(const Profile& p) {
  std::string out;
  auto line = [&out](std::string_view key, const std::string& value) { out += std::string(key) + ": " + value + "\n"; };
  auto sub = [&out](std::string_view key, const std::string& value) { out += "  " + std::string(key) + ": " + value + "\n"; };
  line("name", quoted(p.name));
  line("address", std::to_string(p.address));
  {
    std::string peers;
    for (auto a : p.bus_peers) peers += (peers.empty() ? "" : ", ") + std::to_string(a);
    line("bus_peers", "[" + peers + "]");
  }
  line("remote_enabled", bool_text(p.remote_enabled));
  line("baud", std::to_string(p.baud));
  line("firmware", quoted(p.firmware));
  line("polarization", name_text(kPolTypes, p.pol_type));
  line("azimuth_sensor", name_text(kAzSensors, p.az_sensor));
  line("fluxgate_heading", name_text(kHeadingReferences, p.fluxgate_heading));
  line("hundredths", bool_text(p.hundredths));
  line("stow", bool_text(p.stow));
  line("deploy", bool_text(p.deploy));
  line("dvb_receiver", bool_text(p.dvb_receiver));
  line("counts_per_degree", number_text(p.counts_per_degree));
  line("count_offset", std::to_string(p.count_offset));
  out += "axes:\n";
  sub("az", axis_text(p.az));
  sub("el", axis_text(p.el));
  sub("pol", axis_text(p.pol));
  line("turnaround_ms", number_text(p.turnaround_ms));
  line("agc", std::to_string(p.agc));
  line("agc_channel", name_text(kAgcChannels, p.agc_channel));
  out += "display:\n";
  sub("satellite", quoted(p.display.satellite));
  sub("pol_code", name_text(kPolCodes, p.display.pol_code));
  sub("cursor_row", std::to_string(p.display.cursor_row));
  sub("cursor_column", std::to_string(p.display.cursor_column));
  sub("cursor_blinking", bool_text(p.display.cursor_blinking));
  write_stored_data(out, p);
  const Navigation& nav = p.navigation;
  out += "navigation:\n";
  sub("latlon_source", name_text(kLatLonSources, nav.latlon_source));
  sub("latitude", minutes_text(nav.latitude_min, 2, 'N', 'S'));
  sub("longitude", minutes_text(nav.longitude_min, 3, 'E', 'W'));
  sub("heading_source", name_text(kHeadingSources, nav.heading_source));
  sub("heading", opt_text(nav.heading_tenths, tenths_text));
  sub("magvar", opt_text(nav.magvar_tenths, tenths_text));
  out += "track:\n";
  sub("active", bool_text(p.track.active));
  sub("activity", name_text(kTrackActivities, p.track.activity));
  sub("band", name_text(kTrackBands, p.track.band));
  sub("dual_band", bool_text(p.track.dual_band));
  out += "alarms:\n";
  sub("az", name_text(kAxisAlarms, p.alarms.az));
  sub("el", name_text(kAxisAlarms, p.alarms.el));
  sub("pol", name_text(kAxisAlarms, p.alarms.pol));
  sub("code", std::to_string(p.alarms.code));
  out += "errata:\n";
  sub("stx_restarts_in_data", bool_text(p.stx_restarts_in_data));
  sub("unknown_command_while_offline", name_text(kOfflineUnknown, p.unknown_command_while_offline));
  sub("implements_signal_strength", bool_text(p.implements_signal_strength));
  sub("implements_iess", bool_text(p.implements_iess));
  sub("nak_bad_tle_checksum", bool_text(p.nak_bad_tle_checksum));
  sub("locate_index_min", std::to_string(p.locate_index_min));
  sub("locate_index_max", std::to_string(p.locate_index_max));
  sub("restore_lost_locate_exit", bool_text(p.restore_lost_locate_exit));
  // The pinned readings only: an open point is no key (readings.hpp).
  if (!p.readings.empty()) {
    out += "readings:\n";
    for (const auto& [id, side] : p.readings) sub(id, std::string(to_string(side)));
  }
  return out;
}

std::string to_yaml(const Profile& p, std::string_view comment) {
  return yaml_writer::comment_lines(comment) + to_yaml(p);
}

}  // namespace sabus::harness
