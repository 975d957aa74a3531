// Generates the seed corpora of the fuzz targets from the codecs and the
// manual's examples, so seeds follow the layouts instead of being copied by
// hand: `fuzz_seed_generator OUTDIR` writes OUTDIR/<target>/<name>.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "sabus/protocol/codec.hpp"

namespace fs = std::filesystem;
using sabus::Bytes;

namespace {

void write(const fs::path& dir, const std::string& name, const Bytes& bytes) {
  fs::create_directories(dir);
  std::ofstream out(dir / name, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// One of each reply type, as the codecs encode them.
template <std::size_t... I>
void reply_seeds(const fs::path& dir, std::index_sequence<I...>) {
  auto one = [&]<class T>(std::type_identity<T>) {
    if constexpr (requires { T::kKind; }) {
      for (const auto& info : sabus::catalog()) {
        if (info.reply != T::kKind) continue;
        const auto frame = sabus::reply_frame(sabus::Reply{T{}}, '2', info.code);
        const std::uint8_t selector = static_cast<std::uint8_t>(info.code - sabus::kFirstCommand);
        Bytes seed = {selector, 0};
        seed.insert(seed.end(), frame.value().data.begin(), frame.value().data.end());
        char name[32];
        std::snprintf(name, sizeof name, "reply-%02x", info.code);
        write(dir, name, seed);
      }
    }
  };
  (one(std::type_identity<std::variant_alternative_t<I, sabus::Reply>>{}), ...);
}

// One of each request, for the receiver (as 7-bit characters and on the wire).
template <std::size_t... I>
void request_seeds(const fs::path& dir, std::index_sequence<I...>) {
  auto one = [&]<class T>(std::type_identity<T>) {
    const Bytes frame = sabus::encode_request(sabus::Request{T{}}, '2');
    char name[32];
    std::snprintf(name, sizeof name, "request-%02x", T::kCode);
    write(dir, std::string(name) + "-chars", cat({{0x06, 0x00}, frame}));
    write(dir, std::string(name) + "-wire", cat({{0x07, 0x03}, sabus::add_even_parity(frame)}));
  };
  (one(std::type_identity<std::variant_alternative_t<I, sabus::Request>>{}), ...);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seed_generator OUTDIR\n");
    return 2;
  }
  const fs::path out = argv[1];
  reply_seeds(out / "fuzz_reply_decoders", std::make_index_sequence<std::variant_size_v<sabus::Reply>>{});
  request_seeds(out / "fuzz_receiver", std::make_index_sequence<std::variant_size_v<sabus::Request>>{});
  // Framing cases for the receiver: bad LRC, STX STX, a check byte of 02h.
  const Bytes poll = sabus::encode_request(sabus::StatusPoll{}, '2');
  Bytes bad = poll;
  bad.back() ^= 1;
  write(out / "fuzz_receiver", "framing-bad-lrc", cat({{0x06, 0x00}, bad, poll}));
  write(out / "fuzz_receiver", "framing-stx-stx", cat({{0x06, 0x00}, {sabus::STX}, poll}));
  write(out / "fuzz_receiver", "framing-noise", cat({{0x06, 0x02}, {0x41, 0x42, 0x03, 0x7f}, poll}));
  std::printf("seed corpora written to %s\n", out.c_str());
  return 0;
}
