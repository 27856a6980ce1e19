// SPDX-License-Identifier: Apache-2.0
#pragma once
// The subcommands of `wallcal`: each a help table (apps/command_help.h) and a Run function.
// Run takes the arguments after `wallcal`: argv[0] is the subcommand's name, then its own
// arguments; it returns the exit status and is the one place in the command that catches
// io::InputError (exit 2) and any other exception (exit 3, an internal error): through
// ExitStatusOf (apps/command_help.h), or, in calibrate, itself (it closes its progress line
// first).

#include <vector>

#include "apps/command_help.h"

namespace wallcal::apps {

const CommandHelp& CalibrateHelp();
int RunCalibrate(int argc, char** argv);

const CommandHelp& InspectHelp();
int RunInspect(int argc, char** argv);

const CommandHelp& SimulateHelp();
int RunSimulate(int argc, char** argv);

const CommandHelp& CharacteriseHelp();
int RunCharacterise(int argc, char** argv);

const CommandHelp& GuideHelp();
int RunGuideCommand(int argc, char** argv);

struct Command {
  const CommandHelp& (*help)();
  int (*run)(int argc, char** argv);
};

// Every subcommand, in the order `wallcal --help` lists them.
const std::vector<Command>& Commands();

}  // namespace wallcal::apps
