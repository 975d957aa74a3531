// The front door of the reference controller: Controller::execute checks a
// frame (known code, catalog length, remote control enabled, implemented,
// decodes) and dispatch hands the request to its handler; and the replies
// every handler builds (ACK, status, NAK naming its rule). The handlers
// themselves are in handlers_*.cpp by command family (handlers.hpp).
#include "handlers.hpp"

namespace sabus::harness {

Outcome Handlers::ack(C& c, std::uint8_t code, Reply reply, std::string note) {
  auto frame = reply_frame(reply, c.profile_.address, code);
  return Outcome{c.finish_reply(frame.value()), std::nullopt, std::move(note), false};
}
Outcome Handlers::status(C& c, std::uint8_t code, std::string note) {
  return ack(c, code, StatusReply{c.status_block(), ""}, std::move(note));
}
Outcome Handlers::nak(C& c, std::uint8_t code, NakRule rule, std::string detail) {
  std::string note = "NAK §" + std::string(paragraph(rule)) + ": " + std::string(description(rule));
  if (!detail.empty()) note += " (" + detail + ")";
  return Outcome{c.finish_reply(nak_reply(c.profile_.address, code)), rule, std::move(note), false};
}
Outcome Handlers::stored(Outcome o) {
  o.stored_data_changed = true;
  return o;
}

// Commands that move the antenna hand control to REMOTE mode (§3 Online/Offline
// Reply NOTE: "A few commands ... cause the RC3000 to enter the REMOTE mode";
// ERRATA E-52).
Outcome Handlers::unanswered(std::string note) { return Outcome{std::nullopt, std::nullopt, std::move(note), false}; }
void Handlers::take_remote_control(C& c) {
  if (!c.in_mode("REMOTE_MODE")) c.enter_mode("REMOTE_MODE", "WAITING_FOR_USER_INPUT");
}
// ERRATA E-52: a jog (33h, 47h) or 34h enters REMOTE on the reference side;
// the other side (only 32h of the NOTE's "a few commands") acts from the
// mode it is in, an automatic function it takes over left for MANUAL_MODE.
void Handlers::take_control_to_move(C& c) {
  if (!c.reads_other("E-52")) return take_remote_control(c);
  if (c.in_mode("LOCATE_MODE") || c.in_mode("STOW_MODE") || c.in_mode("DEPLOY_MODE") || c.in_mode("SPIRAL_REMOTE_MODE"))
    c.enter_mode("MANUAL_MODE", "MANUAL_IDLE");
}
bool Handlers::track_busy(const C& c) { return !c.pol_moves_allowed(); }

// ---- §3.9 / §3.14 / §3.15 (not implemented on software 1.59) ---------------------
bool Handlers::implemented(const C& c, std::uint8_t code) {
  if (c.faults_.has(Fault::kUnimplementedAcked)) return true;
  if (code == 0x38) return c.profile_.implements_signal_strength;
  if (code == 0x3D || code == 0x3E) return c.profile_.implements_iess;
  return find_command(code)->implemented;
}

// ---- the front door ------------------------------------------------------------

namespace {

// ERRATA E-91's other side: the polarization fields of 41h (byte 29) and 42h
// (bytes 29-39) are not read on a circular feed, so whatever they hold
// decodes as a selection with no values ('N' none; 'H' with blank
// positions, which §3.19 stores as nothing on a circular feed).
void blank_polarization_fields(Frame& f) {
  constexpr std::size_t kFirstDataByte = 3;  // after STX, address and command (§1)
  constexpr std::size_t kByte29 = 29 - kFirstDataByte;
  if (f.command == 0x41 && f.data.size() > kByte29) f.data[kByte29] = 'N';
  if (f.command == 0x42 && f.data.size() > kByte29 + 10) {
    f.data[kByte29] = 'H';
    std::fill(f.data.begin() + kByte29 + 1, f.data.begin() + kByte29 + 11, ' ');
  }
}

// ERRATA E-66's other side: the commands that leave a LOCATE "immediately
// prior" to a 42h: reads of the state (§3.1, §3.2, §3.8, §3.16, §3.17), the
// LOCATE itself and the Remote Store.
bool keeps_locate_claim(std::uint8_t code) {
  for (std::uint8_t read : {0x30, 0x31, 0x37, 0x3F, 0x40, 0x41, 0x42})
    if (code == read) return true;
  return false;
}

}  // namespace

Outcome Controller::execute(const Frame& f) {
  update();
  const CommandInfo* info = find_command(f.command);
  const bool offline = !profile_.remote_enabled && !faults_.has(Fault::kRemoteDisabledAnswers);
  auto offline_outcome = [&] {
    return Outcome{finish_reply(offline_reply(profile_.address, f.command)), std::nullopt,
                   "offline: remote control disabled", false};
  };
  auto unknown = [&](NakRule rule, std::string detail) -> Outcome {
    // E-10: unknown code (or wrong length) while offline is a profile switch.
    if (offline && profile_.unknown_command_while_offline == OfflineUnknown::kOffline) return offline_outcome();
    if (rule == NakRule::kUnknownCommand && faults_.has(Fault::kSilentUnknownCommand))
      return Handlers::unanswered("unknown command ignored");
    return Handlers::nak(*this, f.command, rule, std::move(detail));
  };
  if (!info) return unknown(NakRule::kUnknownCommand, describe_byte(f.command));

  Frame command = f;
  const std::size_t length = f.data.size() + kFrameOverhead;
  if (info->request_length && length != *info->request_length) {
    if (length > *info->request_length && faults_.has(Fault::kExecutesOverlong))
      command.data.resize(*info->request_length - kFrameOverhead);
    else
      return unknown(NakRule::kWrongLength,
                     std::to_string(length) + " bytes, " + std::to_string(*info->request_length) + " expected");
  }
  // ERRATA E-6, the other side: a control character in the data reached
  // the controller (the receiver read the frame to its ETX) and is "invalid
  // ... data" (§1 Message Protocol): NAKed, not "a valid command" (E-10 says
  // what it gets offline). A control character as the command byte is an
  // unknown code, NAKed above with that byte as CC.
  if (reads_other("E-6") && std::any_of(f.data.begin(), f.data.end(), [](std::uint8_t c) { return is_control(c); }))
    return unknown(NakRule::kMalformedData, "a control character in the data (ERRATA E-6)");
  // §3 Online/Offline Reply: a valid command while remote control is
  // disabled; whether one the controller does not implement is "valid" is
  // ERRATA E-97 (the other side NAKs it, offline or not).
  const bool implemented = Handlers::implemented(*this, f.command);
  if (offline && (implemented || !reads_other("E-97"))) return offline_outcome();
  // ERRATA E-16: "not yet implemented" (§3 table '*'); the other side gives
  // such a code no behaviour at all online, a reply included (offline, as
  // E-97's other side reaches here, the NAK).
  if (!implemented && !offline && reads_other("E-16")) return Handlers::unanswered("not implemented: no reply (E-16)");
  if (!implemented) return Handlers::nak(*this, f.command, NakRule::kNotImplemented);

  // §3.18 byte 29, §3.19 bytes 29-39: "Not applicable if feed type is
  // circular"; the other side of ERRATA E-91 does not read them there.
  if (reads_other("E-91") && profile_.pol_type == PolType::kCircular) blank_polarization_fields(command);
  // ERRATA E-45's other side: §3.3's "right justified and left padded with
  // zeroes" read literally, the zeros left of a target's sign ("00-50" is
  // -5.0), respelled sign first for the codec; "-0050" is malformed there.
  // A field that names a stored satellite is form 1 whatever it spells
  // (READING-NOTES 31).
  // Fault target-spellings-both: zeros left of the sign read on the
  // reference side too, and '-' first on the other.
  const bool both_spellings = faults_.has(Fault::kTargetSpellingsBoth);
  if ((reads_other("E-45") || both_spellings) && command.command == AutoMove::kCode && !Handlers::names_stored(*this, command)) {
    if (!both_spellings && auto_move_spells(command.data, TargetSpelling::kSignFirst))
      return Handlers::nak(*this, f.command, NakRule::kMalformedData, "'-' before a padding zero (E-45: zeros go left of the sign)");
    respell_auto_move(command.data, TargetSpelling::kSignFirst);
  }
  // ERRATA E-14's other side: the 'C' that §3.4's NAK and TRACK sentences
  // list beside W, U, D is a direction: azimuth counterclockwise, 'E'.
  if (reads_other("E-14") && (command.command == Jog::kCode || command.command == JogMinimal::kCode) &&
      !command.data.empty() && command.data[0] == 'C')
    command.data[0] = 'E';
  auto request = decode_request(command);
  if (!request) return Handlers::nak(*this, f.command, NakRule::kMalformedData, request.error().message());
  // ERRATA E-41's other side: a longitude, pol offset or 42h H/V position
  // without its decimal digit ("45") is malformed (§3.10, §3.18, §3.19).
  if (reads_other("E-41") && (f.command == WriteSatellite::kCode || f.command == RemoteLocate::kCode ||
                              f.command == RemoteStore::kCode))
    if (const auto spans = decimals_without_point(request.value(), command.data); !spans.empty())
      return Handlers::nak(*this, f.command, NakRule::kMalformedData,
                           "byte " + std::to_string(spans.front().first + kFrameDataStart) +
                               ": a number without its decimal digit (E-41)");
  // ERRATA E-52 other-2: §2's "commands received will force the controller
  // into REMOTE mode": every command but the polls (30h, 31h, 40h) takes a
  // controller in MANUAL_MODE to REMOTE_MODE as it is received, and then
  // acts (a key may take it back); a command it refuses does not.
  const ModeState mode_before = state_.mode;
  const bool forced = reads_other_2("E-52") && !is_poll(f.command) && in_mode("MANUAL_MODE");
  if (forced) Handlers::take_remote_control(*this);
  Outcome o = dispatch(command, request.value());
  if (forced && !(o.reply && !o.reply->empty() && o.reply->front() == ACK)) state_.mode = mode_before;
  if (o.reply && o.note.empty()) o.note = std::string(info->name);
  // ERRATA E-66: 42h 'C' needs the LOCATE "immediately prior"; the commands
  // taken since, reads aside, are counted (the other side wants none).
  if (o.reply && !o.reply->empty() && o.reply->front() == ACK && !keeps_locate_claim(f.command))
    ++state_.commands_since_locate;
  return o;
}

Outcome Controller::dispatch(const Frame& f, const Request& request) {
  using H = Handlers;
  return std::visit(
      [&](const auto& m) -> Outcome {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, DeviceTypeQuery> || std::is_same_v<T, StatusPoll>) {
          // §3 NOTE: unlike the RC2000, these do not force REMOTE mode.
          if (faults_.has(Fault::kStatusForcesRemote)) H::take_remote_control(*this);
          if constexpr (std::is_same_v<T, DeviceTypeQuery>) return H::device_type(*this);
          else return H::status(*this, 0x31);
        } else if constexpr (std::is_same_v<T, AutoMove>) {
          return H::auto_move(*this, f, m);
        } else if constexpr (std::is_same_v<T, Jog> || std::is_same_v<T, JogMinimal>) {
          return H::jog(*this, T::kCode, m);
        } else if constexpr (std::is_same_v<T, PolPreset>) {
          return H::pol_preset(*this, m);
        } else if constexpr (std::is_same_v<T, QueryName>) {
          return H::query_name(*this, m);
        } else if constexpr (std::is_same_v<T, Misc>) {
          return H::misc(*this, m);
        } else if constexpr (std::is_same_v<T, ReflectDisplayQuery>) {
          return H::ack(*this, 0x37, display());
        } else if constexpr (std::is_same_v<T, SignalStrength>) {
          return H::signal_strength(*this, m);
        } else if constexpr (std::is_same_v<T, WriteSatellite>) {
          return H::write_satellite(*this, m);
        } else if constexpr (std::is_same_v<T, ReadSatellite>) {
          return H::read_satellite(*this, m);
        } else if constexpr (std::is_same_v<T, WriteTle>) {
          return H::write_tle(*this, m);
        } else if constexpr (std::is_same_v<T, ReadTle>) {
          return H::read_tle(*this, m);
        } else if constexpr (std::is_same_v<T, WriteIess>) {
          return H::write_iess(*this, m);
        } else if constexpr (std::is_same_v<T, ReadIess>) {
          return H::read_iess(*this, m);
        } else if constexpr (std::is_same_v<T, PulseCountQuery>) {
          return H::ack(*this, 0x3F, PulseCountReply{counts(AxisId::kAz), counts(AxisId::kEl)});
        } else if constexpr (std::is_same_v<T, ExtendedStatusPoll>) {
          return H::extended_status(*this);
        } else if constexpr (std::is_same_v<T, RemoteLocate>) {
          return H::remote_locate(*this, m);
        } else if constexpr (std::is_same_v<T, RemoteStore>) {
          return H::remote_store(*this, m);
        } else if constexpr (std::is_same_v<T, WriteSignpost>) {
          return H::write_signpost(*this, m);
        } else if constexpr (std::is_same_v<T, ReadSignpost>) {
          return H::read_signpost(*this, m);
        } else if constexpr (std::is_same_v<T, NavigationQuery>) {
          return H::read_navigation(*this);
        } else if constexpr (std::is_same_v<T, WriteNavigation>) {
          return H::write_navigation(*this, m);
        } else {
          static_assert(std::is_same_v<T, RemoteKeypress>);
          return H::keypress(*this, m.key, 0x48);
        }
      },
      request);
}

}  // namespace sabus::harness
