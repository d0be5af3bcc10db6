// A file opened for reading as one span of bytes without copying it: regular files are mapped into
// memory (the kernel pages them in as the readers walk forward and may drop them again, so a reader's
// own memory is what it builds, not the file), other files (pipes, devices) are read whole. The readers
// check the first bytes (magic, header) before they touch the rest, so a huge file of the wrong kind is
// refused at once.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace treeskel::io::detail {

class InputFile {
 public:
  /// @throws InputError naming the file if it is missing, a directory or unreadable.
  explicit InputFile(const std::filesystem::path& path);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  std::string_view bytes() const { return view_; }
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  std::string owned_;  ///< the content of a file that cannot be mapped
  void* map_ = nullptr;
  std::size_t map_size_ = 0;
  std::string_view view_;
};

}  // namespace treeskel::io::detail
