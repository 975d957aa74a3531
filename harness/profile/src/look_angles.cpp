// The geometry of a LOCATE (look_angles.hpp; ERRATA E-80).
#include "sabus/harness/look_angles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sabus::harness::look {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kEarthRadiusKm = 6378.137;   // WGS-84 equatorial radius
constexpr double kOrbitRadiusKm = 42164.17;   // geostationary orbit radius
// Turns of an azimuth tried against a range: positions lie in -180 to 360
// (the profile loader's range), azimuths in -180 to 360.
constexpr int kTurns[] = {-2, -1, 0, 1, 2};

double radians(double deg) { return deg * kPi / 180; }
double degrees(double rad) { return rad * 180 / kPi; }

// Into -180 (excluded) to 180.
double half_turn(double deg) {
  double x = std::fmod(deg, 360.0);
  if (x <= -180) x += 360;
  if (x > 180) x -= 360;
  return x;
}

}  // namespace

// The satellite's position less the site's, in the site's east, north and
// up directions (earth-centred coordinates, the satellite on the equator at
// the orbit radius): exact on a sphere, with no tangent to blow up at the
// poles, the equator or the site's own meridian.
LookAngles geostationary(double latitude_deg, double longitude_deg, double satellite_longitude_deg) {
  const double lat = radians(latitude_deg), lon = radians(longitude_deg), sat = radians(satellite_longitude_deg);
  const double site[3] = {kEarthRadiusKm * std::cos(lat) * std::cos(lon), kEarthRadiusKm * std::cos(lat) * std::sin(lon),
                          kEarthRadiusKm * std::sin(lat)};
  const double d[3] = {kOrbitRadiusKm * std::cos(sat) - site[0], kOrbitRadiusKm * std::sin(sat) - site[1], -site[2]};
  const double east = -std::sin(lon) * d[0] + std::cos(lon) * d[1];
  const double north = -std::sin(lat) * std::cos(lon) * d[0] - std::sin(lat) * std::sin(lon) * d[1] + std::cos(lat) * d[2];
  const double up = std::cos(lat) * std::cos(lon) * d[0] + std::cos(lat) * std::sin(lon) * d[1] + std::sin(lat) * d[2];
  double az = degrees(std::atan2(east, north));
  if (az < 0) az += 360;
  return {az, degrees(std::atan2(up, std::hypot(east, north)))};
}

SiteOf site_of(const Navigation& nav, AzSensor sensor, char fluxgate_heading) {
  if (!nav.latitude_min || !nav.longitude_min) return {std::nullopt, Missing::kLatLon};
  Site s{*nav.latitude_min / 60.0, *nav.longitude_min / 60.0, 0};
  if (sensor == AzSensor::kFluxgate) {
    // §3.2 NOTE: the compass reads where the antenna points; 'M' a magnetic
    // heading, the true azimuth less the variation (east positive, §3.22).
    if (fluxgate_heading == 'M') {
      if (!nav.magvar_tenths) return {std::nullopt, Missing::kMagvar};
      s.azimuth_offset_deg = *nav.magvar_tenths / 10.0;
    }
    return {s, Missing::kNothing};
  }
  // §3.23: "True Heading of mount azimuth 0.0".
  if (!nav.heading_tenths) return {std::nullopt, Missing::kHeading};
  s.azimuth_offset_deg = *nav.heading_tenths / 10.0;
  return {s, Missing::kNothing};
}

std::string describe(Missing m) {
  switch (m) {
    case Missing::kLatLon: return "the site's latitude and longitude (navigation data, §3.22)";
    case Missing::kHeading: return "the true heading of mount azimuth 0.0 (navigation data, §3.23)";
    case Missing::kMagvar:
      return "a magnetic variation (navigation magvar, §3.22), to turn a true azimuth into the magnetic heading the "
             "fluxgate compass reads";
    case Missing::kNothing: break;
  }
  return "";
}

std::string_view waiting_state(Missing m) {
  switch (m) {
    case Missing::kLatLon: return "LOCATE_WAITING_FOR_LAT_LON";
    case Missing::kHeading: return "LOCATE_WAITING_FOR_HEADING";
    case Missing::kMagvar: return "LOCATE_CALCULATING_MAGNETIC_VARIATION";
    case Missing::kNothing: break;
  }
  return "";
}

double mount_azimuth(const Site& s, double true_azimuth_deg) { return half_turn(true_azimuth_deg - s.azimuth_offset_deg); }

Pointing pointing(const Site& s, double satellite_longitude_deg) {
  const LookAngles l = geostationary(s.latitude_deg, s.longitude_deg, satellite_longitude_deg);
  return {mount_azimuth(s, l.azimuth_deg), l.elevation_deg};
}

std::optional<double> azimuth_position(const AxisProfile& a, double azimuth_deg, double from_deg, double margin_deg) {
  std::optional<double> best;
  for (int turn : kTurns) {
    const double x = azimuth_deg + 360.0 * turn;
    if (x < a.min_deg - margin_deg - 1e-9 || x > a.max_deg + margin_deg + 1e-9) continue;
    if (!best || std::abs(x - from_deg) < std::abs(*best - from_deg)) best = x;
  }
  return best;
}

double azimuth_outside_by(const AxisProfile& a, double azimuth_deg) {
  double nearest = std::numeric_limits<double>::infinity();
  for (int turn : kTurns) {
    const double x = azimuth_deg + 360.0 * turn;
    const double beyond = std::max(a.min_deg - x, x - a.max_deg);  // > 0 outside, <= 0 inside
    nearest = std::min(nearest, beyond);
  }
  return nearest;
}

}  // namespace sabus::harness::look
