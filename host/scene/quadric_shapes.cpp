// Tessellations of pbrt-v4's sphere, disk and cylinder (src/pbrt/shapes.h, shapes.cpp): each is
// a list of rows of a surface of revolution about z (distance from the axis, height, normal, v)
// revolved over phi in [0, phimax]; a row on the axis becomes a fan apex.
#include "scene/quadric_shapes.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <utility>
#include <vector>

namespace hrpp {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
constexpr int kMinSegments = 3;
constexpr int kMaxSegments = 4096;

// One row of the revolved grid: distance from the z axis, height, the unit normal's radial and z
// parts, and v. A pole row (rho = 0) becomes one apex vertex per segment.
struct Row {
  double rho;
  double z;
  double n_rho;
  double n_z;
  double v;
  bool pole;
};

// The phi range of a shape: pbrt clamps phimax to [0, 360] degrees.
struct PhiRange {
  double phi_max;  // radians
  bool full_turn;
};

PhiRange phi_range(float phimax_degrees) {
  const double degrees = std::clamp(static_cast<double>(phimax_degrees), 0.0, 360.0);
  return {degrees * (kPi / 180.0), degrees >= 360.0};
}

int clamp_segments(int segments) { return std::clamp(segments, kMinSegments, kMaxSegments); }

// Steps over `angle` radians at `segments` steps per full turn (at least one).
int angle_steps(int segments, double angle) {
  const double steps = std::ceil(static_cast<double>(segments) * angle / kTwoPi - 1e-9);
  return std::max(1, static_cast<int>(steps));
}

bool all_finite(std::initializer_list<float> values) {
  return std::all_of(values.begin(), values.end(), [](float x) { return std::isfinite(x); });
}

class Revolver {
 public:
  Revolver(PhiRange range, int steps) : steps_(steps) {
    for (int j = 0; j <= steps; ++j) {
      // At a full turn the last column is the first one again, bit for bit.
      const int column = range.full_turn && j == steps ? 0 : j;
      const double phi = range.phi_max * column / steps;
      cos_.push_back(std::cos(phi));
      sin_.push_back(std::sin(phi));
    }
  }

  IndexedMesh revolve(const std::vector<Row>& rows) {
    std::vector<std::uint32_t> first;  // each row's first vertex
    for (const Row& row : rows) {
      first.push_back(static_cast<std::uint32_t>(mesh_.positions.size()));
      add_row(row);
    }
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
      for (int j = 0; j < steps_; ++j) add_cell(rows[i], first[i], rows[i + 1], first[i + 1], j);
    }
    return std::move(mesh_);
  }

 private:
  void add_vertex(const Row& row, double c, double s, double u) {
    mesh_.positions.emplace_back(row.rho * c, row.rho * s, row.z);
    mesh_.normals.push_back(glm::normalize(glm::vec3(row.n_rho * c, row.n_rho * s, row.n_z)));
    mesh_.uvs.emplace_back(u, row.v);
  }

  // A ring: steps + 1 columns. A pole: one apex per segment, at the segment's middle u.
  void add_row(const Row& row) {
    if (row.pole) {
      for (int j = 0; j < steps_; ++j) add_vertex(row, 1.0, 0.0, (j + 0.5) / steps_);
      return;
    }
    for (int j = 0; j <= steps_; ++j) {
      add_vertex(row, cos_[static_cast<std::size_t>(j)], sin_[static_cast<std::size_t>(j)],
                 static_cast<double>(j) / steps_);
    }
  }

  // Segment j between rows a (lower v) and b: counter-clockwise in (u, v), which is
  // counter-clockwise about cross(dpdu, dpdv), pbrt's normal.
  void add_cell(const Row& a, std::uint32_t a0, const Row& b, std::uint32_t b0, int j) {
    const std::uint32_t column = static_cast<std::uint32_t>(j);
    const std::uint32_t a_j = a0 + column, a_next = a0 + column + 1;
    const std::uint32_t b_j = b0 + column, b_next = b0 + column + 1;
    auto& idx = mesh_.indices;
    if (a.pole) {
      idx.insert(idx.end(), {a_j, b_next, b_j});
    } else if (b.pole) {
      idx.insert(idx.end(), {a_j, a_next, b_j});
    } else {
      idx.insert(idx.end(), {a_j, a_next, b_next, a_j, b_next, b_j});
    }
  }

  int steps_;
  std::vector<double> cos_, sin_;
  IndexedMesh mesh_;
};

// Row i of n of the sphere, theta from theta_lo (at z_lo, v = 0) to theta_hi (at z_hi, v = 1).
Row sphere_row(double r, double z_lo, double z_hi, int i, int n, bool south, bool north) {
  const double t = static_cast<double>(i) / n;
  if ((i == 0 && south) || (i == n && north)) {
    const double pole_z = i == 0 ? -r : r;
    return {0.0, pole_z, 0.0, pole_z / r, t, true};
  }
  double z = 0.0, rho = 0.0;
  if (i == 0 || i == n) {
    z = i == 0 ? z_lo : z_hi;  // the clipping planes exactly
    rho = std::sqrt(std::max(0.0, r * r - z * z));
  } else {
    const double theta_lo = std::acos(z_lo / r), theta_hi = std::acos(z_hi / r);
    const double theta = theta_lo + t * (theta_hi - theta_lo);
    z = r * std::cos(theta);
    rho = r * std::sin(theta);
  }
  return {rho, z, rho / r, z / r, t, false};
}

}  // namespace

int quadric_segments(float max_sag_fraction) {
  if (!(max_sag_fraction > 0.0f)) return kMaxSegments;
  const double step = std::acos(std::max(-1.0, 1.0 - static_cast<double>(max_sag_fraction)));
  const double segments = std::ceil(kPi * std::sqrt(2.0) / step);
  return static_cast<int>(std::clamp(segments, double{kMinSegments}, double{kMaxSegments}));
}

IndexedMesh tessellate_sphere(float radius, float zmin, float zmax, float phimax_degrees,
                              int segments) {
  if (!all_finite({radius, zmin, zmax, phimax_degrees}) || !(radius > 0.0f)) return {};
  const double r = radius;
  const double z_lo = std::clamp(static_cast<double>(std::min(zmin, zmax)), -r, r);
  const double z_hi = std::clamp(static_cast<double>(std::max(zmin, zmax)), -r, r);
  const PhiRange range = phi_range(phimax_degrees);
  if (!(z_lo < z_hi) || !(range.phi_max > 0.0)) return {};
  segments = clamp_segments(segments);
  const bool south = z_lo <= -r, north = z_hi >= r;
  int n = angle_steps(segments, std::acos(z_lo / r) - std::acos(z_hi / r));
  if (south && north) n = std::max(n, 2);
  std::vector<Row> rows;
  for (int i = 0; i <= n; ++i) rows.push_back(sphere_row(r, z_lo, z_hi, i, n, south, north));
  return Revolver(range, angle_steps(segments, range.phi_max)).revolve(rows);
}

IndexedMesh tessellate_disk(float height, float radius, float innerradius, float phimax_degrees,
                            int segments) {
  if (!all_finite({height, radius, innerradius, phimax_degrees}) || !(radius > 0.0f)) return {};
  const double outer = radius, inner = innerradius, hole = std::abs(inner);
  const PhiRange range = phi_range(phimax_degrees);
  if (!(hole < outer) || !(range.phi_max > 0.0)) return {};
  const std::vector<Row> rows = {
      {outer, height, 0.0, 1.0, 0.0, false},
      {hole, height, 0.0, 1.0, (outer - hole) / (outer - inner), hole == 0.0}};
  return Revolver(range, angle_steps(clamp_segments(segments), range.phi_max)).revolve(rows);
}

IndexedMesh tessellate_cylinder(float radius, float zmin, float zmax, float phimax_degrees,
                                int segments) {
  if (!all_finite({radius, zmin, zmax, phimax_degrees}) || !(radius > 0.0f)) return {};
  const double z_lo = std::min(zmin, zmax), z_hi = std::max(zmin, zmax);
  const PhiRange range = phi_range(phimax_degrees);
  if (!(z_lo < z_hi) || !(range.phi_max > 0.0)) return {};
  const std::vector<Row> rows = {{radius, z_lo, 1.0, 0.0, 0.0, false},
                                 {radius, z_hi, 1.0, 0.0, 1.0, false}};
  return Revolver(range, angle_steps(clamp_segments(segments), range.phi_max)).revolve(rows);
}

}  // namespace hrpp
