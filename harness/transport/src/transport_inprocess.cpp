// InProcessTransport: the reference controllers on a virtual clock, reached
// without a wire. Requests and replies are the bytes a port opened 8N1 would
// carry (even parity in bit 7, READING-NOTES 1), so the runner reads them
// exactly as it reads a real line.
#include <algorithm>

#include "sabus/harness/transports.hpp"

namespace sabus::harness {

namespace {

// "in-process reference controller rc3000-1.59 at 0x32 '2'" (each
// controller of a multi-drop bus), then the injected faults by name.
std::string describe_bus(const std::vector<Profile>& profiles, const FaultSet& faults) {
  std::string s = profiles.size() == 1 ? "in-process reference controller" : "in-process reference controllers";
  for (std::size_t i = 0; i < profiles.size(); ++i)
    s += (i == 0 ? " " : ", ") + profiles[i].name + " at " + describe_byte(profiles[i].address);
  std::string names;
  for (const FaultInfo& f : all_faults())
    if (faults.has(f.fault)) names += (names.empty() ? "" : ", ") + std::string(f.name);
  if (!names.empty()) s += ", faults: " + names;
  return s;
}

}  // namespace

InProcessTransport::InProcessTransport(std::vector<Profile> profiles, FaultSet faults)
    : description_(describe_bus(profiles, faults)),
      bus_(std::move(profiles), clock_, faults, Parity::kEvenBit7) {}

void InProcessTransport::send(ByteView chars, std::span<const std::size_t> wrong_parity) {
  Bytes wire = with_software_parity(chars, wrong_parity);
  if (to_device_) wire = to_device_->pass(wire);
  Bytes out;
  bus_.receive(wire, out);
  if (from_device_ && !out.empty()) out = from_device_->pass(out);
  replies_.insert(replies_.end(), out.begin(), out.end());
}

void InProcessTransport::set_line_faults(const LineFaultSpec& spec) {
  to_device_.emplace(spec);
  LineFaultSpec back = spec;
  back.seed = spec.seed + 1;
  from_device_.emplace(back);
  description_ += ", line faults: " + harness::describe(spec);
}

LineFaultTally InProcessTransport::injected_faults() const {
  LineFaultTally t;
  for (const auto* i : {&to_device_, &from_device_})
    if (*i) {
      const LineFaultTally& o = (*i)->tally();
      t.bytes += o.bytes;
      t.flips += o.flips;
      t.drops += o.drops;
      t.inserts += o.inserts;
      t.outages += o.outages;
    }
  return t;
}

std::size_t InProcessTransport::receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) {
  if (replies_.empty()) {
    // Nothing will come: the wait is the only thing that happens. Advancing
    // the clock lets motion and jog timers run as they would have.
    pause(timeout);
    return 0;
  }
  const std::size_t n = std::min(buf.size(), replies_.size());
  std::copy_n(replies_.begin(), n, buf.begin());
  replies_.erase(replies_.begin(), replies_.begin() + static_cast<std::ptrdiff_t>(n));
  return n;
}

void InProcessTransport::pause(std::chrono::milliseconds d) {
  clock_.advance(std::max(d, std::chrono::milliseconds{0}));
  bus_.tick();
}

std::unique_ptr<InProcessTransport> make_in_process_transport(std::vector<Profile> profiles, FaultSet faults) {
  return std::make_unique<InProcessTransport>(std::move(profiles), faults);
}

}  // namespace sabus::harness
