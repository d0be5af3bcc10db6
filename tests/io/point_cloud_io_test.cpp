#include "treeskel/io/point_cloud_io.h"

#include "support/synthetic.h"
#include "treeskel/error.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace treeskel {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

/// Writes `content` to `name` in `dir` and returns its path.
std::string written(const TempDir& dir, const std::string& name, const std::string& content) {
  const std::string p = dir.path(name);
  write_text(p, content);
  return p;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Expects read_point_cloud to throw an InputError whose message contains every fragment.
void expect_error(const std::string& path, std::initializer_list<std::string> fragments) {
  try {
    io::read_point_cloud(path);
    ADD_FAILURE() << path << ": no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    for (const auto& f : fragments) EXPECT_NE(m.find(f), std::string::npos) << "'" << f << "' not in: " << m;
  }
}

PointCloud random_cloud(bool utm, bool normals, bool colors) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 20.0);
  PointCloud c;
  for (int i = 0; i < 300; ++i) {
    c.positions.emplace_back(u(rng), u(rng), u(rng));
    if (normals) c.normals.emplace_back(Eigen::Vector3f::Random().normalized());
    if (colors) c.colors.push_back({std::uint8_t(i % 256), std::uint8_t(i * 7 % 256), std::uint8_t(i * 13 % 256)});
  }
  if (utm) c.offset = Eigen::Vector3d(312000.25, 5012000.5, 100.0);
  return c;
}

void expect_same_world(const PointCloud& a, const PointCloud& b, double tolerance) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    ASSERT_LE(((a.positions[i] + a.offset) - (b.positions[i] + b.offset)).cwiseAbs().maxCoeff(), tolerance) << i;
  EXPECT_EQ(a.colors, b.colors);
  ASSERT_EQ(a.normals.size(), b.normals.size());
  for (std::size_t i = 0; i < a.normals.size(); ++i) EXPECT_TRUE(a.normals[i].isApprox(b.normals[i], 1e-6f));
}

class RoundTrip : public ::testing::TestWithParam<std::tuple<std::string, bool>> {};

TEST_P(RoundTrip, WritesAndReadsBack) {
  const auto& [ext, utm] = GetParam();
  const TempDir dir;
  const bool attributes = ext != "las";
  for (bool binary : {true, false}) {
    const PointCloud c = random_cloud(utm, attributes, true);
    const std::string path = dir.path("cloud." + ext);
    io::CloudWriteOptions options;
    options.ply_binary = binary;
    io::write_point_cloud(path, c, options);
    const PointCloud back = io::read_point_cloud(path);
    expect_same_world(c, back, ext == "las" ? 0.5e-4 + 1e-9 : 1e-9);
    EXPECT_EQ(bounding_box(back).min(), Eigen::Vector3d::Zero());  // the reader's local frame
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, RoundTrip,
                         ::testing::Combine(::testing::Values("xyz", "txt", "asc", "csv", "pts", "ply", "las"),
                                            ::testing::Bool()));

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A tree id, a class and a height for each of `n` points, as the plot's labelled cloud has them.
std::vector<io::PointField> labelled_fields(std::size_t n) {
  std::vector<io::PointField> fields = {{"tree_id", io::PointField::Type::uint32, {}},
                                        {"class", io::PointField::Type::uint8, {}},
                                        {"height", io::PointField::Type::float32, {}}};
  for (std::size_t i = 0; i < n; ++i) {
    fields[0].values.push_back(static_cast<double>(i * 1000003 % 4000000000u));
    fields[1].values.push_back(static_cast<double>(i % 3));
    fields[2].values.push_back(0.25 * static_cast<double>(i));
  }
  return fields;
}

TEST(WritePly, FieldsPerPointAfterThePositionInBothEncodings) {
  const TempDir dir;
  const PointCloud c = random_cloud(true, true, true);
  io::CloudWriteOptions options;
  options.fields = labelled_fields(c.size());
  for (bool binary : {true, false}) {
    options.ply_binary = binary;
    const std::string path = dir.path(binary ? "b.ply" : "a.ply");
    io::write_point_cloud(path, c, options);
    // The reader passes over the extra properties: the cloud reads back whole.
    expect_same_world(c, io::read_point_cloud(path), 1e-9);
    const std::string text = read_text(path);
    const std::string header = text.substr(0, text.find("end_header"));
    EXPECT_NE(header.find("property uchar blue\nproperty uint tree_id\nproperty uchar class\nproperty float height\n"), std::string::npos)
        << header;
    if (binary) {
      // The last point's fields are the file's last 9 bytes.
      const std::string tail = text.substr(text.size() - 9);
      std::uint32_t id;
      float height;
      std::memcpy(&id, tail.data(), 4);
      std::memcpy(&height, tail.data() + 5, 4);
      EXPECT_EQ(id, static_cast<std::uint32_t>(options.fields[0].values.back()));
      EXPECT_EQ(static_cast<int>(static_cast<unsigned char>(tail[4])), static_cast<int>(options.fields[1].values.back()));
      EXPECT_EQ(height, static_cast<float>(options.fields[2].values.back()));
    } else {
      const std::string last = text.substr(text.rfind('\n', text.size() - 2) + 1);
      std::istringstream in(last);
      std::vector<double> numbers;
      for (double v; in >> v;) numbers.push_back(v);
      ASSERT_GE(numbers.size(), 3u);
      EXPECT_EQ(numbers[numbers.size() - 3], options.fields[0].values.back());
      EXPECT_EQ(numbers[numbers.size() - 2], options.fields[1].values.back());
      EXPECT_EQ(numbers[numbers.size() - 1], options.fields[2].values.back());
    }
  }
  EXPECT_THROW(io::write_point_cloud(dir.path("c.xyz"), c, options), Error);
  EXPECT_FALSE(fs::exists(dir.path("c.xyz")));
}

TEST(ReadText, AcceptsCommentsCrlfCommasHeadersAndExtraColumns) {
  const TempDir dir;
  const std::string path = dir.path("mixed.csv");
  write_text(path,
             "# a comment line\r\n"
             "X,Y,Z,intensity\r\n"
             "1.5,2,3,77\r\n"
             "\r\n"
             "+4,5e0,-6 ,1 # trailing comment\r\n"
             "7;8;9;0\r\n");
  const PointCloud c = io::read_point_cloud(path);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.positions[1] + c.offset, Eigen::Vector3d(4, 5, -6));
  EXPECT_EQ(c.positions[2] + c.offset, Eigen::Vector3d(7, 8, 9));
  EXPECT_FALSE(c.has_normals());
}

TEST(ReadText, HeaderPicksTheColumns) {
  const TempDir dir;
  const std::string path = dir.path("cols.txt");
  write_text(path, "id z y x red green blue\n1 3 2 1 255 0 10\n2 6 5 4 0 128 20\n");
  const PointCloud c = io::read_point_cloud(path);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.positions[1] + c.offset, Eigen::Vector3d(4, 5, 6));
  ASSERT_TRUE(c.has_colors());
  EXPECT_EQ(c.colors[0], (std::array<std::uint8_t, 3>{255, 0, 10}));
}

TEST(ReadText, BundledCrlfFileWithTrailingSpaces) {
  const PointCloud c = io::read_point_cloud(test::data_file("tree_adtree1.xyz"));
  EXPECT_EQ(c.size(), 11855u);
}

TEST(ReadPly, BigEndianFloatWithFacesAfterTheVertices) {
  const TempDir dir;
  const std::string path = dir.path("be.ply");
  std::string data =
      "ply\nformat binary_big_endian 1.0\ncomment made by hand\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\nproperty uchar flag\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  auto put_be = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const char*>(p);
    for (std::size_t i = n; i-- > 0;) data.push_back(b[i]);
  };
  const float v[2][3] = {{1.5f, -2.0f, 3.25f}, {4.0f, 5.0f, 6.0f}};
  for (const auto& p : v) {
    for (float f : p) put_be(&f, 4);
    data.push_back('\x01');
  }
  data.push_back('\x03');
  for (std::int32_t i : {0, 1, 0}) put_be(&i, 4);
  write_text(path, data);
  const PointCloud c = io::read_point_cloud(path);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.positions[0] + c.offset, Eigen::Vector3d(1.5, -2.0, 3.25));
}

TEST(ReadPly, AsciiWithNormalsAndFloatColours) {
  const TempDir dir;
  const std::string path = dir.path("a.ply");
  write_text(path,
             "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty double x\r\nproperty double y\r\nproperty double z\r\n"
             "property float nx\r\nproperty float ny\r\nproperty float nz\r\nproperty float red\r\nproperty float green\r\n"
             "property float blue\r\nend_header\r\n1 2 3 0 0 1 1 0.5 0\r\n4 5 6 1 0 0 0 0 1\r\n");
  const PointCloud c = io::read_point_cloud(path);
  ASSERT_EQ(c.size(), 2u);
  ASSERT_TRUE(c.has_normals());
  EXPECT_EQ(c.normals[1], Eigen::Vector3f(1, 0, 0));
  EXPECT_EQ(c.colors[0], (std::array<std::uint8_t, 3>{255, 128, 0}));
}

/// A LAS 1.4 file with point format 6 (the 64-bit count), written byte by byte.
std::string las14(std::uint64_t declared, std::uint64_t present) {
  std::string h(375, '\0');
  h.replace(0, 4, "LASF");
  h[24] = 1;
  h[25] = 4;
  auto set = [&](std::size_t at, auto v) { std::memcpy(&h[at], &v, sizeof v); };
  set(94, std::uint16_t{375});
  set(96, std::uint32_t{375});
  set(104, std::uint8_t{6});
  set(105, std::uint16_t{30});
  set(247, declared);
  for (int a = 0; a < 3; ++a) {
    set(131 + 8 * a, 0.01);
    set(155 + 8 * a, a == 0 ? 500000.0 : a == 1 ? 4000000.0 : 0.0);
  }
  for (std::uint64_t i = 0; i < present; ++i) {
    std::string rec(30, '\0');
    const std::int32_t xyz[3] = {std::int32_t(100 * i), std::int32_t(200 + i), std::int32_t(300)};
    std::memcpy(&rec[0], xyz, 12);
    rec[15] = static_cast<char>(0xf0);            // classification flags and scanner channel: not the class
    rec[16] = static_cast<char>(i == 0 ? 2 : 40);  // the class, a whole byte in formats 6-10
    h += rec;
  }
  return h;
}

TEST(WriteLas, FieldsAsTheExtraBytesOfALas14File) {
  const TempDir dir;
  PointCloud c = random_cloud(true, false, true);
  c.classes.assign(c.size(), 5);
  io::CloudWriteOptions options;
  options.fields = labelled_fields(c.size());
  const std::string path = dir.path("labelled.las");
  io::write_point_cloud(path, c, options);
  // The reader passes over the extra bytes: positions, colours and classes read back.
  const PointCloud back = io::read_point_cloud(path);
  expect_same_world(c, back, 1e-4);
  EXPECT_EQ(back.classes, c.classes);
  const std::string f = read_text(path);
  auto u16 = [&](std::size_t at) { std::uint16_t v; std::memcpy(&v, f.data() + at, 2); return v; };
  auto u32 = [&](std::size_t at) { std::uint32_t v; std::memcpy(&v, f.data() + at, 4); return v; };
  auto u64 = [&](std::size_t at) { std::uint64_t v; std::memcpy(&v, f.data() + at, 8); return v; };
  // LAS 1.4: a 375-byte header, one VLR, point format 2 (colours) with 9 extra bytes a point.
  EXPECT_EQ(f[24], 1);
  EXPECT_EQ(f[25], 4);
  EXPECT_EQ(u16(94), 375);
  EXPECT_EQ(u32(100), 1u);
  EXPECT_EQ(f[104], 2);
  EXPECT_EQ(u16(105), 26 + 9);
  EXPECT_EQ(u32(107), c.size());
  EXPECT_EQ(u64(247), c.size());
  const std::size_t points = u32(96);
  EXPECT_EQ(points, 375u + 54u + 3u * 192u);
  EXPECT_EQ(f.size(), points + c.size() * (26 + 9));
  // The VLR: user LASF_Spec, record 4, a 192-byte descriptor per field (type at 2, name at 4).
  EXPECT_EQ(f.substr(375 + 2, 10), std::string("LASF_Spec\0", 10));
  EXPECT_EQ(u16(375 + 18), 4);
  EXPECT_EQ(u16(375 + 20), 3 * 192);
  const std::pair<const char*, int> expected[] = {{"tree_id", 5}, {"class", 1}, {"height", 9}};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t d = 375 + 54 + 192 * k;
    EXPECT_EQ(static_cast<int>(f[d + 2]), expected[k].second);
    EXPECT_EQ(std::string(f.c_str() + d + 4), expected[k].first);
  }
  // Each point's extra bytes follow its 26 bytes, in the fields' order.
  for (std::size_t i : {std::size_t{0}, c.size() / 2, c.size() - 1}) {
    const std::size_t at = points + i * (26 + 9) + 26;
    EXPECT_EQ(u32(at), static_cast<std::uint32_t>(options.fields[0].values[i]));
    EXPECT_EQ(static_cast<int>(static_cast<unsigned char>(f[at + 4])), static_cast<int>(options.fields[1].values[i]));
    float height;
    std::memcpy(&height, f.data() + at + 5, 4);
    EXPECT_EQ(height, static_cast<float>(options.fields[2].values[i]));
  }
  // A text format still refuses fields, and a LAS field needs a name that fits.
  EXPECT_THROW(io::write_point_cloud(dir.path("labelled.xyz"), c, options), Error);
  options.fields[0].name = std::string(33, 'x');
  EXPECT_THROW(io::write_point_cloud(dir.path("long.las"), c, options), Error);
}

TEST(ReadLas, Version14PointFormat6) {
  const TempDir dir;
  const std::string path = dir.path("v14.las");
  write_text(path, las14(3, 3));
  const PointCloud c = io::read_point_cloud(path);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_NEAR((c.positions[2] + c.offset - Eigen::Vector3d(500002.0, 4000002.02, 3.0)).norm(), 0.0, 1e-6);
  EXPECT_EQ(c.classes, (std::vector<std::uint8_t>{2, 40, 40}));
}

TEST(ReadLas, ClassesKeptWhenAnyPointIsClassifiedAndWrittenBack) {
  const TempDir dir;
  PointCloud c = random_cloud(true, false, false);
  io::write_point_cloud(dir.path("none.las"), c);
  EXPECT_TRUE(io::read_point_cloud(dir.path("none.las")).classes.empty());  // all 0: no classification
  c.classes.resize(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) c.classes[i] = static_cast<std::uint8_t>(i % 3 == 0 ? 2 : i % 3 == 1 ? 5 : 1);
  io::write_point_cloud(dir.path("classes.las"), c);
  EXPECT_EQ(io::read_point_cloud(dir.path("classes.las")).classes, c.classes);
}

TEST(ReadLaz, DecompressesThroughLazPerfToThePointsOfTheTextVersion) {
  // treeiso's LPine1 plot; the figures are those of its .xyz.gz twin (the same points in the same
  // order, to the LAS scale of 0.01).
  const PointCloud c = io::read_point_cloud(TREESKEL_TEST_LAZ);
  ASSERT_EQ(c.size(), 1544202u);
  EXPECT_TRUE((c.positions.front() + c.offset).isApprox(Eigen::Vector3d(2.16, 1.49, 15.81), 1e-12));
  EXPECT_TRUE((c.positions.back() + c.offset).isApprox(Eigen::Vector3d(14.47, 4.29, 15.02), 1e-12));
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : c.positions) sum += p + c.offset;
  EXPECT_NEAR(sum.x(), 10226503.26, 1e-3);
  EXPECT_NEAR(sum.y(), 4374165.61, 1e-3);
  EXPECT_NEAR(sum.z(), 16481788.53, 1e-3);
  const Eigen::AlignedBox3d box = bounding_box(c);
  EXPECT_TRUE((box.min() + c.offset).isApprox(Eigen::Vector3d(-2.12, -2.48, -1.09), 1e-12));
  EXPECT_TRUE((box.max() + c.offset).isApprox(Eigen::Vector3d(15.04, 8.59, 20.83), 1e-12));
}

TEST(ReadLaz, TruncatedCorruptOrUncompressedFilesAreToldApart) {
  const TempDir dir;
  std::ifstream in(TREESKEL_TEST_LAZ, std::ios::binary);
  const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(dir.path("cut.laz"), std::ios::binary) << whole.substr(0, 300000);
  expect_error(dir.path("cut.laz"), {"cut.laz", "truncated"});
  std::string bad = whole;
  const std::uint32_t start = *reinterpret_cast<const std::uint32_t*>(bad.data() + 96);
  for (std::size_t i = start + 2000; i < start + 4000; ++i) bad[i] = static_cast<char>(bad[i] ^ 0x5a);
  std::ofstream(dir.path("bad.laz"), std::ios::binary) << bad;
  expect_error(dir.path("bad.laz"), {"bad.laz", "cannot be decoded", "corrupt"});
  std::ofstream(dir.path("text.laz")) << "1 2 3\n";
  expect_error(dir.path("text.laz"), {"not a LAZ file"});
  // An uncompressed file named .laz is read as the LAS it is.
  PointCloud small;
  small.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  io::write_point_cloud(dir.path("plain.las"), small);
  std::filesystem::copy_file(dir.path("plain.las"), dir.path("plain.laz"));
  EXPECT_EQ(io::read_point_cloud(dir.path("plain.laz")).size(), 4u);
}

TEST(ReadText, PtsPointCountLinesArePassedOver) {
  const TempDir dir;
  // Leica / CloudCompare .pts: each scan's count on a line of its own, then x y z intensity r g b.
  std::ofstream(dir.path("scan.pts")) << "3\n1 2 3 -120 10 20 30\n4 5 6 -1 0 0 0\n7 8 10 0 1 1 1\n2\n0 0 0 5 1 1 1\n1 1 1 5 1 1 1\n";
  const PointCloud c = io::read_point_cloud(dir.path("scan.pts"));
  ASSERT_EQ(c.size(), 5u);
  EXPECT_TRUE((c.positions[2] + c.offset).isApprox(Eigen::Vector3d(7, 8, 10)));
}

TEST(BadInput, EachGetsAClearMessage) {
  const TempDir dir;
  const auto file = [&](const std::string& name, const std::string& content) { return written(dir, name, content); };
  expect_error(dir.path("missing.xyz"), {"no such file"});
  expect_error(file("empty.xyz", ""), {"empty"});
  expect_error(file("blank.xyz", "# only a comment\n\n"), {"no points"});
  expect_error(file("words.xyz", "1 2 3\n4 five 6\n"), {"line 2", "'five' is not a number"});
  expect_error(file("short.xyz", "1 2 3\n4 5\n"), {"line 2", "at least 3 numbers"});
  expect_error(file("nan.xyz", "1 2 3\nnan 5 6\n"), {"line 2", "not a finite number"});
  expect_error(file("inf.txt", "1 2 3\n4 5 inf\n"), {"line 2", "not a finite number"});
  expect_error(file("cloud.laz", "LASF"), {"truncated", "shorter than a LAS header"});
  expect_error(file("cloud.obj", "v 1 2 3\n"), {"unknown point cloud extension"});
  expect_error(file("fake.ply", "hello\n"), {"not a PLY file"});
  expect_error(file("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"), {"end_header"});
  expect_error(file("noxyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n"), {"x, y and z"});

  // A binary PLY cut short, and one whose header claims fewer points than it holds.
  PointCloud c = random_cloud(false, false, false);
  io::write_point_cloud(dir.path("good.ply"), c);
  const std::string ply = read_bytes(dir.path("good.ply"));
  expect_error(file("truncated.ply", ply.substr(0, ply.size() - 10)), {"truncated", "300 vertex"});
  std::string fewer = ply;
  fewer.replace(fewer.find("vertex 300"), 10, "vertex 299");
  expect_error(file("fewer.ply", fewer), {"bytes follow the last element"});
  std::string more_ascii = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n4 5 6\n";
  expect_error(file("lies.ply", more_ascii), {"declares 3 vertex elements", "only 12 bytes follow"});
  expect_error(file("padded.ply", more_ascii + "\n\n\n\n\n\n"), {"ends after 2 of the 3 vertex"});
  expect_error(file("nanbin.ply", [&] {
                 std::string s = ply;
                 const double bad = std::numeric_limits<double>::quiet_NaN();
                 std::memcpy(&s[s.find("end_header\n") + 11 + 24], &bad, 8);
                 return s;
               }()),
               {"vertex 1", "not a finite number"});

  // LAS cut short, with a header that lies, and not LAS at all.
  io::write_point_cloud(dir.path("good.las"), c);
  const std::string las = read_bytes(dir.path("good.las"));
  expect_error(file("truncated.las", las.substr(0, las.size() - 7)), {"truncated", "300 points"});
  expect_error(file("header.las", las.substr(0, 100)), {"truncated", "shorter than a LAS header"});
  expect_error(file("lies14.las", las14(2, 3)), {"declares 2 points", "more bytes"});
  expect_error(file("short14.las", las14(5, 3)), {"truncated", "5 points"});
  expect_error(file("notlas.las", "PK\x03\x04 zip"), {"not a LAS file"});
  std::string compressed = las;
  compressed[104] = static_cast<char>(0x80 | 3);
  expect_error(file("compressed.las", compressed), {"LAZ-compressed"});
}

// Element counts a header cannot honestly make: no loop, no reservation beyond the file, no conversion
// of an out-of-range number.
TEST(BadInput, ElementCountsAreCheckedAgainstTheFile) {
  const TempDir dir;
  const auto file = [&](const std::string& name, const std::string& content) { return written(dir, name, content); };
  const std::string xyz = "property float x\nproperty float y\nproperty float z\nend_header\n";
  const auto ascii = [&](const std::string& junk) {
    return "ply\nformat ascii 1.0\nelement junk " + junk + "\nelement vertex 3\n" + xyz + "0 0 0\n1 0 0\n0 1 1\n";
  };
  // An element without properties holds no bytes: skipped whatever its count (it used to loop 10^12 times).
  for (const std::string count : {"1000000000000", "18446744073709551615"})
    EXPECT_EQ(io::read_point_cloud(file("junk.ply", ascii(count))).size(), 3u) << count;
  std::string binary = "ply\nformat binary_little_endian 1.0\nelement junk 1000000000000\nelement vertex 1\n" + xyz;
  const float p[3] = {1, 2, 3};
  binary.append(reinterpret_cast<const char*>(p), sizeof p);
  EXPECT_EQ(io::read_point_cloud(file("junk_binary.ply", binary)).size(), 1u);
  // Counts that are not whole numbers below 2^64 are malformed, not 0.
  for (const std::string count : {"18446744073709551616", "1e30", "nan", "inf", "-1", "3.0", "0x10"})
    expect_error(file("count.ply", ascii(count)), {"line 3", "malformed element line"});
  // Counts the bytes that follow cannot hold are refused before anything is reserved.
  const std::string huge = "ply\nformat binary_little_endian 1.0\nelement vertex 9223372036854775808\n" + xyz;
  expect_error(file("huge.ply", huge + "0000"), {"declares 9223372036854775808 vertex elements", "only 4 bytes follow"});
  expect_error(file("huge_ascii.ply", "ply\nformat ascii 1.0\nelement vertex 18446744073709551615\n" + xyz + "0 0 0\n"),
               {"declares 18446744073709551615 vertex", "only 6 bytes"});
  // A list property's length cannot run past the file either.
  // A list row longer than its least size, then an element that is skipped: the skip is checked
  // against what is left (found by the fuzzer: it read past the end).
  {
    std::string b = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n" + xyz.substr(0, xyz.find("end_header")) +
                    "element face 1\nproperty list uchar int vertex_indices\nelement junk 2\nproperty int a\nend_header\n";
    const float v[3] = {0, 0, 0};
    b.append(reinterpret_cast<const char*>(v), sizeof v);
    b += '\x03';
    const std::int32_t ids[3] = {0, 0, 0};
    b.append(reinterpret_cast<const char*>(ids), sizeof ids);  // 13 bytes where the header check counts 1
    b.append(4, '\0');                                           // junk needs 8 bytes: 4 are left
    expect_error(file("list_then_junk.ply", b), {"truncated", "2 junk elements need 8 bytes"});
  }
  expect_error(file("list2.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                     "end_header\n1 2 3\n1e300 0\n"),
               {"bad list length"});
}

TEST(BadInput, LasCountsBeyondTheFileAreNamedExactly) {
  const TempDir dir;
  PointCloud c;
  c.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  io::write_point_cloud(dir.path("good.las"), c);
  std::string las = read_bytes(dir.path("good.las"));
  // LAS 1.2: the 32-bit count at byte 107 only; make it 2^32 - 1.
  const std::uint32_t many = 0xffffffffu;
  std::memcpy(&las[107], &many, 4);
  write_text(dir.path("many.las"), las);
  expect_error(dir.path("many.las"), {"declares 4294967295 points of", "bytes follow"});
}

// The first bytes are checked before the rest is read: a huge file of another kind is refused at once
// (sparse files, so the test costs no disk).
TEST(BadInput, HugeFilesOfAnotherKindAreRefusedAtTheirStart) {
  const TempDir dir;
  const auto sparse = [&](const std::string& name, const std::string& start, std::uintmax_t size) {
    const std::string p = dir.path(name);
    write_text(p, start);
    fs::resize_file(p, size);
    return p;
  };
  expect_error(sparse("junk.ply", "junk", std::uintmax_t{2} << 30), {"not a PLY file"});
  expect_error(sparse("junk.las", "junk", std::uintmax_t{2} << 30), {"not a LAS file"});
  expect_error(sparse("one_line.xyz", "1 2 3 ", std::uintmax_t{100} << 20), {"line 1", "longer than 64 KiB"});
  expect_error(sparse("header.ply", "ply\nformat ascii 1.0\ncomment ", std::uintmax_t{2} << 30),
               {"line 3", "longer than 64 KiB"});
}

}  // namespace
}  // namespace treeskel
