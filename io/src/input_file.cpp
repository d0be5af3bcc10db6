#include "input_file.h"

#include "treeskel/error.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace treeskel::io::detail {

namespace {

/// Closes a descriptor when it goes out of scope.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

InputFile::InputFile(const std::filesystem::path& path) : name_(path.string()) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(name_ + ": no such file");
  if (std::filesystem::is_directory(path, ec)) throw InputError(name_ + ": is a directory, not a file");
  const Descriptor file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) throw InputError(name_ + ": cannot open for reading: " + std::strerror(errno));
  struct stat info {};
  if (::fstat(file.fd, &info) != 0) throw InputError(name_ + ": cannot read: " + std::strerror(errno));
  if (S_ISREG(info.st_mode)) {
    if (info.st_size == 0) return;
    map_size_ = static_cast<std::size_t>(info.st_size);
    map_ = ::mmap(nullptr, map_size_, PROT_READ, MAP_PRIVATE | MAP_POPULATE, file.fd, 0);  // every page is read: map them at once
    if (map_ == MAP_FAILED) {
      map_ = nullptr;
      throw InputError(name_ + ": cannot read: " + std::strerror(errno));
    }
    ::madvise(map_, map_size_, MADV_SEQUENTIAL);
    view_ = std::string_view(static_cast<const char*>(map_), map_size_);
    return;
  }
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(file.fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(name_ + ": read failed: " + std::strerror(errno));
    if (n == 0) break;
    owned_.append(buffer, static_cast<std::size_t>(n));
  }
  view_ = owned_;
}

InputFile::~InputFile() {
  if (map_) ::munmap(map_, map_size_);
}

}  // namespace treeskel::io::detail
