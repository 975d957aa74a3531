// `sabus sim`: serves the reference controller on a pseudo-terminal, a serial
// port or a TCP socket, as a stand-in RC3000 for M&C software.
#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "device.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/harness/line.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/serve.hpp"
#include "sabus/harness/state_file.hpp"

namespace sabus::cli {
namespace {

using namespace sabus::harness;

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

struct SimOptions {
  bool pty = false;
  std::string link;
  std::string port;
  std::string tcp;
  std::string rfc2217;
  bool takeover = false;
  int baud = 0;
  std::string serial_backend = "auto";
  std::string profile;
  std::string addresses;
  bool remote_disabled = false;
  std::vector<std::string> faults;
  std::string reading;
  std::string state_file;
  bool emulate_line = false;
  double turnaround_ms = -1;
  std::string parity = "even";
  std::string log;
  std::string line_faults;
  std::uint64_t line_fault_seed = 1;
  bool list_faults = false;
};

int list_faults() {
  std::size_t width = 0;
  for (const auto& f : all_faults()) width = std::max(width, f.name.size());
  for (const auto& f : all_faults()) std::cout << fmt::format("{:<{}}  {}\n", f.name, width, f.description);
  return kExitOk;
}

// The controllers to serve: the profile, once per --address.
std::optional<std::vector<Profile>> profiles(const SimOptions& o) {
  const std::string path = o.profile.empty() ? default_profile_path() : o.profile;
  ProfileResult loaded = load_profile_file(path);
  if (!loaded) {
    std::cerr << "sabus sim: " << loaded.error->text() << "\n";
    return std::nullopt;
  }
  Profile base = *loaded.profile;
  if (o.remote_disabled) base.remote_enabled = false;
  if (!o.reading.empty())
    if (auto why = apply_reading_spec(o.reading, base.readings)) {
      std::cerr << "sabus sim: --reading: " << *why << "\n";
      return std::nullopt;
    }
  if (o.addresses.empty()) return bus_of(base);  // the profile's bus_peers (§1 multi-drop)
  std::vector<std::uint8_t> addresses;
  std::stringstream list(o.addresses);
  for (std::string item; std::getline(list, item, ',');) {
    auto a = parse_address(item);
    if (!a) {
      std::cerr << "sabus sim: --address: " << a.error().message() << "\n";
      return std::nullopt;
    }
    addresses.push_back(a.value());
  }
  if (addresses.size() == 1) {
    base.address = addresses[0];
    return std::vector<Profile>{base};
  }
  return multi_drop(base, addresses);
}

std::optional<FaultSet> faults(const SimOptions& o) {
  FaultSet set;
  for (const auto& name : o.faults) {
    auto f = find_fault(name);
    if (!f) {
      std::cerr << "sabus sim: unknown fault \"" << name << "\"; `sabus sim --list-faults` lists them\n";
      return std::nullopt;
    }
    set.set(*f);
  }
  return set;
}

int run_sim(const SimOptions& o) {
  if (o.list_faults) return list_faults();
  const int transports =
      (o.pty ? 1 : 0) + (o.port.empty() ? 0 : 1) + (o.tcp.empty() ? 0 : 1) + (o.rfc2217.empty() ? 0 : 1);
  if (transports != 1) {
    std::cerr << "sabus sim: choose one of --pty --link PATH, --port DEV, --tcp HOST:PORT, --rfc2217 HOST:PORT\n";
    return kExitUsage;
  }
  if (o.takeover && o.tcp.empty() && o.rfc2217.empty()) {
    std::cerr << "sabus sim: --takeover needs --tcp or --rfc2217\n";
    return kExitUsage;
  }
  if (o.pty && o.link.empty()) {
    std::cerr << "sabus sim: --pty needs --link PATH\n";
    return kExitUsage;
  }
  auto profs = profiles(o);
  auto fs = faults(o);
  if (!profs || !fs) return kExitUsage;

  SteadyClock clock;
  const Parity parity = o.parity == "none" ? Parity::kNone : Parity::kEvenBit7;
  Bus bus(*profs, clock, *fs, parity);
  std::vector<Controller*> controllers;
  std::vector<const Controller*> const_controllers;
  for (std::size_t i = 0; i < bus.size(); ++i) {
    controllers.push_back(&bus.controller(i));
    const_controllers.push_back(&bus.controller(i));
  }
  if (!o.state_file.empty()) {
    std::string error;
    if (!read_state_file(o.state_file, controllers, error)) {
      std::cerr << "sabus sim: " << error << "\n";
      return kExitUsage;
    }
    bus.on_stored_data_change([&](const Controller&) {
      std::string e;
      if (!write_state_file(o.state_file, const_controllers, e)) std::cerr << "sabus sim: " << e << "\n";
    });
  }

  std::ofstream log_file;
  ServeOptions serve_options;
  serve_options.emulate_line = o.emulate_line;
  serve_options.baud = o.baud > 0 ? o.baud : profs->front().baud;
  serve_options.turnaround_ms = o.turnaround_ms >= 0 ? o.turnaround_ms : profs->front().turnaround_ms;
  if (!o.line_faults.empty()) {
    std::string error;
    serve_options.line_faults = parse_line_faults(o.line_faults, error);
    if (!serve_options.line_faults) {
      std::cerr << "sabus sim: --line-faults: " << error << "\n";
      return kExitUsage;
    }
    serve_options.line_faults->seed = o.line_fault_seed;
  }
  if (!o.log.empty()) {
    log_file.open(o.log, std::ios::app);
    if (!log_file) {
      std::cerr << "sabus sim: cannot write " << o.log << "\n";
      return kExitUsage;
    }
    serve_options.log = &log_file;
  }

  std::optional<HostPort> tcp;
  if (!o.tcp.empty() && !(tcp = parse_host_port(o.tcp))) {
    std::cerr << "sabus sim: --tcp HOST:PORT, with a port 0-65535\n";
    return kExitUsage;
  }
  if (!o.rfc2217.empty() && !(tcp = parse_host_port(o.rfc2217))) {
    std::cerr << "sabus sim: --rfc2217 HOST:PORT, with a port 0-65535\n";
    return kExitUsage;
  }
  serve_options.rfc2217 = !o.rfc2217.empty();
  serve_options.takeover = o.takeover;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  int status = kExitOk;
  try {
    if (tcp) {
      auto listener = TcpListener::listen(tcp->host, tcp->port);
      std::cout << "READY " << (serve_options.rfc2217 ? "rfc2217 " : "tcp ") << tcp->host << ":" << listener->port()
                << std::endl;
      status = serve_tcp(*listener, bus, serve_options, g_stop);
    } else if (o.pty) {
      auto line = PtyLine::create(o.link);
      std::cout << "READY " << o.link << std::endl;
      status = serve(*line, bus, serve_options, g_stop);
    } else {
      std::string note;
      auto backend = parse_serial_backend(o.serial_backend).value_or(SerialBackend::automatic);
      auto line = open_serial_line(o.port, serve_options.baud, backend, &note);
      if (!note.empty() && verbose()) std::cerr << "sabus sim: " << note << "\n";
      std::cout << "READY " << o.port << std::endl;
      status = serve(*line, bus, serve_options, g_stop);
    }
  } catch (const LineError& e) {
    std::cerr << "sabus sim: " << e.what() << "\n";
    status = kExitFailed;
  }
  if (!o.state_file.empty()) {
    std::string error;
    if (!write_state_file(o.state_file, const_controllers, error)) std::cerr << "sabus sim: " << error << "\n";
  }
  return status;
}

}  // namespace

Command add_sim_command(CLI::App& app) {
  auto o = std::make_shared<SimOptions>();
  CLI::App* sub = app.add_subcommand("sim", "Serve the reference RC3000 on a pty, a serial port, TCP or RFC 2217");
  sub->add_flag("--pty", o->pty, "Create a pseudo-terminal (with --link PATH)");
  sub->add_option("--link", o->link, "Symlink PATH to the pseudo-terminal; removed on exit");
  sub->add_option("--port", o->port, "Serve a serial port (e.g. /dev/ttyUSB0)");
  sub->add_option("--tcp", o->tcp, "Serve raw TCP at HOST:PORT, as a serial device server (port 0: any free port)");
  sub->add_option("--rfc2217", o->rfc2217,
                  "Serve Telnet with RFC 2217 at HOST:PORT, as a terminal server's port (rfc2217://HOST:PORT; "
                  "port 0: any free port)");
  sub->add_flag("--takeover", o->takeover,
                "With --tcp/--rfc2217: a new client replaces the one served (default: it is refused at once)");
  sub->add_option("--baud", o->baud, "Baud rate, 300-115200 (default: the profile's)")->check(kBaudRange);
  add_serial_backend_option(sub, o->serial_backend);
  sub->add_option("--profile", o->profile, "Device profile (default vectors/profiles/rc3000-1.59.yaml)");
  sub->add_option("--address", o->addresses, "Address, or a list for a multi-drop bus: 50,51,60");
  sub->add_flag("--remote-disabled", o->remote_disabled, "Remote control disabled: valid commands get the offline reply");
  sub->add_option("--fault", o->faults, "Inject a named fault (repeatable); see --list-faults");
  sub->add_option("--reading", o->reading, kReadingHelp);
  sub->add_option("--state-file", o->state_file, "Keep non-volatile data (STORE list, presets, ...) in this file");
  sub->add_flag("--emulate-line", o->emulate_line, "Hold each reply byte for its wire time at the baud rate");
  sub->add_option("--turnaround", o->turnaround_ms, "Reply turnaround in ms with --emulate-line, 0-10000 (default: the profile's)")
      ->check(CLI::Range(0.0, 10'000.0));
  sub->add_option("--parity", o->parity, "even: bit 7 carries even parity (a 7E1 line); none: 7-bit characters")
      ->check(CLI::IsMember({"even", "none"}));
  sub->add_option("--line-faults", o->line_faults,
                  "Make the line noisy: RATE[,KIND...], a byte error rate each way (1e-3) and flip, drop, insert, "
                  "outage (default all)");
  sub->add_option("--line-fault-seed", o->line_fault_seed, "Seed of --line-faults (default 1)");
  sub->add_option("--log", o->log, "Append a decoded transcript to FILE");
  sub->add_flag("--list-faults", o->list_faults, "List the injectable faults and exit");
  return {sub, [o] { return run_sim(*o); }};
}

}  // namespace sabus::cli
