// Encoding, decoding and describing typed requests and replies, driven by
// the message layouts (messages.hpp) and the command catalog (catalog.hpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sabus/protocol/fields.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/messages.hpp"

namespace sabus {

// The data bytes (3 .. ETX-1) of a request, and the whole command frame.
Bytes encode_request_data(const Request& request);
Bytes encode_request(const Request& request, std::uint8_t address);
Frame request_frame(const Request& request, std::uint8_t address);

// A command frame's typed request. Errors: unknown code, a length that
// contradicts the catalog, or the first field that does not decode.
Expected<Request> decode_request(const Frame& frame);

// The signed targets of a 32h request (§3.3: forms 2A, 2C and 3, in the form
// its byte 3 selects, whether or not the data decodes): each one's first data
// byte (0 = byte 3) and width. Their spelling is ERRATA E-45's reading.
struct DataSpan {
  std::size_t first = 0;
  std::size_t width = 0;
};
std::vector<DataSpan> auto_move_signed_targets(std::uint8_t form_byte);

// ERRATA E-41: the fields of a decoded request that carry a decimal digit
// (longitude, pol offset, the 42h H/V positions: LeftDecimal with decimals)
// whose text in `data` has none ("45", read as "45.0"), by their place in
// the data. Whether such a field is malformed is the reading.
std::vector<DataSpan> decimals_without_point(const Request& request, ByteView data);

// ERRATA E-45's two spellings of a negative target: '-' first, then
// zero-padded digits ("-0050" is -5.0; the codec's), or the value
// right-justified with the zeros left of its sign ("00-50"). A target whose
// digits fill the field ("-1525"), or has no '-', reads alike in both and
// has no spelling of its own.
enum class TargetSpelling : std::uint8_t { kSignFirst, kZerosFirst };
std::optional<TargetSpelling> spelling_of(ByteView target);
// One target respelled `to` when it is spelled the other way; whether it was.
bool respell_target(std::span<std::uint8_t> target, TargetSpelling to);
// Whether a target of 32h `data` (from byte 3) is spelled so.
bool auto_move_spells(ByteView data, TargetSpelling spelling);
// Rewrites each target of 32h `data` spelled the other way into `to`;
// returns whether one changed.
bool respell_auto_move(Bytes& data, TargetSpelling to);

// The reply frame for `command` (ACK with data, NAK, or the offline reply).
// The reply type must be the catalog's reply kind for `command`.
Expected<Frame> reply_frame(const Reply& reply, std::uint8_t address, std::uint8_t command);
Expected<Bytes> encode_reply(const Reply& reply, std::uint8_t address, std::uint8_t command);
Expected<Reply> decode_reply(const Frame& frame);

// One field of a frame as a person reads it:
//   byte 36  az status  0x45  ccw automatic movement in progress
struct FieldDescription {
  std::size_t first = 0;  // byte offsets in the frame, inclusive
  std::size_t last = 0;
  std::string name;
  std::string raw;        // "0x45" for one byte, "\"-152.5\"" for text
  std::string meaning;
  bool ok = true;
  fields::Kind kind = fields::Kind::kHeader;  // the codec that read it
  std::string line() const;
};

struct FrameDescription {
  std::string summary;                  // "ACK 31h Device Status Poll (§3.2) reply from 0x32 (50)"
  std::vector<FieldDescription> fields; // every byte of the frame, in order
  std::optional<DecodeError> error;     // the first problem found, if any
};

// Describes one complete frame of 7-bit characters: header, every data field
// of the request or reply layout, ETX and the check byte.
FrameDescription describe_frame(ByteView frame_bytes);

// The catalog form of a request ("2A", "E", "R", "preset"; "" if none).
std::string_view form_of(const Request& request);

// The command and form of the command frame that ends a byte sequence (the
// frame a slave's receiver last began: from the last STX, READING-NOTES 7),
// however damaged: the request's form when it decodes, else the form the
// selector byte picks, else none. For coverage matrices and reports; `info`
// is null for an unknown code.
struct CommandForm {
  const CommandInfo* info = nullptr;
  const FormInfo* form = nullptr;
};
CommandForm classify_command(ByteView bytes);

}  // namespace sabus
