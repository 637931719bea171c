#include "plucker/sim/camera_observations.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "plucker/sensor/fisheye_rig.h"

namespace plucker {
namespace sim {

using Eigen::Vector2d;
using Eigen::Vector3d;

Eigen::Matrix3d DefaultRotationBodyCamera() {
  Eigen::Matrix3d R_b_c;
  // Columns: the camera axes x (right), y (down), z (forward) in body coordinates.
  R_b_c << 0, 0, 1,  //
      -1, 0, 0,      //
      0, -1, 0;
  return R_b_c;
}

SE3d DefaultBodyCameraPose() {
  return CanonicalPose(SE3d(DefaultRotationBodyCamera(), Vector3d(0.05, -0.02, 0.01)));
}

sensor::CameraRig DefaultRig() {
  sensor::CameraRig rig;
  rig.K = PinholeIntrinsics{400.0, 400.0, 319.5, 239.5};
  rig.width = 640;
  rig.height = 480;
  rig.T_b_c = DefaultBodyCameraPose();
  return rig;
}

SE3d StereoPose(double baseline_m) {
  if (!std::isfinite(baseline_m) || baseline_m == 0.0)
    throw std::invalid_argument("stereo: the baseline must be finite and non-zero");
  return SE3d(Eigen::Quaterniond::Identity(), Vector3d(baseline_m, 0.0, 0.0));
}

sensor::CameraRig FisheyeRig(double view_fov_deg, bool points_in_view) {
  if (!(view_fov_deg > 0.0 && view_fov_deg < 170.0)) {
    throw std::invalid_argument("fisheye rig: the view's field of view must be in (0, 170) deg");
  }
  sensor::CameraRig rig;
  rig.K = PinholeIntrinsics{190.97847715128717, 190.9733070521226, 254.93170605935475,
                            256.8974428996504};
  rig.width = 512;
  rig.height = 512;
  rig.T_b_c = DefaultBodyCameraPose();
  sensor::FisheyeView& f = rig.fisheye.emplace();
  f.coeffs = EquidistantDistortion{0.0034823894022493434, 0.0007150348452162257,
                                   -0.0020532361418706202, 0.00020293673591811182};
  const double fx = 256.0 / std::tan(view_fov_deg * M_PI / 360.0);
  f.view_K = PinholeIntrinsics{fx, fx, 255.5, 255.5};
  f.view_width = 512;
  f.view_height = 512;
  f.points_in_view = points_in_view;
  return rig;
}

namespace {

bool IsNormalizationFixedPoint(const Eigen::Quaterniond& q) {
  return SE3d(q, Vector3d::Zero()).rotation().coeffs() == q.coeffs();
}

}  // namespace

SE3d CanonicalPose(const SE3d& T) {
  // SE3d normalises its quaternion; renormalising an already unit quaternion can move its last
  // bits. Iterate to a fixed point; on a 2-cycle, search the coefficients within +-2 ulp.
  Eigen::Quaterniond q = T.rotation();
  for (int i = 0; i < 8 && !IsNormalizationFixedPoint(q); ++i) {
    q = SE3d(q, Vector3d::Zero()).rotation();
  }
  if (IsNormalizationFixedPoint(q)) return SE3d(q, T.translation());
  for (int k = 1; k < 625; ++k) {
    Eigen::Quaterniond candidate = q;
    int code = k;
    for (int c = 0; c < 4; ++c, code /= 5) {
      const int steps = code % 5 - 2;
      double& x = candidate.coeffs()(c);
      for (int s = 0; s < std::abs(steps); ++s) x = std::nextafter(x, steps > 0 ? 2.0 : -2.0);
    }
    if (IsNormalizationFixedPoint(candidate)) return SE3d(candidate, T.translation());
  }
  return SE3d(q, T.translation());  // not reached in practice; within 1 ulp anyway
}

namespace {

// Pixel bounds shrunk by a hair so that rounding never puts a clipped endpoint outside.
constexpr double kBorderEps = 1e-7;

std::uint64_t DeriveSeed(std::uint64_t seed, std::uint64_t stream) {
  // SplitMix64 of the seed advanced by the stream index.
  std::uint64_t z = seed + (stream + 1) * 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

Vector2d Project(const PinholeIntrinsics& K, const Vector3d& p_c) {
  return Vector2d(K.fx * p_c.x() / p_c.z() + K.cx, K.fy * p_c.y() / p_c.z() + K.cy);
}

void ValidateRig(const sensor::CameraRig& rig) {
  if (!rig.K.IsValid() || rig.width < 2 || rig.height < 2 || !rig.T_b_c.translation().allFinite() ||
      !rig.T_b_c.rotation().coeffs().allFinite()) {
    throw std::invalid_argument("camera rig: invalid intrinsics, image size or extrinsic");
  }
  if (rig.fisheye && (!rig.fisheye->coeffs.IsValid() || !rig.fisheye->view_K.IsValid() ||
                      rig.fisheye->view_width < 2 || rig.fisheye->view_height < 2)) {
    throw std::invalid_argument("camera rig: invalid fisheye coefficients or view");
  }
}

// The pinhole in which the segments are observed: the fisheye rig's view, else the rig.
sensor::CameraRig SegmentRig(const sensor::CameraRig& rig) {
  if (!rig.fisheye) return rig;
  sensor::CameraRig view = rig;
  view.K = rig.fisheye->view_K;
  view.width = rig.fisheye->view_width;
  view.height = rig.fisheye->view_height;
  view.fisheye.reset();
  return view;
}

// The noise-free raw pixel of p_w in a fisheye rig's full image, or nullopt (not visible).
std::optional<Vector2d> ProjectVisibleFisheyePoint(const Vector3d& p_w, const SE3d& T_w_c,
                                                   const sensor::Camera& raw, double min_depth,
                                                   double max_depth) {
  const Vector3d p_c = T_w_c.rotation().conjugate() * (p_w - T_w_c.translation());
  if (!(p_c.z() >= min_depth && p_c.z() <= max_depth)) return std::nullopt;
  const auto uv = raw.Project(p_c);
  if (!uv || !(uv->x() >= 0.0 && uv->x() <= raw.width - 1.0 && uv->y() >= 0.0 &&
               uv->y() <= raw.height - 1.0)) {
    return std::nullopt;
  }
  return uv;
}

void ValidateObservationOptions(const ObservationOptions& o) {
  if (!std::isfinite(o.pixel_sigma) || o.pixel_sigma < 0.0) {
    throw std::invalid_argument("observations: pixel_sigma must be finite and >= 0");
  }
  if (!std::isfinite(o.outlier_ratio) || o.outlier_ratio < 0.0 || o.outlier_ratio > 0.9) {
    throw std::invalid_argument("observations: outlier_ratio must be in [0, 0.9]");
  }
  if (!std::isfinite(o.min_segment_px) || o.min_segment_px < 0.0) {
    throw std::invalid_argument("observations: min_segment_px must be finite and >= 0");
  }
  if (!std::isfinite(o.min_depth) || !std::isfinite(o.max_depth) || o.min_depth <= 0.0 ||
      o.max_depth <= o.min_depth) {
    throw std::invalid_argument("observations: need 0 < min_depth < max_depth (finite)");
  }
}

// How many outliers keep outliers / (inliers + outliers) at `ratio` over the sequence so far.
int OutliersDue(double ratio, long long inliers_so_far, long long outliers_so_far) {
  if (ratio <= 0.0) return 0;
  const long long target =
      std::llround(ratio / (1.0 - ratio) * static_cast<double>(inliers_so_far));
  return static_cast<int>(std::max(0LL, target - outliers_so_far));
}

}  // namespace

std::optional<Vector2d> ProjectVisiblePoint(const Vector3d& p_w, const SE3d& T_w_c,
                                            const sensor::CameraRig& rig, double min_depth,
                                            double max_depth) {
  const Vector3d p_c = T_w_c.rotation().conjugate() * (p_w - T_w_c.translation());
  if (!(p_c.z() >= min_depth && p_c.z() <= max_depth)) return std::nullopt;
  const Vector2d uv = Project(rig.K, p_c);
  if (!(uv.x() >= 0.0 && uv.x() <= rig.width - 1.0 && uv.y() >= 0.0 &&
        uv.y() <= rig.height - 1.0)) {
    return std::nullopt;
  }
  return uv;
}

std::optional<ClippedSegment> ClipSegmentToImage(const LineSegment3& segment_w, const SE3d& T_w_c,
                                                 const sensor::CameraRig& rig, double min_depth,
                                                 double max_depth) {
  if (!(min_depth > 0.0) || !(max_depth > min_depth)) return std::nullopt;
  const Eigen::Quaterniond q_c_w = T_w_c.rotation().conjugate();
  const Vector3d A = q_c_w * (segment_w.a_w - T_w_c.translation());
  const Vector3d B = q_c_w * (segment_w.b_w - T_w_c.translation());
  if (!A.allFinite() || !B.allFinite() || (B - A).norm() == 0.0) return std::nullopt;
  const PinholeIntrinsics& K = rig.K;
  const double u_min = kBorderEps, u_max = rig.width - 1.0 - kBorderEps;
  const double v_min = kBorderEps, v_max = rig.height - 1.0 - kBorderEps;
  // Half-spaces g . P + h >= 0 of the frustum (the side planes assume z > 0, which the near
  // plane guarantees on the kept part).
  struct HalfSpace {
    Vector3d g;
    double h;
  };
  const HalfSpace planes[6] = {
      {Vector3d(0, 0, 1), -min_depth},        {Vector3d(0, 0, -1), max_depth},
      {Vector3d(K.fx, 0, K.cx - u_min), 0.0}, {Vector3d(-K.fx, 0, u_max - K.cx), 0.0},
      {Vector3d(0, K.fy, K.cy - v_min), 0.0}, {Vector3d(0, -K.fy, v_max - K.cy), 0.0},
  };
  double s0 = 0.0, s1 = 1.0;
  for (const HalfSpace& hs : planes) {
    const double fa = hs.g.dot(A) + hs.h, fb = hs.g.dot(B) + hs.h;
    if (fa < 0.0 && fb < 0.0) return std::nullopt;
    if (fa >= 0.0 && fb >= 0.0) continue;
    const double s = fa / (fa - fb);
    if (fa < 0.0) {
      s0 = std::max(s0, s);
    } else {
      s1 = std::min(s1, s);
    }
    if (!(s0 < s1)) return std::nullopt;
  }
  ClippedSegment c;
  c.s0 = s0;
  c.s1 = s1;
  c.a_c = A + s0 * (B - A);
  c.b_c = A + s1 * (B - A);
  c.s_px = Project(K, c.a_c);
  c.e_px = Project(K, c.b_c);
  return c;
}

CameraObservations ObserveScene(const Scene& scene, const sensor::CameraRig& rig,
                                const std::vector<SE3d>& T_w_c, const ObservationOptions& options,
                                std::uint64_t seed) {
  ValidateRig(rig);
  ValidateObservationOptions(options);
  const sensor::CameraRig seg_rig = SegmentRig(rig);  // = rig without a fisheye
  const bool raw_points = rig.fisheye && !rig.fisheye->points_in_view;
  const sensor::CameraRig& point_rig = raw_points ? rig : seg_rig;
  const sensor::Camera raw_camera = sensor::RawCamera(rig);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform_u(0.0, point_rig.width - 1.0);
  std::uniform_real_distribution<double> uniform_v(0.0, point_rig.height - 1.0);
  std::uniform_real_distribution<double> seg_u(0.0, seg_rig.width - 1.0);
  std::uniform_real_distribution<double> seg_v(0.0, seg_rig.height - 1.0);
  auto noise = [&] {
    const double x = normal(rng), y = normal(rng);
    return Vector2d(options.pixel_sigma * x, options.pixel_sigma * y);
  };
  auto random_pixel = [&] {
    const double u = uniform_u(rng), v = uniform_v(rng);
    return Vector2d(u, v);
  };
  auto random_segment_pixel = [&] {
    const double u = seg_u(rng), v = seg_v(rng);
    return Vector2d(u, v);
  };

  CameraObservations out;
  ObservationStats& st = out.stats;
  for (int frame = 0; frame < static_cast<int>(T_w_c.size()); ++frame) {
    const SE3d& T = T_w_c[frame];
    if (options.observe_points) {
      for (int id = 0; id < static_cast<int>(scene.points_w.size()); ++id) {
        const auto uv = raw_points
                            ? ProjectVisibleFisheyePoint(scene.points_w[id], T, raw_camera,
                                                         options.min_depth, options.max_depth)
                            : ProjectVisiblePoint(scene.points_w[id], T, point_rig,
                                                  options.min_depth, options.max_depth);
        if (!uv) continue;
        out.points.push_back({frame, id, *uv + noise()});
        ++st.num_point_inliers;
      }
      const int n_out =
          OutliersDue(options.outlier_ratio, st.num_point_inliers, st.num_point_outliers);
      for (int k = 0; k < n_out; ++k) {
        out.points.push_back({frame, -1, random_pixel()});
        ++st.num_point_outliers;
      }
    }
    if (options.observe_segments) {
      for (int id = 0; id < static_cast<int>(scene.segments_w.size()); ++id) {
        const auto clipped = ClipSegmentToImage(scene.segments_w[id], T, seg_rig, options.min_depth,
                                                options.max_depth);
        if (!clipped || (clipped->e_px - clipped->s_px).norm() < options.min_segment_px) continue;
        const Vector2d ns = noise(), ne = noise();
        out.segments.push_back({frame, id, clipped->s_px + ns, clipped->e_px + ne});
        ++st.num_segment_inliers;
      }
      const int n_out =
          OutliersDue(options.outlier_ratio, st.num_segment_inliers, st.num_segment_outliers);
      for (int k = 0; k < n_out; ++k) {
        // Uniform endpoints, redrawn (a bounded number of times) until long enough.
        Vector2d s = random_segment_pixel(), e = random_segment_pixel();
        for (int attempt = 0; attempt < 100 && (e - s).norm() < options.min_segment_px; ++attempt) {
          s = random_segment_pixel();
          e = random_segment_pixel();
        }
        out.segments.push_back({frame, -1, s, e});
        ++st.num_segment_outliers;
      }
    }
  }
  return out;
}

CameraSimulation SimulateCamera(const CameraSimulationOptions& options) {
  if (options.num_frames < 1) throw std::invalid_argument("SimulateCamera: num_frames < 1");
  if (!std::isfinite(options.frame_rate_hz) || options.frame_rate_hz <= 0.0) {
    throw std::invalid_argument("SimulateCamera: frame_rate_hz must be finite and positive");
  }
  ValidateRig(options.rig);
  ValidateObservationOptions(options.obs);

  CameraSimulation sim;
  sim.scene = MakeScene(options.scene, DeriveSeed(options.seed, 0));
  sim.rig = options.rig;
  sim.rig.T_b_c = CanonicalPose(options.rig.T_b_c);
  sim.imu_options = options.imu;
  sim.obs_options = options.obs;

  TrajectoryOptions trajectory_options = options.trajectory;
  trajectory_options.duration = (options.num_frames - 1) / options.frame_rate_hz;
  const Trajectory trajectory =
      MakeTrajectory(trajectory_options, sim.scene, DeriveSeed(options.seed, 1));
  for (int i = 0; i < options.num_frames; ++i) {
    const double t = i / options.frame_rate_hz;
    sim.frame_times.push_back(t);
    sim.T_w_b_gt.push_back(CanonicalPose(trajectory.T_w_b(t)));
    sim.T_w_c_gt.push_back(CanonicalPose(sim.T_w_b_gt.back() * sim.rig.T_b_c));
    sim.v_w_gt.push_back(trajectory.velocity_w(t));
  }
  if (options.simulate_imu) {
    sim.imu = SimulateImu(trajectory, options.imu, DeriveSeed(options.seed, 2));
  }
  CameraObservations obs =
      ObserveScene(sim.scene, sim.rig, sim.T_w_c_gt, options.obs, DeriveSeed(options.seed, 3));
  sim.points = std::move(obs.points);
  sim.segments = std::move(obs.segments);
  sim.stats = obs.stats;
  if (options.T_c0_c1) {
    if (options.rig.fisheye) throw std::invalid_argument("SimulateCamera: stereo needs a pinhole");
    const SE3d T_c0_c1 = CanonicalPose(*options.T_c0_c1);
    std::vector<SE3d> T_w_c1;
    for (const SE3d& T_w_c0 : sim.T_w_c_gt) T_w_c1.push_back(T_w_c0 * T_c0_c1);
    CameraObservations right =
        ObserveScene(sim.scene, sim.rig, T_w_c1, options.obs, DeriveSeed(options.seed, 4));
    sim.cam1 = sensor::SecondCamera{T_c0_c1, std::move(right.points), std::move(right.segments)};
    sim.cam1_stats = right.stats;
  }
  return sim;
}

sensor::CameraImuSequence ToCameraImuSequence(const CameraSimulation& simulation) {
  sensor::CameraImuSequence out;
  out.rig = simulation.rig;
  out.imu_model = simulation.imu_options.model;
  out.observation_model = simulation.obs_options;
  out.gravity_w = simulation.imu_options.gravity_w;
  out.frame_times = simulation.frame_times;
  out.imu = simulation.imu;
  out.points = simulation.points;
  out.segments = simulation.segments;
  out.cam1 = simulation.cam1;
  sensor::CameraImuGroundTruth& gt = out.ground_truth.emplace();
  gt.T_w_c = simulation.T_w_c_gt;
  gt.T_w_b = simulation.T_w_b_gt;
  gt.v_w = simulation.v_w_gt;
  gt.initial_gyro_bias = simulation.imu_options.initial_gyro_bias;
  gt.initial_accel_bias = simulation.imu_options.initial_accel_bias;
  const Scene& scene = simulation.scene;
  gt.scene_kind = SceneKindName(scene.kind);
  gt.points_w = scene.points_w;
  gt.point_plane_ids = scene.point_plane_ids;
  gt.segments_w = scene.segments_w;
  gt.planes_w = scene.planes_w;
  gt.free_space_w = scene.free_space_w;
  return out;
}

MotionStats MeasureMotion(const CameraSimulation& simulation) {
  MotionStats m;
  for (const Eigen::Vector3d& v : simulation.v_w_gt) m.max_speed = std::max(m.max_speed, v.norm());
  const std::vector<SE3d>& T = simulation.T_w_b_gt;
  for (std::size_t i = 1; i < T.size(); ++i) {
    const double dt = simulation.frame_times[i] - simulation.frame_times[i - 1];
    const double angle = LogSO3<double>(T[i - 1].rotation().conjugate() * T[i].rotation()).norm();
    if (dt > 0.0) m.max_turn_rate = std::max(m.max_turn_rate, angle / dt);
  }
  return m;
}

}  // namespace sim
}  // namespace plucker
