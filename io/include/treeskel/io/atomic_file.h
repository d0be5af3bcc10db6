/// @file atomic_file.h
/// Writing a file so that it either appears complete or not at all.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>

namespace treeskel::io {

/// Writes `target` through `body` into a temporary file beside it, then renames it over `target`.
/// If `body` throws or the disk refuses the data, the temporary file is removed, `target` is left as it
/// was, and treeskel::Error (or `body`'s exception) is thrown.
void write_atomically(const std::filesystem::path& target, const std::function<void(std::ostream&)>& body);

/// Lower-case extension of `path` without the dot ("" if none).
std::string extension_of(const std::filesystem::path& path);

/// The whole content of a file. @throws InputError naming the file if it cannot be read.
std::string read_whole_file(const std::filesystem::path& path);

}  // namespace treeskel::io
