// plucker.MonocularOdometry: the online point + line monocular VO of `plucker vo`
// (odometry/monocular_odometry.h) fed from Python, one image (or one frame's observations) at a
// time. The options are the keys of `plucker vo --config` (apps/plucker/vo_config.cc), on the
// defaults of images or of features folders as the CLI picks them by its input.
#include <pybind11/stl.h>

#include <cmath>
#include <mutex>
#include <optional>

#include "arrays.h"
#include "bindings.h"
#include "options.h"
#include "pipeline_inputs.h"
#include "plucker/odometry/monocular_odometry.h"
#include "vo_config.h"

namespace plucker {
namespace python {

namespace {

using odometry::MonocularFrameRecord;
using odometry::MonocularFrameResult;

constexpr const char* kWho = "MonocularOdometry";

py::dict ResultDict(const MonocularFrameResult& r) {
  py::dict d;
  d["frame"] = r.frame;
  d["time"] = r.time;
  d["status"] = odometry::ToString(r.status);
  d["has_pose"] = r.has_pose;
  d["T_w_c"] = r.has_pose ? py::object(PoseMatrix(r.T_w_c)) : py::object(py::none());
  d["keyframe"] = r.window && r.window->keyframe;
  d["window"] = r.window ? py::object(WindowDict(*r.window)) : py::object(py::none());
  d["observed_points"] = r.observed_points;
  d["observed_segments"] = r.observed_segments;
  d["caught_up_frames"] = r.caught_up_frames;
  return d;
}

class PyMonocularOdometry {
 public:
  PyMonocularOdometry(const py::handle& camera, const std::string& defaults,
                      const py::object& config_path, int max_lost_frames,
                      const py::object& pixel_sigma, const py::kwargs& options) {
    if (defaults != "images" && defaults != "features")
      throw py::value_error("MonocularOdometry: defaults must be 'images' or 'features', got '" +
                            defaults + "'");
    app::VoConfig cfg = defaults == "images" ? app::ImageVoConfig() : app::FeaturesVoConfig();
    if (!config_path.is_none()) {
      try {
        app::LoadVoConfig(config_path.cast<std::string>(), &cfg);
      } catch (const std::runtime_error& e) {
        throw py::value_error(e.what());
      }
    }
    try {
      app::ApplyVoConfigYaml(OptionsYaml(options, kWho), "MonocularOdometry options", &cfg);
    } catch (const std::runtime_error& e) {
      throw py::value_error(e.what());
    }
    if (max_lost_frames < 1)
      throw py::value_error("MonocularOdometry: max_lost_frames must be >= 1");
    cfg.max_lost_frames = max_lost_frames;
    if (!pixel_sigma.is_none()) {  // as plucker vo on a features folder: its observation noise
      const double s = pixel_sigma.cast<double>();
      if (!(std::isfinite(s) && s > 0.0))
        throw py::value_error("MonocularOdometry: pixel_sigma must be positive");
      cfg.window.point_sigma_px = cfg.window.line_sigma_px = std::max(s, 0.5);
    }
    if (py::isinstance<py::dict>(camera)) {
      const sensor::Camera c = CameraArg(camera, kWho);
      size_ = {c.width, c.height};
      vo_ = std::make_unique<odometry::MonocularOdometry>(c, cfg);
    } else {  // K only: the pinhole of the observations (add_frame, or undistorted images)
      const Eigen::Vector4d K = Vec<4>(camera, "camera (fx, fy, cx, cy)");
      vo_ = std::make_unique<odometry::MonocularOdometry>(PinholeIntrinsics{K(0), K(1), K(2), K(3)},
                                                          cfg);
    }
  }

  py::dict AddImage(const py::handle& t, const py::array& image) {
    const double time = TimeArg(t, "add_image");
    const cv::Mat view = GrayImageView(image, "add_image");
    if (size_ && (view.cols != size_->first || view.rows != size_->second))
      throw py::value_error("add_image: the image is " + std::to_string(view.cols) + "x" +
                            std::to_string(view.rows) + ", the camera " +
                            std::to_string(size_->first) + "x" + std::to_string(size_->second));
    return ResultDict(WithoutGil(mutex_, [&] { return vo_->AddImage(time, view); }));
  }

  py::dict AddFrame(const py::handle& t, const py::handle& points, const py::handle& segments) {
    const double time = TimeArg(t, "add_frame");
    const int frame = Locked(mutex_, [&] { return static_cast<int>(vo_->Trajectory().size()); });
    window::FrameInput input = FrameArg(time, points, segments, frame, "add_frame");
    return ResultDict(WithoutGil(mutex_, [&] { return vo_->AddFrame(std::move(input)); }));
  }

  void Finish() {
    WithoutGil(mutex_, [&] { vo_->Finish(); });
  }

  py::dict Trajectory() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<double> times;
    std::vector<SE3d> poses;
    py::list sources, has_pose, keyframes, maps;
    for (const MonocularFrameRecord& r : vo_->Trajectory()) {
      times.push_back(r.time);
      poses.push_back(r.T_w_c);
      sources.append(odometry::ToString(r.source));
      has_pose.append(r.has_pose);
      keyframes.append(r.keyframe);
      maps.append(r.map);
    }
    py::dict d;
    d["times"] = DoubleArray(std::move(times));
    d["T_w_c"] = PoseMatrices(poses);
    d["source"] = sources;
    d["has_pose"] = has_pose;
    d["keyframe"] = keyframes;
    d["map"] = maps;
    return d;
  }

  py::dict Summary() {
    std::lock_guard<std::mutex> lock(mutex_);
    const odometry::MonocularSummary& s = vo_->Summary();
    py::dict d;
    d["frames"] = s.frames;
    d["keyframes"] = s.keyframes;
    d["lost_frames"] = s.lost_frames;
    d["pnp_recoveries"] = s.pnp_recoveries;
    d["marginalized_keyframes"] = s.marginalized_keyframes;
    d["failed_marginalizations"] = s.failed_marginalizations;
    d["maps"] = vo_->Maps().size();
    d["start_failure"] = vo_->StartFailure();
    d["restart_failure"] = vo_->RestartFailure();
    return d;
  }

 private:
  std::optional<std::pair<int, int>> size_;  // of the raw images, when the camera is given
  std::unique_ptr<odometry::MonocularOdometry> vo_;
  std::mutex mutex_;
};

}  // namespace

void RegisterVo(py::module_& m) {
  py::class_<PyMonocularOdometry>(
      m, "MonocularOdometry",
      "Online monocular point + line visual odometry (plucker vo): add_image (or add_frame)\n"
      "frame by frame, finish() at the end, then trajectory() (the refined view).")
      .def(py::init<const py::handle&, const std::string&, const py::object&, int,
                    const py::object&, const py::kwargs&>(),
           py::arg("camera"), py::arg("defaults") = "images", py::arg("config") = py::none(),
           py::arg("max_lost_frames") = 3, py::arg("pixel_sigma") = py::none(),
           "camera: dict K, width, height, distortion (the raw images; distorted ones are\n"
           "undistorted first) or K = (fx, fy, cx, cy) of undistorted pixels. defaults: 'images'\n"
           "(the speed settings of plucker vo --images) or 'features' (those of --features).\n"
           "Options: the keys of `plucker vo --config`, dotted or grouped\n"
           "(window={'size': 8}, **{'points.max_tracks': 150}); config: such a YAML file;\n"
           "max_lost_frames as --max-lost; pixel_sigma: the observation noise of add_frame's\n"
           "pixels (plucker vo --features takes the folder's). Bad keys raise ValueError.")
      .def("add_image", &PyMonocularOdometry::AddImage, py::arg("t"), py::arg("image"),
           "An 8-bit grayscale image (H, W) uint8 at time t (s), read in place (no copy). Returns\n"
           "dict frame, time, status, has_pose, T_w_c (4, 4) or None, keyframe, window,\n"
           "observed_points, observed_segments, caught_up_frames. The GIL is released meanwhile.")
      .def("add_frame", &PyMonocularOdometry::AddFrame, py::arg("t"),
           py::arg("points") = py::none(), py::arg("segments") = py::none(),
           "A frame's observations: points (N, 3) rows (track id, u, v), segments (M, 5) rows\n"
           "(track id, u1, v1, u2, v2), undistorted pixels. Returns the result as add_image.")
      .def("finish", &PyMonocularOdometry::Finish,
           "The end of the input: a pending start search runs on the frames buffered.")
      .def("trajectory", &PyMonocularOdometry::Trajectory,
           "The refined view (complete after finish(), plucker vo --out): dict times, T_w_c\n"
           "(N, 4, 4; frames not localised repeat the last pose), source, has_pose, keyframe, map.")
      .def_property_readonly("summary", &PyMonocularOdometry::Summary,
                             "Counts: frames, keyframes, lost_frames, maps, start_failure, ...");
}

}  // namespace python
}  // namespace plucker
