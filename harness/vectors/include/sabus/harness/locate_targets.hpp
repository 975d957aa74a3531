// The satellites a LOCATE vector sends (§3.18), chosen from the device's
// profile: its site, heading and axis ranges (look_angles.hpp), never a
// fixed longitude, so that a vector holds on any legal controller (ERRATA
// E-80, E-81):
//   - visible: above the horizon and inside both axis ranges, so the LOCATE
//     moves there and a vector checks that it arrives;
//   - below the horizon: under the elevation axis's lower limit (and 0),
//     its azimuth inside the azimuth range, so the only error is the
//     elevation's;
//   - outside the azimuth range: in view and inside the elevation range;
//   - above the elevation range: in view, inside the azimuth range.
// The allowances, one place for every LOCATE check:
//   - two correct controllers' look angles differ by up to kAgreementAz /
//     kAgreementEl (a spherical earth or an ellipsoid, geocentric or
//     geodetic latitude, the orbit radius taken, the tenths of the heading);
//     an arrival is checked within that plus the axis's tolerance_deg and the
//     display's 0.1 deg;
//   - a visible target lies between kLowestElevation and kHighestElevation
//     (near the zenith the azimuth turns fast with the site) and
//     kInsideLimits inside each limit;
//   - an unreachable target lies kBeyondLimits beyond the limit it breaks,
//     so that every such controller finds it out of range.
// Each function gives the satellite's longitude in tenths of a degree
// (-179.9 to 179.9, §3.18 bytes 15-20), or why the profile has none.
#pragma once

#include "sabus/harness/look_angles.hpp"
#include "sabus/harness/motion.hpp"

namespace sabus::harness::locate {

inline constexpr double kAgreementAz = 1.0;
inline constexpr double kAgreementEl = 0.5;
inline constexpr double kLowestElevation = 5.0;
inline constexpr double kHighestElevation = 70.0;
inline constexpr double kInsideLimits = 2.0;
inline constexpr double kBeyondLimits = 3.0;

motion::Maybe<double> visible(const Profile& p);
motion::Maybe<double> below_horizon(const Profile& p);
motion::Maybe<double> outside_azimuth(const Profile& p);
motion::Maybe<double> above_elevation(const Profile& p);

// Where the mount points for the satellite at `longitude`: the azimuth
// reading (the turn inside the azimuth range nearest its middle, a heading
// on a fluxgate mount) and the elevation; why not, without the site.
motion::Maybe<look::Pointing> pointing(const Profile& p, double longitude_deg);
// The half-width of the window an arrival is checked in, per axis (az, el).
double slack(const Profile& p, motion::Axis axis);

}  // namespace sabus::harness::locate
