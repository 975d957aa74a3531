#include "sabus/harness/state_file.hpp"

#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sabus/harness/files.hpp"

namespace sabus::harness {
namespace {

using nlohmann::json;
constexpr int kFormatVersion = 1;

json opt(const std::optional<std::int32_t>& v) { return v ? json(*v) : json(); }

// A state file is a file a person may edit: every value is checked before it
// is converted (json's get<> casts a double such as 1e300 to an int as is,
// undefined behaviour) and errors name the key.
struct BadState : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <class T>
T whole(const json& j, const std::string& key, long long lo = std::numeric_limits<T>::min(),
        long long hi = static_cast<long long>(std::numeric_limits<T>::max())) {
  const bool fits = j.is_number_integer() &&
                    !(j.is_number_unsigned() && j.get<std::uint64_t>() > std::numeric_limits<std::int64_t>::max()) &&
                    j.get<std::int64_t>() >= lo && j.get<std::int64_t>() <= hi;
  if (!fits) throw BadState(key + ": expected a whole number " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " + j.dump());
  return static_cast<T>(j.get<std::int64_t>());
}
std::optional<std::int32_t> opt_int(const json& j, const std::string& key) {
  if (j.is_null()) return std::nullopt;
  return whole<std::int32_t>(j, key);
}
char letter(const json& j, const std::string& key) {
  if (!j.is_string() || j.get_ref<const std::string&>().size() != 1) throw BadState(key + ": expected one character, got " + j.dump());
  return j.get_ref<const std::string&>()[0];
}
double degrees(const json& j, const std::string& key) {
  if (!j.is_number() || !std::isfinite(j.get<double>())) throw BadState(key + ": expected a number of degrees, got " + j.dump());
  return j.get<double>();
}
double position(const json& j, const std::string& key, const AxisProfile& axis) {
  const double d = degrees(j, key);
  if (d < axis.min_deg || d > axis.max_deg)
    throw BadState(key + ": " + j.dump() + " is outside the profile's range " + std::to_string(axis.min_deg) + " to " +
                   std::to_string(axis.max_deg));
  return d;
}

// A stored record is one the controller could have stored: its write command's
// codec writes it and reads it back unchanged (§3.10, §3.12, §3.20).
template <class Write>
void check_record(const Write& write, const std::string& key) {
  const Bytes frame = encode_request(Request{write}, '2');
  const auto f = decode_frame(frame);
  const auto r = f.ok() ? decode_request(f.value()) : Expected<Request>(f.error());
  if (!r.ok() || !(std::get<Write>(r.value()) == write))
    throw BadState(key + ": not a record the " + std::string(find_command(Write::kCode)->name) + " command carries" +
                   (r.ok() ? std::string() : " (" + r.error().message() + ")"));
}

// A STORE name is one the Query Name reply gives back unchanged (§3.6: ten
// printable characters), and is in the list once: the 35h reply would
// otherwise carry it cut short, or its bytes beyond 7Fh (a name such as
// "caf\u00e9" in the file) onto a 7-bit line.
void check_store_name(const std::string& name, const std::vector<StoredSatellite>& before, const std::string& key) {
  const QueryNameReply reply{1, 1, name};
  const auto bytes = encode_reply(Reply{reply}, '2', 0x35);
  const auto frame = bytes.ok() ? decode_frame(bytes.value()) : Expected<Frame>(bytes.error());
  const auto back = frame.ok() ? decode_reply(frame.value()) : Expected<Reply>(frame.error());
  const auto* read = back.ok() ? std::get_if<QueryNameReply>(&back.value()) : nullptr;
  if (!read || !(*read == reply))
    throw BadState(key + ".name: not a name the Query Name reply carries" +
                   (back.ok() ? std::string() : " (" + back.error().message() + ")"));
  for (const auto& other : before)
    if (other.name == name) throw BadState(key + ".name: " + json(name).dump() + " is in the STORE list twice");
}

json sat_json(const SatelliteData& s) {
  return {{"name", s.name}, {"longitude", opt(s.longitude)}, {"inclination", opt(s.inclination)},
          {"band", std::string(1, s.band)}, {"ephemeris", std::string(1, s.ephemeris)}, {"pol_offset", opt(s.pol_offset)}};
}
SatelliteData sat_of(const json& j, const std::string& key) {
  return {j.at("name").get<std::string>(), opt_int(j.at("longitude"), key + ".longitude"),
          opt_int(j.at("inclination"), key + ".inclination"), letter(j.at("band"), key + ".band"),
          letter(j.at("ephemeris"), key + ".ephemeris"), opt_int(j.at("pol_offset"), key + ".pol_offset")};
}

json controller_json(const Controller& c) {
  const ControllerState& s = c.state();
  json j;
  j["positions"] = {{"az", s.az.position}, {"el", s.el.position}, {"pol", s.pol.position}};
  j["store"] = json::array();
  for (const auto& x : s.store)
    j["store"].push_back({{"name", x.name}, {"az", x.az_deg}, {"el", x.el_deg}, {"h_pol", x.h_pol_deg}, {"v_pol", x.v_pol_deg}});
  j["presets"] = json::array();
  for (const auto& p : s.presets)
    if (p) j["presets"].push_back({{"index", p->index}, {"data", sat_json(p->data)}, {"dual_band", p->dual_band}});
  j["tles"] = json::array();
  for (const auto& t : s.tles)
    if (t) j["tles"].push_back({{"index", t->index}, {"line1", t->line1}, {"line2", t->line2}});
  j["signposts"] = json::array();
  for (const auto& sp : s.signposts) {
    if (!sp) continue;
    const SignpostData& d = sp->data;
    j["signposts"].push_back({{"index", sp->index}, {"longitude", opt(d.longitude)}, {"frequency", opt(d.frequency)},
                              {"symbol_rate", opt(d.symbol_rate)}, {"fec", std::string(1, d.fec)},
                              {"polarization", std::string(1, d.polarization)}, {"id", d.id},
                              {"priority", d.priority}});
  }
  const Navigation& n = s.navigation;
  j["navigation"] = {{"latlon_source", n.latlon_source}, {"latitude", opt(n.latitude_min)},
                     {"longitude", opt(n.longitude_min)}, {"heading_source", n.heading_source},
                     {"heading", opt(n.heading_tenths)}, {"magvar", opt(n.magvar_tenths)}};
  return j;
}

// The state `j` gives controller `c`; load_state applies them only when every
// controller's reads, so that a bad file changes nothing.
ControllerState restored(const json& j, const Controller& c) {
  ControllerState s = c.state();
  const Profile& profile = c.profile();
  const auto& pos = j.at("positions");
  s.az.position = position(pos.at("az"), "positions.az", profile.az);
  s.el.position = position(pos.at("el"), "positions.el", profile.el);
  s.pol.position = position(pos.at("pol"), "positions.pol", profile.pol);
  s.store.clear();
  for (const auto& x : j.at("store")) {
    const std::string key = "store[" + std::to_string(s.store.size()) + "]";
    if (s.store.size() == Controller::kMaxStored) throw BadState(key + ": the STORE list holds " + std::to_string(Controller::kMaxStored) + " (§3.6)");
    check_store_name(x.at("name").get<std::string>(), s.store, key);
    s.store.push_back({x.at("name").get<std::string>(), degrees(x.at("az"), key + ".az"), degrees(x.at("el"), key + ".el"),
                       degrees(x.at("h_pol"), key + ".h_pol"), degrees(x.at("v_pol"), key + ".v_pol")});
  }
  s.presets = {};
  for (const auto& p : j.at("presets")) {
    const auto i = whole<std::uint8_t>(p.at("index"), "presets.index", 1, s.presets.size());
    const std::string key = "presets " + std::to_string(i);
    PresetSatellite preset{i, sat_of(p.at("data"), key), p.at("dual_band").get<bool>()};
    check_record(WriteSatellite{i, preset.data}, key);
    s.presets[i - 1] = std::move(preset);
  }
  s.tles = {};
  for (const auto& t : j.at("tles")) {
    const auto i = whole<std::uint8_t>(t.at("index"), "tles.index", 1, s.tles.size());
    TleSet tle{i, t.at("line1").get<std::string>(), t.at("line2").get<std::string>()};
    check_record(WriteTle{i, tle.line1, tle.line2}, "tles " + std::to_string(i));
    s.tles[i - 1] = std::move(tle);
  }
  s.signposts = {};
  for (const auto& sp : j.at("signposts")) {
    const auto i = whole<std::uint8_t>(sp.at("index"), "signposts.index", 1, s.signposts.size());
    const std::string key = "signposts " + std::to_string(i);
    SignpostData d{opt_int(sp.at("longitude"), key + ".longitude"), opt_int(sp.at("frequency"), key + ".frequency"),
                   opt_int(sp.at("symbol_rate"), key + ".symbol_rate"), letter(sp.at("fec"), key + ".fec"),
                   letter(sp.at("polarization"), key + ".polarization"), sp.at("id").get<std::string>(),
                   whole<std::uint32_t>(sp.at("priority"), key + ".priority"), ""};
    check_record(WriteSignpost{i, d}, key);
    s.signposts[i - 1] = Signpost{i, d};
  }
  // §3.22: the sources are 3-bit codes; positions in minutes, headings in tenths.
  const auto& n = j.at("navigation");
  s.navigation = {whole<std::uint8_t>(n.at("latlon_source"), "navigation.latlon_source", 0, 7),
                  opt_int(n.at("latitude"), "navigation.latitude"), opt_int(n.at("longitude"), "navigation.longitude"),
                  whole<std::uint8_t>(n.at("heading_source"), "navigation.heading_source", 0, 7),
                  opt_int(n.at("heading"), "navigation.heading"), opt_int(n.at("magvar"), "navigation.magvar")};
  auto within = [](const std::optional<std::int32_t>& v, std::int32_t limit, const char* key) {
    if (v && (*v < -limit || *v > limit)) throw BadState(std::string(key) + ": " + std::to_string(*v) + " is beyond " + std::to_string(limit));
  };
  within(s.navigation.latitude_min, 90 * 60, "navigation.latitude");
  within(s.navigation.longitude_min, 180 * 60, "navigation.longitude");
  within(s.navigation.magvar_tenths, 999, "navigation.magvar");
  if (s.navigation.heading_tenths && (*s.navigation.heading_tenths < 0 || *s.navigation.heading_tenths > 3599))
    throw BadState("navigation.heading: " + std::to_string(*s.navigation.heading_tenths) + " is not 0 to 3599 tenths");
  return s;
}

}  // namespace

std::string save_state(const std::vector<const Controller*>& controllers) {
  json doc = {{"format", "sabus-sim-state"}, {"version", kFormatVersion}, {"controllers", json::object()}};
  for (const Controller* c : controllers) doc["controllers"][std::to_string(c->profile().address)] = controller_json(*c);
  // Names and texts are the codecs' printable ASCII; a string that is not
  // UTF-8 all the same is written with U+FFFD, not thrown on mid-session.
  return doc.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

bool load_state(const std::string& text, const std::vector<Controller*>& controllers, std::string& error) {
  try {
    const json doc = json::parse(text);
    if (doc.value("format", "") != "sabus-sim-state" || doc.value("version", 0) != kFormatVersion) {
      error = "not a sabus sim state file (format sabus-sim-state, version 1)";
      return false;
    }
    std::vector<std::pair<Controller*, ControllerState>> states;
    for (Controller* c : controllers) {
      const auto key = std::to_string(c->profile().address);
      try {
        if (doc.at("controllers").contains(key)) states.emplace_back(c, restored(doc.at("controllers").at(key), *c));
      } catch (const BadState& e) {
        throw BadState("controller " + key + ": " + e.what());
      }
    }
    for (auto& [c, state] : states) c->mutable_state() = std::move(state);
    return true;
  } catch (const json::exception& e) {
    error = std::string("bad state file: ") + e.what();
    return false;
  } catch (const BadState& e) {
    error = std::string("bad state file: ") + e.what();
    return false;
  }
}

bool write_state_file(const std::string& path, const std::vector<const Controller*>& controllers, std::string& error) {
  return replace_file(path, save_state(controllers), error);
}

bool read_state_file(const std::string& path, const std::vector<Controller*>& controllers, std::string& error) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec) && !ec) return true;  // first start: nothing saved yet
  // A file there that cannot be read is not a first start: the first change
  // would replace it with the profile's defaults.
  std::ifstream in(path);
  if (!in) {
    error = path + ": cannot read: " + (ec ? ec.message() : std::strerror(errno));
    return false;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  if (!load_state(ss.str(), controllers, error)) {
    error = path + ": " + error;
    return false;
  }
  return true;
}

}  // namespace sabus::harness
