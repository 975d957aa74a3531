// The coverage matrix of a vector suite (coverage.hpp): which cells a vector
// fills, and which required cells are reported missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "sabus/harness/coverage.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace sabus::harness {
namespace {

// One vector of paragraph 3.2 with the given steps (YAML, indented 6).
std::vector<VectorFile> suite(const std::string& steps) {
  const std::string text = "paragraph: \"3.2\"\ntitle: t\nvectors:\n  - id: 3.2-x\n    comment: c\n"
                           "    spec: {paragraph: \"3.2\", quote: \"status\"}\n    level: must\n    steps:\n" + steps;
  LoadResult r = load_vector_text(text, "coverage.yaml");
  EXPECT_TRUE(r.ok()) << (r.errors.empty() ? "" : r.errors[0].text());
  return r.files;
}

const CoverageRow& row(const CoverageMatrix& m, std::string_view key, std::string_view form) {
  auto it = std::find_if(m.rows.begin(), m.rows.end(), [&](const CoverageRow& r) {
    return r.command->key == key && (r.form ? r.form->id : std::string_view("?")) == form;
  });
  if (it == m.rows.end()) throw std::runtime_error("no row " + std::string(key) + " " + std::string(form));
  return *it;
}

bool missing(const CoverageMatrix& m, const std::string& line) {
  const auto all = m.missing();
  return std::find(all.begin(), all.end(), line) != all.end();
}

TEST(Coverage, AStepFillsTheCellOfItsCommandFormAndPath) {
  const CoverageMatrix m = coverage(suite(
      "      - send: {command: status}\n        expect: ack\n"
      "      - send: {command: jog, form: W, fields: {speed: F, duration: 50}}\n        expect: ack\n"
      "      - send: {raw: \"02 {addr} 31 03 {lrc}\"}\n        modify: {lrc_xor: 1}\n        expect: silence\n"
      "      - send: {raw: \"02 {addr} 29 03 {lrc}\"}\n        expect: {reply: nak, rule: UnknownCommand}\n"));
  EXPECT_EQ(row(m, "status", "").ids[0], std::vector<std::string>{"3.2-x"});
  EXPECT_EQ(row(m, "status", "").ids[3], std::vector<std::string>{"3.2-x"}) << "a bad LRC is the ignore path";
  EXPECT_EQ(row(m, "jog", "W").ids[0], std::vector<std::string>{"3.2-x"});
  EXPECT_TRUE(row(m, "jog", "E").ids[0].empty());
  EXPECT_EQ(m.unknown_codes, std::vector<std::string>{"3.2-x"});
  EXPECT_EQ(m.nak_rules.at("UnknownCommand"), std::vector<std::string>{"3.2-x"});

  EXPECT_FALSE(missing(m, "31h status: ack"));
  EXPECT_FALSE(missing(m, "31h status: ignore"));
  EXPECT_TRUE(missing(m, "31h status: nak"));
  EXPECT_TRUE(missing(m, "31h status: offline"));
  EXPECT_FALSE(missing(m, "33h jog W: ack"));
  EXPECT_TRUE(missing(m, "33h jog E: ack"));
  EXPECT_FALSE(missing(m, "a code outside 30h-48h: nak"));
  EXPECT_TRUE(missing(m, "NAK rule WrongLength (§3): no vector names it"));
  EXPECT_FALSE(missing(m, "NAK rule UnknownCommand (§3): no vector names it"));
}

TEST(Coverage, ADamagedFrameCountsForItsCommandWhenItsFormCannotBeTold) {
  // 41h with a frame too short to decode: the form (preset flag) is unknown.
  const CoverageMatrix m = coverage(suite("      - send: {raw: \"02 {addr} 41 03 {lrc}\"}\n        length_mismatch: true\n"
                                          "        expect: nak\n"));
  EXPECT_EQ(row(m, "remote_locate", "?").ids[1], std::vector<std::string>{"3.2-x"});
  EXPECT_FALSE(missing(m, "41h remote_locate: nak"));
  EXPECT_TRUE(missing(m, "41h remote_locate preset: ack"));
}

TEST(Coverage, TheShippedSuiteHasNoMissingCell) {
  const LoadResult r = load_vectors({default_vectors_dir()});
  ASSERT_TRUE(r.ok());
  const auto m = coverage(r.files);
  EXPECT_EQ(m.missing(), std::vector<std::string>{});
}


}  // namespace
}  // namespace sabus::harness

namespace sabus::harness {
namespace {

const FieldValueRow& value_row(const CoverageMatrix& m, ReplyKind reply, std::string_view field) {
  auto it = std::find_if(m.fields.begin(), m.fields.end(),
                         [&](const FieldValueRow& r) { return r.field->reply == reply && r.field->field == field; });
  if (it == m.fields.end()) throw std::runtime_error("no field " + std::string(field));
  return *it;
}

bool value_missing(const CoverageMatrix& m, const std::string& line) {
  const auto all = m.missing_values();
  return std::find(all.begin(), all.end(), line) != all.end();
}

// The field-value matrix counts a matcher that compares a field with a
// value, not one that checks its form only: the regex every legal value of
// a status byte passes, a range of constants, `any`.
TEST(CoverageValues, AMatcherThatChecksOnlyTheFormIsNotAValueCheck) {
  const CoverageMatrix m = coverage(suite(
      "      - send: {command: status}\n"
      "        expect:\n          reply: ack\n          fields:\n"
      "            az limits: {regex: \"^0x4[0-7]$\"}\n"  // every legal value of byte 32
      "            el limits: {regex: \"^0x4[2367]$\"}\n"  // the down limit bit set: a value
      "            agc: {range: [0, 999]}\n"
      "            alarm code: any\n"
      "            track: {eq: 0x10}\n"
      "            azimuth: {range: [\"{min_deg(az)}\", \"{max_deg(az)}\"]}\n"));
  EXPECT_TRUE(value_row(m, ReplyKind::kStatus, "az limits").ids.empty());
  EXPECT_EQ(value_row(m, ReplyKind::kStatus, "el limits").ids, std::vector<std::string>{"3.2-x"});
  EXPECT_TRUE(value_row(m, ReplyKind::kStatus, "alarm code").ids.empty());
  EXPECT_EQ(value_row(m, ReplyKind::kStatus, "track").ids, std::vector<std::string>{"3.2-x"});
  EXPECT_EQ(value_row(m, ReplyKind::kStatus, "azimuth").ids, std::vector<std::string>{"3.2-x"});
  EXPECT_TRUE(value_row(m, ReplyKind::kExtendedStatus, "azimuth").ids.empty()) << "another reply's field";
  EXPECT_TRUE(value_missing(m, "status az limits (motion, §3.2): no vector checks it"));
  EXPECT_FALSE(value_missing(m, "status el limits (motion, §3.2): no vector checks it"));
  EXPECT_FALSE(value_missing(m, "status agc (device, §3.2): no vector checks it")) << "a measured level is left to the device";
  EXPECT_TRUE(value_missing(m, "pulse count azimuth count (motion, §3.16): no vector checks it"));
}

// A reply expected byte for byte checks every field; the profile's record
// (from_profile) the stored and echoed ones; a NAK none.
TEST(CoverageValues, WholeRepliesAndProfileRecordsCheckTheirFields) {
  const CoverageMatrix m = coverage(suite(
      "      - send: {command: device_type}\n        expect: {reply: ack, bytes: \"06 {addr} 30 33 4B 31 2E 35 39 03 {lrc}\"}\n"
      "      - send: {command: read_satellite, fields: {index: 1}}\n        expect: {reply: ack, from_profile: 1}\n"
      "      - send: {command: read_tle, fields: {index: 99}}\n        expect: {reply: nak, rule: TleIndex}\n"));
  EXPECT_EQ(value_row(m, ReplyKind::kDeviceType, "version").ids, std::vector<std::string>{"3.2-x"});
  EXPECT_EQ(value_row(m, ReplyKind::kSatelliteData, "pol offset").ids, std::vector<std::string>{"3.2-x"});
  EXPECT_EQ(value_row(m, ReplyKind::kSatelliteData, "index").ids, std::vector<std::string>{"3.2-x"});
  EXPECT_TRUE(value_row(m, ReplyKind::kTleData, "tle line 1").ids.empty());
}

// Issue 32: a vector that requires a literal profile value (a firmware, a
// count) checks a field only on the controllers that have it: it does not
// count, and the field is missing, naming it.
TEST(CoverageValues, AVectorOnALiteralProfileValueDoesNotCount) {
  const std::string text =
      "paragraph: \"3.1\"\ntitle: t\nvectors:\n"
      "  - id: 3.1-literal\n    comment: c\n    spec: {paragraph: \"3.1\", quote: q}\n    level: must\n"
      "    requires: {firmware: \"1.59\"}\n"
      "    steps:\n      - send: {command: device_type}\n        expect: {reply: ack, fields: {version: \"1.59\"}}\n"
      "  - id: 3.1-capability\n    comment: c\n    spec: {paragraph: \"3.1\", quote: q}\n    level: must\n"
      "    requires: {dvb_receiver: true}\n"
      "    steps:\n      - send: {command: device_type}\n        expect: {reply: ack, fields: {controller type: \"3K\"}}\n";
  const LoadResult r = load_vector_text(text, "literal.yaml");
  ASSERT_TRUE(r.ok()) << (r.errors.empty() ? "" : r.errors[0].text());
  const CoverageMatrix m = coverage(r.files);
  const auto& version = *std::find_if(m.fields.begin(), m.fields.end(),
                                      [](const FieldValueRow& f) { return field_label(*f.field) == "device type version"; });
  EXPECT_TRUE(version.ids.empty());
  EXPECT_EQ(version.literal_ids, std::vector<std::string>{"3.1-literal"});
  const auto all = m.missing_values();
  EXPECT_NE(std::find_if(all.begin(), all.end(),
                         [](const std::string& l) {
                           return l.rfind("device type version (profile, §3.1): checked only by vectors that require a literal "
                                          "profile value", 0) == 0 && l.ends_with(" 3.1-literal");
                         }),
            all.end());
  EXPECT_TRUE(literal_requirement(r.files[0].vectors[0].requires_[0]));
  EXPECT_FALSE(literal_requirement(r.files[0].vectors[1].requires_[0]));

  // The shares: the controller type, checked only with a DVB receiver, is
  // unchecked on a profile without one, where the reply is asked for.
  Profile with, without;
  with.dvb_receiver = true;
  without.dvb_receiver = false;
  const auto shares = field_shares(m, {requirement_site(r.files, with, "with"), requirement_site(r.files, without, "without")});
  const auto& type = *std::find_if(shares.begin(), shares.end(),
                                   [](const FieldShare& s) { return field_label(*s.field) == "device type controller type"; });
  EXPECT_EQ(type.exists, 2u) << "3.1-literal asks for the reply on both (1.59 is the default firmware)";
  EXPECT_EQ(type.checked, 1u);
  EXPECT_EQ(type.unchecked, std::vector<std::string>{"without"});
  const auto& v = *std::find_if(shares.begin(), shares.end(),
                                [](const FieldShare& s) { return field_label(*s.field) == "device type version"; });
  EXPECT_EQ(v.exists, 2u);
  EXPECT_EQ(v.checked, 0u);
  // A profile where no vector asks for the reply does not count.
  Profile other_firmware;
  other_firmware.firmware = "2.00";
  const auto none = field_shares(m, {requirement_site(r.files, other_firmware, "2.00")});
  EXPECT_EQ(std::find_if(none.begin(), none.end(), [](const FieldShare& s) {
              return field_label(*s.field) == "device type version";
            })->exists,
            0u);
}

// E-85: a pot or fluxgate mount's pulse counts have no scale the spec or the
// profile gives; the reply is asked for there, but its counts are no value
// to check, so the profile does not count where they exist.
TEST(CoverageValues, PulseCountsCountOnlyWhereTheAzimuthSensorCounts) {
  Profile pot, pulse, fluxgate, resolver;
  pot.az_sensor = AzSensor::kPot;
  pulse.az_sensor = AzSensor::kPulse;
  fluxgate.az_sensor = AzSensor::kFluxgate;
  resolver.az_sensor = AzSensor::kResolver;
  const std::set<std::string> counts = {"pulse count azimuth count", "pulse count elevation count"};
  EXPECT_EQ(undetermined_fields(pot), counts);
  EXPECT_EQ(undetermined_fields(fluxgate), counts);
  EXPECT_TRUE(undetermined_fields(pulse).empty());
  EXPECT_TRUE(undetermined_fields(resolver).empty());

  const auto files = suite("      - send: {command: pulse_count}\n        expect: ack\n");
  const CoverageMatrix m = coverage(files);
  const auto shares = field_shares(m, {requirement_site(files, pot, "pot"), requirement_site(files, pulse, "pulse")});
  const auto& az = *std::find_if(shares.begin(), shares.end(),
                                 [](const FieldShare& s) { return field_label(*s.field) == "pulse count azimuth count"; });
  EXPECT_EQ(az.exists, 1u) << "the pulse mount only";
  EXPECT_EQ(az.checked, 0u);
  EXPECT_EQ(az.unchecked, std::vector<std::string>{"pulse"});
}

}  // namespace
}  // namespace sabus::harness
