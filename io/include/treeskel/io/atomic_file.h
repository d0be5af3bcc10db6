/// @file atomic_file.h
/// Writing a file so that it either appears complete or not at all.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>

namespace treeskel::io {

/// Writes `target` through `body` into a temporary file beside it, flushes it to the disk (close and
/// fsync, so a full disk or a failing device is seen), then renames it over `target`. A `target` that is
/// a symbolic link stays one: the file it points to is replaced. If `body` throws or the disk refuses
/// the data, the temporary file is removed, `target` is left as it was, and treeskel::Error (or
/// `body`'s exception) is thrown.
void write_atomically(const std::filesystem::path& target, const std::function<void(std::ostream&)>& body);

/// Lower-case extension of `path` without the dot ("" if none).
std::string extension_of(const std::filesystem::path& path);

/// The whole content of a file. @throws InputError naming the file if it cannot be read.
std::string read_whole_file(const std::filesystem::path& path);

/// Every temporary file or folder treeskel makes starts with this prefix: ".treeskel-", a tag of this
/// machine, the process id and "-".
std::string temporary_prefix();

/// Removes the temporary files and folders in `dir` that runs on this machine left when they were
/// killed (SIGKILL, power loss): those whose process no longer exists or is a zombie (dead, not yet
/// reaped). Others' are not touched.
/// Returns how many were removed.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir);

/// The folder `path` is in ("." for a bare file name).
std::filesystem::path folder_of(const std::filesystem::path& path);

/// Where writing `target` really goes: the file a symbolic link points to, else `target`.
std::filesystem::path write_destination(const std::filesystem::path& target);

}  // namespace treeskel::io
