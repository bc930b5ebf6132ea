// Rasterising keyframe targets into density grids (issue 3): analytic shapes,
// coverage images (image masks and rendered text) and voxelised meshes.
#pragma once
#include <vector>

#include "pliant/geom/coverage_image.h"
#include "pliant/geom/raster_grid.h"
#include "pliant/geom/triangle_mesh.h"

namespace pliant::geom {

// Circle (2D) / sphere (3D) of radius_m (times p.scale) at p.center_m.
std::vector<float> raster_sphere(const RasterGrid& g, const Placement& p, double radius_m, int supersample = 4);
// Square/box with half extents half_size_m (times p.scale), turned by the placement
// (about z in 2D, any axis in 3D).
std::vector<float> raster_box(const RasterGrid& g, const Placement& p, const std::array<double, 3>& half_size_m,
                              int supersample = 4);
// A coverage image placed so that its height is height_m * p.scale metres (width by
// its aspect ratio), centred at p.center_m, turned by the placement. Outside the image the
// value is 0. In 3D the image is extruded along z over depth_m centred at center_m[2].
std::vector<float> raster_image(const RasterGrid& g, const CoverageImage& img, const Placement& p,
                                double height_m, double depth_m = 0, int supersample = 4);
// A closed triangle mesh, uniformly scaled so its largest bounding-box extent is
// size_m * p.scale, centred at p.center_m, turned by the placement; inside by ray parity
// along +x. 3D grids only.
std::vector<float> raster_mesh(const RasterGrid& g, const TriangleMesh& mesh, const Placement& p, double size_m,
                               int supersample = 2);

// Sum of the values times the cell area/volume (m^2 or m^3).
double raster_measure(const RasterGrid& g, const std::vector<float>& density);

}  // namespace pliant::geom
