// The geometry of a LOCATE (look_angles.hpp; ERRATA E-80): look angles from
// the site checked against what follows from the sphere without the code's
// vector algebra (the same meridian, the horizon's longitude, the mirror of
// the hemispheres), and the mount's azimuth from the heading and the sensor.
#include "sabus/harness/look_angles.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace sabus::harness::look {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRatio = 6378.137 / 42164.17;  // earth radius / orbit radius

// On the site's own meridian the satellite is due south (north of the
// equator) or due north, at the elevation of the plane triangle: tan(el) =
// (cos(lat) - R/r) / sin(lat).
TEST(LookAngles, OnTheSitesMeridianTheSatelliteIsDueSouthOrNorth) {
  const double lat = 40.0 * kPi / 180;
  const double el = std::atan2(std::cos(lat) - kRatio, std::sin(lat)) * 180 / kPi;
  const LookAngles north = geostationary(40.0, -75.0, -75.0);
  EXPECT_NEAR(north.azimuth_deg, 180.0, 1e-9);
  EXPECT_NEAR(north.elevation_deg, el, 1e-9);
  const LookAngles south = geostationary(-40.0, 151.2, 151.2);
  EXPECT_NEAR(std::fmod(south.azimuth_deg, 360.0), 0.0, 1e-9) << "due north seen from the south";
  EXPECT_NEAR(south.elevation_deg, el, 1e-9);
  EXPECT_NEAR(geostationary(0.0, 10.0, 10.0).elevation_deg, 90.0, 1e-9) << "overhead on the equator";
}

// From the equator the satellite sets where cos(dlon) = R/r (81.3 deg away),
// due east or due west.
TEST(LookAngles, TheHorizonFromTheEquator) {
  const double dlon = std::acos(kRatio) * 180 / kPi;
  const LookAngles east = geostationary(0.0, 0.0, dlon);
  EXPECT_NEAR(east.elevation_deg, 0.0, 1e-9);
  EXPECT_NEAR(east.azimuth_deg, 90.0, 1e-9);
  EXPECT_NEAR(geostationary(0.0, 0.0, -dlon).azimuth_deg, 270.0, 1e-9);
  EXPECT_LT(geostationary(0.0, 0.0, dlon + 1).elevation_deg, 0.0);
  EXPECT_GT(geostationary(0.0, 0.0, dlon - 1).elevation_deg, 0.0);
}

// The southern site sees the mirror of the northern one: the same elevation,
// the azimuth reflected about the east-west line (az -> 180 - az); a site
// west of the satellite sees it east of south, in the north.
TEST(LookAngles, TheHemispheresAreMirrors) {
  const LookAngles n = geostationary(33.0 + 52 / 60.0, 151.2, 170.0);
  const LookAngles s = geostationary(-(33.0 + 52 / 60.0), 151.2, 170.0);
  EXPECT_NEAR(n.elevation_deg, s.elevation_deg, 1e-9);
  EXPECT_NEAR(std::fmod(n.azimuth_deg + s.azimuth_deg, 360.0), 180.0, 1e-9);
  EXPECT_GT(n.azimuth_deg, 90.0);
  EXPECT_LT(n.azimuth_deg, 180.0) << "east of south";
  EXPECT_GT(s.azimuth_deg, 0.0);
  EXPECT_LT(s.azimuth_deg, 90.0) << "east of north";
  // A satellite at 97.0 W is below the horizon from 33 52' S 151 12' E (issue 22).
  EXPECT_LT(geostationary(-(33.0 + 52 / 60.0), 151.2, -97.0).elevation_deg, 0.0);
}

// §3.23 "True Heading of mount azimuth 0.0": position = true azimuth - heading.
TEST(LookAngles, TheMountAzimuthIsTheTrueAzimuthLessTheHeading) {
  Navigation nav;
  nav.latitude_min = 40 * 60;
  nav.longitude_min = -75 * 60;
  EXPECT_EQ(site_of(nav, AzSensor::kPot, 'T').missing, Missing::kHeading);
  nav.heading_tenths = 300;
  const SiteOf s = site_of(nav, AzSensor::kPot, 'T');
  ASSERT_TRUE(s.site);
  EXPECT_NEAR(mount_azimuth(*s.site, 180.0), 150.0, 1e-9);
  EXPECT_NEAR(mount_azimuth(*s.site, 10.0), -20.0, 1e-9);
  EXPECT_NEAR(pointing(*s.site, -75.0).azimuth_deg, 150.0, 1e-9);
  // The fluxgate compass reads where the antenna points: the heading plays
  // no part; a magnetic one less the variation, east positive.
  const SiteOf t = site_of(nav, AzSensor::kFluxgate, 'T');
  ASSERT_TRUE(t.site);
  EXPECT_NEAR(mount_azimuth(*t.site, 180.0), 180.0, 1e-9);
  EXPECT_EQ(site_of(nav, AzSensor::kFluxgate, 'M').missing, Missing::kMagvar);
  nav.magvar_tenths = 125;
  const SiteOf m = site_of(nav, AzSensor::kFluxgate, 'M');
  ASSERT_TRUE(m.site);
  EXPECT_NEAR(mount_azimuth(*m.site, 180.0), 167.5, 1e-9);
  nav.latitude_min.reset();
  EXPECT_EQ(site_of(nav, AzSensor::kPot, 'T').missing, Missing::kLatLon);
}

TEST(LookAngles, TheTurnOfAnAzimuthInsideTheLimits) {
  AxisProfile a;
  a.min_deg = -170;
  a.max_deg = 20;
  EXPECT_EQ(azimuth_position(a, 10.0, 0.0), 10.0);
  EXPECT_EQ(azimuth_position(a, 200.0, 0.0), -160.0) << "a turn back";
  EXPECT_EQ(azimuth_position(a, 90.0, 0.0), std::nullopt);
  EXPECT_NEAR(azimuth_outside_by(a, 90.0), 70.0, 1e-9);
  EXPECT_NEAR(azimuth_outside_by(a, -160.0), -10.0, 1e-9);
  AxisProfile wide;
  wide.min_deg = -180;
  wide.max_deg = 360;
  EXPECT_EQ(azimuth_position(wide, 10.0, 300.0), 370.0 - 360.0) << "370 is past the limit";
  EXPECT_EQ(azimuth_position(wide, 10.0, 340.0), 10.0);
  EXPECT_EQ(azimuth_position(wide, 200.0, 0.0), -160.0) << "the turn nearest the current position";
  EXPECT_EQ(azimuth_position(wide, 200.0, 100.0), 200.0);
}

}  // namespace
}  // namespace sabus::harness::look
