// plucker.VisualInertialOdometry: the online point + line VIO of `plucker vio`
// (odometry/visual_inertial_odometry.h) fed from Python: IMU samples, then each image (or a
// frame's observations) once the IMU has reached its time. The options are the keys of
// `plucker vio --config` (apps/plucker/vio_config.cc: the library's field names).
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <mutex>

#include "arrays.h"
#include "bindings.h"
#include "options.h"
#include "pipeline_inputs.h"
#include "plucker/odometry/visual_inertial_odometry.h"
#include "vio_config.h"

namespace plucker {
namespace python {

namespace {

using odometry::VioFrameRecord;
using odometry::VioFrameResult;

constexpr const char* kWho = "VisualInertialOdometry";

py::object OptionalPose(const std::optional<SE3d>& T) {
  if (!T) return py::none();
  return PoseMatrix(*T);
}
py::object OptionalTq(const std::optional<SE3d>& T) {
  if (!T) return py::none();
  return PoseTq(*T);
}

py::dict RecordDict(const VioFrameRecord& r) {
  py::dict d;
  d["frame"] = r.frame;
  d["time"] = r.time;
  d["status"] = odometry::ToString(r);
  d["T_w_b"] = OptionalPose(r.T_w_b);
  d["T_w_b_tq"] = OptionalTq(r.T_w_b);
  d["keyframe"] = r.keyframe;
  return d;
}

py::dict ResultDict(const VioFrameResult& r) {
  py::dict d;
  d["frame"] = r.frame;
  d["time"] = r.time;
  d["status"] = odometry::ToString(r.status);
  d["T_w_b"] = OptionalPose(r.T_w_b);
  d["T_w_b_tq"] = OptionalTq(r.T_w_b);
  d["v_w"] = ToVector(r.v_w);
  d["gyro_bias"] = ToVector(r.bias.gyro);
  d["accel_bias"] = ToVector(r.bias.accel);
  d["keyframe"] = r.window && r.window->keyframe;
  d["window"] = r.window ? py::object(WindowDict(*r.window)) : py::object(py::none());
  d["observed_points"] = r.observed_points;
  d["observed_segments"] = r.observed_segments;
  py::list settled;
  for (const VioFrameRecord& s : r.settled) settled.append(RecordDict(s));
  d["settled"] = settled;
  d["message"] = r.message;
  return d;
}

class PyVisualInertialOdometry {
 public:
  PyVisualInertialOdometry(const py::handle& camera, const py::handle& T_b_c,
                           const py::handle& imu_model, const py::object& config_path,
                           double gravity_magnitude, double pixel_sigma,
                           const py::kwargs& options) {
    odometry::VisualInertialCalibration calibration;
    calibration.camera = CameraArg(camera, kWho);
    calibration.T_b_c = Pose(T_b_c, "T_b_c");
    calibration.imu = ImuModelArg(imu_model, kWho);
    if (!(std::isfinite(gravity_magnitude) && gravity_magnitude > 0.0))
      throw py::value_error("VisualInertialOdometry: gravity_magnitude must be positive");
    if (!(std::isfinite(pixel_sigma) && pixel_sigma > 0.0))
      throw py::value_error("VisualInertialOdometry: pixel_sigma must be positive");
    calibration.gravity_magnitude = gravity_magnitude;
    calibration.pixel_sigma = pixel_sigma;
    app::VioConfig cfg;
    if (!config_path.is_none()) app::ApplyVioConfig(config_path.cast<std::string>(), &cfg);
    try {
      if (!options.contains("point_stride"))  // the flat key: refused below, not as renamed
        app::ApplyVioConfigYaml(OptionsYaml(options, kWho), "VisualInertialOdometry options",
                                &cfg);
    } catch (const std::exception& e) {
      throw py::value_error(e.what());
    }
    // The config file's or the options' input.point_stride would be ignored: refused.
    if (options.contains("point_stride") || cfg.point_stride != 1)
      throw py::value_error(
          "VisualInertialOdometry: input.point_stride selects the tracks of a features folder "
          "(plucker vio --features); give add_frame the points to use");
    if (!cfg.T_b_c.empty()) {  // the config's T_b_c replaces the one given (as in plucker vio)
      const std::vector<double>& e = cfg.T_b_c;
      calibration.T_b_c =
          SE3d(Eigen::Quaterniond(e[6], e[3], e[4], e[5]), Eigen::Vector3d(e[0], e[1], e[2]));
    }
    options_ = cfg.odometry;
    vio_ = std::make_unique<odometry::VisualInertialOdometry>(options_, calibration);
  }

  void AddImu(const py::handle& t_or_samples, const py::object& gyro, const py::object& accel) {
    std::vector<sensor::ImuSample> samples;
    if (gyro.is_none() && accel.is_none()) {
      samples = ImuRows(t_or_samples, "add_imu");
    } else {
      if (gyro.is_none() || accel.is_none())
        throw py::type_error("add_imu: give (t, gyro, accel) or an (N, 7) array");
      sensor::ImuSample s;
      s.t = TimeArg(t_or_samples, "add_imu");
      s.gyro = Vec<3>(gyro, "gyro");
      s.accel = Vec<3>(accel, "accel");
      samples.push_back(s);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    double last = last_imu_t_;
    for (std::size_t i = 0; i < samples.size(); ++i) {  // checked first: all or nothing
      if (!(samples[i].t > last))
        throw py::value_error("add_imu: sample " + std::to_string(i) +
                              " at t = " + std::to_string(samples[i].t) +
                              " s is not after the previous one (times must increase)");
      last = samples[i].t;
    }
    for (const sensor::ImuSample& s : samples) vio_->AddImu(s);
    last_imu_t_ = last;
  }

  py::dict AddImage(const py::handle& t, const py::array& image) {
    const double time = TimeArg(t, "add_image");
    const cv::Mat view = GrayImageView(image, "add_image");
    return ResultDict(WithoutGil(mutex_, [&] { return vio_->AddImage(time, view); }));
  }

  py::dict AddFrame(const py::handle& t, const py::handle& points, const py::handle& segments) {
    const double time = TimeArg(t, "add_frame");
    const int frame =
        Locked(mutex_, [&] { return static_cast<int>(vio_->RefinedTrajectory().size()); });
    const window::FrameInput input = FrameArg(time, points, segments, frame, "add_frame");
    return ResultDict(WithoutGil(mutex_, [&] { return vio_->AddFrame(input); }));
  }

  py::dict Finish() {
    return ResultDict(WithoutGil(mutex_, [&] { return vio_->Finish(); }));
  }

  py::dict Refined() {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::vector<VioFrameRecord>& records = vio_->RefinedTrajectory();
    std::vector<double> times;
    std::vector<SE3d> poses;
    py::list frames, statuses, keyframes;
    for (const VioFrameRecord& r : records) {
      if (!r.T_w_b) continue;
      frames.append(r.frame);
      times.push_back(r.time);
      poses.push_back(*r.T_w_b);
      statuses.append(odometry::ToString(r));
      keyframes.append(r.keyframe);
    }
    py::dict d;
    d["frames"] = frames;
    d["times"] = DoubleArray(std::move(times));
    d["T_w_b"] = PoseMatrices(poses);
    d["T_w_b_tq"] = PosesTq(poses);
    d["status"] = statuses;
    d["keyframe"] = keyframes;
    d["frames_given"] = records.size();
    return d;
  }

  py::dict Initialization() {
    std::lock_guard<std::mutex> lock(mutex_);
    const odometry::VioInitialization& init = vio_->initialization();
    py::dict d;
    d["done"] = init.done;
    d["method"] = init.method;
    d["first"] = init.first;
    d["second"] = init.second;
    return d;
  }

  bool Initialized() {
    std::lock_guard<std::mutex> lock(mutex_);
    return vio_->initialized();
  }
  double TimeOffset() {
    std::lock_guard<std::mutex> lock(mutex_);
    return vio_->TimeOffsetEstimate();
  }
  py::array_t<double> Extrinsic() {
    std::lock_guard<std::mutex> lock(mutex_);
    return PoseMatrix(vio_->ExtrinsicEstimate());
  }

 private:
  odometry::VisualInertialOdometryOptions options_;
  std::unique_ptr<odometry::VisualInertialOdometry> vio_;
  double last_imu_t_ = -std::numeric_limits<double>::infinity();
  std::mutex mutex_;
};

}  // namespace

void RegisterVio(py::module_& m) {
  py::class_<PyVisualInertialOdometry>(
      m, "VisualInertialOdometry",
      "Online monocular point + line visual-inertial odometry (plucker vio): add_imu, then\n"
      "add_image (or add_frame) once the IMU has reached the frame's time; finish() at the end.")
      .def(py::init<const py::handle&, const py::handle&, const py::handle&, const py::object&,
                    double, double, const py::kwargs&>(),
           py::arg("camera"), py::arg("T_b_c"), py::arg("imu_model"),
           py::arg("config") = py::none(), py::arg("gravity_magnitude") = 9.81,
           py::arg("pixel_sigma") = 1.0,
           "camera: dict K (fx, fy, cx, cy), width, height, distortion (k1, k2, p1, p2) of the\n"
           "raw images (read_euroc(...)['camera'] as it is); T_b_c: the camera in the body (IMU)\n"
           "frame (4, 4), or (7,) tx ty tz qx qy qz qw (read_euroc's camera['T_b_c_tq'], exact);\n"
           "imu_model: dict of noise densities and random walks\n"
           "(read_euroc(...)['imu_model']). Options: the keys of `plucker vio --config`\n"
           "(window=10, use_lines=False, estimate_time_offset=True, ...); config: such a YAML "
           "file.\n"
           "Unknown keys, wrong types and values out of range raise ValueError naming the key.")
      .def("add_imu", &PyVisualInertialOdometry::AddImu, py::arg("t"), py::arg("gyro") = py::none(),
           py::arg("accel") = py::none(),
           "One sample add_imu(t, gyro, accel) (s, rad/s, m/s^2 specific force, body frame) or\n"
           "a batch add_imu(samples) of (N, 7) rows t, gyro xyz, accel xyz. Times must increase\n"
           "(ValueError, nothing added).")
      .def(
          "add_image", &PyVisualInertialOdometry::AddImage, py::arg("t"), py::arg("image"),
          "A raw 8-bit grayscale image (H, W) uint8 of the camera at time t (s, the IMU's clock),\n"
          "read in place (no copy; rows must be contiguous): undistorted, the image front end,\n"
          "the window. Returns the frame's result: dict frame, time, status, T_w_b (4, 4) or\n"
          "None while initialising (T_w_b_tq: (7,) tx ty tz qx qy qz qw), v_w, gyro_bias, "
          "accel_bias, keyframe, window (statistics),\n"
          "observed_points, observed_segments, settled (frames whose refined pose became final)\n"
          "and message. The GIL is released meanwhile.")
      .def("add_frame", &PyVisualInertialOdometry::AddFrame, py::arg("t"),
           py::arg("points") = py::none(), py::arg("segments") = py::none(),
           "A frame's observations in undistorted pixels of the camera's K: points (N, 3) rows\n"
           "(track id, u, v), segments (M, 5) rows (track id, u1, v1, u2, v2). Returns the\n"
           "result as add_image.")
      .def("finish", &PyVisualInertialOdometry::Finish,
           "The end of the input: an initialisation still waiting decides on what it has; returns\n"
           "a result whose `settled` lists the frames it settles (status 'failed' and a message\n"
           "when it cannot start).")
      .def("refined_trajectory", &PyVisualInertialOdometry::Refined,
           "Every frame with a pose, the frames before the start backfilled (plucker vio --out):\n"
           "dict frames, times, T_w_b (N, 4, 4), T_w_b_tq (N, 7) rows tx ty tz qx qy qz qw, "
           "status, keyframe, frames_given.")
      .def_property_readonly("initialized", &PyVisualInertialOdometry::Initialized)
      .def_property_readonly("initialization", &PyVisualInertialOdometry::Initialization,
                             "dict done, method (static | dynamic), first, second.")
      .def_property_readonly("time_offset", &PyVisualInertialOdometry::TimeOffset,
                             "The camera-IMU time offset in use (s, t_imu = t_cam + td).")
      .def_property_readonly("T_b_c", &PyVisualInertialOdometry::Extrinsic,
                             "The camera-body extrinsic in use (the estimate when estimated).");
}

}  // namespace python
}  // namespace plucker
