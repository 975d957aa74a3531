// A reference controller on a virtual clock, for tests that drive it
// request by request (the controller's own tests and the readings' tests):
// send a request or raw data, decode its reply, let time pass.
#pragma once

#include <gtest/gtest.h>

#include <string_view>
#include <utility>
#include <variant>

#include "sabus/harness/controller.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness {

struct ControllerRig {
  explicit ControllerRig(Profile p, FaultSet f = {}) : profile(std::move(p)), c(profile, clock, f) {}
  VirtualClock clock;
  Profile profile;
  Controller c;

  Outcome send(const Request& r) { return c.execute(request_frame(r, profile.address)); }
  Outcome send_raw(std::uint8_t code, std::string_view data) {
    return c.execute(Frame{FrameKind::kCommand, profile.address, code, Bytes(data.begin(), data.end())});
  }
  // The reply to `r`, decoded as a T (a test failure when it is not one).
  template <class T>
  T reply(const Request& r) {
    Outcome o = send(r);
    EXPECT_TRUE(o.reply.has_value()) << o.note;
    auto f = decode_frame(*o.reply);
    EXPECT_TRUE(f.ok()) << f.error().message();
    auto d = decode_reply(f.value());
    EXPECT_TRUE(d.ok()) << d.error().message() << " in " << to_hex(*o.reply);
    EXPECT_TRUE(std::holds_alternative<T>(d.value())) << o.note;
    return std::get<T>(d.value());
  }
  void wait(Duration d) {
    clock.advance(d);
    c.update();
  }
  StatusBlock status() { return reply<StatusReply>(StatusPoll{}).status; }
  ExtendedStatusReply extended() { return reply<ExtendedStatusReply>(ExtendedStatusPoll{}); }
};

inline bool is_nak(const Outcome& o) { return o.reply && !o.reply->empty() && (*o.reply)[0] == NAK; }

}  // namespace sabus::harness
