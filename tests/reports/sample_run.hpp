// The run header the report tests start from: a run on the in-process
// reference controller, which answered the identity query as a 1.59 unit.
#pragma once

#include <string>

#include "sabus/reports/document.hpp"

namespace sabus::reports::test_documents {

inline RunDocument sample_header() {
  RunDocument d;
  d.started_at = "2024-01-01T00:00:00Z";
  d.device = "in-process";
  d.profile = "rc3000-1.59";
  d.address = 0x32;  // the profile's address, 50
  d.identity = {true, "3K", "1.59", "06 32 30 33 4b 31 2e 35 39 03 6c", ""};
  return d;
}

// A §3.2 status poll vector of `outcome`, with what that outcome carries (a
// failure its reason, a known issue its listing, an inconclusive vector why,
// a vector in error what the line did and its line counts, a skip its cause
// and no frames): a status poll sent, and its reply with one field described.
inline VectorRecord sample_vector(std::string id, std::string outcome) {
  VectorRecord v;
  v.id = std::move(id);
  v.outcome = std::move(outcome);
  v.paragraph = "3.2";
  v.level = "must";
  v.duration_ms = 3;
  v.wall_ms = 0.5;
  FrameRecord tx;
  tx.dir = "tx";
  tx.hex = "02 32 31 03 02";
  tx.note = "status poll";
  tx.command = "status";
  tx.expect = tx.path = "ack";
  tx.fields = {{0, 0, "start", "0x02", "STX", true}};
  FrameRecord rx;
  rx.dir = "rx";
  rx.t_ms = 3;
  rx.hex = "06 32 31 03 04";
  rx.note = "status reply";
  rx.fields = {{0, 0, "start", "0x06", "ACK", true}};
  v.transcript = {tx, rx};
  if (v.outcome == "fail" || v.outcome == "known failure") v.failures = {"byte 3: expected 0x57, got 0x44"};
  if (v.outcome == "known failure" || v.outcome == "unexpected pass") v.known_issue = "listed";
  if (v.outcome == "inconclusive")
    v.inconclusive_reason = "precondition not met (the search is still running when the stop goes out): byte 45 current "
                            "mode: expected 0x26, got 0x20 (MANUAL_MODE)";
  // One in error: the poll, and the poll again after a bad check byte,
  // which got no clean reply either. (The others count no exchange, as
  // documents before version 5 did.)
  if (v.outcome == "error") {
    v.error_reason = "step 1 (status): no clean reply in 2 tries: bad check byte: expected 0x04, got 0x05";
    v.line = {2, 2, 0, 1};
  }
  if (v.outcome == "skip") {
    v.skip_reason = "needs --allow-motion";
    v.skip_cause = "motion";
    v.transcript.clear();
  }
  return v;
}

}  // namespace sabus::reports::test_documents
