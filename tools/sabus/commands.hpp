// The subcommands of the `sabus` CLI. Each registers its options on the
// CLI11 app and returns the process exit code when it runs.
#pragma once

#include <CLI/CLI.hpp>
#include <charconv>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace sabus::cli {

// Exit codes shared by every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitUsage = 2;

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
