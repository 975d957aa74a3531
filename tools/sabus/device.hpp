// The device options `sabus run` and `sabus fuzz` share: which controller to
// reach (the in-process reference, a serial port, a TCP serial server), its
// profile, address, baud rate and line mode, and faults to inject with --sim.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/faults.hpp"
#include "sabus/harness/line_faults.hpp"
#include "sabus/harness/profile.hpp"
#include "sabus/harness/rfc2217.hpp"
#include "sabus/harness/transport.hpp"

namespace sabus::cli {

struct DeviceOptions {
  bool sim = false;
  std::string port, tcp, profile, address;
  std::string line = "8N1", serial_backend = "auto";
  std::vector<std::string> faults;
  // With --sim: the side of the spec's open points the reference controller
  // takes (readings.hpp); the runner's profile keeps its own pins.
  std::string reading;
  // With --sim (`sabus run --line-faults`): an emulated noisy line between
  // the runner and the controller, "RATE[,KIND...]" (line_faults.hpp), from
  // `line_fault_seed`.
  std::string line_faults;
  std::uint64_t line_fault_seed = 1;
  int baud = 0;
};

// Registers --sim, --port, --tcp, --profile, --address, --baud, --line,
// --serial-backend, --fault and --reading on `sub`.
void add_device_options(CLI::App* sub, DeviceOptions& o);
// --serial-backend (auto, libserialport or termios), for every command that
// opens a serial port.
void add_serial_backend_option(CLI::App* sub, std::string& backend);

// What the telnet layer of an rfc2217:// port has to say, on stderr as
// "sabus TOOL: ...": what matters always (a line error the server saw, a
// SET-CONTROL it did not acknowledge), the rest (modem state, the
// negotiation's round trip) with --verbose.
harness::TelnetNote telnet_note(const std::string& tool);

// The device, ready to use: the profile (with --address and --baud applied),
// the faults and the transport. `exit_code` is 0 when it worked, kExitUsage
// for bad options, 3 when the device cannot be reached; the error is
// printed as "sabus TOOL: ...".
struct OpenedDevice {
  int exit_code = 0;
  harness::Profile profile;
  // With --sim: the reference controller's profile, the device's with the
  // sides --reading pins (a fresh copy of the device for minimizing).
  harness::Profile controller_profile;
  harness::FaultSet faults;
  std::unique_ptr<harness::Transport> transport;
  // With --sim --line-faults: the emulated line's faults so far (transport
  // is an InProcessTransport then); nullptr otherwise.
  std::function<harness::LineFaultTally()> injected_faults;
};
// With none of --sim, --port, --tcp: the in-process reference controller.
OpenedDevice open_device(const std::string& tool, DeviceOptions o);

}  // namespace sabus::cli
