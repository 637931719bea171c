#include "plucker/eval/alignment.h"

#include <gtest/gtest.h>

#include "plucker/verify/random_geometry.h"

namespace plucker {
namespace eval {
namespace {

std::vector<Eigen::Vector3d> Transform(const Similarity& S, const std::vector<Eigen::Vector3d>& p) {
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector3d& v : p) out.push_back(S * v);
  return out;
}

double MaxResidual(const Similarity& S, const std::vector<Eigen::Vector3d>& source,
                   const std::vector<Eigen::Vector3d>& target) {
  double m = 0.0;
  for (std::size_t i = 0; i < source.size(); ++i)
    m = std::max(m, (S * source[i] - target[i]).norm());
  return m;
}

TEST(Umeyama, Sim3RecoversRotationTranslationAndScaleExactly) {
  verify::Rng rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Eigen::Vector3d> source;
    for (int i = 0; i < 30; ++i) source.push_back(verify::RandomVector(rng, 20.0));
    Similarity S_gt;
    S_gt.R = verify::RandomRotation(rng).toRotationMatrix();
    S_gt.t = verify::RandomVector(rng, 100.0);
    S_gt.scale = verify::Uniform(rng, 0.05, 20.0);
    const std::optional<Similarity> S =
        UmeyamaAlignment(source, Transform(S_gt, source), AlignmentMode::kSim3);
    ASSERT_TRUE(S.has_value());
    EXPECT_LT((S->R - S_gt.R).norm(), 1e-9);
    EXPECT_LT((S->t - S_gt.t).norm(), 1e-8);
    EXPECT_NEAR(S->scale, S_gt.scale, 1e-9 * S_gt.scale);
  }
}

TEST(Umeyama, Se3RecoversARotatedTranslatedCopyWithUnitScale) {
  verify::Rng rng(12);
  std::vector<Eigen::Vector3d> source;
  for (int i = 0; i < 20; ++i) source.push_back(verify::RandomVector(rng, 5.0));
  Similarity S_gt;
  S_gt.R = verify::RandomRotation(rng).toRotationMatrix();
  S_gt.t = verify::RandomVector(rng, 10.0);
  const std::optional<Similarity> S =
      UmeyamaAlignment(source, Transform(S_gt, source), AlignmentMode::kSE3);
  ASSERT_TRUE(S.has_value());
  EXPECT_EQ(S->scale, 1.0);
  EXPECT_LT(MaxResidual(*S, source, Transform(S_gt, source)), 1e-10);
}

TEST(Umeyama, MirroredPlanarPointsGiveARotationNotAReflection) {
  // Points in the plane z = 0, target = mirror x -> -x. For planar points this mirror equals
  // the rotation by pi about y, so the best ROTATION fits exactly; the naive U V^T would be the
  // reflection diag(-1, 1, 1) (det -1). Umeyama's sign correction must pick the rotation.
  verify::Rng rng(13);
  std::vector<Eigen::Vector3d> source, target;
  for (int i = 0; i < 25; ++i) {
    const Eigen::Vector3d p(verify::Uniform(rng, -5, 5), verify::Uniform(rng, -5, 5), 0.0);
    source.push_back(p);
    target.emplace_back(-p.x(), p.y(), 0.0);
  }
  for (AlignmentMode mode : {AlignmentMode::kSE3, AlignmentMode::kSim3}) {
    const std::optional<Similarity> S = UmeyamaAlignment(source, target, mode);
    ASSERT_TRUE(S.has_value());
    EXPECT_NEAR(S->R.determinant(), 1.0, 1e-12);
    EXPECT_LT((S->R.transpose() * S->R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(S->scale, 1.0, 1e-12);
    EXPECT_LT(MaxResidual(*S, source, target), 1e-10);
  }
}

TEST(Umeyama, NonPlanarMirrorGivesAProperRotationWithPositiveScale) {
  // A truly mirrored 3D cloud cannot be fitted by a rotation; the result must still be proper.
  verify::Rng rng(14);
  std::vector<Eigen::Vector3d> source, target;
  for (int i = 0; i < 25; ++i) {
    const Eigen::Vector3d p = verify::RandomVector(rng, 3.0);
    source.push_back(p);
    target.emplace_back(-p.x(), p.y(), p.z());
  }
  const std::optional<Similarity> S = UmeyamaAlignment(source, target, AlignmentMode::kSim3);
  ASSERT_TRUE(S.has_value());
  EXPECT_NEAR(S->R.determinant(), 1.0, 1e-12);
  EXPECT_GT(S->scale, 0.0);
}

TEST(Umeyama, CollinearPointsAlignAndDegenerateInputsAreRejected) {
  std::vector<Eigen::Vector3d> line, moved;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()).matrix();
  for (int i = 0; i < 10; ++i) {
    line.emplace_back(0, 0, i);
    moved.push_back(R * line.back() + Eigen::Vector3d(1, 2, 3));
  }
  const std::optional<Similarity> S = UmeyamaAlignment(line, moved, AlignmentMode::kSE3);
  ASSERT_TRUE(S.has_value());
  EXPECT_LT(MaxResidual(*S, line, moved), 1e-10);
  // One point: SE(3) is a translation; Sim(3) has no scale.
  EXPECT_TRUE(UmeyamaAlignment({line[3]}, {moved[3]}, AlignmentMode::kSE3).has_value());
  EXPECT_FALSE(UmeyamaAlignment({line[3]}, {moved[3]}, AlignmentMode::kSim3).has_value());
  EXPECT_FALSE(UmeyamaAlignment(line, {moved[0]}, AlignmentMode::kSE3).has_value());
  EXPECT_FALSE(UmeyamaAlignment({}, {}, AlignmentMode::kNone).has_value());
  const std::optional<Similarity> none = UmeyamaAlignment(line, moved, AlignmentMode::kNone);
  ASSERT_TRUE(none.has_value());
  EXPECT_EQ(none->R, Eigen::Matrix3d::Identity());
  EXPECT_EQ(none->t, Eigen::Vector3d::Zero());
}

TEST(AlignTrajectory, StraightDriveTakesTheRollFromTheOrientations) {
  // Exactly collinear positions: Umeyama cannot see a rotation about the line. The estimate is a
  // rigidly moved copy, so the right alignment makes every orientation agree too.
  verify::Rng rng(15);
  std::vector<SE3d> gt, est;
  Similarity S_gt;
  S_gt.R = verify::RandomRotation(rng).toRotationMatrix();
  S_gt.t = Eigen::Vector3d(3, -2, 7);
  for (int i = 0; i < 40; ++i) {
    gt.emplace_back(Eigen::Quaterniond(Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitZ())),
                    Eigen::Vector3d(0, 0, 1.3 * i));
    est.push_back(S_gt.Apply(gt.back()));
  }
  for (AlignmentMode mode : {AlignmentMode::kSE3, AlignmentMode::kSim3}) {
    const std::optional<TrajectoryAlignment> a = AlignTrajectory(est, gt, mode);
    ASSERT_TRUE(a.has_value());
    EXPECT_TRUE(a->roll_from_orientations);
    for (std::size_t i = 0; i < gt.size(); ++i) {
      const SE3d aligned = a->S.Apply(est[i]);
      EXPECT_LT((aligned.translation() - gt[i].translation()).norm(), 1e-9);
      EXPECT_LT((aligned.RotationMatrix() - gt[i].RotationMatrix()).norm(), 1e-9);
    }
  }
  // A well-spread trajectory keeps the plain Umeyama solution.
  std::vector<SE3d> curve_gt, curve_est;
  for (int i = 0; i < 40; ++i) {
    curve_gt.emplace_back(Eigen::Quaterniond::Identity(),
                          Eigen::Vector3d(10 * std::sin(0.1 * i), 0, 10 * std::cos(0.1 * i)));
    curve_est.push_back(S_gt.Apply(curve_gt.back()));
  }
  const std::optional<TrajectoryAlignment> b =
      AlignTrajectory(curve_est, curve_gt, AlignmentMode::kSE3);
  ASSERT_TRUE(b.has_value());
  EXPECT_FALSE(b->roll_from_orientations);
  EXPECT_LT((b->S.R - S_gt.R.transpose()).norm(), 1e-9);
}

TEST(Umeyama, ApplyToPoseRotatesAndScales) {
  Similarity S;
  S.R = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).matrix();
  S.t = Eigen::Vector3d(1, 0, 0);
  S.scale = 2.0;
  const SE3d T(Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX())),
               Eigen::Vector3d(0, 1, 0));
  const SE3d A = S.Apply(T);
  EXPECT_LT((A.translation() - (2.0 * S.R * Eigen::Vector3d(0, 1, 0) + S.t)).norm(), 1e-15);
  EXPECT_LT((A.RotationMatrix() - S.R * T.RotationMatrix()).norm(), 1e-15);
}

TEST(Umeyama, ModeNames) {
  for (AlignmentMode m : {AlignmentMode::kNone, AlignmentMode::kSE3, AlignmentMode::kSim3}) {
    EXPECT_EQ(ParseAlignmentMode(AlignmentName(m)), m);
  }
  EXPECT_FALSE(ParseAlignmentMode("sim(3)").has_value());
}

// Position + yaw: recovers a yaw and a translation exactly, and leaves a tilt (roll/pitch, which
// VIO observes through gravity) in the error, where SE(3) would absorb it.
TEST(PositionYaw, RecoversYawAndTranslationAndKeepsTilt) {
  verify::Rng rng(21);
  int trials = 0;
  for (int trial = 0; trial < 30; ++trial) {
    std::vector<SE3d> est, gt;
    const double yaw = verify::Uniform(rng, -M_PI, M_PI);
    const Eigen::Matrix3d Rz = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d t = verify::RandomVector(rng, 50.0);
    for (int i = 0; i < 40; ++i) {
      est.push_back(verify::RandomPose(rng, 10.0));
      gt.emplace_back(Eigen::Matrix3d(Rz * est.back().RotationMatrix()),
                      Rz * est.back().translation() + t);
    }
    const std::optional<TrajectoryAlignment> a =
        AlignTrajectory(est, gt, AlignmentMode::kPositionYaw);
    ASSERT_TRUE(a.has_value());
    EXPECT_LT((a->S.R - Rz).norm(), 1e-9);
    EXPECT_LT((a->S.t - t).norm(), 1e-8);
    EXPECT_EQ(a->S.scale, 1.0);
    // A tilted copy: posyaw cannot remove the tilt, SE(3) can.
    const Eigen::Matrix3d tilt =
        Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
    std::vector<SE3d> tilted;
    for (const SE3d& T : gt)
      tilted.emplace_back(Eigen::Matrix3d(tilt * T.RotationMatrix()), tilt * T.translation());
    const auto py = AlignTrajectory(est, tilted, AlignmentMode::kPositionYaw);
    const auto se3 = AlignTrajectory(est, tilted, AlignmentMode::kSE3);
    ASSERT_TRUE(py && se3);
    EXPECT_LT(MaxResidual(se3->S, Positions(est), Positions(tilted)), 1e-8);
    EXPECT_GT(MaxResidual(py->S, Positions(est), Positions(tilted)), 0.1);
    ++trials;
  }
  EXPECT_EQ(trials, 30);
  EXPECT_EQ(AlignmentName(AlignmentMode::kPositionYaw), "posyaw");
  EXPECT_EQ(*ParseAlignmentMode("posyaw"), AlignmentMode::kPositionYaw);
}

// A purely vertical motion has no horizontal extent: the yaw comes from the orientations.
TEST(PositionYaw, VerticalMotionTakesTheYawFromTheOrientations) {
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<SE3d> est, gt;
  for (int i = 0; i < 10; ++i) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(0.3, 0.2, 1).normalized()).toRotationMatrix();
    est.emplace_back(R, Eigen::Vector3d(0, 0, i));
    gt.emplace_back(Eigen::Matrix3d(Rz * R), Eigen::Vector3d(1, 2, i + 3));
  }
  const auto a = AlignTrajectory(est, gt, AlignmentMode::kPositionYaw);
  ASSERT_TRUE(a.has_value());
  EXPECT_LT((a->S.R - Rz).norm(), 1e-9);
  EXPECT_FALSE(AlignTrajectory(est, {}, AlignmentMode::kPositionYaw).has_value());
}

}  // namespace
}  // namespace eval
}  // namespace plucker
