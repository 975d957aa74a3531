// Requests from named fields, as vectors write them.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"

namespace sabus {
namespace {

std::string data_of(const Expected<Request>& r) {
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message());
  if (!r.ok()) return "";
  Bytes d = encode_request_data(r.value());
  return std::string(d.begin(), d.end());
}

const CommandInfo& cmd(std::string_view key) { return *find_command(key); }

TEST(BuildRequest, AutoMoveForms) {
  EXPECT_EQ(data_of(build_request(cmd("auto_move"), "2A", {{"azimuth", "-152.5"}, {"elevation", "45.6"}})),
            " -152500456");
  EXPECT_EQ(data_of(build_request(cmd("auto_move"), "1", {{"polarization", "H"}, {"sat name", "SBS 6"}})),
            "HSBS 6     ");
  EXPECT_EQ(data_of(build_request(cmd("auto_move"), "2C", {{"axis", "A"}, {"target", "-123.45"}})), "A-12345    ");
  EXPECT_EQ(data_of(build_request(cmd("auto_move"), "3", {{"pol target", "50.0"}})), "P0050000000");
}

TEST(BuildRequest, TheFormSetsTheSelector) {
  EXPECT_EQ(data_of(build_request(cmd("jog"), "E", {{"speed", "F"}, {"duration", "50"}})), "EF0050");
  EXPECT_EQ(data_of(build_request(cmd("misc"), "K", {{"parameter", "0x3A"}})), "K:");
  EXPECT_EQ(data_of(build_request(cmd("pol_preset"), "V", {})), "V");
  auto locate = build_request(cmd("remote_locate"), "preset", {{"preset flag/index", "preset 5"}});
  ASSERT_TRUE(locate.ok());
  EXPECT_TRUE(std::get<RemoteLocate>(locate.value()).preset.preset);
  EXPECT_EQ(std::get<RemoteLocate>(locate.value()).preset.index, 5);
}

TEST(BuildRequest, DataCommands) {
  EXPECT_EQ(data_of(build_request(cmd("write_satellite"), "",
                                  {{"index", "20"}, {"sat name", "GALAXY 19"}, {"longitude", "-97.1"},
                                   {"inclination", "0"}, {"band", "1"}, {"pol offset", "-12.5"}})),
            "20GALAXY 19 -97.1 0 10-12.5");
  EXPECT_EQ(data_of(build_request(cmd("write_navigation"), "", {{"latitude", "1234"}, {"longitude", "-1234"},
                                                               {"true heading", "123.4"}})),
            "01234-01234123.4            ");
}

TEST(BuildRequest, ErrorsNameTheField) {
  auto unknown = build_request(cmd("jog"), "E", {{"speeed", "F"}});
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message().find("speeed"), std::string::npos);
  EXPECT_NE(unknown.error().message().find("duration"), std::string::npos) << "lists the known fields";
  auto bad = build_request(cmd("jog"), "E", {{"duration", "fifty"}});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message().find("duration"), std::string::npos);
  EXPECT_FALSE(build_request(cmd("auto_move"), "2Z", {}).ok());
  EXPECT_FALSE(build_request(cmd("query_name"), "", {{"index", "100"}}).ok());
}

TEST(BuildRequest, NumbersOutOfRangeOrWithTwoSignsAreErrors) {
  // A digit string too long for any field (found by fuzz_differential: scaling
  // it to the field's decimals overflowed).
  for (const char* target : {"777777777777777777777777770", "-99999999999999999999", "9223372036854775807",
                             "922337203685477580.7", "2147483648", "--5", "-+5", "+-5", "0x-5", "-0x-5"}) {
    auto r = build_request(cmd("auto_move"), "2C", {{"axis", "A"}, {"target", target}});
    EXPECT_FALSE(r.ok()) << target;
    if (!r.ok()) {
      EXPECT_NE(r.error().message().find("target"), std::string::npos) << target;
    }
  }
  EXPECT_EQ(data_of(build_request(cmd("auto_move"), "2C", {{"axis", "A"}, {"target", "-5"}})), "A-00500    ");
  EXPECT_EQ(data_of(build_request(cmd("auto_move"), "2C", {{"axis", "A"}, {"target", "+5"}})), "A000500    ");
  EXPECT_FALSE(build_request(cmd("jog"), "E", {{"duration", "--5"}}).ok());
  EXPECT_FALSE(build_request(cmd("misc"), "K", {{"parameter", "0x-3A"}}).ok());
}

// A number the field's characters cannot carry is an error, not a value with
// its high digits dropped; out of the spec's range but within the width is
// sent (vectors do so on purpose).
TEST(BuildRequest, NumbersWiderThanTheirFieldAreErrors) {
  for (const auto& [command, form, field, value] : std::vector<std::array<std::string, 4>>{
           {"auto_move", "2A", "azimuth", "-1000"},             // went out as -00000
           {"auto_move", "2A", "azimuth", "12345.6"},           // went out as 2345.6
           {"write_navigation", "", "latitude", "-10000"},
           {"write_navigation", "", "latitude", "123456"},
           {"write_satellite", "", "longitude", "-12345.6"},
           {"write_navigation", "", "true heading", "12345.6"}}) {
    std::map<std::string, std::string> fields{{field, value}};
    if (command == "write_satellite") fields["index"] = "1";
    auto r = build_request(cmd(command), form, fields);
    ASSERT_FALSE(r.ok()) << command << " " << field << " " << value;
    EXPECT_NE(r.error().message().find("does not fit its"), std::string::npos) << r.error().message();
    EXPECT_NE(r.error().message().find(field), std::string::npos) << r.error().message();
  }
  EXPECT_EQ(data_of(build_request(cmd("auto_move"), "2A", {{"azimuth", "-999.9"}, {"elevation", "99.9"}})),
            " -999900999");
  EXPECT_EQ(data_of(build_request(cmd("auto_move"), "2A", {{"azimuth", "999.0"}, {"elevation", "0"}})), " 0999000000");
}

TEST(FieldNames, RequestsAndReplies) {
  EXPECT_EQ(request_field_names(cmd("auto_move"), "2A"),
            (std::vector<std::string>{"polarization", "azimuth", "elevation"}));
  auto status = reply_field_names(cmd("status"));
  for (const char* f : {"start", "az status", "azimuth", "track", "agc channel", "check byte"})
    EXPECT_NE(std::find(status.begin(), status.end(), f), status.end()) << f;
  auto sat = reply_field_names(cmd("read_satellite"));
  EXPECT_NE(std::find(sat.begin(), sat.end(), "no data"), sat.end()) << "the empty-slot form";
  EXPECT_NE(std::find(sat.begin(), sat.end(), "longitude"), sat.end());
}

}  // namespace
}  // namespace sabus
