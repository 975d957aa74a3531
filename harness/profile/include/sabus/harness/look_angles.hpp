// Where a geostationary satellite is seen from the controller's site, and
// which azimuth position of the mount points there: the geometry of a LOCATE
// (§3.18) from the navigation data (§3.22/§3.23: latitude, longitude, true
// heading of mount azimuth 0.0), the primary azimuth sensor (§3.2 NOTE) and
// the axis ranges. One model for the reference controller, which moves
// there or enters a range error, and for the profile expressions that choose
// a LOCATE's satellite (ERRATA E-80, E-81). Pure functions.
#pragma once

#include <optional>
#include <string>

#include "sabus/harness/profile.hpp"

namespace sabus::harness::look {

// The direction of a satellite from the site: true azimuth, clockwise from
// north, 0 to 360; elevation above the horizon, -90 to 90 (a spherical
// earth of the equatorial radius and the geostationary orbit radius).
struct LookAngles {
  double azimuth_deg;
  double elevation_deg;
};
LookAngles geostationary(double latitude_deg, double longitude_deg, double satellite_longitude_deg);

// The site as a LOCATE needs it, from the navigation data: where it is and
// how a true azimuth becomes a reading of the azimuth axis (ERRATA E-80):
//   - a mount whose azimuth 0.0 points to the true heading of §3.23
//     ("True Heading of mount azimuth 0.0"), positions growing clockwise
//     (§3.4 'W' clockwise, §3.2 byte 32 A the clockwise limit): position =
//     true azimuth - heading;
//   - with the fluxgate compass as the primary azimuth sensor (§3.2 NOTE)
//     the reading is the heading the antenna points to, true ('T') or
//     magnetic ('M': the true azimuth less the magnetic variation, east
//     positive, §3.22 bytes 36-41); the vehicle's heading plays no part.
// What the site lacks is the locate state that waits for it (§3.17
// locate_states): no latitude/longitude, no heading, no magnetic variation.
enum class Missing : std::uint8_t { kNothing, kLatLon, kHeading, kMagvar };
struct Site {
  double latitude_deg = 0, longitude_deg = 0;
  // Position = true azimuth - azimuth_offset_deg, taken modulo 360.
  double azimuth_offset_deg = 0;
};
struct SiteOf {
  std::optional<Site> site;
  Missing missing = Missing::kNothing;
};
SiteOf site_of(const Navigation& nav, AzSensor sensor, char fluxgate_heading);
// What a missing piece is, for skip reasons and notes.
std::string describe(Missing m);
// The §3.17 locate_states state a LOCATE waits in for it (ERRATA E-59,
// E-84); "" for kNothing.
std::string_view waiting_state(Missing m);

// The azimuth position pointing to a true azimuth, in -180 (excluded) to 180.
double mount_azimuth(const Site& s, double true_azimuth_deg);

// A mount position of the satellite: the azimuth reading as above and the
// elevation.
struct Pointing {
  double azimuth_deg;
  double elevation_deg;
};
Pointing pointing(const Site& s, double satellite_longitude_deg);

// The position of the azimuth axis that points to `azimuth` (positions a
// turn apart point the same way), inside the axis's limits widened by
// `margin` (negative: held that far inside), nearest `from`; nullopt when
// no turn of it is inside.
std::optional<double> azimuth_position(const AxisProfile& a, double azimuth_deg, double from_deg, double margin_deg = 0);
// How far `azimuth` lies outside the axis's range, the nearest turn of it
// to the nearest limit; 0 or less when a turn of it is inside (minus the
// distance to the nearer limit).
double azimuth_outside_by(const AxisProfile& a, double azimuth_deg);

}  // namespace sabus::harness::look
