// Memory from the kernel in large pages, reused: for the command-line tool and the speed benchmarks.
#pragma once

#include <optional>
#include <string>

namespace treeskel::cli {

/// What the restart asks of glibc's allocator.
enum class Memory {
  /// Transparent huge pages (`glibc.malloc.hugetlb=1`) and memory kept for reuse (below): a
  /// skeleton's stages touch large arrays once each, and fault a 2 MB page where they faulted 512.
  huge_pages,
  /// Memory kept for reuse only. A tree model allocates and frees millions of small blocks (meshes,
  /// exact numbers); where the kernel compacts memory to find a huge page on a fault (transparent
  /// huge pages' `defrag` at `madvise`, Debian's default), that took 0.3-1.2 s of system time on the
  /// AdTree models measured in the README, and `treeskel model` ran up to 7% slower than without it.
  reuse_only,
};

/// The memory `treeskel` asks for with these arguments: `reuse_only` for the command `model`
/// (the first argument that is not an option, past `--threads N`), `huge_pages` for the others.
Memory memory_for(int argc, const char* const* argv);

/// The GLIBC_TUNABLES a restart sets, from what the user set (`user`, empty if unset): theirs
/// followed by `glibc.malloc.mmap_threshold` at 32 MB and `glibc.malloc.trim_threshold` at 1 GB
/// (the memory a stage frees is kept for the next one instead of handed back to the kernel and asked
/// for again), and `glibc.malloc.hugetlb=1` for `Memory::huge_pages`; a tunable the user set keeps
/// their value. Nothing (no restart) when the user set `glibc.malloc.hugetlb`, or when huge pages
/// are asked for and the kernel has them off (`huge_pages_on` false).
std::optional<std::string> tunables_for(const std::string& user, Memory memory, bool huge_pages_on);

/// glibc (2.35 and later) reads its tunables when a process starts only, so this starts the program
/// again, once, with GLIBC_TUNABLES as `tunables_for` makes it. A million-point skeleton then takes
/// about 2,000 page faults instead of 37,000, and the whole command runs about 40% faster (see the
/// README's Speed section). The restarted process puts the variable back as it was, so that the
/// programs it runs (Chromium, the processes of a batch) start with the user's environment. It does
/// nothing when TREESKEL_NO_HUGE_PAGES is set, when `tunables_for` gives nothing, or on another C
/// library; if the restart fails the program goes on as it is.
void restart_with_huge_pages(char** argv, Memory memory = Memory::huge_pages);

}  // namespace treeskel::cli
