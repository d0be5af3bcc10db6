// What `treeskel batch` converts: the input files found from the command line's files, folders and
// patterns, the names their outputs get, and the share of them one shard of an array job takes.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace treeskel::cli {

struct BatchInput {
  std::filesystem::path path;  ///< the file to convert, as found
  std::filesystem::path name;  ///< its outputs' stem, relative to the output folder ("plot1/t3")
  std::string error;           ///< why it will not be converted (not found, a name taken), else empty
};

/// The inputs named by `arguments`, each file once, sorted by path (so that every shard of an array
/// job sees the same list):
/// - a file is taken whatever its extension (the converter refuses what it cannot read), named by
///   its stem;
/// - a folder is searched recursively for files whose lower-case extension is one of `extensions`
///   (hidden files and folders, and `skip`, are not searched), each named by its path below the
///   folder without the extension, so a folder tree of clouds gives the same tree of outputs; a file
///   there that does not look like a cloud (a LICENSE.txt: no line of three numbers near its start;
///   a .ply or .las without its format's first bytes; not an empty file) is passed over, and added to `passed_over`;
/// - an argument that is no file or folder but holds * ? or [ is a pattern (glob(3)), its matches
///   taken as above; one that matches nothing, or names nothing, is an input with an error.
/// Two inputs whose names clash (tree.xyz and tree.las) are named with their extension (tree_xyz,
/// tree_las); if that still clashes (the same stem in two folders given as files), the later ones
/// get an error that says which input holds the name.
std::vector<BatchInput> plan_inputs(const std::vector<std::string>& arguments, const std::vector<std::string>& extensions,
                                    const std::filesystem::path& skip = {},
                                    std::vector<std::filesystem::path>* passed_over = nullptr);

/// One shard of an array job: every `count`-th input, from the `index`-th (0-based).
struct Shard {
  std::size_t index = 0, count = 1;
};

/// Parses "I/N", 0 <= I < N. @throws OptionError naming what is wrong.
Shard parse_shard(const std::string& text);

/// The inputs of `shard`, in their order.
std::vector<BatchInput> take_shard(const std::vector<BatchInput>& inputs, const Shard& shard);

/// `text` as one CSV field (RFC 4180): quoted, with quotes doubled, when it holds a comma, a quote or
/// a line break.
std::string csv_field(const std::string& text);

}  // namespace treeskel::cli
