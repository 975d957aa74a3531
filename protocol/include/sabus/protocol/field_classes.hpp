// What the value of each field of each reply rests on (§3.1-§3.25): the
// one table of it. The conformance suite's coverage gate requires a vector
// that checks the value (not only the syntax) of every field whose class
// ties it to the device (value_required); a lockstep oracle compares such a
// field with a model's exactly, or within a window while an axis moves, and
// never a field the spec leaves to the device.
//
// Fields are named as the reply layouts name them (describe_frame); the
// framing fields every frame has (start, address, command, ETX, check byte)
// are the runner's and are not listed.
#pragma once

#include <span>
#include <string_view>

#include "sabus/protocol/catalog.hpp"

namespace sabus {

enum class FieldClass : std::uint8_t {
  kFixed,    // the spec fixes the value: the same on every controller ("3K", reserved 40h)
  kEcho,     // repeats what the request asked for (a slot index, an axis)
  kProfile,  // the controller's configuration: what its profile says (firmware, feed, AGC channel)
  kStored,   // stored data (STORE list, presets, TLEs, signposts, navigation): the profile's record or the last write
  kState,    // the controller's state: names, counts, modes, states, exit statuses, alarm and track codes
  kMotion,   // positions, limits, motion bits: exact at rest, a window from the motion model while an axis moves
  kDevice,   // the spec leaves the value to the device (display text, a measured signal level, reserved bytes
             // with no content given): never compared
};
std::string_view to_string(FieldClass c);  // "fixed", "echo", "profile", "stored", "state", "motion", "device"

// Whether a conformance suite must check the value of a field of this class:
// every class but kDevice.
constexpr bool value_required(FieldClass c) { return c != FieldClass::kDevice; }

struct ReplyFieldClass {
  ReplyKind reply;
  std::string_view field;      // as describe_frame names it ("azimuth", "exit status")
  FieldClass cls;
  std::string_view paragraph;  // "3.2"
  std::string_view rests_on;   // what the value is, in a few words
};

// Every non-framing field of every reply layout, in reply and byte order
// (tests/protocol/field_classes_test.cpp holds it to the layouts).
std::span<const ReplyFieldClass> reply_field_classes();
// The class of a reply's field, or nullptr for a framing field or a name the
// reply does not have.
const ReplyFieldClass* field_class(ReplyKind reply, std::string_view field);

}  // namespace sabus
