// `sabus ports`: the serial ports libserialport sees, one a line (or --json),
// to find the adapter the controller hangs on before `sabus run --port`.
// Pseudo-terminals are never listed (libserialport walks /sys/class/tty).
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "json_output.hpp"
#include "sabus/harness/line.hpp"

namespace sabus::cli {
namespace {

using harness::SerialPortInfo;

struct PortsOptions {
  bool json = false;
};

std::string hex4(const std::optional<int>& v) { return v ? fmt::format("{:04x}", *v) : std::string("????"); }

// "/dev/ttyUSB0  FT232R USB UART  usb 0403:6001  manufacturer FTDI  product
// FT232R USB UART  serial A50285BI": fields that are unknown are left out.
std::string port_line(const SerialPortInfo& p) {
  std::string s = p.name + "  " + (p.description.empty() ? "(no description)" : p.description) + "  " +
                  std::string(harness::to_string(p.transport));
  if (p.transport == SerialPortInfo::Transport::usb) s += " " + hex4(p.usb_vid) + ":" + hex4(p.usb_pid);
  if (p.transport == SerialPortInfo::Transport::bluetooth && !p.bluetooth_address.empty())
    s += " " + p.bluetooth_address;
  if (!p.manufacturer.empty()) s += "  manufacturer " + p.manufacturer;
  if (!p.product.empty()) s += "  product " + p.product;
  if (!p.serial_number.empty()) s += "  serial " + p.serial_number;
  return s;
}

nlohmann::json optional_int(const std::optional<int>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

nlohmann::json port_json(const SerialPortInfo& p) {
  return {{"name", p.name},
          {"description", p.description},
          {"transport", std::string(harness::to_string(p.transport))},
          {"usb_vid", optional_int(p.usb_vid)},
          {"usb_pid", optional_int(p.usb_pid)},
          {"usb_bus", optional_int(p.usb_bus)},
          {"usb_address", optional_int(p.usb_address)},
          {"manufacturer", p.manufacturer},
          {"product", p.product},
          {"serial_number", p.serial_number},
          {"bluetooth_address", p.bluetooth_address}};
}

int run_ports(const PortsOptions& o) {
  std::vector<SerialPortInfo> ports;
  try {
    ports = harness::list_serial_ports();
  } catch (const harness::LineError& e) {
    std::cerr << "sabus ports: " << e.what() << "\n";
    return kExitFailed;
  }
  if (o.json) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& p : ports) out.push_back(port_json(p));
    std::cout << json_text(out);
  } else if (ports.empty()) {
    std::cout << "no serial ports found\n";
  } else {
    for (const auto& p : ports) std::cout << port_line(p) << "\n";
  }
  return kExitOk;
}

}  // namespace

Command add_ports_command(CLI::App& app) {
  auto o = std::make_shared<PortsOptions>();
  CLI::App* sub = app.add_subcommand("ports", "List the serial ports (name, description, USB ids, serial number)");
  sub->add_flag("--json", o->json, "Print JSON (an array, empty when there are none)");
  sub->footer(
      "A controller behind a terminal server (ser2net, Moxa NPort, Digi PortServer) is not listed: name its port "
      "--port rfc2217://HOST:PORT when the server speaks Telnet with RFC 2217, or --tcp HOST:PORT for a raw TCP port.");
  return {sub, [o] { return run_ports(*o); }};
}

}  // namespace sabus::cli
