// Triangulation of a 3D line (and of the observed 3D segment) from line segments observed in
// several calibrated views (ideal, undistorted pixels).
// Derivations: docs/math/projection-triangulation.md.
//
// Every observed segment (s, e) back-projects to a plane through the camera centre containing the
// 3D line: in the camera frame its normal is n_c = K^-1 s~ x K^-1 e~ (the image line), in the world
// pi_w = (m, -m . t) with m = R n_c / |R n_c|, so that m . x + e = 0 (docs/conventions.md).
//  - Two views: the line is the intersection of the two planes (LineFromPlanes).
//  - N views: the planes, stacked as rows of an N x 4 matrix, share the line as null space: the
//    right singular vectors of the two smallest singular values are two homogeneous points of it.
// The angle between two planes is measured with |cos| (acos(|m_i . m_j|) in [0, pi/2]) so that the
// endpoint order of a segment (which flips the sign of its normal) never matters.
//  - Refinement (RefineLine, TriangulateLineRefined): Levenberg-Marquardt on the line manifold
//    (orthonormal representation, 4 parameters, geometry/orthonormal_line.h) of the endpoint-to-
//    line distances in pixels, the residual of the analytic line factor; its Jacobian is the chain
//    of the tested links (orthonormal -> Plücker, world -> camera, projection, endpoint distance).
//    It lives here (Eigen only) rather than in ba (Ceres): with the cameras fixed the problem is
//    one 4x4 normal equation per line, which the front end and the evaluation call thousands of
//    times without a solver; ba's LineManifold keeps the joint adjustment.
//
// Conditioning (forward motion along a line): when every camera centre lies (nearly) in one
// plane with the line, all back-projected planes coincide and the line is undefined inside it.
// The test is the largest angle between two back-projected planes (the best-conditioned pair;
// the smallest angle is always small between neighbouring frames and says nothing). A plane's
// normal is uncertain by about sigma / f rad (sigma px of endpoint noise, focal f px: 1/707 rad =
// 0.08 deg on KITTI), and the depth of the intersection by about (sigma / f) / angle relative: at
// the default 2 deg that is 4 % on KITTI at 1 px, 1 % on Strecha (f = 2760). Below 2 deg the
// triangulated lines are dominated by noise (line_triangulation_test.cc measures it), and the
// N-view sigma3 / sigma2 test catches views that disagree.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/geometry/se3.h"

namespace plucker {

// One observed segment: camera pose and the two endpoints in ideal pixels.
struct LineObservation {
  SE3d T_w_c;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d end = Eigen::Vector2d::Zero();
};

struct LineTriangulationOptions {
  double min_plane_angle_deg = 2.0;    // the largest angle between two back-projected planes must
                                       // reach this (two-view: the only pair), else kSmallParallax;
                                       // a floor of 1e-8 rad always applies
  double max_sigma_ratio = 0.5;        // N-view: reject when sigma3 / sigma2 exceeds this
  double min_segment_length_px = 1.0;  // shorter observed segments are rejected (kInvalidInput)
  double min_depth = 1e-3;  // the 3D endpoints must be this far in front of each camera (m)
};

struct LineRefinementOptions {
  int max_iterations = 30;
  double initial_lambda = 1e-4;        // Levenberg-Marquardt damping, relative to the diagonal
  double parameter_tolerance = 1e-10;  // stop when |delta| (rad) falls below this
  double cost_tolerance = 1e-12;       // or when the cost decreases by less than this, relatively
};

enum class LineTriangulationStatus {
  kOk,
  kInvalidInput,        // non-finite input, invalid intrinsics, too-short segment
  kTooFewViews,         // fewer than two observations
  kSmallParallax,       // back-projected planes (nearly) coincide: max plane angle < minimum
  kIllConditioned,      // N-view: sigma3 / sigma2 above max_sigma_ratio (no clear 2D null space)
  kBehindCamera,        // an endpoint ray meets the line behind (or too close to) its camera
  kDegenerateEndpoint,  // an endpoint ray is parallel to the 3D line (no closest point)
};
const char* ToString(LineTriangulationStatus status);

struct LineTriangulationResult {
  LineTriangulationStatus status = LineTriangulationStatus::kInvalidInput;
  std::string message;  // reason when status != kOk
  // The line, normalised so that |d| = 1 (|n| = distance from the origin), d oriented from the
  // start towards the end endpoint of the first observation. Valid when ok().
  Line6d L_w = Line6d::Zero();
  // 3D segment: the extent along d of the endpoints recovered in every view (their union),
  // ordered along d. Valid when ok().
  Eigen::Vector3d start_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_w = Eigen::Vector3d::Zero();
  // Conditioning of the N-view system: sigma3 / sigma2 of the stacked plane matrix (0 for exact
  // data and for the two-view method; near 1 when the planes do not define a unique line).
  double sigma_ratio = 0.0;
  double min_parallax_rad = 0.0;  // smallest / largest pairwise plane angle, in [0, pi/2]
  double max_parallax_rad = 0.0;
  // Endpoint-to-line distances of every observation to the returned line [px] (RMS over the 2N
  // endpoint distances and the largest one). Valid when ok().
  double rms_error_px = 0.0;
  double max_error_px = 0.0;
  int refine_iterations = 0;  // TriangulateLineRefined: accepted Levenberg-Marquardt steps
  bool ok() const { return status == LineTriangulationStatus::kOk; }
};

// The world plane (m, e), |m| = 1, m . x + e = 0, through the camera centre and the observed
// segment. nullopt for non-finite input or a segment shorter than min_length_px.
std::optional<Eigen::Vector4d> BackProjectSegment(const PinholeIntrinsics& K, const SE3d& T_w_c,
                                                  const Eigen::Vector2d& start,
                                                  const Eigen::Vector2d& end,
                                                  double min_length_px = 1.0);

// Angle between two planes' normals as unoriented lines, acos(|m1 . m2| / |m1||m2|), in [0, pi/2].
double PlaneAngle(const Eigen::Vector4d& pi1, const Eigen::Vector4d& pi2);

// Two-view triangulation by plane intersection.
LineTriangulationResult TriangulateLineTwoView(const PinholeIntrinsics& K, const LineObservation& a,
                                               const LineObservation& b,
                                               const LineTriangulationOptions& options = {});

// N-view linear triangulation (SVD of the stacked planes), N >= 2.
LineTriangulationResult TriangulateLine(const PinholeIntrinsics& K,
                                        const std::vector<LineObservation>& observations,
                                        const LineTriangulationOptions& options = {});

// Endpoint-to-line distances [px] of every observation (start, end per view) to L_w, in the
// order of the observations; nullopt when the line projects to a point in some view or the input
// is non-finite.
std::optional<Eigen::VectorXd> LineReprojectionErrors(const PinholeIntrinsics& K,
                                                      const std::vector<LineObservation>& obs,
                                                      const Line6d& L_w);

struct LineRefinement {
  Line6d L_w = Line6d::Zero();  // |L| = 1 (orthonormal scale); normalise the direction as needed
  double initial_cost = 0.0;    // 0.5 * sum of squared endpoint distances [px^2]
  double final_cost = 0.0;
  int iterations = 0;  // accepted steps
  bool converged = false;
};

// Levenberg-Marquardt on the line manifold from L_w_init, cameras fixed. nullopt for invalid
// input (invalid K, a non-finite value, a line through a camera centre or |d| = 0).
std::optional<LineRefinement> RefineLine(const PinholeIntrinsics& K,
                                         const std::vector<LineObservation>& observations,
                                         const Line6d& L_w_init,
                                         const LineRefinementOptions& options = {});

// Linear N-view triangulation (with its parallax and conditioning tests), then RefineLine, then
// the 3D segment from the observed endpoints; rms/max_error_px of the refined line.
LineTriangulationResult TriangulateLineRefined(const PinholeIntrinsics& K,
                                               const std::vector<LineObservation>& observations,
                                               const LineTriangulationOptions& options = {},
                                               const LineRefinementOptions& refinement = {});

// Two-view triangulation from the pair of observations with the largest plane angle (|cos|).
// Returns the indices used in *pair when non-null.
LineTriangulationResult TriangulateLineBestPair(const PinholeIntrinsics& K,
                                                const std::vector<LineObservation>& observations,
                                                const LineTriangulationOptions& options = {},
                                                std::pair<int, int>* pair = nullptr);

// The 3D points of L_w closest to the back-projected rays of the observed endpoints, with the ray
// depths (the distance along each unit ray). nullopt when an endpoint ray is parallel to the line
// or the input is non-finite. The caller checks the depths for cheirality.
struct SegmentEndpoints {
  Eigen::Vector3d start_w, end_w;
  double start_depth = 0.0, end_depth = 0.0;
};
std::optional<SegmentEndpoints> SegmentEndpointsOnLine(const PinholeIntrinsics& K,
                                                       const LineObservation& observation,
                                                       const Line6d& L_w);

}  // namespace plucker
