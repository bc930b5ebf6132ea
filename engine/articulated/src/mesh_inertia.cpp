// Mass properties of triangle meshes: the enclosed solid's, and MuJoCo 2.2.2's.
#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "pliant/articulated/model.h"

namespace pliant::articulated {
namespace {

// Tetrahedra (o, a, b, c) over the faces: volume, first moment and second moment
// (integral of p p^T, p relative to o); with `unsigned_volume` each tetrahedron counts
// with |volume| (MuJoCo's pre-3.0 rule), otherwise signed (divergence theorem).
void tetra_sums(const MeshShape& mesh, const Vec3& o, bool unsigned_volume, double* volume, Vec3* first,
                Mat3* second) {
  double v = 0;
  Vec3 f = Vec3::Zero();
  Mat3 sec = Mat3::Zero();
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]] - o, b = mesh.vertices[t[1]] - o, c = mesh.vertices[t[2]] - o;
    double vol = a.dot(b.cross(c)) / 6;
    if (unsigned_volume) vol = std::abs(vol);
    v += vol;
    const Vec3 s = a + b + c;
    f += vol * s / 4;
    // Exact for a tetrahedron with a vertex at o: vol/20 (sum v v^T + (sum v)(sum v)^T).
    if (second) sec += vol / 20 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  *volume = v;
  *first = f;
  if (second) *second = sec;
}

}  // namespace

void mesh_volume_moments(const MeshShape& mesh, double* volume, Vec3* centre, Mat3* second) {
  Vec3 first;
  tetra_sums(mesh, Vec3::Zero(), false, volume, &first, second);
  if (centre) *centre = *volume != 0 ? Vec3(first / *volume) : Vec3::Zero();
}

void mesh_mujoco222_moments(const MeshShape& mesh, double* mass_volume, double* volume, Vec3* centre,
                            Mat3* second) {
  // Surface centroid: face centroids weighted by area.
  double area = 0;
  Vec3 surface = Vec3::Zero();
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const double ar = (b - a).cross(c - a).norm() / 2;
    area += ar;
    surface += ar * (a + b + c) / 3;
  }
  if (area > 0) surface /= area;
  double v1;
  Vec3 first;
  tetra_sums(mesh, surface, true, &v1, &first, nullptr);
  const Vec3 com = v1 > 0 ? Vec3(surface + first / v1) : surface;
  // Second moments about com from tetrahedra with their apex there (not re-centred on
  // these tetrahedra's own centre: matches libmujoco 2.2.2 to ~1e-7 on mug.obj).
  Mat3 s;
  tetra_sums(mesh, com, true, volume, &first, &s);
  const Mat3 inertia = s.trace() * Mat3::Identity() - s;  // per unit density
  const Vec3 j = Eigen::SelfAdjointEigenSolver<Mat3>(inertia, Eigen::EigenvaluesOnly).eigenvalues();
  double box = *volume > 0 ? 8.0 : 0.0;
  for (int i = 0; i < 3 && box > 0; ++i)
    box *= std::sqrt(std::max(0.0, 1.5 / *volume * (j[(i + 1) % 3] + j[(i + 2) % 3] - j[i])));
  *mass_volume = box;
  if (centre) *centre = com;
  if (second) *second = s;
}

}  // namespace pliant::articulated
