// The stored data a profile says a controller holds, as the codecs write it:
// the request that writes a preset satellite, TLE or signpost slot or the
// navigation data back as the profile has it (§3.10, §3.12, §3.20, §3.23),
// and the reply a read of it must give (§3.11, §3.13, §3.21, §3.22). For
// vectors that restore what they overwrote and check what a controller
// reports against its profile (`from_profile`, vectors/README.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "sabus/harness/profile.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness {

// The commands `from_profile` applies to: writes 39h, 3Bh, 43h, 46h and
// reads 35h, 3Ah, 3Ch, 44h, 45h. Indexed ones take a slot index (35h: an
// entry of the STORE list); 46h and 45h the word "navigation".
bool takes_profile_record(std::uint8_t command_code);
bool record_is_indexed(std::uint8_t command_code);
// The highest index `from_profile` may name for a command: the STORE list's
// 50 entries (35h, §3.6), the TLE list's 10 slots (3Bh, 3Ch, §3.12), the
// preset and signpost lists' 20 (§3.10, §3.20).
long long max_record_index(std::uint8_t command_code);

struct RecordRequest {
  std::optional<Request> request;
  std::string unavailable;  // why not: the capability the profile lacks
};
// The write of the profile's slot `index` (or its navigation data).
RecordRequest profile_write(const Profile& p, std::uint8_t write_code, std::uint32_t index);

struct RecordReply {
  std::optional<Reply> reply;  // the read's reply; an empty slot's has no index
  std::string unavailable;
};
// The reply a read of slot `index` (or of the navigation data) gives on a
// controller that holds what the profile says.
RecordReply profile_read_reply(const Profile& p, std::uint8_t read_code, std::uint32_t index);

}  // namespace sabus::harness
