// SPDX-License-Identifier: Apache-2.0
#include "apps/command_help.h"

#include <algorithm>
#include <cstddef>
#include <sstream>

#include "io/types.h"
#include "io/version.h"

namespace wallcal::apps {
namespace {

constexpr size_t kWidth = 96;  // the help text's right margin (the tables are written to it)

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

// Splits a synopsis into words, keeping "[--output FILE]" together.
std::vector<std::string> SynopsisWords(const std::string& synopsis) {
  std::vector<std::string> words;
  std::string word;
  int depth = 0;
  for (char c : synopsis) {
    if (c == '[') ++depth;
    if (c == ']') --depth;
    if (c == ' ' && depth == 0) {
      if (!word.empty()) words.push_back(word);
      word.clear();
    } else {
      word += c;
    }
  }
  if (!word.empty()) words.push_back(word);
  return words;
}

std::string WrapSynopsis(const std::string& prefix, const std::string& synopsis) {
  std::string out = prefix, line = prefix;
  const std::string indent(prefix.size(), ' ');
  bool first = true;
  for (const std::string& word : SynopsisWords(synopsis)) {
    if (!first && line.size() + 1 + word.size() > kWidth) {
      out += "\n" + indent;
      line = indent;
      first = true;
    }
    if (!first) {
      out += " ";
      line += " ";
    }
    out += word;
    line += word;
    first = false;
  }
  return out + "\n";
}

std::string Label(const ArgumentHelp& a) {
  std::string label = a.alias.empty() ? a.name : a.alias + ", " + a.name;
  if (!a.value.empty()) label += " " + a.value;
  return label;
}

// --- man(7) ---

// Escapes one line of text for roff: backslashes, a leading control character, and the hyphen
// of an option name ("--output") as a minus sign so that it can be searched and copied.
std::string Roff(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\\') {
      out += "\\e";
    } else if (c == '-' && (i == 0 || std::string(" -[(|,'`/=").find(text[i - 1]) != std::string::npos)) {
      out += "\\-";
    } else {
      out += c;
    }
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
  return out;
}

// An option's name or alias: every hyphen a minus sign.
std::string RoffOption(const std::string& name) {
  std::string out;
  for (char c : name) out += c == '-' ? std::string("\\-") : std::string(1, c);
  return out;
}

// Text with blank lines between paragraphs; indented lines (small tables) are kept unfilled.
std::string RoffText(const std::string& text) {
  std::string out;
  bool in_table = false;
  for (const std::string& line : Lines(text)) {
    const bool table_line = !line.empty() && line[0] == ' ';
    if (table_line && !in_table) out += ".nf\n";
    if (!table_line && in_table) out += ".fi\n";
    in_table = table_line;
    out += line.empty() ? ".PP\n" : Roff(line) + "\n";
  }
  if (in_table) out += ".fi\n";
  return out;
}

std::string Words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

}  // namespace

std::string FormatHelp(const CommandHelp& command) {
  std::string out;
  for (size_t i = 0; i < command.synopsis.size(); ++i) {
    const std::string prefix = (i == 0 ? "usage: " : "       ") + std::string("wallcal ") +
                               command.name + " ";
    out += WrapSynopsis(prefix, command.synopsis[i]);
  }
  out += "\n" + command.description;
  if (command.description.empty() || command.description.back() != '\n') out += "\n";
  out += "\n";
  size_t label_width = 0;
  for (const ArgumentHelp& a : command.arguments) label_width = std::max(label_width, Label(a).size());
  const std::string indent(2 + label_width + 2, ' ');
  for (const ArgumentHelp& a : command.arguments) {
    const std::string label = Label(a);
    const std::vector<std::string> lines = Lines(a.help);
    out += "  " + label + std::string(label_width + 2 - label.size(), ' ');
    out += (lines.empty() ? "" : lines[0]) + "\n";
    for (size_t i = 1; i < lines.size(); ++i) out += indent + lines[i] + "\n";
  }
  if (!command.notes.empty()) {
    out += "\n" + command.notes;
    if (command.notes.back() != '\n') out += "\n";
  }
  out += "\nExit status: " + command.exit_status;
  if (command.exit_status.empty() || command.exit_status.back() != '\n') out += "\n";
  return out;
}

std::string FormatCommandList(const std::vector<const CommandHelp*>& commands) {
  std::string out =
      "usage: wallcal COMMAND [ARGS...]\n"
      "       wallcal help COMMAND | wallcal COMMAND --help | wallcal --version\n"
      "\n"
      "Calibrates a 2-D laser scanner's mount against a surveyed wall.\n"
      "\n"
      "Commands:\n";
  size_t width = 0;
  for (const CommandHelp* c : commands) width = std::max(width, c->name.size());
  for (const CommandHelp* c : commands) {
    out += "  " + c->name + std::string(width + 3 - c->name.size(), ' ') + c->summary + "\n";
  }
  out += "\nRun 'wallcal help COMMAND' for a command's options (man wallcal: all of them).\n";
  return out;
}

std::string FormatManPage(const std::vector<const CommandHelp*>& commands,
                          const std::string& version) {
  std::string out;
  out += ".\\\" Generated by 'wallcal --print-man' from the help tables in apps/; do not edit.\n";
  out += ".TH WALLCAL 1 \"\" \"wallcal " + version + "\" \"User Commands\"\n";
  out += ".SH NAME\nwallcal \\- calibrate a 2\\-D laser scanner's mount against a surveyed wall\n";
  out += ".SH SYNOPSIS\n.nf\n\\fBwallcal\\fR \\fICOMMAND\\fR [\\fIARGS\\fR...]\n";
  out += "\\fBwallcal help\\fR \\fICOMMAND\\fR\n\\fBwallcal\\fR \\fICOMMAND\\fR \\fB\\-\\-help\\fR\n";
  out += "\\fBwallcal \\-\\-help\\fR\n\\fBwallcal \\-\\-version\\fR\n.fi\n";
  out += ".SH DESCRIPTION\n";
  out += "\\fBwallcal\\fR estimates where a 2\\-D laser scanner sits on a vehicle (x, y and yaw in the\n"
         "GNSS antenna's frame) from a session logged in front of a surveyed wall, checks such a\n"
         "session before the crew leaves the site, simulates sessions with a known truth, and\n"
         "measures the scanner itself. Each job is a command:\n";
  for (const CommandHelp* c : commands) {
    out += ".TP\n.B " + c->name + "\n" + Roff(c->summary) + "\n";
  }
  out += ".SH COMMANDS\n";
  for (const CommandHelp* c : commands) {
    out += ".SS \"wallcal " + c->name + "\"\n";
    for (size_t i = 0; i < c->synopsis.size(); ++i) {
      out += std::string(i == 0 ? "" : ".br\n") + "\\fBwallcal " + c->name + "\\fR " +
             Roff(c->synopsis[i]) + "\n";
    }
    out += ".PP\n" + RoffText(c->description);
    for (const ArgumentHelp& a : c->arguments) {
      out += ".TP\n";
      std::string label = a.positional() ? "\\fI" + a.name + "\\fR"
                                         : "\\fB" + RoffOption(a.name) + "\\fR";
      if (!a.alias.empty()) label = "\\fB" + RoffOption(a.alias) + "\\fR, " + label;
      if (!a.value.empty()) label += " \\fI" + Roff(a.value) + "\\fR";
      out += label + "\n" + RoffText(a.help);
    }
    if (!c->notes.empty()) out += ".PP\n" + RoffText(c->notes);
    out += ".PP\nExit status: " + RoffText(c->exit_status);
  }
  out += ".SH EXIT STATUS\n"
         "0 success; 1 the data cannot give the result (the reason is printed); 2 bad input or\n"
         "usage (one line on stderr names the file, the line and what was expected); 3 an\n"
         "internal error (a bug). Each command's section above gives its own meanings.\n";
  out += ".SH ENVIRONMENT\n.TP\n.B WALLCAL_CONFIG_DIR\n"
         "where the shipped scanner presets and default configs are, instead of\n"
         ".IR /usr/share/wallcal .\n";
  out += ".SH FILES\n.TP\n.I /usr/share/wallcal/\n"
         "the default configs (calibrate.yaml), scanner presets (scanners/) and simulation\n"
         "examples (simulate/).\n";
  out += ".SH \"SEE ALSO\"\nThe field guide, the session format and the method, in\n"
         ".IR /usr/share/doc/wallcal/ .\n";
  return out;
}

std::string FormatBashCompletion(const std::vector<const CommandHelp*>& commands) {
  std::vector<std::string> names;
  for (const CommandHelp* c : commands) names.push_back(c->name);
  std::string out;
  out += "# bash completion for wallcal(1): subcommands, options and option values.\n";
  out += "# Generated by 'wallcal --print-completion' from the help tables in apps/; do not edit.\n";
  out += "_wallcal() {\n";
  out += "  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}\n";
  out += "  COMPREPLY=()\n";
  out += "  if [[ $COMP_CWORD -eq 1 ]]; then\n";
  out += "    COMPREPLY=($(compgen -W \"" + Words(names) + " help --help --version\" -- \"$cur\"))\n";
  out += "    return\n  fi\n";
  out += "  case ${COMP_WORDS[1]} in\n";
  out += "    help)\n";
  out += "      [[ $COMP_CWORD -eq 2 ]] && COMPREPLY=($(compgen -W \"" + Words(names) +
         "\" -- \"$cur\"))\n      ;;\n";
  for (const CommandHelp* c : commands) {
    out += "    " + c->name + ")\n      case $prev in\n";
    std::vector<std::string> options = {"--help", "--version"};
    std::string positional = "-f";
    for (const ArgumentHelp& a : c->arguments) {
      if (a.positional()) {
        if (a.kind == ValueKind::kFolder) positional = "-d";
        continue;
      }
      if (std::find(options.begin(), options.end(), a.name) == options.end()) {
        options.push_back(a.name);
      }
      std::string names_here = a.name;
      if (!a.alias.empty()) names_here = a.alias + "|" + a.name;
      switch (a.kind) {
        case ValueKind::kNone:
          break;
        case ValueKind::kChoice:
          out += "        " + names_here + ") COMPREPLY=($(compgen -W \"" + Words(a.choices) +
                 "\" -- \"$cur\")); return ;;\n";
          break;
        case ValueKind::kFile:
        case ValueKind::kPath:
          out += "        " + names_here +
                 ") compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- \"$cur\")); "
                 "return ;;\n";
          break;
        case ValueKind::kFolder:
          out += "        " + names_here +
                 ") compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- \"$cur\")); "
                 "return ;;\n";
          break;
        case ValueKind::kWord:
          out += "        " + names_here + ") return ;;\n";
          break;
      }
    }
    out += "      esac\n";
    out += "      if [[ $cur == -* ]]; then\n";
    out += "        COMPREPLY=($(compgen -W \"" + Words(options) + "\" -- \"$cur\"))\n";
    out += "      else\n";
    out += "        compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen " + positional +
           " -- \"$cur\"))\n";
    out += "      fi\n      ;;\n";
  }
  out += "  esac\n}\ncomplete -F _wallcal wallcal\n";
  return out;
}

ArgumentHelp SessionArgument() {
  return {"SESSION", "", "", ValueKind::kPath, {},
          "a session.yaml, or the folder holding one (format: docs/session-format.md)"};
}

ArgumentHelp CalibrationConfigOption() {
  return {"--config", "", "FILE", ValueKind::kFile, {},
          "calibration options (YAML; defaults: configs/calibrate.yaml)"};
}

ArgumentHelp HelpOption() { return {"--help", "-h", "", ValueKind::kNone, {}, "this text"}; }

ArgumentHelp VersionOption() {
  return {"--version", "", "", ValueKind::kNone, {}, "the tool version"};
}

bool PrintHelpOrVersion(const std::string& arg, const CommandHelp& command, std::ostream& out) {
  if (arg == "--help" || arg == "-h") {
    out << FormatHelp(command);
  } else if (arg == "--version") {
    out << "wallcal " << command.name << " " << io::kToolVersion << "\n";
  } else {
    return false;
  }
  return true;
}

int ExitStatusOf(const CommandHelp& command, const std::function<int()>& work,
                 std::ostream& err) {
  try {
    return work();
  } catch (const io::InputError& error) {
    err << command.name << ": " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    err << command.name << ": internal error: " << error.what() << "\n";
    return 3;
  }
}

int UsageError(const CommandHelp& command, const std::string& message, std::ostream& err) {
  err << command.name << ": " << message << "\n(run 'wallcal " << command.name
      << " --help' for usage)\n";
  return 2;
}

}  // namespace wallcal::apps
