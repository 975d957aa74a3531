// Differential fuzz target: structured commands (as vectors write them: a
// catalog command, a form and named field values) built and encoded by the
// codecs, executed by the reference controller, the reply decoded by the
// codecs -- and the decoded fields compared with the model's state.
// Input: byte 0 picks the device profile; then up to 8 commands, each
//   [command selector] [form selector] then per request field (in
//   request_field_names order) one byte b: b >= 80h keeps the field's
//   default, else b characters of text follow as its value.
// Oracles, per command:
//  - the encoding is canonical: decode_request(encode(r)) encodes to the same bytes;
//  - there is exactly one reply; it decodes, with the device's address and the command's code;
//  - a NAK names its rule and changes no stored data and no motion;
//  - an ACK's decoded fields agree with the model: status blocks, extended
//    status modes, query name, display, pulse counts, device type, preset /
//    TLE / signpost slots, navigation data, jog position;
//  - a write that was ACKed reads back (39h/3Ah, 3Bh/3Ch, 43h/44h) as the
//    request the controller received;
//  - the model's invariants hold.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "fuzz_support.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"

namespace {

using namespace sabus;
using harness::Controller;

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz_differential oracle: %s\n", what.c_str());
  std::abort();
}

struct Stored {
  std::vector<harness::StoredSatellite> store;
  std::array<std::optional<harness::PresetSatellite>, 20> presets;
  std::array<std::optional<harness::TleSet>, 10> tles;
  std::array<std::optional<harness::Signpost>, 20> signposts;
  harness::Navigation navigation;
  harness::AxisState::Motion az, el, pol;
  bool operator==(const Stored&) const = default;
};
Stored snapshot(const Controller& c) {
  const auto& s = c.state();
  return {s.store, s.presets, s.tles, s.signposts, s.navigation, s.az.motion, s.el.motion, s.pol.motion};
}

std::string trimmed(std::string s) {
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// Executes a command frame; returns the decoded reply frame and reply.
std::pair<Frame, Reply> run_command(Controller& c, const Frame& command) {
  Expected<Frame> f = command;
  const auto o = c.execute(f.value());
  if (!o.reply) fail("no reply to a command for this address");
  auto rf = decode_frame(*o.reply);
  if (!rf) fail("the reply is not a frame: " + rf.error().message());
  if (rf.value().address != c.profile().address) fail("a reply with another address");
  if (rf.value().command != f.value().command) fail("a reply with another command code");
  if ((rf.value().kind == FrameKind::kNak) != o.nak.has_value()) fail("a NAK without a rule, or a rule without NAK");
  auto reply = decode_reply(rf.value());
  if (!reply) fail("the reply does not decode: " + reply.error().message());
  return {rf.value(), reply.value()};
}

template <class ReadT>
Reply read_back(Controller& c, std::uint32_t index) {
  ReadT r;
  r.index = index;
  return run_command(c, request_frame(Request{r}, c.profile().address)).second;
}

void check_ack(Controller& c, const Request& wire_request, const Reply& reply) {
  const auto& st = c.state();
  std::visit(
      [&](const auto& rep) {
        using T = std::decay_t<decltype(rep)>;
        if constexpr (std::is_same_v<T, StatusReply>) {
          if (!(rep.status == c.status_block())) fail("a status reply that is not the model's status");
        } else if constexpr (std::is_same_v<T, ExtendedStatusReply>) {
          if (!(rep.status == c.status_block())) fail("an extended status block that is not the model's");
          if (rep.mode != st.mode.mode || rep.state != st.mode.state || rep.last_mode != st.mode.last_mode ||
              rep.exit_status != st.mode.exit_status)
            fail("extended status modes that are not the model's");
        } else if constexpr (std::is_same_v<T, DeviceTypeReply>) {
          if (rep.version != c.profile().firmware) fail("a version that is not the profile's");
        } else if constexpr (std::is_same_v<T, QueryNameReply>) {
          const auto& q = std::get<QueryName>(wire_request);
          if (rep.index != q.index || rep.total != st.store.size()) fail("query name index or total");
          if (q.index < 1 || q.index > st.store.size() || trimmed(rep.name) != trimmed(st.store[q.index - 1].name))
            fail("query name: a name that is not the STORE list's");
        } else if constexpr (std::is_same_v<T, DisplayReply>) {
          const DisplayReply d = c.display();
          for (std::size_t i = 0; i < 4; ++i)
            if (trimmed(rep.rows[i]) != trimmed(d.rows[i])) fail("a display row that is not the model's");
        } else if constexpr (std::is_same_v<T, PulseCountReply>) {
          if (rep.az != c.counts(harness::AxisId::kAz) || rep.el != c.counts(harness::AxisId::kEl))
            fail("pulse counts that are not the model's");
        } else if constexpr (std::is_same_v<T, SatelliteDataReply>) {
          const auto& p = st.presets[std::get<ReadSatellite>(wire_request).index - 1];
          if (p.has_value() != rep.index.has_value()) fail("a preset slot reported full/empty wrongly");
          if (p && !(rep.sat == p->data)) fail("preset data that is not the model's");
        } else if constexpr (std::is_same_v<T, TleDataReply>) {
          const auto& t = st.tles[std::get<ReadTle>(wire_request).index - 1];
          if (t.has_value() != rep.index.has_value()) fail("a TLE slot reported full/empty wrongly");
          if (t && (trimmed(rep.line1) != trimmed(t->line1) || trimmed(rep.line2) != trimmed(t->line2)))
            fail("TLE lines that are not the model's");
        } else if constexpr (std::is_same_v<T, SignpostDataReply>) {
          const auto& s = st.signposts[std::get<ReadSignpost>(wire_request).index - 1];
          if (s.has_value() != rep.index.has_value()) fail("a signpost slot reported full/empty wrongly");
          if (s && !(rep.signpost == s->data)) fail("signpost data that is not the model's");
        } else if constexpr (std::is_same_v<T, NavigationDataReply>) {
          const auto& n = st.navigation;
          if (rep.latlon_source != n.latlon_source || rep.latitude != n.latitude_min ||
              rep.longitude != n.longitude_min || rep.heading_source != n.heading_source ||
              rep.heading != n.heading_tenths || rep.magvar != n.magvar_tenths)
            fail("navigation data that is not the model's");
        } else if constexpr (std::is_same_v<T, JogPositionReply>) {
          // §3.24: the position when the command was received; the jog has not
          // moved the axis yet (no time passed), so it is the model's position.
          const auto axis = rep.axis == 'A' ? harness::AxisId::kAz
                            : rep.axis == 'E' ? harness::AxisId::kEl
                                              : harness::AxisId::kPol;
          const auto& a = axis == harness::AxisId::kAz ? st.az : axis == harness::AxisId::kEl ? st.el : st.pol;
          if (rep.position && *rep.position != static_cast<std::int32_t>(std::lround(a.position * 10)))
            fail("a jog position that is not the model's");
        }
      },
      reply);

  // Writes read back as the controller received them.
  if (const auto* w = std::get_if<WriteSatellite>(&wire_request)) {
    const auto r = read_back<ReadSatellite>(c, w->index);
    const auto* d = std::get_if<SatelliteDataReply>(&r);
    if (!d || !d->index || !(d->sat == w->sat)) fail("a written preset does not read back");
  } else if (const auto* w = std::get_if<WriteTle>(&wire_request)) {
    const auto r = read_back<ReadTle>(c, w->index);
    const auto* d = std::get_if<TleDataReply>(&r);
    if (!d || !d->index || trimmed(d->line1) != trimmed(w->line1) || trimmed(d->line2) != trimmed(w->line2))
      fail("a written TLE does not read back");
  } else if (const auto* w = std::get_if<WriteSignpost>(&wire_request)) {
    const auto r = read_back<ReadSignpost>(c, w->index);
    const auto* d = std::get_if<SignpostDataReply>(&r);
    if (!d || !d->index || !(d->signpost == w->signpost)) fail("a written signpost does not read back");
  } else if (std::holds_alternative<WriteNavigation>(wire_request)) {
    if (!st.store.empty()) fail("the STORE list survived a navigation write (§3.23 NOTE)");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // No early return: the empty input builds a controller, instrumented code,
  // so libFuzzer has coverage from its first input without a corpus.
  const auto& profiles = fuzz::profiles();
  const harness::Profile& profile = profiles[(size > 0 ? data[0] : 0) % profiles.size()];
  harness::VirtualClock clock;
  Controller c(profile, clock);
  std::size_t at = 1;
  auto next = [&]() -> int { return at < size ? data[at++] : -1; };
  for (int n = 0; n < 8 && at + 2 <= size; ++n) {
    const CommandInfo& info = catalog()[static_cast<std::size_t>(next()) % catalog().size()];
    const FormInfo& form = info.forms[static_cast<std::size_t>(next()) % info.forms.size()];
    std::map<std::string, std::string> fields;
    for (const auto& name : request_field_names(info, form.id)) {
      const int b = next();
      if (b < 0) break;
      if (b >= 0x80) continue;
      std::string value;
      for (int i = 0; i < b && at < size; ++i) value.push_back(static_cast<char>(data[at++] & 0x7F));
      fields[name] = value;
    }
    const auto request = build_request(info, form.id, fields);
    if (!request) continue;  // a value the codecs refuse: nothing to send

    const Bytes bytes = encode_request(request.value(), profile.address);
    // A field may hold a control character on purpose (a vector testing the
    // receiver, READING-NOTES 6): such a frame never reaches the controller.
    bool control = false;
    for (std::size_t i = 1; i + 2 < bytes.size(); ++i) control = control || bytes[i] < 0x20;
    if (control) continue;
    const auto frame = decode_frame(bytes);
    if (!frame) fail("an encoded request is not a frame: " + frame.error().message());
    const auto wire_request = decode_request(frame.value());
    const Stored before = snapshot(c);
    const auto [reply_frame, reply] = run_command(c, frame.value());
    if (!wire_request) {
      // build_request does not check every value against its set, so that a
      // vector can send a wrong one on purpose: the controller must refuse it.
      if (reply_frame.kind != FrameKind::kNak && !is_offline_reply(reply_frame))
        fail("an ACK to a request whose fields do not decode: " + wire_request.error().message());
      if (!(snapshot(c) == before)) fail("a refused request changed stored data or motion");
      continue;
    }
    if (encode_request(wire_request.value(), profile.address) != bytes) fail("the request encoding is not canonical");
    if (reply_frame.kind == FrameKind::kNak) {
      if (!(snapshot(c) == before)) fail("a NAK that changed stored data or motion");
    } else if (!is_offline_reply(reply_frame)) {
      check_ack(c, wire_request.value(), reply);
    }
    const std::string broken = c.check_invariants();
    if (!broken.empty()) fail(broken);
  }
  return 0;
}
