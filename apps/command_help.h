// SPDX-License-Identifier: Apache-2.0
#pragma once
// The help of each wallcal subcommand as data. `wallcal COMMAND --help`, `wallcal help COMMAND`,
// the man page wallcal(1) and the bash completion are all rendered from these tables (the man
// page and the completion at build time, by `wallcal --print-man` and
// `wallcal --print-completion`), so they cannot disagree.

#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace wallcal::apps {

// What completes an argument's value.
enum class ValueKind {
  kNone,    // a flag: takes no value
  kFile,    // a file name
  kFolder,  // a folder name
  kPath,    // a file or a folder
  kWord,    // free text (a number, a frame name, a topic): nothing is offered
  kChoice,  // one of `choices`
};

// One argument: a positional (name in capitals, e.g. "SESSION") or an option ("--output").
struct ArgumentHelp {
  std::string name;                  // "--output", or "SESSION" for a positional
  std::string alias;                 // "-o", or empty
  std::string value;                 // what follows the option in the help ("FILE"), or empty
  ValueKind kind = ValueKind::kNone; // for a positional: what it completes as
  std::vector<std::string> choices;  // the values of a kChoice option, as typed
  // Lines as printed, separated by '\n' (the renderer aligns them); a line starting with a
  // space is part of a small table and kept as is in the man page.
  std::string help;
  bool positional() const { return !name.empty() && name[0] != '-'; }
};

// One subcommand's help.
struct CommandHelp {
  std::string name;                   // "calibrate"
  std::string summary;                // one line for `wallcal --help` and the man page
  std::vector<std::string> synopsis;  // each form after "wallcal NAME ", wrapped by the renderer
  std::string description;            // paragraphs ('\n' between lines, blank line between)
  std::vector<ArgumentHelp> arguments;  // positionals first, then options
  std::string notes;                  // paragraphs after the options, or empty
  std::string exit_status;            // the text after "Exit status: "
};

// Rows several commands share, one text each.
ArgumentHelp SessionArgument();        // SESSION: a session.yaml or its folder
ArgumentHelp CalibrationConfigOption();  // --config FILE: configs/calibrate.yaml's keys
ArgumentHelp HelpOption();             // --help, -h
ArgumentHelp VersionOption();          // --version

// What every command does with --help (or -h) and --version: prints its help, or
// "wallcal NAME VERSION", on `out` and returns true (the command then exits 0); false for any
// other argument.
bool PrintHelpOrVersion(const std::string& arg, const CommandHelp& command, std::ostream& out);

// A bad command line: "NAME: message" and where to find the usage on `err`. Returns 2, the
// exit status of bad usage.
int UsageError(const CommandHelp& command, const std::string& message,
               std::ostream& err = std::cerr);

// Runs a command's work and returns its exit status. The one place a command catches: an
// io::InputError prints "NAME: message" on `err` (bad input: exit 2), any other exception
// "NAME: internal error: message" (a bug: exit 3).
int ExitStatusOf(const CommandHelp& command, const std::function<int()>& work,
                 std::ostream& err = std::cerr);

// `wallcal COMMAND --help`: usage, description, arguments, notes and exit status.
std::string FormatHelp(const CommandHelp& command);

// `wallcal --help`: the usage line and the subcommands with their summaries, one a line.
std::string FormatCommandList(const std::vector<const CommandHelp*>& commands);

// wallcal(1) in man(7) markup: every subcommand with its synopsis, options and exit status.
std::string FormatManPage(const std::vector<const CommandHelp*>& commands,
                          const std::string& version);

// A bash completion script for subcommands, their options and the values of choice options.
std::string FormatBashCompletion(const std::vector<const CommandHelp*>& commands);

}  // namespace wallcal::apps
