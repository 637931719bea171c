// plucker readers and writers: KITTI .bin scans, PCD, trajectories (KITTI / TUM), EuRoC folders.
// Every error is the library's IoError (plucker.IoError in Python) naming the file and the problem.
#include <pybind11/stl.h>

#include <charconv>

#include "arrays.h"
#include "bindings.h"
#include "pipeline_inputs.h"
#include "plucker/io/euroc_dataset.h"
#include "plucker/io/image_folder.h"
#include "plucker/io/kitti_lidar.h"
#include "plucker/io/pcd.h"
#include "plucker/io/trajectory_io.h"
#include "vio_input.h"

namespace plucker {
namespace python {

namespace {

// The KITTI line of a 4x4 pose: its first three rows, each number in the shortest text that
// reads back as the same double (as io::WriteKittiPoses writes them).
std::string FormatKittiPoses(const py::handle& poses) {
  const py::array a = py::array::ensure(poses);
  if (!a || a.ndim() != 3 || a.shape(1) != 4 || a.shape(2) != 4)
    throw py::value_error("poses: expected shape (N, 4, 4)" + (a ? ", got " + ShapeText(a) : ""));
  const auto d = py::array_t<double, py::array::forcecast>::ensure(a);
  const auto u = d.unchecked<3>();
  std::string out;
  char buf[64];
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (r + c > 0) out += ' ';
        const auto res = std::to_chars(buf, buf + sizeof(buf), u(i, r, c));
        out.append(buf, res.ptr);
      }
    }
    out += '\n';
  }
  return out;
}

py::dict EurocDict(io::EurocDataset&& e) {
  py::dict camera;
  const sensor::Camera& c = e.cam0.camera;
  camera["K"] = ToVector(Eigen::Vector4d(c.K.fx, c.K.fy, c.K.cx, c.K.cy));
  camera["distortion"] =
      ToVector(Eigen::Vector4d(c.distortion.k1, c.distortion.k2, c.distortion.p1, c.distortion.p2));
  camera["width"] = c.width;
  camera["height"] = c.height;
  camera["T_b_c"] = PoseMatrix(e.cam0.T_b_c);
  camera["T_b_c_tq"] = PoseTq(e.cam0.T_b_c);  // exact (the 4x4's quaternion rounds)
  camera["rate_hz"] = e.cam0.rate_hz;
  Eigen::MatrixXd imu(static_cast<Eigen::Index>(e.imu.imu.size()), 7);
  for (std::size_t i = 0; i < e.imu.imu.size(); ++i) {
    const sensor::ImuSample& s = e.imu.imu[i];
    imu.row(static_cast<Eigen::Index>(i)) << s.t, s.gyro.transpose(), s.accel.transpose();
  }
  std::vector<double> frame_times;
  std::vector<std::string> images;
  for (const io::EurocFrame& f : e.frames) {
    frame_times.push_back(f.t);
    images.push_back(f.image);
  }
  std::vector<SE3d> gt_poses;
  std::vector<double> gt_times;
  for (const sensor::BodyState& s : e.imu.ground_truth) {
    gt_times.push_back(s.t);
    gt_poses.push_back(s.T_w_b);
  }
  py::dict d;
  d["camera"] = camera;
  d["frame_times"] = DoubleArray(std::move(frame_times));
  d["images"] = images;
  d["imu"] = ToArray(imu);
  d["imu_model"] = ImuModelDict(e.imu.imu_model);
  d["origin_ns"] = e.imu.origin_ns;
  d["ground_truth_times"] = DoubleArray(std::move(gt_times));
  d["ground_truth_T_w_b"] = PoseMatrices(gt_poses);
  d["skipped"] = io::ToStrings(e.skipped);
  d["warnings"] = e.warnings;
  return d;
}

// A features folder as `plucker vio --features` reads it (app::ReadVioFeatures): the rig, the
// IMU, and per frame the kept observations as add_frame takes them.
py::dict FeaturesDict(const std::string& dir, int point_stride) {
  if (point_stride < 1) throw py::value_error("read_features: point_stride must be >= 1");
  const app::VioInput in = app::ReadVioFeatures(dir, point_stride);
  const odometry::VisualInertialCalibration& c = in.calibration;
  py::dict camera;
  camera["K"] =
      ToVector(Eigen::Vector4d(c.camera.K.fx, c.camera.K.fy, c.camera.K.cx, c.camera.K.cy));
  camera["width"] = c.camera.width;
  camera["height"] = c.camera.height;
  camera["T_b_c"] = PoseMatrix(c.T_b_c);
  camera["T_b_c_tq"] = PoseTq(c.T_b_c);
  Eigen::MatrixXd imu(static_cast<Eigen::Index>(in.imu.size()), 7);
  for (std::size_t i = 0; i < in.imu.size(); ++i) {
    const sensor::ImuSample& s = in.imu[i];
    imu.row(static_cast<Eigen::Index>(i)) << s.t, s.gyro.transpose(), s.accel.transpose();
  }
  std::vector<double> times;
  py::list points, segments;
  for (const window::FrameInput& f : in.frames) {
    times.push_back(f.time);
    Eigen::MatrixXd p(static_cast<Eigen::Index>(f.points.size()), 3);
    for (std::size_t k = 0; k < f.points.size(); ++k)
      p.row(static_cast<Eigen::Index>(k)) << f.points[k].point_id, f.points[k].uv.transpose();
    Eigen::MatrixXd l(static_cast<Eigen::Index>(f.segments.size()), 5);
    for (std::size_t k = 0; k < f.segments.size(); ++k) {
      const sensor::SegmentObservation& o = f.segments[k];
      l.row(static_cast<Eigen::Index>(k)) << o.line_id, o.s_px.transpose(), o.e_px.transpose();
    }
    points.append(ToArray(p));
    segments.append(ToArray(l));
  }
  py::dict d;
  d["camera"] = camera;
  d["imu"] = ToArray(imu);
  d["imu_model"] = ImuModelDict(c.imu);
  d["gravity_magnitude"] = c.gravity_magnitude;
  d["pixel_sigma"] = c.pixel_sigma;
  d["frame_times"] = DoubleArray(std::move(times));
  d["points"] = points;
  d["segments"] = segments;
  d["ground_truth_T_w_b"] =
      in.gt_T_w_b ? py::object(PoseMatrices(*in.gt_T_w_b)) : py::object(py::none());
  d["warnings"] = in.warnings;
  return d;
}

}  // namespace

void RegisterIo(py::module_& m) {
  m.def(
      "read_kitti_bin",
      [](const std::string& path) {
        const LidarScan scan = io::ReadKittiBin(path);  // drops non-finite records, as the CLI
        const py::ssize_t n = static_cast<py::ssize_t>(scan.size());
        py::array_t<float> a({n, py::ssize_t{4}});
        auto w = a.mutable_unchecked<2>();
        for (py::ssize_t i = 0; i < n; ++i) {
          const Eigen::Vector3d& p = scan.points[static_cast<std::size_t>(i)];
          for (int k = 0; k < 3; ++k) w(i, k) = static_cast<float>(p(k));  // exact: read as float
          w(i, 3) = scan.intensity.empty() ? 0.0f : scan.intensity[static_cast<std::size_t>(i)];
        }
        return a;
      },
      py::arg("path"),
      "The records x y z intensity of a KITTI .bin scan as an (N, 4) float32 array, as stored\n"
      "(LiDAR frame), the records with a NaN/Inf dropped as `plucker lidar` drops them. Raises\n"
      "IoError for an unreadable, empty or truncated file.");
  m.def(
      "read_pcd", [](const std::string& path) { return ScanDict(io::ReadPcd(path)); },
      py::arg("path"),
      "A .pcd scan: dict with points (N, 3) float64, intensity, ring, time (per point, s from the\n"
      "scan start; empty when absent) and timestamp. NaN points are dropped, as the CLI does.");
  m.def(
      "read_kitti_times",
      [](const std::string& path) { return DoubleArray(io::ReadKittiTimes(path)); },
      py::arg("path"), "A KITTI times.txt: (N,) seconds.");
  m.def(
      "read_kitti_calib_tr",
      [](const std::string& path) -> py::object {
        const auto T = io::ReadKittiCalibTr(path);
        if (!T) return py::none();
        return PoseMatrix(*T);
      },
      py::arg("path"),
      "T_cam0_velo (4x4) from the Tr entry of a KITTI calib.txt, None without Tr.");
  m.def(
      "read_trajectory",
      [](const std::string& path) {
        io::Trajectory t = io::ReadTrajectory(path);
        py::dict d;
        d["times"] = DoubleArray(std::move(t.times));
        d["poses"] = PoseMatrices(t.poses);
        return d;
      },
      py::arg("path"),
      "A KITTI (12 numbers a line) or TUM (t tx ty tz qx qy qz qw) trajectory: dict with times\n"
      "(empty for KITTI) and poses (N, 4, 4).");
  m.def("format_kitti_poses", &FormatKittiPoses, py::arg("poses"),
        "The text `plucker lidar --out` writes for these poses (N, 4, 4): 12 numbers a line,\n"
        "shortest exact form.");
  m.def(
      "write_tum",
      [](const std::string& path, const py::handle& times, const py::handle& poses,
         const py::object& origin_ns, const std::vector<std::string>& comments) {
        const std::vector<SE3d> T = Poses(poses, "poses");
        const Eigen::MatrixXd t = SmallMatrix(times, "times", static_cast<int>(T.size()), 0);
        const std::vector<double> stamps(t.data(), t.data() + t.size());
        if (origin_ns.is_none())
          io::WriteTumTrajectory(path, stamps, T, comments);
        else
          io::WriteTumTrajectoryOnClock(path, origin_ns.cast<std::int64_t>(), stamps, T, comments);
      },
      py::arg("path"), py::arg("times"), py::arg("poses"), py::arg("origin_ns") = py::none(),
      py::arg("comments") = std::vector<std::string>{},
      "Writes a TUM trajectory (t tx ty tz qx qy qz qw) that evo_ape / evo_rpe read as it is.\n"
      "origin_ns: the recording's clock (read_euroc's origin_ns; times are s since it), written\n"
      "as the dataset's own stamps (as plucker vio writes EuRoC runs); comments: '# ' lines.");
  m.def(
      "read_gray_image",
      [](const std::string& path) {
        auto* image = new cv::Mat(io::ReadGrayImage(path));
        py::capsule owner(image, [](void* p) { delete static_cast<cv::Mat*>(p); });
        return py::array_t<std::uint8_t>(
            {static_cast<py::ssize_t>(image->rows), static_cast<py::ssize_t>(image->cols)},
            {static_cast<py::ssize_t>(image->step[0]), py::ssize_t{1}}, image->data, owner);
      },
      py::arg("path"),
      "An image file as 8-bit grayscale (H, W) uint8 (colour converted), as plucker vo/vio read\n"
      "them. Raises IoError for a missing or unreadable file.");
  m.def("read_features", &FeaturesDict, py::arg("dir"), py::arg("point_stride") = 1,
        "A features folder (docs/sim-format.md: rig.txt, imu.txt, points.txt, segments.txt) as\n"
        "plucker vio --features reads it: camera (K, width, height, T_b_c, T_b_c_tq), imu (N, 7),\n"
        "imu_model, gravity_magnitude, pixel_sigma, and per frame the IMU covers frame_times,\n"
        "points (n, 3) = (id, u, v) and segments (m, 5) = (id, x1, y1, x2, y2) as add_frame\n"
        "takes them (point tracks of id >= 0 and a multiple of point_stride), the ground truth\n"
        "T_w_b per frame when the folder has it, and the warnings (frames skipped).");
  m.def(
      "read_euroc", [](const std::string& dir) { return EurocDict(io::ReadEurocDataset(dir)); },
      py::arg("dir"),
      "A EuRoC ASL folder (with mav0/ or mav0 itself): cam0 calibration, frame times and image\n"
      "paths, the IMU log (N, 7) = (t, gyro xyz, accel xyz) and imu_model, ground truth when "
      "present, and the\n"
      "skipped frames and warnings. Times are s since the first IMU sample (origin_ns).");
}

}  // namespace python
}  // namespace plucker
