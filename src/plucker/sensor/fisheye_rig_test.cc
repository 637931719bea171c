// Fisheye rigs: the simulator's Kannala-Brandt output survives the files bit for bit, and
// ToPinholeView maps its raw points onto the view's pinhole projection of the same scene points.
#include "plucker/sensor/fisheye_rig.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "plucker/io/io_error.h"
#include "plucker/io/io_test_utils.h"
#include "plucker/io/sim_format.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace sensor {
namespace {

using io::testing::ScratchDir;

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

sim::CameraSimulation SimulateFisheye(bool points_in_view, double pixel_noise) {
  sim::CameraSimulationOptions o;
  o.num_frames = 8;
  o.obs.pixel_sigma = pixel_noise;
  o.obs.outlier_ratio = 0.05;
  o.rig = sim::FisheyeRig(sim::kDefaultViewFovDeg, points_in_view);
  return sim::SimulateCamera(o);
}

TEST(FisheyeRig, SimulationRoundTripsThroughTheFiles) {
  const ScratchDir scratch;
  const std::string dir = (scratch.path() / "kb").string();
  const CameraImuSequence a = sim::ToCameraImuSequence(SimulateFisheye(false, 1.0));
  io::WriteCameraImuSequence(dir, a);
  const CameraImuSequence b = io::ReadCameraImuSequence(dir);
  ASSERT_TRUE(a.rig.fisheye && b.rig.fisheye);
  const FisheyeView &fa = *a.rig.fisheye, &fb = *b.rig.fisheye;
  EXPECT_EQ(a.rig.K.K(), b.rig.K.K());
  EXPECT_EQ(b.rig.width, 512);
  EXPECT_EQ(fa.coeffs.k1, fb.coeffs.k1);
  EXPECT_EQ(fa.coeffs.k2, fb.coeffs.k2);
  EXPECT_EQ(fa.coeffs.k3, fb.coeffs.k3);
  EXPECT_EQ(fa.coeffs.k4, fb.coeffs.k4);
  EXPECT_NE(fb.coeffs.k1, 0.0);
  EXPECT_EQ(fa.view_K.K(), fb.view_K.K());
  EXPECT_EQ(fa.view_width, fb.view_width);
  EXPECT_EQ(fa.view_height, fb.view_height);
  EXPECT_EQ(fa.points_in_view, fb.points_in_view);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i].uv, b.points[i].uv);
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t i = 0; i < a.segments.size(); ++i)
    EXPECT_EQ(a.segments[i].s_px, b.segments[i].s_px);
}

TEST(FisheyeRig, OneFisheyeRecordWithoutTheOtherIsAnError) {
  const ScratchDir scratch;
  const std::string dir = (scratch.path() / "kb").string();
  io::WriteCameraImuSequence(dir, sim::ToCameraImuSequence(SimulateFisheye(true, 1.0)));
  const std::string rig = dir + "/rig.txt";
  std::string text = ReadText(rig);
  const std::size_t at = text.find("view ");
  ASSERT_NE(at, std::string::npos);
  text.erase(at, text.find('\n', at) - at + 1);
  std::ofstream(rig, std::ios::binary | std::ios::trunc) << text;
  try {
    io::ReadCameraImuSequence(dir);
    ADD_FAILURE() << "no error";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("rig.txt: missing 'view' record"), std::string::npos)
        << e.what();
  }
}

// Noise-free raw fisheye points mapped into the view land on the view's pinhole projection of
// the same scene points (to 1e-6 px), and the points beyond max_incidence_deg are dropped.
TEST(FisheyeRig, RawPointsMapOntoTheViewProjection) {
  const sim::CameraSimulation s = SimulateFisheye(false, 0.0);
  CameraImuSequence seq = sim::ToCameraImuSequence(s);
  const FisheyeView view = *seq.rig.fisheye;
  int raw_outside_view = 0;
  for (const PointObservation& p : seq.points) {
    if (p.point_id < 0) continue;
    const Eigen::Vector3d p_c = s.T_w_c_gt[p.frame].Inverse() * s.scene.points_w[p.point_id];
    const Eigen::Vector2d uv = view.view_K.ToPixel<double>(p_c.head<2>() / p_c.z());
    raw_outside_view += !(uv.x() >= 0 && uv.x() <= 511 && uv.y() >= 0 && uv.y() <= 511);
  }
  EXPECT_GT(raw_outside_view, 100);  // the full image sees more than the view
  const std::size_t before = seq.points.size();
  const PinholeViewStats st = ToPinholeView(&seq, 80.0);
  EXPECT_FALSE(seq.rig.fisheye);
  EXPECT_EQ(seq.rig.K.K(), view.view_K.K());
  EXPECT_GT(st.dropped_points, 0);
  EXPECT_EQ(st.converted_points + st.dropped_points, static_cast<int>(before));
  for (const PointObservation& p : seq.points) {
    if (p.point_id < 0) continue;
    const Eigen::Vector3d p_c = s.T_w_c_gt[p.frame].Inverse() * s.scene.points_w[p.point_id];
    EXPECT_GE(p_c.normalized().z(), std::cos(80.0 * M_PI / 180.0) - 1e-12);
    const Eigen::Vector2d uv = view.view_K.ToPixel<double>(p_c.head<2>() / p_c.z());
    EXPECT_LT((p.uv - uv).norm(), 1e-6) << p.frame << " " << p.point_id;
  }
  EXPECT_THROW(ToPinholeView(&seq, 95.0), std::invalid_argument);
}

// Each mapped point carries the inverse of the raw -> view map's Jacobian (central differences
// through the lens model) as its noise weight; the view points and pinhole rigs carry none.
TEST(FisheyeRig, MappedPointsCarryTheirStretchedRawNoise) {
  CameraImuSequence seq = sim::ToCameraImuSequence(SimulateFisheye(false, 0.0));
  const Camera raw = RawCamera(seq.rig), view = ViewCamera(seq.rig);
  std::vector<Eigen::Vector2d> raw_uv;
  for (const PointObservation& p : seq.points) raw_uv.push_back(p.uv);
  const auto to_view = [&](const Eigen::Vector2d& uv) {
    const Eigen::Vector3d b = *raw.PixelToBearing(uv);
    return Eigen::Vector2d(view.K.ToPixel<double>(b.head<2>() / b.z()));
  };
  const CameraImuSequence before = seq;
  ToPinholeView(&seq, 75.0);
  int checked = 0;
  double most_stretch = 1.0;
  for (const PointObservation& p : seq.points) {
    ASSERT_TRUE(p.sqrt_info_scale);
    if (p.point_id < 0) continue;  // outliers: several a frame share the id
    // The raw pixel of this point (the mapping keeps the order; find it by frame and id).
    Eigen::Vector2d uv_raw = Eigen::Vector2d::Constant(NAN);
    for (const PointObservation& q : before.points)
      if (q.frame == p.frame && q.point_id == p.point_id && (to_view(q.uv) - p.uv).norm() < 1e-9)
        uv_raw = q.uv;
    ASSERT_TRUE(uv_raw.allFinite());
    Eigen::Matrix2d J_view_raw;
    const double h = 1e-4;
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector2d d = h * Eigen::Vector2d::Unit(k);
      J_view_raw.col(k) = (to_view(uv_raw + d) - to_view(uv_raw - d)) / (2 * h);
    }
    const Eigen::Matrix2d product = *p.sqrt_info_scale * J_view_raw;
    EXPECT_LT((product - Eigen::Matrix2d::Identity()).norm(), 1e-6) << p.frame << " " << p.point_id;
    most_stretch =
        std::max(most_stretch, J_view_raw.norm() / std::sqrt(2.0) / (view.K.fx / raw.K.fx));
    ++checked;
  }
  EXPECT_GT(checked, 100);
  EXPECT_GT(most_stretch, 2.0);  // off-axis points really are down-weighted
}

// Points already in the view (and a pinhole rig) are left as they are.
TEST(FisheyeRig, ViewPointsAndPinholeRigsAreUnchanged) {
  CameraImuSequence seq = sim::ToCameraImuSequence(SimulateFisheye(true, 1.0));
  const std::vector<PointObservation> points = seq.points;
  const PinholeIntrinsics view_K = seq.rig.fisheye->view_K;
  EXPECT_EQ(ToPinholeView(&seq).converted_points, 0);
  EXPECT_EQ(seq.rig.K.K(), view_K.K());
  ASSERT_EQ(seq.points.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(seq.points[i].uv, points[i].uv);
    EXPECT_FALSE(seq.points[i].sqrt_info_scale);
  }
  sim::CameraSimulationOptions o;
  o.num_frames = 3;
  CameraImuSequence pinhole = sim::ToCameraImuSequence(sim::SimulateCamera(o));
  const CameraRig rig = pinhole.rig;
  ToPinholeView(&pinhole);
  EXPECT_EQ(pinhole.rig.K.K(), rig.K.K());
  EXPECT_EQ(pinhole.rig.width, rig.width);
}

}  // namespace
}  // namespace sensor
}  // namespace plucker
