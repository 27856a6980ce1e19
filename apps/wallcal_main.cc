// SPDX-License-Identifier: Apache-2.0
// wallcal: one program, one subcommand per job (apps/commands.h). This file only dispatches:
// `wallcal COMMAND ARGS...` runs the command with argv[0] = COMMAND; `wallcal --help`,
// `wallcal help COMMAND` and `wallcal --version` answer here. The hidden `--print-man` and
// `--print-completion` write wallcal(1) and the bash completion from the same help tables (the
// build runs them; see apps/CMakeLists.txt).

#include <iostream>
#include <string>
#include <vector>

#include "apps/command_help.h"
#include "apps/commands.h"
#include "io/version.h"

namespace wallcal::apps {

const std::vector<Command>& Commands() {
  static const std::vector<Command> commands = {
      {&CalibrateHelp, &RunCalibrate},
      {&InspectHelp, &RunInspect},
      {&GuideHelp, &RunGuideCommand},
      {&SimulateHelp, &RunSimulate},
      {&CharacteriseHelp, &RunCharacterise},
  };
  return commands;
}

namespace {

std::vector<const CommandHelp*> Helps() {
  std::vector<const CommandHelp*> helps;
  for (const Command& c : Commands()) helps.push_back(&c.help());
  return helps;
}

const Command* Find(const std::string& name) {
  for (const Command& c : Commands()) {
    if (c.help().name == name) return &c;
  }
  return nullptr;
}

int Unknown(const std::string& name) {
  std::cerr << "wallcal: unknown command '" << name << "'\n\n" << FormatCommandList(Helps());
  return 2;
}

}  // namespace
}  // namespace wallcal::apps

int main(int argc, char** argv) {
  namespace apps = wallcal::apps;
  if (argc < 2) {
    std::cerr << "wallcal: no command given\n\n" << apps::FormatCommandList(apps::Helps());
    return 2;
  }
  const std::string first = argv[1];
  if (first == "--help" || first == "-h" || (first == "help" && argc == 2)) {
    std::cout << apps::FormatCommandList(apps::Helps());
    return 0;
  }
  if (first == "--version") {
    std::cout << "wallcal " << wallcal::io::kToolVersion << "\n";
    return 0;
  }
  if (first == "--print-man" && argc == 2) {
    std::cout << apps::FormatManPage(apps::Helps(), wallcal::io::kToolVersion);
    return 0;
  }
  if (first == "--print-completion" && argc == 2) {
    std::cout << apps::FormatBashCompletion(apps::Helps());
    return 0;
  }
  if (first == "help") {
    if (argc > 3) {
      std::cerr << "wallcal: help takes one COMMAND\n\n" << apps::FormatCommandList(apps::Helps());
      return 2;
    }
    const apps::Command* command = apps::Find(argv[2]);
    if (command == nullptr) return apps::Unknown(argv[2]);
    std::cout << apps::FormatHelp(command->help());
    return 0;
  }
  const apps::Command* command = apps::Find(first);
  if (command == nullptr) return apps::Unknown(first);
  return command->run(argc - 1, argv + 1);
}
