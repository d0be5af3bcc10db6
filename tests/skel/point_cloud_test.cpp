#include "treeskel/point_cloud.h"

#include <gtest/gtest.h>

namespace treeskel {
namespace {

PointCloud cloud_of(std::initializer_list<Eigen::Vector3d> points) {
  PointCloud c;
  c.positions.assign(points.begin(), points.end());
  return c;
}

TEST(PointCloud, ClassifiesDegenerateShapes) {
  EXPECT_EQ(classify_shape(PointCloud{}), CloudShape::empty);
  EXPECT_EQ(classify_shape(cloud_of({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}})), CloudShape::identical);
  EXPECT_EQ(classify_shape(cloud_of({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {5, 5, 5}})), CloudShape::collinear);
  EXPECT_EQ(classify_shape(cloud_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})), CloudShape::ok);
}

TEST(PointCloud, CollinearFarFromOriginIsStillCollinear) {
  PointCloud c;
  for (int i = 0; i < 50; ++i) c.positions.emplace_back(300000.0 + 0.1 * i, 5000000.0 + 0.2 * i, 100.0 + 0.05 * i);
  recentre_offset(c);
  EXPECT_EQ(classify_shape(c), CloudShape::collinear);
}

TEST(PointCloud, RecentreKeepsWorldCoordinates) {
  PointCloud c = cloud_of({{300010.5, 5000020.25, 101.0}, {300012.5, 5000021.25, 103.0}});
  const Eigen::Vector3d first_world = c.positions[0];
  recentre_offset(c);
  EXPECT_EQ(c.offset, Eigen::Vector3d(300010.5, 5000020.25, 101.0));
  EXPECT_EQ(c.positions[0], Eigen::Vector3d::Zero());
  EXPECT_EQ(c.positions[1], Eigen::Vector3d(2.0, 1.0, 2.0));
  EXPECT_EQ(c.positions[0] + c.offset, first_world);
  EXPECT_EQ(bounding_box(c).min(), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace treeskel
