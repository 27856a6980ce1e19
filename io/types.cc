#include "io/types.h"

namespace wallcal::io {

std::string Where(const std::string& file, int line, const std::string& message) {
  std::string text = file;
  if (line > 0) text += ":" + std::to_string(line);
  text += ": ";
  text += message;
  return text;
}

}  // namespace wallcal::io
