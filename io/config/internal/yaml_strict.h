// SPDX-License-Identifier: Apache-2.0
#pragma once
// Internal to io/: loading YAML files strictly (session.yaml, options, presets, truth.yaml).
// Beyond yaml-cpp's own checks: the file must be a regular file of at most
// WALLCAL_MAX_YAML_BYTES (io/input_file.h); no NUL byte; maps and lists nested at most
// kMaxYamlDepth levels; no key given twice in one map (yaml-cpp keeps the first, PyYAML the
// last: two tools would read different files). Every failure is an InputError "file:line: ...".

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <string>

namespace wallcal::io {

YAML::Node LoadYamlStrict(const std::string& file);

// 1-based line of a node (0 when unknown): yaml-cpp marks are 0-based.
inline int YamlLine(const YAML::Node& node) {
  return node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
}

// The line of "section.key" (or "section.list[2].key") under `root`, 0 when it is not in the
// file (a default value). The keys may also sit under one first-level section of `root`.
int LineOfKey(const YAML::Node& root, const std::string& dotted);

}  // namespace wallcal::io
