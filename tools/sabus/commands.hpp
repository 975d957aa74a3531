// The subcommands of the `sabus` CLI. Each registers its options on the
// CLI11 app and returns the process exit code when it runs.
#pragma once

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace sabus::cli {

// Exit codes shared by every subcommand (`sabus run --help` lists them).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitUnreachable = 3;  // the device could not be reached
// Stopped before its end by the bench, not the firmware: SIGINT, SIGTERM or a
// lost device, with the results so far saved. 4 is the first free code;
// pytest's 2 (interrupted) is the usage error here, and 128+signal would say
// "killed" and has no number for a lost device.
inline constexpr int kExitStopped = 4;
// Nothing was checked: no vector selected, or every selected vector skipped.
// pytest's "no tests ran" is 5 too, so a CI set up for either reads it the same.
inline constexpr int kExitNothingRan = 5;
// No vector failed, but some ended in error: the line, not the firmware,
// left them unjudged (harness::kLineErrorExitCode). The next free code.
inline constexpr int kExitLineError = 6;

// --reading of sabus sim, run --sim and fuzz --sim (readings.hpp).
inline constexpr const char* kReadingHelp =
    "The side of the spec's open points the reference controller takes (protocol/ERRATA.md, class reading): "
    "other (every one flipped), other-2 (the third side where a point has one, else other), reference, or "
    "E-NN=SIDE,... one at a time (default: the profile's pins, else reference)";

// How much the commands say: -q only failures and the summary, -v also every
// vector on a terminal and the notes of how a port was opened (options of
// the whole program, taken before or after the subcommand).
enum class Verbosity { kQuiet, kNormal, kVerbose };
inline Verbosity g_verbosity = Verbosity::kNormal;
inline bool quiet() { return g_verbosity == Verbosity::kQuiet; }
inline bool verbose() { return g_verbosity == Verbosity::kVerbose; }

// Colour on `fd`: a terminal, and neither NO_COLOR (https://no-color.org:
// set and not empty) nor TERM=dumb says otherwise.
inline bool use_colour(int fd) {
  const char* no_colour = std::getenv("NO_COLOR");
  const char* term = std::getenv("TERM");
  return ::isatty(fd) == 1 && (no_colour == nullptr || *no_colour == '\0') &&
         (term == nullptr || std::string_view(term) != "dumb");
}

// "HOST:PORT" as --tcp takes it (port 0-65535); nullopt when it is not.
struct HostPort {
  std::string host;
  std::uint16_t port = 0;
};
inline std::optional<HostPort> parse_host_port(std::string_view text) {
  const auto colon = text.rfind(':');
  if (colon == std::string_view::npos || colon == 0) return std::nullopt;
  const std::string_view digits = text.substr(colon + 1);
  unsigned port = 0;
  auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), port);
  if (digits.empty() || ec != std::errc{} || end != digits.data() + digits.size() || port > 65535) return std::nullopt;
  return HostPort{std::string(text.substr(0, colon)), static_cast<std::uint16_t>(port)};
}

// CLI11 checks of numeric options, so a bad value is a usage error (exit 2)
// naming the option: "--pace: Value -5 not in range 0 to 60000".
// Milliseconds between commands (--pace): at most a minute.
inline const CLI::Range kPaceRange(0L, 60'000L);
// A count or a time that cannot be negative (CLI11's NonNegativeNumber
// would print its upper bound, 1.8e308, in full).
inline const CLI::Validator kNonNegative(
    [](std::string& input) -> std::string {
      double value = 0;
      if (!CLI::detail::lexical_cast(input, value) || value < 0) return "Value " + input + " is not a number 0 or more";
      return {};
    },
    "NUMBER >= 0", "NONNEGATIVE");
// A baud rate a serial line here can be set to.
inline const CLI::Range kBaudRange(300, 115'200);

struct Command {
  CLI::App* app;            // the subcommand
  std::function<int()> run; // runs it after parsing
};

Command add_decode_command(CLI::App& app);
Command add_sim_command(CLI::App& app);
Command add_ports_command(CLI::App& app);
Command add_run_command(CLI::App& app);
Command add_vectors_command(CLI::App& app);
Command add_report_command(CLI::App& app);
Command add_diff_command(CLI::App& app);
Command add_proxy_command(CLI::App& app);
Command add_record_command(CLI::App& app);
Command add_fuzz_command(CLI::App& app);

}  // namespace sabus::cli
