// Dictionary entries of the fuzz targets (fuzz_support.hpp dictionary_tokens),
// derived from the catalog and the codecs: never a second list of codes.
#include <cstdio>
#include <string>

#include "fuzz_support.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::fuzz {

std::vector<Token> dictionary_tokens() {
  std::vector<Token> t;
  auto hex = [](std::uint8_t b) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%02Xh", b);
    return std::string(buf);
  };
  t.push_back({"STX", {STX}});
  t.push_back({"ETX", {ETX}});
  t.push_back({"ACK", {ACK}});
  t.push_back({"NAK", {NAK}});
  t.push_back({"STX with parity bit", {with_even_parity(STX)}});
  t.push_back({"ETX with parity bit", {with_even_parity(ETX)}});
  // §2 / READING-NOTES 4: addresses 31h-6Fh (49-111), and one past each end.
  for (std::uint8_t a : {0x30, 0x31, 0x32, 0x6F, 0x70}) t.push_back({"address " + hex(a), {a}});
  for (const auto& info : catalog()) {
    t.push_back({"command " + hex(info.code) + " " + std::string(info.key), {info.code}});
    for (const auto& form : info.forms) {
      for (char c : form.selectors)
        t.push_back({std::string(info.key) + " form " + std::string(form.id) + " selector",
                     {static_cast<std::uint8_t>(c)}});
      // Header of a request of this form: STX '2' code and the selector.
      if (!form.selectors.empty() && info.form_selector_offset == 3)
        t.push_back({std::string(info.key) + " form " + std::string(form.id) + " header",
                     {STX, '2', info.code, static_cast<std::uint8_t>(form.selectors[0])}});
    }
    t.push_back({std::string(info.key) + " header", {STX, '2', info.code}});
  }
  // §3.7 'K' / §3.25 key codes: every character the key table names.
  for (int c = 0x20; c < 0x7F; ++c) {
    const std::string meaning = meanings::key_code(static_cast<char>(c));
    if (meaning.find("not a key code") == std::string::npos)
      t.push_back({"key code " + meaning, {static_cast<std::uint8_t>(c)}});
  }
  return t;
}

}  // namespace sabus::fuzz
