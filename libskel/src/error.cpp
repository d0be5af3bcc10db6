#include "treeskel/error.h"

namespace treeskel::detail {

void fail_precondition(const char* file, int line, const std::string& message) {
  throw Error(message + " (" + file + ":" + std::to_string(line) + ")");
}

}  // namespace treeskel::detail
