// The subcommands of the `sabus` CLI. Each registers its options on the
// CLI11 app and returns the process exit code when it runs.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace sabus::cli {

// Exit codes shared by every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitUsage = 2;

struct Command {
  CLI::App* app;            // the subcommand
  std::function<int()> run; // runs it after parsing
};

Command add_decode_command(CLI::App& app);
Command add_sim_command(CLI::App& app);
Command add_ports_command(CLI::App& app);
Command add_run_command(CLI::App& app);
Command add_vectors_command(CLI::App& app);

}  // namespace sabus::cli
