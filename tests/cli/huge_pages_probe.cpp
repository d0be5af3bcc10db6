// For huge_pages_test: restarts itself as the tool does (given the argument `model`, as `treeskel
// model` does), then prints GLIBC_TUNABLES as it is now, and whether a 20 MB block comes from the heap (the 32 MB mmap threshold took effect) or from a
// mapping of its own. (What the process started with cannot be read back: glibc rewrites the
// variable in place at start-up, and /proc/self/environ shows the rewritten text.)
#include "huge_pages.h"

#include <cstdio>
#include <cstdlib>

#include <unistd.h>

int main(int argc, char** argv) {
  treeskel::cli::restart_with_huge_pages(argv, treeskel::cli::memory_for(argc, argv));  // `probe model`: as a model
  const char* now = std::getenv("GLIBC_TUNABLES");
  void* block = std::malloc(20u << 20);
  const bool heap = static_cast<char*>(block) < static_cast<char*>(::sbrk(0));
  std::printf("now: %s\nmarker: %s\n20 MB from: %s\n", now ? now : "(unset)",
              std::getenv("TREESKEL_GLIBC_TUNABLES_BEFORE") ? "set" : "unset", heap ? "heap" : "a mapping");
  std::free(block);
  return 0;
}
