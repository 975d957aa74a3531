#include "sabus/harness/state_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace sabus::harness {
namespace {

using nlohmann::json;
constexpr int kFormatVersion = 1;

json opt(const std::optional<std::int32_t>& v) { return v ? json(*v) : json(); }
std::optional<std::int32_t> opt_int(const json& j) {
  if (j.is_null()) return std::nullopt;
  return j.get<std::int32_t>();
}

json sat_json(const SatelliteData& s) {
  return {{"name", s.name}, {"longitude", opt(s.longitude)}, {"inclination", opt(s.inclination)},
          {"band", std::string(1, s.band)}, {"ephemeris", std::string(1, s.ephemeris)}, {"pol_offset", opt(s.pol_offset)}};
}
SatelliteData sat_of(const json& j) {
  return {j.at("name").get<std::string>(), opt_int(j.at("longitude")), opt_int(j.at("inclination")),
          j.at("band").get<std::string>().at(0), j.at("ephemeris").get<std::string>().at(0),
          opt_int(j.at("pol_offset"))};
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

void restore(const json& j, Controller& c) {
  ControllerState& s = c.mutable_state();
  const auto& pos = j.at("positions");
  s.az.position = pos.at("az").get<double>();
  s.el.position = pos.at("el").get<double>();
  s.pol.position = pos.at("pol").get<double>();
  s.store.clear();
  for (const auto& x : j.at("store"))
    s.store.push_back({x.at("name").get<std::string>(), x.at("az").get<double>(), x.at("el").get<double>(),
                       x.at("h_pol").get<double>(), x.at("v_pol").get<double>()});
  s.presets = {};
  for (const auto& p : j.at("presets")) {
    const auto i = p.at("index").get<std::uint8_t>();
    if (i >= 1 && i <= s.presets.size()) s.presets[i - 1] = PresetSatellite{i, sat_of(p.at("data")), p.at("dual_band").get<bool>()};
  }
  s.tles = {};
  for (const auto& t : j.at("tles")) {
    const auto i = t.at("index").get<std::uint8_t>();
    if (i >= 1 && i <= s.tles.size()) s.tles[i - 1] = TleSet{i, t.at("line1").get<std::string>(), t.at("line2").get<std::string>()};
  }
  s.signposts = {};
  for (const auto& sp : j.at("signposts")) {
    const auto i = sp.at("index").get<std::uint8_t>();
    if (i < 1 || i > s.signposts.size()) continue;
    SignpostData d{opt_int(sp.at("longitude")), opt_int(sp.at("frequency")), opt_int(sp.at("symbol_rate")),
                   sp.at("fec").get<std::string>().at(0), sp.at("polarization").get<std::string>().at(0),
                   sp.at("id").get<std::string>(), sp.at("priority").get<std::uint32_t>(), ""};
    s.signposts[i - 1] = Signpost{i, d};
  }
  const auto& n = j.at("navigation");
  s.navigation = {n.at("latlon_source").get<std::uint8_t>(), opt_int(n.at("latitude")), opt_int(n.at("longitude")),
                  n.at("heading_source").get<std::uint8_t>(), opt_int(n.at("heading")), opt_int(n.at("magvar"))};
}

}  // namespace

std::string save_state(const std::vector<const Controller*>& controllers) {
  json doc = {{"format", "sabus-sim-state"}, {"version", kFormatVersion}, {"controllers", json::object()}};
  for (const Controller* c : controllers) doc["controllers"][std::to_string(c->profile().address)] = controller_json(*c);
  return doc.dump(2) + "\n";
}

bool load_state(const std::string& text, const std::vector<Controller*>& controllers, std::string& error) {
  try {
    const json doc = json::parse(text);
    if (doc.value("format", "") != "sabus-sim-state" || doc.value("version", 0) != kFormatVersion) {
      error = "not a sabus sim state file (format sabus-sim-state, version 1)";
      return false;
    }
    for (Controller* c : controllers) {
      const auto key = std::to_string(c->profile().address);
      if (doc.at("controllers").contains(key)) restore(doc.at("controllers").at(key), *c);
    }
    return true;
  } catch (const json::exception& e) {
    error = std::string("bad state file: ") + e.what();
    return false;
  }
}

bool write_state_file(const std::string& path, const std::vector<const Controller*>& controllers, std::string& error) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << save_state(controllers);
    if (!out) {
      error = "cannot write " + tmp;
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    error = "cannot rename " + tmp + " to " + path + ": " + ec.message();
    return false;
  }
  return true;
}

bool read_state_file(const std::string& path, const std::vector<Controller*>& controllers, std::string& error) {
  std::ifstream in(path);
  if (!in) return true;  // first start: nothing saved yet
  std::stringstream ss;
  ss << in.rdbuf();
  if (!load_state(ss.str(), controllers, error)) {
    error = path + ": " + error;
    return false;
  }
  return true;
}

}  // namespace sabus::harness
