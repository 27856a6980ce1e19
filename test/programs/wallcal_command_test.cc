// SPDX-License-Identifier: Apache-2.0
// The one program and its subcommands: the command list, `help COMMAND` against
// `COMMAND --help`, --version, an unknown command, and the man page and bash completion the
// build writes from the same help tables (build/share/...).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test/support/program_runner.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;
using testing_support::ProgramRun;
using testing_support::RunWallcal;

const std::vector<std::string> kCommands = {"calibrate", "inspect", "simulate", "characterise"};

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The option names a help text lists ("  --output FILE ..." or "  -o, --output FILE ...").
std::vector<std::string> Options(const std::string& help) {
  std::vector<std::string> options;
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);) {
    const size_t at = line.find("--");
    if (line.rfind("  -", 0) != 0 || at == std::string::npos || at > 6) continue;
    const size_t end = line.find(' ', at);
    options.push_back(line.substr(at, end - at));
  }
  return options;
}

std::string RoffName(const std::string& option) {
  std::string out;
  for (char c : option) out += c == '-' ? std::string("\\-") : std::string(1, c);
  return out;
}

TEST(WallcalCommandTest, HelpListsEveryCommandOnOneLine) {
  const ProgramRun run = RunWallcal({"--help"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const std::string& command : kCommands) {
    EXPECT_NE(run.out.find("\n  " + command + " "), std::string::npos) << run.out;
  }
  EXPECT_EQ(RunWallcal({"help"}).out, run.out);
}

TEST(WallcalCommandTest, HelpCommandAndCommandHelpAgree) {
  for (const std::string& command : kCommands) {
    const ProgramRun help = RunWallcal({"help", command});
    const ProgramRun dashed = RunWallcal({command, "--help"});
    EXPECT_EQ(help.exit_code, 0) << command;
    EXPECT_EQ(dashed.exit_code, 0) << command;
    EXPECT_EQ(help.out, dashed.out) << command;
    EXPECT_EQ(help.out.rfind("usage: wallcal " + command + " ", 0), 0u) << help.out;
    EXPECT_NE(help.out.find("Exit status: "), std::string::npos) << help.out;
  }
}

TEST(WallcalCommandTest, VersionAndUnknownCommand) {
  const ProgramRun version = RunWallcal({"--version"});
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out.rfind("wallcal ", 0), 0u) << version.out;
  const ProgramRun unknown = RunWallcal({"calibrat"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("unknown command 'calibrat'"), std::string::npos) << unknown.err;
  for (const std::string& command : kCommands) {
    EXPECT_NE(unknown.err.find("  " + command + " "), std::string::npos) << unknown.err;
  }
  EXPECT_EQ(RunWallcal({}).exit_code, 2);
  EXPECT_EQ(RunWallcal({"help", "nope"}).exit_code, 2);
}

TEST(WallcalCommandTest, ManPageAndCompletionCarryEveryOption) {
  const fs::path share = fs::path(WALLCAL_BINARY_DIR) / "share";
  const std::string man = ReadText(share / "man" / "man1" / "wallcal.1");
  const std::string completion = ReadText(share / "bash-completion" / "completions" / "wallcal");
  ASSERT_FALSE(man.empty()) << "build the wallcal_docs target first";
  ASSERT_FALSE(completion.empty());
  EXPECT_EQ(man, RunWallcal({"--print-man"}).out);
  for (const std::string& command : kCommands) {
    EXPECT_NE(man.find(".SS \"wallcal " + command + "\""), std::string::npos) << command;
    EXPECT_NE(completion.find("    " + command + ")"), std::string::npos) << command;
    const std::vector<std::string> options = Options(RunWallcal({"help", command}).out);
    EXPECT_GE(options.size(), 3u) << command;
    for (const std::string& option : options) {
      EXPECT_NE(man.find(RoffName(option)), std::string::npos) << command << " " << option;
      EXPECT_NE(completion.find(option), std::string::npos) << command << " " << option;
    }
  }
}

// Runs the completion function as bash would for the words typed so far.
std::string Complete(const std::string& words) {
  const fs::path script =
      fs::path(WALLCAL_BINARY_DIR) / "share" / "bash-completion" / "completions" / "wallcal";
  const ProgramRun run = testing_support::RunProgram(
      {"bash", "-c",
       "source \"$0\"; COMP_WORDS=(" + words + "); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); "
       "_wallcal; echo \"${COMPREPLY[*]}\"",
       script.string()});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return run.out;
}

TEST(WallcalCommandTest, CompletionOffersCommandsOptionsAndValues) {
  EXPECT_EQ(Complete("wallcal ''"), "calibrate inspect guide simulate characterise help --help --version\n");
  EXPECT_EQ(Complete("wallcal calibrate s --emit ''"), "ros2-static-tf urdf json\n");
  EXPECT_EQ(Complete("wallcal calibrate s --me"), "--method\n");
  EXPECT_EQ(Complete("wallcal inspect x --dump s"), "scans survey\n");
  EXPECT_EQ(Complete("wallcal help ch"), "characterise\n");
}

}  // namespace
}  // namespace wallcal
