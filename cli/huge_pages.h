// Memory from the kernel in large pages, reused: for the command-line tool and the speed benchmark.
#pragma once

namespace treeskel::cli {

/// glibc (2.35 and later) backs its allocations with transparent huge pages when its tunable
/// `glibc.malloc.hugetlb` is 1; with `glibc.malloc.mmap_threshold` at 32 MB and
/// `glibc.malloc.trim_threshold` at 1 GB it keeps the memory a stage frees for the next one
/// instead of handing it back to the kernel and asking again. A million-point skeleton then takes
/// about 2,000 page faults instead of 37,000, and the whole command runs about 40% faster (see the
/// README's Speed section). Tunables are read when a process starts only, so this starts the
/// program again, once, with these added to GLIBC_TUNABLES (those the user set there are kept);
/// the restarted process puts the variable back as it was, so that the programs it runs (Chromium,
/// the processes of a batch) start with the user's environment. It does nothing when the user set
/// `glibc.malloc.hugetlb`, when TREESKEL_NO_HUGE_PAGES is set, when the kernel has transparent huge
/// pages off, or on another C library; if the restart fails the program goes on as it is.
void restart_with_huge_pages(char** argv);

}  // namespace treeskel::cli
