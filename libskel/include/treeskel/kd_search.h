/// @file kd_search.h
/// The CGAL kd-tree the stages that look for neighbours share: points named by their index into an
/// array of CGAL points (the array outlives the tree), searched for their k nearest.
#pragma once

#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>

#include <cstdint>

namespace treeskel::kd {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using PointMap = CGAL::Pointer_property_map<Point>::type;
using Traits = CGAL::Search_traits_adapter<std::uint32_t, PointMap, CGAL::Search_traits_3<Kernel>>;
using KnnSearch = CGAL::Orthogonal_k_neighbor_search<Traits>;
using Tree = KnnSearch::Tree;

}  // namespace treeskel::kd
