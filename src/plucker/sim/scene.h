// Procedural scenes of 3D primitives for camera simulation: line segments, points and planes
// arranged as a room, a corridor or a street between building facades. Windows and door frames
// protrude from the walls, so the segments run in all three directions (horizontal along the
// wall, vertical, and in depth along the wall normal). Points are scattered on the planes.
//
// World frame w: z up, floor/ground at z = 0. Planes pi = (m, e) with m . x + e = 0, |m| = 1,
// m pointing into the free space (towards the camera). No I/O, deterministic given the seed.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "plucker/geometry/line_segment.h"

namespace plucker {
namespace sim {

using plucker::LineSegment3;  // world endpoints a_w != b_w (geometry/line_segment.h)

enum class SceneKind { kRoom, kCorridor, kFacades };

// "room" | "corridor" | "facades"; the parse throws std::invalid_argument otherwise.
std::string SceneKindName(SceneKind kind);
SceneKind ParseSceneKind(const std::string& name);

struct Scene {
  SceneKind kind = SceneKind::kRoom;
  std::vector<Eigen::Vector3d> points_w;
  std::vector<int> point_plane_ids;  // points_w[i] lies on planes_w[point_plane_ids[i]]
  std::vector<LineSegment3> segments_w;
  std::vector<Eigen::Vector4d> planes_w;  // (m, e), |m| = 1, m towards the free space
  // Axis-aligned box the camera may move in (inside the room / corridor / street, away from
  // the walls); MakeTrajectory keeps the body position inside it.
  Eigen::AlignedBox3d free_space_w;
};

struct SceneOptions {
  using Kind = SceneKind;
  Kind kind = Kind::kRoom;
  // Extents in metres; 0 selects the kind's default:
  //   room     8 x 6 x 3   (x, y, z; centred on the origin in x, y)
  //   corridor 30 x 2.4 x 2.8 (long axis x)
  //   facades  40 x 12 (street length along x x street width); buildings 6..18 m high.
  double length = 0.0;
  double width = 0.0;
  double height = 0.0;
  // Points scattered on the planes, proportionally to their area; -1 selects the kind's default
  // density (room 3.3, corridor 2.5, facades 1.04 points per m^2: about 600 / 800 / 1500 points
  // at the default sizes; it scales with the size), 0 gives none.
  int num_points = -1;
  double frame_depth = 0.08;  // m, how far window/door frames protrude from the wall
  double wall_margin = 0.8;   // m, free-space distance kept from walls (room, corridor)
};

// Builds a scene; throws std::invalid_argument for non-finite or non-positive sizes or a
// point count below -1.
Scene MakeScene(const SceneOptions& options, std::uint64_t seed);

}  // namespace sim
}  // namespace plucker
