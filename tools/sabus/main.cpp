// sabus: conformance and fuzz test harness for the RC3000 SAbus remote control.
#include <iostream>
#include <vector>

#include "commands.hpp"
#include "sabus/harness/data_dir.hpp"
#include "version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sabus: SAbus conformance and fuzz test harness for the RC3000 antenna controller"};
  app.require_subcommand(1);
  // Options of the whole program, also taken after the subcommand's name.
  app.fallthrough();
  // Declared before --version, whose text names the data directory found.
  app.add_option("--data-dir", "Directory of the vectors, profiles and errata (default: $SABUS_DATA_DIR, then "
                               "share/sabus beside the executable, then the source tree it was built from)")
      ->type_name("DIR")
      ->each([](const std::string& dir) { sabus::harness::set_data_dir_option(dir); });
  bool verbose = false, quiet = false;
  auto* verbose_flag = app.add_flag("-v,--verbose", verbose, "Say more: every vector's verdict on a terminal, how a port was opened");
  app.add_flag("-q,--quiet", quiet, "Say less: only failures, errors and the summary")->excludes(verbose_flag);
  app.set_version_flag("--version", sabus::cli::version_text, "Print the version and the data directory, and exit");
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
  sabus::cli::g_verbosity = quiet     ? sabus::cli::Verbosity::kQuiet
                            : verbose ? sabus::cli::Verbosity::kVerbose
                                      : sabus::cli::Verbosity::kNormal;
  try {
    for (const auto& c : commands)
      if (c.app->parsed()) return c.run();
  } catch (const sabus::harness::DataDirNotFound& e) {
    // A command that needs the shipped vectors, profiles or errata, and none
    // were found: the same exit as a missing profile or vector file.
    std::cerr << "sabus: " << e.what() << "\n";
    return sabus::cli::kExitUsage;
  }
  return sabus::cli::kExitUsage;
}
