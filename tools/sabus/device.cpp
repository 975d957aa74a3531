#include "device.hpp"

#include <iostream>

#include "commands.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/transports.hpp"

namespace sabus::cli {

using namespace sabus::harness;

void add_device_options(CLI::App* sub, DeviceOptions& o) {
  sub->add_flag("--sim", o.sim, "The in-process reference controller (the default)");
  sub->add_option("--port", o.port,
                  "A serial port, or a terminal server's RFC 2217 port: rfc2217://HOST:PORT (pyserial's form)");
  sub->add_option("--tcp", o.tcp, "A TCP serial server, HOST:PORT");
  sub->add_option("--profile", o.profile, "Device profile (default vectors/profiles/rc3000-1.59.yaml)");
  sub->add_option("--address", o.address, "Device address (49-111, or the address character)");
  sub->add_option("--baud", o.baud, "Baud rate, 300-115200 (default: the profile's)")->check(kBaudRange);
  sub->add_option("--line", o.line, "8N1 (default: parity computed by sabus) or 7E1 (a true 7E1 port)")
      ->check(CLI::IsMember({"8N1", "7E1"}));
  add_serial_backend_option(sub, o.serial_backend);
  sub->add_option("--fault", o.faults, "With --sim: inject a named fault (sabus sim --list-faults)");
  sub->add_option("--reading", o.reading, kReadingHelp);
}

TelnetNote telnet_note(const std::string& tool) {
  return [tool](const std::string& text, bool important) {
    if (important || verbose()) std::cerr << "sabus " << tool << ": " << text << "\n";
  };
}

void add_serial_backend_option(CLI::App* sub, std::string& backend) {
  sub->add_option("--serial-backend", backend, "auto, libserialport or termios")
      ->check(CLI::IsMember({"auto", "libserialport", "termios"}));
}

OpenedDevice open_device(const std::string& tool, DeviceOptions o) {
  OpenedDevice d;
  auto usage = [&](const std::string& message) {
    std::cerr << "sabus " << tool << ": " << message << "\n";
    d.exit_code = kExitUsage;
    return std::move(d);
  };
  const int transports = (o.sim ? 1 : 0) + (o.port.empty() ? 0 : 1) + (o.tcp.empty() ? 0 : 1);
  if (transports > 1) return usage("choose one of --sim, --port DEV, --tcp HOST:PORT");
  if (transports == 0) o.sim = true;  // the in-process reference controller is the default
  ProfileResult loaded = load_profile_file(o.profile.empty() ? default_profile_path() : o.profile);
  if (!loaded) return usage(loaded.error->text());
  d.profile = *loaded.profile;
  if (!o.address.empty()) {
    auto a = parse_address(o.address);
    if (!a) return usage("--address: " + a.error().message());
    d.profile.address = a.value();
  }
  if (o.baud > 0) d.profile.baud = o.baud;
  for (const auto& name : o.faults) {
    auto f = find_fault(name);
    if (!f || !o.sim) return usage(o.sim ? "unknown fault \"" + name + "\"" : "--fault needs --sim");
    d.faults.set(*f);
  }
  // The controller's profile: the device's, with the sides --reading pins;
  // the verdicts keep the profile as the user wrote it.
  Profile controller_profile = d.profile;
  if (!o.reading.empty()) {
    if (!o.sim) return usage("--reading needs --sim");
    if (auto why = apply_reading_spec(o.reading, controller_profile.readings)) return usage("--reading: " + *why);
  }
  d.controller_profile = controller_profile;
  std::optional<LineFaultSpec> line_faults;
  if (!o.line_faults.empty()) {
    if (!o.sim) return usage("--line-faults needs --sim: a real line makes its own");
    std::string error;
    if (!(line_faults = parse_line_faults(o.line_faults, error))) return usage("--line-faults: " + error);
    line_faults->seed = o.line_fault_seed;
  }
  std::optional<HostPort> tcp;
  if (!o.tcp.empty() && !(tcp = parse_host_port(o.tcp))) return usage("--tcp HOST:PORT, with a port 0-65535");
  try {
    if (o.sim) {
      auto in_process = make_in_process_transport(bus_of(controller_profile), d.faults);  // §1 multi-drop: bus_peers
      if (line_faults) {
        in_process->set_line_faults(*line_faults);
        const InProcessTransport* t = in_process.get();
        d.injected_faults = [t] { return t->injected_faults(); };
      }
      d.transport = std::move(in_process);
    } else if (is_rfc2217_url(o.port)) {
      std::string error;
      const auto url = parse_rfc2217_url(o.port, error);
      if (!url) return usage("--port " + error);
      d.transport = make_rfc2217_transport(url->host, url->port, d.profile.baud,
                                           o.line == "7E1" ? LineMode::kTrue7E1 : LineMode::kSoftwareParity8N1,
                                           std::chrono::seconds(5), telnet_note(tool));
    } else if (!o.port.empty()) {
      std::string note;
      const auto backend = parse_serial_backend(o.serial_backend).value_or(SerialBackend::automatic);
      d.transport = make_serial_transport(o.port, d.profile.baud, backend,
                                          o.line == "7E1" ? LineMode::kTrue7E1 : LineMode::kSoftwareParity8N1, &note);
      if (!note.empty() && verbose()) std::cerr << "sabus " << tool << ": " << note << "\n";
    } else {
      d.transport = make_tcp_transport(tcp->host, tcp->port, std::chrono::seconds(5));
    }
  } catch (const std::exception& e) {
    std::cerr << "sabus " << tool << ": cannot reach the device: " << e.what() << "\n";
    d.exit_code = kExitUnreachable;
  }
  return d;
}

}  // namespace sabus::cli
