// The open points of the spec that a legal controller may read either way:
// the protocol/ERRATA.md entries of class *reading* whose switch is the
// profile's `readings:` map. This table is the only place their ids live.
//
// Who reads which side:
//  - the reference controller takes the `reference` side of each point
//    unless its profile pins `other` (`readings: {E-90: other}`);
//    `sabus sim --reading other` pins every point to `other` at once;
//  - the vectors accept what every side allows unless the device's profile
//    pins one (Wycheproof's "acceptable"): a pinned side is checked strictly.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sabus::harness {

// A point has the reference side and the other; a few have a third
// (ERRATA's `other-2`, the entry's third alternative).
enum class ReadingSide : std::uint8_t { kReference, kOther, kOther2 };
// "reference", "other", "other-2" (the profile's and the CLI's spelling).
std::string_view to_string(ReadingSide side);
std::optional<ReadingSide> reading_side_named(std::string_view name);

struct ReadingPoint {
  std::string_view id;         // the ERRATA entry, "E-90"
  std::string_view paragraph;  // the spec paragraph it reads, "§3.7 'A'"
  std::string_view reference;  // what a controller of the reference side does
  std::string_view other;      // what a controller of the other side does
  std::string_view other_2{};  // what one of the third side does; empty: no third side
};

// The sides a controller may take on `point`: reference, other, and other-2
// where the point has one.
std::vector<ReadingSide> sides_of(const ReadingPoint& point);
// What a controller of `side` does on `point` ("" for a side it lacks).
std::string_view side_text(const ReadingPoint& point, ReadingSide side);
// "reference or other" / "reference, other or other-2".
std::string sides_named(const ReadingPoint& point);
// Whether `side` is one of the point's sides.
bool has_side(const ReadingPoint& point, ReadingSide side);
// The sides of point `id` besides `taken` (one, or two where it has a third).
std::vector<ReadingSide> sides_besides(std::string_view id, ReadingSide taken);
// The key of a vector's `readings:` alternative for `side` of point `id`:
// the id itself for its other side, "E-23/other-2" for a third.
std::string reading_key(std::string_view id, ReadingSide side);

// Every switchable reading, in ERRATA order.
std::span<const ReadingPoint> reading_points();
const ReadingPoint* find_reading_point(std::string_view id);

// A profile's pins: an id of reading_points() to the side the device takes.
// A point that is not in the map is open: either side is legal.
using ReadingPins = std::map<std::string, ReadingSide, std::less<>>;

// The side a controller with these pins takes: the pinned one, else the reference.
ReadingSide side_taken(const ReadingPins& pins, std::string_view id);
// The side a verdict holds a device to: the pinned one, or nullopt (either).
std::optional<ReadingSide> side_pinned(const ReadingPins& pins, std::string_view id);

// `--reading` of sabus sim / run --sim / fuzz --sim: "other" or "reference"
// (every point), "other-2" (every point with a third side to it, the rest to
// other), or a comma-separated list of ID=SIDE ("E-90=other,E-52=other-2")
// to flip one at a time. Adds to `pins`; on a bad spec returns why and leaves
// `pins` as it was.
std::optional<std::string> apply_reading_spec(std::string_view spec, ReadingPins& pins);

}  // namespace sabus::harness
