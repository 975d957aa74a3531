// The run header the report tests start from: a run on the in-process
// reference controller, which answered the identity query as a 1.59 unit.
#pragma once

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

}  // namespace sabus::reports::test_documents
