// Runs the treeskel tool (or any command) from the tests, capturing what it prints.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace treeskel::test {

struct Result {
  int code = -1;
  std::string out;  // stdout and stderr
};

/// Runs the shell `command` and captures what it writes on stdout.
inline Result capture(const std::string& command) {
  Result r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

#ifdef TREESKEL_EXE
/// Runs the tool with `args` (a shell word list) in `cwd`, capturing both streams; `before` is shell
/// text run first in the same shell (e.g. a ulimit).
inline Result run(const std::string& args, const std::string& cwd = ".", const std::string& before = "") {
  return capture("cd '" + cwd + "' && " + before + " '" TREESKEL_EXE "' " + args + " 2>&1");
}
#endif

inline std::string quoted(const std::string& s) { return "'" + s + "'"; }

}  // namespace treeskel::test
