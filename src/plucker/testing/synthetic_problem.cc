#include "plucker/testing/synthetic_problem.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

namespace plucker {
namespace ba {

namespace {

Eigen::Vector3d Gaussian3(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return Eigen::Vector3d(n(rng), n(rng), n(rng));
}

// Largest angle between two unit vectors of the list, sign-free when `unsigned_angle`.
double MaxPairAngleDeg(const std::vector<Eigen::Vector3d>& v, bool unsigned_angle) {
  double min_cos = 1.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    for (std::size_t j = i + 1; j < v.size(); ++j) {
      const double c = v[i].dot(v[j]);
      min_cos = std::min(min_cos, unsigned_angle ? std::abs(c) : c);
    }
  }
  return std::acos(std::clamp(min_cos, -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

SyntheticProblem MakeSyntheticProblem(const SyntheticProblemOptions& options) {
  SyntheticProblem p;
  p.simulation = sim::SimulateCamera(options.simulation);
  const sim::CameraSimulation& s = p.simulation;
  std::mt19937_64 rng(options.seed);

  // Count inlier observations per structure element; keep the well-observed ones.
  std::map<int, std::vector<Eigen::Vector3d>> point_rays, line_normals;
  for (const auto& o : s.points) {
    if (o.point_id < 0) continue;
    const Eigen::Vector3d c_w = s.T_w_c_gt[o.frame].translation();
    point_rays[o.point_id].push_back((s.scene.points_w[o.point_id] - c_w).normalized());
  }
  for (const auto& o : s.segments) {
    if (o.line_id < 0) continue;
    const Eigen::Vector3d c_w = s.T_w_c_gt[o.frame].translation();
    const sim::LineSegment3& seg = s.scene.segments_w[o.line_id];
    line_normals[o.line_id].push_back((seg.a_w - c_w).cross(seg.b_w - c_w).normalized());
  }
  std::map<int, int> point_index, line_index;  // simulation id -> problem index
  for (const auto& [id, rays] : point_rays) {
    if (static_cast<int>(rays.size()) < options.min_observations ||
        MaxPairAngleDeg(rays, false) < options.min_point_parallax_deg) {
      continue;
    }
    point_index[id] = static_cast<int>(p.points_gt.size());
    p.points_gt.push_back(s.scene.points_w[id]);
    p.initial.points_w.push_back(s.scene.points_w[id] + Gaussian3(rng, options.point_noise_m));
  }
  for (const auto& [id, normals] : line_normals) {
    if (static_cast<int>(normals.size()) < options.min_observations ||
        MaxPairAngleDeg(normals, true) < options.min_line_parallax_deg) {
      continue;
    }
    const sim::LineSegment3& seg = s.scene.segments_w[id];
    line_index[id] = static_cast<int>(p.segments_gt.size());
    p.segments_gt.push_back({seg.a_w, seg.b_w});
    const Eigen::Vector3d a = seg.a_w + Gaussian3(rng, options.line_endpoint_noise_m);
    const Eigen::Vector3d b = seg.b_w + Gaussian3(rng, options.line_endpoint_noise_m);
    p.initial.lines_w.push_back(LineFromPoints<double>(a, b));
  }

  p.initial.K = s.rig.K;
  p.T_w_c_gt = s.T_w_c_gt;
  for (std::size_t i = 0; i < s.T_w_c_gt.size(); ++i) {
    if (static_cast<int>(i) < options.num_fixed_poses) {
      p.initial.T_w_c.push_back(s.T_w_c_gt[i]);
      continue;
    }
    Vector6d delta;
    delta << Gaussian3(rng, options.rotation_noise_deg * M_PI / 180.0),
        Gaussian3(rng, options.translation_noise_m);
    p.initial.T_w_c.push_back(s.T_w_c_gt[i].Plus(delta));
  }
  for (const auto& o : s.points) {
    const auto it = point_index.find(o.point_id);
    if (it != point_index.end())
      p.initial.point_observations.push_back({o.frame, it->second, o.uv});
  }
  for (const auto& o : s.segments) {
    const auto it = line_index.find(o.line_id);
    if (it != line_index.end()) {
      p.initial.line_observations.push_back({o.frame, it->second, o.s_px, o.e_px});
    }
  }
  return p;
}

ProblemAccuracy Evaluate(const SyntheticProblem& problem, const BundleAdjustmentData& state,
                         eval::AlignmentMode alignment) {
  return CompareToGroundTruth(state, problem.T_w_c_gt, problem.points_gt, problem.segments_gt,
                              alignment);
}

}  // namespace ba
}  // namespace plucker
