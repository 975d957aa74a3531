// sabus: conformance and fuzz test harness for the RC3000 SAbus remote control.
#include <vector>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sabus: SAbus conformance and fuzz test harness for the RC3000 antenna controller"};
  app.require_subcommand(1);
  const std::vector<sabus::cli::Command> commands = {
      sabus::cli::add_decode_command(app),
      sabus::cli::add_sim_command(app),
      sabus::cli::add_run_command(app),
      sabus::cli::add_vectors_command(app),
      sabus::cli::add_ports_command(app),
      sabus::cli::add_report_command(app),
      sabus::cli::add_diff_command(app),
      sabus::cli::add_proxy_command(app),
      sabus::cli::add_record_command(app),
      sabus::cli::add_fuzz_command(app),
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? sabus::cli::kExitOk : sabus::cli::kExitUsage;
  }
  for (const auto& c : commands)
    if (c.app->parsed()) return c.run();
  return sabus::cli::kExitUsage;
}
