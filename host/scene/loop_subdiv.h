// Loop subdivision of a triangle control mesh: the triangles pbrt-v4 makes for Shape "loopsubdiv"
// (src/pbrt/util/loopsubdiv.cpp, LoopSubdivide), reimplemented on index arrays.
//
// Rules, as pbrt applies them at each of `levels` refinements (no crease or corner rules):
//   - boundary and valence come from walking the faces around a vertex from its start face (the
//     last control triangle that names it), so a vertex where two fans meet sees only one fan;
//   - even (old) vertex: interior p(1 - n·beta) + beta·(each neighbour), beta = 3/16 for
//     valence 3 and 3/(8n) otherwise; boundary 3/4 p + 1/8 each of its two boundary neighbours;
//   - odd (edge) vertex: 3/8, 3/8 for the ends and 1/8, 1/8 for the two opposite corners, or the
//     midpoint on a boundary edge;
//   - then, also at levels 0, every vertex goes to the limit surface: interior weight
//     gamma = 1/(n + 3/(8·beta)) per neighbour and 1 - n·gamma for itself; boundary 1/5 for each
//     boundary neighbour and 3/5 for itself;
//   - normals are pbrt's cross(S, T) of the limit tangents (not normalised: pbrt interpolates them
//     as they are and normalises afterwards, as hrpp's shader does).
// Vertices come out in pbrt's order: the children of the previous level's vertices in their
// order, then one new vertex per edge in the order the triangles meet their edges; triangle k is
// pbrt's triangle k (child c of triangle t is 4t + c: the corners at v0, v1, v2, then the middle).
//
// Orientation. pbrt's limit normals point to the side from which the triangle's corners run
// clockwise: for a control mesh wound counter-clockwise seen from outside they point inward.
// pbrt makes a mesh's normals authoritative (Triangle::InteractionFromIntersection turns the
// geometric normal to the interpolated normal), so the side they point to is the one pbrt treats
// as outside (glass, one-sided area lights). IndexedMesh's front is the counter-clockwise side, so
// each triangle is returned as pbrt's (v0, v2, v1): the winding agrees with pbrt's normals. The
// caller applies ReverseOrientation and the transform as for any mesh with normals.
//
// Bad input. pbrt links the triangles of an edge through a std::set keyed by the unordered
// vertex pair: the first triangle inserts the edge, the second links to it and erases it
// ("edges.erase(e);", loopsubdiv.cpp line 179 at pbrt-v4 commit 5f7a6068), so a third triangle on
// the same edge starts a new unpaired (boundary) edge, or pairs with a fourth, silently. The
// pairing never checks that the two triangles run the edge in opposite directions; with
// inconsistent orientation the face walks go wrong (two triangles (0 1 2), (0 1 3) loop forever).
// We refuse both as
//   "<where>: loopsubdiv: non-manifold edge between vertices A and B (...)".
// We also refuse: no triangles, an index count not a multiple of 3 (pbrt drops the remainder), an
// index out of range, a triangle that repeats a vertex, a point no triangle uses (pbrt follows a
// null start face there), a negative level, more than 10 levels, and a result over 2^30 triangles.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/indexed_mesh.h"

namespace hrpp {

inline constexpr int kMaxLoopLevels = 10;

// The limit-surface mesh after `levels` refinements of the control mesh (indices: three per
// triangle). Positions and normals are in the control points' space; no uvs, no materials.
// Throws hrpp::Error with a one-line message starting with `where` on bad input.
IndexedMesh loop_subdivide(const std::vector<glm::vec3>& control_points,
                           const std::vector<std::uint32_t>& indices, int levels,
                           const std::string& where);

}  // namespace hrpp
