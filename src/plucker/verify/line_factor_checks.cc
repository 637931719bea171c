// Jacobian checks of factors/line_reprojection_factor.h and factors/line_manifold.h
// (docs/math/lines.md), run by verify/cost_function_check.h. Both checks of a factor compare the
// residual and ambient Jacobian (2 x 13 or 2 x 20) with the autodiff twin (CreateAutoDiff); then
//   *.ambient : the ambient Jacobian vs central differences over the raw parameters (Evaluate
//               normalises q and W, so the ambient derivative is well defined);
//   *.tangent : the tangent Jacobian (ambient * PlusJacobian) vs central differences through the
//               manifolds' Plus.
// Curated first samples: a line along the optical axis through the camera centre (the guard: both
// versions must refuse it; counted as skipped), u1 parallel to world z, a line through the world
// origin (w1 = 0, phi = pi/2), a line 1 km from the origin (phi near 0), rotations near pi.
// The differences are Ridders-extrapolated (cost_function_check.h); their finest step is 1e-6 for
// pose parameters and 1e-6 / max(1, D)^1.25 for line parameters, D the distance of the line from
// the origin: for the 1 km line a unit dphi moves the line by ~D^2 metres, so a fixed step
// measures the curvature, not the derivative. With a single fixed step, D^-1.25 balanced
// truncation against rounding and still failed now and then (1.6e-6 against 1e-6 on sample 3);
// with the extrapolation the worst error over seeds 3000..3150 x 1000 samples is 1.2e-8.
// A tiny step on the 1 km translation would measure rounding, hence per-block steps. The residual
// comparison with the autodiff twin is relative to max(|r|, D): the camera-frame moment is a
// difference of world terms of size D, whose rounding reaches 1.5e-9 px for the 1 km line (2000
// seeds).
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "plucker/factors/anchored_line_factor.h"
#include "plucker/factors/held_extrinsic_factor.h"
#include "plucker/factors/line_manifold.h"
#include "plucker/factors/line_reprojection_factor.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/factors/time_offset_factor.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/cost_function_check.h"
#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace verify {

namespace {

// One factor configuration: parameter blocks, their kinds, and the measurement.
struct LineFactorSample {
  std::vector<Eigen::VectorXd> blocks;  // poses (7) then the line (6)
  PinholeIntrinsics K;
  Eigen::Vector2d s_px, e_px;
  Eigen::Matrix2d sqrt_info;
  bool expect_guard = false;
  LineAnchor anchor;  // the anchored factor's: the line block is in this frame
  // The time-offset factor's endpoint velocities (px/s); its td is the block before the line.
  Eigen::Vector2d v_s = Eigen::Vector2d::Zero(), v_e = Eigen::Vector2d::Zero();
  SE3d held;  // the stereo check's extrinsic T_c0_c1, held (not a block)
};

// A parameter block of size n: a pose or an orthonormal line.
template <typename X>
Eigen::VectorXd Block(const X& x, int n) {
  Eigen::VectorXd p(n);
  x.ToParameters(p.data());
  return p;
}

// Camera pose T_w_c and world line for sample i (first samples curated).
void SampleCameraAndLine(Rng& rng, int i, SE3d* T_w_c, Line6d* L_w, bool* expect_guard) {
  *expect_guard = false;
  auto in_front = [&] {
    return Eigen::Vector3d(Uniform(rng, -3, 3), Uniform(rng, -2, 2), Uniform(rng, 2, 10));
  };
  Eigen::Vector3d p1_c = in_front(), p2_c = in_front();
  switch (i) {
    case 0:  // along the optical axis through the centre: projects to a point -> guard
      *T_w_c = RandomPose(rng);
      p1_c = Eigen::Vector3d(0, 0, 1);
      p2_c = Eigen::Vector3d(0, 0, 4);
      *expect_guard = true;
      break;
    case 1:  // world line n = (0,0,1), d = (1,0,0): u1 parallel to world z
      *T_w_c = SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.3, -1.2, -5.0));
      *L_w = (Line6d() << 0, 0, 1, 1, 0, 0).finished();
      return;
    case 2: {  // world line through the world origin (w1 = 0, phi = pi/2), origin 5 m in front
      const Eigen::Quaterniond q = RandomRotation(rng);
      *T_w_c = SE3d(q, q * Eigen::Vector3d(0.2, -0.1, -5.0));
      *L_w = LineFromPoints<double>(Eigen::Vector3d::Zero(), q * Eigen::Vector3d(1.0, 0.3, 0.2));
      return;
    }
    case 3:  // 1 km from the world origin: phi = atan2(w2, w1) near 0
      *T_w_c = SE3d(RandomRotation(rng), RandomUnitVector(rng) * 1e3);
      break;
    case 4:
      *T_w_c = SE3d(RotationNearPi(rng, 0.0), RandomVector(rng));
      break;
    case 5:
      *T_w_c = SE3d(RotationNearPi(rng, 1e-7), RandomVector(rng));
      break;
    default:
      *T_w_c = RandomPose(rng);
  }
  *L_w = LineFromPoints<double>(*T_w_c * p1_c, *T_w_c * p2_c);
}

// Endpoints: the projections of two points of the camera-frame line, plus noise.
void SampleMeasurement(Rng& rng, const PinholeIntrinsics& K, const Line6d& L_c,
                       LineFactorSample* out) {
  out->K = K;
  const Eigen::Vector3d l = LineIntrinsics(K) * L_c.head<3>();
  const Eigen::Vector2d normal =
      l.head<2>().norm() > 0 ? Eigen::Vector2d(l.head<2>().normalized()) : Eigen::Vector2d(1, 0);
  const Eigen::Vector2d along(-normal(1), normal(0));
  // A point of the image line (closest to the principal point), if the line is regular.
  Eigen::Vector2d base(K.cx, K.cy);
  if (l.head<2>().norm() > 0) base -= normal * (normal.dot(base) + l(2) / l.head<2>().norm());
  if (!base.allFinite()) base = Eigen::Vector2d(K.cx, K.cy);
  out->s_px = base - along * Uniform(rng, 20, 200) + normal * Uniform(rng, -3, 3);
  out->e_px = base + along * Uniform(rng, 20, 200) + normal * Uniform(rng, -3, 3);
  // From rng, not Eigen's Random() (std::rand): a sample is fixed by the seed alone.
  Eigen::Matrix2d A;
  A << Uniform(rng, -0.2, 0.2), Uniform(rng, -0.2, 0.2), Uniform(rng, -0.2, 0.2),
      Uniform(rng, -0.2, 0.2);
  out->sqrt_info = Eigen::Matrix2d::Identity() * Uniform(rng, 0.5, 2.0) + A;
}

LineFactorSample MonoSample(Rng& rng, int i) {
  LineFactorSample smp;
  SE3d T_w_c;
  Line6d L_w;
  SampleCameraAndLine(rng, i, &T_w_c, &L_w, &smp.expect_guard);
  if (smp.expect_guard) {
    // Keep a regular orthonormal block: only the projection is degenerate.
    L_w =
        LineFromPoints<double>(T_w_c * Eigen::Vector3d(0, 0, 1), T_w_c * Eigen::Vector3d(0, 0, 4));
  }
  SampleMeasurement(rng, SampleIntrinsics(rng), TransformLine(T_w_c.Inverse(), L_w), &smp);
  smp.blocks = {Block(T_w_c, 7), Block(*OrthonormalFromPlucker(L_w), 6)};
  return smp;
}

LineFactorSample VISample(Rng& rng, int i) {
  LineFactorSample smp;
  SE3d T_w_c;
  Line6d L_w;
  SampleCameraAndLine(rng, i, &T_w_c, &L_w, &smp.expect_guard);
  // Split T_w_c = T_w_b T_b_c with a random extrinsic (near pi for some curated samples).
  const SE3d T_b_c = (i == 6) ? SE3d(RotationNearPi(rng, 0.0), RandomVector(rng, 0.2))
                              : SE3d(RandomRotation(rng), RandomVector(rng, 0.2));
  const SE3d T_w_b = T_w_c * T_b_c.Inverse();
  SampleMeasurement(rng, SampleIntrinsics(rng), TransformLine(T_w_c.Inverse(), L_w), &smp);
  smp.blocks = {Block(T_w_b, 7), Block(T_b_c, 7), Block(*OrthonormalFromPlucker(L_w), 6)};
  return smp;
}

// The mono sample with the line in an anchor frame: c_w near the camera centre (the translation
// of the pose block [q, t]), scale its distance.
LineFactorSample AnchoredSample(Rng& rng, int i) {
  LineFactorSample smp = MonoSample(rng, i);
  const Line6d L_w = PluckerFromOrthonormal(OrthonormalLine::FromParameters(smp.blocks[1].data()));
  const Eigen::Vector3d c_w = smp.blocks[0].tail<3>() + RandomVector(rng, 0.5);
  smp.anchor = MakeLineAnchor(L_w, c_w);
  smp.blocks[1] = Block(*OrthonormalFromPlucker(AnchoredFromWorld(L_w, smp.anchor)), 6);
  return smp;
}

// The VI sample with the line in an anchor frame near the camera centre.
LineFactorSample AnchoredVISample(Rng& rng, int i) {
  LineFactorSample smp = VISample(rng, i);
  const Line6d L_w = PluckerFromOrthonormal(OrthonormalLine::FromParameters(smp.blocks[2].data()));
  const SE3d T_w_c =
      SE3d::FromParameters(smp.blocks[0].data()) * SE3d::FromParameters(smp.blocks[1].data());
  smp.anchor = MakeLineAnchor(L_w, T_w_c.translation() + RandomVector(rng, 0.5));
  smp.blocks[2] = Block(*OrthonormalFromPlucker(AnchoredFromWorld(L_w, smp.anchor)), 6);
  return smp;
}

// The anchored VI sample with endpoint velocities and a td block (factors/time_offset_factor.h):
// zero velocities on samples 1 and 7, td = 0 on samples 2 and 8 (curated), random otherwise.
LineFactorSample AnchoredVITimeOffsetSample(Rng& rng, int i) {
  LineFactorSample smp = AnchoredVISample(rng, i);
  smp.v_s = Eigen::Vector2d(Uniform(rng, -300, 300), Uniform(rng, -300, 300));
  smp.v_e = Eigen::Vector2d(Uniform(rng, -300, 300), Uniform(rng, -300, 300));
  if (i == 1 || i == 7) smp.v_s = smp.v_e = Eigen::Vector2d::Zero();
  const double td = (i == 2 || i == 8) ? 0.0 : Uniform(rng, -0.05, 0.05);
  smp.blocks.insert(smp.blocks.begin() + 2, Eigen::VectorXd::Constant(1, td));
  return smp;
}

// The stereo right camera's factor (window/window_stereo.cc): the anchored VI sample with its
// extrinsic held as T_c0_c1, on (T_w_c0, line).
LineFactorSample StereoRightSample(Rng& rng, int i) {
  LineFactorSample smp = AnchoredVISample(rng, i);
  smp.held = SE3d::FromParameters(smp.blocks[1].data());
  smp.blocks.erase(smp.blocks.begin() + 1);
  return smp;
}

using CreateFn = std::function<ceres::CostFunction*(const LineFactorSample&)>;
using PlainCreateFn = ceres::CostFunction* (*)(const PinholeIntrinsics&, const Eigen::Vector2d&,
                                               const Eigen::Vector2d&, const Eigen::Matrix2d&);
CreateFn Plain(PlainCreateFn create) {
  return [create](const LineFactorSample& s) { return create(s.K, s.s_px, s.e_px, s.sqrt_info); };
}
CreateFn Anchored(bool autodiff) {
  return [autodiff](const LineFactorSample& s) {
    return autodiff ? AnchoredLineFactor::CreateAutoDiff(s.K, s.s_px, s.e_px, s.sqrt_info, s.anchor)
                    : AnchoredLineFactor::Create(s.K, s.s_px, s.e_px, s.sqrt_info, s.anchor);
  };
}

CreateFn AnchoredVI(bool autodiff) {
  return [autodiff](const LineFactorSample& s) {
    return autodiff
               ? AnchoredLineFactorVI::CreateAutoDiff(s.K, s.s_px, s.e_px, s.sqrt_info, s.anchor)
               : AnchoredLineFactorVI::Create(s.K, s.s_px, s.e_px, s.sqrt_info, s.anchor);
  };
}

CreateFn StereoRight(bool autodiff) {
  return [autodiff](const LineFactorSample& s) -> ceres::CostFunction* {
    return new HeldExtrinsicFactor<6>(AnchoredVI(autodiff)(s), s.held);
  };
}

CreateFn AnchoredVITimeOffset(bool autodiff) {
  return [autodiff](const LineFactorSample& s) {
    return autodiff ? AnchoredLineFactorVITimeOffset::CreateAutoDiff(s.K, s.s_px, s.e_px, s.v_s,
                                                                     s.v_e, s.sqrt_info, s.anchor)
                    : AnchoredLineFactorVITimeOffset::Create(s.K, s.s_px, s.e_px, s.v_s, s.v_e,
                                                             s.sqrt_info, s.anchor);
  };
}

// Check `name` of the factor made by create / create_autodiff on the samples of `sample`, with
// central differences through the manifolds' Plus (tangent) or over the raw parameters.
NamedJacobianCheck LineFactorCheck(const std::string& name, std::uint64_t seed,
                                   LineFactorSample (*sample)(Rng&, int), CreateFn create,
                                   CreateFn create_autodiff, bool tangent) {
  return {name, [=](const JacobianCheckOptions& o) {
            const PoseManifold pose_manifold;
            const LineManifold line_manifold;
            return RunCostFunctionCheck(name, seed, o, [&](Rng& rng, int i) {
              const LineFactorSample smp = sample(rng, i);
              CostFunctionSample c;
              c.analytic.reset(create(smp));
              c.autodiff.reset(create_autodiff(smp));
              c.x = smp.blocks;  // poses (then td, a time-offset factor's), then the line
              c.manifolds.assign(c.x.size(), tangent ? &pose_manifold : nullptr);
              if (tangent) c.manifolds.back() = &line_manifold;
              for (std::size_t b = 0; b < c.x.size(); ++b)
                if (c.x[b].size() == 1) c.manifolds[b] = nullptr;  // td: Euclidean
              // Per-block steps (see the top of the file); w1 / w2 is the line's distance.
              const double distance = std::abs(c.x.back()[4] / c.x.back()[5]);
              c.steps.assign(c.x.size(), 1e-6);
              c.steps.back() = 1e-6 / std::pow(std::max(1.0, distance), 1.25);
              c.residual_scale = std::max(1.0, distance);
              c.what = "sample " + std::to_string(i);
              c.expect_refusal = smp.expect_guard;
              const Eigen::Matrix2d& S = smp.sqrt_info;
              c.inputs = {{"K", Eigen::Vector4d(smp.K.fx, smp.K.fy, smp.K.cx, smp.K.cy)},
                          {"s_px", smp.s_px},
                          {"e_px", smp.e_px},
                          {"sqrt_information", Eigen::Vector4d(S(0, 0), S(0, 1), S(1, 0), S(1, 1))},
                          {"c_w", smp.anchor.c_w},
                          {"scale", Eigen::VectorXd::Constant(1, smp.anchor.scale)},
                          {"s_velocity", smp.v_s},
                          {"e_velocity", smp.v_e}};
              return c;
            });
          }};
}

}  // namespace

std::vector<NamedJacobianCheck> LineFactorJacobianChecks() {
  const CreateFn mono = Plain(&LineReprojectionFactor::Create);
  const CreateFn mono_ad = Plain(&LineReprojectionFactor::CreateAutoDiff);
  const CreateFn vi = Plain(&LineReprojectionFactorVI::Create);
  const CreateFn vi_ad = Plain(&LineReprojectionFactorVI::CreateAutoDiff);
  return {
      LineFactorCheck("factor.line.Reprojection.ambient", 200, MonoSample, mono, mono_ad, false),
      LineFactorCheck("factor.line.Reprojection.tangent", 201, MonoSample, mono, mono_ad, true),
      LineFactorCheck("factor.line.ReprojectionVI.ambient", 202, VISample, vi, vi_ad, false),
      LineFactorCheck("factor.line.ReprojectionVI.tangent", 203, VISample, vi, vi_ad, true),
      LineFactorCheck("factor.line.Anchored.tangent", 204, AnchoredSample, Anchored(false),
                      Anchored(true), true),
      LineFactorCheck("factor.line.AnchoredVI.tangent", 205, AnchoredVISample, AnchoredVI(false),
                      AnchoredVI(true), true),
      LineFactorCheck("factor.line.AnchoredVI.time_offset", 206, AnchoredVITimeOffsetSample,
                      AnchoredVITimeOffset(false), AnchoredVITimeOffset(true), true),
      LineFactorCheck("factor.line.AnchoredStereoRight.tangent", 207, StereoRightSample,
                      StereoRight(false), StereoRight(true), true),
  };
}

}  // namespace verify
}  // namespace plucker
