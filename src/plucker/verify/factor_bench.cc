#include "plucker/verify/factor_bench.h"

#include <time.h>
#include <algorithm>

#include <limits>

#include "plucker/factors/imu_factor.h"
#include "plucker/factors/lidar_factors.h"
#include "plucker/factors/line_reprojection_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/geometry/plucker_line.h"
#include "plucker/verify/imu_factor_sample.h"
#include "plucker/verify/lidar_comparison_factors.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

volatile double g_sink = 0.0;  // keeps the benchmarked results observable

// CPU time of the calling thread [ns]: unlike wall time it does not count the time the thread
// waits for a core, so it stays meaningful on a loaded, shared machine.
double ThreadCpuNs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e9 * static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec);
}

std::vector<double> PoseBlock(const SE3d& T) {
  std::vector<double> p(7);
  T.ToParameters(p.data());
  return p;
}

std::vector<double> PointBlock(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

PinholeIntrinsics BenchCamera(Rng& rng) {
  PinholeIntrinsics K;
  K.fx = Uniform(rng, 450.0, 750.0);
  K.fy = K.fx * Uniform(rng, 0.98, 1.02);
  K.cx = Uniform(rng, 300.0, 340.0);
  K.cy = Uniform(rng, 220.0, 260.0);
  return K;
}

// A point in front of the camera: depth 1..30 m inside a 90 degree field of view.
Eigen::Vector3d PointInView(Rng& rng) {
  const double z = Uniform(rng, 1.0, 30.0);
  return Eigen::Vector3d(Uniform(rng, -0.8, 0.8) * z, Uniform(rng, -0.6, 0.6) * z, z);
}

Eigen::Matrix2d SqrtInformation(Rng& rng) {
  Eigen::Matrix2d S;
  S << 1.0 / Uniform(rng, 0.5, 2.0), Uniform(rng, -0.1, 0.1), 0.0, 1.0 / Uniform(rng, 0.5, 2.0);
  return S;
}

// LiDAR factors: a scan pose, a scan point within 40 m, features within 1 m of its world position.
template <typename Create, typename CreateAutoDiff>
FactorBenchCase LidarCase(const std::string& name, double flops, Rng& rng, bool plane,
                          Create create, CreateAutoDiff create_autodiff) {
  FactorBenchCase c;
  c.name = name;
  c.flops_estimate = flops;
  c.target_ratio = 2.0;
  for (int i = 0; i < kFactorBenchInputs; ++i) {
    const SE3d T_w_s = RandomPose(rng, 50.0);
    const Eigen::Vector3d p_s = RandomVector(rng, 40.0);
    const Eigen::Vector3d p_w = T_w_s * p_s;
    const Eigen::Vector3d a = p_w + RandomVector(rng, 1.0);
    const Eigen::Vector3d b =
        plane ? Eigen::Vector3d(RandomUnitVector(rng)) : Eigen::Vector3d(a + RandomUnitVector(rng));
    const double sigma = Uniform(rng, 0.05, 0.2);
    // Plane: (p_s, m = b, q = a); edges: (p_s, a, b).
    c.analytic.emplace_back(plane ? create(p_s, b, a, sigma) : create(p_s, a, b, sigma));
    c.autodiff.emplace_back(plane ? create_autodiff(p_s, b, a, sigma)
                                  : create_autodiff(p_s, a, b, sigma));
    c.parameters.push_back({PoseBlock(T_w_s)});
  }
  return c;
}

FactorBenchCase PointCase(Rng& rng, bool vi) {
  FactorBenchCase c;
  c.name = vi ? "PointReprojectionVI" : "PointReprojection";
  c.flops_estimate = vi ? 380.0 : 210.0;
  c.target_ratio = 2.0;
  for (int i = 0; i < kFactorBenchInputs; ++i) {
    const PinholeIntrinsics K = BenchCamera(rng);
    const SE3d T_w_b = RandomPose(rng, 20.0), T_b_c = RandomPose(rng, 0.3);
    const Eigen::Vector3d p_c = PointInView(rng);
    const SE3d T_w_c = vi ? T_w_b * T_b_c : T_w_b;
    const Eigen::Vector2d uv =
        K.ToPixel<double>(p_c.head<2>() / p_c.z()) + RandomVector(rng, 2.0).head<2>();
    const Eigen::Matrix2d S = SqrtInformation(rng);
    if (vi) {
      c.analytic.emplace_back(PointReprojectionFactorVI::Create(K, uv, S));
      c.autodiff.emplace_back(PointReprojectionFactorVI::CreateAutoDiff(K, uv, S));
      c.parameters.push_back({PoseBlock(T_w_b), PoseBlock(T_b_c), PointBlock(T_w_c * p_c)});
    } else {
      c.analytic.emplace_back(PointReprojectionFactor::Create(K, uv, S));
      c.autodiff.emplace_back(PointReprojectionFactor::CreateAutoDiff(K, uv, S));
      c.parameters.push_back({PoseBlock(T_w_c), PointBlock(T_w_c * p_c)});
    }
  }
  return c;
}

FactorBenchCase LineCase(Rng& rng, bool vi) {
  FactorBenchCase c;
  c.name = vi ? "LineReprojectionVI" : "LineReprojection";
  c.flops_estimate = vi ? 900.0 : 600.0;
  c.target_ratio = 3.0;
  while (static_cast<int>(c.analytic.size()) < kFactorBenchInputs) {
    const PinholeIntrinsics K = BenchCamera(rng);
    const SE3d T_w_b = RandomPose(rng, 20.0), T_b_c = RandomPose(rng, 0.3);
    const SE3d T_w_c = vi ? T_w_b * T_b_c : T_w_b;
    // A segment seen by the camera: two points in view, observed with a few pixels of noise.
    const Eigen::Vector3d p1_c = PointInView(rng), p2_c = PointInView(rng);
    const Eigen::Vector2d s =
        K.ToPixel<double>(p1_c.head<2>() / p1_c.z()) + RandomVector(rng, 2.0).head<2>();
    const Eigen::Vector2d e =
        K.ToPixel<double>(p2_c.head<2>() / p2_c.z()) + RandomVector(rng, 2.0).head<2>();
    const std::optional<OrthonormalLine> line =
        OrthonormalFromPlucker(LineFromPoints<double>(T_w_c * p1_c, T_w_c * p2_c));
    if (!line || (e - s).norm() < 10.0) continue;
    std::vector<double> line_block(6);
    line->ToParameters(line_block.data());
    const Eigen::Matrix2d S = SqrtInformation(rng);
    if (vi) {
      c.analytic.emplace_back(LineReprojectionFactorVI::Create(K, s, e, S));
      c.autodiff.emplace_back(LineReprojectionFactorVI::CreateAutoDiff(K, s, e, S));
      c.parameters.push_back({PoseBlock(T_w_b), PoseBlock(T_b_c), line_block});
    } else {
      c.analytic.emplace_back(LineReprojectionFactor::Create(K, s, e, S));
      c.autodiff.emplace_back(LineReprojectionFactor::CreateAutoDiff(K, s, e, S));
      c.parameters.push_back({PoseBlock(T_w_c), line_block});
    }
  }
  return c;
}

// ns per evaluation of one version: best of `rounds` rounds (the machine may be shared).
FactorBenchCase ImuCase(Rng& rng) {
  FactorBenchCase c;
  c.name = "ImuPreintegration";
  c.flops_estimate = 8000.0;  // mostly whitening: 15x9 by 9x(6+3+6+6+3) multiply-adds
  c.target_ratio = 2.0;
  for (int i = 0; i < kFactorBenchInputs; ++i) {
    const ImuFactorSample s = MakeImuFactorSample(rng, 6 + i);
    c.analytic.emplace_back(ImuFactor::Create(s.preintegration, kImuSampleGravity));
    c.autodiff.emplace_back(ImuFactor::CreateAutoDiff(s.preintegration, kImuSampleGravity));
    c.parameters.push_back({PoseBlock(s.T_w_b_i),
                            {s.v_i.data(), s.v_i.data() + 3},
                            {s.bias_i.data(), s.bias_i.data() + 6},
                            PoseBlock(s.T_w_b_j),
                            {s.v_j.data(), s.v_j.data() + 3},
                            {s.bias_j.data(), s.bias_j.data() + 6}});
  }
  return c;
}

double TimeCase(const FactorBenchCase& c, bool analytic, int evaluations) {
  FactorBenchBuffers buffers(*c.analytic.front());
  const int n = static_cast<int>(c.parameters.size());
  std::vector<std::vector<const double*>> params(n);
  for (int i = 0; i < n; ++i)
    for (const auto& block : c.parameters[i]) params[i].push_back(block.data());
  const auto& functions = analytic ? c.analytic : c.autodiff;
  double sum = 0.0;
  auto run = [&](int count) {
    for (int k = 0, i = 0; k < count; ++k, i = (i + 1 == n ? 0 : i + 1)) {
      functions[i]->Evaluate(params[i].data(), buffers.residuals(), buffers.jacobians());
      sum += buffers.Checksum();
    }
  };
  run(std::min(evaluations, 4 * n));  // warm-up
  constexpr int kRounds = 20;
  const int per_round = std::max(1, evaluations / kRounds);
  double best = std::numeric_limits<double>::infinity();
  for (int round = 0; round < kRounds; ++round) {
    const double start = ThreadCpuNs();
    run(per_round);
    best = std::min(best, (ThreadCpuNs() - start) / per_round);
  }
  g_sink = g_sink + sum;
  return best;
}

}  // namespace

FactorBenchBuffers::FactorBenchBuffers(const ceres::CostFunction& f)
    : residuals_(f.num_residuals()) {
  for (int size : f.parameter_block_sizes()) storage_.emplace_back(size * f.num_residuals());
  for (auto& s : storage_) pointers_.push_back(s.data());
}

double FactorBenchBuffers::Checksum() const { return residuals_[0] + storage_[0][0]; }

std::vector<FactorBenchCase> MakeFactorBenchCases(std::uint64_t seed) {
  Rng rng(seed);
  std::vector<FactorBenchCase> cases;
  // Flop estimates: hand counts of the analytic Evaluate (docs/math/lidar-and-point-factors.md).
  cases.push_back(LidarCase("PointToPlane", 100.0, rng, true, PointToPlaneFactor::Create,
                            PointToPlaneFactor::CreateAutoDiff));
  cases.push_back(LidarCase("PointToEdge", 185.0, rng, false, PointToEdgeFactor::Create,
                            PointToEdgeFactor::CreateAutoDiff));
  cases.push_back(LidarCase("PointToEdge2", 155.0, rng, false, PointToEdge2Factor::Create,
                            PointToEdge2Factor::CreateAutoDiff));
  cases.push_back(LidarCase("PointToEdgeScalar", 140.0, rng, false, PointToEdgeScalarFactor::Create,
                            PointToEdgeScalarFactor::CreateAutoDiff));
  cases.push_back(PointCase(rng, false));
  cases.push_back(PointCase(rng, true));
  cases.push_back(LineCase(rng, false));
  cases.push_back(LineCase(rng, true));
  cases.push_back(ImuCase(rng));
  return cases;
}

bool EvaluateFactorBenchCase(const FactorBenchCase& c, bool analytic, int index,
                             FactorBenchBuffers* buffers) {
  const auto& blocks = c.parameters[index];
  constexpr size_t kMaxBlocks = 6;  // the IMU factor's
  const double* params[kMaxBlocks] = {};
  for (size_t b = 0; b < blocks.size() && b < kMaxBlocks; ++b) params[b] = blocks[b].data();
  const ceres::CostFunction& f = analytic ? *c.analytic[index] : *c.autodiff[index];
  const bool ok = f.Evaluate(params, buffers->residuals(), buffers->jacobians());
  return ok;
}

std::vector<FactorBenchRow> BenchmarkFactors(int evaluations, std::uint64_t seed) {
  const std::vector<FactorBenchCase> cases = MakeFactorBenchCases(seed);
  std::vector<FactorBenchRow> rows;
  for (const FactorBenchCase& c : cases) {
    FactorBenchRow row;
    row.name = c.name;
    row.flops_estimate = c.flops_estimate;
    row.target_ratio = c.target_ratio;
    row.analytic_ns = TimeCase(c, true, evaluations);
    row.autodiff_ns = TimeCase(c, false, evaluations);
    row.ratio = row.autodiff_ns / row.analytic_ns;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace verify
}  // namespace plucker
