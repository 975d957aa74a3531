// Any sequence of valid commands keeps the reference controller's invariants,
// and every reply is a well-formed frame with the controller's address, a
// correct LRC and the catalog's length for its command (or NAK / offline).
#include "generators.hpp"
#include "sabus/harness/controller.hpp"

namespace sabus::harness {
namespace {

template <std::size_t... I>
Request random_request_of(std::size_t which, std::index_sequence<I...>) {
  Request r = StatusPoll{};
  (void)((which == I ? (r = gen::random_request<std::variant_alternative_t<I, Request>>(), true) : false) || ...);
  return r;
}

Request random_request() {
  const auto which = static_cast<std::size_t>(*rc::gen::inRange<int>(0, std::variant_size_v<Request>));
  return random_request_of(which, std::make_index_sequence<std::variant_size_v<Request>>{});
}

Profile random_profile() {
  Profile p;
  p.pol_type = *rc::gen::element(PolType::kCircular, PolType::kSinglePort, PolType::kDualPort);
  p.az_sensor = *rc::gen::element(AzSensor::kPot, AzSensor::kPulse, AzSensor::kResolver, AzSensor::kFluxgate);
  p.hundredths = *rc::gen::arbitrary<bool>();
  p.dvb_receiver = *rc::gen::arbitrary<bool>();
  p.stow = *rc::gen::arbitrary<bool>();
  p.remote_enabled = *rc::gen::inRange(0, 8) != 0;
  p.implements_iess = *rc::gen::arbitrary<bool>();
  p.implements_signal_strength = *rc::gen::arbitrary<bool>();
  p.track.active = *rc::gen::arbitrary<bool>();
  p.track.activity = *rc::gen::element(TrackActivity::kIdle, TrackActivity::kPeaking, TrackActivity::kSearching,
                                       TrackActivity::kError);
  p.track.dual_band = *rc::gen::arbitrary<bool>();
  p.store = {{"SBS 6", -74.0, 40.0, 10.0, -80.0}};
  return p;
}

RC_GTEST_PROP(ControllerProperties, RepliesAreWellFormedAndInvariantsHold, ()) {
  const Profile p = random_profile();
  VirtualClock clock;
  Controller c(p, clock);
  const int steps = *rc::gen::inRange(1, 40);
  for (int i = 0; i < steps; ++i) {
    const Request r = random_request();
    const Frame command = request_frame(r, p.address);
    const Outcome o = c.execute(command);
    RC_ASSERT(o.reply.has_value());
    const auto frame = decode_frame(*o.reply);
    RC_ASSERT(frame.ok());
    RC_ASSERT(frame.value().address == p.address);
    RC_ASSERT(frame.value().command == command.command);
    const CommandInfo* info = find_command(command.command);
    const std::size_t n = o.reply->size();
    if (frame.value().kind == FrameKind::kNak) {
      RC_ASSERT(n == kNakReplyLength);
      RC_ASSERT(o.nak.has_value());
    } else if (is_offline_reply(frame.value())) {
      RC_ASSERT(!p.remote_enabled);
    } else {
      if (info->reply_length) RC_ASSERT(n == std::size_t{*info->reply_length});
      const auto decoded = decode_reply(frame.value());
      if (!decoded.ok()) RC_FAIL(decoded.error().message() + " in " + to_hex(*o.reply));
    }
    const auto invariants = c.check_invariants();
    if (!invariants.empty()) RC_FAIL(invariants);
    clock.advance(std::chrono::milliseconds(*rc::gen::inRange(0, 20000)));
    c.update();
    RC_ASSERT(c.check_invariants().empty());
  }
}

}  // namespace
}  // namespace sabus::harness
