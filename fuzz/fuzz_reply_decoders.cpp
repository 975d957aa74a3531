// Fuzz target: the reply decoders of every command (§3.1-§3.25).
// Input: byte 0 picks the command (and NAK with bit 7), byte 1 whether the
// data is cut or padded to the catalog's reply length; the rest is the data.
// A header byte the input lacks is 0 (and the data empty), so every input,
// the empty one too, reaches the decoders: returning first left libFuzzer
// with no coverage on its first input when started without a corpus
// ("no interesting inputs were found"). The frame gets a correct LRC so the
// input reaches the field decoders.
// Oracles: decode -> encode -> decode is stable; describe_frame covers every
// byte and agrees with decode_reply on whether the frame is valid.
#include <cstdlib>

#include "sabus/protocol/codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::uint8_t command = size > 0 ? data[0] : 0, pad = size > 1 ? data[1] : 0;
  const auto& info = sabus::catalog()[(command & 0x7F) % sabus::catalog().size()];
  sabus::Frame f{(command & 0x80) ? sabus::FrameKind::kNak : sabus::FrameKind::kAck, '2', info.code, {}};
  for (std::size_t i = 2; i < size; ++i) {
    const std::uint8_t c = data[i] & 0x7F;
    f.data.push_back(c == sabus::ETX ? ' ' : c);  // ETX ends a frame: the receiver never passes one inside
  }
  if ((pad & 1) && info.reply_data_length()) f.data.resize(*info.reply_data_length(), ' ');

  const sabus::Bytes bytes = sabus::encode_frame(f);
  const auto decoded = sabus::decode_reply(f);
  const auto described = sabus::describe_frame(bytes);

  std::size_t next = 0;
  for (const auto& field : described.fields) {
    if (field.first != next || field.last < field.first) std::abort();
    next = field.last + 1;
  }
  if (next != bytes.size()) std::abort();
  if (decoded.ok() && described.error) std::abort();  // the two disagree on validity

  if (!decoded.ok()) return 0;
  const auto again = sabus::encode_reply(decoded.value(), f.address, f.command);
  if (!again.ok()) std::abort();
  const auto frame2 = sabus::decode_frame(again.value());
  if (!frame2.ok()) std::abort();
  const auto decoded2 = sabus::decode_reply(frame2.value());
  if (!decoded2.ok() || !(decoded2.value() == decoded.value())) std::abort();
  const auto again2 = sabus::encode_reply(decoded2.value(), f.address, f.command);
  if (again2.value() != again.value()) std::abort();  // encoding is canonical after one pass
  return 0;
}
