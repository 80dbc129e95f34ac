// Triangle meshes for pbrt-v4's analytic shapes "sphere", "disk" and "cylinder", in object space,
// with pbrt-v4's parameters, (u, v) and default orientation (src/pbrt/shapes.h and shapes.cpp:
// Sphere, Disk, Cylinder, their Create and InteractionFromIntersection).
//
// Parameters as pbrt reads them (its defaults in brackets; the caller fills them in):
//   sphere   radius [1], zmin [-radius], zmax [radius], phimax [360]: z clamped to
//            [-radius, radius] and ordered; u = phi/phimax, v = (theta - theta(zmin)) /
//            (theta(zmax) - theta(zmin)) with theta = acos(z/radius), so v = 0 at zmin.
//   cylinder radius [1], zmin [-1], zmax [1], phimax [360]: z ordered; u = phi/phimax,
//            v = (z - zmin)/(zmax - zmin).
//   disk     height [0], radius [1], innerradius [0], phimax [360]: at z = height, the hole is
//            |innerradius| (pbrt tests r^2 against innerradius^2); u = phi/phimax,
//            v = (radius - r)/(radius - innerradius), so v = 0 on the rim.
//   phimax is clamped to [0, 360] degrees. A shape with no area (phimax 0, zmin = zmax, a hole
//   as large as the disk) or a radius that is not positive (pbrt's formulas give accidents there)
//   makes an empty mesh.
//
// Orientation: pbrt's surface normal is normalize(cross(dpdu, dpdv)): outward (away from the z
// axis, or from the centre) for the sphere and cylinder, +z for the disk. Vertex normals are that
// normal (unit length), and every triangle is counter-clockwise seen from the side it points to.
// ReverseOrientation and a handedness-swapping transform are the caller's.
//
// Tessellation: a grid in (phi, theta) for the sphere, (phi, z) for the cylinder and (phi, r) for
// the disk, with vertices on the true surface. A full turn is cut into `segments` equal angle
// steps; a partial phi range or theta range takes ceil(segments · range / 2π) steps (at least
// one; at least two in theta when the sphere has both poles). The cylinder needs one band in z
// and the disk one ring in r: they are ruled along those directions. A pole (or the disk's centre)
// is a fan: one apex vertex per segment, at u of the segment's middle, so no triangle is
// degenerate. At a full turn the seam's two columns have bit-identical positions.
//
// Error rule: a chord that spans the angle θ on a circle of radius r sags r(1 - cos(θ/2)) below
// it. The worst chord of the sphere's grid is a cell diagonal, which spans at most √2·Δ for the
// step Δ = 2π/segments, so quadric_segments(f) is the least n with 1 - cos(π√2/n) <= f:
// n = ceil(π√2 / acos(1 - f)), 100 for f = 1e-3 (a sag of 0.99e-3 r). The cylinder's and disk's
// chords span one step and sag half as much. `segments` below 3 count as 3.
#pragma once

#include "scene/indexed_mesh.h"

namespace hrpp {

// The largest distance between a quadric and its triangles, as a fraction of the radius, that an
// image cannot tell from the true surface.
inline constexpr float kQuadricMaxSag = 1e-3f;

// Segments per full turn for a sag of at most max_sag_fraction · radius (3 to 65536).
int quadric_segments(float max_sag_fraction = kQuadricMaxSag);

IndexedMesh tessellate_sphere(float radius, float zmin, float zmax, float phimax_degrees,
                              int segments);
IndexedMesh tessellate_disk(float height, float radius, float innerradius, float phimax_degrees,
                            int segments);
IndexedMesh tessellate_cylinder(float radius, float zmin, float zmax, float phimax_degrees,
                                int segments);

}  // namespace hrpp
