// Test oracle: every ray against every triangle in double precision, with a bound on the error
// of the float watertight test (host/trace/watertight.h) so a float answer can be judged.
//
// The scene's float vertices and the ray's float origin and direction are the exact geometry;
// double evaluates the same sheared-space edge functions U, V, W and hit distance t as the
// float test with errors ~2^-53 relative, i.e. exactly for our purposes. The float test rounds
// each step at 2^-24, so for each triangle the oracle bounds the float error of U, V, W and t
// (first-order running-error bounds, ×2 margin) and says:
//   kHit    the triangle is hit whatever the float rounding (inside by more than the bound);
//   kMiss   it cannot be hit (outside by more than the bound, t out of [tmin, tmax] by more than
//           its bound, or a degenerate triangle: never in the BVH);
//   kEither the ray passes within the error bound of an edge, a vertex, the range ends or the
//           triangle's plane (edge-on): both answers are right.
// Tolerances, and why: an edge function is a difference of products of sheared coordinates
// a = v − o (each off by ≤ 4ε(|a_x| + |a_y| + |a_z|), ε = 2^-24, from the subtraction and the
// shear), so |U − U_float| ≤ 16ε·|b|₁·|c|₁ (×2 margin: 32ε); t = (U·a_z + V·b_z + W·c_z)/det
// (computed as Σ (U/det)·a_z) inherits those errors plus 8ε of its own. At translated or scaled scenes these bounds scale
// with |v − o|, not with |v|: the watertight test subtracts the origin first.
#pragma once

#include <limits>
#include <vector>

#include "gpu_types.h"
#include "scene/scene.h"

namespace hrpp::test {

enum class Verdict { kHit, kMiss, kEither };

struct OracleHit {
  Verdict verdict = Verdict::kMiss;
  double t = std::numeric_limits<double>::infinity();  // exact distance (when not edge-on)
  double t_tol = 0.0;                                  // bound on the float t's error
};

// One triangle.
OracleHit oracle_triangle(const Triangle& tri, const gpu::Ray& ray);

// A float answer judged against every triangle of the scene. Empty string: acceptable;
// otherwise why not.
//   closest: prim -1 (miss) or the triangle hit and its float t. Acceptable when the triangle
//            is not kMiss, t is within its bound, and no kHit triangle is certainly closer;
//            a miss is acceptable when no triangle is kHit.
//   any:     occluded is acceptable when some triangle is not kMiss; free when none is kHit.
std::string judge_closest(const Scene& scene, const gpu::Ray& ray, const gpu::Hit& hit);
std::string judge_any(const Scene& scene, const gpu::Ray& ray, bool occluded);

}  // namespace hrpp::test
