// The one PLY reader of treeskel: its header parser serves point clouds, skeletons and format sniffing,
// and its body walker reads ascii and binary (either endianness) bodies row by row.
//
// Every element count is checked against the bytes that follow the header before any row is read
// (a row needs at least one byte per property in binary, two characters per property in ascii), so a
// header cannot make a reader reserve or loop beyond what the file holds. Elements without properties
// take no bytes and are skipped whatever their count.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace treeskel::io::detail {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };
enum class PlyFormat { ascii, little, big };

std::size_t size_of(PlyType type);

/// True on a little-endian host (binary PLY files name their byte order).
bool host_is_little();

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::float32;
  bool list = false;
  PlyType count_type = PlyType::uint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;

  /// Index of the scalar property `name`, or -1.
  int find(std::string_view property) const;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  std::vector<std::string> comments;  ///< text after "comment ", in order
  std::size_t body = 0;               ///< byte where the body starts
  std::size_t header_lines = 0;

  /// The element called `name`, or nullptr.
  const PlyElement* find(std::string_view element) const;
};

/// True if `data` starts like a PLY file ("ply" and a line end).
bool looks_like_ply(std::string_view data);

/// Parses and checks the header of the PLY file `data` (see above).
/// @throws InputError naming `name` and the line.
PlyHeader parse_ply_header(std::string_view data, const std::string& name);

/// Called for each row of the elements a caller asked for: element index in the header, row index,
/// the row's scalar property values in header order (a list property's slot holds NaN).
using PlyRow = std::function<void(std::size_t element, std::uint64_t row, const double* values)>;

/// Walks the body of `data`: rows of the elements whose `wanted[e]` is true go to `row`, the others are
/// skipped (binary rows of fixed size in one step). Refuses data that ends early, a number that does
/// not parse, and bytes after the last element. @throws InputError naming `name` and the line or byte.
void read_ply_body(std::string_view data, const PlyHeader& header, const std::vector<bool>& wanted,
                   const PlyRow& row, const std::string& name);

}  // namespace treeskel::io::detail
