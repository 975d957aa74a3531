// The coverage matrices of a vector suite: catalog command x form x path
// (ack / nak / offline / ignore) -> the vectors that send such a frame and
// expect such an answer; and reply field -> the vectors that check its
// value. `sabus vectors coverage` prints them and fails when a cell the spec
// defines has no vector, or a field whose value rests on the device has no
// vector that checks it.
#pragma once

#include <array>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "sabus/harness/profile.hpp"
#include "sabus/harness/vector.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/field_classes.hpp"

namespace sabus::harness {

// What a step expects back, as the matrix counts it.
enum class CoveragePath : std::uint8_t { kAck, kNak, kOffline, kIgnore };
inline constexpr std::array<CoveragePath, 4> kCoveragePaths = {CoveragePath::kAck, CoveragePath::kNak,
                                                               CoveragePath::kOffline, CoveragePath::kIgnore};
std::string_view to_string(CoveragePath path);

// One row: a command form of the catalog, or (form == nullptr) the frames of
// the command whose form cannot be told (damaged, truncated).
struct CoverageRow {
  const CommandInfo* command = nullptr;
  const FormInfo* form = nullptr;
  std::array<std::vector<std::string>, 4> ids;  // by CoveragePath, each id once
};

// One field of one reply (field_classes.hpp) and the vectors that check its
// value: a step sending a command the reply answers, expecting that reply
// (ACK), with a matcher on the field that compares it with a value
// (checks_value), or expecting the whole reply's bytes, or the profile's
// record (`from_profile`, its stored and echoed fields). `any`, a range of
// constants or a regex that every legal value passes checks only the form.
//
// Only a vector whose requirements are capabilities counts (issue 32): a
// vector that requires a literal profile value (`firmware: "1.59"`, a count,
// an index) judges only the controllers that happen to have it, so its
// checks are kept apart (literal_ids) and a field they alone check is
// missing. Whether the capabilities leave some profiles unchecked is the
// share over profiles (field_shares).
struct FieldValueRow {
  const ReplyFieldClass* field = nullptr;
  std::vector<std::string> ids;
  std::vector<std::string> literal_ids;  // checks by vectors that require a literal profile value
};

struct CoverageMatrix {
  std::vector<CoverageRow> rows;            // catalog order, then the unclassified row of a command
  std::vector<std::string> unknown_codes;   // vectors sending codes outside the catalog (§3 NAK, E-9)
  // Every NAK rule of the reference controller (nak_rules.hpp) -> the
  // vectors whose nak expectation names it.
  std::map<std::string, std::vector<std::string>> nak_rules;
  // The cells the spec defines that no vector covers, one line each:
  // "32h auto_move 2A: ack". Required: an ACK vector for every form of every
  // command (§3.1-§3.25; 38h/3Dh/3Eh on a profile that implements them), and
  // for every command a NAK vector (§3 NAK Reply: a wrong length is NAKed
  // for any code), an offline vector (§3 Online/Offline Reply) and an ignore
  // vector (§1: a damaged frame of that command gets no reply), in any form;
  // and a NAK vector for a code outside the catalog; and, for every NAK rule
  // of the reference controller, a vector naming it.
  std::vector<std::string> missing() const;
  // The field-value matrix: every field of every reply, in reply and byte order.
  std::vector<FieldValueRow> fields;
  // The fields whose value a suite must check (value_required) that no
  // vector on capabilities checks, one line each: "status azimuth (motion,
  // §3.2): no vector checks it", or what follows the colon names the vectors
  // that check it on a literal profile value only.
  std::vector<std::string> missing_values() const;
  // Reply -> the vectors that expect an ACK with that reply (any matcher,
  // any requirement): where they run, the reply's fields exist.
  std::map<ReplyKind, std::vector<std::string>> acked;
};

// Whether a requirement names a literal profile value rather than a
// capability: a capability is a yes/no or a named choice of the profile
// schema (`dvb_receiver: true`, `polarization: circular`, `track.active:
// false`); a number, a version or a text (`firmware: "1.59"`,
// `errata.locate_index_min: 1`, `alarms.code: 2`) is a literal.
bool literal_requirement(const Requirement& r);

// A profile and the vectors that run on it: the ids whose requirements hold
// (requirement_site), or those a run did not skip (sabus vectors sweep).
struct ProfileSite {
  std::string label;            // "rc3000-1.59.yaml", "sweep seed 1 profile 3 (--profile-seed 123)"
  std::set<std::string> runs;   // vector ids
  // The fields (field_label) whose value the spec leaves open on this
  // profile (undetermined_fields): not counted where the field exists.
  std::set<std::string> undetermined;
};
ProfileSite requirement_site(const std::vector<VectorFile>& files, const Profile& profile, std::string label);
// The reply fields whose value the spec does not determine on `profile`,
// by field_label: the pulse counts of a mount whose azimuth sensor does not
// count (ERRATA E-85: only the layout is checked there).
std::set<std::string> undetermined_fields(const Profile& profile);

// The share of profiles on which a field's value is checked (issue 32): of
// the profiles where the field exists (a vector that expects an ACK with its
// reply runs there), those where a vector that checks its value runs too.
// 100% is the gate; `unchecked` names the profiles that leave it unchecked.
struct FieldShare {
  const ReplyFieldClass* field = nullptr;
  std::size_t exists = 0, checked = 0;
  std::vector<std::string> unchecked;  // site labels
};
// Every field whose value a suite must check (value_required), in the
// matrix's order.
std::vector<FieldShare> field_shares(const CoverageMatrix& m, const std::vector<ProfileSite>& sites);

// Every send and poll step of every vector (setup, steps, teardown) that
// expects ack, nak, offline or silence; `any` counts nowhere. The
// field-value matrix counts the steps that expect an ACK.
CoverageMatrix coverage(const std::vector<VectorFile>& files);

// "32h auto_move" and "32h auto_move 2A" (the form when the command has several).
std::string command_label(const CommandInfo& command);
std::string row_label(const CoverageRow& row);
// "status azimuth" (the reply's name, the field's).
std::string field_label(const ReplyFieldClass& field);
// Whether a matcher on a field of `reply` compares the field with a value,
// not only its form: eq, one_of, near, jogged; a range bounded by a profile
// expression or a capture; a regex that picks some of a one-byte field's
// values and not all (the bits of a status byte).
bool checks_value(const FieldMatcher& m, ReplyKind reply);

}  // namespace sabus::harness
