// The satellites a LOCATE vector sends, chosen from the profile
// (locate_targets.hpp; ERRATA E-80, E-81).
#include "sabus/harness/locate_targets.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <tuple>

namespace sabus::harness::locate {
namespace {

// Below this a satellite is near the point under the site, where its
// azimuth is not defined: a below-horizon target stays above it.
constexpr double kDeepestElevation = -60.0;

motion::Maybe<look::Site> site_of(const Profile& p) {
  const look::SiteOf s = look::site_of(p.navigation, p.az_sensor, p.fluxgate_heading);
  if (!s.site) return {std::nullopt, look::describe(s.missing)};
  return {*s.site, {}};
}

// How far inside the azimuth range a turn of `az` lies (negative: outside).
double inside_azimuth(const Profile& p, double az) { return -look::azimuth_outside_by(p.az, az); }

// The elevations a target in view may have on this mount.
motion::Interval in_view(const Profile& p) {
  return {std::max(kLowestElevation, p.el.min_deg + kInsideLimits), std::min(kHighestElevation, p.el.max_deg - kInsideLimits)};
}

// Which search a cached answer belongs to.
enum class Target : std::uint8_t { kVisible, kBelowHorizon, kOutsideAzimuth, kAboveElevation };

// Everything a search reads: the site (navigation data, sensor, heading
// kind, as site_of reduces them) and both axes' limits. Two profiles with the
// same key have the same targets.
struct SearchKey {
  Target target;
  double lat, lon, offset, az_min, az_max, el_min, el_max;
  bool operator==(const SearchKey&) const = default;
};

// The answers of the last few searches on this thread. A search tries 3,599
// longitudes (a sine, a cosine and two arc tangents each), and the same
// profile asks for the same target each time a vector expands a LOCATE
// expression: a run asks hundreds of times, a sweep the same for every
// profile. Keyed by what the search reads, so a changed profile misses; per
// thread, so the sweep's parallel profiles share nothing.
motion::Maybe<double> cached(const SearchKey& key, const std::function<motion::Maybe<double>()>& search) {
  struct Entry {
    SearchKey key;
    motion::Maybe<double> result;
  };
  constexpr std::size_t kKept = 8;  // four targets, for a profile and the one before
  thread_local std::array<std::optional<Entry>, kKept> kept;
  thread_local std::size_t next = 0;
  for (const auto& e : kept)
    if (e && e->key == key) return e->result;
  auto result = search();
  kept[next] = Entry{key, result};
  next = (next + 1) % kKept;
  return result;
}

// The longitude, in tenths of a degree from -179.9 to 179.9 (§3.18 bytes
// 15-20), whose pointing scores highest; a score below 0 rules it out. Each
// score is the least of the margins the target keeps, so the one chosen
// keeps them all best.
using Score = std::function<double(const look::Pointing&)>;
motion::Maybe<double> best(const Profile& p, Target target, const Score& score, const std::string& wanted) {
  const auto site = site_of(p);
  if (!site.value) return {std::nullopt, site.reason};
  const look::Site& at = *site.value;
  const SearchKey key{target, at.latitude_deg, at.longitude_deg, at.azimuth_offset_deg,
                      p.az.min_deg, p.az.max_deg, p.el.min_deg, p.el.max_deg};
  return cached(key, [&]() -> motion::Maybe<double> {
    std::optional<double> lon;
    double top = 0;
    for (int tenths = -1799; tenths <= 1799; ++tenths) {
      const double x = tenths / 10.0;
      const double s = score(look::pointing(at, x));
      if (s >= 0 && (!lon || s > top)) {
        top = s;
        lon = x;
      }
    }
    if (!lon) return {std::nullopt, wanted};
    return {lon, {}};
  });
}

std::string degrees_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

}  // namespace

motion::Maybe<double> visible(const Profile& p) {
  const motion::Interval el = in_view(p);
  return best(
      p, Target::kVisible,
      [&](const look::Pointing& to) {
        return std::min({to.elevation_deg - el.low, el.high - to.elevation_deg, inside_azimuth(p, to.azimuth_deg) - kInsideLimits});
      },
      "a geostationary satellite in view from the site, " + degrees_text(el.low) + " to " + degrees_text(el.high) +
          " deg up and " + degrees_text(kInsideLimits) + " deg inside the azimuth limits");
}

motion::Maybe<double> below_horizon(const Profile& p) {
  const double top = std::min(0.0, p.el.min_deg) - kBeyondLimits;
  return best(
      p, Target::kBelowHorizon,
      [&](const look::Pointing& to) {
        return std::min({top - to.elevation_deg, to.elevation_deg - kDeepestElevation,
                         inside_azimuth(p, to.azimuth_deg) - kInsideLimits});
      },
      "a geostationary satellite " + degrees_text(kBeyondLimits) +
          " deg below the horizon and the elevation's lower limit whose azimuth is inside the azimuth limits");
}

motion::Maybe<double> outside_azimuth(const Profile& p) {
  const motion::Interval el = in_view(p);
  return best(
      p, Target::kOutsideAzimuth,
      [&](const look::Pointing& to) {
        return std::min({to.elevation_deg - el.low, el.high - to.elevation_deg,
                         look::azimuth_outside_by(p.az, to.azimuth_deg) - kBeyondLimits});
      },
      "a geostationary satellite in view, inside the elevation limits, " + degrees_text(kBeyondLimits) +
          " deg outside the azimuth range (a range that leaves out part of the sky in view)");
}

motion::Maybe<double> above_elevation(const Profile& p) {
  const double bottom = p.el.max_deg + kBeyondLimits;
  return best(
      p, Target::kAboveElevation,
      [&](const look::Pointing& to) {
        return std::min({to.elevation_deg - bottom, kHighestElevation - to.elevation_deg,
                         inside_azimuth(p, to.azimuth_deg) - kInsideLimits});
      },
      "a geostationary satellite in view, at most " + degrees_text(kHighestElevation) + " deg up and " +
          degrees_text(kBeyondLimits) + " deg above the elevation's upper limit, inside the azimuth limits");
}

motion::Maybe<look::Pointing> pointing(const Profile& p, double longitude_deg) {
  const auto site = site_of(p);
  if (!site.value) return {std::nullopt, site.reason};
  look::Pointing to = look::pointing(*site.value, longitude_deg);
  if (p.az_sensor == AzSensor::kFluxgate) {
    // §3.2 NOTE: the compass reads a heading 0.0-359.9.
    if (to.azimuth_deg < 0) to.azimuth_deg += 360;
  } else if (const auto turn = look::azimuth_position(p.az, to.azimuth_deg, (p.az.min_deg + p.az.max_deg) / 2)) {
    to.azimuth_deg = *turn;
  }
  return {to, {}};
}

double slack(const Profile& p, motion::Axis axis) {
  const bool az = axis == motion::Axis::kAz;
  return (az ? kAgreementAz : kAgreementEl) + motion::profile_of(p, axis).tolerance_deg + motion::kDisplayResolution;
}

}  // namespace sabus::harness::locate
