// SPDX-License-Identifier: Apache-2.0
#include "io/config/internal/yaml_strict.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <optional>

#include "io/input_file.h"
#include "io/types.h"

namespace wallcal::io {
namespace {

int LineOf(const YAML::Node& node) { return YamlLine(node); }

// 1-based line of byte `offset` in `text`.
int LineAt(const std::string& text, size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(
                                                                std::min(offset, text.size())),
                                         '\n'));
}

// The first line where flow collections ([ {) nest deeper than kMaxYamlDepth, or 0. Quotes and
// comments are skipped roughly: this only finds the place to name in a message.
int FirstTooDeepLine(const std::string& text) {
  int depth = 0;
  char quote = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quote != 0) {
      if (c == quote || c == '\n') quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxYamlDepth) return LineAt(text, i);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return 0;
}

// Rejects what yaml-cpp accepts but a careful reader must not: a key given twice in one map
// (yaml-cpp keeps the first, PyYAML the last: two tools would read different files) and nesting
// deeper than kMaxYamlDepth.
// Aliases are expanded by the walk: a "billion laughs" file of nested aliases would take
// forever, so the walk stops after this many values (our files hold a few hundred).
constexpr int64_t kMaxYamlValues = 1000000;

void CheckYamlTree(const YAML::Node& node, const std::string& file, int depth, int64_t* values) {
  if (++*values > kMaxYamlValues) {
    throw InputError(Where(file, LineOf(node),
                           "more than " + std::to_string(kMaxYamlValues) +
                               " values once aliases are expanded; expected the keys of "
                               "docs/session-format.md"));
  }
  if (depth > kMaxYamlDepth) {
    throw InputError(Where(file, LineOf(node),
                           "maps and lists nested more than " + std::to_string(kMaxYamlDepth) +
                               " levels deep; expected the keys of docs/session-format.md"));
  }
  if (node.IsSequence()) {
    for (const YAML::Node& item : node) CheckYamlTree(item, file, depth + 1, values);
  } else if (node.IsMap()) {
    std::map<std::string, int> lines;
    for (auto it = node.begin(); it != node.end(); ++it) {
      if (it->first.IsScalar()) {
        const auto [seen, inserted] = lines.emplace(it->first.Scalar(), LineOf(it->first));
        if (!inserted) {
          throw InputError(Where(file, LineOf(it->first),
                                 "key '" + EscapeControl(it->first.Scalar()) +
                                     "' given twice in the same map (first at line " +
                                     std::to_string(seen->second) +
                                     "); expected each key once"));
        }
      } else {
        CheckYamlTree(it->first, file, depth + 1, values);
      }
      CheckYamlTree(it->second, file, depth + 1, values);
    }
  }
}

}  // namespace

YAML::Node LoadYamlStrict(const std::string& file) {
  // A folder, a FIFO or a device is refused before it is read; the size is bounded
  // (io/input_file.h, WALLCAL_MAX_YAML_BYTES).
  const std::string text =
      ReadInputFile(file, "the YAML file", CurrentInputLimits().max_yaml_bytes);
  if (const size_t nul = text.find('\0'); nul != std::string::npos) {
    throw InputError(Where(file, LineAt(text, nul), "a NUL byte; expected YAML text"));
  }
  if (const int line = FirstTooDeepLine(text); line > 0) {
    throw InputError(Where(file, line,
                           "maps and lists nested more than " + std::to_string(kMaxYamlDepth) +
                               " levels deep; expected the keys of docs/session-format.md"));
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    throw InputError(Where(file, e.mark.line >= 0 ? e.mark.line + 1 : 0,
                           "maps and lists nested more than " + std::to_string(e.depth()) +
                               " levels deep; expected the keys of docs/session-format.md"));
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(file, e.mark.line >= 0 ? e.mark.line + 1 : 0,
                           "YAML syntax error: " + EscapeControl(e.msg)));
  } catch (const YAML::Exception& e) {
    throw InputError(Where(file, 0, std::string("cannot read YAML: ") + EscapeControl(e.what())));
  }
  int64_t values = 0;
  CheckYamlTree(root, file, 0, &values);
  return root;
}


// The line of "section.key" (or "section.list[2].key") in the file, 0 when it is not there (a
// default value). `root` may hold the keys at its top or under a first-level section.
int LineOfKey(const YAML::Node& root, const std::string& dotted) {
  for (const bool drop_first : {false, true}) {
    YAML::Node node = root;
    size_t start = 0;
    bool first = true;
    bool found = true;
    while (start <= dotted.size() && found) {
      size_t end = dotted.find('.', start);
      if (end == std::string::npos) end = dotted.size();
      std::string part = dotted.substr(start, end - start);
      start = end + 1;
      if (first && drop_first) {
        first = false;
        continue;
      }
      first = false;
      std::optional<size_t> index;
      if (const size_t bracket = part.find('['); bracket != std::string::npos) {
        index = static_cast<size_t>(std::atoi(part.c_str() + bracket + 1));
        part = part.substr(0, bracket);
      }
      found = false;
      if (!node.IsMap()) break;
      for (auto it = node.begin(); it != node.end(); ++it) {
        if (it->first.IsScalar() && it->first.Scalar() == part) {
          node = it->second;
          found = true;
          break;
        }
      }
      if (found && index) {
        found = node.IsSequence() && *index < node.size();
        if (found) node = node[*index];
      }
      if (start > dotted.size() && found) return LineOf(node);
    }
  }
  return 0;
}

}  // namespace wallcal::io
