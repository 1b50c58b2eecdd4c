// popcut's command table: each command group's add/run pair, the unknown-command message, parsing and dispatch.
#include "cli/commands.h"

#include <CLI/CLI.hpp>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli/client.h"
#include "cli/common.h"
#include "cli/devices.h"
#include "cli/fold.h"
#include "cli/import.h"
#include "cli/import_pattern.h"
#include "cli/pattern.h"
#include "cli/sim_plotter.h"
#include "cli/calibrate.h"
#include "cli/cut.h"
#include "cli/test_cut.h"

namespace popcut::cli {
namespace {

// The parsed options of every group; only the chosen subcommand's are read.
struct CommandStates {
  PatternCommands pattern;
  FoldCommands fold;
  ImportCommand import;
  ImportPatternCommand import_pattern;
  CutCommands cut;
  TestCutCommand test_cut;
  CalibrateCommand calibrate;
  ClientCommands client;
  DevicesCommand devices;
  SimPlotterCommand sim_plotter;
};

// A group of subcommands sharing one options struct, and the pair that adds and runs them.
// Each subcommand's name and --help line are set by `add`, in the group's file cli/NAME.cpp.
struct CommandGroup {
  void (*add)(CLI::App& app, CommandStates& states);
  std::optional<int> (*run)(const CommandStates& states);  // nullopt: none of the group's subcommands was chosen
  std::string_view unlisted = "";                          // a subcommand the unknown-command message does not name
};

// A row for the group whose options live in CommandStates::*member.
template <auto member, auto add_group, auto run_group>
constexpr CommandGroup group(std::string_view unlisted = "") {
  return {[](CLI::App& app, CommandStates& s) { add_group(app, s.*member); },
          [](const CommandStates& s) { return run_group(s.*member); }, unlisted};
}

// In the order popcut --help lists the subcommands.
const CommandGroup kCommandGroups[] = {
    group<&CommandStates::pattern, add_pattern_commands, run_pattern_commands>(),  // pattern, validate, repair
    group<&CommandStates::fold, add_fold_commands, run_fold_commands>(),           // fold, render
    group<&CommandStates::import, add_import_command, run_import_command>(),       // import
    group<&CommandStates::import_pattern, add_import_pattern_command, run_import_pattern_command>(),  // import-pattern
    group<&CommandStates::cut, add_cut_commands, run_cut_commands>(),                                 // plan, cut
    group<&CommandStates::test_cut, add_test_cut_command, run_test_cut_command>(),                    // test-cut
    group<&CommandStates::calibrate, add_calibrate_command, run_calibrate_command>(),                 // calibrate
    group<&CommandStates::client, add_client_commands, run_client_commands>(
        "resume"),  // submit, jobs, move, cancel, resume, sheet
    group<&CommandStates::devices, add_devices_command, run_devices_command>(),              // devices
    group<&CommandStates::sim_plotter, add_sim_plotter_command, run_sim_plotter_command>(),  // sim-plotter
};

// "pattern, validate, ... devices or sim-plotter": the subcommands each group added, in order.
std::string expected_commands(CLI::App& app) {
  const std::vector<CLI::App*> listed = app.get_subcommands([](CLI::App* sub) {
    for (const CommandGroup& g : kCommandGroups) {
      if (sub->get_name() == g.unlisted) return false;
    }
    return true;
  });
  std::string out;
  for (std::size_t i = 0; i < listed.size(); ++i) {
    if (i > 0) out += i + 1 == listed.size() ? " or " : ", ";
    out += listed[i]->get_name();
  }
  return out;
}

bool is_subcommand(CLI::App& app, const std::string& word) {
  return !app.get_subcommands([&](CLI::App* sub) { return sub->get_name() == word; }).empty();
}

// Parses the command line into the groups' states; an exit code when popcut is done already (help,
// version, a usage error), nullopt when a subcommand is to run.
std::optional<int> parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const auto used = app.get_subcommands();
    std::cerr << "popcut: error: " << e.what() << "\nRun 'popcut "
              << (used.empty() ? "" : used.front()->get_name() + " ") << "--help' for usage.\n";
    return kBadInput;
  }
  return std::nullopt;
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{
      "popcut — design origamic-architecture pop-up cards and cut them on a plotter.\n"
      "Exit codes: 0 ok, 1 card does not pop up, 2 bad input or usage, 3 cannot write output (or reach the cutter), 4 "
      "internal error."};
  app.set_version_flag("--version", std::string("popcut ") + POPCUT_VERSION);
  app.require_subcommand(1);
  CommandStates states;
  for (const CommandGroup& g : kCommandGroups) g.add(app, states);

  // A first word that is no subcommand is named as such, not reported as "subcommand required".
  if (argc > 1 && argv[1][0] != '-' && !is_subcommand(app, argv[1])) {
    std::cerr << "popcut: error: unknown command '" << argv[1] << "' (expected " << expected_commands(app) << ")\n"
              << "Run 'popcut --help' for usage.\n";
    return kBadInput;
  }
  if (const std::optional<int> rc = parse(app, argc, argv)) return *rc;
  for (const CommandGroup& g : kCommandGroups) {
    if (const std::optional<int> rc = g.run(states)) return *rc;
  }
  return kBadInput;
}

}  // namespace popcut::cli
