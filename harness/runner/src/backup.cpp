// Bench safety for destructive vectors: the controller's stored data read
// back through the protocol before the first of them, and written back after
// the last; what the protocol cannot restore is said, not hidden.
#include "backup.hpp"

#include <algorithm>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "sabus/harness/files.hpp"
#include "sabus/protocol/fields.hpp"

namespace sabus::harness::detail {
namespace {

std::string fmt_slot(std::uint8_t read_code, std::uint8_t index) {
  const char* what = read_code == 0x3A ? "preset satellite" : read_code == 0x3C ? "TLE" : "signpost";
  return std::string(what) + " " + std::to_string(index);
}

// A slot read's data, or nullopt for an empty slot (7Fh 7Fh, E-18) or no reply.
std::optional<Bytes> slot_data(Session& s, const Request& request) {
  auto data = s.ask(request);
  if (!data || data->size() < 2 || (*data)[0] == fields::kEmptySlot) return std::nullopt;
  return data;
}

// The STORE list's names, read with 35h from index 1 until the NAK (§3.6).
std::vector<std::string> read_store_names(Session& s) {
  std::vector<std::string> names;
  for (std::uint32_t i = 1; i <= 50; ++i) {
    auto d = s.ask(QueryName{{i}});
    if (!d) break;
    if (auto r = decode_reply(Frame{FrameKind::kAck, s.profile.address, 0x35, *d});
        r && std::holds_alternative<QueryNameReply>(r.value()))
      names.push_back(std::get<QueryNameReply>(r.value()).name);
  }
  return names;
}

// Writes back every slot of one list that differs from the backup.
template <class Read, class Reply, class Write>
void restore_slots(Session& s, std::uint8_t code, std::uint8_t max, const std::map<std::uint8_t, Bytes>& saved,
                   Write write, std::vector<std::string>& notes) {
  for (std::uint8_t i = 1; i <= max; ++i) {
    const auto now = slot_data(s, Read{{i}});
    const auto it = saved.find(i);
    if (it == saved.end()) {
      if (now) notes.push_back(fmt_slot(code, i) + " was empty and now holds data; the protocol cannot clear a slot");
      continue;
    }
    if (now && *now == it->second) continue;
    const auto decoded = decode_reply(Frame{FrameKind::kAck, s.profile.address, code, it->second});
    if (!decoded || !std::holds_alternative<Reply>(decoded.value())) continue;
    const bool ok = s.ask(write(i, std::get<Reply>(decoded.value()))).has_value();
    notes.push_back(fmt_slot(code, i) + (ok ? " restored" : " could not be restored (NAK or no reply)"));
  }
}

// §3.23 takes sddmm / sdddmm; writing it deletes the STORE list.
void restore_navigation(Session& s, const StoredDataBackup& b, std::vector<std::string>& notes) {
  const auto nav = s.ask(NavigationQuery{});
  if (!b.navigation || !nav || *nav == *b.navigation) return;
  const auto d = decode_reply(Frame{FrameKind::kAck, s.profile.address, 0x45, *b.navigation});
  const auto* n = d ? std::get_if<NavigationDataReply>(&d.value()) : nullptr;
  if (!n || !n->latitude || !n->longitude) {
    notes.push_back("navigation data changed and the backup holds no position to write back");
    return;
  }
  auto ddmm = [](std::int32_t minutes) {
    return (minutes < 0 ? -1 : 1) * (std::abs(minutes) / 60 * 100 + std::abs(minutes) % 60);
  };
  const bool ok = s.ask(WriteNavigation{ddmm(*n->latitude), ddmm(*n->longitude), n->heading.value_or(0), ""}).has_value();
  notes.push_back(std::string("navigation data ") +
                  (ok ? "restored (this deletes the STORE list, §3.23)" : "could not be restored"));
}

}  // namespace

StoredDataBackup take_backup(Session& s, std::string& error) {
  StoredDataBackup b;
  std::vector<TranscriptEntry> scratch;
  s.transcript = &scratch;
  b.store_names = read_store_names(s);
  for (std::uint8_t i = 1; i <= 20; ++i)
    if (auto d = slot_data(s, ReadSatellite{{i}})) b.presets[i] = *d;
  for (std::uint8_t i = 1; i <= 10; ++i)
    if (auto d = slot_data(s, ReadTle{{i}})) b.tles[i] = *d;
  for (std::uint8_t i = 1; i <= 20; ++i) {
    auto d = s.ask(ReadSignpost{{i}});
    if (!d) break;  // no DVB option: 44h is NAKed (E-23)
    if (d->size() >= 2 && (*d)[0] != fields::kEmptySlot) b.signposts[i] = *d;
  }
  b.navigation = s.ask(NavigationQuery{});
  b.taken = true;
  s.transcript = nullptr;
  if (!s.options.backup_path.empty()) {
    // A backup already there may be the only copy of what a device held
    // before an earlier run whose restore failed: it is never replaced.
    if (auto file = write_new_file(s.options.backup_path, b.to_json(), error)) b.file = *file;
    else error = "the stored-data backup cannot be written: " + error;
  }
  return b;
}

void restore_backup(Session& s, const StoredDataBackup& b, std::vector<std::string>& notes) {
  std::vector<TranscriptEntry> scratch;
  s.transcript = &scratch;
  restore_slots<ReadSatellite, SatelliteDataReply>(
      s, 0x3A, 20, b.presets, [](std::uint8_t i, const SatelliteDataReply& r) { return Request{WriteSatellite{i, r.sat}}; },
      notes);
  restore_slots<ReadTle, TleDataReply>(
      s, 0x3C, 10, b.tles, [](std::uint8_t i, const TleDataReply& r) { return Request{WriteTle{i, r.line1, r.line2}}; },
      notes);
  if (!b.signposts.empty())
    restore_slots<ReadSignpost, SignpostDataReply>(
        s, 0x44, 20, b.signposts,
        [](std::uint8_t i, const SignpostDataReply& r) { return Request{WriteSignpost{i, r.signpost}}; }, notes);
  restore_navigation(s, b, notes);
  const std::vector<std::string> names = read_store_names(s);
  for (const auto& n : b.store_names)
    if (std::find(names.begin(), names.end(), n) == names.end())
      notes.push_back("STORE entry \"" + n +
                      "\" is gone; it can only be stored again at its satellite (42h stores the current position)");
  s.transcript = nullptr;
}

}  // namespace sabus::harness::detail

namespace sabus::harness {

std::string StoredDataBackup::to_json() const {
  using json = nlohmann::ordered_json;
  auto slots = [](const std::map<std::uint8_t, Bytes>& m) {
    json out = json::object();
    for (const auto& [i, d] : m) out[std::to_string(i)] = to_hex(d);
    return out;
  };
  const json doc = {{"store_names", store_names},
                    {"presets", slots(presets)},
                    {"tles", slots(tles)},
                    {"signposts", slots(signposts)},
                    {"navigation", navigation ? json(to_hex(*navigation)) : json()}};
  // Names are 35h's printable text; one that is not UTF-8 all the same is
  // written with U+FFFD rather than thrown on before the destructive vectors.
  return doc.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace sabus::harness

namespace sabus::harness {

std::optional<StoredDataBackup> StoredDataBackup::from_json(const std::string& text, std::string& error) {
  using json = nlohmann::json;
  const json doc = json::parse(text, nullptr, false);
  if (!doc.is_object()) {
    error = "not a JSON object";
    return std::nullopt;
  }
  StoredDataBackup b;
  std::string where = "store_names";
  auto bytes = [&](const json& hex) {
    auto parsed = parse_hex(hex.get<std::string>());
    if (!parsed) throw std::invalid_argument("not hex: " + hex.get<std::string>());
    return parsed.value();
  };
  try {
    b.store_names = doc.at("store_names").get<std::vector<std::string>>();
    for (const auto& [key, slots] : {std::pair{"presets", &b.presets}, std::pair{"tles", &b.tles}, std::pair{"signposts", &b.signposts}}) {
      where = key;
      for (const auto& [slot, hex] : doc.at(key).items()) {
        const int index = std::stoi(slot);
        if (index < 1 || index > 255 || std::to_string(index) != slot) throw std::invalid_argument("slot \"" + slot + "\"");
        (*slots)[static_cast<std::uint8_t>(index)] = bytes(hex);
      }
    }
    where = "navigation";
    if (const json& nav = doc.at("navigation"); !nav.is_null()) b.navigation = bytes(nav);
  } catch (const std::exception& e) {
    error = where + ": " + e.what();
    return std::nullopt;
  }
  return b;
}

}  // namespace sabus::harness
