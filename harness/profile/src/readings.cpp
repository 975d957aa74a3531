// The switchable readings of protocol/ERRATA.md (readings.hpp).
#include "sabus/harness/readings.hpp"

#include <algorithm>
#include <array>

#include "sabus/harness/yaml_reader.hpp"  // quoted_clip

namespace sabus::harness {
namespace {

// One row per ERRATA entry of class *reading* with a `readings:` switch; the
// entry says more, and names the vectors that accept both sides.
constexpr std::array kPoints{
    ReadingPoint{"E-6", "§1 Data Format; §1 Message Protocol",
                 "a control character between the address and ETX is a protocol error: the frame is ignored",
                 "the frame is read to its ETX and NAKed as invalid command or data"},
    ReadingPoint{"E-8", "§1 Message Protocol",
                 "a frame longer than the longest command (145 bytes) is an overrun: ignored",
                 "overrun is the UART's: a long frame with a good check byte is NAKed for its length (§3)"},
    ReadingPoint{"E-14", "§3.4; §3.24", "'C' is a typo for 'E': no direction, NAKed as an invalid one",
                 "'C' is a direction, azimuth counterclockwise (as 'E'): the NAK and TRACK sentences list it"},
    ReadingPoint{"E-16", "§3 Command Set; §3.9; §3.14; §3.15", "38h, 3Dh and 3Eh where not implemented are NAKed",
                 "38h, 3Dh and 3Eh where not implemented are not answered online (offline, E-97 decides)"},
    ReadingPoint{"E-18", "§3.11; §3.13; §3.15; §3.21", "an empty slot's reply is blank after its 7Fh 7Fh index",
                 "an empty slot's reply holds zeros after its 7Fh 7Fh index"},
    ReadingPoint{"E-20", "§3.8 bytes 164-165", "the cursor column counts from 0 (0-39)",
                 "the cursor column counts from 1 (1-40), as the row does"},
    ReadingPoint{"E-23", "§3.20; §3.21", "without the DVB receiver option 43h and 44h are NAKed; 43h takes priority 0-9",
                 "without the DVB receiver option 43h and 44h are not answered",
                 "43h NAKs priority 0 (\"1 - 9\" as 44h reads it); without the option, NAKed"},
    ReadingPoint{"E-29", "§3.18, §3.19 byte 3 B",
                 "byte 3 is 40h | A<<4 | tens, tens 0-2: preset index 20 can be sent",
                 "B is one bit: a tens digit of 2 is malformed and NAKed (41h and 42h)"},
    ReadingPoint{"E-30", "§3.17 bytes 49-50", "without 0.01 deg feedback the hundredths digits are '0'",
                 "without 0.01 deg feedback the hundredths bytes are blank"},
    ReadingPoint{"E-31", "§3.3 forms 1, 2A", "a field that names a stored satellite is form 1, even when it parses as a 2A pair",
                 "a field that parses as a valid 2A pair is form 2A, whatever is stored"},
    ReadingPoint{"E-32", "§3.20 byte 21; §3.21 byte 21", "FEC codes 4 and 8 name no code: 43h NAKs them",
                 "4 and 8 lie in the range \"1 - 9\": 43h stores them and 44h reads them back"},
    ReadingPoint{"E-33", "§3.2 bytes 14-31; §3.16; §3.22 bytes 30-34; §3.24 bytes 4-9",
                 "positions are right-justified and blank-padded; pulse counts and the 45h heading are zero-padded",
                 "positions are left-justified; pulse counts and the 45h heading are padded with blanks"},
    ReadingPoint{"E-34", "§3.17 track_states", "the printed order: JOG_POL_CCW 45h, AUTO_POL_MOVE, IDLE, JOG_POL_CW 48h",
                 "the order of manual_states: JOG_POL_CW 45h, JOG_POL_CCW, AUTO_POL_MOVE, IDLE 48h"},
    ReadingPoint{"E-40", "§3.22 bytes 36-41", "the magnetic variation is right-justified, blank-padded",
                 "the magnetic variation is left-justified"},
    ReadingPoint{"E-41", "§3.10; §3.18; §3.19", "a longitude or pol offset without its decimal digit (\"45\") is 45.0",
                 "a longitude, pol offset or 42h H/V position without its decimal digit is malformed: NAKed"},
    ReadingPoint{"E-42", "§3.2 bytes 14-19; §3.24 bytes 4-9", "an A/D error shows six '*' in the 6-byte field",
                 "the azimuth's A/D error shows the five '*' the text prints, after a blank"},
    ReadingPoint{"E-43", "§3.7 'K'; §3.25", "an unused key code (3Ah-3Fh, 40h) is NAKed",
                 "an unused key code (3Ah-3Fh, 40h) is ACKed and does nothing"},
    ReadingPoint{"E-46", "§3.24", "47h 'X' replies 'A' and the azimuth position",
                 "47h 'X' replies the axis last jogged and its position (the azimuth before any jog)"},
    ReadingPoint{"E-45", "§3.3 forms 2A, 2C, 3",
                 "a negative target is '-' first, then zero-padded digits (\"-0050\" is -5.0)",
                 "a negative target is right-justified with the zeros left of its sign (\"00-50\"); \"-0050\" is malformed"},
    ReadingPoint{"E-50", "§3.3 forms 2B, 2C",
                 "form 2B without count sensors and form 2C without 0.01 deg feedback are NAKed",
                 "they are ACKed and executed as well as the mount can: counts by the profile's scale, 2C to the tenth"},
    ReadingPoint{"E-51", "§3.10", "39h with an ephemeris code for an index above 10 is NAKed",
                 "39h with an ephemeris code for an index above 10 is stored and ACKed"},
    ReadingPoint{"E-52", "§3 RC3000 Online/Offline Reply (NOTE); §3.4",
                 "32h, the jogs (33h, 47h) and 34h enter REMOTE_MODE; 41h, 42h and 36h S/D/A their own modes",
                 "only 32h enters REMOTE_MODE: a jog or 34h acts from the mode the controller is in",
                 "every command but the polls (30h, 31h, 40h) takes the controller from MANUAL_MODE to REMOTE_MODE"},
    ReadingPoint{"E-53", "§3.2 bytes 36-38", "a remote jog reports movement in progress (0100/0101)",
                 "a remote jog reports jog movement pending (0010/0011) while its time runs"},
    ReadingPoint{"E-54", "§3.3", "an auto-move target outside the axis's limits is NAKed",
                 "an auto-move target outside the axis's limits is ACKed and the axis driven to the limit"},
    ReadingPoint{"E-56", "§3.7 'K'; §3.25; §2 JOG", "a jog key moves its axis for the remote jog hold time, 0.5 s",
                 "a jog key moves its axis for the hold time the device is configured with (here 40 x 1/40 s)"},
    ReadingPoint{"E-57", "§3.5", "34h with no auto move since power-on takes the first STORE entry",
                 "34h with no auto move since power-on is NAKed: there is no last target"},
    ReadingPoint{"E-58", "§3.19 byte 29", "42h 'H'/'V' put the other position 90 deg away, folded into -90.0..90.0; 'C' H from the pol offset",
                 "42h 'H'/'V' put V = H + 90 deg, H = V - 90 deg, unfolded",
                 "42h 'C' takes H from the polarization skew at the site, V 90 deg away"},
    ReadingPoint{"E-61", "§3.4 bytes 5-8", "a jog duration is rounded up to the 50 ms timer",
                 "a jog duration is rounded to the nearest 50 ms: under 25 ms it does not move"},
    ReadingPoint{"E-60", "§3.23 NOTE", "valid navigation data takes latitude 90 deg 00 and longitude 180 deg 00 either way",
                 "the poles and -180 deg 00 are NAKed: the antimeridian is +180 deg 00 only"},
    ReadingPoint{"E-63", "§3.5", "on a dual-port feed 'H' and 'V' move to the satellite's horizontal position",
                 "on a dual-port feed 'H' and 'V' move to the satellite's vertical position"},
    ReadingPoint{"E-64", "§3.5", "34h with no satellite in memory is NAKed at once, even while TRACK peaks",
                 "while TRACK peaks or searches 34h is deferred and ACKed; the check waits until it runs"},
    ReadingPoint{"E-65", "§3.19; §3.6", "with 50 satellites stored, 42h with a new name is NAKed",
                 "with 50 satellites stored, 42h with a new name is ACKed and its STORE ends STORE_LIST_FULL, storing nothing"},
    ReadingPoint{"E-66", "§3.19 byte 29 'C'",
                 "a LOCATE keeps its claim for 42h 'C' until an automatic function (STOW, DEPLOY, a search) starts",
                 "42h 'C' needs the LOCATE as the last command before it, status reads aside"},
    ReadingPoint{"E-67", "§1 Message Protocol", "no inter-character timeout: a frame whose bytes pause is answered",
                 "an inter-character timeout of 20 ms: a frame whose bytes pause longer is dropped"},
    ReadingPoint{"E-68", "§3.18 bytes 5-14; §3.19 bytes 5-14",
                 "a lower-case name in 41h/42h is accepted and shown and stored in capitals",
                 "a lower-case name in 41h/42h (data form) is NAKed as an error in the supplied data"},
    ReadingPoint{"E-74", "§3.2 bytes 3-12; §3.6", "a name is shown left-justified in bytes 3-12",
                 "a name is shown after a blank (a USER entry with a blank entered before it)"},
    ReadingPoint{"E-76", "§3.2 bytes 14-31; §3.17 bytes 49-50", "a position is rounded to its display unit",
                 "its digits beyond the unit are dropped toward zero",
                 "its digits beyond the unit are dropped toward minus infinity"},
    ReadingPoint{"E-82", "§3.17 locate_exit_conditions; §3.4 'X'",
                 "'X' exits a LOCATE with the STOP_KEY entry of its movement; one left before moving takes LOCATE_FIRST_ELEV_MOVEMENT's",
                 "'X' exits a LOCATE with the MODE_CHANGED entry of its movement; one left before moving takes LOCATE_AZIM_MOVEMENT's"},
    ReadingPoint{"E-83", "§3.19 byte 29 'C'; §3.17 locate_states",
                 "a LOCATE that ended in a range error was not performed: a following 42h 'C' is NAKed",
                 "a LOCATE that ended in a range error counts as performed: 42h 'C' is ACKed with its satellite's values"},
    ReadingPoint{"E-87", "§3.17 bytes 49-50", "the hundredths digit extends the magnitude (-123.4 and '5' is -123.45)",
                 "the digit is added to tenths rounded down (-123.5 and '5' is -123.45)"},
    ReadingPoint{"E-88", "§3.7 'K'; §3.25; §3.17 bytes 45-46",
                 "the Stop key stops a remote auto move and REMOTE_MODE keeps control (WAITING_FOR_USER_INPUT)",
                 "the Stop key leaves REMOTE: MANUAL_MODE / MANUAL_IDLE"},
    ReadingPoint{"E-89", "§3.7 'S', 'D'; §3.17 stow_exit_conditions, deploy_exit_conditions; §3.4 'X'",
                 "'X' exits a STOW or DEPLOY with MOVE_STOPPED; a STOW moves its axes together",
                 "'X' exits a STOW or DEPLOY with MODE_CHANGED; a STOW moves the azimuth, then the polarization, then the elevation"},
    ReadingPoint{"E-90", "§3.7 'A'", "a search gives up after 20 s with no peak found",
                 "a search gives up within a second"},
    ReadingPoint{"E-91", "§3.18 byte 29; §3.19 bytes 29-39",
                 "an invalid polarization field is NAKed on a circular feed too",
                 "the polarization fields are not applicable on a circular feed and are not read"},
    ReadingPoint{"E-92", "§3.18 bytes 5-14", "41h with a blank satellite name is NAKed",
                 "41h with a blank satellite name is ACKed"},
    ReadingPoint{"E-93", "§3.17 locate_exit_conditions", "a LOCATE that completes returns to MANUAL_MODE",
                 "a LOCATE that completes returns to REMOTE_MODE"},
    ReadingPoint{"E-94", "§3.17 locate_states", "a LOCATE moves azimuth and elevation together",
                 "a LOCATE moves in the order of locate_states: elevation, polarization, azimuth, elevation"},
    ReadingPoint{"E-95", "§3.2 byte 35 Y", "Y is 1 whenever polarization moves are allowed",
                 "Y is 0 outside TRACK, where it carries no meaning"},
    ReadingPoint{"E-96", "§3.2 byte 35 ZZZ", "the code shown is the one asked for, in capitals",
                 "the code is shown in lower case while the feed is still moving to it"},
    ReadingPoint{"E-97", "§3 Online/Offline Reply; §3.14", "an unimplemented command while offline gets the offline reply",
                 "an unimplemented command is NAKed, offline or not"},
    ReadingPoint{"E-98", "§3.2 bytes 36-38 S", "S during an auto move is the speed of the move (fast)",
                 "S is the speed the axis is configured for, whatever moves it"},
    ReadingPoint{"E-99", "§3.7 'S'; §3.2 bytes 32-34; §3.17 stow_exit_conditions",
                 "a STOW drives every axis with a stow limit to it and exits with STOW_FINISHED_NORMALLY",
                 "a STOW leaves the elevation a degree short of its stow position and exits with STOW_FINISHED_WITH_ELEV_NOT_AT_STOW"},
    ReadingPoint{"E-100", "§3.2 bytes 35-40; §3.17 track_states",
                 "TRACK keeps its power-on submode and holds the antenna still",
                 "TRACK's peaking or search moves the azimuth and elevation about where it began; a search goes on to peaking"},
    ReadingPoint{"E-101", "§3.2 byte 39; §3.7 'R'", "a drive reset of the axis whose code shows sets byte 39 to 0",
                 "after that reset byte 39 shows the code of an alarm still active"},
};

}  // namespace

std::string_view to_string(ReadingSide side) {
  switch (side) {
    case ReadingSide::kReference: return "reference";
    case ReadingSide::kOther: return "other";
    case ReadingSide::kOther2: return "other-2";
  }
  return "?";
}

std::optional<ReadingSide> reading_side_named(std::string_view name) {
  for (ReadingSide side : {ReadingSide::kReference, ReadingSide::kOther, ReadingSide::kOther2})
    if (name == to_string(side)) return side;
  return std::nullopt;
}

std::vector<ReadingSide> sides_of(const ReadingPoint& point) {
  if (point.other_2.empty()) return {ReadingSide::kReference, ReadingSide::kOther};
  return {ReadingSide::kReference, ReadingSide::kOther, ReadingSide::kOther2};
}

std::string_view side_text(const ReadingPoint& point, ReadingSide side) {
  switch (side) {
    case ReadingSide::kReference: return point.reference;
    case ReadingSide::kOther: return point.other;
    case ReadingSide::kOther2: return point.other_2;
  }
  return {};
}

std::span<const ReadingPoint> reading_points() { return kPoints; }

std::string sides_named(const ReadingPoint& point) {
  std::string out;
  const auto sides = sides_of(point);
  for (std::size_t k = 0; k < sides.size(); ++k) {
    out += k == 0 ? "" : k + 1 == sides.size() ? " or " : ", ";
    out += to_string(sides[k]);
  }
  return out;
}

bool has_side(const ReadingPoint& point, ReadingSide side) {
  const auto sides = sides_of(point);
  return std::find(sides.begin(), sides.end(), side) != sides.end();
}

std::vector<ReadingSide> sides_besides(std::string_view id, ReadingSide taken) {
  std::vector<ReadingSide> sides = sides_of(*find_reading_point(id));
  std::erase(sides, taken);
  return sides;
}

std::string reading_key(std::string_view id, ReadingSide side) {
  std::string key(id);
  if (side != ReadingSide::kOther) {
    key += '/';
    key += to_string(side);
  }
  return key;
}

const ReadingPoint* find_reading_point(std::string_view id) {
  auto it = std::find_if(kPoints.begin(), kPoints.end(), [&](const ReadingPoint& p) { return p.id == id; });
  return it == kPoints.end() ? nullptr : &*it;
}

ReadingSide side_taken(const ReadingPins& pins, std::string_view id) {
  return side_pinned(pins, id).value_or(ReadingSide::kReference);
}

std::optional<ReadingSide> side_pinned(const ReadingPins& pins, std::string_view id) {
  auto it = pins.find(id);
  return it == pins.end() ? std::nullopt : std::optional<ReadingSide>(it->second);
}

std::optional<std::string> apply_reading_spec(std::string_view spec, ReadingPins& pins) {
  if (auto every = reading_side_named(spec)) {
    for (const ReadingPoint& p : kPoints)
      pins[std::string(p.id)] = *every == ReadingSide::kOther2 && p.other_2.empty() ? ReadingSide::kOther : *every;
    return std::nullopt;
  }
  ReadingPins added;
  for (bool more = !spec.empty(); more;) {
    const std::size_t comma = spec.find(',');
    const std::string_view item = spec.substr(0, comma);
    more = comma != std::string_view::npos;  // "E-90=other," leaves an empty item: an error
    spec = more ? spec.substr(comma + 1) : std::string_view{};
    const std::size_t eq = item.find('=');
    const std::string_view id = item.substr(0, eq);
    if (eq == std::string_view::npos)
      return yaml_reader::quoted_clip(item) + ": expected other, reference, other-2 or a list of E-NN=SIDE";
    const ReadingPoint* point = find_reading_point(id);
    if (!point) {
      std::string known;
      for (const ReadingPoint& p : kPoints) known += (known.empty() ? "" : ", ") + std::string(p.id);
      return yaml_reader::quoted_clip(id) + " is not a switchable reading (ERRATA entries: " + known + ")";
    }
    const auto side = reading_side_named(item.substr(eq + 1));
    if (!side || !has_side(*point, *side))
      return yaml_reader::quoted_clip(item.substr(eq + 1)) + ": a side of " + std::string(id) + " is " + sides_named(*point);
    added[std::string(id)] = *side;
  }
  if (added.empty()) return std::string("an empty --reading: expected other, reference, other-2 or E-NN=SIDE");
  for (auto& [id, side] : added) pins[id] = side;
  return std::nullopt;
}

}  // namespace sabus::harness
